//! Where a continuous contact happens: the impact geometry of a primitive pair at its time
//! of impact (what `GlcolImpactGeometry` reports: barycentric weights of the contact point on
//! each feature, and a unit normal from b towards a).
//!
//! Everything is computed in double at the given `toi`, on the positions
//! `p(toi) = p0 + toi (p1 - p0)`, after an exact power-of-two scaling of the query (its
//! largest coordinate magnitude brought into `[1, 2)`: no overflow or underflow, and a
//! query scaled by `2^k` gets bit-identical answers). The thresholds below are in those
//! scaled units, i.e. relative to the query's largest coordinate.
//!
//! * **Weights**: the closest points of the two features at `toi` (point-triangle with its
//!   barycentric weights; segment-segment, parallel and degenerate segments included), the
//!   least distance over the candidates (the interior solution and every boundary one), so
//!   a badly conditioned interior solution never wins over a better boundary one. Every
//!   weight is a multiple of `2^-53` in `[0, 1]` and each feature's weights sum to exactly 1.
//!   A vertex uses 1 weight (`[1, 0, 0]`), an edge 2 (`[1 - s, s, 0]`), a triangle 3; the
//!   caller repeats the last used vertex index for the unused weights (which are 0). The
//!   interior solutions are computed in an orthonormal frame and refined
//!   ([`least_squares`]), so slivers and nearly parallel edges keep their accuracy: the
//!   tests find `|point_a - point_b|` (exact, for the weights given) within about `eps S`
//!   of the exact least distance (`S` the largest coordinate), and within `2^-19 M` of 0
//!   at a time of impact of the primitives (`M` the largest vertex motion: the contract).
//! * **Normal** (unit, never NaN), the first of [`NormalFrom`] that applies:
//!   1. [`NormalFrom::Features`]: the features' normal `e1 x e2` (the triangle's
//!      `(f1 - f0) x (f2 - f0)`; the edges' `(a1 - a0) x (b1 - b0)`), from the positions at
//!      `toi` enclosed in interval arithmetic, when its direction is certain to `2^-26`. It
//!      is turned towards a's side: the certified sign of `det(e1, e2, w)` (`w = v - f0`,
//!      or `a0 - b0`) at `toi`, else at earlier times back to 0 (`toi - 2^-40 16^k`, then
//!      0: the first certain nonzero sign, so "just before toi"), else from the relative
//!      motion of the contact points (a approaches b's plane from the side the normal
//!      points to: `n . v_rel < 0`), else (coplanar throughout, motion within the plane) as
//!      the features are given (`e1 x e2` itself).
//!   2. [`NormalFrom::ClosestPoints`]: the feature normal being degenerate (a triangle that
//!      is a segment or a point, parallel edges, an edge that is a point, or a direction
//!      not certain), the difference of the closest points at `toi`, from b's to a's, when
//!      longer than `2^-40`.
//!   3. [`NormalFrom::Motion`]: minus the relative velocity of the contact points
//!      (`-(v_a - v_b)`, the weights held), when longer than `2^-40`.
//!   4. [`NormalFrom::Start`]: the difference of the closest points at `t = 0` (recomputed
//!      there), when longer than `2^-40`.
//!   5. [`NormalFrom::LastResort`]: `[0, 0, 1]` (the features coincide and do not move
//!      relative to each other: a pair that already meets at the start, standing still).

use super::filter::Iv;
use super::Points;
use crate::geom::P3;

/// Where an [`ImpactPoint`]'s normal came from: the first of these that applies, in this
/// order (see the module's notes).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum NormalFrom {
    /// The features' own normal (the triangle's, or the edges' cross product), turned to the
    /// side a is on just before `toi`.
    Features,
    /// The closest points' difference at `toi` (the features' normal is degenerate).
    ClosestPoints,
    /// Minus the relative velocity of the contact points (the closest points coincide).
    Motion,
    /// The closest points' difference at the start of the step.
    Start,
    /// `[0, 0, 1]`: nothing gives a direction.
    LastResort,
}

/// The impact geometry of a primitive pair at a time of impact.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ImpactPoint {
    /// Barycentric weights of the contact point on a's feature, at `toi`: a vertex
    /// `[1, 0, 0]`, an edge `[w0, w1, 0]`, a triangle `[w0, w1, w2]`; each a multiple of
    /// `2^-53` in `[0, 1]`, the sum exactly 1. `point_a = sum w[k] p_k(toi)`.
    pub weights_a: [f64; 3],
    /// The same on b's feature.
    pub weights_b: [f64; 3],
    /// Unit, at `toi`, from b towards a.
    pub normal: P3,
    /// Which rule gave the normal.
    pub normal_from: NormalFrom,
}

