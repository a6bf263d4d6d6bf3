// contact_check: glcollide's contact geometry (glcol_query_geometry, issue 13) against an exact
// reference built on CGAL's exact constructions (Epeck: GMP rationals behind interval filters).
//
// Only the public header and libglcollide are used for glcollide (the peer harness supplies
// the scenes of real meshes and the OBJ reader). For every reported pair (polygon a of A,
// polygon b of B) the float coordinates glcollide got are taken as exact rationals and:
//   flags         INTERSECTING == exact do_intersect of the closed polygons (quads: either
//                 triangle; collinear triangles as the segment or point they are);
//                 COPLANAR == intersecting and all distinct vertices in one plane (orient3d)
//   points        intersecting: distance of point_a and point_b to the exact intersection set
//                 (union of CGAL::intersection of the triangle sub-pairs) and |point_a -
//                 point_b| against the set's exact diameter (its longest extent), in ulps of M
//   depth         intersecting, not coplanar: two triangles, against the exact separating-axis
//                 minimum, min over axes u of overlap(u)^2 / |u|^2 (rationals; axes: the 2
//                 normals and the 9 edge-edge crosses); a quad, the union of its triangles
//                 (issue 28), against the exact depth of that union (union_depth: the distance
//                 from the origin to the closure of the complement of the union of the
//                 triangle pairs' Minkowski differences, big integers)
//   separation    a translated by (depth + k ulp(E)) * normal (exact rationals, the float
//                 normal as given) no longer meets b for some k in 1, 2, 4, 8 (the least is
//                 reported; none is a failure); for a quad, whose union may be apart only in a
//                 wedge of directions at the nearest point that the normal's ray misses, else:
//                 a translated by depth * normal touches b (its exact depth then within
//                 k ulp(E)); a translated by (depth - s) * normal still meets b when depth > s,
//                 s = 8 ulp(E) (see the rule below)
//   normal        | |normal| - 1 | in ulps of 1; coplanar: the angle to a's exact normal
//   band          (not intersecting) -depth against the exact distance (min over vertex-simplex
//                 and segment-segment squared distances); point_a on a and point_b on b, and
//                 dist(point_a, b), dist(point_b, a) against the exact distance (ulps of M);
//                 normal: the exact separation along it of the two nearest triangles
//                 (sub-triangles of a quad), min_a(a.n) - max_b(b.n), against the distance
//                 (ulps of E; a wrong direction makes it negative)
// Units (float ulps, ulp(x) = 2^(floor(log2 x) - 23)): M = the pair's largest coordinate
// magnitude (a float point cannot be nearer than half an ulp of it), E = the pair's extent
// (largest side of its box; depth and normal come from coordinate differences, exact in f64,
// so their error scales with E, not M). Depth and distance errors are in ulps of
// max(exact value, 2^-24 E): relative to the value, but never finer than the float
// resolution of the pair's extent. The rule for separation: a float normal is within about
// one float rounding (2^-24 rad) of the exact direction, which moves the depth needed along
// it by up to about 2 E 2^-24; s = 8 ulp(E) covers that and depth's own rounding.
// Families: every base configuration at the origin, 1e3 and 1e5 off it, at scales 1e-4 and
// 1e4, and placed by glcol_mesh_set_transform (a random rotation, at the origin and 1e3 off,
// scale 1 and 1e-4): then the world positions are doubles that are not floats (the
// reference takes them exactly, computed as docs/API.md defines them), and the configurations
// keep their shape to within the placement's rounding (a plane's two triangles 1e-16 rad
// apart, a vertex 1e-17 off an edge). Quad pairs: random, coplanar, near misses and touching;
// and quads that are not convex and planar (issue 28: bent, bowtie, dart, degenerate,
// crossing or touching a triangle or a quad), at the origin, 1e3 off it and placed.
// Fails (exit 1) on: any error above --limit ulps (default 8), a flag that is not the exact
// one, a NaN or infinity, a non-separating translation, a reported count that differs from
// the pair count, an intersecting depth < 0 or a band depth > 0.
//
//   contact_check [--meshes DIR] [--pairs N (3000 per family)] [--frames N (10 per mesh scene)]
//                 [--limit ULPS (8)] [--only TEXT] [--inject]
// --inject: self-test; the first intersecting pair of every family gets its depth raised by
// 64 ulps (and its normal flipped); the run must then fail.
#include "scenes.hpp"

#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/intersections.h>
#include <CGAL/squared_distance_3.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <queue>
#include <map>
#include <random>
#include <stdexcept>
#include <tuple>
#include <string>
#include <vector>

using namespace peers;

