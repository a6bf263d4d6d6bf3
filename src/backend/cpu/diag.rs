//! Polygons' bounds along six diagonal directions ([`Diag`]): with their boxes an 18-DOP,
//! tighter than the box alone around an oblique triangle. At epsilon 0 a self-colliding
//! triangle mesh's box pairs apart along a diagonal are dropped before any test
//! ([`super::lanes::Lanes::pairs_16`]), and so are its
//! sub-leaf pairs so apart.

use super::lanes::{LANES, PAD};

/// Polygons' bounds along the six diagonal directions `x + y`, `x - y`, `x + z`, `x - z`,
/// `y + z`, `y - z` (with the box's three, an 18-DOP), stored as [`super::lanes::Lanes`] stores boxes
/// and padded as they are (padding meets nothing). Two closed polygons whose bounds along
/// one direction do not meet share no point: at epsilon 0 such a pair needs no test, and
/// two groups of polygons (sub-leaves) so apart have no pair to list. Between two layers
/// of a crumpled cloth about half the box-meeting triangle pairs are apart so (an
/// oblique triangle's box is mostly empty), for twelve compares done in registers where
/// the box test left a candidate.
///
/// Bounds are rounded outward: each sum of two coordinates, rounded to nearest, is moved
/// out by 2^-21 of its size and 2^-140, more than its own rounding and the rounding to
/// `f32` can err ([`outward`], [`outward_f32`]): each bound holds the exact sums of the
/// corners it bounds (a float mesh's computed in `f32` straight from its points, others'
/// from their `f64` corners).
#[derive(Clone, Debug, Default)]
pub(crate) struct Diag {
    lo: [Vec<f32>; 6],
    hi: [Vec<f32>; 6],
}

impl Diag {
    /// Number of polygons (padding not counted).
    #[inline]
    pub fn len(&self) -> usize {
        self.lo[0].len().saturating_sub(PAD)
    }

    /// The bounds of each triangle of `tris`, padded; in chunks shared between the
    /// caller's worker threads with `par` (inside a pool).
    pub fn set_triangles(&mut self, tris: &[[crate::geom::P3; 3]], par: bool) {
        self.fill::<POLYGON_CHUNK>(tris.len(), par, |first, out| {
            for (i, t) in tris[first..first + out[0].len()].iter().enumerate() {
                let [a, b, c] = t.map(|v| diag_sums(&v));
                for k in 0..6 {
                    let (lo, hi) = (a[k].min(b[k]).min(c[k]), a[k].max(b[k]).max(c[k]));
                    (out[k][i], out[k + 6][i]) = outward(lo, hi);
                }
            }
        });
    }

    /// [`Diag::set_triangles`] for the triangles of a float mesh, given by their corners'
    /// indices into `points`, in `f32` (the bounds moved out as [`outward_f32`] says),
    /// triangle by triangle in one pass with no branch: where the CPU has AVX-512F the
    /// compiler runs it sixteen triangles at a time.
    pub fn set_corners(&mut self, points: &[[f32; 3]], corners: &[[u32; 3]], par: bool) {
        self.fill::<POLYGON_CHUNK>(corners.len(), par, |first, out| {
            let corners = &corners[first..first + out[0].len()];
            #[cfg(target_arch = "x86_64")]
            if std::is_x86_feature_detected!("avx512f") {
                // SAFETY: the CPU supports AVX-512F, checked just above.
                return unsafe { corner_bounds_avx512(points, corners, out) };
            }
            corner_bounds(points, corners, out)
        });
    }

    /// The union of the bounds of `of` in each run `starts[s]..starts[s + 1]` (a
    /// sub-leaf's polygons), padded.
    pub fn set_union(&mut self, of: &Diag, starts: &[u32], par: bool) {
        // (A run is up to sixteen polygons: chunks of as many polygons as theirs, so that
        // two workers share the ~7,000 sub-leaves of a 92k-triangle cloth.)
        self.fill::<{ POLYGON_CHUNK / 16 }>(starts.len() - 1, par, |first, out| {
            #[cfg(target_arch = "x86_64")]
            if std::is_x86_feature_detected!("avx512f") {
                // SAFETY: the CPU supports AVX-512F, checked just above.
                return unsafe { union_avx512(of, &starts[first..], out) };
            }
            let (lo, hi) = out.split_at_mut(6);
            for k in 0..6 {
                for (i, (l, h)) in lo[k].iter_mut().zip(hi[k].iter_mut()).enumerate() {
                    let r = starts[first + i] as usize..starts[first + i + 1] as usize;
                    *l = of.lo[k][r.clone()]
                        .iter()
                        .fold(f32::INFINITY, |m, &x| if x < m { x } else { m });
                    *h = of.hi[k][r]
                        .iter()
                        .fold(f32::NEG_INFINITY, |m, &x| if x > m { x } else { m });
                }
            }
        });
    }

