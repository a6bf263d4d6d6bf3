//! A scene: meshes by id and the last query's answer. Each query is handed to the planning
//! layer ([`crate::plan`]), which decides which engine answers what, on which threads.

use std::collections::BTreeMap;
use std::sync::atomic::{AtomicU32, Ordering};

use crate::backend::{self, Backend, BackendRequest, Contact, CpuSelector, Pair, Selector};
use crate::error::{Error, ErrorKind, Result};
use crate::geom::ccd::First;
use crate::geom::contact::ContactGeometry;
use crate::gpu::Lookup;
use crate::mesh::{Mesh, Positions};
use crate::plan::{unknown, Answer, Planner};
use crate::query::all::AllStats;
use crate::query::continuous::{ContinuousStats, Impact};
use crate::query::impact::{impact_geometry, ImpactGeometry};
use crate::query::QueryStats;

pub use crate::mesh::MeshId;

/// How a scene answers queries.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SceneConfig {
    /// Viewing-volume depth in model units; 0 asks for exact intersection (CPU backend).
    pub epsilon: f32,
    /// Leaf size; 0 applies the paper's rule of thumb.
    pub max_polygons_per_box: u32,
    /// Worker threads for queries: 0 = one per core the process may use, 1 = the calling
    /// thread only. The answer is the same for every count.
    pub threads: u32,
}

impl Default for SceneConfig {
    fn default() -> Self {
        SceneConfig {
            epsilon: 0.0,
            max_polygons_per_box: 0,
            threads: 0,
        }
    }
}

impl SceneConfig {
    /// Checks the values; the message names the field at fault.
    pub fn validate(&self) -> Result<()> {
        if !self.epsilon.is_finite() || self.epsilon < 0.0 {
            return Err(Error::invalid(format!(
                "epsilon is {}; it must be finite and >= 0",
                self.epsilon
            )));
        }
        Ok(())
    }
}

/// Meshes, a backend and the last query's answer.
///
/// ```
/// use glcollide::{Positions, Scene, SceneConfig};
///
/// // A quad (two triangles) and a triangle falling through it, frame by frame.
/// let mut scene = Scene::new(SceneConfig { threads: 1, ..SceneConfig::default() })?;
/// let floor = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0]];
/// let f = scene.create_mesh(Positions::from_points(&floor), &[0, 1, 2, 3], 4)?;
/// let t = scene.create_mesh(
///     Positions::from_points(&[[0.5, 0.5, 2.0], [0.6, 0.5, 3.0], [0.5, 0.6, 3.0]]),
///     &[0, 1, 2],
///     3,
/// )?;
/// scene.set_self_collision(f, true)?;
/// let mut hits = Vec::new();
/// for frame in 0..5 {
///     let z = 2.0 - frame as f32; // 2, 1, 0, -1, -2
///     let moved = [[0.5, 0.5, z], [0.6, 0.5, z + 1.0], [0.5, 0.6, z + 1.0]];
///     scene.update_positions(t, 0, Positions::from_points(&moved))?;
///     hits.push(scene.query_all()?.len());
/// }
/// // The triangle reaches the floor at frame 2 (a corner on it) and spans it at frame 3.
/// assert_eq!(hits, [0, 0, 1, 1, 0]);
/// // Where and how deep, for the last successful query's pairs.
/// scene.update_positions(t, 0, Positions::from_points(&[[0.5, 0.5, -0.5], [0.6, 0.5, 0.5], [0.5, 0.6, 0.5]]))?;
/// let pair = scene.query_all()?[0];
/// assert_eq!((pair.mesh_a, pair.mesh_b), (f, t));
/// let g = scene.contact_geometry()?[0];
/// assert!(g.intersecting && g.depth > 0.0);
/// # Ok::<(), glcollide::Error>(())
/// ```
pub struct Scene {
    config: SceneConfig,
    meshes: BTreeMap<MeshId, Mesh>,
    /// Routes each query to the backend and the CPU engines (and owns the workers).
    plan: Planner,
    contacts: Vec<Contact>,
    /// The next answer, built here and swapped into `contacts` on success.
    scratch: Vec<Contact>,
    /// The last successful whole-scene query's pairs, and the next answer.
    pairs: Vec<Pair>,
    pairs_scratch: Vec<Pair>,
    /// Which answer [`Scene::contact_geometry`] describes (`None` before any query, after a
    /// failed one, or after any change to the meshes), and its geometry once computed.
    last: LastQuery,
    geometry: Vec<ContactGeometry>,
    /// The last successful continuous query's pairs, the primitive pair that met first of
    /// each, and the next answer.
    impacts: Vec<Impact>,
    firsts: Vec<First>,
    impacts_scratch: Vec<Impact>,
    firsts_scratch: Vec<First>,
    /// The impacts still describe the meshes and their targets (the impact geometry is
    /// computed only then), and their geometry once computed.
    impacts_current: bool,
    impact_geometry: Vec<ImpactGeometry>,
}

