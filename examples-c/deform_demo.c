/*
 * deform_demo: a scissors blade (the reference object) moving in and out of a deforming
 * gallbladder, both read from data/ (or the folder given). Each frame it moves the organ's
 * vertices, hands them to glcollide, asks which polygons of the blade touch which polygons
 * of the organ, and prints the count; at the end it prints the median frame time.
 *
 * It runs the same motion twice, side by side in two scenes: without a response (the
 * "contacts" column) and with one (the "with response" column). In the second scene, after
 * each query it asks glcol_query_geometry for every contact's geometry and pushes the
 * organ's vertices of each intersecting organ polygon by 1.1 * depth * normal the other way
 * (moving polygon b by -depth * normal separates it from the blade's polygon a as moving a
 * by +depth * normal would), all of the polygon's vertices by the same amount (the polygon
 * moves rigidly, so that pair comes apart); a vertex shared by several contacting polygons
 * takes the deepest push. Four rounds of query, geometry and push per frame; "after its
 * push" is the count the last round leaves. The pushes accumulate in a displacement field
 * (the tissue yields and keeps its new shape: no spring back), and the response scene's
 * organ is the wave plus that field. The blade starts 2 mm deep in the organ, so the first
 * frames push the tissue out of it (more contacts for a while); then the contacts per
 * frame fall to a few and mostly to none, while the scene without response keeps 35-55
 * whenever the blade is in.
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

/* The response: rounds of query, geometry and push per frame, and how far past the
 * separating translation a polygon is pushed (a 10% overshoot, as position-based solvers
 * use, so that a pair does not come back at the next round from its neighbours' pushes). */
#define RESPONSE_PASSES 4
#define OVERSHOOT 1.1f

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
    const char *dir = argc > 1 ? argv[1] : "data";
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
    /* The same scene with a response (see the top of the file). */
    GlcolScene *rscene = NULL;
    CHECK(glcol_scene_create(&sd, &rscene));
    GlcolMeshId rorgan_id = add_mesh(rscene, &organ, organ.positions);
    GlcolMeshId rblade_id = add_mesh(rscene, &blade, blade_rest);
    printf("glcollide %s: blade %zu triangles, gallbladder %zu triangles, epsilon %g, %d frames\n",
           glcol_version(), blade.polygon_count, organ.polygon_count, (double)epsilon, frames);

    double *times = malloc((size_t)frames * sizeof(double));
    float *disp = calloc(nv * 3, sizeof(float));    /* the response's displacement field */
    float *vpush = calloc(nv * 3, sizeof(float));    /* this frame's push per vertex */
    float *push_depth = calloc(nv, sizeof(float));  /* and its depth (the deepest wins) */
    float *rorgan_now = malloc(nv * 3 * sizeof(float));
    if (!times || !disp || !vpush || !push_depth || !rorgan_now) return 1;
    size_t total = 0, max_contacts = 0, rtotal = 0, rmax = 0, rleft = 0, pushed_total = 0;
    double max_depth = 0, gsum = 0;
    size_t gpairs = 0;
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

        /* The response scene: the same motion plus the displacement field; RESPONSE_PASSES
         * rounds of query, geometry and push per frame (the first round's count is the
         * frame's contacts, the last round's what is left after the response). */
        size_t rn = 0, first = 0, pushed = 0;
        for (int pass = 0; pass <= RESPONSE_PASSES; pass++) {
            for (size_t i = 0; i < 3 * nv; i++) rorgan_now[i] = organ_now[i] + disp[i];
            const GlcolContact *rc = NULL;
            CHECK(glcol_mesh_update_positions(rscene, rorgan_id, rorgan_now, 0, nv, 0));
            CHECK(glcol_mesh_update_positions(rscene, rblade_id, blade_now, 0, bv, 0));
            CHECK(glcol_query(rscene, rblade_id, &rc, &rn));
            if (pass == 0) first = rn;
            if (pass == RESPONSE_PASSES) break;
            const GlcolContactGeometry *geo = NULL;
            size_t gn = 0;
            double g0 = now_us();
            CHECK(glcol_query_geometry(rscene, &geo, &gn));
            gsum += now_us() - g0;
            gpairs += gn;
            if (gn != rn) {
                fprintf(stderr, "frame %d: %zu geometry entries for %zu contacts\n", f, gn, rn);
                return 1;
            }
            /* Polygon a is the blade's (the reference), b the organ's: b moves by
             * -depth * normal. Band-only pairs (epsilon > 0, depth < 0) and touching ones
             * (depth 0) get none. */
            for (size_t i = 0; i < rn; i++) {
                const GlcolContactGeometry *g = &geo[i];
                if (!(g->flags & GLCOL_CONTACT_INTERSECTING) || !(g->depth > 0)) continue;
                if (rc[i].other_mesh != rorgan_id || rc[i].other_polygon >= organ.polygon_count) {
                    fprintf(stderr, "frame %d: contact %zu names a polygon that does not exist\n", f, i);
                    return 1;
                }
                if (g->depth > max_depth) max_depth = g->depth;
                for (int j = 0; j < 3; j++) {
                    uint32_t v = organ.indices[3 * (size_t)rc[i].other_polygon + j];
                    if (g->depth <= push_depth[v]) continue;
                    if (push_depth[v] == 0) pushed++;
                    push_depth[v] = g->depth;
                    for (int k = 0; k < 3; k++) vpush[3 * v + k] = -OVERSHOOT * g->depth * g->normal[k];
                }
            }
            for (size_t v = 0; v < nv; v++) {
                if (push_depth[v] == 0) continue;
                for (int k = 0; k < 3; k++) disp[3 * v + k] += vpush[3 * v + k];
                push_depth[v] = 0;
            }
        }
        pushed_total += pushed;
        rtotal += first;
        rleft += rn;
        if (first > rmax) rmax = first;
        printf("frame %3d contacts %zu  with response %zu (after its push %zu, vertices pushed %zu)\n", f, n, first,
               rn, pushed);
    }
    qsort(times, (size_t)frames, sizeof(double), cmp_double);
    printf("frames %d, contacts total %zu, max %zu per frame\n", frames, total, max_contacts);
    printf("with response: contacts total %zu, max %zu per frame (%.0f%% of the contacts without); "
           "%zu after the pushes; %zu vertex pushes, deepest contact %.3g\n",
           rtotal, rmax, total ? 100.0 * (double)rtotal / (double)total : 0.0, rleft, pushed_total, max_depth);
    printf("median frame time (update both meshes + query): %.1f us\n", times[frames / 2]);
    printf("glcol_query_geometry: %.0f ns per contact (%zu contacts, all rounds)\n",
           gpairs ? 1e3 * gsum / (double)gpairs : 0.0, gpairs);

    glcol_scene_destroy(scene);
    glcol_scene_destroy(rscene);
    free(disp);
    free(vpush);
    free(push_depth);
    free(rorgan_now);
    glcol_obj_free(&blade);
    glcol_obj_free(&organ);
    free(blade_rest);
    free(blade_now);
    free(organ_now);
    free(times);
    return total > 0 ? 0 : 2; /* the blade must touch the organ at some point */
}
