//! The CPU backend's five steps ([`WholeQuery::run_query`](crate::backend::WholeQuery)),
//! with the tests of [`crate::query::run`] (so the same answer and the same per-step counts
//! as the step-by-step path), run leaf pair by leaf pair over scratch buffers the selector
//! keeps: no batches, no allocation once the buffers have grown.
//!
//! Box tests compare `f32` boxes with volumes grown by `h` and rounded outward to `f32`
//! ([`Aabb::grown`]), which keeps exactly the pairs an `f64` comparison keeps. Polygon
//! boxes are computed a leaf at a time into [`Lanes`] and tested eight at a time: steps 3
//! and 4 test a leaf's polygons against the other leaf's box, step 5 tests every other
//! polygon's box against all the reference polygons' (a sort-and-sweep only for very large
//! leaf pairs, where it is cheaper than testing every pair). The narrow test of step 5 is
//! [`Prepared::meets`].

use std::time::Instant;

use super::lanes::Lanes;
use super::BoxCache;
use crate::backend::{Contact, QueryMeshes, QueryStats};
use crate::geom::polygon::Prepared;
use crate::geom::predicates::P3;
use crate::geom::sweep::Sweep;
use crate::geom::volume::Cell;
use crate::geom::Aabb;
use crate::mesh::Mesh;

/// A step-5 leaf pair with more than this many polygon pairs is swept like step 2, not
/// tested pair by pair (vectorised).
const SWEEP_STEP5_ABOVE: usize = 1 << 16;

/// Buffers of the query, reused from query to query.
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
    /// Step 5: the polygons of the current leaf pair, prepared on first use.
    vprep: Vec<Stamped>,
    cprep: Vec<Stamped>,
    /// Step 5 (`h > 0`): the reference polygons' viewing volumes, made on first use; the
    /// other polygons' too when the query is symmetric.
    cells: Vec<Option<[Cell; 2]>>,
    ccells: Vec<Option<[Cell; 2]>>,
    /// Leaf pairs prepared so far (64 bits: never wraps, so a stale entry never looks
    /// fresh).
    stamp: u64,
}

/// A polygon prepared for the current step-5 leaf pair, valid while `stamp` is the pair's:
/// its triangles on first use, its planes only when the scalar test needs them (the lanes
/// read the triangles alone, and decide most pairs).
#[derive(Clone, Copy, Default)]
struct Stamped {
    stamp: u64,
    /// The planes of `p` are made (for this stamp).
    planes: bool,
    p: Prepared,
}

impl Stamped {
    /// The polygon's triangles (`p.poly`; its planes may be stale).
    #[inline]
    fn tris(&mut self, stamp: u64, m: &Mesh, poly: u32) -> &Prepared {
        if self.stamp != stamp {
            self.p.poly.n = m.triangles(poly as usize, &mut self.p.poly.tris);
            self.planes = false;
            self.stamp = stamp;
        }
        &self.p
    }

    /// The polygon prepared whole, planes included.
    #[inline]
    fn get(&mut self, stamp: u64, m: &Mesh, poly: u32) -> &Prepared {
        self.tris(stamp, m, poly);
        if !self.planes {
            self.p.remake(self.p.poly.n);
            self.planes = true;
        }
        &self.p
    }
}

/// One query: the meshes, the scratch and the caches it works in, the counts it keeps.
pub(super) struct Run<'a, 'q> {
    pub q: &'a QueryMeshes<'q>,
    /// Half the viewing-volume depth.
    pub h: f64,
    pub s: &'a mut Scratch,
    pub caches: &'a mut [BoxCache],
    /// Query mesh slot -> index in `caches`.
    pub slot_cache: &'a [usize],
    pub stats: &'a mut QueryStats,
}

/// The leaf pairs of a query (steps 1 and 2), to be shared out: steps 3 to 5 of any subset
/// of `pairs` give that subset's contacts ([`Run::some_pairs`]).
#[derive(Clone, Debug, Default)]
pub struct LeafPairs {
    /// (query mesh, leaf) of the other meshes' leaves that meet the reference root.
    pub others: Vec<(u32, u32)>,
    /// Their boxes grown by `h`.
    pub grown: Vec<Aabb>,
    /// (position in `others`, reference leaf), sorted.
    pub pairs: Vec<(u32, u32)>,
}

