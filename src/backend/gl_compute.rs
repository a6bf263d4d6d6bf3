//! The GL_COMPUTE backend: the five steps as compute dispatches (GL 4.3+, core or
//! compatibility).
//!
//! - Every mesh's positions live in one buffer object (an arena of xyz floats, all meshes),
//!   uploaded when a mesh's positions change, or gathered on the GPU from the host's own
//!   buffer object (`glcol_mesh_bind_gl_buffer`: no copy through the CPU).
//! - The whole query runs on the GPU ([`Selector::run_query`], shaders/query.glsl), one
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
//!   dispatched.
//! - Box tests are padded (float rounding can only add pairs); the polygon viewing volume
//!   of step 5 is clipped in double precision in a frame local to the reference polygon.
//!   When every mesh of the query has its positions on the CPU too, each step-5 hit is
//!   confirmed with the CPU backend's test, so the answer equals the CPU backend's; with
//!   buffer-bound meshes the GPU's answer is final (extras within epsilon / 2 + 2^-40 of
//!   the local size).

use std::collections::BTreeMap;

use glow::HasContext;

use super::{Backend, Contact, Engine, QueryMeshes, QueryStats, Selector, WholeQuery};
use crate::error::{Error, ErrorKind, Result};
use crate::geom::polygon::polygon_meets;
use crate::gpu::state::{StateGuard, Uses};
use crate::gpu::{buffer, unavailable, Gl};
use crate::mesh::Mesh;

const COMMON: &str = include_str!("../gpu/shaders/common.glsl");
const GATHER: &str = include_str!("../gpu/shaders/gather.glsl");
const MEETS: &str = include_str!("../gpu/shaders/meets.glsl");
const QUERY: &str = include_str!("../gpu/shaders/query.glsl");

/// Indexed buffer bindings the shaders use (0..BINDINGS).
const BINDINGS: u32 = 12;
/// Shader storage blocks the busiest kernel uses.
const BLOCKS: u32 = 7;
const GROUP: u32 = 64;

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

/// A host buffer a mesh reads its positions from.
#[derive(Clone, Copy, Debug)]
struct Bound {
    buffer: u32,
    offset: usize,
    stride: usize,
}

struct Objects {
    gather: glow::NativeProgram,
    /// The whole-query kernels of query.glsl: refit + root, step 1, dispatch sizes, step 2,
    /// steps 3 and 4, step 5.
    query: [glow::NativeProgram; 6],
    /// See the buffer constants (POS ... RESULT).
    buffers: [glow::NativeBuffer; NBUF],
}

/// Room in the whole-query buffers (entries); grown when a query's answer needs more.
#[derive(Clone, Copy, Debug)]
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
    obj: Option<Objects>,
    slots: BTreeMap<u32, Slot>,
    bound: BTreeMap<u32, Bound>,
    caps: Caps,
    /// GL_MAX_SHADER_STORAGE_BLOCK_SIZE, bytes.
    max_block: u64,
    /// Read-backs since `take_readbacks`.
    readbacks: u32,
    /// Capacities the GPU buffers were last sized for (None: never).
    sized: Option<(Caps, u32)>,
    /// Scratch for the leaf boxes of a mesh.
    box_words: Vec<f32>,
}

fn bytes<T: Copy>(v: &[T]) -> &[u8] {
    // SAFETY: plain-old-data (u32/f32) viewed as bytes.
    unsafe { std::slice::from_raw_parts(v.as_ptr().cast(), std::mem::size_of_val(v)) }
}

fn gl_err(e: String) -> Error {
    Error::new(ErrorKind::GlError, e)
}

/// Compiles common.glsl, meets.glsl when the kernel tests primitives, and `body` (source
/// string numbers in the GL's log: 0 common, 1 meets, 2 body).
unsafe fn compile(
    g: &glow::Context,
    name: &str,
    body: &str,
    meets: bool,
) -> Result<glow::NativeProgram> {
    let sh = g.create_shader(glow::COMPUTE_SHADER).map_err(gl_err)?;
    let meets = if meets { MEETS } else { "" };
    let src = format!("{COMMON}\n#line 1 1\n{meets}\n#line 1 2\n{body}");
    g.shader_source(sh, &src);
    g.compile_shader(sh);
    if !g.get_shader_compile_status(sh) {
        let log = g.get_shader_info_log(sh);
        g.delete_shader(sh);
        return Err(Error::new(
            ErrorKind::GlUnavailable,
            format!("the {name} compute shader does not compile here: {log}"),
        ));
    }
    let p = g.create_program().map_err(gl_err)?;
    g.attach_shader(p, sh);
    g.link_program(p);
    g.detach_shader(p, sh);
    g.delete_shader(sh);
    if !g.get_program_link_status(p) {
        let log = g.get_program_info_log(p);
        g.delete_program(p);
        return Err(Error::new(
            ErrorKind::GlUnavailable,
            format!("the {name} compute shader does not link here: {log}"),
        ));
    }
    Ok(p)
}