    /// Sizes the arrays for `n` entries, padded, then has `make(first, bounds)` write the
    /// twelve bounds (lo 0..6, hi 6..12) of entries `first..` in chunks of `CHUNK`.
    fn fill<const CHUNK: usize>(
        &mut self,
        n: usize,
        par: bool,
        make: impl Fn(usize, &mut [&mut [f32]; 12]) + Sync,
    ) {
        use rayon::prelude::*;
        // The entries are all written below: only a new length touches the padding.
        if self.lo[0].len() != n + PAD {
            for v in self.lo.iter_mut() {
                v.clear();
                v.resize(n + PAD, f32::INFINITY);
            }
            for v in self.hi.iter_mut() {
                v.clear();
                v.resize(n + PAD, f32::NEG_INFINITY);
            }
        }
        let mut cols = self
            .lo
            .iter_mut()
            .chain(self.hi.iter_mut())
            .map(|v| v[..n].chunks_mut(CHUNK));
        let mut chunks: Vec<[&mut [f32]; 12]> = Vec::with_capacity(n.div_ceil(CHUNK));
        let mut its: [_; 12] = std::array::from_fn(|_| cols.next().unwrap());
        while let Some(a) = its[0].next() {
            let rest: [&mut [f32]; 11] = std::array::from_fn(|k| its[k + 1].next().unwrap());
            let [b, c, d, e, f, g, h, i, j, k, l] = rest;
            chunks.push([a, b, c, d, e, f, g, h, i, j, k, l]);
        }
        let run = |(x, out): (usize, &mut [&mut [f32]; 12])| make(x * CHUNK, out);
        if par {
            // One job a chunk: a worker done early takes over a slower one's.
            chunks
                .par_iter_mut()
                .enumerate()
                .with_max_len(1)
                .for_each(run);
        } else {
            chunks.iter_mut().enumerate().for_each(run);
        }
    }

    /// Entries `i` and `j` meet along all six directions (closed bounds).
    #[inline]
    pub fn meets(&self, i: usize, j: usize) -> bool {
        (0..6).all(|k| self.hi[k][i] >= self.lo[k][j] && self.lo[k][i] <= self.hi[k][j])
    }
}

/// Polygons a job of [`Diag::fill`] bounds (one job a chunk).
const POLYGON_CHUNK: usize = 2048;

/// 2^-140 (a subnormal `f32`): the absolute part of [`outward`]'s and [`outward_f32`]'s
/// margins.
const TINY: f32 = f32::from_bits(1 << 9);

/// [`Diag::set_union`] for one chunk in AVX-512: each run (at most sixteen entries, read
/// sixteen at a time from its start, padding included) reduced under a mask.
///
/// # Safety
/// The CPU must support AVX-512F.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f")]
unsafe fn union_avx512(of: &Diag, starts: &[u32], out: &mut [&mut [f32]; 12]) {
    use std::arch::x86_64::*;
    for i in 0..out[0].len() {
        let r = starts[i] as usize..starts[i + 1] as usize;
        assert!(r.len() <= 2 * LANES && r.start <= of.len());
        let keep = ((1u32 << r.len()) - 1) as u16;
        for k in 0..6 {
            let (lo, hi) = (
                &of.lo[k][r.start..r.start + 2 * LANES],
                &of.hi[k][r.start..r.start + 2 * LANES],
            );
            // SAFETY: sixteen floats each (the arrays are padded past their last entry); no
            // alignment needed.
            let (lo, hi) = unsafe { (_mm512_loadu_ps(lo.as_ptr()), _mm512_loadu_ps(hi.as_ptr())) };
            out[k][i] = _mm512_mask_reduce_min_ps(keep, lo);
            out[k + 6][i] = _mm512_mask_reduce_max_ps(keep, hi);
        }
    }
}