impl Run<'_, '_> {
    /// The five steps for `q.meshes[0]` against the others: contacts appended to `out`
    /// (each pair once, in no particular order), counts and times in `stats`.
    pub fn all(&mut self, out: &mut Vec<Contact>) {
        let t = &mut Instant::now();
        let _ = self.timed(0, t, Run::step1)
            && self.timed(1, t, Run::step2)
            && self.timed(2, t, Run::step3)
            && self.timed(3, t, Run::step4)
            && self.timed(4, t, |r| r.step5(out));
    }

    /// Steps 1 and 2 only: the leaf pairs into `lp` (counts and times of steps 1 and 2 in
    /// `stats`).
    pub fn leaf_pairs(&mut self, lp: &mut LeafPairs) {
        lp.others.clear();
        lp.grown.clear();
        lp.pairs.clear();
        let t = &mut Instant::now();
        if self.timed(0, t, Run::step1) && self.timed(1, t, Run::step2) {
            lp.others.extend_from_slice(&self.s.others);
            lp.grown.extend_from_slice(&self.s.grown);
            lp.pairs.extend_from_slice(&self.s.pairs);
        }
    }

    /// Steps 3 to 5 on the leaf pairs `lp.pairs[range]`: their contacts appended to `out`
    /// (counts and times of steps 3 to 5 in `stats`).
    pub fn some_pairs(
        &mut self,
        lp: &LeafPairs,
        range: std::ops::Range<usize>,
        out: &mut Vec<Contact>,
    ) {
        let s = &mut *self.s;
        s.others.clear();
        s.others.extend_from_slice(&lp.others);
        s.grown.clear();
        s.grown.extend_from_slice(&lp.grown);
        s.pairs.clear();
        s.pairs.extend_from_slice(&lp.pairs[range]);
        self.stats.hits[1] = s.pairs.len();
        let t = &mut Instant::now();
        let _ = self.timed(2, t, Run::step3)
            && self.timed(3, t, Run::step4)
            && self.timed(4, t, |r| r.step5(out));
    }

    /// Runs `step`, which starts at `t`, and records its time; `t` becomes its end (the
    /// next step's start: one clock read per step, which on a scene of thousands of small
    /// mesh pairs is a few percent of the query); whether the query goes on.
    fn timed(&mut self, i: usize, t: &mut Instant, step: impl FnOnce(&mut Self) -> bool) -> bool {
        let go_on = step(self);
        let now = Instant::now();
        self.stats.nanos[i] = (now - *t).as_nanos() as u64;
        *t = now;
        go_on
    }

    /// Step 1: the other meshes' leaves inside the reference's root box.
    fn step1(&mut self) -> bool {
        let (q, s, h) = (self.q, &mut *self.s, self.h);
        let reference = q.meshes[0].1;
        let root = reference.root().grown(h);
        s.others.clear();
        for (mi, (_, m)) in q.meshes.iter().enumerate().skip(1) {
            if reference.root().overlaps(&m.root(), h) {
                self.stats.tests[0] += m.leaf_count();
                s.others.extend(
                    m.leaf_boxes()
                        .iter()
                        .enumerate()
                        .filter(|(_, b)| root.meets(b))
                        .map(|(l, _)| (mi as u32, l as u32)),
                );
            }
        }
        self.stats.hits[0] = s.others.len();
        !s.others.is_empty()
    }

    /// Step 2: for each of those leaves, the reference leaves inside its box.
    fn step2(&mut self) -> bool {
        let (q, s, h) = (self.q, &mut *self.s, self.h);
        let reference = q.meshes[0].1;
        s.grown.clear();
        s.grown.extend(
            s.others
                .iter()
                .map(|&(mi, l)| q.meshes[mi as usize].1.leaf_boxes()[l as usize].grown(h)),
        );
        self.stats.tests[1] = s.others.len() * reference.leaf_count();
        s.pairs.clear();
        s.sweep
            .pairs(&s.grown, reference.leaf_boxes(), &mut s.pairs);
        s.pairs.sort_unstable();
        self.stats.hits[1] = s.pairs.len();
        !s.pairs.is_empty()
    }

    /// Step 3: per pair, the reference leaf's polygons inside the other leaf's box.
    fn step3(&mut self) -> bool {
        let reference = self.q.meshes[0].1;
        let s = &mut *self.s;
        let rc = &mut self.caches[self.slot_cache[0]];
        s.ref_start.clear();
        s.ref_start.push(0);
        s.refs.clear();
        for &(o, r) in &s.pairs {
            let vol = s.grown[o as usize];
            let polys = rc.leaf(reference, r as usize);
            self.stats.tests[2] += polys.len();
            rc.boxes.select(polys, &vol, &mut s.masks, &mut s.refs);
            s.ref_start.push(s.refs.len() as u32);
        }
        self.stats.hits[2] = s.refs.len();
        true
    }