impl GlComputeSelector {
    /// Needs GL 4.3+ (compute shaders, SSBOs, double precision).
    pub fn new(gl: Gl) -> Result<GlComputeSelector> {
        if !gl.info.compute {
            return Err(unavailable(format!(
                "GLCOL_BACKEND_GL_COMPUTE needs GL 4.3 (compute shaders); the context is \"{}\"",
                gl.info.version_string
            )));
        }
        let (bindings, blocks) = unsafe {
            (
                gl.gl
                    .get_parameter_i32(glow::MAX_SHADER_STORAGE_BUFFER_BINDINGS),
                gl.gl
                    .get_parameter_i32(glow::MAX_COMPUTE_SHADER_STORAGE_BLOCKS),
            )
        };
        if bindings < BINDINGS as i32 || blocks < BLOCKS as i32 {
            return Err(unavailable(format!(
                "GLCOL_BACKEND_GL_COMPUTE needs {BINDINGS} shader storage buffer bindings and \
                 {BLOCKS} storage blocks per compute shader; this GL has {bindings} and {blocks}"
            )));
        }
        let max_block =
            unsafe { gl.gl.get_parameter_i64(glow::MAX_SHADER_STORAGE_BLOCK_SIZE) } as u64;
        let mut s = GlComputeSelector {
            gl,
            obj: None,
            slots: BTreeMap::new(),
            bound: BTreeMap::new(),
            caps: Caps::default(),
            max_block,
            readbacks: 0,
            sized: None,
            box_words: Vec::new(),
        };
        let guard = StateGuard::enter(&s.gl, uses())?;
        let g = &s.gl.gl;
        let made = unsafe {
            (|| -> Result<Objects> {
                let gather = compile(g, "gather", GATHER, false)?;
                let mut programs = vec![gather];
                let fail = |programs: &[glow::NativeProgram]| {
                    for &p in programs {
                        g.delete_program(p);
                    }
                };
                let mut query = Vec::new();
                for k in 1..=6 {
                    let body = format!("#define KERNEL {k}\n#line 1 2\n{QUERY}");
                    let p = compile(g, "query", &body, true).inspect_err(|_| fail(&programs))?;
                    programs.push(p);
                    query.push(p);
                }
                let mut buffers = Vec::new();
                for _ in 0..NBUF {
                    let b = g.create_buffer().map_err(gl_err)?;
                    g.bind_buffer(glow::SHADER_STORAGE_BUFFER, Some(b));
                    g.buffer_data_size(glow::SHADER_STORAGE_BUFFER, 16, glow::DYNAMIC_DRAW);
                    buffers.push(b);
                }
                Ok(Objects {
                    gather,
                    query: query.try_into().unwrap(),
                    buffers: buffers.try_into().unwrap(),
                })
            })()
        };
        let done = guard.finish();
        let obj = made?;
        s.obj = Some(obj);
        if let Err(e) = done {
            s.release();
            return Err(e);
        }
        Ok(s)
    }
}

fn uses() -> Uses {
    Uses {
        fixed_function: false,
        indexed_bindings: BINDINGS,
    }
}

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
/// Shader binding of each buffer (the host source buffer is binding 6; the roots share
/// gather's binding 8).
const BINDING: [u32; NBUF] = [0, 1, 7, 8, 9, 10, 11, 2, 3, 4, 5, 8];
/// Words of the whole query's result header.
const HEADER: usize = 64;

