//! The CPU backend: selection semantics computed exactly or in `f64`.
//!
//! Box volumes (steps 1-4) keep a candidate when its box meets the volume grown by `h`
//! (closed, exact comparisons): for polygons that is a superset of what clipping keeps,
//! which only costs step 5 some work. Polygon volumes (step 5) give the final answer:
//! - `h = 0`: the closed polygons intersect, decided by exact predicates;
//! - `h > 0`: the candidate survives clipping against the reference polygon's volume
//!   ([`Cell`]) in `f64` in the volume's own frame, or intersects the polygon exactly (so
//!   rounding in the clipper can never lose a true intersection).
//!
//! Inside a group, volumes and candidates are first paired by their boxes (grown by `h`):
//! all pairs for small groups, a sort-and-sweep along the widest axis for large ones, so a
//! leaf pair in deep contact costs about its box overlaps rather than the product of its
//! polygon counts.
//!
//! The whole query normally runs fused ([`fused`]): the same five steps and tests, leaf pair
//! by leaf pair, without batches. [`CpuSelector::set_fused`] turns that off, so each step
//! goes through [`Selector::select`] (the tests compare the two).

mod fused;
mod lanes;

use super::{Backend, Batch, Hit, Prim, QueryMeshes, Selector, Step};
use crate::error::Result;
use crate::geom::tritri::{separated, triangles_intersect_with, Plane};
use crate::geom::volume::Cell;
use crate::geom::{Aabb, P3};
use crate::query::{Contact, QueryStats};
use lanes::Lanes;

/// Groups with at most this many volume-candidate tests are paired by brute force.
const SWEEP_ABOVE: usize = 1024;

/// Polygon boxes of one mesh, computed on first use (polygon by polygon, or a whole leaf at
/// once) and valid while the mesh's positions do not change (its generation): a polygon is
/// boxed once per frame, however many steps and leaf pairs ask about it.
#[derive(Default)]
struct BoxCache {
    id: u32,
    generation: u64,
    /// `stamp[p] == current` marks `boxes[p]` valid.
    stamp: Vec<u32>,
    /// `leaf_stamp[l] == current` marks the boxes of all of leaf `l`'s polygons valid.
    leaf_stamp: Vec<u32>,
    current: u32,
    boxes: Lanes,
}

impl BoxCache {
    fn revalidate(&mut self, id: u32, m: &crate::mesh::Mesh) {
        let n = m.polygon_count();
        if self.id != id
            || self.boxes.len() != n
            || self.leaf_stamp.len() != m.leaf_count()
            || self.current == u32::MAX
        {
            self.stamp.clear();
            self.stamp.resize(n, 0);
            self.leaf_stamp.clear();
            self.leaf_stamp.resize(m.leaf_count(), 0);
            self.boxes.resize(n);
            self.current = 1;
        } else if self.generation != m.generation {
            self.current += 1;
        }
        self.id = id;
        self.generation = m.generation;
    }

    /// Makes the boxes of leaf `l`'s polygons valid; returns their range in `boxes`.
    #[inline]
    fn leaf(&mut self, m: &crate::mesh::Mesh, l: usize) -> std::ops::Range<usize> {
        let r = m.leaves.polys(l);
        if self.leaf_stamp[l] != self.current {
            self.boxes.fit_polygons(m, r.clone());
            self.stamp[r.clone()].fill(self.current);
            self.leaf_stamp[l] = self.current;
        }
        r
    }

    #[inline]
    fn get(&mut self, m: &crate::mesh::Mesh, p: usize) -> Aabb {
        if self.stamp[p] != self.current {
            self.boxes.set(p, &m.poly_box(p));
            self.stamp[p] = self.current;
        }
        self.boxes.get(p)
    }
}

