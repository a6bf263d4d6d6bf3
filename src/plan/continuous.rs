//! The continuous query's plan: every enabled mesh's step made ready (on the workers when
//! there are several meshes), the leaf pairs found on the calling thread, shared out over
//! the workers in runs of equal size, then one sort. Always on the CPU: a GL backend
//! answers it from the CPU positions it keeps, and refuses meshes it reads from a host
//! GL buffer (their start lives on the GPU).

use std::collections::BTreeMap;
use std::time::Instant;

use super::Planner;
use crate::backend::Backend;
use crate::error::{try_reserve, Error, ErrorKind, Result};
use crate::geom::ccd::First;
use crate::mesh::{Mesh, MeshId};
use crate::query::all::{nanos_since, SceneMesh};
use crate::query::continuous::{self as cont, ContinuousStats, Impact, LeafPair};

/// Leaf pairs per task handed to a worker.
const LEAF_PAIRS_PER_TASK: usize = 32;

impl Planner {
    /// Every pair of polygons that meet during the step (see
    /// [`crate::Scene::query_continuous`]), sorted, into `out`, and the primitive pair that
    /// met first of each into `firsts` (both cleared first; undefined on failure). Band
    /// `d` (half the scene's epsilon).
    pub fn query_continuous(
        &mut self,
        meshes: &mut BTreeMap<MeshId, Mesh>,
        d: f64,
        out: &mut Vec<Impact>,
        firsts: &mut Vec<First>,
    ) -> Result<()> {
        let start = Instant::now();
        self.continuous_stats = ContinuousStats::default();
        out.clear();
        firsts.clear();
        // A CPU scene reads meshes bound to host GL buffers in here (its context current
        // then); a GL backend keeps them on the GPU, and needs nothing else of its context
        // here: the continuous query runs on the CPU positions.
        if self.selector.backend() == Backend::Cpu {
            self.selector.prepare(meshes)?;
        } else if let Some((&id, _)) = meshes
            .iter()
            .find(|(&id, m)| m.enabled && self.selector.gl_bound(id))
        {
            return Err(Error::new(
                ErrorKind::Unsupported,
                format!(
                    "mesh {id} reads its positions from a GL buffer, which this GL \
                         backend keeps on the GPU; the continuous query runs on the CPU: \
                         disable the mesh for it, or give it its positions with an update \
                         of all its vertices"
                ),
            ));
        }
        self.workers.start()?;
        let list: Vec<SceneMesh<'_>> = meshes
            .iter()
            .filter(|(_, m)| m.enabled)
            .map(|(&id, m)| SceneMesh {
                id,
                mesh: m,
                root: m.root(),
                self_collision: m.self_collision,
                group: m.group,
                mask: m.mask,
            })
            .collect();
        let mut st = ContinuousStats::default();
        let t = Instant::now();
        self.make_swept(&list, d);
        let swept = &self.swept[..list.len()];
        let list: Vec<SceneMesh<'_>> = list
            .iter()
            .zip(swept)
            .map(|(m, s)| SceneMesh { root: s.root, ..*m })
            .collect();
        st.moving_meshes = swept.iter().filter(|s| s.moves()).count();
        st.sweep_nanos = nanos_since(t);
        let t = Instant::now();
        let mut lps = std::mem::take(&mut self.leaf_pairs);
        cont::leaf_pairs(&list, swept, d, &mut self.continuous_broad, &mut lps);
        st.leaf_pairs = lps.len();
        st.broad_nanos = nanos_since(t);
        let mut found = self.narrow_shared(&list, &lps, d, &mut st);
        self.leaf_pairs = lps;
        let t = Instant::now();
        found.sort_unstable_by_key(|(i, _)| i.key());
        try_reserve(out, found.len(), "the continuous query's pairs")?;
        try_reserve(firsts, found.len(), "the continuous query's pairs")?;
        out.extend(found.iter().map(|f| f.0));
        firsts.extend(found.iter().map(|f| f.1));
        st.found = out.len();
        st.merge_nanos = nanos_since(t);
        st.total_nanos = nanos_since(start);
        self.continuous_stats = st;
        Ok(())
    }

    /// Every listed mesh's step into `self.swept` (one per mesh, on the workers when the
    /// pool runs and there are several).
    fn make_swept(&mut self, list: &[SceneMesh<'_>], d: f64) {
        if self.swept.len() < list.len() {
            self.swept.resize_with(list.len(), Default::default);
        }
        let swept = &mut self.swept[..list.len()];
        match &self.workers.pool {
            Some(pool) if list.len() > 1 => pool.install(|| {
                use rayon::prelude::*;
                swept
                    .par_iter_mut()
                    .zip(list)
                    .for_each(|(s, m)| s.make(m.mesh, d))
            }),
            _ => swept
                .iter_mut()
                .zip(list)
                .for_each(|(s, m)| s.make(m.mesh, d)),
        }
    }

    /// The narrow phase of leaf pairs `lps`, in runs shared out over the workers; the
    /// pairs found (unsorted), the workers' counts into `st`.
    fn narrow_shared(
        &self,
        list: &[SceneMesh<'_>],
        lps: &[LeafPair],
        d: f64,
        st: &mut ContinuousStats,
    ) -> Vec<(Impact, First)> {
        let swept = &self.swept[..list.len()];
        let run = |chunk: &[LeafPair]| {
            let t = Instant::now();
            let mut out = Vec::new();
            let mut s = ContinuousStats::default();
            cont::narrow(list, swept, chunk, d, &mut out, &mut s);
            s.narrow_nanos = nanos_since(t);
            (out, s)
        };
        let parts: Vec<(Vec<(Impact, First)>, ContinuousStats)> = match &self.workers.pool {
            Some(pool) if lps.len() > LEAF_PAIRS_PER_TASK => pool.install(|| {
                use rayon::prelude::*;
                lps.par_chunks(LEAF_PAIRS_PER_TASK).map(run).collect()
            }),
            _ => vec![run(lps)],
        };
        let mut found = Vec::with_capacity(parts.iter().map(|p| p.0.len()).sum());
        for (f, s) in parts {
            st.add_worker(&s);
            found.extend(f);
        }
        found
    }

    /// Counts and times of the last continuous query.
    pub fn continuous_stats(&self) -> ContinuousStats {
        self.continuous_stats
    }
}
