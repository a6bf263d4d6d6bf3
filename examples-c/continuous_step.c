/*
 * continuous_step: what discrete frames miss and a continuous step catches. A scissors blade
 * (data/scissors_blade.obj, units of cm) is driven sideways through a thin membrane (a 40 x 40
 * sheet of quads, rippling by 1 mm) fast: each step it moves 2.5 cm, farther than its own
 * thickness (1.4 cm), so at no frame does it
 * touch the membrane, and glcol_query_all says 0 pairs at every frame. The same motion as
 * simulator steps: each step gives glcollide the end of the step (the blade's next transform
 * as its target transform, the membrane's next positions as its target positions), asks
 * glcol_query_continuous, and, when something would be hit, advances every vertex only to a
 * fraction of the earliest toi (0.9 of it: no new contact) and stops the blade there, the
 * response a simulator would apply; glcol_query_impact_geometry tells where the first contact
 * happens (which vertex on which face, or which edges, and the normal). Prints both, step by
 * step.
 *
 *   make -C examples-c && examples-c/build/continuous_step [meshes_dir]
 */
#include <glcollide.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#define CHECK(call)                                                                     \
    do {                                                                                \
        GlcolStatus s_ = (call);                                                        \
        if (s_ != GLCOL_STATUS_OK) {                                                    \
            fprintf(stderr, "%s:%d: %s failed: %s: %s\n", __FILE__, __LINE__, #call,    \
                    glcol_status_name(s_), glcol_last_error_message());                 \
            exit(1);                                                                    \
        }                                                                               \
    } while (0)

#define N 40 /* membrane cells a side */
#define STEPS 4

/* The membrane at time `t` (in steps): a 10 x 25 cm wall at x = 0 with a 1 mm ripple. */
static void membrane(double t, double *xyz) {
    for (int j = 0; j <= N; j++)
        for (int i = 0; i <= N; i++) {
            double *p = xyz + 3 * (j * (N + 1) + i);
            p[0] = 0.1 * sin(0.3 * i + 0.2 * j + 0.5 * t);
            p[1] = -5.0 + 10.0 * i / N;
            p[2] = -5.0 + 25.0 * j / N;
        }
}

/* The blade's transform at offset x (a translation). */
static void blade_at(double x, double m[12]) {
    const double id[12] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0};
    for (int k = 0; k < 12; k++) m[k] = id[k];
    m[3] = x;
}

/* The membrane (an f64 mesh of quads, a simulator's state in doubles) at `xyz`, in `scene`. */
static GlcolMeshId add_membrane(GlcolScene *scene, const double *xyz, const uint32_t *quads) {
    GlcolMeshDesc md;
    glcol_mesh_desc_init(&md);
    md.positions_f64 = xyz;
    md.vertex_count = (N + 1) * (N + 1);
    md.indices = quads;
    md.polygon_count = N * N;
    md.vertices_per_polygon = 4;
    GlcolMeshId id;
    CHECK(glcol_mesh_create(scene, &md, &id));
    return id;
}

/* The blade, placed by the transform `m`, in `scene`. */
static GlcolMeshId add_blade(GlcolScene *scene, const GlcolObjMesh *obj, const double m[12]) {
    GlcolMeshDesc md;
    glcol_mesh_desc_init(&md);
    md.positions = obj->positions;
    md.vertex_count = obj->vertex_count;
    md.indices = obj->indices;
    md.polygon_count = obj->polygon_count;
    md.vertices_per_polygon = 3;
    GlcolMeshId id;
    CHECK(glcol_mesh_create(scene, &md, &id));
    CHECK(glcol_mesh_set_transform(scene, id, m));
    return id;
}