/// The CPU backend. Holds scratch space and the polygon-box caches.
#[derive(Default)]
pub struct CpuSelector {
    /// Answer step by step through [`Selector::select`] instead of the fused query.
    step_by_step: bool,
    fused: fused::Scratch,
    caches: Vec<BoxCache>,
    /// Query mesh slot -> index in `caches`.
    slot_cache: Vec<usize>,
    vboxes: Vec<Aabb>,
    cboxes: Vec<Aabb>,
    pairs: Vec<(u32, u32)>,
    vwide: Vec<Wide>,
    cwide: Vec<Wide>,
    keys: Vec<(u64, u32)>,
    tmp: Vec<Wide>,
    cells: Vec<Option<[Cell; 2]>>,
    vprep: Vec<Prepared>,
    cprep: Vec<Prepared>,
    stamp: u64,
}

/// A polygon as one or two `f64` triangles.
#[derive(Clone, Copy, Default)]
struct Polygon {
    tris: [[P3; 3]; 2],
    n: usize,
}

/// A polygon of the current step-5 group, widened and with its triangles' planes, valid
/// while `stamp` is the group's.
#[derive(Clone, Copy)]
struct Prepared {
    stamp: u64,
    poly: Polygon,
    planes: [Plane; 2],
}

impl Default for Prepared {
    fn default() -> Self {
        let zero = [[0.0; 3]; 3];
        Prepared {
            stamp: 0,
            poly: Polygon::default(),
            planes: [Plane::of(&zero); 2],
        }
    }
}

impl Prepared {
    /// The polygon made of `tris[..n]`.
    #[inline]
    fn of(tris: [[P3; 3]; 2], n: usize, stamp: u64) -> Prepared {
        Prepared {
            stamp,
            poly: Polygon { tris, n },
            planes: [Plane::of(&tris[0]), Plane::of(&tris[n - 1])],
        }
    }

    #[inline]
    fn get(&mut self, stamp: u64, q: &QueryMeshes<'_>, p: Prim) -> &Prepared {
        if self.stamp != stamp {
            let mut tris = [[[0.0; 3]; 3]; 2];
            let n = q.mesh(p).triangles(p.index as usize, &mut tris);
            *self = Prepared::of(tris, n, stamp);
        }
        self
    }

    /// The viewing volumes of the polygon's triangles (`h > 0`).
    fn cells(&self, h: f64) -> [Cell; 2] {
        [
            Cell::of_triangle(&self.poly.tris[0], h),
            Cell::of_triangle(&self.poly.tris[self.poly.n - 1], h),
        ]
    }
}

/// The CPU backend's step-5 decision for one polygon pair, each given as its triangles
/// (`v_tris[..nv]`, `c_tris[..nc]`): with `h > 0`, does the candidate meet the viewing
/// volume of `v` or intersect it exactly; with `h = 0`, do the closed polygons intersect?
/// The GL backends confirm their hits with it, so their contacts are this backend's.
pub fn polygon_meets(
    v_tris: &[[P3; 3]; 2],
    nv: usize,
    c_tris: &[[P3; 3]; 2],
    nc: usize,
    h: f64,
) -> bool {
    let (v, c) = (Prepared::of(*v_tris, nv, 0), Prepared::of(*c_tris, nc, 0));
    let cells = (h > 0.0).then(|| v.cells(h));
    polygons_meet(&v, &c, cells.as_ref())
}

/// Step 5's test of a box-overlapping pair: candidate polygon `c` survives clipping against
/// the viewing volumes `cells` of volume polygon `v` (`h > 0`), or the closed polygons
/// intersect (exact predicates, after a conservative plane rejection).
#[inline]
fn polygons_meet(v: &Prepared, c: &Prepared, cells: Option<&[Cell; 2]>) -> bool {
    (0..v.poly.n).any(|a| {
        (0..c.poly.n).any(|b| {
            let (ta, tb) = (&v.poly.tris[a], &c.poly.tris[b]);
            cells.is_some_and(|cl| cl[a].meets_triangle(tb)) || {
                // The planes' certain signs spare the exact test those orientations.
                let su = v.planes[a].sides(tb);
                !separated(su) && {
                    let st = c.planes[b].sides(ta);
                    !separated(st) && triangles_intersect_with(ta, tb, su, st)
                }
            }
        })
    })
}

