//! The CPU backend's whole query ([`Selector::run_query`](crate::backend::Selector)): the
//! five steps of [`crate::query::run`] with the same tests, so the same answer and the same
//! per-step counts, run leaf pair by leaf pair over scratch buffers the selector keeps: no
//! batches, no allocation once the buffers have grown.
//!
//! Box tests compare `f32` boxes with volumes grown by `h` and rounded outward to `f32`
//! ([`grown`]), which keeps exactly the pairs the step path's `f64` comparisons keep.
//! Polygon boxes are computed a leaf at a time into [`Lanes`] and tested eight at a time:
//! steps 3 and 4 test a leaf's polygons against the other leaf's box, step 5 tests every
//! other polygon's box against all the reference polygons' (a sort-and-sweep only for very
//! large leaf pairs, where it is cheaper than testing every pair). The narrow test of step
//! 5 is the step path's ([`polygons_meet`]).

use std::time::Instant;

use super::lanes::Lanes;
use super::{meets_exact as meets, polygons_meet, CpuSelector, Prepared};
use crate::backend::{Prim, QueryMeshes};
use crate::geom::Aabb;
use crate::query::{Contact, QueryStats};

/// Buffers of the fused query, reused from query to query.
#[derive(Default)]
pub(super) struct Scratch {
    /// Step 1: (query mesh, leaf) of the other meshes' leaves that meet the reference root.
    others: Vec<(u32, u32)>,
    /// Their boxes grown by `h` (the volumes of steps 2 and 3).
    grown: Vec<Aabb>,
    /// Step 2: (position in `others`, reference leaf), sorted.
    pairs: Vec<(u32, u32)>,
    /// Steps 3 and 4, per pair `i`: the reference polygons inside the other leaf's box,
    /// `refs[ref_start[i]..ref_start[i + 1]]`, and the other polygons inside the reference
    /// leaf's box.
    ref_start: Vec<u32>,
    refs: Vec<u32>,
    other_start: Vec<u32>,
    other_polys: Vec<u32>,
    /// Step 5, one pair at a time: the reference polygons' boxes grown by `h`, the other
    /// polygons' boxes, and the box pairs that meet.
    vboxes: Vec<Aabb>,
    cboxes: Vec<Aabb>,
    box_pairs: Vec<(u32, u32)>,
    /// Step 5: the reference polygons' grown boxes in lanes; box-test bit masks (steps 3
    /// to 5).
    lanes: Lanes,
    masks: Vec<u32>,
    sweep: Sweep,
}

