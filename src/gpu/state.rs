//! The one place where GL state is saved and restored.
//!
//! [`StateGuard::enter`] takes the host's pending GL error (kept, not ours), saves every
//! piece of state a backend may change, and its `Drop` (or [`StateGuard::finish`]) puts
//! all of it back, so even a panic caught at the C boundary leaves the host's state as it
//! was. What is saved and restored is listed once, for users, in docs/API.md "GL state is
//! left as it was found" (the GL contract): `save` and `restore` below are what it describes, tests/gl_state.rs
//! checks it, and the three change together. Fixed-function state (GL_SELECT) and the
//! indexed buffer bindings (GL_COMPUTE) are saved as far as [`Uses`] says a backend touches
//! them. Never touched, so never saved: the transform feedback object and buffer bindings,
//! textures, samplers and images. A host in the middle of transform feedback that is not
//! paused is refused (no program could be changed without ending it): pause it around the
//! call.
//!
//! A host error pending on entry (say GL_INVALID_ENUM) does not fail our call; it is raised
//! again on exit when it can be (GL_INVALID_ENUM, GL_INVALID_VALUE, GL_INVALID_OPERATION),
//! so the host's next glGetError still sees it.

use glow::HasContext;

use super::compat;
use super::{buffer, framebuffer, program, renderbuffer, vertex_array, Gl};
use crate::error::{Error, ErrorKind, Result};

/// What a backend will touch beyond the common state.
#[derive(Clone, Copy, Debug, Default)]
pub struct Uses {
    /// Fixed-function state (matrices, render mode, selection buffer, clip planes).
    pub fixed_function: bool,
    /// Indexed buffer bindings `0..n` of the shader storage, atomic counter and uniform
    /// targets.
    pub indexed_bindings: u32,
}

const MAX_CLIP: u32 = 8;

/// glGetError is drained at most this many times (a GL keeps one flag per error kind).
const MAX_ERRORS: usize = 8;

struct FixedFunction {
    /// Program pipeline binding (GL 4.1+ with the entry point loaded).
    pipeline: Option<u32>,
    matrix_mode: i32,
    projection: [f64; 16],
    modelview: [f64; 16],
    select_ptr: *mut u32,
    select_size: i32,
    name_depth: i32,
    clip_planes: Vec<[f64; 4]>,
}

/// An indexed binding, its range in 64 bits (`GLintptr` / `GLsizeiptr`: a range past 2 GiB
/// is restored as it was).
struct Indexed {
    target: u32,
    index: u32,
    buffer: u32,
    start: i64,
    size: i64,
}

struct Saved {
    program: u32,
    vao: Option<u32>,
    generic: Vec<(u32, u32)>,
    indexed: Vec<Indexed>,
    draw_fb: u32,
    read_fb: u32,
    renderbuffer: u32,
    viewport: [i32; 4],
    scissor: [i32; 4],
    polygon_mode: [i32; 2],
    enables: Vec<(u32, bool)>,
    pixel_store: Vec<(u32, i32)>,
    ff: Option<FixedFunction>,
}

/// Saves the host's state on entry, restores it on drop.
pub struct StateGuard<'a> {
    gl: &'a Gl,
    saved: Option<Saved>,
    host_error: u32,
    restored: bool,
}

const IDENTITY: [f64; 16] = [
    1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0,
];

/// Takes every pending GL error; the first one, or GL_NO_ERROR.
fn drain_errors(g: &glow::Context) -> u32 {
    let mut first = glow::NO_ERROR;
    for _ in 0..MAX_ERRORS {
        // SAFETY: glGetError on the current context (a guard exists only for a `Gl`
        // loaded for the context current on this thread: the C API's contract).
        let e = unsafe { g.get_error() };
        if e == glow::NO_ERROR {
            break;
        }
        if first == glow::NO_ERROR {
            first = e;
        }
    }
    first
}

