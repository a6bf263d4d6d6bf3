// The peer harness (README.md beside this file): the types both drivers share, the engines'
// interface and the exact judge. No peer or CGAL headers here, so each library's heavy
// headers stay in its own .cpp.
#pragma once

#include <glcollide.h>

#include <chrono>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace peers {

// A mesh as glcollide sees it (polygons, 3 or 4 vertices each) and as the peers see it
// (triangles). Quad q = (v0,v1,v2,v3) becomes triangles 2q = (v0,v1,v2) and
// 2q+1 = (v0,v2,v3), the split glcollide documents, so tri_poly[t] = t / 2; for a triangle
// mesh tri == poly and tri_poly[t] = t.
struct Mesh {
    std::string name;
    std::vector<double> rest;       // x, y, z per vertex, rest pose, local frame
    std::vector<uint32_t> poly;     // vpp indices per polygon (glcollide)
    uint32_t vpp = 3;               // vertices per polygon: 3 or 4
    std::vector<uint32_t> tri;      // 3 indices per triangle (peers, exact reference)
    std::vector<uint32_t> tri_poly; // triangle -> polygon

    size_t nv() const { return rest.size() / 3; }
    size_t npoly() const { return poly.size() / vpp; }
    size_t ntri() const { return tri.size() / 3; }
    void split_polygons();          // fills tri and tri_poly from poly
};

// A pair (polygon or triangle of A, polygon or triangle of B) packed in 64 bits: sorting keys
// sorts the pairs by A, then B.
using Key = uint64_t;
inline Key key(uint32_t a, uint32_t b) { return (uint64_t(a) << 32) | b; }
inline uint32_t key_a(Key k) { return uint32_t(k >> 32); }
inline uint32_t key_b(Key k) { return uint32_t(k); }
void sort_unique(std::vector<Key> &v);

// One frame's positions of both meshes, computed in double and rounded to float (what
// glcollide takes), and those floats widened back to double (what FCL, Bullet, Embree and
// CGAL take), so every library sees exactly the same coordinates.
struct Frame {
    std::vector<float> a, b;
    std::vector<double> ad, bd;
};

inline double now_us() {
    using namespace std::chrono;
    return duration<double, std::micro>(steady_clock::now().time_since_epoch()).count();
}
struct Timer {
    double t0 = now_us();
    double us() const { return now_us() - t0; }
};
// The median (mean of the two middle values for an even count); NaN for none.
double median(std::vector<double> v);

// ---- engines: one library each, on two meshes A (the reference) and B ----------------
struct Engine {
    virtual ~Engine() {}
    virtual std::string name() const = 0;
    // Builds the library's structures for the meshes at frame f0.
    virtual void build(const Mesh &a, const Mesh &b, const Frame &f0) = 0;
    // Hands a frame's positions to the library the way it reads them (its own type, or the
    // caller's array in place); the benchmark does not time it.
    virtual void prepare(const Frame &) {}
    // The library's update calls for both meshes after their vertices changed (after prepare).
    virtual void update(const Frame &f) = 0;
    // The collision query and whatever narrow phase gives the exact pair list: pairs
    // (A, B), unsorted, of triangles (the peers) or of polygons (glcollide).
    virtual void query(std::vector<Key> &out) = 0;
    // Bytes of the structures the library holds for the two meshes (memory_note says what).
    virtual size_t bytes() const = 0;
    virtual std::string memory_note() const { return ""; }
};

// FCL 0.7: BVHModel<AABBd>, refit bottom-up, all contacts (fcl_engine.cpp).
Engine *make_fcl();

// Bullet 3.24 (double): GImpact quantized BVH, refit, find_collision + the exact test
// (bullet_engine.cpp).
struct BulletEngine : Engine {
    // GImpact's own triangle test (margin 0) on the last query's candidates: triangle pairs.
    virtual void native(std::vector<Key> &out) = 0;
    // With the rebuild guard: how many times a mesh was rebuilt because it left its 16-bit
    // quantization frame; without: how many times a mesh was out of it (refit only).
    virtual int rebuilds() const = 0;
};
// margin_a, margin_b: GImpact's margin per mesh; 0 = one quantum of the mesh's own frame at
// build. rebuild_guard: rebuild instead of refit when a mesh leaves its quantization frame.
BulletEngine *make_bullet(double margin_a, double margin_b, bool rebuild_guard);

// Embree 3.13: rtcCollide on REFIT user geometry + the exact test (embree_engine.cpp).
Engine *make_embree();

// glcollide through its C API (glcol_engine.cpp). backend: a GlcolBackend value; the GL
// backends load their entry points through get_proc (gl_context.cpp has one).
struct GlcolEngine : Engine {
    // The same query asked with B as the reference; pairs swapped back to (A, B).
    virtual void query_from_b(std::vector<Key> &out) = 0;
};
GlcolEngine *make_glcol(int backend, float epsilon, uint32_t leaf,
                        GlcolGetProcAddress get_proc = nullptr);

// gl_context.cpp (links -lEGL; only the benchmark uses it): a headless EGL context (Mesa
// surfaceless), current on this thread, and its loader; false if there is none.
bool gl_context_init(std::string &renderer);
void *gl_get_proc(void *user, const char *name);

// ---- exact.cpp (CGAL) ------------------------------------------------------------------
// Every triangle pair of A x B that intersects (closed triangles; touching, coplanar overlap
// and degenerate triangles count), by an exact sweep over the exact double boxes and
// CGAL::do_intersect with exact predicates. Output: triangle pairs, sorted.
void exact_pairs(const Mesh &A, const double *pa, const Mesh &B, const double *pb,
                 std::vector<Key> &out);
// Exact closed-triangle intersection of triangle ta of A and tb of B.
bool exact_tri_intersect(const double *pa, const uint32_t *ta, const double *pb,
                         const uint32_t *tb);

enum Class { CROSS = 0, TOUCH = 1, BAND = 2, APART = 3, NCLASS = 4 };
extern const char *const class_name[NCLASS];
struct Verdict {
    Class cls;
    bool coplanar;   // for TOUCH: the two polygons lie in one plane
    double dist;     // exact distance rounded to double (0 when they meet)
};
// Judges polygon pair (a, b): computes the exact intersection and the exact squared
// distance (rationals, GMP) and classifies: CROSS (the polygons meet and no plane separates
// them), TOUCH (they meet, but only on a common boundary or plane), BAND (apart, distance
// <= half_eps), APART (distance > half_eps). half_eps is compared exactly.
Verdict judge(const Mesh &A, const double *pa, uint32_t a, const Mesh &B, const double *pb,
              uint32_t b, double half_eps);

} // namespace peers
