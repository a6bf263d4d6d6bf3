/* readme_example: the program README.md shows under "Use from C" (scripts/test.sh checks
 * that the two are identical, builds this with the warning flags of examples-c/Makefile
 * and runs it). */
#include <glcollide.h>
#include <stdio.h>

/* Two unit squares of two triangles each: the organ lies in z = 0, the tool stands upright. */
static const float organ[] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
static const float tool[] = {0.5f, 0.5f, -1, 0.5f, 0.5f, 1, 0.5f, -0.5f, 1, 0.5f, -0.5f, -1};
static const uint32_t square[] = {0, 1, 2, 0, 2, 3};

static GlcolStatus add(GlcolScene *scene, const float *xyz, GlcolMeshId *id) {
    GlcolMeshDesc md;
    glcol_mesh_desc_init(&md); /* triangles; positions and indices are copied */
    md.positions = xyz; md.vertex_count = 4; md.indices = square; md.polygon_count = 2;
    return glcol_mesh_create(scene, &md, id);
}

int main(void) {
    GlcolSceneDesc sd;
    glcol_scene_desc_init(&sd); /* AUTO backend (the CPU: no GL loader), epsilon 0 = exact */
    GlcolScene *scene = NULL; GlcolMeshId organ_id, tool_id;
    GlcolStatus s = glcol_scene_create(&sd, &scene); /* GLCOL_STATUS_OK is 0 */
    if (!s) s = add(scene, organ, &organ_id);
    if (!s) s = add(scene, tool, &tool_id);
    for (int frame = 0; !s && frame < 3; frame++) { /* the simulation loop */
        float xyz[12]; /* this frame's tool: 0.5 further along x */
        for (int i = 0; i < 12; i++) xyz[i] = tool[i] + (i % 3 ? 0.0f : 0.5f * (float)frame);
        const GlcolContact *c = NULL; size_t n = 0;
        s = glcol_mesh_update_positions(scene, tool_id, xyz, 0, 4, 0);
        if (!s) s = glcol_query(scene, tool_id, &c, &n); /* c[] lives until the next change */
        for (size_t i = 0; !s && i < n; i++)
            printf("frame %d: tool polygon %u touches organ polygon %u\n", frame,
                   (unsigned)c[i].reference_polygon, (unsigned)c[i].other_polygon);
    }
    if (s) fprintf(stderr, "%s: %s\n", glcol_status_name(s), glcol_last_error_message());
    glcol_scene_destroy(scene); /* NULL is fine */
    return s != GLCOL_STATUS_OK;
}
