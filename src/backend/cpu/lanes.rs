//! Boxes stored coordinate by coordinate ("structure of arrays") and tested against one box
//! eight at a time: with AVX2 (checked at run time on x86-64) that is six packed compares
//! and a bit mask per eight boxes, several times cheaper than testing them one by one. A
//! self-colliding mesh's sub-leaves (at most sixteen boxes) are tested sixteen at a time,
//! in one AVX-512 register per bound where the CPU has AVX-512F.

pub(crate) use super::diag::Diag;
use super::diag::DiagRun;
use crate::geom::Aabb;
use crate::mesh::Mesh;

/// Boxes tested together.
pub(super) const LANES: usize = 8;
/// Padding after the boxes: two chunks ([`Lanes::each_pair_16`] reads sixteen boxes).
pub(super) const PAD: usize = 2 * LANES;

/// `len` boxes followed by [`PAD`] padding boxes that meet nothing (min `+inf`, max
/// `-inf`), so that the sixteen boxes from any position below `len` can be read.
#[derive(Clone, Debug, Default)]
pub(crate) struct Lanes {
    lo: [Vec<f32>; 3],
    hi: [Vec<f32>; 3],
}

impl Lanes {
    /// Number of boxes (padding not counted).
    #[inline]
    pub fn len(&self) -> usize {
        self.lo[0].len().saturating_sub(PAD)
    }

    /// Makes room for `n` boxes (their contents unspecified), padded.
    pub fn resize(&mut self, n: usize) {
        for k in 0..3 {
            self.lo[k].resize(n, f32::INFINITY);
            self.lo[k].truncate(n);
            self.lo[k].resize(n + PAD, f32::INFINITY);
            self.hi[k].resize(n, f32::NEG_INFINITY);
            self.hi[k].truncate(n);
            self.hi[k].resize(n + PAD, f32::NEG_INFINITY);
        }
    }

    /// The boxes become `boxes` grown by `h` ([`Aabb::grown`]), padded; in one pass over
    /// `boxes` (not one per bound: the reads cost more than the arithmetic), shared between
    /// the caller's worker threads with `par` (inside a pool).
    pub fn set_grown(&mut self, boxes: &[Aabb], h: f64, par: bool) {
        use rayon::prelude::*;
        const CHUNK: usize = 2048;
        let n = boxes.len();
        self.resize(n);
        let [lx, ly, lz] = &mut self.lo;
        let [hx, hy, hz] = &mut self.hi;
        // The six bounds' chunks side by side.
        let mut bounds: Vec<[&mut [f32]; 6]> = lx[..n]
            .chunks_mut(CHUNK)
            .zip(ly[..n].chunks_mut(CHUNK))
            .zip(lz[..n].chunks_mut(CHUNK))
            .zip(hx[..n].chunks_mut(CHUNK))
            .zip(hy[..n].chunks_mut(CHUNK))
            .zip(hz[..n].chunks_mut(CHUNK))
            .map(|(((((a, b), c), d), e), f)| [a, b, c, d, e, f])
            .collect();
        let fill = |(boxes, out): (&[Aabb], &mut [&mut [f32]; 6])| {
            for (i, b) in boxes.iter().enumerate() {
                let g = b.grown(h);
                for k in 0..3 {
                    out[k][i] = g.min[k];
                    out[k + 3][i] = g.max[k];
                }
            }
        };
        if par {
            boxes
                .par_chunks(CHUNK)
                .zip(bounds.par_iter_mut())
                // One job a chunk: a worker done early takes over a slower one's.
                .with_max_len(1)
                .for_each(fill);
        } else {
            boxes.chunks(CHUNK).zip(bounds.iter_mut()).for_each(fill);
        }
    }

    /// Box `i` (`i < len`).
    #[inline]
    pub fn set(&mut self, i: usize, b: &Aabb) {
        for k in 0..3 {
            self.lo[k][i] = b.min[k];
            self.hi[k][i] = b.max[k];
        }
    }

    /// Boxes `range` become those of `m`'s leaf-ordered polygons `range`
    /// ([`Mesh::poly_box`], in one pass; one by one under a placement or for an f64 mesh).
    pub fn fit_polygons(&mut self, m: &Mesh, range: std::ops::Range<usize>) {
        if m.needs_cpu() {
            for p in range {
                self.set(p, &m.poly_box(p));
            }
            return;
        }
        let corners = &m.polys[range.start * m.k..range.end * m.k];
        if m.k == 3 {
            self.fit::<3>(corners, &m.slots, range.start);
        } else {
            self.fit::<4>(corners, &m.slots, range.start);
        }
    }

    fn fit<const K: usize>(&mut self, corners: &[u32], slots: &[[f32; 3]], first: usize) {
        let n = corners.len() / K;
        let [lx, ly, lz] = &mut self.lo;
        let [hx, hy, hz] = &mut self.hi;
        let r = first..first + n;
        let (lx, ly, lz) = (&mut lx[r.clone()], &mut ly[r.clone()], &mut lz[r.clone()]);
        let (hx, hy, hz) = (&mut hx[r.clone()], &mut hy[r.clone()], &mut hz[r]);
        for (i, c) in corners.chunks_exact(K).enumerate() {
            let (mut lo, mut hi) = (slots[c[0] as usize], slots[c[0] as usize]);
            for &v in &c[1..] {
                let p = slots[v as usize];
                for k in 0..3 {
                    lo[k] = if p[k] < lo[k] { p[k] } else { lo[k] };
                    hi[k] = if p[k] > hi[k] { p[k] } else { hi[k] };
                }
            }
            (lx[i], ly[i], lz[i]) = (lo[0], lo[1], lo[2]);
            (hx[i], hy[i], hz[i]) = (hi[0], hi[1], hi[2]);
        }
    }