/// Direction `k` of [`Diag`]: coordinate `a` plus `sign` times coordinate `b`.
const DIRS: [(usize, usize, f32); 6] = [
    (0, 1, 1.0),
    (0, 1, -1.0),
    (0, 2, 1.0),
    (0, 2, -1.0),
    (1, 2, 1.0),
    (1, 2, -1.0),
];

/// [`Diag::set_corners`] for one chunk: triangle `i`'s twelve bounds into `out[..][i]`.
fn corner_bounds(points: &[[f32; 3]], corners: &[[u32; 3]], out: &mut [&mut [f32]; 12]) {
    for (i, c) in corners.iter().enumerate() {
        let p = c.map(|x| points[x as usize]);
        for (k, &(a, b, sign)) in DIRS.iter().enumerate() {
            let [s0, s1, s2] = p.map(|p| p[a] + sign * p[b]);
            (out[k][i], out[k + 6][i]) = outward_f32(s0.min(s1).min(s2), s0.max(s1).max(s2));
        }
    }
}

/// [`corner_bounds`] sixteen triangles at a time (the corners' indices and coordinates
/// gathered), the rest one by one; the same operations in the same order, so the same
/// bounds.
///
/// # Safety
/// The CPU must support AVX-512F.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f")]
unsafe fn corner_bounds_avx512(
    points: &[[f32; 3]],
    corners: &[[u32; 3]],
    out: &mut [&mut [f32]; 12],
) {
    use std::arch::x86_64::*;
    let full = corners.len() / 16 * 16;
    assert!(points.len() < i32::MAX as usize / 3);
    let (limit, three) = (_mm512_set1_epi32(points.len() as i32), _mm512_set1_epi32(3));
    let lane3 = _mm512_mullo_epi32(
        _mm512_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15),
        three,
    );
    let (rel, abs) = (
        _mm512_set1_ps(1.0 / (1u32 << 21) as f32),
        _mm512_set1_ps(TINY),
    );
    let (max, min) = (_mm512_set1_ps(f32::MAX), _mm512_set1_ps(-f32::MAX));
    for i in (0..full).step_by(16) {
        let at = corners[i..i + 16].as_ptr().cast::<i32>();
        let mut p = [[_mm512_setzero_ps(); 3]; 3];
        for (c, pc) in p.iter_mut().enumerate() {
            // SAFETY: lane `l` reads `corners[i + l][c]`, inside the slice.
            let idx = unsafe {
                _mm512_i32gather_epi32::<4>(
                    _mm512_add_epi32(lane3, _mm512_set1_epi32(c as i32)),
                    at,
                )
            };
            // The points' indices are checked before any is read.
            assert_eq!(
                _mm512_cmpge_epu32_mask(idx, limit),
                0,
                "corner index out of range"
            );
            let idx3 = _mm512_mullo_epi32(idx, three);
            for (a, v) in pc.iter_mut().enumerate() {
                let offs = _mm512_add_epi32(idx3, _mm512_set1_epi32(a as i32));
                // SAFETY: each index is below `points.len()` (checked above), so each
                // offset reads a coordinate inside `points`.
                *v = unsafe { _mm512_i32gather_ps::<4>(offs, points.as_ptr().cast::<f32>()) };
            }
        }
        for (k, &(a, b, sign)) in DIRS.iter().enumerate() {
            let sign = _mm512_set1_ps(sign);
            let s = p.map(|p| _mm512_add_ps(p[a], _mm512_mul_ps(sign, p[b])));
            let lo = _mm512_min_ps(_mm512_min_ps(s[0], s[1]), s[2]);
            let hi = _mm512_max_ps(_mm512_max_ps(s[0], s[1]), s[2]);
            let abs_of = |x| _mm512_abs_ps(x);
            let l = _mm512_sub_ps(_mm512_sub_ps(lo, _mm512_mul_ps(abs_of(lo), rel)), abs);
            let h = _mm512_add_ps(_mm512_add_ps(hi, _mm512_mul_ps(abs_of(hi), rel)), abs);
            let (l, h) = (_mm512_min_ps(l, max), _mm512_max_ps(h, min));
            // SAFETY: sixteen floats from `i` in each output (`i + 16 <= corners.len()`,
            // their common length); no alignment needed.
            unsafe {
                _mm512_storeu_ps(out[k][i..i + 16].as_mut_ptr(), l);
                _mm512_storeu_ps(out[k + 6][i..i + 16].as_mut_ptr(), h);
            }
        }
    }
    let mut rest: [&mut [f32]; 12] = std::array::from_fn(|_| &mut [][..]);
    for (r, o) in rest.iter_mut().zip(out.iter_mut()) {
        *r = &mut o[full..];
    }
    corner_bounds(points, &corners[full..], &mut rest);
}

