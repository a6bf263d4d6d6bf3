//! A scene: meshes by id, one backend, and the last query's contacts.

use std::collections::BTreeMap;
use std::mem::MaybeUninit;
use std::sync::atomic::{AtomicU32, Ordering};

use std::sync::Mutex;
use std::time::Instant;

use crate::backend::{Backend, CpuSelector, LeafPairs, Pair, QueryMeshes, Selector};
use crate::error::{try_reserve, Error, ErrorKind, Result};
use crate::geom::contact::{contact_geometry_into, ContactGeometry, PolygonPairs};
use crate::geom::{Aabb, P3};
use crate::mesh::{Mesh, Positions};
use crate::query::all::{self as whole, AllStats, BroadPhase, SceneMesh, SelfPrep, SelfScratch};
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
    /// The self-colliding meshes made ready for the query, kept from query to query.
    self_preps: Vec<SelfPrep>,
    /// Stages of the last whole-scene query.
    all_stats: AllStats,
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
    /// Its share of the query's counts and times.
    stats: AllStats,
    /// One mesh pair's contacts (scratch).
    found: Vec<Contact>,
    /// The pairs it found in this query, in no particular order (the query sorts them all
    /// at the end): kept from query to query, so that a task allocates nothing.
    pairs: Vec<Pair>,
}

/// A unit of whole-scene work: a mesh pair (positions in the query's mesh list), or a run
/// of one mesh's self-colliding leaf pairs.
enum Task {
    Pair(u32, u32),
    /// A share of a big mesh pair's leaf pairs: (index in the shared pairs, range).
    Share(usize, std::ops::Range<usize>),
    /// Mesh `list[i]`, its `n`-th self-colliding preparation, leaf pairs `range` of it.
    Own {
        i: u32,
        n: u32,
        range: std::ops::Range<usize>,
    },
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
            self_preps: Vec::new(),
            all_stats: AllStats::default(),
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

