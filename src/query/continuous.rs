//! Continuous detection over a scene's step: every pair of polygons that meet at some time
//! in `[0, 1]` while each vertex moves on a straight line from its start (the mesh's
//! current world position) to its end (its target), and when first.
//!
//! The paper's structure carries over to the step: each polygon's box holds its corners at
//! the start and at the end (a polygon whose vertices move on straight lines stays inside
//! the box of its start and end corners for the whole step), the leaf boxes are the union
//! of their polygons' boxes, refitted at every query, and the same two levels are swept:
//! the meshes' roots ([`mesh_pairs`]), then leaf boxes against leaf boxes (between meshes,
//! and a self-colliding mesh's leaves against its own), then the polygons of each leaf
//! pair by their boxes, then the exact test of the polygon pair
//! ([`polygons_first_meet`]). A mesh with no target costs what a discrete query costs it:
//! its boxes are its positions' boxes.

use super::all::{mesh_pairs, BroadPhase, SceneMesh};
use crate::geom::adjacent::shares_vertex;
use crate::geom::ccd::{polygons_first_meet, First, MovingPolygon, Toi};
use crate::geom::sweep::Sweep;
use crate::geom::{f32_down, f32_up, Aabb, P3};
use crate::mesh::{Mesh, MeshId};

/// A pair of polygons that meet during the step (see [`crate::Scene::query_continuous`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Impact {
    /// The lower mesh id.
    pub mesh_a: MeshId,
    /// Polygon index in `mesh_a`.
    pub polygon_a: u32,
    /// The higher mesh id (or `mesh_a` for a self-collision pair).
    pub mesh_b: MeshId,
    /// Polygon index in `mesh_b` (above `polygon_a` when the meshes are one).
    pub polygon_b: u32,
    /// The earliest time in `[0, 1]` at which the pair meets, as a certified lower bound:
    /// never later than the exact time, at most `2^-20` earlier; 0 exactly when it meets
    /// at the start.
    pub toi: f64,
    /// The pair already meets at `t = 0` (then `toi` is 0).
    pub at_start: bool,
}

impl Impact {
    /// The sort key: (mesh_a, polygon_a, mesh_b, polygon_b) as one 128-bit number.
    #[inline]
    pub fn key(&self) -> u128 {
        (u128::from(self.mesh_a) << 96)
            | (u128::from(self.polygon_a) << 64)
            | (u128::from(self.mesh_b) << 32)
            | u128::from(self.polygon_b)
    }
}

/// Counts and times of the last continuous query.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ContinuousStats {
    /// Start and end positions and swept boxes of every enabled mesh.
    pub sweep_nanos: u64,
    /// Mesh pairs and leaf pairs.
    pub broad_nanos: u64,
    /// Polygon pairs and their exact tests (summed over the workers).
    pub narrow_nanos: u64,
    /// Sorting the answer.
    pub merge_nanos: u64,
    /// The whole query, on the calling thread.
    pub total_nanos: u64,
    /// Meshes with a target (moving) among the enabled ones.
    pub moving_meshes: usize,
    /// Leaf pairs whose swept boxes meet.
    pub leaf_pairs: usize,
    /// Polygon pairs whose swept boxes meet (tested exactly).
    pub polygon_pairs: usize,
    /// Pairs found.
    pub found: usize,
}

impl ContinuousStats {
    /// Adds a worker's counts and times.
    pub fn add_worker(&mut self, w: &ContinuousStats) {
        self.narrow_nanos += w.narrow_nanos;
        self.polygon_pairs += w.polygon_pairs;
    }
}

/// A mesh's step: its slots' world positions at the start and the end, and the boxes that
/// hold each polygon for the whole step. Kept from query to query (no allocation once
/// grown).
#[derive(Default)]
pub struct SweptMesh {
    start: Vec<P3>,
    /// Empty when the mesh stands still.
    end: Vec<P3>,
    /// Per leaf-ordered polygon: its box over the step, and (a moving mesh only) its boxes
    /// at the start and at the end.
    boxes: Vec<Aabb>,
    ends: Vec<[Aabb; 2]>,
    leaves: Vec<Aabb>,
    /// The leaves grown by the band (the broad phase's volumes).
    grown: Vec<Aabb>,
    pub root: Aabb,
}

