//! The GL_COMPUTE backend: the five steps as compute dispatches (GL 4.3+, core or
//! compatibility).
//!
//! - Every mesh's positions live in one buffer object (an arena of xyz floats, all meshes),
//!   uploaded when a mesh's positions change, or gathered on the GPU from the host's own
//!   buffer object ([`crate::Scene::bind_gl_buffer`]: no copy through the CPU).
//! - The whole query runs on the GPU ([`WholeQuery::run_query`], shaders/query.glsl), one
//!   thread per test in every step: step 1 over the other meshes' leaves, step 2 over (step-1
//!   hit, reference leaf), steps 3-4 and 5 over the tests of each leaf pair, counted by a scan
//!   over the pairs on the GPU and dispatched indirectly. Each step appends through atomic
//!   counters into buffers the next step reads; the CPU reads one buffer once, at the end (a
//!   header of counters, then the step-5 hits). When an answer outgrows a buffer (the
//!   counters keep counting), the buffers grow to fit and the query runs again:
//!   `QueryStats::readbacks` counts both.
//! - Leaf boxes: the CPU's refit is uploaded with the positions (24 bytes a leaf), roots
//!   and the half depth come from the CPU. When a mesh of the query reads a host buffer,
//!   its leaves are refitted on the GPU (one thread per leaf), its root reduced with
//!   atomics, the half depth raised on the GPU to 2^-20 of the largest root extent, and a
//!   NaN or infinity names the mesh in the result.
//! - Limits: room past `GL_MAX_SHADER_STORAGE_BLOCK_SIZE` is refused (OUT_OF_MEMORY)
//!   before anything is allocated; a step of 2^31 tests or more (UNSUPPORTED) before it is
//!   dispatched; every byte size and offset is computed with checked arithmetic
//!   ([`gl_bytes`](crate::gpu::gl_bytes)).
//! - Box tests are padded (float rounding can only add pairs); the polygon viewing volume
//!   of step 5 is clipped in double precision in a frame local to the reference polygon.
//!   When every mesh of the query has its positions on the CPU too, each step-5 hit is
//!   confirmed with the CPU backend's test, so the answer equals the CPU backend's; with
//!   buffer-bound meshes the GPU's answer is final (extras within epsilon / 2 + 2^-40 of
//!   the local size).
//!
//! Borrows: the state guard borrows the selector's [`Gl`] while the work runs on the rest of
//! it ([`Compute`]), two disjoint fields ([`GlComputeSelector::guarded`]).
//!
//! # The files
//!
//! * `mod.rs`: the selector and its state (the buffers' indices and shader bindings, the
//!   result header's words, where each mesh lives, the room), its creation and state
//!   guard, and the backend's [`Selector`] face.
//! * `objects.rs`: the GL side: what the kernels need of the GL, the programs compiled and
//!   the buffers made, and the plain calls every stage makes (upload, allocate, uniforms,
//!   dispatch).
//! * `arena.rs`: the meshes laid out in the arenas, their positions and leaf boxes
//!   uploaded before each query.
//! * `bound.rs`: meshes reading a host's buffer: checked, gathered into the arena on the
//!   GPU, read back for contact geometry.
//! * `steps.rs`: one query: its plan, the buffers sized for its room, the kernels
//!   dispatched, run again until the answer fits.
//! * `results.rs`: the one read-back, the header's failures, the hits as contacts.

#![deny(unsafe_op_in_unsafe_fn)]

use std::collections::BTreeMap;

use glow::HasContext;

use super::{Backend, Contact, Engine, QueryMeshes, QueryStats, Selector, WholeQuery};
use crate::error::{Error, ErrorKind, Result};
use crate::gpu::state::{StateGuard, Uses};
use crate::gpu::{Gl, HostBuffer, HostCheck};
use crate::mesh::Mesh;

mod arena;
mod bound;
mod objects;
mod results;
mod steps;

use objects::{capabilities, create_objects};