impl CpuSelector {
    pub fn new() -> CpuSelector {
        CpuSelector::default()
    }

    /// Fused query (the default) or step by step through batches: the same answer and
    /// the same per-step test and hit counts.
    pub fn set_fused(&mut self, on: bool) {
        self.step_by_step = !on;
    }

    /// Maps the query's meshes to their caches (made or revalidated), dropping the caches
    /// of meshes no longer in the query.
    fn sync_caches(&mut self, q: &QueryMeshes<'_>) {
        self.caches
            .retain(|c| q.meshes.iter().any(|(id, _)| *id == c.id));
        self.slot_cache.clear();
        for &(id, m) in &q.meshes {
            let i = match self.caches.iter().position(|c| c.id == id) {
                Some(i) => i,
                None => {
                    self.caches.push(BoxCache::default());
                    self.caches.len() - 1
                }
            };
            self.caches[i].revalidate(id, m);
            self.slot_cache.push(i);
        }
    }
}

impl std::fmt::Debug for CpuSelector {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("CpuSelector")
    }
}

impl Selector for CpuSelector {
    fn backend(&self) -> Backend {
        Backend::Cpu
    }

    fn run_query(
        &mut self,
        q: &QueryMeshes<'_>,
        out: &mut Vec<Contact>,
        stats: &mut QueryStats,
    ) -> Result<bool> {
        if self.step_by_step {
            return Ok(false);
        }
        self.run_fused(q, out, stats);
        Ok(true)
    }

    fn select(&mut self, q: &QueryMeshes<'_>, batch: &Batch, hits: &mut Vec<Hit>) -> Result<()> {
        let h = q.half_depth;
        if batch.step != Step::BoxesInBoxes {
            self.sync_caches(q);
        }
        for g in &batch.groups {
            let vols = &batch.volumes[g.volumes.start as usize..g.volumes.end as usize];
            let cands = &batch.candidates[g.candidates.start as usize..g.candidates.end as usize];
            self.vboxes.clear();
            self.cboxes.clear();
            match batch.step {
                Step::BoxesInBoxes => {
                    self.vboxes.extend(vols.iter().map(|&v| q.boxed(v)));
                    self.cboxes.extend(cands.iter().map(|&c| q.boxed(c)));
                }
                Step::PolygonsInBoxes => {
                    self.vboxes.extend(vols.iter().map(|&v| q.boxed(v)));
                    for &c in cands {
                        let cache = &mut self.caches[self.slot_cache[c.mesh as usize]];
                        self.cboxes.push(cache.get(q.mesh(c), c.index as usize));
                    }
                }
                Step::PolygonsInPolygons => {
                    for &v in vols {
                        let cache = &mut self.caches[self.slot_cache[v.mesh as usize]];
                        self.vboxes.push(cache.get(q.mesh(v), v.index as usize));
                    }
                    for &c in cands {
                        let cache = &mut self.caches[self.slot_cache[c.mesh as usize]];
                        self.cboxes.push(cache.get(q.mesh(c), c.index as usize));
                    }
                }
            }
            self.pairs.clear();
            box_pairs(
                &self.vboxes,
                &self.cboxes,
                h,
                &mut self.vwide,
                &mut self.cwide,
                &mut self.keys,
                &mut self.tmp,
                &mut self.pairs,
            );
            let hit = |(v, c): (u32, u32)| Hit {
                volume: g.volumes.start + v,
                candidate: g.candidates.start + c,
            };
            if batch.step != Step::PolygonsInPolygons {
                hits.extend(self.pairs.iter().map(|&p| hit(p)));
                continue;
            }
            // Step 5: the narrow test on the box-overlapping pairs. Each polygon of the
            // group is widened to f64 and given its planes once (on first use), and each
            // volume its cells.
            self.stamp += 1; // 64 bits: never wraps, so a stale entry never looks fresh
            let stamp = self.stamp;
            if self.vprep.len() < vols.len() {
                self.vprep.resize(vols.len(), Prepared::default());
            }
            if self.cprep.len() < cands.len() {
                self.cprep.resize(cands.len(), Prepared::default());
            }
            self.cells.clear();
            self.cells
                .resize(if h > 0.0 { vols.len() } else { 0 }, None);
            for &(v, c) in &self.pairs {
                let pv = self.vprep[v as usize].get(stamp, q, vols[v as usize]);
                let pc = self.cprep[c as usize].get(stamp, q, cands[c as usize]);
                let cells =
                    (h > 0.0).then(|| &*self.cells[v as usize].get_or_insert_with(|| pv.cells(h)));
                if polygons_meet(pv, pc, cells) {
                    hits.push(hit((v, c)));
                }
            }
        }
        Ok(())
    }
}