namespace {

using K = CGAL::Exact_predicates_exact_constructions_kernel;
using FT = K::FT;
using Pt = K::Point_3;
using Vec = K::Vector_3;
using Seg = K::Segment_3;
using Tri = K::Triangle_3;

void check(GlcolStatus s, const char *what) {
    if (s != GLCOL_STATUS_OK)
        throw std::runtime_error(std::string(what) + ": " + glcol_status_name(s) + ": " + glcol_last_error_message());
}

double ulp32(double x) {
    x = std::fabs(x);
    if (!(x >= std::ldexp(1.0, -126))) return std::ldexp(1.0, -149);
    return std::ldexp(1.0, std::ilogb(x) - 23);
}

// A closed triangle as what it is: a triangle (dim 2), a segment (1) or a point (0).
struct Simplex {
    int dim;
    Pt p[3];
};
Simplex simplex(const Pt &a, const Pt &b, const Pt &c) {
    if (!CGAL::collinear(a, b, c)) return {2, {a, b, c}};
    Pt lo = a, hi = a;
    for (const Pt *x : {&b, &c}) {
        if (CGAL::compare_xyz(*x, lo) == CGAL::SMALLER) lo = *x;
        if (CGAL::compare_xyz(*x, hi) == CGAL::LARGER) hi = *x;
    }
    if (lo == hi) return {0, {lo, lo, lo}};
    return {1, {lo, hi, hi}};
}

// A polygon: 1 or 2 triangles (a quad (v0,v1,v2,v3) as (v0,v1,v2), (v0,v2,v3)), its
// distinct vertices.
struct Poly {
    std::vector<Simplex> s;
    std::vector<Pt> v;
};
Poly make_poly(const double *const *corner, int n) {
    Poly P;
    std::vector<Pt> c;
    for (int i = 0; i < n; i++) c.emplace_back(corner[i][0], corner[i][1], corner[i][2]);
    P.s.push_back(simplex(c[0], c[1], c[2]));
    if (n == 4) P.s.push_back(simplex(c[0], c[2], c[3]));
    for (const Pt &x : c)
        if (std::find(P.v.begin(), P.v.end(), x) == P.v.end()) P.v.push_back(x);
    return P;
}
Poly translated(const Poly &P, const Vec &t) {
    Poly Q = P;
    for (auto &s : Q.s)
        for (auto &p : s.p) p = p + t;
    for (auto &p : Q.v) p = p + t;
    return Q;
}

bool meet(const Simplex &s, const Simplex &t) {
    if (s.dim < t.dim) return meet(t, s);
    switch (s.dim * 3 + t.dim) {
    case 8: return CGAL::do_intersect(Tri(s.p[0], s.p[1], s.p[2]), Tri(t.p[0], t.p[1], t.p[2]));
    case 7: return CGAL::do_intersect(Tri(s.p[0], s.p[1], s.p[2]), Seg(t.p[0], t.p[1]));
    case 6: return Tri(s.p[0], s.p[1], s.p[2]).has_on(t.p[0]);
    case 4: return CGAL::do_intersect(Seg(s.p[0], s.p[1]), Seg(t.p[0], t.p[1]));
    case 3: return Seg(s.p[0], s.p[1]).has_on(t.p[0]);
    default: return s.p[0] == t.p[0];
    }
}
bool meet(const Poly &A, const Poly &B) {
    for (auto &s : A.s)
        for (auto &t : B.s)
            if (meet(s, t)) return true;
    return false;
}

// The exact intersection of two simplices that meet, as convex pieces (each its vertices).
template <class R> void collect(const R &r, std::vector<std::vector<Pt>> &out) {
    if (!r) return;
    if (auto p = boost::get<Pt>(&*r)) out.push_back({*p});
    else if (auto s = boost::get<Seg>(&*r)) out.push_back({s->source(), s->target()});
}
void pieces(const Simplex &s, const Simplex &t, std::vector<std::vector<Pt>> &out) {
    if (s.dim < t.dim) return pieces(t, s, out);
    switch (s.dim * 3 + t.dim) {
    case 8: {
        auto r = CGAL::intersection(Tri(s.p[0], s.p[1], s.p[2]), Tri(t.p[0], t.p[1], t.p[2]));
        if (!r) return;
        if (auto p = boost::get<Pt>(&*r)) out.push_back({*p});
        else if (auto g = boost::get<Seg>(&*r)) out.push_back({g->source(), g->target()});
        else if (auto T = boost::get<Tri>(&*r)) out.push_back({T->vertex(0), T->vertex(1), T->vertex(2)});
        else if (auto v = boost::get<std::vector<Pt>>(&*r)) out.push_back(*v);
        return;
    }
    case 7: collect(CGAL::intersection(Tri(s.p[0], s.p[1], s.p[2]), Seg(t.p[0], t.p[1])), out); return;
    case 4: collect(CGAL::intersection(Seg(s.p[0], s.p[1]), Seg(t.p[0], t.p[1])), out); return;
    default: out.push_back({t.p[0]}); return; // a point that lies on s
    }
}

// Squared distances, written out in exact rationals (independent of CGAL's distance
// functions): point-segment by the clamped projection, point-triangle by the projection onto
// the plane when it falls inside (exact signs) else the edges, segment-segment by the lines'
// closest pair when it lies inside both, else the four endpoint-segment distances.
FT sq_point_segment(const Pt &x, const Pt &p0, const Pt &p1) {
    Vec d = p1 - p0, w = x - p0;
    FT dd = d * d;
    if (dd == 0) return w * w;
    FT t = (w * d) / dd;
    if (t <= 0) return w * w;
    if (t >= 1) return (x - p1) * (x - p1);
    Vec r = w - d * t;
    return r * r;
}
FT sq_point_triangle(const Pt &x, const Pt &a, const Pt &b, const Pt &c) {
    Vec n = CGAL::cross_product(b - a, c - a);
    bool inside = true;
    const Pt *v[3] = {&a, &b, &c};
    for (int e = 0; e < 3 && inside; e++)
        inside = CGAL::cross_product(*v[(e + 1) % 3] - *v[e], x - *v[e]) * n >= 0;
    if (inside) {
        FT h = (x - a) * n;
        return h * h / (n * n);
    }
    return std::min(sq_point_segment(x, a, b), std::min(sq_point_segment(x, b, c), sq_point_segment(x, c, a)));
}
FT sq_segment_segment(const Pt &p0, const Pt &p1, const Pt &q0, const Pt &q1) {
    Vec d1 = p1 - p0, d2 = q1 - q0, w = p0 - q0;
    FT a = d1 * d1, e = d2 * d2, b = d1 * d2, c = d1 * w, f = d2 * w, den = a * e - b * b;
    if (den != 0) {
        FT s = (b * f - c * e) / den, r = (a * f - b * c) / den;
        if (s >= 0 && s <= 1 && r >= 0 && r <= 1) {
            Vec g = w + d1 * s - d2 * r;
            return g * g;
        }
    }
    return std::min(std::min(sq_point_segment(p0, q0, q1), sq_point_segment(p1, q0, q1)),
                    std::min(sq_point_segment(q0, p0, p1), sq_point_segment(q1, p0, p1)));
}
FT sq_point_simplex(const Pt &x, const Simplex &t) {
    if (t.dim == 2) return sq_point_triangle(x, t.p[0], t.p[1], t.p[2]);
    if (t.dim == 1) return sq_point_segment(x, t.p[0], t.p[1]);
    return CGAL::squared_distance(x, t.p[0]);
}
FT sq_point_piece(const Pt &x, const std::vector<Pt> &p) {
    if (p.size() == 1) return CGAL::squared_distance(x, p[0]);
    if (p.size() == 2) return sq_point_segment(x, p[0], p[1]);
    FT best = -1;
    for (size_t i = 1; i + 1 < p.size(); i++) {
        Simplex t = simplex(p[0], p[i], p[i + 1]);
        FT d = sq_point_simplex(x, t);
        if (best < 0 || d < best) best = d;
    }
    return best;
}
FT sq_point_poly(const Pt &x, const Poly &P) {
    FT best = -1;
    for (auto &s : P.s) {
        FT d = sq_point_simplex(x, s);
        if (best < 0 || d < best) best = d;
    }
    return best;
}
int edges(const Simplex &s, Seg *e) {
    if (s.dim == 2) {
        for (int i = 0; i < 3; i++) e[i] = Seg(s.p[i], s.p[(i + 1) % 3]);
        return 3;
    }
    if (s.dim == 1) {
        e[0] = Seg(s.p[0], s.p[1]);
        return 1;
    }
    return 0;
}
// Squared distance of two disjoint simplices: min over vertex-simplex and edge-edge.
FT sq_simplices(const Simplex &s, const Simplex &t) {
    FT best = -1;
    auto take = [&](const FT &d) {
        if (best < 0 || d < best) best = d;
    };
    for (int i = 0; i <= s.dim; i++) take(sq_point_simplex(s.p[i], t));
    for (int i = 0; i <= t.dim; i++) take(sq_point_simplex(t.p[i], s));
    Seg es[3], et[3];
    int ns = edges(s, es), nt = edges(t, et);
    for (int i = 0; i < ns; i++)
        for (int j = 0; j < nt; j++) take(sq_segment_segment(es[i].source(), es[i].target(), et[j].source(), et[j].target()));
    return best;
}

bool all_coplanar(const std::vector<Pt> &v) {
    for (size_t i = 0; i < v.size(); i++)
        for (size_t j = i + 1; j < v.size(); j++)
            for (size_t k = j + 1; k < v.size(); k++)
                if (!CGAL::collinear(v[i], v[j], v[k])) {
                    for (size_t l = 0; l < v.size(); l++)
                        if (!CGAL::coplanar(v[i], v[j], v[k], v[l])) return false;
                    return true;
                }
    return true; // all collinear
}

// Exact squared penetration depth of the hulls (see the header comment).
FT sat_depth2(const Poly &A, const Poly &B) {
    std::vector<Vec> axes, da, db;
    auto triples = [&](const std::vector<Pt> &v) {
        for (size_t i = 0; i < v.size(); i++)
            for (size_t j = i + 1; j < v.size(); j++)
                for (size_t k = j + 1; k < v.size(); k++) {
                    Vec n = CGAL::cross_product(v[j] - v[i], v[k] - v[i]);
                    if (n != CGAL::NULL_VECTOR) axes.push_back(n);
                }
    };
    auto dirs = [](const std::vector<Pt> &v, std::vector<Vec> &d) {
        for (size_t i = 0; i < v.size(); i++)
            for (size_t j = i + 1; j < v.size(); j++) d.push_back(v[j] - v[i]);
    };
    triples(A.v);
    triples(B.v);
    dirs(A.v, da);
    dirs(B.v, db);
    for (auto &x : da)
        for (auto &y : db) {
            Vec n = CGAL::cross_product(x, y);
            if (n != CGAL::NULL_VECTOR) axes.push_back(n);
        }
    FT best = -1;
    for (auto &u : axes) {
        FT amin = 0, amax = 0, bmin = 0, bmax = 0;
        for (size_t i = 0; i < A.v.size(); i++) {
            FT d = (A.v[i] - CGAL::ORIGIN) * u;
            if (i == 0 || d < amin) amin = d;
            if (i == 0 || d > amax) amax = d;
        }
        for (size_t i = 0; i < B.v.size(); i++) {
            FT d = (B.v[i] - CGAL::ORIGIN) * u;
            if (i == 0 || d < bmin) bmin = d;
            if (i == 0 || d > bmax) bmax = d;
        }
        FT o = std::min(bmax - amin, amax - bmin);
        if (o < 0) o = 0; // cannot happen for polygons that meet
        FT d2 = o * o / u.squared_length();
        if (best < 0 || d2 < best) best = d2;
    }
    return best < 0 ? FT(0) : best; // no axis: everything collinear (coplanar, not asked)
}

// ---- the union's depth (issue 28) --------------------------------------------------------
// A quad is the union of its triangles (v0,v1,v2), (v0,v2,v3), planar or not, and depth is
// the smallest translation of a that separates the polygons: the distance from the origin to
// the closure of the complement of M = B - A, the union of the pieces B_j - A_i (convex; one
// per triangle pair; a flat piece is nowhere dense and leaves that closure as it is, so only
// full-dimensional pieces count). The nearest point of that closure is the foot of the origin
// on the intersection of 1 to 3 facet planes of distinct pieces and lies in each of them;
// every such candidate outside the union's interior is at least as far. Candidates are built
// exactly (homogeneous big integers: all coordinates scaled by one power of two), tried in the
// order of their rounded norms, and accepted when some direction leaves every piece holding
// them: for some choice of one facet through the point per such piece, the origin is not in
// the hull of the chosen normals (Gordan), decided exactly. (The same method as the crate's
// test-only src/geom/union_depth.rs, written again on GMP.)
using Z = CGAL::Gmpz;
struct ZV {
    Z c[3];
};
ZV zsub(const ZV &a, const ZV &b) { return {{a.c[0] - b.c[0], a.c[1] - b.c[1], a.c[2] - b.c[2]}}; }
Z zdot(const ZV &a, const ZV &b) { return a.c[0] * b.c[0] + a.c[1] * b.c[1] + a.c[2] * b.c[2]; }
ZV zcross(const ZV &a, const ZV &b) {
    return {{a.c[1] * b.c[2] - a.c[2] * b.c[1], a.c[2] * b.c[0] - a.c[0] * b.c[2], a.c[0] * b.c[1] - a.c[1] * b.c[0]}};
}
bool zzero(const ZV &a) { return a.c[0] == 0 && a.c[1] == 0 && a.c[2] == 0; }
bool zsame(const ZV &a, const ZV &b) { return a.c[0] == b.c[0] && a.c[1] == b.c[1] && a.c[2] == b.c[2]; }
ZV zcombo(const Z &s, const ZV &a, const Z &t, const ZV &b, const Z &u, const ZV &c) {
    ZV r;
    for (int k = 0; k < 3; k++) r.c[k] = s * a.c[k] + t * b.c[k] + u * c.c[k];
    return r;
}
// |n| / |d| as a double, from their exact values.
double zratio(const Z &n, const Z &d) {
    if (n == 0) return 0;
    long en, ed;
    double mn = mpz_get_d_2exp(&en, n.mpz()), md = mpz_get_d_2exp(&ed, d.mpz());
    return std::ldexp(std::fabs(mn / md), int(en - ed));
}

// A full-dimensional piece {x : n.x <= h} over its facets (outward, primitive normals).
struct ZPiece {
    std::vector<std::pair<ZV, Z>> f;
    // -1: x / w (w > 0) outside; else the number of facets through it (0: inside), listed
    // in act when given.
    int active(const ZV &x, const Z &w, std::vector<int> *act = nullptr) const {
        int n = 0;
        for (size_t i = 0; i < f.size(); i++) {
            Z s = zdot(f[i].first, x) - f[i].second * w;
            if (s > 0) return -1;
            if (s == 0) {
                n++;
                if (act) act->push_back(int(i));
            }
        }
        return n;
    }
};
bool zpiece(const ZV *a, const ZV *b, ZPiece &P) {
    std::vector<ZV> d;
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) {
            ZV x = zsub(b[i], a[j]);
            bool seen = false;
            for (auto &y : d) seen = seen || zsame(x, y);
            if (!seen) d.push_back(x);
        }
    bool solid = false;
    for (size_t i = 0; i < d.size(); i++)
        for (size_t j = i + 1; j < d.size(); j++)
            for (size_t k = j + 1; k < d.size(); k++) {
                ZV n = zcross(zsub(d[j], d[i]), zsub(d[k], d[i]));
                if (zzero(n)) continue;
                bool pos = false, neg = false;
                for (auto &x : d) {
                    Z s = zdot(n, zsub(x, d[i]));
                    pos = pos || s > 0;
                    neg = neg || s < 0;
                }
                solid = solid || pos || neg;
                if (pos == neg) continue;
                if (pos)
                    for (auto &c : n.c) c = -c;
                Z g = 0;
                for (auto &c : n.c) mpz_gcd(g.mpz(), g.mpz(), c.mpz());
                for (auto &c : n.c) c = c / g;
                bool seen = false;
                for (auto &e : P.f) seen = seen || zsame(e.first, n);
                if (!seen) P.f.push_back({n, zdot(n, d[i])});
            }
    return solid;
}
// Is the origin in the hull of these (at most four) vectors? (A pair opposite, a triple around
// it in a plane through it, or a tetrahedron around it.)
bool zero_in_hull(const std::vector<const ZV *> &v) {
    size_t n = v.size();
    for (size_t i = 0; i < n; i++) {
        if (zzero(*v[i])) return true;
        for (size_t j = i + 1; j < n; j++) {
            if (zzero(zcross(*v[i], *v[j])) && zdot(*v[i], *v[j]) < 0) return true;
            for (size_t k = j + 1; k < n; k++) {
                ZV ab = zcross(*v[i], *v[j]), bc = zcross(*v[j], *v[k]), ca = zcross(*v[k], *v[i]);
                if (zdot(ab, *v[k]) != 0) continue;
                const ZV *w = !zzero(ab) ? &ab : !zzero(bc) ? &bc : !zzero(ca) ? &ca : nullptr;
                if (!w) continue;
                Z s[3] = {zdot(*w, bc), zdot(*w, ca), zdot(*w, ab)};
                if ((s[0] >= 0 && s[1] >= 0 && s[2] >= 0) || (s[0] <= 0 && s[1] <= 0 && s[2] <= 0)) return true;
            }
        }
    }
    if (n == 4) {
        ZV o = {{0, 0, 0}};
        auto orient = [](const ZV &p, const ZV &q, const ZV &r, const ZV &s) {
            return zdot(zsub(q, p), zcross(zsub(r, p), zsub(s, p)));
        };
        Z total = orient(*v[0], *v[1], *v[2], *v[3]);
        if (total != 0) {
            Z l[4] = {orient(o, *v[1], *v[2], *v[3]), orient(*v[0], o, *v[2], *v[3]), orient(*v[0], *v[1], o, *v[3]),
                      orient(*v[0], *v[1], *v[2], o)};
            bool in = true;
            for (auto &x : l) in = in && (x == 0 || (x > 0) == (total > 0));
            if (in) return true;
        }
    }
    return false;
}
// Is x / w in the closure of the complement of the pieces' union?
bool zoutside(const std::vector<ZPiece> &P, const ZV &x, const Z &w) {
    std::vector<std::pair<size_t, std::vector<int>>> holding;
    for (size_t k = 0; k < P.size(); k++) {
        std::vector<int> act;
        int a = P[k].active(x, w, &act);
        if (a == 0) return false;
        if (a > 0) holding.push_back({k, act});
    }
    std::vector<const ZV *> chosen;
    std::function<bool(size_t)> any = [&](size_t h) {
        if (h == holding.size()) return !zero_in_hull(chosen);
        for (int f : holding[h].second) {
            chosen.push_back(&P[holding[h].first].f[f].first);
            bool found = any(h + 1);
            chosen.pop_back();
            if (found) return true;
        }
        return false;
    };
    return any(0);
}
// The union's depth of polygons a (na corners) and b (nb corners), which meet.
double union_depth(const double *const *ca, int na, const double *const *cb, int nb) {
    // Every coordinate m 2^e (m an integer of 53 bits), scaled by 2^-e0, e0 the least e.
    std::vector<double> xs;
    for (int i = 0; i < na; i++) xs.insert(xs.end(), ca[i], ca[i] + 3);
    for (int i = 0; i < nb; i++) xs.insert(xs.end(), cb[i], cb[i] + 3);
    int e0 = INT32_MAX;
    std::vector<std::pair<double, int>> me;
    for (double x : xs) {
        int e;
        double f = std::frexp(x, &e);
        me.push_back({std::ldexp(f, 53), e - 53});
        if (x != 0) e0 = std::min(e0, e - 53);
    }
    std::vector<ZV> pts;
    for (size_t i = 0; i < xs.size(); i += 3) {
        ZV p;
        for (int k = 0; k < 3; k++) {
            Z m(me[i + k].first);
            if (me[i + k].first != 0) mpz_mul_2exp(m.mpz(), m.mpz(), (unsigned long)(me[i + k].second - e0));
            p.c[k] = m;
        }
        pts.push_back(p);
    }
    auto tris = [&](int base, int n) {
        std::vector<std::array<ZV, 3>> t = {{pts[base], pts[base + 1], pts[base + 2]}};
        if (n == 4) t.push_back({pts[base], pts[base + 2], pts[base + 3]});
        return t;
    };
    std::vector<ZPiece> P;
    for (auto &t : tris(0, na))
        for (auto &u : tris(na, nb)) {
            ZPiece p;
            if (zpiece(t.data(), u.data(), p)) P.push_back(p);
        }
    ZV zero = {{0, 0, 0}};
    if (zoutside(P, zero, Z(1))) return 0;
    // Every facet plane g: (piece, facet) and its squared distance from the origin, a lower
    // bound of the norm of every candidate on it.
    std::vector<std::pair<int, int>> fs;
    std::vector<double> lb;
    for (int k = 0; k < int(P.size()); k++)
        for (int i = 0; i < int(P[k].f.size()); i++) {
            auto &[n, h] = P[k].f[i];
            fs.push_back({k, i});
            lb.push_back(zratio(h * h, zdot(n, n)));
        }
    // Candidates on 1, 2 or 3 planes of distinct pieces, built when the queue (by the least
    // norm they can have) reaches them.
    struct Item {
        double key;
        int g[3], n, built;
    };
    auto later = [](const Item &x, const Item &y) { return x.key > y.key; };
    std::priority_queue<Item, std::vector<Item>, decltype(later)> q(later);
    int nf = int(fs.size());
    for (int a = 0; a < nf; a++) {
        q.push({lb[a], {a, 0, 0}, 1, -1});
        for (int b = a + 1; b < nf; b++) {
            if (fs[b].first == fs[a].first) continue;
            q.push({std::max(lb[a], lb[b]), {a, b, 0}, 2, -1});
            for (int c = b + 1; c < nf; c++)
                if (fs[c].first != fs[b].first && fs[c].first != fs[a].first)
                    q.push({std::max({lb[a], lb[b], lb[c]}), {a, b, c}, 3, -1});
        }
    }
    struct Cand {
        ZV x;
        Z w;
    };
    std::vector<Cand> cs;
    int best = -1;
    double best_key = 0;
    while (!q.empty()) {
        Item it = q.top();
        q.pop();
        if (best >= 0 && it.key > best_key * (1 + 1e-12)) break;
        auto plane = [&](int m) -> const std::pair<ZV, Z> & { return P[fs[it.g[m]].first].f[fs[it.g[m]].second]; };
        if (it.built < 0) {
            ZV x;
            Z w;
            if (it.n == 1) {
                auto &[n, h] = plane(0);
                x = zcombo(h, n, 0, n, 0, n), w = zdot(n, n);
            } else if (it.n == 2) {
                auto &[n1, h1] = plane(0);
                auto &[n2, h2] = plane(1);
                ZV m = zcross(n1, n2);
                if (zzero(m)) continue;
                x = zcombo(h1, zcross(n2, m), h2, zcross(m, n1), 0, m), w = zdot(m, m);
            } else {
                auto &[n1, h1] = plane(0);
                auto &[n2, h2] = plane(1);
                auto &[n3, h3] = plane(2);
                ZV c23 = zcross(n2, n3);
                w = zdot(n1, c23);
                if (w == 0) continue;
                x = zcombo(h1, c23, h2, zcross(n3, n1), h3, zcross(n1, n2));
            }
            if (w < 0) {
                for (auto &c : x.c) c = -c;
                w = -w;
            }
            it.key = zratio(zdot(x, x), w * w);
            it.built = int(cs.size());
            cs.push_back({x, w});
            q.push(it);
            continue;
        }
        const Cand &c = cs[it.built];
        bool on = true;
        for (int m = 0; m < it.n; m++) on = on && P[fs[it.g[m]].first].active(c.x, c.w) >= 0;
        if (!on || !zoutside(P, c.x, c.w)) continue;
        if (best < 0 || zdot(c.x, c.x) * (cs[best].w * cs[best].w) < zdot(cs[best].x, cs[best].x) * (c.w * c.w))
            best = it.built, best_key = it.key;
    }
    if (best < 0) throw std::runtime_error("union_depth: no nearest point");
    return std::sqrt(std::ldexp(best_key, 2 * e0));
}

