/* gl_host: a host program with its own OpenGL context that calls glcollide between its
 * own draws, the way a simulator does mid-frame.
 *
 *   make -C examples-c && examples-c/build/gl_host [meshes_dir] [frames] [out.png]
 *
 * It makes a headless EGL context (Mesa's surfaceless platform: llvmpipe without a GPU),
 * compatibility profile, and its own framebuffer. For each backend (CPU, GL_SELECT,
 * GL_COMPUTE) it runs the README demo (a blade in a deforming gallbladder, epsilon 0.001):
 * every frame it draws the organ, updates both meshes and queries glcollide, checks that
 * its GL state survived the call, and draws the contacts. It prints the median query time
 * per backend, checks that the three backends found the same contacts, and writes the frame
 * with the most contacts to a PNG with the colliding polygons in red (organ) and yellow
 * (blade) and, from glcol_query_geometry, each intersecting pair's intersection segment
 * (point_a to point_b, green) and its separating normal (cyan, from the segment's midpoint,
 * NORMAL_LEN mm long: the depths are far below a pixel), drawn over everything. */
#define GL_GLEXT_PROTOTYPES 1
#include <EGL/egl.h>
#include <EGL/eglext.h>
#include <GL/gl.h>
#include <GL/glext.h>
#include <glcollide.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#define W 640
#define H 480
#define EPSILON 0.001f
#define NORMAL_LEN 1.5f

#define CHECK(call)                                                                       \
    do {                                                                                  \
        GlcolStatus s_ = (call);                                                          \
        if (s_ != GLCOL_STATUS_OK) {                                                      \
            fprintf(stderr, "%s:%d: %s: %s\n", __FILE__, __LINE__, glcol_status_name(s_), \
                    glcol_last_error_message());                                          \
            exit(1);                                                                      \
        }                                                                                 \
    } while (0)

static void *gpa(void *user, const char *name) {
    (void)user;
    /* Function pointer to object pointer, as dlsym does (POSIX guarantees it works). */
    __extension__ void *p;
    __extension__ union { __eglMustCastToProperFunctionPointerType f; void *o; } u;
    u.f = eglGetProcAddress(name);
    p = u.o;
    return p;
}

static double now_us(void) {
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return t.tv_sec * 1e6 + t.tv_nsec / 1e3;
}

