//! The backends: the one question every backend answers, "which of these primitives lie in
//! this viewing volume?" (paper section 2.2), and the backends that answer it.
//!
//! A backend answers a query in one of two ways ([`Engine`]):
//! - [`Engine::Steps`]: it answers each step's [`Batch`] and [`crate::query::run`] sequences
//!   the five steps (GL_SELECT, the paper's method);
//! - [`Engine::Whole`]: it runs all five steps itself (the CPU backend, leaf pair by leaf
//!   pair; GL_COMPUTE, on the GPU with one read-back).
//!
//! A [`Batch`] is a list of groups; a group pairs a run of volumes with a run of candidates,
//! and every volume of the group is asked about every candidate of the group. A hit names
//! the volume and the candidate by their positions in the batch.
//!
//! [`create`] makes the backend a scene asks for. The module depends on `geom`, `mesh` and
//! `gpu`, never on `query`, `scene` or `ffi`.

#[cfg(any(test, feature = "internals"))]
pub(crate) mod brute;
pub(crate) mod cpu;
mod gl_compute;
mod gl_select;

pub use cpu::{CpuSelector, LeafPairs};
pub use gl_compute::GlComputeSelector;
pub use gl_select::GlSelectSelector;

use std::collections::BTreeMap;

use crate::error::{Error, ErrorKind, Result};
use crate::gpu::{unavailable, Gl, Lookup};
use crate::mesh::Mesh;

/// One colliding polygon pair, in the caller's numbering.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Contact {
    /// Id of the other mesh (first: contacts sort by mesh, then by the polygons).
    pub other_mesh: u32,
    /// Polygon index in the reference mesh.
    pub reference_polygon: u32,
    /// Polygon index in the other mesh.
    pub other_polygon: u32,
}

/// One colliding polygon pair of a whole-scene query: `(mesh_a, polygon_a) < (mesh_b,
/// polygon_b)`; pairs sort by (mesh_a, polygon_a, mesh_b, polygon_b).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Pair {
    /// The lower mesh id.
    pub mesh_a: u32,
    /// Polygon index in `mesh_a`.
    pub polygon_a: u32,
    /// The higher mesh id (or `mesh_a` for a self-collision pair).
    pub mesh_b: u32,
    /// Polygon index in `mesh_b` (above `polygon_a` when the meshes are one).
    pub polygon_b: u32,
}

/// How much each step asked and found in the last query.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct QueryStats {
    /// Volume-candidate tests asked for, steps 1 to 5.
    pub tests: [usize; 5],
    /// Hits returned, steps 1 to 5.
    pub hits: [usize; 5],
    /// Time the backend took for each step, nanoseconds (a backend that runs the whole
    /// query at once may report all of it under step 1; a query shared out between worker
    /// threads reports the sum over the workers).
    pub nanos: [u64; 5],
    /// GL read-backs (buffer reads or maps that wait for the GPU) the query made.
    pub readbacks: u32,
}

/// The one list of backends. `with_backends!(m)` expands to `m! { /// doc \n Name, ... }`:
/// [`Backend`] and [`BackendRequest`] are declared from it below, and the C API (`ffi`) derives its
/// value mapping from it, so no second list can drift from this one.
macro_rules! with_backends {
    ($m:ident) => {
        $m! {
            /// The CPU: exact predicates and `f64` clipping (needs no GL).
            Cpu,
            /// The GL's selection mode, as in the paper (GL_SELECT).
            GlSelect,
            /// GL compute dispatches (GL_COMPUTE).
            GlCompute,
        }
    };
}
pub(crate) use with_backends;