    #[inline]
    pub fn get(&self, i: usize) -> Aabb {
        Aabb {
            min: [self.lo[0][i], self.lo[1][i], self.lo[2][i]],
            max: [self.hi[0][i], self.hi[1][i], self.hi[2][i]],
        }
    }

    /// Calls `f(i)` for every box `i` of `range` (`range.end <= len`) that meets `b`
    /// (closed boxes), in ascending order. `masks` is scratch.
    #[inline]
    pub fn each_meeting(
        &self,
        range: std::ops::Range<usize>,
        b: &Aabb,
        masks: &mut Vec<u32>,
        mut f: impl FnMut(u32),
    ) {
        self.each_pair(range, std::slice::from_ref(b), masks, |i, _| f(i));
    }

    /// Appends the positions in `range` of the boxes that meet `b`.
    #[inline]
    pub fn select(
        &self,
        range: std::ops::Range<usize>,
        b: &Aabb,
        masks: &mut Vec<u32>,
        out: &mut Vec<u32>,
    ) {
        self.each_meeting(range, b, masks, |i| out.push(i));
    }

    /// Calls `f(i, c)` for every box `i` of `range` (`range.end <= len`) that meets
    /// `cands[c]`, candidate after candidate, in ascending order for each (for very large
    /// requests, past 2^24 chunk tests, block of the range by block). `masks` is scratch.
    pub fn each_pair(
        &self,
        range: std::ops::Range<usize>,
        cands: &[Aabb],
        masks: &mut Vec<u32>,
        mut f: impl FnMut(u32, u32),
    ) {
        assert!(range.end <= self.len());
        // A mask entry names (candidate, chunk) in 24 bits: blocks of at most 2^12
        // candidates and 2^12 chunks keep every name in range.
        const BLOCK: usize = 1 << 12;
        if cands.len() * range.len().div_ceil(LANES) < 1 << 24 {
            return self.each_pair_block(range, cands, 0, masks, &mut f);
        }
        for start in range.clone().step_by(BLOCK * LANES) {
            let r = start..(start + BLOCK * LANES).min(range.end);
            for (b, block) in cands.chunks(BLOCK).enumerate() {
                self.each_pair_block(r.clone(), block, (b * BLOCK) as u32, masks, &mut f);
            }
        }
    }

    /// [`Lanes::each_pair`] for a range of at most 16 boxes (a self-colliding mesh's
    /// sub-leaf), the same calls in the same order: each candidate's bits of both chunks
    /// in one word, taken at once (no mask buffer, no division to name an entry). With
    /// `upper` (the candidates are the range's own boxes), candidate `c` is paired with
    /// the boxes after it only: each unordered pair once, no box with itself.
    #[inline]
    pub fn each_pair_16(
        &self,
        range: std::ops::Range<usize>,
        cands: &[Aabb],
        upper: bool,
        mut f: impl FnMut(u32, u32),
    ) {
        assert!(range.end <= self.len() && range.len() <= 2 * LANES);
        assert!(!upper || cands.len() == range.len());
        if range.is_empty() {
            return;
        }
        let keep = (1u32 << range.len()) - 1;
        let first = range.start as u32;
        // Sixteen candidates' masks first, the calls after: a call inside the compare loop
        // would make the bound registers be saved and reloaded around it.
        for (block, cs) in cands.chunks(16).enumerate() {
            let masks = self.masks_16(range.start, cs, keep);
            for (i, &m) in masks[..cs.len()].iter().enumerate() {
                let c = 16 * block + i;
                let mut bits = u32::from(m & lanes_kept(keep, upper, c));
                while bits != 0 {
                    f(first + bits.trailing_zeros(), c as u32);
                    bits &= bits - 1;
                }
            }
        }
    }

    /// [`Lanes::each_pair_16`]'s pairs for at most sixteen candidates (a sub-leaf),
    /// appended to `out` as `[range.start + i, c0 + c]`, in the same order, less those
    /// `excl` names (bit `i` of `excl[c]`: box `range.start + i` with candidate `c`; one
    /// entry per candidate) and, with `diag`, those apart along a diagonal (counted: the
    /// result). Where the CPU has AVX-512F, without a call or a branch per pair: each
    /// candidate meeting a box has its sixteen answers compressed into pairs in registers
    /// and stored whole (the stores past the new end land in capacity reserved first).
    /// A self-colliding mesh's pairs sharing a vertex are left out this way (the mesh's
    /// topology says which; see `query::neighbours`): all that is listed goes to one list
    /// (the exact test), so no per-pair decision is left for a call to make.
    #[allow(clippy::too_many_arguments)]
    #[inline]
    pub fn pairs_16(
        &self,
        range: std::ops::Range<usize>,
        cands: &[Aabb],
        c0: u32,
        upper: bool,
        diag: Option<&Diag>,
        excl: Option<&[u16]>,
        out: &mut Vec<[u32; 2]>,
    ) -> usize {
        assert!(range.end <= self.len() && range.len() <= 2 * LANES && cands.len() <= 16);
        assert!(!upper || cands.len() == range.len());
        assert!(diag.is_none_or(|d| d.len() == self.len()));
        assert!(excl.is_none_or(|e| e.len() == cands.len()));
        if range.is_empty() {
            return 0;
        }
        #[cfg(target_arch = "x86_64")]
        if std::is_x86_feature_detected!("avx512f") && std::is_x86_feature_detected!("popcnt") {
            let keep = (1u32 << range.len()) - 1;
            let run = self.run(range.start..range.start + 2 * LANES);
            // SAFETY: the CPU supports AVX-512F and POPCNT, checked just above; `run` holds
            // sixteen boxes (the padding included), `diag` as many entries as the lanes,
            // `excl` one per candidate.
            return unsafe {
                let first = range.start as u32;
                let kernel = match (diag.is_some(), excl.is_some()) {
                    (true, true) => pairs_16_avx512::<true, true>,
                    (true, false) => pairs_16_avx512::<true, false>,
                    (false, true) => pairs_16_avx512::<false, true>,
                    (false, false) => pairs_16_avx512::<false, false>,
                };
                kernel(&run, cands, keep, upper, first, c0, diag, excl, out)
            };
        }
        self.pairs_16_plain(range, cands, c0, upper, diag, excl, out)
    }

