//! The exact triangle test of four pairs at once, for the pairs whose answer floating
//! point certifies: step 5's common case at epsilon 0 (two triangles of different bodies
//! in general position). A lane is decided only from signs that are certain: the planes'
//! filter of [`super::Plane::side`] (the same bound) rejects pairs with one triangle
//! strictly on one side of the other's plane; when all six signs are certain and mixed,
//! Guigue and Devillers' two orientations (after the same permutation of the vertices as
//! the scalar test, by blends) are evaluated with Shewchuk's static filter (the bound of
//! `predicates::orient3d_filtered`) and decide when it certifies their signs, or when an
//! orientation the filter leaves is exactly 0 because its four points share a coordinate
//! (the triangles then touch where their intervals meet). Every other lane (a vertex on or
//! near the other's plane, a flat triangle, an orientation within its error bound) is left
//! undecided, for the scalar exact test: so the answer is always the exact one, and the
//! same as [`super::triangles_intersect`]'s.
//!
//! The kernel's body ([`intersect_lanes`]) is written for any lane width ([`Float`]):
//! [`super::eight`] runs it on eight AVX-512 lanes, with the same operations in each lane,
//! so a pair gets the same answer (decided or not) at either width.

use super::PLANE_SLACK;
use crate::geom::lanes::{sel3w, Float, Mask, Plane, TriLanes, W};

/// What the exact test asks of a plane.
impl<T: Float> Plane<T> {
    /// Per point: (certainly `orient3d < 0`, certainly `orient3d > 0`), as
    /// [`super::Plane::side`] answers -1 and 1.
    #[inline(always)]
    fn certain_side(&self, p: &W<T>) -> (T::Mask, T::Mask) {
        let (s, scale) = self.distance(p);
        let bound = self.o.x.like(PLANE_SLACK) * scale;
        (s.gt(bound), s.lt(-bound))
    }
}

/// `orient3d(a, b, c, d)` where the static filter certifies its sign: (certainly
/// negative, certainly positive).
#[inline(always)]
fn orient3d<T: Float>(a: &W<T>, b: &W<T>, c: &W<T>, d: &W<T>) -> (T::Mask, T::Mask) {
    // (7 + 56 eps) eps, eps = 2^-53: Shewchuk's `o3derrboundA`, as in predicates.rs.
    const EPS: f64 = 0.000_000_000_000_000_111_022_302_462_515_65;
    const BOUND_A: f64 = (7.0 + 56.0 * EPS) * EPS;
    let (ad, bd, cd) = (a.sub(d), b.sub(d), c.sub(d));
    let (bdxcdy, cdxbdy) = (bd.x * cd.y, cd.x * bd.y);
    let (cdxady, adxcdy) = (cd.x * ad.y, ad.x * cd.y);
    let (adxbdy, bdxady) = (ad.x * bd.y, bd.x * ad.y);
    let det = ad.z * (bdxcdy - cdxbdy) + bd.z * (cdxady - adxcdy) + cd.z * (adxbdy - bdxady);
    let permanent = (bdxcdy.abs() + cdxbdy.abs()) * ad.z.abs()
        + (cdxady.abs() + adxcdy.abs()) * bd.z.abs()
        + (adxbdy.abs() + bdxady.abs()) * cd.z.abs();
    let err = det.like(BOUND_A) * permanent;
    (det.lt(-err), det.gt(err))
}

/// Where the four points have one coordinate in common (the four `x` equal, or the `y`, or
/// the `z`): there `orient3d(a, b, c, d)` is exactly 0 (a column of exact zeros in its
/// determinant), which the static filter cannot certify.
#[inline(always)]
fn in_one_coordinate_plane<T: Float>(a: &W<T>, b: &W<T>, c: &W<T>, d: &W<T>) -> T::Mask {
    let x = a.x.eq(d.x).and(b.x.eq(d.x)).and(c.x.eq(d.x));
    let y = a.y.eq(d.y).and(b.y.eq(d.y)).and(c.y.eq(d.y));
    let z = a.z.eq(d.z).and(b.z.eq(d.z)).and(c.z.eq(d.z));
    x.or(y).or(z)
}

/// The vertex alone on its side, from the three "positive" masks of mixed signs:
/// (vertex 0, vertex 1; neither: vertex 2).
#[inline(always)]
fn lonely<M: Mask>(p: [M; 3]) -> (M, M) {
    let m0 = p[1].xor(p[2]).not();
    let m1 = m0.not().and(p[0].xor(p[2]).not());
    (m0, m1)
}

/// Pair `l` is (lane `l` of `a`, lane `l` of `b`). Returns (decided, meets) as lane bit
/// masks: bit `l` of `decided` when lane `l`'s answer was certain here, bit `l` of `meets`
/// when, moreover, the closed triangles intersect. Undecided lanes need the scalar exact
/// test.
///
/// # Safety
/// The CPU has AVX2 and FMA.
#[target_feature(enable = "avx2,fma")]
pub(crate) unsafe fn intersect(a: &TriLanes, b: &TriLanes) -> (u32, u32) {
    // SAFETY: the caller's promise.
    let (ta, tb) = unsafe {
        (
            a.load::<crate::geom::lanes::F>(),
            b.load::<crate::geom::lanes::F>(),
        )
    };
    intersect_lanes(&ta, &tb)
}

