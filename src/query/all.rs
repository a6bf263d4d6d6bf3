//! Whole-scene queries: every pair of polygons that meet, from two different meshes or
//! from one self-colliding mesh.
//!
//! - Broad phase ([`mesh_pairs`]): the meshes' root boxes, grown by the half depth, swept
//!   once ([`Sweep`]), so a scene costs about its overlapping mesh pairs, not the square of
//!   its mesh count; filters are applied before any leaf box is touched.
//! - Each overlapping mesh pair then runs the five steps through the backend (the lower id
//!   as the reference, symmetric narrow test).
//! - Self-collision ([`self_pairs`]): paper 2.1-2.2 carried over to one mesh: its leaf boxes
//!   against its own leaf boxes, then the polygons of each leaf pair, then the narrow test;
//!   polygons that share a vertex index are decided by [`adjacent_polygons_meet`] (they
//!   count only where they meet beyond what they share, at every epsilon).

use crate::backend::cpu::lanes::Lanes;
use crate::backend::Pair;
use crate::geom::adjacent::{
    adjacent_polygons_meet, shares_vertex, triangles_touch_only_at_joint_planes,
};
use crate::geom::polygon::Prepared;
use crate::geom::sweep::Sweep;
use crate::geom::tritri::Plane;
use crate::geom::volume::Cell;
use crate::geom::Aabb;
use crate::geom::P3;
use crate::mesh::Mesh;
use std::time::Instant;

/// A mesh as a whole-scene query sees it.
#[derive(Clone, Copy)]
pub struct SceneMesh<'a> {
    /// Its id.
    pub id: u32,
    /// Its geometry.
    pub mesh: &'a Mesh,
    /// Collide it with itself.
    pub self_collision: bool,
    /// Filter group bits.
    pub group: u32,
    /// Filter mask bits.
    pub mask: u32,
}

/// Do two different meshes' filters let them collide?
#[inline]
pub fn filters_pass(a: &SceneMesh<'_>, b: &SceneMesh<'_>) -> bool {
    a.group & b.mask != 0 && b.group & a.mask != 0
}

/// Scratch of [`mesh_pairs`].
#[derive(Default)]
pub struct BroadPhase {
    grown: Vec<Aabb>,
    roots: Vec<Aabb>,
    found: Vec<(u32, u32)>,
    sweep: Sweep,
}

