//! Triangle pairs gathered into lanes for a kernel: the exact test (epsilon 0) eight at a
//! time on a CPU with AVX-512F ([`crate::geom::tritri::eight::intersect`]), four at a
//! time on one with AVX2 and FMA only ([`crate::geom::tritri::four::intersect`]), the
//! pairs of two triangles in one coordinate plane in batches of their own, for the test in
//! that plane ([`crate::geom::tritri::axis_plane`], as wide); the band test (epsilon > 0,
//! [`crate::geom::volume::four::band`]) four at a time. Each kernel decides the lanes
//! whose answer floating point certifies; the caller's scalar test ([`Judge::scalar`])
//! decides the others, so the answers are the scalar path's.
//!
//! The pairs' triangles are written straight into lanes ([`TriLanes`]: each coordinate
//! stored once, where the kernel loads it), and a batch's answers are read from its masks
//! a bit at a time: only the lanes that meet or that the kernel left undecided cost a step.

use crate::geom::lanes::{TriLanes, LANES};
use crate::geom::predicates::P3;
use crate::geom::tritri::shared_axis_plane;

/// Which test the lanes run.
#[derive(Clone, Copy, Debug)]
pub(crate) enum Kernel {
    /// Do the closed triangles intersect (`tritri::triangles_intersect`)?
    Exact,
    /// Does `b` meet `a`'s viewing volume of half depth `h` or `a` itself and, when
    /// `both`, does `a` meet `b`'s (`Prepared::meets` one or both ways round)?
    Band { h: f64, both: bool },
}

/// Pairs gathered for one run of a kernel of `N` lanes: lane `l` is the pair of the
/// triangles in lane `l` of `a` and `b`, named `at[l]`; the first `n` lanes are in use.
/// (Also the batches of [`crate::geom::contact`]'s many-pair kernel.)
pub(crate) struct Batch<K, const N: usize> {
    pub(crate) a: TriLanes<N>,
    pub(crate) b: TriLanes<N>,
    pub(crate) at: [K; N],
    pub(crate) n: usize,
}

impl<K: Copy + Default, const N: usize> Batch<K, N> {
    /// An empty batch.
    pub(crate) fn new() -> Batch<K, N> {
        Batch {
            a: TriLanes::ZERO,
            b: TriLanes::ZERO,
            at: [K::default(); N],
            n: 0,
        }
    }

    /// Pair `key` of triangles `a` and `b` into the next lane; true when the batch is full.
    #[inline(always)]
    pub(crate) fn push(&mut self, key: K, a: &[P3; 3], b: &[P3; 3]) -> bool {
        self.a.set(self.n, a);
        self.b.set(self.n, b);
        self.at[self.n] = key;
        self.n += 1;
        self.n == N
    }

    /// [`Batch::push`] of two triangles in the coordinate plane that drops axis `ax`,
    /// projected on it ([`TriLanes::set_plane`]).
    #[inline(always)]
    fn push_plane(&mut self, key: K, a: &[P3; 3], b: &[P3; 3], ax: usize) -> bool {
        self.a.set_plane(self.n, a, ax);
        self.b.set_plane(self.n, b, ax);
        self.at[self.n] = key;
        self.n += 1;
        self.n == N
    }

    /// Unused lanes repeat the first (their answers are dropped).
    pub(crate) fn pad(&mut self) {
        self.a.pad(self.n);
        self.b.pad(self.n);
    }

    /// `judge.found` for each pair of the batch that meets, in lane order: the lanes'
    /// answer where `decided`, the scalar test's elsewhere; the batch emptied. (`meets`
    /// has no bit outside `decided`.)
    #[inline]
    fn answer(&mut self, decided: u32, meets: u32, judge: &mut impl Judge<K>) {
        let n = std::mem::take(&mut self.n);
        // The lanes that meet, or that only the scalar test can answer.
        let mut ask = (meets | !decided) & ((1 << n) - 1);
        while ask != 0 {
            let l = ask.trailing_zeros() as usize;
            ask &= ask - 1;
            let key = self.at[l];
            if decided & (1 << l) != 0 || judge.scalar(key) {
                judge.found(key);
            }
        }
    }
}

