//! No silent wrong answers inside a host's GL (issue 14): every misuse a host can make of
//! the GL backends is refused with a clear status and message, changes nothing (in the
//! scene, in the host's objects, in its GL state or pending errors), and the next correct
//! call answers as the CPU backend does (the exact oracle, checked too). On headless Mesa:
//! GL_SELECT in a compatibility context, GL_COMPUTE in a core 4.5 and a compatibility one.
//!
//! - no context current, and an unshared context current: on the first query, after a
//!   successful one, for `bind_gl_buffer`, `query_all` and `scene_destroy` (which must not
//!   delete the other context's objects that carry our names);
//! - a context sharing the scene's objects: answered as in the scene's own;
//! - a bound buffer re-specified smaller (to 48 bytes, and 4 bytes short), mapped, or
//!   deleted: INVALID_ARGUMENT naming the mesh and the sizes, at every query;
//! - a host error pending, with a debug callback installed: our calls log nothing and the
//!   host's error is still pending after each;
//! - a partial update of a bound mesh: refused; a full one unbinds and is answered;
//! - AUTO on llvmpipe (the CPU backend) with a bound buffer: read back at each query,
//!   answered exactly as the CPU, the same misuses refused, no debug message.
mod common;

use common::backends::gl_support;

use std::sync::{Arc, Mutex};

use common::{brute_force_exact, brute_force_within, TestMesh};
use gl_support::*;
use glcollide::ffi::*;
use glow::HasContext;

/// An `n` x `n` triangle grid over the unit square, lifted by `f(u, v)` into 3D.
fn grid(n: u32, f: impl Fn(f32, f32) -> [f32; 3]) -> TestMesh {
    let mut pos = Vec::new();
    for j in 0..=n {
        for i in 0..=n {
            pos.push(f(i as f32 / n as f32, j as f32 / n as f32));
        }
    }
    let mut idx = Vec::new();
    let at = |i: u32, j: u32| j * (n + 1) + i;
    for j in 0..n {
        for i in 0..n {
            idx.extend([at(i, j), at(i + 1, j), at(i + 1, j + 1)]);
            idx.extend([at(i, j), at(i + 1, j + 1), at(i, j + 1)]);
        }
    }
    TestMesh { pos, idx, k: 3 }
}

/// Two wavy sheets crossing along a curve (many contacts), `t` moves the second.
fn sheets(t: f32) -> (TestMesh, TestMesh) {
    let a = grid(20, |u, v| [u, v, 0.05 * (7.0 * u).sin() * (5.0 * v).cos()]);
    let b = grid(20, |u, v| {
        [
            u,
            0.5 + 0.04 * (6.0 * u + t).sin(),
            v - 0.5 + 0.03 * (4.0 * v).cos(),
        ]
    });
    (a, b)
}

/// (reference polygon, other polygon) of a query's contacts.
type Pairs = Vec<(u32, u32)>;

fn pairs(c: &[(u32, u32, u32)]) -> Pairs {
    c.iter().map(|c| (c.1, c.2)).collect()
}

/// A query's status and message, and its pairs when it answered.
fn try_query(s: *mut GlcolScene, reference: GlcolMeshId) -> Result<Pairs, (GlcolStatus, String)> {
    let mut c = std::ptr::null();
    let mut n = 0;
    // SAFETY: a live scene of the calling test; the out pointers are valid.
    let st = unsafe { glcol_query(s, reference, &mut c, &mut n) };
    if st != GlcolStatus::Ok {
        return Err((st, last_error()));
    }
    if n == 0 {
        return Ok(Vec::new());
    }
    // SAFETY: the scene's array of `n` contacts, valid until the next call on it.
    let c = unsafe { std::slice::from_raw_parts(c, n) };
    Ok(c.iter()
        .map(|c| (c.reference_polygon, c.other_polygon))
        .collect())
}

fn query_all_status(s: *mut GlcolScene) -> (GlcolStatus, String) {
    let mut p = std::ptr::null();
    let mut n = 0;
    // SAFETY: a live scene of the calling test; the out pointers are valid.
    let st = unsafe { glcol_query_all(s, &mut p, &mut n) };
    (st, last_error())
}

fn refused(r: Result<Pairs, (GlcolStatus, String)>, status: GlcolStatus, words: &[&str]) {
    let (st, msg) = match r {
        Ok(p) => panic!("a misuse answered OK with {} pairs", p.len()),
        Err(e) => e,
    };
    assert_eq!(st, status, "{msg}");
    for w in words {
        assert!(msg.contains(w), "{msg:?} does not say {w:?}");
    }
}

