//! The GL_COMPUTE backend: the five steps as compute dispatches (GL 4.3+, core or
//! compatibility).
//!
//! - Every mesh's positions live in one buffer object (an arena of xyz floats, all meshes),
//!   uploaded when a mesh's positions change, or gathered on the GPU from the host's own
//!   buffer object (`glcol_mesh_bind_gl_buffer`: no copy through the CPU).
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
//!   ([`gl_bytes`]).
//! - Box tests are padded (float rounding can only add pairs); the polygon viewing volume
//!   of step 5 is clipped in double precision in a frame local to the reference polygon.
//!   When every mesh of the query has its positions on the CPU too, each step-5 hit is
//!   confirmed with the CPU backend's test, so the answer equals the CPU backend's; with
//!   buffer-bound meshes the GPU's answer is final (extras within epsilon / 2 + 2^-40 of
//!   the local size).
//!
//! Borrows: the state guard borrows the selector's [`Gl`] while the work runs on the rest of
//! it ([`Compute`]), two disjoint fields ([`GlComputeSelector::guarded`]).

#![deny(unsafe_op_in_unsafe_fn)]

use std::collections::BTreeMap;

use glow::HasContext;

use super::{Backend, Contact, Engine, QueryMeshes, QueryStats, Selector, WholeQuery};
use crate::error::{Error, ErrorKind, Result};
use crate::geom::polygon::polygon_meets;
use crate::geom::sortable_key;
use crate::gpu::state::{StateGuard, Uses};
use crate::gpu::{buffer, gl_bytes, gl_err, shaders, unavailable, Gl, HostBuffer, HostCheck};
use crate::mesh::Mesh;

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

/// Types whose every bit pattern is a value and which have no padding.
trait Plain: Copy {}
impl Plain for u32 {}
impl Plain for f32 {}
impl Plain for [f32; 3] {}

fn bytes<T: Plain>(v: &[T]) -> &[u8] {
    // SAFETY: `T` is plain data without padding (`Plain`), so its bytes are initialized; the
    // slice covers exactly `v`'s memory, borrowed for as long as `v`.
    unsafe { std::slice::from_raw_parts(v.as_ptr().cast(), std::mem::size_of_val(v)) }
}

/// Compiles common.glsl, meets.glsl when the kernel tests primitives, and `body` (source
/// string numbers in the GL's log: 0 common, 1 meets, 2 body). Deletes the shader, and the
/// program when it does not link.
///
/// # Safety
/// `g` was loaded for the context current on this thread.
unsafe fn compile(
    g: &glow::Context,
    name: &str,
    body: &str,
    meets: bool,
) -> Result<glow::NativeProgram> {
    let meets = if meets { shaders::MEETS } else { "" };
    let src = format!("{}\n#line 1 1\n{meets}\n#line 1 2\n{body}", shaders::COMMON);
    let refused = |what: &str, log: String| {
        unavailable(format!(
            "the {name} compute shader does not {what} here: {log}"
        ))
    };
    // SAFETY: the caller's contract; the shader and program are ours, made here.
    unsafe {
        let sh = g.create_shader(glow::COMPUTE_SHADER).map_err(gl_err)?;
        g.shader_source(sh, &src);
        g.compile_shader(sh);
        if !g.get_shader_compile_status(sh) {
            let log = g.get_shader_info_log(sh);
            g.delete_shader(sh);
            return Err(refused("compile", log));
        }
        let p = match g.create_program() {
            Ok(p) => p,
            Err(e) => {
                g.delete_shader(sh);
                return Err(gl_err(e));
            }
        };
        g.attach_shader(p, sh);
        g.link_program(p);
        g.detach_shader(p, sh);
        g.delete_shader(sh);
        if !g.get_program_link_status(p) {
            let log = g.get_program_info_log(p);
            g.delete_program(p);
            return Err(refused("link", log));
        }
        Ok(p)
    }
}

/// Compiles the kernels and creates the buffers; on a failure deletes what it made.
///
/// # Safety
/// `g` was loaded for the context current on this thread.
unsafe fn create_objects(g: &glow::Context) -> Result<Objects> {
    let mut programs = Vec::new();
    let mut buffers = Vec::new();
    // SAFETY: the caller's contract; every object is ours, made here.
    let made = (|| unsafe {
        programs.push(compile(g, "gather", shaders::GATHER, false)?);
        for k in 1..=6 {
            let body = format!("#define KERNEL {k}\n#line 1 2\n{}", shaders::QUERY);
            programs.push(compile(g, "query", &body, true)?);
        }
        for _ in 0..NBUF {
            let b = g.create_buffer().map_err(gl_err)?;
            buffers.push(b);
            g.bind_buffer(glow::SHADER_STORAGE_BUFFER, Some(b));
            g.buffer_data_size(glow::SHADER_STORAGE_BUFFER, 16, glow::DYNAMIC_DRAW);
        }
        Ok::<(), Error>(())
    })();
    if let Err(e) = made {
        // SAFETY: the caller's contract; these objects are ours and bound nowhere the host
        // keeps (the caller's guard restores the bindings).
        unsafe {
            for p in programs {
                g.delete_program(p);
            }
            for b in buffers {
                g.delete_buffer(b);
            }
        }
        return Err(e);
    }
    let [gather, refit, step1, sizes, step2, step34, step5] = programs[..] else {
        unreachable!("seven programs made")
    };
    Ok(Objects {
        gather,
        query: Kernels {
            refit,
            step1,
            sizes,
            step2,
            step34,
            step5,
        },
        buffers: buffers.try_into().expect("NBUF buffers made"),
    })
}

