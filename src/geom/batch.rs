//! Triangle pairs gathered four at a time for a lane kernel: the exact test
//! ([`crate::geom::tritri::four::intersect`], epsilon 0) or the band test
//! ([`crate::geom::volume::four::band`], epsilon > 0). Each kernel decides the lanes whose
//! answer floating point certifies; the caller's scalar test ([`Judge::scalar`]) decides
//! the others, so the answers are the scalar path's.

use crate::geom::lanes::LANES;
use crate::geom::predicates::P3;

/// Which test the lanes run.
#[derive(Clone, Copy, Debug)]
pub(crate) enum Kernel {
    /// Do the closed triangles intersect (`tritri::triangles_intersect`)?
    Exact,
    /// Does `b` meet `a`'s viewing volume of half depth `h` or `a` itself and, when
    /// `both`, does `a` meet `b`'s (`Prepared::meets` one or both ways round)?
    Band { h: f64, both: bool },
}

/// Pairs gathered for one run of a kernel: lane `l` is `(a[l], b[l])`, named `at[l]`.
struct Batch<K> {
    a: [[P3; 3]; LANES],
    b: [[P3; 3]; LANES],
    at: [K; LANES],
    n: usize,
}

impl<K: Copy + Default> Batch<K> {
    fn new() -> Batch<K> {
        Batch {
            a: [[[0.0; 3]; 3]; LANES],
            b: [[[0.0; 3]; 3]; LANES],
            at: [K::default(); LANES],
            n: 0,
        }
    }

    /// Unused lanes repeat the first (their answers are dropped).
    fn pad(&mut self) {
        for l in self.n..LANES {
            (self.a[l], self.b[l]) = (self.a[0], self.b[0]);
        }
    }

    /// `judge.found` for each pair of the batch that meets: the lanes' answer where
    /// `decided`, the scalar test's elsewhere; the batch emptied.
    fn answer(&mut self, decided: u32, meets: u32, judge: &mut impl Judge<K>) {
        for l in 0..std::mem::take(&mut self.n) {
            let key = self.at[l];
            let yes = if decided & (1 << l) != 0 {
                meets & (1 << l) != 0
            } else {
                judge.scalar(key)
            };
            if yes {
                judge.found(key);
            }
        }
    }
}

/// Triangle pairs gathered four at a time for a [`Kernel`]. A value exists only on a CPU
/// with AVX2 and FMA ([`Fours::new`] checks), so its methods are safe.
///
/// The band test runs in two stages: a cheap test of every batch
/// ([`band_far`](crate::geom::volume::four::band_far): corners beyond one plane of a
/// volume) drops the pairs certainly apart, and the others are gathered again into full
/// batches for the whole test (most box-overlapping pairs within a thin band are apart,
/// and the whole test costs several times the cheap one).
pub(crate) struct Fours<K: Copy + Default> {
    first: Batch<K>,
    /// The band test's second stage.
    second: Batch<K>,
    kernel: Kernel,
}

impl<K: Copy + Default> Fours<K> {
    /// `None` on a CPU without AVX2 and FMA.
    pub(crate) fn new(kernel: Kernel) -> Option<Fours<K>> {
        (std::is_x86_feature_detected!("avx2") && std::is_x86_feature_detected!("fma")).then(|| {
            Fours {
                first: Batch::new(),
                second: Batch::new(),
                kernel,
            }
        })
    }

    /// Runs the kernel on the first-stage batch (and on the second when it fills up, or
    /// at the `end`), answering through `judge`.
    fn run(&mut self, end: bool, judge: &mut impl Judge<K>) {
        use crate::geom::tritri::four::intersect;
        use crate::geom::volume::four::{band, band_far};
        let b = &mut self.first;
        if b.n > 0 {
            b.pad();
        }
        match self.kernel {
            Kernel::Exact => {
                if b.n > 0 {
                    // SAFETY: a `Fours` exists only on a CPU with AVX2 and FMA (`new`).
                    let (decided, meets) = unsafe { intersect(&b.a, &b.b) };
                    b.answer(decided, meets, judge);
                }
            }
            Kernel::Band { h, both } => {
                let far = if b.n > 0 {
                    // SAFETY: as above.
                    unsafe { band_far(&b.a, &b.b, h, both) }
                } else {
                    0
                };
                let c = &mut self.second;
                for l in 0..std::mem::take(&mut b.n) {
                    if far & (1 << l) != 0 {
                        continue;
                    }
                    (c.a[c.n], c.b[c.n], c.at[c.n]) = (b.a[l], b.b[l], b.at[l]);
                    c.n += 1;
                    if c.n == LANES {
                        // SAFETY: as above.
                        let (decided, meets) = unsafe { band(&c.a, &c.b, h, both) };
                        c.answer(decided, meets, judge);
                    }
                }
                if end && c.n > 0 {
                    c.pad();
                    // SAFETY: as above.
                    let (decided, meets) = unsafe { band(&c.a, &c.b, h, both) };
                    c.answer(decided, meets, judge);
                }
            }
        }
    }
}

/// What [`Fours::decide`] asks of its caller about each pair (named by a key).
pub(crate) trait Judge<K> {
    /// When both polygons of the pair are triangles (then the lanes may decide it): writes
    /// them to `a` and `b` and answers `true`; `false` for a pair with a quad.
    fn triangles(&mut self, key: K, a: &mut [P3; 3], b: &mut [P3; 3]) -> bool;
    /// The scalar test the kernel stands for: for the pairs the lanes leave undecided, and
    /// those with a quad.
    fn scalar(&mut self, key: K) -> bool;
    /// A pair that meets.
    fn found(&mut self, key: K);
}

impl<K: Copy + Default> Fours<K> {
    /// Every pair of `keys`: `judge.found` for each that meets (the scalar test's answer; in
    /// batches of four, so not quite in the order of `keys`).
    #[inline]
    pub(crate) fn decide(&mut self, keys: impl Iterator<Item = K>, judge: &mut impl Judge<K>) {
        for key in keys {
            // Written in place: the next lane of the batch.
            let b = &mut self.first;
            if !judge.triangles(key, &mut b.a[b.n], &mut b.b[b.n]) {
                if judge.scalar(key) {
                    judge.found(key);
                }
                continue;
            }
            b.at[b.n] = key;
            b.n += 1;
            if b.n == LANES {
                self.run(false, judge);
            }
        }
        self.run(true, judge);
    }
}