/// [`intersect`] of triangles already in lanes (lane `l`: pair `l`), out of line.
///
/// # Safety
/// The CPU has AVX2 and FMA.
#[target_feature(enable = "avx2,fma")]
#[inline(never)]
pub(crate) unsafe fn intersect_loaded(ta: &[W; 3], tb: &[W; 3]) -> (u32, u32) {
    intersect_lanes(ta, tb)
}

/// [`intersect`]'s body, for any lane width (lane `l`: the pair of the triangles in lane
/// `l` of `ta` and `tb`).
#[inline(always)]
pub(super) fn intersect_lanes<T: Float>(ta: &[W<T>; 3], tb: &[W<T>; 3]) -> (u32, u32) {
    let all: u32 = (1 << T::LANES) - 1;
    // Signs of orient3d(a, b_k) and orient3d(b, a_k): (negative, positive) where certain.
    // Most box-overlapping pairs of two bodies are apart, most often with one triangle on
    // one side of the other's plane: a batch whose pairs all are returns at once.
    let pa = Plane::of(ta);
    let (bn0, bp0) = pa.certain_side(&tb[0]);
    let (bn1, bp1) = pa.certain_side(&tb[1]);
    let (bn2, bp2) = pa.certain_side(&tb[2]);
    let apart_b = bn0.and(bn1).and(bn2).or(bp0.and(bp1).and(bp2));
    if apart_b.bits() == all {
        return (all, 0);
    }
    let pb = Plane::of(tb);
    let (an0, ap0) = pb.certain_side(&ta[0]);
    let (an1, ap1) = pb.certain_side(&ta[1]);
    let (an2, ap2) = pb.certain_side(&ta[2]);
    let apart = apart_b.or(an0.and(an1).and(an2)).or(ap0.and(ap1).and(ap2));
    if apart.bits() == all {
        return (all, 0);
    }
    let certain = bn0
        .or(bp0)
        .and(bn1.or(bp1))
        .and(bn2.or(bp2))
        .and(an0.or(ap0))
        .and(an1.or(ap1))
        .and(an2.or(ap2));
    // General position (all six certain, neither triangle on one side): the scalar
    // `general_position`'s permutation. a's lone vertex first (p1, q1, r1), by the
    // pattern of a's negative signs; when its sign is positive, b's q and r swap.
    let (k0, k1) = lonely([an0, an1, an2]);
    let p1 = sel3w(k0, k1, &ta[0], &ta[1], &ta[2]);
    let q1 = sel3w(k0, k1, &ta[1], &ta[2], &ta[0]);
    let r1 = sel3w(k0, k1, &ta[2], &ta[0], &ta[1]);
    let swap_b = k0.and(ap0).or(k1.and(ap1)).or(k0.or(k1).not().and(ap2));
    // b with its vertices 1 and 2 swapped where `swap_b`, and their negative signs.
    let lb = [
        tb[0],
        swap_b.selw(&tb[2], &tb[1]),
        swap_b.selw(&tb[1], &tb[2]),
    ];
    let nb = [bn0, swap_b.selm(bn2, bn1), swap_b.selm(bn1, bn2)];
    let pbs = [bp0, swap_b.selm(bp2, bp1), swap_b.selm(bp1, bp2)];
    // Then b's lone vertex first (p2, q2, r2); when its sign is positive, q1 and r1 swap.
    let (j0, j1) = lonely(nb);
    let p2 = sel3w(j0, j1, &lb[0], &lb[1], &lb[2]);
    let q2 = sel3w(j0, j1, &lb[1], &lb[2], &lb[0]);
    let r2 = sel3w(j0, j1, &lb[2], &lb[0], &lb[1]);
    let swap_a = j0
        .and(pbs[0])
        .or(j1.and(pbs[1]))
        .or(j0.or(j1).not().and(pbs[2]));
    let (q1, r1) = (swap_a.selw(&r1, &q1), swap_a.selw(&q1, &r1));
    // The scalar CHECK_MIN_MAX: orient3d(p2, p1, q2, q1) <= 0 and orient3d(p2, r1, r2,
    // p1) <= 0 (neither is zero in general position).
    let (o1n, o1p) = orient3d(&p2, &p1, &q2, &q1);
    let (o2n, o2p) = orient3d(&p2, &r1, &r2, &p1);
    let general = certain.and(apart.not());
    // Certainly `<= 0`: negative beyond the filter's bound or, looked for only where the
    // filter leaves a lane in general position, exactly 0 by four points in one coordinate
    // plane (two triangles with an edge each in a plane `z = c`, those edges crossing: the
    // rows of a cloth laid out on a grid, rolled so that its layers cross, as 2% of the
    // pairs of the benchmarks' rolled cloth).
    let (mut o1z, mut o2z) = (o1n, o2n);
    if general.and(o1p.or(o2p).or(o1n.and(o2n)).not()).bits() != 0 {
        o1z = o1z.or(in_one_coordinate_plane(&p2, &p1, &q2, &q1));
        o2z = o2z.or(in_one_coordinate_plane(&p2, &r1, &r2, &p1));
    }
    let decided_gd = o1p.or(o2p).or(o1z.and(o2z));
    let decided = apart.or(general.and(decided_gd)).bits();
    let meets = general.and(o1z).and(o2z).bits();
    (decided, meets & decided)
}
