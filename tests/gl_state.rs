//! Host etiquette: a host with plenty of non-default GL state calls every GL-backed
//! function; a long list of state is snapshotted before and after each call and must not
//! change. A GL error the host left pending must not fail our call and must still be
//! pending after it. Runs in a compatibility context (GL_SELECT and GL_COMPUTE) and in a
//! core 4.5 context (GL_COMPUTE). The host also has a program pipeline, a transform feedback
//! object with its own buffers, and indexed bindings up to 15, one of them a range whose
//! offset and size are past 2 GiB where the GL reports such a range (Mesa 22 does not: see
//! `bind_far_range`); a host whose transform feedback is running is refused with a message,
//! and answered once it pauses it.
mod common;

use common::backends::gl_support;

use std::ffi::c_void;

use common::{place, shared_mesh, TestMesh};
use gl_support::*;
use glcollide::ffi::*;
use glow::HasContext;

type Snapshot = Vec<(String, Vec<f64>)>;

const INDEXED: u32 = 16;

fn snapshot(ctx: &Ctx, g: &glow::Context, profile: Profile) -> Snapshot {
    let mut s: Snapshot = Vec::new();
    // SAFETY: this test's GL context is current on this thread; the objects are its own.
    unsafe {
        let mut ints = |name: &str, p: u32, n: usize| {
            let mut v = vec![0i32; n];
            g.get_parameter_i32_slice(p, &mut v);
            s.push((name.to_string(), v.iter().map(|&x| x as f64).collect()));
        };
        for (name, p) in [
            ("CURRENT_PROGRAM", glow::CURRENT_PROGRAM),
            ("VERTEX_ARRAY_BINDING", glow::VERTEX_ARRAY_BINDING),
            ("ARRAY_BUFFER_BINDING", glow::ARRAY_BUFFER_BINDING),
            (
                "ELEMENT_ARRAY_BUFFER_BINDING",
                glow::ELEMENT_ARRAY_BUFFER_BINDING,
            ),
            ("PIXEL_PACK_BUFFER_BINDING", glow::PIXEL_PACK_BUFFER_BINDING),
            (
                "PIXEL_UNPACK_BUFFER_BINDING",
                glow::PIXEL_UNPACK_BUFFER_BINDING,
            ),
            ("UNIFORM_BUFFER_BINDING", glow::UNIFORM_BUFFER_BINDING),
            ("COPY_READ_BUFFER_BINDING", glow::COPY_READ_BUFFER_BINDING),
            ("COPY_WRITE_BUFFER_BINDING", glow::COPY_WRITE_BUFFER_BINDING),
            (
                "ATOMIC_COUNTER_BUFFER_BINDING",
                glow::ATOMIC_COUNTER_BUFFER_BINDING,
            ),
            (
                "SHADER_STORAGE_BUFFER_BINDING",
                glow::SHADER_STORAGE_BUFFER_BINDING,
            ),
            (
                "DISPATCH_INDIRECT_BUFFER_BINDING",
                glow::DISPATCH_INDIRECT_BUFFER_BINDING,
            ),
            (
                "DRAW_INDIRECT_BUFFER_BINDING",
                glow::DRAW_INDIRECT_BUFFER_BINDING,
            ),
            (
                "TRANSFORM_FEEDBACK_BUFFER_BINDING",
                glow::TRANSFORM_FEEDBACK_BUFFER_BINDING,
            ),
            ("DRAW_FRAMEBUFFER_BINDING", glow::DRAW_FRAMEBUFFER_BINDING),
            ("READ_FRAMEBUFFER_BINDING", glow::READ_FRAMEBUFFER_BINDING),
            ("RENDERBUFFER_BINDING", glow::RENDERBUFFER_BINDING),
            ("ACTIVE_TEXTURE", glow::ACTIVE_TEXTURE),
            ("TEXTURE_BINDING_2D", glow::TEXTURE_BINDING_2D),
            ("DEPTH_WRITEMASK", glow::DEPTH_WRITEMASK),
            ("DEPTH_FUNC", glow::DEPTH_FUNC),
            ("CULL_FACE_MODE", glow::CULL_FACE_MODE),
            ("FRONT_FACE", glow::FRONT_FACE),
            ("BLEND_SRC_RGB", glow::BLEND_SRC_RGB),
            ("BLEND_DST_RGB", glow::BLEND_DST_RGB),
            ("STENCIL_FUNC", glow::STENCIL_FUNC),
            ("STENCIL_WRITEMASK", glow::STENCIL_WRITEMASK),
            ("PROVOKING_VERTEX", glow::PROVOKING_VERTEX),
            ("PACK_ALIGNMENT", glow::PACK_ALIGNMENT),
            ("UNPACK_ALIGNMENT", glow::UNPACK_ALIGNMENT),
            ("PACK_ROW_LENGTH", glow::PACK_ROW_LENGTH),
            ("UNPACK_ROW_LENGTH", glow::UNPACK_ROW_LENGTH),
            ("PACK_SKIP_PIXELS", glow::PACK_SKIP_PIXELS),
            ("UNPACK_SKIP_ROWS", glow::UNPACK_SKIP_ROWS),
            ("UNPACK_IMAGE_HEIGHT", glow::UNPACK_IMAGE_HEIGHT),
            ("PATCH_VERTICES", glow::PATCH_VERTICES),
            ("PROGRAM_PIPELINE_BINDING", glow::PROGRAM_PIPELINE_BINDING),
            (
                "TRANSFORM_FEEDBACK_BINDING",
                glow::TRANSFORM_FEEDBACK_BINDING,
            ),
            ("TRANSFORM_FEEDBACK_ACTIVE", glow::TRANSFORM_FEEDBACK_ACTIVE),
            ("TRANSFORM_FEEDBACK_PAUSED", glow::TRANSFORM_FEEDBACK_PAUSED),
        ] {
            ints(name, p, 1);
        }
        ints("VIEWPORT", glow::VIEWPORT, 4);
        ints("SCISSOR_BOX", glow::SCISSOR_BOX, 4);
        ints("COLOR_WRITEMASK", glow::COLOR_WRITEMASK, 4);
        ints(
            "POLYGON_MODE",
            glow::POLYGON_MODE,
            if profile == Profile::Core { 1 } else { 2 },
        );
        let mut f = vec![0f32; 4];
        g.get_parameter_f32_slice(glow::COLOR_CLEAR_VALUE, &mut f);
        s.push((
            "COLOR_CLEAR_VALUE".into(),
            f.iter().map(|&x| x as f64).collect(),
        ));
        s.push((
            "LINE_WIDTH".into(),
            vec![g.get_parameter_f32(glow::LINE_WIDTH) as f64],
        ));
        s.push((
            "POINT_SIZE".into(),
            vec![g.get_parameter_f32(glow::POINT_SIZE) as f64],
        ));
        for (name, cap) in [
            ("DEPTH_TEST", glow::DEPTH_TEST),
            ("BLEND", glow::BLEND),
            ("CULL_FACE", glow::CULL_FACE),
            ("SCISSOR_TEST", glow::SCISSOR_TEST),
            ("STENCIL_TEST", glow::STENCIL_TEST),
            ("RASTERIZER_DISCARD", glow::RASTERIZER_DISCARD),
            ("PRIMITIVE_RESTART", glow::PRIMITIVE_RESTART),
            ("FRAMEBUFFER_SRGB", glow::FRAMEBUFFER_SRGB),
            ("POLYGON_OFFSET_FILL", glow::POLYGON_OFFSET_FILL),
            ("DEPTH_CLAMP", glow::DEPTH_CLAMP),
            ("MULTISAMPLE", glow::MULTISAMPLE),
            ("PROGRAM_POINT_SIZE", glow::PROGRAM_POINT_SIZE),
            ("DEBUG_OUTPUT", glow::DEBUG_OUTPUT),
        ] {
            s.push((name.into(), vec![g.is_enabled(cap) as u8 as f64]));
        }
        for k in 0..8 {
            s.push((
                format!("CLIP_DISTANCE{k}"),
                vec![g.is_enabled(glow::CLIP_DISTANCE0 + k) as u8 as f64],
            ));
        }
        for (target, b, st, sz) in [
            (
                "SSBO",
                glow::SHADER_STORAGE_BUFFER_BINDING,
                glow::SHADER_STORAGE_BUFFER_START,
                glow::SHADER_STORAGE_BUFFER_SIZE,
            ),
            (
                "UBO",
                glow::UNIFORM_BUFFER_BINDING,
                glow::UNIFORM_BUFFER_START,
                glow::UNIFORM_BUFFER_SIZE,
            ),
            (
                "ACB",
                glow::ATOMIC_COUNTER_BUFFER_BINDING,
                glow::ATOMIC_COUNTER_BUFFER_START,
                glow::ATOMIC_COUNTER_BUFFER_SIZE,
            ),
            (
                "TFB",
                glow::TRANSFORM_FEEDBACK_BUFFER_BINDING,
                glow::TRANSFORM_FEEDBACK_BUFFER_START,
                glow::TRANSFORM_FEEDBACK_BUFFER_SIZE,
            ),
        ] {
            let n = if target == "TFB" { 4 } else { INDEXED };
            for i in 0..n {
                s.push((
                    format!("{target}[{i}]"),
                    vec![
                        g.get_parameter_indexed_i32(b, i) as f64,
                        g.get_parameter_indexed_i64(st, i) as f64,
                        g.get_parameter_indexed_i64(sz, i) as f64,
                    ],
                ));
            }
        }
        if profile == Profile::Compat {
            let c = ctx.compat();
            let mut i1 = |name: &str, p: u32| {
                let mut v = 0;
                c.GetIntegerv(p, &mut v);
                s.push((name.into(), vec![v as f64]));
            };
            i1("MATRIX_MODE", 0x0BA0);
            i1("MODELVIEW_STACK_DEPTH", 0x0BA3);
            i1("PROJECTION_STACK_DEPTH", 0x0BA4);
            i1("TEXTURE_STACK_DEPTH", 0x0BA5);
            i1("RENDER_MODE", 0x0C40);
            i1("SELECTION_BUFFER_SIZE", 0x0DF4);
            i1("NAME_STACK_DEPTH", 0x0D70);
            i1("SHADE_MODEL", 0x0B54);
            i1("LIGHTING", 0x0B50);
            i1("TEXTURE_2D", 0x0DE1);
            let mut p: *mut c_void = std::ptr::null_mut();
            c.GetPointerv(0x0DF3, (&raw mut p).cast_const());
            s.push(("SELECTION_BUFFER_POINTER".into(), vec![p as usize as f64]));
            for (name, q) in [
                ("MODELVIEW_MATRIX", 0x0BA6),
                ("PROJECTION_MATRIX", 0x0BA7),
                ("TEXTURE_MATRIX", 0x0BA8),
                ("CURRENT_COLOR", 0x0B00),
            ] {
                let mut m = [0f64; 16];
                c.GetDoublev(q, m.as_mut_ptr());
                s.push((name.into(), m.to_vec()));
            }
            for k in 0..6 {
                let mut eq = [0f64; 4];
                c.GetClipPlane(glow::CLIP_DISTANCE0 + k, eq.as_mut_ptr());
                s.push((format!("CLIP_PLANE{k}"), eq.to_vec()));
            }
        }
    }
    s
}

