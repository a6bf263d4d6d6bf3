//! Four crossing triangle pairs at once: the fast path of [`super::contact_geometry`]
//! (two triangles crossing transversally) written with AVX2 vectors of four `f64`, one
//! lane per pair, so that one instruction serves four pairs.
//!
//! It is only for pairs **known to intersect** (the pairs of a query at epsilon 0, each
//! decided by the exact test, or those the four-lane exact test `tritri::four` certifies),
//! which lets it skip the exact test itself. A lane is answered here only when the scalar
//! fast path would take none of its rare branches: every vertex's side of the other plane
//! certified by the filter (no vertex on the other plane), cuts that overlap, no edge along
//! the other's plane in the separating-axis search, and a finite unit result. (Cut ends
//! that need the accurate distances get them here too.) Every other lane is left to
//! [`super::contact_geometry`] by the caller.
//!
//! The operations are the scalar fast path's, in the same order on the same values
//! (`minpd`/`maxpd` are its `min`/`max`, the only fused multiply-adds its explicit
//! `mul_add`s), and the winning axis is chosen by the same rule (the least key; among
//! equal keys the first in the scalar path's order), so a lane answered here is bit for
//! bit the scalar answer (the tests compare them on random and real pairs). Choices that
//! follow a lane's data (which vertex is alone on its side, which edge pairs are facets)
//! are blends, as the scalar path's are table lookups.
//!
//! Written with the AVX2 lanes of `geom/lanes.rs` (no closures: see there why).

use std::mem::MaybeUninit;

use super::cut::{FACE_SLACK, REFINE};
use super::ContactGeometry;
use crate::geom::lanes::{sel3, sel3w, store2, transpose, transpose2, Float, Mask, Plane, F, M, W};

/// Pairs per pass.
pub(super) use crate::geom::lanes::LANES;

/// The scalar path's `min_max` of three values.
#[inline(always)]
fn min_max(d: &[F; 3]) -> (F, F) {
    let le = d[0].le(d[1]);
    let (lo, hi) = (le.sel(d[0], d[1]), le.sel(d[1], d[0]));
    (d[2].lt(lo).sel(d[2], lo), d[2].gt(hi).sel(d[2], hi))
}

/// `a + b` as the rounded sum and its exact error (the scalar `two_sum`).
#[inline(always)]
fn two_sum(a: F, b: F) -> (F, F) {
    let s = a + b;
    let bb = s - a;
    (s, (a - (s - bb)) + (b - bb))
}

/// `a b` as the rounded product and its exact error (the scalar `two_prod`).
#[inline(always)]
fn two_prod(a: F, b: F) -> (F, F) {
    let p = a * b;
    (p, a.mul_add(b, -p))
}

/// `a b - c d` as an unevaluated sum (the scalar `distance_accurately`'s steps).
#[inline(always)]
fn diff_of_products(a: F, b: F, c: F, d: F) -> (F, F) {
    let (p1, e1) = two_prod(a, b);
    let (p2, e2) = two_prod(c, d);
    let (nh, e3) = two_sum(p1, -p2);
    (nh, e3 + (e1 - e2))
}

/// A triangle's plane, as the scalar path's `Face`.
type Face = Plane;

/// What the contact kernel asks of a plane.
impl Plane {
    /// The points' signed distances (times `|n|`), the scales of their rounding errors,
    /// and the lanes where every side is certain and not all are the same (the triangle
    /// crosses the plane).
    #[inline(always)]
    fn sides(&self, p: &[W; 3]) -> ([F; 3], [F; 3], M) {
        let zero = self.o.x.like(0.0);
        let ((d0, s0, c0), (d1, s1, c1), (d2, s2, c2)) =
            (self.side(&p[0]), self.side(&p[1]), self.side(&p[2]));
        let (u0, u1, u2) = (d0.gt(zero), d1.gt(zero), d2.gt(zero));
        let mixed = u0.xor(u1).or(u1.xor(u2));
        ([d0, d1, d2], [s0, s1, s2], c0.and(c1).and(c2).and(mixed))
    }