/// The CPU backend's answer and the exact oracle's (which must agree).
fn cpu_answer(a: &TestMesh, b: &TestMesh) -> Pairs {
    let s = scene(GlcolBackend::Cpu, 0.0, 0);
    add_mesh(s, &b.pos, &b.idx, 3);
    let a_id = add_mesh(s, &a.pos, &a.idx, 3);
    let got = pairs(&query(s, a_id));
    // SAFETY: a live CPU scene of this test.
    unsafe { glcol_scene_destroy(s) };
    assert_eq!(
        got,
        brute_force_exact(a, b),
        "the CPU backend against the oracle"
    );
    assert!(
        got.len() > 20,
        "the test scene has contacts ({})",
        got.len()
    );
    got
}

/// Buffers of the current (host) context: many, so some carry the scene's names.
fn host_buffers(g: &glow::Context, n: usize) -> Vec<(glow::NativeBuffer, i32)> {
    (0..n)
        .map(|i| {
            let size = 1000 + 4 * i as i32;
            // SAFETY: the test's host context is current; the buffers are its own.
            unsafe {
                let b = g.create_buffer().unwrap();
                g.bind_buffer(glow::ARRAY_BUFFER, Some(b));
                g.buffer_data_size(glow::ARRAY_BUFFER, size, glow::STATIC_DRAW);
                g.bind_buffer(glow::ARRAY_BUFFER, None);
                (b, size)
            }
        })
        .collect()
}

/// Every host buffer is still there with its size.
fn host_buffers_intact(g: &glow::Context, bufs: &[(glow::NativeBuffer, i32)]) {
    for &(b, size) in bufs {
        // SAFETY: the test's host context is current; `b` is its buffer.
        unsafe {
            assert!(g.is_buffer(b), "host buffer {} was deleted", b.0);
            g.bind_buffer(glow::ARRAY_BUFFER, Some(b));
            let got = g.get_buffer_parameter_i32(glow::ARRAY_BUFFER, glow::BUFFER_SIZE);
            g.bind_buffer(glow::ARRAY_BUFFER, None);
            assert_eq!(got, size, "host buffer {} was re-specified", b.0);
        }
    }
}

/// No context, then an unshared one, on the first query and after a good one; then a
/// context sharing the scene's objects. Every misuse: GL_UNAVAILABLE, nothing changed,
/// and the next correct query answers as the CPU.
fn wrong_contexts(profile: Profile, backend: GlcolBackend) {
    let (a, b) = sheets(0.0);
    let (_, b2) = sheets(0.7);
    let home = Ctx::new(profile);
    let want = cpu_answer(&a, &b);
    let want2 = cpu_answer(&a, &b2);
    let s = scene(backend, 0.0, 0);
    let b_id = add_mesh(s, &b.pos, &b.idx, 3);
    let a_id = add_mesh(s, &a.pos, &a.idx, 3);
    let lone = scene(backend, 0.0, 0);
    let lone_id = add_mesh(lone, &a.pos, &a.idx, 3);

    // No context current, first query.
    home.release_current();
    let no = ["no GL context is current"];
    refused(try_query(s, a_id), GlcolStatus::GlUnavailable, &no);
    assert_eq!(query_all_status(s).0, GlcolStatus::GlUnavailable);
    // A query with no other mesh asks the GL nothing, and is refused all the same.
    refused(try_query(lone, lone_id), GlcolStatus::GlUnavailable, &no);
    home.make_current();
    assert_eq!(pairs(&query(s, a_id)), want, "{backend:?} after no context");

    // An unshared context full of buffers (some carry our names), first query of a new
    // scene and after a good one with an update.
    let fresh = scene(backend, 0.0, 0);
    add_mesh(fresh, &b.pos, &b.idx, 3);
    let fa_id = add_mesh(fresh, &a.pos, &a.idx, 3);
    let other = Ctx::new(profile);
    let og = other.glow();
    let theirs = host_buffers(&og, 64);
    let wrong = ["wrong GL context current"];
    refused(try_query(fresh, fa_id), GlcolStatus::GlUnavailable, &wrong);
    update(s, b_id, &b2.pos);
    refused(try_query(s, a_id), GlcolStatus::GlUnavailable, &wrong);
    assert_eq!(query_all_status(s).0, GlcolStatus::GlUnavailable);
    // SAFETY: a live scene of this test.
    let st = unsafe { glcol_mesh_bind_gl_buffer(s, b_id, theirs[0].0 .0.get(), 0, 0) };
    let expect = if backend == GlcolBackend::GlCompute {
        GlcolStatus::GlUnavailable
    } else {
        GlcolStatus::Unsupported
    };
    assert_eq!(st, expect, "{}", last_error());
    host_buffers_intact(&og, &theirs);
    // Destroying a scene from the wrong context deletes nothing of that context's.
    let doomed = scene_in(&home, &other, backend);
    // SAFETY: a live scene of this test (destroyed with the wrong context current).
    unsafe { glcol_scene_destroy(doomed) };
    host_buffers_intact(&og, &theirs);

    // Back home: both scenes answer as the CPU.
    home.make_current();
    assert_eq!(
        pairs(&query(fresh, fa_id)),
        want,
        "{backend:?}: fresh scene"
    );
    assert_eq!(
        pairs(&query(s, a_id)),
        want2,
        "{backend:?} after the update"
    );

    // A context sharing the scene's objects is the scene's as far as we care.
    let shared = Ctx::new_shared(profile, &home);
    update(s, b_id, &b.pos);
    assert_eq!(
        pairs(&query(s, a_id)),
        want,
        "{backend:?} in a shared context"
    );
    home.make_current();
    drop(shared); // leaves no context current
    home.make_current();
    assert_eq!(pairs(&query(s, a_id)), want, "{backend:?} home again");
    // SAFETY: live scenes of this test; their context is current.
    unsafe {
        glcol_scene_destroy(s);
        glcol_scene_destroy(fresh);
        glcol_scene_destroy(lone);
    }
    other.make_current();
    host_buffers_intact(&og, &theirs);
    drop(other);
    drop(home);
}

