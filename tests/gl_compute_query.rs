//! GL_COMPUTE's query (steps 1 to 5 on the GPU, one read-back) against the step-by-step
//! path (each step through a batch, answered by the brute-force test adapter
//! `BruteSelector`) and against the CPU backend, on real meshes, headless on Mesa
//! (llvmpipe), in a core 4.5 context:
//! - the same contacts as the CPU backend, every frame;
//! - the same step-1 to step-4 hits as the step path (the same tests, run in another order);
//! - exactly one GL read-back per query once the buffers have room, and a complete answer
//!   when they have to grow mid-query (started with room for one entry each);
//! - a NaN in a host buffer is reported as NON_FINITE, and the next good frame is answered;
//!   the failed query leaves `Scene::contacts()` as the last successful query left it.
mod common;

use common::backends::gl_support;

use common::{place, shared_mesh, wave, TestMesh};
use gl_support::{gl_loader, host_buffer, Ctx, Profile};
use glcollide::internals::{BruteSelector, Gl, GlComputeSelector};
use glcollide::{Contact, ErrorKind, MeshId, Positions, QueryStats, Scene, SceneConfig};

/// How the GL_COMPUTE scene is set up.
#[derive(Clone, Copy, Debug)]
enum Path {
    Whole,
    /// Buffers starting with room for one entry each.
    WholeTiny,
}

fn gl_scene(config: SceneConfig, path: Path) -> Scene {
    gl_scene_with(config, |sel| match path {
        Path::Whole => {}
        Path::WholeTiny => sel.set_room(1, 1, 1),
    })
}

/// The five steps asked one batch at a time of the brute-force test adapter.
fn step_scene(config: SceneConfig) -> Scene {
    Scene::with_selector(config, Box::new(BruteSelector)).unwrap()
}

fn add(s: &mut Scene, m: &TestMesh) -> MeshId {
    s.create_mesh(Positions::from_points(&m.pos), &m.idx, m.k)
        .unwrap()
}

/// A scene's meshes, moved frame by frame; the reference is mesh 0.
struct Case {
    meshes: Vec<TestMesh>,
    /// frames[f][m]: positions of mesh m in frame f.
    frames: Vec<Vec<Vec<[f32; 3]>>>,
    /// Meshes disabled in every frame.
    disabled: Vec<usize>,
    epsilon: f32,
}

/// A contact with the other mesh named by its position in the case (ids differ by scene).
type Found = (usize, u32, u32);

/// Runs a case; per frame, the contacts and the stats.
fn run(case: &Case, make: &dyn Fn(SceneConfig) -> Scene) -> Vec<(Vec<Found>, QueryStats)> {
    let mut s = make(SceneConfig {
        epsilon: case.epsilon,
        max_polygons_per_box: 0,
        ..SceneConfig::default()
    });
    let ids: Vec<MeshId> = case.meshes.iter().map(|m| add(&mut s, m)).collect();
    for &d in &case.disabled {
        s.set_enabled(ids[d], false).unwrap();
    }
    let out = case
        .frames
        .iter()
        .map(|frame| {
            for (id, p) in ids.iter().zip(frame) {
                s.update_positions(*id, 0, Positions::from_points(p))
                    .unwrap();
            }
            let at = |id: MeshId| ids.iter().position(|&i| i == id).unwrap();
            let c: Vec<Found> = s
                .query(ids[0])
                .unwrap()
                .iter()
                .map(|c: &Contact| (at(c.other_mesh), c.reference_polygon, c.other_polygon))
                .collect();
            (c, s.stats())
        })
        .collect();
    s.release_gl();
    out
}

/// The blade through the gallbladder, a second gallbladder it also cuts, and a disabled
/// liver in the way.
fn instrument_case() -> Case {
    let blade = TestMesh::from_obj(&shared_mesh("scissors_blade"));
    let organ = TestMesh::from_obj(&shared_mesh("gallbladder_glt"));
    let liver = TestMesh::from_obj(&shared_mesh("liver_glt"));
    let far = *organ
        .pos
        .iter()
        .max_by(|a, b| a[0].total_cmp(&b[0]))
        .unwrap();
    let frames = (0..4)
        .map(|f| {
            let o = wave(&organ.pos, 0.3, 0.1, f as f32);
            let o2: Vec<[f32; 3]> = o.iter().map(|p| [p[0] + 3.0, p[1] + 1.0, p[2]]).collect();
            vec![
                place(&blade.pos, [far[0] - f as f32, far[1], far[2]], 1.57),
                o,
                o2,
                place(&liver.pos, far, 0.0),
            ]
        })
        .collect();
    Case {
        meshes: vec![blade, organ.clone(), organ, liver],
        frames,
        disabled: vec![3],
        epsilon: 0.001,
    }
}