macro_rules! declare_backends {
    ($($(#[$doc:meta])* $backend:ident,)*) => {
        /// The backends of the C API.
        #[derive(Clone, Copy, Debug, PartialEq, Eq)]
        pub enum Backend {
            $($(#[$doc])* $backend,)*
        }

        /// The backend asked for at scene creation: AUTO or one of [`Backend`]'s (see
        /// [`Scene::with_backend`](crate::Scene::with_backend)).
        #[derive(Clone, Copy, Debug, PartialEq, Eq)]
        pub enum BackendRequest {
            /// The best available: see [`create`].
            Auto,
            $($(#[$doc])* $backend,)*
        }
    };
}
with_backends!(declare_backends);

/// A box or a polygon of one of the query's meshes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Prim {
    /// Position of the mesh in [`QueryMeshes::meshes`] (0 is the reference).
    pub mesh: u32,
    /// A leaf index, [`ROOT`] for the mesh's root box, or a leaf-ordered polygon index.
    pub index: u32,
}

/// `Prim::index` of a mesh's root box.
pub const ROOT: u32 = u32::MAX;

/// What the volumes and the candidates of a batch are.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Step {
    /// Steps 1 and 2: box volumes, box candidates.
    BoxesInBoxes,
    /// Steps 3 and 4: box volumes, polygon candidates.
    PolygonsInBoxes,
    /// Step 5: polygon viewing volumes (section 2.3), polygon candidates.
    PolygonsInPolygons,
}

/// Every volume in `volumes` against every candidate in `candidates` (ranges into the
/// batch's arrays; groups may share candidate ranges).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Group {
    pub volumes: std::ops::Range<u32>,
    pub candidates: std::ops::Range<u32>,
}

/// One step's question.
#[derive(Clone, Debug)]
pub struct Batch {
    pub step: Step,
    pub volumes: Vec<Prim>,
    pub candidates: Vec<Prim>,
    pub groups: Vec<Group>,
}

impl Batch {
    pub fn new() -> Batch {
        Batch {
            step: Step::BoxesInBoxes,
            volumes: Vec::new(),
            candidates: Vec::new(),
            groups: Vec::new(),
        }
    }

    pub fn reset(&mut self, step: Step) {
        self.step = step;
        self.volumes.clear();
        self.candidates.clear();
        self.groups.clear();
    }

    /// Number of volume-candidate tests the batch asks for.
    pub fn tests(&self) -> usize {
        self.groups
            .iter()
            .map(|g| g.volumes.len() * g.candidates.len())
            .sum()
    }
}

impl Default for Batch {
    fn default() -> Self {
        Batch::new()
    }
}

/// A candidate found in a volume: positions in the batch's `volumes` and `candidates`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub struct Hit {
    pub volume: u32,
    pub candidate: u32,
}

/// The meshes of one query and the viewing-volume depth.
pub struct QueryMeshes<'a> {
    /// The reference mesh first, then the other enabled meshes, each with its id.
    pub meshes: Vec<(u32, &'a Mesh)>,
    /// Half the viewing-volume depth: `epsilon / 2`.
    pub half_depth: f64,
    /// With `half_depth > 0`: a polygon pair is a contact when either polygon meets the
    /// other's viewing volume (whole-scene queries, whose answer must not depend on which
    /// mesh comes first), not only when the other meets the reference's. Backends that
    /// cannot (the GL ones) leave it to the caller to ask both ways.
    pub symmetric: bool,
}

impl QueryMeshes<'_> {
    #[inline]
    pub fn mesh(&self, p: Prim) -> &Mesh {
        self.meshes[p.mesh as usize].1
    }

    /// The half-depth the GL backends use for this query (epsilon raised to their minimum,
    /// [`crate::gpu::min_half_depth`]).
    pub fn gl_half_depth(&self) -> f64 {
        crate::gpu::min_half_depth(self.half_depth, self.meshes.iter().map(|(_, m)| m.root()))
    }

    /// The box a box primitive stands for.
    #[inline]
    pub fn boxed(&self, p: Prim) -> crate::geom::Aabb {
        let m = self.mesh(p);
        if p.index == ROOT {
            m.root()
        } else {
            m.leaf_boxes()[p.index as usize]
        }
    }
}

/// How a backend answers a query.
pub enum Engine<'a> {
    /// It answers each step's batch; [`crate::query::run`] sequences the steps.
    Steps(&'a mut dyn StepQuery),
    /// It runs all five steps itself.
    Whole(&'a mut dyn WholeQuery),
}

/// A backend that answers one step's batch at a time. Hits may come in any order; each
/// (volume, candidate) pair at most once.
pub trait StepQuery {
    /// Appends to `hits` every (volume, candidate) of `batch` where the candidate lies in
    /// the volume.
    fn select(
        &mut self,
        meshes: &QueryMeshes<'_>,
        batch: &Batch,
        hits: &mut Vec<Hit>,
    ) -> Result<()>;
}

/// A backend that runs the five steps itself (the same tests, so the same answer and the
/// same per-step counts as the step-by-step path).
pub trait WholeQuery {
    /// Appends the contacts of `q.meshes[0]` against the others to `out` (each pair once,
    /// any order; the caller sorts them) and fills `stats`.
    fn run_query(
        &mut self,
        q: &QueryMeshes<'_>,
        out: &mut Vec<Contact>,
        stats: &mut QueryStats,
    ) -> Result<()>;
}

/// A backend: how it answers queries, plus what it must hear about the scene's meshes.
pub trait Selector: Send {
    /// Which backend this is.
    fn backend(&self) -> Backend;

    /// How this backend answers a query.
    fn engine(&mut self) -> Engine<'_>;

    /// Called before each query with every mesh of the scene: a GPU backend refreshes what
    /// it holds (meshes whose positions live in a host buffer get their boxes refitted and
    /// written back here).
    fn prepare(&mut self, _meshes: &mut BTreeMap<u32, Mesh>) -> Result<()> {
        Ok(())
    }

    /// Is this the CPU engine itself ([`CpuSelector`])? Then the scene may answer its
    /// reference queries with its workers' own CPU engines (the same answer, shared out).
    fn is_cpu_engine(&self) -> bool {
        false
    }

    /// GL read-backs (reads that wait for the GL) since the last call.
    fn take_readbacks(&mut self) -> u32 {
        0
    }

    /// Mesh `id` got new positions from the CPU.
    fn mesh_updated(&mut self, _id: u32) {}

    /// Mesh `id` was destroyed.
    fn mesh_destroyed(&mut self, _id: u32) {}

    /// From now on mesh `id` reads its positions from the host's GL buffer object
    /// (GL_COMPUTE; the CPU backend when AUTO chose it on a GL context, reading it back at
    /// each query; the others answer Unsupported).
    fn bind_gl_buffer(
        &mut self,
        _id: u32,
        _mesh: &Mesh,
        _buffer: u32,
        _offset: usize,
        _stride: usize,
    ) -> Result<()> {
        Err(Error::new(
            ErrorKind::Unsupported,
            format!(
                "reading positions from a GL buffer needs the GL_COMPUTE backend; this scene runs \
                 on {:?}",
                self.backend()
            ),
        ))
    }

    /// Mesh `id` reads its positions from a host GL buffer (so the CPU has none).
    fn gl_bound(&self, _id: u32) -> bool {
        false
    }

    /// Some mesh reads its positions from a host GL buffer.
    fn any_gl_bound(&self) -> bool {
        false
    }

    /// Contact geometry is about to read the meshes `ids` (those of the last answer): each
    /// one bound to a host GL buffer gets, in its CPU positions, the positions the last
    /// query used. GL_COMPUTE reads back what that query gathered on the GPU (the scene's
    /// context must be current); a CPU scene read the buffers into the meshes at the query
    /// already (nothing to do).
    fn positions_for_geometry(
        &mut self,
        _meshes: &mut BTreeMap<u32, Mesh>,
        _ids: &[u32],
    ) -> Result<()> {
        Ok(())
    }

    /// Deletes the backend's GL objects (the scene's context must be current). Called once,
    /// when the scene is destroyed; dropping without it leaks them (it never calls GL).
    fn release(&mut self) {}
}

/// Makes the backend a scene asks for, loading GL through `loader` for the current context.
/// AUTO: the CPU when there is no loader, no usable context or a software renderer
/// (llvmpipe, softpipe, SwiftShader); GL_COMPUTE on a hardware GL 4.3+ context; the CPU
/// otherwise. A CPU chosen on a GL context keeps its entry points, so that meshes can still
/// be bound to host buffers (read back at each query).
///
/// # Safety
/// `loader`, when given, must load entry points for the calling thread's current context.
pub unsafe fn create(req: BackendRequest, loader: Option<Lookup<'_>>) -> Result<Box<dyn Selector>> {
    let name = match req {
        BackendRequest::Cpu => return Ok(Box::new(CpuSelector::new())),
        BackendRequest::Auto => "AUTO",
        BackendRequest::GlSelect => "GL_SELECT",
        BackendRequest::GlCompute => "GL_COMPUTE",
    };
    let Some(loader) = loader else {
        if req == BackendRequest::Auto {
            return Ok(Box::new(CpuSelector::new()));
        }
        return Err(unavailable(format!(
            "backend {name} needs a GL loader (none was given)"
        )));
    };
    // SAFETY: the caller's contract: `loader` loads for the current context.
    let gl = match unsafe { Gl::load(loader) } {
        Ok(gl) => gl,
        Err(_) if req == BackendRequest::Auto => return Ok(Box::new(CpuSelector::new())),
        Err(e) => return Err(Error::new(e.kind, format!("backend {name}: {}", e.message))),
    };
    match req {
        BackendRequest::Auto if gl.info.software() || !gl.info.compute => {
            Ok(Box::new(CpuSelector::with_gl(gl)))
        }
        BackendRequest::Auto => match GlComputeSelector::new(gl) {
            Ok(s) => Ok(Box::new(s)),
            Err(_) => Ok(Box::new(CpuSelector::new())),
        },
        BackendRequest::GlSelect => Ok(Box::new(GlSelectSelector::new(gl)?)),
        _ => Ok(Box::new(GlComputeSelector::new(gl)?)),
    }
}