/// The impact geometry of the moving vertex `v` (a; `[start, end]`) and the moving triangle
/// `f` (b; `[its three corners at the start, at the end]`) at `toi` in `[0, 1]` (as
/// [`vertex_face`] gives it): the vertex's weights `[1, 0, 0]`, the triangle's closest
/// point's, and the triangle's normal turned towards the vertex (the module's rules).
/// Coordinates must be finite.
pub fn vertex_face_impact(v: [P3; 2], f: [[P3; 3]; 2], toi: f64) -> ImpactPoint {
    impact(Pair::VertexFace, &super::vertex_face_points(v, f), toi)
}

/// The impact geometry of the moving edges `a` and `b` (each `[its two ends at the start,
/// at the end]`) at `toi` in `[0, 1]` (as [`edge_edge`] gives it): the weights of their
/// closest points (`[1 - s, s, 0]`, `[1 - t, t, 0]`), and their common normal from b towards
/// a (the module's rules). Coordinates must be finite.
pub fn edge_edge_impact(a: [[P3; 2]; 2], b: [[P3; 2]; 2], toi: f64) -> ImpactPoint {
    impact(Pair::EdgeEdge, &super::edge_edge_points(a, b), toi)
}

/// Which primitives: the points are `v, f0, f1, f2` or `a0, a1, b0, b1`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Pair {
    VertexFace,
    EdgeEdge,
}

impl Pair {
    /// How many of the points are a's.
    fn split(self) -> usize {
        match self {
            Pair::VertexFace => 1,
            Pair::EdgeEdge => 2,
        }
    }

    /// The feature vectors `e1`, `e2` (their cross product is the normal) and `w` (from a
    /// point of b's plane or line to one of a's), as `(from, to)` point indices.
    fn vectors(self) -> [(usize, usize); 3] {
        match self {
            Pair::VertexFace => [(1, 2), (1, 3), (1, 0)],
            Pair::EdgeEdge => [(0, 1), (2, 3), (2, 0)],
        }
    }
}

/// Lengths below this (relative to the query's largest coordinate) give no direction.
const NOISE: f64 = 1.0 / (1u64 << 40) as f64;
/// The features' normal is used when its enclosure is this tight, relative to its length.
const NORMAL_WIDTH: f64 = 1.0 / (1u64 << 26) as f64;
/// `2^53`, the weights' quantum's inverse.
const TWO_53: f64 = (1u64 << 53) as f64;

fn impact(pair: Pair, pts: &Points, toi: f64) -> ImpactPoint {
    debug_assert!(pts.iter().flatten().flatten().all(|x| x.is_finite()));
    debug_assert!((0.0..=1.0).contains(&toi), "{toi}");
    let pts = scaled(pts);
    let x = pts.map(|p| at(p, toi));
    let (weights_a, weights_b) = closest(pair, &x);
    let (normal, normal_from) = normal(pair, &pts, &x, toi, &weights_a, &weights_b);
    ImpactPoint {
        weights_a,
        weights_b,
        normal,
        normal_from,
    }
}

/// `x 2^k`, exactly (unless the result is subnormal).
fn ldexp(mut x: f64, mut k: i32) -> f64 {
    while k > 1000 {
        x *= f64::powi(2.0, 1000);
        k -= 1000;
    }
    while k < -1000 {
        x *= f64::powi(2.0, -1000);
        k += 1000;
    }
    x * f64::powi(2.0, k)
}

/// The query scaled by the power of two that brings its largest coordinate magnitude into
/// `[1, 2)` (unchanged when every coordinate is 0).
fn scaled(pts: &Points) -> Points {
    let m = pts
        .iter()
        .flatten()
        .flatten()
        .fold(0.0f64, |m, x| m.max(x.abs()));
    if m == 0.0 || !m.is_finite() {
        return *pts;
    }
    // floor(log2 m), subnormals included.
    let e = if m < f64::MIN_POSITIVE {
        ((m * f64::powi(2.0, 64)).to_bits() >> 52) as i32 - 1023 - 64
    } else {
        (m.to_bits() >> 52) as i32 - 1023
    };
    pts.map(|p| p.map(|x| x.map(|c| ldexp(c, -e))))
}

/// The position at `t` (the end exactly at 1).
fn at(p: [P3; 2], t: f64) -> P3 {
    if t == 1.0 {
        p[1]
    } else {
        std::array::from_fn(|k| p[0][k] + t * (p[1][k] - p[0][k]))
    }
}

