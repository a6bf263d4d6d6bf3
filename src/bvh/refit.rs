//! The per-frame refit (paper section 2.4): every leaf box and the root refitted around the
//! leaf's contiguous run of vertices.

use super::LeafBoxes;
use crate::geom::{f32_down, f32_up, Aabb};

impl LeafBoxes {
    /// Refits every leaf and the root to the slot positions. No allocation.
    pub fn refit(&mut self, slots: &[[f32; 3]]) {
        let mut root = Aabb::EMPTY;
        for (l, out) in self.boxes.iter_mut().enumerate() {
            let run = &slots[self.leaf_slots[l] as usize..self.leaf_slots[l + 1] as usize];
            *out = fit(run);
            root.merge(out);
        }
        self.root = root;
    }

    /// Refits every leaf and the root to double slot positions (an f64 mesh's): each box
    /// fitted in `f64`, then rounded outward to `f32`, so it holds every position.
    pub fn refit_f64(&mut self, slots: &[[f64; 3]]) {
        let mut root = Aabb::EMPTY;
        for (l, out) in self.boxes.iter_mut().enumerate() {
            let run = &slots[self.leaf_slots[l] as usize..self.leaf_slots[l + 1] as usize];
            let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
            for p in run {
                for k in 0..3 {
                    lo[k] = if p[k] < lo[k] { p[k] } else { lo[k] };
                    hi[k] = if p[k] > hi[k] { p[k] } else { hi[k] };
                }
            }
            *out = Aabb {
                min: lo.map(f32_down),
                max: hi.map(f32_up),
            };
            root.merge(out);
        }
        self.root = root;
    }
}

/// Box of a run of points. Four points (twelve floats) at a time into twelve independent
/// accumulators, which the compiler turns into packed min/max; the inputs are finite (the
/// mesh rejects anything else), so the plain comparisons need no NaN handling.
#[inline]
pub fn fit(run: &[[f32; 3]]) -> Aabb {
    let flat = run.as_flattened();
    let mut lo = [f32::INFINITY; 12];
    let mut hi = [f32::NEG_INFINITY; 12];
    let mut chunks = flat.chunks_exact(12);
    for c in &mut chunks {
        for i in 0..12 {
            lo[i] = if c[i] < lo[i] { c[i] } else { lo[i] };
            hi[i] = if c[i] > hi[i] { c[i] } else { hi[i] };
        }
    }
    for (i, &v) in chunks.remainder().iter().enumerate() {
        lo[i] = if v < lo[i] { v } else { lo[i] };
        hi[i] = if v > hi[i] { v } else { hi[i] };
    }
    let mut b = Aabb::EMPTY;
    for i in 0..12 {
        let k = i % 3;
        b.min[k] = b.min[k].min(lo[i]);
        b.max[k] = b.max[k].max(hi[i]);
    }
    b
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fit_matches_a_plain_loop_for_every_length() {
        for n in 1..40 {
            let pts: Vec<[f32; 3]> = (0..n)
                .map(|i| {
                    [
                        (i as f32 * 1.7).sin(),
                        (i as f32 * 0.3).cos() * 5.0,
                        -(i as f32),
                    ]
                })
                .collect();
            let mut want = Aabb::EMPTY;
            pts.iter().for_each(|p| want.grow(p));
            assert_eq!(fit(&pts), want, "n = {n}");
        }
    }
}
