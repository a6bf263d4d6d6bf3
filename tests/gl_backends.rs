//! All three backends on the same scenes, through the C API, on headless Mesa (llvmpipe):
//! GL_SELECT in a compatibility context, GL_COMPUTE in a core 4.5 and a compatibility
//! context. Each answer is checked against the independent exact oracle: every exactly
//! intersecting pair is found, and every extra pair is within epsilon / 2. The GL backends
//! confirm their last step with the CPU's test, so they must also equal the CPU backend.
mod common;

use common::backends::gl_support;

use common::{brute_force_exact, brute_force_within, place, shared_mesh, wave, TestMesh};
use gl_support::*;
use glcollide::ffi::*;

type Pairs = Vec<(u32, u32)>;
/// One frame: the reference's positions and the other mesh's.
type Frame = (Vec<[f32; 3]>, Vec<[f32; 3]>);

/// Runs `frames` (reference, other) position sets through a scene of `backend`.
fn run(
    backend: GlcolBackend,
    eps: f32,
    r: &TestMesh,
    o: &TestMesh,
    frames: &[Frame],
) -> Vec<Pairs> {
    let s = scene(backend, eps, 0);
    let o_id = add_mesh(s, &o.pos, &o.idx, o.k);
    let r_id = add_mesh(s, &r.pos, &r.idx, r.k);
    let out = frames
        .iter()
        .map(|(rp, op)| {
            update(s, r_id, rp);
            update(s, o_id, op);
            let q = query(s, r_id);
            assert!(q.iter().all(|c| c.0 == o_id));
            q.iter().map(|c| (c.1, c.2)).collect()
        })
        .collect();
    // SAFETY: `s` is a live scene of this test; its GL context is current on this thread.
    unsafe { glcol_scene_destroy(s) };
    out
}

/// Checks one scene on the backends usable in `profile` against the CPU and the oracle.
fn check(
    profile: Profile,
    eps: f32,
    r: &TestMesh,
    o: &TestMesh,
    frames: &[Frame],
    min_contacts: usize,
) {
    let _ctx = Ctx::new(profile);
    let cpu = run(GlcolBackend::Cpu, eps, r, o, frames);
    let mut backends = vec![GlcolBackend::GlCompute];
    if profile == Profile::Compat {
        backends.push(GlcolBackend::GlSelect);
    }
    let mut total = 0;
    for (f, (rp, op)) in frames.iter().enumerate() {
        let rm = TestMesh {
            pos: rp.clone(),
            ..r.clone()
        };
        let om = TestMesh {
            pos: op.clone(),
            ..o.clone()
        };
        let exact = brute_force_exact(&rm, &om);
        let band = brute_force_within(&rm, &om, f64::from(eps) / 2.0 * (1.0 + 1e-6) + 1e-12);
        for p in &exact {
            assert!(
                cpu[f].binary_search(p).is_ok(),
                "frame {f}: CPU missed exact pair {p:?}"
            );
        }
        for p in &cpu[f] {
            assert!(
                band.binary_search(p).is_ok(),
                "frame {f}: CPU pair {p:?} beyond epsilon/2"
            );
        }
        total += exact.len();
    }
    assert!(
        total >= min_contacts,
        "scene too easy: {total} exact contacts"
    );
    for b in backends {
        let got = match std::panic::catch_unwind(|| run(b, eps, r, o, frames)) {
            Ok(g) => g,
            Err(e) => std::panic::resume_unwind(e),
        };
        for f in 0..frames.len() {
            assert_eq!(
                got[f], cpu[f],
                "{b:?} in {profile:?}, frame {f}: differs from the CPU backend"
            );
        }
    }
}

fn blade_and_gallbladder() -> (TestMesh, TestMesh, Vec<Frame>) {
    let blade = TestMesh::from_obj(&shared_mesh("scissors_blade"));
    let organ = TestMesh::from_obj(&shared_mesh("gallbladder_glt"));
    // The blade centred on the organ's vertex farthest along +x: it crosses the surface.
    let far = *organ
        .pos
        .iter()
        .max_by(|a, b| a[0].total_cmp(&b[0]))
        .unwrap();
    let frames = (0..3)
        .map(|f| {
            let b = place(&blade.pos, [far[0] - f as f32, far[1], far[2]], 1.57);
            (b, wave(&organ.pos, 0.3, 0.1, f as f32))
        })
        .collect();
    (blade, organ, frames)
}

#[test]
fn real_meshes_compat() {
    let (b, o, frames) = blade_and_gallbladder();
    check(Profile::Compat, 0.001, &b, &o, &frames, 1);
}

#[test]
fn real_meshes_core() {
    let (b, o, frames) = blade_and_gallbladder();
    check(Profile::Core, 0.001, &b, &o, &frames, 1);
}

