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

use super::neighbours::{Neighbours, SUB_MAX};
use crate::backend::cpu::lanes::{Diag, Lanes};
use crate::backend::Pair;
use crate::geom::adjacent::{adjacent_polygons_meet, triangles_touch_only_at_joint_planes};
use crate::geom::fan::Fans;
use crate::geom::patch::{mask_axis, turn_mask, Loop, PatchCheck, NONE};
use crate::geom::polygon::Prepared;
use crate::geom::sweep::Sweep;
use crate::geom::tritri::{apart_in_projection, in_one_axis_plane, Plane};
use crate::geom::volume::Cell;
use crate::geom::P3;
use crate::geom::{f32_down, f32_up, Aabb};
use crate::mesh::Mesh;
use std::time::Instant;

/// A mesh as a whole-scene query sees it.
#[derive(Clone, Copy)]
pub struct SceneMesh<'a> {
    /// Its id.
    pub id: u32,
    /// Its geometry.
    pub mesh: &'a Mesh,
    /// Its root box for the broad phase: `mesh.root()`, or every point for a mesh whose
    /// positions the backend reads from a host GL buffer on the GPU (its CPU boxes are
    /// stale; the backend's own query culls).
    pub root: crate::geom::Aabb,
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
    bp.roots.extend(meshes.iter().map(|m| m.root));
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

/// Half the surface of box `b` (in `f64`).
fn half_area(b: &Aabb) -> f64 {
    let d = [0, 1, 2].map(|k| f64::from(b.max[k] - b.min[k]));
    d[0] * d[1] + d[1] * d[2] + d[2] * d[0]
}

/// Where a run `part` of more than [`SUB_LEAF`] polygons (boxes `pb`) is cut on the way to
/// sub-leaves: `part` left sorted by box centre along the chosen axis, the cut's position
/// returned. Of the cuts that keep the fewest sub-leaves in all (`ceil(len / SUB_LEAF)`),
/// along each axis, the one with the least summed box surface times sub-leaves of its two
/// sides (a bounding volume hierarchy's surface area heuristic, swept: each side's box
/// grown polygon by polygon). The box stage's cost is per sub-leaf pair, about the same
/// whether a sub-leaf's sixteen lanes are full or not, and a sub-leaf meets the fewer
/// others the tighter its box: median halves along the widest axis left the 92k-triangle
/// crumpled cloth's leaves of ~354 in 8,390 sub-leaves of mostly 9-12 (354 / 2^5) and
/// ~86,000 sub-leaf pairs; the fewest sub-leaves, cut where this sweep says, make 6,708
/// and ~67,200 pairs (`bench-results/scene.md`, seventh round).
fn sweep_cut(part: &mut [u32], pb: &[Aabb], scratch: &mut Vec<f64>) -> usize {
    debug_assert!(part.len() > SUB_LEAF);
    let len = part.len();
    let m = len.div_ceil(SUB_LEAF);
    let subs = |c: usize| c.div_ceil(SUB_LEAF);
    let centre = |p: u32, k: usize| pb[p as usize].min[k] * 0.5 + pb[p as usize].max[k] * 0.5;
    // (A cut after the first SUB_LEAF always keeps the count: the fall-back, should no
    // cost compare, as a NaN would not.)
    let mut best = (f64::INFINITY, 2, SUB_LEAF);
    for axis in 0..3 {
        part.sort_unstable_by(|&x, &y| centre(x, axis).total_cmp(&centre(y, axis)));
        scratch.clear();
        let mut b = Aabb::EMPTY;
        scratch.push(0.0);
        for &p in part.iter() {
            b.merge(&pb[p as usize]);
            scratch.push(half_area(&b));
        }
        let mut b = Aabb::EMPTY;
        for c in (1..len).rev() {
            b.merge(&pb[part[c] as usize]);
            if subs(c) + subs(len - c) != m {
                continue;
            }
            let cost = scratch[c] * subs(c) as f64 + half_area(&b) * subs(len - c) as f64;
            if cost < best.0 {
                best = (cost, axis, c);
            }
        }
    }
    if best.1 != 2 {
        let axis = best.1;
        part.sort_unstable_by(|&x, &y| centre(x, axis).total_cmp(&centre(y, axis)));
    }
    best.2
}

// A sub-leaf's polygon boxes are tested sixteen at a time (`Lanes::each_pair_16`).
const _: () = assert!(SUB_LEAF <= SUB_MAX);

/// Polygons from which [`SelfPrep::make`] shares a mesh's preparation between workers.
const PAR_MIN: usize = 4096;

/// Polygons, and leaves, per job of the preparation's parallel loops: small enough that a
/// worker done early takes over the rest of a slower one's share (a core shared with other
/// work: left to rayon's own split, one worker of two was seen working alone for half of a
/// loop), big enough that a job's hand-over costs nothing next to its work.
const PAR_POLYGONS: usize = 2048;
/// (Two: the leaves' pieces, and so their layouts' and certificates' costs, differ widely;
/// eight left one of two workers alone with the last jobs of the certificates.)
const PAR_LEAVES: usize = 2;

/// `out` made `items` mapped by `f`: shared between the caller's workers in jobs of
/// [`PAR_POLYGONS`] with `par`, else on this thread.
fn map_into<T: Sync, U: Send>(
    out: &mut Vec<U>,
    items: &[T],
    par: bool,
    f: impl Fn(&T) -> U + Sync + Send,
) {
    use rayon::prelude::*;
    out.clear();
    if par {
        out.par_extend(items.par_iter().with_max_len(PAR_POLYGONS).map(f));
    } else {
        out.extend(items.iter().map(f));
    }
}

/// The projections in which all triangles `ids` turn the same way ([`turn_mask`] bits
/// common to all; 0 as soon as there is none).
fn common_turns(ids: &mut dyn Iterator<Item = usize>, turns: &[u8]) -> u8 {
    let mut m = 0x3f;
    for p in ids {
        m &= turns[p];
        if m == 0 {
            break;
        }
    }
    m
}

/// `f` over `items` with a [`PatchCheck`] scratch per worker: shared between the scene's
/// workers when `par` (the caller runs inside its pool), else on this thread.
fn map_checked<I: Send, O: Send>(
    items: Vec<I>,
    par: bool,
    f: impl Fn(&mut PatchCheck, I) -> O + Sync + Send,
) -> Vec<O> {
    use rayon::prelude::*;
    if par {
        items
            .into_par_iter()
            .with_max_len(PAR_LEAVES)
            .map_init(PatchCheck::default, f)
            .collect()
    } else {
        let mut check = PatchCheck::default();
        items.into_iter().map(|x| f(&mut check, x)).collect()
    }
}