impl CpuSelector {
    /// The five steps for `q.meshes[0]` against the others: contacts appended to `out`
    /// (each pair once, in no particular order), counts and times in `stats`.
    pub(super) fn run_fused(
        &mut self,
        q: &QueryMeshes<'_>,
        out: &mut Vec<Contact>,
        stats: &mut QueryStats,
    ) {
        let h = q.half_depth;
        let reference = q.meshes[0].1;
        self.sync_caches(q);
        let s = &mut self.fused;

        // Step 1: the other meshes' leaves inside the reference's root box.
        let t = Instant::now();
        let root = grown(&reference.root(), h);
        s.others.clear();
        for (mi, (_, m)) in q.meshes.iter().enumerate().skip(1) {
            if reference.root().overlaps(&m.root(), h) {
                stats.tests[0] += m.leaf_count();
                s.others.extend(
                    m.leaves
                        .boxes
                        .iter()
                        .enumerate()
                        .filter(|(_, b)| meets(&root, b))
                        .map(|(l, _)| (mi as u32, l as u32)),
                );
            }
        }
        if stats.tests[0] == 0 {
            return;
        }
        stats.hits[0] = s.others.len();
        stats.nanos[0] = t.elapsed().as_nanos() as u64;
        if s.others.is_empty() {
            return;
        }

        // Step 2: for each of those leaves, the reference leaves inside its box.
        let t = Instant::now();
        s.grown.clear();
        s.grown.extend(
            s.others
                .iter()
                .map(|&(mi, l)| grown(&q.meshes[mi as usize].1.leaves.boxes[l as usize], h)),
        );
        stats.tests[1] = s.others.len() * reference.leaf_count();
        s.pairs.clear();
        s.sweep
            .pairs(&s.grown, &reference.leaves.boxes, &mut s.pairs);
        s.pairs.sort_unstable();
        stats.hits[1] = s.pairs.len();
        stats.nanos[1] = t.elapsed().as_nanos() as u64;
        if s.pairs.is_empty() {
            return;
        }

        // Step 3: per pair, the reference leaf's polygons inside the other leaf's box.
        let t = Instant::now();
        let rc = &mut self.caches[self.slot_cache[0]];
        s.ref_start.clear();
        s.ref_start.push(0);
        s.refs.clear();
        for &(o, r) in &s.pairs {
            let vol = s.grown[o as usize];
            let polys = rc.leaf(reference, r as usize);
            stats.tests[2] += polys.len();
            rc.boxes.select(polys, &vol, &mut s.masks, &mut s.refs);
            s.ref_start.push(s.refs.len() as u32);
        }
        stats.hits[2] = s.refs.len();
        stats.nanos[2] = t.elapsed().as_nanos() as u64;

        // Step 4: per pair, the other leaf's polygons inside the reference leaf's box.
        let t = Instant::now();
        s.other_start.clear();
        s.other_start.push(0);
        s.other_polys.clear();
        for &(o, r) in &s.pairs {
            let (mi, l) = s.others[o as usize];
            let vol = grown(&reference.leaves.boxes[r as usize], h);
            let oc = &mut self.caches[self.slot_cache[mi as usize]];
            let polys = oc.leaf(q.meshes[mi as usize].1, l as usize);
            stats.tests[3] += polys.len();
            oc.boxes
                .select(polys, &vol, &mut s.masks, &mut s.other_polys);
            s.other_start.push(s.other_polys.len() as u32);
        }
        stats.hits[3] = s.other_polys.len();
        stats.nanos[3] = t.elapsed().as_nanos() as u64;

        // Step 5: per pair, each reference polygon's viewing volume against the other
        // polygons: box pairs first, then the narrow test.
        let t = Instant::now();
        let found = out.len();
        let rc = &self.caches[self.slot_cache[0]];
        for (i, &(o, _)) in s.pairs.iter().enumerate() {
            let refs = &s.refs[s.ref_start[i] as usize..s.ref_start[i + 1] as usize];
            let others = &s.other_polys[s.other_start[i] as usize..s.other_start[i + 1] as usize];
            if refs.is_empty() || others.is_empty() {
                continue;
            }
            stats.tests[4] += refs.len() * others.len();
            let mi = s.others[o as usize].0;
            let oc = &self.caches[self.slot_cache[mi as usize]];
            s.box_pairs.clear();
            s.cboxes.clear();
            s.cboxes
                .extend(others.iter().map(|&p| oc.boxes.get(p as usize)));
            if refs.len() * others.len() > SWEEP_STEP5_ABOVE {
                s.vboxes.clear();
                s.vboxes
                    .extend(refs.iter().map(|&p| grown(&rc.boxes.get(p as usize), h)));
                s.sweep.pairs(&s.vboxes, &s.cboxes, &mut s.box_pairs);
            } else {
                // The reference polygons' grown boxes in lanes, each other polygon's box
                // against all of them, eight at a time.
                s.lanes.resize(refs.len());
                for (v, &p) in refs.iter().enumerate() {
                    s.lanes.set(v, &grown(&rc.boxes.get(p as usize), h));
                }
                let pairs = &mut s.box_pairs;
                s.lanes
                    .each_pair(0..refs.len(), &s.cboxes, &mut s.masks, |v, c| {
                        pairs.push((v, c))
                    });
            }
            if s.box_pairs.is_empty() {
                continue;
            }
            self.stamp += 1; // 64 bits: never wraps, so a stale entry never looks fresh
            let stamp = self.stamp;
            if self.vprep.len() < refs.len() {
                self.vprep.resize(refs.len(), Prepared::default());
            }
            if self.cprep.len() < others.len() {
                self.cprep.resize(others.len(), Prepared::default());
            }
            self.cells.clear();
            self.cells
                .resize(if h > 0.0 { refs.len() } else { 0 }, None);
            let (id, m) = q.meshes[mi as usize];
            for &(v, c) in &s.box_pairs {
                let (rp, op) = (refs[v as usize], others[c as usize]);
                let pv = self.vprep[v as usize].get(stamp, q, Prim { mesh: 0, index: rp });
                let pc = self.cprep[c as usize].get(
                    stamp,
                    q,
                    Prim {
                        mesh: mi,
                        index: op,
                    },
                );
                let cells =
                    (h > 0.0).then(|| &*self.cells[v as usize].get_or_insert_with(|| pv.cells(h)));
                if polygons_meet(pv, pc, cells) {
                    out.push(Contact {
                        other_mesh: id,
                        reference_polygon: reference.poly_ids[rp as usize],
                        other_polygon: m.poly_ids[op as usize],
                    });
                }
            }
        }
        stats.hits[4] = out.len() - found;
        stats.nanos[4] = t.elapsed().as_nanos() as u64;
    }
}

/// `b` grown by `h` on every side with its bounds rounded outward to `f32`. An `f32` box
/// meets it (closed comparisons) exactly when the box's bounds meet `b.min - h` and
/// `b.max + h` computed in `f64`, the step path's test: a float is at least a real number
/// exactly when it is at least the smallest float above that number.
#[inline]
fn grown(b: &Aabb, h: f64) -> Aabb {
    if h == 0.0 {
        return *b;
    }
    Aabb {
        min: b.min.map(|x| f32_up(f64::from(x) - h)),
        max: b.max.map(|x| f32_down(f64::from(x) + h)),
    }
}