    /// [`Lanes::pairs_16`] pair by pair (any CPU).
    #[allow(clippy::too_many_arguments)]
    fn pairs_16_plain(
        &self,
        range: std::ops::Range<usize>,
        cands: &[Aabb],
        c0: u32,
        upper: bool,
        diag: Option<&Diag>,
        excl: Option<&[u16]>,
        out: &mut Vec<[u32; 2]>,
    ) -> usize {
        let (first, mut culled) = (range.start as u32, 0);
        self.each_pair_16(range, cands, upper, |i, c| {
            if excl.is_some_and(|e| e[c as usize] >> (i - first) & 1 == 1) {
                return;
            }
            if diag.is_some_and(|d| !d.meets(i as usize, (c0 + c) as usize)) {
                culled += 1;
            } else {
                out.push([i, c0 + c]);
            }
        });
        culled
    }

    /// For each of `cands` (at most 16), the boxes of the 16 from `start` (padding
    /// included) that meet it, as bits, within `keep`: in AVX2 where the CPU has it, else
    /// one box at a time (where it has AVX-512, [`Lanes::pairs_16`] tests them in
    /// [`Boxes16`]).
    #[inline]
    fn masks_16(&self, start: usize, cands: &[Aabb], keep: u32) -> [u16; 16] {
        debug_assert!(cands.len() <= 16);
        let run = self.run(start..start + 2 * LANES);
        #[cfg(target_arch = "x86_64")]
        if std::is_x86_feature_detected!("avx2") {
            // SAFETY: the CPU supports AVX2, checked just above.
            return unsafe { masks_16_avx2(&run, cands, keep) };
        }
        masks_16_plain(&run, cands, keep)
    }

    /// [`Lanes::each_pair`] for `cands.len() * chunks < 2^24`, candidates numbered from
    /// `c0`.
    fn each_pair_block(
        &self,
        range: std::ops::Range<usize>,
        cands: &[Aabb],
        c0: u32,
        masks: &mut Vec<u32>,
        f: &mut impl FnMut(u32, u32),
    ) {
        if range.is_empty() {
            return;
        }
        let chunks = range.len().div_ceil(LANES);
        debug_assert!(cands.len() * chunks < 1 << 24);
        if masks.len() < chunks * cands.len() {
            masks.resize(chunks * cands.len(), 0);
        }
        let run = self.run(range.start..range.start + chunks * LANES);
        #[cfg(target_arch = "x86_64")]
        let found = if std::is_x86_feature_detected!("avx2") {
            // SAFETY: the CPU supports AVX2, checked just above.
            unsafe { masks_avx2(&run, cands, masks) }
        } else {
            masks_plain(&run, cands, masks)
        };
        #[cfg(not(target_arch = "x86_64"))]
        let found = masks_plain(&run, cands, masks);
        // The last chunk reaches past the range: drop its extra lanes.
        let last = (1u32 << (range.len() - (chunks - 1) * LANES)) - 1;
        let first = range.start as u32;
        for &e in &masks[..found] {
            let (at, mut bits) = (e >> 8, e & 0xff);
            let (c, j) = (at / chunks as u32, at % chunks as u32);
            if j + 1 == chunks as u32 {
                bits &= last;
            }
            while bits != 0 {
                f(first + j * LANES as u32 + bits.trailing_zeros(), c0 + c);
                bits &= bits - 1;
            }
        }
    }

    /// The bounds of the boxes in `range`: lo xyz, hi xyz.
    #[inline]
    fn run(&self, range: std::ops::Range<usize>) -> [&[f32]; 6] {
        let (lo, hi) = (&self.lo, &self.hi);
        [
            &lo[0][range.clone()],
            &lo[1][range.clone()],
            &lo[2][range.clone()],
            &hi[0][range.clone()],
            &hi[1][range.clone()],
            &hi[2][range],
        ]
    }
}

/// Box `i` of `run` (bounds lo xyz, hi xyz) meets `b` (closed boxes).
#[inline(always)]
fn meets(run: &[&[f32]; 6], i: usize, b: &Aabb) -> bool {
    (run[3][i] >= b.min[0])
        & (run[0][i] <= b.max[0])
        & (run[4][i] >= b.min[1])
        & (run[1][i] <= b.max[1])
        & (run[5][i] >= b.min[2])
        & (run[2][i] <= b.max[2])
}

/// Box tests of every candidate `c` against every chunk `j` of [`LANES`] boxes of `run`
/// (bounds lo xyz, hi xyz, of one length, a multiple of [`LANES`]), in that order: for each
/// chunk where boxes meet, `masks` gets `(c * chunks + j) << 8 | bits` (bit `l` for box
/// `j * LANES + l`), one after the other (it must have room for all). Returns how many.
#[inline(always)]
fn masks_plain(run: &[&[f32]; 6], cands: &[Aabb], masks: &mut [u32]) -> usize {
    let chunks = run[0].len() / LANES;
    let mut found = 0;
    for (c, b) in cands.iter().enumerate() {
        for j in 0..chunks {
            let mut bits = 0;
            for l in 0..LANES {
                bits |= u32::from(meets(run, j * LANES + l, b)) << l;
            }
            if bits != 0 {
                masks[found] = ((c * chunks + j) as u32) << 8 | bits;
                found += 1;
            }
        }
    }
    found
}

