//! Exact self-collision test for *adjacent* polygons: two polygons of one mesh that share a
//! vertex index.
//!
//! Such polygons always meet where they are joined, so they are reported only when the two
//! closed polygons meet somewhere else: a fold onto the neighbour, a vertex pushed through
//! the next triangle. This module decides that exactly, from the signs of exact `orient3d` /
//! `orient2d` predicates on the input points (and exact comparisons of their coordinates):
//! no epsilon, no constructed point, so no rounding and no NaN can decide an answer.
//!
//! # Definitions
//!
//! * A polygon is a triangle `(v0, v1, v2)` or a quad `(v0, v1, v2, v3)`; a quad is the
//!   union of its closed triangles `(v0, v1, v2)` and `(v0, v2, v3)` (as
//!   [`crate::mesh::Mesh::triangles`] splits it). Any triangle may be degenerate: a
//!   segment or a point, also through repeated indices.
//! * Its *boundary edges* are `{v_k, v_k+1}` (cyclically) with two different indices. A
//!   quad's diagonal `{v0, v2}` is not a boundary edge.
//! * *Shared vertices*: the indices that appear in both polygons. Vertices at the same
//!   position with different indices are not shared.
//! * *Shared edges*: unordered index pairs that are a boundary edge of both polygons.
//! * The *joint* `S` is the union of the shared vertices' positions and the closed segments
//!   of the shared edges.
//!
//! [`adjacent_polygons_meet`] is true iff `(A ∩ B) \ S` is not empty, for the closed
//! polygons `A` and `B`. As `A ∩ B` is the union of `t ∩ u` over the triangles `t` of `A`
//! and `u` of `B`, that is: some triangle pair has `C = t ∩ u ⊄ S`, with the joint `S` of
//! the *polygons* (not of the triangles: a quad's diagonal is never part of it).
//!
//! # The rule
//!
//! `C = t ∩ u` is convex. A convex set covered by finitely many points and segments is a
//! point or a segment, so `C ⊆ S` holds exactly when either
//!
//! 1. `C = {s}` for a shared vertex position `s`, or
//! 2. `C ⊆ M` for a *merged interval* `M`: a connected union of collinear shared edges (a
//!    segment between two shared vertices). A segment `C` inside `S` lies in the union of
//!    the shared edges on its line (the others meet that line in finitely many points, and
//!    a closed union of intervals covering all but finitely many points of `C` covers `C`),
//!    and `C` is connected, so it lies in one component of that union.
//!
//! The decision per triangle pair:
//!
//! * `C` empty ([`triangles_intersect`]): not a meeting.
//! * `t`, `u` proper triangles in one plane: they meet with area (reported) unless an edge
//!   line `λ` of one of them weakly separates them (separating axis test in 2D, exact
//!   `orient2d`). Then `C = (t ∩ λ) ∩ (u ∩ λ)` is the overlap of two collinear faces (edges
//!   or vertices), a segment between two *input* points, and rules 1 and 2 are plain
//!   point-on-segment tests.
//! * Otherwise `C` lies in a line or is a point (different planes, or a degenerate
//!   triangle).
//!   - Rule 1 for a shared position `s ∈ C`: cut `t` into the pieces of its fan around `s`
//!     (triangles `(s, a, b)` for the edges `(a, b)`, or segments `[s, a]`), each a convex
//!     set in which `s` is a corner, whose far side `F` (the edge `[a, b]`, the end `a`)
//!     does not contain `s`. Every ray from `s` into a piece leaves it through `F`. So
//!     for pieces `K1` of `t`, `K2` of `u`, `K1 ∩ K2 ≠ {s}` iff `F1` meets `K2` or `F2`
//!     meets `K1` (the first exit along a common ray is a point of one far side inside the
//!     other piece, and no far side contains `s`). Closed segment/triangle tests decide it.
//!   - Rule 2: a shared edge `σ` whose relative interior holds a point `x` of `C` lies in
//!     the affine hull of `t` (every triangle of a polygon has an end `e` of each boundary
//!     edge as a vertex, so `[e, x] ⊆ t ∩ σ`), and of `u`. So only merged intervals `M` on
//!     a line `ℓ ⊆ aff t ∩ aff u` can matter; then `C ⊆ ℓ` (`ℓ` is the planes' common line,
//!     or the line of a degenerate triangle), and on that line `C ⊆ M` iff `M` meets `t`
//!     and `u` (with `C ≠ ∅`, three intervals of a line that meet pairwise have a common
//!     point) and `C` does not leave `M` past either end `m`: `m ∈ C` and the direction
//!     away from `M` lies in the tangent cones of both `t` and `u` at `m`. That direction
//!     is `m - o` (`o` the other end), and cone membership is a sign test on `m`, `o` and
//!     the fan pieces' vertices.
//!
//! # Fast paths
//!
//! The common cloth pair (two proper triangles in different planes, sharing an edge or a
//! vertex) is decided in one to a few `orient3d`:
//!
//! * triangles sharing a shared edge `{i, j}` whose third vertex `w` of `u` is off `t`'s
//!   plane: `C` is the edge itself (both triangles are proper, and `t` meets the planes'
//!   common line only along its edge). One `orient3d`. In one plane (flat cloth), with the
//!   third vertices strictly on either side of the edge: the edge again, two `orient2d`
//!   more.
//! * triangles sharing one vertex `p` where the other vertices of one lie strictly on one
//!   side of the other's plane: `C = {p}`. Two to four `orient3d`.
//! * triangles sharing one vertex `p`, proper and not coplanar: rule 1 with the whole
//!   triangles as the pieces: `C ≠ {p}` iff the edge opposite `p` in one meets the other.
//!   A few more `orient3d`.
//! * proper triangles in one plane sharing one vertex `p`: their sectors at `p` share a
//!   ray iff `C ≠ {p}`; eight `orient2d`.
//!
//! A fast path concludes "covered" from a part of the joint, which stays true for the
//! whole joint; it concludes "not covered" from "`C ≠ {p}`" only for two triangle
//! polygons, whose joint is then exactly `{p}`. Everything else goes to the general rule.

use super::predicates::{collinear, drop_axis, orient2d, orient3d, P3};
use super::tritri::{segments_intersect, triangles_intersect, Plane};

/// Do two polygons share a vertex index (are they *adjacent*)? Every comparison made, no
/// early exit: in a self-colliding mesh about half the box pairs are neighbours, at random,
/// and the branches of an early exit mispredicted (7% of a rod's self query).
#[inline]
pub fn shares_vertex(a_idx: &[u32], b_idx: &[u32]) -> bool {
    /// All `N * M` comparisons, unrolled.
    #[inline(always)]
    fn any_equal<const N: usize, const M: usize>(a: &[u32; N], b: &[u32; M]) -> bool {
        let mut any = false;
        for x in a {
            for y in b {
                any |= x == y;
            }
        }
        any
    }
    match (<&[u32; 3]>::try_from(a_idx), <&[u32; 3]>::try_from(b_idx)) {
        // Triangles (a mesh's polygons all have one size: a predictable branch).
        (Ok(a), Ok(b)) => any_equal(a, b),
        _ => {
            let mut any = false;
            for x in a_idx {
                for y in b_idx {
                    any |= x == y;
                }
            }
            any
        }
    }
}

/// Do two adjacent polygons meet somewhere other than their shared vertices and shared
/// edges? Decided exactly; see the [module documentation](self) for the rule.
///
/// `a_idx` holds the polygon's vertex indices (3 for a triangle, 4 for a quad) and `a_tris`
/// its `na` triangles as [`crate::mesh::Mesh::triangles`] writes them: `(v0, v1, v2)`, and
/// `(v0, v2, v3)` for a quad, so that `na == a_idx.len() - 2`. Likewise for `b`.
///
/// The indices must name the *same* vertex exactly when they are equal: pass the caller's
/// vertex indices (for a [`crate::mesh::Mesh`], `slot_vertices()[slot]`), not the per-leaf
/// slot indices of `Mesh::poly`, under which one vertex has a slot per leaf.
///
/// Polygons that share no vertex get the plain answer "do they intersect". Coordinates
/// must be finite (as a mesh's are); a shared index's position is taken from `a`.
///
/// # Panics
///
/// When `na` or `nb` is not 1 or 2, or an index slice's length is not `na + 2`
/// (`nb + 2`).
pub fn adjacent_polygons_meet(
    a_idx: &[u32],
    a_tris: &[[P3; 3]; 2],
    na: usize,
    b_idx: &[u32],
    b_tris: &[[P3; 3]; 2],
    nb: usize,
) -> bool {
    let a = Polygon::new(a_idx, a_tris, na);
    let b = Polygon::new(b_idx, b_tris, nb);
    polygons_meet(&a, &b)
}

/// A cheap sufficient condition for two triangles sharing vertex indices *not* to meet
/// beyond their joint: `true` proves [`adjacent_polygons_meet`] false for them; `false`
/// tells nothing. One or two exact `orient3d` and no setup, for the common neighbours of a
/// triangle mesh (it is two of the fast paths of the [module documentation](self), without
/// building the polygons' joint):
///
/// * exactly two shared indices `{i, j}` (an edge of both) and the third vertex `w` of `b`
///   off `a`'s plane: then `a` is proper, and the points of `b = conv(i, j, w)` in `a`'s
///   plane are those with no weight on `w`, the shared edge; so `a ∩ b` lies in it;
/// * exactly one shared index `s`, and the other two vertices of one triangle strictly on
///   one side of the other's plane (which is then a plane: the triangle is proper): the
///   orientation is affine and vanishes at `s` only, so the first triangle meets that
///   plane at `s` alone, and `a ∩ b ⊆ {s}`.
///
/// When those fail (neighbours in one plane, or nearly), the same conclusions from a
/// projection onto the coordinate plane across `a`'s largest normal component, if both
/// triangles project to proper triangles there (exact `orient2d`; the projection is then
/// one-to-one on each triangle), whether or not they are in one plane:
///
/// * shared edge, the third vertices strictly on either side of its projected line: the
///   projections meet on that line only, whose preimage in each triangle is the edge;
/// * shared vertex `s`, the projected sectors at `s` (convex, below π) sharing no ray
///   (no boundary ray of one in the other's closed sector): the projections meet at `s`'s
///   image only, whose preimage in each triangle is `s`.
///
/// A triangle with a repeated index, or two triangles with all three indices in common,
/// get `false`.
#[inline]
pub fn triangles_touch_only_at_joint(
    ai: &[u32; 3],
    a: &[P3; 3],
    bi: &[u32; 3],
    b: &[P3; 3],
) -> bool {
    let sign = |x: f64| (x > 0.0) as i8 - (x < 0.0) as i8;
    touch_only_at_joint(
        ai,
        a,
        bi,
        b,
        |k| sign(orient3d(&a[0], &a[1], &a[2], &b[k])),
        |k| sign(orient3d(&b[0], &b[1], &b[2], &a[k])),
    )
}

