//! The band test of step 5 ([`super::Cell::meets_triangle`] and the exact test behind it)
//! four triangle pairs at once, for the pairs whose answer floating point certifies: the
//! common case within a band (epsilon > 0), where a box-overlapping pair is most often
//! clearly apart or clearly inside the other's viewing volume.
//!
//! A triangle `t` meets the right prism of half depth `h` over a triangle `a` exactly when
//! `Q`, the part of `t` inside the slab `|w| <= h` (`w` the height above `a`'s plane), seen
//! from above, meets `a`: the prism is `a` times `[-h, h]`. Both are convex polygons of
//! `a`'s plane, so they meet unless one of their edges' normals separates them (the
//! separating axis theorem in 2D): `a`'s three, `t`'s three projected edges', and, where
//! the slab cuts `t`, the normal of the cut lines (the 2D part of `t`'s normal). `Q` is
//! the convex hull of `t`'s corners inside the slab and of the points where `t`'s edges
//! cross `w = +-h` (no clipping loop: nine candidate points, each valid or not).
//!
//! Certification: every quantity is computed in `f64` in a frame at `a`'s first corner, so
//! its error is a few ulps of `R`, the local magnitude (`R >= h`, every coordinate, the
//! edges from `a`'s first corner; every other edge is within `2 R`). A lane is decided
//! only when the corners' places against the slab are certain by `1e-6 R` (then the
//! crossing points are within `~1e-10 R` of the exact ones) and every axis's answer is
//! certain by `1e-7 R^2` (`R^3` for the cut normal, which is a product of two edges): far
//! above those errors and the errors of the axes themselves. The reference must be well
//! shaped ([`shaped`]: its height over its longest edge more than `1e-3` of that edge, so
//! no angle is below about `1e-3` radian): the scalar volume of a degenerate triangle is
//! another shape, and the scalar clipping against a needle's volume is itself unstable
//! near the tip (its two long sides' planes nearly coincide: Sutherland-Hodgman can keep a
//! sliver `1e-7 R` outside), so those pairs are left to the scalar test, which decides
//! them the same way on every backend. Undecided lanes go to the scalar test: a decided
//! lane is at least `~1e-7 R` from the volume's boundary, where the scalar path's rounding
//! cannot change its answer.

use crate::geom::lanes::{Float, Mask, TriLanes, F, LANES, M, W};

/// Margin of a corner's place against the slab, relative to `R`.
const TOL_W: f64 = 1e-6;
/// Margin of an axis's answer, relative to `R^2` (its values' scale: an edge times a
/// coordinate).
const TOL_AXIS: f64 = 1e-7;

/// A 2D point per lane, in `a`'s frame.
#[derive(Clone, Copy)]
struct P2 {
    x: F,
    y: F,
}

impl P2 {
    /// The projection on axis `(kx, ky)` (not normalized).
    #[inline(always)]
    fn along(&self, kx: F, ky: F) -> F {
        kx * self.x + ky * self.y
    }
}

/// `|x| + |y| + |z|`: a bound on every coordinate of `w` in any orthonormal frame.
#[inline(always)]
fn l1(w: &W) -> F {
    w.x.abs() + w.y.abs() + w.z.abs()
}

/// Lanes whose triangle is well shaped: twice its area over its longest edge squared more
/// than `1e-3` (`|e x f|^2 > 1e-6 l^2` with `l` the longest edge's squared length). Zero
/// and NaN fail.
#[inline(always)]
fn shaped(t: &[W; 3]) -> M {
    let (e, f) = (t[1].sub(&t[0]), t[2].sub(&t[0]));
    shaped_by(t, &e, &f, e.cross(&f).norm_squared())
}

/// [`shaped`] given `t`'s edges `e = t1 - t0`, `f = t2 - t0` and `|e x f|^2`, when the
/// caller has them already.
#[inline(always)]
fn shaped_by(t: &[W; 3], e: &W, f: &W, nn: F) -> M {
    let l = e
        .norm_squared()
        .max(f.norm_squared())
        .max(t[2].sub(&t[1]).norm_squared());
    nn.gt(l * l * l.like(1e-6))
}