// A rational to the nearest double (well, within one ulp), from its exact value: Epeck's own
// CGAL::to_double rounds its interval approximation, which after a cancellation (a small
// overlap or gap between projections of coordinates far larger) can be wide.
double todbl(const FT &x) { return CGAL::to_double(CGAL::exact(x)); }
double dsqrt(const FT &x) { return std::sqrt(std::max(0.0, todbl(x))); }

// Worst errors of one family, in ulps (see the header comment).
struct Stats {
    std::string name;
    long pairs = 0, inter = 0, copl = 0, band = 0, fails = 0;
    double pt = 0, ext = 0, depth = 0, sep = 0, nlen = 0, cnorm = 0, bdist = 0, bpts = 0, bnorm = 0;
    std::vector<std::string> msgs;
    void fail(const std::string &m) {
        fails++;
        if (msgs.size() < 5) msgs.push_back(m);
    }
};

std::string fmt1(float x) {
    char b[40];
    snprintf(b, sizeof b, "%a", double(x));
    return b;
}
std::string fmt3(const float *x) { return "{" + fmt1(x[0]) + ", " + fmt1(x[1]) + ", " + fmt1(x[2]) + "}"; }

// The two polygons' corners as C99 hex floats (exact), ready for a reproduction.
std::string corners(const double *const *ca, int na, const double *const *cb, int nb) {
    std::string o;
    char b[128];
    for (auto cs : {std::make_pair(ca, na), std::make_pair(cb, nb)}) {
        o += "\n    {";
        for (int i = 0; i < cs.second; i++) {
            snprintf(b, sizeof b, "%s{%a, %a, %a}", i ? ", " : "", cs.first[i][0], cs.first[i][1], cs.first[i][2]);
            o += b;
        }
        o += "}";
    }
    return o;
}

struct Checker {
    double limit = 8;
    bool inject = false;
    bool injected = false;