    /// Moves vertices `first..first + positions.len()` and refits the mesh's boxes. A mesh
    /// bound to a GL buffer takes only a full update (all its vertices), which unbinds it:
    /// a partial one is refused (InvalidArgument), as the other vertices' CPU positions are
    /// stale.
    pub fn update_positions(
        &mut self,
        id: MeshId,
        first: usize,
        positions: Positions<'_>,
    ) -> Result<()> {
        let n = self.mesh(id)?.vertex_count();
        if self.selector.gl_bound(id) && (first != 0 || positions.len() != n) {
            return Err(Error::invalid(format!(
                "mesh {id} reads its positions from a GL buffer (glcol_mesh_bind_gl_buffer); \
                 its CPU positions are stale, so a partial update (vertices {first}..{} of {n}) \
                 is refused: give all {n} vertices (which unbinds the buffer), or write the \
                 range into the buffer",
                first.saturating_add(positions.len())
            )));
        }
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

    /// Places mesh `id` rigidly (or affinely): the world position of a vertex is `m * (x, y,
    /// z, 1)` with `m` row-major 3x4, in `f64` (see [`crate::geom::affine`]); None is the
    /// identity. Every query answers for the world positions. Costs a few operations per
    /// leaf box; no vertex is touched. NonFinite (nothing changes) for a non-finite entry or
    /// world positions that could leave the `f32` range; Unsupported for a mesh reading its
    /// positions from a GL buffer.
    pub fn set_transform(&mut self, id: MeshId, m: Option<&[f64; 12]>) -> Result<()> {
        let bound = self.selector.gl_bound(id);
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
        if m.place.is_some() {
            return Err(Error::new(
                ErrorKind::Unsupported,
                format!(
                    "mesh {id} has a transform: it cannot read its positions from a GL buffer \
                     (set its transform to the identity first)"
                ),
            ));
        }
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
        let h = f64::from(self.config.epsilon) / 2.0;
        // A GL backend holds the meshes in their own frames: pairs with a placed mesh are
        // answered by the CPU engine (all of them when the reference is placed).
        let mut on_cpu = Vec::new();
        if self.selector.backend() != Backend::Cpu && meshes.iter().any(|(_, m)| m.place.is_some())
        {
            if r.place.is_some() {
                on_cpu = std::mem::take(&mut meshes);
            } else {
                on_cpu.push(meshes[0]);
                on_cpu.extend(meshes.iter().skip(1).filter(|(_, m)| m.place.is_some()));
                meshes.retain(|(_, m)| m.place.is_none());
            }
            for &(id, _) in &on_cpu {
                if self.selector.gl_bound(id) {
                    self.workspace.stats.readbacks = self.selector.take_readbacks();
                    return Err(gl_bound_and_placed(id, &on_cpu));
                }
            }
        }
        // The answer goes to `scratch`, swapped in only on success: after a failed query
        // `contacts()` still holds the last successful query's.
        // The CPU backend's query is the scene's own CPU query (the workers share out its
        // leaf pairs).
        if self.selector.is_cpu_engine() {
            on_cpu = std::mem::take(&mut meshes);
        }
        self.scratch.clear();
        let mut res = Ok(());
        if meshes.len() > 1 {
            let q = QueryMeshes {
                meshes,
                half_depth: h,
                symmetric: false,
            };
            res = query::run(
                self.selector.as_mut(),
                &q,
                &mut self.workspace,
                &mut self.scratch,
            );
        }
        if res.is_ok() && on_cpu.len() > 1 {
            let q = QueryMeshes {
                meshes: on_cpu,
                half_depth: h,
                symmetric: false,
            };
            let share = self.threads > 1 && worth_sharing(&q);
            if share {
                res = start_pool(&mut self.pool, self.threads);
            }
            if res.is_ok() {
                let pool = if share { self.pool.as_ref() } else { None };
                let mut found = Vec::new();
                let mut stats = QueryStats::default();
                cpu_query(&self.workers, pool, &q, &mut found, &mut stats);
                self.scratch.extend_from_slice(&found);
                self.scratch.sort_unstable();
                let total = &mut self.workspace.stats;
                for k in 0..5 {
                    total.tests[k] += stats.tests[k];
                    total.hits[k] += stats.hits[k];
                    total.nanos[k] += stats.nanos[k];
                }
            }
        }
        if res.is_err() {
            self.workspace.stats = QueryStats::default();
            self.scratch.clear();
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
        if self.threads > 1 {
            start_pool(&mut self.pool, self.threads)?;
        }
        Ok(())
    }

    fn query_all_inner(&mut self) -> Result<()> {
        let start = Instant::now();
        self.all_stats = AllStats::default();
        self.start_workers()?;
        let h = f64::from(self.config.epsilon) / 2.0;
        let on_gpu = self.selector.backend() != Backend::Cpu;
        let selector = &self.selector;
        let list: Vec<SceneMesh<'_>> = self
            .meshes
            .iter()
            .filter(|(_, m)| m.enabled)
            .map(|(&id, m)| SceneMesh {
                id,
                mesh: m,
                // A mesh read from a host buffer on the GPU has no current box on the CPU:
                // paired with every mesh here, culled by the backend.
                root: if on_gpu && selector.gl_bound(id) {
                    Aabb::EVERYTHING
                } else {
                    m.root()
                },
                self_collision: m.self_collision,
                group: m.group,
                mask: m.mask,
            })
            .collect();
        let mut mesh_pairs = Vec::new();
        let t = Instant::now();
        whole::mesh_pairs(&list, h, &mut self.broad, &mut mesh_pairs);
        let mut st = AllStats {
            broad_nanos: nanos_since(t),
            mesh_pairs: mesh_pairs.len(),
            ..AllStats::default()
        };
        let t = Instant::now();
        let on_cpu = self.selector.backend() == Backend::Cpu;
        // A GL backend holds the meshes in their own frames: pairs with a placed mesh go to
        // the CPU engine.
        let cpu_pair = |&(i, j): &(u32, u32)| {
            on_cpu || list[i as usize].mesh.place.is_some() || list[j as usize].mesh.place.is_some()
        };
        for &(i, j) in mesh_pairs.iter().filter(|p| !on_cpu && cpu_pair(p)) {
            for (a, b) in [(i, j), (j, i)] {
                let id = list[a as usize].id;
                if self.selector.gl_bound(id) {
                    let other = &list[b as usize];
                    return Err(gl_bound_and_placed(id, &[(other.id, other.mesh)]));
                }
            }
        }
        let mut tasks: Vec<Task> = Vec::new();
        // A big mesh pair is shared out by its leaf pairs (steps 1 and 2 here, on the
        // calling thread), like a big reference query; the others are one task each.
        let mut shared: Vec<(u32, u32, LeafPairs)> = Vec::new();
        let pair_query = |i: u32, j: u32| {
            let (a, b) = (&list[i as usize], &list[j as usize]);
            QueryMeshes {
                meshes: vec![(a.id, a.mesh), (b.id, b.mesh)],
                half_depth: h,
                symmetric: true,
            }
        };
        for &(i, j) in mesh_pairs.iter().filter(|p| cpu_pair(p)) {
            let q = pair_query(i, j);
            if self.threads > 1 && worth_sharing(&q) {
                let mut lp = LeafPairs::default();
                let mut stats = QueryStats::default();
                lock(&self.workers[0])
                    .cpu
                    .leaf_pairs(&q, &mut lp, &mut stats);
                let k = shared.len();
                tasks.extend(shares(lp.pairs.len(), self.threads).map(|r| Task::Share(k, r)));
                shared.push((i, j, lp));
            } else {
                tasks.push(Task::Pair(i, j));
            }
        }
        let selfs: Vec<u32> = (0..list.len() as u32)
            .filter(|&i| list[i as usize].self_collision)
            .collect();
        // Self-collision runs on the CPU, from the mesh's CPU positions: a GL backend does
        // not have those of a mesh read from a host buffer (a CPU scene reads the buffer in
        // at each query).
        if !on_cpu {
            if let Some(&i) = selfs
                .iter()
                .find(|&&i| self.selector.gl_bound(list[i as usize].id))
            {
                self.workspace.stats.readbacks = self.selector.take_readbacks();
                return Err(Error::new(
                    ErrorKind::Unsupported,
                    format!(
                        "mesh {} reads its positions from a GL buffer and has self-collision \
                        on, which runs on the CPU from positions this backend keeps on the \
                        GPU: turn its self-collision off, or give it its positions with \
                        glcol_mesh_update_positions",
                        list[i as usize].id
                    ),
                ));
            }
        }
        if self.self_preps.len() < selfs.len() {
            self.self_preps.resize_with(selfs.len(), SelfPrep::default);
        }
        let preps = &mut self.self_preps[..selfs.len()];
        match &self.pool {
            Some(pool) if !selfs.is_empty() => pool.install(|| {
                use rayon::prelude::*;
                preps.par_iter_mut().zip(&selfs).for_each(|(prep, &i)| {
                    let sm = &list[i as usize];
                    prep.make(sm.id, sm.mesh, h, true)
                })
            }),
            _ => {
                for (prep, &i) in preps.iter_mut().zip(&selfs) {
                    let sm = &list[i as usize];
                    prep.make(sm.id, sm.mesh, h, false);
                }
            }
        }
        let preps = &self.self_preps[..selfs.len()];
        for (n, (prep, &i)) in preps.iter().zip(&selfs).enumerate() {
            let pairs = prep.leaf_pairs.len();
            st.self_cert_patches += prep.certified_patches;
            st.self_cert_subs += prep.certified_subs;
            st.self_leaf_pairs += pairs;
            tasks.extend((0..pairs).step_by(LEAF_PAIRS_PER_TASK).map(|s| Task::Own {
                i,
                n: n as u32,
                range: s..(s + LEAF_PAIRS_PER_TASK).min(pairs),
            }));
        }
        st.self_leaf_nanos = nanos_since(t);
        for w in &self.workers {
            let mut w = lock(w);
            w.stats = AllStats::default();
            w.pairs.clear();
        }
        let t = Instant::now();
        let workers = &self.workers;
        let run = |t: &Task| {
            let at = rayon::current_thread_index().unwrap_or(0) % workers.len();
            let mut w = lock(&workers[at]);
            let w = &mut *w;
            let out = &mut w.pairs;
            match *t {
                Task::Pair(i, j) => {
                    let q = pair_query(i, j);
                    // The CPU engine never fails.
                    if query::run(&mut w.cpu, &q, &mut w.workspace, &mut w.found).is_ok() {
                        out.extend(w.found.iter().map(|c| pair(list[i as usize].id, c)));
                    }
                    for k in 0..5 {
                        w.stats.pair_step_nanos[k] += w.workspace.stats.nanos[k];
                    }
                    w.stats.pair_found += w.found.len();
                }
                Task::Share(k, ref r) => {
                    let (i, j, ref lp) = shared[k];
                    let q = pair_query(i, j);
                    let mut stats = QueryStats::default();
                    w.found.clear();
                    w.cpu
                        .some_pairs(&q, lp, r.clone(), &mut w.found, &mut stats);
                    w.stats.pair_found += w.found.len();
                    out.extend(w.found.iter().map(|c| pair(list[i as usize].id, c)));
                }
                Task::Own { i, n, ref range } => {
                    let sm = &list[i as usize];
                    let prep = &preps[n as usize];
                    whole::self_pairs(
                        sm.id,
                        sm.mesh,
                        prep,
                        h,
                        &prep.leaf_pairs[range.clone()],
                        &mut w.selfs,
                        out,
                        &mut w.stats,
                    );
                }
            }
        };
        match &self.pool {
            Some(pool) => pool.install(|| {
                use rayon::prelude::*;
                tasks.par_iter().for_each(run)
            }),
            None => tasks.iter().for_each(run),
        }
        st.tasks_nanos = nanos_since(t);
        let out = &mut self.pairs_scratch;
        out.clear();
        for w in &self.workers {
            let mut w = lock(w);
            st.add_worker(&w.stats);
            out.extend_from_slice(&w.pairs);
            w.pairs.clear();
        }
        if !on_cpu {
            // A GL backend answers mesh pair by mesh pair, on the calling thread (its
            // context is current here); with a band, both ways round, as its viewing
            // volumes are the reference's only.
            for &(i, j) in mesh_pairs.iter().filter(|p| !cpu_pair(p)) {
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
        let t = Instant::now();
        // By one 128-bit key: the order of `Pair` (mesh_a, polygon_a, mesh_b, polygon_b),
        // compared in two instructions rather than field by field. (A stable sort, to merge
        // the mesh pairs' sorted runs, was slower: the runs are short.)
        out.sort_unstable_by_key(|p| {
            (u128::from(p.mesh_a) << 96)
                | (u128::from(p.polygon_a) << 64)
                | (u128::from(p.mesh_b) << 32)
                | u128::from(p.polygon_b)
        });
        out.dedup();
        st.merge_nanos = nanos_since(t);
        st.total_nanos = nanos_since(start);
        self.all_stats = st;
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
    /// Computed here, on demand (see
    /// [`contact_geometry`](crate::geom::contact::contact_geometry) for every rule).
    /// InvalidArgument before any query, after a failed one, or after any change to the
    /// meshes since
    /// (create, update, enable, destroy, filter, self-collision, GL buffer binding). A mesh
    /// of the answer that reads its positions from a host GL buffer is read at the positions
    /// the query used (GL_COMPUTE reads back what the query gathered: the scene's context
    /// must be current, else GlUnavailable, the answer kept).
    pub fn contact_geometry(&mut self) -> Result<&[ContactGeometry]> {
        let last = self.last;
        let n = match last {
            LastQuery::None => {
                return Err(Error::invalid(
                    "no contact geometry: there was no successful glcol_query or \
                     glcol_query_all since the scene was made, its meshes last changed, or a \
                     query last failed",
                ))
            }
            LastQuery::One(_) => self.contacts.len(),
            LastQuery::All => self.pairs.len(),
        };
        if self.geometry.len() == n && n > 0 {
            return Ok(&self.geometry);
        }
        // Meshes of the answer read from a host GL buffer: their positions as the query used
        // them, into their CPU positions (each mesh once per run of pairs: the pairs of an
        // answer come from a few meshes, in runs; no scan when no mesh reads a GL buffer).
        let bound = self.selector.any_gl_bound();
        if bound {
            let mut ids: Vec<MeshId> = Vec::new();
            let mut last_seen = [None; 2];
            for k in 0..n {
                let (a, _, b, _) = item(last, &self.contacts, &self.pairs, k);
                for (side, id) in [a, b].into_iter().enumerate() {
                    if last_seen[side] != Some(id) {
                        last_seen[side] = Some(id);
                        if self.selector.gl_bound(id) && !ids.contains(&id) {
                            ids.push(id);
                        }
                    }
                }
            }
            self.selector
                .positions_for_geometry(&mut self.meshes, &ids)?;
        }
        if n > PAR_GEOMETRY {
            self.start_workers()?;
        }
        let mut out = std::mem::take(&mut self.geometry);
        out.clear();
        try_reserve(&mut out, n, "the contact geometry")?;
        // Written once, by the fill below, in the vector's spare capacity.
        let spare = &mut out.spare_capacity_mut()[..n];
        // Four triangle pairs at a time. At epsilon 0 every pair of the answer intersects
        // (the exact test decided it), so the geometry skips that test; not where a mesh
        // reads a host GL buffer on a GL backend (GL_COMPUTE's answer for it has no CPU
        // confirmation and may hold pairs within its rounding band: the geometry decides
        // them exactly). A CPU scene reads the buffer in and answers exactly.
        let unconfirmed = bound && self.selector.backend() != Backend::Cpu;
        let known = self.config.epsilon == 0.0 && !unconfirmed;
        let (meshes, contacts, pairs) = (&self.meshes, &self.contacts, &self.pairs);
        // Entries `out` from pair `base` on.
        let fill = |out: &mut [MaybeUninit<ContactGeometry>], base: usize| -> Result<()> {
            contact_geometry_into(
                out,
                known,
                AnswerPairs {
                    last,
                    contacts,
                    pairs,
                    meshes,
                    base,
                    seen: [None; 2],
                },
            )
        };
        match &self.pool {
            Some(pool) if n > PAR_GEOMETRY => pool.install(|| {
                use rayon::prelude::*;
                spare
                    .par_chunks_mut(GEOMETRY_CHUNK)
                    .enumerate()
                    .try_for_each(|(c, chunk)| fill(chunk, c * GEOMETRY_CHUNK))
            })?,
            _ => fill(spare, 0)?,
        }
        // SAFETY: the fill succeeded, so it initialized every one of the first `n` entries
        // (capacity reserved above).
        unsafe { out.set_len(n) };
        self.geometry = out;
        Ok(&self.geometry)
    }

    /// Where the time of the last whole-scene query went ([`Scene::query_all`]; reset by
    /// each one, zero after a failed one).
    pub fn all_stats(&self) -> AllStats {
        self.all_stats
    }

    /// What each step asked and found in the last query.
    pub fn stats(&self) -> QueryStats {
        self.workspace.stats
    }
}

/// Contact geometry is shared between the workers above this many pairs, in chunks of
/// `GEOMETRY_CHUNK`.
const PAR_GEOMETRY: usize = 256;
const GEOMETRY_CHUNK: usize = 64;

/// The pairs of the last answer from `base` on, as [`contact_geometry_into`] reads them.
struct AnswerPairs<'m> {
    last: LastQuery,
    contacts: &'m [Contact],
    pairs: &'m [Pair],
    meshes: &'m BTreeMap<MeshId, Mesh>,
    base: usize,
    /// The mesh of each side last read.
    seen: Last<'m>,
}

impl PolygonPairs for AnswerPairs<'_> {
    type Error = Error;
    #[inline(always)]
    fn fetch(
        &mut self,
        i: usize,
        ta: [&mut [P3; 3]; 2],
        tb: [&mut [P3; 3]; 2],
    ) -> Result<(usize, usize)> {
        let (a, pa, b, pb) = item(self.last, self.contacts, self.pairs, self.base + i);
        let na = polygon(self.meshes, &mut self.seen, 0, a, pa, ta)?;
        let nb = polygon(self.meshes, &mut self.seen, 1, b, pb, tb)?;
        Ok((na, nb))
    }
}

/// Pair `k` of the last answer as (mesh a, polygon a, mesh b, polygon b).
#[inline(always)]
fn item(
    last: LastQuery,
    contacts: &[Contact],
    pairs: &[Pair],
    k: usize,
) -> (MeshId, u32, MeshId, u32) {
    match last {
        LastQuery::One(r) => {
            let c = &contacts[k];
            (r, c.reference_polygon, c.other_mesh, c.other_polygon)
        }
        _ => {
            let p = &pairs[k];
            (p.mesh_a, p.polygon_a, p.mesh_b, p.polygon_b)
        }
    }
}

/// The last mesh looked up for each side of a run of pairs (consecutive pairs mostly
/// share them).
type Last<'m> = [Option<(MeshId, &'m Mesh)>; 2];

/// Fills `out` with polygon `p` of mesh `id` (its triangles in world positions), returning
/// how many.
#[inline(always)]
fn polygon<'m>(
    meshes: &'m BTreeMap<MeshId, Mesh>,
    last: &mut Last<'m>,
    side: usize,
    id: MeshId,
    p: u32,
    out: [&mut [P3; 3]; 2],
) -> Result<usize> {
    let m = match last[side] {
        Some((at, m)) if at == id => m,
        _ => {
            let m = meshes.get(&id).ok_or_else(|| unknown(id))?;
            last[side] = Some((id, m));
            m
        }
    };
    m.polygon_triangles_into(p, out)
        .ok_or_else(|| Error::new(ErrorKind::Internal, format!("mesh {id} has no polygon {p}")))
}

