//! The worker threads of a scene and how a query's work is shared out between them.
//!
//! One pool per scene, started by the first query that has work for it and asleep between
//! queries; one CPU engine and one self-collision scratch per worker. A reference query (or
//! a big mesh pair) is shared out by its leaf pairs: steps 1 and 2 on the calling thread,
//! steps 3 to 5 in contiguous shares. The answer is the same for every thread count (the
//! union of disjoint leaf pairs' contacts, sorted).

use std::sync::Mutex;

use crate::backend::{Contact, CpuSelector, LeafPairs, Pair, QueryMeshes, Selector};
use crate::error::{Error, ErrorKind, Result};
use crate::query::all::{AllStats, SelfScratch};
use crate::query::{self, QueryStats, Workspace};

/// What one worker thread works with: its own CPU engine (box caches, scratch) and
/// self-collision scratch.
#[derive(Default)]
pub(super) struct Worker {
    pub cpu: CpuSelector,
    pub workspace: Workspace,
    pub selfs: SelfScratch,
    /// Its share of the query's counts and times.
    pub stats: AllStats,
    /// One mesh pair's contacts (scratch).
    pub found: Vec<Contact>,
    /// The pairs it found in this query, in no particular order: kept from query to query,
    /// so that a task allocates nothing.
    pub pairs: Vec<Pair>,
    /// The same as sorted keys, made by this worker once its tasks are done (see
    /// `Planner::run_tasks`), and their sort's scratch.
    pub keys: Vec<u64>,
    pub key_scratch: Vec<u64>,
}

/// The scene's workers: the pool (None: the calling thread only) and each worker's state.
pub(super) struct Workers {
    /// Worker threads, started once, asleep between queries. Started by the first query
    /// that has work for them (a scene that never asks a shared query starts no thread).
    pub pool: Option<rayon::ThreadPool>,
    /// Worker threads wanted (1: the calling thread only).
    pub threads: usize,
    /// One per worker (at least one: the calling thread's).
    pub each: Vec<Mutex<Worker>>,
}

impl Workers {
    /// `threads` workers (0: one per core the process may use).
    pub fn new(threads: u32) -> Workers {
        let threads = match threads {
            0 => std::thread::available_parallelism().map_or(1, |n| n.get()),
            n => n as usize,
        };
        Workers {
            pool: None,
            threads,
            each: (0..threads.max(1)).map(|_| Mutex::default()).collect(),
        }
    }

    /// Starts the worker threads if the scene wants them and they are not running yet.
    pub fn start(&mut self) -> Result<()> {
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

    /// Worker `i`'s state.
    pub fn lock(&self, i: usize) -> std::sync::MutexGuard<'_, Worker> {
        lock(&self.each[i])
    }

    /// The worker of the calling pool thread (worker 0 off the pool).
    pub fn here(&self) -> std::sync::MutexGuard<'_, Worker> {
        let at = rayon::current_thread_index().unwrap_or(0) % self.each.len();
        self.lock(at)
    }

    /// Mesh `id` was destroyed: every worker's engine forgets it.
    pub fn mesh_destroyed(&mut self, id: u32) {
        for w in &mut self.each {
            lock(w).cpu.mesh_destroyed(id);
        }
    }

    /// The CPU engine's reference query `q` (its contacts sorted into `out`, the counts
    /// and times into `stats`), shared out when it is worth it (the pool is started then).
    pub fn cpu_query(
        &mut self,
        q: &QueryMeshes<'_>,
        out: &mut Vec<Contact>,
        stats: &mut QueryStats,
    ) -> Result<()> {
        let share = self.threads > 1 && worth_sharing(q);
        if share {
            self.start()?;
        }
        let pool = if share { self.pool.as_ref() } else { None };
        cpu_query(&self.each, pool, q, out, stats);
        Ok(())
    }
}

/// Is the reference query `q` big enough to share out between workers: its reference
/// mesh, and the other meshes whose roots meet its root, have [`SHARE_QUERY_ABOVE`]
/// polygons or more?
pub(super) fn worth_sharing(q: &QueryMeshes<'_>) -> bool {
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
pub(super) fn shares(n: usize, threads: usize) -> impl Iterator<Item = std::ops::Range<usize>> {
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

/// A worker's state; a worker that panicked left nothing half-done that matters (scratch
/// and caches are rebuilt as needed), so a poisoned lock is taken as it is.
fn lock(w: &Mutex<Worker>) -> std::sync::MutexGuard<'_, Worker> {
    w.lock().unwrap_or_else(|e| e.into_inner())
}