    /// One point's distance, its error's scale, and whether its sign is certain. (No
    /// closures in this module: one is compiled as its own function, without AVX2, and
    /// then every intrinsic in it is a call.)
    #[inline(always)]
    fn side(&self, p: &W) -> (F, F, M) {
        let (d, scale) = self.distance(p);
        (d, scale, d.abs().gt(self.o.x.like(FACE_SLACK) * scale))
    }
}

/// The scalar `Face::distance_accurately`, operation for operation: the signed distance
/// of `p` to the plane of `t` (times `|n|`) from the differences with their rounding
/// errors (error-free transformations, terms of second order in `eps` kept).
#[inline(always)]
fn distance_accurately(t: &[W; 3], p: &W) -> F {
    let (e, el) = diff(&t[1], &t[0]);
    let (f, fl) = diff(&t[2], &t[0]);
    let (w, wl) = diff(p, &t[0]);
    let mut hi = w.x.like(0.0);
    let mut lo = w.x.like(0.0);
    for ((a, al), (b, bl), (c, cl), (d, dl), (x, xl)) in [
        (
            (e.y, el.y),
            (f.z, fl.z),
            (e.z, el.z),
            (f.y, fl.y),
            (w.x, wl.x),
        ),
        (
            (e.z, el.z),
            (f.x, fl.x),
            (e.x, el.x),
            (f.z, fl.z),
            (w.y, wl.y),
        ),
        (
            (e.x, el.x),
            (f.y, fl.y),
            (e.y, el.y),
            (f.x, fl.x),
            (w.z, wl.z),
        ),
    ] {
        let (nh, n0) = diff_of_products(a, b, c, d);
        let nl = n0 + (((a * bl + al * b) - (c * dl + cl * d)) + (al * bl - cl * dl));
        let (t, tl) = two_prod(nh, x);
        let (s, e4) = two_sum(hi, t);
        hi = s;
        lo = lo + (((e4 + tl) + nl * x) + (nh * xl + nl * xl));
    }
    hi + lo
}

/// `a - b` as the rounded difference and its exact error, per component.
#[inline(always)]
fn diff(a: &W, b: &W) -> (W, W) {
    let (x, y, z) = (two_sum(a.x, -b.x), two_sum(a.y, -b.y), two_sum(a.z, -b.z));
    (
        W {
            x: x.0,
            y: y.0,
            z: z.0,
        },
        W {
            x: x.1,
            y: y.1,
            z: z.1,
        },
    )
}

/// A triangle's plane with its normal as the scalar `Face::of` makes it
/// (`triangle_normal`, operation for operation): each component `a b - c d` by Kahan's
/// method, within 1.5 ulps however much the products cancel, plus the first-order part of
/// the edges' rounding (a sliver's plane is right to about the ulp).
#[inline(always)]
fn face(t: &[W; 3]) -> Face {
    let mut p = Plane::of(t);
    let (e, f) = (&p.e, &p.f);
    let n = W {
        x: kahan(e.y, f.z, e.z, f.y),
        y: kahan(e.z, f.x, e.x, f.z),
        z: kahan(e.x, f.y, e.y, f.x),
    };
    // What the edges' rounding left out, to first order, in the lanes where it left out
    // anything (the scalar `triangle_normal`; none for f32 positions, the common case).
    let (el, fl) = (lost(&t[1], &t[0]), lost(&t[2], &t[0]));
    let zero = n.x.like(0.0);
    // (No closures here: see the module's note.)
    let exact = (el.x.eq(zero).and(el.y.eq(zero)).and(el.z.eq(zero)))
        .and(fl.x.eq(zero).and(fl.y.eq(zero)).and(fl.z.eq(zero)));
    p.n = if exact.bits() == 0b1111 {
        n
    } else {
        let c = W {
            x: n.x + ((e.y * fl.z + el.y * f.z) - (e.z * fl.y + el.z * f.y)),
            y: n.y + ((e.z * fl.x + el.z * f.x) - (e.x * fl.z + el.x * f.z)),
            z: n.z + ((e.x * fl.y + el.x * f.y) - (e.y * fl.x + el.y * f.x)),
        };
        exact.selw(&n, &c)
    };
    p
}

