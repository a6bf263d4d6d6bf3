// glcollide through its C API (include/glcollide.h), on the CPU backend or a GL backend (the
// caller supplies the GL loader: gl_context.cpp has a headless EGL one).
#include "common.hpp"

#include <stdexcept>

namespace peers {
namespace {

void check(GlcolStatus s, const char *what) {
    if (s != GLCOL_STATUS_OK)
        throw std::runtime_error(std::string(what) + ": " + glcol_status_name(s) + ": " + glcol_last_error_message());
}

struct GlcolImpl : GlcolEngine {
    int backend;
    float eps;
    uint32_t leaf;
    GlcolGetProcAddress get_proc;
    GlcolScene *scene = nullptr;
    GlcolMeshId ia = 0, ib = 0;
    size_t na = 0, nb = 0;

    GlcolImpl(int be, float e, uint32_t l, GlcolGetProcAddress gp) : backend(be), eps(e), leaf(l), get_proc(gp) {}
    ~GlcolImpl() override {
        if (scene) glcol_scene_destroy(scene);
    }
    std::string name() const override {
        switch (backend) {
        case GLCOL_BACKEND_GL_SELECT: return "glcollide_gl_select";
        case GLCOL_BACKEND_GL_COMPUTE: return "glcollide_gl_compute";
        default: return "glcollide";
        }
    }
    GlcolMeshId add(const Mesh &m, const std::vector<float> &v) {
        GlcolMeshDesc d;
        glcol_mesh_desc_init(&d);
        d.positions = v.data();
        d.vertex_count = m.nv();
        d.indices = m.poly.data();
        d.polygon_count = m.npoly();
        d.vertices_per_polygon = m.vpp;
        GlcolMeshId id = 0;
        check(glcol_mesh_create(scene, &d, &id), "glcol_mesh_create");
        return id;
    }
    void build(const Mesh &a, const Mesh &b, const Frame &f) override {
        GlcolSceneDesc d;
        glcol_scene_desc_init(&d);
        d.backend = GlcolBackend(backend);
        d.epsilon = eps;
        d.max_polygons_per_box = leaf; // 0: the library's rule of thumb
        d.threads = 1; // one thread, like every peer here (glcol_query shares out otherwise)
        if (backend != GLCOL_BACKEND_CPU) {
            if (!get_proc) throw std::runtime_error("no GL context");
            d.get_proc_address = get_proc;
        }
        check(glcol_scene_create(&d, &scene), "glcol_scene_create");
        ia = add(a, f.a);
        ib = add(b, f.b);
        na = a.nv();
        nb = b.nv();
    }
    void update(const Frame &f) override {
        check(glcol_mesh_update_positions(scene, ia, f.a.data(), 0, na, 0), "update a");
        check(glcol_mesh_update_positions(scene, ib, f.b.data(), 0, nb, 0), "update b");
    }
    // Pairs (polygon of A, polygon of B), asking with A (or, reversed, B) as the reference.
    void ask(std::vector<Key> &out, bool reversed) {
        const GlcolContact *c = nullptr;
        size_t n = 0;
        check(glcol_query(scene, reversed ? ib : ia, &c, &n), "glcol_query");
        out.clear();
        for (size_t i = 0; i < n; i++) {
            if (c[i].other_mesh != (reversed ? ia : ib)) continue;
            out.push_back(reversed ? key(c[i].other_polygon, c[i].reference_polygon)
                                   : key(c[i].reference_polygon, c[i].other_polygon));
        }
    }
    void query(std::vector<Key> &out) override { ask(out, false); }
    void query_from_b(std::vector<Key> &out) override { ask(out, true); }
    // The library has no memory accessor yet: the Rust bench (benches/parry.rs) counts it
    // from the structures; here nothing is claimed.
    size_t bytes() const override { return 0; }
};

} // namespace

GlcolEngine *make_glcol(int backend, float eps, uint32_t leaf, GlcolGetProcAddress get_proc) {
    return new GlcolImpl(backend, eps, leaf, get_proc);
}

} // namespace peers