/// Two organs deformed against each other (hundreds of contacts a frame).
fn organ_case() -> Case {
    let a = TestMesh::from_obj(&shared_mesh("colon"));
    let b = TestMesh::from_obj(&shared_mesh("small_intestine"));
    let (lo, hi) = common::bounds(&a.pos);
    let extent = (0..3).map(|k| hi[k] - lo[k]).fold(0.0, f32::max);
    let frames = (0..2)
        .map(|f| {
            vec![
                wave(&a.pos, 0.004 * extent, 8.0 / extent, f as f32 * 0.1),
                wave(&b.pos, -0.004 * extent, 8.0 / extent, f as f32 * 0.1),
            ]
        })
        .collect();
    Case {
        meshes: vec![a, b],
        frames,
        disabled: vec![],
        epsilon: 0.001,
    }
}

fn check(case: &Case, min_contacts: usize) {
    let _ctx = Ctx::new(Profile::Core);
    let cpu = run(case, &|c| Scene::new(c).unwrap());
    let whole = run(case, &|c| gl_scene(c, Path::Whole));
    let steps = run(case, &step_scene);
    let tiny = run(case, &|c| gl_scene(c, Path::WholeTiny));
    let mut total = 0;
    for f in 0..case.frames.len() {
        total += cpu[f].0.len();
        assert_eq!(whole[f].0, cpu[f].0, "frame {f}: whole query != CPU");
        assert_eq!(steps[f].0, cpu[f].0, "frame {f}: step path != CPU");
        assert_eq!(tiny[f].0, cpu[f].0, "frame {f}: grown buffers != CPU");
        let (w, s) = (whole[f].1, steps[f].1);
        assert_eq!(w.hits[..4], s.hits[..4], "frame {f}: steps 1-4 hits differ");
        assert_eq!(
            w.tests[1..4],
            s.tests[1..4],
            "frame {f}: steps 2-4 tests differ"
        );
        assert_eq!(
            w.readbacks, 1,
            "frame {f}: whole query read back {} times",
            w.readbacks
        );
        if f > 0 {
            assert_eq!(
                tiny[f].1.readbacks, 1,
                "frame {f}: buffers did not keep their room"
            );
        }
    }
    assert!(
        tiny[0].1.readbacks > 1,
        "room for one entry cannot hold the first frame"
    );
    assert!(total >= min_contacts, "scene too easy: {total} contacts");
}

#[test]
fn instrument_in_two_organs() {
    check(&instrument_case(), 10);
}

#[test]
fn organ_against_organ() {
    check(&organ_case(), 200);
}

/// Replaces the contents of the host's buffer `host` with `p` (xyz floats).
fn fill(g: &glow::Context, host: glow::NativeBuffer, p: &[[f32; 3]]) {
    use glow::HasContext;
    let flat: Vec<f32> = p.iter().flatten().copied().collect();
    // SAFETY: the bytes of `flat`'s floats, borrowed while `flat` lives.
    let bytes = unsafe { std::slice::from_raw_parts(flat.as_ptr().cast::<u8>(), flat.len() * 4) };
    // SAFETY: this test's GL context is current on this thread; `host` is its own buffer.
    unsafe {
        g.bind_buffer(glow::ARRAY_BUFFER, Some(host));
        g.buffer_data_u8_slice(glow::ARRAY_BUFFER, bytes, glow::STREAM_DRAW);
        g.bind_buffer(glow::ARRAY_BUFFER, None);
    }
}