impl SweptMesh {
    /// Makes `self` the step of `mesh` with band `d` (boxes of a still float mesh without a
    /// placement are its own; the others are the f64 corners' boxes rounded outward).
    pub fn make(&mut self, mesh: &Mesh, d: f64) {
        mesh.step_positions(&mut self.start, &mut self.end);
        let n = mesh.polygon_count();
        self.boxes.clear();
        self.ends.clear();
        if self.end.is_empty() {
            self.boxes.extend((0..n).map(|p| mesh.poly_box(p)));
        } else {
            let (start, end) = (&self.start, &self.end);
            self.ends.extend((0..n).map(|p| {
                [start, end].map(|at| {
                    let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
                    for &s in mesh.poly(p) {
                        let q = &at[s as usize];
                        for k in 0..3 {
                            lo[k] = lo[k].min(q[k]);
                            hi[k] = hi[k].max(q[k]);
                        }
                    }
                    Aabb {
                        min: lo.map(f32_down),
                        max: hi.map(f32_up),
                    }
                })
            }));
            self.boxes.extend(self.ends.iter().map(|[a, b]| {
                let mut u = *a;
                u.merge(b);
                u
            }));
        }
        let lb = mesh.leaves();
        self.leaves.clear();
        self.leaves.extend((0..lb.len()).map(|l| {
            let mut b = Aabb::EMPTY;
            for p in lb.polys(l) {
                b.merge(&self.boxes[p]);
            }
            b
        }));
        self.grown.clear();
        self.grown.extend(self.leaves.iter().map(|b| b.grown(d)));
        self.root = Aabb::EMPTY;
        for b in &self.leaves {
            self.root.merge(b);
        }
    }

    /// Does the mesh move in the step?
    pub fn moves(&self) -> bool {
        !self.end.is_empty()
    }

    /// Leaf-ordered polygon `p`'s boxes at the start and the end of the step.
    #[inline]
    fn ends(&self, p: usize) -> [Aabb; 2] {
        match self.ends.get(p) {
            Some(e) => *e,
            None => [self.boxes[p]; 2],
        }
    }

    /// Leaf-ordered polygon `p` of `mesh` over the step (vertex indices: the caller's).
    fn polygon(&self, mesh: &Mesh, p: usize) -> MovingPolygon {
        let slots = mesh.poly(p);
        let mut m = MovingPolygon {
            k: slots.len(),
            ids: [0; 4],
            p: [[[0.0; 3]; 4]; 2],
        };
        for (c, &s) in slots.iter().enumerate() {
            let s = s as usize;
            m.ids[c] = mesh.slot_vertex[s];
            m.p[0][c] = self.start[s];
            m.p[1][c] = if self.end.is_empty() {
                self.start[s]
            } else {
                self.end[s]
            };
        }
        m
    }
}

/// Are boxes `a` and `b` (each at the start and the end of the step) more than `d` apart
/// along one axis, on the same side, at both ends? Then the polygons they hold are apart
/// for the whole step (the gap along a fixed direction is concave in time:
/// [`crate::geom::ccd`]'s `apart.rs`), however far both move. The `f64` difference of two
/// floats rounds monotonically and `d` is a double: a gap of at most `d` never passes.
#[inline]
fn apart_at_both_ends(a: [Aabb; 2], b: [Aabb; 2], d: f64) -> bool {
    (0..3).any(|k| {
        let side = |w: usize| {
            if f64::from(b[w].min[k]) - f64::from(a[w].max[k]) > d {
                1
            } else if f64::from(a[w].min[k]) - f64::from(b[w].max[k]) > d {
                -1
            } else {
                0
            }
        };
        let s0 = side(0);
        s0 != 0 && side(1) == s0
    })
}

/// The time reported for `toi`: its bound, except that 0 is kept for the pairs that meet at
/// the start (API.md: toi is 0 exactly then). A primitive's bound may be 0 for a pair first
/// meeting within `2^-20` of the start without meeting at it; it becomes the least positive
/// double, still below the exact time, which is positive.
#[inline]
fn reported_toi(toi: Toi) -> f64 {
    if toi.t == 0.0 && !toi.at_start {
        f64::from_bits(1)
    } else {
        toi.t
    }
}

/// Leaf `la` of mesh `i` and leaf `lb` of mesh `j` (positions in the query's mesh list;
/// `i == j` for a self-colliding mesh, `la <= lb`), whose swept boxes meet.
#[derive(Clone, Copy, Debug)]
pub struct LeafPair {
    pub i: u32,
    pub j: u32,
    pub la: u32,
    pub lb: u32,
}

