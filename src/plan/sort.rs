//! Sorting a whole-scene answer: each pair as one 128-bit key, sorted least significant
//! byte first (radix sort), one pass per byte that differs between the keys. The pairs of
//! a scene differ in few bytes (a big mesh's polygon numbers need three of each four, one
//! mesh's self pairs none of the mesh ids'): six passes over the 78,000 pairs of a
//! crumpled cloth, where a comparison sort makes seventeen.

/// Keys below this count are sorted by comparison (the radix sort's 4,096 counters cost
/// more than a short sort).
const RADIX_MIN: usize = 4096;

/// Sorts `keys` ascending; `scratch` is reused from call to call. With `par` (called
/// inside a pool of two or more workers), the two halves are sorted side by side, then
/// merged.
pub(super) fn sort_keys(keys: &mut Vec<u128>, scratch: &mut Vec<u128>, par: bool) {
    if !par || keys.len() < 2 * RADIX_MIN {
        return radix(keys, scratch);
    }
    let half = keys.len() / 2;
    let (mut lo, mut hi) = (keys[..half].to_vec(), keys[half..].to_vec());
    let (mut lo_scratch, mut hi_scratch) = (Vec::new(), std::mem::take(scratch));
    rayon::join(
        || radix(&mut lo, &mut lo_scratch),
        || radix(&mut hi, &mut hi_scratch),
    );
    *scratch = hi_scratch;
    // The two sorted runs merged back into `keys`.
    let (mut i, mut j) = (0, 0);
    for k in keys.iter_mut() {
        let take_lo = j == hi.len() || (i < lo.len() && lo[i] <= hi[j]);
        *k = if take_lo { lo[i] } else { hi[j] };
        i += usize::from(take_lo);
        j += usize::from(!take_lo);
    }
}

/// The radix sort of [`sort_keys`] (a comparison sort below [`RADIX_MIN`] keys).
fn radix(keys: &mut Vec<u128>, scratch: &mut Vec<u128>) {
    if keys.len() < RADIX_MIN {
        keys.sort_unstable();
        return;
    }
    // The bytes in which some two keys differ, and every byte's counts, in one read.
    let (mut all_and, mut all_or) = (!0u128, 0u128);
    let mut counts = vec![[0u32; 256]; 16];
    for &k in keys.iter() {
        all_and &= k;
        all_or |= k;
        for (b, c) in counts.iter_mut().enumerate() {
            c[(k >> (8 * b)) as usize & 0xff] += 1;
        }
    }
    let differ = all_and ^ all_or;
    scratch.clear();
    scratch.resize(keys.len(), 0);
    for (b, c) in counts.iter().enumerate() {
        if (differ >> (8 * b)) & 0xff == 0 {
            continue;
        }
        // Stable scatter of `keys` by byte `b` into `scratch`, then swap.
        let mut at = [0u32; 256];
        let mut sum = 0;
        for (a, &n) in at.iter_mut().zip(c) {
            *a = sum;
            sum += n;
        }
        for &k in keys.iter() {
            let d = (k >> (8 * b)) as usize & 0xff;
            scratch[at[d] as usize] = k;
            at[d] += 1;
        }
        std::mem::swap(keys, scratch);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Against the standard sort: random keys, keys differing in a few scattered bytes
    /// (as a scene's pairs), equal keys, short lists (the comparison path) and long ones.
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
