//! The penetration depth and normal of an intersecting pair by the separating-axis
//! theorem: the best axis so far ([`Axis`], which the fast path's search over two
//! triangles' facets in `crossing.rs` fills too) and the general path's search over every
//! candidate axis of the polygons' hulls.

use super::poly::Poly;
use super::V;

/// Separating-axis penetration of the polygons' convex hulls: the smallest translation of
/// `a`, as (unit normal, depth >= 0); `None` if every axis is zero.
pub(super) fn sat(pa: &Poly, pb: &Poly) -> Option<(V, f64)> {
    let (va, vb) = (pa.verts(), pb.verts());
    let mut best = Axis::default();
    // A triangle's only facet normal is its own.
    if pa.nt == 1 && pa.nv == 3 {
        best.offer(&pa.tris[0].n, va, vb);
    } else {
        for_triples(va, |c| best.offer(&c, va, vb));
    }
    if pb.nt == 1 && pb.nv == 3 {
        best.offer(&pb.tris[0].n, va, vb);
    } else {
        for_triples(vb, |c| best.offer(&c, va, vb));
    }
    for_pairs(va, |e| for_pairs(vb, |f| best.offer(&e.cross(&f), va, vb)));
    best.result()
}

/// The best axis so far: moving `a` by `s / |c|` along `dir * c`, ranked by
/// `key = s |s| / |c|^2` (the signed square of that distance; no root per axis).
pub(super) struct Axis {
    pub(super) c: V,
    pub(super) s: f64,
    pub(super) dir: f64,
    pub(super) key: f64,
}

impl Default for Axis {
    fn default() -> Self {
        Axis {
            c: V::zeros(),
            s: 0.0,
            dir: 1.0,
            key: f64::INFINITY,
        }
    }
}

impl Axis {
    /// (unit normal, depth >= 0), if some axis was non-zero.
    #[inline(always)]
    pub(super) fn result(&self) -> Option<(V, f64)> {
        let len = self.c.norm();
        (self.key.is_finite() && len > 0.0).then(|| {
            let depth = (self.s / len).max(0.0);
            (self.c * (self.dir / len), depth)
        })
    }

    #[inline]
    fn offer(&mut self, c: &V, va: &[V], vb: &[V]) {
        // (offer_intervals skips a zero axis.)
        self.offer_intervals(c, interval(va, c), interval(vb, c));
    }

    /// Axis `c` on which `a` projects to `[amin, amax]` and `b` to `[bmin, bmax]`.
    #[inline(always)]
    pub(super) fn offer_intervals(
        &mut self,
        c: &V,
        (amin, amax): (f64, f64),
        (bmin, bmax): (f64, f64),
    ) {
        let cc = c.norm_squared();
        if cc.is_nan() || cc <= 0.0 {
            return;
        }
        // Moving a along +c by (bmax - amin), or along -c by (amax - bmin).
        let up = bmax - amin;
        let down = amax - bmin;
        let (s, dir) = if up <= down { (up, 1.0) } else { (down, -1.0) };
        // s |s| / cc < key without a division per axis (both sides are of degree 6 in
        // the coordinates: within f64's range for f32 inputs).
        if s * s.abs() < self.key * cc {
            *self = Axis {
                c: *c,
                s,
                dir,
                key: s * s.abs() / cc,
            };
        }
    }
}

/// The projection interval of points on `c`.
#[inline]
fn interval(v: &[V], c: &V) -> (f64, f64) {
    let x = c.dot(&v[0]);
    let (mut lo, mut hi) = (x, x);
    for p in &v[1..] {
        let x = c.dot(p);
        if x < lo {
            lo = x;
        }
        if x > hi {
            hi = x;
        }
    }
    (lo, hi)
}

/// The normal of every vertex triple (the hull's facets are among them).
#[inline]
fn for_triples(v: &[V], mut f: impl FnMut(V)) {
    for i in 0..v.len() {
        for j in i + 1..v.len() {
            for k in j + 1..v.len() {
                f((v[j] - v[i]).cross(&(v[k] - v[i])));
            }
        }
    }
}

/// The direction of every vertex pair (the hull's edges are among them).
#[inline]
fn for_pairs(v: &[V], mut f: impl FnMut(V)) {
    for i in 0..v.len() {
        for j in i + 1..v.len() {
            f(v[j] - v[i]);
        }
    }
}