fn nanos_since(t: Instant) -> u64 {
    t.elapsed().as_nanos() as u64
}

/// Starts `threads` worker threads into `pool` unless they are running.
fn start_pool(pool: &mut Option<rayon::ThreadPool>, threads: usize) -> Result<()> {
    if pool.is_none() {
        *pool = Some(
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

/// Is the reference query `q` big enough to share out between workers: its reference
/// mesh, and the other meshes whose roots meet its root, have [`SHARE_QUERY_ABOVE`]
/// polygons or more?
fn worth_sharing(q: &QueryMeshes<'_>) -> bool {
    let r = q.meshes[0].1;
    let root = r.root();
    let near: usize = q.meshes[1..]
        .iter()
        .filter(|(_, m)| root.overlaps(&m.root(), q.half_depth))
        .map(|(_, m)| m.polygon_count())
        .sum();
    near.min(r.polygon_count()) >= SHARE_QUERY_ABOVE
}

/// A reference query whose reference mesh, and whose other meshes near it, have fewer
/// polygons than this runs on the calling thread (sharing it out would cost more than it
/// saves).
const SHARE_QUERY_ABOVE: usize = 2048;

/// Leaf pairs per share of a reference query, at least: about eight shares per worker
/// otherwise, so that the workers stay busy however unevenly the pairs cost.
const LEAF_PAIRS_PER_SHARE: usize = 4;

/// `n` leaf pairs in contiguous shares for `threads` workers: about eight shares per
/// worker, at least [`LEAF_PAIRS_PER_SHARE`] pairs each.
fn shares(n: usize, threads: usize) -> impl Iterator<Item = std::ops::Range<usize>> {
    let share = n.div_ceil(8 * threads.max(1)).max(LEAF_PAIRS_PER_SHARE);
    (0..n).step_by(share).map(move |a| a..(a + share).min(n))
}

/// The CPU engine's reference query `q` (its contacts sorted into `out`, the counts and
/// times into `stats`), on worker 0 alone without a pool; with one, steps 1 and 2 on the
/// calling thread, then steps 3 to 5 shared out by leaf pairs. The answer is the same
/// either way (the union of disjoint leaf pairs' contacts, sorted); step times are summed
/// over the workers.
fn cpu_query(
    workers: &[Mutex<Worker>],
    pool: Option<&rayon::ThreadPool>,
    q: &QueryMeshes<'_>,
    out: &mut Vec<Contact>,
    stats: &mut QueryStats,
) {
    out.clear();
    *stats = QueryStats::default();
    let Some(pool) = pool else {
        let mut w = lock(&workers[0]);
        let w = &mut *w;
        // The CPU engine never fails.
        if query::run(&mut w.cpu, q, &mut w.workspace, out).is_ok() {
            *stats = w.workspace.stats;
        }
        return;
    };
    let mut lp = LeafPairs::default();
    lock(&workers[0]).cpu.leaf_pairs(q, &mut lp, stats);
    let n = lp.pairs.len();
    if n == 0 {
        return;
    }
    let ranges: Vec<std::ops::Range<usize>> = shares(n, pool.current_num_threads()).collect();
    let found: Vec<(Vec<Contact>, QueryStats)> = pool.install(|| {
        use rayon::prelude::*;
        ranges
            .par_iter()
            .map(|r| {
                let at = rayon::current_thread_index().unwrap_or(0) % workers.len();
                let mut w = lock(&workers[at]);
                let (mut c, mut st) = (Vec::new(), QueryStats::default());
                w.cpu.some_pairs(q, &lp, r.clone(), &mut c, &mut st);
                (c, st)
            })
            .collect()
    });
    for (c, st) in &found {
        out.extend_from_slice(c);
        for k in 2..5 {
            stats.tests[k] += st.tests[k];
            stats.hits[k] += st.hits[k];
            stats.nanos[k] += st.nanos[k];
        }
    }
    out.sort_unstable();
    out.dedup();
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

/// A query that needs the CPU for a placed mesh, with mesh `id` (of `meshes`) reading its
/// positions from a GL buffer.
fn gl_bound_and_placed(id: MeshId, meshes: &[(MeshId, &Mesh)]) -> Error {
    let placed: Vec<String> = meshes
        .iter()
        .filter(|(_, m)| m.place.is_some())
        .map(|(i, _)| i.to_string())
        .collect();
    Error::new(
        ErrorKind::Unsupported,
        format!(
            "mesh {id} reads its positions from a GL buffer and would be collided with \
             transformed mesh(es) {}, which the GL backends leave to the CPU: give those \
             meshes the identity, or disable one side",
            placed.join(", ")
        ),
    )
}

fn unknown(id: MeshId) -> Error {
    Error::new(
        ErrorKind::UnknownMesh,
        format!("mesh id {id} is not in this scene (destroyed, or never created)"),
    )
}