fn sub(a: P3, b: P3) -> P3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn dot(a: P3, b: P3) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// `sum w[k] p[k]` over the points given.
fn combine(w: &[f64; 3], p: &[P3]) -> P3 {
    std::array::from_fn(|c| p.iter().zip(w).map(|(p, w)| w * p[c]).sum())
}

/// `v / |v|`, `None` for a zero (or not finite) vector.
fn unit(v: P3) -> Option<P3> {
    let m = v.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    if !(m > 0.0 && m.is_finite()) {
        return None;
    }
    let u = v.map(|x| x / m);
    let l = dot(u, u).sqrt();
    Some(u.map(|x| x / l))
}

/// The Euclidean length, without overflow or underflow.
fn length(v: P3) -> f64 {
    let m = v.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    if m == 0.0 {
        return 0.0;
    }
    let u = v.map(|x| x / m);
    m * dot(u, u).sqrt()
}

/// `x` in `[0, 1]` rounded to a multiple of `2^-53` (exact arithmetic).
fn quantize(x: f64) -> f64 {
    (x.clamp(0.0, 1.0) * TWO_53).round() / TWO_53
}

/// The edge weights of the parameter `s` (a multiple of `2^-53` in `[0, 1]`): `[1 - s, s]`,
/// both exact.
fn edge_weights(s: f64) -> [f64; 2] {
    [1.0 - s, s]
}

/// Nonnegative triangle weights (not all 0) normalized: the two smaller ones quantized to
/// multiples of `2^-53` (each at most 1/2, so exact), the largest `1 -` their sum (exact),
/// so the three sum to exactly 1.
fn triangle_weights(w: [f64; 3]) -> [f64; 3] {
    let s = w[0] + w[1] + w[2];
    let w = w.map(|x| x / s);
    let k = if w[0] >= w[1] && w[0] >= w[2] {
        0
    } else if w[1] >= w[2] {
        1
    } else {
        2
    };
    let (i, j) = ((k + 1) % 3, (k + 2) % 3);
    let wi = quantize(w[i]);
    let mut wj = quantize(w[j]);
    if wi + wj >= 1.0 {
        // (Only by rounding: each is at most about 1/2.)
        wj = 1.0 - wi;
    }
    let mut out = [0.0; 3];
    out[i] = wi;
    out[j] = wj;
    out[k] = 1.0 - (wi + wj);
    out
}

/// The parameter (a multiple of `2^-53` in `[0, 1]`) of the point of the closed segment
/// `[a, b]` closest to `p` (0 for a point segment).
fn point_segment(p: P3, a: P3, b: P3) -> f64 {
    let ab = sub(b, a);
    let l2 = dot(ab, ab);
    if l2 > 0.0 {
        quantize(dot(sub(p, a), ab) / l2)
    } else {
        0.0
    }
}

/// The least squared distance to `p` over candidate weights, the first on ties.
struct Best<const N: usize> {
    w: [f64; N],
    d2: f64,
}

impl<const N: usize> Best<N> {
    fn consider(&mut self, w: [f64; N], d2: f64) {
        if d2 < self.d2 {
            *self = Best { w, d2 };
        }
    }
}

fn dist2(a: P3, b: P3) -> f64 {
    let d = sub(a, b);
    dot(d, d)
}

/// Refinement steps of the interior solutions on their residual.
const REFINE: usize = 2;

fn scale(a: P3, s: f64) -> P3 {
    a.map(|x| x * s)
}

/// The `(x, y)` that minimize `|r - x e1 - y e2|` (`None` when `e1`, `e2` are parallel to
/// the last bit). In an orthonormal frame of the longer vector `q1` and its complement
/// `q2` (Gram-Schmidt done twice, so `q2` is orthogonal to `q1` to rounding even for nearly
/// parallel vectors), the coordinate along `q2` gives one unknown and the one along `q1`
/// the other *from it*, so the solution's error, however ill-conditioned the unknowns
/// (`eps / sin` of the angle), stays in the direction where it does not move the point;
/// then refined on the residual.
fn least_squares(r: P3, e1: P3, e2: P3) -> Option<(f64, f64)> {
    let swap = dot(e2, e2) > dot(e1, e1);
    let (e1, e2) = if swap { (e2, e1) } else { (e1, e2) };
    let l1 = length(e1);
    if !(l1 > 0.0 && l1.is_finite()) {
        return None;
    }
    let q1 = scale(e1, 1.0 / l1);
    let c = dot(e2, q1);
    let f = sub(e2, scale(q1, c));
    let c2 = dot(f, q1);
    let f = sub(f, scale(q1, c2));
    let (c, h) = (c + c2, length(f));
    if !(h > 0.0 && h.is_finite()) {
        return None;
    }
    let q2 = scale(f, 1.0 / h);
    let (mut x, mut y) = (0.0, 0.0);
    let mut res = r;
    for _ in 0..=REFINE {
        let dy = dot(res, q2) / h;
        let dx = (dot(res, q1) - dy * c) / l1;
        if dx == 0.0 && dy == 0.0 {
            break;
        }
        (x, y) = (x + dx, y + dy);
        res = sub(sub(r, scale(e1, x)), scale(e2, y));
    }
    Some(if swap { (y, x) } else { (x, y) })
}

