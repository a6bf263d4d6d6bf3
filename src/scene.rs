//! A scene: meshes by id, one backend, and the last query's contacts.

use std::collections::BTreeMap;
use std::sync::atomic::{AtomicU32, Ordering};

use std::sync::Mutex;

use crate::backend::{Backend, CpuSelector, Pair, QueryMeshes, Selector};
use crate::error::{try_reserve, Error, ErrorKind, Result};
use crate::geom::contact::{contact_geometry, ContactGeometry};
use crate::geom::P3;
use crate::mesh::{Mesh, Positions};
use crate::query::all::{self as whole, BroadPhase, SceneMesh, SelfScratch};
use crate::query::{self, Contact, QueryStats, Workspace};

/// Id of a mesh. Ids start at 1, are never 0 and never reused (unique in the process).
pub type MeshId = u32;

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
pub struct Scene {
    config: SceneConfig,
    meshes: BTreeMap<MeshId, Mesh>,
    selector: Box<dyn Selector>,
    workspace: Workspace,
    contacts: Vec<Contact>,
    /// The next answer, built here and swapped into `contacts` on success.
    scratch: Vec<Contact>,
    /// The last successful whole-scene query's pairs, and the next answer.
    pairs: Vec<Pair>,
    pairs_scratch: Vec<Pair>,
    /// Worker threads (None: the calling thread only), started once, asleep between
    /// queries; one CPU engine and one self-collision scratch per worker.
    /// Started by the first query that has work for them (a scene that never asks a
    /// whole-scene query starts no thread).
    pool: Option<rayon::ThreadPool>,
    /// Worker threads wanted (1: the calling thread only).
    threads: usize,
    workers: Vec<Mutex<Worker>>,
    broad: BroadPhase,
    /// Which answer [`Scene::contact_geometry`] describes (`None` before any query, after a
    /// failed one, or after any change to the meshes), and its geometry once computed.
    last: LastQuery,
    geometry: Vec<ContactGeometry>,
}

/// The last successful query whose answer still describes the meshes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum LastQuery {
    None,
    One(MeshId),
    All,
}

/// What one worker thread works with: its own CPU engine (box caches, scratch) and
/// self-collision scratch.
#[derive(Default)]
struct Worker {
    cpu: CpuSelector,
    workspace: Workspace,
    selfs: SelfScratch,
}

/// A unit of whole-scene work: a mesh pair (positions in the query's mesh list), or a run
/// of one mesh's self-colliding leaf pairs.
enum Task {
    Pair(u32, u32),
    Own(u32, Vec<(u32, u32)>),
}

/// Self-collision leaf pairs per task: small enough to spread a big mesh over the workers,
/// big enough that a task is worth handing out.
const LEAF_PAIRS_PER_TASK: usize = 8;

impl Scene {
    /// A scene on the CPU backend.
    pub fn new(config: SceneConfig) -> Result<Scene> {
        Scene::with_selector(config, Box::new(CpuSelector::new()))
    }

    /// A scene answering through `selector`.
    pub fn with_selector(config: SceneConfig, selector: Box<dyn Selector>) -> Result<Scene> {
        config.validate()?;
        let threads = match config.threads {
            0 => std::thread::available_parallelism().map_or(1, |n| n.get()),
            n => n as usize,
        };
        Ok(Scene {
            config,
            meshes: BTreeMap::new(),
            selector,
            workspace: Workspace::default(),
            contacts: Vec::new(),
            scratch: Vec::new(),
            pairs: Vec::new(),
            pairs_scratch: Vec::new(),
            threads,
            pool: None,
            workers: (0..threads.max(1)).map(|_| Mutex::default()).collect(),
            broad: BroadPhase::default(),
            last: LastQuery::None,
            geometry: Vec::new(),
        })
    }

    /// The configuration the scene was made with.
    pub fn config(&self) -> &SceneConfig {
        &self.config
    }

    /// The backend answering the scene's queries.
    pub fn backend(&self) -> Backend {
        self.selector.backend()
    }

    /// Adds a mesh (`vertices_per_polygon` indices per polygon in `indices`).
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