    void pair(Stats &S, const double *const *ca, int na, const double *const *cb, int nb, GlcolContactGeometry g,
              const char *where) {
        S.pairs++;
        char buf[512];
        auto bad = [&](const char *what, double v) {
            snprintf(buf, sizeof buf, "%s: %s = %.3g", where, what, v);
            S.fail(buf + corners(ca, na, cb, nb) +
                   "\n    geometry: point_a " + fmt3(g.point_a) + " point_b " + fmt3(g.point_b) + " normal " +
                   fmt3(g.normal) + " depth " + fmt1(g.depth));
        };
        Poly A = make_poly(ca, na), B = make_poly(cb, nb);
        double M = 0, lo[3] = {HUGE_VAL, HUGE_VAL, HUGE_VAL}, hi[3] = {-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
        for (auto cs : {std::make_pair(ca, na), std::make_pair(cb, nb)})
            for (int i = 0; i < cs.second; i++)
                for (int k = 0; k < 3; k++) {
                    double x = cs.first[i][k];
                    M = std::max(M, std::fabs(x));
                    lo[k] = std::min(lo[k], x);
                    hi[k] = std::max(hi[k], x);
                }
        double E = std::max(hi[0] - lo[0], std::max(hi[1] - lo[1], hi[2] - lo[2]));
        double uM = ulp32(M), uE = ulp32(E);
        bool inter = meet(A, B);
        if (inject && inter && !injected) {
            injected = true;
            g.depth += 64 * float(ulp32(std::max(double(g.depth), E * 0x1p-24)));
            for (float &x : g.normal) x = -x;
        }
        const float *all[4] = {g.point_a, g.point_b, g.normal, &g.depth};
        for (int i = 0; i < 4; i++)
            for (int k = 0; k < (i == 3 ? 1 : 3); k++)
                if (!std::isfinite(all[i][k])) return bad("non-finite output", all[i][k]);
        bool f_inter = g.flags & GLCOL_CONTACT_INTERSECTING, f_copl = g.flags & GLCOL_CONTACT_COPLANAR;
        if (f_inter != inter) return bad("INTERSECTING flag differs from exact; exact", inter);
        Pt pa(g.point_a[0], g.point_a[1], g.point_a[2]), pb(g.point_b[0], g.point_b[1], g.point_b[2]);
        Vec n(g.normal[0], g.normal[1], g.normal[2]);
        double nl = std::sqrt(double(g.normal[0]) * g.normal[0] + double(g.normal[1]) * g.normal[1] +
                              double(g.normal[2]) * g.normal[2]);
        double e_nl = std::fabs(nl - 1) / ulp32(1);
        S.nlen = std::max(S.nlen, e_nl);
        if (e_nl > limit) bad("| |normal| - 1 | / ulp(1)", e_nl);
        if (inter) {
            S.inter++;
            std::vector<Pt> allv = A.v;
            allv.insert(allv.end(), B.v.begin(), B.v.end());
            bool copl = all_coplanar(allv);
            if (f_copl != copl) return bad("COPLANAR flag differs from exact; exact", copl);
            // Points on the exact intersection, and their spread against its diameter.
            std::vector<std::vector<Pt>> I;
            for (auto &s : A.s)
                for (auto &t : B.s)
                    if (meet(s, t)) pieces(s, t, I);
            auto dist_I = [&](const Pt &x) {
                FT best = -1;
                for (auto &p : I) {
                    FT d = sq_point_piece(x, p);
                    if (best < 0 || d < best) best = d;
                }
                return dsqrt(best);
            };
            double e_pt = std::max(dist_I(pa), dist_I(pb)) / uM;
            FT diam2 = 0;
            std::vector<Pt> iv;
            for (auto &p : I) iv.insert(iv.end(), p.begin(), p.end());
            for (size_t i = 0; i < iv.size(); i++)
                for (size_t j = i + 1; j < iv.size(); j++) {
                    FT d = CGAL::squared_distance(iv[i], iv[j]);
                    if (d > diam2) diam2 = d;
                }
            double spread = dsqrt(CGAL::squared_distance(pa, pb));
            double e_ext = std::fabs(spread - dsqrt(diam2)) / uM;
            S.pt = std::max(S.pt, e_pt);
            S.ext = std::max(S.ext, e_ext);
            if (e_pt > limit) bad("point distance to the exact intersection / ulp(M)", e_pt);
            if (e_ext > limit) bad("| |pa-pb| - exact diameter | / ulp(M)", e_ext);
            if (copl) {
                S.copl++;
                if (g.depth != 0) bad("coplanar depth (must be 0)", g.depth);
                // Any translation along the normal separates: 1 ulp(E) must.
                if (meet(translated(A, n * FT(uE)), B)) bad("coplanar: a moved by ulp(E) * normal still meets b", 1);
                else S.sep = std::max(S.sep, 1.0);
                // a's normal: the sum of its triangles' area vectors; where they cancel (a
                // bowtie with equal halves), a proper half's, either way up (issue 28).
                Vec N = CGAL::NULL_VECTOR, half = CGAL::NULL_VECTOR;
                for (auto &s : A.s)
                    if (s.dim == 2) {
                        N = N + CGAL::cross_product(s.p[1] - s.p[0], s.p[2] - s.p[0]);
                        if (half == CGAL::NULL_VECTOR) half = CGAL::cross_product(s.p[1] - s.p[0], s.p[2] - s.p[0]);
                    }
                bool either = N == CGAL::NULL_VECTOR;
                if (either) N = half;
                if (N != CGAL::NULL_VECTOR) {
                    double Nd[3] = {todbl(N.x()), todbl(N.y()), todbl(N.z())};
                    double c[3] = {g.normal[1] * Nd[2] - g.normal[2] * Nd[1], g.normal[2] * Nd[0] - g.normal[0] * Nd[2],
                                   g.normal[0] * Nd[1] - g.normal[1] * Nd[0]};
                    double dot = g.normal[0] * Nd[0] + g.normal[1] * Nd[1] + g.normal[2] * Nd[2];
                    if (either) dot = std::fabs(dot);
                    double ang = std::atan2(std::sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]), dot);
                    double e_c = ang / 0x1p-24;
                    S.cnorm = std::max(S.cnorm, e_c);
                    if (e_c > limit) bad("coplanar normal's angle to a's normal / 2^-24 rad", e_c);
                }
                return;
            }
            if (!(g.depth >= 0)) return bad("intersecting depth < 0", g.depth);
            // Triangles: the separating-axis minimum (their difference is convex); a quad:
            // the union of its triangles' (issue 28).
            double D = na == 4 || nb == 4 ? union_depth(ca, na, cb, nb) : dsqrt(sat_depth2(A, B));
            double e_d = std::fabs(g.depth - D) / ulp32(std::max(D, E * 0x1p-24));
            S.depth = std::max(S.depth, e_d);
            if (e_d > limit) {
                snprintf(buf, sizeof buf, "%s: |depth - exact depth (%a)| / ulp(max(D, 2^-24 E)) = %.3g", where, D, e_d);
                S.fail(buf + corners(ca, na, cb, nb));
            }
            // Separation, exactly on the translated polygons.
            // The least slack k ulp(E), k in 1, 2, 4, 8, after which the translation separates.
            double s = 8 * uE, need = 0;
            for (double k : {1.0, 2.0, 4.0, 8.0})
                if (!meet(translated(A, n * (FT(double(g.depth)) + FT(k * uE))), B)) {
                    need = k;
                    break;
                }
            if (need == 0 && (na == 4 || nb == 4)) {
                // A union (a quad) may be apart only in a wedge of directions at its nearest
                // point that the normal's ray misses: then a moved by depth * normal must
                // touch b (the moved pair's exact depth within k ulp(E)).
                double xa[4][3];
                const double *ma[4] = {xa[0], xa[1], xa[2], xa[3]};
                for (int i = 0; i < na; i++)
                    for (int k = 0; k < 3; k++) xa[i][k] = ca[i][k] + double(g.depth) * double(g.normal[k]);
                double rest = union_depth(ma, na, cb, nb);
                for (double k : {1.0, 2.0, 4.0, 8.0})
                    if (rest <= k * uE) {
                        need = k;
                        break;
                    }
            }
            if (need == 0) bad("a moved by (depth + 8 ulp(E)) * normal still meets b; depth", g.depth);
            S.sep = std::max(S.sep, need);
            // Any translation shorter than the exact depth leaves them meeting.
            if (double(g.depth) > s) {
                Vec dn = n * (FT(double(g.depth)) - FT(s));
                if (!meet(translated(A, dn), B))
                    bad("a moved by (depth - 8 ulp(E)) * normal is already apart; depth", g.depth);
            }
            return;
        }
        S.band++;
        if (f_copl) return bad("COPLANAR on a pair that does not intersect", 1);
        if (!(g.depth <= 0)) return bad("band depth > 0", g.depth);
        FT d2 = -1;
        for (auto &s : A.s)
            for (auto &t : B.s) {
                FT d = sq_simplices(s, t);
                if (d2 < 0 || d < d2) d2 = d;
            }
        double d = dsqrt(d2);
        double e_bd = std::fabs(-double(g.depth) - d) / ulp32(std::max(d, E * 0x1p-24));
        S.bdist = std::max(S.bdist, e_bd);
        if (e_bd > limit) bad("|-depth - exact distance| / ulp(max(d, 2^-24 E))", e_bd);
        double e_p = std::max({dsqrt(sq_point_poly(pa, A)), dsqrt(sq_point_poly(pb, B)),
                               std::fabs(dsqrt(sq_point_poly(pa, B)) - d), std::fabs(dsqrt(sq_point_poly(pb, A)) - d)}) /
                     uM;
        S.bpts = std::max(S.bpts, e_p);
        if (e_p > limit) bad("band closest points (on their polygon, at the distance) / ulp(M)", e_p);
        // The exact separation along the normal, min_a a.n - max_b b.n, of the nearest
        // triangles (for triangles the polygons themselves; a quad bent or not convex is not
        // separated along its closest points' direction as its hull would be): the best
        // over the sub-triangle pairs within the limit of the distance (two may be nearest
        // to within rounding, a vertex by a quad's diagonal; the geometry takes either).
        FT amin = 0, bmax = 0;
        bool first = true;
        for (auto &s : A.s)
            for (auto &t : B.s) {
                if (dsqrt(sq_simplices(s, t)) > d + limit * uE) continue;
                FT lo = 0, hi = 0;
                for (int i = 0; i <= s.dim; i++) {
                    FT x = (s.p[i] - CGAL::ORIGIN) * n;
                    if (i == 0 || x < lo) lo = x;
                }
                for (int i = 0; i <= t.dim; i++) {
                    FT x = (t.p[i] - CGAL::ORIGIN) * n;
                    if (i == 0 || x > hi) hi = x;
                }
                if (first || lo - hi > amin - bmax) amin = lo, bmax = hi;
                first = false;
            }
        double gap = todbl(amin - bmax) / nl;
        double e_bn = (d - gap) / uE;
        S.bnorm = std::max(S.bnorm, e_bn);
        if (e_bn > limit) bad("(distance - separation along the normal) / ulp(E)", e_bn);
    }
};