/// What of one leaf depends on vertex indices alone (its connected pieces and each candidate
/// patch's boundary loop) or was fixed when it was first made (the sub-leaf split, from that
/// query's positions; later queries refit its boxes, as the leaves themselves are refit):
/// kept from query to query for one mesh.
struct LeafLayout {
    /// Sub-leaf ends (positions in the leaf order) and each sub-leaf's piece (within the
    /// leaf).
    ends: Vec<u32>,
    sub_piece: Vec<u32>,
    pieces: Vec<PieceLayout>,
}

/// One connected piece of a leaf: its range of the leaf's polygons (positions from the
/// leaf's start) and boundary loop.
///
/// Only whole pieces are tried as patches: trying the halves, quarters... and sub-leaves
/// of the pieces that fail (a crumpled cloth's) cost more than the pairs they saved once
/// the fans decide neighbour pairs and the lanes list the others (all real and generated
/// scenes as fast or faster without: crumpled cloth 27.2-29.0 -> 26.4-26.7 ms, rolled
/// 17.6-17.8 -> 15.8-17.2, one thread, interleaved).
struct PieceLayout {
    range: (usize, usize),
    boundary: Option<Loop>,
}

/// The layout of one leaf of a self-colliding mesh: `items` (its polygons, positions
/// `start..` of the leaf order) are grouped by connected piece (shared edges, from the twins
/// `tw`; one piece without them), each piece cut into sub-leaves of at most [`SUB_LEAF`] by
/// cuts of the box centres ([`sweep_cut`]: as few sub-leaves as hold the piece, cut where
/// their boxes are tightest); `local` gets each polygon's piece;
/// then the boundary loop of every piece.
#[allow(clippy::too_many_arguments)]
fn leaf_layout(
    start: usize,
    items: &mut [u32],
    local: &mut [u32],
    pb: &[Aabb],
    tw: Option<&[u32]>,
    verts: &[[u32; 4]],
    check: &mut PatchCheck,
) -> LeafLayout {
    let len = items.len();
    let inside = |t: u32| (t as usize).wrapping_sub(start) < len;
    // Connected pieces: union-find over the shared edges inside the leaf.
    let pieces = if let Some(tw) = tw {
        let mut up: Vec<u32> = (0..len as u32).collect();
        fn root(up: &mut [u32], mut x: u32) -> u32 {
            while up[x as usize] != x {
                up[x as usize] = up[up[x as usize] as usize];
                x = up[x as usize];
            }
            x
        }
        for i in 0..len {
            for e in 0..3 {
                let t = tw[3 * (start + i) + e];
                if t != NONE && inside(t) {
                    let (a, b) = (root(&mut up, i as u32), root(&mut up, t - start as u32));
                    up[a.max(b) as usize] = a.min(b);
                }
            }
        }
        let mut count = 0;
        for i in 0..len {
            let r = root(&mut up, i as u32) as usize;
            local[i] = if r == i {
                count += 1;
                count - 1
            } else {
                local[r]
            };
        }
        count as usize
    } else {
        local.fill(0);
        1
    };
    items.sort_unstable_by_key(|&p| local[p as usize - start]);
    let mut out = LeafLayout {
        ends: Vec::with_capacity(len / (SUB_LEAF / 2) + pieces + 1),
        sub_piece: Vec::new(),
        pieces: Vec::with_capacity(pieces),
    };
    let mut stack = Vec::new();
    let scratch_cut = &mut Vec::new();
    let mut run = 0;
    while run < len {
        let c = local[items[run] as usize - start];
        let end = run
            + items[run..]
                .iter()
                .take_while(|&&p| local[p as usize - start] == c)
                .count();
        // Depth-first, left half first: sub-leaves come out in order.
        stack.push((run, end));
        while let Some((a, b)) = stack.pop() {
            if b - a <= SUB_LEAF {
                out.ends.push((start + b) as u32);
                out.sub_piece.push(c);
                continue;
            }
            let part = &mut items[a..b];
            let mid = sweep_cut(part, pb, scratch_cut);
            stack.push((a + mid, b));
            stack.push((a, a + mid));
        }
        out.pieces.push(PieceLayout {
            range: (run, end),
            boundary: None,
        });
        run = end;
    }
    let Some(tw) = tw else {
        return out;
    };
    // Each polygon's position in `items`; a candidate's boundary: the edges whose twin lies
    // outside its range.
    let mut pos_of = vec![0u32; len];
    for (at, &p) in items.iter().enumerate() {
        pos_of[p as usize - start] = at as u32;
    }
    let pos_of = &pos_of;
    let bound = |a: usize, b: usize| {
        let within = move |t: u32| {
            t != NONE && inside(t) && (a..b).contains(&(pos_of[t as usize - start] as usize))
        };
        items[a..b]
            .iter()
            .flat_map(|&p| 3 * p as usize..3 * p as usize + 3)
            .filter(move |&x| !within(tw[x]))
            .map(|x| x as u32)
    };
    for piece in &mut out.pieces {
        let (a, b) = piece.range;
        piece.boundary = check.boundary_loop(bound(a, b), verts);
    }
    out
}

/// This query's certificates of one leaf laid out as `lay` (its polygons at positions
/// `start..` of the layout's order, the numbering of `tris` and `turns`): each piece is
/// tried as a patch ([`crate::geom::patch`]), its usable projections (0: not proven)
/// into `out` (an entry per piece).
fn leaf_certify(
    lay: &LeafLayout,
    start: usize,
    tris: &[[P3; 3]],
    turns: &[u8],
    check: &mut PatchCheck,
    out: &mut [u8],
) {
    for (piece, cert) in lay.pieces.iter().zip(out) {
        *cert = 0;
        let Some(l) = &piece.boundary else {
            continue;
        };
        let (a, b) = piece.range;
        let m = common_turns(&mut (start + a..start + b), turns);
        if m != 0 && check.simple(l, mask_axis(m), tris) {
            *cert = m;
        }
    }
}

