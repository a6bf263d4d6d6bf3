//! Continuous distance-band primitive tests: does a moving vertex come within a distance
//! `d` of a moving triangle, do two moving edges come within `d` of each other, and when
//! first (continuous detection at epsilon `e > 0`, where the band is `d = e / 2`).
//!
//! Shapes and motion are those of [`super::vertex_face`] and [`super::edge_edge`]: every
//! point moves on `p(t) = p0 + t (p1 - p0)`, `t` in `[0, 1]`; the primitives are closed and
//! may be degenerate (a triangle that is a segment or a point, an edge that is a point).
//! Write `dist(t)` for the distance between the primitives at `t`, `D = d (1 + 2^-20)`,
//! `t_d` the least `t` with `dist(t) <= d` and `t_D` the least with `dist(t) <= D`
//! (`t_D <= t_d`). The promises are stated at [`vertex_face_within`].
//!
//! # Route
//!
//! 1. Swept boxes more than `d` apart along an axis (the gap rounded down): apart.
//! 2. A power-of-two scaling puts the largest coordinate in `[1, 2)` (exact, or enclosed by
//!    an ulp where a coordinate falls among the subnormals): nothing below can overflow,
//!    whatever the input's scale. Positions are taken relative to point 0 (the vertex, or
//!    the first edge's first end): `R_k(t) = R_k + t V_k`, enclosed in intervals ([`Iv`],
//!    rounded outward), exact for exact differences; so errors scale with the features'
//!    size, not with an offset.
//! 3. `t = 0` is decided exactly: a lower bound of `dist(0)` above `d`, or an upper bound at
//!    most `d`, else the exact test in big integers ([`exact`]).
//! 4. Conservative advancement from `ta = 0`, keeping `[0, ta)` proved farther than `d`.
//!    At `ta` the closest points are found in plain doubles (any choice keeps the bounds
//!    valid, a good one makes them tight): a direction `n`, a pair of points with fixed
//!    barycentric weights, and the feature they lie on.
//!    * Lower bound, fixed axis. For any `n != 0`, `dist(t) >= s(t) / |n|` with
//!      `s(t) = min_{k second} n.R_k(t) - max_{l first} n.R_l(t)` (a convex hull's extent
//!      along `n` is its vertices'). Every `n.R_k(t)` is affine in `t`, so `s` is concave:
//!      `s > d |n|` at both ends of `[ta, t1]` proves `dist > d` on all of it. `t1` is
//!      where the lines first reach `d |n|`, backed off by `2^-10` of the way, checked.
//!      Plain doubles with an a priori error bound ([`Motion::lines`]: `2^-48` of the
//!      magnitudes). This is never weaker than the Lipschitz bound `dist(tm) - L w / 2`
//!      with the same direction (`L` the largest relative speed of two vertices, one of
//!      each primitive): each line's slope `n.(v_k - v_l)` is at most `L |n|`; and it is
//!      exact for a point passing a face at constant height, where Lipschitz would bisect
//!      down to the band's width. It is Newton's method on the distance along `n`.
//!    * Lower bound, turning axis ([`Motion::advance_turning`]), where the fixed axis
//!      cannot advance or its steps shrink slowly (the closest direction turns: a fixed
//!      axis loses the features' size times the angle turned): `n(τ)` a polynomial in
//!      `τ = t - ta` (the face's normal, the lines' common normal, the perpendicular from a
//!      point to an edge's line, the difference of two points), and `g^2 - d^2 |n|^2 > 0`
//!      bounded below over `[0, w]` from its Taylor coefficients, enclosed. The plane and
//!      the lines bound the distance whatever the closest feature, and are tried too.
//!    * Upper bound (a witness). The pair's difference `y(t) - x(t)` is affine in `t`; its
//!      norm is least near some `t*` in `[ta, ta + 2^-20]`, where `|y - x|^2` is enclosed.
//!      At most `D^2` (rounded down): `dist(t*) <= D`.
//!    * The step: proved farther than `d` up to `t = 1`: apart. Advancing less than
//!      `2^-20`, and a witness in `[ta, ta + 2^-20]`: reported at `ta` (`ta <= t_d`, as
//!      `[0, ta)` is excluded; `t_D <= t* <= ta + 2^-20`). Else `ta = t1`.
//! 5. A reported pair that also touches (the zero-distance [`super::decide`]) keeps the
//!    smaller of the two times: the zero-distance toi is at most the touch time and at
//!    most `2^-20` below it, and `t_D <= t_d <=` the touch, so the smaller one is still in
//!    `[t_D - 2^-20, t_d]`, and the band's toi is never later than the contact's. Skipped
//!    when the pair is proved apart (distance > 0) until `ta + 2^-20`: the contact's toi
//!    is then later anyway.
//!
//! Rounding is accounted everywhere a decision is taken: intervals rounded outward (each
//! sum widened by an ulp where the error-free sum says it was inexact, each product by an
//! ulp), a priori bounds for the fixed axis, squares and powers rounded up or down as
//! their side requires, comparisons of a rounded value with a double (monotonic).
//!
//! # Limits
//!
//! Work is bounded: at most [`MAX_STEPS`] advancement steps (a few in practice: the
//! ground truth's queries take 1 to about 8). A step that can neither advance nor find a
//! witness, or the step count running out, ends with the conservative answer: reported,
//! `toi = ta` (no false negative, the toi never later than `t_d`, but neither the `D`
//! promise nor the toi's earliness certified; [`Route::Capped`]). It happens when the
//! distance stays within the rounding of the bounds of the band's edge: the sliver `2^-20 d`
//! must exceed the rounding of the features' coordinates (about `2^-52` of their size,
//! measured from point 0), so for `d` below about `2^-32` of the features' size, and
//! the largest coordinate's `2^-400`; then pairs that come within that rounding of `d`
//! (touching ones included) are capped. With the ground truth at `d = 2^-36` of the
//! scene's size a few touching pairs are; at `2^-30` and above, none, nor any of the
//! tests' constructed, random or thin-band motions.

use super::filter::Iv;
use super::predicate::Kind;
use super::{edge_edge_points, vertex_face_points, Points, Toi};
use crate::geom::{add_down, add_up, P3};

/// Advancement steps at most (each one excludes a piece of the step or ends the search).
pub(crate) const MAX_STEPS: u32 = 64;
/// The turning axis is tried too (it costs several fixed ones) when a fixed axis cannot
/// advance, or its step is more than this fraction of the previous one: the fixed axis'
/// advancement is Newton's method on the distance along it, whose steps shrink much faster
/// while the closest direction does not turn.
const SLOW: f64 = 0.5;
/// The toi's promised precision, `2^-20`: the witness window after `ta`.
const WINDOW: f64 = 1.0 / (1u32 << 20) as f64;
/// `2^-20` as the band's relative sliver.
const SLIVER: f64 = WINDOW;