/// Scratch of [`leaf_pairs`].
#[derive(Default)]
pub struct Broad {
    meshes: BroadPhase,
    sweep: Sweep,
    found: Vec<(u32, u32)>,
    pairs: Vec<(u32, u32)>,
}

/// Every leaf pair of the step whose swept boxes come within `d` (`list[i]`'s step is
/// `swept[i]`, whose root is the list's root), mesh pairs first, in a fixed order.
pub fn leaf_pairs(
    list: &[SceneMesh<'_>],
    swept: &[SweptMesh],
    d: f64,
    broad: &mut Broad,
    out: &mut Vec<LeafPair>,
) {
    out.clear();
    mesh_pairs(list, d, &mut broad.meshes, &mut broad.pairs);
    for &(i, j) in &broad.pairs {
        broad.found.clear();
        let (a, b) = (&swept[i as usize], &swept[j as usize]);
        broad.sweep.pairs(&a.grown, &b.leaves, &mut broad.found);
        broad.found.sort_unstable();
        out.extend(
            broad
                .found
                .iter()
                .map(|&(la, lb)| LeafPair { i, j, la, lb }),
        );
    }
    for (i, sm) in list.iter().enumerate() {
        if !sm.self_collision {
            continue;
        }
        let a = &swept[i];
        broad.found.clear();
        broad.sweep.pairs(&a.grown, &a.leaves, &mut broad.found);
        broad.found.retain(|&(la, lb)| la <= lb);
        broad.found.sort_unstable();
        let i = i as u32;
        out.extend(
            broad
                .found
                .iter()
                .map(|&(la, lb)| LeafPair { i, j: i, la, lb }),
        );
    }
}

/// The pairs of leaf pairs `lps` that meet during the step, appended to `out` with the
/// primitive pair that meets first (unsorted); counts into `stats`.
pub fn narrow(
    list: &[SceneMesh<'_>],
    swept: &[SweptMesh],
    lps: &[LeafPair],
    d: f64,
    out: &mut Vec<(Impact, First)>,
    stats: &mut ContinuousStats,
) {
    let mut sweep = Sweep::default();
    let (mut va, mut cb, mut found) = (Vec::new(), Vec::new(), Vec::new());
    for lp in lps {
        let (ma, mb) = (&list[lp.i as usize], &list[lp.j as usize]);
        let (sa, sb) = (&swept[lp.i as usize], &swept[lp.j as usize]);
        let own = lp.i == lp.j;
        let (ra, rb) = (
            ma.mesh.leaves().polys(lp.la as usize),
            mb.mesh.leaves().polys(lp.lb as usize),
        );
        // The polygon box pairs of the leaf pair by a sweep, not all the products: leaves
        // hold up to hundreds of polygons.
        va.clear();
        va.extend(sa.boxes[ra.clone()].iter().map(|b| b.grown(d)));
        cb.clear();
        cb.extend_from_slice(&sb.boxes[rb.clone()]);
        found.clear();
        sweep.pairs(&va, &cb, &mut found);
        if own && lp.la == lp.lb {
            found.retain(|&(x, y)| x < y);
        }
        found.sort_unstable();
        for &(x, y) in &found {
            let (pa, pb) = (ra.start + x as usize, rb.start + y as usize);
            if apart_at_both_ends(sa.ends(pa), sb.ends(pb), d) {
                continue;
            }
            stats.polygon_pairs += 1;
            let (a, b) = (sa.polygon(ma.mesh, pa), sb.polygon(mb.mesh, pb));
            let adjacent = own && shares_vertex(&a.ids[..a.k], &b.ids[..b.k]);
            let Some((toi, first)) = polygons_first_meet(&a, &b, adjacent, d) else {
                continue;
            };
            let (ia, ib) = (ma.mesh.poly_ids[pa], mb.mesh.poly_ids[pb]);
            let (ia, ib, first) = if own && ib < ia {
                (ib, ia, first.swapped())
            } else {
                (ia, ib, first)
            };
            out.push((
                Impact {
                    mesh_a: ma.id,
                    polygon_a: ia,
                    mesh_b: mb.id,
                    polygon_b: ib,
                    toi: reported_toi(toi),
                    at_start: toi.at_start,
                },
                first,
            ));
        }
    }
}