/// One self-colliding mesh made ready for a query, once, before the tasks: its leaf pairs,
/// and each leaf cut into sub-leaves of at most [`SUB_LEAF`] polygons (cuts of the
/// polygons' box centres, see [`sweep_cut`]), with their boxes. A leaf pair's polygon box
/// pairs then come from the sub-leaf pairs whose boxes meet, each tested
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
    /// Sub-leaf boxes, as they are and grown by `h` (in lanes: a leaf pair's sub-leaf
    /// pairs are tested eight at a time too).
    sub_boxes: Vec<Aabb>,
    sub_grown: Lanes,
    /// At epsilon 0, a triangle mesh's bounds along six diagonal directions ([`Diag`]),
    /// per polygon and per sub-leaf: pairs of either apart along one are never listed.
    /// Empty otherwise (a band's viewing volumes reach beyond a polygon's diagonal bounds
    /// by more than its box's growth says).
    diag: Diag,
    sub_diag: Diag,
    /// Whether the diagonal bounds are made (see [`SelfPrep::use_diag`]), queries since
    /// they were last made, and the last query's pairs sharing no vertex left to the exact
    /// test and pairs the bounds dropped (summed by its tasks).
    diag_made: bool,
    diag_idle: u32,
    apart_left: std::sync::atomic::AtomicUsize,
    diag_dropped: std::sync::atomic::AtomicUsize,
    /// Which polygons share a vertex index (made with the layout): the box stage leaves
    /// those pairs out, and the neighbour tasks list the ones to test around `open`.
    near: Neighbours,
    /// Per polygon, numbered by position in `order` (as every per-polygon array here and
    /// the pairs [`SelfPrep::box_pairs`] names): the caller's vertex indices (the first
    /// `k` count), kept with the layout.
    verts: Vec<[u32; 4]>,
    k: usize,
    /// A triangle mesh's corner slots per position (made with the layout): a float mesh's
    /// triangles are read through them in order (not through `order` and the polygon list).
    corner_slots: Vec<[u32; 3]>,
    /// The caller's polygon index per position (made with the layout): what a found pair
    /// names.
    ids: Vec<u32>,
    /// Triangle meshes: per polygon, its corners in `f64` (a plane is made only for the
    /// few neighbour pairs the fans leave to a test).
    tris: Vec<[P3; 3]>,
    grown_leaves: Vec<Aabb>,
    found: Vec<(u32, u32)>,
    sweep: Sweep,
    /// Patch certificates ([`crate::geom::patch`]; triangle meshes with consistently
    /// oriented edges). A patch is one connected piece (by shared edges) of one leaf; each
    /// sub-leaf lies in one patch (`sub_patch`). Per patch: its usable projections
    /// ([`turn_mask`]; 0: not proven) when it is proven free of self-intersection. Parts
    /// of pieces are not tried ([`PieceLayout`]), nor two patches together (their union's
    /// loop cost more than the pairs it saved once the fans decide neighbour pairs: rolled
    /// cloth 28.7 -> 23.8-25.6 ms, rods 62-64 -> 61, cloth-funnel 5.5-5.7 -> 4.8-4.9,
    /// armadillo 9.8-10.2 -> 8.6-8.7).
    sub_patch: Vec<u32>,
    patch_cert: Vec<u8>,
    /// Per leaf-order triangle: [`turn_mask`].
    turns: Vec<u8>,
    /// The layout of each leaf ([`LeafLayout`]), each polygon's piece within its leaf, and
    /// the mesh (id, polygons, leaves) they were made for.
    layouts: Vec<LeafLayout>,
    piece_of: Vec<u32>,
    layout_key: Option<(u32, usize, usize)>,
    /// Vertex-fan certificates ([`crate::geom::fan`]; triangle meshes with consistently
    /// oriented edges): the fans (made with the layout) and each vertex index's verdict
    /// this query (empty: none proven): a neighbour pair sharing a proven one is decided
    /// without a test.
    fans: Fans,
    fan_scratch: Vec<bool>,
    fan_ok: Vec<bool>,
    /// The vertex indices held by two polygons or more whose fan is not proven this
    /// query: the neighbour pairs left to a test lie around them
    /// ([`Neighbours::pairs_at`]; shared out between tasks, see [`self_neighbours`]).
    pub open: Vec<u32>,
    /// Vertices whose fan is proven in the last [`SelfPrep::make`].
    pub certified_fans: usize,
    /// Patches proven by their certificate in the last [`SelfPrep::make`].
    pub certified_patches: usize,
    /// Leaf pairs `(i, j)`, `i <= j`, whose boxes meet once grown by `h`, sorted: the
    /// units of work of [`self_pairs`] (callers may split them between threads).
    pub leaf_pairs: Vec<(u32, u32)>,
}