/// Does the moving vertex `v` (`[start, end]`) come within distance `d` of the moving closed
/// triangle `f` (`[its three vertices at the start, at the end]`, possibly a segment or a
/// point) at some time in `[0, 1]`, and when first? Coordinates finite, `d` finite and
/// positive.
///
/// With `D = d (1 + 2^-20)`, `t_d` the earliest time within `d` and `t_D` the earliest
/// within `D`: every pair within `d` at some time is reported; a reported pair comes within
/// `D` at some time; `toi.t` is in `[t_D - 2^-20, t_d]` (never later than the earliest time
/// within `d`, at most `2^-20` before the earliest within `D`), and no later than the
/// zero-distance [`super::vertex_face`]'s when that one reports. `toi.at_start` exactly
/// when the pair is within `d` at `t = 0` (decided exactly), and then `toi.t = 0`;
/// otherwise `toi.t` is 0 only when the pair comes within `D` in the first `2^-20` of the
/// step and its distance at 0 exceeds `d` by less than the rounding can tell. The
/// promises on `D` and the toi's earliness hold unless the work bound is hit (see the
/// module's "Limits": the answer is then reported, with a toi still never later than
/// `t_d`).
pub fn vertex_face_within(v: [P3; 2], f: [[P3; 3]; 2], d: f64) -> Option<Toi> {
    decide_within(Kind::VertexFace, &vertex_face_points(v, f), d).0
}

/// Do the moving closed segments `a` and `b` (each `[its two ends at the start, at the
/// end]`, possibly points) come within distance `d` of each other at some time in
/// `[0, 1]`, and when first? Coordinates finite, `d` finite and positive. The promises are
/// those of [`vertex_face_within`] (with [`super::edge_edge`] for the zero-distance toi).
pub fn edge_edge_within(a: [[P3; 2]; 2], b: [[P3; 2]; 2], d: f64) -> Option<Toi> {
    decide_within(Kind::EdgeEdge, &edge_edge_points(a, b), d).0
}

/// How a query ended (for the tests' and the benchmark's tallies).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Route {
    /// Swept boxes apart.
    Boxes,
    /// Decided at `t = 0` (within) or by the advancement (apart or a witness), in floats.
    Float,
    /// `t = 0` needed the exact test in big integers (then the advancement as above).
    ExactStart,
    /// The conservative answer (reported, not certified to come within `D`).
    Capped,
}

const AT_START: Toi = Toi {
    t: 0.0,
    at_start: true,
};

/// The answer and how it was reached.
pub(crate) fn decide_within(kind: Kind, pts: &Points, d: f64) -> (Option<Toi>, Route) {
    debug_assert!(pts.iter().flatten().flatten().all(|x| x.is_finite()));
    debug_assert!(d.is_finite() && d > 0.0);
    let split = split(kind);
    if boxes_apart(pts, split, d) {
        return (None, Route::Boxes);
    }
    let Some(m) = Motion::new(kind, pts, d) else {
        return (Some(AT_START), Route::Float);
    };
    let (found, route) = m.search(pts, d);
    let (t, clear) = match found {
        Found::Apart => return (None, route),
        Found::AtStart => return (Some(AT_START), route),
        Found::From(t, clear) => (t, clear),
    };
    // A pair that touches: the smaller toi keeps both promises (the module's doc, 5). Not
    // needed when it cannot touch before t + 2^-20: the zero-distance toi is then later.
    let t = match (!clear).then(|| super::decide(kind, pts).0).flatten() {
        Some(z) if z.t < t => z.t,
        _ => t,
    };
    (Some(Toi { t, at_start: false }), route)
}

/// How many of the four points are the first primitive's.
fn split(kind: Kind) -> usize {
    match kind {
        Kind::VertexFace => 1,
        Kind::EdgeEdge => 2,
    }
}

/// Are the swept boxes (every point at the start and the end) of the two primitives more
/// than `d` apart along one axis? The gap is rounded down, so a true gap at most `d` never
/// passes; the primitives stay in their boxes for the whole step.
fn boxes_apart(pts: &Points, split: usize, d: f64) -> bool {
    (0..3).any(|ax| {
        let range = |r: std::ops::Range<usize>| {
            r.flat_map(|i| pts[i].iter().map(move |p| p[ax]))
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), x| {
                    (lo.min(x), hi.max(x))
                })
        };
        let (a, b) = (range(0..split), range(split..4));
        add_down(b.0, -a.1) > d || add_down(a.0, -b.1) > d
    })
}

/// `2^e` for `e` in `[-1022, 1023]` (a normal double, exactly).
fn pow2(e: i32) -> f64 {
    debug_assert!((-1022..=1023).contains(&e));
    f64::from_bits(((e + 1023) as u64) << 52)
}

/// `x 2^k` for `|k| <= 2098`, in two steps by normal powers of two: exact unless the result
/// is subnormal, where the (at most two) roundings are below `2^-1074` together.
fn mul_pow2(x: f64, k: i32) -> f64 {
    let h = k / 2;
    x * pow2(h) * pow2(k - h)
}

/// `floor(log2(x))` for a finite `x > 0` (subnormals too).
fn exponent_of(x: f64) -> i32 {
    let bits = x.to_bits();
    let e = ((bits >> 52) & 0x7ff) as i32;
    if e == 0 {
        (63 - bits.leading_zeros() as i32) - 1074
    } else {
        e - 1023
    }
}

/// An interval times a double, rounded outward (each product within half an ulp, or within
/// `2^-1075` underflowed: one `next_*` covers it); exactly 0 when either is.
#[inline(always)]
fn mulp(a: Iv, s: f64) -> Iv {
    if s == 0.0 || (a.lo == 0.0 && a.hi == 0.0) {
        return Iv::point(0.0);
    }
    let (x, y) = (a.lo * s, a.hi * s);
    let (lo, hi) = if s > 0.0 { (x, y) } else { (y, x) };
    Iv {
        lo: lo.next_down(),
        hi: hi.next_up(),
    }
}

/// An upper bound of `x^2` for every `x` in `a`.
#[inline(always)]
fn sq_up(a: Iv) -> f64 {
    let m = a.lo.abs().max(a.hi.abs());
    (m * m).next_up()
}