/// Sets plenty of non-default state, as a busy host would have mid-frame.
fn busy_host(ctx: &Ctx, g: &glow::Context, profile: Profile) -> Vec<u32> {
    // SAFETY: this test's GL context is current on this thread; the objects are its own.
    unsafe {
        let vs = g.create_shader(glow::VERTEX_SHADER).unwrap();
        g.shader_source(vs, "#version 330 core\nlayout(location=0) in vec3 p; void main(){gl_Position=vec4(p,1.0);}");
        g.compile_shader(vs);
        let fs = g.create_shader(glow::FRAGMENT_SHADER).unwrap();
        g.shader_source(
            fs,
            "#version 330 core\nout vec4 c; void main(){c=vec4(1.0);}",
        );
        g.compile_shader(fs);
        let prog = g.create_program().unwrap();
        g.attach_shader(prog, vs);
        g.attach_shader(prog, fs);
        g.link_program(prog);
        assert!(g.get_program_link_status(prog));
        g.use_program(Some(prog));
        let vao = g.create_vertex_array().unwrap();
        g.bind_vertex_array(Some(vao));
        let bufs: Vec<_> = (0..8).map(|_| g.create_buffer().unwrap()).collect();
        for (i, b) in bufs.iter().enumerate() {
            g.bind_buffer(glow::COPY_WRITE_BUFFER, Some(*b));
            g.buffer_data_size(glow::COPY_WRITE_BUFFER, 4096, glow::STATIC_DRAW);
            let _ = i;
        }
        g.bind_buffer(glow::ARRAY_BUFFER, Some(bufs[0]));
        g.bind_buffer(glow::ELEMENT_ARRAY_BUFFER, Some(bufs[1]));
        g.bind_buffer(glow::PIXEL_PACK_BUFFER, Some(bufs[2]));
        g.bind_buffer_range(glow::SHADER_STORAGE_BUFFER, 0, Some(bufs[3]), 256, 512);
        g.bind_buffer_base(glow::SHADER_STORAGE_BUFFER, 5, Some(bufs[4]));
        g.bind_buffer_base(glow::UNIFORM_BUFFER, 2, Some(bufs[5]));
        g.bind_buffer_range(glow::ATOMIC_COUNTER_BUFFER, 1, Some(bufs[6]), 0, 64);
        g.bind_buffer_range(glow::SHADER_STORAGE_BUFFER, 11, Some(bufs[6]), 128, 256);
        g.bind_buffer(glow::SHADER_STORAGE_BUFFER, Some(bufs[7]));
        bind_far_range(g, bufs[4]);
        // A transform feedback object with its own buffers, and a program pipeline.
        let tf = g.create_transform_feedback().unwrap();
        g.bind_transform_feedback(glow::TRANSFORM_FEEDBACK, Some(tf));
        g.bind_buffer_base(glow::TRANSFORM_FEEDBACK_BUFFER, 0, Some(bufs[3]));
        g.bind_buffer_range(glow::TRANSFORM_FEEDBACK_BUFFER, 2, Some(bufs[4]), 64, 128);
        let pipeline = Pipelines::load();
        let mut name = 0;
        (pipeline.gen)(1, &mut name);
        (pipeline.bind)(name);
        g.bind_buffer(glow::COPY_READ_BUFFER, Some(bufs[2]));
        g.bind_buffer(glow::COPY_WRITE_BUFFER, Some(bufs[5]));
        let rb = g.create_renderbuffer().unwrap();
        g.bind_renderbuffer(glow::RENDERBUFFER, Some(rb));
        g.renderbuffer_storage(glow::RENDERBUFFER, glow::RGBA8, 64, 64);
        let fb = g.create_framebuffer().unwrap();
        g.bind_framebuffer(glow::FRAMEBUFFER, Some(fb));
        g.framebuffer_renderbuffer(
            glow::FRAMEBUFFER,
            glow::COLOR_ATTACHMENT0,
            glow::RENDERBUFFER,
            Some(rb),
        );
        let fb2 = g.create_framebuffer().unwrap();
        g.bind_framebuffer(glow::READ_FRAMEBUFFER, Some(fb2));
        g.viewport(3, 4, 50, 60);
        g.scissor(1, 2, 30, 40);
        for cap in [
            glow::DEPTH_TEST,
            glow::BLEND,
            glow::CULL_FACE,
            glow::SCISSOR_TEST,
            glow::RASTERIZER_DISCARD,
            glow::DEPTH_CLAMP,
            glow::CLIP_DISTANCE1,
            glow::CLIP_DISTANCE4,
            glow::PRIMITIVE_RESTART,
        ] {
            g.enable(cap);
        }
        g.disable(glow::MULTISAMPLE);
        g.polygon_mode(glow::FRONT_AND_BACK, glow::LINE);
        g.pixel_store_i32(glow::PACK_ALIGNMENT, 1);
        g.pixel_store_i32(glow::UNPACK_ALIGNMENT, 2);
        g.pixel_store_i32(glow::UNPACK_ROW_LENGTH, 7);
        g.depth_func(glow::GREATER);
        g.clear_color(0.1, 0.2, 0.3, 0.4);
        if profile == Profile::Compat {
            let c = ctx.compat();
            c.MatrixMode(0x1701);
            c.LoadIdentity();
            c.Ortho(-2.0, 3.0, -4.0, 5.0, -6.0, 7.0);
            c.MatrixMode(0x1700);
            c.LoadIdentity();
            c.Translated(1.0, 2.0, 3.0);
            c.PushMatrix();
            c.Rotated(30.0, 0.0, 0.0, 1.0);
            c.ClipPlane(glow::CLIP_DISTANCE0, [1.0, 2.0, 3.0, 4.0].as_ptr());
            c.ClipPlane(glow::CLIP_DISTANCE2, [0.0, -1.0, 0.5, 9.0].as_ptr());
            c.MatrixMode(0x1702); // TEXTURE
            let buf: &'static mut [u32] = Box::leak(vec![0u32; 64].into_boxed_slice());
            c.SelectBuffer(64, buf.as_mut_ptr());
            c.Color4f(0.5, 0.25, 0.125, 1.0);
        }
        assert_eq!(g.get_error(), glow::NO_ERROR);
        bufs.iter().map(|b| b.0.get()).collect()
    }
}