/// [`triangles_touch_only_at_joint`] with the triangles' planes made beforehand
/// ([`Plane::of`]): each orientation is read from the plane when its floating-point value
/// is certain of the sign ([`Plane::side`]) and taken as unknown otherwise (no exact
/// `orient3d`, which is slow exactly where points are coplanar: the projected rules decide
/// those). `true` only where [`triangles_touch_only_at_joint`] is `true`.
#[inline]
pub fn triangles_touch_only_at_joint_planes(
    ai: &[u32; 3],
    a: &[P3; 3],
    pa: &Plane,
    bi: &[u32; 3],
    b: &[P3; 3],
    pb: &Plane,
) -> bool {
    touch_only_at_joint(ai, a, bi, b, |k| pa.side(&b[k]), |k| pb.side(&a[k]))
}

/// The rule of [`triangles_touch_only_at_joint`], given the signs `ob(k)` of `orient3d` of
/// `b`'s vertex `k` against `a`'s plane and `oa(k)` of `a`'s vertex `k` against `b`'s (0:
/// zero or unknown; a nonzero sign must be the true one).
#[inline(always)]
fn touch_only_at_joint(
    ai: &[u32; 3],
    a: &[P3; 3],
    bi: &[u32; 3],
    b: &[P3; 3],
    ob: impl Fn(usize) -> i8,
    oa: impl Fn(usize) -> i8,
) -> bool {
    let distinct = |i: &[u32; 3]| i[0] != i[1] && i[1] != i[2] && i[0] != i[2];
    if !distinct(ai) || !distinct(bi) {
        return false;
    }
    let shared = ai.iter().filter(|i| bi.contains(i)).count();
    // The two vertices of `x` whose index is not in `y`.
    let others = |xi: &[u32; 3], yi: &[u32; 3]| -> [usize; 2] {
        let mut o = [0; 2];
        let mut n = 0;
        for (k, i) in xi.iter().enumerate() {
            if !yi.contains(i) && n < 2 {
                o[n] = k;
                n += 1;
            }
        }
        o
    };
    // The projection of the projected rules: across `a`'s largest normal component, where
    // both triangles must project to proper triangles.
    let projected = || -> Option<usize> {
        let axis = normal_axis_guess(&a[0], &a[1], &a[2]);
        let proper = |t: &[P3; 3]| {
            orient2d(
                drop_axis(&t[0], axis),
                drop_axis(&t[1], axis),
                drop_axis(&t[2], axis),
            ) != 0.0
        };
        (proper(a) && proper(b)).then_some(axis)
    };
    match shared {
        2 => {
            let Some(w) = (0..3).find(|&k| !ai.contains(&bi[k])) else {
                return false;
            };
            if ob(w) != 0 {
                return true;
            }
            let Some(axis) = projected() else {
                return false;
            };
            // `a`'s vertex off the shared edge, and the edge's ends.
            let Some(v) = (0..3).find(|&k| !bi.contains(&ai[k])) else {
                return false;
            };
            let (i, j) = ((v + 1) % 3, (v + 2) % 3);
            let p = |x: &P3| drop_axis(x, axis);
            let sv = orient2d(p(&a[i]), p(&a[j]), p(&a[v]));
            let sw = orient2d(p(&a[i]), p(&a[j]), p(&b[w]));
            (sv > 0.0 && sw < 0.0) || (sv < 0.0 && sw > 0.0)
        }
        1 => {
            let [c, d] = others(bi, ai);
            let s = ob(c);
            if s != 0 && ob(d) == s {
                return true;
            }
            let [e, f] = others(ai, bi);
            let s = oa(e);
            if s != 0 && oa(f) == s {
                return true;
            }
            let Some(axis) = projected() else {
                return false;
            };
            let p = |x: &P3| drop_axis(x, axis);
            let apex = p(&a[3 - e - f]);
            // The sectors' rays, counterclockwise (both triangles are proper there).
            let ccw = |x: [f64; 2], y: [f64; 2]| {
                if orient2d(apex, x, y) > 0.0 {
                    [x, y]
                } else {
                    [y, x]
                }
            };
            let sa = ccw(p(&a[e]), p(&a[f]));
            let sb = ccw(p(&b[c]), p(&b[d]));
            let inside = |r: [f64; 2], s: &[[f64; 2]; 2]| {
                orient2d(apex, s[0], r) >= 0.0 && orient2d(apex, r, s[1]) >= 0.0
            };
            !(inside(sb[0], &sa) || inside(sb[1], &sa) || inside(sa[0], &sb) || inside(sa[1], &sb))
        }
        _ => false,
    }
}

/// [`adjacent_polygons_meet`] with one position per vertex: `a_pos[k]` is the position of
/// vertex `a_idx[k]`; 3 or 4 vertices each.
///
/// # Panics
///
/// When a polygon has not 3 or 4 vertices, or its two slices differ in length.
pub fn adjacent_polygons_meet_at(a_idx: &[u32], a_pos: &[P3], b_idx: &[u32], b_pos: &[P3]) -> bool {
    let a = Polygon::from_vertices(a_idx, a_pos);
    let b = Polygon::from_vertices(b_idx, b_pos);
    polygons_meet(&a, &b)
}

/// A triangle or quad: its vertices (indices and positions), `n` of them.
#[derive(Clone, Copy, Debug)]
struct Polygon {
    idx: [u32; 4],
    pos: [P3; 4],
    n: usize,
}

impl Polygon {
    fn new(idx: &[u32], tris: &[[P3; 3]; 2], ntri: usize) -> Polygon {
        assert!(ntri == 1 || ntri == 2, "a polygon has 1 or 2 triangles");
        let n = ntri + 2;
        let mut p = Polygon {
            idx: [0; 4],
            pos: [tris[0][0], tris[0][1], tris[0][2], tris[0][2]],
            n,
        };
        assert_eq!(
            idx.len(),
            n,
            "a polygon with {ntri} triangles has {n} vertices"
        );
        p.idx[..n].copy_from_slice(idx);
        if n == 4 {
            p.pos[3] = tris[1][2];
        }
        p
    }

    fn from_vertices(idx: &[u32], pos: &[P3]) -> Polygon {
        let n = idx.len();
        assert!(
            (n == 3 || n == 4) && pos.len() == n,
            "3 or 4 vertices, one position each"
        );
        let mut p = Polygon {
            idx: [0; 4],
            pos: [pos[0]; 4],
            n,
        };
        p.idx[..n].copy_from_slice(idx);
        p.pos[..n].copy_from_slice(pos);
        p
    }

    /// Triangle `k` (0, or 1 for a quad) with its vertex indices.
    #[inline]
    fn tri(&self, k: usize) -> Tri {
        let c = if k == 0 { [0, 1, 2] } else { [0, 2, 3] };
        Tri {
            i: c.map(|c| self.idx[c]),
            p: c.map(|c| self.pos[c]),
        }
    }

    /// Boundary edge `k` as an index pair.
    #[inline]
    fn edge(&self, k: usize) -> (u32, u32) {
        (self.idx[k], self.idx[(k + 1) % self.n])
    }

    fn has_edge(&self, i: u32, j: u32) -> bool {
        (0..self.n).any(|k| {
            let (a, b) = self.edge(k);
            (a == i && b == j) || (a == j && b == i)
        })
    }
}

/// One triangle of a polygon: vertex indices and positions.
#[derive(Clone, Copy, Debug)]
struct Tri {
    i: [u32; 3],
    p: [P3; 3],
}

/// The shared edges of two polygons, as index pairs (all the fast paths need).
#[derive(Clone, Copy, Debug)]
struct SharedEdges {
    e: [(u32, u32); 4],
    n: usize,
}

impl SharedEdges {
    fn of(a: &Polygon, b: &Polygon) -> SharedEdges {
        let mut s = SharedEdges {
            e: [(0, 0); 4],
            n: 0,
        };
        for k in 0..a.n {
            let (u, v) = a.edge(k);
            if u != v && b.has_edge(u, v) && !s.has(u, v) {
                s.e[s.n] = (u, v);
                s.n += 1;
            }
        }
        s
    }

    #[inline]
    fn has(&self, u: u32, v: u32) -> bool {
        self.e[..self.n]
            .iter()
            .any(|&(a, b)| (a == u && b == v) || (a == v && b == u))
    }
}

/// The joint of two polygons as points: the shared vertices' positions and the merged
/// intervals of the shared edges (see the module documentation).
#[derive(Clone, Debug)]
struct Joint {
    /// Positions of the shared vertices.
    pts: [P3; 4],
    n_pts: usize,
    /// Merged intervals: segments between two shared positions (never a single point).
    segs: [[P3; 2]; 4],
    n_segs: usize,
}

impl Joint {
    /// The positions are `a`'s (equal indices are one vertex, at one position).
    fn of(a: &Polygon, b: &Polygon, edges: &SharedEdges) -> Joint {
        let mut j = Joint {
            pts: [[0.0; 3]; 4],
            n_pts: 0,
            segs: [[[0.0; 3]; 2]; 4],
            n_segs: 0,
        };
        for k in 0..a.n {
            let i = a.idx[k];
            if !a.idx[..k].contains(&i) && b.idx[..b.n].contains(&i) {
                j.pts[j.n_pts] = a.pos[k];
                j.n_pts += 1;
            }
        }
        for &(u, v) in &edges.e[..edges.n] {
            let at = |i: u32| (0..a.n).find(|&k| a.idx[k] == i).map(|k| a.pos[k]);
            if let (Some(pu), Some(pv)) = (at(u), at(v)) {
                if pu != pv {
                    j.segs[j.n_segs] = [pu, pv];
                    j.n_segs += 1;
                }
            }
        }
        j.merge();
        j
    }

    /// Replaces collinear shared edges that meet (overlap or touch) by their union, until
    /// the intervals left are the connected components of the collinear unions.
    fn merge(&mut self) {
        'again: loop {
            for x in 0..self.n_segs {
                for y in x + 1..self.n_segs {
                    let [a, b] = self.segs[x];
                    let [c, d] = self.segs[y];
                    if collinear(&a, &b, &c)
                        && collinear(&a, &b, &d)
                        && segments_intersect(&a, &b, &c, &d)
                    {
                        self.segs[x] = hull_on_line(&[a, b, c, d]);
                        self.segs[y] = self.segs[self.n_segs - 1];
                        self.n_segs -= 1;
                        continue 'again;
                    }
                }
            }
            return;
        }
    }
}

/// The two extreme points of collinear points, not all equal (ordered by a coordinate on
/// which they differ, which orders a line).
fn hull_on_line(p: &[P3]) -> [P3; 2] {
    let k = (0..3)
        .find(|&k| p.iter().any(|q| q[k] != p[0][k]))
        .unwrap_or(0);
    let (mut lo, mut hi) = (p[0], p[0]);
    for q in p {
        if q[k] < lo[k] {
            lo = *q;
        }
        if q[k] > hi[k] {
            hi = *q;
        }
    }
    [lo, hi]
}