/// Indexed buffer bindings the shaders use (0..BINDINGS).
const BINDINGS: u32 = 12;
/// Shader storage blocks the busiest kernel uses.
const BLOCKS: u32 = 7;
/// Threads per work group (`local_size_x` in common.glsl).
const GROUP: u32 = 64;

/// The state the guard saves around our work: the common state and our indexed bindings.
const USES: Uses = Uses {
    fixed_function: false,
    indexed_bindings: BINDINGS,
};

const POS: usize = 0;
const POLYS: usize = 1;
const LEAF_RANGE: usize = 2;
const LEAF_VERTS: usize = 3;
const BOXES: usize = 4;
/// First and end global polygon of each global leaf.
const LEAF_POLYS: usize = 5;
/// (first global leaf, leaves, first thread) of each other mesh.
const OTHERS: usize = 6;
/// Step-1 hits (global leaf ids).
const L1: usize = 7;
/// Leaf pairs (8 words each).
const PAIRS: usize = 8;
/// Each pair's step-3 and step-4 polygon lists.
const LISTS: usize = 9;
/// A 64-word header of counters, then the step-5 hits.
const RESULT: usize = 10;
/// Root box keys per mesh of the arena.
const ROOTS: usize = 11;
const NBUF: usize = 12;
/// Shader binding of each buffer (the roots share gather's binding 8).
const BINDING: [u32; NBUF] = [0, 1, 7, 8, 9, 10, 11, 2, 3, 4, 5, 8];
/// Shader binding of the host's source buffer (gather.glsl).
const SRC_BINDING: u32 = 6;
/// Words of the result header.
const HEADER: usize = 64;
/// Header words (query.glsl's `Result` block).
const H_NONFINITE: usize = 0;
const H_L1: usize = 1;
const H_PAIRS: usize = 2;
const H_LIST: usize = 3;
const H_HITS: usize = 4;
const H_TESTS3: usize = 5;
const H_TESTS4: usize = 6;
const H_HITS3: usize = 7;
const H_HITS4: usize = 8;
const H_TOTAL5: usize = 10;
const H_TOO_MANY: usize = 11;
const H_HALF_DEPTH: usize = 12;
/// Header words of the indirect dispatch sizes of steps 2, 3-4 and 5.
const H_ARGS: [u32; 3] = [24, 28, 32];
/// Box padding relative to the local size (`u_pad_rel`): 2^-40.
const PAD_REL: f32 = 1.0 / (1u64 << 40) as f32;

/// Where a mesh lives in the arenas.
#[derive(Clone, Debug, PartialEq)]
struct Slot {
    /// Position in the arenas' mesh order.
    index: u32,
    vertex_base: u32,
    poly_base: u32,
    leaf_base: u32,
    vertices: u32,
    leaves: u32,
    polys: u32,
    /// `Mesh::generation` last uploaded (None: must upload).
    uploaded: Option<u64>,
}

/// A host buffer a mesh reads its positions from, in floats (gather.glsl's units).
#[derive(Clone, Copy, Debug)]
struct Bound {
    /// The buffer and its layout, in bytes (checked at every query).
    host: HostBuffer,
    offset: u32,
    stride: u32,
}

struct Objects {
    gather: glow::NativeProgram,
    /// The kernels of query.glsl.
    query: Kernels,
    /// See the buffer constants (POS ... ROOTS).
    buffers: [glow::NativeBuffer; NBUF],
}

/// query.glsl compiled once per `KERNEL` (1 to 6, in this order).
#[derive(Clone, Copy)]
struct Kernels {
    refit: glow::NativeProgram,
    step1: glow::NativeProgram,
    sizes: glow::NativeProgram,
    step2: glow::NativeProgram,
    step34: glow::NativeProgram,
    step5: glow::NativeProgram,
}

impl Kernels {
    fn all(&self) -> [glow::NativeProgram; 6] {
        [
            self.refit,
            self.step1,
            self.sizes,
            self.step2,
            self.step34,
            self.step5,
        ]
    }
}

/// Room in the query's buffers (entries); grown when a query's answer needs more.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Caps {
    pairs: u32,
    lists: u32,
    hits: u32,
}

