//! The exact test of pairs of triangles in one coordinate plane (all six vertices with the
//! same `x`, or `y`, or `z`: a flat sheet, the usual first frame of a cloth simulation; a
//! box's face; a floor), four pairs at once on a CPU with AVX2 and FMA, eight on one with
//! AVX-512F. Every orientation of the 3D test is then exactly 0, which its lanes
//! ([`super::four`]) cannot certify; the scalar test decides such pairs in their plane
//! ([`super::coplanar_2d`]), and so does this kernel, with the same signs: each
//! triangle's orientation, and for each edge of each triangle whether the other's three
//! vertices are strictly outside the edge's line (then that line separates them), every
//! `orient2d` with Shewchuk's static filter (the bound of
//! [`crate::geom::predicates::orient2d_filtered`]). A lane is decided apart when an edge
//! of a triangle whose orientation is certain certainly separates, and meeting when both
//! orientations are certain and every edge certainly has a vertex of the other triangle
//! strictly inside its line. Every other lane (a flat triangle, a vertex on or within the
//! error bound of an edge's line: touching triangles, slivers) is left undecided, for the
//! scalar exact test: so the answer is always the exact one, the same as
//! [`super::triangles_intersect`]'s.
//!
//! The pairs come projected on their plane ([`TriLanes::set_plane`]: two coordinates per
//! vertex). The kernel's body ([`intersect_lanes`]) is written for any lane width
//! ([`Float`]): the same operations in each lane at either width, so a pair gets the same
//! answer (decided or not) on four lanes or eight.
//!
//! On the benchmarks' flat cloth (every pair of non-adjacent triangles with touching
//! boxes, all apart) every pair is decided here, and a batch ends at the first exit (an
//! edge's line separates each pair): the pairs cost about what those of the same cloth
//! jittered off its plane cost in the 3D kernel, rather than twice as much one by one in
//! the scalar test.

use crate::geom::lanes::{Float, Mask, TriLanes};

/// A point or a vector of the plane, per lane.
type V<T> = [T; 2];

/// Pair `l` is (lane `l` of `a`, lane `l` of `b`), both triangles stored by
/// [`TriLanes::set_plane`]. Returns (decided, meets) as lane bit masks, as
/// [`super::four::intersect`] does: bit `l` of `decided` when lane `l`'s answer was
/// certain here, bit `l` of `meets` when, moreover, the closed triangles intersect.
/// Undecided lanes need the scalar exact test.
///
/// # Safety
/// The CPU has AVX2 and FMA.
#[target_feature(enable = "avx2,fma")]
pub(crate) unsafe fn four(a: &TriLanes, b: &TriLanes) -> (u32, u32) {
    // SAFETY: the caller's promise.
    let (ta, tb) = unsafe {
        (
            a.load_plane::<crate::geom::lanes::F>(),
            b.load_plane::<crate::geom::lanes::F>(),
        )
    };
    intersect_lanes(&ta, &tb)
}

/// [`four`] on eight lanes.
///
/// # Safety
/// The CPU has AVX-512F (and so AVX2 and FMA).
#[target_feature(enable = "avx2,fma,avx512f")]
pub(crate) unsafe fn eight(a: &TriLanes<8>, b: &TriLanes<8>) -> (u32, u32) {
    // SAFETY: the caller's promise.
    let (ta, tb) = unsafe {
        (
            a.load_plane::<crate::geom::lanes8::F8>(),
            b.load_plane::<crate::geom::lanes8::F8>(),
        )
    };
    intersect_lanes(&ta, &tb)
}

#[inline(always)]
fn sub<T: Float>(p: &V<T>, q: &V<T>) -> V<T> {
    [p[0] - q[0], p[1] - q[1]]
}