fn polygons_meet(a: &Polygon, b: &Polygon) -> bool {
    let edges = SharedEdges::of(a, b);
    // With two triangles the triangles' common vertices are the whole joint.
    let whole = a.n == 3 && b.n == 3;
    let mut joint = None;
    for ka in 0..a.n - 2 {
        let t = a.tri(ka);
        for kb in 0..b.n - 2 {
            let u = b.tri(kb);
            let meets = match fast(&t, &u, &edges, whole) {
                Some(r) => r,
                None => general(&t, &u, joint.get_or_insert_with(|| Joint::of(a, b, &edges))),
            };
            if meets {
                return true;
            }
        }
    }
    false
}

/// The fast paths for a triangle pair (see the module documentation): `Some(answer)` to
/// "is `t ∩ u` not inside the joint?", `None` when they cannot tell. `whole` says that
/// the two triangles are the two polygons.
fn fast(t: &Tri, u: &Tri, edges: &SharedEdges, whole: bool) -> Option<bool> {
    let mut common = [0u32; 3];
    let mut nc = 0;
    for k in 0..3 {
        let i = t.i[k];
        if u.i.contains(&i) && !common[..nc].contains(&i) {
            common[nc] = i;
            nc += 1;
        }
    }
    if nc == 2 && edges.has(common[0], common[1]) {
        // A shared edge `[p, q]` of both triangles. If the third vertex `w` of `u` is off
        // `t`'s plane, both are proper (`t` has an orientation, and `w` is off the edge's
        // line, which lies in `t`'s plane), their planes differ, and `C` lies on the
        // common line, which meets `t` along the edge only.
        let not_common = |x: &Tri| (0..3).find(|&k| !common[..2].contains(&x.i[k]));
        let w = u.p[not_common(u)?];
        if orient3d(&t.p[0], &t.p[1], &t.p[2], &w) != 0.0 {
            return Some(false);
        }
        // In `t`'s plane (flat cloth): `t` proper, `w` strictly across the edge from `t`'s
        // third vertex `v`. Then the closed half-planes of the edge's line hold one each,
        // and `C` is the edge.
        let v = t.p[not_common(t)?];
        let ax = projection_axis(&t.p[0], &t.p[1], &t.p[2])?;
        let at = |i: u32| {
            (0..3)
                .find(|&k| t.i[k] == i)
                .map(|k| drop_axis(&t.p[k], ax))
        };
        let (p, q) = (at(common[0])?, at(common[1])?);
        let sv = orient2d(p, q, drop_axis(&v, ax));
        let sw = orient2d(p, q, drop_axis(&w, ax));
        if (sv > 0.0 && sw < 0.0) || (sv < 0.0 && sw > 0.0) {
            return Some(false);
        }
    } else if nc == 0 {
        // No common vertex (a quad's other triangle): apart is the common answer.
        if !triangles_intersect(&t.p, &u.p) {
            return Some(false);
        }
    } else if nc == 1 {
        let c = common[0];
        // `u`'s other vertices strictly on one side of `t`'s plane: `u` meets the plane at
        // the common vertex only, so `C` is that vertex.
        let ou = sides(t, u, c);
        if ou.one_side() {
            return Some(false);
        }
        let ot = sides(u, t, c);
        if ot.one_side() {
            return Some(false);
        }
        // "More than `p`" answers the pair only when `p` is the whole joint.
        let r = if ou.n == 2 && ou.o[0] == 0.0 && ou.o[1] == 0.0 {
            coplanar_vertex(t, u, c)
        } else {
            vertex_rule(&ou, &ot, t, u)
        };
        match r {
            Some(false) => return Some(false),
            Some(true) if whole => return Some(true),
            _ => {}
        }
    }
    None
}

/// Two triangles in one plane, sharing the single vertex index `c` (position `p`): does
/// `t ∩ u` hold more than `p`? `None` when one of them is not proper. Near `p` each is
/// its sector at `p`, a convex cone of angle below π, and `C` is convex, so `C ≠ {p}` iff
/// the sectors share a ray; then a bounding ray of their intersection bounds one of them
/// and lies in the other. So: is an edge direction at `p` of one inside the other's
/// sector? Eight `orient2d`.
fn coplanar_vertex(t: &Tri, u: &Tri, c: u32) -> Option<bool> {
    let ax = projection_axis(&t.p[0], &t.p[1], &t.p[2])?;
    let q = |x: &P3| drop_axis(x, ax);
    // The common vertex first, then the other two.
    let corner = |x: &Tri| -> Option<[[f64; 2]; 3]> {
        let k = (0..3).find(|&k| x.i[k] == c)?;
        Some([q(&x.p[k]), q(&x.p[(k + 1) % 3]), q(&x.p[(k + 2) % 3])])
    };
    let (ct, cu) = (corner(t)?, corner(u)?);
    let (st, su) = (orient2d(ct[0], ct[1], ct[2]), orient2d(cu[0], cu[1], cu[2]));
    if st == 0.0 || su == 0.0 {
        return None;
    }
    // Direction `x - p` in the sector `(p, a, b)` of orientation `s`.
    let inside = |x: [f64; 2], k: &[[f64; 2]; 3], s: f64| {
        orient2d(k[0], k[1], x) * s >= 0.0 && orient2d(k[0], x, k[2]) * s >= 0.0
    };
    Some(
        inside(cu[1], &ct, st)
            || inside(cu[2], &ct, st)
            || inside(ct[1], &cu, su)
            || inside(ct[2], &cu, su),
    )
}

/// Orientations of the vertices of `u` other than index `c` against `t`'s plane.
struct Sides {
    o: [f64; 3],
    /// Positions of those vertices.
    p: [P3; 3],
    n: usize,
}

impl Sides {
    /// All strictly on one side (vacuously when there are none: `u` is the common point).
    fn one_side(&self) -> bool {
        let o = &self.o[..self.n];
        o.iter().all(|&x| x > 0.0) || o.iter().all(|&x| x < 0.0)
    }

    /// Two vertices strictly on either side.
    fn straddles(&self) -> bool {
        self.n == 2
            && ((self.o[0] > 0.0 && self.o[1] < 0.0) || (self.o[0] < 0.0 && self.o[1] > 0.0))
    }
}

fn sides(t: &Tri, u: &Tri, c: u32) -> Sides {
    let mut s = Sides {
        o: [0.0; 3],
        p: [[0.0; 3]; 3],
        n: 0,
    };
    for k in 0..3 {
        if u.i[k] != c {
            s.o[s.n] = orient3d(&t.p[0], &t.p[1], &t.p[2], &u.p[k]);
            s.p[s.n] = u.p[k];
            s.n += 1;
        }
    }
    s
}

/// Two triangles sharing the single vertex index `c` (position `p`), with the orientations
/// `ou` of `u`'s other vertices against `t`'s plane and `ot` the other way: does `t ∩ u`
/// hold more than `p`? When one has its two other vertices strictly on either side of the
/// other's plane and the other is proper, both are proper, `p` is a corner of each, and
/// the answer is whether the edge opposite `p` in one meets the other (rule 1 with the
/// triangles as the pieces). `None`: not that case.
fn vertex_rule(ou: &Sides, ot: &Sides, t: &Tri, u: &Tri) -> Option<bool> {
    // Straddling makes the plane's triangle proper; a vertex off the other plane makes the
    // other proper (straddling alone does not: `p` may lie between the two).
    let off = |s: &Sides| s.o[..s.n].iter().any(|&x| x != 0.0);
    if !((ou.straddles() && off(ot)) || (ot.straddles() && off(ou))) || ou.n != 2 || ot.n != 2 {
        return None;
    }
    Some(
        crossing_segment_meets(&ou.p[0], &ou.p[1], ou, &t.p)
            || crossing_segment_meets(&ot.p[0], &ot.p[1], ot, &u.p),
    )
}

/// Does the segment `a`-`b` meet the proper triangle `t`, given the orientations `s` of
/// `a` and `b` against `t`'s plane?
fn crossing_segment_meets(a: &P3, b: &P3, s: &Sides, t: &[P3; 3]) -> bool {
    if s.straddles() {
        // The segment crosses the plane at one point, inside the closed triangle iff the
        // three edge orientations have no two strictly opposite signs.
        let o = [
            orient3d(a, b, &t[0], &t[1]),
            orient3d(a, b, &t[1], &t[2]),
            orient3d(a, b, &t[2], &t[0]),
        ];
        let pos = o.iter().any(|&x| x > 0.0);
        let neg = o.iter().any(|&x| x < 0.0);
        !(pos && neg)
    } else if s.one_side() {
        false
    } else {
        triangles_intersect(&[*a, *b, *b], t)
    }
}

/// The shape of a closed triangle: proper, a segment (its two extreme points, distinct) or
/// a point.
#[derive(Clone, Copy, Debug)]
enum Shape {
    Proper,
    Segment(P3, P3),
    Point(P3),
}

fn shape(t: &[P3; 3]) -> Shape {
    if !collinear(&t[0], &t[1], &t[2]) {
        return Shape::Proper;
    }
    if t[0] == t[1] && t[0] == t[2] {
        return Shape::Point(t[0]);
    }
    let [a, b] = hull_on_line(t);
    Shape::Segment(a, b)
}

/// A coordinate plane on which the triangle `(a, b, c)` projects with area (one-to-one on
/// its plane); `None` when it is degenerate. The axis of the largest component of a
/// floating-point normal is tried first, as a guess only: the exact `orient2d` decides.
fn projection_axis(a: &P3, b: &P3, c: &P3) -> Option<usize> {
    let first = normal_axis_guess(a, b, c);
    [first, (first + 1) % 3, (first + 2) % 3]
        .into_iter()
        .find(|&ax| orient2d(drop_axis(a, ax), drop_axis(b, ax), drop_axis(c, ax)) != 0.0)
}

/// The axis of the largest component of the floating-point normal of `(a, b, c)`: a guess
/// at the coordinate plane it projects onto best (exact predicates decide).
#[inline]
fn normal_axis_guess(a: &P3, b: &P3, c: &P3) -> usize {
    let e = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
    let f = [c[0] - a[0], c[1] - a[1], c[2] - a[2]];
    let n = [
        (e[1] * f[2] - e[2] * f[1]).abs(),
        (e[2] * f[0] - e[0] * f[2]).abs(),
        (e[0] * f[1] - e[1] * f[0]).abs(),
    ];
    if n[0] >= n[1] && n[0] >= n[2] {
        0
    } else if n[1] >= n[2] {
        1
    } else {
        2
    }
}

/// [`projection_axis`] of a triangle known to be proper (which always has one).
fn proper_axis(a: &P3, b: &P3, c: &P3) -> usize {
    projection_axis(a, b, c).unwrap_or(2)
}

/// Closed segment `a`-`b` (possibly a point) contains `s`.
fn on_segment(s: &P3, a: &P3, b: &P3) -> bool {
    if a == b {
        return s == a;
    }
    collinear(a, b, s) && (0..3).all(|k| s[k] >= a[k].min(b[k]) && s[k] <= a[k].max(b[k]))
}