impl Default for Caps {
    fn default() -> Caps {
        Caps {
            pairs: 1 << 14,
            lists: 1 << 20,
            hits: 1 << 16,
        }
    }
}

/// The GL_COMPUTE backend.
pub struct GlComputeSelector {
    gl: Gl,
    st: Compute,
}

/// Everything of the backend but its GL entry points, so that the state guard can borrow
/// the one while the work borrows the other.
struct Compute {
    obj: Option<Objects>,
    slots: BTreeMap<u32, Slot>,
    bound: BTreeMap<u32, Bound>,
    /// Bound meshes whose positions the last query gathered into the arena (what contact
    /// geometry reads back); emptied by each `prepare` and by `distrust`.
    gathered: std::collections::BTreeSet<u32>,
    caps: Caps,
    /// GL_MAX_SHADER_STORAGE_BLOCK_SIZE, bytes.
    max_block: u64,
    /// Read-backs since `take_readbacks`.
    readbacks: u32,
    /// Capacities the GPU buffers were last sized for, and the step-1 room (None: never).
    sized: Option<(Caps, u32)>,
    /// Scratch for the leaf boxes of a mesh.
    box_words: Vec<f32>,
}

impl GlComputeSelector {
    /// Needs GL 4.3+ (compute shaders, SSBOs, double precision: see
    /// [`crate::gpu::compute_gl_version`]) and the context current on this thread.
    pub fn new(mut gl: Gl) -> Result<GlComputeSelector> {
        let max_block = capabilities(&gl)?;
        gl.adopt_context(USES)?;
        let mut s = GlComputeSelector {
            gl,
            st: Compute {
                obj: None,
                slots: BTreeMap::new(),
                bound: BTreeMap::new(),
                gathered: std::collections::BTreeSet::new(),
                caps: Caps::default(),
                max_block,
                readbacks: 0,
                sized: None,
                box_words: Vec::new(),
            },
        };
        let made = s.guarded(|gl, st| {
            // SAFETY: `gl` is loaded for the context current on this thread (this
            // function's contract, as every GL-backed call's).
            st.obj = Some(unsafe { create_objects(&gl.gl) }?);
            Ok(())
        });
        if let Err(e) = made {
            s.release(); // objects made before the guard reported an error
            return Err(e);
        }
        Ok(s)
    }

    /// Runs `work` between saving the host's GL state and restoring it: the guard borrows
    /// `self.gl` while `work` gets the GL and the rest of the selector as separate borrows.
    /// `work`'s error comes first, then the guard's (a GL error of ours). The guard refuses
    /// (changing nothing) when the scene's context is not current. After a failure
    /// nothing the failed work may have half-made is trusted: the next query lays the
    /// arenas out, uploads every position and sizes its buffers afresh.
    fn guarded<R>(&mut self, work: impl FnOnce(&Gl, &mut Compute) -> Result<R>) -> Result<R> {
        let guard = StateGuard::enter(&self.gl, USES)?;
        let r = work(&self.gl, &mut self.st);
        let done = guard.finish();
        if r.is_err() || done.is_err() {
            self.st.distrust();
        }
        let r = r?;
        done.map(|()| r)
    }

    #[cfg(any(test, feature = "internals"))]
    /// Room the query's buffers start from (leaf pairs, step-3/4 list words, step-5 hits);
    /// they grow when a query needs more. For tests of the growth path.
    pub fn set_room(&mut self, pairs: u32, lists: u32, hits: u32) {
        self.st.caps = Caps {
            pairs: pairs.max(1),
            lists: lists.max(1),
            hits: hits.max(1),
        };
    }
}

impl Compute {
    /// Forgets what the GL buffers were last known to hold.
    fn distrust(&mut self) {
        self.slots.clear();
        self.gathered.clear();
        self.sized = None;
    }

    fn objects(&self) -> &Objects {
        self.obj.as_ref().expect("GL objects exist until release")
    }
}

impl WholeQuery for GlComputeSelector {
    fn run_query(
        &mut self,
        q: &QueryMeshes<'_>,
        out: &mut Vec<Contact>,
        stats: &mut QueryStats,
    ) -> Result<()> {
        self.guarded(|gl, st| st.query(gl, q, out, stats))
    }
}