// ---- generated pairs ---------------------------------------------------------------------
using T3 = std::array<std::array<double, 3>, 3>;
struct Gen {
    std::mt19937_64 rng{12345};
    double u(double a, double b) { return std::uniform_real_distribution<double>(a, b)(rng); }
    std::array<double, 3> p(double r) { return {u(-r, r), u(-r, r), u(-r, r)}; }
    T3 tri(double r) { return {p(r), p(r), p(r)}; }
};
std::array<double, 3> cross(const std::array<double, 3> &a, const std::array<double, 3> &b) {
    return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
std::array<double, 3> sub(const std::array<double, 3> &a, const std::array<double, 3> &b) {
    return {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
}
std::array<double, 3> unit(std::array<double, 3> a) {
    double l = std::sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
    return {a[0] / l, a[1] / l, a[2] / l};
}

// The base configurations (unit size, at the origin); the families scale and offset them.
enum Kind { RANDOM, COPLANAR, TOUCHING, SLIVER, NEAR, DEGENERATE, NEAR_SLIVER, SHARED, TILTED, NKIND };
std::pair<T3, T3> make(Gen &G, Kind k, int i) {
    switch (k) {
    case RANDOM: {
        T3 a = G.tri(1), b = G.tri(1);
        return {a, b};
    }
    case COPLANAR: {
        // In z = c, in x = c, or in the plane y = x (exact in floats).
        T3 a = G.tri(1), b = G.tri(1);
        int m = i % 3;
        double c = float(G.u(-1, 1));
        for (T3 *t : {&a, &b})
            for (auto &v : *t) {
                if (m == 0) v[2] = c;
                else if (m == 1) v[0] = c;
                else v[1] = float(v[0]);
            }
        return {a, b};
    }
    case TOUCHING: {
        // a in z = 0; b touches it with a vertex inside a, on a's edge, on a's vertex, or
        // shares a's edge folded up.
        T3 a = {{{0, 0, 0}, {1, 0, 0}, {0.25, 1, 0}}};
        double s = G.u(0.1, 0.9), t = G.u(0.05, 0.4);
        std::array<double, 3> q;
        switch (i % 4) {
        case 0: q = {float(s * 0.6 + 0.1), float(t), 0}; break; // inside (usually)
        case 1: q = {float(s), 0, 0}; break;                    // on the edge y = 0
        case 2: q = {1, 0, 0}; break;                           // on a vertex
        default: {
            std::array<double, 3> top = {G.u(0, 1), G.u(-1, 0), G.u(0.1, 1)};
            return {a, {{{0, 0, 0}, {1, 0, 0}, top}}}; // shared edge, folded
        }
        }
        T3 b = {{q, {q[0] + G.u(-0.5, 0.5), q[1] + G.u(-0.5, 0.5), G.u(0.1, 1)},
                 {q[0] + G.u(-0.5, 0.5), q[1] + G.u(-0.5, 0.5), G.u(0.1, 1)}}};
        return {a, b};
    }
    case SLIVER: {
        // a: one side 1e-6 .. 1e-3 thin; b random through it.
        auto p0 = G.p(1), p1 = G.p(1);
        double w = std::pow(10.0, G.u(-6, -3)), s = G.u(0, 1);
        auto off = unit(cross(sub(p1, p0), G.p(1)));
        T3 a = {{p0, p1, {p0[0] + s * (p1[0] - p0[0]) + w * off[0], p0[1] + s * (p1[1] - p0[1]) + w * off[1],
                          p0[2] + s * (p1[2] - p0[2]) + w * off[2]}}};
        auto m = a[2];
        T3 b = {{{m[0] + G.u(-1, 1), m[1] + G.u(-1, 1), m[2] + G.u(-1, 1)}, {m[0] - G.u(-1, 1), m[1] - G.u(-1, 1), m[2] - G.u(-1, 1)}, G.p(1)}};
        if (i % 2) std::swap(a, b);
        return {a, b};
    }
    case NEAR: {
        // b's vertex h = 1e-3 .. 1e-7 above (apart) or below (crossing) a's plane, inside a,
        // or b's edge passing h from a's edge.
        T3 a = G.tri(1);
        auto n = unit(cross(sub(a[1], a[0]), sub(a[2], a[0])));
        double h = std::pow(10.0, G.u(-7, -3)) * (i % 2 ? 1 : -1);
        if (i % 4 < 2) {
            double w0 = G.u(0.1, 0.8), w1 = G.u(0.05, 1 - w0 - 0.05), w2 = 1 - w0 - w1;
            std::array<double, 3> q;
            for (int k = 0; k < 3; k++) q[k] = w0 * a[0][k] + w1 * a[1][k] + w2 * a[2][k] + h * n[k];
            auto up = [&](double s) {
                auto r = G.p(0.7);
                return std::array<double, 3>{q[0] + r[0] + s * n[0], q[1] + r[1] + s * n[1], q[2] + r[2] + s * n[2]};
            };
            return {a, {{q, up(h > 0 ? 0.8 : 0.8), up(0.5)}}};
        }
        // Edge-edge: b's edge crosses the midpoint of a's edge 0-1 at height h, skew.
        std::array<double, 3> m, e = unit(sub(a[1], a[0])), o = unit(cross(e, n));
        for (int k = 0; k < 3; k++) m[k] = 0.5 * (a[0][k] + a[1][k]) + h * n[k];
        auto d = unit({o[0] + 0.3 * e[0], o[1] + 0.3 * e[1], o[2] + 0.3 * e[2]});
        std::array<double, 3> b0, b1, b2;
        for (int k = 0; k < 3; k++) {
            b0[k] = m[k] - 0.5 * d[k];
            b1[k] = m[k] + 0.5 * d[k];
            b2[k] = m[k] + 0.6 * n[k] - 0.2 * o[k];
        }
        return {a, {{b0, b1, b2}}};
    }
    case NEAR_SLIVER: {
        // a: one side 1e-6 .. 1e-3 thin; b's vertex h = 1e-3 .. 1e-7 above a's interior, its
        // other vertices farther on the same side (the closest points: that vertex and its
        // foot on the sliver, whose plane a naive normal tilts by eps over its width).
        auto p0 = G.p(1), p1 = G.p(1);
        double w = std::pow(10.0, G.u(-6, -3));
        auto off = unit(cross(sub(p1, p0), G.p(1)));
        std::array<double, 3> p2;
        for (int k = 0; k < 3; k++) p2[k] = float(p0[k] + 0.7 * (p1[k] - p0[k]) + w * off[k]);
        T3 a = {{p0, p1, p2}};
        auto n = unit(cross(sub(a[1], a[0]), sub(a[2], a[0])));
        double h = std::pow(10.0, G.u(-7, -3));
        std::array<double, 3> q;
        for (int k = 0; k < 3; k++) q[k] = 0.15 * a[0][k] + 0.45 * a[1][k] + 0.4 * a[2][k] + h * n[k];
        auto up = [&](double s) {
            auto r = G.p(0.7);
            return std::array<double, 3>{q[0] + r[0] + s * n[0], q[1] + r[1] + s * n[1], q[2] + r[2] + s * n[2]};
        };
        T3 b = {{q, up(0.3), up(0.5)}};
        if (i % 2) std::swap(a, b);
        return {a, b};
    }
    case TILTED: {
        // Both in one random plane, rounded to floats: nearly coplanar (each vertex within
        // half a float ulp of the plane), crossing at tiny angles or just missing; half of
        // them share a corner.
        auto o = G.p(1), e1 = unit(G.p(1)), e2 = unit(cross(e1, G.p(1)));
        auto at = [&](double u, double v) {
            return std::array<double, 3>{float(o[0] + u * e1[0] + v * e2[0]), float(o[1] + u * e1[1] + v * e2[1]),
                                         float(o[2] + u * e1[2] + v * e2[2])};
        };
        T3 a = {{at(G.u(-1, 1), G.u(-1, 1)), at(G.u(-1, 1), G.u(-1, 1)), at(G.u(-1, 1), G.u(-1, 1))}};
        T3 b = {{at(G.u(-1, 1), G.u(-1, 1)), at(G.u(-1, 1), G.u(-1, 1)), at(G.u(-1, 1), G.u(-1, 1))}};
        if (i % 2) b[0] = a[0];
        return {a, b};
    }
    case SHARED: {
        // Neighbours of a folding mesh (what self-collision reports): b shares a's corner 0
        // and folds through a's interior (one corner above a's plane, one below), or shares
        // a corner or a's edge 0-1 and lies folded flat onto a (in z = 0: coplanar overlap).
        T3 a = {{{0, 0, 0}, {1, 0, 0}, {float(G.u(0.1, 0.9)), float(G.u(0.3, 1)), 0}}};
        auto in_a = [&] {
            double w1 = G.u(0.05, 0.9), w2 = G.u(0.05, 0.95 - w1);
            return std::array<double, 3>{float(w1 * a[1][0] + w2 * a[2][0]), float(w2 * a[2][1]), 0};
        };
        switch (i % 3) {
        case 0: {
            auto x = in_a(), y = in_a();
            x[2] = float(G.u(0.01, 1));
            y[2] = -float(G.u(0.01, 1));
            return {a, {{a[0], x, y}}};
        }
        case 1: return {a, {{a[0], in_a(), in_a()}}};
        default: return {a, {{a[0], a[1], in_a()}}};
        }
    }
    default: {
        // Degenerate: segments (a repeated vertex or a collinear third), points.
        T3 a = G.tri(1), b = G.tri(1);
        switch (i % 5) {
        case 0: b[2] = b[0]; break;                                              // segment vs triangle
        case 1: for (int k = 0; k < 3; k++) b[2][k] = float(0.5 * (float(b[0][k]) + float(b[1][k]))); break; // collinear
        case 2: {                                                               // point on a (in a's plane)
            a[0][2] = a[1][2] = a[2][2] = 0.25;
            std::array<double, 3> q = {float(0.3 * a[0][0] + 0.3 * a[1][0] + 0.4 * a[2][0]),
                                       float(0.3 * a[0][1] + 0.3 * a[1][1] + 0.4 * a[2][1]), 0.25};
            b = {{q, q, q}};
            break;
        }
        case 3: {                                                               // crossing segments in z = 0
            a = {{{G.u(-1, 0), G.u(-1, 1), 0}, {G.u(0, 1), G.u(-1, 1), 0}, {0, 0, 0}}};
            a[2] = a[0];
            b = {{{G.u(-1, 1), G.u(-1, 0), 0}, {G.u(-1, 1), G.u(0, 1), 0}, {0, 0, 0}}};
            b[2] = b[1];
            break;
        }
        default: a[1] = a[0]; b[2] = b[1]; break;                               // segment vs segment (skew)
        }
        return {a, b};
    }
    }
}
const char *kind_name[NKIND] = {"random",          "coplanar",   "touching",
                                "slivers",         "near 1e-3..1e-7", "degenerate",
                                "sliver, vertex 1e-3..1e-7 above", "shared corner or edge, folded",
                                "coplanar, tilted (float-rounded)"};

// Quad pairs (meshes of one quad each: the union of triangles (v0,v1,v2), (v0,v2,v3);
// the general path of the geometry, and the hull's depth).
enum QuadKind { Q_RANDOM, Q_COPLANAR, Q_NEAR, Q_TOUCHING, NQUAD };
const char *quad_name[NQUAD] = {"quads, random", "quads, coplanar", "quads, near 1e-3..1e-7",
                                "quads, touching"};
using Q4 = std::array<std::array<double, 3>, 4>;
std::pair<Q4, Q4> make_quads(Gen &G, QuadKind k, int i) {
    // A convex quad in z = 0 whose diagonal v0-v2 lies on the x axis (a point on it is
    // exact in floats), or a random one.
    auto flat = [&](double z) {
        Q4 q = {{{0, 0, z}, {float(G.u(0.2, 0.8)), float(-G.u(0.3, 1)), z}, {1, 0, z},
                 {float(G.u(0.2, 0.8)), float(G.u(0.3, 1)), z}}};
        return q;
    };
    auto random = [&](double r) {
        Q4 q = {{G.p(r), G.p(r), G.p(r), G.p(r)}};
        return q;
    };
    switch (k) {
    case Q_RANDOM: {
        // b shifted so that a point of it (its first triangle) coincides with one of a.
        Q4 a = random(1), b = random(1);
        double w0 = G.u(0, 1), w1 = G.u(0, 1 - w0);
        for (int c = 0; c < 3; c++) {
            double pa = w0 * a[0][c] + w1 * a[1][c] + (1 - w0 - w1) * a[2][c];
            double pb = w0 * b[0][c] + w1 * b[1][c] + (1 - w0 - w1) * b[2][c];
            for (auto &v : b) v[c] += pa - pb;
        }
        return {a, b};
    }
    case Q_COPLANAR: {
        // Both in z = c (exact in floats), random or convex.
        double c = float(G.u(-1, 1));
        Q4 a = i % 2 ? flat(c) : random(1), b = random(1);
        for (auto *q : {&a, &b})
            for (auto &v : *q) v[2] = c;
        return {a, b};
    }
    case Q_NEAR: {
        // b's first vertex h = 1e-3..1e-7 above (apart) or below (crossing) a point of a's
        // interior or of its diagonal, its others farther on that side. Half of the quads
        // are not convex: bent along the diagonal (corners 1 and 3 raised: a valley over
        // it) or a dart (corner 3 pulled in past the diagonal).
        Q4 a = flat(0);
        if (i % 8 >= 6) {
            a[3] = {float(G.u(0.3, 0.6)), float(-G.u(0.05, 0.2)), 0};
        } else if (i % 8 >= 4) {
            a[1][2] = a[3][2] = float(G.u(1e-3, 0.3));
        }
        double h = std::pow(10.0, G.u(-7, -3)) * (i % 2 ? 1 : -1);
        std::array<double, 3> q = i % 4 < 2 ? std::array<double, 3>{G.u(0.2, 0.8), 0, h}
                                            : std::array<double, 3>{G.u(0.3, 0.7), G.u(-0.1, 0.1), h};
        auto up = [&] { return std::array<double, 3>{q[0] + G.u(-0.5, 0.5), q[1] + G.u(-0.5, 0.5), h + G.u(0.1, 1) * (h > 0 ? 1 : -1) * (i % 3 ? 1 : -1)}; };
        Q4 b = {{q, up(), up(), up()}};
        return {a, b};
    }
    default: {
        // b's first vertex on a's diagonal (inside the quad), on an edge or on a corner;
        // its others above (some below: crossing).
        Q4 a = flat(0);
        std::array<double, 3> q;
        switch (i % 3) {
        case 0: q = {float(G.u(0.1, 0.9)), 0, 0}; break; // on the diagonal
        case 1: q = a[1]; break;                           // a corner
        default: {                                         // on edge v2-v3 (at its middle, exact)
            for (int c = 0; c < 3; c++) q[c] = 0.5 * (a[2][c] + a[3][c]);
            if (float(q[0]) != q[0] || float(q[1]) != q[1]) q = a[2];
        }
        }
        auto up = [&](double s) { return std::array<double, 3>{q[0] + G.u(-0.5, 0.5), q[1] + G.u(-0.5, 0.5), s * G.u(0.1, 1)}; };
        Q4 b = {{q, up(1), up(i % 5 ? 1 : -1), up(1)}};
        return {a, b};
    }
    }
}

// Quads whose union of triangles is not their hull, or is degenerate (issue 28): bent
// (v1, v3 raised or lowered off the diagonal v0-v2), bowties (edges v0-v1 and v2-v3 cross;
// planar half the time, and every fourth a symmetric one in z = 0 whose halves' area
// vectors cancel, with a partner in its plane), darts (reflex at v0: the diagonal inside,
// the union the dart), degenerate (repeated or collinear vertices), each against a triangle
// or a quad (random, or odd too), crossing (a point of each made to coincide); and touching:
// the partner's first vertex on a's diagonal or at its v0, its others on the concave side
// (between a bent quad's halves, else above), so that many pairs only touch although they
// enter the hull. In a frame where the diagonal is the x axis from 0 to 1, then turned at
// random (not the degenerate ones, whose collinear vertices stay exact on that axis; a
// touching pair half the time, when its touching point stays exact).
enum UnionKind { U_BENT, U_BOWTIE, U_DART, U_DEGENERATE, U_TOUCHING, NUNION };
const char *union_name[NUNION] = {"quads bent", "quads bowtie", "quads dart", "quads degenerate",
                                  "quads bent/bowtie/dart, touching"};
std::array<double, 9> random_turn(Gen &G) {
    double q[4] = {G.u(-1, 1), G.u(-1, 1), G.u(-1, 1), G.u(-1, 1)};
    double l = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
    double w = q[0] / l, x = q[1] / l, y = q[2] / l, z = q[3] / l;
    return {1 - 2 * (y * y + z * z), 2 * (x * y - w * z),     2 * (x * z + w * y),
            2 * (x * y + w * z),     1 - 2 * (x * x + z * z), 2 * (y * z - w * x),
            2 * (x * z - w * y),     2 * (y * z + w * x),     1 - 2 * (x * x + y * y)};
}
void turn(const std::array<double, 9> &m, Q4 &q) {
    for (auto &p : q) {
        std::array<double, 3> r;
        for (int k = 0; k < 3; k++) r[k] = m[3 * k] * p[0] + m[3 * k + 1] * p[1] + m[3 * k + 2] * p[2];
        p = r;
    }
}
Q4 odd_local(Gen &G, int k, int i) {
    auto side = [&] { return G.u(0.3, 1); };
    switch (k) {
    case U_BENT: return {{{0, 0, 0}, {G.u(0.1, 0.9), -side(), G.u(-0.6, 0.6)}, {1, 0, 0}, {G.u(0.1, 0.9), side(), G.u(-0.6, 0.6)}}};
    case U_BOWTIE: {
        if (i % 4 == 3) {
            double s = float(G.u(0.3, 1));
            return {{{0, 0, 0}, {s, s, 0}, {s, 0, 0}, {0, s, 0}}};
        }
        double h = i % 2 ? 0.5 : 0;
        return {{{0, 0, 0}, {G.u(0.6, 1.2), side(), G.u(-h, h)}, {1, 0, 0}, {G.u(-0.2, 0.4), side(), G.u(-h, h)}}};
    }
    case U_DART: {
        double h = i % 2 ? 0.3 : 0, y = side();
        return {{{0, 0, 0}, {G.u(-1, -0.5), -y, G.u(-h, h)}, {1, 0, 0}, {G.u(-1, -0.5), y, G.u(-h, h)}}};
    }
    default: {
        auto v0 = G.p(1), v1 = G.p(1), v3 = G.p(1);
        std::array<double, 3> o = {0, 0, 0}, v2 = {1, 0, 0}, x1 = {float(G.u(0, 1)), 0, 0}, x3 = {float(G.u(0, 1)), 0, 0};
        switch (i % 6) {
        case 0: return {{v0, v1, v0, v3}}; // two segments from v0
        case 1: return {{o, x1, v2, v3}};  // v1 on the diagonal
        case 2: return {{v0, v1, v2, v2}}; // v3 = v2
        case 3: return {{v0, v1, v2, v1}}; // v3 = v1: one triangle twice
        case 4: return {{v0, v0, v0, v3}}; // a segment
        default: return {{o, x1, v2, x3}}; // all collinear
        }
    }
    }
}
std::array<double, 3> point_of(Gen &G, const Q4 &q, int n) {
    int t = n == 4 && G.u(0, 1) < 0.5;
    const std::array<double, 3> &p0 = q[0], &p1 = q[t ? 2 : 1], &p2 = q[t ? 3 : 2];
    double w0 = G.u(0, 1), w1 = G.u(0, 1 - w0);
    std::array<double, 3> r;
    for (int k = 0; k < 3; k++) r[k] = w0 * p0[k] + w1 * p1[k] + (1 - w0 - w1) * p2[k];
    return r;
}
// a: an odd quad; b: nb = 3 a random triangle, nb = 4 a random or odd quad.
std::pair<Q4, Q4> make_union(Gen &G, UnionKind k, int i, int nb) {
    Q4 b = {{G.p(1), G.p(1), G.p(1), G.p(1)}};
    if (nb == 4 && i % 2) {
        b = odd_local(G, int(G.u(0, 3.999)), i / 2);
        turn(random_turn(G), b);
    }
    if (k != U_TOUCHING) {
        Q4 a = odd_local(G, k, i);
        if (k != U_DEGENERATE) turn(random_turn(G), a);
        if (k == U_BOWTIE && i % 4 == 3) {
            // In a's plane z = 0: a point, a segment or a triangle.
            for (auto &p : b) p[2] = 0;
            if (i % 12 == 3) b[1] = b[2] = b[3] = b[0];
            else if (i % 12 == 7) b[2] = b[3] = b[1];
        }
        auto x = point_of(G, a, 4), y = point_of(G, b, nb);
        for (auto &p : b)
            for (int c = 0; c < 3; c++) p[c] += x[c] - y[c];
        return {a, b};
    }
    int kind = i % 3;
    Q4 a = odd_local(G, kind, i / 3);
    std::array<double, 3> at = i % 4 == 0 ? a[0] : std::array<double, 3>{float(G.u(0.05, 0.95)), 0, 0};
    std::array<double, 3> up = {0, 0, 1};
    if (kind == U_BENT && a[1][2] + a[3][2] < 0) up[2] = -1;
    b[0] = at;
    for (int v = 1; v < 4; v++) {
        double h = G.u(0.05, 0.55);
        for (int c = 0; c < 3; c++) b[v][c] = at[c] + G.u(-0.4, 0.4) + h * up[c];
    }
    if (i % 2) {
        auto m = random_turn(G);
        turn(m, a);
        turn(m, b);
    }
    return {a, b};
}

// A position placed by the 3x4 row-major matrix m as docs/API.md defines it: each coordinate
// m[r*4+0]*x + m[r*4+1]*y + m[r*4+2]*z + m[r*4+3], in that order, every product and sum
// rounded to double (volatile: no fused multiply-add whatever the compiler flags).
void place(const double *m, const float *x, double *out) {
    for (int r = 0; r < 3; r++) {
        volatile double p0 = m[r * 4 + 0] * double(x[0]);
        volatile double p1 = m[r * 4 + 1] * double(x[1]);
        volatile double p2 = m[r * 4 + 2] * double(x[2]);
        volatile double s = p0 + p1;
        s = s + p2;
        out[r] = s + m[r * 4 + 3];
    }
}

// One family: every base kind at a scale and offset, through one scene of two one-triangle
// meshes (updated per pair), glcol_query then glcol_query_geometry. `placed`: both meshes
// under one rigid placement (glcol_mesh_set_transform: a random rotation, the offset as its
// translation; the floats are the configuration at the origin), so the world positions are
// doubles that are not floats, and the configurations (near misses, slivers) keep their
// shape to within the placement's rounding; the reference takes those doubles exactly.
// `quad` >= 0: quad pairs of that QuadKind instead of `kind`'s triangle pairs; `uni` >= 0:
// pairs of that UnionKind, a quad against a triangle (`nb` 3) or a quad (4).
void family(Checker &C, Stats &S, Kind kind, double scale, double offset, int n, uint64_t seed,
            bool placed = false, int quad = -1, int uni = -1, int nb = 3) {
    const int nva = quad >= 0 || uni >= 0 ? 4 : 3, nvb = quad >= 0 ? 4 : uni >= 0 ? nb : 3;
    Gen G;
    G.rng.seed(seed);
    GlcolSceneDesc sd;
    glcol_scene_desc_init(&sd);
    sd.backend = GLCOL_BACKEND_CPU;
    sd.epsilon = float(0.05 * scale); // band pairs too
    sd.threads = 1;
    GlcolScene *scene = nullptr;
    check(glcol_scene_create(&sd, &scene), "glcol_scene_create");
    float pa[12] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0}, pb[12] = {0, 0, 1, 1, 0, 1, 1, 1, 1, 0, 1, 1};
    uint32_t idx[4] = {0, 1, 2, 3};
    GlcolMeshId ids[2];
    for (int m = 0; m < 2; m++) {
        GlcolMeshDesc d;
        glcol_mesh_desc_init(&d);
        d.positions = m ? pb : pa;
        d.vertex_count = uint32_t(m ? nvb : nva);
        d.indices = idx;
        d.polygon_count = 1;
        d.vertices_per_polygon = uint32_t(m ? nvb : nva);
        check(glcol_mesh_create(scene, &d, &ids[m]), "glcol_mesh_create");
    }
    std::array<double, 3> off = unit(G.p(1));
    for (auto &x : off) x *= offset;
    // The placement: rotation from a random unit quaternion, translation `off`.
    double m[12] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0};
    if (placed) {
        double q[4] = {G.u(-1, 1), G.u(-1, 1), G.u(-1, 1), G.u(-1, 1)};
        double l = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
        for (double &x : q) x /= l;
        double w = q[0], x = q[1], y = q[2], z = q[3];
        double r[9] = {1 - 2 * (y * y + z * z), 2 * (x * y - w * z),     2 * (x * z + w * y),
                       2 * (x * y + w * z),     1 - 2 * (x * x + z * z), 2 * (y * z - w * x),
                       2 * (x * z - w * y),     2 * (y * z + w * x),     1 - 2 * (x * x + y * y)};
        for (int row = 0; row < 3; row++) {
            for (int k = 0; k < 3; k++) m[row * 4 + k] = r[row * 3 + k];
            m[row * 4 + 3] = off[row];
        }
        for (int k = 0; k < 2; k++) check(glcol_mesh_set_transform(scene, ids[k], m), "glcol_mesh_set_transform");
        off = {0, 0, 0};
    }
    double wa[12], wb[12];
    for (int i = 0; i < n; i++) {
        Q4 a{}, b{};
        if (quad >= 0) {
            std::tie(a, b) = make_quads(G, QuadKind(quad), i);
        } else if (uni >= 0) {
            std::tie(a, b) = make_union(G, UnionKind(uni), i, nb);
        } else {
            auto t = make(G, kind, i);
            std::copy(t.first.begin(), t.first.end(), a.begin());
            std::copy(t.second.begin(), t.second.end(), b.begin());
        }
        for (int v = 0; v < 4; v++)
            for (int k = 0; k < 3; k++) {
                pa[3 * v + k] = float(a[v][k] * scale + off[k]);
                pb[3 * v + k] = float(b[v][k] * scale + off[k]);
            }
        for (int v = 0; v < 4; v++) {
            place(m, pa + 3 * v, wa + 3 * v);
            place(m, pb + 3 * v, wb + 3 * v);
        }
        check(glcol_mesh_update_positions(scene, ids[0], pa, 0, uint32_t(nva), 0), "update a");
        check(glcol_mesh_update_positions(scene, ids[1], pb, 0, uint32_t(nvb), 0), "update b");
        const GlcolContact *c = nullptr;
        size_t nc = 0;
        check(glcol_query(scene, ids[0], &c, &nc), "glcol_query");
        const GlcolContactGeometry *g = nullptr;
        size_t ng = 0;
        check(glcol_query_geometry(scene, &g, &ng), "glcol_query_geometry");
        char where[64];
        snprintf(where, sizeof where, "%s pair %d", S.name.c_str(), i);
        if (ng != nc) {
            S.fail(std::string(where) + ": geometry count differs from the contact count");
            continue;
        }
        const double *ca[4] = {wa, wa + 3, wa + 6, wa + 9}, *cb[4] = {wb, wb + 3, wb + 6, wb + 9};
        if (nc == 0) {
            // Not reported: must not intersect (the query's exactness, checked in passing).
            Poly A = make_poly(ca, nva), B = make_poly(cb, nvb);
            if (meet(A, B)) S.fail(std::string(where) + ": an intersecting pair was not reported" + corners(ca, nva, cb, nvb));
            continue;
        }
        C.pair(S, ca, nva, cb, nvb, g[0], where);
    }
    glcol_scene_destroy(scene);
}

