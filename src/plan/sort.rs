//! Sorting a whole-scene answer: each pair as one integer key (64 bits where the scene's
//! mesh ids and polygon numbers fit, else 128), sorted least significant byte first
//! (radix sort), one pass per byte that differs between the keys. The pairs of a scene
//! differ in few bytes (a big mesh's polygon numbers need three of each four, one mesh's
//! self pairs none of the mesh ids'): five passes over the 78,000 pairs of a crumpled
//! cloth, where a comparison sort makes seventeen. A whole-scene query's workers each sort
//! their own pairs so ([`sort_own`], key widths from the scene's bounds: [`short_widths`])
//! and the sorted lists are merged in one pass ([`merge_keys`]; two lists in two halves
//! side by side on two workers, [`merge_split`]); [`sort_pairs`] sorts a list whole (an
//! answer with the GL backend's pairs, or keys of 128 bits).

use crate::backend::Pair;
use std::mem::MaybeUninit;

/// The keys and scratch of [`sort_pairs`], reused from query to query.
#[derive(Default)]
pub(super) struct PairKeys {
    wide: Vec<u128>,
    wide_scratch: Vec<u128>,
    short: Vec<u64>,
    short_scratch: Vec<u64>,
}

/// Sorts `pairs` in the order of `Pair` (mesh_a, polygon_a, mesh_b, polygon_b) and drops
/// repeats: each pair made one integer once (sorting the pairs by a key made at each
/// comparison took 2 ms for the 78,000 pairs of a crumpled cloth), 64 bits where every
/// mesh id and polygon number fits in 32 bits for the two (half the memory traffic of 128
/// bits and a pass less for the crumpled cloth), sorted by [`sort_keys`] (on `pool`'s
/// workers where given).
pub(super) fn sort_pairs(
    pairs: &mut Vec<Pair>,
    k: &mut PairKeys,
    pool: Option<&rayon::ThreadPool>,
) {
    let (mut ids, mut polys) = (0u32, 0u32);
    for p in pairs.iter() {
        ids |= p.mesh_a | p.mesh_b;
        polys |= p.polygon_a | p.polygon_b;
    }
    if let Some(widths) = short_widths(ids, polys) {
        let keys = &mut k.short;
        keys.clear();
        keys.extend(pairs.iter().map(|p| short_key(p, widths)));
        sort_on(keys, &mut k.short_scratch, pool);
        keys.dedup();
        pairs.clear();
        pairs.extend(keys.iter().map(|&key| short_pair(key, widths)));
    } else {
        let keys = &mut k.wide;
        keys.clear();
        keys.extend(pairs.iter().map(|p| {
            (u128::from(p.mesh_a) << 96)
                | (u128::from(p.polygon_a) << 64)
                | (u128::from(p.mesh_b) << 32)
                | u128::from(p.polygon_b)
        }));
        sort_on(keys, &mut k.wide_scratch, pool);
        keys.dedup();
        pairs.clear();
        pairs.extend(keys.iter().map(|&k| Pair {
            mesh_a: (k >> 96) as u32,
            polygon_a: (k >> 64) as u32,
            mesh_b: (k >> 32) as u32,
            polygon_b: k as u32,
        }));
    }
}

/// The widths `(pb, half)` of [`sort_pairs`]'s 64-bit keys (polygon bits; bits of a mesh
/// id and a polygon together) for pairs whose mesh ids have no bit outside `ids` and whose
/// polygon numbers none outside `polys`, where two such halves fit in 64 bits.
pub(super) fn short_widths(ids: u32, polys: u32) -> Option<(u32, u32)> {
    let bits = |x: u32| 32 - x.leading_zeros();
    let (ib, pb) = (bits(ids), bits(polys));
    (2 * (ib + pb) <= 64).then_some((pb, ib + pb))
}

