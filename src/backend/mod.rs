//! The one question every backend answers: "which of these primitives lie in this viewing
//! volume?" (paper section 2.2), asked in batches so a GPU backend can answer a whole step
//! in one dispatch.
//!
//! A [`Batch`] is a list of groups; a group pairs a run of volumes with a run of candidates,
//! and every volume of the group is asked about every candidate of the group. A hit names
//! the volume and the candidate by their positions in the batch.

pub mod cpu;
pub mod gl_compute;
pub mod gl_select;

use std::collections::BTreeMap;

use crate::error::{Error, ErrorKind, Result};
use crate::mesh::Mesh;
use crate::query::{Contact, QueryStats};

/// The backends of the C API.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Backend {
    Cpu,
    GlSelect,
    GlCompute,
}

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
}

impl QueryMeshes<'_> {
    #[inline]
    pub fn mesh(&self, p: Prim) -> &Mesh {
        self.meshes[p.mesh as usize].1
    }

    /// The box a box primitive stands for.
    #[inline]
    pub fn boxed(&self, p: Prim) -> crate::geom::Aabb {
        let m = self.mesh(p);
        if p.index == ROOT {
            m.leaves.root
        } else {
            m.leaves.boxes[p.index as usize]
        }
    }
}

/// A way of answering batches. Hits may come in any order; each (volume, candidate) pair
/// at most once.
pub trait Selector: Send {
    fn backend(&self) -> Backend;
    fn select(
        &mut self,
        meshes: &QueryMeshes<'_>,
        batch: &Batch,
        hits: &mut Vec<Hit>,
    ) -> Result<()>;

    /// Called before each query with every mesh of the scene: a GPU backend refreshes what
    /// it holds (meshes whose positions live in a host buffer get their boxes refitted and
    /// written back here).
    fn prepare(&mut self, _meshes: &mut BTreeMap<u32, Mesh>) -> Result<()> {
        Ok(())
    }

    /// Runs all five steps itself (a GPU backend that keeps every step's output on the GPU
    /// and reads back only the answer): appends the contacts to `out` (any order; the caller
    /// sorts them) and fills `stats`. `Ok(false)`: not supported, ask step by step through
    /// [`Selector::select`].
    fn run_query(
        &mut self,
        _q: &QueryMeshes<'_>,
        _out: &mut Vec<Contact>,
        _stats: &mut QueryStats,
    ) -> Result<bool> {
        Ok(false)
    }

    /// GL read-backs (reads that wait for the GL) since the last call.
    fn take_readbacks(&mut self) -> u32 {
        0
    }

    /// Mesh `id` got new positions from the CPU.
    fn mesh_updated(&mut self, _id: u32) {}

    /// Mesh `id` was destroyed.
    fn mesh_destroyed(&mut self, _id: u32) {}

    /// From now on mesh `id` reads its positions from the host's GL buffer object (GL
    /// backends that can; the others answer Unsupported).
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
                "glcol_mesh_bind_gl_buffer needs the GL_COMPUTE backend; this scene runs on {:?}",
                self.backend()
            ),
        ))
    }

    /// Deletes the backend's GL objects (the scene's context must be current). Called once,
    /// by `glcol_scene_destroy`; dropping without it leaks them (it never calls GL).
    fn release(&mut self) {}
}
