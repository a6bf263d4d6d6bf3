//! The whole-scene query's plan: mesh pairs from the broad phase, each answered by the CPU
//! engine (as a task for the workers, a big one shared out by leaf pairs) or by the GL
//! backend (on the calling thread, where its context is current), self-collision in runs
//! of leaf pairs, then one sort.

use std::collections::BTreeMap;
use std::time::Instant;

use super::workers::{shares, worth_sharing, Worker};
use super::{gl_bound_and_placed, Planner};
use crate::backend::{Backend, Contact, LeafPairs, Pair, QueryMeshes};
use crate::error::{Error, ErrorKind, Result};
use crate::geom::Aabb;
use crate::mesh::Mesh;
use crate::mesh::MeshId;
use crate::query::all::{self as whole, AllStats, SceneMesh, SelfPrep};
use crate::query::{self, QueryStats};

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
    /// Mesh `list[i]`, its `n`-th self-colliding preparation, the neighbour pairs around
    /// its open vertices `range` ([`SelfPrep::open`]).
    Open {
        i: u32,
        n: u32,
        range: std::ops::Range<usize>,
    },
}

/// Self-collision leaf pairs per task: small enough to spread a big mesh over the workers,
/// big enough that a task is worth handing out.
const LEAF_PAIRS_PER_TASK: usize = 8;

/// Open vertices per task (their neighbour pairs): a few dozen pairs to decide, so that
/// the last tasks of a query are short.
const OPEN_VERTICES_PER_TASK: usize = 64;

/// What the tasks of one query read.
struct Work<'a, 'm> {
    list: &'a [SceneMesh<'m>],
    /// Big mesh pairs shared out: (i, j, their leaf pairs).
    shared: Vec<(u32, u32, LeafPairs)>,
    preps: &'a [SelfPrep],
    h: f64,
}

impl Work<'_, '_> {
    /// The CPU engine's query of mesh pair (i, j) of the list.
    fn pair_query(&self, i: u32, j: u32) -> QueryMeshes<'_> {
        let (a, b) = (&self.list[i as usize], &self.list[j as usize]);
        QueryMeshes {
            meshes: vec![(a.id, a.mesh), (b.id, b.mesh)],
            half_depth: self.h,
            symmetric: true,
        }
    }

    /// Runs task `t` on worker `w` (its pairs into `w.pairs`).
    fn run(&self, t: &Task, w: &mut Worker) {
        let out = &mut w.pairs;
        match *t {
            Task::Pair(i, j) => {
                let q = self.pair_query(i, j);
                // The CPU engine never fails.
                if query::run(&mut w.cpu, &q, &mut w.workspace, &mut w.found).is_ok() {
                    out.extend(w.found.iter().map(|c| pair(self.list[i as usize].id, c)));
                }
                for k in 0..5 {
                    w.stats.pair_step_nanos[k] += w.workspace.stats.nanos[k];
                }
                w.stats.pair_found += w.found.len();
            }
            Task::Share(k, ref r) => {
                let (i, j, ref lp) = self.shared[k];
                let q = self.pair_query(i, j);
                let mut stats = QueryStats::default();
                w.found.clear();
                w.cpu
                    .some_pairs(&q, lp, r.clone(), &mut w.found, &mut stats);
                w.stats.pair_found += w.found.len();
                out.extend(w.found.iter().map(|c| pair(self.list[i as usize].id, c)));
            }
            Task::Own { i, n, ref range } => {
                let sm = &self.list[i as usize];
                let prep = &self.preps[n as usize];
                whole::self_pairs(
                    sm.id,
                    sm.mesh,
                    prep,
                    self.h,
                    &prep.leaf_pairs[range.clone()],
                    &mut w.selfs,
                    out,
                    &mut w.stats,
                );
            }
            Task::Open { i, n, ref range } => {
                let sm = &self.list[i as usize];
                let prep = &self.preps[n as usize];
                let (s, st) = (&mut w.selfs, &mut w.stats);
                whole::self_neighbours(sm.id, sm.mesh, prep, range.clone(), s, out, st);
            }
        }
    }
}