/// Replaces the contents of buffer `b` with `data` (16 bytes when empty: a GL buffer bound
/// to a storage block must have a size).
///
/// # Safety
/// `g` was loaded for the context current on this thread; `b` is a buffer of ours.
unsafe fn upload(g: &glow::Context, b: glow::NativeBuffer, data: &[u8]) {
    // SAFETY: the caller's contract; glow passes the slice's own length.
    unsafe {
        g.bind_buffer(glow::SHADER_STORAGE_BUFFER, Some(b));
        if data.is_empty() {
            g.buffer_data_size(glow::SHADER_STORAGE_BUFFER, 16, glow::DYNAMIC_DRAW);
        } else {
            g.buffer_data_u8_slice(glow::SHADER_STORAGE_BUFFER, data, glow::DYNAMIC_DRAW);
        }
    }
}

/// Allocates buffer `b` with `size` bytes (at least 16), contents undefined.
///
/// # Safety
/// As [`upload`].
unsafe fn allocate(g: &glow::Context, b: glow::NativeBuffer, size: i32, usage: u32) {
    // SAFETY: the caller's contract; `size` is non-negative (checked by `gl_bytes`).
    unsafe {
        g.bind_buffer(glow::SHADER_STORAGE_BUFFER, Some(b));
        g.buffer_data_size(glow::SHADER_STORAGE_BUFFER, size.max(16), usage);
    }
}

/// Sets the `uint` uniform `name` of the program in use (ignored when the kernel has none).
///
/// # Safety
/// `g` was loaded for the context current on this thread; `p` is ours and in use.
unsafe fn set_u32(g: &glow::Context, p: glow::NativeProgram, name: &str, v: u32) {
    // SAFETY: the caller's contract; a location of `p` (or none).
    unsafe {
        let l = g.get_uniform_location(p, name);
        g.uniform_1_u32(l.as_ref(), v);
    }
}

/// Sets the `float` uniform `name` of the program in use, as [`set_u32`].
///
/// # Safety
/// As [`set_u32`].
unsafe fn set_f32(g: &glow::Context, p: glow::NativeProgram, name: &str, v: f32) {
    // SAFETY: the caller's contract; a location of `p` (or none).
    unsafe {
        let l = g.get_uniform_location(p, name);
        g.uniform_1_f32(l.as_ref(), v);
    }
}

/// Dispatches `n` threads of the program in use (2D grid when `n` is large).
///
/// # Safety
/// As [`set_u32`].
unsafe fn dispatch(g: &glow::Context, p: glow::NativeProgram, n: u32) {
    let groups = n.div_ceil(GROUP).max(1);
    let x = groups.min(65535);
    let y = groups.div_ceil(x);
    // SAFETY: the caller's contract; at most 65535 groups a side.
    unsafe {
        set_u32(g, p, "u_count", n);
        g.dispatch_compute(x, y, 1);
    }
}

fn too_big() -> Error {
    Error::new(
        ErrorKind::Unsupported,
        "the query needs more GPU buffer room than 32-bit counts can address",
    )
}