/// A scene made in `home`, with a mesh, then `other` made current again.
fn scene_in(home: &Ctx, other: &Ctx, backend: GlcolBackend) -> *mut GlcolScene {
    home.make_current();
    let (a, _) = sheets(0.0);
    let s = scene(backend, 0.0, 0);
    add_mesh(s, &a.pos, &a.idx, 3);
    other.make_current();
    s
}

#[test]
fn wrong_contexts_gl_compute_core() {
    wrong_contexts(Profile::Core, GlcolBackend::GlCompute);
}

#[test]
fn wrong_contexts_gl_compute_compat() {
    wrong_contexts(Profile::Compat, GlcolBackend::GlCompute);
}

#[test]
fn wrong_contexts_gl_select_compat() {
    wrong_contexts(Profile::Compat, GlcolBackend::GlSelect);
}

/// A host buffer holding `pos` packed (xyz floats).
fn host_positions(g: &glow::Context, pos: &[[f32; 3]]) -> glow::NativeBuffer {
    // SAFETY: the test's context is current; the buffer is its own.
    unsafe {
        let h = g.create_buffer().unwrap();
        respecify(g, h, pos);
        h
    }
}

/// glBufferData of `pos` into `h`.
fn respecify(g: &glow::Context, h: glow::NativeBuffer, pos: &[[f32; 3]]) {
    let flat: Vec<f32> = pos.iter().flatten().copied().collect();
    // SAFETY: the test's context is current; `h` is its buffer; the bytes are `flat`'s.
    unsafe {
        let bytes = std::slice::from_raw_parts(flat.as_ptr().cast::<u8>(), flat.len() * 4);
        g.bind_buffer(glow::ARRAY_BUFFER, Some(h));
        g.buffer_data_u8_slice(glow::ARRAY_BUFFER, bytes, glow::STATIC_DRAW);
        g.bind_buffer(glow::ARRAY_BUFFER, None);
    }
}

/// A bound mode answer: every exact pair, and nothing beyond the GL's minimum band.
fn within_bound(got: &Pairs, a: &TestMesh, b: &TestMesh) {
    for p in brute_force_exact(a, b) {
        assert!(got.binary_search(&p).is_ok(), "bound: missed {p:?}");
    }
    let (lo, hi) = common::bounds(&[a.pos.clone(), b.pos.clone()].concat());
    let extent = (0..3).map(|k| (hi[k] - lo[k]) as f64).fold(0.0, f64::max);
    let band = brute_force_within(
        a,
        b,
        extent * glcollide::internals::MIN_RELATIVE_EPSILON / 2.0 * 1.000001 + 1e-12,
    );
    for p in got {
        assert!(
            band.binary_search(p).is_ok(),
            "bound: {p:?} beyond the band"
        );
    }
}