/// The closed triangle `t` of shape `sh` contains `s`.
fn contains(t: &[P3; 3], sh: Shape, s: &P3) -> bool {
    match sh {
        Shape::Proper => {
            if orient3d(&t[0], &t[1], &t[2], s) != 0.0 {
                return false;
            }
            let ax = proper_axis(&t[0], &t[1], &t[2]);
            let q = |p: &P3| drop_axis(p, ax);
            let o = [
                orient2d(q(&t[0]), q(&t[1]), q(s)),
                orient2d(q(&t[1]), q(&t[2]), q(s)),
                orient2d(q(&t[2]), q(&t[0]), q(s)),
            ];
            !(o.iter().any(|&x| x > 0.0) && o.iter().any(|&x| x < 0.0))
        }
        Shape::Segment(a, b) => on_segment(s, &a, &b),
        Shape::Point(a) => *s == a,
    }
}

/// The affine hull of the triangle `t` of shape `sh` (a plane, a line or a point) contains
/// `s`.
fn in_hull(t: &[P3; 3], sh: Shape, s: &P3) -> bool {
    match sh {
        Shape::Proper => orient3d(&t[0], &t[1], &t[2], s) == 0.0,
        Shape::Segment(a, b) => collinear(&a, &b, s),
        Shape::Point(a) => *s == a,
    }
}

/// A piece of a triangle's fan around a point `s` of it: `s` is a corner of the piece and
/// not on its far side.
#[derive(Clone, Copy, Debug)]
enum Piece {
    /// The proper triangle `(s, a, b)`; far side the edge `[a, b]`.
    Wedge(P3, P3),
    /// The segment `[s, a]`, `a ≠ s`; far side `{a}`.
    Ray(P3),
}

impl Piece {
    fn far(&self) -> [P3; 3] {
        match *self {
            Piece::Wedge(a, b) => [a, b, b],
            Piece::Ray(a) => [a, a, a],
        }
    }

    fn set(&self, s: &P3) -> [P3; 3] {
        match *self {
            Piece::Wedge(a, b) => [*s, a, b],
            Piece::Ray(a) => [*s, a, a],
        }
    }
}

/// The fan of `t` (shape `sh`, containing `s`) around `s`: pieces whose union is `t`.
/// A proper triangle is the union of the triangles `(s, a, b)` over its edges `(a, b)`;
/// the degenerate ones among them (`s` on the edge's line) are covered by the others, and
/// at least one is proper. A segment `[a, b]` is `[s, a] ∪ [s, b]`; a point has no piece.
fn fan(t: &[P3; 3], sh: Shape, s: &P3) -> ([Piece; 3], usize) {
    let mut out = [Piece::Ray(*s); 3];
    let mut n = 0;
    match sh {
        Shape::Proper => {
            for k in 0..3 {
                let (a, b) = (t[k], t[(k + 1) % 3]);
                if !collinear(s, &a, &b) {
                    out[n] = Piece::Wedge(a, b);
                    n += 1;
                }
            }
        }
        Shape::Segment(a, b) => {
            for e in [a, b] {
                if e != *s {
                    out[n] = Piece::Ray(e);
                    n += 1;
                }
            }
        }
        Shape::Point(_) => {}
    }
    (out, n)
}

/// Does `t ∩ u`, which contains `s`, contain another point? (Rule 1, see the module
/// documentation.)
fn more_than_point(s: &P3, t: &[P3; 3], st: Shape, u: &[P3; 3], su: Shape) -> bool {
    let (pt, nt) = fan(t, st, s);
    let (pu, nu) = fan(u, su, s);
    pt[..nt].iter().any(|k1| {
        pu[..nu].iter().any(|k2| {
            triangles_intersect(&k1.far(), &k2.set(s)) || triangles_intersect(&k2.far(), &k1.set(s))
        })
    })
}

/// Is the direction `m - o` (`o ≠ m`) in the tangent cone at `m` of `t` (shape `sh`,
/// containing `m`): do the points `m + ε (m - o)` lie in `t` for every small `ε > 0`?
fn leaves_along(t: &[P3; 3], sh: Shape, m: &P3, o: &P3) -> bool {
    let (pieces, n) = fan(t, sh, m);
    pieces[..n].iter().any(|piece| match *piece {
        Piece::Wedge(a, b) => {
            // In the wedge's plane, `d = m - o` is `λ (a - m) + μ (b - m)` with
            // `μ ~ cross(a - m, d)` and `λ ~ cross(d, b - m)` (scaled by the wedge's
            // orientation); `d` is in the wedge iff both are non-negative.
            if orient3d(m, &a, &b, o) != 0.0 {
                return false;
            }
            let ax = proper_axis(m, &a, &b);
            let q = |p: &P3| drop_axis(p, ax);
            let w = orient2d(q(m), q(&a), q(&b));
            // cross(a - m, m - o) = -orient2d(m, a, o); cross(m - o, b - m) = -orient2d(m, o, b).
            let mu = -orient2d(q(m), q(&a), q(o));
            let lambda = -orient2d(q(m), q(o), q(&b));
            mu * w >= 0.0 && lambda * w >= 0.0
        }
        Piece::Ray(a) => {
            // `a - m` and `m - o` point the same way along their common line.
            collinear(o, m, &a)
                && (0..3).any(|k| (o[k] < m[k] && m[k] < a[k]) || (o[k] > m[k] && m[k] > a[k]))
        }
    })
}

/// Rule 2 for the merged interval `[m0, m1]` (see the module documentation).
fn inside_interval(m0: &P3, m1: &P3, t: &[P3; 3], st: Shape, u: &[P3; 3], su: Shape) -> bool {
    if !(in_hull(t, st, m0) && in_hull(t, st, m1) && in_hull(u, su, m0) && in_hull(u, su, m1)) {
        return false;
    }
    let seg = [*m0, *m1, *m1];
    if !triangles_intersect(&seg, t) || !triangles_intersect(&seg, u) {
        return false;
    }
    let escapes = |m: &P3, o: &P3| {
        contains(t, st, m)
            && contains(u, su, m)
            && leaves_along(t, st, m, o)
            && leaves_along(u, su, m, o)
    };
    !escapes(m1, m0) && !escapes(m0, m1)
}

/// The general rule for a triangle pair: is `t ∩ u` not inside the joint?
fn general(t: &Tri, u: &Tri, joint: &Joint) -> bool {
    let (t, u) = (&t.p, &u.p);
    if !triangles_intersect(t, u) {
        return false;
    }
    let st = shape(t);
    let su = shape(u);
    if let (Shape::Proper, Shape::Proper) = (st, su) {
        if u.iter().all(|p| orient3d(&t[0], &t[1], &t[2], p) == 0.0) {
            return coplanar(t, u, joint);
        }
    }
    // `C` is a point or lies on a line.
    for s in &joint.pts[..joint.n_pts] {
        if contains(t, st, s) && contains(u, su, s) && !more_than_point(s, t, st, u, su) {
            return false;
        }
    }
    for [m0, m1] in &joint.segs[..joint.n_segs] {
        if inside_interval(m0, m1, t, st, u, su) {
            return false;
        }
    }
    true
}

/// Two proper triangles in one plane that meet: is `t ∩ u` not inside the joint?
fn coplanar(t: &[P3; 3], u: &[P3; 3], joint: &Joint) -> bool {
    let ax = proper_axis(&t[0], &t[1], &t[2]);
    let q = |p: &P3| drop_axis(p, ax);
    // Both counter-clockwise in the projection (which is one-to-one on the plane).
    let ccw = |x: &[P3; 3]| -> [P3; 3] {
        if orient2d(q(&x[0]), q(&x[1]), q(&x[2])) > 0.0 {
            *x
        } else {
            [x[0], x[2], x[1]]
        }
    };
    let (t, u) = (ccw(t), ccw(u));
    // Separating axis: an edge line of one with the other on its closed outer side. The
    // interiors are disjoint iff there is one (the Minkowski difference's edges are the
    // triangles' edges).
    let separating = |x: &[P3; 3], y: &[P3; 3]| {
        (0..3).find(|&k| {
            let (a, b) = (q(&x[k]), q(&x[(k + 1) % 3]));
            y.iter().all(|p| orient2d(a, b, q(p)) <= 0.0)
        })
    };
    let (x, y, k) = match (separating(&t, &u), separating(&u, &t)) {
        (Some(k), _) => (t, u, k),
        (None, Some(k)) => (u, t, k),
        (None, None) => return true,
    };
    // `C` lies on the line of `x`'s edge `[a, b]`: it is that edge's overlap with the face
    // of `y` on the line (its vertices on it).
    let (a, b) = (x[k], x[(k + 1) % 3]);
    let (qa, qb) = (q(&a), q(&b));
    let mut on = [[0.0; 3]; 3];
    let mut n = 0;
    for p in &y {
        if orient2d(qa, qb, q(p)) == 0.0 {
            on[n] = *p;
            n += 1;
        }
    }
    if n == 0 {
        return false;
    }
    // Order along the line by a coordinate on which `a` and `b` differ.
    let c = (0..3).find(|&c| a[c] != b[c]).unwrap_or(0);
    let [f0, f1] = if n == 1 {
        [on[0], on[0]]
    } else {
        hull_on_line(&on[..n])
    };
    let (e0, e1) = if a[c] <= b[c] { (a, b) } else { (b, a) };
    let lo = if f0[c] > e0[c] { f0 } else { e0 };
    let hi = if f1[c] < e1[c] { f1 } else { e1 };
    if lo[c] > hi[c] {
        return false;
    }
    // `C = [lo, hi]` between two input points.
    let point = lo == hi && joint.pts[..joint.n_pts].contains(&lo);
    let interval = joint.segs[..joint.n_segs]
        .iter()
        .any(|[m0, m1]| on_segment(&lo, m0, m1) && on_segment(&hi, m0, m1));
    !(point || interval)
}

#[cfg(test)]
mod tests {
    //! The predicate against an independent exact oracle, on adversarial cases.
    //!
    //! The oracle ([`oracle::meets`]) shares nothing with the predicate but the definitions:
    //! it *constructs* `t ∩ u` in exact rationals and measures it.

    use super::*;

    /// Integer arithmetic for the oracle: `BigInt`, or `i128` that flags an overflow.
    pub trait Int: Sized {
        fn one() -> Self;
        fn is_zero(&self) -> bool;
        fn is_neg(&self) -> bool;
        fn is_pos(&self) -> bool;
        /// `±m * 2^shift`.
        fn from_parts(m: u64, shift: u32, neg: bool) -> Self;
    }

    impl Int for num_bigint::BigInt {
        fn one() -> Self {
            num_traits::One::one()
        }
        fn is_zero(&self) -> bool {
            num_traits::Zero::is_zero(self)
        }
        fn is_neg(&self) -> bool {
            num_traits::Signed::is_negative(self)
        }
        fn is_pos(&self) -> bool {
            num_traits::Signed::is_positive(self)
        }
        fn from_parts(m: u64, shift: u32, neg: bool) -> Self {
            let z = num_bigint::BigInt::from(m) << shift as usize;
            if neg {
                -z
            } else {
                z
            }
        }
    }