/// Eight boxes (bounds loaded: lo xyz, hi xyz) against one (broadcast: min xyz, max xyz):
/// the bits of those that meet it (closed boxes). (A safe function with a target feature:
/// callable from the AVX2 kernels below, which have it.)
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
#[inline]
fn meet8(
    lo: &[std::arch::x86_64::__m256; 3],
    hi: &[std::arch::x86_64::__m256; 3],
    min: &[std::arch::x86_64::__m256; 3],
    max: &[std::arch::x86_64::__m256; 3],
) -> u32 {
    use std::arch::x86_64::*;
    // Ordered, non-signalling compares: `>=` and `<=` as in Rust.
    let axis = |k: usize| {
        _mm256_and_ps(
            _mm256_cmp_ps::<_CMP_GE_OQ>(hi[k], min[k]),
            _mm256_cmp_ps::<_CMP_LE_OQ>(lo[k], max[k]),
        )
    };
    _mm256_movemask_ps(_mm256_and_ps(axis(0), _mm256_and_ps(axis(1), axis(2)))) as u32
}

/// [`masks_plain`], eight boxes per AVX2 compare.
///
/// # Safety
/// The CPU must support AVX2.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn masks_avx2(run: &[&[f32]; 6], cands: &[Aabb], masks: &mut [u32]) -> usize {
    use std::arch::x86_64::*;
    let chunks = run[0].len() / LANES;
    // SAFETY: each chunk holds eight floats; the loads need no alignment.
    let ld = |k: usize, j: usize| unsafe { _mm256_loadu_ps(run[k][j * LANES..].as_ptr()) };
    let mut found = 0;
    let mut at = 0u32;
    for b in cands {
        let min = b.min.map(|x| _mm256_set1_ps(x));
        let max = b.max.map(|x| _mm256_set1_ps(x));
        for j in 0..chunks {
            let (lo, hi) = (
                [ld(0, j), ld(1, j), ld(2, j)],
                [ld(3, j), ld(4, j), ld(5, j)],
            );
            let bits = meet8(&lo, &hi, &min, &max);
            if bits != 0 {
                masks[found] = at << 8 | bits;
                found += 1;
            }
            at += 1;
        }
    }
    found
}

/// [`Lanes::masks_16`] one box at a time (no AVX2): `run` holds sixteen boxes.
fn masks_16_plain(run: &[&[f32]; 6], cands: &[Aabb], keep: u32) -> [u16; 16] {
    let mut masks = [0u16; 16];
    for (m, b) in masks.iter_mut().zip(cands) {
        let mut bits = 0u32;
        for i in 0..2 * LANES {
            bits |= u32::from(meets(run, i, b)) << i;
        }
        *m = (bits & keep) as u16;
    }
    masks
}

/// [`Lanes::masks_16`] in AVX2: the sixteen boxes loaded once (two chunks), each
/// candidate compared with both.
///
/// # Safety
/// The CPU must support AVX2; `run` holds sixteen boxes.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn masks_16_avx2(run: &[&[f32]; 6], cands: &[Aabb], keep: u32) -> [u16; 16] {
    use std::arch::x86_64::*;
    // SAFETY: each slice holds sixteen floats; the loads need no alignment.
    let ld = |k: usize, h: usize| unsafe { _mm256_loadu_ps(run[k][h * LANES..].as_ptr()) };
    let lo = [0, 1].map(|h| [ld(0, h), ld(1, h), ld(2, h)]);
    let hi = [0, 1].map(|h| [ld(3, h), ld(4, h), ld(5, h)]);
    let mut masks = [0u16; 16];
    for (m, b) in masks.iter_mut().zip(cands) {
        let min = b.min.map(|x| _mm256_set1_ps(x));
        let max = b.max.map(|x| _mm256_set1_ps(x));
        let bits = meet8(&lo[0], &hi[0], &min, &max) | meet8(&lo[1], &hi[1], &min, &max) << LANES;
        *m = (bits & keep) as u16;
    }
    masks
}

/// Sixteen boxes in AVX-512 registers, one per bound (lo xyz, hi xyz).
#[cfg(target_arch = "x86_64")]
#[derive(Clone, Copy)]
struct Boxes16([std::arch::x86_64::__m512; 6]);

#[cfg(target_arch = "x86_64")]
impl Boxes16 {
    /// # Safety
    /// The CPU must support AVX-512F; `run` holds sixteen boxes.
    #[target_feature(enable = "avx512f")]
    #[inline]
    unsafe fn load(run: &[&[f32]; 6]) -> Boxes16 {
        // SAFETY: each slice holds sixteen floats (the caller's promise); the loads need
        // no alignment.
        Boxes16(run.map(|r| unsafe { std::arch::x86_64::_mm512_loadu_ps(r.as_ptr()) }))
    }