impl Planner {
    /// Every pair of polygons that meet (see [`crate::Scene::query_all`]), sorted, into
    /// `out` (its contents undefined on failure). Half-depth `h`.
    pub fn query_all(
        &mut self,
        meshes: &mut BTreeMap<MeshId, Mesh>,
        h: f64,
        out: &mut Vec<Pair>,
    ) -> Result<()> {
        self.selector.take_readbacks();
        self.workspace.stats = QueryStats::default();
        let res = self
            .selector
            .prepare(meshes)
            .and_then(|()| self.query_all_prepared(meshes, h, out));
        self.workspace.stats.readbacks = self.selector.take_readbacks();
        res
    }

    /// [`Planner::query_all`] once the backend is prepared.
    fn query_all_prepared(
        &mut self,
        meshes: &BTreeMap<MeshId, Mesh>,
        h: f64,
        out: &mut Vec<Pair>,
    ) -> Result<()> {
        let start = Instant::now();
        self.all_stats = AllStats::default();
        self.workers.start()?;
        let list = self.scene_meshes(meshes);
        let mut mesh_pairs = Vec::new();
        let t = Instant::now();
        whole::mesh_pairs(&list, h, &mut self.broad, &mut mesh_pairs);
        let mut st = AllStats {
            broad_nanos: whole::nanos_since(t),
            mesh_pairs: mesh_pairs.len(),
            ..AllStats::default()
        };
        let t = Instant::now();
        let on_cpu = self.selector.backend() == Backend::Cpu;
        // A GL backend holds float meshes in their own frames: pairs with a placed or f64
        // mesh go to the CPU engine.
        let cpu_pair = |&(i, j): &(u32, u32)| {
            on_cpu || list[i as usize].mesh.needs_cpu() || list[j as usize].mesh.needs_cpu()
        };
        let selfs: Vec<u32> = (0..list.len() as u32)
            .filter(|&i| list[i as usize].self_collision)
            .collect();
        if !on_cpu {
            self.refuse_bound(&list, mesh_pairs.iter().filter(|p| cpu_pair(p)), &selfs)?;
        }
        let mut tasks: Vec<Task> = Vec::new();
        let shared = self.pair_tasks(
            &list,
            h,
            mesh_pairs.iter().filter(|p| cpu_pair(p)),
            &mut tasks,
        );
        self.prepare_selfs(&list, &selfs, h);
        let preps = &self.self_preps[..selfs.len()];
        for (n, (prep, &i)) in preps.iter().zip(&selfs).enumerate() {
            let pairs = prep.leaf_pairs.len();
            st.self_cert_patches += prep.certified_patches;
            st.self_cert_fans += prep.certified_fans;
            st.self_leaf_pairs += pairs;
            tasks.extend((0..pairs).step_by(LEAF_PAIRS_PER_TASK).map(|s| Task::Own {
                i,
                n: n as u32,
                range: s..(s + LEAF_PAIRS_PER_TASK).min(pairs),
            }));
            let open = prep.open.len();
            tasks.extend(
                (0..open)
                    .step_by(OPEN_VERTICES_PER_TASK)
                    .map(|s| Task::Open {
                        i,
                        n: n as u32,
                        range: s..(s + OPEN_VERTICES_PER_TASK).min(open),
                    }),
            );
        }
        st.self_leaf_nanos = whole::nanos_since(t);
        let work = Work {
            list: &list,
            shared,
            preps,
            h,
        };
        // The widths of the answer's keys, from the scene's mesh ids and polygon counts.
        let (ids, polys) = list.iter().fold((0u32, 0u32), |(i, p), m| {
            (
                i | m.id,
                p | m.mesh.polygon_count().saturating_sub(1) as u32,
            )
        });
        let widths = super::sort::short_widths(ids, polys);
        let (sorted, tasks_nanos, sort_nanos) = self.run_tasks(&work, &tasks, widths, out, &mut st);
        // The leaf-pair tasks counted every pair sharing a vertex (outside proven patches)
        // as decided by a fan; the open-vertex tasks tested some of them (never more: they
        // are among those counted).
        st.self_adjacent_fans = st.self_adjacent_fans.saturating_sub(st.self_adjacent_tests);
        st.tasks_nanos = tasks_nanos;
        let merged = out.len();
        if !on_cpu {
            // A GL backend answers mesh pair by mesh pair, on the calling thread (its
            // context is current here); with a band, both ways round, as its viewing
            // volumes are the reference's only.
            for &(i, j) in mesh_pairs.iter().filter(|p| !cpu_pair(p)) {
                let (a, b) = (&list[i as usize], &list[j as usize]);
                self.gl_pair(a, b, h, out)?;
                if h > 0.0 {
                    self.gl_pair(b, a, h, out)?;
                }
            }
        }
        // The workers' answer comes sorted; the GL backend's pairs after it, or an answer
        // whose keys need 128 bits, are sorted here.
        let t = Instant::now();
        if !sorted || out.len() != merged {
            super::sort::sort_pairs(out, &mut self.merge_keys, self.workers.pool.as_ref());
        }
        st.merge_nanos = sort_nanos + whole::nanos_since(t);
        st.total_nanos = whole::nanos_since(start);
        self.all_stats = st;
        Ok(())
    }