/// A box in `f64` (min xyz, max xyz) tagged with its position in the group.
#[derive(Clone, Copy)]
struct Wide {
    b: [f64; 6],
    at: u32,
}

#[inline]
fn meets(v: &[f64; 6], c: &[f64; 6]) -> bool {
    // Branch-free: all six comparisons, combined with `&`.
    (c[3] >= v[0])
        & (c[0] <= v[3])
        & (c[4] >= v[1])
        & (c[1] <= v[4])
        & (c[5] >= v[2])
        & (c[2] <= v[5])
}

/// Sorts boxes by their lower bound along `axis` through compact integer keys (an order-
/// preserving map of the f64 bits), which is much cheaper than moving the boxes around.
fn sort_by_axis(w: &mut Vec<Wide>, axis: usize, keys: &mut Vec<(u64, u32)>, tmp: &mut Vec<Wide>) {
    let key = |x: f64| {
        let b = x.to_bits();
        if b >> 63 == 1 {
            !b
        } else {
            b | (1 << 63)
        }
    };
    keys.clear();
    keys.extend(
        w.iter()
            .enumerate()
            .map(|(i, b)| (key(b.b[axis]), i as u32)),
    );
    keys.sort_unstable();
    tmp.clear();
    tmp.extend(keys.iter().map(|&(_, i)| w[i as usize]));
    std::mem::swap(w, tmp);
}

#[inline]
fn meets_exact(v: &Aabb, c: &Aabb) -> bool {
    (c.max[0] >= v.min[0])
        & (c.min[0] <= v.max[0])
        & (c.max[1] >= v.min[1])
        & (c.min[1] <= v.max[1])
        & (c.max[2] >= v.min[2])
        & (c.min[2] <= v.max[2])
}

#[inline]
fn meets_f32(v: &[f64; 6], c: &Aabb) -> bool {
    let f = f64::from;
    (f(c.max[0]) >= v[0])
        & (f(c.min[0]) <= v[3])
        & (f(c.max[1]) >= v[1])
        & (f(c.min[1]) <= v[4])
        & (f(c.max[2]) >= v[2])
        & (f(c.min[2]) <= v[5])
}

