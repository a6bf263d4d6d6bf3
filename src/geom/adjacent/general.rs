//! The general rule for a triangle pair (rule 1 by the fans around a shared position,
//! rule 2 by the merged intervals, two proper triangles in one plane by a separating edge
//! line), and the exact tests it is built on: a triangle's shape, containment, the
//! coordinate plane to project on.

use super::joint::{hull_on_line, Joint, Tri};
use crate::geom::predicates::{collinear, drop_axis, orient2d, orient3d, P3};
use crate::geom::tritri::triangles_intersect;

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
pub(super) fn projection_axis(a: &P3, b: &P3, c: &P3) -> Option<usize> {
    let first = normal_axis_guess(a, b, c);
    [first, (first + 1) % 3, (first + 2) % 3]
        .into_iter()
        .find(|&ax| orient2d(drop_axis(a, ax), drop_axis(b, ax), drop_axis(c, ax)) != 0.0)
}

/// The axis of the largest component of the floating-point normal of `(a, b, c)`: a guess
/// at the coordinate plane it projects onto best (exact predicates decide).
#[inline]
pub(super) fn normal_axis_guess(a: &P3, b: &P3, c: &P3) -> usize {
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
pub(super) fn general(t: &Tri, u: &Tri, joint: &Joint) -> bool {
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