/// The weights of `p`'s projection onto the plane of the triangle `t` when it lies in the
/// closed triangle (`None` when outside or the triangle is degenerate), from
/// [`least_squares`] (accurate for slivers too).
fn projection_inside(p: P3, t: [P3; 3]) -> Option<[f64; 3]> {
    let (v, w) = least_squares(sub(p, t[0]), sub(t[1], t[0]), sub(t[2], t[0]))?;
    (v >= 0.0 && w >= 0.0 && v + w <= 1.0).then(|| triangle_weights([1.0 - v - w, v, w]))
}

/// Barycentric weights of the point of the closed triangle `t` closest to `p` (degenerate
/// triangles included): the projection onto its plane when it lies inside
/// ([`projection_inside`]), and the closest point of each edge; the nearest of these.
fn point_triangle(p: P3, t: [P3; 3]) -> [f64; 3] {
    let mut best = Best {
        w: [1.0, 0.0, 0.0],
        d2: f64::INFINITY,
    };
    if let Some(w) = projection_inside(p, t) {
        best.consider(w, dist2(p, combine(&w, &t)));
    }
    for (i, j) in [(0, 1), (1, 2), (2, 0)] {
        let [wi, wj] = edge_weights(point_segment(p, t[i], t[j]));
        let mut w = [0.0; 3];
        w[i] = wi;
        w[j] = wj;
        best.consider(w, dist2(p, combine(&w, &t)));
    }
    best.w
}

/// The parameters `(s, t)` of the closest points of the closed segments `[a0, a1]` and
/// `[b0, b1]` (parallel and point segments included): the lines' closest points when both
/// lie inside, and each end's closest point on the other segment; the nearest of these.
fn segment_segment(a0: P3, a1: P3, b0: P3, b1: P3) -> (f64, f64) {
    let mut best = Best {
        w: [0.0, 0.0],
        d2: f64::INFINITY,
    };
    let mut consider = |s: f64, t: f64| {
        let pa = combine(&[1.0 - s, s, 0.0], &[a0, a1]);
        let pb = combine(&[1.0 - t, t, 0.0], &[b0, b1]);
        best.consider([s, t], dist2(pa, pb));
    };
    // The lines' closest points: a0 + s d1 - (b0 + t d2) least.
    if let Some((s, t)) = least_squares(sub(b0, a0), sub(a1, a0), sub(b0, b1)) {
        if (0.0..=1.0).contains(&s) && (0.0..=1.0).contains(&t) {
            consider(quantize(s), quantize(t));
        }
    }
    consider(0.0, point_segment(a0, b0, b1));
    consider(1.0, point_segment(a1, b0, b1));
    consider(point_segment(b0, a0, a1), 0.0);
    consider(point_segment(b1, a0, a1), 1.0);
    (best.w[0], best.w[1])
}

/// The closest points' weights on a's and b's features, the points at one time.
fn closest(pair: Pair, x: &[P3; 4]) -> ([f64; 3], [f64; 3]) {
    match pair {
        Pair::VertexFace => ([1.0, 0.0, 0.0], point_triangle(x[0], [x[1], x[2], x[3]])),
        Pair::EdgeEdge => {
            let (s, t) = segment_segment(x[0], x[1], x[2], x[3]);
            let ([a0, a1], [b0, b1]) = (edge_weights(s), edge_weights(t));
            ([a0, a1, 0.0], [b0, b1, 0.0])
        }
    }
}

/// `point_a - point_b` for the weights, the points at one time.
fn difference(pair: Pair, x: &[P3; 4], wa: &[f64; 3], wb: &[f64; 3]) -> P3 {
    let s = pair.split();
    sub(combine(wa, &x[..s]), combine(wb, &x[s..]))
}