/// Pair `p`'s 64-bit key of widths `(pb, half)` ([`short_widths`]): (mesh_a, polygon_a)
/// above (mesh_b, polygon_b), each mesh id above its polygon number, so that keys sort as
/// pairs do.
#[inline(always)]
fn short_key(p: &Pair, (pb, half): (u32, u32)) -> u64 {
    let a = u64::from(p.mesh_a) << pb | u64::from(p.polygon_a);
    let b = u64::from(p.mesh_b) << pb | u64::from(p.polygon_b);
    a << half | b
}

/// The pair of a [`short_key`] of widths `(pb, half)`.
#[inline(always)]
fn short_pair(key: u64, (pb, half): (u32, u32)) -> Pair {
    let (poly, side) = ((1u64 << pb) - 1, (1u64 << half) - 1);
    let (a, b) = (key >> half, key & side);
    Pair {
        mesh_a: (a >> pb) as u32,
        polygon_a: (a & poly) as u32,
        mesh_b: (b >> pb) as u32,
        polygon_b: (b & poly) as u32,
    }
}

/// `pairs` as 64-bit keys of widths `(pb, half)` ([`short_widths`]), sorted, into `keys`
/// (`scratch` reused), on the calling thread: a worker's own answer, sorted where it was
/// made, to be merged with the others' by [`merge_keys`].
pub(super) fn sort_own(
    pairs: &[Pair],
    (pb, half): (u32, u32),
    keys: &mut Vec<u64>,
    scratch: &mut Vec<u64>,
) {
    keys.clear();
    keys.extend(pairs.iter().map(|p| short_key(p, (pb, half))));
    sort_keys(keys, scratch, false);
}

/// Merges `lists` of sorted keys of widths `(pb, half)` ([`sort_own`]) into `out` (cleared
/// first) as pairs, sorted, repeats dropped: one pass, two lists side by side (a compare
/// and two selects per key, no branch on the order), more through a heap of their heads.
/// With `par` (called inside a pool of two or more workers), two long lists are merged
/// in two halves side by side ([`merge_split`]).
pub(super) fn merge_keys(lists: &[&[u64]], (pb, half): (u32, u32), out: &mut Vec<Pair>, par: bool) {
    if let ([a, b], true) = (lists, par) {
        if a.len() + b.len() >= 2 * RADIX_MIN {
            merge_split(a, b, (pb, half), out);
            return;
        }
    }
    out.clear();
    out.reserve(lists.iter().map(|l| l.len()).sum());
    let mut push = unique(None, |k| out.push(short_pair(k, (pb, half))));
    match lists {
        [] => {}
        [one] => one.iter().for_each(|&k| push(k)),
        [a, b] => merge_two(a, b, push),
        _ => {
            use std::cmp::Reverse;
            let mut heads: std::collections::BinaryHeap<Reverse<(u64, usize, usize)>> = lists
                .iter()
                .enumerate()
                .filter(|(_, l)| !l.is_empty())
                .map(|(n, l)| Reverse((l[0], n, 0)))
                .collect();
            while let Some(Reverse((k, n, i))) = heads.pop() {
                push(k);
                if let Some(&next) = lists[n].get(i + 1) {
                    heads.push(Reverse((next, n, i + 1)));
                }
            }
        }
    }
}

/// [`sort_keys`] on `pool`'s workers where given.
fn sort_on<K: Key>(keys: &mut Vec<K>, scratch: &mut Vec<K>, pool: Option<&rayon::ThreadPool>) {
    match pool {
        Some(pool) => pool.install(|| sort_keys(keys, scratch, true)),
        None => sort_keys(keys, scratch, false),
    }
}

/// An unsigned integer key of [`sort_keys`].
pub(super) trait Key: Copy + Ord + Send + Sync + Default {
    /// Its size in bytes.
    const BYTES: usize;
    /// Byte `b` (0: least significant).
    fn byte(self, b: usize) -> usize;
    /// The bytes in which some two of `keys` differ, as bits (bit `b`: byte `b`).
    fn differ(keys: &[Self]) -> u32;
}

