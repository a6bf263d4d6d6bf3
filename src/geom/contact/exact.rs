//! Error-free arithmetic: a sum and a product with their exact errors, positions'
//! differences with theirs, and the accurate crosses and triangle normals built on them.

use super::V;
use crate::geom::predicates::P3;

pub(super) use crate::geom::two_sum;

/// `a b` as the rounded product and its exact error (a fused multiply-add: one
/// instruction where the CPU has it, a correctly rounded library call elsewhere).
#[inline(always)]
pub(super) fn two_prod(a: f64, b: f64) -> (f64, f64) {
    let p = a * b;
    (p, a.mul_add(b, -p))
}

/// `a b - c d` by Kahan's method: within 1.5 ulps (see [`accurate_cross`]).
#[inline(always)]
fn kahan(a: f64, b: f64, c: f64, d: f64) -> f64 {
    let w = c * d;
    let err = (-c).mul_add(d, w);
    a.mul_add(b, -w) + err
}

/// `e x f` with each component `a b - c d` evaluated by Kahan's method (two fused
/// multiply-adds): within 1.5 ulps of its exact value, however much the two products
/// cancel. The plain cross is off by a few eps of `|e| |f|`, which on a sliver (`|n|` far
/// below `|e| |f|`) turns its plane by eps over its width and moves a distance to it by
/// that times the lever. (The differences of `f32` positions are exact, so the normal of
/// such a triangle is then right to the ulp.)
#[inline(always)]
fn accurate_cross(e: &V, f: &V) -> V {
    V::new(
        kahan(e.y, f.z, e.z, f.y),
        kahan(e.z, f.x, e.x, f.z),
        kahan(e.x, f.y, e.y, f.x),
    )
}

/// The normal `(t1 - t0) x (t2 - t0)` of the exact differences: [`accurate_cross`] of the
/// rounded ones plus, to first order, what their rounding left out (zero for `f32`
/// positions, whose differences are exact; for `f64` ones, a placed mesh's, the rounding
/// of an edge would turn a sliver's plane by eps over its width all the same).
#[inline(always)]
pub(super) fn triangle_normal(t: &[V; 3]) -> V {
    let (e, f) = (t[1] - t[0], t[2] - t[0]);
    let lost = |a: &V, b: &V| {
        V::new(
            two_sum(a.x, -b.x).1,
            two_sum(a.y, -b.y).1,
            two_sum(a.z, -b.z).1,
        )
    };
    let (el, fl) = (lost(&t[1], &t[0]), lost(&t[2], &t[0]));
    let n = accurate_cross(&e, &f);
    if el == V::zeros() && fl == V::zeros() {
        // Exact differences (f32 positions, the common case).
        return n;
    }
    V::new(
        n.x + ((e.y * fl.z + el.y * f.z) - (e.z * fl.y + el.z * f.y)),
        n.y + ((e.z * fl.x + el.z * f.x) - (e.x * fl.z + el.x * f.z)),
        n.z + ((e.x * fl.y + el.x * f.y) - (e.y * fl.x + el.y * f.x)),
    )
}

/// `a - b` as the rounded difference and its exact error (zero for `f32` positions).
#[inline(always)]
pub(super) fn exact_diff(a: &P3, b: &P3) -> (V, V) {
    let (x, y, z) = (
        two_sum(a[0], -b[0]),
        two_sum(a[1], -b[1]),
        two_sum(a[2], -b[2]),
    );
    (V::new(x.0, y.0, z.0), V::new(x.1, y.1, z.1))
}

/// The cross product of two vectors given as unevaluated sums `hi + lo` (the
/// [`exact_diff`] of positions), each component to within about an ulp: the products of
/// the high parts error-free, the terms of first order in the low parts added (those of
/// second order are below the result's ulp unless it cancels to that level). A vertex
/// 1e-17 from an edge's line crossed with the edge, say, where the plain cross of the
/// rounded differences would be all rounding.
#[inline(always)]
pub(super) fn cross_accurately((a, al): &(V, V), (b, bl): &(V, V)) -> V {
    let component =
        |(x, xl): (f64, f64), (y, yl): (f64, f64), (z, zl): (f64, f64), (w, wl): (f64, f64)| {
            // (x + xl)(y + yl) - (z + zl)(w + wl).
            let (p1, e1) = two_prod(x, y);
            let (p2, e2) = two_prod(z, w);
            let (h, e3) = two_sum(p1, -p2);
            h + ((e3 + (e1 - e2)) + ((x * yl + xl * y) - (z * wl + zl * w)))
        };
    V::new(
        component((a.y, al.y), (b.z, bl.z), (a.z, al.z), (b.y, bl.y)),
        component((a.z, al.z), (b.x, bl.x), (a.x, al.x), (b.z, bl.z)),
        component((a.x, al.x), (b.y, bl.y), (a.y, al.y), (b.x, bl.x)),
    )
}