/// A GL_COMPUTE scene (a leaf a polygon, `epsilon`) with `case`'s blade at frame `f`'s
/// positions and its organ read from a new host buffer holding frame `f`'s: (scene, blade,
/// organ, the buffer).
fn blade_and_bound_organ(
    g: &glow::Context,
    case: &Case,
    epsilon: f32,
    f: usize,
) -> (Scene, MeshId, MeshId, glow::NativeBuffer) {
    use glow::HasContext;
    let config = SceneConfig {
        epsilon,
        max_polygons_per_box: 0,
        ..SceneConfig::default()
    };
    let mut s = gl_scene(config, Path::Whole);
    let blade = add(&mut s, &case.meshes[0]);
    let organ = add(&mut s, &case.meshes[1]);
    let frame = &case.frames[f];
    s.update_positions(blade, 0, Positions::from_points(&frame[0]))
        .unwrap();
    // SAFETY: this test's GL context is current on this thread; the objects are its own.
    let host = unsafe { g.create_buffer().unwrap() };
    fill(g, host, &frame[1]);
    s.bind_gl_buffer(organ, host.0.get(), 0, 0).unwrap();
    (s, blade, organ, host)
}

/// A host buffer with a NaN: NON_FINITE, then the next good frame is answered in full.
#[test]
fn nan_in_a_host_buffer() {
    use glow::HasContext;
    let ctx = Ctx::new(Profile::Core);
    let g = ctx.glow();
    let case = instrument_case();
    let mut s = gl_scene(
        SceneConfig {
            epsilon: 0.001,
            max_polygons_per_box: 0,
            ..SceneConfig::default()
        },
        Path::Whole,
    );
    let blade = add(&mut s, &case.meshes[0]);
    let organ = add(&mut s, &case.meshes[1]);
    let mut cpu = Scene::new(*s.config()).unwrap();
    let cb = add(&mut cpu, &case.meshes[0]);
    let co = add(&mut cpu, &case.meshes[1]);
    // SAFETY: this test's GL context is current on this thread; the objects are its own.
    let host = unsafe { g.create_buffer().unwrap() };
    let frame = &case.frames[1];
    s.update_positions(blade, 0, Positions::from_points(&frame[0]))
        .unwrap();
    cpu.update_positions(cb, 0, Positions::from_points(&frame[0]))
        .unwrap();
    cpu.update_positions(co, 0, Positions::from_points(&frame[1]))
        .unwrap();
    let want: Vec<(u32, u32)> = cpu
        .query(cb)
        .unwrap()
        .iter()
        .map(|c| (c.reference_polygon, c.other_polygon))
        .collect();
    assert!(!want.is_empty());
    let mut bad = frame[1].clone();
    bad[17][1] = f32::NAN;
    fill(&g, host, &bad);
    s.bind_gl_buffer(organ, host.0.get(), 0, 0).unwrap();
    let e = s.query(blade).unwrap_err();
    assert_eq!(e.kind, ErrorKind::NonFinite, "{}", e.message);
    assert!(e.message.contains(&organ.to_string()), "{}", e.message);
    fill(&g, host, &frame[1]);
    let got: Vec<(u32, u32)> = s
        .query(blade)
        .unwrap()
        .iter()
        .map(|c| (c.reference_polygon, c.other_polygon))
        .collect();
    // No CPU confirmation with a host buffer: every exact pair, extras within the band.
    for p in &want {
        assert!(got.binary_search(p).is_ok(), "missed {p:?}");
    }
    assert!(
        got.len() <= want.len() * 2,
        "{} vs {}",
        got.len(),
        want.len()
    );
    assert_eq!(s.stats().readbacks, 1);
    s.release_gl();
    // SAFETY: this test's GL context is current on this thread; the objects are its own.
    unsafe { g.delete_buffer(host) };
}

/// A query that fails (a NaN in a host buffer) leaves `Scene::contacts()` as the last
/// successful query answered it, as its documentation promises.
#[test]
fn a_failed_query_keeps_the_last_contacts() {
    use glow::HasContext;
    let ctx = Ctx::new(Profile::Core);
    let g = ctx.glow();
    let case = instrument_case();
    let frame = &case.frames[1];
    let (mut s, blade, _, host) = blade_and_bound_organ(&g, &case, 0.001, 1);
    let good: Vec<Contact> = s.query(blade).unwrap().to_vec();
    assert!(!good.is_empty(), "the scene should collide");
    assert_eq!(s.contacts(), &good[..]);
    // Contact geometry with no context current: GL_UNAVAILABLE (the organ's positions are
    // on the GPU), and the answer stays; with it, one entry a contact.
    ctx.release_current();
    let e = s.contact_geometry().unwrap_err();
    assert_eq!(e.kind, ErrorKind::GlUnavailable, "{}", e.message);
    ctx.make_current();
    assert_eq!(s.contacts(), &good[..]);
    assert_eq!(s.contact_geometry().unwrap().len(), good.len());
    assert_eq!(s.contacts(), &good[..]);
    let mut bad = frame[1].clone();
    bad[17][1] = f32::NAN;
    fill(&g, host, &bad);
    let e = s.query(blade).unwrap_err();
    assert_eq!(e.kind, ErrorKind::NonFinite, "{}", e.message);
    assert_eq!(
        s.contacts(),
        &good[..],
        "a failed query changed contacts() (cleared or partial)"
    );
    s.release_gl();
    // SAFETY: this test's GL context is current on this thread; the objects are its own.
    unsafe { g.delete_buffer(host) };
}