/// The pairs `(i, j)`, `i < j` positions in `meshes`, whose root boxes meet once grown by
/// `h` and whose filters pass, sorted.
pub fn mesh_pairs(
    meshes: &[SceneMesh<'_>],
    h: f64,
    bp: &mut BroadPhase,
    out: &mut Vec<(u32, u32)>,
) {
    out.clear();
    bp.roots.clear();
    bp.roots.extend(meshes.iter().map(|m| m.mesh.root()));
    bp.grown.clear();
    bp.grown.extend(bp.roots.iter().map(|r| r.grown(h)));
    bp.found.clear();
    bp.sweep.pairs(&bp.grown, &bp.roots, &mut bp.found);
    out.extend(
        bp.found
            .iter()
            .copied()
            .filter(|&(i, j)| i < j && filters_pass(&meshes[i as usize], &meshes[j as usize])),
    );
    out.sort_unstable();
}

/// Polygons per sub-leaf of a self-colliding mesh (see [`SelfPrep`]).
const SUB_LEAF: usize = 16;

/// Polygons from which [`SelfPrep::make`] shares a mesh's preparation between workers.
const PAR_MIN: usize = 4096;

/// Cuts the polygons `items` of one leaf (positions `start..` of the leaf order) into
/// sub-leaves of at most [`SUB_LEAF`] by median splits of their box centres along the widest
/// axis, reordering `items`; returns the sub-leaves' end positions, in order.
fn split_leaf(start: usize, items: &mut [u32], pb: &[Aabb]) -> Vec<u32> {
    let centre = |b: &Aabb, k: usize| b.min[k] * 0.5 + b.max[k] * 0.5;
    let mut ends = Vec::with_capacity(items.len() / (SUB_LEAF / 2) + 1);
    let mut stack = vec![(0, items.len())];
    // Depth-first, left half first: sub-leaves come out in order.
    while let Some((a, b)) = stack.pop() {
        if b - a <= SUB_LEAF {
            ends.push((start + b) as u32);
            continue;
        }
        let items = &mut items[a..b];
        let (mut lo, mut hi) = ([f32::INFINITY; 3], [f32::NEG_INFINITY; 3]);
        for &p in items.iter() {
            let c = &pb[p as usize];
            for k in 0..3 {
                lo[k] = lo[k].min(centre(c, k));
                hi[k] = hi[k].max(centre(c, k));
            }
        }
        let axis = (0..3).fold(0, |best, k| {
            if hi[k] - lo[k] > hi[best] - lo[best] {
                k
            } else {
                best
            }
        });
        let mid = items.len() / 2;
        items.select_nth_unstable_by(mid, |&x, &y| {
            centre(&pb[x as usize], axis).total_cmp(&centre(&pb[y as usize], axis))
        });
        stack.push((a + mid, b));
        stack.push((a, a + mid));
    }
    ends
}

/// One self-colliding mesh made ready for a query, once, before the tasks: its leaf pairs,
/// and each leaf cut into sub-leaves of at most [`SUB_LEAF`] polygons (median splits of
/// the polygons' box centres, as the leaves themselves), with their boxes. A leaf pair's
/// polygon box pairs then come from the sub-leaf pairs whose boxes meet, each tested
/// eight boxes at a time ([`Lanes`]): a leaf of 450 polygons is a patch of a surface, and
/// testing it against itself or a neighbour polygon by polygon (or sweeping it along one
/// axis) costs far more than the few neighbours each polygon really has. Kept from query
/// to query (no allocation once grown).
#[derive(Default)]
pub struct SelfPrep {
    /// Leaf-order polygon indices, leaf by leaf (the leaves' ranges), sub-leaf by sub-leaf
    /// within each leaf.
    order: Vec<u32>,
    /// Their boxes, in that order, as they are, and grown by `h` (rounded outward) in
    /// lanes.
    boxes: Vec<Aabb>,
    lanes: Lanes,
    /// Sub-leaf `s` holds `order[sub_start[s]..sub_start[s + 1]]`; leaf `l` the sub-leaves
    /// `leaf_sub[l]..leaf_sub[l + 1]`.
    sub_start: Vec<u32>,
    leaf_sub: Vec<u32>,
    /// Sub-leaf boxes, as they are and grown by `h`.
    sub_boxes: Vec<Aabb>,
    sub_grown: Vec<Aabb>,
    /// Per leaf-order polygon: its box; the caller's vertex indices (the first `k` count).
    poly_boxes: Vec<Aabb>,
    verts: Vec<[u32; 4]>,
    /// Triangle meshes: per leaf-order polygon, its corners in `f64` and its plane.
    tris: Vec<[P3; 3]>,
    planes: Vec<Plane>,
    grown_leaves: Vec<Aabb>,
    found: Vec<(u32, u32)>,
    sweep: Sweep,
    /// Leaf pairs `(i, j)`, `i <= j`, whose boxes meet once grown by `h`, sorted: the
    /// units of work of [`self_pairs`] (callers may split them between threads).
    pub leaf_pairs: Vec<(u32, u32)>,
}

impl SelfPrep {
    /// Makes the leaf pairs, sub-leaves and vertex indices of mesh `m` for half depth `h`.
    /// With `par` (the caller runs inside the scene's worker pool), a big mesh's
    /// per-polygon and per-leaf work is shared between the workers: for a scene of one big
    /// cloth this runs before any task and would otherwise keep the other cores idle.
    pub fn make(&mut self, m: &Mesh, h: f64, par: bool) {
        use rayon::prelude::*;
        let n = m.polygon_count();
        let par = par && n >= PAR_MIN;
        self.grown_leaves.clear();
        self.grown_leaves
            .extend(m.leaf_boxes().iter().map(|b| b.grown(h)));
        self.found.clear();
        self.sweep
            .pairs(&self.grown_leaves, m.leaf_boxes(), &mut self.found);
        self.leaf_pairs.clear();
        self.leaf_pairs
            .extend(self.found.iter().copied().filter(|&(i, j)| i <= j));
        self.leaf_pairs.sort_unstable();
        self.poly_boxes.clear();
        self.verts.clear();
        self.tris.clear();
        self.planes.clear();
        let tri = |p: usize| {
            let mut t = [[[0.0; 3]; 3]; 2];
            m.triangles(p, &mut t);
            t[0]
        };
        let triangles = m.vertices_per_polygon() == 3;
        if par {
            self.poly_boxes
                .par_extend((0..n).into_par_iter().map(|p| m.poly_box(p)));
            self.verts
                .par_extend((0..n).into_par_iter().map(|p| vertices(m, p)));
            if triangles {
                self.tris.par_extend((0..n).into_par_iter().map(tri));
                self.planes.par_extend(self.tris.par_iter().map(Plane::of));
            }
        } else {
            self.poly_boxes.extend((0..n).map(|p| m.poly_box(p)));
            self.verts.extend((0..n).map(|p| vertices(m, p)));
            if triangles {
                self.tris.extend((0..n).map(tri));
                self.planes.extend(self.tris.iter().map(Plane::of));
            }
        }
        self.order.clear();
        self.order.extend(0..n as u32);
        self.sub_start.clear();
        self.sub_start.push(0);
        self.leaf_sub.clear();
        self.leaf_sub.push(0);
        // Each leaf's polygons are split on their own (disjoint ranges of `order`); the
        // sub-leaf ends come back leaf by leaf, in order.
        let (order, pb) = (&mut self.order[..], &self.poly_boxes[..]);
        let mut slices = Vec::with_capacity(m.leaf_count());
        let mut rest = order;
        for l in 0..m.leaf_count() {
            let r = m.leaves.polys(l);
            debug_assert_eq!(
                r.start,
                n - rest.len(),
                "leaves cover the polygons in order"
            );
            let (this, tail) = std::mem::take(&mut rest).split_at_mut(r.end - r.start);
            slices.push((r.start, this));
            rest = tail;
        }
        let split = |(start, items): (usize, &mut [u32])| split_leaf(start, items, pb);
        let ends: Vec<Vec<u32>> = if par {
            slices.into_par_iter().map(split).collect()
        } else {
            slices.into_iter().map(split).collect()
        };
        for e in ends {
            self.sub_start.extend(e);
            self.leaf_sub.push(self.sub_start.len() as u32 - 1);
        }
        self.boxes.clear();
        self.boxes
            .extend(self.order.iter().map(|&p| self.poly_boxes[p as usize]));
        self.lanes.resize(n);
        for (i, b) in self.boxes.iter().enumerate() {
            self.lanes.set(i, &b.grown(h));
        }
        self.sub_boxes.clear();
        self.sub_boxes.extend(self.sub_start.windows(2).map(|w| {
            let mut b = Aabb::EMPTY;
            for c in &self.boxes[w[0] as usize..w[1] as usize] {
                b.merge(c);
            }
            b
        }));
        self.sub_grown.clear();
        self.sub_grown
            .extend(self.sub_boxes.iter().map(|b| b.grown(h)));
    }

    /// The range of `order` of sub-leaf `s`.
    #[inline]
    fn sub(&self, s: usize) -> std::ops::Range<usize> {
        self.sub_start[s] as usize..self.sub_start[s + 1] as usize
    }

    /// Calls `f(p, q)` for the leaf-order polygons `p` of leaf `i` and `q` of leaf `j`
    /// whose boxes meet once `p`'s is grown by `h` (`p < q` when `i == j`), each pair
    /// once. `masks` is scratch.
    #[inline]
    fn box_pairs(&self, i: usize, j: usize, masks: &mut Vec<u32>, mut f: impl FnMut(u32, u32)) {
        let (si, sj) = (
            self.leaf_sub[i] as usize..self.leaf_sub[i + 1] as usize,
            self.leaf_sub[j] as usize..self.leaf_sub[j + 1] as usize,
        );
        for a in si {
            let g = &self.sub_grown[a];
            let first = if i == j { a } else { sj.start };
            for b in first..sj.end {
                if !g.meets(&self.sub_boxes[b]) {
                    continue;
                }
                let rb = self.sub(b);
                let cands = &self.boxes[rb.clone()];
                self.lanes.each_pair(self.sub(a), cands, masks, |x, y| {
                    let (p, q) = (self.order[x as usize], self.order[rb.start + y as usize]);
                    if a != b || p < q {
                        f(p, q);
                    }
                });
            }
        }
    }
}

/// Scratch of [`self_pairs`], reused from query to query.
#[derive(Default)]
pub struct SelfScratch {
    /// Box-meeting polygon pairs (leaf order) of a task: sharing a vertex, and not.
    adjacent: Vec<(u32, u32)>,
    apart: Vec<(u32, u32)>,
    masks: Vec<u32>,
    /// Polygons prepared for the narrow test (by leaf-order index), valid for the task
    /// whose stamp they carry; their viewing volumes likewise (`h > 0`).
    prepared: Vec<(u64, Prepared)>,
    cells: Vec<(u64, Option<[Cell; 2]>)>,
    /// Tasks run so far (64 bits: never wraps, so a stale entry never looks fresh).
    stamp: u64,
}

/// Where the time of a whole-scene query went, and how much work each stage did. Times
/// of the work done on worker threads are summed over the workers (CPU time); the others
/// are wall-clock times on the calling thread.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct AllStats {
    /// Wall-clock time of the whole query, nanoseconds.
    pub total_nanos: u64,
    /// Broad phase over the meshes' root boxes (sweep and filters), nanoseconds.
    pub broad_nanos: u64,
    /// Mesh pairs whose root boxes meet and whose filters pass.
    pub mesh_pairs: usize,
    /// Self-collision leaf pairs: finding them (sweep of each mesh's leaf boxes), ns.
    pub self_leaf_nanos: u64,
    /// Self-collision leaf pairs found (`i <= j`).
    pub self_leaf_pairs: usize,
    /// Wall-clock time of the worker part (mesh pairs and self-collision), ns.
    pub tasks_nanos: u64,
    /// Mesh pairs: the CPU engine's steps 1 to 5 (steps 1-2 leaf pairs, 3-5 polygons), ns.
    pub pair_step_nanos: [u64; 5],
    /// Mesh pairs: polygon pairs found.
    pub pair_found: usize,
    /// Self-collision: polygon boxes and polygon box pairs of the leaf pairs, ns.
    pub self_box_nanos: u64,
    /// Self-collision: polygon pairs whose boxes meet (`p < q`).
    pub self_box_pairs: usize,
    /// Self-collision: time and count of adjacency decisions (pairs sharing a vertex).
    pub self_adjacent_nanos: u64,
    /// Pairs sharing a vertex index whose boxes meet.
    pub self_adjacent_tests: usize,
    /// Of them, pairs decided by a cheap conservative test without the exact adjacency
    /// predicate.
    pub self_adjacent_quick: usize,
    /// Self-collision: time and count of narrow tests of pairs sharing no vertex.
    pub self_narrow_nanos: u64,
    /// Pairs sharing no vertex index whose boxes meet.
    pub self_narrow_tests: usize,
    /// Self-collision: polygon pairs found.
    pub self_found: usize,
    /// Sorting and merging the answer, ns.
    pub merge_nanos: u64,
}