    thread_local! {
        /// Set when a [`Small`] operation overflowed: its results are then meaningless.
        static OVERFLOW: std::cell::Cell<bool> = const { std::cell::Cell::new(false) };
    }

    /// An `i128` whose overflowing operations set [`OVERFLOW`] (and yield 0).
    #[derive(Clone, Debug, PartialEq, Eq, PartialOrd, Ord)]
    pub struct Small(i128);

    fn checked(r: Option<i128>) -> Small {
        Small(r.unwrap_or_else(|| {
            OVERFLOW.with(|o| o.set(true));
            0
        }))
    }

    macro_rules! small_op {
        ($tr:ident, $f:ident, $checked:ident) => {
            impl std::ops::$tr<&Small> for &Small {
                type Output = Small;
                fn $f(self, o: &Small) -> Small {
                    checked(self.0.$checked(o.0))
                }
            }
            impl std::ops::$tr<Small> for Small {
                type Output = Small;
                fn $f(self, o: Small) -> Small {
                    checked(self.0.$checked(o.0))
                }
            }
        };
    }
    small_op!(Add, add, checked_add);
    small_op!(Sub, sub, checked_sub);
    small_op!(Mul, mul, checked_mul);

    impl std::ops::Neg for Small {
        type Output = Small;
        fn neg(self) -> Small {
            checked(self.0.checked_neg())
        }
    }

    impl Int for Small {
        fn one() -> Self {
            Small(1)
        }
        fn is_zero(&self) -> bool {
            self.0 == 0
        }
        fn is_neg(&self) -> bool {
            self.0 < 0
        }
        fn is_pos(&self) -> bool {
            self.0 > 0
        }
        fn from_parts(m: u64, shift: u32, neg: bool) -> Self {
            let z = if shift < 64 {
                checked(i128::from(m).checked_mul(1i128 << shift))
            } else {
                checked(None)
            };
            if neg {
                -z
            } else {
                z
            }
        }
    }

    macro_rules! exact_oracle {
        ($m:ident, $Z:ty) => {
            mod $m {

                use crate::geom::adjacent::tests::Int;
                use crate::geom::P3;
                use std::cmp::Ordering;

                type Z = $Z;
                type V = [Z; 3];

                fn sub(a: &V, b: &V) -> V {
                    [&a[0] - &b[0], &a[1] - &b[1], &a[2] - &b[2]]
                }
                fn add(a: &V, b: &V) -> V {
                    [&a[0] + &b[0], &a[1] + &b[1], &a[2] + &b[2]]
                }
                fn scale(a: &V, s: &Z) -> V {
                    [&a[0] * s, &a[1] * s, &a[2] * s]
                }
                fn dot(a: &V, b: &V) -> Z {
                    &a[0] * &b[0] + &a[1] * &b[1] + &a[2] * &b[2]
                }
                fn cross(a: &V, b: &V) -> V {
                    [
                        &a[1] * &b[2] - &a[2] * &b[1],
                        &a[2] * &b[0] - &a[0] * &b[2],
                        &a[0] * &b[1] - &a[1] * &b[0],
                    ]
                }
                fn zero(a: &V) -> bool {
                    a.iter().all(Int::is_zero)
                }

                /// The rational point `p / w`, `w > 0`.
                #[derive(Clone, Debug)]
                struct Pt {
                    p: V,
                    w: Z,
                }

                impl Pt {
                    fn int(p: &V) -> Pt {
                        Pt {
                            p: p.clone(),
                            w: <Z as Int>::one(),
                        }
                    }
                    /// `p / w` with `w != 0`, made positive.
                    fn new(p: V, w: Z) -> Pt {
                        if w.is_neg() {
                            Pt {
                                p: p.map(|x| -x),
                                w: -w,
                            }
                        } else {
                            Pt { p, w }
                        }
                    }
                    fn same(&self, o: &Pt) -> bool {
                        (0..3).all(|k| &self.p[k] * &o.w == &o.p[k] * &self.w)
                    }
                    /// `w * (self - a)` for an integer point `a`.
                    fn from(&self, a: &V) -> V {
                        sub(&self.p, &scale(a, &self.w))
                    }
                }

                /// A fraction `n / d`, `d > 0`, ordered by value.
                #[derive(Clone, Debug)]
                struct Frac(Z, Z);

                impl Frac {
                    fn cmp(&self, o: &Frac) -> Ordering {
                        (&self.0 * &o.1).cmp(&(&o.0 * &self.1))
                    }
                }

                /// Closed segment `a`-`b` (maybe a point) contains `x`.
                fn on_segment(x: &Pt, a: &V, b: &V) -> bool {
                    let d = sub(b, a);
                    let w = x.from(a);
                    if zero(&d) {
                        return zero(&w);
                    }
                    let s = dot(&w, &d);
                    zero(&cross(&w, &d)) && !s.is_neg() && s <= &x.w * &dot(&d, &d)
                }

                /// A closed triangle with what its tests need.
                struct Tri {
                    v: [V; 3],
                    e1: V,
                    e2: V,
                    /// Normal `e1 x e2`; zero when degenerate.
                    n: V,
                    nn: Z,
                    /// The farthest two vertices (the segment, when degenerate).
                    far: (usize, usize),
                }

                impl Tri {
                    fn new(v: [V; 3]) -> Tri {
                        let e1 = sub(&v[1], &v[0]);
                        let e2 = sub(&v[2], &v[0]);
                        let n = cross(&e1, &e2);
                        let nn = dot(&n, &n);
                        let far = [(0, 1), (0, 2), (1, 2)]
                            .into_iter()
                            .max_by_key(|&(i, j)| {
                                let d = sub(&v[j], &v[i]);
                                dot(&d, &d)
                            })
                            .expect("three pairs");
                        Tri {
                            v,
                            e1,
                            e2,
                            n,
                            nn,
                            far,
                        }
                    }
                    fn proper(&self) -> bool {
                        !self.nn.is_zero()
                    }
                    fn contains(&self, x: &Pt) -> bool {
                        if !self.proper() {
                            return on_segment(x, &self.v[self.far.0], &self.v[self.far.1]);
                        }
                        // w (x - v0) = b e1 + g e2 with b n = (W x e2), g n = (e1 x W), scaled by w.
                        let w = x.from(&self.v[0]);
                        if !dot(&w, &self.n).is_zero() {
                            return false;
                        }
                        let b = dot(&cross(&w, &self.e2), &self.n);
                        let g = dot(&cross(&self.e1, &w), &self.n);
                        !b.is_neg() && !g.is_neg() && b + g <= &x.w * &self.nn
                    }
                    /// Signed distances (scaled) of points to the plane, when proper.
                    fn sides(&self, p: &[V; 3]) -> Option<[Z; 3]> {
                        self.proper()
                            .then(|| [0, 1, 2].map(|k| dot(&sub(&p[k], &self.v[0]), &self.n)))
                    }
                }

                /// The point where the lines `p`-`p2` and `r`-`r2` cross, if exactly one.
                fn line_line(p: &V, p2: &V, r: &V, r2: &V) -> Option<Pt> {
                    let d = sub(p2, p);
                    let e = sub(r2, r);
                    let n = cross(&d, &e);
                    if zero(&n) {
                        return None;
                    }
                    let w = sub(r, p);
                    if !dot(&w, &n).is_zero() {
                        return None;
                    }
                    // p + s d = r + s' e; (w x e) = s (d x e).
                    let den = dot(&n, &n);
                    let num = dot(&cross(&w, &e), &n);
                    Some(Pt::new(add(&scale(p, &den), &scale(&d, &num)), den))
                }

                fn strictly_one_side(d: &Option<[Z; 3]>) -> bool {
                    d.as_ref()
                        .is_some_and(|d| d.iter().all(Int::is_pos) || d.iter().all(Int::is_neg))
                }

                /// Candidate points of `t ∩ u` that lie in it (see the module doc).
                fn meeting_points(t: &Tri, u: &Tri) -> Vec<Pt> {
                    let du = t.sides(&u.v);
                    let dt = u.sides(&t.v);
                    if strictly_one_side(&du) || strictly_one_side(&dt) {
                        return Vec::new();
                    }
                    let mut out: Vec<Pt> = Vec::new();
                    let push = |x: Pt, out: &mut Vec<Pt>| {
                        if t.contains(&x) && u.contains(&x) && !out.iter().any(|y| y.same(&x)) {
                            out.push(x);
                        }
                    };
                    for x in t.v.iter().chain(&u.v) {
                        push(Pt::int(x), &mut out);
                    }
                    let pairs = [(0, 1), (0, 2), (1, 2)];
                    // An edge of `x` crossing the plane of `y` (`d`: sides of `x` against it).
                    let crossings = |x: &Tri, d: &Option<[Z; 3]>, out: &mut Vec<Pt>| {
                        if let Some(d) = d {
                            for &(i, j) in &pairs {
                                let (a, b) = (&d[i], &d[j]);
                                if (a.is_pos() && b.is_neg()) || (a.is_neg() && b.is_pos()) {
                                    // v_i + a / (a - b) (v_j - v_i) = (a v_j - b v_i) / (a - b).
                                    let p = sub(&scale(&x.v[j], a), &scale(&x.v[i], b));
                                    push(Pt::new(p, a - b), out);
                                }
                            }
                        }
                    };
                    crossings(t, &dt, &mut out);
                    crossings(u, &du, &mut out);
                    let coplanar = du.as_ref().is_some_and(|d| d.iter().all(Int::is_zero));
                    if !t.proper() || !u.proper() || coplanar {
                        for &(i, j) in &pairs {
                            for &(k, l) in &pairs {
                                if t.v[i] != t.v[j] && u.v[k] != u.v[l] {
                                    if let Some(x) = line_line(&t.v[i], &t.v[j], &u.v[k], &u.v[l]) {
                                        push(x, &mut out);
                                    }
                                }
                            }
                        }
                    }
                    out
                }

                /// Is the convex hull of the points `c` (not empty) inside the joint?
                fn covered(c: &[Pt], pts: &[V], segs: &[[V; 2]]) -> bool {
                    let p0 = &c[0];
                    let Some(p1) = c.iter().find(|x| !x.same(p0)) else {
                        return pts.iter().any(|s| p0.same(&Pt::int(s)))
                            || segs.iter().any(|[a, b]| on_segment(p0, a, b));
                    };
                    // rel(x) = w0 wx (x - p0); d ~ p1 - p0.
                    let rel = |x: &Pt| sub(&scale(&x.p, &p0.w), &scale(&p0.p, &x.w));
                    let d = rel(p1);
                    if c.iter().any(|x| !zero(&cross(&rel(x), &d))) {
                        return false; // area
                    }
                    // (x - p0) . d up to the common factor w0 > 0.
                    let param = |x: &Pt| Frac(dot(&rel(x), &d), x.w.clone());
                    let mut ps: Vec<Frac> = c.iter().map(param).collect();
                    ps.sort_by(Frac::cmp);
                    let (lo, hi) = (ps[0].clone(), ps[ps.len() - 1].clone());
                    let mut iv: Vec<(Frac, Frac)> = segs
                        .iter()
                        .filter(|[a, b]| {
                            zero(&cross(&rel(&Pt::int(a)), &d))
                                && zero(&cross(&rel(&Pt::int(b)), &d))
                        })
                        .map(|[a, b]| {
                            let (x, y) = (param(&Pt::int(a)), param(&Pt::int(b)));
                            if x.cmp(&y).is_le() {
                                (x, y)
                            } else {
                                (y, x)
                            }
                        })
                        .collect();
                    iv.sort_by(|x, y| x.0.cmp(&y.0));
                    let mut reach = lo;
                    for (s, e) in iv {
                        if reach.cmp(&hi).is_ge() {
                            break;
                        }
                        if s.cmp(&reach).is_gt() {
                            return false;
                        }
                        if e.cmp(&reach).is_gt() {
                            reach = e;
                        }
                    }
                    reach.cmp(&hi).is_ge()
                }

                /// All coordinates as integers, scaled by one power of two.
                fn integers(coords: &[f64]) -> Vec<Z> {
                    let parts: Vec<(u64, i16, i8)> = coords
                        .iter()
                        .map(|&x| {
                            // Odd mantissas: the smallest integers.
                            let (m, e, s) = num_traits::Float::integer_decode(x);
                            let z = if m == 0 { 0 } else { m.trailing_zeros() };
                            (m >> z, e + z as i16, s)
                        })
                        .collect();
                    let e0 = parts
                        .iter()
                        .filter(|p| p.0 != 0)
                        .map(|p| p.1)
                        .min()
                        .unwrap_or(0);
                    parts
                        .iter()
                        .map(|&(m, e, s)| {
                            if m == 0 {
                                Z::from_parts(0, 0, false)
                            } else {
                                Z::from_parts(m, (e - e0) as u32, s < 0)
                            }
                        })
                        .collect()
                }

                /// The definition, decided by construction: do the closed polygons meet outside
                /// their shared vertices and shared edges? `a_pos[k]` is the position of vertex
                /// `a_idx[k]`; quads split as `(v0, v1, v2)`, `(v0, v2, v3)`.
                pub fn meets(a_idx: &[u32], a_pos: &[P3], b_idx: &[u32], b_pos: &[P3]) -> bool {
                    let flat: Vec<f64> = a_pos.iter().chain(b_pos).flatten().copied().collect();
                    let z = integers(&flat);
                    let pt =
                        |k: usize| [z[3 * k].clone(), z[3 * k + 1].clone(), z[3 * k + 2].clone()];
                    let av: Vec<V> = (0..a_pos.len()).map(pt).collect();
                    let bv: Vec<V> = (a_pos.len()..a_pos.len() + b_pos.len()).map(pt).collect();
                    let edges = |idx: &[u32]| -> Vec<(u32, u32)> {
                        (0..idx.len())
                            .map(|k| (idx[k], idx[(k + 1) % idx.len()]))
                            .filter(|(i, j)| i != j)
                            .collect()
                    };
                    let (ea, eb) = (edges(a_idx), edges(b_idx));
                    let at =
                        |i: u32| av[a_idx.iter().position(|&x| x == i).expect("a's index")].clone();
                    let pts: Vec<V> = a_idx
                        .iter()
                        .filter(|i| b_idx.contains(i))
                        .map(|&i| at(i))
                        .collect();
                    let segs: Vec<[V; 2]> = ea
                        .iter()
                        .filter(|&&(i, j)| eb.contains(&(i, j)) || eb.contains(&(j, i)))
                        .map(|&(i, j)| [at(i), at(j)])
                        .collect();
                    let tris = |p: &[V]| -> Vec<Tri> {
                        let mut t = vec![Tri::new([p[0].clone(), p[1].clone(), p[2].clone()])];
                        if p.len() == 4 {
                            t.push(Tri::new([p[0].clone(), p[2].clone(), p[3].clone()]));
                        }
                        t
                    };
                    let (ta, tb) = (tris(&av), tris(&bv));
                    for t in &ta {
                        for u in &tb {
                            let c = meeting_points(t, u);
                            if !c.is_empty() && !covered(&c, &pts, &segs) {
                                return true;
                            }
                        }
                    }
                    false
                }
            }
        };
    }

