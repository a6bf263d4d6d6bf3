//! Sort and sweep: every pair of boxes, one from each of two sets, that meet, found in
//! about the time of the pairs that meet rather than the product of the set sizes.

use super::{sortable_key, Aabb};

/// Sets with at most this many volume-candidate pairs are paired by brute force.
const BRUTE_UP_TO: usize = 1024;

/// A box tagged with its position in the caller's list.
#[derive(Clone, Copy)]
struct Tagged {
    b: Aabb,
    at: u32,
}

/// Scratch of [`Sweep::pairs`], reused from call to call.
#[derive(Default)]
pub struct Sweep {
    keys: Vec<u64>,
    v: Vec<Tagged>,
    c: Vec<Tagged>,
}

impl Sweep {
    /// Appends every (volume, candidate) pair whose boxes meet, as positions in `vols` and
    /// `cands`: all pairs for small sets, else a sort-and-sweep along the axis where the
    /// candidates are most spread out for their size.
    pub fn pairs(&mut self, vols: &[Aabb], cands: &[Aabb], out: &mut Vec<(u32, u32)>) {
        if vols.len() * cands.len() <= BRUTE_UP_TO || vols.len() == 1 || cands.len() == 1 {
            for (i, v) in vols.iter().enumerate() {
                out.extend(
                    cands
                        .iter()
                        .enumerate()
                        .filter(|(_, c)| v.meets(c))
                        .map(|(j, _)| (i as u32, j as u32)),
                );
            }
            return;
        }
        let axis = spread_axis(cands);
        sorted(vols, axis, &mut self.keys, &mut self.v);
        sorted(cands, axis, &mut self.keys, &mut self.c);
        let (vs, cs) = (&self.v, &self.c);
        let (mut i, mut j) = (0, 0);
        while i < vs.len() && j < cs.len() {
            let (v, c) = (&vs[i], &cs[j]);
            if v.b.min[axis] <= c.b.min[axis] {
                // v starts first: every candidate starting before v ends may meet it.
                for ck in &cs[j..] {
                    if ck.b.min[axis] > v.b.max[axis] {
                        break;
                    }
                    if v.b.meets(&ck.b) {
                        out.push((v.at, ck.at));
                    }
                }
                i += 1;
            } else {
                for vk in &vs[i..] {
                    if vk.b.min[axis] > c.b.max[axis] {
                        break;
                    }
                    if vk.b.meets(&c.b) {
                        out.push((vk.at, c.at));
                    }
                }
                j += 1;
            }
        }
    }
}

/// The axis along which the boxes spread the most for their mean size.
fn spread_axis(b: &[Aabb]) -> usize {
    let ratio = |k: usize| {
        let (mut lo, mut hi, mut size) = (f32::INFINITY, f32::NEG_INFINITY, 0.0f64);
        for c in b {
            lo = lo.min(c.min[k]);
            hi = hi.max(c.max[k]);
            size += f64::from(c.max[k] - c.min[k]);
        }
        (f64::from(hi) - f64::from(lo)) / (size / b.len() as f64 + f64::MIN_POSITIVE)
    };
    let (r0, r1, r2) = (ratio(0), ratio(1), ratio(2));
    if r0 >= r1 && r0 >= r2 {
        0
    } else if r1 >= r2 {
        1
    } else {
        2
    }
}

/// `b` tagged and sorted by lower bound along `axis`, through integer keys (an
/// order-preserving map of the `f32` bits, then the position).
fn sorted(b: &[Aabb], axis: usize, keys: &mut Vec<u64>, out: &mut Vec<Tagged>) {
    keys.clear();
    keys.extend(
        b.iter()
            .enumerate()
            .map(|(i, x)| u64::from(sortable_key(x.min[axis])) << 32 | i as u64),
    );
    keys.sort_unstable();
    out.clear();
    out.extend(keys.iter().map(|&k| {
        let at = k as u32;
        Tagged {
            b: b[at as usize],
            at,
        }
    }));
}

#[cfg(test)]
mod tests {
    use super::*;

    /// 150 boxes of sides up to 2 and 170 of sides up to 1 in a cube of side 10
    /// (deterministic).
    fn random_boxes() -> (Vec<Aabb>, Vec<Aabb>) {
        let mut s = 12345u64;
        let mut rnd = || {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            (s >> 40) as f32 / (1u64 << 24) as f32
        };
        let mut boxes = |n: usize, size: f32| -> Vec<Aabb> {
            (0..n)
                .map(|_| {
                    let p = [rnd() * 10.0, rnd() * 10.0, rnd() * 10.0];
                    let d = [rnd() * size, rnd() * size, rnd() * size];
                    Aabb {
                        min: p,
                        max: [p[0] + d[0], p[1] + d[1], p[2] + d[2]],
                    }
                })
                .collect()
        };
        let vb = boxes(150, 2.0);
        (vb, boxes(170, 1.0))
    }

    #[test]
    fn sweep_finds_exactly_the_overlapping_pairs() {
        let (vb, cb) = random_boxes();
        let mut got = Vec::new();
        Sweep::default().pairs(&vb, &cb, &mut got);
        got.sort_unstable();
        let mut want = Vec::new();
        for (i, v) in vb.iter().enumerate() {
            for (j, c) in cb.iter().enumerate() {
                if v.overlaps(c, 0.0) {
                    want.push((i as u32, j as u32));
                }
            }
        }
        assert!(!want.is_empty());
        assert_eq!(got, want);
    }
}
