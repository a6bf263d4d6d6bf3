//! Sorting a whole-scene answer: each pair as one 128-bit key, sorted least significant
//! byte first (radix sort), one pass per byte that differs between the keys. The pairs of
//! a scene differ in few bytes (a big mesh's polygon numbers need three of each four, one
//! mesh's self pairs none of the mesh ids'): six passes over the 78,000 pairs of a
//! crumpled cloth, where a comparison sort makes seventeen.

/// Keys below this count are sorted by comparison (the radix sort's 4,096 counters cost
/// more than a short sort).
const RADIX_MIN: usize = 4096;

/// Sorts `keys` ascending; `scratch` is reused from call to call (no allocation once
/// grown). With `par` (called inside a pool of two or more workers), the two halves are
/// sorted side by side, then merged.
pub(super) fn sort_keys(keys: &mut Vec<u128>, scratch: &mut Vec<u128>, par: bool) {
    scratch.clear();
    scratch.resize(keys.len(), 0);
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
        let sort = |keys: &mut [u128], scratch: &mut [u128]| {
            if radix(keys, scratch) {
                keys.copy_from_slice(scratch);
            }
        };
        rayon::join(|| sort(lo, lo_scratch), || sort(hi, hi_scratch));
    }
    // The two sorted halves merged into `scratch`, which becomes the keys.
    let (lo, hi) = keys.split_at(half);
    let (mut i, mut j) = (0, 0);
    for k in scratch.iter_mut() {
        let take_lo = j == hi.len() || (i < lo.len() && lo[i] <= hi[j]);
        *k = if take_lo { lo[i] } else { hi[j] };
        i += usize::from(take_lo);
        j += usize::from(!take_lo);
    }
    std::mem::swap(keys, scratch);
}

/// The radix sort of [`sort_keys`] (a comparison sort below [`RADIX_MIN`] keys), with
/// `scratch` as long as `keys`: true when the sorted keys are left in `scratch` (an odd
/// number of passes), false when in `keys`.
fn radix(keys: &mut [u128], scratch: &mut [u128]) -> bool {
    if keys.len() < RADIX_MIN {
        keys.sort_unstable();
        return false;
    }
    // The bytes in which some two keys differ, and every byte's counts, in one read.
    let (mut all_and, mut all_or) = (!0u128, 0u128);
    let mut counts = [[0u32; 256]; 16];
    for &k in keys.iter() {
        all_and &= k;
        all_or |= k;
        for (b, c) in counts.iter_mut().enumerate() {
            c[(k >> (8 * b)) as usize & 0xff] += 1;
        }
    }
    let differ = all_and ^ all_or;
    let (mut from, mut to) = (keys, scratch);
    let mut moved = false;
    for (b, c) in counts.iter().enumerate() {
        if (differ >> (8 * b)) & 0xff == 0 {
            continue;
        }
        // Stable scatter by byte `b`, then the buffers change roles.
        let mut at = [0u32; 256];
        let mut sum = 0;
        for (a, &n) in at.iter_mut().zip(c) {
            *a = sum;
            sum += n;
        }
        for &k in from.iter() {
            let d = (k >> (8 * b)) as usize & 0xff;
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

    /// Against the standard sort: random keys, keys differing in a few scattered bytes
    /// (as a scene's pairs), equal keys, short lists (the comparison path) and long ones;
    /// whole and in halves.
    #[test]
    fn sorts_as_the_standard_sort() {
        let mut rng = crate::geom::test_rng::Rng(5);
        let mut scratch = Vec::new();
        for (n, shape) in [
            (10, 0),
            (5000, 0),
            (20_000, 1),
            (20_000, 2),
            (70_000, 1),
            (30_000, 4),
            (4096, 3),
        ] {
            let mut keys: Vec<u128> = (0..n)
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
            let mut want = keys.clone();
            want.sort_unstable();
            let mut halves = keys.clone();
            sort_keys(&mut keys, &mut scratch, false);
            assert_eq!(keys, want, "{n} keys, shape {shape}");
            sort_keys(&mut halves, &mut scratch, true);
            assert_eq!(halves, want, "{n} keys, shape {shape}, in halves");
        }
    }
}