impl Selector for GlComputeSelector {
    fn backend(&self) -> Backend {
        Backend::GlCompute
    }

    fn prepare(&mut self, meshes: &mut BTreeMap<u32, Mesh>) -> Result<()> {
        self.guarded(|gl, st| st.prepare(gl, meshes))
    }

    fn engine(&mut self) -> Engine<'_> {
        Engine::Whole(self)
    }

    fn take_readbacks(&mut self) -> u32 {
        std::mem::take(&mut self.st.readbacks)
    }

    fn mesh_updated(&mut self, id: u32) {
        self.st.bound.remove(&id);
        if let Some(s) = self.st.slots.get_mut(&id) {
            s.uploaded = None;
        }
    }

    fn mesh_destroyed(&mut self, id: u32) {
        self.st.bound.remove(&id);
    }

    fn gl_bound(&self, id: u32) -> bool {
        self.st.bound.contains_key(&id)
    }

    fn any_gl_bound(&self) -> bool {
        !self.st.bound.is_empty()
    }

    fn positions_for_geometry(
        &mut self,
        meshes: &mut BTreeMap<u32, Mesh>,
        ids: &[u32],
    ) -> Result<()> {
        let bound: Vec<u32> = ids
            .iter()
            .copied()
            .filter(|id| self.st.bound.contains_key(id))
            .collect();
        if bound.is_empty() {
            return Ok(());
        }
        self.guarded(|gl, st| {
            for id in bound {
                let m = meshes.get_mut(&id).ok_or_else(|| {
                    Error::new(
                        ErrorKind::Internal,
                        format!("mesh {id} of the answer is gone"),
                    )
                })?;
                st.read_gathered(gl, id, m)?;
            }
            Ok(())
        })
    }

    fn bind_gl_buffer(
        &mut self,
        id: u32,
        mesh: &Mesh,
        buf: u32,
        offset: usize,
        stride: usize,
    ) -> Result<()> {
        let host = HostBuffer::new(buf, offset, stride, mesh.vertex_count())?;
        // gather.glsl indexes the host's buffer in 32-bit float units.
        let floats = |n: u64| u32::try_from(n / 4).ok();
        let (Some(_), Some(offset), Some(stride)) =
            (floats(host.need), floats(host.offset), floats(host.stride))
        else {
            return Err(Error::new(
                ErrorKind::Unsupported,
                format!(
                    "gl_buffer {buf}: {} bytes at offset {}, stride {} reach past the 16 GiB \
                     the shaders address with 32-bit indices",
                    host.need, host.offset, host.stride
                ),
            ));
        };
        self.guarded(|gl, _| host.check(gl, HostCheck::Bind))?;
        self.st.bound.insert(
            id,
            Bound {
                host,
                offset,
                stride,
            },
        );
        Ok(())
    }

    fn release(&mut self) {
        if self.gl.check_current().is_err() {
            // Not the scene's context: deleting our names here could delete a host's
            // objects. Ours are left (leaked) rather than risk that.
            self.st.obj = None;
            return;
        }
        let Some(o) = self.st.obj.take() else {
            self.gl.release_sentinel();
            return;
        };
        // Our objects are bound nowhere between calls (the guard gave every binding back),
        // so deleting them changes no host state: done even when the guard refuses (say,
        // the host's transform feedback is running), rather than leaked.
        {
            let guard = StateGuard::enter(&self.gl, USES).ok();
            let g = &self.gl.gl;
            // SAFETY: the scene's context (or one sharing its objects) is current (checked
            // above); the objects are ours, made by `create_objects` and deleted once (`obj`
            // was taken).
            unsafe {
                for p in std::iter::once(o.gather).chain(o.query.all()) {
                    g.delete_program(p);
                }
                for b in o.buffers {
                    g.delete_buffer(b);
                }
            }
            if let Some(guard) = guard {
                let _ = guard.finish();
            }
        }
        self.gl.release_sentinel();
    }
}