// glcol_query_all, then glcol_query_geometry: the pair count, or SIZE_MAX (a failure
// recorded) when the two counts differ.
size_t query_all_geometry(GlcolScene *scene, Stats &S, const GlcolPair **p, const GlcolContactGeometry **g) {
    size_t np = 0, ng = 0;
    check(glcol_query_all(scene, p, &np), "glcol_query_all");
    check(glcol_query_geometry(scene, g, &ng), "glcol_query_geometry");
    if (ng != np) {
        S.fail(S.name + ": geometry count differs from the pair count");
        return SIZE_MAX;
    }
    return np;
}

// A scene of real (or the cross-check's generated) meshes: glcol_query_all at the scene's
// epsilon on some frames, every pair checked.
void mesh_scene(Checker &C, Stats &S, const Scene &sc, int frames) {
    GlcolSceneDesc sd;
    glcol_scene_desc_init(&sd);
    sd.backend = GLCOL_BACKEND_CPU;
    sd.epsilon = sc.eps;
    GlcolScene *scene = nullptr;
    check(glcol_scene_create(&sd, &scene), "glcol_scene_create");
    Frame f;
    sc.frame(0, f);
    GlcolMeshId ids[2];
    const Mesh *ms[2] = {&sc.A.mesh, &sc.B.mesh};
    for (int m = 0; m < 2; m++) {
        GlcolMeshDesc d;
        glcol_mesh_desc_init(&d);
        d.positions = m ? f.b.data() : f.a.data();
        d.vertex_count = ms[m]->nv();
        d.indices = ms[m]->poly.data();
        d.polygon_count = ms[m]->npoly();
        d.vertices_per_polygon = ms[m]->vpp;
        check(glcol_mesh_create(scene, &d, &ids[m]), "glcol_mesh_create");
    }
    for (int fi = 0; fi < frames; fi++) {
        int fr = frames == 1 ? 0 : fi * (sc.frames - 1) / (frames - 1);
        sc.frame(fr, f);
        check(glcol_mesh_update_positions(scene, ids[0], f.a.data(), 0, ms[0]->nv(), 0), "update a");
        check(glcol_mesh_update_positions(scene, ids[1], f.b.data(), 0, ms[1]->nv(), 0), "update b");
        const GlcolPair *p = nullptr;
        const GlcolContactGeometry *g = nullptr;
        size_t np = query_all_geometry(scene, S, &p, &g);
        if (np == SIZE_MAX) continue;
        for (size_t i = 0; i < np; i++) {
            if (p[i].mesh_a != ids[0] || p[i].mesh_b != ids[1]) continue;
            double xa[4][3], xb[4][3];
            const double *ca[4] = {xa[0], xa[1], xa[2], xa[3]}, *cb[4] = {xb[0], xb[1], xb[2], xb[3]};
            uint32_t va = ms[0]->vpp, vb = ms[1]->vpp;
            for (uint32_t j = 0; j < va; j++)
                for (int k = 0; k < 3; k++) xa[j][k] = f.a[3 * size_t(ms[0]->poly[size_t(p[i].polygon_a) * va + j]) + k];
            for (uint32_t j = 0; j < vb; j++)
                for (int k = 0; k < 3; k++) xb[j][k] = f.b[3 * size_t(ms[1]->poly[size_t(p[i].polygon_b) * vb + j]) + k];
            char where[160];
            snprintf(where, sizeof where, "%s frame %d pair (%u, %u)", S.name.c_str(), fr, p[i].polygon_a,
                     p[i].polygon_b);
            C.pair(S, ca, int(va), cb, int(vb), g[i], where);
        }
    }
    glcol_scene_destroy(scene);
}