impl<'a> StateGuard<'a> {
    /// Takes the host's pending error and saves the state `uses` says will be touched.
    /// Fails (changing nothing) when a compatibility context is in GL_SELECT or
    /// GL_FEEDBACK render mode, which no call could undo exactly.
    ///
    /// First of all, [`Gl::check_current`]: with no context, or a context that is neither
    /// the scene's nor one sharing its objects, it fails with GL_UNAVAILABLE before any
    /// GL call that could change or raise anything.
    pub fn enter(gl: &'a Gl, uses: Uses) -> Result<StateGuard<'a>> {
        gl.check_current()?;
        let mut guard = StateGuard {
            gl,
            saved: None,
            host_error: drain_errors(&gl.gl),
            restored: false,
        };
        // SAFETY: `gl` was loaded for the context current on this thread (the C API's
        // contract for GL-backed calls); `save` only queries state. On an error the guard
        // drops: it raises the host's error again and restores nothing.
        guard.saved = Some(unsafe { save(gl, uses) }?);
        Ok(guard)
    }

    /// Restores the host's state; `Err(GL_ERROR)` if the GL reported an error of ours
    /// (during the work or the restore).
    pub fn finish(mut self) -> Result<()> {
        let r = self.gl.check("glcollide's GL work");
        self.restore();
        r
    }

    fn restore(&mut self) {
        if std::mem::replace(&mut self.restored, true) {
            return;
        }
        if let Some(s) = self.saved.take() {
            // SAFETY: the context `save` read `s` from is current (as in `enter`), and `s`
            // holds the host's own names and values, which the GL accepted before.
            unsafe { restore(self.gl, &s) };
        }
        // Our errors were reported (finish) or superseded by the failure in flight.
        drain_errors(&self.gl.gl);
        // SAFETY: as in `enter`.
        unsafe { reraise(&self.gl.gl, self.host_error) };
        self.host_error = glow::NO_ERROR;
    }
}

impl Drop for StateGuard<'_> {
    fn drop(&mut self) {
        self.restore();
    }
}

/// Raises GL error `e` again (the kinds a call can raise on purpose), with the debug
/// output (GL 4.3 / KHR_debug) off meanwhile: the host's glGetError sees its error again,
/// and its debug callback or log gets no message of ours (the host's own call already
/// reported it).
///
/// # Safety
/// `g` was loaded for the context current on this thread.
unsafe fn reraise(g: &glow::Context, e: u32) {
    if e == glow::NO_ERROR {
        return;
    }
    // SAFETY: the caller's contract; each call is invalid on purpose (enum 0, a negative
    // viewport, a VAO name never generated) and changes no state; GL_DEBUG_OUTPUT is put
    // back as it was.
    unsafe {
        let quiet = g.supports_debug() && g.is_enabled(glow::DEBUG_OUTPUT);
        if quiet {
            g.disable(glow::DEBUG_OUTPUT);
        }
        match e {
            glow::INVALID_ENUM => g.enable(0),
            glow::INVALID_VALUE => g.viewport(0, 0, -1, -1),
            glow::INVALID_OPERATION => g.bind_vertex_array(vertex_array(0xFFFF_FFF0)),
            _ => {}
        }
        if quiet {
            g.enable(glow::DEBUG_OUTPUT);
        }
    }
}

fn at_least(gl: &Gl, v: (u32, u32)) -> bool {
    gl.info.version >= v
}

/// Generic buffer binding queries and their targets, for the context's version.
fn generic_targets(gl: &Gl) -> Vec<(u32, u32)> {
    let mut t = vec![
        (glow::ARRAY_BUFFER_BINDING, glow::ARRAY_BUFFER),
        (
            glow::ELEMENT_ARRAY_BUFFER_BINDING,
            glow::ELEMENT_ARRAY_BUFFER,
        ),
        (glow::PIXEL_PACK_BUFFER_BINDING, glow::PIXEL_PACK_BUFFER),
        (glow::PIXEL_UNPACK_BUFFER_BINDING, glow::PIXEL_UNPACK_BUFFER),
    ];
    if at_least(gl, (3, 1)) {
        t.push((glow::UNIFORM_BUFFER_BINDING, glow::UNIFORM_BUFFER));
        t.push((glow::COPY_READ_BUFFER_BINDING, glow::COPY_READ_BUFFER));
        t.push((glow::COPY_WRITE_BUFFER_BINDING, glow::COPY_WRITE_BUFFER));
    }
    if at_least(gl, (4, 2)) {
        t.push((
            glow::ATOMIC_COUNTER_BUFFER_BINDING,
            glow::ATOMIC_COUNTER_BUFFER,
        ));
    }
    if at_least(gl, (4, 3)) {
        t.push((
            glow::SHADER_STORAGE_BUFFER_BINDING,
            glow::SHADER_STORAGE_BUFFER,
        ));
        t.push((
            glow::DISPATCH_INDIRECT_BUFFER_BINDING,
            glow::DISPATCH_INDIRECT_BUFFER,
        ));
    }
    t
}

/// An indexed buffer target: the GL version that has it, the target, its binding, start
/// and size queries, and the query of how many binding points the GL has.
struct IndexedTarget {
    since: (u32, u32),
    target: u32,
    binding: u32,
    start: u32,
    size: u32,
    points: u32,
}