    /// The boxes among `keep` that meet `b` (closed), as bits: each axis's two compares
    /// chained through a mask register (the second only where the first held).
    #[target_feature(enable = "avx512f")]
    #[inline]
    fn meet(&self, b: &Aabb, keep: u16) -> u16 {
        use std::arch::x86_64::*;
        let [lx, ly, lz, hx, hy, hz] = self.0;
        // Ordered, non-signalling compares: `>=` and `<=` as in Rust.
        let x = _mm512_mask_cmp_ps_mask::<_CMP_GE_OQ>(keep, hx, _mm512_set1_ps(b.min[0]));
        let x = _mm512_mask_cmp_ps_mask::<_CMP_LE_OQ>(x, lx, _mm512_set1_ps(b.max[0]));
        let y = _mm512_mask_cmp_ps_mask::<_CMP_GE_OQ>(keep, hy, _mm512_set1_ps(b.min[1]));
        let y = _mm512_mask_cmp_ps_mask::<_CMP_LE_OQ>(y, ly, _mm512_set1_ps(b.max[1]));
        let z = _mm512_mask_cmp_ps_mask::<_CMP_GE_OQ>(keep, hz, _mm512_set1_ps(b.min[2]));
        let z = _mm512_mask_cmp_ps_mask::<_CMP_LE_OQ>(z, lz, _mm512_set1_ps(b.max[2]));
        x & y & z
    }
}

/// The lanes `c`'s sixteen boxes keep: all those of `keep` or, with `upper` (a range
/// against its own boxes), those after `c`.
#[inline]
fn lanes_kept(keep: u32, upper: bool, c: usize) -> u16 {
    (if upper {
        keep & !((2u32 << c) - 1)
    } else {
        keep
    }) as u16
}

/// Each candidate's lanes that meet it ([`Boxes16::meet`], within [`lanes_kept`]), and
/// the candidates that meet any as bits; `EXCL`: less the lanes `excl[c]` names (an entry
/// per candidate; not read otherwise).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f")]
#[inline]
fn meets16<const EXCL: bool>(
    boxes: &Boxes16,
    cands: &[Aabb],
    keep: u32,
    upper: bool,
    excl: &[u16],
) -> ([u16; 16], u32) {
    let (mut masks, mut hit) = ([0u16; 16], 0);
    for (c, (b, m)) in cands.iter().zip(&mut masks).enumerate() {
        let mut kept = lanes_kept(keep, upper, c);
        if EXCL {
            kept &= !excl[c];
        }
        *m = boxes.meet(b, kept);
        hit |= u32::from(*m != 0) << c;
    }
    (masks, hit)
}

/// Pair words of sixteen lanes (64 bits each: `[i, c]` as two `u32`, little-endian) in two
/// registers, lanes 0-7 and 8-15: the lanes `first..first + 16` with candidate `c`.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f")]
#[inline]
fn pair_words(first: u32, c: u32) -> [std::arch::x86_64::__m512i; 2] {
    use std::arch::x86_64::*;
    let c = _mm512_set1_epi64(i64::from(c) << 32);
    let lo = _mm512_add_epi64(
        _mm512_set1_epi64(i64::from(first)),
        _mm512_setr_epi64(0, 1, 2, 3, 4, 5, 6, 7),
    );
    let hi = _mm512_add_epi64(lo, _mm512_set1_epi64(8));
    [_mm512_or_si512(lo, c), _mm512_or_si512(hi, c)]
}

/// Appends the pairs of the lanes in `m` to the list at `base` of length `*len`: each half
/// compressed to the front of its register and stored whole (eight pairs), the length
/// advanced by its count. No branch: a candidate meeting nothing costs the same stores.
///
/// # Safety
/// The CPU must support AVX-512F and POPCNT; `*len + 24` pairs fit in the allocation at
/// `base` (sixteen appended, and one whole store past them).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f,popcnt")]
#[inline]
unsafe fn append16(
    base: *mut [u32; 2],
    len: &mut usize,
    m: u16,
    pairs: &[std::arch::x86_64::__m512i; 2],
) {
    use std::arch::x86_64::*;
    for (half, words) in [m as u8, (m >> 8) as u8].into_iter().zip(pairs) {
        let packed = _mm512_maskz_compress_epi64(half, *words);
        // SAFETY: `*len + 16 <= capacity` here (the caller's promise, at most eight pairs
        // appended before), and a `[u32; 2]` is eight bytes: the store writes inside the
        // allocation; it needs no alignment.
        unsafe { _mm512_storeu_si512(base.add(*len).cast(), packed) };
        *len += half.count_ones() as usize;
    }
}

