//! The CPU backend: the five steps run leaf pair by leaf pair ([`steps`]), selection
//! semantics computed exactly or in `f64`.
//!
//! Box volumes (steps 1-4) keep a candidate when its box meets the volume grown by `h`
//! (closed, exact comparisons): for polygons that is a superset of what clipping keeps,
//! which only costs step 5 some work. Polygon volumes (step 5) give the final answer
//! ([`Prepared::meets`](crate::geom::polygon::Prepared::meets)):
//! - `h = 0`: the closed polygons intersect, decided by exact predicates;
//! - `h > 0`: the candidate survives clipping against the reference polygon's volume in
//!   `f64` in the volume's own frame, or intersects the polygon exactly (so rounding in the
//!   clipper can never lose a true intersection).
//!
//! Polygon boxes are cached per mesh ([`BoxCache`]) and computed a leaf at a time, once per
//! frame however many leaf pairs ask about them.

mod diag;
pub(crate) mod lanes;
mod steps;

use std::collections::BTreeMap;

use super::{Backend, Contact, Engine, QueryMeshes, QueryStats, Selector, WholeQuery};
use crate::error::{Error, ErrorKind, Result};
use crate::gpu::state::{StateGuard, Uses};
use crate::gpu::{Gl, HostBuffer, HostCheck};
use crate::mesh::{Mesh, Positions};
use lanes::Lanes;
pub use steps::LeafPairs;

/// Polygon boxes of one mesh, computed a whole leaf at a time on first use and valid while
/// the mesh's positions and placement do not change (its generation and pose).
#[derive(Default)]
struct BoxCache {
    id: u32,
    generation: u64,
    pose: u64,
    /// `leaf_stamp[l] == current` marks the boxes of all of leaf `l`'s polygons valid.
    leaf_stamp: Vec<u32>,
    current: u32,
    boxes: Lanes,
}

impl BoxCache {
    fn revalidate(&mut self, id: u32, m: &Mesh) {
        let n = m.polygon_count();
        if self.id != id
            || self.boxes.len() != n
            || self.leaf_stamp.len() != m.leaf_count()
            || self.current == u32::MAX
        {
            self.leaf_stamp.clear();
            self.leaf_stamp.resize(m.leaf_count(), 0);
            self.boxes.resize(n);
            self.current = 1;
        } else if self.generation != m.generation || self.pose != m.pose {
            self.current += 1;
        }
        self.id = id;
        self.generation = m.generation;
        self.pose = m.pose;
    }

    /// Makes the boxes of leaf `l`'s polygons valid; returns their range in `boxes`.
    #[inline]
    fn leaf(&mut self, m: &Mesh, l: usize) -> std::ops::Range<usize> {
        let r = m.leaves.polys(l);
        if self.leaf_stamp[l] != self.current {
            self.boxes.fit_polygons(m, r.clone());
            self.leaf_stamp[l] = self.current;
        }
        r
    }
}

/// The CPU backend. Holds scratch space and the polygon-box caches.
#[derive(Default)]
pub struct CpuSelector {
    scratch: steps::Scratch,
    caches: Vec<BoxCache>,
    /// Mesh id -> index in `caches`.
    cache_of: std::collections::HashMap<u32, usize>,
    /// Query mesh slot -> index in `caches`.
    slot_cache: Vec<usize>,
    /// AUTO chose the CPU on a GL context: meshes may read their positions from the host's
    /// buffer objects, read back at each query.
    host: Option<Box<HostPositions>>,
}

/// Host buffers a CPU scene reads back (meshes bound to GL buffers under AUTO).
struct HostPositions {
    /// The GL of the context AUTO was created in; its sentinel is made at the first bind.
    gl: Gl,
    bound: BTreeMap<u32, HostBuffer>,
    /// Scratch for the bytes read back.
    bytes: Vec<u8>,
}

/// The state reading a buffer back touches (the COPY_READ_BUFFER binding, common state).
const READ_BACK: Uses = Uses {
    fixed_function: false,
    indexed_bindings: 0,
};

impl CpuSelector {
    /// A CPU backend with empty caches.
    pub fn new() -> CpuSelector {
        CpuSelector::default()
    }

    /// A CPU backend that AUTO chose on a GL context (software renderer, or GL below 4.3):
    /// it can also read meshes' positions from the host's buffer objects.
    pub fn with_gl(gl: Gl) -> CpuSelector {
        CpuSelector {
            host: Some(Box::new(HostPositions {
                gl,
                bound: BTreeMap::new(),
                bytes: Vec::new(),
            })),
            ..CpuSelector::default()
        }
    }

    /// Maps the query's meshes to their caches (made or revalidated). A cache lives until
    /// its mesh is destroyed, so queries over different mesh pairs reuse each other's boxes.
    fn sync_caches(&mut self, q: &QueryMeshes<'_>) {
        self.slot_cache.clear();
        for &(id, m) in &q.meshes {
            let caches = &mut self.caches;
            let i = *self.cache_of.entry(id).or_insert_with(|| {
                caches.push(BoxCache::default());
                caches.len() - 1
            });
            self.caches[i].revalidate(id, m);
            self.slot_cache.push(i);
        }
    }
}

impl CpuSelector {
    /// A run of the query `q` over this selector's caches (synchronised with `q` first).
    fn start<'a, 'q>(
        &'a mut self,
        q: &'a QueryMeshes<'q>,
        stats: &'a mut QueryStats,
    ) -> steps::Run<'a, 'q> {
        self.sync_caches(q);
        steps::Run {
            q,
            h: q.half_depth,
            s: &mut self.scratch,
            caches: &mut self.caches,
            slot_cache: &self.slot_cache,
            stats,
        }
    }