fn shrunk_buffers(profile: Profile) {
    let ctx = Ctx::new(profile);
    let g = ctx.glow();
    let (a, b) = sheets(0.0);
    let s = scene(GlcolBackend::GlCompute, 0.0, 0);
    let b_id = add_mesh(s, &b.pos, &b.idx, 3);
    let a_id = add_mesh(s, &a.pos, &a.idx, 3);
    let host = host_positions(&g, &b.pos);
    // SAFETY: a live scene; its context is current.
    ok(unsafe { glcol_mesh_bind_gl_buffer(s, b_id, host.0.get(), 0, 0) });
    let good = try_query(s, a_id).unwrap();
    within_bound(&good, &a, &b);
    let need = 12 * b.pos.len();
    let id = format!("mesh {b_id}");
    // Re-specified to 48 bytes, then 4 bytes short: refused at the query, naming sizes.
    // SAFETY: the test's context is current; `host` is its buffer.
    unsafe {
        g.bind_buffer(glow::ARRAY_BUFFER, Some(host));
        g.buffer_data_size(glow::ARRAY_BUFFER, 48, glow::STATIC_DRAW);
    }
    let words = [id.as_str(), "48 bytes", &need.to_string()];
    refused(try_query(s, a_id), GlcolStatus::InvalidArgument, &words);
    assert_eq!(query_all_status(s).0, GlcolStatus::InvalidArgument);
    let short = b.pos.len() * 12 - 4;
    // SAFETY: as above.
    unsafe { g.buffer_data_size(glow::ARRAY_BUFFER, short as i32, glow::STATIC_DRAW) };
    let short_s = format!("{short} bytes");
    let words = [id.as_str(), short_s.as_str(), &need.to_string()];
    refused(try_query(s, a_id), GlcolStatus::InvalidArgument, &words);
    // Whole again: answered as before.
    respecify(&g, host, &b.pos);
    assert_eq!(try_query(s, a_id).unwrap(), good);
    // Mapped by the host: refused, then answered once unmapped.
    // SAFETY: as above; mapped and unmapped by this test.
    unsafe {
        g.bind_buffer(glow::ARRAY_BUFFER, Some(host));
        let p = g.map_buffer_range(glow::ARRAY_BUFFER, 0, 12, glow::MAP_READ_BIT);
        assert!(!p.is_null());
    }
    refused(
        try_query(s, a_id),
        GlcolStatus::InvalidArgument,
        &[&id, "mapped"],
    );
    // SAFETY: as above.
    unsafe {
        g.unmap_buffer(glow::ARRAY_BUFFER);
        g.bind_buffer(glow::ARRAY_BUFFER, None);
    }
    assert_eq!(try_query(s, a_id).unwrap(), good);
    // Deleted: refused; bound to a new buffer: answered.
    // SAFETY: as above.
    unsafe { g.delete_buffer(host) };
    refused(
        try_query(s, a_id),
        GlcolStatus::InvalidArgument,
        &[&id, "no longer a buffer object"],
    );
    let again = host_positions(&g, &b.pos);
    // SAFETY: a live scene; its context is current.
    ok(unsafe { glcol_mesh_bind_gl_buffer(s, b_id, again.0.get(), 0, 0) });
    assert_eq!(try_query(s, a_id).unwrap(), good);
    // SAFETY: a live scene; its context is current; `again` is the test's buffer.
    unsafe {
        glcol_scene_destroy(s);
        g.delete_buffer(again);
    }
}

#[test]
fn shrunk_mapped_deleted_buffers_core() {
    shrunk_buffers(Profile::Core);
}

#[test]
fn shrunk_mapped_deleted_buffers_compat() {
    shrunk_buffers(Profile::Compat);
}

/// A partial update of a bound mesh is refused (its CPU positions are stale); a full one
/// unbinds the buffer, and the answer is the CPU's for those positions.
#[test]
fn partial_update_of_a_bound_mesh() {
    let ctx = Ctx::new(Profile::Core);
    let g = ctx.glow();
    let (a, b) = sheets(0.0);
    let (_, b2) = sheets(0.7);
    let want2 = cpu_answer(&a, &b2);
    let s = scene(GlcolBackend::GlCompute, 0.0, 0);
    // Created at b2's positions, bound to a buffer holding b's: the stale CPU copy differs.
    let b_id = add_mesh(s, &b2.pos, &b.idx, 3);
    let a_id = add_mesh(s, &a.pos, &a.idx, 3);
    let host = host_positions(&g, &b.pos);
    // SAFETY: a live scene; its context is current.
    ok(unsafe { glcol_mesh_bind_gl_buffer(s, b_id, host.0.get(), 0, 0) });
    let bound = try_query(s, a_id).unwrap();
    within_bound(&bound, &a, &b);
    // SAFETY: a live scene; the positions are 5 vertices.
    let st =
        unsafe { glcol_mesh_update_positions(s, b_id, b.pos[10..15].as_ptr().cast(), 10, 5, 0) };
    assert_eq!(st, GlcolStatus::InvalidArgument);
    let msg = last_error();
    assert!(
        msg.contains(&format!("mesh {b_id}")) && msg.contains("partial"),
        "{msg}"
    );
    // Nothing changed: still bound, same answer.
    assert_eq!(try_query(s, a_id).unwrap(), bound);
    // A full update unbinds: the answer is the CPU's for b2.
    update(s, b_id, &b2.pos);
    assert_eq!(pairs(&query(s, a_id)), want2);
    // Host buffer changes no longer matter.
    respecify(&g, host, &b.pos[..4]);
    assert_eq!(pairs(&query(s, a_id)), want2);
    // SAFETY: a live scene; its context is current; `host` is the test's buffer.
    unsafe {
        glcol_scene_destroy(s);
        g.delete_buffer(host);
    }
}