    /// Exact construction of the meeting set, in integers.
    ///
    /// All coordinates of a case are scaled by one power of two into integers (exact:
    /// every `f64` is an integer times a power of two, and a common scale changes nothing
    /// about incidence or order). Constructed points are rational, kept as `P / w` with an
    /// integer vector `P` and an integer `w > 0`, so every test is an exact integer sign.
    ///
    /// For closed convex polytopes `t` and `u`, every vertex `v` of `C = t ∩ u` lies in the
    /// relative interiors of one face `F` of `t` and one `G` of `u`, and near `v` the set
    /// `C` is `aff F ∩ aff G`; `v` being extreme, `aff F ∩ aff G = {v}`. The faces of a
    /// triangle given by three points are among: the points, the segments between two of
    /// them, the triangle itself (when proper). Pairs whose hulls meet in exactly one point
    /// are a point and anything, two coplanar non-parallel lines, or a line and a plane it
    /// crosses. So `C` is the convex hull of those candidate points that lie in both closed
    /// triangles (all of them are in `C`, and every vertex of `C` is one). Two shortcuts,
    /// both exact: a line/plane candidate is needed only when the edge's ends are strictly
    /// on either side of the plane (`v` is inside `F`; an end on the plane is a point
    /// candidate), and line/line candidates only when a triangle is degenerate or both are
    /// in one plane (for proper triangles in different planes, `F` or `G` is not in the
    /// other's plane, else both lie on the planes' common line and are parallel, and then
    /// `v` is also that edge's line/plane candidate).
    ///
    /// `C` is then a point, a segment (the extreme candidates along its direction) or has
    /// area. It is inside the joint `S` iff: a point lying in `S`; a segment covered by the
    /// shared edges collinear with it (an interval sweep of their parameters; the other
    /// pieces of `S` meet its line in finitely many points, which cannot fill a gap); never
    /// when it has area.
    ///
    /// Computed in `i128` when no operation overflows there (every one is checked), else
    /// in `BigInt`.
    pub mod oracle {
        use super::OVERFLOW;
        use crate::geom::P3;

        exact_oracle!(big, num_bigint::BigInt);
        exact_oracle!(small, crate::geom::adjacent::tests::Small);

        pub fn meets(a_idx: &[u32], a_pos: &[P3], b_idx: &[u32], b_pos: &[P3]) -> bool {
            OVERFLOW.with(|o| o.set(false));
            let r = small::meets(a_idx, a_pos, b_idx, b_pos);
            if !OVERFLOW.with(|o| o.get()) {
                return r;
            }
            big::meets(a_idx, a_pos, b_idx, b_pos)
        }
    }

    /// xorshift64: deterministic cases.
    use crate::geom::test_rng::Rng;

    /// Two polygons: indices and one position per vertex.
    #[derive(Clone, Debug)]
    struct Case {
        a_idx: Vec<u32>,
        a_pos: Vec<P3>,
        b_idx: Vec<u32>,
        b_pos: Vec<P3>,
    }

    impl Case {
        /// Polygons `a` and `b` over the vertex positions `pos`.
        fn new(a: &[u32], b: &[u32], pos: &[P3]) -> Case {
            Case {
                a_idx: a.to_vec(),
                a_pos: a.iter().map(|&i| pos[i as usize]).collect(),
                b_idx: b.to_vec(),
                b_pos: b.iter().map(|&i| pos[i as usize]).collect(),
            }
        }

        fn tris(pos: &[P3]) -> ([[P3; 3]; 2], usize) {
            let mut t = [[pos[0], pos[1], pos[2]]; 2];
            if pos.len() == 4 {
                t[1] = [pos[0], pos[2], pos[3]];
            }
            (t, pos.len() - 2)
        }

        /// The predicate, in both orders (which must agree), and through the other entry point
        /// too when asked.
        fn predicate(&self, both_entries: bool) -> bool {
            let r = adjacent_polygons_meet_at(&self.a_idx, &self.a_pos, &self.b_idx, &self.b_pos);
            if both_entries {
                let (ta, na) = Case::tris(&self.a_pos);
                let (tb, nb) = Case::tris(&self.b_pos);
                assert_eq!(
                    r,
                    adjacent_polygons_meet(&self.a_idx, &ta, na, &self.b_idx, &tb, nb),
                    "entry points disagree on {self:?}"
                );
            }
            assert_eq!(
                r,
                adjacent_polygons_meet_at(&self.b_idx, &self.b_pos, &self.a_idx, &self.a_pos),
                "asymmetric answer on {self:?}"
            );
            r
        }

        fn oracle(&self) -> bool {
            oracle::meets(&self.a_idx, &self.a_pos, &self.b_idx, &self.b_pos)
        }
    }

    /// Counts of a family of cases.
    #[derive(Default)]
    struct Tally {
        cases: usize,
        meets: usize,
        /// Triangle pairs [`triangles_touch_only_at_joint`] decided (either order).
        quick: usize,
        bad: Vec<String>,
    }

    impl Tally {
        fn check(&mut self, c: &Case) {
            let want = c.oracle();
            let got = c.predicate(self.cases.is_multiple_of(8));
            self.cases += 1;
            self.meets += usize::from(want);
            if got != want && self.bad.len() < 5 {
                self.bad
                    .push(format!("predicate {got}, oracle {want}: {c:?}"));
            }
            // The quick test: "no meeting" only where the oracle says so.
            if c.a_idx.len() == 3 && c.b_idx.len() == 3 {
                let tri = |i: &[u32], p: &[P3]| ([i[0], i[1], i[2]], [p[0], p[1], p[2]]);
                let (ai, ap) = tri(&c.a_idx, &c.a_pos);
                let (bi, bp) = tri(&c.b_idx, &c.b_pos);
                let (pa, pb) = (Plane::of(&ap), Plane::of(&bp));
                let planes = triangles_touch_only_at_joint_planes(&ai, &ap, &pa, &bi, &bp, &pb);
                let exact = triangles_touch_only_at_joint(&ai, &ap, &bi, &bp);
                if planes && !exact && self.bad.len() < 5 {
                    self.bad
                        .push(format!("quick test: planes {planes}, exact {exact}: {c:?}"));
                }
                for quick in [exact, triangles_touch_only_at_joint(&bi, &bp, &ai, &ap)] {
                    self.quick += usize::from(quick);
                    if quick && want && self.bad.len() < 5 {
                        self.bad
                            .push(format!("quick test: no meeting, oracle: meets: {c:?}"));
                    }
                }
            }
        }