/// A grid of quads (k = 4) or triangles in the plane z = `z`.
fn grid(n: usize, step: f32, origin: [f32; 3], quads: bool) -> TestMesh {
    let mut pos = Vec::new();
    for j in 0..=n {
        for i in 0..=n {
            pos.push([
                origin[0] + i as f32 * step,
                origin[1] + j as f32 * step,
                origin[2],
            ]);
        }
    }
    let id = |i: usize, j: usize| (j * (n + 1) + i) as u32;
    let mut idx = Vec::new();
    for j in 0..n {
        for i in 0..n {
            if quads {
                idx.extend([id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)]);
            } else {
                idx.extend([
                    id(i, j),
                    id(i + 1, j),
                    id(i + 1, j + 1),
                    id(i, j),
                    id(i + 1, j + 1),
                    id(i, j + 1),
                ]);
            }
        }
    }
    TestMesh {
        pos,
        idx,
        k: if quads { 4 } else { 3 },
    }
}

#[test]
fn coplanar_touching_and_quads() {
    // Coplanar overlap: two grids in z = 0, shifted by half a cell; a third frame lifts the
    // other grid to touch the reference only along... nothing (just above epsilon/2).
    let r = grid(6, 1.0, [0.0; 3], true);
    let o = grid(8, 0.75, [2.5, 2.5, 0.0], false);
    let frames = vec![
        (r.pos.clone(), o.pos.clone()),
        // Touching at an edge: the other grid starts exactly at x = 6 (the reference's edge).
        (
            r.pos.clone(),
            o.pos.iter().map(|p| [p[0] + 3.5, p[1], p[2]]).collect(),
        ),
        // Lifted above the plane by more than epsilon / 2: only band pairs may appear.
        (
            r.pos.clone(),
            o.pos.iter().map(|p| [p[0], p[1], p[2] + 0.0004]).collect(),
        ),
        (
            r.pos.clone(),
            o.pos.iter().map(|p| [p[0], p[1], p[2] + 0.0006]).collect(),
        ),
    ];
    check(Profile::Compat, 0.001, &r, &o, &frames, 1);
    check(Profile::Core, 0.001, &r, &o, &frames, 1);
}

#[test]
fn degenerate_polygons_and_touching_vertices() {
    // Reference: a fan with a zero-area (collinear) triangle and a point triangle.
    let r = TestMesh {
        pos: vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [2.0, 0.0, 0.0],
            [0.5, 0.5, 0.0],
        ],
        idx: vec![0, 1, 2, 0, 1, 3, 4, 4, 4],
        k: 3,
    };
    // Other: a triangle through the segment, one touching vertex 2, one crossing the point.
    let o = TestMesh {
        pos: vec![
            [1.5, -1.0, -1.0],
            [1.5, 1.0, -1.0],
            [1.5, 0.0, 1.0],
            [0.0, 1.0, 0.0],
            [-1.0, 2.0, 1.0],
            [-1.0, 2.0, -1.0],
            [0.5, 0.5, -1.0],
            [0.5, 0.5, 1.0],
            [0.6, 0.6, 1.0],
        ],
        idx: vec![0, 1, 2, 3, 4, 5, 6, 7, 8],
        k: 3,
    };
    let frames = vec![(r.pos.clone(), o.pos.clone())];
    check(Profile::Compat, 0.001, &r, &o, &frames, 3);
    check(Profile::Core, 0.001, &r, &o, &frames, 3);
}

#[test]
fn far_from_origin() {
    let a = TestMesh::from_obj(&shared_mesh("bunny"));
    let b = TestMesh::from_obj(&shared_mesh("teapot"));
    let far = [1.0e5f32, -2.0e5, 1.5e5];
    let frames: Vec<_> = (0..2)
        .map(|f| {
            (
                place(&a.pos, [far[0] + 2.0 * f as f32, far[1], far[2]], 0.3),
                place(&b.pos, [far[0] + 5.0, far[1] + 1.0, far[2]], 0.0),
            )
        })
        .collect();
    // Float positions near 2e5 are 1/64 apart; epsilon 0.05 is well above that.
    check(Profile::Compat, 0.05, &a, &b, &frames, 1);
    check(Profile::Core, 0.05, &a, &b, &frames, 1);
}

