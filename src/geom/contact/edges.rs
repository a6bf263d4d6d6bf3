//! The nine edge pairs of the closest-point search between two triangles
//! ([`super::band::closest_search`], what a pair within the band costs most), three at a
//! time: AVX2 lanes hold the second triangle's three edges (a fourth lane repeats the
//! first), and each of the first triangle's edges is set against them in one pass.
//!
//! The operations are [`super::band::segment_params`]'s and the points' after it, in the
//! same order on the same values (plain IEEE operations, no fused multiply-add; `clamp` as a
//! compare and a blend, so a NaN stays one), and its branches are blends of every case, so
//! each pair comes out bit for bit as the scalar code gives it (the tests compare them).

use super::band::EdgePair;
use super::poly::Tri;
use super::V;
use crate::geom::lanes::{Float, Mask, F, W};

/// `W` whose lanes are the vertices `v` (x, y, z).
///
/// # Safety
/// The CPU has AVX2 and FMA.
#[inline(always)]
unsafe fn lanes(v: [&V; 4]) -> W {
    // SAFETY: the caller's promise.
    unsafe {
        W {
            x: F::new([v[0].x, v[1].x, v[2].x, v[3].x]),
            y: F::new([v[0].y, v[1].y, v[2].y, v[3].y]),
            z: F::new([v[0].z, v[1].z, v[2].z, v[3].z]),
        }
    }
}

/// `f64::clamp(x, 0, 1)`: `x < 0` gives 0, then `x > 1` gives 1, a NaN stays.
#[inline(always)]
fn unit_clamp(x: F) -> F {
    let (zero, one) = (x.like(0.0), x.like(1.0));
    let x = x.lt(zero).sel(zero, x);
    x.gt(one).sel(one, x)
}

/// The nearest of the edge pairs of `t` and `u`, as `(i, j, pair)` for edge `i` of `t`
/// (`v[i]`-`v[i+1]`) and edge `j` of `u`: the first in the scalar search's order (`i`, then
/// `j`) among those of least `d2`. `None` when a `d2` is NaN (coordinates near the `f64`
/// range's end), where that order's rule cannot be kept lane by lane: the caller searches
/// one pair at a time.
///
/// # Safety
/// The CPU has AVX2 and FMA.
#[target_feature(enable = "avx2,fma")]
pub(super) unsafe fn nearest_edge_pair(t: &Tri, u: &Tri) -> Option<(usize, usize, EdgePair)> {
    let v = &u.v;
    // SAFETY: the caller's promise.
    let (q0, q1) = unsafe {
        (
            lanes([&v[0], &v[1], &v[2], &v[0]]),
            lanes([&v[1], &v[2], &v[0], &v[1]]),
        )
    };
    let d2 = q1.sub(&q0);
    let e = d2.norm_squared();
    let zero = e.like(0.0);
    let e_zero = e.eq(zero);
    // Lane j: the least d2 over t's edges so far and the first edge giving it.
    let mut best: Option<Pass> = None;
    let mut nan = zero.eq(zero).not();
    for i in 0..3 {
        let (p0, p1) = (t.v[i], t.v[(i + 1) % 3]);
        let d1v = p1 - p0;
        let a = d1v.norm_squared();
        // SAFETY: the caller's promise.
        let (p0l, d1) = unsafe { (lanes([&p0; 4]), lanes([&d1v; 4])) };
        let al = zero.like(a);
        let w = p0l.sub(&q0);
        let f = d2.dot(&w);
        let c = d1.dot(&w);
        let b = d1.dot(&d2);
        // Both edges of positive length.
        let denom = al * e - b * b;
        let s = denom
            .gt(zero)
            .sel(unit_clamp((b * f - c * e) / denom), zero);
        let r = (b * s + f) / e;
        let (below, above) = (r.lt(zero), r.gt(zero.like(1.0)));
        let s = below.sel(unit_clamp(-c / al), above.sel(unit_clamp((b - c) / al), s));
        let r = below.sel(zero, above.sel(zero.like(1.0), r));
        // The first edge a point (the second a point or not); else the second a point.
        let (s, r) = if a == 0.0 {
            (zero, e_zero.sel(zero, unit_clamp(f / e)))
        } else {
            (e_zero.sel(unit_clamp(-c / al), s), e_zero.sel(zero, r))
        };
        let p = p0l.add_scaled(&d1, s);
        let q = q0.add_scaled(&d2, r);
        let dist2 = p.sub(&q).norm_squared();
        nan = nan.or(dist2.eq(dist2).not());
        let pass = Pass {
            d2: dist2,
            i: zero.like(i as f64),
            p,
            q,
            s,
            r,
        };
        best = Some(match best {
            None => pass,
            Some(b) => {
                let take = pass.d2.lt(b.d2);
                Pass {
                    d2: take.sel(pass.d2, b.d2),
                    i: take.sel(pass.i, b.i),
                    p: take.selw(&pass.p, &b.p),
                    q: take.selw(&pass.q, &b.q),
                    s: take.sel(pass.s, b.s),
                    r: take.sel(pass.r, b.r),
                }
            }
        });
    }
    let b = best?;
    if nan.bits() & 0b111 != 0 {
        return None;
    }
    let mut x = [[0.0; 4]; 10];
    for (k, l) in [
        b.p.x, b.p.y, b.p.z, b.q.x, b.q.y, b.q.z, b.d2, b.s, b.r, b.i,
    ]
    .iter()
    .enumerate()
    {
        // SAFETY: `x[k]` holds four f64.
        unsafe { l.store(x[k].as_mut_ptr()) };
    }
    // Across the lanes (u's edges): the least d2, then the first edge of t, then of u.
    let mut j = 0;
    for k in 1..3 {
        if x[6][k] < x[6][j] || (x[6][k] == x[6][j] && x[9][k] < x[9][j]) {
            j = k;
        }
    }
    Some((
        x[9][j] as usize,
        j,
        EdgePair {
            p: V::new(x[0][j], x[1][j], x[2][j]),
            q: V::new(x[3][j], x[4][j], x[5][j]),
            d2: x[6][j],
            s: x[7][j],
            r: x[8][j],
        },
    ))
}

/// One pass of [`nearest_edge_pair`]: an edge of `t` against `u`'s three.
#[derive(Clone, Copy)]
struct Pass {
    d2: F,
    /// The edge of `t`, as a value.
    i: F,
    p: W,
    q: W,
    s: F,
    r: F,
}