/// GL debug messages the callback received.
type Log = Arc<Mutex<Vec<String>>>;

/// With a host error pending and a debug callback installed (synchronous), every
/// GL-backed call of `backend` logs nothing and leaves the host's error pending.
fn pending_error_is_kept_quietly(profile: Profile, backend: GlcolBackend) {
    let ctx = Ctx::new(profile);
    let mut g = ctx.glow();
    let log: Log = Arc::default();
    let sink = log.clone();
    // SAFETY: the test's context is current; the callback only records.
    unsafe {
        g.enable(glow::DEBUG_OUTPUT);
        g.enable(glow::DEBUG_OUTPUT_SYNCHRONOUS);
        g.debug_message_callback(move |_source, kind, id, _severity, msg: &str| {
            sink.lock()
                .unwrap()
                .push(format!("type 0x{kind:x} id {id}: {msg}"));
        });
    }
    // The harness works: the host's own error is logged.
    let raise = || {
        // SAFETY: the test's context is current; an invalid enum on purpose.
        unsafe { g.enable(0) };
        let n = std::mem::take(&mut *log.lock().unwrap()).len();
        assert_eq!(n, 1, "the host's own error is logged once");
    };
    let kept = |what: &str| {
        // SAFETY: the test's context is current.
        unsafe {
            assert_eq!(g.get_error(), glow::INVALID_ENUM, "{what}: host error lost");
            assert_eq!(g.get_error(), glow::NO_ERROR, "{what}: an error of ours");
        }
        let l = std::mem::take(&mut *log.lock().unwrap());
        assert!(l.is_empty(), "{backend:?} {profile:?} {what} logged {l:#?}");
    };
    let (a, b) = sheets(0.0);
    raise();
    let s = scene(backend, 0.0, 0);
    kept("glcol_scene_create");
    let b_id = add_mesh(s, &b.pos, &b.idx, 3);
    let a_id = add_mesh(s, &a.pos, &a.idx, 3);
    raise();
    let first = pairs(&query(s, a_id));
    kept("glcol_query");
    assert_eq!(first, brute_force_exact(&a, &b));
    raise();
    assert_eq!(query_all_status(s).0, GlcolStatus::Ok);
    kept("glcol_query_all");
    if backend == GlcolBackend::GlCompute {
        let host = host_positions(&g, &b.pos);
        raise();
        // SAFETY: a live scene; its context is current.
        ok(unsafe { glcol_mesh_bind_gl_buffer(s, b_id, host.0.get(), 0, 0) });
        kept("glcol_mesh_bind_gl_buffer");
        raise();
        within_bound(&try_query(s, a_id).unwrap(), &a, &b);
        kept("glcol_query (bound)");
        // A refused query (shrunk buffer) raises nothing of its own either.
        respecify(&g, host, &b.pos[..4]);
        raise();
        assert!(try_query(s, a_id).is_err());
        kept("a refused glcol_query");
        // SAFETY: the test's buffer.
        unsafe { g.delete_buffer(host) };
    }
    raise();
    // SAFETY: a live scene; its context is current.
    unsafe { glcol_scene_destroy(s) };
    kept("glcol_scene_destroy");
    // SAFETY: the test's context is current.
    unsafe { g.disable(glow::DEBUG_OUTPUT) };
    drop(ctx);
}

#[test]
fn pending_error_is_kept_quietly_gl_compute_core() {
    pending_error_is_kept_quietly(Profile::Core, GlcolBackend::GlCompute);
}