impl SelfPrep {
    /// Makes the leaf pairs, sub-leaves and vertex indices of mesh `m` for half depth `h`.
    /// With `par` (the caller runs inside the scene's worker pool), a big mesh's
    /// per-polygon and per-leaf work is shared between the workers: for a scene of one big
    /// cloth this runs before any task and would otherwise keep the other cores idle.
    pub fn make(&mut self, id: u32, m: &Mesh, h: f64, par: bool) {
        use rayon::prelude::*;
        let n = m.polygon_count();
        let par = par && n >= PAR_MIN;
        // The layout (pieces, sub-leaf split, boundary loops; the vertex indices and fans)
        // is made at the first query of this mesh and kept (a mesh's topology never
        // changes, and its id is never reused): later queries refit the sub-leaves' boxes
        // and redo only the certificates' exact tests on the new positions.
        let key = (id, n, m.leaf_count());
        let new_layout = self.layout_key != Some(key);
        let tri = |x: &u32| {
            let mut t = [[[0.0; 3]; 3]; 2];
            m.triangles(*x as usize, &mut t);
            t[0]
        };
        // A float mesh's corners read straight from its positions (exactly, widened).
        let slots = &m.slots;
        let float_tri = |c: &[u32; 3]| c.map(|s| crate::geom::widen(&slots[s as usize]));
        let float = !m.needs_cpu();
        let triangles = m.vertices_per_polygon() == 3;
        let tw = m.twins();
        let certify = tw.is_some();
        let leaf_range = |l: usize| m.leaves.polys(l);
        if new_layout {
            self.make_layout(m, key, par);
        }
        // The leaf pairs (a sweep over the leaf boxes, on one thread)...
        let mut leaf_pairs = || {
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
        };
        // ... and per position of `order`, the triangle's corners and turn mask.
        let mut tris_turns = || {
            match (triangles, float) {
                (true, true) => map_into(&mut self.tris, &self.corner_slots, par, float_tri),
                (true, false) => map_into(&mut self.tris, &self.order, par, tri),
                (false, _) => self.tris.clear(),
            }
            if certify {
                map_into(&mut self.turns, &self.tris, par, turn_mask);
            } else {
                self.turns.clear();
            }
        };
        // Side by side with workers: the sweep alone would leave the other cores idle
        // (and asleep: waking one costs tens of microseconds).
        if par {
            rayon::join(leaf_pairs, tris_turns);
        } else {
            leaf_pairs();
            tris_turns();
        }
        // The fans' verdicts, then the vertices around which neighbours are left to test;
        // side by side, the patches' certificates (numbered as `sub_patch` says), each
        // leaf's written in its own part of `patch_cert`. (Each is a parallel loop whose
        // last jobs leave a worker idle; side by side the other's jobs fill the gap.)
        let (tris, turns) = (&self.tris[..], &self.turns[..]);
        let (fans, fan_scratch, fan_ok) = (&self.fans, &mut self.fan_scratch, &mut self.fan_ok);
        let (near, open) = (&self.near, &mut self.open);
        let mut prove_fans = || {
            fans.prove(
                tris,
                float.then_some(&slots[..]),
                turns,
                par,
                fan_scratch,
                fan_ok,
            );
            open.clear();
            open.extend(
                near.shared_vertices()
                    .iter()
                    .copied()
                    .filter(|&v| !fan_ok.get(v as usize).is_some_and(|&x| x)),
            );
            fan_ok.iter().filter(|&&x| x).count()
        };
        let (layouts, patch_cert) = (&self.layouts, &mut self.patch_cert);
        let mut certify_patches = || {
            patch_cert.clear();
            if !certify {
                // No certificate: every leaf one unproven patch.
                patch_cert.resize(layouts.len(), 0);
                return;
            }
            let pieces = layouts.iter().map(|lay| lay.pieces.len());
            patch_cert.resize(pieces.clone().sum(), 0);
            let mut rest = &mut patch_cert[..];
            let mut parts = Vec::with_capacity(layouts.len());
            for (l, count) in pieces.enumerate() {
                let (this, tail) = std::mem::take(&mut rest).split_at_mut(count);
                parts.push((l, this));
                rest = tail;
            }
            let cert = |check: &mut PatchCheck, (l, out): (usize, &mut [u8])| {
                leaf_certify(&layouts[l], leaf_range(l).start, tris, turns, check, out)
            };
            if par {
                parts
                    .into_par_iter()
                    .with_max_len(PAR_LEAVES)
                    .for_each_init(PatchCheck::default, cert);
            } else {
                let mut check = PatchCheck::default();
                parts.into_iter().for_each(|x| cert(&mut check, x));
            }
        };
        self.certified_fans = if par {
            rayon::join(prove_fans, certify_patches).0
        } else {
            let proven = prove_fans();
            certify_patches();
            proven
        };
        self.certified_patches = self.patch_cert.iter().filter(|&&c| c != 0).count();
        // The polygons' boxes: a float mesh's triangle's from its corner slots (as
        // `Mesh::poly_box`, in order); another triangle's from its corners, already made
        // (bounds rounded outward: a box holding the very triangle tested).
        let slot_box = |c: &[u32; 3]| {
            let mut b = Aabb::EMPTY;
            c.iter().for_each(|&s| b.grow(&slots[s as usize]));
            b
        };
        let poly_box = |&p: &u32| m.poly_box(p as usize);
        match (triangles, float) {
            (true, true) => map_into(&mut self.boxes, &self.corner_slots, par, slot_box),
            (true, false) => map_into(&mut self.boxes, &self.tris, par, corner_box),
            (false, _) => map_into(&mut self.boxes, &self.order, par, poly_box),
        }
        self.lanes.set_grown(&self.boxes, h, par);
        let sub_box = |w: &[u32]| {
            let mut b = Aabb::EMPTY;
            for c in &self.boxes[w[0] as usize..w[1] as usize] {
                b.merge(c);
            }
            b
        };
        self.sub_boxes.clear();
        if par {
            self.sub_boxes.par_extend(
                self.sub_start
                    .par_windows(2)
                    .with_max_len(PAR_POLYGONS / 16)
                    .map(sub_box),
            );
        } else {
            self.sub_boxes
                .extend(self.sub_start.windows(2).map(sub_box));
        }
        self.sub_grown.set_grown(&self.sub_boxes, h, par);
        if h == 0.0 && triangles && self.use_diag(n) {
            if float {
                self.diag.set_corners(slots, &self.corner_slots, par);
            } else {
                self.diag.set_triangles(&self.tris, par);
            }
            self.sub_diag.set_union(&self.diag, &self.sub_start, par);
            self.diag_made = true;
        } else {
            self.diag = Diag::default();
            self.sub_diag = Diag::default();
            self.diag_made = false;
        }
    }

    /// Whether to make the diagonal bounds for this query of a mesh of `n` polygons.
    /// Making a polygon's bounds costs about what an exact test costs, and each pair they
    /// drop saves one; they pay where box pairs between layers of a mesh folded onto
    /// itself stay close, so that many pairs are left to the exact test even after the
    /// bounds drop theirs. Where the only pairs sharing no vertex are neighbours across
    /// patch borders (flat or gently curved sheets, spheres), the bounds drop them all,
    /// but making and testing them cost more than those cheap tests (flat 300x300 cloth
    /// 16.4 -> 18.7 ms, 1000 spheres 88 -> 94 ms, with the bounds always made). So: made
    /// while the last query that made them dropped at least five pairs per four polygons
    /// and left at least one per eight polygons to the exact test; else made again once
    /// every [`DIAG_RETRY`] queries, to see. Measured per polygon (dropped, left; one
    /// thread): crumpled cloth 2.8, 2.2 (21.4 -> 19.2 ms); rods 3.5, 1.1 (42.3 -> 41.6);
    /// the rolled cloth of `self-scaling` at 10k, 28k, 92k triangles 4.0, 2.2, 1.4 (1.94
    /// -> 1.49, 4.58 -> 3.94, 13.0 -> 11.9 ms), at 179k and 403k 1.15 and 1.0 (24.5 ->
    /// 27.1 and 62.1 -> 68.4 ms: off); armadillo 0.95 (about even: off); flat sheets 1.4,
    /// 0 (off). The answer is the same either way.
    fn use_diag(&mut self, n: usize) -> bool {
        let left = self
            .apart_left
            .swap(0, std::sync::atomic::Ordering::Relaxed);
        let dropped = self
            .diag_dropped
            .swap(0, std::sync::atomic::Ordering::Relaxed);
        let paying = self.diag_made && 8 * left >= n && 4 * dropped >= 5 * n;
        // A mesh's first query makes them (`diag_idle` starts at 0).
        let make = paying || (!self.diag_made && self.diag_idle.is_multiple_of(DIAG_RETRY));
        self.diag_idle = if make { 0 } else { self.diag_idle + 1 };
        make
    }

    /// The diagonal bounds of the polygons and of the sub-leaves, when made.
    #[inline]
    fn diags(&self) -> (Option<&Diag>, Option<&Diag>) {
        if self.diag.len() == 0 {
            (None, None)
        } else {
            (Some(&self.diag), Some(&self.sub_diag))
        }
    }