/// The rounding error of `a - b`, per component (the scalar `two_sum(a, -b).1`).
#[inline(always)]
fn lost(a: &W, b: &W) -> W {
    W {
        x: two_sum(a.x, -b.x).1,
        y: two_sum(a.y, -b.y).1,
        z: two_sum(a.z, -b.z).1,
    }
}

/// `a b - c d` by Kahan's method (the scalar `kahan`).
#[inline(always)]
fn kahan(a: F, b: F, c: F, d: F) -> F {
    let w = c * d;
    let err = (-c).mul_add(d, w);
    a.mul_add(b, -w) + err
}

/// The vertex alone on its side of three signs as two masks (`m0`: vertex 0, `m1`:
/// vertex 1, neither: vertex 2), as the scalar `LONELY[pattern(d)]` when the signs are
/// mixed.
#[inline(always)]
fn lonely(d: &[F; 3]) -> (M, M) {
    let zero = d[0].like(0.0);
    let (p0, p1, p2) = (d[0].gt(zero), d[1].gt(zero), d[2].gt(zero));
    let m0 = p1.xor(p2).not();
    let m1 = m0.not().and(p0.xor(p2).not());
    (m0, m1)
}

/// Distance `x` of `v` to the plane of `t` evaluated accurately in the lanes of `shaky`
/// (where of the same sign: the exact one).
#[inline(always)]
fn accurate(t: &[W; 3], v: &W, x: F, shaky: M) -> F {
    let zero = x.like(0.0);
    let y = distance_accurately(t, v);
    let same = y.gt(zero).xor(x.gt(zero)).not();
    let finite = y.abs().lt(zero.like(f64::INFINITY));
    shaky.and(same).and(y.eq(zero).not()).and(finite).sel(y, x)
}

/// The cut of triangle `v` by `plane` (`d`: its vertices' distances to it, all non-zero,
/// not all of one sign), as the scalar `Cutting::cut`: where rounding could move an end
/// too far, from the distances evaluated accurately (keeping the exact signs), as the
/// scalar `Cutting::cut_accurately`.
#[inline(always)]
fn cut(v: &[W; 3], d: &[F; 3], s: &[F; 3], mag: F, plane: &[W; 3]) -> (W, W) {
    let (m0, m1) = lonely(d);
    let vk = sel3w(m0, m1, &v[0], &v[1], &v[2]);
    let vi = sel3w(m0, m1, &v[1], &v[2], &v[0]);
    let vj = sel3w(m0, m1, &v[2], &v[0], &v[1]);
    let mut dk = sel3(m0, m1, d[0], d[1], d[2]);
    let dvi = sel3(m0, m1, d[1], d[2], d[0]);
    let dvj = sel3(m0, m1, d[2], d[0], d[1]);
    let sk = sel3(m0, m1, s[0], s[1], s[2]);
    let si = sel3(m0, m1, s[1], s[2], s[0]);
    let sj = sel3(m0, m1, s[2], s[0], s[1]);
    let (ei, ej) = (vi.sub(&vk), vj.sub(&vk));
    let (mut di, mut dj) = (dk - dvi, dk - dvj);
    let limit = mag.like(REFINE) * mag;
    let two_half = mag.like(2.5);
    let shaky_i = (two_half * (sk + si) * ei.amax()).gt(limit * di.abs());
    let shaky_j = (two_half * (sk + sj) * ej.amax()).gt(limit * dj.abs());
    let shaky = shaky_i.or(shaky_j);
    if shaky.bits() != 0 {
        // Rare on real meshes (a few pairs in a thousand): the accurate distances, used
        // where shaky and of the same sign.
        let fine = [
            accurate(plane, &v[0], d[0], shaky),
            accurate(plane, &v[1], d[1], shaky),
            accurate(plane, &v[2], d[2], shaky),
        ];
        dk = sel3(m0, m1, fine[0], fine[1], fine[2]);
        di = dk - sel3(m0, m1, fine[1], fine[2], fine[0]);
        dj = dk - sel3(m0, m1, fine[2], fine[0], fine[1]);
    }
    let (zero, one) = (mag.like(0.0), mag.like(1.0));
    // The scalar `max(0.0, min(r, 1.0))`.
    let ti = zero.max((dk / di).min(one));
    let tj = zero.max((dk / dj).min(one));
    (vk.add_scaled(&ei, ti), vk.add_scaled(&ej, tj))
}