/// Every (volume, candidate) pair whose boxes meet once the volume is grown by `h`, as
/// positions in `vb` and `cb`. The grown volume is rounded in `f64`; rounding is monotone
/// and the unmoved bounds are floats, so a pair whose plain boxes meet is never lost.
fn box_pairs(
    vb: &[Aabb],
    cb: &[Aabb],
    h: f64,
    vw: &mut Vec<Wide>,
    cw: &mut Vec<Wide>,
    keys: &mut Vec<(u64, u32)>,
    tmp: &mut Vec<Wide>,
    out: &mut Vec<(u32, u32)>,
) {
    let widen = |b: &Aabb, h: f64, at: usize| Wide {
        b: [
            f64::from(b.min[0]) - h,
            f64::from(b.min[1]) - h,
            f64::from(b.min[2]) - h,
            f64::from(b.max[0]) + h,
            f64::from(b.max[1]) + h,
            f64::from(b.max[2]) + h,
        ],
        at: at as u32,
    };
    if vb.len() * cb.len() <= SWEEP_ABOVE || vb.len() == 1 || cb.len() == 1 {
        // Brute force, straight over the f32 boxes (no copies).
        if h == 0.0 {
            // Exact in f32: no conversions.
            for (i, v) in vb.iter().enumerate() {
                out.extend(
                    cb.iter()
                        .enumerate()
                        .filter(|(_, c)| meets_exact(v, c))
                        .map(|(j, _)| (i as u32, j as u32)),
                );
            }
            return;
        }
        for (i, v) in vb.iter().enumerate() {
            let w = widen(v, h, i).b;
            out.extend(
                cb.iter()
                    .enumerate()
                    .filter(|(_, c)| meets_f32(&w, c))
                    .map(|(j, _)| (i as u32, j as u32)),
            );
        }
        return;
    }
    vw.clear();
    vw.extend(vb.iter().enumerate().map(|(i, b)| widen(b, h, i)));
    cw.clear();
    cw.extend(cb.iter().enumerate().map(|(i, b)| widen(b, 0.0, i)));
    // Sweep along the axis where the candidates are most spread out for their size.
    let axis = (0..3)
        .map(|k| {
            let (mut lo, mut hi, mut size) = (f64::INFINITY, f64::NEG_INFINITY, 0.0);
            for c in cw.iter() {
                lo = lo.min(c.b[k]);
                hi = hi.max(c.b[k + 3]);
                size += c.b[k + 3] - c.b[k];
            }
            (hi - lo) / (size / cw.len() as f64 + f64::MIN_POSITIVE)
        })
        .enumerate()
        .fold((0, f64::NEG_INFINITY), |best, (k, r)| {
            if r > best.1 {
                (k, r)
            } else {
                best
            }
        })
        .0;
    sort_by_axis(vw, axis, keys, tmp);
    sort_by_axis(cw, axis, keys, tmp);
    let (mut i, mut j) = (0, 0);
    while i < vw.len() && j < cw.len() {
        let (v, c) = (&vw[i], &cw[j]);
        if v.b[axis] <= c.b[axis] {
            // v starts first: every candidate starting before v ends may meet it.
            for ck in &cw[j..] {
                if ck.b[axis] > v.b[axis + 3] {
                    break;
                }
                if meets(&v.b, &ck.b) {
                    out.push((v.at, ck.at));
                }
            }
            i += 1;
        } else {
            for vk in &vw[i..] {
                if vk.b[axis] > c.b[axis + 3] {
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

#[cfg(test)]
mod tests {
    use super::*;

    /// 150 boxes of sides up to 2 and 170 of sides up to 1 in a cube of side 10
    /// (deterministic), for the sweeps' tests.
    pub(super) fn random_boxes() -> (Vec<Aabb>, Vec<Aabb>) {
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
        for h in [0.0, 0.3] {
            let mut got = Vec::new();
            box_pairs(
                &vb,
                &cb,
                h,
                &mut Vec::new(),
                &mut Vec::new(),
                &mut Vec::new(),
                &mut Vec::new(),
                &mut got,
            );
            got.sort_unstable();
            let mut want = Vec::new();
            for (i, v) in vb.iter().enumerate() {
                for (j, c) in cb.iter().enumerate() {
                    if v.overlaps(c, h) {
                        want.push((i as u32, j as u32));
                    }
                }
            }
            assert!(!want.is_empty());
            assert_eq!(got, want, "h = {h}");
        }
    }
}