/// [`Lanes::pairs_16`] in AVX-512: per candidate, the meeting lanes' pairs appended
/// ([`append16`]). `DIAG`: `diag` is given; `EXCL`: `excl` is (each compiled apart, so
/// that the kernel without them keeps no trace of their code or registers).
///
/// # Safety
/// The CPU must support AVX-512F and POPCNT; `run` holds sixteen boxes; `excl`, when
/// given, an entry per candidate.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f,popcnt")]
#[allow(clippy::too_many_arguments)]
unsafe fn pairs_16_avx512<const DIAG: bool, const EXCL: bool>(
    run: &[&[f32]; 6],
    cands: &[Aabb],
    keep: u32,
    upper: bool,
    first: u32,
    c0: u32,
    diag: Option<&Diag>,
    excl: Option<&[u16]>,
    out: &mut Vec<[u32; 2]>,
) -> usize {
    // SAFETY: the caller's promise.
    let boxes = unsafe { Boxes16::load(run) };
    let mut culled = 0;
    // Every candidate's boxes first, then the candidates that meet one (a fifth of them
    // between two sub-leaves of a crumpled cloth): the stores cost more than the tests.
    let (masks, mut hit) = meets16::<EXCL>(&boxes, cands, keep, upper, excl.unwrap_or(&[]));
    // The diagonal bounds read only where some box meets.
    // SAFETY: as many entries as the lanes, padded (the caller's promise).
    let diag = diag
        .filter(|_| DIAG && hit != 0)
        .map(|d| unsafe { DiagRun::new(d, first as usize, c0 as usize, cands.len()) });
    // Room for sixteen pairs per candidate and one whole store past the last.
    out.reserve(16 * cands.len() + 8);
    let (mut len, base) = (out.len(), out.as_mut_ptr());
    while hit != 0 {
        let c = hit.trailing_zeros() as usize;
        hit &= hit - 1;
        let mut m = masks[c];
        if let Some(d) = &diag {
            // SAFETY: AVX-512F (the caller's promise); `c` is a candidate.
            let kept = unsafe { d.meet(c, m) };
            culled += (m & !kept).count_ones() as usize;
            m = kept;
        }
        // SAFETY: at most sixteen pairs appended per candidate so far: room reserved.
        unsafe { append16(base, &mut len, m, &pair_words(first, c0 + c as u32)) };
    }
    // SAFETY: the pairs up to `len` were all written, within capacity.
    unsafe { out.set_len(len) };
    culled
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Per candidate of `others`, the lanes of `range` whose polygon shares a vertex index
    /// with it (the first `k` of `verts` count): what a self-colliding mesh's topology gives
    /// [`Lanes::pairs_16`] to leave out.
    fn sharing(
        verts: &[[u32; 4]],
        k: usize,
        range: std::ops::Range<usize>,
        others: std::ops::Range<usize>,
    ) -> Vec<u16> {
        others
            .map(|q| {
                range.clone().enumerate().fold(0u16, |m, (i, p)| {
                    let shares = verts[p][..k].iter().any(|v| verts[q][..k].contains(v));
                    m | u16::from(shares) << i
                })
            })
            .collect()
    }

    /// [`Lanes::pairs_16`] with diagonal bounds against a brute force: the pairs of the
    /// bounds-free lists, less those whose triangles lie apart along a diagonal by more
    /// than 10^-3 (computed here in `f64` from the corners; the corners are hundredths, so
    /// a pair's gap is either at most rounding or at least 10^-2), counted; with the pairs
    /// sharing a vertex left out too; AVX-512 and one by one alike.
    #[test]
    fn diagonal_bounds_drop_pairs_apart_along_a_diagonal() {
        let mut rng = crate::geom::test_rng::Rng(23);
        let n = 61;
        let points: Vec<[f32; 3]> = (0..40)
            .map(|i| {
                let x = 0.2 * i as f32;
                [
                    x + rng.below(100) as f32 / 100.0,
                    rng.below(100) as f32 / 100.0,
                    rng.below(100) as f32 / 100.0,
                ]
            })
            .collect();
        let corners: Vec<[u32; 3]> = (0..n)
            .map(|i| {
                let base = (i * 2 / 3).min(36);
                [0, 1, 2].map(|_| (base + rng.below(4)) as u32)
            })
            .collect();
        let tris: Vec<[P; 3]> = corners
            .iter()
            .map(|c| c.map(|x| points[x as usize]))
            .collect();
        type P = [f32; 3];
        let boxes: Vec<Aabb> = tris
            .iter()
            .map(|t| {
                let mut b = Aabb::EMPTY;
                t.iter().for_each(|p| b.grow(p));
                b
            })
            .collect();
        let mut lanes = Lanes::default();
        lanes.resize(n);
        for (i, b) in boxes.iter().enumerate() {
            lanes.set(i, b);
        }
        let gap = |p: usize, q: usize| {
            let ext = |t: &[P; 3], k: usize| {
                let s: Vec<f64> = t
                    .iter()
                    .map(|v| super::super::diag::diag_sums(&crate::geom::widen(v))[k])
                    .collect();
                (
                    s.iter().copied().fold(f64::INFINITY, f64::min),
                    s.iter().copied().fold(f64::NEG_INFINITY, f64::max),
                )
            };
            (0..6)
                .map(|k| {
                    let ((a0, a1), (b0, b1)) = (ext(&tris[p], k), ext(&tris[q], k));
                    (b0 - a1).max(a0 - b1)
                })
                .fold(f64::NEG_INFINITY, f64::max)
        };
        let verts: Vec<[u32; 4]> = corners
            .iter()
            .map(|c| [c[0], c[1], c[2], u32::MAX])
            .collect();
        let mut checked = [0usize; 2];
        for diag in super::super::diag::all_diags(&points, &corners) {
            for (range, others) in [
                (0..16, 16..32),
                (3..19, 3..19),
                (40..53, 20..36),
                (45..61, 45..61),
                (5..6, 0..16),
            ] {
                let upper = range == others;
                let (mut want_all, mut want_apart, mut want_cut) = (Vec::new(), Vec::new(), 0);
                for (c, q) in others.clone().enumerate() {
                    for p in range.clone() {
                        if (upper && p <= range.start + c) || !boxes[p].overlaps(&boxes[q], 0.0) {
                            continue;
                        }
                        let g = gap(p, q);
                        assert!(g <= 1e-3 || g >= 1e-2, "gap {g}");
                        let pair = [p as u32, q as u32];
                        let shared = (0..3)
                            .filter(|&ci| verts[q][..3].contains(&verts[p][ci]))
                            .fold(0u8, |b, ci| b | 1 << ci);
                        if g > 1e-3 {
                            assert_eq!(shared, 0, "triangles sharing a corner apart");
                            want_cut += 1;
                            continue;
                        }
                        want_all.push(pair);
                        if shared == 0 {
                            want_apart.push(pair);
                        }
                    }
                }
                checked[0] += want_cut;
                checked[1] += want_all.len();
                let cands = &boxes[others.clone()];
                let mut all = Vec::new();
                let c0 = others.start as u32;
                let cut =
                    lanes.pairs_16(range.clone(), cands, c0, upper, Some(&diag), None, &mut all);
                assert_eq!(
                    (all, cut),
                    (want_all, want_cut),
                    "pairs_16 {range:?} {others:?}"
                );
                // Pairs sharing a vertex left out: they are never apart along a diagonal,
                // so the same count is dropped.
                let excl = sharing(&verts, 3, range.clone(), others.clone());
                let want = (want_apart, want_cut);
                for plain in [false, true] {
                    let (d, e, mut apart) = (Some(&diag), Some(&excl[..]), Vec::new());
                    let got = if plain {
                        lanes.pairs_16_plain(range.clone(), cands, c0, upper, d, e, &mut apart)
                    } else {
                        lanes.pairs_16(range.clone(), cands, c0, upper, d, e, &mut apart)
                    };
                    assert_eq!(
                        (apart, got),
                        want,
                        "pairs_16 {range:?} {others:?} leaving out, plain {plain}"
                    );
                }
            }
        }
        assert!(
            checked[0] > 20 && checked[1] > 20,
            "{checked:?} pairs dropped / kept"
        );
    }

    #[test]
    fn each_meeting_matches_one_by_one_tests() {
        let mut s = 7u64;
        let mut rnd = || {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            (s >> 40) as f32 / (1u64 << 24) as f32
        };
        let boxes: Vec<Aabb> = (0..37)
            .map(|_| {
                let p = [rnd() * 4.0, rnd() * 4.0, rnd() * 4.0];
                Aabb {
                    min: p,
                    max: [p[0] + rnd(), p[1] + rnd(), p[2] + rnd()],
                }
            })
            .collect();
        let mut lanes = Lanes::default();
        lanes.resize(boxes.len());
        for (i, b) in boxes.iter().enumerate() {
            lanes.set(i, b);
            assert_eq!(lanes.get(i), *b);
        }
        assert_eq!(lanes.len(), 37);
        let mut touching = boxes[0];
        touching.min[1] = boxes[5].max[1];
        touching.max[1] = touching.min[1];
        for v in boxes.iter().chain([&touching]) {
            for range in [0..37, 3..29, 5..6, 36..37, 9..9, 0..16] {
                let want: Vec<u32> = range
                    .clone()
                    .filter(|&i| v.overlaps(&boxes[i], 0.0))
                    .map(|i| i as u32)
                    .collect();
                let (mut got, mut masks) = (Vec::new(), Vec::new());
                lanes.select(range.clone(), v, &mut masks, &mut got);
                assert_eq!(got, want);
                // The portable path too (the test machine may have AVX2).
                let chunks = range.len().div_ceil(LANES);
                let run = lanes.run(range.start..range.start + chunks * LANES);
                let mut plain = vec![0; chunks];
                let found = masks_plain(&run, std::slice::from_ref(v), &mut plain);
                got.clear();
                for &e in &plain[..found] {
                    let (j, m) = ((e >> 8) as usize, e & 0xff);
                    for l in 0..LANES {
                        let i = range.start + j * LANES + l;
                        if m >> l & 1 == 1 && i < range.end {
                            got.push(i as u32);
                        }
                    }
                }
                assert_eq!(got, want);
            }
        }
        // Ranges of at most 16 boxes: the 16-box kernel gives each_pair's calls, in order.
        let mut own_pairs = 0;
        let chain: Vec<Aabb> = (0..boxes.len())
            .map(|i| {
                let x = 0.3 * i as f32 + rnd();
                Aabb {
                    min: [x, rnd(), 0.0],
                    max: [x + 1.0, 1.0 + rnd(), 1.0],
                }
            })
            .collect();
        let mut dense = Lanes::default();
        dense.resize(chain.len());
        for (i, b) in chain.iter().enumerate() {
            dense.set(i, b);
        }
        for range in [0..16, 3..19, 21..37, 30..37, 36..37, 9..9, 5..13] {
            let (mut want, mut got) = (Vec::new(), Vec::new());
            let cands = &boxes[..];
            lanes.each_pair(range.clone(), cands, &mut Vec::new(), |i, c| {
                want.push((c, i))
            });
            lanes.each_pair_16(range.clone(), cands, false, |i, c| got.push((c, i)));
            assert_eq!(got, want, "{range:?}");
            // As pairs appended to a list (after what it holds), candidates numbered from
            // 100: the same, in the same order.
            let mut list = vec![[7, 7]];
            for cs in cands.chunks(16).enumerate() {
                lanes.pairs_16(
                    range.clone(),
                    cs.1,
                    100 + 16 * cs.0 as u32,
                    false,
                    None,
                    None,
                    &mut list,
                );
            }
            let listed: Vec<(u32, u32)> = list[1..].iter().map(|&[i, c]| (c - 100, i)).collect();
            assert_eq!(
                (list[0], listed),
                ([7, 7], want.clone()),
                "{range:?}, listed"
            );
            if range.len() > 3 {
                assert!(!want.is_empty());
            }
            // The range against itself, each unordered pair once (a chain of boxes, each
            // meeting the next few).
            let own = &chain[range.clone()];
            let (mut want, mut got) = (Vec::new(), Vec::new());
            dense.each_pair(range.clone(), own, &mut Vec::new(), |i, c| {
                if i > range.start as u32 + c {
                    want.push((c, i));
                }
            });
            dense.each_pair_16(range.clone(), own, true, |i, c| got.push((c, i)));
            assert_eq!(got, want, "{range:?} with itself");
            let mut list = Vec::new();
            dense.pairs_16(
                range.clone(),
                own,
                range.start as u32,
                true,
                None,
                None,
                &mut list,
            );
            let listed: Vec<(u32, u32)> = list
                .iter()
                .map(|&[i, c]| (c - range.start as u32, i))
                .collect();
            assert_eq!(listed, want, "{range:?} with itself, listed");
            // Each kernel's masks give those pairs: the portable one and AVX2 too (the test
            // machine may prefer AVX-512).
            if !range.is_empty() {
                let keep = (1u32 << range.len()) - 1;
                let run = dense.run(range.start..range.start + 2 * LANES);
                let pairs = |masks: [u16; 16]| {
                    let mut out = Vec::new();
                    for (c, &m) in masks[..own.len()].iter().enumerate() {
                        for l in 0..16 {
                            if m >> l & 1 == 1 && l > c {
                                out.push((c as u32, range.start as u32 + l as u32));
                            }
                        }
                    }
                    out
                };
                assert_eq!(
                    pairs(masks_16_plain(&run, own, keep)),
                    want,
                    "{range:?} with itself, portable"
                );
                #[cfg(target_arch = "x86_64")]
                if std::is_x86_feature_detected!("avx2") {
                    // SAFETY: AVX2 checked just above; the boxes are padded.
                    let masks = unsafe { masks_16_avx2(&run, own, keep) };
                    assert_eq!(pairs(masks), want, "{range:?} with itself, AVX2");
                }
            }
            own_pairs += want.len();
        }
        assert!(own_pairs > 10, "{own_pairs} pairs within the ranges");
        // Past 2^24 chunk tests the range is taken block by block: same pairs.
        let many: Vec<Aabb> = (0..5000).map(|i| boxes[i % boxes.len()]).collect();
        let mut big = Lanes::default();
        big.resize(40_000);
        for i in 0..40_000 {
            big.set(i, &boxes[i % boxes.len()]);
        }
        let mut got = Vec::new();
        big.each_pair(0..40_000, &many[..3], &mut Vec::new(), |i, c| {
            got.push((c, i))
        });
        let mut blocked = Vec::new();
        big.each_pair(0..40_000, &many, &mut Vec::new(), |i, c| {
            if c < 3 {
                blocked.push((c, i))
            }
        });
        got.sort_unstable();
        blocked.sort_unstable();
        assert!(!got.is_empty());
        assert_eq!(got, blocked);
        // Shrinking keeps the padding.
        lanes.resize(3);
        assert_eq!(lanes.len(), 3);
        assert_eq!(lanes.get(3), Aabb::EMPTY);
    }

    /// [`Lanes::pairs_16`] leaving out the pairs sharing a vertex (AVX-512 here where the
    /// CPU has it) and its portable path against a brute force: every box pair by
    /// `Aabb::overlaps`, every shared corner by comparing vertex indices, on boxes that
    /// often meet and vertex indices from a small pool (so that pairs share one, two or
    /// three corners), triangles and quads, a range against another and against itself.
    #[test]
    fn pairs_16_leaves_out_what_it_is_told() {
        let mut rng = crate::geom::test_rng::Rng(11);
        let n = 53;
        let boxes: Vec<Aabb> = (0..n)
            .map(|i| {
                let x = 0.25 * i as f32 + rng.below(100) as f32 / 100.0;
                let y = rng.below(100) as f32 / 100.0;
                Aabb {
                    min: [x, y, 0.0],
                    max: [x + 1.5, y + 0.8, rng.below(2) as f32],
                }
            })
            .collect();
        let mut lanes = Lanes::default();
        lanes.resize(n);
        for (i, b) in boxes.iter().enumerate() {
            lanes.set(i, b);
        }
        let (mut counts, mut calls) = ([0usize; 2], 0);
        for k in [3, 4] {
            let verts: Vec<[u32; 4]> = (0..n)
                .map(|_| {
                    let mut v = [u32::MAX; 4];
                    for x in &mut v[..k] {
                        *x = rng.below(24) as u32;
                    }
                    v
                })
                .collect();
            for (range, others) in [
                (0..16, 16..32),
                (3..19, 3..19),
                (30..37, 30..37),
                (40..53, 20..36),
                (5..6, 0..16),
                (44..53, 44..53),
            ] {
                let upper = range == others;
                let (mut want, mut left_out) = (Vec::new(), 0);
                for (c, q) in others.clone().enumerate() {
                    for p in range.clone() {
                        if (upper && p <= range.start + c) || !boxes[p].overlaps(&boxes[q], 0.0) {
                            continue;
                        }
                        if verts[p][..k].iter().any(|v| verts[q][..k].contains(v)) {
                            left_out += 1;
                        } else {
                            want.push([p as u32, 1000 + c as u32]);
                        }
                    }
                }
                let cands = &boxes[others.clone()];
                let excl = sharing(&verts, k, range.clone(), others.clone());
                for plain in [false, true] {
                    let mut got = vec![[9, 9]];
                    let e = Some(&excl[..]);
                    let cut = if plain {
                        lanes.pairs_16_plain(range.clone(), cands, 1000, upper, None, e, &mut got)
                    } else {
                        lanes.pairs_16(range.clone(), cands, 1000, upper, None, e, &mut got)
                    };
                    assert_eq!(got.remove(0), [9, 9]);
                    assert_eq!(
                        (got, cut),
                        (want.clone(), 0),
                        "{range:?} {others:?} k {k} plain {plain}"
                    );
                }
                counts[0] += want.len();
                counts[1] += left_out;
                calls += 1;
            }
        }
        // Both outcomes were met, many times.
        assert!(
            counts.iter().all(|&c| c > 20),
            "{counts:?} over {calls} calls"
        );
    }
}