#[test]
fn pending_error_is_kept_quietly_gl_compute_compat() {
    pending_error_is_kept_quietly(Profile::Compat, GlcolBackend::GlCompute);
}

#[test]
fn pending_error_is_kept_quietly_gl_select_compat() {
    pending_error_is_kept_quietly(Profile::Compat, GlcolBackend::GlSelect);
}

/// A host buffer holding `pos` at byte `offset`, `stride` bytes apart (padding 7.0).
fn host_strided(
    g: &glow::Context,
    pos: &[[f32; 3]],
    offset: usize,
    stride: usize,
) -> glow::NativeBuffer {
    let mut words = vec![7.0f32; (offset + pos.len() * stride) / 4];
    for (i, p) in pos.iter().enumerate() {
        words[(offset + i * stride) / 4..][..3].copy_from_slice(p);
    }
    // SAFETY: the test's context is current; the buffer is its own; the bytes are `words`'.
    unsafe {
        let h = g.create_buffer().unwrap();
        let bytes = std::slice::from_raw_parts(words.as_ptr().cast::<u8>(), words.len() * 4);
        g.bind_buffer(glow::ARRAY_BUFFER, Some(h));
        g.buffer_data_u8_slice(glow::ARRAY_BUFFER, bytes, glow::STATIC_DRAW);
        g.bind_buffer(glow::ARRAY_BUFFER, None);
        h
    }
}

/// AUTO on llvmpipe runs on the CPU, and binding works there too: each query reads the
/// buffer back (strided, at an offset) and answers exactly as the CPU does with those
/// positions; the same misuses are refused as on GL_COMPUTE. (With a hardware GPU AUTO
/// picks GL_COMPUTE: the answer is then checked against the band.)
#[test]
fn binding_under_auto() {
    let home = Ctx::new(Profile::Core);
    let g = home.glow();
    let (a, b) = sheets(0.0);
    let (_, b2) = sheets(0.7);
    let want = cpu_answer(&a, &b);
    let want2 = cpu_answer(&a, &b2);
    let s = scene(GlcolBackend::Auto, 0.0, 0);
    let on_cpu = backend_of(s) == GlcolBackend::Cpu as u32;
    let check = |got: Pairs, want: &Pairs, b: &TestMesh| {
        if on_cpu {
            assert_eq!(&got, want);
        } else {
            within_bound(&got, &a, b);
        }
    };
    // Created at b2's positions, bound to a buffer holding b's.
    let b_id = add_mesh(s, &b2.pos, &b.idx, 3);
    let a_id = add_mesh(s, &a.pos, &a.idx, 3);
    let (offset, stride) = (16, 24);
    let host = host_strided(&g, &b.pos, offset, stride);
    // SAFETY: a live scene; its context is current.
    ok(unsafe { glcol_mesh_bind_gl_buffer(s, b_id, host.0.get(), offset, stride) });
    check(try_query(s, a_id).unwrap(), &want, &b);
    // Contact geometry of the buffer's positions (not those the mesh was created with, at
    // which no pair meets): at epsilon 0 every pair intersects.
    let (mut gp, mut gn) = (std::ptr::null(), 0);
    // SAFETY: a live scene; its context is current.
    ok(unsafe { glcol_query_geometry(s, &mut gp, &mut gn) });
    assert!(gn > 0);
    // SAFETY: the scene's `gn` entries, alive until its next query.
    let geo = unsafe { std::slice::from_raw_parts(gp, gn) };
    assert!(
        geo.iter()
            .all(|g| g.flags & GLCOL_CONTACT_INTERSECTING != 0 && g.depth >= 0.0),
        "geometry of positions other than the buffer's"
    );
    // The host rewrites its buffer: the next query sees it.
    let moved = host_strided(&g, &b2.pos, offset, stride);
    // SAFETY: the test's context is current; both buffers are its own.
    unsafe {
        g.bind_buffer(glow::COPY_READ_BUFFER, Some(moved));
        g.bind_buffer(glow::COPY_WRITE_BUFFER, Some(host));
        let n = (offset + b2.pos.len() * stride) as i32;
        g.copy_buffer_sub_data(glow::COPY_READ_BUFFER, glow::COPY_WRITE_BUFFER, 0, 0, n);
        g.delete_buffer(moved);
    }
    check(try_query(s, a_id).unwrap(), &want2, &b2);
    // Shrunk, then whole again.
    // SAFETY: the test's context is current; `host` is its buffer.
    unsafe {
        g.bind_buffer(glow::ARRAY_BUFFER, Some(host));
        g.buffer_data_size(glow::ARRAY_BUFFER, 48, glow::STATIC_DRAW);
        g.bind_buffer(glow::ARRAY_BUFFER, None);
    }
    let id = format!("mesh {b_id}");
    refused(
        try_query(s, a_id),
        GlcolStatus::InvalidArgument,
        &[&id, "48 bytes"],
    );
    // No context, an unshared one: refused, nothing read.
    home.release_current();
    refused(
        try_query(s, a_id),
        GlcolStatus::GlUnavailable,
        &["no GL context is current"],
    );
    let other = Ctx::new(Profile::Core);
    let og = other.glow();
    let theirs = host_buffers(&og, 16);
    refused(
        try_query(s, a_id),
        GlcolStatus::GlUnavailable,
        &["wrong GL context current"],
    );
    host_buffers_intact(&og, &theirs);
    home.make_current();
    let back = host_strided(&g, &b.pos, offset, stride);
    // SAFETY: a live scene; its context is current.
    ok(unsafe { glcol_mesh_bind_gl_buffer(s, b_id, back.0.get(), offset, stride) });
    check(try_query(s, a_id).unwrap(), &want, &b);
    // A NaN in the buffer: NON_FINITE naming the mesh (CPU read-back and GPU alike).
    let mut bad = b.pos.clone();
    bad[3][1] = f32::NAN;
    let nan = host_strided(&g, &bad, offset, stride);
    // SAFETY: a live scene; its context is current.
    ok(unsafe { glcol_mesh_bind_gl_buffer(s, b_id, nan.0.get(), offset, stride) });
    refused(try_query(s, a_id), GlcolStatus::NonFinite, &[&id]);
    // SAFETY: as above.
    ok(unsafe { glcol_mesh_bind_gl_buffer(s, b_id, back.0.get(), offset, stride) });
    // Partial update: refused; full update: unbinds.
    // SAFETY: a live scene; the positions are 5 vertices.
    let st =
        unsafe { glcol_mesh_update_positions(s, b_id, b.pos[10..15].as_ptr().cast(), 10, 5, 0) };
    assert_eq!(st, GlcolStatus::InvalidArgument, "{}", last_error());
    update(s, b_id, &b2.pos);
    assert_eq!(pairs(&query(s, a_id)), want2);
    // SAFETY: a live scene; its context is current; the buffers are the test's.
    unsafe {
        glcol_scene_destroy(s);
        g.delete_buffer(host);
        g.delete_buffer(back);
        g.delete_buffer(nan);
    }
    other.make_current();
    host_buffers_intact(&og, &theirs);
    drop(other);
    drop(home);
}

