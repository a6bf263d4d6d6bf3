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
//! * `C` empty ([`triangles_intersect`](super::tritri::triangles_intersect)): not a
//!   meeting.
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

//!
//! # The files
//!
//! * `mod.rs`: the entry points ([`shares_vertex`], [`adjacent_polygons_meet`],
//!   [`adjacent_polygons_meet_at`]) and the decision for each triangle pair (the fast
//!   paths, then the general rule).
//! * `certificate.rs`: [`triangles_touch_only_at_joint`] (and its variant on planes made
//!   beforehand): a cheap sufficient condition for two neighbour triangles not to meet
//!   beyond their joint, with no setup.
//! * `joint.rs`: a pair's polygons and triangles, their shared edges and their joint.
//! * `fast.rs`: the fast paths.
//! * `general.rs`: the general rule, and the exact tests it is built on (a triangle's
//!   shape, containment, the coordinate plane to project on).
//! * `tests/`: the predicate against an independent exact oracle in integers
//!   (`tests/oracle.rs`), on adversarial families and named cases.

use super::predicates::P3;

mod certificate;
mod fast;
mod general;
mod joint;
#[cfg(test)]
mod tests;

#[cfg(any(test, feature = "internals"))]
pub use certificate::triangles_touch_only_at_joint;
pub use certificate::triangles_touch_only_at_joint_planes;
use fast::fast;
use general::general;
use joint::{Joint, Polygon, SharedEdges};

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

#[cfg(any(test, feature = "internals"))]
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