/// The best separating axis so far in each lane: the least key, the first offered among
/// equal keys (offers come in the scalar path's order).
struct Best {
    key: F,
    c: W,
    s: F,
    dir: F,
    den: F,
}

impl Best {
    /// Axis `n` (squared length `den`), moving `a` by `sn` along `dn * n`; only in the
    /// lanes of `facet`.
    #[inline(always)]
    fn offer(&mut self, n: &W, sn: F, dn: F, den: F, facet: M) {
        let inf = sn.like(f64::INFINITY);
        let valid = den.gt(sn.like(0.0)).and(facet);
        let k = valid.sel(sn * sn.abs() / den, inf);
        let take = k.lt(self.key);
        self.key = take.sel(k, self.key);
        self.c = take.selw(n, &self.c);
        self.s = take.sel(sn, self.s);
        self.dir = take.sel(dn, self.dir);
        self.den = take.sel(den, self.den);
    }
}

/// The edge pairs of the separating-axis search, counted from the lone signs: `a`'s
/// vertices from `ib` on (`ib`, the next, the previous: the scalar `ib, i1, i2`), `b`'s and
/// `a3` from `ja` on. (An edge is the difference of two of these vertices, as `edges`
/// makes it: the same value, and twelve fewer vectors to keep.)
struct Sat {
    va: [W; 3],
    vb: [W; 3],
    a3: [F; 3],
    /// Lanes where the lone signs differ: five facets (else four).
    five: M,
}

impl Sat {
    #[inline(always)]
    fn new(ta: &[W; 3], tb: &[W; 3], a3: &[F; 3], b3: &[F; 3]) -> Sat {
        let (i0, i1) = lonely(b3);
        let (j0, j1) = lonely(a3);
        let a3 = [
            sel3(j0, j1, a3[0], a3[1], a3[2]),
            sel3(j0, j1, a3[1], a3[2], a3[0]),
            sel3(j0, j1, a3[2], a3[0], a3[1]),
        ];
        let zero = a3[0].like(0.0);
        let b3_lone = sel3(i0, i1, b3[0], b3[1], b3[2]);
        Sat {
            va: turn((i0, i1), ta),
            vb: turn((j0, j1), tb),
            a3,
            five: a3[0].gt(zero).xor(b3_lone.gt(zero)),
        }
    }

    /// The facet of relative edges `five_at` where there are five facets, `four_at` where
    /// four (constants: a choice between them is a blend), in the lanes of `facet`.
    #[inline(always)]
    fn offer(&self, best: &mut Best, five_at: (usize, usize), four_at: (usize, usize), facet: M) {
        let ((i5, j5), (i4, j4)) = (five_at, four_at);
        let va = pick(self.five, &self.va, i5, i4);
        let ea = pick(self.five, &self.va, (i5 + 1) % 3, (i4 + 1) % 3).sub(&va);
        let vb = pick(self.five, &self.vb, j5, j4);
        let eb = pick(self.five, &self.vb, (j5 + 1) % 3, (j4 + 1) % 3).sub(&vb);
        let a3 = if j5 == j4 {
            self.a3[j5]
        } else {
            self.five.sel(self.a3[j5], self.a3[j4])
        };
        let c = ea.cross(&eb);
        let dn = a3.sign_one();
        let sn = dn * c.dot(&vb.sub(&va));
        best.offer(&c, sn, dn, c.norm_squared(), facet);
    }
}

/// `v` from the vertex that [`lonely`]'s masks name on: that one, the next, the previous.
/// (Functions, not closures, in this module: see [`Plane::side`].)
#[inline(always)]
fn turn((m0, m1): (M, M), v: &[W; 3]) -> [W; 3] {
    [
        sel3w(m0, m1, &v[0], &v[1], &v[2]),
        sel3w(m0, m1, &v[1], &v[2], &v[0]),
        sel3w(m0, m1, &v[2], &v[0], &v[1]),
    ]
}

/// `x[k5]` in the lanes of `five`, `x[k4]` in the others (constant indices: one blend, or
/// none when they are the same).
#[inline(always)]
fn pick(five: M, x: &[W; 3], k5: usize, k4: usize) -> W {
    if k5 == k4 {
        x[k5]
    } else {
        five.selw(&x[k5], &x[k4])
    }
}