    /// Step 4: per pair, the other leaf's polygons inside the reference leaf's box.
    fn step4(&mut self) -> bool {
        let (q, h) = (self.q, self.h);
        let reference = q.meshes[0].1;
        let s = &mut *self.s;
        s.other_start.clear();
        s.other_start.push(0);
        s.other_polys.clear();
        for &(o, r) in &s.pairs {
            let (mi, l) = s.others[o as usize];
            let vol = reference.leaf_boxes()[r as usize].grown(h);
            let oc = &mut self.caches[self.slot_cache[mi as usize]];
            let polys = oc.leaf(q.meshes[mi as usize].1, l as usize);
            self.stats.tests[3] += polys.len();
            oc.boxes
                .select(polys, &vol, &mut s.masks, &mut s.other_polys);
            s.other_start.push(s.other_polys.len() as u32);
        }
        self.stats.hits[3] = s.other_polys.len();
        true
    }

    /// Step 5: per pair, each reference polygon's viewing volume against the other
    /// polygons: box pairs first, then the narrow test.
    fn step5(&mut self, out: &mut Vec<Contact>) -> bool {
        let found = out.len();
        for i in 0..self.s.pairs.len() {
            let s = &*self.s;
            let (refs, others) = (
                s.ref_start[i] as usize..s.ref_start[i + 1] as usize,
                s.other_start[i] as usize..s.other_start[i + 1] as usize,
            );
            if refs.is_empty() || others.is_empty() {
                continue;
            }
            self.stats.tests[4] += refs.len() * others.len();
            let mi = s.others[s.pairs[i].0 as usize].0;
            self.box_pairs(refs.clone(), others.clone(), mi);
            if !self.s.box_pairs.is_empty() {
                self.narrow(refs, others, mi, out);
            }
        }
        self.stats.hits[4] = out.len() - found;
        true
    }

    /// Step 5 of one leaf pair, first part: the (reference, other) polygon pairs whose
    /// boxes meet (the reference's grown by `h`) into `box_pairs`, as positions in `refs`
    /// and `others`.
    fn box_pairs(&mut self, refs: std::ops::Range<usize>, others: std::ops::Range<usize>, mi: u32) {
        let h = self.h;
        let s = &mut *self.s;
        let (refs, others) = (&s.refs[refs], &s.other_polys[others]);
        let rc = &self.caches[self.slot_cache[0]];
        let oc = &self.caches[self.slot_cache[mi as usize]];
        s.box_pairs.clear();
        s.cboxes.clear();
        s.cboxes
            .extend(others.iter().map(|&p| oc.boxes.get(p as usize)));
        if refs.len() * others.len() > SWEEP_STEP5_ABOVE {
            s.vboxes.clear();
            s.vboxes
                .extend(refs.iter().map(|&p| rc.boxes.get(p as usize).grown(h)));
            s.sweep.pairs(&s.vboxes, &s.cboxes, &mut s.box_pairs);
        } else {
            // The reference polygons' grown boxes in lanes, each other polygon's box
            // against all of them, eight at a time.
            s.lanes.resize(refs.len());
            for (v, &p) in refs.iter().enumerate() {
                s.lanes.set(v, &rc.boxes.get(p as usize).grown(h));
            }
            let pairs = &mut s.box_pairs;
            s.lanes
                .each_pair(0..refs.len(), &s.cboxes, &mut s.masks, |v, c| {
                    pairs.push((v, c))
                });
        }
    }