const INDEXED_TARGETS: [IndexedTarget; 3] = [
    IndexedTarget {
        since: (3, 1),
        target: glow::UNIFORM_BUFFER,
        binding: glow::UNIFORM_BUFFER_BINDING,
        start: glow::UNIFORM_BUFFER_START,
        size: glow::UNIFORM_BUFFER_SIZE,
        points: glow::MAX_UNIFORM_BUFFER_BINDINGS,
    },
    IndexedTarget {
        since: (4, 2),
        target: glow::ATOMIC_COUNTER_BUFFER,
        binding: glow::ATOMIC_COUNTER_BUFFER_BINDING,
        start: glow::ATOMIC_COUNTER_BUFFER_START,
        size: glow::ATOMIC_COUNTER_BUFFER_SIZE,
        points: glow::MAX_ATOMIC_COUNTER_BUFFER_BINDINGS,
    },
    IndexedTarget {
        since: (4, 3),
        target: glow::SHADER_STORAGE_BUFFER,
        binding: glow::SHADER_STORAGE_BUFFER_BINDING,
        start: glow::SHADER_STORAGE_BUFFER_START,
        size: glow::SHADER_STORAGE_BUFFER_SIZE,
        points: glow::MAX_SHADER_STORAGE_BUFFER_BINDINGS,
    },
];

/// The enables we save (and may change), for the context's version.
pub fn enable_caps(gl: &Gl) -> Vec<u32> {
    let mut c = vec![
        glow::DEPTH_TEST,
        glow::BLEND,
        glow::CULL_FACE,
        glow::SCISSOR_TEST,
        glow::STENCIL_TEST,
        glow::POLYGON_OFFSET_FILL,
        glow::MULTISAMPLE,
    ];
    if at_least(gl, (3, 0)) {
        c.push(glow::RASTERIZER_DISCARD);
        c.push(glow::FRAMEBUFFER_SRGB);
    }
    if at_least(gl, (3, 1)) {
        c.push(glow::PRIMITIVE_RESTART);
    }
    if at_least(gl, (3, 2)) {
        c.push(glow::DEPTH_CLAMP);
    }
    let n = clip_planes(gl);
    c.extend((0..n).map(|i| glow::CLIP_DISTANCE0 + i));
    c
}

/// User clip planes / clip distances saved (at most 8).
pub fn clip_planes(gl: &Gl) -> u32 {
    // SAFETY: a GL 3.0 query (GL_MAX_CLIP_PLANES before it, same value) on the current
    // context.
    let n = unsafe { gl.gl.get_parameter_i32(glow::MAX_CLIP_DISTANCES) };
    (n.max(0) as u32).min(MAX_CLIP)
}

const PIXEL_STORE: [u32; 10] = [
    glow::PACK_ALIGNMENT,
    glow::UNPACK_ALIGNMENT,
    glow::PACK_ROW_LENGTH,
    glow::UNPACK_ROW_LENGTH,
    glow::PACK_SKIP_PIXELS,
    glow::UNPACK_SKIP_PIXELS,
    glow::PACK_SKIP_ROWS,
    glow::UNPACK_SKIP_ROWS,
    glow::PACK_IMAGE_HEIGHT,
    glow::UNPACK_IMAGE_HEIGHT,
];

/// Refuses a host whose transform feedback runs unpaused (no program could be changed).
///
/// # Safety
/// `gl` was loaded for the context current on this thread.
unsafe fn refuse_running_transform_feedback(gl: &Gl) -> Result<()> {
    if !at_least(gl, (4, 0)) {
        return Ok(());
    }
    // SAFETY: the caller's contract; GL 4.0 queries.
    let running = unsafe {
        gl.gl.get_parameter_i32(glow::TRANSFORM_FEEDBACK_ACTIVE) != 0
            && gl.gl.get_parameter_i32(glow::TRANSFORM_FEEDBACK_PAUSED) == 0
    };
    if running {
        return Err(Error::new(
            ErrorKind::GlUnavailable,
            "transform feedback is active on this context; pause it (glPauseTransformFeedback) \
             or end it before calling glcollide",
        ));
    }
    Ok(())
}