unsafe fn upload(g: &glow::Context, b: glow::NativeBuffer, data: &[u8]) {
    g.bind_buffer(glow::SHADER_STORAGE_BUFFER, Some(b));
    if data.is_empty() {
        g.buffer_data_size(glow::SHADER_STORAGE_BUFFER, 16, glow::DYNAMIC_DRAW);
    } else {
        g.buffer_data_u8_slice(glow::SHADER_STORAGE_BUFFER, data, glow::DYNAMIC_DRAW);
    }
}

unsafe fn set_u32(g: &glow::Context, p: glow::NativeProgram, name: &str, v: u32) {
    let l = g.get_uniform_location(p, name);
    g.uniform_1_u32(l.as_ref(), v);
}

/// Dispatches `n` threads of the bound program (2D grid when `n` is large).
unsafe fn dispatch(g: &glow::Context, p: glow::NativeProgram, n: u32) {
    set_u32(g, p, "u_count", n);
    let groups = n.div_ceil(GROUP).max(1);
    let x = groups.min(65535);
    let y = groups.div_ceil(x);
    g.dispatch_compute(x, y, 1);
}

impl GlComputeSelector {
    /// Lays every mesh out in the arenas again (meshes were added or removed).
    unsafe fn rebuild(&mut self, meshes: &BTreeMap<u32, Mesh>) {
        let g = &self.gl.gl;
        let o = self.obj.as_ref().unwrap();
        self.slots.clear();
        let (mut vb, mut pb, mut lb) = (0u32, 0u32, 0u32);
        let mut polys: Vec<u32> = Vec::new();
        let mut range: Vec<u32> = Vec::new();
        let mut verts: Vec<u32> = Vec::new();
        let mut leaf_polys: Vec<u32> = Vec::new();
        for (index, (&id, m)) in meshes.iter().enumerate() {
            let k = m.k;
            let nslots = m.slot_positions().len() as u32;
            for p in 0..m.polygon_count() {
                let v = m.poly(p);
                polys.extend(v.iter().map(|&x| x + vb));
                if k == 3 {
                    polys.push(u32::MAX);
                }
            }
            let lv = &m.leaves;
            for l in 0..lv.len() {
                range.extend([
                    lv.leaf_slots[l] + vb,
                    lv.leaf_slots[l + 1] + vb,
                    index as u32,
                ]);
                leaf_polys.extend([lv.leaf_polys[l] + pb, lv.leaf_polys[l + 1] + pb]);
            }
            verts.extend_from_slice(m.slot_vertices());
            self.slots.insert(
                id,
                Slot {
                    index: index as u32,
                    vertex_base: vb,
                    poly_base: pb,
                    leaf_base: lb,
                    vertices: nslots,
                    leaves: m.leaf_count() as u32,
                    polys: m.polygon_count() as u32,
                    uploaded: None,
                },
            );
            vb += nslots;
            pb += m.polygon_count() as u32;
            lb += m.leaf_count() as u32;
        }
        let b = &o.buffers;
        g.bind_buffer(glow::SHADER_STORAGE_BUFFER, Some(b[POS]));
        g.buffer_data_size(
            glow::SHADER_STORAGE_BUFFER,
            (vb as i32 * 12).max(16),
            glow::DYNAMIC_DRAW,
        );
        upload(g, b[POLYS], bytes(&polys));
        upload(g, b[LEAF_RANGE], bytes(&range));
        upload(g, b[LEAF_VERTS], bytes(&verts));
        upload(g, b[LEAF_POLYS], bytes(&leaf_polys));
        g.bind_buffer(glow::SHADER_STORAGE_BUFFER, Some(b[BOXES]));
        g.buffer_data_size(
            glow::SHADER_STORAGE_BUFFER,
            (lb as i32 * 24).max(16),
            glow::DYNAMIC_DRAW,
        );
        g.bind_buffer(glow::SHADER_STORAGE_BUFFER, Some(b[ROOTS]));
        g.buffer_data_size(
            glow::SHADER_STORAGE_BUFFER,
            (meshes.len() as i32 * 24).max(16),
            glow::DYNAMIC_DRAW,
        );
    }

    fn layout_matches(&self, meshes: &BTreeMap<u32, Mesh>) -> bool {
        self.slots.len() == meshes.len()
            && self.slots.iter().zip(meshes).all(|((a, s), (b, m))| {
                a == b
                    && s.vertices as usize == m.slot_positions().len()
                    && s.polys as usize == m.polygon_count()
            })
    }

