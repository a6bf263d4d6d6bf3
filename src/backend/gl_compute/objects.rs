//! The GL side of the backend: what the kernels need of the GL, the programs compiled and
//! the buffers made (and deleted on a failure), and the plain calls every stage makes
//! (upload, allocate, uniforms, dispatch).

use glow::HasContext;

use super::{Kernels, Objects, BINDINGS, BLOCKS, GROUP, NBUF};
use crate::error::{Error, Result};
use crate::gpu::{gl_err, shaders, unavailable, Gl};

/// Types whose every bit pattern is a value and which have no padding.
pub(super) trait Plain: Copy {}
impl Plain for u32 {}
impl Plain for f32 {}
impl Plain for [f32; 3] {}

pub(super) fn bytes<T: Plain>(v: &[T]) -> &[u8] {
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
pub(super) unsafe fn create_objects(g: &glow::Context) -> Result<Objects> {
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
pub(super) unsafe fn upload(g: &glow::Context, b: glow::NativeBuffer, data: &[u8]) {
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
pub(super) unsafe fn allocate(g: &glow::Context, b: glow::NativeBuffer, size: i32, usage: u32) {
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
pub(super) unsafe fn set_u32(g: &glow::Context, p: glow::NativeProgram, name: &str, v: u32) {
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
pub(super) unsafe fn set_f32(g: &glow::Context, p: glow::NativeProgram, name: &str, v: f32) {
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
pub(super) unsafe fn dispatch(g: &glow::Context, p: glow::NativeProgram, n: u32) {
    let groups = n.div_ceil(GROUP).max(1);
    let x = groups.min(65535);
    let y = groups.div_ceil(x);
    // SAFETY: the caller's contract; at most 65535 groups a side.
    unsafe {
        set_u32(g, p, "u_count", n);
        g.dispatch_compute(x, y, 1);
    }
}

/// Checks what the kernels need of the GL; GL_MAX_SHADER_STORAGE_BLOCK_SIZE in bytes.
pub(super) fn capabilities(gl: &Gl) -> Result<u64> {
    if !gl.info.compute {
        let (major, minor) = crate::gpu::compute_gl_version();
        return Err(unavailable(format!(
            "backend GL_COMPUTE needs GL {major}.{minor} (its shaders are GLSL \
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
            "backend GL_COMPUTE needs {BINDINGS} shader storage buffer bindings and \
             {BLOCKS} storage blocks per compute shader; this GL has {bindings} and {blocks}"
        )));
    }
    Ok(max_block.max(0) as u64)
}