// A frame of a simulation scene (../shared/meshes/sim: one OBJ per body), every body a mesh
// with its self-collision on, glcol_query_all at `eps` times the scene's extent, and every
// pair checked: between bodies and within one (a folding cloth, a twisted rod: neighbours
// included, which meet elsewhere than where they are joined).
void sim_scene(Checker &C, Stats &S, const std::string &dir, const std::string &frame, int parts, double eps) {
    std::vector<Mesh> ms;
    std::vector<std::vector<float>> pos;
    double lo[3] = {HUGE_VAL, HUGE_VAL, HUGE_VAL}, hi[3] = {-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
    for (int k = 0; k < parts; k++) {
        char name[64];
        snprintf(name, sizeof name, "%s_part%02d", frame.c_str(), k);
        ms.push_back(load_obj(dir, name));
        pos.emplace_back(ms.back().rest.begin(), ms.back().rest.end());
        double l[3], h[3];
        bbox(ms.back(), l, h);
        for (int c = 0; c < 3; c++) lo[c] = std::min(lo[c], l[c]), hi[c] = std::max(hi[c], h[c]);
    }
    GlcolSceneDesc sd;
    glcol_scene_desc_init(&sd);
    sd.backend = GLCOL_BACKEND_CPU;
    sd.epsilon = float(eps * std::max(hi[0] - lo[0], std::max(hi[1] - lo[1], hi[2] - lo[2])));
    GlcolScene *scene = nullptr;
    check(glcol_scene_create(&sd, &scene), "glcol_scene_create");
    std::map<GlcolMeshId, int> of;
    for (int k = 0; k < parts; k++) {
        GlcolMeshDesc d;
        glcol_mesh_desc_init(&d);
        d.positions = pos[k].data();
        d.vertex_count = ms[k].nv();
        d.indices = ms[k].poly.data();
        d.polygon_count = ms[k].npoly();
        d.vertices_per_polygon = ms[k].vpp;
        GlcolMeshId id;
        check(glcol_mesh_create(scene, &d, &id), "glcol_mesh_create");
        check(glcol_mesh_set_self_collision(scene, id, true), "glcol_mesh_set_self_collision");
        of[id] = k;
    }
    const GlcolPair *p = nullptr;
    const GlcolContactGeometry *g = nullptr;
    size_t np = query_all_geometry(scene, S, &p, &g);
    for (size_t i = 0; np != SIZE_MAX && i < np; i++) {
        const double *c[2][4];
        double x[2][4][3];
        int nv[2];
        for (int side = 0; side < 2; side++) {
            int k = of[side ? p[i].mesh_b : p[i].mesh_a];
            uint32_t poly = side ? p[i].polygon_b : p[i].polygon_a, vpp = ms[k].vpp;
            nv[side] = int(vpp);
            for (uint32_t j = 0; j < vpp; j++) {
                for (int q = 0; q < 3; q++) x[side][j][q] = pos[k][3 * size_t(ms[k].poly[size_t(poly) * vpp + j]) + q];
                c[side][j] = x[side][j];
            }
        }
        char where[160];
        snprintf(where, sizeof where, "%s pair (%u:%u, %u:%u)", S.name.c_str(), p[i].mesh_a, p[i].polygon_a,
                 p[i].mesh_b, p[i].polygon_b);
        C.pair(S, c[0], nv[0], c[1], nv[1], g[i], where);
    }
    glcol_scene_destroy(scene);
}

} // namespace