/// Contact geometry of a mesh read from a host GL buffer on GL_COMPUTE: read back from what
/// the query gathered on the GPU, so bit for bit the geometry of the buffer's positions at
/// the query, even when the host has written the buffer since; at epsilon 0 the pairs the
/// GPU answer adds within its rounding band (no CPU confirmation) get INTERSECTING false
/// and their closest points, every other pair the exact intersection's geometry.
#[test]
fn geometry_of_a_bound_mesh_is_what_its_query_read() {
    use glcollide::internals::contact::{contact_geometry, ContactGeometry};
    use glow::HasContext;
    let ctx = Ctx::new(Profile::Core);
    let g = ctx.glow();
    let case = instrument_case();
    let (mut s, blade, _, host) = blade_and_bound_organ(&g, &case, 0.0, 0);
    let triangle = |m: &TestMesh, pos: &[[f32; 3]], p: u32| {
        let c = |k: usize| pos[m.idx[3 * p as usize + k] as usize].map(f64::from);
        [[c(0), c(1), c(2)]; 2]
    };
    let mut checked = (0, 0);
    for f in 0..3 {
        let frame = &case.frames[f];
        s.update_positions(blade, 0, Positions::from_points(&frame[0]))
            .unwrap();
        fill(&g, host, &frame[1]);
        let contacts: Vec<Contact> = s.query(blade).unwrap().to_vec();
        assert!(!contacts.is_empty(), "frame {f}: the scene should collide");
        // The host moves its organ on before asking: the geometry is the query's.
        let moved: Vec<[f32; 3]> = frame[1].iter().map(|p| [p[0] + 0.5, p[1], p[2]]).collect();
        fill(&g, host, &moved);
        let got: Vec<ContactGeometry> = s.contact_geometry().unwrap().to_vec();
        assert_eq!(got.len(), contacts.len());
        for (c, h) in contacts.iter().zip(&got) {
            let a = triangle(&case.meshes[0], &frame[0], c.reference_polygon);
            let b = triangle(&case.meshes[1], &frame[1], c.other_polygon);
            let want = contact_geometry(&a, 1, &b, 1);
            let bits = |g: &ContactGeometry| {
                let mut v: Vec<u64> = [g.point_a, g.point_b, g.normal]
                    .iter()
                    .flatten()
                    .chain([&g.depth])
                    .map(|x| (x + 0.0).to_bits())
                    .collect();
                v.extend([u64::from(g.intersecting), u64::from(g.coplanar)]);
                v
            };
            assert_eq!(bits(h), bits(&want), "frame {f}: {c:?}");
            checked.0 += 1;
            checked.1 += usize::from(!h.intersecting);
        }
        // The whole-scene query likewise (blade = the lower mesh id: polygon a).
        fill(&g, host, &frame[1]);
        let pairs = s.query_all().unwrap().to_vec();
        assert!(!pairs.is_empty() && pairs.iter().all(|p| p.mesh_a == blade));
        fill(&g, host, &moved);
        let got: Vec<ContactGeometry> = s.contact_geometry().unwrap().to_vec();
        for (p, h) in pairs.iter().zip(&got) {
            let a = triangle(&case.meshes[0], &frame[0], p.polygon_a);
            let b = triangle(&case.meshes[1], &frame[1], p.polygon_b);
            let want = contact_geometry(&a, 1, &b, 1);
            assert_eq!(h.point_a, want.point_a, "frame {f}: {p:?}");
            assert_eq!(
                (h.normal, h.depth, h.intersecting),
                (want.normal, want.depth, want.intersecting)
            );
        }
    }
    assert!(checked.0 > 20, "{checked:?}");
    s.release_gl();
    // SAFETY: this test's GL context is current on this thread; the objects are its own.
    unsafe { g.delete_buffer(host) };
}

