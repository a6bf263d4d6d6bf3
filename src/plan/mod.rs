//! The planning layer: which engine answers which part of a query, and on which threads.
//!
//! A scene keeps its meshes and hands every query here. The decisions a query needs are
//! made in this module and nowhere else:
//! - **engine**: the CPU backend's queries run on the scene's own CPU engines (one per
//!   worker thread); a GL backend answers the pairs of meshes it holds in their own frames
//!   and leaves the pairs with a placed mesh (a transform) or an f64 mesh to the CPU engine
//!   ([`Mesh::needs_cpu`]);
//! - **meshes read from host GL buffers**: a GL backend has no CPU positions for them, so
//!   the broad phase pairs them with every mesh and any part of a query that would need the
//!   CPU for them is refused (Unsupported, naming the meshes);
//! - **work sharing**: big reference queries and mesh pairs are shared out by leaf pairs,
//!   self-collision by runs of leaf pairs, over worker threads started once per scene
//!   (`workers.rs`); the answer is the same for every thread count.
//!
//! Files: `mod.rs` the planner and the reference query; `all.rs` the whole-scene query;
//! `continuous.rs` the continuous query; `geometry.rs` the contact geometry of an answer; `workers.rs` the worker threads.

mod all;
mod continuous;
mod geometry;
mod sort;
mod workers;

use std::collections::BTreeMap;

pub(crate) use geometry::Answer;

use crate::backend::{Backend, Contact, QueryMeshes, Selector};
use crate::error::{Error, ErrorKind, Result};
use crate::mesh::Mesh;
use crate::mesh::MeshId;
use crate::query::all::{AllStats, BroadPhase, SelfPrep};
use crate::query::continuous::{Broad, ContinuousStats, LeafPair, SweptMesh};
use crate::query::{self, QueryStats, Workspace};
use workers::Workers;

/// Routes a scene's queries to its backend and to its CPU engines, on its worker threads.
pub(crate) struct Planner {
    selector: Box<dyn Selector>,
    /// The step-by-step query's scratch, and the last query's counts and times.
    workspace: Workspace,
    workers: Workers,
    broad: BroadPhase,
    /// The self-colliding meshes made ready for the query, kept from query to query.
    self_preps: Vec<SelfPrep>,
    /// The whole-scene answer's pairs as sort keys, and the sort's scratch.
    merge_keys: sort::PairKeys,
    /// Stages of the last whole-scene query.
    all_stats: AllStats,
    /// The continuous query's meshes over the step, leaf pairs and broad-phase scratch,
    /// kept from query to query.
    swept: Vec<SweptMesh>,
    leaf_pairs: Vec<LeafPair>,
    continuous_broad: Broad,
    continuous_stats: ContinuousStats,
}

impl Planner {
    /// A planner over `selector` with `threads` workers (0: one per core).
    pub fn new(selector: Box<dyn Selector>, threads: u32) -> Planner {
        Planner {
            selector,
            workspace: Workspace::default(),
            workers: Workers::new(threads),
            broad: BroadPhase::default(),
            self_preps: Vec::new(),
            merge_keys: sort::PairKeys::default(),
            all_stats: AllStats::default(),
            swept: Vec::new(),
            leaf_pairs: Vec::new(),
            continuous_broad: Broad::default(),
            continuous_stats: ContinuousStats::default(),
        }
    }

    /// The backend answering the queries.
    pub fn backend(&self) -> Backend {
        self.selector.backend()
    }

    /// Mesh `id` reads its positions from a host GL buffer.
    pub fn gl_bound(&self, id: MeshId) -> bool {
        self.selector.gl_bound(id)
    }

    /// Mesh `id` got new positions from the CPU.
    pub fn mesh_updated(&mut self, id: MeshId) {
        self.selector.mesh_updated(id);
    }

    /// Mesh `id` was destroyed.
    pub fn mesh_destroyed(&mut self, id: MeshId) {
        self.selector.mesh_destroyed(id);
        self.workers.mesh_destroyed(id);
    }

    /// From now on mesh `id` reads its positions from the host's GL buffer `buffer`.
    pub fn bind_gl_buffer(
        &mut self,
        id: MeshId,
        mesh: &Mesh,
        buffer: u32,
        offset: usize,
        stride: usize,
    ) -> Result<()> {
        self.selector
            .bind_gl_buffer(id, mesh, buffer, offset, stride)
    }

    /// Deletes the backend's GL objects (the scene's context must be current).
    pub fn release_gl(&mut self) {
        self.selector.release();
    }

    /// What each step asked and found in the last query.
    pub fn stats(&self) -> QueryStats {
        self.workspace.stats
    }

    /// Where the time of the last whole-scene query went.
    pub fn all_stats(&self) -> AllStats {
        self.all_stats
    }