int main(int argc, char **argv) {
    std::string dir = "../shared/meshes", only;
    int npairs = 3000, frames = 10;
    Checker C;
    for (int i = 1; i < argc; i++) {
        std::string a = argv[i];
        auto next = [&]() -> std::string {
            if (i + 1 >= argc) {
                fprintf(stderr, "%s needs a value\n", a.c_str());
                exit(2);
            }
            return argv[++i];
        };
        if (a == "--meshes") dir = next();
        else if (a == "--pairs") npairs = atoi(next().c_str());
        else if (a == "--frames") frames = atoi(next().c_str());
        else if (a == "--limit") C.limit = atof(next().c_str());
        else if (a == "--only") only = next();
        else if (a == "--inject") C.inject = true;
        else {
            fprintf(stderr,
                    "usage: contact_check [--meshes DIR] [--pairs N] [--frames N] [--limit ULPS] [--only TEXT] "
                    "[--inject]\n");
            return 2;
        }
    }
    std::vector<Stats> all;
    try {
        struct Fam {
            const char *tag;
            double scale, offset;
            std::vector<Kind> kinds;
            bool placed = false;
        };
        std::vector<Kind> every = {RANDOM, COPLANAR, TOUCHING, SLIVER, NEAR, DEGENERATE, NEAR_SLIVER};
        std::vector<Fam> fams = {
            {"", 1, 0, every},
            {", offset 1e3", 1, 1e3, every},
            {", offset 1e5", 1, 1e5, {RANDOM, SLIVER, NEAR, DEGENERATE, NEAR_SLIVER}},
            {", scale 1e-4", 1e-4, 0, {RANDOM, COPLANAR, SLIVER, NEAR, DEGENERATE, NEAR_SLIVER}},
            {", scale 1e4", 1e4, 0, {RANDOM, COPLANAR, SLIVER, NEAR, DEGENERATE, NEAR_SLIVER}},
            // Placed by glcol_mesh_set_transform: world positions in double, not floats.
            {", placed", 1, 0, every, true},
            {", placed, offset 1e3", 1, 1e3, every, true},
            {", placed, scale 1e-4", 1e-4, 0, {RANDOM, SLIVER, NEAR, DEGENERATE, NEAR_SLIVER}, true},
        };
        uint64_t seed = 1;
        // One family: its own seed (counted whether it runs or not, so that --only draws
        // the same pairs), run unless --only leaves it out.
        auto one = [&](const std::string &name, const std::function<void(Stats &)> &run) {
            Stats S;
            S.name = name;
            seed++;
            if (!only.empty() && name.find(only) == std::string::npos) return;
            C.injected = false;
            run(S);
            all.push_back(S);
        };
        auto families = [&](const std::vector<Fam> &list) {
            for (auto &F : list)
                for (Kind k : F.kinds)
                    one(std::string(kind_name[k]) + F.tag,
                        [&](Stats &S) { family(C, S, k, F.scale, F.offset, npairs, seed, F.placed); });
        };
        families(fams);
        // Quad pairs, at the origin, 1e3 off it, and placed.
        struct QFam {
            const char *tag;
            double offset;
            bool placed;
        };
        for (QFam F : {QFam{"", 0, false}, QFam{", offset 1e3", 1e3, false}, QFam{", placed", 0, true}})
            for (int k = 0; k < NQUAD; k++)
                one(std::string(quad_name[k]) + F.tag,
                    [&](Stats &S) { family(C, S, RANDOM, 1, F.offset, npairs / 2, seed, F.placed, k); });
        // Quads that are not convex and planar (issue 28), against triangles and quads, at
        // the origin, 1e3 off it, and placed.
        for (QFam F : {QFam{"", 0, false}, QFam{", offset 1e3", 1e3, false}, QFam{", placed", 0, true}})
            for (int k = 0; k < NUNION; k++)
                for (int nb : {3, 4})
                    one(std::string(union_name[k]) + (nb == 3 ? " vs triangles" : " vs quads") + F.tag,
                        [&](Stats &S) { family(C, S, RANDOM, 1, F.offset, npairs / 6, seed, F.placed, -1, k, nb); });
        // Neighbours folded through each other (self-collision's adjacent pairs), then one
        // random plane rounded to floats: at the origin, 1e3 off it, and placed.
        for (Kind k : {SHARED, TILTED})
            families({{"", 1, 0, {k}}, {", offset 1e3", 1, 1e3, {k}}, {", placed", 1, 0, {k}, true}});
        // The float range's ends: near its smallest normal numbers, and placed near its
        // largest (every product of the constructions within f64's range either way).
        families({{", scale 1e-36", 1e-36, 0, every}, {", placed, scale 1e30", 1e30, 0, every, true}});
        // Real meshes: the heavy organ pair and two instrument cases (the cross-check's
        // placement and warps), then the cross-check's generated scenes that stress geometry.
        std::vector<std::function<Scene()>> scenes;
        const double d1[3] = {-0.2, 1, 0.4}, d0[3] = {1, 0.3, 0.2};
        scenes.push_back([&] { return organ_vs_organ(load_obj(dir, "colon"), load_obj(dir, "small_intestine"), 100); });
        scenes.push_back([&] { return instrument_vs_organ(load_obj(dir, "forceps_jaw"), load_obj(dir, "colon"), d1, 100); });
        scenes.push_back(
            [&] { return instrument_vs_organ(load_obj(dir, "scissors_blade"), load_obj(dir, "liver_glt"), d0, 100); });
        auto cc = crosscheck_scenes(dir, 0);
        const char *picked[] = {"coplanar overlap", "edge touch, folded", "vertex on face", "thin blade", "quads"};
        for (size_t i = 24; i < cc.size(); i++) scenes.push_back(cc[i]); // the generated ones (cheap to build)
        for (auto &make : scenes) {
            Scene sc = make();
            bool want = sc.kind != "generated";
            for (const char *p : picked) want = want || sc.name.find(p) == 0;
            if (!want || (!only.empty() && sc.name.find(only) == std::string::npos)) continue;
            Stats S;
            S.name = sc.name;
            C.injected = false;
            mesh_scene(C, S, sc, frames);
            all.push_back(S);
        }
        // Simulation frames, self-collision on (at epsilon 0 and within a band).
        // (The rods touch along their length: a band of 1e-5 of the extent gives 34,537 pairs, 1e-3 190,387.)
        struct Sim {
            const char *scene, *frame;
            int parts;
            double band;
        };
        for (Sim sim : {Sim{"cloth-funnel", "frame227", 4, 1e-3}, Sim{"rod-twist", "frame3036", 4, 1e-5},
                        Sim{"armadillo-rollers", "frame326", 7, 1e-3}})
            for (double eps : {0.0, sim.band}) {
                Stats S;
                char band[32];
                snprintf(band, sizeof band, ", band %g", eps);
                S.name = std::string("sim ") + sim.scene + " " + sim.frame + (eps > 0 ? band : "") +
                         " (self-collision on)";
                if (!only.empty() && S.name.find(only) == std::string::npos) continue;
                C.injected = false;
                sim_scene(C, S, dir + "/sim/" + sim.scene, sim.frame, sim.parts, eps);
                all.push_back(S);
            }
    } catch (const std::exception &e) {
        fprintf(stderr, "contact_check: %s\n", e.what());
        return 2;
    }
    printf("Worst errors in float ulps (limit %.0f). pt: point to the exact intersection, ext: |pa-pb| vs "
           "its diameter (ulps of M); depth: vs exact SAT (ulps of max(D, 2^-24 E)); sep: least k in 1,2,4,8 such that a moved by (depth + k ulp(E)) * normal no longer meets b; n len: | |normal| - 1 | in ulps of 1; "
           "copl n: angle to a's normal / 2^-24; band d: distance (as depth); band pts: ulps of M; band n: "
           "distance - separation along n (ulps of E)\n\n",
           C.limit);
    printf("| family | pairs | intersecting | coplanar | band | pt | ext | depth | sep | n len | copl n | band d | "
           "band pts | band n | failures |\n|---|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|\n");
    long fails = 0;
    Stats W;
    W.name = "**worst**";
    for (auto &S : all) {
        printf("| %s | %ld | %ld | %ld | %ld | %.2f | %.2f | %.2f | %.0f | %.2f | %.2f | %.2f | %.2f | %.2f | %ld |\n",
               S.name.c_str(), S.pairs, S.inter, S.copl, S.band, S.pt, S.ext, S.depth, S.sep, S.nlen, S.cnorm, S.bdist,
               S.bpts, S.bnorm, S.fails);
        fails += S.fails;
        W.pairs += S.pairs, W.inter += S.inter, W.copl += S.copl, W.band += S.band;
        W.pt = std::max(W.pt, S.pt), W.ext = std::max(W.ext, S.ext), W.depth = std::max(W.depth, S.depth);
        W.sep = std::max(W.sep, S.sep);
        W.nlen = std::max(W.nlen, S.nlen), W.cnorm = std::max(W.cnorm, S.cnorm), W.bdist = std::max(W.bdist, S.bdist);
        W.bpts = std::max(W.bpts, S.bpts), W.bnorm = std::max(W.bnorm, S.bnorm);
    }
    printf("| %s | %ld | %ld | %ld | %ld | %.2f | %.2f | %.2f | %.0f | %.2f | %.2f | %.2f | %.2f | %.2f | %ld |\n",
           W.name.c_str(), W.pairs, W.inter, W.copl, W.band, W.pt, W.ext, W.depth, W.sep, W.nlen, W.cnorm, W.bdist,
           W.bpts, W.bnorm, fails);
    for (auto &S : all)
        for (auto &m : S.msgs) printf("FAIL %s\n", m.c_str());
    if (fails) {
        printf("\ncontact_check: %ld failing pairs\n", fails);
        return 1;
    }
    printf("\ncontact_check: all %ld pairs within %.0f ulps\n", W.pairs, C.limit);
    return 0;
}