/// [`outward`] for bounds `lo` and `hi` of sums of two `f32` coordinates, each rounded to
/// nearest `f32`: moved out by 2^-21 of their size and 2^-140 in `f32` (the sum's error
/// and the two roundings here are each under 2^-23 of the result, or 2^-150 below the
/// normal range); past the range as there (a sum that overflowed makes `inf - inf`, a NaN,
/// which the comparisons replace by the finite limit).
#[inline(always)]
fn outward_f32(lo: f32, hi: f32) -> (f32, f32) {
    const REL: f32 = 1.0 / (1u32 << 21) as f32;
    const ABS: f32 = TINY;
    let l = lo - lo.abs() * REL - ABS;
    let h = hi + hi.abs() * REL + ABS;
    // As `_mm512_min_ps(l, MAX)`: the second operand where either is NaN.
    let l = if l < f32::MAX { l } else { f32::MAX };
    let h = if h > -f32::MAX { h } else { -f32::MAX };
    (l, h)
}

/// Point `v`'s coordinates along [`Diag`]'s six directions (each rounded to nearest).
#[inline(always)]
pub(super) fn diag_sums(v: &crate::geom::P3) -> [f64; 6] {
    [
        v[0] + v[1],
        v[0] - v[1],
        v[0] + v[2],
        v[0] - v[2],
        v[1] + v[2],
        v[1] - v[2],
    ]
}

/// `f32` bounds below `lo` and above `hi`, two sums of corner coordinates each rounded to
/// nearest in `f64`: each moved out by 2^-21 of its size (past that rounding and the
/// rounding to `f32` below, each under 2^-23 of it) and 2^-140 (below the smallest normal
/// `f32`, where those relative errors are not bounded), then rounded to nearest `f32`; a
/// bound past the `f32` range stays finite on the side that keeps it conservative
/// (`f32::MAX` below a huge low, `-f32::MAX` above a huge negative high). No branch.
#[inline(always)]
fn outward(lo: f64, hi: f64) -> (f32, f32) {
    const REL: f64 = 1.0 / (1u64 << 21) as f64;
    const ABS: f64 = TINY as f64;
    let l = ((lo - lo.abs() * REL - ABS) as f32).min(f32::MAX);
    let h = ((hi + hi.abs() * REL + ABS) as f32).max(-f32::MAX);
    (l, h)
}

/// The [`Diag`] bounds of a sixteen-lane kernel: the lanes' (sixteen from `first`) in
/// AVX-512 registers, lo of the six directions then hi; the candidates' (`c0..c0 + n`)
/// read one by one.
#[cfg(target_arch = "x86_64")]
pub(super) struct DiagRun<'a> {
    lanes: [std::arch::x86_64::__m512; 12],
    cands: [&'a [f32]; 12],
}