/// The separating-axis answer along `(kx, ky)`: (certainly separated, certainly
/// overlapping), for the points `q` against `a`'s corners `c`, with margin `m`.
#[inline(always)]
fn axis<const N: usize>(kx: F, ky: F, q: &[P2; N], c: &[P2; 3], m: F) -> (M, M) {
    let (c0, c1, c2) = (c[0].along(kx, ky), c[1].along(kx, ky), c[2].along(kx, ky));
    let (alo, ahi) = (c0.min(c1).min(c2), c0.max(c1).max(c2));
    let mut lo = q[0].along(kx, ky);
    let mut hi = lo;
    for p in &q[1..] {
        let v = p.along(kx, ky);
        lo = lo.min(v);
        hi = hi.max(v);
    }
    let apart = hi.lt(alo - m).or(lo.gt(ahi + m));
    let overlap = hi.gt(alo + m).and(lo.lt(ahi - m));
    (apart, overlap)
}

/// Triangle `t` seen from triangle `a`'s frame (origin `a0`, `u` along `a`'s first edge,
/// `n` its unit normal, `v = n x u`): what both tests start from.
struct Seen {
    /// `a` is far enough from a segment for its frame to be trusted.
    ok: M,
    /// The local magnitude.
    r: F,
    /// `a`'s corners, `(0, 0)`, `(|e|, 0)` and `f`'s coordinates.
    corners: [P2; 3],
    /// `t`'s corners.
    xs: [F; 3],
    ys: [F; 3],
    ws: [F; 3],
    /// Each of `t`'s corners certainly inside the slab, above it, below it.
    inside: [M; 3],
    above: [M; 3],
    below: [M; 3],
    /// All three corners certainly above, or all certainly below.
    empty: M,
}

impl Seen {
    #[inline(always)]
    fn of(a: &[W; 3], t: &[W; 3], h: F) -> Seen {
        let e = a[1].sub(&a[0]);
        let f = a[2].sub(&a[0]);
        let nv = e.cross(&f);
        let (nn, ee) = (nv.norm_squared(), e.norm_squared());
        let ok = shaped_by(a, &e, &f, nn);
        let n = nv.scale(h.like(1.0) / nn.sqrt());
        let ex = ee.sqrt();
        let u = e.scale(h.like(1.0) / ex);
        let v = n.cross(&u);
        let zero = h.like(0.0);
        let corners = [
            P2 { x: zero, y: zero },
            P2 { x: ex, y: zero },
            P2 {
                x: f.dot(&u),
                y: f.dot(&v),
            },
        ];
        let p = [t[0].sub(&a[0]), t[1].sub(&a[0]), t[2].sub(&a[0])];
        let r = l1(&e)
            .max(l1(&f))
            .max(l1(&p[0]))
            .max(l1(&p[1]))
            .max(l1(&p[2]))
            .max(h);
        let ws = [p[0].dot(&n), p[1].dot(&n), p[2].dot(&n)];
        let mw = r * h.like(TOL_W);
        let (lo, hi) = (h - mw, h + mw);
        let above = [ws[0].gt(hi), ws[1].gt(hi), ws[2].gt(hi)];
        let below = [ws[0].lt(-hi), ws[1].lt(-hi), ws[2].lt(-hi)];
        Seen {
            ok,
            r,
            corners,
            xs: [p[0].dot(&u), p[1].dot(&u), p[2].dot(&u)],
            ys: [p[0].dot(&v), p[1].dot(&v), p[2].dot(&v)],
            ws,
            inside: [ws[0].abs().lt(lo), ws[1].abs().lt(lo), ws[2].abs().lt(lo)],
            above,
            below,
            empty: above[0]
                .and(above[1])
                .and(above[2])
                .or(below[0].and(below[1]).and(below[2])),
        }
    }

    /// The margin of an axis made of two edges' coordinates.
    #[inline(always)]
    fn margin(&self) -> F {
        self.r * self.r * self.r.like(TOL_AXIS)
    }

    /// `a`'s edges' (inward or outward) normals.
    #[inline(always)]
    fn edge_axes(&self) -> [(F, F); 3] {
        let (ex, fx, fy) = (self.corners[1].x, self.corners[2].x, self.corners[2].y);
        [(fy.like(0.0), ex), (-fy, fx - ex), (fy, -fx)]
    }