macro_rules! key {
    ($t:ty) => {
        impl Key for $t {
            const BYTES: usize = std::mem::size_of::<$t>();
            #[inline(always)]
            fn byte(self, b: usize) -> usize {
                (self >> (8 * b)) as usize & 0xff
            }
            fn differ(keys: &[Self]) -> u32 {
                let (mut and, mut or) = (!0, 0);
                for &k in keys {
                    and &= k;
                    or |= k;
                }
                let d = and ^ or;
                (0..Self::BYTES).fold(0, |m, b| m | u32::from(d.byte(b) != 0) << b)
            }
        }
    };
}
key!(u64);
key!(u128);

/// Keys below this count are sorted by comparison (the radix sort's 4,096 counters cost
/// more than a short sort).
const RADIX_MIN: usize = 4096;

/// Sorts `keys` ascending; `scratch` is reused from call to call (no allocation once
/// grown). With `par` (called inside a pool of two or more workers), the two halves are
/// sorted side by side, then merged.
pub(super) fn sort_keys<K: Key>(keys: &mut Vec<K>, scratch: &mut Vec<K>, par: bool) {
    scratch.clear();
    scratch.resize(keys.len(), K::default());
    if !par || keys.len() < 2 * RADIX_MIN {
        if radix(keys, scratch) {
            std::mem::swap(keys, scratch);
        }
        return;
    }
    let half = keys.len() / 2;
    {
        let ((lo, hi), (lo_scratch, hi_scratch)) =
            (keys.split_at_mut(half), scratch.split_at_mut(half));
        let sort = |keys: &mut [K], scratch: &mut [K]| {
            if radix(keys, scratch) {
                keys.copy_from_slice(scratch);
            }
        };
        rayon::join(|| sort(lo, lo_scratch), || sort(hi, hi_scratch));
    }
    // The two sorted halves merged into `scratch`, which becomes the keys.
    let (lo, hi) = keys.split_at(half);
    let mut at = 0;
    merge_two(lo, hi, |k| {
        scratch[at] = k;
        at += 1;
    });
    std::mem::swap(keys, scratch);
}

/// [`merge_keys`] of two lists on two workers: the answer cut in the middle (the first
/// half's keys taken from the fronts of both lists, found by bisection), each half merged
/// by one worker straight into its part of `out`. Repeats are dropped within each half
/// and across the cut; where the first half dropped some, the second is moved down to
/// follow it.
fn merge_split(a: &[u64], b: &[u64], widths: (u32, u32), out: &mut Vec<Pair>) {
    let n = a.len() + b.len();
    let cut = n / 2;
    // The least `i` with `a[i] > b[cut - i - 1]`: then `a[..i]` and `b[..cut - i]` are
    // `cut` keys none greater than any of the rest.
    let (mut lo, mut hi) = (cut.saturating_sub(b.len()), cut.min(a.len()));
    while lo < hi {
        let mid = (lo + hi) / 2;
        if a[mid] <= b[cut - mid - 1] {
            lo = mid + 1;
        } else {
            hi = mid;
        }
    }
    let (i, j) = (lo, cut - lo);
    // The key before the second half (its repeat there is dropped).
    let before = a[..i].last().max(b[..j].last()).copied();
    out.clear();
    out.reserve(n);
    let (first, second) = out.spare_capacity_mut()[..n].split_at_mut(cut);
    let merge_into = |x: &[u64], y: &[u64], last: Option<u64>, to: &mut [MaybeUninit<Pair>]| {
        let mut at = 0;
        merge_two(
            x,
            y,
            unique(last, |k| {
                to[at].write(short_pair(k, widths));
                at += 1;
            }),
        );
        at
    };
    let (made, more) = rayon::join(
        || merge_into(&a[..i], &b[..j], None, first),
        || merge_into(&a[i..], &b[j..], before, second),
    );
    let spare = out.spare_capacity_mut();
    spare.copy_within(cut..cut + more, made);
    // SAFETY: the first `made` entries were written by the first half's merge, the next
    // `more` by the second's (moved to follow them): every one up to the new length is
    // initialised, within the reserved capacity.
    unsafe { out.set_len(made + more) };
}