/// The last successful query whose answer still describes the meshes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum LastQuery {
    None,
    One(MeshId),
    All,
}

impl Scene {
    /// A scene on the CPU backend (needs no GL).
    pub fn new(config: SceneConfig) -> Result<Scene> {
        Scene::on(config, Box::new(CpuSelector::new()))
    }

    /// A scene on the backend `request` asks for, inside the host's GL context: GL entry
    /// points are loaded through `loader` for the context current on the calling thread.
    /// AUTO picks GL_COMPUTE on a hardware GL 4.3+ context, and the CPU when there is no
    /// loader, no usable context, or a software renderer (llvmpipe, softpipe, SwiftShader:
    /// the CPU is faster there); [`Scene::backend`] tells which. CPU needs no loader.
    /// GlUnavailable (with the reason) when an explicit GL backend cannot run here.
    ///
    /// GL-backed calls ([`Scene::query`], [`Scene::query_all`], [`Scene::bind_gl_buffer`],
    /// [`Scene::contact_geometry`] of a mesh read from a GL buffer, [`Scene::release_gl`])
    /// must run with this context, or one sharing its objects, current; each checks it,
    /// and leaves every piece of the host's GL state as it found it.
    ///
    /// # Safety
    /// `loader`, when given, returns entry points of the context current on the calling
    /// thread (as `eglGetProcAddress` or `glXGetProcAddress` do).
    pub unsafe fn with_backend(
        config: SceneConfig,
        request: BackendRequest,
        loader: Option<Lookup<'_>>,
    ) -> Result<Scene> {
        config.validate()?;
        // SAFETY: the caller's contract: the loader serves the current context.
        let selector = unsafe { backend::create(request, loader) }?;
        Scene::on(config, selector)
    }

    /// A scene answering through `selector` (the crate's tests: a brute-force step
    /// adapter, a backend made beforehand).
    #[cfg(any(test, feature = "internals"))]
    #[doc(hidden)]
    pub fn with_selector(config: SceneConfig, selector: Box<dyn Selector>) -> Result<Scene> {
        Scene::on(config, selector)
    }

    fn on(config: SceneConfig, selector: Box<dyn Selector>) -> Result<Scene> {
        config.validate()?;
        Ok(Scene {
            config,
            meshes: BTreeMap::new(),
            plan: Planner::new(selector, config.threads),
            contacts: Vec::new(),
            scratch: Vec::new(),
            pairs: Vec::new(),
            pairs_scratch: Vec::new(),
            last: LastQuery::None,
            geometry: Vec::new(),
            impacts: Vec::new(),
            firsts: Vec::new(),
            impacts_scratch: Vec::new(),
            firsts_scratch: Vec::new(),
            impacts_current: false,
            impact_geometry: Vec::new(),
        })
    }

    /// The configuration the scene was made with.
    pub fn config(&self) -> &SceneConfig {
        &self.config
    }

    /// The backend answering the scene's queries.
    pub fn backend(&self) -> Backend {
        self.plan.backend()
    }

    /// Adds a mesh (`vertices_per_polygon` indices per polygon in `indices`). Float
    /// positions ([`Positions::new`], [`Positions::from_points`]) make a float mesh; double
    /// positions ([`Positions::new_f64`], [`Positions::from_points_f64`]) an f64 mesh, which
    /// keeps them as doubles: every query answers exactly for those doubles (under its
    /// transform, if any), and its updates and targets take doubles only. A coordinate
    /// that is not finite, or whose magnitude exceeds the float range (3.4e38): NonFinite.
    pub fn create_mesh(
        &mut self,
        positions: Positions<'_>,
        indices: &[u32],
        vertices_per_polygon: usize,
    ) -> Result<MeshId> {
        let mesh = Mesh::new(
            positions,
            indices,
            vertices_per_polygon,
            self.config.max_polygons_per_box as usize,
        )?;
        let id = fresh_mesh_id().ok_or_else(|| {
            Error::new(
                ErrorKind::Unsupported,
                "this process has used up its 2^32 - 2 mesh ids",
            )
        })?;
        self.meshes.insert(id, mesh);
        self.forget_query();
        Ok(id)
    }