    /// Collides `reference` with every other enabled mesh whose filters pass: the contacts,
    /// sorted, into `out` (cleared first; left empty on failure). Half-depth `h`.
    pub fn query(
        &mut self,
        meshes: &mut BTreeMap<MeshId, Mesh>,
        reference: MeshId,
        h: f64,
        out: &mut Vec<Contact>,
    ) -> Result<()> {
        out.clear();
        self.selector.take_readbacks();
        self.workspace.stats = QueryStats::default();
        let mut res = self.selector.prepare(meshes);
        if res.is_ok() {
            res = self.query_prepared(meshes, reference, h, out);
        }
        if res.is_err() {
            self.workspace.stats = QueryStats::default();
            out.clear();
        }
        self.workspace.stats.readbacks = self.selector.take_readbacks();
        res
    }

    /// [`Planner::query`] once the backend is prepared.
    fn query_prepared(
        &mut self,
        meshes: &BTreeMap<MeshId, Mesh>,
        reference: MeshId,
        h: f64,
        out: &mut Vec<Contact>,
    ) -> Result<()> {
        let r = meshes.get(&reference).ok_or_else(|| unknown(reference))?;
        let mut list: Vec<(MeshId, &Mesh)> = vec![(reference, r)];
        if r.enabled {
            list.extend(
                meshes
                    .iter()
                    .filter(|(&id, m)| {
                        id != reference
                            && m.enabled
                            && r.group & m.mask != 0
                            && m.group & r.mask != 0
                    })
                    .map(|(&id, m)| (id, m)),
            );
        }
        let on_cpu = self.cpu_share(&mut list)?;
        if list.len() > 1 {
            let q = QueryMeshes {
                meshes: list,
                half_depth: h,
                symmetric: false,
            };
            query::run(self.selector.as_mut(), &q, &mut self.workspace, out)?;
        }
        if on_cpu.len() > 1 {
            let q = QueryMeshes {
                meshes: on_cpu,
                half_depth: h,
                symmetric: false,
            };
            let mut found = Vec::new();
            let mut stats = QueryStats::default();
            self.workers.cpu_query(&q, &mut found, &mut stats)?;
            out.extend_from_slice(&found);
            out.sort_unstable();
            let total = &mut self.workspace.stats;
            for k in 0..5 {
                total.tests[k] += stats.tests[k];
                total.hits[k] += stats.hits[k];
                total.nanos[k] += stats.nanos[k];
            }
        }
        Ok(())
    }

    /// Takes out of a reference query's meshes `list` (the reference first) those the CPU
    /// engine answers, returned as their own query (the reference first): all of them on
    /// the CPU backend (the scene's workers share its leaf pairs out); on a GL backend,
    /// which holds float meshes in their own frames, the placed and f64 meshes (all of them
    /// when the reference is one). Unsupported when such a query would need the CPU
    /// positions of a mesh read from a GL buffer.
    fn cpu_share<'m>(&self, list: &mut Vec<(MeshId, &'m Mesh)>) -> Result<Vec<(MeshId, &'m Mesh)>> {
        if self.selector.is_cpu_engine() {
            return Ok(std::mem::take(list));
        }
        let mut on_cpu = Vec::new();
        if self.selector.backend() != Backend::Cpu && list.iter().any(|(_, m)| m.needs_cpu()) {
            if list[0].1.needs_cpu() {
                on_cpu = std::mem::take(list);
            } else {
                on_cpu.push(list[0]);
                on_cpu.extend(list.iter().skip(1).filter(|(_, m)| m.needs_cpu()));
                list.retain(|(_, m)| !m.needs_cpu());
            }
            for &(id, _) in &on_cpu {
                if self.selector.gl_bound(id) {
                    return Err(gl_bound_and_placed(id, &on_cpu));
                }
            }
        }
        Ok(on_cpu)
    }
}

/// A query that needs the CPU for a placed (or f64) mesh, with mesh `id` (of `meshes`)
/// reading its positions from a GL buffer.
fn gl_bound_and_placed(id: MeshId, meshes: &[(MeshId, &Mesh)]) -> Error {
    let placed: Vec<String> = meshes
        .iter()
        .filter(|(_, m)| m.needs_cpu())
        .map(|(i, _)| i.to_string())
        .collect();
    Error::new(
        ErrorKind::Unsupported,
        format!(
            "mesh {id} reads its positions from a GL buffer and would be collided with \
             transformed or f64 mesh(es) {}, which the GL backends leave to the CPU: give \
             those meshes the identity, or disable one side",
            placed.join(", ")
        ),
    )
}

/// The error for a mesh id not in the scene.
pub(crate) fn unknown(id: MeshId) -> Error {
    Error::new(
        ErrorKind::UnknownMesh,
        format!("mesh id {id} is not in this scene (destroyed, or never created)"),
    )
}