/// `emit` for each key given it but a repeat of the one before (`last` before the first):
/// sorted keys with their repeats dropped.
#[inline(always)]
fn unique(mut last: Option<u64>, mut emit: impl FnMut(u64)) -> impl FnMut(u64) {
    move |k| {
        if last != Some(k) {
            emit(k);
            last = Some(k);
        }
    }
}

/// Two sorted lists merged in order, each key to `emit`: a compare and two selects per
/// key, no branch on which list it comes from.
#[inline(always)]
fn merge_two<K: Copy + Ord>(a: &[K], b: &[K], mut emit: impl FnMut(K)) {
    let (mut i, mut j) = (0, 0);
    while i < a.len() && j < b.len() {
        let (x, y) = (a[i], b[j]);
        let take_a = x <= y;
        emit(if take_a { x } else { y });
        i += usize::from(take_a);
        j += usize::from(!take_a);
    }
    a[i..].iter().chain(&b[j..]).for_each(|&k| emit(k));
}

/// The radix sort of [`sort_keys`] (a comparison sort below [`RADIX_MIN`] keys), with
/// `scratch` as long as `keys`: true when the sorted keys are left in `scratch` (an odd
/// number of passes), false when in `keys`.
fn radix<K: Key>(keys: &mut [K], scratch: &mut [K]) -> bool {
    if keys.len() < RADIX_MIN {
        keys.sort_unstable();
        return false;
    }
    // The bytes in which some two keys differ, then their counts, in one more read.
    let differ = K::differ(keys);
    let bytes: Vec<usize> = (0..K::BYTES).filter(|&b| differ >> b & 1 != 0).collect();
    let mut counts = vec![[0u32; 256]; bytes.len()];
    for &k in keys.iter() {
        for (c, &b) in counts.iter_mut().zip(&bytes) {
            c[k.byte(b)] += 1;
        }
    }
    let (mut from, mut to) = (keys, scratch);
    let mut moved = false;
    for (c, &b) in counts.iter().zip(&bytes) {
        // Stable scatter by byte `b`, then the buffers change roles.
        let mut at = [0u32; 256];
        let mut sum = 0;
        for (a, &n) in at.iter_mut().zip(c) {
            *a = sum;
            sum += n;
        }
        for &k in from.iter() {
            let d = k.byte(b);
            to[at[d] as usize] = k;
            at[d] += 1;
        }
        std::mem::swap(&mut from, &mut to);
        moved = !moved;
    }
    moved
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A pool of two workers, for the paths that run side by side.
    fn pool_of_two() -> rayon::ThreadPool {
        rayon::ThreadPoolBuilder::new()
            .num_threads(2)
            .build()
            .unwrap()
    }

    /// `keys` sorted by [`sort_keys`], whole and in halves, as by the standard sort.
    fn check<K: Key + std::fmt::Debug>(keys: Vec<K>, scratch: &mut Vec<K>, what: &str) {
        let mut want = keys.clone();
        want.sort_unstable();
        let (mut whole, mut halves) = (keys.clone(), keys);
        sort_keys(&mut whole, scratch, false);
        assert_eq!(whole, want, "{what}");
        sort_keys(&mut halves, scratch, true);
        assert_eq!(halves, want, "{what}, in halves");
    }

    /// Against the standard sort: random keys, keys differing in a few scattered bytes
    /// (as a scene's pairs), equal keys, short lists (the comparison path) and long ones;
    /// whole and in halves.
    #[test]
    fn sorts_as_the_standard_sort() {
        let mut rng = crate::geom::test_rng::Rng(5);
        let (mut scratch, mut scratch_short) = (Vec::new(), Vec::new());
        for (n, shape) in [
            (10, 0),
            (5000, 0),
            (20_000, 1),
            (20_000, 2),
            (70_000, 1),
            (30_000, 4),
            (4096, 3),
        ] {
            let keys: Vec<u128> = (0..n)
                .map(|_| {
                    let (a, b) = (u128::from(rng.next()), u128::from(rng.next()));
                    match shape {
                        0 => a << 64 | b,
                        // Mesh ids 3 and 7, polygons below 2^17.
                        1 => 3 << 96 | (a & 0x1ffff) << 64 | 7 << 32 | (b & 0x1ffff),
                        // Many equal keys.
                        2 => (a & 0xf) << 64 | (b & 0x3),
                        // Keys differing in an odd number of bytes (an odd number of
                        // passes: the sorted keys left in the scratch buffer).
                        4 => (a & 0xff_ffff) << 40,
                        _ => 42,
                    }
                })
                .collect();
            // The same shapes as 64-bit keys (high and low halves folded together).
            let short: Vec<u64> = keys.iter().map(|&k| (k ^ k >> 61) as u64).collect();
            check(
                short,
                &mut scratch_short,
                &format!("{n} 64-bit keys, shape {shape}"),
            );
            check(keys, &mut scratch, &format!("{n} keys, shape {shape}"));
        }
    }

    /// Each list sorted as keys on its own (`sort_own`) and the lists merged (`merge_keys`)
    /// against sorting all their pairs together as tuples and dropping repeats: no list,
    /// one, two, three and five lists (some empty, repeats within and across lists), the
    /// widest ids and polygon numbers that fit 64-bit keys, and the widths refused where
    /// they do not fit.
    #[test]
    fn lists_sorted_apart_then_merged_as_one_sort() {
        let mut rng = crate::geom::test_rng::Rng(17);
        let pool = pool_of_two();
        assert_eq!(short_widths(0, 92_449), Some((17, 17)));
        assert_eq!(short_widths(999, 483), Some((9, 19)));
        assert_eq!(short_widths((1 << 15) - 1, (1 << 17) - 1), Some((17, 32)));
        assert_eq!(short_widths(1 << 15, (1 << 17) - 1), None);
        assert_eq!(short_widths(u32::MAX, 0), Some((0, 32)));
        assert_eq!(short_widths(u32::MAX, 1), None);
        for (lists, n, ids, polys) in [
            (0, 0, 0, 10),
            (1, 20_000, 0, 92_449),
            (2, 30_000, 0, 92_449),
            (3, 10_000, 999, 483),
            (5, 3_000, (1 << 15) - 1, (1 << 17) - 1),
            (2, 100, 3, 7),
            // Long lists of a few keys: repeats across the two halves' cut.
            (2, 6_000, 0, 7),
        ] {
            let widths = short_widths(ids, polys).unwrap();
            let pair = |r: &mut crate::geom::test_rng::Rng| {
                let m = |r: &mut crate::geom::test_rng::Rng, top: u32| {
                    (r.next() % (u64::from(top) + 1)) as u32
                };
                let (a, b) = (m(r, ids), m(r, ids));
                let (p, q) = (m(r, polys), m(r, polys));
                Pair {
                    mesh_a: a.min(b),
                    polygon_a: p,
                    mesh_b: a.max(b),
                    polygon_b: q,
                }
            };
            let mut all: Vec<Vec<Pair>> = (0..lists)
                .map(|l| {
                    let len = if l == 1 && lists > 2 { 0 } else { n };
                    (0..len).map(|_| pair(&mut rng)).collect()
                })
                .collect();
            if lists > 1 && n > 0 {
                let again: Vec<Pair> = all[0][..n / 10].to_vec();
                all[lists - 1].extend(again.iter().chain(&again));
            }
            let mut want: Vec<Pair> = all.iter().flatten().copied().collect();
            want.sort_unstable();
            want.dedup();
            let (mut keys, mut scratch) = (Vec::new(), Vec::new());
            let sorted: Vec<Vec<u64>> = all
                .iter()
                .map(|l| {
                    sort_own(l, widths, &mut keys, &mut scratch);
                    keys.clone()
                })
                .collect();
            let slices: Vec<&[u64]> = sorted.iter().map(|l| &l[..]).collect();
            for par in [false, true] {
                let mut got = vec![pair(&mut rng)];
                pool.install(|| merge_keys(&slices, widths, &mut got, par));
                assert!(
                    got == want,
                    "{lists} lists of {n}, ids to {ids}, polygons to {polys}, par {par}"
                );
            }
        }
    }

    /// The two-worker merge where the cut falls at either end of a list: one list all
    /// below the other, one empty, the lists interleaved, against one sort.
    #[test]
    fn merge_split_at_the_ends() {
        let pool = pool_of_two();
        let widths = short_widths(0, 1 << 16).unwrap();
        let keys = |r: std::ops::Range<u64>, step: u64| -> Vec<u64> {
            r.step_by(step as usize)
                .map(|p| p << widths.1 | (p + 1))
                .collect()
        };
        for (a, b) in [
            (keys(0..10_000, 1), keys(10_000..20_000, 1)),
            (keys(10_000..20_000, 1), keys(0..10_000, 1)),
            (keys(0..20_000, 1), keys(0..20_000, 1)),
            (keys(0..20_000, 2), keys(1..20_000, 2)),
            (Vec::new(), keys(0..20_000, 1)),
            (keys(0..20_000, 1), Vec::new()),
            (keys(0..9_000, 1), keys(5..7, 1)),
        ] {
            let mut want: Vec<Pair> = a.iter().chain(&b).map(|&k| short_pair(k, widths)).collect();
            want.sort_unstable();
            want.dedup();
            let mut got = Vec::new();
            pool.install(|| merge_keys(&[&a, &b], widths, &mut got, true));
            assert!(got == want, "lists of {} and {}", a.len(), b.len());
        }
    }

    /// `sort_pairs` against sorting the pairs as tuples and dropping repeats: ids and
    /// polygon numbers that fit 64-bit keys (one mesh, a thousand meshes, the widest that
    /// fit) and that do not; whole and on a pool of two.
    #[test]
    fn sorts_pairs_as_tuples() {
        let mut rng = crate::geom::test_rng::Rng(9);
        let pool = pool_of_two();
        let mut keys = PairKeys::default();
        for (n, ids, polys) in [
            (50_000, 1, 92_450),
            (30_000, 1000, 484),
            (20_000, (1 << 15) - 1, (1 << 17) - 1),
            (20_000, 1 << 16, 1 << 16),
            (10_000, u32::MAX, 3),
            (3000, 5, u32::MAX),
            (100, 3, 10),
        ] {
            let pairs: Vec<Pair> = (0..n)
                .map(|_| {
                    let m = |r: &mut crate::geom::test_rng::Rng, top: u32| {
                        (r.next() % (u64::from(top) + 1)) as u32
                    };
                    let (a, b) = (m(&mut rng, ids), m(&mut rng, ids));
                    Pair {
                        mesh_a: a.min(b),
                        polygon_a: m(&mut rng, polys),
                        mesh_b: a.max(b),
                        polygon_b: m(&mut rng, polys),
                    }
                })
                .chain((0..n / 10).map(|_| Pair {
                    mesh_a: 0,
                    polygon_a: 1,
                    mesh_b: 0,
                    polygon_b: 2,
                }))
                .collect();
            let tuple = |p: &Pair| (p.mesh_a, p.polygon_a, p.mesh_b, p.polygon_b);
            let mut want = pairs.clone();
            want.sort_unstable_by_key(tuple);
            want.dedup();
            for on_pool in [None, Some(&pool)] {
                let mut got = pairs.clone();
                sort_pairs(&mut got, &mut keys, on_pool);
                assert!(
                    got == want,
                    "{n} pairs, ids to {ids}, polygons to {polys}, pool {}",
                    on_pool.is_some()
                );
            }
        }
    }
}