    /// The enabled meshes as the broad phase sees them.
    fn scene_meshes<'m>(&self, meshes: &'m BTreeMap<MeshId, Mesh>) -> Vec<SceneMesh<'m>> {
        let on_gpu = self.selector.backend() != Backend::Cpu;
        meshes
            .iter()
            .filter(|(_, m)| m.enabled)
            .map(|(&id, m)| SceneMesh {
                id,
                mesh: m,
                // A mesh read from a host buffer on the GPU has no current box on the CPU:
                // paired with every mesh here, culled by the backend.
                root: if on_gpu && self.selector.gl_bound(id) {
                    Aabb::EVERYTHING
                } else {
                    m.root()
                },
                self_collision: m.self_collision,
                group: m.group,
                mask: m.mask,
            })
            .collect()
    }

    /// On a GL backend: Unsupported when a mesh read from a host GL buffer would go to the
    /// CPU engine (paired with a placed mesh, or self-colliding: self-collision runs on the
    /// CPU, from positions the GL backend keeps on the GPU; a CPU scene reads the buffer in
    /// at each query).
    fn refuse_bound<'p>(
        &self,
        list: &[SceneMesh<'_>],
        cpu_pairs: impl Iterator<Item = &'p (u32, u32)>,
        selfs: &[u32],
    ) -> Result<()> {
        for &(i, j) in cpu_pairs {
            for (a, b) in [(i, j), (j, i)] {
                let id = list[a as usize].id;
                if self.selector.gl_bound(id) {
                    let other = &list[b as usize];
                    return Err(gl_bound_and_placed(id, &[(other.id, other.mesh)]));
                }
            }
        }
        if let Some(&i) = selfs
            .iter()
            .find(|&&i| self.selector.gl_bound(list[i as usize].id))
        {
            return Err(Error::new(
                ErrorKind::Unsupported,
                format!(
                    "mesh {} reads its positions from a GL buffer and has self-collision \
                     on, which runs on the CPU from positions this backend keeps on the \
                     GPU: turn its self-collision off, or give it its positions with \
                     an update of all its vertices",
                    list[i as usize].id
                ),
            ));
        }
        Ok(())
    }

    /// The CPU engine's mesh pairs as tasks: a big pair shared out by its leaf pairs (steps
    /// 1 and 2 here, on the calling thread), like a big reference query; the others one task
    /// each. Returns the shared pairs' leaf pairs.
    fn pair_tasks<'p>(
        &self,
        list: &[SceneMesh<'_>],
        h: f64,
        cpu_pairs: impl Iterator<Item = &'p (u32, u32)>,
        tasks: &mut Vec<Task>,
    ) -> Vec<(u32, u32, LeafPairs)> {
        let threads = self.workers.threads;
        let mut shared = Vec::new();
        for &(i, j) in cpu_pairs {
            let (a, b) = (&list[i as usize], &list[j as usize]);
            let q = QueryMeshes {
                meshes: vec![(a.id, a.mesh), (b.id, b.mesh)],
                half_depth: h,
                symmetric: true,
            };
            if threads > 1 && worth_sharing(&q) {
                let mut lp = LeafPairs::default();
                let mut stats = QueryStats::default();
                self.workers.lock(0).cpu.leaf_pairs(&q, &mut lp, &mut stats);
                let k = shared.len();
                tasks.extend(shares(lp.pairs.len(), threads).map(|r| Task::Share(k, r)));
                shared.push((i, j, lp));
            } else {
                tasks.push(Task::Pair(i, j));
            }
        }
        shared
    }

    /// Makes the self-colliding meshes `selfs` (positions in `list`) ready, on the workers
    /// when there are some.
    fn prepare_selfs(&mut self, list: &[SceneMesh<'_>], selfs: &[u32], h: f64) {
        if self.self_preps.len() < selfs.len() {
            self.self_preps.resize_with(selfs.len(), SelfPrep::default);
        }
        let preps = &mut self.self_preps[..selfs.len()];
        match &self.workers.pool {
            Some(pool) if !selfs.is_empty() => pool.install(|| {
                use rayon::prelude::*;
                preps.par_iter_mut().zip(selfs).for_each(|(prep, &i)| {
                    let sm = &list[i as usize];
                    prep.make(sm.id, sm.mesh, h, true)
                })
            }),
            _ => {
                for (prep, &i) in preps.iter_mut().zip(selfs) {
                    let sm = &list[i as usize];
                    prep.make(sm.id, sm.mesh, h, false);
                }
            }
        }
    }

    /// Runs the tasks on the workers; their pairs into `out` (cleared first), their counts
    /// and times into `st`. With `widths` (the scene's mesh ids and polygon numbers fit
    /// [`super::sort::sort_pairs`]'s 64-bit keys), each worker then sorts its own pairs as
    /// keys, on its own thread and side by side with the others (the pool still awake, each
    /// worker reading the pairs it wrote), and the sorted lists are merged into `out` on
    /// the pool (two lists in two halves side by side), repeats dropped: the answer is then
    /// sorted (the result: true); else `out` gets the pairs as they are. Returns also the
    /// time of the tasks and of the sort, nanoseconds.
    fn run_tasks(
        &self,
        work: &Work<'_, '_>,
        tasks: &[Task],
        widths: Option<(u32, u32)>,
        out: &mut Vec<Pair>,
        st: &mut AllStats,
    ) -> (bool, u64, u64) {
        let start = Instant::now();
        let workers = &self.workers;
        let count = workers.each.len();
        for i in 0..count {
            let mut w = workers.lock(i);
            w.stats = AllStats::default();
            w.pairs.clear();
        }
        let run = |t: &Task| work.run(t, &mut workers.here());
        let sort_own = |i: usize, widths: (u32, u32)| {
            let mut w = workers.lock(i);
            let w = &mut *w;
            super::sort::sort_own(&w.pairs, widths, &mut w.keys, &mut w.key_scratch);
        };
        let mut merge = |widths: (u32, u32), par: bool| {
            let each: Vec<_> = (0..count).map(|i| workers.lock(i)).collect();
            let lists: Vec<&[u64]> = each.iter().map(|w| &w.keys[..]).collect();
            super::sort::merge_keys(&lists, widths, out, par);
        };
        let mut tasks_done = start;
        match &workers.pool {
            Some(pool) => pool.install(|| {
                use rayon::prelude::*;
                tasks.par_iter().with_max_len(1).for_each(run);
                tasks_done = Instant::now();
                if let Some(widths) = widths {
                    // Worker `i`'s pairs were made on pool thread `i` (`Workers::here`).
                    rayon::broadcast(|ctx| {
                        if ctx.index() < count {
                            sort_own(ctx.index(), widths)
                        }
                    });
                    // The sorted lists merged on the pool.
                    merge(widths, true);
                }
            }),
            None => {
                tasks.iter().for_each(run);
                tasks_done = Instant::now();
                if let Some(widths) = widths {
                    (0..count).for_each(|i| sort_own(i, widths));
                    merge(widths, false);
                }
            }
        }
        let mut each: Vec<_> = (0..count).map(|i| workers.lock(i)).collect();
        for w in &each {
            st.add_worker(&w.stats);
        }
        if widths.is_none() {
            out.clear();
            for w in &each {
                out.extend_from_slice(&w.pairs);
            }
        }
        for w in &mut each {
            w.pairs.clear();
            w.keys.clear();
        }
        let nanos = |a: Instant, b: Instant| (b - a).as_nanos() as u64;
        (
            widths.is_some(),
            nanos(start, tasks_done),
            nanos(tasks_done, Instant::now()),
        )
    }

    /// The GL backend's contacts of reference `r` against `o`, as pairs into `out`.
    fn gl_pair(
        &mut self,
        r: &SceneMesh<'_>,
        o: &SceneMesh<'_>,
        h: f64,
        out: &mut Vec<Pair>,
    ) -> Result<()> {
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