    /// The mesh `id`, or UnknownMesh.
    pub fn mesh(&self, id: MeshId) -> Result<&Mesh> {
        self.meshes.get(&id).ok_or_else(|| unknown(id))
    }

    fn mesh_mut(&mut self, id: MeshId) -> Result<&mut Mesh> {
        self.meshes.get_mut(&id).ok_or_else(|| unknown(id))
    }

    /// Ids of the live meshes, ascending.
    pub fn mesh_ids(&self) -> impl Iterator<Item = MeshId> + '_ {
        self.meshes.keys().copied()
    }

    /// Moves vertices `first..first + positions.len()` and refits the mesh's boxes, in the
    /// mesh's precision: float positions for a float mesh, doubles for an f64 mesh (the
    /// other: InvalidArgument). A coordinate that is not finite, or a double beyond the
    /// float range: NonFinite. A mesh bound to a GL buffer takes only a full update (all its
    /// vertices), which unbinds it: a partial one is refused (InvalidArgument), as the
    /// other vertices' CPU positions are stale. Drops the mesh's target. Rejected whole:
    /// nothing changes on failure.
    pub fn update_positions(
        &mut self,
        id: MeshId,
        first: usize,
        positions: Positions<'_>,
    ) -> Result<()> {
        let n = self.mesh(id)?.vertex_count();
        if self.plan.gl_bound(id) && (first != 0 || positions.len() != n) {
            return Err(Error::invalid(format!(
                "mesh {id} reads its positions from a GL buffer (bound to it); \
                 its CPU positions are stale, so a partial update (vertices {first}..{} of {n}) \
                 is refused: give all {n} vertices (which unbinds the buffer), or write the \
                 range into the buffer",
                first.saturating_add(positions.len())
            )));
        }
        self.mesh_mut(id)?.update_positions(first, positions)?;
        self.plan.mesh_updated(id);
        self.forget_query();
        Ok(())
    }

    /// [`Scene::update_positions`] of an f64 mesh from packed double points.
    pub fn update_positions_f64(
        &mut self,
        id: MeshId,
        first: usize,
        positions: &[[f64; 3]],
    ) -> Result<()> {
        self.update_positions(id, first, Positions::from_points_f64(positions))
    }

    /// Sets the end of a continuous step for vertices `first..first + positions.len()` of
    /// mesh `id`: their target positions, in the mesh's own frame and precision (float
    /// positions for a float mesh, doubles for an f64 mesh; the other: InvalidArgument),
    /// replacing any they had. The other vertices keep their target positions, or their
    /// start positions. A target is not committed: it changes no discrete query's answer
    /// and does not invalidate [`Scene::contact_geometry`]; it lasts until
    /// [`Scene::update_positions`], [`Scene::set_transform`] or [`Scene::clear_target`] on
    /// that mesh. Rejected whole, nothing changed: UnknownMesh; InvalidArgument (a range
    /// past the end, the wrong precision); NonFinite (a coordinate not finite or beyond the
    /// float range, or end world positions that could leave it). See [`Mesh::has_target`],
    /// [`Mesh::end_world_position`].
    pub fn set_target_positions(
        &mut self,
        id: MeshId,
        first: usize,
        positions: Positions<'_>,
    ) -> Result<()> {
        self.refuse_target_of_bound(id)?;
        self.mesh_mut(id)?.set_target_positions(first, positions)?;
        self.impacts_current = false;
        Ok(())
    }

    /// Unsupported for a mesh that reads its positions from a GL buffer: the start of its
    /// step lives in the host's buffer (on the GPU, or read back at each query), so the
    /// vertices a target leaves where they are have no start the CPU holds.
    fn refuse_target_of_bound(&self, id: MeshId) -> Result<()> {
        self.mesh(id)?;
        if self.plan.gl_bound(id) {
            return Err(Error::new(
                ErrorKind::Unsupported,
                format!(
                    "mesh {id} reads its positions from a GL buffer: it cannot be given a \
                     target (give it its positions with an update of all its vertices first, \
                     which unbinds it)"
                ),
            ));
        }
        Ok(())
    }

    /// [`Scene::set_target_positions`] of an f64 mesh from packed double points.
    pub fn set_target_positions_f64(
        &mut self,
        id: MeshId,
        first: usize,
        positions: &[[f64; 3]],
    ) -> Result<()> {
        self.set_target_positions(id, first, Positions::from_points_f64(positions))
    }

    /// The transform mesh `id` takes at the end of a continuous step (row-major 3x4,
    /// evaluated as [`Scene::set_transform`] says); its target positions, if any, stay. An
    /// instrument that only moves needs nothing else. Not committed, as
    /// [`Scene::set_target_positions`]. Rejected, nothing changed: UnknownMesh; NonFinite
    /// (an entry not finite, or end world positions that could leave the float range).
    pub fn set_target_transform(&mut self, id: MeshId, m: &[f64; 12]) -> Result<()> {
        self.refuse_target_of_bound(id)?;
        self.mesh_mut(id)?.set_target_transform(m)?;
        self.impacts_current = false;
        Ok(())
    }

    /// Drops mesh `id`'s target (its target positions and transform): it stands still in
    /// a continuous step. UnknownMesh for an id not in the scene.
    pub fn clear_target(&mut self, id: MeshId) -> Result<()> {
        self.mesh_mut(id)?.clear_target();
        self.impacts_current = false;
        Ok(())
    }

    /// Enables or disables mesh `id` (a disabled mesh costs nothing in a query).
    pub fn set_enabled(&mut self, id: MeshId, enabled: bool) -> Result<()> {
        self.mesh_mut(id)?.enabled = enabled;
        self.forget_query();
        Ok(())
    }

    /// Removes mesh `id` (its id is never reused).
    pub fn destroy_mesh(&mut self, id: MeshId) -> Result<()> {
        self.meshes
            .remove(&id)
            .map(drop)
            .ok_or_else(|| unknown(id))?;
        self.plan.mesh_destroyed(id);
        self.forget_query();
        Ok(())
    }

    /// Whole-scene queries collide mesh `id` with itself (off by default).
    pub fn set_self_collision(&mut self, id: MeshId, on: bool) -> Result<()> {
        self.mesh_mut(id)?.self_collision = on;
        self.forget_query();
        Ok(())
    }

    /// Two different meshes a and b are collided only if `(a.group & b.mask) != 0 &&
    /// (b.group & a.mask) != 0` (default group 1, mask all bits).
    pub fn set_filter(&mut self, id: MeshId, group: u32, mask: u32) -> Result<()> {
        let m = self.mesh_mut(id)?;
        m.group = group;
        m.mask = mask;
        self.forget_query();
        Ok(())
    }

    /// Places mesh `id` rigidly (or affinely): the world position of a vertex is `m * (x, y,
    /// z, 1)` with `m` row-major 3x4, in `f64` (see [`crate::geom::affine`]); None is the
    /// identity. Every query answers for the world positions. Costs a few operations per
    /// leaf box; no vertex is touched. NonFinite (nothing changes) for a non-finite entry or
    /// world positions that could leave the `f32` range; Unsupported for a mesh reading its
    /// positions from a GL buffer. Drops the mesh's target (see
    /// [`Scene::set_target_positions`]) when it succeeds.
    pub fn set_transform(&mut self, id: MeshId, m: Option<&[f64; 12]>) -> Result<()> {
        let bound = self.plan.gl_bound(id);
        let mesh = self.mesh_mut(id)?;
        if bound && m.is_some_and(|m| *m != crate::geom::affine::IDENTITY) {
            return Err(Error::new(
                ErrorKind::Unsupported,
                format!(
                    "mesh {id} reads its positions from a GL buffer: it cannot be given a \
                     transform (transform the buffer's positions instead)"
                ),
            ));
        }
        mesh.set_transform(m)?;
        self.forget_query();
        Ok(())
    }

    /// GL_COMPUTE: mesh `id` reads its positions (xyz `f32`, `stride` bytes apart from
    /// `offset`, 0 = 12) from the host's buffer object `buffer` at each query.
    pub fn bind_gl_buffer(
        &mut self,
        id: MeshId,
        buffer: u32,
        offset: usize,
        stride: usize,
    ) -> Result<()> {
        let m = self.meshes.get(&id).ok_or_else(|| unknown(id))?;
        if m.is_f64() {
            return Err(Error::new(
                ErrorKind::Unsupported,
                format!(
                    "mesh {id} is an f64 mesh (made from double positions): it cannot read \
                     float positions from a GL buffer"
                ),
            ));
        }
        if m.has_target() {
            return Err(Error::new(
                ErrorKind::Unsupported,
                format!(
                    "mesh {id} has a target (the end of a continuous step): it cannot read its \
                     positions from a GL buffer (clear its target first)"
                ),
            ));
        }
        if m.place.is_some() {
            return Err(Error::new(
                ErrorKind::Unsupported,
                format!(
                    "mesh {id} has a transform: it cannot read its positions from a GL buffer \
                     (set its transform to the identity first)"
                ),
            ));
        }
        self.plan.bind_gl_buffer(id, m, buffer, offset, stride)?;
        self.forget_query();
        Ok(())
    }

    /// Deletes the backend's GL objects (GL backends; the scene's context must be current).
    pub fn release_gl(&mut self) {
        self.plan.release_gl();
    }

    /// Collides `reference` with every other enabled mesh. Contacts are sorted by (other
    /// mesh, reference polygon, other polygon), each pair once. A disabled reference has
    /// no contacts. On failure [`Scene::contacts`] keeps the last successful answer.
    pub fn query(&mut self, reference: MeshId) -> Result<&[Contact]> {
        self.forget_query();
        if !self.meshes.contains_key(&reference) {
            return Err(unknown(reference));
        }
        let h = self.half_depth();
        // The answer goes to `scratch`, swapped in only on success.
        self.plan
            .query(&mut self.meshes, reference, h, &mut self.scratch)?;
        std::mem::swap(&mut self.scratch, &mut self.contacts);
        self.last = LastQuery::One(reference);
        Ok(&self.contacts)
    }

    /// Every pair of polygons that meet, from two different enabled meshes (whose filters
    /// pass) or from one enabled mesh whose self-collision is on: sorted by (mesh_a,
    /// polygon_a, mesh_b, polygon_b), each pair once, `(mesh_a, polygon_a) < (mesh_b,
    /// polygon_b)`. Two polygons of one mesh that share a vertex index are reported only
    /// when they meet somewhere other than their shared vertices and edges. With epsilon >
    /// 0 a pair is reported when either polygon meets the other's viewing volume. The same
    /// answer for every backend and thread count. On failure [`Scene::pairs`] keeps the
    /// last successful answer.
    pub fn query_all(&mut self) -> Result<&[Pair]> {
        self.forget_query();
        let h = self.half_depth();
        self.plan
            .query_all(&mut self.meshes, h, &mut self.pairs_scratch)?;
        std::mem::swap(&mut self.pairs, &mut self.pairs_scratch);
        self.last = LastQuery::All;
        Ok(&self.pairs)
    }

    /// Continuous detection over the step from every mesh's current state (t = 0) to its
    /// target (t = 1; a mesh with none stands still), each vertex moving on the straight
    /// line between its start and end world positions: every pair [`Scene::query_all`]
    /// would report at *some* time in `[0, 1]` (the same meshes, filters, self-collision,
    /// the adjacency rule at each time), each once, sorted as `query_all`'s pairs, with
    /// its earliest time `toi` as a certified lower bound (never late, at most `2^-20`
    /// early; 0 with [`Impact::at_start`] exactly when the pair
    /// meets at the start). Exact at epsilon 0 for the double world positions. At epsilon
    /// `e > 0` the band is a distance: a pair is also reported when at some time a vertex of
    /// one polygon (that the other does not have) comes within `e / 2` of the other, or an
    /// edge of one within `e / 2` of an edge of the other with which it shares no vertex;
    /// every such pair is reported, and a reported pair comes within `(e / 2)(1 + 2^-20)`.
    /// With no target anywhere that is a thickness query (pairs within `e / 2`). The same
    /// answer for every backend (it runs on the CPU), thread count and mesh creation
    /// order. Unsupported on a GL backend when an enabled mesh reads its positions from
    /// a host GL buffer. On failure [`Scene::impacts`] keeps the last successful answer.
    pub fn query_continuous(&mut self) -> Result<&[Impact]> {
        self.impacts_current = false;
        self.impact_geometry.clear();
        let d = self.half_depth();
        self.plan.query_continuous(
            &mut self.meshes,
            d,
            &mut self.impacts_scratch,
            &mut self.firsts_scratch,
        )?;
        std::mem::swap(&mut self.impacts, &mut self.impacts_scratch);
        std::mem::swap(&mut self.firsts, &mut self.firsts_scratch);
        self.impacts_current = true;
        Ok(&self.impacts)
    }

    /// The pairs of the last successful [`Scene::query_continuous`].
    pub fn impacts(&self) -> &[Impact] {
        &self.impacts
    }

    /// Where each pair of the last successful [`Scene::query_continuous`] meets first, entry
    /// `i` for impact `i` (see [`ImpactGeometry`]): the primitive pair (a vertex and a
    /// triangle, or two edges), the contact points' weights and the normal at `toi`, in
    /// double. Computed here, on demand (a step that does not ask pays nothing). A pair
    /// that meets at the start gets [`ImpactFeature::None`](crate::ImpactFeature::None).
    /// InvalidArgument before any continuous query, after a failed one, or after a change
    /// to the meshes or their targets since.
    pub fn impact_geometry(&mut self) -> Result<&[ImpactGeometry]> {
        if !self.impacts_current {
            return Err(Error::invalid(
                "no impact geometry: there was no successful continuous query since the \
                 scene was made, its meshes or targets last changed, or a query last failed",
            ));
        }
        if self.impact_geometry.len() != self.impacts.len() || self.impacts.is_empty() {
            let mut out = std::mem::take(&mut self.impact_geometry);
            let res = impact_geometry(&self.meshes, &self.impacts, &self.firsts, &mut out);
            if res.is_err() {
                out.clear();
            }
            self.impact_geometry = out;
            res?;
        }
        Ok(&self.impact_geometry)
    }

    /// Counts and times of the last [`Scene::query_continuous`].
    pub fn continuous_stats(&self) -> ContinuousStats {
        self.plan.continuous_stats()
    }

    /// Half the viewing-volume depth.
    fn half_depth(&self) -> f64 {
        f64::from(self.config.epsilon) / 2.0
    }

    /// The pairs of the last successful [`Scene::query_all`].
    pub fn pairs(&self) -> &[Pair] {
        &self.pairs
    }

    /// The contacts of the last successful query.
    pub fn contacts(&self) -> &[Contact] {
        &self.contacts
    }

    /// From now on [`Scene::contact_geometry`] refuses until the next successful query (a
    /// caller whose own handling of a query's answer failed calls it; every change to the
    /// meshes does).
    pub fn forget_query(&mut self) {
        self.last = LastQuery::None;
        self.geometry.clear();
        self.impacts_current = false;
    }

    /// The contact geometry of the last successful query's answer, entry `i` for contact
    /// (or pair) `i`: polygon `a` is the reference polygon (or `polygon_a`), `b` the other.
    /// Computed here, on demand (see [`ContactGeometry`] for every rule).
    /// InvalidArgument before any query, after a failed one, or after any change to the
    /// meshes since (create, update, enable, destroy, transform, filter, self-collision, GL
    /// buffer binding). A mesh of the answer that reads its positions from a host GL buffer
    /// is read at the positions the query used (GL_COMPUTE reads back what the query
    /// gathered: the scene's context must be current, else GlUnavailable, the answer kept).
    pub fn contact_geometry(&mut self) -> Result<&[ContactGeometry]> {
        let answer = match self.last {
            LastQuery::None => {
                return Err(Error::invalid(
                    "no contact geometry: there was no successful query (of one reference \
                     mesh or of the whole scene) since the scene was made, its meshes last \
                     changed, or a query last failed",
                ))
            }
            LastQuery::One(r) => Answer::One(r, &self.contacts),
            LastQuery::All => Answer::All(&self.pairs),
        };
        let n = answer.len();
        if self.geometry.len() == n && n > 0 {
            return Ok(&self.geometry);
        }
        let exact = self.config.epsilon == 0.0;
        let mut out = std::mem::take(&mut self.geometry);
        let res = self
            .plan
            .contact_geometry(&mut self.meshes, answer, exact, &mut out);
        if res.is_err() {
            out.clear();
        }
        self.geometry = out;
        res?;
        Ok(&self.geometry)
    }

    /// Where the time of the last whole-scene query went ([`Scene::query_all`]; reset by
    /// each one, zero after a failed one).
    pub fn all_stats(&self) -> AllStats {
        self.plan.all_stats()
    }

    /// What each step asked and found in the last query.
    pub fn stats(&self) -> QueryStats {
        self.plan.stats()
    }
}

/// Mesh ids come from one process-wide counter: an id is never reused, and an id from
/// another scene is never the id of a live mesh in this one (it answers UNKNOWN_MESH).
static NEXT_MESH_ID: AtomicU32 = AtomicU32::new(1);

fn fresh_mesh_id() -> Option<MeshId> {
    NEXT_MESH_ID
        .fetch_update(Ordering::Relaxed, Ordering::Relaxed, |v| {
            (v < MeshId::MAX).then_some(v + 1)
        })
        .ok()
}