    /// The layout of mesh `m` (the first query of this mesh): each leaf's pieces, sub-leaf
    /// split and boundary loops, the fans; then everything renumbered by position in
    /// `order` (sub-leaf by sub-leaf), the numbering of every per-polygon array of a query,
    /// so that a sub-leaf's triangles, vertex indices and masks lie side by side (the
    /// pair tests of two sub-leaves then read two short runs, not polygons all over their
    /// leaves).
    fn make_layout(&mut self, m: &Mesh, key: (u32, usize, usize), par: bool) {
        use rayon::prelude::*;
        let n = m.polygon_count();
        let leaf_range = |l: usize| m.leaves.polys(l);
        let triangles = m.vertices_per_polygon() == 3;
        let tw = m.twins();
        self.verts.clear();
        let mut poly_boxes = Vec::with_capacity(n);
        if par {
            poly_boxes.par_extend((0..n).into_par_iter().map(|p| m.poly_box(p)));
            self.verts
                .par_extend((0..n).into_par_iter().map(|p| vertices(m, p)));
        } else {
            poly_boxes.extend((0..n).map(|p| m.poly_box(p)));
            self.verts.extend((0..n).map(|p| vertices(m, p)));
        }
        self.order.clear();
        self.order.extend(0..n as u32);
        self.piece_of.clear();
        self.piece_of.resize(n, 0);
        let (verts, pb) = (&self.verts[..], &poly_boxes[..]);
        let mut slices = Vec::with_capacity(m.leaf_count());
        let (mut rest, mut rest_piece) = (&mut self.order[..], &mut self.piece_of[..]);
        for l in 0..m.leaf_count() {
            let r = leaf_range(l);
            debug_assert_eq!(
                r.start,
                n - rest.len(),
                "leaves cover the polygons in order"
            );
            let (this, tail) = std::mem::take(&mut rest).split_at_mut(r.len());
            let (this_p, tail_p) = std::mem::take(&mut rest_piece).split_at_mut(r.len());
            slices.push((r.start, this, this_p));
            rest = tail;
            rest_piece = tail_p;
        }
        let lay = |check: &mut PatchCheck,
                   (start, items, local): (usize, &mut [u32], &mut [u32])| {
            leaf_layout(start, items, local, pb, tw, verts, check)
        };
        self.layouts = map_checked(slices, par, lay);
        self.sub_start.clear();
        self.sub_start.push(0);
        self.leaf_sub.clear();
        self.leaf_sub.push(0);
        // Each sub-leaf's patch: with twins, its piece's, the pieces numbered leaf after
        // leaf; without, its leaf's (one unproven patch a leaf).
        self.sub_patch.clear();
        let mut first = 0;
        for (l, lay) in self.layouts.iter().enumerate() {
            self.sub_start.extend(&lay.ends);
            self.leaf_sub.push(self.sub_start.len() as u32 - 1);
            if tw.is_some() {
                self.sub_patch
                    .extend(lay.sub_piece.iter().map(|&c| c + first));
                first += lay.pieces.len() as u32;
            } else {
                self.sub_patch
                    .extend(std::iter::repeat_n(l as u32, lay.ends.len()));
            }
        }
        self.fans = match tw {
            Some(tw) if triangles => Fans::new(m.vertex_count(), &self.verts, tw),
            _ => Fans::default(),
        };
        // Renumber by position: `pos_of[p]` is polygon p's position in `order`.
        let mut pos_of = vec![0u32; n];
        for (x, &p) in self.order.iter().enumerate() {
            pos_of[p as usize] = x as u32;
        }
        let edge = |e: &mut u32| *e = 3 * pos_of[*e as usize / 3] + *e % 3;
        for lay in &mut self.layouts {
            for piece in &mut lay.pieces {
                if let Some(l) = &mut piece.boundary {
                    l.edges.iter_mut().for_each(edge);
                }
            }
        }
        self.fans.renumber(&pos_of);
        let verts: Vec<[u32; 4]> = self.order.iter().map(|&p| self.verts[p as usize]).collect();
        self.verts = verts;
        self.ids.clear();
        self.ids
            .extend(self.order.iter().map(|&p| m.poly_ids[p as usize]));
        self.corner_slots.clear();
        if triangles {
            self.corner_slots.extend(
                self.order
                    .iter()
                    .map(|&p| [0, 1, 2].map(|c| m.poly(p as usize)[c])),
            );
            self.fans.set_points(&self.corner_slots);
        }
        self.k = m.vertices_per_polygon();
        self.near = Neighbours::new(&self.verts, self.k, m.vertex_count(), &self.sub_start);
        self.layout_key = Some(key);
    }

    /// Do sub-leaves `a` and `b` lie in one patch proven free of self-intersection?
    #[inline]
    fn together(&self, a: usize, b: usize) -> bool {
        let (pa, pb) = (self.sub_patch[a], self.sub_patch[b]);
        pa == pb && self.patch_cert[pa as usize] != 0
    }

    /// The range of `order` of sub-leaf `s`.
    #[inline]
    fn sub(&self, s: usize) -> std::ops::Range<usize> {
        self.sub_start[s] as usize..self.sub_start[s + 1] as usize
    }

    /// The polygons `p` of leaf `i` and `q` of leaf `j` (positions in `order`) sharing no
    /// vertex index whose boxes meet once `p`'s is grown by `h` (`p != q`), each unordered
    /// pair once, as `[p, q]`, appended to `apart`, less those apart along a diagonal
    /// (counted: the second result). Pairs sharing a vertex index are left out of the box
    /// tests (their boxes always meet; [`Neighbours`] says which they are) and counted (the
    /// first result) unless `proven_subs` of their two sub-leaves says that both lie in a
    /// patch proven free of self-intersection. With `exact` (epsilon 0) the pairs of
    /// proven sub-leaf pairs are not enumerated at all. `subs` is scratch.
    #[inline]
    fn box_pairs(
        &self,
        i: usize,
        j: usize,
        exact: bool,
        subs: &mut Vec<[u32; 2]>,
        mut proven_subs: impl FnMut(usize, usize) -> bool,
        apart: &mut Vec<[u32; 2]>,
    ) -> (usize, usize) {
        let (diag, sub_diag) = self.diags();
        let (si, sj) = (
            self.leaf_sub[i] as usize..self.leaf_sub[i + 1] as usize,
            self.leaf_sub[j] as usize..self.leaf_sub[j + 1] as usize,
        );
        // The sub-leaf pairs whose boxes meet (within one leaf each unordered pair once,
        // and each sub-leaf with itself), sixteen sub-leaves at a time, then their polygon
        // box pairs.
        subs.clear();
        if i == j {
            subs.extend(si.clone().map(|a| [a as u32; 2]));
        }
        for a in si.clone().step_by(16) {
            let ra = a..(a + 16).min(si.end);
            for b in sj.clone().step_by(16) {
                if i == j && b < a {
                    continue;
                }
                let rb = b..(b + 16).min(sj.end);
                let cands = &self.sub_boxes[rb];
                let upper = i == j && a == b;
                self.sub_grown
                    .pairs_16(ra.clone(), cands, b as u32, upper, sub_diag, None, subs);
            }
        }
        let (mut shared, mut culled) = (0, 0);
        for &[a, b] in subs.iter() {
            let (a, b) = (a as usize, b as usize);
            let proven = proven_subs(a, b);
            if proven && exact {
                continue;
            }
            // The lower sub-leaf in the lanes, the other's polygons as candidates (the
            // masks are kept that way round).
            let (lo, hi) = (a.min(b), a.max(b));
            let rh = self.sub(hi);
            let cands = &self.boxes[rh.clone()];
            let (excl, count) = if lo == hi {
                let (own, count) = self.near.within(lo, rh.clone());
                (Some(own), count)
            } else {
                match self.near.between(lo, hi) {
                    Some((m, count)) => (Some(&m[..rh.len()]), count),
                    None => (None, 0),
                }
            };
            let c0 = rh.start as u32;
            culled += self
                .lanes
                .pairs_16(self.sub(lo), cands, c0, lo == hi, diag, excl, apart);
            if !proven {
                shared += count;
            }
        }
        (shared, culled)
    }
}