    /// `t`'s corners beyond one of the prism's planes, all of them, and by more than `h`
    /// for a side plane when `BY_H` (certainly: with the margins). Without, `t` misses the
    /// prism (the cheap first test); with, `t` is farther than `h` from `a` (the
    /// caps' test, `empty`, already says so: `|w| > h`), so neither triangle meets the
    /// other's volume (every point of a volume lies within `h` of its triangle) and one
    /// `Seen` answers for both ways round, `t` being well shaped too (the caller's check:
    /// see the module documentation).
    #[inline(always)]
    fn corners_beyond<const BY_H: bool>(&self, h: F) -> M {
        let m = self.margin();
        let (xs, ys) = (self.xs, self.ys);
        let t = [
            P2 { x: xs[0], y: ys[0] },
            P2 { x: xs[1], y: ys[1] },
            P2 { x: xs[2], y: ys[2] },
        ];
        let mut beyond = self.empty;
        for (kx, ky) in self.edge_axes() {
            // Beyond by `h` along the unit axis: by `h |k|` along `k`.
            let reach = if BY_H {
                h * (kx * kx + ky * ky).sqrt() + m
            } else {
                m
            };
            let (c0, c1, c2) = (
                self.corners[0].along(kx, ky),
                self.corners[1].along(kx, ky),
                self.corners[2].along(kx, ky),
            );
            let (alo, ahi) = (c0.min(c1).min(c2), c0.max(c1).max(c2));
            let (v0, v1, v2) = (t[0].along(kx, ky), t[1].along(kx, ky), t[2].along(kx, ky));
            let (tlo, thi) = (v0.min(v1).min(v2), v0.max(v1).max(v2));
            beyond = beyond.or(thi.lt(alo - reach).or(tlo.gt(ahi + reach)));
        }
        self.ok.and(beyond)
    }
}

/// Per lane: (certainly meets, certainly misses) for triangle `t` against the prism of
/// half depth `h` over triangle `a`.
#[inline(always)]
fn prism(a: &[W; 3], t: &[W; 3], h: F) -> (M, M) {
    let s = Seen::of(a, t, h);
    let (xs, ys, ws) = (s.xs, s.ys, s.ws);
    let (inside, above, below) = (s.inside, s.above, s.below);
    let mut certain = s.ok;
    for k in 0..3 {
        certain = certain.and(inside[k].or(above[k]).or(below[k]));
    }
    let cut = inside[0].and(inside[1]).and(inside[2]).not();
    // Q's candidate points: the corners inside, the crossings of each edge with w = h
    // and w = -h (where its ends are on either side); an invalid one is replaced by a
    // valid one (any: they only widen nothing), so every min and max runs over nine.
    let mut q = [s.corners[0]; 9];
    let mut valid = [inside[0]; 9];
    for k in 0..3 {
        q[k] = P2 { x: xs[k], y: ys[k] };
        valid[k] = inside[k];
        let j = (k + 1) % 3;
        let (dx, dy, dw) = (xs[j] - xs[k], ys[j] - ys[k], ws[j] - ws[k]);
        let inv = h.like(1.0) / dw;
        for (i, level, side) in [(0, h, above), (1, -h, below)] {
            let t = (level - ws[k]) * inv;
            q[3 + 2 * k + i] = P2 {
                x: xs[k] + dx * t,
                y: ys[k] + dy * t,
            };
            valid[3 + 2 * k + i] = side[k].xor(side[j]);
        }
    }
    let mut any = q[0];
    for i in 1..9 {
        any = P2 {
            x: valid[i].sel(q[i].x, any.x),
            y: valid[i].sel(q[i].y, any.y),
        };
    }
    for i in 0..9 {
        q[i] = P2 {
            x: valid[i].sel(q[i].x, any.x),
            y: valid[i].sel(q[i].y, any.y),
        };
    }
    let m = s.margin();
    // a's edges' normals, then t's projected edges', then the cut lines'.
    let mut apart = s.empty;
    let mut overlap = certain.and(s.empty.not());
    for (kx, ky) in s.edge_axes() {
        let (sep, o) = axis(kx, ky, &q, &s.corners, m);
        apart = apart.or(certain.and(sep));
        overlap = overlap.and(o);
    }
    for k in 0..3 {
        let j = (k + 1) % 3;
        let (sep, o) = axis(ys[k] - ys[j], xs[j] - xs[k], &q, &s.corners, m);
        apart = apart.or(certain.and(sep));
        overlap = overlap.and(o);
    }
    let d1 = W {
        x: xs[1] - xs[0],
        y: ys[1] - ys[0],
        z: ws[1] - ws[0],
    };
    let d2 = W {
        x: xs[2] - xs[0],
        y: ys[2] - ys[0],
        z: ws[2] - ws[0],
    };
    let nt = d1.cross(&d2);
    let (sep, o) = axis(nt.x, nt.y, &q, &s.corners, m * s.r);
    apart = apart.or(certain.and(sep));
    overlap = overlap.and(o.or(cut.not()));
    (overlap, s.ok.and(apart))
}