/// Self-collision of a mesh read from a host buffer runs on the CPU, which GL_COMPUTE
/// leaves without its positions: `query_all` refuses it (UNSUPPORTED naming the mesh), and
/// answers once it is off, with contact geometry read back for the mesh.
#[test]
fn self_collision_of_a_bound_mesh_is_refused() {
    use glow::HasContext;
    let ctx = Ctx::new(Profile::Core);
    let g = ctx.glow();
    let case = instrument_case();
    let (mut s, _, organ, host) = blade_and_bound_organ(&g, &case, 0.0, 1);
    s.set_self_collision(organ, true).unwrap();
    let e = s.query_all().unwrap_err();
    assert_eq!(e.kind, ErrorKind::Unsupported, "{}", e.message);
    assert!(
        e.message.contains(&format!("mesh {organ}"))
            && e.message.contains("self-collision off")
            && !e.message.contains("  "),
        "{}",
        e.message
    );
    s.set_self_collision(organ, false).unwrap();
    let n = s.query_all().unwrap().len();
    assert!(n > 0);
    assert_eq!(s.contact_geometry().unwrap().len(), n);
    s.release_gl();
    // SAFETY: this test's GL context is current on this thread; the objects are its own.
    unsafe { g.delete_buffer(host) };
}

/// A mesh bound to a host buffer after being created at placeholder positions far away:
/// `query_all` finds its pairs as `query` does (the whole-scene broad phase cannot use its
/// CPU box, which is the placeholders'), and their geometry is read back.
#[test]
fn query_all_finds_a_bound_mesh_created_elsewhere() {
    use glow::HasContext;
    let ctx = Ctx::new(Profile::Core);
    let g = ctx.glow();
    let case = instrument_case();
    let mut s = gl_scene(SceneConfig::default(), Path::Whole);
    let frame = &case.frames[1];
    let blade = add(&mut s, &case.meshes[0]);
    s.update_positions(blade, 0, Positions::from_points(&frame[0]))
        .unwrap();
    let far: Vec<[f32; 3]> = frame[1].iter().map(|p| [p[0] + 1e4, p[1], p[2]]).collect();
    let organ = s
        .create_mesh(Positions::from_points(&far), &case.meshes[1].idx, 3)
        .unwrap();
    // SAFETY: this test's GL context is current on this thread; the objects are its own.
    let host = unsafe { g.create_buffer().unwrap() };
    fill(&g, host, &frame[1]);
    s.bind_gl_buffer(organ, host.0.get(), 0, 0).unwrap();
    let one: Vec<(u32, u32)> = s
        .query(blade)
        .unwrap()
        .iter()
        .map(|c| (c.reference_polygon, c.other_polygon))
        .collect();
    assert!(!one.is_empty());
    let all: Vec<(u32, u32)> = s
        .query_all()
        .unwrap()
        .iter()
        .map(|p| (p.polygon_a, p.polygon_b))
        .collect();
    assert_eq!(all, one);
    let geo = s.contact_geometry().unwrap();
    assert!(
        geo.iter().all(|g| g.point_a[0] < 1e3),
        "placeholder positions read"
    );
    s.release_gl();
    // SAFETY: this test's GL context is current on this thread; the objects are its own.
    unsafe { g.delete_buffer(host) };
}

fn gl_scene_with(config: SceneConfig, f: impl FnOnce(&mut GlComputeSelector)) -> Scene {
    // SAFETY: a context is current on this thread (made by the caller); the loader serves it.
    let gl = unsafe { Gl::load(&gl_loader) }.expect("GL loads");
    let mut sel = GlComputeSelector::new(gl).expect("GL_COMPUTE on llvmpipe");
    f(&mut sel);
    Scene::with_selector(config, Box::new(sel)).unwrap()
}