/// Triangle pairs gathered into lanes for a [`Kernel`] (four at a time, or eight for the
/// exact test on a CPU with AVX-512F). A value exists only on a CPU with AVX2 and FMA
/// ([`Fours::new`] checks; and it runs the eight-lane kernels only where AVX-512F was
/// found), so its methods are safe.
///
/// The exact test gathers the pairs of two triangles in one coordinate plane (a flat
/// sheet: every orientation of the 3D test is exactly 0 there, and its lanes would leave
/// all of them to the scalar test) into batches of their own, for the test in that plane.
///
/// The band test runs in two stages: a cheap test of every batch
/// ([`band_far`](crate::geom::volume::four::band_far): corners beyond one plane of a
/// volume) drops the pairs certainly apart, and the others are gathered again into full
/// batches for the whole test (most box-overlapping pairs within a thin band are apart,
/// and the whole test costs several times the cheap one).
pub(crate) struct Fours<K: Copy + Default> {
    kernel: Kernel,
    /// The exact test runs on eight lanes (the CPU has AVX-512F).
    eight: bool,
    /// The exact test's batches on eight lanes.
    wide: Batch<K, 8>,
    /// The exact test's batches of pairs in one coordinate plane, on eight lanes.
    wide_plane: Batch<K, 8>,
    /// The exact test's batches on four lanes; the band test's first stage.
    first: Batch<K, LANES>,
    /// The exact test's batches of pairs in one coordinate plane, on four lanes; the band
    /// test's second stage.
    second: Batch<K, LANES>,
}

impl<K: Copy + Default> Fours<K> {
    /// `None` on a CPU without AVX2 and FMA.
    pub(crate) fn new(kernel: Kernel) -> Option<Fours<K>> {
        let eight = std::is_x86_feature_detected!("avx512f");
        Fours::with(kernel, eight)
    }

    /// [`Fours::new`], on eight lanes only when `eight` and the CPU has AVX-512F.
    fn with(kernel: Kernel, eight: bool) -> Option<Fours<K>> {
        (std::is_x86_feature_detected!("avx2") && std::is_x86_feature_detected!("fma")).then(|| {
            Fours {
                kernel,
                eight: eight && std::is_x86_feature_detected!("avx512f"),
                wide: Batch::new(),
                wide_plane: Batch::new(),
                first: Batch::new(),
                second: Batch::new(),
            }
        })
    }

    /// Every pair of `keys`: `judge.found` for each that meets (the scalar test's answer; in
    /// batches, so not quite in the order of `keys`).
    #[inline]
    pub(crate) fn decide(
        &mut self,
        keys: impl Iterator<Item = K> + Clone,
        judge: &mut impl Judge<K>,
    ) {
        use crate::geom::tritri::{axis_plane, eight, four};
        use crate::geom::volume::four::{band, band_far};
        let Fours {
            kernel,
            eight: on_eight,
            wide,
            wide_plane,
            first,
            second,
        } = self;
        match *kernel {
            Kernel::Exact if *on_eight => gather(
                [wide, wide_plane],
                keys,
                judge,
                shared_axis_plane,
                |b, judge| {
                    // SAFETY: the CPU has AVX-512F (`eight` is set only then, `with`).
                    let (decided, meets) = unsafe { eight::intersect(&b.a, &b.b) };
                    b.answer(decided, meets, judge);
                },
                |b, judge| {
                    // SAFETY: as above.
                    let (decided, meets) = unsafe { axis_plane::eight(&b.a, &b.b) };
                    b.answer(decided, meets, judge);
                },
            ),
            Kernel::Exact => gather(
                [first, second],
                keys,
                judge,
                shared_axis_plane,
                |b, judge| {
                    // SAFETY: a `Fours` exists only on a CPU with AVX2 and FMA (`with`).
                    let (decided, meets) = unsafe { four::intersect(&b.a, &b.b) };
                    b.answer(decided, meets, judge);
                },
                |b, judge| {
                    // SAFETY: as above.
                    let (decided, meets) = unsafe { axis_plane::four(&b.a, &b.b) };
                    b.answer(decided, meets, judge);
                },
            ),
            Kernel::Band { h, both } => {
                // Every pair in space (the band kernel has no plane variant): the plane
                // batch is never filled.
                let space_only = |_: &[P3; 3], _: &[P3; 3]| None;
                let mut unused = Batch::new();
                let run = |b: &mut Batch<K, LANES>, judge: &mut _| {
                    // SAFETY: as above.
                    let far = unsafe { band_far(&b.a, &b.b, h, both) };
                    for l in 0..std::mem::take(&mut b.n) {
                        if far & (1 << l) != 0 {
                            continue;
                        }
                        if second.push(b.at[l], &b.a.get(l), &b.b.get(l)) {
                            // SAFETY: as above.
                            let (decided, meets) = unsafe { band(&second.a, &second.b, h, both) };
                            second.answer(decided, meets, judge);
                        }
                    }
                };
                gather(
                    [first, &mut unused],
                    keys,
                    judge,
                    space_only,
                    run,
                    |_, _| {},
                );
                if second.n > 0 {
                    second.pad();
                    // SAFETY: as above.
                    let (decided, meets) = unsafe { band(&second.a, &second.b, h, both) };
                    second.answer(decided, meets, judge);
                }
            }
        }
    }
}