/// Queries between two tries of a mesh's diagonal bounds where they did not pay
/// ([`SelfPrep::use_diag`]).
const DIAG_RETRY: u32 = 16;

/// Scratch of [`self_pairs`] and [`self_neighbours`], reused from query to query.
#[derive(Default)]
pub struct SelfScratch {
    /// Polygon pairs (positions in the layout's order) of the task at hand: a neighbour
    /// task's pairs left to the adjacency test; a leaf-pair task's box-meeting pairs
    /// sharing no vertex, left to the exact test.
    adjacent: Vec<[u32; 2]>,
    apart: Vec<[u32; 2]>,
    /// Sub-leaf pairs of the leaf pair at hand whose boxes meet.
    subs: Vec<[u32; 2]>,
    /// Polygons prepared for the narrow test (by leaf-order index) in the task at hand;
    /// their viewing volumes likewise (`h > 0`). Made on demand, only for the pairs the
    /// lanes leave undecided and for quads: a few per task, so kept in a short list with a
    /// slot per polygon rather than a full-size value per polygon (a 92k-triangle cloth
    /// would need ~28 MB of preparations and ~55 MB of volumes per worker).
    prepared: Slots<Prepared>,
    cells: Slots<[Cell; 2]>,
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
    /// Self-collision: polygon pairs whose boxes meet (`p < q`), in sub-leaf pairs whose
    /// boxes and diagonal bounds meet.
    pub self_box_pairs: usize,
    /// Of them, pairs apart along a diagonal direction (epsilon 0, triangles; see
    /// `backend::cpu::diag::Diag`): not tested.
    pub self_box_culled: usize,
    /// Self-collision: time and count of adjacency decisions (pairs sharing a vertex).
    pub self_adjacent_nanos: u64,
    /// Pairs sharing a vertex index whose boxes meet.
    pub self_adjacent_tests: usize,
    /// Of them, pairs decided by a cheap conservative test without the exact adjacency
    /// predicate.
    pub self_adjacent_quick: usize,
    /// Pairs sharing a vertex index decided by that vertex's fan certificate
    /// ([`crate::geom::fan`]): not tested, not counted in `self_adjacent_tests`.
    pub self_adjacent_fans: usize,
    /// Vertices whose fan certificate holds.
    pub self_cert_fans: usize,
    /// Self-collision: time and count of narrow tests of pairs sharing no vertex.
    pub self_narrow_nanos: u64,
    /// Pairs sharing no vertex index whose boxes meet.
    pub self_narrow_tests: usize,
    /// Self-collision: polygon pairs found.
    pub self_found: usize,
    /// Self-collision patch certificates ([`crate::geom::patch`]): patches (connected
    /// pieces of leaves) proven free of self-intersection.
    pub self_cert_patches: usize,
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
        self.self_box_culled += o.self_box_culled;
        self.self_adjacent_nanos += o.self_adjacent_nanos;
        self.self_adjacent_tests += o.self_adjacent_tests;
        self.self_adjacent_quick += o.self_adjacent_quick;
        self.self_adjacent_fans += o.self_adjacent_fans;
        self.self_narrow_nanos += o.self_narrow_nanos;
        self.self_narrow_tests += o.self_narrow_tests;
        self.self_found += o.self_found;
    }
}

pub(crate) fn nanos_since(t: Instant) -> u64 {
    t.elapsed().as_nanos() as u64
}

/// The self-collision pairs of mesh `id` (made ready in `prep`) sharing a vertex index
/// among the open vertices `prep.open[range]` ([`SelfPrep::open`]: those whose fan is not
/// proven), each decided by [`adjacent_polygons_meet`] (most at once by
/// [`triangles_touch_only_at_joint_planes`]), appended to `out` as [`self_pairs`] does;
/// counts and times added to `st`. The pairs of all open vertices with those of all leaf
/// pairs are the mesh's self-collision answer.
#[allow(clippy::too_many_arguments)]
pub fn self_neighbours(
    id: u32,
    m: &Mesh,
    prep: &SelfPrep,
    range: std::ops::Range<usize>,
    s: &mut SelfScratch,
    out: &mut Vec<Pair>,
    st: &mut AllStats,
) {
    let t = Instant::now();
    let k = m.vertices_per_polygon();
    s.adjacent.clear();
    let near = &prep.near;
    let together = |p: u32, q: u32| prep.together(near.sub_of(p as usize), near.sub_of(q as usize));
    // The polygons around an open vertex lie anywhere in the mesh's arrays: those of the
    // vertex a few ahead are asked for while this one's pairs are listed.
    const AHEAD: usize = 8;
    let open = &prep.open[range];
    for (x, &v) in open.iter().enumerate() {
        if let Some(&w) = open.get(x + 2 * AHEAD) {
            near.prefetch_polys(w as usize);
        }
        if let Some(&w) = open.get(x + AHEAD) {
            for &p in near.polys(w as usize) {
                crate::geom::prefetch_item(&prep.verts, p as usize);
                crate::geom::prefetch_item(&prep.tris, p as usize);
            }
        }
        near.pairs_at(v, &prep.verts, k, &prep.fan_ok, together, &mut s.adjacent);
    }
    st.self_adjacent_tests += s.adjacent.len();
    let found = out.len();
    let mut push = |p, q| push_pair(out, id, &prep.ids, p, q);
    let mut quick = 0;
    for &[p, q] in &s.adjacent {
        let (p, q) = (p as usize, q as usize);
        let (vp, vq) = (&prep.verts[p], &prep.verts[q]);
        if k == 3 {
            let (ip, iq) = ([vp[0], vp[1], vp[2]], [vq[0], vq[1], vq[2]]);
            let (tp, tq) = (&prep.tris[p], &prep.tris[q]);
            let (pp, pq) = (Plane::of(tp), Plane::of(tq));
            if triangles_touch_only_at_joint_planes(&ip, tp, &pp, &iq, tq, &pq) {
                quick += 1;
                continue;
            }
        }
        let (mut tp, mut tq) = ([[[0.0; 3]; 3]; 2], [[[0.0; 3]; 3]; 2]);
        let np = m.triangles(prep.order[p] as usize, &mut tp);
        let nq = m.triangles(prep.order[q] as usize, &mut tq);
        if adjacent_polygons_meet(&vp[..k], &tp, np, &vq[..k], &tq, nq) {
            push(p as u32, q as u32);
        }
    }
    st.self_adjacent_quick += quick;
    st.self_adjacent_nanos += nanos_since(t);
    st.self_found += out.len() - found;
}