/// Binds `b` to shader storage binding 3 at 3 GiB, 2 GiB + 4 KiB long: glBindBufferRange
/// checks the alignment, not the buffer's size, and a restore through 32-bit offsets and
/// sizes would lose the range. Where the GL itself reports the range wrong (Mesa 22.3's
/// glGetInteger64i_v answers GL_SHADER_STORAGE_BUFFER_START and _SIZE from a 32-bit int, so
/// no host could save it), binds 256 bytes at 256 instead and says so: the range past
/// 2 GiB is then not checked.
fn bind_far_range(g: &glow::Context, b: glow::NativeBuffer) {
    let (far, size) = (3i64 << 30, (1i64 << 31) + 4096);
    bind_range_64(glow::SHADER_STORAGE_BUFFER, 3, b, far, size);
    // SAFETY: this test's GL context is current on this thread; the objects are its own.
    let read = unsafe {
        (
            g.get_parameter_indexed_i64(glow::SHADER_STORAGE_BUFFER_START, 3),
            g.get_parameter_indexed_i64(glow::SHADER_STORAGE_BUFFER_SIZE, 3),
        )
    };
    // SAFETY: this test's GL context is current on this thread; the objects are its own.
    assert_eq!(unsafe { g.get_error() }, glow::NO_ERROR);
    if read != (far, size) {
        eprintln!(
            "this GL reports the range {far}+{size} as {read:?} (32 bits): a range past 2 GiB \
             is not checked here"
        );
        bind_range_64(glow::SHADER_STORAGE_BUFFER, 3, b, 256, 256);
    }
}

