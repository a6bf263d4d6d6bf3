// The exact reference and the judge of both drivers, built on CGAL (libcgal-dev), which
// shares no code with glcollide, FCL, Bullet or Embree.
//
// * exact_pairs: a sweep over the triangles' exact double boxes (closed comparisons, so no
//   rounding can lose a pair), then CGAL::do_intersect on the closed triangles with the
//   Exact_predicates_inexact_constructions_kernel (filtered, exact predicates). A triangle
//   whose corners are collinear is a segment or a point (glcollide's documented meaning),
//   so it is tested as a CGAL Segment_3 / Point_3 instead (CGAL's Triangle_3 predicates
//   require non-degenerate triangles).
// * judge: for one polygon pair, exact intersection (as above), then with exact constructions
//   (Exact_predicates_exact_constructions_kernel: GMP rationals, evaluated only when its
//   interval filter cannot decide) the exact squared distance (min over vertex-simplex and
//   edge-edge distances, which is the distance of two disjoint triangles) and, for pairs
//   that meet, whether a plane separates them weakly (the 17 SAT axes of two triangles,
//   exact dot products): then they only touch (shared vertex/edge, contact on the boundary,
//   coplanar overlap), else they truly cross.
// The cross-check judges every disagreement with these; the benchmark takes exact_pairs as
// its exact answer, exact_tri_intersect as the narrow phase after Bullet's and Embree's
// candidates, and judge's distance for the pairs a configuration reports beyond the answer.
#include "common.hpp"

#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Gmpq.h>
#include <CGAL/Interval_nt.h>
#include <CGAL/Simple_cartesian.h>
#include <CGAL/intersections.h>
#include <CGAL/squared_distance_3.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>