/// Pushes the found pair of positions `p`, `q` into `out` as the caller's polygons
/// (`ids`) of mesh `id`.
#[inline]
fn push_pair(out: &mut Vec<Pair>, id: u32, ids: &[u32], p: u32, q: u32) {
    let (pa, pb) = (ids[p as usize], ids[q as usize]);
    out.push(Pair {
        mesh_a: id,
        polygon_a: pa.min(pb),
        mesh_b: id,
        polygon_b: pa.max(pb),
    });
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
    s.apart.clear();
    let k = m.vertices_per_polygon();
    let exact = h == 0.0;
    let (mut shared, mut culled) = (0, 0);
    for &(i, j) in leaf_pairs {
        // Proven patches meet only where they share: their neighbours need no decision.
        let (sh, c) = prep.box_pairs(
            i as usize,
            j as usize,
            exact,
            &mut s.subs,
            |a, b| prep.together(a, b),
            &mut s.apart,
        );
        shared += sh;
        culled += c;
    }
    st.self_box_nanos += nanos_since(t);
    prep.apart_left
        .fetch_add(s.apart.len(), std::sync::atomic::Ordering::Relaxed);
    prep.diag_dropped
        .fetch_add(culled, std::sync::atomic::Ordering::Relaxed);
    // Every pair sharing a vertex counted here as decided by a fan: the neighbour tasks'
    // tests are taken off once all are done ([`AllStats::self_adjacent_fans`]).
    st.self_box_pairs += s.apart.len() + shared + culled;
    st.self_box_culled += culled;
    st.self_adjacent_fans += shared;
    st.self_narrow_tests += s.apart.len();
    let found = out.len();
    let mut push = |p, q| push_pair(out, id, &prep.ids, p, q);
    let t = Instant::now();
    s.stamp += 1;
    let stamp = s.stamp;
    let n = m.polygon_count();
    s.prepared.start(n, stamp);
    if h > 0.0 {
        s.cells.start(n, stamp);
    }
    let mut judge = Apart {
        m,
        order: &prep.order,
        tris: (k == 3).then_some(&prep.tris[..]),
        h,
        prepared: &mut s.prepared,
        cells: &mut s.cells,
        push: &mut push,
    };
    #[cfg(target_arch = "x86_64")]
    {
        use crate::geom::batch::{Fours, Kernel};
        let kernel = if h == 0.0 {
            Kernel::Exact
        } else {
            Kernel::Band { h, both: true }
        };
        if let Some(mut fours) = Fours::<(u32, u32)>::new(kernel) {
            // Four pairs at a time where floating point certifies the answer, the others
            // (and quads) by the scalar test: the same answer as the loop below.
            fours.decide(s.apart.iter().map(|&[p, q]| (p, q)), &mut judge);
            st.self_narrow_nanos += nanos_since(t);
            st.self_found += out.len() - found;
            return;
        }
    }
    for &[p, q] in &s.apart {
        let key = (p, q);
        if judge.scalar(key) {
            (judge.push)(key.0, key.1);
        }
    }
    st.self_narrow_nanos += nanos_since(t);
    st.self_found += out.len() - found;
}

/// The narrow test of a task's non-adjacent polygon pairs (keys: positions in the
/// layout's order).
struct Apart<'a, F> {
    m: &'a Mesh,
    /// The mesh's polygon at each position (the keys are positions).
    order: &'a [u32],
    /// A triangle mesh's triangles, already made for this query (`None` for quads): the
    /// lanes read them there, and only the pairs they leave undecided are prepared (the
    /// preparation's scattered writes over a big mesh cost more than the test).
    tris: Option<&'a [[P3; 3]]>,
    h: f64,
    prepared: &'a mut Slots<Prepared>,
    cells: &'a mut Slots<[Cell; 2]>,
    push: F,
}

impl<F: FnMut(u32, u32)> Apart<'_, F> {
    /// The scalar test: the closed polygons intersect (`h = 0`), or either meets the
    /// other's viewing volumes.
    #[inline]
    fn scalar(&mut self, (p, q): (u32, u32)) -> bool {
        let (p, q, h) = (p as usize, q as usize, self.h);
        if let (Some(t), 0.0) = (self.tris, h) {
            // Two triangles in one coordinate plane (a flat sheet, a box, a floor): decided
            // in that plane, before preparing either polygon (the lanes of the test in
            // that plane leave such a pair undecided when a vertex is on or near the
            // other's edge line, or a triangle is flat).
            if let Some(meet) = in_one_axis_plane(&t[p], &t[q]) {
                return meet;
            }
            // Apart in a projection (exact): most of the rest of such pairs, coplanar in
            // a slanted plane, before the exact 3D orientations.
            if apart_in_projection(&t[p], &t[q]) {
                return false;
            }
        }
        let (m, order) = (self.m, self.order);
        let ip = self.prepared.get(p, || prepared(m, order[p] as usize));
        let iq = self.prepared.get(q, || prepared(m, order[q] as usize));
        let (a, b) = (&self.prepared.made[ip], &self.prepared.made[iq]);
        if h == 0.0 {
            return a.meets(b, None);
        }
        let ca = self.cells.get(p, || a.cells(h));
        let ca = &self.cells.made[ca];
        // Farther than `h` apart: neither meets the other's volumes (saves making `b`'s
        // and clipping both ways).
        if a.far_apart(ca, b, h) {
            return false;
        }
        a.meets(b, Some(ca)) || {
            let cb = self.cells.get(q, || b.cells(h));
            b.meets(a, Some(&self.cells.made[cb]))
        }
    }
}

#[cfg(target_arch = "x86_64")]
impl<F: FnMut(u32, u32)> crate::geom::batch::Judge<(u32, u32)> for Apart<'_, F> {
    #[inline(always)]
    fn triangles(&mut self, (p, q): (u32, u32)) -> Option<[&[P3; 3]; 2]> {
        if let Some(t) = self.tris {
            // (Two in one coordinate plane, a flat sheet's, go to the lanes of the exact
            // test in that plane.)
            return Some([&t[p as usize], &t[q as usize]]);
        }
        let (m, order) = (self.m, self.order);
        let ip = self
            .prepared
            .get(p as usize, || prepared(m, order[p as usize] as usize));
        let iq = self
            .prepared
            .get(q as usize, || prepared(m, order[q as usize] as usize));
        self.prepared.made[ip].triangle_pair(&self.prepared.made[iq])
    }
    #[inline]
    fn scalar(&mut self, key: (u32, u32)) -> bool {
        Apart::scalar(self, key)
    }
    #[inline]
    fn found(&mut self, (p, q): (u32, u32)) {
        (self.push)(p, q);
    }
    /// The two triangles' cache lines (a triangle spans two at most), when the mesh's
    /// triangles are made: the pairs' second triangles are scattered over the mesh.
    #[inline(always)]
    fn prefetch(&self, (p, q): (u32, u32)) {
        use std::arch::x86_64::{_mm_prefetch, _MM_HINT_T0};
        if let Some(t) = self.tris {
            for i in [p, q] {
                if let Some(t) = t.get(i as usize) {
                    let at = t.as_ptr().cast::<i8>();
                    // SAFETY: a prefetch is a hint (no access, no fault); both addresses are
                    // within the triangle (72 bytes, so `add(64)` stays inside it).
                    unsafe {
                        _mm_prefetch::<_MM_HINT_T0>(at);
                        _mm_prefetch::<_MM_HINT_T0>(at.add(64));
                    }
                }
            }
        }
    }
}