/// Every pair of `keys` whose polygons are both triangles into lanes: those that
/// `plane_axis` puts in one coordinate plane (the axis it drops) into the lanes of
/// `plane`, projected on it, the others into the lanes of `space`; `run_space` and
/// `run_plane` on each full batch of theirs and on their last one (padded), which they
/// empty. The other pairs by the scalar test.
#[inline(always)]
fn gather<K: Copy + Default, const N: usize, J: Judge<K>>(
    [space, plane]: [&mut Batch<K, N>; 2],
    keys: impl Iterator<Item = K> + Clone,
    judge: &mut J,
    plane_axis: impl Fn(&[P3; 3], &[P3; 3]) -> Option<usize>,
    mut run_space: impl FnMut(&mut Batch<K, N>, &mut J),
    mut run_plane: impl FnMut(&mut Batch<K, N>, &mut J),
) {
    // The pair this many ahead is announced ([`Judge::prefetch`]): its triangles are
    // fetched from memory while the pairs before it are gathered and tested.
    const AHEAD: usize = 16;
    let mut ahead = keys.clone().skip(AHEAD);
    for key in keys {
        if let Some(next) = ahead.next() {
            judge.prefetch(next);
        }
        match judge.triangles(key) {
            Some([ta, tb]) => match plane_axis(ta, tb) {
                None => {
                    if space.push(key, ta, tb) {
                        run_space(space, judge);
                    }
                }
                Some(ax) => {
                    if plane.push_plane(key, ta, tb, ax) {
                        run_plane(plane, judge);
                    }
                }
            },
            None => {
                if judge.scalar(key) {
                    judge.found(key);
                }
            }
        }
    }
    if space.n > 0 {
        space.pad();
        run_space(space, judge);
    }
    if plane.n > 0 {
        plane.pad();
        run_plane(plane, judge);
    }
}