/// `e x d` and the bound of Shewchuk's static filter on its rounding error: its sign is
/// certain where its magnitude exceeds the bound. With `e = q - p` and `d = x - p`,
/// `e x d` is `orient2d(q, x, p)` (= `orient2d(p, q, x)`) as his formula rounds it (the
/// differences from the third point), so his bound holds: `(3 + 16 eps) eps` times the
/// sum of the two products' magnitudes. But not less than twice
/// [`crate::geom::predicates::orient2d_filtered`]'s 1e-250, below which the products may
/// have lost bits to underflow: a determinant beyond that has products of magnitudes
/// summing beyond 1e-250 (the sum is at least the determinant's magnitude, up to a
/// rounding), where `orient2d_filtered` trusts its bound. (One maximum rather than a
/// second comparison per determinant.)
#[inline(always)]
fn cross<T: Float>(e: &V<T>, d: &V<T>) -> (T, T) {
    const EPS: f64 = f64::EPSILON / 2.0;
    const BOUND: f64 = (3.0 + 16.0 * EPS) * EPS;
    const TINY: f64 = 2e-250;
    let (left, right) = (e[0] * d[1], e[1] * d[0]);
    let err = e[0].like(BOUND) * (left.abs() + right.abs());
    (left - right, err.max(e[0].like(TINY)))
}