/// The fixed-function state GL_SELECT changes; refuses a context not in GL_RENDER mode.
///
/// # Safety
/// `gl` was loaded for the context current on this thread, with fixed-function entry points.
unsafe fn save_fixed_function(gl: &Gl) -> Result<FixedFunction> {
    let f = gl.ff();
    // SAFETY: the caller's contract; every query writes at most the array it is given
    // (16 doubles for a matrix, 4 for a clip plane, one pointer, one int).
    unsafe {
        let i = |p: u32| gl.gl.get_parameter_i32(p);
        if i(compat::RENDER_MODE) as u32 != compat::RENDER {
            return Err(Error::new(
                ErrorKind::GlUnavailable,
                "the context is in GL_SELECT or GL_FEEDBACK render mode; call glcollide in GL_RENDER mode",
            ));
        }
        let mut projection = [0.0; 16];
        let mut modelview = [0.0; 16];
        f.GetDoublev(compat::PROJECTION_MATRIX, projection.as_mut_ptr());
        f.GetDoublev(compat::MODELVIEW_MATRIX, modelview.as_mut_ptr());
        let mut ptr: *mut std::ffi::c_void = std::ptr::null_mut();
        // The generated binding takes `*const *mut c_void` for the GL's `void **`: pass a
        // pointer that may be written through.
        f.GetPointerv(
            compat::SELECTION_BUFFER_POINTER,
            (&raw mut ptr).cast_const(),
        );
        let clip_planes = (0..clip_planes(gl))
            .map(|k| {
                let mut eq = [0.0; 4];
                f.GetClipPlane(compat::CLIP_PLANE0 + k, eq.as_mut_ptr());
                eq
            })
            .collect();
        let pipeline = gl
            .info
            .program_pipelines
            .then(|| i(glow::PROGRAM_PIPELINE_BINDING) as u32);
        Ok(FixedFunction {
            pipeline,
            matrix_mode: i(compat::MATRIX_MODE),
            projection,
            modelview,
            select_ptr: ptr.cast(),
            select_size: i(compat::SELECTION_BUFFER_SIZE),
            name_depth: i(compat::NAME_STACK_DEPTH),
            clip_planes,
        })
    }
}

/// The indexed bindings `0..uses.indexed_bindings` of every indexed target the GL has.
///
/// # Safety
/// `gl` was loaded for the context current on this thread.
unsafe fn save_indexed(gl: &Gl, uses: Uses) -> Vec<Indexed> {
    let g = &gl.gl;
    let mut indexed = Vec::new();
    for t in INDEXED_TARGETS.iter().filter(|t| at_least(gl, t.since)) {
        // SAFETY: the caller's contract; queries of a target this version has, at indices
        // below its number of binding points.
        unsafe {
            let points = g.get_parameter_i32(t.points).max(0) as u32;
            for index in 0..uses.indexed_bindings.min(points) {
                indexed.push(Indexed {
                    target: t.target,
                    index,
                    buffer: g.get_parameter_indexed_i32(t.binding, index) as u32,
                    start: g.get_parameter_indexed_i64(t.start, index),
                    size: g.get_parameter_indexed_i64(t.size, index),
                });
            }
        }
    }
    indexed
}

/// # Safety
/// `gl` was loaded for the context current on this thread.
unsafe fn save(gl: &Gl, uses: Uses) -> Result<Saved> {
    // SAFETY: the caller's contract.
    unsafe { refuse_running_transform_feedback(gl) }?;
    let ff = if uses.fixed_function {
        // SAFETY: the caller's contract; a backend that uses fixed-function state exists
        // only with the entry points (GL_SELECT checks them at creation).
        Some(unsafe { save_fixed_function(gl) }?)
    } else {
        None
    };
    // SAFETY: the caller's contract.
    let indexed = unsafe { save_indexed(gl, uses) };
    let g = &gl.gl;
    // SAFETY: the caller's contract; queries of state this version has, each writing at
    // most the slice it is given (4 ints for a box, 1 or 2 for the polygon mode).
    let s = unsafe {
        let i = |p: u32| g.get_parameter_i32(p);
        let mut viewport = [0; 4];
        g.get_parameter_i32_slice(glow::VIEWPORT, &mut viewport);
        let mut scissor = [0; 4];
        g.get_parameter_i32_slice(glow::SCISSOR_BOX, &mut scissor);
        let mut polygon_mode = [glow::FILL as i32; 2];
        g.get_parameter_i32_slice(
            glow::POLYGON_MODE,
            &mut polygon_mode[..if gl.info.core_profile { 1 } else { 2 }],
        );
        if gl.info.core_profile {
            polygon_mode[1] = polygon_mode[0];
        }
        Saved {
            program: i(glow::CURRENT_PROGRAM) as u32,
            vao: at_least(gl, (3, 0)).then(|| i(glow::VERTEX_ARRAY_BINDING) as u32),
            generic: generic_targets(gl)
                .into_iter()
                .map(|(q, t)| (t, i(q) as u32))
                .collect(),
            indexed,
            draw_fb: i(glow::DRAW_FRAMEBUFFER_BINDING) as u32,
            read_fb: i(glow::READ_FRAMEBUFFER_BINDING) as u32,
            renderbuffer: i(glow::RENDERBUFFER_BINDING) as u32,
            viewport,
            scissor,
            polygon_mode,
            enables: enable_caps(gl)
                .into_iter()
                .map(|c| (c, g.is_enabled(c)))
                .collect(),
            pixel_store: PIXEL_STORE.iter().map(|&p| (p, i(p))).collect(),
            ff,
        }
    };
    // Queries of this version's state cannot fail; if one did, the context is not what its
    // version says: report it rather than restore garbage.
    gl.check("saving the host's GL state")?;
    Ok(s)
}

