// The exact answer and the exact test the peers without one use: CGAL 5.5 with exact
// predicates (Epick). Inputs are floats widened to double, so they are exact.
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/intersections.h>
#include <CGAL/squared_distance_3.h>

#include <algorithm>
#include <cmath>

#include "common.h"

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using P3 = K::Point_3;
using T3 = K::Triangle_3;
using S3 = K::Segment_3;

static P3 pt(const double* p) { return P3(p[0], p[1], p[2]); }

// CGAL's Triangle_3 predicates assume a non-degenerate triangle: degenerate ones are
// treated as the segment (or point) they collapse to.
static bool degenerate(const double* a, const double* b, const double* c) {
  return CGAL::collinear(pt(a), pt(b), pt(c));
}

static bool seg_of(const double* a, const double* b, const double* c, S3& s) {
  // the longest side covers a collinear triple
  P3 p[3] = {pt(a), pt(b), pt(c)};
  int best = 0;
  double bl = -1;
  for (int i = 0; i < 3; i++) {
    double l = CGAL::squared_distance(p[i], p[(i + 1) % 3]);
    if (l > bl) bl = l, best = i;
  }
  s = S3(p[best], p[(best + 1) % 3]);
  return bl > 0;
}

bool tri_exact(const double* a0, const double* a1, const double* a2, const double* b0,
               const double* b1, const double* b2) {
  bool da = degenerate(a0, a1, a2), db = degenerate(b0, b1, b2);
  if (!da && !db) return CGAL::do_intersect(T3(pt(a0), pt(a1), pt(a2)), T3(pt(b0), pt(b1), pt(b2)));
  if (da && db) {
    S3 sa, sb;
    bool ha = seg_of(a0, a1, a2, sa), hb = seg_of(b0, b1, b2, sb);
    if (ha && hb) return CGAL::do_intersect(sa, sb);
    if (!ha && !hb) return pt(a0) == pt(b0);
    if (!ha) return sb.has_on(pt(a0));
    return sa.has_on(pt(b0));
  }
  const double *t0 = da ? b0 : a0, *t1 = da ? b1 : a1, *t2 = da ? b2 : a2;
  const double *s0 = da ? a0 : b0, *s1 = da ? a1 : b1, *s2 = da ? a2 : b2;
  T3 t(pt(t0), pt(t1), pt(t2));
  S3 s;
  if (!seg_of(s0, s1, s2, s)) return t.has_on(pt(s0));
  return CGAL::do_intersect(t, s);
}

double tri_distance(const double* a0, const double* a1, const double* a2, const double* b0,
                    const double* b1, const double* b2) {
  if (degenerate(a0, a1, a2) || degenerate(b0, b1, b2)) {
    // distance over the corners and sides (enough for the size of an error)
    const double* A[3] = {a0, a1, a2};
    const double* B[3] = {b0, b1, b2};
    double d = INFINITY;
    for (int i = 0; i < 3; i++)
      for (int j = 0; j < 3; j++) {
        S3 sa(pt(A[i]), pt(A[(i + 1) % 3])), sb(pt(B[j]), pt(B[(j + 1) % 3]));
        if (sa.is_degenerate() || sb.is_degenerate())
          d = std::min(d, CGAL::squared_distance(pt(A[i]), pt(B[j])));
        else
          d = std::min(d, CGAL::squared_distance(sa, sb));
      }
    return std::sqrt(d);
  }
  return std::sqrt(CGAL::squared_distance(T3(pt(a0), pt(a1), pt(a2)), T3(pt(b0), pt(b1), pt(b2))));
}

namespace {
struct Box {
  double lo[3], hi[3];
  uint32_t id;
};
std::vector<Box> boxes(const Mesh& m, const std::vector<double>& v) {
  std::vector<Box> out(m.nt());
  for (size_t i = 0; i < m.nt(); i++) {
    Box& b = out[i];
    b.id = uint32_t(i);
    for (int k = 0; k < 3; k++) b.lo[k] = INFINITY, b.hi[k] = -INFINITY;
    for (int c = 0; c < 3; c++) {
      const double* p = &v[3 * m.t[3 * i + c]];
      for (int k = 0; k < 3; k++) b.lo[k] = std::min(b.lo[k], p[k]), b.hi[k] = std::max(b.hi[k], p[k]);
    }
  }
  std::sort(out.begin(), out.end(), [](const Box& x, const Box& y) { return x.lo[0] < y.lo[0]; });
  return out;
}
bool overlap(const Box& x, const Box& y) {
  for (int k = 0; k < 3; k++)
    if (x.lo[k] > y.hi[k] || y.lo[k] > x.hi[k]) return false;
  return true;
}
}  // namespace

std::vector<Pair> reference_pairs(const Mesh& a, const std::vector<double>& av, const Mesh& b,
                                  const std::vector<double>& bv) {
  std::vector<Box> ba = boxes(a, av), bb = boxes(b, bv);
  std::vector<Pair> out;
  auto test = [&](uint32_t i, uint32_t j) {
    const uint32_t* ta = &a.t[3 * i];
    const uint32_t* tb = &b.t[3 * j];
    if (tri_exact(&av[3 * ta[0]], &av[3 * ta[1]], &av[3 * ta[2]], &bv[3 * tb[0]], &bv[3 * tb[1]],
                  &bv[3 * tb[2]]))
      out.push_back({i, j});
  };
  // two-list sweep along x
  size_t i = 0, j = 0;
  while (i < ba.size() && j < bb.size()) {
    if (ba[i].lo[0] <= bb[j].lo[0]) {
      for (size_t k = j; k < bb.size() && bb[k].lo[0] <= ba[i].hi[0]; k++)
        if (overlap(ba[i], bb[k])) test(ba[i].id, bb[k].id);
      i++;
    } else {
      for (size_t k = i; k < ba.size() && ba[k].lo[0] <= bb[j].hi[0]; k++)
        if (overlap(ba[k], bb[j])) test(ba[k].id, bb[j].id);
      j++;
    }
  }
  std::sort(out.begin(), out.end());
  return out;
}