impl AllStats {
    /// Adds the worker-side counts and times of `o`.
    pub fn add_worker(&mut self, o: &AllStats) {
        for k in 0..5 {
            self.pair_step_nanos[k] += o.pair_step_nanos[k];
        }
        self.pair_found += o.pair_found;
        self.self_box_nanos += o.self_box_nanos;
        self.self_box_pairs += o.self_box_pairs;
        self.self_adjacent_nanos += o.self_adjacent_nanos;
        self.self_adjacent_tests += o.self_adjacent_tests;
        self.self_adjacent_quick += o.self_adjacent_quick;
        self.self_narrow_nanos += o.self_narrow_nanos;
        self.self_narrow_tests += o.self_narrow_tests;
        self.self_found += o.self_found;
    }
}

fn nanos_since(t: Instant) -> u64 {
    t.elapsed().as_nanos() as u64
}

/// The self-collision pairs of mesh `id` (made ready in `prep`) among the given leaf
/// pairs, appended to `out` (caller's polygon numbering, `polygon_a < polygon_b`, any
/// order); counts and times added to `st`.
#[allow(clippy::too_many_arguments)]
pub fn self_pairs(
    id: u32,
    m: &Mesh,
    prep: &SelfPrep,
    h: f64,
    leaf_pairs: &[(u32, u32)],
    s: &mut SelfScratch,
    out: &mut Vec<Pair>,
    st: &mut AllStats,
) {
    let t = Instant::now();
    s.adjacent.clear();
    s.apart.clear();
    let k = m.vertices_per_polygon();
    let (adjacent, apart) = (&mut s.adjacent, &mut s.apart);
    for &(i, j) in leaf_pairs {
        prep.box_pairs(i as usize, j as usize, &mut s.masks, |p, q| {
            let (vp, vq) = (&prep.verts[p as usize], &prep.verts[q as usize]);
            if shares_vertex(&vp[..k], &vq[..k]) {
                adjacent.push((p, q));
            } else {
                apart.push((p, q));
            }
        });
    }
    st.self_box_nanos += nanos_since(t);
    st.self_box_pairs += s.adjacent.len() + s.apart.len();
    st.self_adjacent_tests += s.adjacent.len();
    st.self_narrow_tests += s.apart.len();
    let found = out.len();
    let mut push = |p: u32, q: u32| {
        let (pa, pb) = (m.poly_ids[p as usize], m.poly_ids[q as usize]);
        out.push(Pair {
            mesh_a: id,
            polygon_a: pa.min(pb),
            mesh_b: id,
            polygon_b: pa.max(pb),
        });
    };
    let t = Instant::now();
    let mut quick = 0;
    for &(p, q) in &s.adjacent {
        let (p, q) = (p as usize, q as usize);
        let (vp, vq) = (&prep.verts[p], &prep.verts[q]);
        if k == 3 {
            let (ip, iq) = ([vp[0], vp[1], vp[2]], [vq[0], vq[1], vq[2]]);
            let (tp, tq) = (&prep.tris[p], &prep.tris[q]);
            let (pp, pq) = (&prep.planes[p], &prep.planes[q]);
            if triangles_touch_only_at_joint_planes(&ip, tp, pp, &iq, tq, pq) {
                quick += 1;
                continue;
            }
        }
        let (mut tp, mut tq) = ([[[0.0; 3]; 3]; 2], [[[0.0; 3]; 3]; 2]);
        let np = m.triangles(p, &mut tp);
        let nq = m.triangles(q, &mut tq);
        if adjacent_polygons_meet(&vp[..k], &tp, np, &vq[..k], &tq, nq) {
            push(p as u32, q as u32);
        }
    }
    st.self_adjacent_quick += quick;
    st.self_adjacent_nanos += nanos_since(t);
    let t = Instant::now();
    s.stamp += 1;
    let stamp = s.stamp;
    let n = m.polygon_count();
    if s.prepared.len() < n {
        s.prepared.resize(n, (0, Prepared::default()));
    }
    if h > 0.0 && s.cells.len() < n {
        s.cells.resize(n, (0, None));
    }
    for &(p, q) in &s.apart {
        let (p, q) = (p as usize, q as usize);
        prepare(m, p, stamp, &mut s.prepared);
        prepare(m, q, stamp, &mut s.prepared);
        let (a, b) = (&s.prepared[p].1, &s.prepared[q].1);
        let meets = if h == 0.0 {
            a.meets(b, None)
        } else {
            fill_cells(a, p, h, stamp, &mut s.cells);
            // Farther than `h` apart: neither meets the other's volumes (saves making
            // `b`'s and clipping both ways).
            let far = s.cells[p].1.as_ref().is_some_and(|c| a.far_apart(c, b, h));
            !far && (a.meets(b, s.cells[p].1.as_ref()) || {
                fill_cells(b, q, h, stamp, &mut s.cells);
                b.meets(a, s.cells[q].1.as_ref())
            })
        };
        if meets {
            push(p as u32, q as u32);
        }
    }
    st.self_narrow_nanos += nanos_since(t);
    st.self_found += out.len() - found;
}

/// Prepares leaf-order polygon `p` of `m` for the narrow test, unless done for this task.
#[inline]
fn prepare(m: &Mesh, p: usize, stamp: u64, prepared: &mut [(u64, Prepared)]) {
    if prepared[p].0 != stamp {
        let mut t = [[[0.0; 3]; 3]; 2];
        let n = m.triangles(p, &mut t);
        prepared[p] = (stamp, Prepared::of(t, n));
    }
}

/// Makes the viewing volumes of prepared polygon `a` (leaf-order index `p`), unless done
/// for this task.
#[inline]
fn fill_cells(a: &Prepared, p: usize, h: f64, stamp: u64, cells: &mut [(u64, Option<[Cell; 2]>)]) {
    if cells[p].0 != stamp {
        cells[p] = (stamp, Some(a.cells(h)));
    }
}

/// The caller's vertex indices of leaf-ordered polygon `p` (the first `k` count).
#[inline]
fn vertices(m: &Mesh, p: usize) -> [u32; 4] {
    let mut v = [0; 4];
    for (k, &slot) in m.poly(p).iter().enumerate() {
        v[k] = m.slot_vertex[slot as usize];
    }
    v
}