/// The smallest `f32` at or above `x` (not NaN); `+inf` above `f32::MAX`.
#[inline]
fn f32_up(x: f64) -> f32 {
    let f = x as f32;
    if f64::from(f) >= x {
        f
    } else if f == 0.0 {
        f32::from_bits(1)
    } else if f > 0.0 {
        f32::from_bits(f.to_bits() + 1)
    } else {
        // Negative (`-inf` included): one step towards zero.
        f32::from_bits(f.to_bits() - 1)
    }
}

/// The largest `f32` at or below `x` (not NaN); `-inf` below `-f32::MAX`.
#[inline]
fn f32_down(x: f64) -> f32 {
    -f32_up(-x)
}

/// Sets with at most this many volume-candidate pairs are paired by brute force.
const BRUTE_UP_TO: usize = 1024;

/// A step-5 leaf pair with more than this many polygon pairs is swept like step 2, not
/// tested pair by pair (vectorised).
const SWEEP_STEP5_ABOVE: usize = 1 << 16;

/// A box tagged with its position in the caller's list.
#[derive(Clone, Copy)]
struct Tagged {
    b: Aabb,
    at: u32,
}

/// Scratch of [`Sweep::pairs`].
#[derive(Default)]
struct Sweep {
    keys: Vec<u64>,
    v: Vec<Tagged>,
    c: Vec<Tagged>,
}

impl Sweep {
    /// Appends every (volume, candidate) pair whose boxes meet, as positions in `vols` and
    /// `cands`: all pairs for small sets, else a sort-and-sweep along the axis where the
    /// candidates are most spread out for their size.
    fn pairs(&mut self, vols: &[Aabb], cands: &[Aabb], out: &mut Vec<(u32, u32)>) {
        if vols.len() * cands.len() <= BRUTE_UP_TO || vols.len() == 1 || cands.len() == 1 {
            for (i, v) in vols.iter().enumerate() {
                out.extend(
                    cands
                        .iter()
                        .enumerate()
                        .filter(|(_, c)| meets(v, c))
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
                    if meets(&v.b, &ck.b) {
                        out.push((v.at, ck.at));
                    }
                }
                i += 1;
            } else {
                for vk in &vs[i..] {
                    if vk.b.min[axis] > c.b.max[axis] {
                        break;
                    }
                    if meets(&vk.b, &c.b) {
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
    let key = |x: f32| {
        let u = x.to_bits();
        u64::from(if u >> 31 == 1 { !u } else { u | 1 << 31 })
    };
    keys.clear();
    keys.extend(
        b.iter()
            .enumerate()
            .map(|(i, x)| key(x.min[axis]) << 32 | i as u64),
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

    #[test]
    fn outward_rounding_is_tight() {
        // The float just below a finite `f32` (as f64).
        let below = |f: f32| {
            let b = f.to_bits();
            f64::from(if f == 0.0 {
                -f32::from_bits(1)
            } else if f > 0.0 {
                f32::from_bits(b - 1)
            } else {
                f32::from_bits(b + 1)
            })
        };
        for x in [
            0.0, 1.0, -1.0, 0.1, -0.1, 1e-45, -1e-45, 1e-50, 3e38, -3e38, -1e300,
        ] {
            let (u, d) = (f32_up(x), f32_down(-x));
            assert!(f64::from(u) >= x && below(u) < x, "{x}");
            assert_eq!(d, -u, "{x}");
        }
        assert_eq!(f32_up(1e300), f32::INFINITY);
        assert_eq!(f32_up(-1e300), -f32::MAX);
        assert_eq!(f32_down(1e300), f32::MAX);
        assert_eq!(
            f32_up(f64::from(f32::MIN_POSITIVE) / 4.0),
            f32::MIN_POSITIVE / 4.0
        );
        assert_eq!(f32_up(1e-50), f32::from_bits(1));
        assert_eq!(f32_up(-1e-50), -0.0);
    }

    #[test]
    fn grown_boxes_keep_what_the_f64_test_keeps() {
        // Boxes at distances around h, near f32 ties: the f32 test against the rounded-out
        // box agrees with Aabb-style f64 arithmetic on every one.
        let mut s = 99u64;
        let mut rnd = || {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            (s >> 40) as f32 / (1u64 << 24) as f32
        };
        for h in [0.0, 1e-7, 0.3, 0.5, 1.0 / 3.0] {
            for _ in 0..20000 {
                let v = Aabb {
                    min: [rnd(), rnd(), rnd()],
                    max: [1.0 + rnd(), 1.0 + rnd(), 1.0 + rnd()],
                };
                let o = rnd() * 0.001;
                let c = Aabb {
                    min: v.max.map(|x| x + (h as f32) - 0.0005 + o),
                    max: v.max.map(|x| x + 2.0 + o),
                };
                let f64_test = (0..3).all(|k| {
                    f64::from(c.max[k]) >= f64::from(v.min[k]) - h
                        && f64::from(c.min[k]) <= f64::from(v.max[k]) + h
                });
                assert_eq!(meets(&grown(&v, h), &c), f64_test, "h = {h}");
            }
        }
    }

    #[test]
    fn sweep_finds_exactly_the_overlapping_pairs() {
        let (vb, cb) = super::super::tests::random_boxes();
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