/// A grid of nx x ny squares (two triangles each) over [0, 1]^2 at height z.
fn sheet(nx: u32, ny: u32, z: f32) -> TestMesh {
    let mut pos = Vec::new();
    for j in 0..=ny {
        for i in 0..=nx {
            pos.push([i as f32 / nx as f32, j as f32 / ny as f32, z]);
        }
    }
    let v = |i: u32, j: u32| j * (nx + 1) + i;
    let mut idx = Vec::new();
    for j in 0..ny {
        for i in 0..nx {
            idx.extend([v(i, j), v(i + 1, j), v(i + 1, j + 1)]);
            idx.extend([v(i, j), v(i + 1, j + 1), v(i, j + 1)]);
        }
    }
    TestMesh { pos, idx, k: 3 }
}

/// Meshes created with placeholder positions (a million times too large, or all zero) and
/// then bound to host buffers: the minimum epsilon comes from the boxes refitted on the
/// GPU, not from the placeholders (two sheets 0.05 apart at epsilon 0.001: no contact).
#[test]
fn bound_meshes_raise_epsilon_from_their_real_extent() {
    use glow::HasContext;
    let ctx = Ctx::new(Profile::Core);
    let g = ctx.glow();
    let (a, b) = (sheet(4, 4, 0.0), sheet(4, 4, 0.05));
    let config = SceneConfig {
        epsilon: 0.001,
        max_polygons_per_box: 0,
        ..SceneConfig::default()
    };
    for scale in [1e6f32, 0.0] {
        let mut s = gl_scene(config, Path::Whole);
        let mut hosts = Vec::new();
        let mut ids = Vec::new();
        for m in [&a, &b] {
            let fake: Vec<[f32; 3]> = m.pos.iter().map(|p| p.map(|x| x * scale)).collect();
            let id = s
                .create_mesh(Positions::from_points(&fake), &m.idx, 3)
                .unwrap();
            let host = host_buffer(&g, &m.pos);
            s.bind_gl_buffer(id, host.0.get(), 0, 0).unwrap();
            hosts.push(host);
            ids.push(id);
        }
        let n = s.query(ids[0]).unwrap().len();
        assert_eq!(n, 0, "placeholders x{scale}: {n} contacts");
        s.release_gl();
        for h in hosts {
            // SAFETY: this test's GL context is current on this thread; the objects are its own.
            unsafe { g.delete_buffer(h) };
        }
    }
}

/// One leaf pair asking 65536 x 65536 = 2^32 step-5 tests: refused with UNSUPPORTED (a
/// 32-bit product would wrap to 0 and answer "no contact").
#[test]
fn a_step_past_two_to_the_31_tests_is_refused() {
    let _ctx = Ctx::new(Profile::Core);
    let (a, b) = (sheet(128, 256, 0.0), sheet(128, 256, 0.0002));
    assert_eq!(a.polygons(), 65536);
    let config = SceneConfig {
        epsilon: 0.001,
        max_polygons_per_box: 65536,
        ..SceneConfig::default()
    };
    let mut s = gl_scene(config, Path::Whole);
    let ra = add(&mut s, &a);
    add(&mut s, &b);
    assert_eq!(s.mesh(ra).unwrap().leaf_count(), 1);
    let e = s.query(ra).unwrap_err();
    assert_eq!(e.kind, ErrorKind::Unsupported, "{}", e.message);
    s.release_gl();
}

/// Room the GL cannot give (a 2 GiB pair buffer) is refused with OUT_OF_MEMORY before any
/// allocation, and the next query starts from the usual room and answers in full.
#[test]
fn room_past_the_gl_limit_is_refused_then_recovered() {
    let _ctx = Ctx::new(Profile::Core);
    let (a, b) = (sheet(20, 20, 0.0), sheet(20, 20, 0.0002));
    let config = SceneConfig {
        epsilon: 0.001,
        max_polygons_per_box: 0,
        ..SceneConfig::default()
    };
    let mut cpu = Scene::new(config).unwrap();
    let ca = add(&mut cpu, &a);
    add(&mut cpu, &b);
    let want = cpu.query(ca).unwrap().len();
    assert!(want > 100);
    let mut s = gl_scene_with(config, |sel| sel.set_room(1 << 26, 1 << 20, 1 << 16));
    let ra = add(&mut s, &a);
    add(&mut s, &b);
    let e = s.query(ra).unwrap_err();
    assert_eq!(e.kind, ErrorKind::OutOfMemory, "{}", e.message);
    for _ in 0..2 {
        assert_eq!(s.query(ra).unwrap().len(), want);
        assert_eq!(s.stats().readbacks, 1);
    }
    s.release_gl();
}
