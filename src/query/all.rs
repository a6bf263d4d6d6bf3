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

use crate::backend::Pair;
use crate::geom::adjacent::{adjacent_polygons_meet, shares_vertex};
use crate::geom::polygon::Prepared;
use crate::geom::sweep::Sweep;
use crate::geom::Aabb;
use crate::mesh::Mesh;

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

/// Scratch of [`self_pairs`], reused from query to query.
#[derive(Default)]
pub struct SelfScratch {
    grown_leaves: Vec<Aabb>,
    leaf_pairs: Vec<(u32, u32)>,
    boxes: Vec<Aabb>,
    vols: Vec<Aabb>,
    cands: Vec<Aabb>,
    box_pairs: Vec<(u32, u32)>,
    sweep: Sweep,
    poly_sweep: Sweep,
}

/// Leaf pairs `(i, j)`, `i <= j`, of mesh `m` whose boxes meet once grown by `h`: the units
/// of work of [`self_leaf_pairs`] (callers may split them between threads).
pub fn self_leaf_pairs(m: &Mesh, h: f64, s: &mut SelfScratch) -> Vec<(u32, u32)> {
    s.grown_leaves.clear();
    s.grown_leaves
        .extend(m.leaf_boxes().iter().map(|b| b.grown(h)));
    s.leaf_pairs.clear();
    s.sweep
        .pairs(&s.grown_leaves, m.leaf_boxes(), &mut s.leaf_pairs);
    let mut pairs: Vec<(u32, u32)> = s
        .leaf_pairs
        .iter()
        .copied()
        .filter(|&(i, j)| i <= j)
        .collect();
    pairs.sort_unstable();
    pairs
}

/// The self-collision pairs of mesh `id` among the given leaf pairs, appended to `out`
/// (caller's polygon numbering, `polygon_a < polygon_b`, any order).
pub fn self_pairs(
    id: u32,
    m: &Mesh,
    h: f64,
    leaf_pairs: &[(u32, u32)],
    s: &mut SelfScratch,
    out: &mut Vec<Pair>,
) {
    if s.boxes.len() != m.polygon_count() {
        s.boxes.clear();
        s.boxes.resize(m.polygon_count(), Aabb::EMPTY);
    }
    // Polygon boxes of the leaves these pairs touch (each leaf once).
    let mut boxed = vec![false; m.leaf_count()];
    for &(i, j) in leaf_pairs {
        for l in [i, j] {
            if !std::mem::replace(&mut boxed[l as usize], true) {
                for p in m.leaves.polys(l as usize) {
                    s.boxes[p] = m.poly_box(p);
                }
            }
        }
    }
    for &(i, j) in leaf_pairs {
        let (ri, rj) = (m.leaves.polys(i as usize), m.leaves.polys(j as usize));
        s.vols.clear();
        s.vols
            .extend(s.boxes[ri.clone()].iter().map(|b| b.grown(h)));
        s.cands.clear();
        s.cands.extend_from_slice(&s.boxes[rj.clone()]);
        s.box_pairs.clear();
        s.poly_sweep.pairs(&s.vols, &s.cands, &mut s.box_pairs);
        for &(a, b) in &s.box_pairs {
            let (p, q) = (ri.start + a as usize, rj.start + b as usize);
            if i == j && p >= q {
                continue;
            }
            if polygons_meet_in_mesh(m, p, q, h) {
                let (pa, pb) = (m.poly_ids[p], m.poly_ids[q]);
                out.push(Pair {
                    mesh_a: id,
                    polygon_a: pa.min(pb),
                    mesh_b: id,
                    polygon_b: pa.max(pb),
                });
            }
        }
    }
}

/// The narrow test of two different polygons `p`, `q` (leaf order) of one mesh: adjacent
/// ones (sharing a vertex index) exactly beyond what they share; the others as any two
/// polygons of a whole-scene query (exact at `h = 0`, else either one meeting the other's
/// viewing volume).
fn polygons_meet_in_mesh(m: &Mesh, p: usize, q: usize, h: f64) -> bool {
    let vertices = |p: usize| -> [u32; 4] {
        let mut v = [0; 4];
        for (k, &slot) in m.poly(p).iter().enumerate() {
            v[k] = m.slot_vertex[slot as usize];
        }
        v
    };
    let k = m.vertices_per_polygon();
    let (vp, vq) = (vertices(p), vertices(q));
    let (mut tp, mut tq) = ([[[0.0; 3]; 3]; 2], [[[0.0; 3]; 3]; 2]);
    let np = m.triangles(p, &mut tp);
    let nq = m.triangles(q, &mut tq);
    if shares_vertex(&vp[..k], &vq[..k]) {
        return adjacent_polygons_meet(&vp[..k], &tp, np, &vq[..k], &tq, nq);
    }
    let (a, b) = (Prepared::of(tp, np), Prepared::of(tq, nq));
    if h == 0.0 {
        a.meets(&b, None)
    } else {
        a.meets(&b, Some(&a.cells(h))) || b.meets(&a, Some(&b.cells(h)))
    }
}