/// glBindBufferRange with 64-bit offset and size (glow's takes `i32`), through the host's
/// loader.
fn bind_range_64(target: u32, index: u32, buffer: glow::NativeBuffer, offset: i64, size: i64) {
    type BindBufferRange = unsafe extern "system" fn(u32, u32, u32, isize, isize);
    // SAFETY: glBindBufferRange as this context's loader gives it (non-NULL, checked),
    // with its C signature; the context is current on this thread and the GL validates the
    // range.
    unsafe {
        let f = get_proc_address(std::ptr::null_mut(), c"glBindBufferRange".as_ptr());
        assert!(!f.is_null());
        let f = std::mem::transmute::<*mut c_void, BindBufferRange>(f);
        f(
            target,
            index,
            buffer.0.get(),
            offset as isize,
            size as isize,
        );
    }
}

/// glGenProgramPipelines / glBindProgramPipeline (not in glow), through the host's loader.
struct Pipelines {
    gen: unsafe extern "system" fn(i32, *mut u32),
    bind: unsafe extern "system" fn(u32),
}

impl Pipelines {
    fn load() -> Pipelines {
        // SAFETY: the entry points this context's loader gives (non-NULL, checked), with
        // their C signatures.
        unsafe {
            let gen = get_proc_address(std::ptr::null_mut(), c"glGenProgramPipelines".as_ptr());
            let bind = get_proc_address(std::ptr::null_mut(), c"glBindProgramPipeline".as_ptr());
            assert!(!gen.is_null() && !bind.is_null());
            Pipelines {
                gen: std::mem::transmute::<*mut c_void, unsafe extern "system" fn(i32, *mut u32)>(
                    gen,
                ),
                bind: std::mem::transmute::<*mut c_void, unsafe extern "system" fn(u32)>(bind),
            }
        }
    }
}