    /// Step 5 of one leaf pair, second part: the narrow test on `box_pairs`, each polygon
    /// prepared (widened, its planes and viewing volumes made) once.
    fn narrow(
        &mut self,
        refs: std::ops::Range<usize>,
        others: std::ops::Range<usize>,
        mi: u32,
        out: &mut Vec<Contact>,
    ) {
        let (q, h) = (self.q, self.h);
        let reference = q.meshes[0].1;
        let (id, m) = q.meshes[mi as usize];
        let s = &mut *self.s;
        let (refs, others) = (&s.refs[refs], &s.other_polys[others]);
        s.stamp += 1;
        let stamp = s.stamp;
        if s.vprep.len() < refs.len() {
            s.vprep.resize(refs.len(), Stamped::default());
        }
        if s.cprep.len() < others.len() {
            s.cprep.resize(others.len(), Stamped::default());
        }
        let symmetric = h > 0.0 && q.symmetric;
        s.cells.clear();
        s.cells.resize(if h > 0.0 { refs.len() } else { 0 }, None);
        s.ccells.clear();
        s.ccells
            .resize(if symmetric { others.len() } else { 0 }, None);
        let mut five = Five {
            refs,
            others,
            vprep: &mut s.vprep,
            cprep: &mut s.cprep,
            cells: &mut s.cells,
            ccells: &mut s.ccells,
            h,
            symmetric,
            stamp,
            reference,
            other: (id, m),
            out,
        };
        #[cfg(target_arch = "x86_64")]
        {
            use crate::geom::batch::{Fours, Kernel};
            let kernel = if h == 0.0 {
                Kernel::Exact
            } else {
                Kernel::Band { h, both: symmetric }
            };
            if let Some(mut fours) = Fours::new(kernel) {
                // Four pairs at a time where floating point certifies the answer, the
                // others (and quads) by the scalar test: the same answer as the loop below.
                fours.decide(s.box_pairs.iter().copied(), &mut five);
                return;
            }
        }
        for &key in &s.box_pairs {
            if five.scalar(key) {
                five.found(key);
            }
        }
    }
}

/// Step 5's narrow test on the box pairs of one leaf pair (keys: positions in `refs` and
/// `others`): the leaf pair's polygons prepared on demand, their viewing volumes (`h > 0`)
/// made on first use, and where contacts go.
struct Five<'a> {
    refs: &'a [u32],
    others: &'a [u32],
    vprep: &'a mut [Stamped],
    cprep: &'a mut [Stamped],
    cells: &'a mut [Option<[Cell; 2]>],
    ccells: &'a mut [Option<[Cell; 2]>],
    h: f64,
    symmetric: bool,
    stamp: u64,
    reference: &'a Mesh,
    other: (u32, &'a Mesh),
    out: &'a mut Vec<Contact>,
}

impl Five<'_> {
    /// The pair's polygons, triangles only (for the lanes).
    #[inline]
    fn both(&mut self, (v, c): (u32, u32)) -> (&Prepared, &Prepared) {
        let (v, c) = (v as usize, c as usize);
        let pv = self.vprep[v].tris(self.stamp, self.reference, self.refs[v]);
        let pc = self.cprep[c].tris(self.stamp, self.other.1, self.others[c]);
        (pv, pc)
    }

    /// The scalar narrow test of one pair ([`Prepared::meets`], both ways round when the
    /// query is symmetric).
    #[inline]
    fn scalar(&mut self, (v, c): (u32, u32)) -> bool {
        let h = self.h;
        let (vu, cu) = (v as usize, c as usize);
        let pv = self.vprep[vu].get(self.stamp, self.reference, self.refs[vu]);
        let pc = self.cprep[cu].get(self.stamp, self.other.1, self.others[cu]);
        if h == 0.0 {
            return pv.meets(pc, None);
        }
        let cells = &*self.cells[vu].get_or_insert_with(|| pv.cells(h));
        // Farther than `h` apart: no meeting either way round (no clipping, and no
        // volume made for the other polygon).
        if pv.far_apart(cells, pc, h) {
            return false;
        }
        pv.meets(pc, Some(cells))
            || self.symmetric
                && pc.meets(
                    pv,
                    Some(&*self.ccells[cu].get_or_insert_with(|| pc.cells(h))),
                )
    }

    #[inline]
    fn found(&mut self, (v, c): (u32, u32)) {
        self.out.push(Contact {
            other_mesh: self.other.0,
            reference_polygon: self.reference.poly_ids[self.refs[v as usize] as usize],
            other_polygon: self.other.1.poly_ids[self.others[c as usize] as usize],
        });
    }
}

#[cfg(target_arch = "x86_64")]
impl crate::geom::batch::Judge<(u32, u32)> for Five<'_> {
    #[inline]
    fn triangles(&mut self, key: (u32, u32)) -> Option<[&[P3; 3]; 2]> {
        let (pv, pc) = self.both(key);
        pv.triangle_pair(pc)
    }
    #[inline]
    fn scalar(&mut self, key: (u32, u32)) -> bool {
        Five::scalar(self, key)
    }
    #[inline]
    fn found(&mut self, key: (u32, u32)) {
        Five::found(self, key)
    }
}