static int cmp_double(const void *a, const void *b) {
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* ---- PNG writer: stored (uncompressed) deflate blocks, no library needed ---- */
static uint32_t crc_table[256];
static void crc_init(void) {
    for (uint32_t n = 0; n < 256; n++) {
        uint32_t c = n;
        for (int k = 0; k < 8; k++) c = c & 1 ? 0xedb88320u ^ (c >> 1) : c >> 1;
        crc_table[n] = c;
    }
}
static uint32_t crc(uint32_t c, const unsigned char *p, size_t n) {
    c ^= 0xffffffffu;
    while (n--) c = crc_table[(c ^ *p++) & 0xff] ^ (c >> 8);
    return c ^ 0xffffffffu;
}
static void put32(unsigned char *p, uint32_t v) {
    p[0] = v >> 24; p[1] = v >> 16; p[2] = v >> 8; p[3] = v;
}
static void chunk(FILE *f, const char *type, const unsigned char *data, uint32_t n) {
    unsigned char b[8];
    put32(b, n);
    memcpy(b + 4, type, 4);
    fwrite(b, 1, 8, f);
    if (n) fwrite(data, 1, n, f);
    uint32_t c = crc(crc(0, (const unsigned char *)type, 4), data, n);
    put32(b, c);
    fwrite(b, 1, 4, f);
}
static int write_png(const char *path, const unsigned char *rgba_bottom_up, int w, int h) {
    size_t row = (size_t)w * 3 + 1, raw_n = row * h;
    unsigned char *raw = malloc(raw_n);
    for (int y = 0; y < h; y++) {
        unsigned char *r = raw + row * y;
        const unsigned char *src = rgba_bottom_up + (size_t)(h - 1 - y) * w * 4;
        r[0] = 0;
        for (int x = 0; x < w; x++) memcpy(r + 1 + 3 * x, src + 4 * x, 3);
    }
    size_t blocks = (raw_n + 65534) / 65535;
    size_t z_n = 2 + raw_n + 5 * blocks + 4;
    unsigned char *z = malloc(z_n), *p = z;
    *p++ = 0x78; *p++ = 0x01;
    uint32_t a = 1, b = 0;
    for (size_t i = 0; i < raw_n; i++) { a = (a + raw[i]) % 65521; b = (b + a) % 65521; }
    for (size_t off = 0; off < raw_n; off += 65535) {
        size_t n = raw_n - off < 65535 ? raw_n - off : 65535;
        *p++ = off + n == raw_n;
        *p++ = n & 0xff; *p++ = n >> 8; *p++ = ~n & 0xff; *p++ = (~n >> 8) & 0xff;
        memcpy(p, raw + off, n);
        p += n;
    }
    put32(p, (b << 16) | a);
    FILE *f = fopen(path, "wb");
    if (!f) return 0;
    static const unsigned char sig[8] = {137, 80, 78, 71, 13, 10, 26, 10};
    fwrite(sig, 1, 8, f);
    unsigned char ihdr[13];
    put32(ihdr, (uint32_t)w); put32(ihdr + 4, (uint32_t)h);
    ihdr[8] = 8; ihdr[9] = 2; ihdr[10] = ihdr[11] = ihdr[12] = 0;
    chunk(f, "IHDR", ihdr, 13);
    chunk(f, "IDAT", z, (uint32_t)z_n);
    chunk(f, "IEND", NULL, 0);
    fclose(f);
    free(raw);
    free(z);
    return 1;
}

/* ---- the host's state, as it checks it after each glcollide call ---- */
typedef struct {
    GLint ints[16];
    GLdouble proj[16], mv[16];
    GLboolean enables[6];
} HostState;

static void host_state(HostState *s) {
    static const GLenum q[] = {GL_DRAW_FRAMEBUFFER_BINDING, GL_READ_FRAMEBUFFER_BINDING,
                               GL_CURRENT_PROGRAM, GL_ARRAY_BUFFER_BINDING, GL_MATRIX_MODE,
                               GL_RENDER_MODE, GL_SELECTION_BUFFER_SIZE, GL_SHADER_STORAGE_BUFFER_BINDING,
                               GL_VIEWPORT};
    memset(s, 0, sizeof *s);
    for (int i = 0; i < 8; i++) glGetIntegerv(q[i], &s->ints[i]);
    glGetIntegerv(GL_VIEWPORT, &s->ints[8]);
    glGetIntegerv(GL_POLYGON_MODE, &s->ints[12]);
    glGetDoublev(GL_PROJECTION_MATRIX, s->proj);
    glGetDoublev(GL_MODELVIEW_MATRIX, s->mv);
    static const GLenum e[] = {GL_DEPTH_TEST, GL_LIGHTING, GL_CULL_FACE, GL_CLIP_PLANE0,
                               GL_COLOR_MATERIAL, GL_BLEND};
    for (int i = 0; i < 6; i++) s->enables[i] = glIsEnabled(e[i]);
}

typedef struct {
    const float *pos;
    const uint32_t *idx;
    size_t n;
} DrawMesh;

static void draw_mesh(DrawMesh m, float r, float g, float b, const unsigned char *mark,
                      float mr, float mg, float mb) {
    glBegin(GL_TRIANGLES);
    for (size_t t = 0; t < m.n; t++) {
        const float *a = m.pos + 3 * m.idx[3 * t], *bb = m.pos + 3 * m.idx[3 * t + 1],
                    *c = m.pos + 3 * m.idx[3 * t + 2];
        float u[3] = {bb[0] - a[0], bb[1] - a[1], bb[2] - a[2]};
        float v[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
        float nx = u[1] * v[2] - u[2] * v[1], ny = u[2] * v[0] - u[0] * v[2], nz = u[0] * v[1] - u[1] * v[0];
        float l = sqrtf(nx * nx + ny * ny + nz * nz) + 1e-20f;
        float shade = 0.35f + 0.65f * fabsf((0.3f * nx + 0.5f * ny + 0.8f * nz) / l);
        if (mark && mark[t]) glColor3f(mr, mg, mb);
        else glColor3f(r * shade, g * shade, b * shade);
        glVertex3fv(a); glVertex3fv(bb); glVertex3fv(c);
    }
    glEnd();
}

int main(int argc, char **argv) {
    const char *dir = argc > 1 ? argv[1] : "data";
    int frames = argc > 2 ? atoi(argv[2]) : 60;
    const char *out = argc > 3 ? argv[3] : "gl_host.png";
    if (frames < 1) frames = 1;
    crc_init();

    /* The host's own context: EGL surfaceless, compatibility profile. */
    EGLDisplay dpy = eglGetPlatformDisplay(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, NULL);
    if (dpy == EGL_NO_DISPLAY || !eglInitialize(dpy, NULL, NULL)) {
        fprintf(stderr, "no EGL surfaceless display\n");
        return 1;
    }
    eglBindAPI(EGL_OPENGL_API);
    static const EGLint cfg_attr[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_SURFACE_TYPE, EGL_PBUFFER_BIT, EGL_NONE};
    EGLConfig cfg;
    EGLint n_cfg = 0;
    if (!eglChooseConfig(dpy, cfg_attr, &cfg, 1, &n_cfg) || n_cfg < 1) {
        fprintf(stderr, "no EGL config for OpenGL\n");
        return 1;
    }
    static const EGLint ctx_attr[] = {EGL_CONTEXT_OPENGL_PROFILE_MASK, EGL_CONTEXT_OPENGL_COMPATIBILITY_PROFILE_BIT, EGL_NONE};
    EGLContext ctx = eglCreateContext(dpy, cfg, EGL_NO_CONTEXT, ctx_attr);
    if (ctx == EGL_NO_CONTEXT || !eglMakeCurrent(dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, ctx)) {
        fprintf(stderr, "cannot make a GL context current\n");
        return 1;
    }
    printf("host context: %s / %s\n", glGetString(GL_VERSION), glGetString(GL_RENDERER));

    /* Its framebuffer and its state. */
    GLuint fbo, rb[2];
    glGenFramebuffers(1, &fbo);
    glGenRenderbuffers(2, rb);
    glBindRenderbuffer(GL_RENDERBUFFER, rb[0]);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, W, H);
    glBindRenderbuffer(GL_RENDERBUFFER, rb[1]);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT24, W, H);
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, rb[0]);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, rb[1]);
    if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
        fprintf(stderr, "host framebuffer incomplete\n");
        return 1;
    }
    static GLuint host_select[128];
    glSelectBuffer(128, host_select);
    glViewport(0, 0, W, H);
    glEnable(GL_DEPTH_TEST);

    /* The README demo scene (as examples-c/deform_demo.c). */
    char path[4096];
    GlcolObjMesh blade, organ;
    snprintf(path, sizeof path, "%s/scissors_blade.obj", dir);
    CHECK(glcol_obj_load(path, &blade));
    snprintf(path, sizeof path, "%s/gallbladder_glt.obj", dir);
    CHECK(glcol_obj_load(path, &organ));
    size_t nv = organ.vertex_count, bv = blade.vertex_count, far = 0;
    double c[3] = {0, 0, 0};
    for (size_t i = 0; i < nv; i++)
        for (int k = 0; k < 3; k++) c[k] += organ.positions[3 * i + k] / (double)nv;
    for (size_t i = 1; i < nv; i++)
        if (organ.positions[3 * i] > organ.positions[3 * far]) far = i;
    float lo[3], hi[3];
    for (int k = 0; k < 3; k++) lo[k] = hi[k] = blade.positions[k];
    for (size_t i = 0; i < bv; i++)
        for (int k = 0; k < 3; k++) {
            float v = blade.positions[3 * i + k];
            lo[k] = v < lo[k] ? v : lo[k];
            hi[k] = v > hi[k] ? v : hi[k];
        }
    float *blade_rest = malloc(bv * 12), *blade_now = malloc(bv * 12), *organ_now = malloc(nv * 12);
    for (size_t i = 0; i < bv; i++) {
        float x = blade.positions[3 * i] - (lo[0] + hi[0]) / 2;
        float y = blade.positions[3 * i + 1] - (lo[1] + hi[1]) / 2;
        float z = blade.positions[3 * i + 2] - lo[2];
        blade_rest[3 * i] = organ.positions[3 * far] + z - 2.0f;
        blade_rest[3 * i + 1] = organ.positions[3 * far + 1] + y;
        blade_rest[3 * i + 2] = organ.positions[3 * far + 2] + x;
    }
    const float *fp = organ.positions + 3 * far;

    static const GlcolBackend backends[3] = {GLCOL_BACKEND_CPU, GLCOL_BACKEND_GL_SELECT, GLCOL_BACKEND_GL_COMPUTE};
    static const char *names[3] = {"CPU", "GL_SELECT", "GL_COMPUTE"};
    double medians[3];
    size_t total[3] = {0, 0, 0}, best_n = 0, best_drawn = 0;
    uint32_t hash[3] = {0, 0, 0};
    unsigned char *pixels = malloc((size_t)W * H * 4);
    unsigned char *organ_mark = calloc(organ.polygon_count, 1), *blade_mark = calloc(blade.polygon_count, 1);
    double *times = malloc((size_t)frames * sizeof(double));
    int state_ok = 1;
    for (int bi = 0; bi < 3; bi++) {
        GlcolSceneDesc sd;
        glcol_scene_desc_init(&sd);
        sd.backend = backends[bi];
        sd.get_proc_address = gpa;
        sd.epsilon = EPSILON;
        GlcolScene *scene = NULL;
        CHECK(glcol_scene_create(&sd, &scene));
        GlcolMeshDesc md;
        glcol_mesh_desc_init(&md);
        md.positions = organ.positions; md.vertex_count = nv;
        md.indices = organ.indices; md.polygon_count = organ.polygon_count;
        GlcolMeshId organ_id, blade_id;
        CHECK(glcol_mesh_create(scene, &md, &organ_id));
        md.positions = blade_rest; md.vertex_count = bv;
        md.indices = blade.indices; md.polygon_count = blade.polygon_count;
        CHECK(glcol_mesh_create(scene, &md, &blade_id));
        for (int f = 0; f < frames; f++) {
            double t = 0.05 * f;
            for (size_t i = 0; i < nv; i++) {
                const float *p = organ.positions + 3 * i;
                double r[3] = {p[0] - c[0], p[1] - c[1], p[2] - c[2]};
                double len = sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2]) + 1e-9;
                double a = 1.0 * sin(t + 0.1 * p[1]);
                for (int k = 0; k < 3; k++) organ_now[3 * i + k] = (float)(p[k] + a * r[k] / len);
            }
            double push = 3.0 + 3.0 * sin(0.7 * t);
            for (size_t i = 0; i < bv; i++) {
                blade_now[3 * i] = (float)(blade_rest[3 * i] - push);
                blade_now[3 * i + 1] = blade_rest[3 * i + 1];
                blade_now[3 * i + 2] = blade_rest[3 * i + 2];
            }
            /* The host draws: a camera on the blade's working area, looking along -z. */
            glBindFramebuffer(GL_FRAMEBUFFER, fbo);
            glClearColor(0.08f, 0.09f, 0.12f, 1.0f);
            glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
            glMatrixMode(GL_PROJECTION);
            glLoadIdentity();
            glOrtho(fp[0] - 16.0 * W / H, fp[0] + 4.0 * W / H, fp[1] - 10.0, fp[1] + 10.0, -1000.0, 1000.0);
            glMatrixMode(GL_MODELVIEW);
            glLoadIdentity();
            DrawMesh om = {organ_now, organ.indices, organ.polygon_count};
            DrawMesh bm = {blade_now, blade.indices, blade.polygon_count};
            draw_mesh(om, 0.85f, 0.55f, 0.5f, NULL, 0, 0, 0);

            /* glcollide between the host's draws. */
            HostState before, after;
            host_state(&before);
            const GlcolContact *contacts = NULL;
            size_t n = 0;
            double t0 = now_us();
            CHECK(glcol_mesh_update_positions(scene, organ_id, organ_now, 0, nv, 0));
            CHECK(glcol_mesh_update_positions(scene, blade_id, blade_now, 0, bv, 0));
            CHECK(glcol_query(scene, blade_id, &contacts, &n));
            times[f] = now_us() - t0;
            host_state(&after);
            GLenum err = glGetError();
            if (memcmp(&before, &after, sizeof before) != 0 || err != GL_NO_ERROR) {
                fprintf(stderr, "%s frame %d: the host's GL state changed (GL error 0x%x)\n", names[bi], f, err);
                state_ok = 0;
            }

            /* The host draws on: the contacts highlighted. */
            memset(organ_mark, 0, organ.polygon_count);
            memset(blade_mark, 0, blade.polygon_count);
            for (size_t i = 0; i < n; i++) {
                organ_mark[contacts[i].other_polygon] = 1;
                blade_mark[contacts[i].reference_polygon] = 1;
            }
            glDepthFunc(GL_LEQUAL);
            draw_mesh(om, 0.85f, 0.55f, 0.5f, organ_mark, 1.0f, 0.1f, 0.1f);
            draw_mesh(bm, 0.55f, 0.65f, 0.9f, blade_mark, 1.0f, 0.9f, 0.1f);
            glDepthFunc(GL_LESS);

            /* The contacts' geometry, over everything: intersection segments and normals
             * (band-only pairs, which do not intersect, are not drawn). */
            const GlcolContactGeometry *geo = NULL;
            size_t gn = 0;
            CHECK(glcol_query_geometry(scene, &geo, &gn));
            if (gn != n) {
                fprintf(stderr, "%s frame %d: %zu geometry entries for %zu contacts\n", names[bi], f, gn, n);
                return 1;
            }
            size_t drawn = 0;
            glDisable(GL_DEPTH_TEST);
            glLineWidth(2.0f);
            glBegin(GL_LINES);
            for (size_t i = 0; i < gn; i++) {
                const GlcolContactGeometry *g = &geo[i];
                if (!(g->flags & GLCOL_CONTACT_INTERSECTING)) continue;
                float m[3];
                for (int k = 0; k < 3; k++) m[k] = 0.5f * (g->point_a[k] + g->point_b[k]);
                glColor3f(0.1f, 1.0f, 0.2f);
                glVertex3fv(g->point_a);
                glVertex3fv(g->point_b);
                glColor3f(0.1f, 0.9f, 1.0f);
                glVertex3fv(m);
                glVertex3f(m[0] + NORMAL_LEN * g->normal[0], m[1] + NORMAL_LEN * g->normal[1],
                           m[2] + NORMAL_LEN * g->normal[2]);
                drawn++;
            }
            glEnd();
            glLineWidth(1.0f);
            glEnable(GL_DEPTH_TEST);
            total[bi] += n;
            hash[bi] = crc(hash[bi], (const unsigned char *)&n, sizeof n);
            for (size_t i = 0; i < n; i++) { /* mesh ids differ between scenes: polygons only */
                uint32_t pr[2] = {contacts[i].reference_polygon, contacts[i].other_polygon};
                hash[bi] = crc(hash[bi], (const unsigned char *)pr, sizeof pr);
            }
            if (bi == 0 && (f == 0 || n > best_n)) { /* the picture: the frame with most contacts */
                best_n = n;
                best_drawn = drawn;
                glPixelStorei(GL_PACK_ALIGNMENT, 1);
                glReadPixels(0, 0, W, H, GL_RGBA, GL_UNSIGNED_BYTE, pixels);
                glPixelStorei(GL_PACK_ALIGNMENT, 4);
            }
        }
        GlcolBackend got;
        CHECK(glcol_scene_backend(scene, &got));
        glcol_scene_destroy(scene);
        qsort(times, (size_t)frames, sizeof(double), cmp_double);
        medians[bi] = times[frames / 2];
        printf("%-10s (backend %d): %d frames, %zu contacts in all, median update+query %.1f us\n",
               names[bi], (int)got, frames, total[bi], medians[bi]);
    }
    int same = total[0] > 0 && hash[1] == hash[0] && hash[2] == hash[0];
    printf("contacts of the three backends, frame by frame: %s\n", same ? "identical" : "DIFFERENT (or none)");
    if (!write_png(out, pixels, W, H)) {
        fprintf(stderr, "cannot write %s\n", out);
        return 1;
    }
    printf("wrote %s (%dx%d, the frame with most contacts, %zu): organ contacts red, blade contacts yellow, "
           "%zu intersection segments green, their normals cyan (%.1f mm)\n",
           out, W, H, best_n, best_drawn, (double)NORMAL_LEN);
    printf("host GL state after every glcollide call: %s\n", state_ok ? "unchanged" : "CHANGED");

    glDeleteFramebuffers(1, &fbo);
    glDeleteRenderbuffers(2, rb);
    eglMakeCurrent(dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    eglDestroyContext(dpy, ctx);
    eglTerminate(dpy);
    glcol_obj_free(&blade);
    glcol_obj_free(&organ);
    return state_ok && same ? 0 : 1;
}