    /// Moves vertices `first..first + positions.len()` and refits the mesh's boxes.
    pub fn update_positions(
        &mut self,
        id: MeshId,
        first: usize,
        positions: Positions<'_>,
    ) -> Result<()> {
        self.mesh_mut(id)?.update_positions(first, positions)?;
        self.selector.mesh_updated(id);
        self.forget_query();
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
        self.selector.mesh_destroyed(id);
        for w in &mut self.workers {
            lock(w).cpu.mesh_destroyed(id);
        }
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
        self.selector
            .bind_gl_buffer(id, m, buffer, offset, stride)?;
        self.forget_query();
        Ok(())
    }

    /// Deletes the backend's GL objects (GL backends; the scene's context must be current).
    pub fn release_gl(&mut self) {
        self.selector.release();
    }

    /// Collides `reference` with every other enabled mesh. Contacts are sorted by (other
    /// mesh, reference polygon, other polygon), each pair once. A disabled reference has
    /// no contacts.
    pub fn query(&mut self, reference: MeshId) -> Result<&[Contact]> {
        self.forget_query();
        if !self.meshes.contains_key(&reference) {
            return Err(unknown(reference));
        }
        self.selector.take_readbacks();
        let prepared = self.selector.prepare(&mut self.meshes);
        self.workspace.stats = QueryStats::default();
        if let Err(e) = prepared {
            self.workspace.stats.readbacks = self.selector.take_readbacks();
            return Err(e);
        }
        let r = self
            .meshes
            .get(&reference)
            .ok_or_else(|| unknown(reference))?;
        let mut meshes = vec![(reference, r)];
        if r.enabled {
            meshes.extend(
                self.meshes
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
        let q = QueryMeshes {
            meshes,
            half_depth: f64::from(self.config.epsilon) / 2.0,
            symmetric: false,
        };
        // The answer goes to `scratch`, swapped in only on success: after a failed query
        // `contacts()` still holds the last successful query's.
        let res = if q.meshes.len() > 1 {
            query::run(
                self.selector.as_mut(),
                &q,
                &mut self.workspace,
                &mut self.scratch,
            )
        } else {
            self.scratch.clear();
            Ok(())
        };
        if res.is_err() {
            self.workspace.stats = QueryStats::default();
        }
        self.workspace.stats.readbacks = self.selector.take_readbacks();
        res?;
        std::mem::swap(&mut self.scratch, &mut self.contacts);
        self.last = LastQuery::One(reference);
        Ok(&self.contacts)
    }

    /// Every pair of polygons that meet, from two different enabled meshes (whose filters
    /// pass) or from one enabled mesh whose self-collision is on: sorted by (mesh_a,
    /// polygon_a, mesh_b, polygon_b), each pair once, `(mesh_a, polygon_a) < (mesh_b,
    /// polygon_b)`. The same answer for every backend and thread count. On failure
    /// [`Scene::pairs`] keeps the last successful answer.
    pub fn query_all(&mut self) -> Result<&[Pair]> {
        self.forget_query();
        self.selector.take_readbacks();
        self.workspace.stats = QueryStats::default();
        let prepared = self.selector.prepare(&mut self.meshes);
        let res = prepared.and_then(|()| self.query_all_inner());
        self.workspace.stats.readbacks = self.selector.take_readbacks();
        res?;
        std::mem::swap(&mut self.pairs, &mut self.pairs_scratch);
        self.last = LastQuery::All;
        Ok(&self.pairs)
    }

    /// Starts the worker threads if the scene wants them and they are not running yet.
    fn start_workers(&mut self) -> Result<()> {
        if self.threads > 1 && self.pool.is_none() {
            let threads = self.threads;
            self.pool = Some(
                rayon::ThreadPoolBuilder::new()
                    .num_threads(threads)
                    .thread_name(|i| format!("glcollide-{i}"))
                    .build()
                    .map_err(|e| {
                        Error::new(
                            ErrorKind::OutOfMemory,
                            format!("could not start {threads} worker threads: {e}"),
                        )
                    })?,
            );
        }
        Ok(())
    }

    fn query_all_inner(&mut self) -> Result<()> {
        self.start_workers()?;
        let h = f64::from(self.config.epsilon) / 2.0;
        let list: Vec<SceneMesh<'_>> = self
            .meshes
            .iter()
            .filter(|(_, m)| m.enabled)
            .map(|(&id, m)| SceneMesh {
                id,
                mesh: m,
                self_collision: m.self_collision,
                group: m.group,
                mask: m.mask,
            })
            .collect();
        let mut mesh_pairs = Vec::new();
        whole::mesh_pairs(&list, h, &mut self.broad, &mut mesh_pairs);
        let on_cpu = self.selector.backend() == Backend::Cpu;
        let mut tasks: Vec<Task> = Vec::new();
        if on_cpu {
            tasks.extend(mesh_pairs.iter().map(|&(i, j)| Task::Pair(i, j)));
        }
        for (i, sm) in list.iter().enumerate() {
            if sm.self_collision {
                let mut w = lock(&self.workers[0]);
                let leaf_pairs = whole::self_leaf_pairs(sm.mesh, h, &mut w.selfs);
                tasks.extend(
                    leaf_pairs
                        .chunks(LEAF_PAIRS_PER_TASK)
                        .map(|c| Task::Own(i as u32, c.to_vec())),
                );
            }
        }
        let workers = &self.workers;
        let run = |t: &Task| -> Vec<Pair> {
            let at = rayon::current_thread_index().unwrap_or(0) % workers.len();
            let mut w = lock(&workers[at]);
            let w = &mut *w;
            let mut out = Vec::new();
            match *t {
                Task::Pair(i, j) => {
                    let (a, b) = (&list[i as usize], &list[j as usize]);
                    let q = QueryMeshes {
                        meshes: vec![(a.id, a.mesh), (b.id, b.mesh)],
                        half_depth: h,
                        symmetric: true,
                    };
                    let mut found = Vec::new();
                    // The CPU engine never fails.
                    if query::run(&mut w.cpu, &q, &mut w.workspace, &mut found).is_ok() {
                        out.extend(found.iter().map(|c| pair(a.id, c)));
                    }
                }
                Task::Own(i, ref leaf_pairs) => {
                    let sm = &list[i as usize];
                    whole::self_pairs(sm.id, sm.mesh, h, leaf_pairs, &mut w.selfs, &mut out);
                }
            }
            out
        };
        let found: Vec<Vec<Pair>> = match &self.pool {
            Some(pool) => pool.install(|| {
                use rayon::prelude::*;
                tasks.par_iter().map(run).collect()
            }),
            None => tasks.iter().map(run).collect(),
        };
        let out = &mut self.pairs_scratch;
        out.clear();
        out.extend(found.into_iter().flatten());
        if !on_cpu {
            // A GL backend answers mesh pair by mesh pair, on the calling thread (its
            // context is current here); with a band, both ways round, as its viewing
            // volumes are the reference's only.
            for &(i, j) in &mesh_pairs {
                let (a, b) = (&list[i as usize], &list[j as usize]);
                let mut ask = |r: &SceneMesh<'_>, o: &SceneMesh<'_>| -> Result<()> {
                    let q = QueryMeshes {
                        meshes: vec![(r.id, r.mesh), (o.id, o.mesh)],
                        half_depth: h,
                        symmetric: false,
                    };
                    let mut found = Vec::new();
                    query::run(self.selector.as_mut(), &q, &mut self.workspace, &mut found)?;
                    out.extend(found.iter().map(|c| {
                        if r.id < o.id {
                            pair(r.id, c)
                        } else {
                            pair(o.id, &swap(r.id, c))
                        }
                    }));
                    Ok(())
                };
                ask(a, b)?;
                if h > 0.0 {
                    ask(b, a)?;
                }
            }
        }
        out.sort_unstable();
        out.dedup();
        Ok(())
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
    }

    /// The contact geometry of the last successful query's answer, entry `i` for contact
    /// (or pair) `i`: polygon `a` is the reference polygon (or `polygon_a`), `b` the other.
    /// Computed here, on demand (see [`contact_geometry`] for every rule). InvalidArgument
    /// before any query, after a failed one, or after any change to the meshes since
    /// (create, update, enable, destroy, filter, self-collision, GL buffer binding);
    /// Unsupported when a mesh of the answer reads its positions from a GL buffer.
    pub fn contact_geometry(&mut self) -> Result<&[ContactGeometry]> {
        let items: Vec<(MeshId, u32, MeshId, u32)> = match self.last {
            LastQuery::None => {
                return Err(Error::invalid(
                    "no contact geometry: there was no successful glcol_query or \
                     glcol_query_all since the scene was made, its meshes last changed, or a \
                     query last failed",
                ))
            }
            LastQuery::One(r) => self
                .contacts
                .iter()
                .map(|c| (r, c.reference_polygon, c.other_mesh, c.other_polygon))
                .collect(),
            LastQuery::All => self
                .pairs
                .iter()
                .map(|p| (p.mesh_a, p.polygon_a, p.mesh_b, p.polygon_b))
                .collect(),
        };
        if self.geometry.len() == items.len() && !items.is_empty() {
            return Ok(&self.geometry);
        }
        // Each mesh once (the pairs of an answer come from a few meshes, in runs).
        let mut checked = None;
        for &(a, _, b, _) in &items {
            for id in [a, b] {
                if checked == Some(id) {
                    continue;
                }
                checked = Some(id);
                if self.selector.gl_bound(id) {
                    return Err(Error::new(
                        ErrorKind::Unsupported,
                        format!(
                            "mesh {id} reads its positions from a GL buffer: contact geometry \
                             needs positions on the CPU"
                        ),
                    ));
                }
            }
        }
        if items.len() > 256 {
            self.start_workers()?;
        }
        let mut out = Vec::new();
        try_reserve(&mut out, items.len(), "the contact geometry")?;
        let meshes = &self.meshes;
        // The last mesh looked up for each side, since consecutive pairs mostly share them.
        type Last<'m> = [Option<(MeshId, &'m Mesh)>; 2];
        fn get<'m>(
            meshes: &'m BTreeMap<MeshId, Mesh>,
            last: &mut Last<'m>,
            side: usize,
            id: MeshId,
        ) -> Result<&'m Mesh> {
            match last[side] {
                Some((at, m)) if at == id => Ok(m),
                _ => {
                    let m = meshes.get(&id).ok_or_else(|| unknown(id))?;
                    last[side] = Some((id, m));
                    Ok(m)
                }
            }
        }
        fn one<'m>(
            meshes: &'m BTreeMap<MeshId, Mesh>,
            last: &mut Last<'m>,
            &(a, pa, b, pb): &(MeshId, u32, MeshId, u32),
        ) -> Result<ContactGeometry> {
            let mut ta = [[P3::default(); 3]; 2];
            let mut tb = [[P3::default(); 3]; 2];
            let ma = get(meshes, last, 0, a)?;
            let mb = get(meshes, last, 1, b)?;
            let bad =
                |m, p| Error::new(ErrorKind::Internal, format!("mesh {m} has no polygon {p}"));
            let na = ma
                .polygon_triangles(pa, &mut ta)
                .ok_or_else(|| bad(a, pa))?;
            let nb = mb
                .polygon_triangles(pb, &mut tb)
                .ok_or_else(|| bad(b, pb))?;
            Ok(contact_geometry(&ta, na, &tb, nb))
        }
        match &self.pool {
            Some(pool) if items.len() > 256 => {
                let found: Result<Vec<ContactGeometry>> = pool.install(|| {
                    use rayon::prelude::*;
                    items
                        .par_iter()
                        .map_init(|| [None; 2], |last, it| one(meshes, last, it))
                        .collect()
                });
                out = found?;
            }
            _ => {
                let mut last = [None; 2];
                for it in &items {
                    out.push(one(meshes, &mut last, it)?);
                }
            }
        }
        self.geometry = out;
        Ok(&self.geometry)
    }

    /// What each step asked and found in the last query.
    pub fn stats(&self) -> QueryStats {
        self.workspace.stats
    }
}

/// A contact of `reference` as a whole-scene pair (`reference` has the lower id).
fn pair(reference: MeshId, c: &Contact) -> Pair {
    Pair {
        mesh_a: reference,
        polygon_a: c.reference_polygon,
        mesh_b: c.other_mesh,
        polygon_b: c.other_polygon,
    }
}

/// A contact of `reference` seen from its other mesh.
fn swap(reference: MeshId, c: &Contact) -> Contact {
    Contact {
        other_mesh: reference,
        reference_polygon: c.other_polygon,
        other_polygon: c.reference_polygon,
    }
}

/// A worker's state; a worker that panicked left nothing half-done that matters (scratch
/// and caches are rebuilt as needed), so a poisoned lock is taken as it is.
fn lock(w: &Mutex<Worker>) -> std::sync::MutexGuard<'_, Worker> {
    w.lock().unwrap_or_else(|e| e.into_inner())
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

fn unknown(id: MeshId) -> Error {
    Error::new(
        ErrorKind::UnknownMesh,
        format!("mesh id {id} is not in this scene (destroyed, or never created)"),
    )
}