/// A CPU scene from AUTO that binds a buffer: its read-back logs no debug message and
/// keeps the host's pending error.
#[test]
fn binding_under_auto_is_quiet() {
    let ctx = Ctx::new(Profile::Compat);
    let mut g = ctx.glow();
    let log: Log = Arc::default();
    let sink = log.clone();
    // SAFETY: the test's context is current; the callback only records.
    unsafe {
        g.enable(glow::DEBUG_OUTPUT);
        g.enable(glow::DEBUG_OUTPUT_SYNCHRONOUS);
        g.debug_message_callback(move |_source, kind, id, _severity, msg: &str| {
            sink.lock()
                .unwrap()
                .push(format!("type 0x{kind:x} id {id}: {msg}"));
        });
    }
    let (a, b) = sheets(0.0);
    let s = scene(GlcolBackend::Auto, 0.0, 0);
    add_mesh(s, &a.pos, &a.idx, 3);
    let b_id = add_mesh(s, &b.pos, &b.idx, 3);
    let host = host_positions(&g, &b.pos);
    for what in ["bind", "query_all", "destroy"] {
        // SAFETY: the test's context is current; an invalid enum on purpose.
        unsafe { g.enable(0) };
        log.lock().unwrap().clear();
        match what {
            // SAFETY: a live scene; its context is current.
            "bind" => ok(unsafe { glcol_mesh_bind_gl_buffer(s, b_id, host.0.get(), 0, 0) }),
            "query_all" => assert_eq!(query_all_status(s).0, GlcolStatus::Ok),
            // SAFETY: a live scene; its context is current.
            _ => unsafe { glcol_scene_destroy(s) },
        }
        // SAFETY: the test's context is current.
        unsafe {
            assert_eq!(g.get_error(), glow::INVALID_ENUM, "{what}: host error lost");
            assert_eq!(g.get_error(), glow::NO_ERROR, "{what}: an error of ours");
            let l = std::mem::take(&mut *log.lock().unwrap());
            assert!(l.is_empty(), "{what} logged {l:#?}");
        }
    }
    // SAFETY: the test's context is current; the buffer is its own.
    unsafe {
        g.delete_buffer(host);
        g.disable(glow::DEBUG_OUTPUT);
    }
}

