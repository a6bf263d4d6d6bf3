/*
 * api_errors: provokes each status code of the C API with bad input and checks that the
 * call said so, left a message naming the problem, and changed nothing: the same query
 * gives the same contacts before and after every rejected call.
 */
#include <glcollide.h>

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static int failures = 0, checks = 0;

static void expect(GlcolStatus got, GlcolStatus want, const char *needle, const char *what) {
    checks++;
    const char *msg = glcol_last_error_message();
    if (got != want) {
        printf("FAIL %s: got %s, want %s (%s)\n", what, glcol_status_name(got), glcol_status_name(want), msg);
        failures++;
    } else if (want != GLCOL_STATUS_OK && needle && !strstr(msg, needle)) {
        printf("FAIL %s: message \"%s\" does not mention \"%s\"\n", what, msg, needle);
        failures++;
    }
}

/* Every status with its name as the header spells it: glcol_status_name must answer it. */
#define STATUS(s) {s, #s}
static const struct {
    GlcolStatus status;
    const char *name;
} status_names[] = {
    STATUS(GLCOL_STATUS_OK),
    STATUS(GLCOL_STATUS_NULL_POINTER),
    STATUS(GLCOL_STATUS_INVALID_ARGUMENT),
    STATUS(GLCOL_STATUS_NON_FINITE),
    STATUS(GLCOL_STATUS_INDEX_OUT_OF_RANGE),
    STATUS(GLCOL_STATUS_UNKNOWN_MESH),
    STATUS(GLCOL_STATUS_GL_UNAVAILABLE),
    STATUS(GLCOL_STATUS_GL_ERROR),
    STATUS(GLCOL_STATUS_UNSUPPORTED),
    STATUS(GLCOL_STATUS_OUT_OF_MEMORY),
    STATUS(GLCOL_STATUS_INTERNAL),
};

/* Two unit quads (as 2 triangles each) crossing each other: 4 vertices per quad. */
static float pa[12] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
static float pb[12] = {0.5f, 0.5f, -1, 0.5f, 0.5f, 1, 0.5f, -0.5f, 1, 0.5f, -0.5f, -1};
static uint32_t tris[6] = {0, 1, 2, 0, 2, 3};

static size_t snapshot(GlcolScene *s, GlcolMeshId ref, GlcolContact *out, size_t cap) {
    const GlcolContact *c = NULL;
    size_t n = 0;
    if (glcol_query(s, ref, &c, &n) != GLCOL_STATUS_OK) {
        printf("FAIL snapshot query: %s\n", glcol_last_error_message());
        failures++;
        return 0;
    }
    if (n > cap) n = cap;
    if (n) memcpy(out, c, n * sizeof *c);
    return n;
}

