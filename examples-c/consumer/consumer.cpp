// consumer: a C++ program built against an installed glcollide through CMake
// (find_package(glcollide 0.1 REQUIRED), target glcollide::glcollide; see CMakeLists.txt).
// Collides the two crossing squares of scene.h and prints the contacts (expected.txt).
#include <glcollide.h>

#include <cstdio>
#include <memory>
#include <stdexcept>
#include <string>

#include "scene.h"

namespace {

void check(GlcolStatus s, const char *what) {
    if (s != GLCOL_STATUS_OK)
        throw std::runtime_error(std::string(what) + ": " + glcol_status_name(s) + ": " +
                                 glcol_last_error_message());
}

struct SceneDeleter {
    void operator()(GlcolScene *s) const { glcol_scene_destroy(s); }
};
using ScenePtr = std::unique_ptr<GlcolScene, SceneDeleter>;

GlcolMeshId add_mesh(GlcolScene *scene, const float *xyz) {
    GlcolMeshDesc md;
    glcol_mesh_desc_init(&md);
    md.positions = xyz;
    md.vertex_count = 4;
    md.indices = consumer_tris;
    md.polygon_count = 2;
    md.vertices_per_polygon = 3;
    GlcolMeshId id = 0;
    check(glcol_mesh_create(scene, &md, &id), "glcol_mesh_create");
    return id;
}

}  // namespace

int main() try {
    static_assert(GLCOL_ABI_VERSION >= 1, "header without an ABI version");
    if (glcol_abi_version() != GLCOL_ABI_VERSION)
        throw std::runtime_error("header and library ABI versions differ");
    std::fprintf(stderr, "glcollide %s (ABI %u)\n", glcol_version(), glcol_abi_version());

    GlcolSceneDesc sd;
    glcol_scene_desc_init(&sd);
    sd.backend = GLCOL_BACKEND_CPU;
    sd.epsilon = 0.0f;
    GlcolScene *raw = nullptr;
    check(glcol_scene_create(&sd, &raw), "glcol_scene_create");
    ScenePtr scene(raw);

    GlcolMeshId a = add_mesh(scene.get(), consumer_a_xyz);
    GlcolMeshId b = add_mesh(scene.get(), consumer_b_xyz);
    const GlcolContact *c = nullptr;
    size_t n = 0;
    check(glcol_query(scene.get(), a, &c, &n), "glcol_query");
    std::printf("contacts %zu\n", n);
    for (size_t i = 0; i < n; i++) {
        if (c[i].other_mesh != b) throw std::runtime_error("contact with a mesh other than B");
        std::printf("contact %u %u\n", c[i].reference_polygon, c[i].other_polygon);
    }
    return 0;
} catch (const std::exception &e) {
    std::fprintf(stderr, "consumer: %s\n", e.what());
    return 1;
}