    fn prepare_inner(&mut self, meshes: &mut BTreeMap<u32, Mesh>) -> Result<()> {
        unsafe {
            if !self.layout_matches(meshes) {
                self.rebuild(meshes);
            }
            let g = &self.gl.gl;
            let o = self.obj.as_ref().unwrap();
            // CPU-side positions that changed, and their CPU-refitted boxes.
            for (id, m) in meshes.iter() {
                let s = self.slots.get_mut(id).unwrap();
                if !self.bound.contains_key(id) && s.uploaded != Some(m.generation) {
                    g.bind_buffer(glow::SHADER_STORAGE_BUFFER, Some(o.buffers[POS]));
                    g.buffer_sub_data_u8_slice(
                        glow::SHADER_STORAGE_BUFFER,
                        s.vertex_base as i32 * 12,
                        bytes(m.slot_positions()),
                    );
                    self.box_words.clear();
                    for b in &m.leaves.boxes {
                        self.box_words.extend(b.min.iter().chain(&b.max));
                    }
                    g.bind_buffer(glow::SHADER_STORAGE_BUFFER, Some(o.buffers[BOXES]));
                    g.buffer_sub_data_u8_slice(
                        glow::SHADER_STORAGE_BUFFER,
                        s.leaf_base as i32 * 24,
                        bytes(&self.box_words),
                    );
                    s.uploaded = Some(m.generation);
                }
            }
            if self.bound.is_empty() {
                return self.gl.check("uploading positions");
            }
            // Host buffers: gather into the arena on the GPU (after the host's own shader
            // writes to them); the query refits their leaves on the GPU and reads nothing back
            // (disabled meshes are not in it).
            g.memory_barrier(glow::SHADER_STORAGE_BARRIER_BIT);
            g.use_program(Some(o.gather));
            for k in [POS, LEAF_VERTS] {
                g.bind_buffer_base(glow::SHADER_STORAGE_BUFFER, BINDING[k], Some(o.buffers[k]));
            }
            for (id, b) in &self.bound {
                if !meshes[id].enabled {
                    continue;
                }
                let s = &self.slots[id];
                g.bind_buffer_base(glow::SHADER_STORAGE_BUFFER, 6, buffer(b.buffer));
                set_u32(g, o.gather, "u_src_offset", (b.offset / 4) as u32);
                set_u32(g, o.gather, "u_src_stride", (b.stride / 4) as u32);
                set_u32(g, o.gather, "u_dst_vertex", s.vertex_base);
                dispatch(g, o.gather, s.vertices);
            }
            g.memory_barrier(glow::SHADER_STORAGE_BARRIER_BIT);
            self.gl.check("gathering positions from host buffers")
        }
    }

    /// Room the whole query's buffers start from (leaf pairs, step-3/4 list words, step-5
    /// hits); they grow when a query needs more. For tests of the growth path.
    pub fn set_room(&mut self, pairs: u32, lists: u32, hits: u32) {
        self.caps = Caps {
            pairs: pairs.max(1),
            lists: lists.max(1),
            hits: hits.max(1),
        };
    }

    /// Sizes the whole query's buffers for `caps` and `l1` step-1 hits. A size the GL
    /// cannot take (past `i32::MAX` bytes or the largest storage block) is refused before
    /// any allocation; an allocation the GL reports failing forgets the sizes and the room.
    unsafe fn size_query_buffers(&mut self, l1: u32) -> Result<()> {
        if self.sized.is_some_and(|(c, l)| {
            c.pairs == self.caps.pairs
                && c.lists == self.caps.lists
                && c.hits == self.caps.hits
                && l >= l1
        }) {
            return Ok(());
        }
        let c = self.caps;
        let l1 = l1.max(self.sized.map_or(0, |(_, l)| l));
        let sizes = [
            (L1, "step-1 hits", l1 as u64),
            (PAIRS, "leaf pairs", 8 * c.pairs as u64),
            (LISTS, "step-3/4 lists", c.lists as u64),
            (RESULT, "contacts", HEADER as u64 + 2 * c.hits as u64),
        ];
        let limit = self.max_block.min(i32::MAX as u64);
        if let Some((_, what, words)) = sizes.iter().find(|(_, _, w)| 4 * w > limit) {
            self.caps = Caps::default(); // the next query starts from the usual room
            return Err(Error::new(
                ErrorKind::OutOfMemory,
                format!(
                    "the query needs a {} MiB buffer for its {what}; this GL's storage blocks \
                     take at most {} MiB",
                    (4 * words) >> 20,
                    limit >> 20
                ),
            ));
        }
        let g = &self.gl.gl;
        let b = &self.obj.as_ref().unwrap().buffers;
        self.sized = None;
        for (buf, _, words) in sizes {
            g.bind_buffer(glow::SHADER_STORAGE_BUFFER, Some(b[buf]));
            g.buffer_data_size(
                glow::SHADER_STORAGE_BUFFER,
                (4 * words).max(16) as i32,
                if buf == RESULT {
                    glow::DYNAMIC_READ
                } else {
                    glow::DYNAMIC_COPY
                },
            );
        }
        if let Err(e) = self.gl.check_alloc("allocating the query's buffers") {
            self.caps = Caps::default();
            return Err(e);
        }
        self.sized = Some((c, l1));
        Ok(())
    }

