/* readme_example: the program README.md shows under "Use from C" (scripts/test.sh checks
 * that the two are identical, builds this with the warning flags of examples-c/Makefile
 * and runs it). */
#include <glcollide.h>

#include <stdio.h>

/* Every call that can fail returns a status: on failure, say which call and why. */
static int ok(GlcolStatus s, const char *call) {
    if (s != GLCOL_STATUS_OK)
        fprintf(stderr, "%s: %s: %s\n", call, glcol_status_name(s), glcol_last_error_message());
    return s == GLCOL_STATUS_OK;
}

/* Two unit squares of two triangles each: the organ lies in z = 0, the tool stands upright. */
static const float organ_xyz[] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
static const float tool_rest[] = {0.5f, 0.5f, -1, 0.5f, 0.5f, 1, 0.5f, -0.5f, 1, 0.5f, -0.5f, -1};
static const uint32_t square[] = {0, 1, 2, 0, 2, 3};

static int add_mesh(GlcolScene *scene, const float *xyz, GlcolMeshId *id) {
    GlcolMeshDesc md;
    glcol_mesh_desc_init(&md);
    md.positions = xyz; md.vertex_count = 4; /* copied, like the indices */
    md.indices = square; md.polygon_count = 2; md.vertices_per_polygon = 3;
    return ok(glcol_mesh_create(scene, &md, id), "glcol_mesh_create");
}

int main(void) {
    if (glcol_abi_version() != GLCOL_ABI_VERSION) return 1; /* library and header differ */
    GlcolSceneDesc sd;
    glcol_scene_desc_init(&sd); /* AUTO backend (the CPU: no GL loader), epsilon 0 = exact */
    GlcolScene *scene = NULL;
    if (!ok(glcol_scene_create(&sd, &scene), "glcol_scene_create")) return 1;
    GlcolMeshId organ, tool;
    int good = add_mesh(scene, organ_xyz, &organ) && add_mesh(scene, tool_rest, &tool);
    for (int frame = 0; good && frame < 3; frame++) { /* the simulation loop */
        float xyz[12]; /* this frame's tool: 0.5 further along x */
        for (int i = 0; i < 12; i++) xyz[i] = tool_rest[i] + (i % 3 ? 0.0f : 0.5f * (float)frame);
        const GlcolContact *c = NULL;
        size_t n = 0;
        good = ok(glcol_mesh_update_positions(scene, tool, xyz, 0, 4, 0), "update_positions") &&
               ok(glcol_query(scene, tool, &c, &n), "glcol_query");
        if (good) printf("frame %d: %zu contacts\n", frame, n);
        for (size_t i = 0; good && i < n; i++) /* c[] lives until the scene's next change */
            printf("  tool polygon %u touches polygon %u of mesh %u\n",
                   (unsigned)c[i].reference_polygon, (unsigned)c[i].other_polygon,
                   (unsigned)c[i].other_mesh);
    }
    glcol_scene_destroy(scene);
    return good ? 0 : 1;
}