fn compare(what: &str, a: &Snapshot, b: &Snapshot) {
    assert_eq!(a.len(), b.len());
    for (x, y) in a.iter().zip(b) {
        assert_eq!(x, y, "{what} changed {}", x.0);
    }
}

fn run(profile: Profile, backend: GlcolBackend) {
    let ctx = Ctx::new(profile);
    let g = ctx.glow();
    let host_bufs = busy_host(&ctx, &g, profile);
    let blade = TestMesh::from_obj(&shared_mesh("scissors_blade"));
    let organ = TestMesh::from_obj(&shared_mesh("teapot"));
    let (lo, hi) = common::bounds(&organ.pos);
    let bp = place(
        &blade.pos,
        [hi[0], (lo[1] + hi[1]) / 2.0, (lo[2] + hi[2]) / 2.0],
        1.0,
    );
    let check = |what: &str, f: &mut dyn FnMut()| {
        let before = snapshot(&ctx, &g, profile);
        f();
        let after = snapshot(&ctx, &g, profile);
        compare(what, &before, &after);
        assert_eq!(
            // SAFETY: this test's GL context is current on this thread; the objects are its own.
            unsafe { g.get_error() },
            glow::NO_ERROR,
            "{what} left a GL error"
        );
    };
    let mut s = std::ptr::null_mut();
    check("glcol_scene_create", &mut || s = scene(backend, 0.01, 0));
    let (mut o, mut b) = (0, 0);
    check("glcol_mesh_create", &mut || {
        o = add_mesh(s, &organ.pos, &organ.idx, 3);
        b = add_mesh(s, &bp, &blade.idx, 3);
    });
    check("glcol_mesh_update_positions", &mut || update(s, b, &bp));
    let mut n = 0;
    check("glcol_query", &mut || n = query(s, b).len());
    assert!(n > 0, "the scene should collide");
    check("glcol_query again", &mut || {
        assert_eq!(query(s, b).len(), n)
    });
    if backend == GlcolBackend::GlCompute {
        // The host's buffer 0 holds the teapot's positions from here on.
        // SAFETY: this test's GL context is current on this thread; the objects are its own.
        unsafe {
            g.bind_buffer(
                glow::COPY_WRITE_BUFFER,
                glcollide::internals::buffer(host_bufs[0]),
            );
        }
        let data: Vec<f32> = organ.pos.iter().flatten().copied().collect();
        // SAFETY: this test's GL context is current on this thread; the objects are its own.
        unsafe {
            let bytes = std::slice::from_raw_parts(data.as_ptr().cast::<u8>(), data.len() * 4);
            g.buffer_data_u8_slice(glow::COPY_WRITE_BUFFER, bytes, glow::STATIC_DRAW);
            g.bind_buffer(
                glow::COPY_WRITE_BUFFER,
                glcollide::internals::buffer(host_bufs[5]),
            );
        }
        check("glcol_mesh_bind_gl_buffer", &mut || {
            // SAFETY: `s` is a live scene of this test; its GL context is current on this thread.
            ok(unsafe { glcol_mesh_bind_gl_buffer(s, o, host_bufs[0], 0, 0) })
        });
        check("glcol_query (bound buffer)", &mut || {
            assert_eq!(query(s, b).len(), n)
        });
    }
    // A host error pending before our call: our call succeeds, the error is still there.
    // SAFETY: this test's GL context is current on this thread; the objects are its own.
    unsafe { g.enable(0) };
    let before = snapshot(&ctx, &g, profile);
    let _ = query(s, b);
    let after = snapshot(&ctx, &g, profile);
    compare("glcol_query with a pending error", &before, &after);
    assert_eq!(
        // SAFETY: this test's GL context is current on this thread; the objects are its own.
        unsafe { g.get_error() },
        glow::INVALID_ENUM,
        "the host's pending error was lost"
    );
    // SAFETY: this test's GL context is current on this thread; the objects are its own.
    assert_eq!(unsafe { g.get_error() }, glow::NO_ERROR);
    // SAFETY: `s` is a live scene of this test; its GL context is current on this thread.
    check("glcol_scene_destroy", &mut || unsafe {
        glcol_scene_destroy(s)
    });
}

