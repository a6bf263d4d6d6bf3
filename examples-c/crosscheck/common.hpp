// crosscheck: shared types of the translation units (no peer or CGAL headers here, so each
// peer's heavy headers stay in its own .cpp).
#pragma once

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace xc {

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

// A pair (polygon or triangle of A, polygon or triangle of B) packed in 64 bits.
using Key = uint64_t;
inline Key key(uint32_t a, uint32_t b) { return (uint64_t(a) << 32) | b; }
inline uint32_t key_a(Key k) { return uint32_t(k >> 32); }
inline uint32_t key_b(Key k) { return uint32_t(k); }
void sort_unique(std::vector<Key> &v);

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

// ---- fcl_peer.cpp ----------------------------------------------------------------------
struct FclPeer;
FclPeer *fcl_create(const Mesh &A, const double *pa, const Mesh &B, const double *pb);
void fcl_update(FclPeer *p, const double *pa, const double *pb);
void fcl_query(FclPeer *p, std::vector<Key> &tri_pairs);
void fcl_destroy(FclPeer *p);

// ---- bullet_peer.cpp -------------------------------------------------------------------
struct BulletPeer;
// rebuild_guard: rebuild (instead of refit) when a mesh leaves its quantization frame.
BulletPeer *bullet_create(const Mesh &A, const double *pa, const Mesh &B, const double *pb,
                          bool rebuild_guard);
// Refit (or, with the guard, rebuild when a mesh left its quantization frame; counted).
void bullet_update(BulletPeer *p, const double *pa, const double *pb);
// Triangle pairs whose GImpact boxes overlap (find_collision).
void bullet_candidates(BulletPeer *p, std::vector<Key> &tri_pairs);
// GImpact's own triangle test (collide_sat_triangles, margin 0) on the candidates.
void bullet_native(BulletPeer *p, const std::vector<Key> &cand, std::vector<Key> &tri_pairs);
int bullet_rebuilds(const BulletPeer *p); // with the guard: rebuilds; without: frames out of frame
void bullet_destroy(BulletPeer *p);

} // namespace xc