/// Puts back the fixed-function state `save_fixed_function` read.
///
/// # Safety
/// `gl` was loaded for the context current on this thread, with fixed-function entry
/// points; `ff` was read from it.
unsafe fn restore_fixed_function(gl: &Gl, ff: &FixedFunction) {
    let f = gl.ff();
    // SAFETY: the caller's contract; the values are the host's own (its selection buffer
    // and size as it set them, matrices of 16 doubles, planes of 4).
    unsafe {
        if gl.gl.get_parameter_i32(compat::RENDER_MODE) as u32 != compat::RENDER {
            // Interrupted mid-selection: pop our names, leave selection mode.
            let mut depth = gl.gl.get_parameter_i32(compat::NAME_STACK_DEPTH);
            while depth > ff.name_depth {
                f.PopName();
                depth -= 1;
            }
            f.RenderMode(compat::RENDER);
        }
        f.SelectBuffer(ff.select_size, ff.select_ptr);
        // Clip-plane equations are stored in eye coordinates: give them back under an
        // identity modelview so they are stored unchanged.
        f.MatrixMode(compat::MODELVIEW);
        f.LoadMatrixd(IDENTITY.as_ptr());
        for (k, eq) in ff.clip_planes.iter().enumerate() {
            f.ClipPlane(compat::CLIP_PLANE0 + k as u32, eq.as_ptr());
        }
        f.LoadMatrixd(ff.modelview.as_ptr());
        f.MatrixMode(compat::PROJECTION);
        f.LoadMatrixd(ff.projection.as_ptr());
        f.MatrixMode(ff.matrix_mode as u32);
        if let Some(p) = ff.pipeline {
            f.BindProgramPipeline(p);
        }
    }
}

/// # Safety
/// `gl` was loaded for the context current on this thread; `s` was saved from it.
unsafe fn restore(gl: &Gl, s: &Saved) {
    if let Some(ff) = &s.ff {
        // SAFETY: the caller's contract.
        unsafe { restore_fixed_function(gl, ff) };
    }
    let g = &gl.gl;
    // SAFETY: the caller's contract; every name and value is one the host had bound or
    // set, read back from this context.
    unsafe {
        for &(cap, on) in &s.enables {
            if on {
                g.enable(cap)
            } else {
                g.disable(cap)
            }
        }
        if gl.info.core_profile {
            g.polygon_mode(glow::FRONT_AND_BACK, s.polygon_mode[0] as u32);
        } else {
            g.polygon_mode(glow::FRONT, s.polygon_mode[0] as u32);
            g.polygon_mode(glow::BACK, s.polygon_mode[1] as u32);
        }
        g.use_program(program(s.program));
        if let Some(v) = s.vao {
            g.bind_vertex_array(vertex_array(v));
        }
        // Indexed first: binding an indexed point also sets the generic one.
        for x in &s.indexed {
            if x.buffer == 0 || x.size == 0 {
                g.bind_buffer_base(x.target, x.index, buffer(x.buffer));
            } else {
                gl.bind_buffer_range(x.target, x.index, x.buffer, x.start, x.size);
            }
        }
        for &(target, b) in &s.generic {
            g.bind_buffer(target, buffer(b));
        }
        g.bind_framebuffer(glow::DRAW_FRAMEBUFFER, framebuffer(s.draw_fb));
        g.bind_framebuffer(glow::READ_FRAMEBUFFER, framebuffer(s.read_fb));
        g.bind_renderbuffer(glow::RENDERBUFFER, renderbuffer(s.renderbuffer));
        let v = s.viewport;
        g.viewport(v[0], v[1], v[2], v[3]);
        let c = s.scissor;
        g.scissor(c[0], c[1], c[2], c[3]);
        for &(p, v) in &s.pixel_store {
            g.pixel_store_i32(p, v);
        }
    }
}