/// Leaf-order polygon `p` of `m` prepared for the narrow test.
#[inline]
fn prepared(m: &Mesh, p: usize) -> Prepared {
    let mut prep = Prepared::default();
    let n = m.triangles(p, &mut prep.poly.tris);
    prep.remake(n);
    prep
}

/// Values made on demand during one task, by leaf-order polygon: a slot per polygon (the
/// task's stamp and a position in `made`), the values in the order they were made.
struct Slots<T> {
    at: Vec<(u64, u32)>,
    made: Vec<T>,
    stamp: u64,
}

impl<T> Default for Slots<T> {
    fn default() -> Self {
        Slots {
            at: Vec::new(),
            made: Vec::new(),
            stamp: 0,
        }
    }
}

impl<T> Slots<T> {
    /// A new task, `stamp` (never seen before), over `n` polygons: nothing made yet.
    fn start(&mut self, n: usize, stamp: u64) {
        if self.at.len() < n {
            self.at.resize(n, (0, 0));
        }
        self.made.clear();
        self.stamp = stamp;
    }

    /// The position in `made` of polygon `p`'s value, made by `make` on first use.
    #[inline]
    fn get(&mut self, p: usize, make: impl FnOnce() -> T) -> usize {
        let (at, i) = self.at[p];
        if at == self.stamp {
            return i as usize;
        }
        let i = self.made.len();
        self.made.push(make());
        self.at[p] = (self.stamp, i as u32);
        i
    }
}

/// The box of a triangle's corners, bounds rounded outward to `f32`.
#[inline]
fn corner_box(t: &[P3; 3]) -> Aabb {
    let [a, b, c] = t;
    Aabb {
        min: std::array::from_fn(|k| f32_down(a[k].min(b[k]).min(c[k]))),
        max: std::array::from_fn(|k| f32_up(a[k].max(b[k]).max(c[k]))),
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

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::atomic::Ordering::Relaxed;

    /// Cutting at `sweep_cut` down to runs of at most `SUB_LEAF` (as `leaf_layout` does)
    /// leaves the fewest sub-leaves that can hold the run, each cut inside it, the run
    /// rearranged, not changed; and where two clusters of polygons lie apart, the cut
    /// falls between them.
    #[test]
    fn cuts_make_the_fewest_sub_leaves_where_boxes_are_tightest() {
        fn cut_all(part: &mut [u32], pb: &[Aabb], out: &mut Vec<usize>) {
            if part.len() <= SUB_LEAF {
                out.push(part.len());
                return;
            }
            let c = sweep_cut(part, pb, &mut Vec::new());
            assert!(0 < c && c < part.len(), "{} cut at {c}", part.len());
            let (l, r) = part.split_at_mut(c);
            cut_all(l, pb, out);
            cut_all(r, pb, out);
        }
        let mut rng = crate::geom::test_rng::Rng(5);
        let pb: Vec<Aabb> = (0..3000)
            .map(|_| {
                let c = [0, 1, 2].map(|_| rng.f() as f32);
                let r = 0.01 * rng.unit() as f32;
                Aabb {
                    min: c.map(|x| x - r),
                    max: c.map(|x| x + r),
                }
            })
            .collect();
        for len in (1..3000usize).step_by(7) {
            let mut part: Vec<u32> = (0..len as u32).collect();
            let mut sizes = Vec::new();
            cut_all(&mut part, &pb, &mut sizes);
            assert_eq!(sizes.len(), len.div_ceil(SUB_LEAF), "{len}: {sizes:?}");
            assert!(sizes.iter().all(|&x| x <= SUB_LEAF), "{len}: {sizes:?}");
            part.sort_unstable();
            assert!(
                part.iter().copied().eq(0..len as u32),
                "{len}: not a permutation"
            );
        }
        // Two clusters along y, of 16 and 24, interleaved in the input: 3 sub-leaves, so
        // the cuts at 1-16 and 24-39 keep the count; the tightest is between the clusters.
        let first = |i: u32| i % 5 < 2;
        let two: Vec<Aabb> = (0..40)
            .map(|i| {
                let y = if first(i) { 0.0 } else { 10.0 } + 0.01 * i as f32;
                Aabb {
                    min: [0.0, y, 0.0],
                    max: [1.0, y + 0.5, 1.0],
                }
            })
            .collect();
        let mut part: Vec<u32> = (0..40).collect();
        let c = sweep_cut(&mut part, &two, &mut Vec::new());
        assert_eq!(c, 16);
        assert!(part[..16].iter().all(|&p| first(p)), "{part:?}");
    }

    /// The diagonal bounds are made at a mesh's first query; kept while the query that
    /// made them dropped at least five pairs per four polygons and left at least one pair
    /// per eight polygons to the exact test; else made once every `DIAG_RETRY` queries.
    #[test]
    fn diagonal_bounds_are_made_while_they_pay() {
        let n = 800;
        let mut p = SelfPrep::default();
        // One query: make or not as `use_diag` says, then `left` pairs left by its tasks
        // and 1,000 dropped.
        let query = |p: &mut SelfPrep, left: usize| {
            let made = p.use_diag(n);
            p.diag_made = made;
            p.apart_left.store(left, Relaxed);
            p.diag_dropped.store(1000, Relaxed);
            made
        };
        assert!(query(&mut p, 100), "first query");
        assert!(query(&mut p, 100), "100 left of 800 polygons: paying");
        assert!(query(&mut p, 99), "still paying when made");
        let made: Vec<bool> = (0..40).map(|_| query(&mut p, 0)).collect();
        let at: Vec<usize> = (0..40).filter(|&i| made[i]).collect();
        assert_eq!(
            at,
            [DIAG_RETRY as usize, 2 * DIAG_RETRY as usize + 1],
            "99 of 800 left: dropped, then retried every {DIAG_RETRY} queries"
        );
        // A retry that pays keeps them; too few dropped does not.
        while !query(&mut p, 0) {}
        p.apart_left.store(500, Relaxed);
        assert!((0..5).all(|_| query(&mut p, 500)));
        p.diag_dropped.store(999, Relaxed);
        assert!(!p.use_diag(n), "999 dropped for 800 polygons");
    }
}