    /// Steps 1 and 2 of the query `q`: its leaf pairs into `lp`, the counts and times of
    /// those steps into `stats` (the rest zeroed).
    pub fn leaf_pairs(&mut self, q: &QueryMeshes<'_>, lp: &mut LeafPairs, stats: &mut QueryStats) {
        *stats = QueryStats::default();
        let mut run = self.start(q, stats);
        run.leaf_pairs(lp);
    }

    /// Steps 3 to 5 of the query `q` on the leaf pairs `lp.pairs[range]` (from
    /// [`CpuSelector::leaf_pairs`] of the same query, on any selector): their contacts
    /// appended to `out` (each once, any order), the counts and times of steps 3 to 5 into
    /// `stats` (the rest zeroed, but for step 2's hits: the pairs taken). The contacts of
    /// disjoint ranges covering all pairs are the query's.
    pub fn some_pairs(
        &mut self,
        q: &QueryMeshes<'_>,
        lp: &LeafPairs,
        range: std::ops::Range<usize>,
        out: &mut Vec<Contact>,
        stats: &mut QueryStats,
    ) {
        *stats = QueryStats::default();
        let mut run = self.start(q, stats);
        run.some_pairs(lp, range, out);
    }
}

impl std::fmt::Debug for CpuSelector {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("CpuSelector")
    }
}

impl Selector for CpuSelector {
    fn backend(&self) -> Backend {
        Backend::Cpu
    }

    fn engine(&mut self) -> Engine<'_> {
        Engine::Whole(self)
    }

    /// Bound meshes: checks each buffer and reads it back into the mesh (a sync point:
    /// glGetBufferSubData waits for the host's GPU work on it), inside a state guard that
    /// first checks the scene's context is current.
    fn prepare(&mut self, meshes: &mut BTreeMap<u32, Mesh>) -> Result<()> {
        let Some(h) = self.host.as_deref_mut() else {
            return Ok(());
        };
        if h.bound.is_empty() {
            return Ok(());
        }
        let HostPositions { gl, bound, bytes } = h;
        let guard = StateGuard::enter(gl, READ_BACK)?;
        let mut read = || -> Result<()> {
            for (&id, hb) in bound.iter() {
                let Some(m) = meshes.get_mut(&id).filter(|m| m.enabled) else {
                    continue;
                };
                hb.check(gl, HostCheck::Use(id))?;
                hb.read(gl, bytes)?;
                let pos = Positions::new(bytes, m.vertex_count(), hb.stride as usize)?;
                if let Some(v) = pos.first_non_finite() {
                    return Err(Error::new(
                        ErrorKind::NonFinite,
                        format!(
                            "mesh {id}: its bound GL buffer holds a NaN or infinite coordinate \
                             (vertex {v})"
                        ),
                    ));
                }
                m.refresh_positions(pos)?;
            }
            Ok(())
        };
        let r = read();
        let done = guard.finish();
        r?;
        done
    }

    fn bind_gl_buffer(
        &mut self,
        id: u32,
        mesh: &Mesh,
        buffer: u32,
        offset: usize,
        stride: usize,
    ) -> Result<()> {
        let Some(h) = self.host.as_deref_mut() else {
            return Err(Error::new(
                ErrorKind::Unsupported,
                "reading positions from a GL buffer needs backend GL_COMPUTE, or AUTO with a GL \
                 loader; this scene was asked for the CPU backend",
            ));
        };
        let hb = HostBuffer::new(buffer, offset, stride, mesh.vertex_count())?;
        // The context current at the first bind becomes the scene's (checked from then on).
        if !h.gl.adopted() {
            h.gl.adopt_context(READ_BACK)?;
        }
        let guard = StateGuard::enter(&h.gl, READ_BACK)?;
        let r = hb.check(&h.gl, HostCheck::Bind);
        let done = guard.finish();
        r?;
        done?;
        h.bound.insert(id, hb);
        Ok(())
    }

    fn gl_bound(&self, id: u32) -> bool {
        self.host
            .as_ref()
            .is_some_and(|h| h.bound.contains_key(&id))
    }

    fn any_gl_bound(&self) -> bool {
        self.host.as_ref().is_some_and(|h| !h.bound.is_empty())
    }

    fn mesh_updated(&mut self, id: u32) {
        if let Some(h) = self.host.as_deref_mut() {
            h.bound.remove(&id);
        }
    }

    fn release(&mut self) {
        if let Some(h) = self.host.as_deref_mut() {
            h.gl.release_sentinel();
        }
    }

    fn is_cpu_engine(&self) -> bool {
        true
    }

    fn mesh_destroyed(&mut self, id: u32) {
        if let Some(h) = self.host.as_deref_mut() {
            h.bound.remove(&id);
        }
        if let Some(i) = self.cache_of.remove(&id) {
            self.caches.swap_remove(i);
            if let Some(moved) = self.caches.get(i) {
                self.cache_of.insert(moved.id, i);
            }
        }
    }
}

impl WholeQuery for CpuSelector {
    fn run_query(
        &mut self,
        q: &QueryMeshes<'_>,
        out: &mut Vec<Contact>,
        stats: &mut QueryStats,
    ) -> Result<()> {
        let mut run = self.start(q, stats);
        run.all(out);
        Ok(())
    }
}