/// Epsilon 0 on the GL backends: the GL's tests use the documented minimum depth (2^-20 of
/// the extent) and each hit is confirmed with the CPU's exact test, so the answer is the
/// exact one. With a mesh bound to a GL buffer (no CPU positions) the GPU's answer at the
/// minimum depth is final: every exact pair, extras within that band.
#[test]
fn epsilon_zero_is_exact_on_the_gl_backends() {
    use glow::HasContext;
    let (b, o, frames) = blade_and_gallbladder();
    let ctx = Ctx::new(Profile::Compat);
    let om = TestMesh {
        pos: frames[0].1.clone(),
        ..o.clone()
    };
    let bm = TestMesh {
        pos: frames[0].0.clone(),
        ..b.clone()
    };
    let exact = brute_force_exact(&bm, &om);
    assert!(!exact.is_empty());
    for backend in [GlcolBackend::GlSelect, GlcolBackend::GlCompute] {
        let got = run(backend, 0.0, &b, &o, &frames[..1]);
        assert_eq!(got[0], exact, "{backend:?} at epsilon 0");
    }
    // Bound to a host buffer: the minimum epsilon band.
    let (lo, hi) = common::bounds(&om.pos);
    let extent = (0..3).map(|k| (hi[k] - lo[k]) as f64).fold(0.0, f64::max);
    let min_eps = extent * glcollide::internals::MIN_RELATIVE_EPSILON;
    let g = ctx.glow();
    let s = scene(GlcolBackend::GlCompute, 0.0, 0);
    let o_id = add_mesh(s, &om.pos, &om.idx, 3);
    let b_id = add_mesh(s, &bm.pos, &bm.idx, 3);
    let host = host_buffer(&g, &om.pos);
    // SAFETY: `s` is a live scene of this test; its GL context is current on this thread.
    ok(unsafe { glcol_mesh_bind_gl_buffer(s, o_id, host.0.get(), 0, 0) });
    let got: Pairs = query(s, b_id).iter().map(|c| (c.1, c.2)).collect();
    for p in &exact {
        assert!(got.binary_search(p).is_ok(), "bound: missed {p:?}");
    }
    let band = brute_force_within(&bm, &om, min_eps / 2.0 * 1.000001 + 1e-12);
    for p in &got {
        assert!(
            band.binary_search(p).is_ok(),
            "bound: {p:?} beyond the minimum epsilon band"
        );
    }
    // Contact geometry of the bound mesh (read back from what the query gathered): the
    // exact pairs intersect, any pair the band added does not (closest points, depth <= 0).
    let contacts = query(s, b_id);
    let (mut gp, mut gn) = (std::ptr::null(), 0);
    // SAFETY: `s` is a live scene of this test; its GL context is current on this thread.
    ok(unsafe { glcol_query_geometry(s, &mut gp, &mut gn) });
    assert_eq!(gn, contacts.len());
    // SAFETY: the scene's `gn` entries, alive until its next query.
    let geo = unsafe { std::slice::from_raw_parts(gp, gn) };
    let mut extras = 0;
    for (c, g) in contacts.iter().zip(geo) {
        let intersecting = g.flags & GLCOL_CONTACT_INTERSECTING != 0;
        assert_eq!(
            intersecting,
            exact.binary_search(&(c.1, c.2)).is_ok(),
            "bound: geometry of {c:?}"
        );
        assert!(intersecting || g.depth <= 0.0, "{c:?}");
        extras += usize::from(!intersecting);
    }
    println!(
        "bound: {} pairs, {extras} within the band only",
        contacts.len()
    );
    // SAFETY: `s` is a live scene of this test; its GL context is current on this thread.
    unsafe {
        glcol_scene_destroy(s);
        g.delete_buffer(host);
    }
}

#[test]
fn backend_choice_and_refusals() {
    {
        let _ctx = Ctx::new(Profile::Core);
        let e = try_scene(GlcolBackend::GlSelect, 0.001, 0).unwrap_err();
        assert_eq!(e.0, GlcolStatus::GlUnavailable);
        assert!(
            e.1.contains("core-profile") && e.1.contains("compatibility"),
            "{}",
            e.1
        );
        // AUTO on a software renderer is the CPU.
        let s = scene(GlcolBackend::Auto, 0.001, 0);
        assert_eq!(backend_of(s), GlcolBackend::Cpu as u32);
        // SAFETY: `s` is a live scene of this test; its GL context is current on this thread.
        unsafe { glcol_scene_destroy(s) };
        let s = scene(GlcolBackend::GlCompute, 0.001, 0);
        assert_eq!(backend_of(s), GlcolBackend::GlCompute as u32);
        // SAFETY: `s` is a live scene of this test; its GL context is current on this thread.
        unsafe { glcol_scene_destroy(s) };
    }
    // No current context.
    let e = try_scene(GlcolBackend::GlCompute, 0.001, 0).unwrap_err();
    assert_eq!(e.0, GlcolStatus::GlUnavailable);
    assert!(e.1.contains("no GL context is current"), "{}", e.1);
    // No loader.
    // SAFETY: this test's GL context is current on this thread; the objects are its own.
    unsafe {
        let mut d = std::mem::zeroed::<GlcolSceneDesc>();
        glcol_scene_desc_init_sized(&mut d, std::mem::size_of::<GlcolSceneDesc>());
        d.backend = GlcolBackend::GlSelect as u32;
        let mut s = std::ptr::null_mut();
        assert_eq!(glcol_scene_create(&d, &mut s), GlcolStatus::GlUnavailable);
        d.backend = GlcolBackend::Auto as u32;
        ok(glcol_scene_create(&d, &mut s));
        assert_eq!(backend_of(s), GlcolBackend::Cpu as u32);
        let p = [[0.0f32; 3]; 3];
        let m = add_mesh(s, &p, &[0, 1, 2], 3);
        assert_eq!(
            glcol_mesh_bind_gl_buffer(s, m, 1, 0, 0),
            GlcolStatus::Unsupported
        );
        glcol_scene_destroy(s);
    }
    let _ctx = Ctx::new(Profile::Compat);
    let s = scene(GlcolBackend::GlSelect, 0.001, 0);
    assert_eq!(backend_of(s), GlcolBackend::GlSelect as u32);
    let p = [[0.0f32; 3]; 3];
    let m = add_mesh(s, &p, &[0, 1, 2], 3);
    assert_eq!(
        // SAFETY: `s` is a live scene of this test; its GL context is current on this thread.
        unsafe { glcol_mesh_bind_gl_buffer(s, m, 1, 0, 0) },
        GlcolStatus::Unsupported
    );
    // SAFETY: `s` is a live scene of this test; its GL context is current on this thread.
    unsafe { glcol_scene_destroy(s) };
}