/// [`four`]'s body, for any lane width (lane `l`: the pair of the triangles in lane `l` of
/// `ta` and `tb`, two coordinates per vertex).
///
/// Every `orient2d` of a vertex against an edge's line is taken from the edge's first
/// vertex: `orient2d(a_i, a_i+1, b_j) = ea_i x (b_j - a_i)` and
/// `orient2d(b_j, b_j+1, a_i) = eb_j x (a_i - b_j)`, and `a_i - b_j` rounds to exactly
/// `-(b_j - a_i)`: the nine differences `d_ij = b_j - a_i` serve both triangles' edges.
/// Each edge is turned (negated: exact) so that a vertex certainly strictly outside its
/// line is one whose determinant is certainly positive: `ea_i` reversed where `a` is
/// counter-clockwise, `eb_j` reversed where `b` is clockwise (the negation of `d_ij`
/// taken into it).
#[inline(always)]
pub(super) fn intersect_lanes<T: Float>(ta: &[V<T>; 3], tb: &[V<T>; 3]) -> (u32, u32) {
    let all: u32 = (1 << T::LANES) - 1;
    let ea = [
        sub(&ta[1], &ta[0]),
        sub(&ta[2], &ta[1]),
        sub(&ta[0], &ta[2]),
    ];
    let eb = [
        sub(&tb[1], &tb[0]),
        sub(&tb[2], &tb[1]),
        sub(&tb[0], &tb[2]),
    ];
    // orient2d(t0, t1, t2) = (t1 - t0) x (t2 - t0) = e2 x e0 (t2 - t0 = -e2 exactly).
    let (oa, ea_err) = cross(&ea[2], &ea[0]);
    let (ob, eb_err) = cross(&eb[2], &eb[0]);
    let (a_cw, a_ccw) = (oa.lt(-ea_err), oa.gt(ea_err));
    let (b_cw, b_ccw) = (ob.lt(-eb_err), ob.gt(eb_err));
    let mut fa = ea;
    let mut fb = eb;
    for k in 0..3 {
        fa[k] = [
            a_ccw.sel(-ea[k][0], ea[k][0]),
            a_ccw.sel(-ea[k][1], ea[k][1]),
        ];
        fb[k] = [b_cw.sel(-eb[k][0], eb[k][0]), b_cw.sel(-eb[k][1], eb[k][1])];
    }
    // The determinants of `b_j` against `a`'s edge `i` (`da`, `ra`: its bound) and of
    // `a_i` against `b`'s edge `j` (`db`, `rb`), positive outside.
    let (mut da, mut ra) = ([[oa; 3]; 3], [[oa; 3]; 3]);
    let (mut db, mut rb) = ([[oa; 3]; 3], [[oa; 3]; 3]);
    for i in 0..3 {
        for j in 0..3 {
            let d = sub(&tb[j], &ta[i]);
            (da[i][j], ra[i][j]) = cross(&fa[i], &d);
            (db[i][j], rb[i][j]) = cross(&fb[j], &d);
        }
    }
    // An edge's line certainly separates: all three of the other's vertices certainly
    // outside. That proves the pair apart even when the other triangle is flat (its
    // vertices, and so the segment or point they span, are strictly beyond the line).
    let mut sep_a = da[0][0].gt(ra[0][0]).and(da[0][1].gt(ra[0][1]));
    sep_a = sep_a.and(da[0][2].gt(ra[0][2]));
    let mut sep_b = db[0][0].gt(rb[0][0]).and(db[1][0].gt(rb[1][0]));
    sep_b = sep_b.and(db[2][0].gt(rb[2][0]));
    for k in 1..3 {
        let a = da[k][0].gt(ra[k][0]).and(da[k][1].gt(ra[k][1]));
        sep_a = sep_a.or(a.and(da[k][2].gt(ra[k][2])));
        let b = db[0][k].gt(rb[0][k]).and(db[1][k].gt(rb[1][k]));
        sep_b = sep_b.or(b.and(db[2][k].gt(rb[2][k])));
    }
    let apart = a_cw.or(a_ccw).and(sep_a).or(b_cw.or(b_ccw).and(sep_b));
    // Two triangles of a sheet are apart: most batches end here.
    if apart.bits() == all {
        return (all, 0);
    }
    // Meeting: both orientations certain, and every edge has a vertex of the other
    // certainly strictly inside its line (so no line of an edge separates them).
    let mut meets = a_cw.or(a_ccw).and(b_cw.or(b_ccw));
    for k in 0..3 {
        let a = da[k][0].lt(-ra[k][0]).or(da[k][1].lt(-ra[k][1]));
        let b = db[0][k].lt(-rb[0][k]).or(db[1][k].lt(-rb[1][k]));
        meets = meets.and(a.or(da[k][2].lt(-ra[k][2])));
        meets = meets.and(b.or(db[2][k].lt(-rb[2][k])));
    }
    (apart.or(meets).bits(), meets.bits())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::predicates::{orient2d, P3};
    use crate::geom::test_rng::Rng;
    use crate::geom::tritri::{coplanar_2d, meet_in_3d, shared_axis_plane, triangles_intersect};

    /// The kinds of pairs (see [`pair`]).
    const KINDS: usize = 9;
    const NAMES: [&str; KINDS] = [
        "random",
        "touching",
        "nearly collinear",
        "sliver",
        "degenerate",
        "far",
        "scaled",
        "cloth",
        "underflow, overflow",
    ];

    type T2 = [[f64; 2]; 3];

    /// On a grid of 1/64 in [-1, 1): sums, halves and quarters of these are exact.
    fn grid(rng: &mut Rng) -> [f64; 2] {
        [0, 1].map(|_| (rng.f() * 128.0).floor() / 64.0)
    }

    fn random(rng: &mut Rng) -> T2 {
        [0, 1, 2].map(|_| [rng.f(), rng.f()])
    }

    /// `p + (q - p) s`, per coordinate.
    fn along(p: [f64; 2], q: [f64; 2], s: f64) -> [f64; 2] {
        [0, 1].map(|k| p[k] + (q[k] - p[k]) * s)
    }

    /// Two triangles of the plane, of kind `kind` (the names in [`NAMES`]), and the offset
    /// of the plane's coordinate.
    fn pair_2d(rng: &mut Rng, kind: usize) -> (T2, T2, f64) {
        match kind {
            // Random, about half overlapping.
            0 => (random(rng), random(rng), rng.f()),
            // Touching, exactly (on the grid): `u`'s first vertex at a vertex of `t` (the
            // same position, not the same index) or at the midpoint of an edge, or `u`'s
            // first edge along an edge of `t`; `u`'s other vertices beyond that edge (or,
            // one time in three, anywhere). One time in four, moved off by about 1e-12.
            1 => {
                let t = [grid(rng), grid(rng), grid(rng)];
                let i = rng.below(3);
                let (p, q, r) = (t[i], t[(i + 1) % 3], t[(i + 2) % 3]);
                let mid = along(p, q, 0.5);
                // Beyond the edge p-q, from the opposite vertex r.
                let beyond = |rng: &mut Rng, at: [f64; 2]| {
                    let s = [0.25, 0.5, 1.0][rng.below(3)];
                    let o = along(mid, r, -s);
                    along(at, o, [0.5, 1.0, 2.0][rng.below(3)])
                };
                let mut u = match rng.below(3) {
                    0 => [p, beyond(rng, p), beyond(rng, q)],
                    1 => [mid, beyond(rng, p), beyond(rng, q)],
                    _ => [
                        mid,
                        along(p, q, [0.75, 1.5, 2.0][rng.below(3)]),
                        beyond(rng, mid),
                    ],
                };
                if rng.below(3) == 0 {
                    u[1] = grid(rng);
                    u[2] = grid(rng);
                }
                if rng.below(4) == 0 {
                    let e = [rng.f() * 1e-12, rng.f() * 1e-12];
                    u = u.map(|v| [v[0] + e[0], v[1] + e[1]]);
                }
                rng.shuffle(&mut u);
                (t, u, 0.0)
            }
            // A vertex of `u` within 1e-10..1e-16 of an edge's line of `t` (either side, or
            // on it), the others beyond it or anywhere.
            2 => {
                let t = random(rng);
                let i = rng.below(3);
                let (p, q) = (t[i], t[(i + 1) % 3]);
                let d = [q[0] - p[0], q[1] - p[1]];
                let off = [1e-10, 1e-13, 1e-16, 0.0][rng.below(4)] * rng.f();
                let on = along(p, q, rng.range(-0.5, 1.5));
                let near = [on[0] - d[1] * off, on[1] + d[0] * off];
                let o = along(along(p, q, 0.5), t[(i + 2) % 3], -1.0);
                let mut u = [
                    near,
                    along(near, o, rng.range(0.1, 1.0)),
                    [rng.f(), rng.f()],
                ];
                rng.shuffle(&mut u);
                (t, u, 0.0)
            }
            // A sliver (aspect about 1e9, 1e13 or 1e15) and a random triangle, or two
            // slivers.
            3 => {
                let sliver = |rng: &mut Rng| {
                    let (a, b) = ([rng.f(), rng.f()], [rng.f(), rng.f()]);
                    let m = along(a, b, rng.unit());
                    let e = [1e-9, 1e-13, 1e-15][rng.below(3)];
                    [a, b, [m[0] + rng.f() * e, m[1] + rng.f() * e]]
                };
                let u = if rng.below(2) == 0 {
                    sliver(rng)
                } else {
                    random(rng)
                };
                (sliver(rng), u, 0.0)
            }
            // Degenerate (no area): a segment, a point or three collinear points, against
            // a random triangle or another degenerate one.
            4 => {
                let flat = |rng: &mut Rng| {
                    let (a, b) = (grid(rng), grid(rng));
                    match rng.below(3) {
                        0 => [a, b, a],
                        1 => [a, a, a],
                        _ => [a, b, along(a, b, 2.0)],
                    }
                };
                let u = if rng.below(3) == 0 {
                    flat(rng)
                } else {
                    random(rng)
                };
                (flat(rng), u, 0.0)
            }
            // Far from the origin: at 1e7, size about 1.
            5 => {
                let far = |t: T2| t.map(|p| p.map(|x| 1e7 + x));
                (far(random(rng)), far(random(rng)), 1e7)
            }
            // Huge and tiny: random, scaled by 1e-30..1e30.
            6 => {
                let s = [1e-30, 1e-8, 1e8, 1e30][rng.below(4)];
                let scaled = |t: T2| t.map(|p| p.map(|x| x * s));
                (scaled(random(rng)), scaled(random(rng)), s)
            }
            // The bench's flat cloth (`f32` grid of step 1/n, each cell cut along its
            // diagonal): a triangle and one of the cell or of a neighbouring cell (shared
            // vertices, boxes touching along a grid line or at a corner).
            7 => {
                let n = [100, 300, 7][rng.below(3)];
                let tri = |i: i32, j: i32, upper: bool| {
                    let v = |a: i32, b: i32| [a, b].map(|x| f64::from(x as f32 / n as f32));
                    if upper {
                        [v(i, j), v(i + 1, j + 1), v(i, j + 1)]
                    } else {
                        [v(i, j), v(i + 1, j), v(i + 1, j + 1)]
                    }
                };
                let (i, j) = (rng.below(n - 2) as i32 + 1, rng.below(n - 2) as i32 + 1);
                let (di, dj) = (rng.below(3) as i32 - 1, rng.below(3) as i32 - 1);
                let t = tri(i, j, rng.below(2) == 0);
                let u = tri(i + di, j + dj, rng.below(2) == 0);
                (t, u, 0.0)
            }
            // Random, touching or nearly collinear (scaled by a power of two beyond the
            // filter's range in `pair`).
            _ => {
                let kind = rng.below(3);
                pair_2d(rng, kind)
            }
        }
    }

    /// `p` in the plane `x_ax = c`.
    fn lift(p: [f64; 2], ax: usize, c: f64) -> P3 {
        let mut q = [c; 3];
        q[(ax + 1) % 3] = p[0];
        q[(ax + 2) % 3] = p[1];
        q
    }

    /// A pair of kind `kind` in a random coordinate plane, and the same pair at a scale
    /// where its exact answer is known: for the last kind, scaled by a power of two (so
    /// exactly, the answer unchanged) to about 1e-127 (products of coordinates below the
    /// filter's 1e-250), 1e-163 (they underflow) or 1e156 (they overflow), beyond the
    /// exact predicates' range too; the pair itself for the others.
    #[allow(clippy::type_complexity)]
    fn pair(rng: &mut Rng, kind: usize) -> (([P3; 3], [P3; 3]), ([P3; 3], [P3; 3])) {
        let (t, u, c) = pair_2d(rng, kind);
        let ax = rng.below(3);
        let s = if kind == 8 {
            2f64.powi([-420, -515, -540, 520][rng.below(4)])
        } else {
            1.0
        };
        let at = |t: T2, s: f64| t.map(|p| lift(p.map(|x| x * s), ax, c * s));
        ((at(t, s), at(u, s)), (at(t, 1.0), at(u, 1.0)))
    }

    /// No orientation of the scalar test is exactly 0: both triangles' and every edge's
    /// against the other's vertices (in the plane the pair is projected on).
    fn general(t: &[P3; 3], u: &[P3; 3], ax: usize) -> bool {
        let p = |t: &[P3; 3]| t.map(|v| crate::geom::predicates::drop_axis(&v, ax));
        let (t, u) = (p(t), p(u));
        let edges = |t: &T2, u: &T2| {
            (0..3).all(|i| u.iter().all(|&x| orient2d(t[i], t[(i + 1) % 3], x) != 0.0))
        };
        orient2d(t[0], t[1], t[2]) != 0.0
            && orient2d(u[0], u[1], u[2]) != 0.0
            && edges(&t, &u)
            && edges(&u, &t)
    }

    /// The lanes of pairs in one coordinate plane decide only what floating point
    /// certifies, and then as the exact tests (the 3D test with exact orientations, and
    /// the scalar test in the plane), on pairs of every kind mixed in each batch: random,
    /// touching (a vertex at a vertex, a vertex on an edge, an edge along an edge: exact),
    /// a vertex nearly on an edge's line, slivers, degenerate triangles, far from the
    /// origin (1e7), at scales 1e-30..1e30, and the pairs of a flat cloth, in the planes
    /// `x`, `y` and `z = c`, and (left to the scalar test) at 1e-160 and 1e160, where
    /// the products underflow or overflow. Four lanes decide each pair as eight do; most pairs without
    /// an orientation exactly 0 are decided, and every pair of non-adjacent triangles of
    /// the cloth.
    #[test]
    fn lanes_decide_as_the_exact_test() {
        if !(std::is_x86_feature_detected!("avx2") && std::is_x86_feature_detected!("fma")) {
            println!("no AVX2 and FMA: the lanes are not used");
            return;
        }
        let on_eight = std::is_x86_feature_detected!("avx512f");
        if !on_eight {
            println!("no AVX-512F: four lanes only");
        }
        let mut rng = Rng(0xF1A7_5EED_2D00_u64);
        let (mut decided, mut total, mut meets) = ([0usize; KINDS], [0; KINDS], [0; KINDS]);
        let (mut general_pairs, mut general_decided) = (0usize, 0usize);
        let (mut cloth_apart, mut cloth_apart_decided) = (0usize, 0usize);
        for _ in 0..12_000 {
            let kinds: [usize; 8] = std::array::from_fn(|_| rng.below(KINDS));
            let both = kinds.map(|k| pair(&mut rng, k));
            let (pairs, known) = (both.map(|p| p.0), both.map(|p| p.1));
            // Gathered as `Fours` does: projected on the plane the pair shares.
            let (mut a, mut b) = (TriLanes::<8>::ZERO, TriLanes::<8>::ZERO);
            let (mut a4, mut b4) = ([TriLanes::<4>::ZERO; 2], [TriLanes::<4>::ZERO; 2]);
            let mut axes = [0; 8];
            for (l, (t, u)) in pairs.iter().enumerate() {
                let ax = shared_axis_plane(t, u).expect("one coordinate plane");
                axes[l] = ax;
                a.set_plane(l, t, ax);
                b.set_plane(l, u, ax);
                a4[l / 4].set_plane(l % 4, t, ax);
                b4[l / 4].set_plane(l % 4, u, ax);
            }
            // SAFETY: AVX2 and FMA checked above.
            let ((d0, m0), (d1, m1)) = unsafe { (four(&a4[0], &b4[0]), four(&a4[1], &b4[1])) };
            let (d, m) = (d0 | d1 << 4, m0 | m1 << 4);
            if on_eight {
                // SAFETY: AVX-512F checked.
                let wide = unsafe { eight(&a, &b) };
                assert_eq!(wide, (d, m), "{pairs:?}");
            }
            for (l, (t, u)) in pairs.iter().enumerate() {
                let kind = kinds[l];
                // The exact tests, at a scale where they are exact (the pair's own but
                // for the last kind).
                let (kt, ku) = &known[l];
                let want = meet_in_3d(kt, ku, [0; 3], [0; 3]);
                assert_eq!(triangles_intersect(kt, ku), want, "{kt:?} {ku:?}");
                if let Some(meet) = coplanar_2d(kt, ku, axes[l]) {
                    assert_eq!(meet, want, "{kt:?} {ku:?}");
                }
                total[kind] += 1;
                meets[kind] += usize::from(want);
                let here = d & (1 << l) != 0;
                if here {
                    decided[kind] += 1;
                    assert_eq!(m & (1 << l) != 0, want, "{}: {t:?} {u:?}", NAMES[kind]);
                } else {
                    assert_eq!(m & (1 << l), 0);
                }
                if kind != 8 && general(t, u, axes[l]) {
                    general_pairs += 1;
                    general_decided += usize::from(here);
                }
                let shared = t.iter().any(|p| u.contains(p));
                if kind == 7 && !shared && !want {
                    cloth_apart += 1;
                    cloth_apart_decided += usize::from(here);
                }
            }
        }
        println!(
            "decided in the lanes ({NAMES:?}): {decided:?} of {total:?}, {meets:?} meet; \
             without a zero orientation {general_decided} of {general_pairs}; the cloth's \
             non-adjacent pairs {cloth_apart_decided} of {cloth_apart}"
        );
        // Every kind seen, meeting and apart (the cloth's pairs meet where they share a
        // vertex), and the lanes decided some of each kind with an area.
        for k in 0..KINDS {
            assert!(meets[k] > 100 && meets[k] + 100 < total[k], "{}", NAMES[k]);
        }
        assert!(decided[0] * 10 > total[0] * 9, "{decided:?}");
        assert!(decided[5] * 10 > total[5] * 9 && decided[6] * 10 > total[6] * 9);
        assert!(general_pairs > 20_000 && general_decided * 20 > general_pairs * 19);
        assert!(cloth_apart > 1_000 && cloth_apart_decided == cloth_apart);
    }

    /// The filter ([`cross`]) certifies only the exact sign of `orient2d(p, q, x)`,
    /// for nearly collinear points at every scale, 2^-515 included, where the products
    /// fall below the normal range and the relative bound no longer holds (there the
    /// first four cases, found by a search, give a floating-point determinant of the
    /// wrong sign, which the filter must not certify). The exact sign: `orient2d` of the
    /// points scaled by a power of two into its range (exactly).
    #[test]
    fn the_filter_certifies_only_exact_signs() {
        use crate::geom::lanes::F;
        if !(std::is_x86_feature_detected!("avx2") && std::is_x86_feature_detected!("fma")) {
            return;
        }
        let mut cases: Vec<[[f64; 2]; 3]> = vec![
            [
                [-4.458_214_795_571_052_5e-156, -6.557_217_773_008_845e-156],
                [3.899_250_773_435_602_5e-156, 8.685_875_518_429_324e-156],
                [1.099_718_329_809_305_4e-155, 2.163_171_977_663_624e-155],
            ],
            [
                [5.630_360_658_760_462e-156, 4.635_964_681_785_054e-156],
                [-9.073_426_190_933_584e-156, 7.933_195_709_787_542e-156],
                [-2.119_708_104_505_980_3e-155, 1.065_184_848_722_832_3e-155],
            ],
            [
                [-2.652_797_040_520_881_3e-156, 9.000_737_835_239_431e-156],
                [2.711_554_176_318_281e-156, -6.568_726_536_009_748e-156],
                [7.784_622_262_128_962e-156, -2.129_277_230_076_319_5e-155],
            ],
            [
                [8.112_868_298_794_227e-156, 7.932_592_365_935_283e-156],
                [-7.251_355_390_589_863e-156, 6.276_185_287_221_444e-156],
                [-2.239_373_218_943_776_5e-155, 4.643_695_379_157_021e-156],
            ],
        ];
        // Random points on a line through two (rounded: off it by about an ulp), at
        // scales 2^-515 (underflowing products), 2^-100, 1 and 2^100.
        let mut rng = Rng(0xC011_1EA5_u64);
        for i in 0..40_000 {
            let s = 2f64.powi([-515, -100, 0, 100][i % 4]);
            let (p, q) = ([rng.f() * s, rng.f() * s], [rng.f() * s, rng.f() * s]);
            cases.push([p, q, along(p, q, rng.range(-1.0, 2.0))]);
        }
        let (mut certain, mut wrong) = (0, 0);
        for c in cases.chunks(4) {
            let lane = |v: usize, k: usize| -> F {
                let x: [f64; 4] = std::array::from_fn(|l| c[l % c.len()][v][k]);
                // SAFETY: AVX2 and FMA checked above.
                unsafe { F::new(x) }
            };
            let (p, q, x) = (
                [lane(0, 0), lane(0, 1)],
                [lane(1, 0), lane(1, 1)],
                [lane(2, 0), lane(2, 1)],
            );
            let (det, err) = cross(&sub(&q, &p), &sub(&x, &p));
            let (neg, pos) = (det.lt(-err), det.gt(err));
            for (l, [p, q, x]) in c.iter().enumerate() {
                // Into orient2d's range, exactly (a power of two; no coordinate
                // overflows or falls below the normal range).
                let m = p[0].abs().max(p[1].abs()).max(q[0].abs()).max(q[1].abs());
                let up = 2f64.powi(-(m.log2().floor() as i32));
                let [p, q, x] = [p, q, x].map(|v| v.map(|c| c * up));
                let exact = orient2d(p, q, x);
                let (n, o) = (neg.bits() >> l & 1 == 1, pos.bits() >> l & 1 == 1);
                certain += usize::from(n || o);
                wrong += usize::from((n && exact >= 0.0) || (o && exact <= 0.0));
            }
        }
        assert_eq!(wrong, 0);
        println!("{certain} of the 40,004 signs certain");
        assert!(certain > 1_000);
    }
}
