/*
 * consumer: a C program built against an installed glcollide through pkg-config:
 *   cc consumer.c $(pkg-config --cflags --libs glcollide) -o consumer
 * Collides the two crossing squares of scene.h and prints the contacts (expected.txt).
 */
#include <glcollide.h>

#include <stdio.h>

#include "scene.h"

static int check(GlcolStatus s, const char *what) {
    if (s != GLCOL_STATUS_OK) {
        fprintf(stderr, "%s: %s: %s\n", what, glcol_status_name(s), glcol_last_error_message());
        return 0;
    }
    return 1;
}

int main(void) {
    if (glcol_abi_version() != GLCOL_ABI_VERSION) {
        fprintf(stderr, "header ABI %u, library ABI %u\n", (unsigned)GLCOL_ABI_VERSION,
                (unsigned)glcol_abi_version());
        return 1;
    }
    fprintf(stderr, "glcollide %s (ABI %u)\n", glcol_version(), (unsigned)glcol_abi_version());

    GlcolSceneDesc sd;
    glcol_scene_desc_init(&sd);
    sd.backend = GLCOL_BACKEND_CPU;
    sd.epsilon = 0.0f;
    GlcolScene *scene = NULL;
    if (!check(glcol_scene_create(&sd, &scene), "glcol_scene_create")) return 1;

    GlcolMeshDesc md;
    glcol_mesh_desc_init(&md);
    md.vertex_count = 4;
    md.indices = consumer_tris;
    md.polygon_count = 2;
    md.vertices_per_polygon = 3;
    GlcolMeshId a = 0, b = 0;
    md.positions = consumer_a_xyz;
    int ok = check(glcol_mesh_create(scene, &md, &a), "glcol_mesh_create(A)");
    md.positions = consumer_b_xyz;
    ok = ok && check(glcol_mesh_create(scene, &md, &b), "glcol_mesh_create(B)");

    const GlcolContact *c = NULL;
    size_t n = 0;
    ok = ok && check(glcol_query(scene, a, &c, &n), "glcol_query");
    if (ok) {
        printf("contacts %zu\n", n);
        for (size_t i = 0; i < n; i++) {
            if (c[i].other_mesh != b) {
                fprintf(stderr, "contact %zu names mesh %u, not B\n", i, (unsigned)c[i].other_mesh);
                ok = 0;
            }
            printf("contact %u %u\n", (unsigned)c[i].reference_polygon, (unsigned)c[i].other_polygon);
        }
    }
    glcol_scene_destroy(scene);
    return ok ? 0 : 1;
}