/// Positions straight from a buffer object the host owns (interleaved with normals, at an
/// offset): GL_COMPUTE's answer is checked against the oracle (no CPU confirmation here).
#[test]
fn positions_from_a_host_buffer() {
    use glow::HasContext;
    let (b, o, frames) = blade_and_gallbladder();
    let ctx = Ctx::new(Profile::Core);
    let g = ctx.glow();
    let eps = 0.001f32;
    let s = scene(GlcolBackend::GlCompute, eps, 0);
    let o_id = add_mesh(s, &o.pos, &o.idx, 3);
    let b_id = add_mesh(s, &b.pos, &b.idx, 3);
    // Host layout: 16 bytes of header, then (x, y, z, nx, ny, nz) per vertex.
    // SAFETY: this test's GL context is current on this thread; the objects are its own.
    let host = unsafe { g.create_buffer().unwrap() };
    for (f, (bp, op)) in frames.iter().enumerate() {
        let mut data: Vec<f32> = vec![0.0; 4];
        for p in op {
            data.extend_from_slice(&[p[0], p[1], p[2], 0.0, 0.0, 1.0]);
        }
        // SAFETY: this test's GL context is current on this thread; the objects are its own.
        unsafe {
            g.bind_buffer(glow::ARRAY_BUFFER, Some(host));
            let bytes = std::slice::from_raw_parts(data.as_ptr().cast::<u8>(), data.len() * 4);
            g.buffer_data_u8_slice(glow::ARRAY_BUFFER, bytes, glow::STREAM_DRAW);
            g.bind_buffer(glow::ARRAY_BUFFER, None);
        }
        update(s, b_id, bp);
        // SAFETY: `s` is a live scene of this test; its GL context is current on this thread.
        ok(unsafe { glcol_mesh_bind_gl_buffer(s, o_id, host.0.get(), 16, 24) });
        let got: Pairs = query(s, b_id).iter().map(|c| (c.1, c.2)).collect();
        let bm = TestMesh {
            pos: bp.clone(),
            ..b.clone()
        };
        let om = TestMesh {
            pos: op.clone(),
            ..o.clone()
        };
        let exact = brute_force_exact(&bm, &om);
        assert!(!exact.is_empty());
        for p in &exact {
            assert!(got.binary_search(p).is_ok(), "frame {f}: missed {p:?}");
        }
        let band = brute_force_within(&bm, &om, f64::from(eps) / 2.0 * 1.00001);
        for p in &got {
            assert!(
                band.binary_search(p).is_ok(),
                "frame {f}: {p:?} beyond epsilon/2"
            );
        }
    }
    // Bad bindings are refused and change nothing.
    // SAFETY: this test's GL context is current on this thread; the objects are its own.
    unsafe {
        assert_eq!(
            glcol_mesh_bind_gl_buffer(s, o_id, 0, 0, 0),
            GlcolStatus::InvalidArgument
        );
        assert_eq!(
            glcol_mesh_bind_gl_buffer(s, o_id, host.0.get(), 2, 12),
            GlcolStatus::InvalidArgument
        );
        assert_eq!(
            glcol_mesh_bind_gl_buffer(s, o_id, host.0.get(), 1 << 30, 12),
            GlcolStatus::InvalidArgument
        );
        assert_eq!(
            glcol_mesh_bind_gl_buffer(s, 999, host.0.get(), 0, 12),
            GlcolStatus::UnknownMesh
        );
        glcol_scene_destroy(s);
        g.delete_buffer(host);
    }
}