/// Edges `v_{k+1} - v_k`.
#[inline(always)]
fn edges(v: &[W; 3]) -> [W; 3] {
    [v[1].sub(&v[0]), v[2].sub(&v[1]), v[0].sub(&v[2])]
}

/// Lanes where the three are non-zero and not all of one sign.
#[inline(always)]
fn fine(x: &[F; 3]) -> M {
    let zero = x[0].like(0.0);
    let nonzero = x[0].eq(zero).or(x[1].eq(zero)).or(x[2].eq(zero)).not();
    let (u0, u1, u2) = (x[0].gt(zero), x[1].gt(zero), x[2].gt(zero));
    nonzero.and(u0.xor(u1).or(u1.xor(u2)))
}

/// Geometry of four triangle pairs `(ta, tb)` (lane `l` the pair `l`), each known to
/// intersect (exactly). Returns the lanes answered here (bit `l` for lane `l`: the scalar
/// fast path's answer), and writes those among `want` into `out[at[l]]`; the other lanes
/// are left to [`super::contact_geometry`].
///
/// # Safety
/// The CPU has AVX2 and FMA (the caller is compiled for them, or checked); `at[l]` is in
/// `out` for every lane of `want`.
#[inline(always)]
pub(super) unsafe fn crossing(
    ta: &[W; 3],
    tb: &[W; 3],
    want: u32,
    at: &[usize; LANES],
    out: &mut [MaybeUninit<ContactGeometry>],
) -> u32 {
    let zero = ta[0].x.like(0.0);
    let fa = face(ta);
    let (db, scale_b, ok_b) = fa.sides(tb);
    let fb = face(tb);
    let (da, scale_a, ok_a) = fb.sides(ta);
    // The pair's magnitude, to within its extent (as the scalar path).
    let mag = ta[0].amax().max(tb[0].amax());
    let (a0, a1) = cut(ta, &da, &scale_a, mag, tb);
    let (b0, b1) = cut(tb, &db, &scale_b, mag, ta);
    // The overlap of the two cuts on the planes' common line (the scalar `transverse`:
    // ordered along the longer cut).
    let (da_, db_) = (a1.sub(&a0), b1.sub(&b0));
    let line = da_.norm_squared().ge(db_.norm_squared()).selw(&da_, &db_);
    let (ka0, ka1, kb0, kb1) = (line.dot(&a0), line.dot(&a1), line.dot(&b0), line.dot(&b1));
    let (ca, cb) = (ka0.le(ka1), kb0.le(kb1));
    let (la, ha) = (ca.selw(&a0, &a1), ca.selw(&a1, &a0));
    let (lb, hb) = (cb.selw(&b0, &b1), cb.selw(&b1, &b0));
    // (Only compared: the choice between equal values does not matter.)
    let (kla, kha) = (ka0.min(ka1), ka0.max(ka1));
    let (klb, khb) = (kb0.min(kb1), kb0.max(kb1));
    let lo = kla.ge(klb).selw(&la, &lb);
    let hi = kha.le(khb).selw(&ha, &hb);
    let half = zero.like(0.5);
    let mid = W {
        x: (lo.x + hi.x) * half,
        y: (lo.y + hi.y) * half,
        z: (lo.z + hi.z) * half,
    };
    let apart = kla.max(klb).gt(kha.min(khb));
    let (p, q) = (apart.selw(&mid, &lo), apart.selw(&mid, &hi));

    // The separating-axis search (the scalar `triangles_sat`): edges `e_k = v_{k+1} -
    // v_k`; `a3_j = -eb_j . na`, `b3_i = ea_i . nb`; the edge pair (i, j) is a facet of
    // the Minkowski difference when b3_i and a3_j differ in sign.
    let (ea, eb) = (edges(ta), edges(tb));
    let a3 = [-eb[0].dot(&fa.n), -eb[1].dot(&fa.n), -eb[2].dot(&fa.n)];
    let b3 = [ea[0].dot(&fb.n), ea[1].dot(&fb.n), ea[2].dot(&fb.n)];
    let (fine_a, fine_b) = (fine(&a3), fine(&b3));
    // Counted from the lone signs, `ib` of b3 and `ja` of a3 (as the scalar path does),
    // the facets are the same relative pairs in every lane: four or five of them.
    let sides = Sat::new(ta, tb, &a3, &b3);

    // The two faces: on na, a at 0 and b at db; on nb, b at 0 and a at da.
    let mut best = Best {
        key: zero.like(f64::INFINITY),
        c: W {
            x: zero,
            y: zero,
            z: zero,
        },
        s: zero,
        dir: zero,
        den: zero,
    };
    let (one, minus_one) = (zero.like(1.0), zero.like(-1.0));
    let all = zero.eq(zero);
    let (bmin, bmax) = min_max(&db);
    let (up, down) = (bmax - zero, zero - bmin);
    let dir = up.le(down).sel(one, minus_one);
    let den = fa.n.norm_squared();
    best.offer(&fa.n, up.min(down), dir, den, all);
    let (amin, amax) = min_max(&da);
    let (up, down) = (zero - amin, amax - zero);
    let dir = up.le(down).sel(one, minus_one);
    let den = fb.n.norm_squared();
    best.offer(&fb.n, up.min(down), dir, den, all);
    // The facets in the scalar path's order (its `pairs`), by relative (i, j): where the
    // lone signs agree (i, j) = (0, 1), (0, 2), (1, 0), (2, 0); where they differ (0, 0),
    // (1, 1), (1, 2), (2, 1), (2, 2). Offered in that order and taken only when strictly
    // better, as the scalar `take_min`: among equal keys the first wins.
    sides.offer(&mut best, (0, 0), (0, 1), all);
    sides.offer(&mut best, (1, 1), (0, 2), all);
    sides.offer(&mut best, (1, 2), (1, 0), all);
    sides.offer(&mut best, (2, 1), (2, 0), all);
    sides.offer(&mut best, (2, 2), (2, 2), sides.five);
    // The result (the scalar `Axis::result`), then `finish`'s guard.
    let len = best.den.sqrt();
    let depth = (best.s / len).max(zero);
    let normal = best.c.scale(best.dir / len);
    let n2 = normal.norm_squared();
    // A lane whose cuts come out apart (a touch within rounding, or, were a caller wrong
    // about the pair, no intersection at all) goes to the scalar path, which decides
    // exactly: so a pair that does not intersect is never answered here unless its cuts
    // overlap by less than their rounding.
    // A lane with a value that is not finite goes to the scalar path too (coordinates are
    // within the f32 range: the sum overflows only where a term is not finite).
    let sum = p.x + p.y + p.z + q.x + q.y + q.z + normal.x + normal.y + normal.z + depth;
    let finite = sum.abs().lt(zero.like(f64::INFINITY));
    let ok = ok_a
        .and(ok_b)
        .and(apart.not())
        .and(fine_a)
        .and(fine_b)
        .and(best.key.lt(zero.like(f64::INFINITY)))
        .and(len.gt(zero))
        .and((n2 - one).abs().lt(zero.like(1e-12)))
        .and(finite)
        .bits();
    // Each answered lane's ten values, transposed into the lane's entry (`ContactGeometry`
    // is `repr(C)`: point_a, point_b, normal, depth, contiguous), four at a time. (`+ 0`:
    // the scalar path's `finish` adds its origin, 0, which makes -0 into +0.)
    let first = transpose([p.x + zero, p.y + zero, p.z + zero, q.x + zero]);
    let second = transpose([q.y + zero, q.z + zero, normal.x, normal.y]);
    let last = transpose2(normal.z, depth);
    let write = ok & want;
    for l in 0..LANES {
        if write & (1 << l) != 0 {
            let g: *mut ContactGeometry = out[at[l]].as_mut_ptr();
            // SAFETY: `g` is an entry (perhaps not initialized: every field is written,
            // none read); its first ten fields are f64 in order (checked at compile time
            // next to the type).
            unsafe {
                let v = g.cast::<f64>();
                first[l].store(v);
                second[l].store(v.add(4));
                store2(v.add(8), last[l]);
                (*g).intersecting = true;
                (*g).coplanar = false;
            }
        }
    }
    ok
}