/// An upper bound of `|x|^2` over the box `q`.
fn norm2_up(q: &[Iv; 3]) -> f64 {
    add_up(add_up(sq_up(q[0]), sq_up(q[1])), sq_up(q[2]))
}

type V3 = [f64; 3];

fn sub(a: V3, b: V3) -> V3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn dot(a: V3, b: V3) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn cross(a: V3, b: V3) -> V3 {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

fn axpy(a: V3, s: f64, b: V3) -> V3 {
    [a[0] + s * b[0], a[1] + s * b[1], a[2] + s * b[2]]
}

/// `x > 0` (false for NaN).
fn positive(x: f64) -> bool {
    x > 0.0
}

/// `x` in `[0, 1]` (NaN: 0).
fn unit_clamp(x: f64) -> f64 {
    if x > 0.0 {
        x.min(1.0)
    } else {
        0.0
    }
}

/// The parameter of the point of segment `[a, b]` nearest the origin (plain doubles).
fn seg_param(a: V3, b: V3) -> f64 {
    let u = sub(b, a);
    let uu = dot(u, u);
    if uu > 0.0 {
        unit_clamp(-dot(a, u) / uu)
    } else {
        0.0
    }
}

/// Which distance the closest pair realizes, naming points by index (`0..4`, relative to
/// point 0): it picks the moving axis of [`Motion::advance_turning`].
#[derive(Clone, Copy, Debug, PartialEq)]
enum Feature {
    /// The vertex and the triangle's plane (the nearest point inside the triangle).
    Plane,
    /// The two edges' lines (the nearest points inside both, the lines not near parallel).
    Lines,
    /// A point and the line of an edge `(e0, e1)`.
    PointLine { p: usize, e0: usize, e1: usize },
    /// Two points.
    PointPoint { p: usize, q: usize },
}

/// A point of each primitive by fixed weights, the direction from the first toward the
/// second, and the feature, chosen (in plain doubles) as the closest pair at some time.
struct Pair {
    /// Vertex-face: the weights of `R2 - R1` and `R3 - R1` on the triangle
    /// (`y = R1 + w0 (R2 - R1) + w1 (R3 - R1)`). Edge-edge: `x = w0 R1` on the first edge
    /// (from point 0, at the origin), `y = R2 + w1 (R3 - R2)` on the second.
    w: [f64; 2],
    /// The direction: the triangle's normal when the nearest point is inside (accurate to
    /// the rounding of the edges, not of the small difference `y - x`), the edges' cross
    /// product likewise, else `y - x`.
    n: V3,
    feature: Feature,
}

/// The closest pair of the vertex (the origin) and the triangle `r[1..4]`.
fn vf_pair(r: &[V3; 4]) -> Pair {
    let (a, b, c) = (r[1], r[2], r[3]);
    let (ab, ac) = (sub(b, a), sub(c, a));
    let nrm = cross(ab, ac);
    let nn = dot(nrm, nrm);
    if nn > 0.0 && nn.is_finite() {
        let ap = [-a[0], -a[1], -a[2]];
        let wb = dot(cross(ap, ac), nrm) / nn;
        let wc = dot(cross(ab, ap), nrm) / nn;
        if wb >= 0.0 && wc >= 0.0 && wb + wc <= 1.0 {
            let n = if dot(nrm, a) >= 0.0 {
                nrm
            } else {
                nrm.map(|x| -x)
            };
            return Pair {
                w: [wb, wc],
                n,
                feature: Feature::Plane,
            };
        }
    }
    // The boundary: the nearest of the three edges `(i, j)`, its weights as above.
    let mut best: Option<(f64, Pair)> = None;
    for (i, j) in [(1, 2), (1, 3), (2, 3)] {
        let s = seg_param(r[i], r[j]);
        let y = axpy(r[i], s, sub(r[j], r[i]));
        let d2 = dot(y, y);
        if best.as_ref().is_some_and(|b| !positive(b.0 - d2)) {
            continue;
        }
        let w = match (i, j) {
            (1, 2) => [s, 0.0],
            (1, 3) => [0.0, s],
            _ => [1.0 - s, s],
        };
        let feature = if s <= 0.0 {
            Feature::PointPoint { p: 0, q: i }
        } else if s >= 1.0 {
            Feature::PointPoint { p: 0, q: j }
        } else {
            Feature::PointLine { p: 0, e0: i, e1: j }
        };
        best = Some((d2, Pair { w, n: y, feature }));
    }
    best.expect("three edges").1
}

/// The closest pair of the segments `[0, r1]` and `[r2, r3]` (Ericson's closest points of
/// two segments, degenerate ones included).
fn ee_pair(r: &[V3; 4]) -> Pair {
    let (d1, d2) = (r[1], sub(r[3], r[2]));
    let rr = [-r[2][0], -r[2][1], -r[2][2]];
    let (a, e, f) = (dot(d1, d1), dot(d2, d2), dot(d2, rr));
    let mut crossing = false;
    let (s, t) = if !positive(a) && !positive(e) {
        (0.0, 0.0)
    } else if !positive(a) {
        (0.0, unit_clamp(f / e))
    } else {
        let c = dot(d1, rr);
        if !positive(e) {
            (unit_clamp(-c / a), 0.0)
        } else {
            let b = dot(d1, d2);
            let denom = a * e - b * b;
            let mut s = if denom > 0.0 {
                unit_clamp((b * f - c * e) / denom)
            } else {
                0.0
            };
            let mut t = (b * s + f) / e;
            if t < 0.0 {
                t = 0.0;
                s = unit_clamp(-c / a);
            } else if t > 1.0 {
                t = 1.0;
                s = unit_clamp((b - c) / a);
            }
            crossing = denom > 0.0;
            (s, unit_clamp(t))
        }
    };
    let x = d1.map(|v| s * v);
    let y = axpy(r[2], t, d2);
    let yx = sub(y, x);
    let (s_in, t_in) = (s > 0.0 && s < 1.0, t > 0.0 && t < 1.0);
    let (end_a, end_b) = (if s >= 1.0 { 1 } else { 0 }, if t >= 1.0 { 3 } else { 2 });
    let feature = match (s_in, t_in) {
        // (Near parallel, the search falls back to a point against the second's line.)
        (true, true) if crossing => Feature::Lines,
        // Parallel: a point of the first against the second's line.
        (true, true) | (false, true) => Feature::PointLine {
            p: end_a,
            e0: 2,
            e1: 3,
        },
        (true, false) => Feature::PointLine {
            p: end_b,
            e0: 0,
            e1: 1,
        },
        (false, false) => Feature::PointPoint { p: end_a, q: end_b },
    };
    let n = if feature == Feature::Lines {
        let m = cross(d1, d2);
        if dot(m, yx) >= 0.0 {
            m
        } else {
            m.map(|v| -v)
        }
    } else {
        yx
    };
    Pair {
        w: [s, t],
        n,
        feature,
    }
}

/// `n` scaled to about unit length (any nonzero multiple would do: the bounds divide by a
/// rigorous `|n|`); zero stays zero.
fn unit(n: V3) -> V3 {
    let nn = dot(n, n);
    if nn > 0.0 && nn.is_finite() {
        let s = 1.0 / nn.sqrt();
        n.map(|x| x * s)
    } else if n.iter().all(|x| x.is_finite()) {
        n
    } else {
        [0.0; 3]
    }
}

/// A polynomial in `τ = t - ta` with `N` coefficients, each enclosed (rounded outward, as
/// [`Iv`]). Products name their length (`N + M - 1`, checked in debug builds).
#[derive(Clone, Copy)]
struct Tp<const N: usize>([Iv; N]);

const IV0: Iv = Iv { lo: 0.0, hi: 0.0 };

/// The polynomial that every condition is widened to (degree 8).
type Cond = Tp<9>;

impl<const N: usize> Tp<N> {
    #[inline]
    fn add(&self, o: &Tp<N>) -> Tp<N> {
        Tp(std::array::from_fn(|i| self.0[i].add(o.0[i])))
    }

    #[inline]
    fn sub(&self, o: &Tp<N>) -> Tp<N> {
        Tp(std::array::from_fn(|i| self.0[i].sub(o.0[i])))
    }

    #[inline]
    fn neg(&self) -> Tp<N> {
        Tp(self.0.map(|x| Iv {
            lo: -x.hi,
            hi: -x.lo,
        }))
    }

    #[inline]
    fn mul<const M: usize, const R: usize>(&self, o: &Tp<M>) -> Tp<R> {
        debug_assert_eq!(R, N + M - 1);
        let mut c = [IV0; R];
        for i in 0..N {
            for j in 0..M {
                c[i + j] = c[i + j].add(self.0[i].mul(o.0[j]));
            }
        }
        Tp(c)
    }

    #[inline]
    fn scale(&self, s: f64) -> Tp<N> {
        Tp(self.0.map(|x| mulp(x, s)))
    }

    /// The same polynomial with `R >= N` coefficients.
    #[inline]
    fn widen<const R: usize>(&self) -> Tp<R> {
        debug_assert!(R >= N);
        Tp(std::array::from_fn(|i| if i < N { self.0[i] } else { IV0 }))
    }

    /// A lower bound of the polynomial over `τ` in `[0, w]` (`w >= 0`):
    /// `c0 + sum min(0, c_i) w^i`, each `c_i` by its enclosure's lower end (every term
    /// `c_i τ^i >= min(0, c_i) w^i` there), the powers rounded up and the products and sums
    /// down. `-inf` if a bound is NaN (never, in the scaled problem: nothing overflows).
    fn lower_on(&self, w: f64) -> f64 {
        let mut acc = self.0[0].lo;
        let mut wi = 1.0f64;
        for x in &self.0[1..] {
            wi = (wi * w).next_up();
            if x.lo < 0.0 {
                acc = add_down(acc, (x.lo * wi).next_down());
            } else if x.lo.is_nan() {
                return f64::NEG_INFINITY;
            }
        }
        if acc.is_nan() {
            f64::NEG_INFINITY
        } else {
            acc
        }
    }

    /// [`Tp::lower_on`] in plain doubles (to choose `w`).
    fn lower_plain(&self, w: f64) -> f64 {
        let mut acc = 0.0;
        for x in self.0[1..].iter().rev() {
            acc = (acc + x.lo.min(0.0)) * w;
        }
        self.0[0].lo + acc
    }
}

/// A vector of polynomials.
type TpV<const N: usize> = [Tp<N>; 3];

#[inline]
fn tp_sub<const N: usize>(a: &TpV<N>, b: &TpV<N>) -> TpV<N> {
    std::array::from_fn(|k| a[k].sub(&b[k]))
}

#[inline]
fn tp_dot<const N: usize, const M: usize, const R: usize>(a: &TpV<N>, b: &TpV<M>) -> Tp<R> {
    a[0].mul::<M, R>(&b[0])
        .add(&a[1].mul(&b[1]))
        .add(&a[2].mul(&b[2]))
}

#[inline]
fn tp_cross(a: &TpV<2>, b: &TpV<2>) -> TpV<3> {
    std::array::from_fn(|r| {
        let (r1, r2) = ((r + 1) % 3, (r + 2) % 3);
        a[r1].mul::<2, 3>(&b[r2]).sub(&a[r2].mul(&b[r1]))
    })
}

/// `g^2 - d^2 |n|^2` for a pair's `g` and its axis' `|n|^2` (`d2` an upper bound of
/// `d^2`), if `g(0) > 0`.
#[inline]
fn pair_cond<const G: usize, const S: usize>(g: &Tp<G>, nn: &Tp<S>, d2: f64) -> Option<Cond> {
    (g.0[0].lo > 0.0).then(|| {
        let g2: Tp<S> = g.mul(g);
        g2.sub(&nn.scale(d2)).widen()
    })
}

/// The lines `n.R_k(t) = a_k + t b_k` of a fixed direction, in plain doubles (`k = 0`:
/// identically 0), and how far the separation computed from them can be from the true one.
struct Lines {
    a: [f64; 4],
    b: [f64; 4],
    /// A bound of `|s_computed(t) - s(t)|` for `t` in `[0, 1]` ([`Motion::lines`]).
    err: f64,
    /// An upper bound of `d |n|`.
    threshold: f64,
}

/// The relative error bound of [`Motion::lines`] (`2^-48`, over twice the `14 u`, `u =
/// 2^-53`, derived there, so that the bound's own rounding is covered too).
const ERR_REL: f64 = 1.0 / (1u64 << 48) as f64;
/// An absolute allowance for products that underflow (each off by at most `2^-1075`),
/// far below any band the scaled problem resolves.
const ERR_ABS: f64 = 1e-300;

/// What the search found.
enum Found {
    Apart,
    AtStart,
    /// Reported, with this toi (not at the start), and whether the pair is certainly
    /// apart (distance > 0) until `toi + 2^-20`.
    From(f64, bool),
}

/// A query scaled and relative to point 0, ready for the search.
struct Motion {
    kind: Kind,
    /// Point `k`'s position minus point 0's at the start, enclosed (`k = 0`: zero).
    r0: [[Iv; 3]; 4],
    /// Their velocities, `R_k(1) - R_k(0)`, enclosed.
    v: [[Iv; 3]; 4],
    /// Midpoints of `r0` and `v` (plain).
    r0m: [V3; 4],
    vm: [V3; 4],
    /// The largest `|r0m_k|_1 + |vm_k|_1`, and the largest sum of the widths of `r0_k` and
    /// `v_k`, doubled (for [`Motion::lines`]'s error).
    mag: f64,
    width: f64,
    /// Upper bound of the scaled `d`.
    d_hi: f64,
    /// Lower bounds of the scaled `d^2` and `D^2`.
    d2_lo: f64,
    big2_lo: f64,
}

fn mid(a: Iv) -> f64 {
    0.5 * a.lo + 0.5 * a.hi
}

impl Motion {
    /// The scaled query; `None` when the pair is certainly within `d` at the start (no
    /// extent: all points at the origin, or the scaled `d` beyond any distance there).
    fn new(kind: Kind, pts: &Points, d: f64) -> Option<Motion> {
        let m = pts
            .iter()
            .flatten()
            .flatten()
            .fold(0.0f64, |m, x| m.max(x.abs()));
        if m == 0.0 {
            return None;
        }
        let k = -exponent_of(m);
        // Each scaled coordinate exactly, or (fallen among the subnormals) within an ulp.
        let scaled = |x: f64| {
            let y = mul_pow2(x, k);
            if mul_pow2(y, -k) == x {
                Iv::point(y)
            } else {
                Iv {
                    lo: y.next_down(),
                    hi: y.next_up(),
                }
            }
        };
        let ds = scaled(d);
        // Every scaled coordinate is below 2 in magnitude: two points at most 4 sqrt(3) < 8
        // apart.
        if ds.lo >= 8.0 {
            return None;
        }
        let p: [[[Iv; 3]; 2]; 4] = pts.map(|q| q.map(|x| x.map(scaled)));
        let r0: [[Iv; 3]; 4] =
            std::array::from_fn(|i| std::array::from_fn(|ax| p[i][0][ax].sub(p[0][0][ax])));
        let v: [[Iv; 3]; 4] = std::array::from_fn(|i| {
            std::array::from_fn(|ax| p[i][1][ax].sub(p[0][1][ax]).sub(r0[i][ax]))
        });
        let d_lo = ds.lo.max(0.0);
        // d 2^-20 is exact unless subnormal; rounded down there.
        let sliver = if d_lo * SLIVER >= f64::MIN_POSITIVE {
            d_lo * SLIVER
        } else {
            (d_lo * SLIVER).next_down().max(0.0)
        };
        let big_lo = add_down(d_lo, sliver);
        // A square rounded to nearest, then down by an ulp (at least the rounding error).
        let sq_down = |x: f64| (x * x).next_down().max(0.0);
        let (r0m, vm) = (r0.map(|q| q.map(mid)), v.map(|q| q.map(mid)));
        let l1 = |x: &V3| x[0].abs() + x[1].abs() + x[2].abs();
        let widths = |x: &[Iv; 3]| x.iter().map(|i| i.hi - i.lo).sum::<f64>();
        let mag = (0..4).map(|k| l1(&r0m[k]) + l1(&vm[k])).fold(0.0, f64::max);
        let width = (0..4)
            .map(|k| 2.0 * (widths(&r0[k]) + widths(&v[k])))
            .fold(0.0, f64::max);
        Some(Motion {
            kind,
            r0,
            v,
            r0m,
            vm,
            mag,
            width,
            d_hi: ds.hi,
            d2_lo: sq_down(d_lo),
            big2_lo: sq_down(big_lo),
        })
    }

    /// The points relative to point 0 at `t`, in plain doubles.
    fn at_plain(&self, t: f64) -> [V3; 4] {
        std::array::from_fn(|k| axpy(self.r0m[k], t, self.vm[k]))
    }

    /// The closest pair at `t` (plain doubles).
    fn pair(&self, t: f64) -> Pair {
        let r = self.at_plain(t);
        match self.kind {
            Kind::VertexFace => vf_pair(&r),
            Kind::EdgeEdge => ee_pair(&r),
        }
    }

    /// The lines of the direction `n`, and `d |n|` bounded above.
    fn lines(&self, n: V3) -> Lines {
        // The error, for `t` in [0, 1] (Higham's gamma_k = k u / (1 - k u), u = 2^-53):
        // * a_k = fl(n.R_k) and b_k = fl(n.V_k), three-term dot products of the midpoints:
        //   each within gamma_3 N M_k of the exact ones, N = max |n_i|, M_k = |R_k|_1 +
        //   |V_k|_1 (midpoints); the midpoints within W_k (the enclosures' widths, summed,
        //   doubled: the midpoint is rounded) of the true values: N W_k more.
        // * f_k(t) = fl(a_k + fl(t b_k)): within gamma_2 (|a_k| + |b_k|) of a_k + t b_k,
        //   so within (gamma_3 + gamma_2 (1 + gamma_3)) N M_k <= gamma_5 N M_k in all.
        // * s = fl(min_second f - max_first f): twice that, plus u |s| <= 2 u (1 + gamma_5)
        //   N M: below 14 u N M + 2 N W, M and W the largest M_k and W_k.
        // `err` takes 2^-48 > 28 u and 4 W (its own rounding, a few u relative, is
        // covered), and ERR_ABS for underflow.
        let a = std::array::from_fn(|k| dot(n, self.r0m[k]));
        let b = std::array::from_fn(|k| dot(n, self.vm[k]));
        let big_n = n[0].abs().max(n[1].abs()).max(n[2].abs());
        let err = big_n * (ERR_REL * self.mag + 4.0 * self.width) + ERR_ABS;
        // |n| <= sqrt(fl(n.n)) (1 + 2^-50) (the sum and the root round by a few u);
        // the product rounds by u more: (1 + 2^-48) covers both.
        let norm = dot(n, n).sqrt();
        Lines {
            a,
            b,
            err,
            threshold: self.d_hi * norm * (1.0 + ERR_REL) + ERR_ABS,
        }
    }

    /// The points of each primitive: `(first, second)` index ranges.
    fn sides(&self) -> (std::ops::Range<usize>, std::ops::Range<usize>) {
        let s = split(self.kind);
        (0..s, s..4)
    }

    /// A lower bound of `s(t)`, the separation along the lines' direction at `t`, as far as
    /// comparisons with a double go: `sep_lo(t) > c` implies `s(t) > c` (the last
    /// subtraction rounds monotonically).
    fn sep_lo(&self, l: &Lines, t: f64) -> f64 {
        let (first, second) = self.sides();
        let at = |k: usize| l.a[k] + t * l.b[k];
        let hi_a = first.map(at).fold(f64::NEG_INFINITY, f64::max);
        let lo_b = second.map(at).fold(f64::INFINITY, f64::min);
        (lo_b - hi_a) - l.err
    }

    /// The end `t1 > ta` of the piece `[ta, t1]` the lines prove farther than `d` (given
    /// `s(ta) > d |n|`), if a check passes: where the lines first reach the threshold,
    /// backed off by `2^-10` of the way (then `1/2`, `1/8`, `1/64`) until the bound there
    /// exceeds it. `s` is concave: both ends suffice.
    fn advance(&self, l: &Lines, ta: f64) -> Option<f64> {
        let (first, second) = self.sides();
        let c = l.threshold + l.err;
        let mut t1 = 1.0f64;
        for k in second {
            for j in first.clone() {
                let slope = l.b[k] - l.b[j];
                if slope < 0.0 {
                    let g = (l.a[k] - l.a[j]) + ta * slope;
                    let tc = ta + (g - c) / -slope;
                    if tc < t1 {
                        t1 = tc;
                    }
                }
            }
        }
        // (Not past ta; NaN: ta.)
        t1 = t1.max(ta);
        let w = t1 - ta;
        let tries = [
            if t1 >= 1.0 { 1.0 } else { f64::NAN },
            ta + w * (1.0 - 1.0 / 1024.0),
            ta + w * 0.5,
            ta + w * 0.125,
            ta + w / 64.0,
        ];
        tries
            .into_iter()
            .find(|&t| t > ta && t <= 1.0 && self.sep_lo(l, t) > l.threshold)
    }

    /// The end `t1 > ta` of a piece `[ta, t1]` proved farther than `d` with a turning
    /// axis, if one is found. The axis `n(τ)` follows the closest feature at `ta`
    /// (polynomials in `τ = t - ta`, coefficients enclosed). At each `τ`, as for a fixed
    /// axis, `dist >= g_kl(τ) / |n(τ)|` for every pair of a point `k` of the second
    /// primitive and `l` of the first, `g_kl = n.(R_k - R_l)`; so `g_kl > 0` and
    /// `g_kl^2 - d^2 |n|^2 > 0` for all of them prove `dist > d`, and with `g_kl(0) > 0`
    /// it is enough that the latter stay positive on `[0, w]` (`g_kl` cannot reach 0
    /// without it going negative first): [`Tp::lower_on`] bounds it.
    ///
    /// * Plane: `n = (R2 - R1) x (R3 - R1)`; every `g` is `n.R1` (the normal is orthogonal
    ///   to the triangle), `g / |n|` the distance to the plane.
    /// * Lines: `n = R1 x (R3 - R2)`; every `g` is `n.R2`, the distance between the lines.
    /// * A point `p` and the line of `(e0, e1)`, `u = R_e1 - R_e0`: `n = -+ u x c_p` with
    ///   `c_k = (R_k - R_e0) x u`; then `n.(R_k - R_e0) = -+ c_p.c_k` (0 on the line) and
    ///   `|n| = |u| |c_p|`, so the point against the line is `|c_p|^2 - d^2 |u|^2 > 0` (the
    ///   distance to the line) and any other pair `g = +- c_p.(c_l - c_k)`. Written so, the
    ///   rounding is about `2^-52` of the features' size in distance, where a direction
    ///   taken from the small difference `y - x` (or `n` expanded, in intervals) loses
    ///   that size squared over the distance.
    /// * Two points `p`, `q`: `n = R_q - R_p`, the pair itself `|n|^2 - d^2 > 0`.
    ///
    /// These are exact to first order however the primitives turn, where a fixed axis
    /// loses the features' size times the angle turned.
    fn advance_turning(&self, feature: Feature, ta: f64) -> Option<f64> {
        let pos: [TpV<2>; 4] = std::array::from_fn(|k| {
            std::array::from_fn(|ax| {
                Tp([self.r0[k][ax].add(mulp(self.v[k][ax], ta)), self.v[k][ax]])
            })
        });
        let d2 = (self.d_hi * self.d_hi).next_up();
        let (first, second) = self.sides();
        // Polynomials that must stay positive on [0, w].
        let mut conds = [Tp([IV0; 9]); 4];
        let mut count = 0;
        let mut push = |c: Cond| {
            conds[count] = c;
            count += 1;
        };
        match feature {
            Feature::Plane | Feature::Lines => {
                let (n, g): (TpV<3>, Tp<4>) = if feature == Feature::Plane {
                    let n = tp_cross(&tp_sub(&pos[2], &pos[1]), &tp_sub(&pos[3], &pos[1]));
                    (n, tp_dot(&n, &pos[1]))
                } else {
                    let n = tp_cross(&pos[1], &tp_sub(&pos[3], &pos[2]));
                    (n, tp_dot(&n, &pos[2]))
                };
                let g = if g.0[0].hi < 0.0 { g.neg() } else { g };
                let nn: Tp<5> = tp_dot(&n, &n);
                push(pair_cond::<4, 7>(&g, &nn.widen(), d2)?);
            }
            Feature::PointLine { p, e0, e1 } => {
                let u = tp_sub(&pos[e1], &pos[e0]);
                let line = |k: usize| k == e0 || k == e1;
                // (Not needed on the line: there c = 0.)
                let c: [TpV<3>; 4] = std::array::from_fn(|k| {
                    if line(k) {
                        [Tp([IV0; 3]); 3]
                    } else {
                        tp_cross(&tp_sub(&pos[k], &pos[e0]), &u)
                    }
                });
                let uu: Tp<3> = tp_dot(&u, &u);
                let cp2: Tp<5> = tp_dot(&c[p], &c[p]);
                push(cp2.sub(&uu.widen::<5>().scale(d2)).widen());
                let nn: Tp<7> = uu.mul(&cp2);
                // n.(R_k - R_e0) = -sign c_p.c_k, sign + when p is on the first side.
                let proj = |k: usize| -> Tp<5> {
                    if line(k) {
                        Tp([IV0; 5])
                    } else if first.contains(&p) {
                        tp_dot::<3, 3, 5>(&c[p], &c[k]).neg()
                    } else {
                        tp_dot(&c[p], &c[k])
                    }
                };
                for k in second.clone() {
                    for l in first.clone() {
                        // The feature's own pair; both ends of the line project to 0, so
                        // one of them is enough.
                        let own = (k == p && line(l)) || (l == p && line(k));
                        let twin =
                            (l == e1 && first.contains(&e0)) || (k == e1 && second.contains(&e0));
                        if !own && !twin {
                            push(pair_cond::<5, 9>(&proj(k).sub(&proj(l)), &nn.widen(), d2)?);
                        }
                    }
                }
            }
            Feature::PointPoint { p, q } => {
                let n = tp_sub(&pos[q], &pos[p]);
                let nn: Tp<3> = tp_dot(&n, &n);
                let mut own = nn;
                own.0[0] = own.0[0].sub(Iv::point(d2));
                push(own.widen());
                for k in second.clone() {
                    for l in first.clone() {
                        if (k, l) != (q, p) {
                            let g: Tp<3> = tp_dot(&n, &tp_sub(&pos[k], &pos[l]));
                            push(pair_cond::<3, 5>(&g, &nn.widen(), d2)?);
                        }
                    }
                }
            }
        }
        let conds = &conds[..count];
        if !conds.iter().all(|h| h.0[0].lo > 0.0) {
            return None;
        }
        let plain = |w: f64| {
            conds
                .iter()
                .map(|h| h.lower_plain(w))
                .fold(f64::INFINITY, f64::min)
        };
        // The bounds decrease in w: the largest w they keep positive, roughly (halving from
        // the rest of the step, then 12 bisections), then backed off and checked.
        let rest = 1.0 - ta;
        let mut tries = [f64::NAN; 4];
        if plain(rest) > 0.0 {
            tries[0] = 1.0;
        } else {
            let mut lo = rest;
            while lo > 1e-300 && !positive(plain(lo)) {
                lo *= 0.5;
            }
            let mut hi = 2.0 * lo;
            for _ in 0..12 {
                let m = 0.5 * (lo + hi);
                if plain(m) > 0.0 {
                    lo = m;
                } else {
                    hi = m;
                }
            }
            tries[1] = ta + lo * (1.0 - 1.0 / 1024.0);
            tries[2] = ta + lo * 0.5;
            tries[3] = ta + lo * 0.125;
        }
        tries.into_iter().find(|&t1| {
            t1 > ta && t1 <= 1.0 && {
                let w = add_up(t1, -ta);
                conds.iter().all(|h| h.lower_on(w) > 0.0)
            }
        })
    }

    /// Is there a time in `[lo, hi]` where the pair's points are within `sqrt(bound2)`? The
    /// difference `y(t) - x(t) = C + t E` (exact reals, enclosed) is affine for fixed
    /// weights; its norm is least near `t* = -C.E / |E|^2` (plain doubles, clamped), where
    /// `|C + t* E|^2` is bounded above. The weights are made valid first (nonnegative, a
    /// triangle's two at most 1 together: the third, `1 - w0 - w1`, is then a nonnegative
    /// real), so `x` and `y` are points of the primitives.
    fn witness(&self, w: [f64; 2], lo: f64, hi: f64, bound2: f64) -> bool {
        let (mut w0, mut w1) = (unit_clamp(w[0]), unit_clamp(w[1]));
        if self.kind == Kind::VertexFace && add_up(w0, w1) > 1.0 {
            w1 = add_down(1.0, -w0).max(0.0);
            if add_up(w0, w1) > 1.0 {
                (w0, w1) = (1.0, 0.0);
            }
        }
        let affine = |x: &[[Iv; 3]; 4]| -> [Iv; 3] {
            std::array::from_fn(|ax| match self.kind {
                Kind::VertexFace => x[1][ax]
                    .add(mulp(x[2][ax].sub(x[1][ax]), w0))
                    .add(mulp(x[3][ax].sub(x[1][ax]), w1)),
                Kind::EdgeEdge => x[2][ax]
                    .add(mulp(x[3][ax].sub(x[2][ax]), w1))
                    .sub(mulp(x[1][ax], w0)),
            })
        };
        let (c, e) = (affine(&self.r0), affine(&self.v));
        let (cm, em) = (c.map(mid), e.map(mid));
        let ee = dot(em, em);
        // In [lo, hi] (NaN: lo).
        let t = if ee > 0.0 { -dot(cm, em) / ee } else { lo };
        let t = t.max(lo).min(hi);
        let q: [Iv; 3] = std::array::from_fn(|ax| c[ax].add(mulp(e[ax], t)));
        norm2_up(&q) <= bound2
    }

    /// Is the pair within `d` at `t = 0`? From the float bounds, else exactly.
    fn within_at_start(&self, pts: &Points, d: f64, pair: &Pair, l: &Lines) -> (bool, bool) {
        if self.sep_lo(l, 0.0) > l.threshold {
            (false, false)
        } else if self.witness(pair.w, 0.0, 0.0, self.d2_lo) {
            (true, false)
        } else {
            (exact::within_at_start(self.kind, pts, d), true)
        }
    }

    /// The search (see the module's doc): the finding and the route.
    fn search(&self, pts: &Points, d: f64) -> (Found, Route) {
        let mut route = Route::Float;
        let mut ta = 0.0f64;
        let mut last_step = f64::INFINITY;
        for step in 0..MAX_STEPS {
            let pair = self.pair(ta);
            let l = self.lines(unit(pair.n));
            if step == 0 {
                let (within, exact) = self.within_at_start(pts, d, &pair, &l);
                if exact {
                    route = Route::ExactStart;
                }
                if within {
                    return (Found::AtStart, route);
                }
            }
            let mut next = if self.sep_lo(&l, ta) > l.threshold {
                self.advance(&l, ta)
            } else {
                None
            };
            // The turning axes where the fixed one cannot advance or is slow (`SLOW`): the
            // closest feature's, and the primitives' own hull (the plane, the two lines),
            // a lower bound whatever the closest feature (where a vertex slides from beside
            // an edge over the face, it is the one that carries on); edges near parallel
            // may lose their lines' distance in the rounding of u x v, a point against the
            // other's line then.
            let slow = next.is_none_or(|t1| t1 - ta > SLOW * last_step);
            if next != Some(1.0) && slow {
                let hull = match self.kind {
                    Kind::VertexFace => Feature::Plane,
                    Kind::EdgeEdge => Feature::Lines,
                };
                let mut features = [Some(pair.feature), Some(hull), None];
                if pair.feature == hull {
                    features[1] = None;
                }
                let near_parallel = Feature::PointLine { p: 0, e0: 2, e1: 3 };
                if self.kind == Kind::EdgeEdge && pair.feature != near_parallel {
                    features[2] = Some(near_parallel);
                }
                // In that order, until one at least doubles the fixed axis' step and is no
                // shorter than the last step (the progress is no longer slow).
                let fixed = next.map_or(0.0, |t1| t1 - ta).max(last_step.min(1.0));
                for f in features.into_iter().flatten() {
                    if let Some(t) = self.advance_turning(f, ta) {
                        if next.is_none_or(|n| t > n) {
                            next = Some(t);
                        }
                        if t - ta >= 2.0 * fixed {
                            break;
                        }
                    }
                }
            }
            if next == Some(1.0) {
                return (Found::Apart, route);
            }
            let end = (ta + WINDOW).min(1.0);
            if next.is_none_or(|t1| t1 - ta < WINDOW) && self.witness(pair.w, ta, end, self.big2_lo)
            {
                // Apart until `end`: the separation positive at both ends (concave).
                let clear = self.sep_lo(&l, ta) > 0.0 && self.sep_lo(&l, end) > 0.0;
                return (Found::From(ta, clear), route);
            }
            match next {
                Some(t1) => (last_step, ta) = (t1 - ta, t1),
                None => return (Found::From(ta, false), Route::Capped),
            }
        }
        (Found::From(ta, false), Route::Capped)
    }
}

/// The exact test at `t = 0`: is the squared distance between the primitives at most
/// `d^2`? All thirteen doubles (the four start points, `d`) are scaled by one power of two
/// into integers; then closest-feature distances in integers, without division:
///
/// * point `p`, segment `[a, b]` (`u = b - a`, `w = p - a`): `|w|^2` when `u = 0` or
///   `w.u <= 0`, `|p - b|^2` when `w.u >= u.u`, else `|w x u|^2 / |u|^2`;
/// * point, triangle: when the normal `m` is not zero and the point projects into the
///   closed triangle (`m.((e1 - e0) x (p - e0)) >= 0` for its three edges), the plane's
///   distance `(m.(p - a))^2 / |m|^2`; else the nearest of its three edges (a degenerate
///   triangle is the union of its edges, and otherwise the nearest point is on the
///   boundary);
/// * segments `a0 + s u`, `b0 + t v`: when `m = u x v` is not zero and the lines' closest
///   points are inside both (`s = ((b0 - a0) x v).m / |m|^2`, `t = ((b0 - a0) x u).m /
///   |m|^2` in `[0, 1]`), `((b0 - a0).m)^2 / |m|^2`; else (the convex distance is least on
///   the boundary of the parameter square) the nearest of the four end-to-segment
///   distances.
mod exact {
    use super::super::predicate::Kind;
    use super::super::Points;
    use num_bigint::BigInt;
    use num_traits::Zero;

    use super::super::exact::decompose;

    type Int = BigInt;
    type V = [Int; 3];

    fn sub(a: &V, b: &V) -> V {
        std::array::from_fn(|k| &a[k] - &b[k])
    }

    fn dot(a: &V, b: &V) -> Int {
        &a[0] * &b[0] + &a[1] * &b[1] + &a[2] * &b[2]
    }

    fn cross(a: &V, b: &V) -> V {
        [
            &a[1] * &b[2] - &a[2] * &b[1],
            &a[2] * &b[0] - &a[0] * &b[2],
            &a[0] * &b[1] - &a[1] * &b[0],
        ]
    }

    /// Is `p` within `sqrt(d2)` of the segment `[a, b]`?
    fn point_segment(p: &V, a: &V, b: &V, d2: &Int) -> bool {
        let (u, w) = (sub(b, a), sub(p, a));
        let uu = dot(&u, &u);
        let wu = dot(&w, &u);
        if uu.is_zero() || wu <= Int::zero() {
            return dot(&w, &w) <= *d2;
        }
        if wu >= uu {
            let pb = sub(p, b);
            return dot(&pb, &pb) <= *d2;
        }
        let x = cross(&w, &u);
        dot(&x, &x) <= d2 * &uu
    }

    fn point_triangle(p: &V, a: &V, b: &V, c: &V, d2: &Int) -> bool {
        let m = cross(&sub(b, a), &sub(c, a));
        let mm = dot(&m, &m);
        if !mm.is_zero() {
            let inside = [(a, b), (b, c), (c, a)]
                .iter()
                .all(|(e0, e1)| dot(&m, &cross(&sub(e1, e0), &sub(p, e0))) >= Int::zero());
            if inside {
                let h = dot(&m, &sub(p, a));
                return &h * &h <= d2 * &mm;
            }
        }
        point_segment(p, a, b, d2) || point_segment(p, b, c, d2) || point_segment(p, c, a, d2)
    }

    fn segment_segment(a0: &V, a1: &V, b0: &V, b1: &V, d2: &Int) -> bool {
        let (u, v, r) = (sub(a1, a0), sub(b1, b0), sub(b0, a0));
        let m = cross(&u, &v);
        let mm = dot(&m, &m);
        if !mm.is_zero() {
            let s = dot(&cross(&r, &v), &m);
            let t = dot(&cross(&r, &u), &m);
            let zero = Int::zero();
            if s >= zero && s <= mm && t >= zero && t <= mm {
                let h = dot(&r, &m);
                return &h * &h <= d2 * &mm;
            }
        }
        point_segment(a0, b0, b1, d2)
            || point_segment(a1, b0, b1, d2)
            || point_segment(b0, a0, a1, d2)
            || point_segment(b1, a0, a1, d2)
    }

    /// Are the primitives within `d` at `t = 0`, exactly?
    pub(super) fn within_at_start(kind: Kind, pts: &Points, d: f64) -> bool {
        let parts: Vec<(i64, i32)> = pts
            .iter()
            .flat_map(|p| p[0])
            .chain([d])
            .map(decompose)
            .collect();
        let emin = parts
            .iter()
            .filter(|(m, _)| *m != 0)
            .map(|&(_, e)| e)
            .min()
            .unwrap_or(0);
        let int = |(m, e): (i64, i32)| Int::from(m) << (e - emin) as usize;
        let pt = |i: usize| -> V { std::array::from_fn(|k| int(parts[3 * i + k])) };
        let p = [pt(0), pt(1), pt(2), pt(3)];
        let di = int(parts[12]);
        let d2 = &di * &di;
        match kind {
            Kind::VertexFace => point_triangle(&p[0], &p[1], &p[2], &p[3], &d2),
            Kind::EdgeEdge => segment_segment(&p[0], &p[1], &p[2], &p[3], &d2),
        }
    }
}
