/*
 * abi_v01: a program written against glcollide 0.1's header (examples-c/compat/
 * glcollide_v01.h, a verbatim copy of the 0.1 include/glcollide.h) must keep working with
 * the 0.1.1 library: its GlcolSceneDesc has no `threads` field, so its struct_size is 0.1's
 * size, which the library accepts with `threads` defaulted, and glcol_scene_desc_init
 * (the exported symbol) fills that size, no more. Creates a scene with the old struct, adds two meshes (the teapot, and a copy of it moved by a fraction of its size),
 * queries, and checks every status.
 *
 *   abi_v01 MESH_DIR      (e.g. data, the meshes bundled with the repository)
 */
#include "compat/glcollide_v01.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static int failures = 0;

static int check(GlcolStatus s, const char *what) {
    if (s != GLCOL_STATUS_OK) {
        printf("FAIL %s: %s (%s)\n", what, glcol_status_name(s), glcol_last_error_message());
        failures++;
        return 0;
    }
    return 1;
}

int main(int argc, char **argv) {
    const char *dir = argc > 1 ? argv[1] : "data";
    if (glcol_abi_version() != GLCOL_ABI_VERSION) {
        printf("FAIL abi version %u, the 0.1 header says %u\n", glcol_abi_version(), GLCOL_ABI_VERSION);
        return 1;
    }
    char path[4096];
    snprintf(path, sizeof path, "%s/teapot.obj", dir);
    GlcolObjMesh obj;
    memset(&obj, 0, sizeof obj);
    if (!check(glcol_obj_load(path, &obj), "obj_load")) return 1;

    /* glcol_scene_desc_init, as a 0.1 program calls it, with guard bytes behind the 0.1
       struct: it must write nothing past it and set 0.1's struct_size. */
    union {
        GlcolSceneDesc d;
        unsigned char room[sizeof(GlcolSceneDesc) + 64];
    } probe;
    memset(&probe, 0xA5, sizeof probe);
    glcol_scene_desc_init(&probe.d);
    for (size_t i = sizeof(GlcolSceneDesc); i < sizeof probe.room; i++)
        if (probe.room[i] != 0xA5) {
            printf("FAIL glcol_scene_desc_init wrote byte %zu of a %zu-byte 0.1 GlcolSceneDesc\n", i,
                   sizeof(GlcolSceneDesc));
            return 1;
        }
    if (probe.d.struct_size != sizeof(GlcolSceneDesc) || probe.d.backend != GLCOL_BACKEND_AUTO ||
        probe.d.get_proc_address != NULL || probe.d.epsilon != 0.0f) {
        printf("FAIL glcol_scene_desc_init: struct_size %u backend %d\n", probe.d.struct_size,
               (int)probe.d.backend);
        return 1;
    }
    GlcolSceneDesc sd = probe.d;
    sd.backend = GLCOL_BACKEND_CPU;
    GlcolScene *scene = NULL;
    if (!check(glcol_scene_create(&sd, &scene), "scene_create (0.1 GlcolSceneDesc)")) return 1;

    GlcolBackend b = GLCOL_BACKEND_AUTO;
    check(glcol_scene_backend(scene, &b), "scene_backend");
    if (b != GLCOL_BACKEND_CPU) {
        printf("FAIL backend %d, asked for CPU\n", (int)b);
        failures++;
    }

    /* The second copy: moved by a fifth of the teapot's x extent, so the two overlap. */
    float lo = obj.positions[0], hi = obj.positions[0];
    for (size_t i = 0; i < obj.vertex_count; i++) {
        float x = obj.positions[3 * i];
        lo = x < lo ? x : lo;
        hi = x > hi ? x : hi;
    }
    float *moved = malloc(obj.vertex_count * 3 * sizeof(float));
    if (!moved) return 1;
    for (size_t i = 0; i < obj.vertex_count * 3; i++)
        moved[i] = obj.positions[i] + (i % 3 == 0 ? (hi - lo) * 0.2f : 0.0f);

    GlcolMeshDesc md;
    glcol_mesh_desc_init(&md);
    md.positions = obj.positions;
    md.vertex_count = obj.vertex_count;
    md.indices = obj.indices;
    md.polygon_count = obj.polygon_count;
    md.vertices_per_polygon = 3;
    GlcolMeshId a = 0, c = 0;
    check(glcol_mesh_create(scene, &md, &a), "mesh_create a");
    md.positions = moved;
    check(glcol_mesh_create(scene, &md, &c), "mesh_create b");

    const GlcolContact *contacts = NULL;
    size_t n = 0;
    if (check(glcol_query(scene, a, &contacts, &n), "query")) {
        if (n == 0 || !contacts) {
            printf("FAIL the two overlapping teapots have no contacts\n");
            failures++;
        }
        for (size_t i = 0; i < n; i++) {
            if (contacts[i].other_mesh != c || contacts[i].reference_polygon >= obj.polygon_count ||
                contacts[i].other_polygon >= obj.polygon_count) {
                printf("FAIL contact %zu names mesh %u polygons %u, %u\n", i, contacts[i].other_mesh,
                       contacts[i].reference_polygon, contacts[i].other_polygon);
                failures++;
                break;
            }
        }
    }
    /* Moving b away: no contacts. */
    for (size_t i = 0; i < obj.vertex_count * 3; i++)
        moved[i] = obj.positions[i] + (i % 3 == 0 ? (hi - lo) * 2.0f : 0.0f);
    check(glcol_mesh_update_positions(scene, c, moved, 0, obj.vertex_count, 0), "update_positions");
    if (check(glcol_query(scene, a, &contacts, &n), "query after moving apart") && n != 0) {
        printf("FAIL %zu contacts after moving apart\n", n);
        failures++;
    }
    check(glcol_mesh_destroy(scene, c), "mesh_destroy");
    check(glcol_mesh_destroy(scene, a), "mesh_destroy");
    glcol_scene_destroy(scene);
    free(moved);
    glcol_obj_free(&obj);
    if (failures) {
        printf("abi_v01: %d failure(s)\n", failures);
        return 1;
    }
    printf("abi_v01: ok (library %s, 0.1 GlcolSceneDesc of %zu bytes accepted)\n", glcol_version(),
           sizeof(GlcolSceneDesc));
    return 0;
}