/// A context sharing the scene's objects but of a kind the backend cannot use: a core
/// profile for GL_SELECT is refused with a message (GL_SELECT's entry points would fail
/// there); a compatibility one for a GL_COMPUTE scene made in a core context is fine.
#[test]
fn a_shared_context_of_another_kind() {
    let (a, b) = sheets(0.0);
    let want = cpu_answer(&a, &b);
    for (home_profile, backend, shared_profile, usable) in [
        (
            Profile::Compat,
            GlcolBackend::GlSelect,
            Profile::Core,
            false,
        ),
        (
            Profile::Core,
            GlcolBackend::GlCompute,
            Profile::Compat,
            true,
        ),
    ] {
        let home = Ctx::new(home_profile);
        let s = scene(backend, 0.0, 0);
        add_mesh(s, &b.pos, &b.idx, 3);
        let a_id = add_mesh(s, &a.pos, &a.idx, 3);
        let shared = Ctx::new_shared(shared_profile, &home);
        if usable {
            assert_eq!(try_query(s, a_id).unwrap(), want, "{backend:?}");
        } else {
            refused(
                try_query(s, a_id),
                GlcolStatus::GlUnavailable,
                &["wrong GL context current", "compatibility profile"],
            );
        }
        drop(shared);
        home.make_current();
        assert_eq!(try_query(s, a_id).unwrap(), want, "{backend:?} home");
        // SAFETY: a live scene; its context is current.
        unsafe { glcol_scene_destroy(s) };
    }
}

/// Targets and GL buffers (issue 25): a mesh bound to a GL buffer has the start of its step
/// in the host's buffer, so it takes no target (UNSUPPORTED, nothing changed), and a mesh with
/// a target cannot be bound until its target is cleared (AUTO on llvmpipe: a CPU scene that
/// reads bound buffers back at each query; GL_COMPUTE keeps them on the GPU).
#[test]
fn targets_and_bound_buffers_exclude_each_other() {
    let home = Ctx::new(Profile::Core);
    let g = home.glow();
    let (a, b) = sheets(0.0);
    let s = scene(GlcolBackend::Auto, 0.0, 0);
    let b_id = add_mesh(s, &b.pos, &b.idx, 3);
    let a_id = add_mesh(s, &a.pos, &a.idx, 3);
    let shift: [f64; 12] = [1.0, 0.0, 0.0, 0.25, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0];
    // SAFETY: a live scene; its context is current; `shift` is 12 doubles.
    ok(unsafe { glcol_mesh_set_target_transform(s, a_id, shift.as_ptr()) });
    // A mesh with a target is not bound.
    let host = host_strided(&g, &b.pos, 0, 12);
    // SAFETY: as above.
    ok(unsafe { glcol_mesh_set_target_transform(s, b_id, shift.as_ptr()) });
    // SAFETY: as above.
    let st = unsafe { glcol_mesh_bind_gl_buffer(s, b_id, host.0.get(), 0, 0) };
    assert_eq!(st, GlcolStatus::Unsupported, "{}", last_error());
    assert!(
        last_error().contains("clear its target"),
        "{}",
        last_error()
    );
    // SAFETY: as above.
    ok(unsafe { glcol_mesh_clear_target(s, b_id) });
    // SAFETY: as above.
    ok(unsafe { glcol_mesh_bind_gl_buffer(s, b_id, host.0.get(), 0, 0) });
    // A bound mesh takes no target.
    // SAFETY: as above.
    let st = unsafe { glcol_mesh_set_target_transform(s, b_id, shift.as_ptr()) };
    assert_eq!(st, GlcolStatus::Unsupported, "{}", last_error());
    let p = [0.0f32; 3];
    // SAFETY: as above; `p` holds one vertex.
    let st = unsafe { glcol_mesh_set_target_positions(s, b_id, p.as_ptr(), 0, 1, 0) };
    assert_eq!(st, GlcolStatus::Unsupported, "{}", last_error());
    assert!(last_error().contains("GL buffer"), "{}", last_error());
    // The refusals changed nothing: the bound mesh answers as before, and a's target is
    // still there to clear.
    assert!(!try_query(s, a_id).unwrap().is_empty());
    // SAFETY: as above.
    ok(unsafe { glcol_mesh_clear_target(s, a_id) });
    // SAFETY: a live scene; its context is current.
    unsafe { glcol_scene_destroy(s) };
}