namespace peers {

const char *const class_name[NCLASS] = {"cross", "touch", "band", "apart"};

namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using P = K::Point_3;

// A closed triangle reduced to what it is: triangle (dim 2), segment (dim 1) or point (0).
template <class Pt> struct Simplex {
    int dim;
    Pt p[3];
};

Simplex<P> simplex(const double *pos, const uint32_t *t) {
    P a(pos[3 * t[0]], pos[3 * t[0] + 1], pos[3 * t[0] + 2]);
    P b(pos[3 * t[1]], pos[3 * t[1] + 1], pos[3 * t[1] + 2]);
    P c(pos[3 * t[2]], pos[3 * t[2] + 1], pos[3 * t[2] + 2]);
    if (!CGAL::collinear(a, b, c)) return {2, {a, b, c}};
    // Collinear: the hull is the segment between the lexicographic extremes.
    P lo = a, hi = a;
    for (const P &x : {b, c}) {
        if (CGAL::compare_xyz(x, lo) == CGAL::SMALLER) lo = x;
        if (CGAL::compare_xyz(x, hi) == CGAL::LARGER) hi = x;
    }
    if (lo == hi) return {0, {lo, lo, lo}};
    return {1, {lo, hi, hi}};
}

bool meet(const Simplex<P> &s, const Simplex<P> &t) {
    using T = K::Triangle_3;
    using S = K::Segment_3;
    if (s.dim < t.dim) return meet(t, s);
    switch (s.dim * 3 + t.dim) {
    case 8: return CGAL::do_intersect(T(s.p[0], s.p[1], s.p[2]), T(t.p[0], t.p[1], t.p[2]));
    case 7: return CGAL::do_intersect(T(s.p[0], s.p[1], s.p[2]), S(t.p[0], t.p[1]));
    case 6: return T(s.p[0], s.p[1], s.p[2]).has_on(t.p[0]);
    case 4: return CGAL::do_intersect(S(s.p[0], s.p[1]), S(t.p[0], t.p[1]));
    case 3: return S(s.p[0], s.p[1]).has_on(t.p[0]);
    default: return s.p[0] == t.p[0];
    }
}

struct Box {
    double lo[3], hi[3];
    uint32_t id;
};

void boxes(const Mesh &M, const double *pos, const Box *filter, std::vector<Box> &out) {
    out.clear();
    for (size_t t = 0; t < M.ntri(); t++) {
        Box b;
        b.id = uint32_t(t);
        for (int k = 0; k < 3; k++) {
            double v0 = pos[3 * M.tri[3 * t] + k], v1 = pos[3 * M.tri[3 * t + 1] + k],
                   v2 = pos[3 * M.tri[3 * t + 2] + k];
            b.lo[k] = std::min(v0, std::min(v1, v2));
            b.hi[k] = std::max(v0, std::max(v1, v2));
        }
        if (filter) {
            bool ok = true;
            for (int k = 0; k < 3; k++)
                ok = ok && b.lo[k] <= filter->hi[k] && filter->lo[k] <= b.hi[k];
            if (!ok) continue;
        }
        out.push_back(b);
    }
}

Box total(const std::vector<Box> &v) {
    Box t{{HUGE_VAL, HUGE_VAL, HUGE_VAL}, {-HUGE_VAL, -HUGE_VAL, -HUGE_VAL}, 0};
    for (const Box &b : v)
        for (int k = 0; k < 3; k++) {
            t.lo[k] = std::min(t.lo[k], b.lo[k]);
            t.hi[k] = std::max(t.hi[k], b.hi[k]);
        }
    return t;
}

// ---- exact constructions, filtered ----
// Each question is first answered with interval arithmetic (CGAL::Interval_nt, rounding
// upward), which throws when the answer is not certain; then it is asked again with exact
// rationals (Epeck's lazy GMP numbers, or Gmpq), so every answer is exact.
using IK = CGAL::Simple_cartesian<CGAL::Interval_nt<false>>;
using Q = CGAL::Exact_predicates_exact_constructions_kernel;

template <class KK> Simplex<typename KK::Point_3> to_k(const Simplex<P> &s) {
    Simplex<typename KK::Point_3> r;
    r.dim = s.dim;
    for (int i = 0; i < 3; i++) r.p[i] = typename KK::Point_3(s.p[i].x(), s.p[i].y(), s.p[i].z());
    return r;
}

template <class KK> typename KK::FT sq_point(const typename KK::Point_3 &x, const Simplex<typename KK::Point_3> &t) {
    if (t.dim == 2) return CGAL::squared_distance(x, typename KK::Triangle_3(t.p[0], t.p[1], t.p[2]));
    if (t.dim == 1) return CGAL::squared_distance(x, typename KK::Segment_3(t.p[0], t.p[1]));
    return CGAL::squared_distance(x, t.p[0]);
}

template <class KK> int edges(const Simplex<typename KK::Point_3> &s, typename KK::Segment_3 *e) {
    if (s.dim == 2) {
        for (int i = 0; i < 3; i++) e[i] = typename KK::Segment_3(s.p[i], s.p[(i + 1) % 3]);
        return 3;
    }
    if (s.dim == 1) {
        e[0] = typename KK::Segment_3(s.p[0], s.p[1]);
        return 1;
    }
    return 0;
}

// Squared distance of two disjoint simplices: the nearest of the vertex-simplex and edge-edge
// distances. take() is a min that does not compare intervals.
template <class KK> typename KK::FT sq_dist(const Simplex<P> &s0, const Simplex<P> &t0) {
    using FT = typename KK::FT;
    auto s = to_k<KK>(s0), t = to_k<KK>(t0);
    bool first = true;
    FT best = 0;
    auto take = [&](const FT &d) {
        if (first) best = d;
        else best = CGAL::min(best, d);
        first = false;
    };
    for (int i = 0; i <= s.dim; i++) take(sq_point<KK>(s.p[i], t));
    for (int i = 0; i <= t.dim; i++) take(sq_point<KK>(t.p[i], s));
    typename KK::Segment_3 es[3], et[3];
    int ns = edges<KK>(s, es), nt = edges<KK>(t, et);
    for (int i = 0; i < ns; i++)
        for (int j = 0; j < nt; j++) take(CGAL::squared_distance(es[i], et[j]));
    return best;
}

// Is there a plane with s on one closed side and t on the other (weak separation)? Tried on
// the SAT axes of two triangles: both normals, the 9 edge x edge directions and the 6
// in-plane edge normals (fewer for segments and points).
template <class NT> bool sat_weak(const Simplex<P> &s, const Simplex<P> &t) {
    using V = std::array<NT, 3>;
    auto pt = [](const P &p) { return V{NT(p.x()), NT(p.y()), NT(p.z())}; };
    auto sub = [](const V &a, const V &b) { return V{a[0] - b[0], a[1] - b[1], a[2] - b[2]}; };
    auto cross = [](const V &a, const V &b) {
        return V{a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
    };
    auto dot = [](const V &a, const V &b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; };
    V ps[3], pq[3];
    for (int i = 0; i <= s.dim; i++) ps[i] = pt(s.p[i]);
    for (int i = 0; i <= t.dim; i++) pq[i] = pt(t.p[i]);
    std::vector<V> es, et, axes;
    int nes = s.dim == 2 ? 3 : s.dim, net = t.dim == 2 ? 3 : t.dim;
    for (int i = 0; i < nes; i++) es.push_back(sub(ps[(i + 1) % (s.dim + 1)], ps[i]));
    for (int i = 0; i < net; i++) et.push_back(sub(pq[(i + 1) % (t.dim + 1)], pq[i]));
    if (s.dim == 2) axes.push_back(cross(es[0], es[1]));
    if (t.dim == 2) axes.push_back(cross(et[0], et[1]));
    for (auto &a : es)
        for (auto &b : et) axes.push_back(cross(a, b));
    if (s.dim == 2)
        for (auto &a : es) axes.push_back(cross(axes[0], a));
    if (t.dim == 2)
        for (auto &b : et) axes.push_back(cross(axes[s.dim == 2 ? 1 : 0], b));
    for (const V &ax : axes) {
        // A zero axis is skipped; an interval that only might be zero makes the comparisons
        // below uncertain, so the exact pass decides.
        if (CGAL::certainly(ax[0] == 0) && CGAL::certainly(ax[1] == 0) && CGAL::certainly(ax[2] == 0))
            continue;
        NT lo_s = dot(ax, ps[0]), hi_s = lo_s, lo_t = dot(ax, pq[0]), hi_t = lo_t;
        for (int i = 1; i <= s.dim; i++) { // min/max of intervals: no comparison needed
            NT d = dot(ax, ps[i]);
            lo_s = CGAL::min(lo_s, d);
            hi_s = CGAL::max(hi_s, d);
        }
        for (int i = 1; i <= t.dim; i++) {
            NT d = dot(ax, pq[i]);
            lo_t = CGAL::min(lo_t, d);
            hi_t = CGAL::max(hi_t, d);
        }
        if (bool(hi_s <= lo_t) || bool(hi_t <= lo_s)) return true;
    }
    return false;
}

bool weakly_separated(const Simplex<P> &s, const Simplex<P> &t) {
    {
        CGAL::Protect_FPU_rounding<true> guard;
        try {
            return sat_weak<CGAL::Interval_nt<false>>(s, t);
        } catch (CGAL::Uncertain_conversion_exception &) {
        }
    }
    return sat_weak<CGAL::Gmpq>(s, t);
}

// Distance class of two disjoint polygons given as sub-pairs: BAND (<= h) or APART, and the
// distance rounded to double.
Class distance_class(const std::vector<std::pair<Simplex<P>, Simplex<P>>> &sub, double h, double &dist) {
    {
        CGAL::Protect_FPU_rounding<true> guard;
        try {
            using I = CGAL::Interval_nt<false>;
            I best;
            for (size_t k = 0; k < sub.size(); k++) {
                I d = sq_dist<IK>(sub[k].first, sub[k].second);
                best = k == 0 ? d : CGAL::min(best, d);
            }
            I hh = I(h) * I(h);
            CGAL::Uncertain<bool> in = best <= hh;
            if (CGAL::is_certain(in) && !bool(best <= I(0))) { // certain, and certainly apart
                dist = std::sqrt((best.inf() + best.sup()) / 2);
                return CGAL::get_certain(in) ? BAND : APART;
            }
        } catch (CGAL::Uncertain_conversion_exception &) {
        }
    }
    Q::FT best = 0;
    for (size_t k = 0; k < sub.size(); k++) {
        Q::FT d = sq_dist<Q>(sub[k].first, sub[k].second);
        if (d == 0) throw std::runtime_error("judge: CGAL do_intersect and distance disagree");
        best = k == 0 ? d : CGAL::min(best, d);
    }
    Q::FT hq(h);
    dist = std::sqrt(CGAL::to_double(best));
    return best <= hq * hq ? BAND : APART;
}

void poly_tris(const Mesh &M, uint32_t p, uint32_t *t, int &n) {
    if (M.vpp == 3) {
        t[0] = p;
        n = 1;
    } else {
        t[0] = 2 * p;
        t[1] = 2 * p + 1;
        n = 2;
    }
}

} // namespace

bool exact_tri_intersect(const double *pa, const uint32_t *ta, const double *pb,
                         const uint32_t *tb) {
    return meet(simplex(pa, ta), simplex(pb, tb));
}

void exact_pairs(const Mesh &A, const double *pa, const Mesh &B, const double *pb,
                 std::vector<Key> &out) {
    out.clear();
    std::vector<Box> ba, bb;
    boxes(A, pa, nullptr, ba);
    Box ta = total(ba);
    boxes(B, pb, &ta, bb);
    Box tb = total(bb);
    boxes(A, pa, &tb, ba);
    auto by_x = [](const Box &x, const Box &y) { return x.lo[0] < y.lo[0]; };
    std::sort(ba.begin(), ba.end(), by_x);
    std::sort(bb.begin(), bb.end(), by_x);
    std::vector<const Box *> act[2];
    size_t i = 0, j = 0;
    while (i < ba.size() || j < bb.size()) {
        bool is_a = j >= bb.size() || (i < ba.size() && ba[i].lo[0] <= bb[j].lo[0]);
        const Box &cur = is_a ? ba[i++] : bb[j++];
        auto &other = act[is_a ? 1 : 0];
        size_t m = 0;
        for (size_t k = 0; k < other.size(); k++)
            if (other[k]->hi[0] >= cur.lo[0]) other[m++] = other[k];
        other.resize(m);
        for (const Box *o : other) {
            if (o->hi[1] < cur.lo[1] || cur.hi[1] < o->lo[1] || o->hi[2] < cur.lo[2] ||
                cur.hi[2] < o->lo[2])
                continue;
            uint32_t a = is_a ? cur.id : o->id, b = is_a ? o->id : cur.id;
            if (exact_tri_intersect(pa, &A.tri[3 * a], pb, &B.tri[3 * b])) out.push_back(key(a, b));
        }
        act[is_a ? 0 : 1].push_back(&cur);
    }
    sort_unique(out);
}

Verdict judge(const Mesh &A, const double *pa, uint32_t a, const Mesh &B, const double *pb,
              uint32_t b, double half_eps) {
    uint32_t tas[2], tbs[2];
    int na, nb;
    poly_tris(A, a, tas, na);
    poly_tris(B, b, tbs, nb);
    std::vector<std::pair<Simplex<P>, Simplex<P>>> sub, met;
    for (int i = 0; i < na; i++)
        for (int j = 0; j < nb; j++) {
            std::pair<Simplex<P>, Simplex<P>> st(simplex(pa, &A.tri[3 * tas[i]]), simplex(pb, &B.tri[3 * tbs[j]]));
            (meet(st.first, st.second) ? met : sub).push_back(st);
        }
    if (met.empty()) {
        double dist = 0;
        Class c = distance_class(sub, half_eps, dist);
        return {c, false, dist};
    }
    bool cross = false, coplanar = true;
    for (const auto &st : met) {
        const Simplex<P> &s = st.first, &t = st.second;
        if (!weakly_separated(s, t)) cross = true;
        bool cp = s.dim == 2 && t.dim == 2;
        for (int k = 0; cp && k < 3; k++) cp = CGAL::coplanar(s.p[0], s.p[1], s.p[2], t.p[k]);
        coplanar = coplanar && cp;
    }
    return {cross ? CROSS : TOUCH, !cross && coplanar, 0.0};
}

} // namespace peers