/// The cheap first test of [`band`]: the lanes whose pair is certainly apart, as a lane
/// bit mask: `b`'s corners beyond one plane of `a`'s volume; when `both`, farther than `h`
/// from `a` (then `a` misses `b`'s volume too; `b` well shaped).
///
/// # Safety
/// The CPU has AVX2 and FMA.
#[target_feature(enable = "avx2,fma")]
pub(crate) unsafe fn band_far(a: &TriLanes, b: &TriLanes, h: f64, both: bool) -> u32 {
    // SAFETY: the caller's promise.
    let (ta, tb, h) = unsafe { (a.load(), b.load(), F::splat(h)) };
    let seen = Seen::of(&ta, &tb, h);
    if both {
        seen.corners_beyond::<true>(h).and(shaped(&tb)).bits()
    } else {
        seen.corners_beyond::<false>(h).bits()
    }
}

/// Step 5's band test of four pairs: lane `l` asks whether `b[l]` meets the viewing volume
/// of half depth `h` of `a[l]` or intersects `a[l]` (the scalar `Prepared::meets` with
/// `a`'s volumes) and, when `both`, also whether `a[l]` meets `b[l]`'s volume. Returns
/// (decided, meets) as lane bit masks, as `tritri::four::intersect` does: undecided lanes
/// need the scalar test.
///
/// # Safety
/// The CPU has AVX2 and FMA.
#[target_feature(enable = "avx2,fma")]
pub(crate) unsafe fn band(a: &TriLanes, b: &TriLanes, h: f64, both: bool) -> (u32, u32) {
    // SAFETY: the caller's promise.
    let (ta, tb, h) = unsafe { (a.load(), b.load(), F::splat(h)) };
    // A triangle meeting `a` meets `a`'s volume (`a` lies in it): "misses the volume"
    // certifies the exact test's answer too.
    let (meets, misses) = prism(&ta, &tb, h);
    if !both {
        return (meets.or(misses).bits(), meets.bits());
    }
    if meets.bits() == (1 << LANES) - 1 {
        // All four meet one way round (common among deeply crossing bodies): no need to
        // look the other way.
        return (meets.bits(), meets.bits());
    }
    let (meets2, misses2) = prism(&tb, &ta, h);
    let meets = meets.or(meets2);
    (meets.or(misses.and(misses2)).bits(), meets.bits())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::polygon::Prepared;
    use crate::geom::predicates::P3;
    use crate::geom::test_rng::Rng;

    /// The scalar test the lanes stand for: `b` meets `a`'s volumes or `a` (and, when
    /// `both`, `a` meets `b`'s).
    fn scalar(a: &[P3; 3], b: &[P3; 3], h: f64, both: bool) -> bool {
        let (pa, pb) = (Prepared::of([*a; 2], 1), Prepared::of([*b; 2], 1));
        pa.meets(&pb, Some(&pa.cells(h))) || both && pb.meets(&pa, Some(&pb.cells(h)))
    }

    /// A triangle of the kind `kind` near the origin, size about 1: random; nearly flat
    /// (z within `0.05`, as the facing sides of two bodies kept a small gap apart); on a
    /// coarse grid (shared corners, coplanar and flat triangles, corners exactly `h` off).
    fn triangle(rng: &mut Rng, kind: usize, z: f64) -> [P3; 3] {
        let mut p = || match kind {
            0 => [rng.f(), rng.f(), rng.f()],
            1 => [rng.f(), rng.f(), z + rng.f() * 0.05],
            _ => [0, 1, 2].map(|_| (rng.below(5) as f64 - 2.0) * 0.25),
        };
        [p(), p(), p()]
    }

    /// A triangle folded onto `a` or away from it by 1e-3..1e-7 radian about `a`'s first
    /// edge (sharing that edge), or, one time in three, sharing only `a`'s first corner:
    /// the cases whose points lie on the volume's boundary.
    fn fold(rng: &mut Rng, a: &[P3; 3]) -> [P3; 3] {
        let sub = |p: &P3, q: &P3| [p[0] - q[0], p[1] - q[1], p[2] - q[2]];
        let (e, f) = (sub(&a[1], &a[0]), sub(&a[2], &a[0]));
        let n = [
            e[1] * f[2] - e[2] * f[1],
            e[2] * f[0] - e[0] * f[2],
            e[0] * f[1] - e[1] * f[0],
        ];
        let nl = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt().max(1e-300);
        let ee = (e[0] * e[0] + e[1] * e[1] + e[2] * e[2]).max(1e-300);
        let k = (f[0] * e[0] + f[1] * e[1] + f[2] * e[2]) / ee;
        let side = [f[0] - k * e[0], f[1] - k * e[1], f[2] - k * e[2]];
        let angle =
            10f64.powi(-3 - rng.below(5) as i32) * if rng.below(2) == 0 { 1.0 } else { -1.0 };
        // Onto `a` (the apex's side) or away from it.
        let s = if rng.below(2) == 0 { 1.0 } else { -1.0 } * rng.range(0.2, 1.2);
        let along = rng.unit();
        let p: P3 = std::array::from_fn(|c| {
            a[0][c] + e[c] * along + side[c] * s * angle.cos() + n[c] / nl * s.abs() * angle.sin()
        });
        if rng.below(3) == 0 {
            let q: P3 = std::array::from_fn(|c| p[c] + e[c] * 0.3 + n[c] / nl * 1e-3);
            [a[0], p, q]
        } else {
            [a[0], a[1], p]
        }
    }

    /// A needle: a right angle at the first corner, whose first edge is 1e-4..1e-10 of the
    /// second (the scalar volume's two long sides nearly coincide beyond the tip).
    fn needle(rng: &mut Rng) -> [P3; 3] {
        let o = [rng.f(), rng.f(), rng.f()];
        let d = rng.dir();
        let k = if d[0].abs() < 0.9 {
            [1.0, 0.0, 0.0]
        } else {
            [0.0, 1.0, 0.0]
        };
        let c = [
            d[1] * k[2] - d[2] * k[1],
            d[2] * k[0] - d[0] * k[2],
            d[0] * k[1] - d[1] * k[0],
        ];
        let short = 10f64.powi(-4 - rng.below(7) as i32);
        let long = rng.range(0.5, 1.0);
        [
            o,
            std::array::from_fn(|i| o[i] + c[i] * short),
            std::array::from_fn(|i| o[i] + d[i] * long),
        ]
    }

    /// A pair found by review: a needle reference (1e-10 edge next to a right angle) and a
    /// triangle just past its tip, where the scalar clipping keeps a sliver and the exact
    /// answer is "misses": never decided in the lanes, either way round.
    #[test]
    fn needle_references_are_left_to_the_scalar_test() {
        if !(std::is_x86_feature_detected!("avx2") && std::is_x86_feature_detected!("fma")) {
            return;
        }
        let (a, b, eps) = crate::geom::volume::NEEDLE_PAST_TIP;
        let h = f64::from(eps) / 2.0;
        for both in [false, true] {
            for (x, y) in [(a, b), (b, a)] {
                // SAFETY: AVX2 and FMA checked above.
                let (d, m) = unsafe {
                    band(
                        &TriLanes::of(&[x; LANES]),
                        &TriLanes::of(&[y; LANES]),
                        h,
                        both,
                    )
                };
                let want = scalar(&x, &y, h, both);
                assert!(
                    d == 0 || (m != 0) == want,
                    "both {both}: {d:b} {m:b}, scalar {want}"
                );
            }
            // SAFETY: as above.
            let far = unsafe {
                band_far(
                    &TriLanes::of(&[b; LANES]),
                    &TriLanes::of(&[a; LANES]),
                    h,
                    both,
                )
            };
            assert!(far == 0 || !scalar(&b, &a, h, both));
        }
    }

    /// Decided lanes answer as the scalar test, one way and both ways round, on random
    /// pairs, nearly parallel pairs a fraction of `h` apart, grid pairs with exact ties,
    /// folds (a shared edge or corner, 1e-3..1e-7 radian, or moved about `h` apart),
    /// needles (a 1e-4..1e-10 edge at a right angle) against triangles near their tips,
    /// degenerate triangles (segments, points), at offsets up to 1e5 and scales 1e-4 to
    /// 1e4; most random and nearly parallel pairs are decided in the lanes.
    #[test]
    fn four_lanes_decide_as_the_scalar_test() {
        if !(std::is_x86_feature_detected!("avx2") && std::is_x86_feature_detected!("fma")) {
            return;
        }
        let mut rng = Rng(0xBA2D_5EED_u64);
        let (mut decided, mut total, mut meets) = ([0usize; 5], [0usize; 5], [0usize; 5]);
        let mut far_count = [0usize; 5];
        for i in 0..50_000 {
            let kind = i % 5;
            let off = [0.0, 1e3, 1e5][i / 5 % 3];
            let scale = [1.0, 1e-4, 1e4][i / 15 % 3];
            let both = i / 45 % 2 == 0;
            let h = if kind == 2 {
                0.25 * scale
            } else {
                rng.range(0.002, 0.2) * scale
            };
            let mut pairs = [[[[0.0; 3]; 3]; 2]; LANES];
            let mut flat = [false; LANES];
            for (pair, flat) in pairs.iter_mut().zip(&mut flat) {
                let gap = rng.range(-0.5, 2.5) * h / scale;
                let mut pair_first = [[0.0; 3]; 3];
                for (s, t) in pair.iter_mut().enumerate() {
                    *t = match (kind, s) {
                        (4, 0) => needle(&mut rng),
                        (4, _) => {
                            // Near the needle's tip or along it.
                            let c = pair_first[2];
                            let mut p = || std::array::from_fn(|k| c[k] + rng.f() * 0.5);
                            [p(), p(), p()]
                        }
                        (3, 1) => {
                            let t = fold(&mut rng, &pair_first);
                            // One time in three moved off `a` by about `h` (a near miss or
                            // a near hit across a gap) along a random direction.
                            if rng.below(3) == 0 {
                                let d = rng.dir();
                                let g = rng.range(0.5, 2.0) * h / scale;
                                t.map(|p| std::array::from_fn(|c| p[c] + d[c] * g))
                            } else {
                                t
                            }
                        }
                        (3, _) => triangle(&mut rng, 0, 0.0),
                        _ => triangle(&mut rng, kind, s as f64 * gap),
                    };
                    pair_first = *t;
                    if rng.below(16) == 0 {
                        t[2] = t[rng.below(2)]; // a segment or, now and then, a point
                        *flat = true;
                    }
                    *t = t.map(|p| p.map(|x| (off + x * scale) as f32 as f64));
                }
            }
            let (a, b) = (pairs.map(|p| p[0]), pairs.map(|p| p[1]));
            let (la, lb) = (TriLanes::of(&a), TriLanes::of(&b));
            // SAFETY: AVX2 and FMA checked above.
            let (d, m) = unsafe { band(&la, &lb, h, both) };
            // SAFETY: as above.
            let far = unsafe { band_far(&la, &lb, h, both) };
            // Counted where f32 keeps the triangles' shapes (not size 1e-4 at 1e3 or 1e5),
            // without the segments and points (never decided as references).
            let counted = off * 1e-5 < scale;
            for l in 0..LANES {
                let want = scalar(&a[l], &b[l], h, both);
                if counted && !flat[l] {
                    total[kind] += 1;
                    meets[kind] += usize::from(want);
                    decided[kind] += usize::from(d & (1 << l) != 0);
                }
                if d & (1 << l) != 0 {
                    assert_eq!(
                        m & (1 << l) != 0,
                        want,
                        "h {h} both {both}: {:?} {:?}",
                        a[l],
                        b[l]
                    );
                } else {
                    assert_eq!(m & (1 << l), 0);
                }
                // The first stage only drops pairs the whole test finds apart.
                if far & (1 << l) != 0 {
                    assert!(!want, "far: h {h} both {both}: {:?} {:?}", a[l], b[l]);
                    far_count[kind] += usize::from(counted);
                }
            }
        }
        println!(
            "decided in the lanes (random, nearly parallel, grid, folds, needles): {decided:?} of \
             {total:?}; meet {meets:?}; far at the first stage {far_count:?}"
        );
        for k in 0..2 {
            assert!(decided[k] * 100 > total[k] * 98, "{decided:?} of {total:?}");
            assert!(meets[k] * 10 > total[k] && meets[k] * 10 < total[k] * 9);
            assert!(far_count[k] * 10 > total[k]);
        }
    }
}
