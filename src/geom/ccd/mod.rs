//! Continuous detection's exact primitive tests: does a moving vertex touch a moving
//! triangle, do two moving edges touch, and when first.
//!
//! Each vertex moves on the straight line `p(t) = p0 + t (p1 - p0)`, `t` in `[0, 1]`, from
//! and to the given doubles. The primitives are closed (touching counts) and may be
//! degenerate (a triangle that is a segment or a point, an edge that is a point), the motion
//! too (none, coplanar for the whole step, parallel edges, a touch at one instant, a vertex
//! sliding along an edge): the answer is exact for the doubles given, every time, and the
//! time of impact is a certified lower bound of the earliest meeting time, at most `2^-20`
//! below it, and exactly 0 when the primitives meet at `t = 0`.
//!
//! * `predicate.rs`: the static tests as functions of polynomial signs (degenerate cases
//!   included), shared by both stages.
//! * `filter.rs`: the floating-point filter (interval arithmetic, rounding accounted for,
//!   bisection of the step): most queries end there.
//! * `exact.rs`: the exact test, in big integers: the coplanarity cubic's roots, or when
//!   it vanishes identically the roots of every sign's polynomial, and the static test at
//!   each, earliest first.
//! * `poly.rs`: integer polynomials, root isolation and signs at real algebraic numbers.
//! * `impact.rs`: where a contact happens: the weights of the closest points and the normal
//!   at the time of impact, and the primitive pair of a polygon pair that meets first.
//! * `band.rs`: the distance-band tests (within a distance `d > 0` rather than touching,
//!   continuous detection at epsilon `e = 2 d`), by conservative advancement.
//! * `tests/`: the ground truth of the simulation steps, an independent rational
//!   reference, adversarial motions by construction, and the timing (ignored).

mod apart;
mod band;
mod exact;
mod filter;
mod impact;
mod poly;
mod polygons;
mod predicate;
#[cfg(test)]
mod tests;

use super::P3;
pub use impact::{edge_edge_impact, vertex_face_impact};
pub use polygons::{polygons_first_meet, First, MovingPolygon};
use predicate::Kind;

/// A time of impact.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Toi {
    /// A lower bound of the earliest meeting time, at most `2^-20` below it (0 exactly when
    /// `at_start`).
    pub t: f64,
    /// The primitives already meet at `t = 0`.
    pub at_start: bool,
}

/// The four points of a query, each at the start and the end of the step:
/// `[point][0 = start, 1 = end]`.
type Points = [[P3; 2]; 4];

/// Which stage decided a query (for the benchmark's tally).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Stage {
    /// The floating-point filter.
    Filter,
    /// The exact test.
    Exact,
}

/// Does the moving vertex `v` (`[start, end]`) touch the moving closed triangle `f`
/// (`[its three vertices at the start, at the end]`) at some time in `[0, 1]`, and when
/// first? Coordinates must be finite.
// The whole-step tests: the primitive tests' own tests and benchmarks (the continuous query
// asks the `_before` forms).
#[cfg_attr(not(test), allow(dead_code))]
pub fn vertex_face(v: [P3; 2], f: [[P3; 3]; 2]) -> Option<Toi> {
    decide(Kind::VertexFace, &vertex_face_points(v, f)).0
}

/// Do the moving closed segments `a` and `b` (each `[its two ends at the start, at the
/// end]`) touch at some time in `[0, 1]`, and when first? Coordinates must be finite.
#[cfg_attr(not(test), allow(dead_code))]
pub fn edge_edge(a: [[P3; 2]; 2], b: [[P3; 2]; 2]) -> Option<Toi> {
    decide(Kind::EdgeEdge, &edge_edge_points(a, b)).0
}

fn vertex_face_points(v: [P3; 2], f: [[P3; 3]; 2]) -> Points {
    [
        v,
        [f[0][0], f[1][0]],
        [f[0][1], f[1][1]],
        [f[0][2], f[1][2]],
    ]
}

fn edge_edge_points(a: [[P3; 2]; 2], b: [[P3; 2]; 2]) -> Points {
    [
        [a[0][0], a[1][0]],
        [a[0][1], a[1][1]],
        [b[0][0], b[1][0]],
        [b[0][1], b[1][1]],
    ]
}

/// [`vertex_face`], looking only for a meeting before `t_max` (in `(0, 1]`): a pair that
/// first meets at `t_max` or later may answer None (a caller that knows of a meeting at
/// `t_max` needs no later one). A time it gives is the same as [`vertex_face`]'s.
pub fn vertex_face_before(v: [P3; 2], f: [[P3; 3]; 2], t_max: f64) -> Option<Toi> {
    decide_before(Kind::VertexFace, &vertex_face_points(v, f), t_max).0
}

/// [`edge_edge`], looking only for a meeting before `t_max` (as [`vertex_face_before`]).
pub fn edge_edge_before(a: [[P3; 2]; 2], b: [[P3; 2]; 2], t_max: f64) -> Option<Toi> {
    decide_before(Kind::EdgeEdge, &edge_edge_points(a, b), t_max).0
}

/// The answer, and which stage gave it.
#[cfg_attr(not(test), allow(dead_code))]
fn decide(kind: Kind, pts: &Points) -> (Option<Toi>, Stage) {
    decide_before(kind, pts, 1.0)
}

/// [`decide`] looking only for meetings before `t_max`.
fn decide_before(kind: Kind, pts: &Points, t_max: f64) -> (Option<Toi>, Stage) {
    debug_assert!(pts.iter().flatten().flatten().all(|x| x.is_finite()));
    match filter::filter_before(kind, pts, t_max) {
        filter::Verdict::Apart => (None, Stage::Filter),
        filter::Verdict::Meets(t) => (Some(t), Stage::Filter),
        filter::Verdict::Undecided => (exact::decide(kind, pts), Stage::Exact),
    }
}