#[cfg(target_arch = "x86_64")]
impl<'a> DiagRun<'a> {
    /// # Safety
    /// The CPU must support AVX-512F; `d` has entries `first..first + 16` (padding
    /// included) and `c0..c0 + n`.
    #[inline(always)]
    pub(super) unsafe fn new(d: &'a Diag, first: usize, c0: usize, n: usize) -> DiagRun<'a> {
        use std::arch::x86_64::*;
        let bound = |k: usize| if k < 6 { &d.lo[k] } else { &d.hi[k - 6] };
        // SAFETY: AVX-512F (the caller's promise).
        let mut lanes = [unsafe { _mm512_setzero_ps() }; 12];
        let mut cands: [&[f32]; 12] = [&[]; 12];
        for k in 0..12 {
            let v = &bound(k)[first..first + 2 * LANES];
            // SAFETY: sixteen floats; the load needs no alignment; AVX-512F (the caller's
            // promise).
            lanes[k] = unsafe { _mm512_loadu_ps(v.as_ptr()) };
            cands[k] = &bound(k)[c0..c0 + n];
        }
        DiagRun { lanes, cands }
    }

    /// The lanes among `keep` whose bounds meet candidate `c`'s (`c < n`) along all six
    /// directions: six independent chains of two compares, then their intersection.
    ///
    /// # Safety
    /// The CPU must support AVX-512F.
    #[inline(always)]
    pub(super) unsafe fn meet(&self, c: usize, keep: u16) -> u16 {
        use std::arch::x86_64::*;
        let mut all = keep;
        for k in 0..6 {
            let (lo, hi) = (self.lanes[k], self.lanes[k + 6]);
            let (clo, chi) = (self.cands[k][c], self.cands[k + 6][c]);
            // SAFETY: AVX-512F (the caller's promise).
            unsafe {
                let a = _mm512_mask_cmp_ps_mask::<_CMP_GE_OQ>(keep, hi, _mm512_set1_ps(clo));
                all &= _mm512_mask_cmp_ps_mask::<_CMP_LE_OQ>(a, lo, _mm512_set1_ps(chi));
            }
        }
        all
    }
}

#[cfg(test)]
/// Every path's diagonal bounds, triangle by triangle: from `f64` corners, and from
/// `f32` points through corner indices (AVX-512 where the CPU has it, and one by one).
pub(super) fn all_diags(points: &[[f32; 3]], corners: &[[u32; 3]]) -> Vec<Diag> {
    let tris: Vec<[crate::geom::P3; 3]> = corners
        .iter()
        .map(|c| c.map(|x| crate::geom::widen(&points[x as usize])))
        .collect();
    let (mut a, mut b) = (Diag::default(), Diag::default());
    a.set_triangles(&tris, false);
    b.set_corners(points, corners, true);
    let n = corners.len();
    let mut cols = vec![vec![0f32; n]; 12];
    let mut it = cols.iter_mut();
    let mut out: [&mut [f32]; 12] = std::array::from_fn(|_| it.next().unwrap().as_mut_slice());
    corner_bounds(points, corners, &mut out);
    for k in 0..6 {
        assert_eq!(
            (&b.lo[k][..n], &b.hi[k][..n]),
            (&cols[k][..], &cols[k + 6][..]),
            "AVX-512 and one by one, direction {k}"
        );
    }
    vec![a, b]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::Aabb;

    /// Each bound holds the exact sums of its triangle's corners (checked in `f64`, where
    /// a sum of two `f32` is exact or off by 2^-53 of it, far below the 2^-24 an `f32`
    /// rounding would leave), at every scale, far from the origin, with subnormal
    /// coordinates and sums past the `f32` range; no bound is NaN.
    #[test]
    fn diagonal_bounds_hold_their_triangles() {
        let mut rng = crate::geom::test_rng::Rng(3);
        let mut points: Vec<[f32; 3]> = Vec::new();
        for (scale, offset) in [
            (1.0, 0.0),
            (1e-30, 0.0),
            (1e30, 0.0),
            (1.0, 1e7),
            (3e38, 0.0),
            (1e-40, 0.0),
            (1e-3, -2e4),
        ] {
            for _ in 0..60 {
                points.push(std::array::from_fn(|_| (offset + scale * rng.f()) as f32));
            }
        }
        points.push([f32::MAX, f32::MAX, -f32::MAX]);
        points.push([-f32::MAX, f32::MAX, f32::MAX]);
        points.push([f32::MIN_POSITIVE / 8.0, -f32::MIN_POSITIVE / 4.0, 0.0]);
        let m = points.len();
        let corners: Vec<[u32; 3]> = (0..m - 2)
            .map(|i| [i as u32, i as u32 + 1, i as u32 + 2])
            .chain([[m as u32 - 1, m as u32 - 2, m as u32 - 3], [0, 60, 120]])
            .collect();
        for d in all_diags(&points, &corners) {
            assert_eq!(d.len(), corners.len());
            for (i, c) in corners.iter().enumerate() {
                for &x in c {
                    let s = diag_sums(&crate::geom::widen(&points[x as usize]));
                    for (k, &s) in s.iter().enumerate() {
                        let (lo, hi) = (d.lo[k][i], d.hi[k][i]);
                        assert!(!lo.is_nan() && !hi.is_nan(), "triangle {i} direction {k}");
                        assert!(
                            f64::from(lo) <= s && s <= f64::from(hi),
                            "triangle {i} direction {k}: {lo} {s} {hi}"
                        );
                    }
                }
            }
            // The padding meets nothing.
            assert!(!d.meets(0, corners.len()) && !d.meets(corners.len() + 3, 0));
        }
    }

    /// Triangles that meet (by the exact test) always have meeting diagonal bounds: a
    /// corner on the other's edge or face, a shared corner position under another index,
    /// crossing triangles, coplanar overlaps, at several scales and far from the origin;
    /// and the bounds do drop pairs (triangles whose boxes meet but that lie apart).
    #[test]
    fn diagonal_bounds_never_part_meeting_triangles() {
        use crate::geom::tritri::triangles_intersect;
        let mut rng = crate::geom::test_rng::Rng(17);
        let (mut met, mut dropped, mut boxed) = (0, 0, 0);
        for round in 0..3000 {
            let (scale, offset) = [(1.0, 0.0), (1e-20, 0.0), (1e20, 0.0), (1.0, 3e6)][round % 4];
            let at = |rng: &mut crate::geom::test_rng::Rng| -> [f32; 3] {
                std::array::from_fn(|_| (offset + scale * rng.f()) as f32)
            };
            let a = [at(&mut rng), at(&mut rng), at(&mut rng)];
            // The other triangle: random, or touching `a` through a point of it that `f32`
            // holds exactly (a corner, or an edge's midpoint where it rounds back).
            let mut b = [at(&mut rng), at(&mut rng), at(&mut rng)];
            match round % 3 {
                1 => b[0] = a[rng.below(3)],
                2 => {
                    let (p, q) = (a[rng.below(3)], a[rng.below(3)]);
                    b[0] = std::array::from_fn(|k| (p[k] + q[k]) * 0.5);
                }
                _ => {}
            }
            let points = [a[0], a[1], a[2], b[0], b[1], b[2]];
            let corners = [[0, 1, 2], [3, 4, 5]];
            let (ta, tb) = (
                a.map(|p| crate::geom::widen(&p)),
                b.map(|p| crate::geom::widen(&p)),
            );
            let meet = triangles_intersect(&ta, &tb);
            let box_of = |t: &[[f32; 3]; 3]| {
                let mut x = Aabb::EMPTY;
                t.iter().for_each(|p| x.grow(p));
                x
            };
            let boxes_meet = box_of(&a).overlaps(&box_of(&b), 0.0);
            for d in all_diags(&points, &corners) {
                if meet {
                    assert!(d.meets(0, 1) && d.meets(1, 0), "round {round}: {a:?} {b:?}");
                    met += 1;
                } else if boxes_meet {
                    boxed += 1;
                    dropped += usize::from(!d.meets(0, 1));
                }
            }
        }
        assert!(met > 2000, "{met} meeting pairs");
        assert!(
            dropped > boxed / 5,
            "{dropped} of {boxed} box-meeting pairs dropped"
        );
    }

    /// A run's union is the least low and the greatest high of its entries, for runs of 1
    /// to 16 entries (the last one ending at the padding), whole and in chunks shared out.
    #[test]
    fn union_is_the_runs_least_and_greatest() {
        let mut rng = crate::geom::test_rng::Rng(31);
        let points: Vec<[f32; 3]> = (0..600).map(|_| rng.v(10.0).map(|x| x as f32)).collect();
        let corners: Vec<[u32; 3]> = (0..5000)
            .map(|_| [0, 1, 2].map(|_| rng.below(600) as u32))
            .collect();
        let mut starts = vec![0u32];
        while (*starts.last().unwrap() as usize) < corners.len() {
            let next = *starts.last().unwrap() as usize + 1 + rng.below(16);
            starts.push(next.min(corners.len()) as u32);
        }
        for d in all_diags(&points, &corners) {
            for par in [false, true] {
                let mut u = Diag::default();
                u.set_union(&d, &starts, par);
                assert_eq!(u.len(), starts.len() - 1);
                for (s, w) in starts.windows(2).enumerate() {
                    let r = w[0] as usize..w[1] as usize;
                    for k in 0..6 {
                        let lo = r.clone().map(|i| d.lo[k][i]).fold(f32::INFINITY, f32::min);
                        let hi = r
                            .clone()
                            .map(|i| d.hi[k][i])
                            .fold(f32::NEG_INFINITY, f32::max);
                        assert_eq!((u.lo[k][s], u.hi[k][s]), (lo, hi), "run {s} direction {k}");
                    }
                }
            }
        }
    }
}