/// What [`Fours::decide`] asks of its caller about each pair (named by a key).
pub(crate) trait Judge<K> {
    /// When both polygons of the pair are triangles (then the lanes may decide it): the
    /// two triangles; `None` for a pair with a quad, or one the lanes are known to leave
    /// undecided.
    fn triangles(&mut self, key: K) -> Option<[&[P3; 3]; 2]>;
    /// The scalar test the kernel stands for: for the pairs the lanes leave undecided, and
    /// those with a quad.
    fn scalar(&mut self, key: K) -> bool;
    /// A pair that meets.
    fn found(&mut self, key: K);
    /// A hint: pair `key` comes soon (its triangles might be fetched into the cache).
    #[inline(always)]
    fn prefetch(&self, key: K) {
        let _ = key;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::polygon::Prepared;
    use crate::geom::test_rng::Rng;
    use crate::geom::tritri::triangles_intersect;

    /// Pairs named by their position; one in ten stands for a pair with a quad (no
    /// triangles for the lanes). The scalar test is `triangles_intersect` (or, for the
    /// band, `Prepared::meets` both ways round).
    struct Pairs {
        pairs: Vec<[[P3; 3]; 2]>,
        band: Option<f64>,
        found: Vec<usize>,
        /// The pairs asked of the scalar test.
        scalar: Vec<usize>,
    }

    impl Judge<usize> for Pairs {
        fn triangles(&mut self, key: usize) -> Option<[&[P3; 3]; 2]> {
            let [a, b] = &self.pairs[key];
            (key % 10 != 3).then_some([a, b])
        }
        fn scalar(&mut self, key: usize) -> bool {
            self.scalar.push(key);
            let [a, b] = &self.pairs[key];
            match self.band {
                None => triangles_intersect(a, b),
                Some(h) => {
                    let (pa, pb) = (Prepared::of([*a; 2], 1), Prepared::of([*b; 2], 1));
                    pa.meets(&pb, Some(&pa.cells(h))) || pb.meets(&pa, Some(&pb.cells(h)))
                }
            }
        }
        fn found(&mut self, key: usize) {
            self.found.push(key);
        }
    }

    /// A pair: random (about half crossing), on a coarse grid (shared vertices, coplanar
    /// and flat triangles: left to the scalar test), within about `0.05` of each other, or
    /// both in one coordinate plane (`x`, `y` or `z` = 0.25): random there (for the lanes
    /// of that plane), or on a coarse grid of it (shared vertices, touching and flat
    /// triangles: left to the scalar test).
    fn pair(rng: &mut Rng, kind: usize) -> [[P3; 3]; 2] {
        let ax = rng.below(3);
        let mut t = || -> [P3; 3] {
            std::array::from_fn(|_| match kind {
                0 => rng.v(1.0),
                1 => [0, 1, 2].map(|_| rng.below(3) as f64),
                2 => [rng.f(), rng.f(), rng.f() * 0.05],
                3 | 4 => {
                    let mut p = [0, 1, 2].map(|_| match kind {
                        3 => rng.f(),
                        _ => rng.below(3) as f64 * 0.5,
                    });
                    p[ax] = 0.25;
                    p
                }
                _ => unreachable!(),
            })
        };
        [t(), t()]
    }

    /// The whole path (gathering, the lanes, the scalar test for the lanes left undecided
    /// and for quads, the last batch of each kernel padded) finds what the scalar test
    /// finds, each pair once: the exact test on eight lanes (where the CPU has AVX-512F)
    /// and on four, with the pairs in one coordinate plane in batches of their own, and
    /// the band test, over a number of pairs that is not a multiple of eight. The exact
    /// test's lanes decide most random pairs in one coordinate plane.
    #[test]
    fn decides_as_the_scalar_test() {
        let mut rng = Rng(0x0BA7_C4E5_u64);
        let pairs: Vec<_> = (0..4_001).map(|i| pair(&mut rng, i % 5)).collect();
        for (kernel, eight) in [
            (Kernel::Exact, true),
            (Kernel::Exact, false),
            (
                Kernel::Band {
                    h: 0.01,
                    both: true,
                },
                false,
            ),
        ] {
            let Some(mut fours) = Fours::with(kernel, eight) else {
                println!("no AVX2 and FMA: the lanes are not used");
                return;
            };
            if eight && !fours.eight {
                println!("no AVX-512F: the exact test on four lanes only");
            }
            let band = match kernel {
                Kernel::Exact => None,
                Kernel::Band { h, .. } => Some(h),
            };
            let mut judge = Pairs {
                pairs: pairs.clone(),
                band,
                found: Vec::new(),
                scalar: Vec::new(),
            };
            let want: Vec<usize> = (0..pairs.len()).filter(|&k| judge.scalar(k)).collect();
            judge.scalar.clear();
            fours.decide(0..pairs.len(), &mut judge);
            let mut found = std::mem::take(&mut judge.found);
            found.sort_unstable();
            assert_eq!(found, want, "{kernel:?}, eight lanes: {}", fours.eight);
            // The lanes decided most pairs, and left some (and the quads) to the scalar
            // test.
            let scalar = judge.scalar.len();
            // The random pairs in one coordinate plane (not standing for quads).
            let plane = |k: &usize| k % 5 == 3 && k % 10 != 3;
            let plane_pairs = (0..pairs.len()).filter(plane).count();
            let plane_scalar = judge.scalar.iter().filter(|k| plane(k)).count();
            println!(
                "{kernel:?} (eight lanes: {}): {} of {} pairs meet, {scalar} by the scalar \
                 test, {plane_scalar} of the {plane_pairs} random in a coordinate plane",
                fours.eight,
                want.len(),
                pairs.len(),
            );
            assert!(want.len() > 500 && want.len() < pairs.len() - 500);
            assert!(scalar > pairs.len() / 10 && scalar < pairs.len() / 2);
            if let Kernel::Exact = kernel {
                assert!(plane_pairs > 300 && plane_scalar * 20 < plane_pairs);
            }
        }
    }
}