/// The enclosures of the points at `t` (exact at 0 and 1).
fn enclose(pts: &Points, t: f64) -> [[Iv; 3]; 4] {
    pts.map(|p| {
        std::array::from_fn(|k| {
            if t == 0.0 {
                Iv::point(p[0][k])
            } else if t == 1.0 {
                Iv::point(p[1][k])
            } else {
                let d = Iv::point(p[1][k]).sub(Iv::point(p[0][k]));
                Iv::point(p[0][k]).add(Iv::point(t).mul(d))
            }
        })
    })
}

/// The feature vectors `e1`, `e2`, `w` enclosed at one time.
fn vectors(pair: Pair, x: &[[Iv; 3]; 4]) -> [[Iv; 3]; 3] {
    pair.vectors()
        .map(|(i, j)| std::array::from_fn(|k| x[j][k].sub(x[i][k])))
}

fn cross_iv(a: &[Iv; 3], b: &[Iv; 3]) -> [Iv; 3] {
    std::array::from_fn(|r| {
        let (r1, r2) = ((r + 1) % 3, (r + 2) % 3);
        a[r1].mul(b[r2]).sub(a[r2].mul(b[r1]))
    })
}

/// The certain sign of `det(e1, e2, w) = (e1 x e2) . w` at `t`, if any.
fn side_at(pair: Pair, pts: &Points, t: f64) -> Option<i8> {
    let [e1, e2, w] = vectors(pair, &enclose(pts, t));
    let n = cross_iv(&e1, &e2);
    n[0].mul(w[0])
        .add(n[1].mul(w[1]))
        .add(n[2].mul(w[2]))
        .sign()
}

/// The side of b's plane (or of the plane through b's line parallel to a's) a is on just
/// before `toi`: the first certain nonzero sign at `toi`, `toi - 2^-40 16^k` (`k` up to 9),
/// 0.
fn side_before(pair: Pair, pts: &Points, toi: f64) -> Option<i8> {
    let mut t = toi;
    let mut back = NOISE;
    loop {
        if let Some(s) = side_at(pair, pts, t).filter(|&s| s != 0) {
            return Some(s);
        }
        if t == 0.0 {
            return None;
        }
        t = if back < 1.0 && toi - back > 0.0 {
            toi - back
        } else {
            0.0
        };
        back *= 16.0;
    }
}

/// The relative velocity of the contact points over the step (the weights held).
fn relative_velocity(pair: Pair, pts: &Points, wa: &[f64; 3], wb: &[f64; 3]) -> P3 {
    let v: [P3; 4] = pts.map(|p| sub(p[1], p[0]));
    difference(pair, &v, wa, wb)
}

/// The normal and its source (the module's rules), the points scaled, `x` at `toi`.
fn normal(
    pair: Pair,
    pts: &Points,
    x: &[P3; 4],
    toi: f64,
    wa: &[f64; 3],
    wb: &[f64; 3],
) -> (P3, NormalFrom) {
    let v_rel = relative_velocity(pair, pts, wa, wb);
    // 1. The features' normal, where its direction is certain.
    let [e1, e2, _] = vectors(pair, &enclose(pts, toi));
    let n = cross_iv(&e1, &e2);
    let mid = n.map(|c| 0.5 * c.lo + 0.5 * c.hi);
    let width = n.iter().fold(0.0f64, |m, c| m.max(c.hi - c.lo));
    if let Some(u) = unit(mid).filter(|_| width <= NORMAL_WIDTH * length(mid)) {
        let sign = side_before(pair, pts, toi).unwrap_or_else(|| {
            // Approaching along -n: a comes from the side n points to.
            if dot(u, v_rel) > NOISE {
                -1
            } else {
                1
            }
        });
        return (u.map(|c| f64::from(sign) * c), NormalFrom::Features);
    }
    // 2. The closest points' difference.
    let d = difference(pair, x, wa, wb);
    if length(d) > NOISE {
        if let Some(u) = unit(d) {
            return (u, NormalFrom::ClosestPoints);
        }
    }
    // 3. Minus the relative velocity.
    if length(v_rel) > NOISE {
        if let Some(u) = unit(v_rel.map(|c| -c)) {
            return (u, NormalFrom::Motion);
        }
    }
    // 4. The closest points' difference at the start.
    let x0 = pts.map(|p| p[0]);
    let (wa0, wb0) = closest(pair, &x0);
    let d0 = difference(pair, &x0, &wa0, &wb0);
    if length(d0) > NOISE {
        if let Some(u) = unit(d0) {
            return (u, NormalFrom::Start);
        }
    }
    // 5. Nothing gives a direction.
    ([0.0, 0.0, 1.0], NormalFrom::LastResort)
}
