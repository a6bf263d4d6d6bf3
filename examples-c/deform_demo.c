/*
 * deform_demo: a scissors blade (the reference object) moving in and out of a deforming
 * gallbladder, both read from ../shared/meshes. Each frame it moves the organ's vertices,
 * hands them to glcollide, asks which polygons of the blade touch which polygons of the
 * organ, and prints the count; at the end it prints the median frame time.
 *
 *   make -C examples-c && examples-c/build/deform_demo [meshes_dir] [frames] [epsilon]
 */
#include <glcollide.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#define CHECK(call)                                                                     \
    do {                                                                                \
        GlcolStatus s_ = (call);                                                        \
        if (s_ != GLCOL_STATUS_OK) {                                                    \
            fprintf(stderr, "%s:%d: %s failed: %s: %s\n", __FILE__, __LINE__, #call,    \
                    glcol_status_name(s_), glcol_last_error_message());                 \
            exit(1);                                                                    \
        }                                                                               \
    } while (0)

static double now_us(void) {
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec * 1e6 + (double)t.tv_nsec / 1e3;
}

static int cmp_double(const void *a, const void *b) {
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static GlcolMeshId add_mesh(GlcolScene *scene, const GlcolObjMesh *m, const float *positions) {
    GlcolMeshDesc d;
    glcol_mesh_desc_init(&d);
    d.positions = positions;
    d.vertex_count = m->vertex_count;
    d.indices = m->indices;
    d.polygon_count = m->polygon_count;
    d.vertices_per_polygon = 3;
    GlcolMeshId id = 0;
    CHECK(glcol_mesh_create(scene, &d, &id));
    return id;
}

int main(int argc, char **argv) {
    const char *dir = argc > 1 ? argv[1] : "../shared/meshes";
    int frames = argc > 2 ? atoi(argv[2]) : 300;
    float epsilon = argc > 3 ? (float)atof(argv[3]) : 0.0f;
    if (frames < 1) frames = 1;

    char path[4096];
    GlcolObjMesh blade, organ;
    snprintf(path, sizeof path, "%s/scissors_blade.obj", dir);
    CHECK(glcol_obj_load(path, &blade));
    snprintf(path, sizeof path, "%s/gallbladder_glt.obj", dir);
    CHECK(glcol_obj_load(path, &organ));

    /* The organ's centre and its vertex farthest along +x: the blade works there. */
    size_t nv = organ.vertex_count, far = 0;
    double c[3] = {0, 0, 0};
    for (size_t i = 0; i < nv; i++)
        for (int k = 0; k < 3; k++) c[k] += organ.positions[3 * i + k] / (double)nv;
    for (size_t i = 1; i < nv; i++)
        if (organ.positions[3 * i] > organ.positions[3 * far]) far = i;

    /* Blade centred on its own box, long axis (z) turned onto x, tip at the surface. */
    size_t bv = blade.vertex_count;
    float lo[3], hi[3];
    for (int k = 0; k < 3; k++) lo[k] = hi[k] = blade.positions[k];
    for (size_t i = 0; i < bv; i++)
        for (int k = 0; k < 3; k++) {
            float v = blade.positions[3 * i + k];
            lo[k] = v < lo[k] ? v : lo[k];
            hi[k] = v > hi[k] ? v : hi[k];
        }
    float *blade_rest = malloc(bv * 3 * sizeof(float));
    float *blade_now = malloc(bv * 3 * sizeof(float));
    float *organ_now = malloc(nv * 3 * sizeof(float));
    if (!blade_rest || !blade_now || !organ_now) return 1;
    for (size_t i = 0; i < bv; i++) {
        float x = blade.positions[3 * i] - (lo[0] + hi[0]) / 2;
        float y = blade.positions[3 * i + 1] - (lo[1] + hi[1]) / 2;
        float z = blade.positions[3 * i + 2] - lo[2]; /* z from 0 (one end) to its length */
        blade_rest[3 * i] = organ.positions[3 * far] + z - 2.0f;
        blade_rest[3 * i + 1] = organ.positions[3 * far + 1] + y;
        blade_rest[3 * i + 2] = organ.positions[3 * far + 2] + x;
    }

    GlcolSceneDesc sd;
    glcol_scene_desc_init(&sd);
    sd.backend = GLCOL_BACKEND_CPU;
    sd.epsilon = epsilon;
    GlcolScene *scene = NULL;
    CHECK(glcol_scene_create(&sd, &scene));
    GlcolMeshId organ_id = add_mesh(scene, &organ, organ.positions);
    GlcolMeshId blade_id = add_mesh(scene, &blade, blade_rest);
    printf("glcollide %s: blade %zu triangles, gallbladder %zu triangles, epsilon %g, %d frames\n",
           glcol_version(), blade.polygon_count, organ.polygon_count, (double)epsilon, frames);

    double *times = malloc((size_t)frames * sizeof(double));
    size_t total = 0, max_contacts = 0;
    for (int f = 0; f < frames; f++) {
        double t = 0.05 * f;
        /* Organ: a travelling wave along the radius, 1 mm at most. */
        for (size_t i = 0; i < nv; i++) {
            const float *p = organ.positions + 3 * i;
            double r[3] = {p[0] - c[0], p[1] - c[1], p[2] - c[2]};
            double len = sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2]) + 1e-9;
            double a = 1.0 * sin(t + 0.1 * p[1]);
            for (int k = 0; k < 3; k++) organ_now[3 * i + k] = (float)(p[k] + a * r[k] / len);
        }
        /* Blade: in and out along -x by up to 6 mm. */
        double push = 3.0 + 3.0 * sin(0.7 * t);
        for (size_t i = 0; i < bv; i++) {
            blade_now[3 * i] = (float)(blade_rest[3 * i] - push);
            blade_now[3 * i + 1] = blade_rest[3 * i + 1];
            blade_now[3 * i + 2] = blade_rest[3 * i + 2];
        }
        const GlcolContact *contacts = NULL;
        size_t n = 0;
        double t0 = now_us();
        CHECK(glcol_mesh_update_positions(scene, organ_id, organ_now, 0, nv, 0));
        CHECK(glcol_mesh_update_positions(scene, blade_id, blade_now, 0, bv, 0));
        CHECK(glcol_query(scene, blade_id, &contacts, &n));
        times[f] = now_us() - t0;
        for (size_t i = 0; i < n; i++) {
            if (contacts[i].other_mesh != organ_id || contacts[i].reference_polygon >= blade.polygon_count ||
                contacts[i].other_polygon >= organ.polygon_count) {
                fprintf(stderr, "frame %d: contact %zu names a polygon that does not exist\n", f, i);
                return 1;
            }
        }
        total += n;
        if (n > max_contacts) max_contacts = n;
        printf("frame %3d contacts %zu\n", f, n);
    }
    qsort(times, (size_t)frames, sizeof(double), cmp_double);
    printf("frames %d, contacts total %zu, max %zu per frame\n", frames, total, max_contacts);
    printf("median frame time (update both meshes + query): %.1f us\n", times[frames / 2]);

    glcol_scene_destroy(scene);
    glcol_obj_free(&blade);
    glcol_obj_free(&organ);
    free(blade_rest);
    free(blade_now);
    free(organ_now);
    free(times);
    return total > 0 ? 0 : 2; /* the blade must touch the organ at some point */
}