#[test]
fn state_survives_gl_select_compat() {
    run(Profile::Compat, GlcolBackend::GlSelect);
}

#[test]
fn state_survives_gl_compute_compat() {
    run(Profile::Compat, GlcolBackend::GlCompute);
}

#[test]
fn state_survives_gl_compute_core() {
    run(Profile::Core, GlcolBackend::GlCompute);
}

/// A host in the middle of transform feedback: refused with GL_UNAVAILABLE and a message
/// while it runs (changing nothing, leaving no error), answered once it is paused, and
/// the paused transform feedback survives the call.
fn transform_feedback_in_flight(profile: Profile, backend: GlcolBackend) {
    let ctx = Ctx::new(profile);
    let g = ctx.glow();
    busy_host(&ctx, &g, profile);
    let blade = TestMesh::from_obj(&shared_mesh("scissors_blade"));
    let organ = TestMesh::from_obj(&shared_mesh("teapot"));
    let (lo, hi) = common::bounds(&organ.pos);
    let bp = place(
        &blade.pos,
        [hi[0], (lo[1] + hi[1]) / 2.0, (lo[2] + hi[2]) / 2.0],
        1.0,
    );
    let s = scene(backend, 0.01, 0);
    add_mesh(s, &organ.pos, &organ.idx, 3);
    let b = add_mesh(s, &bp, &blade.idx, 3);
    let n = query(s, b).len();
    assert!(n > 0);
    // SAFETY: this test's GL context is current on this thread; the objects are its own.
    unsafe {
        let vs = g.create_shader(glow::VERTEX_SHADER).unwrap();
        g.shader_source(
            vs,
            "#version 330 core\nout float v; void main(){v=1.0; gl_Position=vec4(0.0);}",
        );
        g.compile_shader(vs);
        let prog = g.create_program().unwrap();
        g.attach_shader(prog, vs);
        g.transform_feedback_varyings(prog, &["v"], glow::INTERLEAVED_ATTRIBS);
        g.link_program(prog);
        assert!(
            g.get_program_link_status(prog),
            "{}",
            g.get_program_info_log(prog)
        );
        g.use_program(Some(prog));
        g.begin_transform_feedback(glow::POINTS);
        assert_eq!(g.get_error(), glow::NO_ERROR);
        let before = snapshot(&ctx, &g, profile);
        let (mut c, mut count) = (std::ptr::null(), 0);
        let st = glcol_query(s, b, &mut c, &mut count);
        assert_eq!(st, GlcolStatus::GlUnavailable);
        assert!(
            last_error().contains("transform feedback"),
            "{}",
            last_error()
        );
        compare(
            "a refused glcol_query",
            &before,
            &snapshot(&ctx, &g, profile),
        );
        assert_eq!(g.get_error(), glow::NO_ERROR);
        g.pause_transform_feedback();
        let before = snapshot(&ctx, &g, profile);
        assert_eq!(query(s, b).len(), n);
        compare(
            "glcol_query with transform feedback paused",
            &before,
            &snapshot(&ctx, &g, profile),
        );
        assert_eq!(g.get_error(), glow::NO_ERROR);
        g.resume_transform_feedback();
        g.end_transform_feedback();
        assert_eq!(g.get_error(), glow::NO_ERROR);
        glcol_scene_destroy(s);
    }
}

#[test]
fn transform_feedback_gl_compute_core() {
    transform_feedback_in_flight(Profile::Core, GlcolBackend::GlCompute);
}

#[test]
fn transform_feedback_gl_select_compat() {
    transform_feedback_in_flight(Profile::Compat, GlcolBackend::GlSelect);
}