int main(void) {
    GlcolSceneDesc sd;
    glcol_scene_desc_init(&sd);
    GlcolScene *scene = NULL;

    /* Scene creation. */
    expect(glcol_scene_create(NULL, &scene), GLCOL_STATUS_NULL_POINTER, "desc", "create(NULL desc)");
    expect(glcol_scene_create(&sd, NULL), GLCOL_STATUS_NULL_POINTER, "out_scene", "create(NULL out)");
    sd.struct_size = 4;
    expect(glcol_scene_create(&sd, &scene), GLCOL_STATUS_INVALID_ARGUMENT, "struct_size", "create(struct_size)");
    glcol_scene_desc_init(&sd);
    sd.epsilon = -1.0f;
    expect(glcol_scene_create(&sd, &scene), GLCOL_STATUS_INVALID_ARGUMENT, "epsilon", "create(epsilon < 0)");
    sd.epsilon = NAN;
    expect(glcol_scene_create(&sd, &scene), GLCOL_STATUS_INVALID_ARGUMENT, "epsilon", "create(epsilon NaN)");
    glcol_scene_desc_init(&sd);
    sd.backend = (GlcolBackend)7;
    expect(glcol_scene_create(&sd, &scene), GLCOL_STATUS_INVALID_ARGUMENT, "backend", "create(backend 7)");
    sd.backend = GLCOL_BACKEND_GL_COMPUTE;
    expect(glcol_scene_create(&sd, &scene), GLCOL_STATUS_GL_UNAVAILABLE, "get_proc_address", "create(GL, no loader)");
    if (scene != NULL) {
        printf("FAIL a failed create wrote *out_scene\n");
        failures++;
    }
    glcol_scene_desc_init(&sd);
    expect(glcol_scene_create(&sd, &scene), GLCOL_STATUS_OK, NULL, "create");
    GlcolBackend b = GLCOL_BACKEND_GL_SELECT;
    expect(glcol_scene_backend(scene, &b), GLCOL_STATUS_OK, NULL, "backend");
    if (b != GLCOL_BACKEND_CPU) {
        printf("FAIL AUTO without a loader chose %d, not CPU\n", (int)b);
        failures++;
    }
    expect(glcol_scene_backend(NULL, &b), GLCOL_STATUS_NULL_POINTER, "scene", "backend(NULL)");

    /* Meshes. */
    GlcolMeshDesc md;
    glcol_mesh_desc_init(&md);
    md.positions = pa;
    md.vertex_count = 4;
    md.indices = tris;
    md.polygon_count = 2;
    GlcolMeshId a = 0, bb = 0, junk = 12345;
    expect(glcol_mesh_create(scene, &md, &a), GLCOL_STATUS_OK, NULL, "mesh a");
    md.positions = pb;
    expect(glcol_mesh_create(scene, &md, &bb), GLCOL_STATUS_OK, NULL, "mesh b");

    GlcolContact before[16], after[16];
    size_t n0 = snapshot(scene, a, before, 16);
    if (n0 == 0) {
        printf("FAIL the crossing quads do not collide\n");
        failures++;
    }

    GlcolMeshDesc bad = md;
    expect(glcol_mesh_create(NULL, &md, &junk), GLCOL_STATUS_NULL_POINTER, "scene", "mesh_create(NULL scene)");
    expect(glcol_mesh_create(scene, NULL, &junk), GLCOL_STATUS_NULL_POINTER, "desc", "mesh_create(NULL desc)");
    expect(glcol_mesh_create(scene, &md, NULL), GLCOL_STATUS_NULL_POINTER, "out_id", "mesh_create(NULL out)");
    bad.positions = NULL; /* neither positions nor positions_f64 */
    expect(glcol_mesh_create(scene, &bad, &junk), GLCOL_STATUS_INVALID_ARGUMENT, "positions_f64", "mesh_create(no positions)");
    bad = md;
    bad.indices = NULL;
    expect(glcol_mesh_create(scene, &bad, &junk), GLCOL_STATUS_NULL_POINTER, "indices", "mesh_create(NULL indices)");
    bad = md;
    bad.struct_size = 0;
    expect(glcol_mesh_create(scene, &bad, &junk), GLCOL_STATUS_INVALID_ARGUMENT, "struct_size", "mesh_create(struct_size)");
    bad = md;
    bad.vertex_count = 0;
    expect(glcol_mesh_create(scene, &bad, &junk), GLCOL_STATUS_INVALID_ARGUMENT, "vertex_count", "mesh_create(0 vertices)");
    bad = md;
    bad.polygon_count = 0;
    expect(glcol_mesh_create(scene, &bad, &junk), GLCOL_STATUS_INVALID_ARGUMENT, "polygon_count", "mesh_create(0 polygons)");
    bad = md;
    bad.vertices_per_polygon = 5;
    expect(glcol_mesh_create(scene, &bad, &junk), GLCOL_STATUS_INVALID_ARGUMENT, "vertices_per_polygon", "mesh_create(k=5)");
    bad = md;
    bad.position_stride = 8;
    expect(glcol_mesh_create(scene, &bad, &junk), GLCOL_STATUS_INVALID_ARGUMENT, "stride", "mesh_create(stride 8)");
    bad.position_stride = 14;
    expect(glcol_mesh_create(scene, &bad, &junk), GLCOL_STATUS_INVALID_ARGUMENT, "stride", "mesh_create(stride 14)");
    bad = md;
    bad.positions = (const float *)((const char *)pb + 2);
    expect(glcol_mesh_create(scene, &bad, &junk), GLCOL_STATUS_INVALID_ARGUMENT, "aligned", "mesh_create(misaligned)");
    bad = md;
    bad.vertex_count = SIZE_MAX / 4;
    bad.position_stride = 64;
    expect(glcol_mesh_create(scene, &bad, &junk), GLCOL_STATUS_INVALID_ARGUMENT, "overflow", "mesh_create(count*stride overflow)");
    bad = md;
    bad.polygon_count = SIZE_MAX / 2;
    expect(glcol_mesh_create(scene, &bad, &junk), GLCOL_STATUS_INVALID_ARGUMENT, "overflow", "mesh_create(polygon overflow)");
#if SIZE_MAX > UINT32_MAX
    /* The vertex limit, 2^32 - 1: one above is refused as a count; at the limit the count
       passes and the bad stride checked next is what is refused (no array is read). */
    bad = md;
    bad.vertex_count = (size_t)UINT32_MAX + 1;
    bad.position_stride = 4;
    expect(glcol_mesh_create(scene, &bad, &junk), GLCOL_STATUS_INVALID_ARGUMENT, "vertex_count", "mesh_create(2^32 vertices)");
    bad.vertex_count = UINT32_MAX;
    expect(glcol_mesh_create(scene, &bad, &junk), GLCOL_STATUS_INVALID_ARGUMENT, "position_stride", "mesh_create(2^32 - 1 vertices)");
#endif
    uint32_t oob[6] = {0, 1, 2, 0, 2, 9};
    bad = md;
    bad.indices = oob;
    expect(glcol_mesh_create(scene, &bad, &junk), GLCOL_STATUS_INDEX_OUT_OF_RANGE, "vertex 9", "mesh_create(index 9)");
    float nanpos[12];
    memcpy(nanpos, pb, sizeof nanpos);
    nanpos[7] = INFINITY;
    bad = md;
    bad.positions = nanpos;
    expect(glcol_mesh_create(scene, &bad, &junk), GLCOL_STATUS_NON_FINITE, "vertex 2", "mesh_create(inf)");
    if (junk != 12345) {
        printf("FAIL a failed mesh_create wrote *out_id\n");
        failures++;
    }

    /* Updates. */
    expect(glcol_mesh_update_positions(NULL, a, pa, 0, 4, 0), GLCOL_STATUS_NULL_POINTER, "scene", "update(NULL scene)");
    expect(glcol_mesh_update_positions(scene, 999, pa, 0, 4, 0), GLCOL_STATUS_UNKNOWN_MESH, "999", "update(unknown)");
    expect(glcol_mesh_update_positions(scene, a, NULL, 0, 4, 0), GLCOL_STATUS_NULL_POINTER, "positions", "update(NULL)");
    expect(glcol_mesh_update_positions(scene, a, pa, 0, 0, 0), GLCOL_STATUS_INVALID_ARGUMENT, "vertex_count", "update(0)");
    expect(glcol_mesh_update_positions(scene, a, pa, 2, 4, 0), GLCOL_STATUS_INVALID_ARGUMENT, "past", "update(past end)");
    expect(glcol_mesh_update_positions(scene, a, pa, SIZE_MAX, 2, 0), GLCOL_STATUS_INVALID_ARGUMENT, "past", "update(first overflow)");
    expect(glcol_mesh_update_positions(scene, a, pa, 0, 4, 4), GLCOL_STATUS_INVALID_ARGUMENT, "stride", "update(stride 4)");
    float moved[12];
    for (int i = 0; i < 12; i++) moved[i] = pa[i] + 10.0f; /* would end all contacts */
    moved[11] = NAN;
    expect(glcol_mesh_update_positions(scene, a, moved, 0, 4, 0), GLCOL_STATUS_NON_FINITE, "vertex 3", "update(NaN)");
    expect(glcol_mesh_update_positions(scene, a, moved + 9, 3, 1, 0), GLCOL_STATUS_NON_FINITE, "vertex 3", "update(range NaN)");

    /* Transforms: a NaN entry, world positions past the float range, an unknown mesh, a NULL
       scene; a NULL matrix is the identity. */
    double m[12] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0};
    m[5] = NAN;
    expect(glcol_mesh_set_transform(scene, a, m), GLCOL_STATUS_NON_FINITE, "m[5]", "set_transform(NaN)");
    m[5] = 1;
    m[3] = 1e300;
    expect(glcol_mesh_set_transform(scene, a, m), GLCOL_STATUS_NON_FINITE, "float range", "set_transform(overflow)");
    m[3] = 0;
    expect(glcol_mesh_set_transform(scene, 999, m), GLCOL_STATUS_UNKNOWN_MESH, "999", "set_transform(unknown)");
    expect(glcol_mesh_set_transform(NULL, a, m), GLCOL_STATUS_NULL_POINTER, "scene", "set_transform(NULL scene)");
    expect(glcol_mesh_set_transform(scene, a, NULL), GLCOL_STATUS_OK, NULL, "set_transform(NULL m)");

    /* f64 meshes: both kinds of positions or neither, a double beyond the float range, a NaN,
       a stride below 24, each update call for the other kind of mesh, binding to a GL buffer. */
    static double da[12] = {0, 0, 0.5, 1, 0, 0.5, 1, 1, 0.5, 0, 1, 0.5};
    GlcolMeshDesc md64;
    glcol_mesh_desc_init(&md64);
    md64.positions_f64 = da;
    md64.vertex_count = 4;
    md64.indices = tris;
    md64.polygon_count = 2;
    bad = md64;
    bad.positions = pa;
    expect(glcol_mesh_create(scene, &bad, &junk), GLCOL_STATUS_INVALID_ARGUMENT, "positions_f64", "mesh_create(both positions)");
    double dbad[12];
    memcpy(dbad, da, sizeof dbad);
    dbad[4] = 1e39;
    bad.positions = NULL;
    bad.positions_f64 = dbad;
    expect(glcol_mesh_create(scene, &bad, &junk), GLCOL_STATUS_NON_FINITE, "float range", "mesh_create(1e39)");
    dbad[4] = NAN;
    expect(glcol_mesh_create(scene, &bad, &junk), GLCOL_STATUS_NON_FINITE, "vertex 1", "mesh_create(f64 NaN)");
    bad = md64;
    bad.position_stride = 12;
    expect(glcol_mesh_create(scene, &bad, &junk), GLCOL_STATUS_INVALID_ARGUMENT, "stride", "mesh_create(f64 stride 12)");
    GlcolMeshId d64 = 0;
    expect(glcol_mesh_create(scene, &md64, &d64), GLCOL_STATUS_OK, NULL, "f64 mesh");
    expect(glcol_mesh_set_enabled(scene, d64, false), GLCOL_STATUS_OK, NULL, "disable the f64 mesh");
    expect(glcol_mesh_update_positions(scene, d64, pa, 0, 4, 0), GLCOL_STATUS_INVALID_ARGUMENT, "_f64", "update(float call, f64 mesh)");
    expect(glcol_mesh_update_positions_f64(scene, a, da, 0, 4, 0), GLCOL_STATUS_INVALID_ARGUMENT, "float mesh", "update_f64(float mesh)");
    expect(glcol_mesh_update_positions_f64(scene, d64, NULL, 0, 4, 0), GLCOL_STATUS_NULL_POINTER, "positions", "update_f64(NULL)");
    expect(glcol_mesh_update_positions_f64(scene, 999, da, 0, 4, 0), GLCOL_STATUS_UNKNOWN_MESH, "999", "update_f64(unknown)");
    expect(glcol_mesh_update_positions_f64(scene, d64, da, 1, 4, 0), GLCOL_STATUS_INVALID_ARGUMENT, "past", "update_f64(past end)");
    expect(glcol_mesh_update_positions_f64(scene, d64, dbad, 0, 4, 0), GLCOL_STATUS_NON_FINITE, "vertex 1", "update_f64(NaN)");
    expect(glcol_mesh_bind_gl_buffer(scene, d64, 1, 0, 12), GLCOL_STATUS_UNSUPPORTED, "f64 mesh", "bind_gl_buffer(f64 mesh)");

    /* Targets: each call rejected whole (a range past the end, a NaN, the wrong precision, an
       unknown mesh, NULL, an overflowing end transform). */
    expect(glcol_mesh_set_target_positions(scene, a, moved, 0, 4, 0), GLCOL_STATUS_NON_FINITE, "vertex 3", "target(NaN)");
    expect(glcol_mesh_set_target_positions(scene, a, pa, 3, 2, 0), GLCOL_STATUS_INVALID_ARGUMENT, "past", "target(past end)");
    expect(glcol_mesh_set_target_positions(scene, a, NULL, 0, 1, 0), GLCOL_STATUS_NULL_POINTER, "positions", "target(NULL)");
    expect(glcol_mesh_set_target_positions(scene, 999, pa, 0, 1, 0), GLCOL_STATUS_UNKNOWN_MESH, "999", "target(unknown)");
    expect(glcol_mesh_set_target_positions(scene, d64, pa, 0, 1, 0), GLCOL_STATUS_INVALID_ARGUMENT, "_f64", "target(float call, f64 mesh)");
    expect(glcol_mesh_set_target_positions_f64(scene, a, da, 0, 1, 0), GLCOL_STATUS_INVALID_ARGUMENT, "float mesh", "target_f64(float mesh)");
    dbad[4] = -1e39;
    expect(glcol_mesh_set_target_positions_f64(scene, d64, dbad, 0, 4, 0), GLCOL_STATUS_NON_FINITE, "float range", "target_f64(1e39)");
    expect(glcol_mesh_set_target_positions(scene, a, moved, 0, 3, 0), GLCOL_STATUS_OK, NULL, "target");
    expect(glcol_mesh_set_target_positions_f64(scene, d64, da, 1, 2, 0), GLCOL_STATUS_OK, NULL, "target_f64");
    double tm[12] = {1, 0, 0, 0.5, 0, 1, 0, 0, 0, 0, 1, 0};
    expect(glcol_mesh_set_target_transform(scene, a, NULL), GLCOL_STATUS_NULL_POINTER, "m", "target_transform(NULL)");
    tm[0] = 1e39;
    expect(glcol_mesh_set_target_transform(scene, a, tm), GLCOL_STATUS_NON_FINITE, "float range", "target_transform(overflow)");
    tm[0] = INFINITY;
    expect(glcol_mesh_set_target_transform(scene, a, tm), GLCOL_STATUS_NON_FINITE, "m[0]", "target_transform(inf)");
    tm[0] = 1;
    expect(glcol_mesh_set_target_transform(scene, 999, tm), GLCOL_STATUS_UNKNOWN_MESH, "999", "target_transform(unknown)");
    expect(glcol_mesh_set_target_transform(scene, a, tm), GLCOL_STATUS_OK, NULL, "target_transform");
    expect(glcol_mesh_clear_target(scene, 999), GLCOL_STATUS_UNKNOWN_MESH, "999", "clear_target(unknown)");
    expect(glcol_mesh_clear_target(NULL, a), GLCOL_STATUS_NULL_POINTER, "scene", "clear_target(NULL)");
    expect(glcol_mesh_clear_target(scene, a), GLCOL_STATUS_OK, NULL, "clear_target");
    expect(glcol_mesh_desc_init_sized(&md64, 3), GLCOL_STATUS_INVALID_ARGUMENT, "sizeof(GlcolMeshDesc)", "desc_init_sized(3)");

    /* Enable, destroy, query, bind. */
    expect(glcol_mesh_set_enabled(scene, 0, false), GLCOL_STATUS_UNKNOWN_MESH, "0", "set_enabled(id 0)");
    expect(glcol_mesh_set_enabled(NULL, a, false), GLCOL_STATUS_NULL_POINTER, "scene", "set_enabled(NULL)");
    expect(glcol_mesh_destroy(scene, 777), GLCOL_STATUS_UNKNOWN_MESH, "777", "destroy(unknown)");
    const GlcolContact *c = NULL;
    size_t n = 0;
    expect(glcol_query(scene, 42, &c, &n), GLCOL_STATUS_UNKNOWN_MESH, "42", "query(unknown)");
    expect(glcol_query(scene, a, NULL, &n), GLCOL_STATUS_NULL_POINTER, "out_contacts", "query(NULL out)");
    expect(glcol_query(scene, a, &c, NULL), GLCOL_STATUS_NULL_POINTER, "out_count", "query(NULL count)");
    expect(glcol_mesh_bind_gl_buffer(scene, a, 1, 0, 12), GLCOL_STATUS_UNSUPPORTED, "GL_COMPUTE", "bind_gl_buffer(CPU)");

    size_t n1 = snapshot(scene, a, after, 16);
    if (n1 != n0 || memcmp(before, after, n0 * sizeof *before) != 0) {
        printf("FAIL rejected calls changed the scene: %zu contacts before, %zu after\n", n0, n1);
        failures++;
    }

    /* A destroyed mesh is gone for good, and its id is not reused. */
    expect(glcol_mesh_destroy(scene, bb), GLCOL_STATUS_OK, NULL, "destroy b");
    expect(glcol_mesh_destroy(scene, bb), GLCOL_STATUS_UNKNOWN_MESH, "not in this scene", "destroy b twice");
    GlcolMeshId again = 0;
    expect(glcol_mesh_create(scene, &md, &again), GLCOL_STATUS_OK, NULL, "mesh again");
    if (again == bb || again == a) {
        printf("FAIL mesh id %u was reused\n", again);
        failures++;
    }
    expect(glcol_query(scene, a, &c, &n), GLCOL_STATUS_OK, NULL, "query after");
    if (n != n0) {
        printf("FAIL re-created mesh gives %zu contacts, not %zu\n", n, n0);
        failures++;
    }
    /* Each status's name is the header's identifier. */
    for (int i = 0; i < (int)(sizeof status_names / sizeof *status_names); i++) {
        checks++;
        const char *got = glcol_status_name(status_names[i].status);
        if (!got || strcmp(got, status_names[i].name) != 0) {
            printf("FAIL status_name(%d) is %s, not %s\n", (int)status_names[i].status, got ? got : "NULL",
                   status_names[i].name);
            failures++;
        }
    }
    const char *unknown = glcol_status_name((GlcolStatus)99);
    if (!unknown || strcmp(unknown, "GLCOL_STATUS_UNKNOWN") != 0) {
        printf("FAIL status_name(99)\n");
        failures++;
    }
    glcol_scene_destroy(scene);
    glcol_scene_destroy(NULL);
    glcol_obj_free(NULL);
    GlcolObjMesh om;
    expect(glcol_obj_load("/nonexistent.obj", &om), GLCOL_STATUS_INVALID_ARGUMENT, "nonexistent", "obj_load(missing)");
    expect(glcol_obj_load(NULL, &om), GLCOL_STATUS_NULL_POINTER, "path", "obj_load(NULL)");

    printf("%d passed, %d failed\n", checks - failures, failures);
    return failures ? 1 : 0;
}