        fn finish(self, name: &str, min_cases: usize) {
            println!(
                "{name}: {} cases, {} meeting, {} quick decisions, {} disagreements",
                self.cases,
                self.meets,
                self.quick,
                self.bad.len()
            );
            assert!(
                self.bad.is_empty(),
                "{name}: disagreements:\n{}",
                self.bad.join("\n")
            );
            assert!(self.cases >= min_cases, "{name}: only {} cases", self.cases);
            assert!(
                self.meets > self.cases / 50 && self.meets < self.cases - self.cases / 50,
                "{name}: {} of {} meet: the cases are not adversarial",
                self.meets,
                self.cases
            );
        }
    }

    /// A polygon pair on a small integer grid: shapes `k` in {3, 4}, `shared` common
    /// indices, random repeats and coincident positions.
    fn grid_case(r: &mut Rng, half: i32) -> Case {
        let na = r.pick(&[3usize, 4]);
        let nb = r.pick(&[3usize, 4]);
        let mut a: Vec<u32> = (0..na as u32).collect();
        if r.below(12) == 0 {
            let (x, y) = (r.below(na), r.below(na));
            a[x] = a[y];
        }
        let mut distinct = a.clone();
        distinct.sort_unstable();
        distinct.dedup();
        r.shuffle(&mut distinct);
        let shared = 1 + r.below(distinct.len().min(nb));
        let mut b: Vec<u32> = distinct[..shared].to_vec();
        b.extend((0..(nb - shared) as u32).map(|k| 4 + k));
        match r.below(3) {
            // Consecutive shared indices in reversed order, as a consistent mesh has them.
            0 => {
                b.reverse();
                let rot = r.below(nb);
                b.rotate_left(rot);
            }
            _ => r.shuffle(&mut b),
        }
        if r.below(12) == 0 {
            let (x, y) = (r.below(nb), r.below(nb));
            b[x] = b[y];
        }
        let mut pos = [[0.0; 3]; 8];
        for i in 0..8 {
            pos[i] = if i > 0 && r.below(8) == 0 {
                pos[r.below(i)]
            } else {
                [0; 3].map(|_| f64::from(r.below(2 * half as usize + 1) as i32 - half))
            };
        }
        Case::new(&a, &b, &pos)
    }

    #[test]
    fn grid_cases_match_the_oracle() {
        let mut r = Rng(0x9E37_79B9_7F4A_7C15);
        let mut tally = Tally::default();
        for n in 0..120_000 {
            tally.check(&grid_case(&mut r, if n % 3 == 0 { 1 } else { 2 }));
        }
        tally.finish("grid", 120_000);
    }

    /// Where a family puts its local configuration: a rotation (none, to keep exact
    /// coplanarity, or random), a scale (1, 1e-4, 1e4) and an offset (none or 1e5), then
    /// each coordinate rounded to `f32` as the library stores it.
    struct Place {
        rot: Option<[[f64; 3]; 3]>,
        scale: f64,
        offset: P3,
    }

    impl Place {
        fn random(r: &mut Rng) -> Place {
            let rot = (r.below(3) != 0).then(|| {
                // A random unit quaternion.
                let q = loop {
                    let q = [0; 4].map(|_| r.range(-1.0, 1.0));
                    let n = q.iter().map(|x| x * x).sum::<f64>();
                    if n > 0.01 && n < 1.0 {
                        break q.map(|x| x / n.sqrt());
                    }
                };
                crate::geom::test_rng::rotation_of(q)
            });
            let scale = r.pick(&[1.0, 1e-4, 1e4]);
            let offset = match r.below(3) {
                0 => [1e5; 3],
                1 => [1e5, -1e5 * r.range(0.0, 1.0), 0.5e5],
                _ => [0.0; 3],
            };
            Place { rot, scale, offset }
        }

        fn at(&self, p: [f64; 3]) -> P3 {
            let q = match &self.rot {
                Some(m) => [0, 1, 2].map(|i| m[i][0] * p[0] + m[i][1] * p[1] + m[i][2] * p[2]),
                None => p,
            };
            [0, 1, 2].map(|k| (q[k] * self.scale + self.offset[k]) as f32 as f64)
        }
    }

    /// A tiny signed offset: 0 or ±1e-3 .. ±1e-7.
    fn tiny(r: &mut Rng) -> f64 {
        let m = r.pick(&[0.0, 1e-3, 1e-4, 1e-5, 1e-6, 1e-7]);
        if r.below(2) == 0 {
            m
        } else {
            -m
        }
    }

    fn lerp(a: [f64; 3], b: [f64; 3], s: f64) -> [f64; 3] {
        [0, 1, 2].map(|k| a[k] + s * (b[k] - a[k]))
    }

    /// Two polygons hinged on the edge `{0, 1}`: folded onto each other by a tiny angle,
    /// lying flat (angle π, the ordinary cloth), or at a random angle; triangles or quads.
    fn fold_case(r: &mut Rng) -> Case {
        let at_angle = |x: f64, h: f64, th: f64| [x, h * th.cos(), h * th.sin()];
        let th = match r.below(4) {
            0 | 1 => tiny(r),
            2 => std::f64::consts::PI + tiny(r),
            _ => r.range(0.0, 6.3),
        };
        let mut v = [[0.0; 3]; 6];
        v[1] = [1.0, 0.0, 0.0];
        v[2] = [r.range(-0.5, 1.5), r.range(0.05, 1.0), 0.0];
        v[3] = [r.range(-0.5, 1.5), r.range(0.05, 1.0), 0.0];
        let (x4, h4) = (r.range(-0.5, 1.5), r.range(0.05, 1.0));
        let th4 = th + 0.3 * tiny(r);
        v[4] = at_angle(x4, h4, th4);
        let (x5, h5) = (r.range(-0.5, 1.5), r.range(0.05, 1.0));
        v[5] = at_angle(x5, h5, th);
        if r.below(4) == 0 {
            // One apex of the fold exactly onto the other polygon's plane, inside or out.
            v[4] = [r.range(-0.5, 1.5), r.range(-0.2, 1.0), 0.0];
        }
        let place = Place::random(r);
        let pos = v.map(|p| place.at(p));
        // Quads (0, 1, 2, 3) / (1, 0, 4, 5) go around their corners in order: the far
        // corners are sorted so that 2 is nearer to 1, 5 nearer to 0 (mostly convex).
        let a: &[u32] = if r.below(2) == 0 {
            &[0, 1, 2]
        } else {
            &[0, 1, 2, 3]
        };
        let b: &[u32] = if r.below(2) == 0 {
            &[1, 0, 4]
        } else {
            &[1, 0, 4, 5]
        };
        Case::new(a, b, &pos)
    }

    /// A vertex pushed through its neighbour: `u` shares the edge `{0, 2}` or the vertex
    /// `0` of `t = (0, 1, 2)`, with its other vertices at a tiny height over points of
    /// `t`'s plane inside or near `t`.
    fn push_case(r: &mut Rng) -> Case {
        let mut v = [[0.0; 3]; 6];
        v[1] = [1.0, 0.0, 0.0];
        v[2] = [r.range(-0.5, 1.0), r.range(0.1, 1.0), 0.0];
        let near = |r: &mut Rng, v: &[[f64; 3]; 6]| {
            let (al, be) = (r.range(-0.3, 1.1), r.range(-0.3, 1.1));
            let h = tiny(r);
            [al * v[1][0] + be * v[2][0], al * v[1][1] + be * v[2][1], h]
        };
        v[3] = near(r, &v);
        v[4] = if r.below(2) == 0 {
            near(r, &v)
        } else {
            [r.range(-1.0, 1.0), r.range(-1.0, 1.0), r.range(-1.0, 1.0)]
        };
        v[5] = near(r, &v);
        let place = Place::random(r);
        let pos = v.map(|p| place.at(p));
        let a: &[u32] = if r.below(3) == 0 {
            &[0, 1, 2, 5]
        } else {
            &[0, 1, 2]
        };
        let b: &[u32] = match r.below(4) {
            0 => &[2, 0, 3],
            1 => &[0, 3, 4],
            2 => &[0, 2, 3, 4],
            _ => &[3, 0, 4],
        };
        Case::new(a, b, &pos)
    }

    /// Two fans pinched at one vertex: `u`'s other vertices are combinations of `t`'s
    /// edges at the common vertex (inside its wedge, across it, opposite), a tiny height
    /// off its plane.
    fn pinch_case(r: &mut Rng) -> Case {
        let mut v = [[0.0; 3]; 6];
        v[1] = [r.range(0.2, 1.0), r.range(-0.2, 0.2), 0.0];
        v[2] = [r.range(-0.5, 0.5), r.range(0.2, 1.0), 0.0];
        v[3] = [r.range(-0.8, 0.8), r.range(-0.8, 0.8), r.range(-0.5, 0.5)];
        for k in [4, 5] {
            let (l, m) = (r.range(-1.0, 1.2), r.range(-1.0, 1.2));
            let h = tiny(r);
            v[k] = [l * v[1][0] + m * v[2][0], l * v[1][1] + m * v[2][1], h];
            if r.below(4) == 0 {
                // Exactly along an edge of `t` (inside it, past it, or opposite).
                v[k] = lerp([0.0; 3], v[1 + r.below(2)], r.range(-1.0, 1.5));
            }
        }
        let place = Place::random(r);
        let pos = v.map(|p| place.at(p));
        let a: &[u32] = if r.below(3) == 0 {
            &[0, 1, 3, 2]
        } else {
            &[0, 1, 2]
        };
        let b: &[u32] = if r.below(3) == 0 {
            &[0, 4, 3, 5]
        } else {
            &[0, 4, 5]
        };
        Case::new(a, b, &pos)
    }

    /// Sliver fans: needle triangles around vertex 0 whose far ends are 1e-3 .. 1e-7 apart
    /// (and off the common plane by as little), sharing an edge or the vertex.
    fn sliver_case(r: &mut Rng) -> Case {
        let d = [1.0, r.range(-0.3, 0.3), r.range(-0.3, 0.3)];
        let e = [r.range(-1.0, 1.0), 1.0, r.range(-1.0, 1.0)];
        let f = [r.range(-1.0, 1.0), r.range(-1.0, 1.0), 1.0];
        let w = |r: &mut Rng| {
            let (a, b) = (tiny(r), 0.3 * tiny(r));
            let s = r.range(0.5, 1.5);
            [0, 1, 2].map(|k| s * d[k] + a * e[k] + b * f[k])
        };
        let mut v = [[0.0; 3]; 6];
        for p in &mut v[1..] {
            *p = w(r);
        }
        if r.below(3) == 0 {
            v[3] = lerp(v[0], v[1], r.range(0.2, 1.5)); // exactly on a needle's line
        }
        let place = Place::random(r);
        let pos = v.map(|p| place.at(p));
        let a: &[u32] = if r.below(3) == 0 {
            &[0, 1, 2, 5]
        } else {
            &[0, 1, 2]
        };
        let b: &[u32] = match r.below(3) {
            0 => &[0, 2, 3],
            1 => &[2, 0, 3, 4],
            _ => &[0, 3, 4],
        };
        Case::new(a, b, &pos)
    }