    /// Steps 1 to 5 on the GPU, one read-back (see the module's documentation).
    fn query_inner(
        &mut self,
        q: &QueryMeshes<'_>,
        out: &mut Vec<Contact>,
        stats: &mut QueryStats,
    ) -> Result<()> {
        let t0 = std::time::Instant::now();
        let reference = &self.slots[&q.meshes[0].0];
        let (ref_mesh, ref_base, ref_leaves) =
            (reference.index, reference.leaf_base, reference.leaves);
        // Other meshes: (first global leaf, leaves, first thread, arena index); polygon
        // bases for mapping hits back, sorted.
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
                    for k in 0..3 {
                        r[k] = order_key(b.min[k]);
                        r[3 + k] = order_key(b.max[k]);
                    }
                }
                _ => r[..3].fill(u32::MAX), // grown down by the refit
            }
        }
        let h_base = (q.half_depth as f32).max(0.0);
        let mut header = [0u32; HEADER];
        header[12] = if refit.is_empty() {
            ((q.gl_half_depth() * (1.0 + 1e-6)) as f32).to_bits()
        } else {
            h_base.to_bits()
        };
        let mut raw: Vec<u32> = Vec::new();
        let mut runs = 0;
        loop {
            runs += 1;
            let caps = self.caps;
            unsafe { self.size_query_buffers(l1_cap)? };
            let g = &self.gl.gl;
            unsafe {
                let o = self.obj.as_ref().unwrap();
                let b = &o.buffers;
                upload(g, b[OTHERS], bytes(&others));
                upload(g, b[ROOTS], bytes(&roots));
                g.bind_buffer(glow::SHADER_STORAGE_BUFFER, Some(b[RESULT]));
                g.buffer_sub_data_u8_slice(glow::SHADER_STORAGE_BUFFER, 0, bytes(&header));
                for k in [
                    POS, POLYS, BOXES, LEAF_RANGE, LEAF_POLYS, OTHERS, L1, PAIRS, LISTS, RESULT,
                    ROOTS,
                ] {
                    g.bind_buffer_base(glow::SHADER_STORAGE_BUFFER, BINDING[k], Some(b[k]));
                }
                g.bind_buffer(glow::DISPATCH_INDIRECT_BUFFER, Some(b[RESULT]));
                let uniforms = |p: glow::NativeProgram| {
                    g.use_program(Some(p));
                    set_u32(g, p, "u_ref_mesh", ref_mesh);
                    set_u32(g, p, "u_ref_leaf_base", ref_base);
                    set_u32(g, p, "u_ref_leaves", ref_leaves);
                    set_u32(g, p, "u_others", q.meshes.len() as u32 - 1);
                    set_u32(g, p, "u_l1_cap", l1_cap);
                    set_u32(g, p, "u_pair_cap", caps.pairs);
                    set_u32(g, p, "u_list_cap", caps.lists);
                    set_u32(g, p, "u_hit_cap", caps.hits);
                    let l = g.get_uniform_location(p, "u_pad_rel");
                    g.uniform_1_f32(l.as_ref(), 1.0 / (1u64 << 40) as f32);
                    let l = g.get_uniform_location(p, "u_h_base");
                    g.uniform_1_f32(l.as_ref(), h_base);
                };
                let [k_refit, step1, sizes, step2, step34, step5] = o.query;
                let storage = glow::SHADER_STORAGE_BARRIER_BIT;
                let command = storage | glow::COMMAND_BARRIER_BIT;
                if !refit.is_empty() {
                    uniforms(k_refit);
                    for &(first, leaves) in &refit {
                        set_u32(g, k_refit, "u_first_leaf", first);
                        dispatch(g, k_refit, leaves);
                    }
                    g.memory_barrier(storage);
                    uniforms(sizes);
                    set_u32(g, sizes, "u_src", 3);
                    dispatch(g, sizes, GROUP);
                    g.memory_barrier(storage);
                }
                uniforms(step1);
                dispatch(g, step1, l1_cap);
                g.memory_barrier(storage);
                // Each step after step 1: one workgroup sizes it, then it runs.
                for (src, step, args) in [(0, step2, 24), (1, step34, 28), (2, step5, 32)] {
                    uniforms(sizes);
                    set_u32(g, sizes, "u_src", src);
                    dispatch(g, sizes, GROUP);
                    g.memory_barrier(command);
                    uniforms(step);
                    g.dispatch_compute_indirect(4 * args);
                    g.memory_barrier(storage);
                }
                g.memory_barrier(glow::BUFFER_UPDATE_BARRIER_BIT);
                self.gl.check("the query dispatches")?;
                // The one read-back: map the result, copy the header and the hits it counts.
                g.bind_buffer(glow::SHADER_STORAGE_BUFFER, Some(b[RESULT]));
                let len = 4 * (HEADER + 2 * caps.hits as usize);
                let p = g.map_buffer_range(
                    glow::SHADER_STORAGE_BUFFER,
                    0,
                    len as i32,
                    glow::MAP_READ_BIT,
                );
                if p.is_null() {
                    self.gl.check("mapping the query's result")?;
                    return Err(gl_err("glMapBufferRange returned NULL".into()));
                }
                let words = p.cast::<u32>();
                let n = (*words.add(4)).min(caps.hits) as usize;
                raw.clear();
                raw.extend_from_slice(std::slice::from_raw_parts(words, HEADER + 2 * n));
                g.unmap_buffer(glow::SHADER_STORAGE_BUFFER);
                self.readbacks += 1;
                self.gl.check("reading the query's result")?;
            }
            if raw[0] != 0 {
                let id = self
                    .slots
                    .iter()
                    .find(|(_, s)| s.index == raw[0] - 1)
                    .map_or(0, |(id, _)| *id);
                return Err(Error::new(
                    ErrorKind::NonFinite,
                    format!("mesh {id}: its bound GL buffer holds a NaN or infinite coordinate"),
                ));
            }
            if raw[11] != 0 {
                return Err(Error::new(
                    ErrorKind::Unsupported,
                    "a step of this query asks 2^31 tests or more, more than one dispatch takes",
                ));
            }
            // Grow what overflowed; the counters after an overflowed one may be short, so
            // loop until nothing overflows (each run completes one more step: at most 4).
            let grow = |need: u32, cap: u32| {
                if need > cap {
                    need.saturating_add(need / 2).max(cap.saturating_mul(2))
                } else {
                    cap
                }
            };
            let next = Caps {
                pairs: grow(raw[2], caps.pairs),
                lists: grow(raw[3], caps.lists),
                hits: grow(raw[4], caps.hits),
            };
            if next.pairs == caps.pairs && next.lists == caps.lists && next.hits == caps.hits {
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
        let r = &raw[..];
        stats.tests = [
            l1_cap as usize,
            r[1] as usize * ref_leaves as usize,
            r[5] as usize,
            r[6] as usize,
            r[10] as usize,
        ];
        stats.hits = [r[1], r[2], r[7], r[8], r[4]].map(|x| x as usize);
        // Global polygon id -> (mesh position, leaf-ordered polygon).
        let locate = |gp: u32| {
            let i = bases.partition_point(|&(b, _)| b <= gp) - 1;
            let (base, mi) = bases[i];
            (mi, gp - base)
        };
        // Every position on the CPU: each hit is confirmed with the CPU backend's test at
        // the epsilon asked for (the GPU used at least the minimum depth: it lost nothing).
        let confirm = refit.is_empty().then_some(q.half_depth);
        let ref_mesh = q.meshes[0].1;
        for hit in raw[HEADER..].chunks_exact(2) {
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
        stats.nanos[0] = t0.elapsed().as_nanos() as u64;
        Ok(())
    }
}

/// A float's key whose unsigned order is the float order (as `key` in query.glsl).
fn order_key(f: f32) -> u32 {
    let b = f.to_bits();
    if b & 0x8000_0000 != 0 {
        !b
    } else {
        b | 0x8000_0000
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

fn too_big() -> Error {
    Error::new(
        ErrorKind::Unsupported,
        "the query needs more GPU buffer room than 32-bit counts can address",
    )
}

impl WholeQuery for GlComputeSelector {
    fn run_query(
        &mut self,
        q: &QueryMeshes<'_>,
        out: &mut Vec<Contact>,
        stats: &mut QueryStats,
    ) -> Result<()> {
        let gl: *const Gl = &self.gl;
        // SAFETY: as in prepare.
        let guard = StateGuard::enter(unsafe { &*gl }, uses())?;
        let r = self.query_inner(q, out, stats);
        let done = guard.finish();
        r?;
        done
    }
}

impl Selector for GlComputeSelector {
    fn backend(&self) -> Backend {
        Backend::GlCompute
    }

    fn prepare(&mut self, meshes: &mut BTreeMap<u32, Mesh>) -> Result<()> {
        let gl: *const Gl = &self.gl;
        // SAFETY: the guard only reads `gl`, which prepare_inner never moves or replaces.
        let guard = StateGuard::enter(unsafe { &*gl }, uses())?;
        let r = self.prepare_inner(meshes);
        let done = guard.finish();
        r?;
        done
    }

    fn engine(&mut self) -> Engine<'_> {
        Engine::Whole(self)
    }

    fn take_readbacks(&mut self) -> u32 {
        std::mem::take(&mut self.readbacks)
    }

    fn mesh_updated(&mut self, id: u32) {
        self.bound.remove(&id);
        if let Some(s) = self.slots.get_mut(&id) {
            s.uploaded = None;
        }
    }

    fn mesh_destroyed(&mut self, id: u32) {
        self.bound.remove(&id);
    }

    fn gl_bound(&self, id: u32) -> bool {
        self.bound.contains_key(&id)
    }

    fn bind_gl_buffer(
        &mut self,
        id: u32,
        mesh: &Mesh,
        buf: u32,
        offset: usize,
        stride: usize,
    ) -> Result<()> {
        let stride = if stride == 0 { 12 } else { stride };
        if stride < 12 || stride % 4 != 0 || offset % 4 != 0 {
            return Err(Error::invalid(format!(
                "offset {offset} and stride {stride} must be multiples of 4, stride 0 or >= 12"
            )));
        }
        let need = crate::mesh::Positions::byte_len(mesh.vertex_count(), stride)
            .and_then(|n| n.checked_add(offset))
            .ok_or_else(|| Error::invalid("offset + vertex_count * stride overflows"))?;
        let guard = StateGuard::enter(&self.gl, uses())?;
        let g = &self.gl.gl;
        let size = unsafe {
            if buf == 0 || !g.is_buffer(glow::NativeBuffer(std::num::NonZeroU32::new(buf).unwrap()))
            {
                None
            } else {
                g.bind_buffer(glow::COPY_READ_BUFFER, buffer(buf));
                Some(g.get_buffer_parameter_i32(glow::COPY_READ_BUFFER, glow::BUFFER_SIZE))
            }
        };
        guard.finish()?;
        match size {
            None => Err(Error::invalid(format!("gl_buffer {buf} is not a buffer object of this context"))),
            Some(s) if (s as usize) < need => Err(Error::invalid(format!(
                "gl_buffer {buf} holds {s} bytes; {need} are needed for {} vertices at offset {offset}, stride {stride}",
                mesh.vertex_count()
            ))),
            Some(_) => {
                self.bound.insert(id, Bound { buffer: buf, offset, stride });
                Ok(())
            }
        }
    }

    fn release(&mut self) {
        if let Some(o) = self.obj.take() {
            // Our objects are bound nowhere between calls (the guard gave every binding
            // back), so deleting them changes no host state: done even when the guard
            // refuses (say, the host's transform feedback is running), rather than leaked.
            let guard = StateGuard::enter(&self.gl, uses()).ok();
            unsafe {
                let g = &self.gl.gl;
                g.delete_program(o.gather);
                for p in o.query {
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
    }
}