int main(int argc, char **argv) {
    const char *dir = argc > 1 ? argv[1] : "data";
    char path[4096];
    snprintf(path, sizeof path, "%s/scissors_blade.obj", dir);
    GlcolObjMesh blade_obj;
    CHECK(glcol_obj_load(path, &blade_obj));

    GlcolSceneDesc sd;
    glcol_scene_desc_init(&sd);
    sd.backend = GLCOL_BACKEND_CPU;
    GlcolScene *scene;
    CHECK(glcol_scene_create(&sd, &scene));

    /* The membrane: an f64 mesh of quads (a simulator's state in doubles). */
    static double now[3 * (N + 1) * (N + 1)], next[3 * (N + 1) * (N + 1)];
    static uint32_t quads[4 * N * N];
    for (int j = 0, q = 0; j < N; j++)
        for (int i = 0; i < N; i++, q += 4) {
            uint32_t v = (uint32_t)(j * (N + 1) + i);
            quads[q] = v, quads[q + 1] = v + 1, quads[q + 2] = v + N + 2, quads[q + 3] = v + N + 1;
        }
    membrane(0, now);
    GlcolMeshId sheet = add_membrane(scene, now, quads);

    /* The blade, placed by its transform, 3 cm in front of the membrane. */
    float lo = INFINITY;
    for (size_t v = 0; v < blade_obj.vertex_count; v++)
        lo = fminf(lo, blade_obj.positions[3 * v]);
    double x = 3.0 - lo, speed = 2.5; /* 2.5 cm a step: more than the blade is thick */
    double m[12], m_next[12];
    blade_at(x, m);
    GlcolMeshId blade = add_blade(scene, &blade_obj, m);

    printf("step | discrete pairs (start, end) | continuous pairs | earliest toi | advanced to\n");
    int stopped = 0;
    for (int step = 0; step < STEPS; step++) {
        const GlcolPair *pairs;
        size_t n_start, n_end;
        CHECK(glcol_query_all(scene, &pairs, &n_start));

        /* The end of the step: where the simulator would put everything. */
        membrane(step + 1, next);
        double x_next = stopped ? x : x - speed;
        blade_at(x_next, m_next);
        CHECK(glcol_mesh_set_target_positions_f64(scene, sheet, next, 0, (N + 1) * (N + 1), 0));
        CHECK(glcol_mesh_set_target_transform(scene, blade, m_next));
        const GlcolImpact *hits;
        size_t n_hits;
        CHECK(glcol_query_continuous(scene, &hits, &n_hits));
        double toi = 1.0;
        size_t first = 0;
        char where[256] = "";
        for (size_t k = 0; k < n_hits; k++)
            if (hits[k].toi < toi) toi = hits[k].toi, first = k;
        if (n_hits > 0) {
            /* Where the first contact happens: the features, their weights and the normal a
             * response pushes along (from b, the blade, towards a, the membrane). */
            const GlcolImpactGeometry *g;
            size_t n_g;
            CHECK(glcol_query_impact_geometry(scene, &g, &n_g));
            const char *kinds[] = {"none", "vertex-face", "face-vertex", "edge-edge"};
            snprintf(where, sizeof where, "     first contact: %s, membrane vertices %u %u %u, blade vertices %u %u %u, "
                   "normal (%.3f, %.3f, %.3f)\n",
                   kinds[g[first].kind], g[first].vertices_a[0], g[first].vertices_a[1],
                   g[first].vertices_a[2], g[first].vertices_b[0], g[first].vertices_b[1],
                   g[first].vertices_b[2], g[first].normal[0], g[first].normal[1],
                   g[first].normal[2]);
        }

        /* Advance to a fraction of the earliest toi (all of the step when nothing is hit):
         * every vertex to p0 + s (p1 - p0), which creates no new contact for s < toi. */
        double s = n_hits > 0 ? 0.9 * toi : 1.0;
        for (int k = 0; k < 3 * (N + 1) * (N + 1); k++) now[k] += s * (next[k] - now[k]);
        x += s * (x_next - x);
        blade_at(x, m);
        CHECK(glcol_mesh_update_positions_f64(scene, sheet, now, 0, (N + 1) * (N + 1), 0));
        CHECK(glcol_mesh_set_transform(scene, blade, m));
        if (n_hits > 0) stopped = 1; /* the response: the blade stops at the membrane */

        /* What a discrete check at the end of the unconstrained step would have seen. */
        GlcolScene *probe;
        CHECK(glcol_scene_create(&sd, &probe));
        add_blade(probe, &blade_obj, m_next);
        add_membrane(probe, next, quads);
        CHECK(glcol_query_all(probe, &pairs, &n_end));
        glcol_scene_destroy(probe);

        printf("%4d | %zu, %zu | %zu | %.6f | %.6f%s\n%s", step, n_start, n_end, n_hits,
               n_hits ? toi : 1.0, s, n_hits ? " (blade stopped)" : "", where);
    }
    glcol_scene_destroy(scene);

    /* The thickness a cloth simulator keeps: with no target, glcol_query_continuous at
     * epsilon e is a distance query (pairs within e / 2); glcol_query_all's band at the same
     * epsilon is the paper's viewing volume (each polygon thickened along its normal). The
     * blade stopped just in front of the membrane: pairs within 5 mm. */
    sd.epsilon = 1.0f; /* cm: e / 2 = 5 mm */
    GlcolScene *thick;
    CHECK(glcol_scene_create(&sd, &thick));
    add_membrane(thick, now, quads);
    add_blade(thick, &blade_obj, m);
    const GlcolImpact *near;
    const GlcolPair *vol;
    size_t n_near, n_vol;
    CHECK(glcol_query_continuous(thick, &near, &n_near));
    CHECK(glcol_query_all(thick, &vol, &n_vol));
    printf("thickness 5 mm, blade at rest: %zu pairs within 5 mm (glcol_query_continuous), %zu "
           "in the viewing volumes (glcol_query_all)\n", n_near, n_vol);
    glcol_scene_destroy(thick);
    glcol_obj_free(&blade_obj);
    if (!stopped) {
        fprintf(stderr, "continuous_step: the blade went through the membrane unseen\n");
        return 1;
    }
    return 0;
}