    fn family(name: &str, seed: u64, n: usize, gen: fn(&mut Rng) -> Case) {
        let mut r = Rng(seed);
        let mut tally = Tally::default();
        for _ in 0..n {
            tally.check(&gen(&mut r));
        }
        tally.finish(name, n);
    }

    #[test]
    fn folds_match_the_oracle() {
        family("folds", 0x1234_5678_9ABC_DEF1, 60_000, fold_case);
    }

    #[test]
    fn pushed_vertices_match_the_oracle() {
        family("pushed", 0x0F1E_2D3C_4B5A_6978, 60_000, push_case);
    }

    #[test]
    fn pinched_vertices_match_the_oracle() {
        family("pinched", 0x5555_AAAA_3333_CCCC, 60_000, pinch_case);
    }

    #[test]
    fn sliver_fans_match_the_oracle() {
        family("slivers", 0x7777_1111_9999_4444, 60_000, sliver_case);
    }

    /// The predicate on polygons `a`, `b` over `pos`, checked against the oracle.
    fn meets(a: &[u32], b: &[u32], pos: &[P3]) -> bool {
        let c = Case::new(a, b, pos);
        let r = c.predicate(true);
        assert_eq!(r, c.oracle(), "oracle disagrees on {c:?}");
        r
    }

    #[test]
    fn named_cases() {
        let f = |x: f64| x as f32 as f64;
        // Cloth: flat neighbours, and folded by a tiny angle (they meet along the edge only:
        // a fold meets the neighbour's face only when exactly flat onto it).
        let mut pos = vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.3, 1.0, 0.0],
            [0.6, -1.0, 0.0],
        ];
        assert!(!meets(&[0, 1, 2], &[1, 0, 3], &pos));
        pos[3] = [0.6, 1.0, f(1e-7)];
        assert!(!meets(&[0, 1, 2], &[1, 0, 3], &pos));
        pos[3] = [0.6, 1.0, 0.0];
        assert!(
            meets(&[0, 1, 2], &[1, 0, 3], &pos),
            "folded flat onto the neighbour"
        );
        // Sharing a vertex: apart, the next triangle's edge pushed through, pinched flat.
        let mut pos = vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [-1.0, 0.0, 0.5],
            [0.0, -1.0, 0.5],
        ];
        assert!(!meets(&[0, 1, 2], &[0, 3, 4], &pos));
        pos[3] = [0.3, 0.3, -0.5];
        pos[4] = [0.3, 0.3, 0.5];
        assert!(
            meets(&[0, 1, 2], &[0, 3, 4], &pos),
            "edge through the neighbour"
        );
        pos[3] = [-1.0, 0.0, 0.0];
        pos[4] = [0.0, -1.0, 0.0];
        assert!(
            !meets(&[0, 1, 2], &[0, 3, 4], &pos),
            "opposite sectors touch at the vertex"
        );
        pos[4] = [1.0, 1.0, 0.0];
        assert!(meets(&[0, 1, 2], &[0, 3, 4], &pos), "overlapping sectors");
        // A quad's diagonal is not an edge: a triangle on it meets the quad along it.
        let pos = vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, 1.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.5, 0.5, 1.0],
            [0.5, -1.0, 0.0],
        ];
        assert!(meets(&[0, 1, 2, 3], &[2, 0, 4], &pos), "on the diagonal");
        assert!(!meets(&[0, 1, 2, 3], &[1, 0, 5], &pos), "on an edge");
        assert!(
            !meets(&[0, 1, 2, 3], &[0, 4, 1], &pos),
            "on an edge, folded up"
        );
        assert!(
            !meets(&[0, 1, 2, 3], &[1, 0, 5, 4], &pos),
            "two quads on an edge"
        );
        // Duplicates meet unless degenerate; a degenerate polygon on a shared edge does not.
        let pos = vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [2.0, 0.0, 0.0],
        ];
        assert!(meets(&[0, 1, 2], &[2, 1, 0], &pos));
        assert!(!meets(&[0, 1, 3], &[3, 1, 0], &pos), "collinear duplicates");
        assert!(
            !meets(&[0, 1, 1], &[1, 0, 2], &pos),
            "a segment on the shared edge"
        );
        // The same position under another index is not shared: meeting there counts.
        let pos = vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, -1.0, 1.0],
        ];
        assert!(meets(&[0, 1, 2], &[0, 3, 4], &pos));
        // Collinear shared edges: quads (0, 1, 2, 3) and (2, 1, 0, 4) with 1 on 0-2 share
        // the edges {0, 1} and {1, 2}; their union covers the segment 0-2 where they meet.
        let pos = vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [2.0, 0.0, 0.0],
            [1.0, 1.0, 0.0],
            [1.0, -1.0, 0.0],
        ];
        assert!(!meets(&[0, 1, 2, 3], &[2, 1, 0, 4], &pos));
        assert!(meets(&[0, 1, 2, 3], &[2, 1, 0, 3], &pos), "same side");
    }

    /// Wavy cloth, `n` x `n` cells: vertex positions and polygons (two triangles or one
    /// quad per cell).
    fn cloth(n: usize, quads: bool) -> (Vec<P3>, Vec<Vec<u32>>) {
        let id = |i: usize, j: usize| (j * (n + 1) + i) as u32;
        let mut pos = Vec::new();
        for j in 0..=n {
            for i in 0..=n {
                let (x, y) = (i as f64 * 0.01, j as f64 * 0.01);
                let z = 0.02 * (x * 9.0).sin() * (y * 7.0).cos();
                pos.push([x, y, z].map(|c| c as f32 as f64));
            }
        }
        let mut polys = Vec::new();
        for j in 0..n {
            for i in 0..n {
                let (a, b, c, d) = (id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
                if quads {
                    polys.push(vec![a, b, c, d]);
                } else {
                    polys.push(vec![a, b, c]);
                    polys.push(vec![a, c, d]);
                }
            }
        }
        (pos, polys)
    }

    /// ns per call on the adjacent pairs of a wavy cloth (none meets). Not a test of
    /// speed: run with `--ignored --nocapture` and read.
    #[test]
    #[ignore]
    fn cloth_pair_timing() {
        for quads in [false, true] {
            let (pos, polys) = cloth(60, quads);
            let prepared: Vec<(Vec<u32>, [[P3; 3]; 2], usize)> = polys
                .iter()
                .map(|p| {
                    let v: Vec<P3> = p.iter().map(|&i| pos[i as usize]).collect();
                    let (t, n) = Case::tris(&v);
                    (p.clone(), t, n)
                })
                .collect();
            let mut by_edge = Vec::new();
            let mut by_vertex = Vec::new();
            for x in 0..polys.len() {
                // Neighbours are at most two rows of cells apart in this order.
                for y in x + 1..polys.len().min(x + 2 * 60 + 4) {
                    let shared = polys[x].iter().filter(|i| polys[y].contains(i)).count();
                    match shared {
                        0 => {}
                        1 => by_vertex.push((x, y)),
                        _ => by_edge.push((x, y)),
                    }
                }
            }
            for (name, pairs) in [("an edge", &by_edge), ("a vertex only", &by_vertex)] {
                let run = || {
                    pairs
                        .iter()
                        .filter(|&&(x, y)| {
                            let (a, b) = (&prepared[x], &prepared[y]);
                            adjacent_polygons_meet(&a.0, &a.1, a.2, &b.0, &b.1, b.2)
                        })
                        .count()
                };
                assert_eq!(run(), 0, "a wavy cloth does not fold onto itself");
                // The fastest of many passes: the machine may be shared, and a pass that
                // was not interrupted is the measure of the code.
                let t0 = std::time::Instant::now();
                let mut best = f64::INFINITY;
                while t0.elapsed().as_secs_f64() < 1.0 {
                    let t = std::time::Instant::now();
                    std::hint::black_box(run());
                    best = best.min(t.elapsed().as_secs_f64());
                }
                let ns = best * 1e9 / pairs.len() as f64;
                let kind = if quads { "quads" } else { "triangles" };
                println!(
                    "{kind} sharing {name}: {} pairs, {ns:.1} ns per call",
                    pairs.len()
                );
            }
        }
    }

    #[test]
    fn sharing_is_by_index() {
        assert!(shares_vertex(&[0, 1, 2], &[2, 3, 4]));
        assert!(!shares_vertex(&[0, 1, 2], &[3, 4, 5, 6]));
    }

    /// Through a real mesh: its polygons index per-leaf slots, so adjacency must go by the
    /// caller's vertex indices (`slot_vertices`). A flat sheet has no meeting neighbours;
    /// folding one corner onto the next triangle makes that pair meet.
    #[test]
    fn through_a_mesh() {
        use crate::mesh::{Mesh, Positions};
        let n = 6usize;
        let mut pos: Vec<[f32; 3]> = Vec::new();
        for j in 0..=n {
            for i in 0..=n {
                pos.push([i as f32, j as f32, 0.0]);
            }
        }
        let id = |i: usize, j: usize| (j * (n + 1) + i) as u32;
        let mut idx = Vec::new();
        for j in 0..n {
            for i in 0..n {
                idx.extend([id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
                idx.extend([id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
            }
        }
        let reported = |pos: &[[f32; 3]]| {
            let mesh = Mesh::new(Positions::from_points(pos), &idx, 3, 4).expect("valid mesh");
            assert!(
                mesh.leaf_count() > 1,
                "vertices are split over several leaves"
            );
            let verts = |p: usize| -> Vec<u32> {
                mesh.poly(p)
                    .iter()
                    .map(|&s| mesh.slot_vertices()[s as usize])
                    .collect()
            };
            let mut out = Vec::new();
            let mut tris = [[[0.0; 3]; 3]; 2];
            let mut uris = [[[0.0; 3]; 3]; 2];
            for x in 0..mesh.polygon_count() {
                for y in x + 1..mesh.polygon_count() {
                    let (vx, vy) = (verts(x), verts(y));
                    if !shares_vertex(&vx, &vy) {
                        continue;
                    }
                    let nx = mesh.triangles(x, &mut tris);
                    let ny = mesh.triangles(y, &mut uris);
                    if adjacent_polygons_meet(&vx, &tris, nx, &vy, &uris, ny) {
                        let (a, b) = (mesh.polygon_ids()[x], mesh.polygon_ids()[y]);
                        out.push((a.min(b), a.max(b)));
                    }
                }
            }
            out.sort_unstable();
            out
        };
        assert_eq!(reported(&pos), vec![]);
        // Fold the far corner of the last cell's first triangle flat onto its second.
        let last = id(n, n - 1) as usize;
        pos[last] = [n as f32 - 0.8, n as f32 - 0.1, 0.0];
        let r = reported(&pos);
        let (t0, t1) = ((2 * n * n - 2) as u32, (2 * n * n - 1) as u32);
        assert!(r.contains(&(t0, t1)), "{r:?}");
    }
}