fn arena_too_big(what: &str) -> Error {
    Error::new(
        ErrorKind::Unsupported,
        format!("the scene's meshes have 2^32 {what} or more in all; GL_COMPUTE numbers them in 32 bits"),
    )
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

/// Checks what the kernels need of the GL; GL_MAX_SHADER_STORAGE_BLOCK_SIZE in bytes.
fn capabilities(gl: &Gl) -> Result<u64> {
    if !gl.info.compute {
        let (major, minor) = crate::gpu::compute_gl_version();
        return Err(unavailable(format!(
            "GLCOL_BACKEND_GL_COMPUTE needs GL {major}.{minor} (its shaders are GLSL \
             {major}.{minor}0: compute shaders, shader storage blocks); the context is \"{}\"",
            gl.info.version_string
        )));
    }
    // SAFETY: GL 4.3 queries (checked above) on the context current on this thread.
    let (bindings, blocks, max_block) = unsafe {
        (
            gl.gl
                .get_parameter_i32(glow::MAX_SHADER_STORAGE_BUFFER_BINDINGS),
            gl.gl
                .get_parameter_i32(glow::MAX_COMPUTE_SHADER_STORAGE_BLOCKS),
            gl.gl.get_parameter_i64(glow::MAX_SHADER_STORAGE_BLOCK_SIZE),
        )
    };
    if bindings < BINDINGS as i32 || blocks < BLOCKS as i32 {
        return Err(unavailable(format!(
            "GLCOL_BACKEND_GL_COMPUTE needs {BINDINGS} shader storage buffer bindings and \
             {BLOCKS} storage blocks per compute shader; this GL has {bindings} and {blocks}"
        )));
    }
    Ok(max_block.max(0) as u64)
}

/// The arenas' index arrays for a set of meshes, and where each mesh lives in them.
#[derive(Default)]
struct Arena {
    slots: BTreeMap<u32, Slot>,
    /// 4 global slot ids per polygon (the 4th u32::MAX for a triangle).
    polys: Vec<u32>,
    /// (first slot, end slot, arena index) per global leaf.
    range: Vec<u32>,
    /// Slot -> the caller's vertex index, all meshes.
    verts: Vec<u32>,
    /// (first, end) global polygon per global leaf.
    leaf_polys: Vec<u32>,
    vertices: u32,
    leaves: u32,
}

impl Arena {
    /// Lays `meshes` out one after the other; counts past 32 bits are refused.
    fn of(meshes: &BTreeMap<u32, Mesh>) -> Result<Arena> {
        let mut a = Arena::default();
        let mut polys_total = 0u32;
        for (index, (&id, m)) in meshes.iter().enumerate() {
            let (vb, pb, lb) = (a.vertices, polys_total, a.leaves);
            let count = |n: usize, what| u32::try_from(n).map_err(|_| arena_too_big(what));
            let nslots = count(m.slot_positions().len(), "vertex slots")?;
            let npolys = count(m.polygon_count(), "polygons")?;
            let nleaves = count(m.leaf_count(), "leaves")?;
            // Every id below is below these ends, so no sum below can wrap.
            a.vertices = vb
                .checked_add(nslots)
                .ok_or_else(|| arena_too_big("vertex slots"))?;
            polys_total = pb
                .checked_add(npolys)
                .ok_or_else(|| arena_too_big("polygons"))?;
            a.leaves = lb
                .checked_add(nleaves)
                .ok_or_else(|| arena_too_big("leaves"))?;
            for p in 0..m.polygon_count() {
                let v = m.poly(p);
                a.polys.extend(v.iter().map(|&x| x + vb));
                if m.k == 3 {
                    a.polys.push(u32::MAX);
                }
            }
            let lv = &m.leaves;
            for l in 0..lv.len() {
                a.range.extend([
                    lv.leaf_slots[l] + vb,
                    lv.leaf_slots[l + 1] + vb,
                    index as u32,
                ]);
                a.leaf_polys
                    .extend([lv.leaf_polys[l] + pb, lv.leaf_polys[l + 1] + pb]);
            }
            a.verts.extend_from_slice(m.slot_vertices());
            a.slots.insert(
                id,
                Slot {
                    index: index as u32,
                    vertex_base: vb,
                    poly_base: pb,
                    leaf_base: lb,
                    vertices: nslots,
                    leaves: nleaves,
                    polys: npolys,
                    uploaded: None,
                },
            );
        }
        Ok(a)
    }
}

/// What a query asks of the kernels, worked out on the CPU before any dispatch.
struct Plan {
    /// The reference mesh: arena index, first global leaf, leaves.
    ref_mesh: u32,
    ref_base: u32,
    ref_leaves: u32,
    /// Other meshes of the query.
    n_others: u32,
    /// Per other mesh: first global leaf, leaves, first step-1 thread, arena index.
    others: Vec<u32>,
    /// Step-1 threads: every leaf of the other meshes (below 2^31).
    l1_cap: u32,
    /// (first global polygon, position in the query) per mesh, sorted: maps hits back.
    bases: Vec<(u32, u32)>,
    /// (first global leaf, leaves) of the meshes refitted on the GPU (host buffers).
    refit: Vec<(u32, u32)>,
    /// Root box keys per mesh of the arena (min xyz, max xyz).
    roots: Vec<u32>,
    /// The half depth asked for, before the GPU raises it.
    h_base: f32,
    /// The result header the kernels start from.
    header: [u32; HEADER],
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

    /// Bound mesh `id`'s positions as the last query gathered them from the host's buffer
    /// into the arena (slot order, gather.glsl), read back into `m`'s CPU positions: what
    /// contact geometry needs (the host may have written its buffer since). A sync point.
    fn read_gathered(&mut self, gl: &Gl, id: u32, m: &mut Mesh) -> Result<()> {
        let n = m.slot_positions().len();
        let slot = self.slots.get(&id).filter(|s| s.vertices as usize == n);
        let Some(s) = slot.filter(|_| self.gathered.contains(&id)) else {
            // (A GL error since the query dropped the GPU's copy.)
            return Err(Error::invalid(format!(
                "mesh {id} reads its positions from a GL buffer, and the GPU no longer holds \
                those the last query gathered (a GL error since?): query again for its \
                contact geometry"
            )));
        };
        let at = gl_bytes(s.vertex_base.into(), 12, "the positions")?;
        let len = gl_bytes(n as u64, 12, "the positions")?;
        if n == 0 {
            return Ok(());
        }
        let g = &gl.gl;
        let b = self.objects().buffers[POS];
        // SAFETY: as in `rebuild`; the mesh's `n` slots lie at `vertex_base` in the
        // positions buffer (its layout); the mapping is read only within them and unmapped
        // before anything else touches the buffer. The barrier makes the gather's shader
        // writes visible to the mapping.
        unsafe {
            g.memory_barrier(glow::BUFFER_UPDATE_BARRIER_BIT);
            g.bind_buffer(glow::SHADER_STORAGE_BUFFER, Some(b));
            let p = g.map_buffer_range(glow::SHADER_STORAGE_BUFFER, at, len, glow::MAP_READ_BIT);
            if p.is_null() {
                gl.check("mapping the gathered positions")?;
                return Err(gl_err("glMapBufferRange returned NULL".into()));
            }
            let f = std::slice::from_raw_parts(p.cast::<f32>(), 3 * n);
            m.set_slot_positions(f);
            g.unmap_buffer(glow::SHADER_STORAGE_BUFFER);
        }
        self.readbacks += 1;
        gl.check("reading back the positions a query gathered")
    }

    fn layout_matches(&self, meshes: &BTreeMap<u32, Mesh>) -> bool {
        self.slots.len() == meshes.len()
            && self.slots.iter().zip(meshes).all(|((a, s), (b, m))| {
                a == b
                    && s.vertices as usize == m.slot_positions().len()
                    && s.polys as usize == m.polygon_count()
            })
    }

    /// Before each query: checks the host buffers, lays the meshes out again if they
    /// changed, uploads positions and boxes that changed on the CPU. (Host buffers are
    /// gathered by the query that uses them, whose read-back then waits for the gather: a
    /// call that answers has finished reading them.)
    fn prepare(&mut self, gl: &Gl, meshes: &BTreeMap<u32, Mesh>) -> Result<()> {
        self.gathered.clear();
        self.check_bound(gl, meshes)?;
        if !self.layout_matches(meshes) {
            self.rebuild(gl, meshes)?;
        }
        self.upload_changed(gl, meshes)?;
        gl.check("uploading positions")
    }

    /// Every enabled mesh's host buffer, before anything is touched: still a buffer object,
    /// not mapped, and still holding the mesh's vertices (the host may have re-specified it
    /// smaller or deleted it since `bind_gl_buffer`). INVALID_ARGUMENT naming the mesh and
    /// the sizes otherwise. The guard restores the COPY_READ_BUFFER binding used to ask.
    fn check_bound(&self, gl: &Gl, meshes: &BTreeMap<u32, Mesh>) -> Result<()> {
        for (&id, b) in &self.bound {
            if meshes.get(&id).is_some_and(|m| m.enabled) {
                b.host.check(gl, HostCheck::Use(id))?;
            }
        }
        Ok(())
    }

    /// Lays every mesh out in the arenas again (meshes were added or removed).
    fn rebuild(&mut self, gl: &Gl, meshes: &BTreeMap<u32, Mesh>) -> Result<()> {
        self.slots.clear();
        let a = Arena::of(meshes)?;
        let sizes = [
            (POS, gl_bytes(a.vertices.into(), 12, "the positions")?),
            (BOXES, gl_bytes(a.leaves.into(), 24, "the leaf boxes")?),
            (ROOTS, gl_bytes(meshes.len() as u64, 24, "the root boxes")?),
        ];
        let g = &gl.gl;
        let b = &self.objects().buffers;
        // SAFETY: `gl` is loaded for the context current on this thread (every GL-backed
        // call's contract); the buffers are ours, the sizes checked.
        unsafe {
            for (k, size) in sizes {
                allocate(g, b[k], size, glow::DYNAMIC_DRAW);
            }
            upload(g, b[POLYS], bytes(&a.polys));
            upload(g, b[LEAF_RANGE], bytes(&a.range));
            upload(g, b[LEAF_VERTS], bytes(&a.verts));
            upload(g, b[LEAF_POLYS], bytes(&a.leaf_polys));
        }
        self.slots = a.slots;
        Ok(())
    }

    /// CPU-side positions that changed, and their CPU-refitted boxes.
    fn upload_changed(&mut self, gl: &Gl, meshes: &BTreeMap<u32, Mesh>) -> Result<()> {
        let g = &gl.gl;
        let bufs = self
            .obj
            .as_ref()
            .expect("GL objects exist until release")
            .buffers;
        for (id, m) in meshes {
            let s = self.slots.get_mut(id).expect("laid out");
            if self.bound.contains_key(id) || s.uploaded == Some(m.generation) {
                continue;
            }
            let at = gl_bytes(s.vertex_base.into(), 12, "the positions")?;
            self.box_words.clear();
            for b in &m.leaves.boxes {
                self.box_words.extend(b.min.iter().chain(&b.max));
            }
            let boxes_at = gl_bytes(s.leaf_base.into(), 24, "the leaf boxes")?;
            // SAFETY: as in `rebuild`; the ranges lie in the buffers as `rebuild` sized them
            // (the mesh's slots and leaves are where its layout put them).
            unsafe {
                g.bind_buffer(glow::SHADER_STORAGE_BUFFER, Some(bufs[POS]));
                g.buffer_sub_data_u8_slice(
                    glow::SHADER_STORAGE_BUFFER,
                    at,
                    bytes(m.slot_positions()),
                );
                g.bind_buffer(glow::SHADER_STORAGE_BUFFER, Some(bufs[BOXES]));
                g.buffer_sub_data_u8_slice(
                    glow::SHADER_STORAGE_BUFFER,
                    boxes_at,
                    bytes(&self.box_words),
                );
            }
            s.uploaded = Some(m.generation);
        }
        Ok(())
    }

    /// Host buffers of the query's meshes: gathers their positions into the arena on the
    /// GPU, behind a `GL_SHADER_STORAGE_BARRIER_BIT` barrier so that the host's own shader
    /// writes before the call are seen (the host needs no barrier); the query then refits
    /// their leaves.
    fn gather_bound(&self, gl: &Gl, q: &QueryMeshes<'_>) -> Result<()> {
        let bound: Vec<(&Bound, &Slot)> = q
            .meshes
            .iter()
            .filter_map(|(id, _)| Some((self.bound.get(id)?, &self.slots[id])))
            .collect();
        if bound.is_empty() {
            return Ok(());
        }
        let g = &gl.gl;
        let o = self.objects();
        // SAFETY: as in `rebuild`; the host's buffer was checked to be a buffer object of
        // this context holding every vertex at its offset and stride, and not mapped, by
        // `check_bound` in this call's `prepare`.
        unsafe {
            g.memory_barrier(glow::SHADER_STORAGE_BARRIER_BIT);
            g.use_program(Some(o.gather));
            for k in [POS, LEAF_VERTS] {
                g.bind_buffer_base(glow::SHADER_STORAGE_BUFFER, BINDING[k], Some(o.buffers[k]));
            }
            for (b, s) in bound {
                g.bind_buffer_base(
                    glow::SHADER_STORAGE_BUFFER,
                    SRC_BINDING,
                    buffer(b.host.buffer),
                );
                set_u32(g, o.gather, "u_src_offset", b.offset);
                set_u32(g, o.gather, "u_src_stride", b.stride);
                set_u32(g, o.gather, "u_dst_vertex", s.vertex_base);
                dispatch(g, o.gather, s.vertices);
            }
            g.memory_barrier(glow::SHADER_STORAGE_BARRIER_BIT);
        }
        gl.check("gathering positions from host buffers")
    }

    /// Steps 1 to 5 on the GPU, one read-back (see the module's documentation).
    fn query(
        &mut self,
        gl: &Gl,
        q: &QueryMeshes<'_>,
        out: &mut Vec<Contact>,
        stats: &mut QueryStats,
    ) -> Result<()> {
        let t0 = std::time::Instant::now();
        self.gather_bound(gl, q)?;
        for &(id, _) in q.meshes.iter() {
            if self.bound.contains_key(&id) {
                self.gathered.insert(id);
            }
        }
        let plan = self.plan(q)?;
        let raw = self.run_until_room(gl, &plan)?;
        stats.tests = [
            plan.l1_cap as usize,
            raw[H_L1] as usize * plan.ref_leaves as usize,
            raw[H_TESTS3] as usize,
            raw[H_TESTS4] as usize,
            raw[H_TOTAL5] as usize,
        ];
        stats.hits = [
            raw[H_L1],
            raw[H_PAIRS],
            raw[H_HITS3],
            raw[H_HITS4],
            raw[H_HITS],
        ]
        .map(|x| x as usize);
        contacts(q, &plan, &raw[HEADER..], out);
        stats.nanos[0] = t0.elapsed().as_nanos() as u64;
        Ok(())
    }

    /// The query's plan: the other meshes' leaves, the roots, the half depth.
    fn plan(&self, q: &QueryMeshes<'_>) -> Result<Plan> {
        let reference = &self.slots[&q.meshes[0].0];
        let mut others: Vec<u32> = Vec::with_capacity(4 * q.meshes.len());
        let mut l1_cap = 0u32;
        let mut bases: Vec<(u32, u32)> = Vec::with_capacity(q.meshes.len());
        for (mi, (id, _)) in q.meshes.iter().enumerate() {
            let s = &self.slots[id];
            bases.push((s.poly_base, mi as u32));
            if mi > 0 {
                others.extend([s.leaf_base, s.leaves, l1_cap, s.index]);
                l1_cap = l1_cap
                    .checked_add(s.leaves)
                    .filter(|&n| n < 1 << 31)
                    .ok_or_else(too_big)?;
            }
        }
        bases.sort_unstable();
        // Meshes reading a host buffer are refitted on the GPU, their roots reduced there,
        // and the half depth raised there from the roots; the others' boxes and roots are
        // the CPU's, and so is the half depth when every mesh is on the CPU.
        let refit: Vec<(u32, u32)> = q
            .meshes
            .iter()
            .filter(|(id, _)| self.bound.contains_key(id))
            .map(|(id, _)| (self.slots[id].leaf_base, self.slots[id].leaves))
            .collect();
        let mut roots = vec![0u32; 6 * self.slots.len()];
        for (id, s) in &self.slots {
            let r = &mut roots[6 * s.index as usize..][..6];
            match q.meshes.iter().find(|(i, _)| i == id) {
                Some((_, m)) if !self.bound.contains_key(id) => {
                    let b = m.leaves.root;
                    for (k, key) in r.iter_mut().enumerate() {
                        *key = sortable_key(if k < 3 { b.min[k] } else { b.max[k - 3] });
                    }
                }
                _ => r[..3].fill(u32::MAX), // grown down by the refit
            }
        }
        let h_base = (q.half_depth as f32).max(0.0);
        let mut header = [0u32; HEADER];
        header[H_HALF_DEPTH] = if refit.is_empty() {
            ((q.gl_half_depth() * (1.0 + 1e-6)) as f32).to_bits()
        } else {
            h_base.to_bits()
        };
        Ok(Plan {
            ref_mesh: reference.index,
            ref_base: reference.leaf_base,
            ref_leaves: reference.leaves,
            n_others: q.meshes.len() as u32 - 1,
            others,
            l1_cap,
            bases,
            refit,
            roots,
            h_base,
            header,
        })
    }

    /// Runs the kernels and reads the result back until the buffers hold the whole answer
    /// (each run completes at least one more step: at most 4 runs grow them); the header
    /// and the step-5 hits it counts.
    fn run_until_room(&mut self, gl: &Gl, plan: &Plan) -> Result<Vec<u32>> {
        let mut raw = Vec::new();
        for runs in 1.. {
            let caps = self.caps;
            self.size_buffers(gl, plan.l1_cap)?;
            self.upload_plan(gl, plan);
            self.dispatch_steps(gl, plan, caps);
            self.read_back(gl, caps, &mut raw)?;
            self.check_header(&raw)?;
            // Grow what overflowed; the counters after an overflowed one may be short, so
            // run again until nothing overflows.
            let next = grown(&raw, caps);
            if next == caps {
                break;
            }
            if runs >= 8 {
                return Err(Error::new(
                    ErrorKind::Internal,
                    "the query's buffers still overflow after 8 runs (a bug)",
                ));
            }
            self.caps = next;
        }
        Ok(raw)
    }

    /// Sizes the query's buffers for the room `self.caps` and `l1` step-1 hits. A size
    /// the GL cannot take (past `i32::MAX` bytes or the largest storage block) is refused
    /// before any allocation; an allocation the GL reports failing forgets the sizes and
    /// the room.
    fn size_buffers(&mut self, gl: &Gl, l1: u32) -> Result<()> {
        let c = self.caps;
        if self.sized.is_some_and(|(sc, sl)| sc == c && sl >= l1) {
            return Ok(());
        }
        let l1 = l1.max(self.sized.map_or(0, |(_, l)| l));
        let words = [
            (L1, "step-1 hits", u64::from(l1)),
            (PAIRS, "leaf pairs", 8 * u64::from(c.pairs)),
            (LISTS, "step-3/4 lists", u64::from(c.lists)),
            (RESULT, "contacts", HEADER as u64 + 2 * u64::from(c.hits)),
        ];
        let limit = self.max_block.min(i32::MAX as u64);
        if let Some((_, what, w)) = words.iter().find(|(_, _, w)| 4 * w > limit) {
            self.caps = Caps::default(); // the next query starts from the usual room
            return Err(Error::new(
                ErrorKind::OutOfMemory,
                format!(
                    "the query needs a {} MiB buffer for its {what}; this GL's storage blocks \
                     take at most {} MiB",
                    (4 * w) >> 20,
                    limit >> 20
                ),
            ));
        }
        let g = &gl.gl;
        let b = self.objects().buffers;
        self.sized = None;
        for (k, what, w) in words {
            let size = gl_bytes(w, 4, what)?;
            let usage = if k == RESULT {
                glow::DYNAMIC_READ
            } else {
                glow::DYNAMIC_COPY
            };
            // SAFETY: as in `rebuild`; the size is checked against the GL's limits above.
            unsafe { allocate(g, b[k], size, usage) };
        }
        if let Err(e) = gl.check_alloc("allocating the query's buffers") {
            self.caps = Caps::default();
            return Err(e);
        }
        self.sized = Some((c, l1));
        Ok(())
    }

    /// Uploads what the plan computed (other meshes, roots, the header) and binds every
    /// buffer the kernels use (the guard gave the host its bindings back after the last
    /// call).
    fn upload_plan(&self, gl: &Gl, plan: &Plan) {
        let g = &gl.gl;
        let b = &self.objects().buffers;
        // SAFETY: as in `rebuild`; the header fits the result buffer (sized for it and the
        // hits).
        unsafe {
            upload(g, b[OTHERS], bytes(&plan.others));
            upload(g, b[ROOTS], bytes(&plan.roots));
            g.bind_buffer(glow::SHADER_STORAGE_BUFFER, Some(b[RESULT]));
            g.buffer_sub_data_u8_slice(glow::SHADER_STORAGE_BUFFER, 0, bytes(&plan.header));
            for k in [
                POS, POLYS, BOXES, LEAF_RANGE, LEAF_POLYS, OTHERS, L1, PAIRS, LISTS, RESULT, ROOTS,
            ] {
                g.bind_buffer_base(glow::SHADER_STORAGE_BUFFER, BINDING[k], Some(b[k]));
            }
            g.bind_buffer(glow::DISPATCH_INDIRECT_BUFFER, Some(b[RESULT]));
        }
    }

    /// The kernels, in order: refit of the host-buffer meshes (and their half depth),
    /// step 1, then for steps 2, 3-4 and 5: one workgroup sizes the step, the step runs
    /// (dispatched indirectly with those sizes).
    fn dispatch_steps(&self, gl: &Gl, plan: &Plan, caps: Caps) {
        let g = &gl.gl;
        let k = self.objects().query;
        let storage = glow::SHADER_STORAGE_BARRIER_BIT;
        let command = storage | glow::COMMAND_BARRIER_BIT;
        // SAFETY: as in `rebuild`; the programs are ours, their buffers bound by
        // `upload_plan`, the indirect sizes written by the sizes kernel into the bound
        // result buffer (workgroup counts of at most 65535 a side).
        unsafe {
            if !plan.refit.is_empty() {
                use_kernel(g, k.refit, plan, caps);
                for &(first, leaves) in &plan.refit {
                    set_u32(g, k.refit, "u_first_leaf", first);
                    dispatch(g, k.refit, leaves);
                }
                g.memory_barrier(storage);
                use_kernel(g, k.sizes, plan, caps);
                set_u32(g, k.sizes, "u_src", 3); // the half depth from the refitted roots
                dispatch(g, k.sizes, GROUP);
                g.memory_barrier(storage);
            }
            use_kernel(g, k.step1, plan, caps);
            dispatch(g, k.step1, plan.l1_cap);
            g.memory_barrier(storage);
            for (src, (step, args)) in [k.step2, k.step34, k.step5]
                .into_iter()
                .zip(H_ARGS)
                .enumerate()
            {
                use_kernel(g, k.sizes, plan, caps);
                set_u32(g, k.sizes, "u_src", src as u32);
                dispatch(g, k.sizes, GROUP);
                g.memory_barrier(command);
                use_kernel(g, step, plan, caps);
                g.dispatch_compute_indirect(4 * args as i32);
                g.memory_barrier(storage);
            }
            g.memory_barrier(glow::BUFFER_UPDATE_BARRIER_BIT);
        }
    }

    /// The one read-back: maps the result, copies the header and the hits it counts into
    /// `raw`.
    fn read_back(&mut self, gl: &Gl, caps: Caps, raw: &mut Vec<u32>) -> Result<()> {
        gl.check("the query dispatches")?;
        let len = gl_bytes(HEADER as u64 + 2 * u64::from(caps.hits), 4, "contacts")?;
        let g = &gl.gl;
        let b = self.objects().buffers[RESULT];
        // SAFETY: as in `rebuild`; the result buffer holds `len` bytes (sized for `caps`);
        // the mapping is read only within them (the hit count is clamped to the room) and
        // unmapped before anything else touches the buffer.
        unsafe {
            g.bind_buffer(glow::SHADER_STORAGE_BUFFER, Some(b));
            let p = g.map_buffer_range(glow::SHADER_STORAGE_BUFFER, 0, len, glow::MAP_READ_BIT);
            if p.is_null() {
                gl.check("mapping the query's result")?;
                return Err(gl_err("glMapBufferRange returned NULL".into()));
            }
            let words = p.cast::<u32>();
            let n = (*words.add(H_HITS)).min(caps.hits) as usize;
            raw.clear();
            raw.extend_from_slice(std::slice::from_raw_parts(words, HEADER + 2 * n));
            g.unmap_buffer(glow::SHADER_STORAGE_BUFFER);
        }
        self.readbacks += 1;
        gl.check("reading the query's result")
    }

    /// The header's failures: a NaN or infinity in a host buffer (naming the mesh), or a
    /// step of 2^31 tests or more.
    fn check_header(&self, raw: &[u32]) -> Result<()> {
        if raw[H_NONFINITE] != 0 {
            let id = self
                .slots
                .iter()
                .find(|(_, s)| s.index == raw[H_NONFINITE] - 1)
                .map_or(0, |(id, _)| *id);
            return Err(Error::new(
                ErrorKind::NonFinite,
                format!("mesh {id}: its bound GL buffer holds a NaN or infinite coordinate"),
            ));
        }
        if raw[H_TOO_MANY] != 0 {
            return Err(Error::new(
                ErrorKind::Unsupported,
                "a step of this query asks 2^31 tests or more, more than one dispatch takes",
            ));
        }
        Ok(())
    }
}

/// Makes `p` the program in use and sets the uniforms every query kernel shares.
///
/// # Safety
/// `g` was loaded for the context current on this thread; `p` is one of our kernels.
unsafe fn use_kernel(g: &glow::Context, p: glow::NativeProgram, plan: &Plan, caps: Caps) {
    // SAFETY: the caller's contract.
    unsafe {
        g.use_program(Some(p));
        for (name, v) in [
            ("u_ref_mesh", plan.ref_mesh),
            ("u_ref_leaf_base", plan.ref_base),
            ("u_ref_leaves", plan.ref_leaves),
            ("u_others", plan.n_others),
            ("u_l1_cap", plan.l1_cap),
            ("u_pair_cap", caps.pairs),
            ("u_list_cap", caps.lists),
            ("u_hit_cap", caps.hits),
        ] {
            set_u32(g, p, name, v);
        }
        set_f32(g, p, "u_pad_rel", PAD_REL);
        set_f32(g, p, "u_h_base", plan.h_base);
    }
}

/// The room the next run needs: each counter that passed its room grows to fit it.
fn grown(raw: &[u32], caps: Caps) -> Caps {
    let grow = |need: u32, cap: u32| {
        if need > cap {
            need.saturating_add(need / 2).max(cap.saturating_mul(2))
        } else {
            cap
        }
    };
    Caps {
        pairs: grow(raw[H_PAIRS], caps.pairs),
        lists: grow(raw[H_LIST], caps.lists),
        hits: grow(raw[H_HITS], caps.hits),
    }
}

/// The step-5 hits (global reference polygon, global other polygon) as contacts. When
/// every position is on the CPU, each hit is confirmed with the CPU backend's test at the
/// epsilon asked for (the GPU used at least the minimum depth: it lost nothing).
fn contacts(q: &QueryMeshes<'_>, plan: &Plan, hits: &[u32], out: &mut Vec<Contact>) {
    // Global polygon id -> (mesh position, leaf-ordered polygon).
    let locate = |gp: u32| {
        let i = plan.bases.partition_point(|&(b, _)| b <= gp) - 1;
        let (base, mi) = plan.bases[i];
        (mi, gp - base)
    };
    let confirm = plan.refit.is_empty().then_some(q.half_depth);
    let ref_mesh = q.meshes[0].1;
    for hit in hits.chunks_exact(2) {
        let (rm, rp) = locate(hit[0]);
        let (cm, cp) = locate(hit[1]);
        debug_assert_eq!(rm, 0);
        let (other_id, other) = q.meshes[cm as usize];
        if let Some(h) = confirm {
            if !confirmed(ref_mesh, rp as usize, other, cp as usize, h) {
                continue;
            }
        }
        out.push(Contact {
            other_mesh: other_id,
            reference_polygon: ref_mesh.poly_ids[rp as usize],
            other_polygon: other.poly_ids[cp as usize],
        });
    }
}

/// The CPU backend's step-5 test ([`polygon_meets`]) for polygon `v` of `vm` and polygon
/// `c` of `cm` at half depth `h` (exact intersection at 0).
fn confirmed(vm: &Mesh, v: usize, cm: &Mesh, c: usize, h: f64) -> bool {
    let mut vt = [[[0.0; 3]; 3]; 2];
    let nv = vm.triangles(v, &mut vt);
    let mut ct = [[[0.0; 3]; 3]; 2];
    let nc = cm.triangles(c, &mut ct);
    polygon_meets(&vt, nv, &ct, nc, h)
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
