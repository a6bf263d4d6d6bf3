//! What 0.2 adds to the C API, through the C API only: growing structs (a 0.1
//! GlcolSceneDesc is accepted, `threads` defaulted), whole-scene queries, self-collision,
//! filters, threads, and contact geometry.

#![allow(clippy::missing_safety_doc)]

mod common;

use std::ffi::c_void;
use std::ptr::null_mut;

use common::backends::{last_error, ok, FfiScene, TestScene};
use common::{has_shared, sim_part, TestMesh};
use glcollide::ffi::*;
use GlcolStatus as S;

/// GlcolSceneDesc as glcollide 0.1's header declares it (no `threads`).
#[repr(C)]
#[derive(Clone, Copy)]
struct SceneDescV01 {
    struct_size: u32,
    backend: u32,
    get_proc_address: GlcolGetProcAddress,
    user_data: *mut c_void,
    epsilon: f32,
    max_polygons_per_box: u32,
}

/// A 0.1 struct followed by bytes it does not own (what a 0.1 caller may have after it).
#[repr(C)]
struct V01WithTail {
    d: SceneDescV01,
    tail: [u32; 4],
}

fn v01_desc() -> SceneDescV01 {
    SceneDescV01 {
        struct_size: std::mem::size_of::<SceneDescV01>() as u32,
        backend: GlcolBackend::Cpu as u32,
        get_proc_address: None,
        user_data: null_mut(),
        epsilon: 0.0,
        max_polygons_per_box: 0,
    }
}

fn square(z: f32, dx: f32) -> TestMesh {
    TestMesh {
        pos: vec![[dx, 0., z], [dx + 1., 0., z], [dx + 1., 1., z], [dx, 1., z]],
        idx: vec![0, 1, 2, 0, 2, 3],
        k: 3,
    }
}

fn wall(x: f32) -> TestMesh {
    TestMesh {
        pos: vec![[x, 0.5, -1.], [x, 0.5, 1.], [x, -0.5, 1.], [x, -0.5, -1.]],
        idx: vec![0, 1, 2, 0, 2, 3],
        k: 3,
    }
}

#[test]
fn a_v01_scene_desc_is_accepted_with_threads_defaulted() {
    let size = std::mem::size_of::<GlcolSceneDesc>();
    let old = std::mem::size_of::<SceneDescV01>();
    assert_eq!(old, std::mem::offset_of!(GlcolSceneDesc, threads));
    assert!(old < size);
    // The bytes after the 0.1 struct hold u32::MAX: were they read as `threads`, the call
    // would fail (at most 1024 threads). It succeeds, so they were not read.
    let d = V01WithTail {
        d: v01_desc(),
        tail: [u32::MAX; 4],
    };
    let mut s: *mut GlcolScene = null_mut();
    let st = unsafe { glcol_scene_create((&d.d as *const SceneDescV01).cast(), &mut s) };
    ok(st, "0.1-sized desc");
    let mut scene = FfiScene(s);
    let a = scene.add(&square(0., 0.));
    let b = scene.add(&wall(0.5));
    let hits = scene.query(a);
    assert!(
        !hits.is_empty() && hits.iter().all(|h| h.0 == b),
        "{hits:?}"
    );

    // The full size reads `threads`: u32::MAX is refused, naming the field.
    let mut full = unsafe { std::mem::zeroed::<GlcolSceneDesc>() };
    unsafe { glcol_scene_desc_init_sized(&mut full, std::mem::size_of::<GlcolSceneDesc>()) };
    assert_eq!(full.struct_size as usize, size);
    assert_eq!(full.threads, 0);
    full.threads = u32::MAX;
    let mut s2: *mut GlcolScene = null_mut();
    assert_eq!(
        unsafe { glcol_scene_create(&full, &mut s2) },
        S::InvalidArgument
    );
    assert!(last_error().contains("threads"), "{}", last_error());
    assert!(s2.is_null());
}

/// `glcol_scene_desc_init` (the symbol 0.1 programs call) writes 0.1's struct and nothing
/// past it; `glcol_scene_desc_init_sized` (what the header's macro calls) writes exactly
/// the size it is given, refusing other sizes without writing.
#[test]
fn the_desc_init_functions_write_no_byte_past_the_callers_struct() {
    let size = std::mem::size_of::<GlcolSceneDesc>();
    let old = std::mem::size_of::<SceneDescV01>();
    #[repr(C)]
    struct Room {
        d: GlcolSceneDesc,
        tail: [u8; 64],
    }
    // The bytes written, as (first byte not 0xA5 from the end: how far the call wrote,
    // the bytes before `threads`' end); the struct's tail padding is never read (it may be
    // left uninitialised by a typed copy).
    let fields_end = std::mem::offset_of!(GlcolSceneDesc, threads) + 4;
    let written = |f: &dyn Fn(*mut GlcolSceneDesc)| -> (Vec<u8>, usize) {
        let mut room: Room = unsafe { std::mem::zeroed() };
        let p = (&mut room as *mut Room).cast::<u8>();
        let total = std::mem::size_of::<Room>();
        unsafe { std::ptr::write_bytes(p, 0xA5, total) };
        f(&mut room.d);
        let head = unsafe { std::slice::from_raw_parts(p, fields_end) }.to_vec();
        let tail = unsafe { std::slice::from_raw_parts(p.add(size), total - size) };
        let end = if let Some(i) = tail.iter().rposition(|&b| b != 0xA5) {
            size + i + 1
        } else {
            head.iter().rposition(|&b| b != 0xA5).map_or(0, |i| i + 1)
        };
        (head, end)
    };
    // 0.1's symbol: 0.1's size, defaults, struct_size = 0.1's size.
    let (b, end) = written(&|d| unsafe { glcol_scene_desc_init(d) });
    assert!(
        end <= old,
        "glcol_scene_desc_init wrote {end} bytes, 0.1's struct has {old}"
    );
    let d = unsafe { std::ptr::read_unaligned(b.as_ptr().cast::<SceneDescV01>()) };
    assert_eq!(d.struct_size as usize, old);
    assert_eq!(d.backend, GlcolBackend::Auto as u32);
    assert!(d.get_proc_address.is_none() && d.user_data.is_null());
    assert_eq!((d.epsilon, d.max_polygons_per_box), (0.0, 0));
    // A scene made from it works, with threads defaulted.
    let mut s: *mut GlcolScene = null_mut();
    ok(
        unsafe { glcol_scene_create((&d as *const SceneDescV01).cast(), &mut s) },
        "scene from glcol_scene_desc_init",
    );
    drop(FfiScene(s));
    // The sized one, for both versions: exactly that many bytes.
    for n in [old, size] {
        let (b, end) = written(&|d| {
            ok(unsafe { glcol_scene_desc_init_sized(d, n) }, "init_sized");
        });
        assert!(end <= n, "init_sized({n}) wrote {end} bytes");
        assert_eq!(u32::from_ne_bytes(b[..4].try_into().unwrap()) as usize, n);
        if n == size {
            let threads = &b[fields_end - 4..];
            assert_eq!(u32::from_ne_bytes(threads.try_into().unwrap()), 0);
        }
    }
    // Other sizes: INVALID_ARGUMENT naming the valid sizes, nothing written; NULL refused.
    for bad in [0, 4, old - 4, old + 4, size + 8, usize::MAX] {
        let (_, end) = written(&|d| {
            assert_eq!(
                unsafe { glcol_scene_desc_init_sized(d, bad) },
                S::InvalidArgument
            );
        });
        assert_eq!(end, 0, "init_sized({bad}) wrote");
        let m = last_error();
        assert!(
            m.contains(&old.to_string()) && m.contains(&size.to_string()),
            "{m}"
        );
    }
    assert_eq!(
        unsafe { glcol_scene_desc_init_sized(null_mut(), size) },
        S::NullPointer
    );
    assert!(last_error().contains("desc"), "{}", last_error());
}

#[test]
fn a_size_between_the_versions_is_refused_naming_both() {
    let size = std::mem::size_of::<GlcolSceneDesc>();
    let old = std::mem::offset_of!(GlcolSceneDesc, threads);
    for bad in (old + 1..size).chain([old - 4, old - 8, size + 4, size + 8]) {
        let mut d = unsafe { std::mem::zeroed::<GlcolSceneDesc>() };
        unsafe { glcol_scene_desc_init_sized(&mut d, std::mem::size_of::<GlcolSceneDesc>()) };
        d.struct_size = bad as u32;
        let mut s: *mut GlcolScene = null_mut();
        assert_eq!(
            unsafe { glcol_scene_create(&d, &mut s) },
            S::InvalidArgument,
            "struct_size {bad}"
        );
        let m = last_error();
        assert!(
            m.contains("struct_size")
                && m.contains(&size.to_string())
                && m.contains(&old.to_string()),
            "{m}"
        );
        assert!(s.is_null());
    }
}

// ---------------------------------------------------------------------------------------
// Whole-scene queries, self-collision, filters, threads, geometry (C API only).

type P = (u32, u32, u32, u32);

fn scene_with(epsilon: f32, threads: u32) -> FfiScene {
    let mut d = unsafe { std::mem::zeroed::<GlcolSceneDesc>() };
    unsafe { glcol_scene_desc_init_sized(&mut d, std::mem::size_of::<GlcolSceneDesc>()) };
    d.backend = GlcolBackend::Cpu as u32;
    d.epsilon = epsilon;
    d.threads = threads;
    let mut s = null_mut();
    ok(
        unsafe { glcol_scene_create(&d, &mut s) },
        "glcol_scene_create",
    );
    FfiScene(s)
}

fn try_all(s: &FfiScene) -> (GlcolStatus, Vec<P>) {
    let mut p: *const GlcolPair = std::ptr::null();
    let mut n = usize::MAX;
    let st = unsafe { glcol_query_all(s.0, &mut p, &mut n) };
    if st != S::Ok {
        return (st, Vec::new());
    }
    if n == 0 {
        assert!(p.is_null());
        return (st, Vec::new());
    }
    let v = unsafe { std::slice::from_raw_parts(p, n) };
    (
        st,
        v.iter()
            .map(|q| (q.mesh_a, q.polygon_a, q.mesh_b, q.polygon_b))
            .collect(),
    )
}

fn all(s: &FfiScene) -> Vec<P> {
    let (st, v) = try_all(s);
    ok(st, "glcol_query_all");
    v
}

fn try_geometry(s: &FfiScene) -> (GlcolStatus, Vec<GlcolContactGeometry>) {
    let mut p: *const GlcolContactGeometry = std::ptr::null();
    let mut n = usize::MAX;
    let st = unsafe { glcol_query_geometry(s.0, &mut p, &mut n) };
    if st != S::Ok || n == 0 {
        return (st, Vec::new());
    }
    (st, unsafe { std::slice::from_raw_parts(p, n) }.to_vec())
}

fn funnel() -> Vec<TestMesh> {
    (0..4).map(|p| sim_part("cloth-funnel", 227, p)).collect()
}

/// Three teapots overlapping each other (moved by a fraction of their size) and a bunny.
fn overlapping_real_meshes() -> Vec<TestMesh> {
    let t = TestMesh::from_obj(&common::shared_mesh("teapot"));
    let (lo, hi) = common::bounds(&t.pos);
    let size = (0..3).map(|i| hi[i] - lo[i]).fold(0.0f32, f32::max);
    let moved = |d: [f32; 3]| TestMesh {
        pos: t
            .pos
            .iter()
            .map(|p| [p[0] + d[0] * size, p[1] + d[1] * size, p[2] + d[2] * size])
            .collect(),
        idx: t.idx.clone(),
        k: t.k,
    };
    vec![
        moved([0.0, 0.0, 0.0]),
        moved([0.2, 0.05, 0.0]),
        moved([0.1, 0.0, 0.25]),
        moved([3.0, 0.0, 0.0]),
    ]
}

/// query_all equals the union of glcol_query over every mesh (epsilon 0), normalised.
#[test]
fn query_all_is_the_union_of_the_per_mesh_queries() {
    let parts = overlapping_real_meshes();
    let mut s = scene_with(0.0, 0);
    let ids: Vec<u32> = parts.iter().map(|m| s.add(m)).collect();
    let got = all(&s);
    let mut want = Vec::new();
    for &r in &ids {
        for (o, rp, op) in s.query(r) {
            want.push(if r < o {
                (r, rp, o, op)
            } else {
                (o, op, r, rp)
            });
        }
    }
    want.sort_unstable();
    want.dedup();
    assert!(!got.is_empty());
    assert_eq!(got, want);
    // Sorted, each once, a < b.
    assert!(got.windows(2).all(|w| w[0] < w[1]));
    assert!(got.iter().all(|p| (p.0, p.1) < (p.2, p.3)));
}

/// A flat grid folded over itself: self pairs only when self-collision is on, never
/// between adjacent polygons that merely share their edge.
#[test]
fn self_collision_on_a_folded_grid() {
    let n = 8usize;
    let mut pos = Vec::new();
    for j in 0..=n {
        for i in 0..=n {
            // x in 0..n folds back at n/2 onto the lower half, 0.001 apart... then pushed
            // through: the upper half dips below the lower one at its far end.
            let x = i as f32;
            let (px, pz) = if i <= n / 2 {
                (x, 0.0)
            } else {
                let back = x - (n / 2) as f32;
                ((n / 2) as f32 - back, 0.3 - 0.2 * back)
            };
            pos.push([px, j as f32, pz]);
        }
    }
    let id = |i: usize, j: usize| (j * (n + 1) + i) as u32;
    let mut idx = Vec::new();
    for j in 0..n {
        for i in 0..n {
            idx.extend([id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)]);
        }
    }
    let m = TestMesh { pos, idx, k: 4 };
    let mut s = scene_with(0.0, 1);
    let a = s.add(&m);
    assert!(all(&s).is_empty(), "self-collision is off by default");
    ok(
        unsafe { glcol_mesh_set_self_collision(s.0, a, true) },
        "set_self_collision",
    );
    let got = all(&s);
    assert!(!got.is_empty());
    for p in &got {
        assert_eq!((p.0, p.2), (a, a));
        assert!(p.1 < p.3);
        // Quads sharing a vertex that only meet where joined are never reported: the flat
        // half has no pair of its own.
        let flat = |q: u32| (q as usize % n) < n / 2 - 1;
        assert!(!(flat(p.1) && flat(p.3)), "{p:?}");
    }
    ok(
        unsafe { glcol_mesh_set_self_collision(s.0, a, false) },
        "set_self_collision off",
    );
    assert!(all(&s).is_empty());
    assert_eq!(
        unsafe { glcol_mesh_set_self_collision(s.0, 0, true) },
        S::UnknownMesh
    );
    assert_eq!(
        unsafe { glcol_mesh_set_self_collision(null_mut(), a, true) },
        S::NullPointer
    );
}

#[test]
fn filters_choose_the_mesh_pairs() {
    let mut s = scene_with(0.0, 0);
    let a = s.add(&square(0., 0.));
    let b = s.add(&wall(0.5));
    let c = s.add(&wall(0.25));
    let meshes_of = |v: &[P]| {
        let mut m: Vec<(u32, u32)> = v.iter().map(|p| (p.0, p.2)).collect();
        m.sort_unstable();
        m.dedup();
        m
    };
    assert_eq!(meshes_of(&all(&s)), [(a, b), (a, c)]);
    // b in group 2, a accepts only group 1: a-b filtered out, both ways.
    ok(
        unsafe { glcol_mesh_set_filter(s.0, b, 2, u32::MAX) },
        "filter b",
    );
    ok(unsafe { glcol_mesh_set_filter(s.0, a, 1, 1) }, "filter a");
    assert_eq!(meshes_of(&all(&s)), [(a, c)]);
    assert!(s.query(a).iter().all(|h| h.0 == c));
    assert!(s.query(b).is_empty());
    ok(
        unsafe { glcol_mesh_set_filter(s.0, a, 1, u32::MAX) },
        "filter a back",
    );
    assert_eq!(meshes_of(&all(&s)), [(a, b), (a, c)]);
    assert_eq!(
        unsafe { glcol_mesh_set_filter(s.0, 0, 1, 1) },
        S::UnknownMesh
    );
    assert_eq!(
        unsafe { glcol_mesh_set_filter(null_mut(), a, 1, 1) },
        S::NullPointer
    );
}

#[test]
fn one_thread_and_one_per_core_answer_the_same() {
    if !has_shared("meshes/sim/cloth-funnel") {
        return;
    }
    let parts = funnel();
    let mut answers = Vec::new();
    for threads in [1, 0, 3] {
        let mut s = scene_with(0.001, threads);
        let ids: Vec<u32> = parts.iter().map(|m| s.add(m)).collect();
        let cloth = (0..4).max_by_key(|&p| parts[p].polygons()).unwrap();
        ok(
            unsafe { glcol_mesh_set_self_collision(s.0, ids[cloth], true) },
            "self",
        );
        // Ids differ per scene: compare by position in `ids`.
        let at = |m: u32| ids.iter().position(|&i| i == m).unwrap() as u32;
        let v: Vec<P> = all(&s)
            .into_iter()
            .map(|p| (at(p.0), p.1, at(p.2), p.3))
            .collect();
        answers.push(v);
    }
    assert!(!answers[0].is_empty());
    assert_eq!(answers[0], answers[1]);
    assert_eq!(answers[0], answers[2]);
}

/// The checks every geometry answer passes, against the pairs it describes.
fn check_geometry(s: &FfiScene, meshes: &[(u32, &TestMesh)], pairs: &[P]) -> usize {
    use glcollide::internals::tritri::triangles_intersect;
    let (st, g) = try_geometry(s);
    ok(st, "glcol_query_geometry");
    assert_eq!(g.len(), pairs.len());
    let mesh = |id: u32| meshes.iter().find(|m| m.0 == id).unwrap().1;
    let mut checked = 0;
    for (p, g) in pairs.iter().zip(&g) {
        let (ma, mb) = (mesh(p.0), mesh(p.2));
        let (ta, tb) = (ma.tris(p.1 as usize), mb.tris(p.3 as usize));
        let meets = ta
            .iter()
            .any(|t| tb.iter().any(|u| triangles_intersect(t, u)));
        let flagged = g.flags & GLCOL_CONTACT_INTERSECTING != 0;
        assert_eq!(meets, flagged, "{p:?} {g:?}");
        assert_eq!(
            g.flags & !(GLCOL_CONTACT_INTERSECTING | GLCOL_CONTACT_COPLANAR),
            0
        );
        if g.flags & GLCOL_CONTACT_COPLANAR != 0 {
            assert!(flagged);
        }
        let floats = g.point_a.iter().chain(&g.point_b).chain(&g.normal);
        assert!(floats.chain([&g.depth]).all(|x| x.is_finite()), "{g:?}");
        let n: f64 = g
            .normal
            .iter()
            .map(|&x| f64::from(x).powi(2))
            .sum::<f64>()
            .sqrt();
        assert!((n - 1.0).abs() < 1e-6, "|normal| = {n}: {g:?}");
        if flagged {
            assert!(g.depth >= 0.0, "{g:?}");
        } else {
            assert!(g.depth <= 0.0, "{g:?}");
        }
        // Depth 0 (touching): no translation to check.
        if flagged && g.flags & GLCOL_CONTACT_COPLANAR == 0 && g.depth > 0.0 {
            let d = f64::from(g.depth) * (1.0 + 1e-6);
            let t = g.normal.map(|x| f64::from(x) * d);
            let moved: Vec<[[f64; 3]; 3]> = ta
                .iter()
                .map(|tri| tri.map(|v| [v[0] + t[0], v[1] + t[1], v[2] + t[2]]))
                .collect();
            let still = moved
                .iter()
                .any(|t| tb.iter().any(|u| triangles_intersect(t, u)));
            assert!(!still, "{p:?}: moved by depth * normal, still meets: {g:?}");
            checked += 1;
        }
    }
    checked
}

#[test]
fn geometry_of_query_all_and_of_query() {
    if !has_shared("meshes/sim/cloth-funnel") {
        return;
    }
    let parts = funnel();
    let mut s = scene_with(0.001, 0);
    let ids: Vec<u32> = parts.iter().map(|m| s.add(m)).collect();
    let real = overlapping_real_meshes();
    let mut r = scene_with(0.0, 0);
    let rids: Vec<u32> = real.iter().map(|m| r.add(m)).collect();
    let rmeshes: Vec<(u32, &TestMesh)> = rids.iter().copied().zip(real.iter()).collect();
    let rpairs = all(&r);
    assert!(!rpairs.is_empty());
    assert!(
        check_geometry(&r, &rmeshes, &rpairs) > 0,
        "no penetrating pair checked"
    );
    let cloth = (0..4).max_by_key(|&p| parts[p].polygons()).unwrap();
    ok(
        unsafe { glcol_mesh_set_self_collision(s.0, ids[cloth], true) },
        "self",
    );
    let meshes: Vec<(u32, &TestMesh)> = ids.iter().copied().zip(parts.iter()).collect();
    let pairs = all(&s);
    assert!(!pairs.is_empty());
    check_geometry(&s, &meshes, &pairs);
    // The pairs array survives glcol_query_geometry (read it again through the pointer).
    for &r in &ids {
        let hits = s.query(r);
        let as_pairs: Vec<P> = hits.iter().map(|&(o, rp, op)| (r, rp, o, op)).collect();
        check_geometry(&s, &meshes, &as_pairs);
    }
    // Two crossing squares: one intersecting pair per triangle pair that meets.
    let mut t = scene_with(0.0, 1);
    let (qa, qb) = (square(0., 0.), wall(0.5));
    let a = t.add(&qa);
    let b = t.add(&qb);
    let pairs = all(&t);
    check_geometry(&t, &[(a, &qa), (b, &qb)], &pairs);
    let (_, g) = try_geometry(&t);
    assert!(g.iter().all(|g| g.flags == GLCOL_CONTACT_INTERSECTING));
}

#[test]
fn geometry_errors() {
    let mut s = scene_with(0.0, 1);
    let (st, _) = try_geometry(&s);
    assert_eq!(st, S::InvalidArgument, "before any query");
    assert!(!last_error().is_empty());
    let q = square(0., 0.);
    let a = s.add(&q);
    let b = s.add(&wall(0.5));
    let n = all(&s).len();
    let (st, g) = try_geometry(&s);
    ok(st, "after query_all");
    assert_eq!(g.len(), n);
    // NULL out-parameters.
    let mut cnt = 7usize;
    assert_eq!(
        unsafe { glcol_query_geometry(s.0, std::ptr::null_mut(), &mut cnt) },
        S::NullPointer
    );
    assert_eq!(cnt, 7);
    assert_eq!(
        unsafe { glcol_query_geometry(null_mut(), std::ptr::null_mut(), &mut cnt) },
        S::NullPointer
    );
    // After an update.
    s.update(a, 0, &q.pos);
    let (st, _) = try_geometry(&s);
    assert_eq!(st, S::InvalidArgument, "after an update");
    assert!(last_error().contains("query"), "{}", last_error());
    // After a successful glcol_query, then a failed one (unknown mesh).
    let hits = s.query(a);
    let (st, g) = try_geometry(&s);
    ok(st, "after glcol_query");
    assert_eq!(g.len(), hits.len());
    let (st, _) = s.try_query(0);
    assert_eq!(st, S::UnknownMesh);
    let (st, _) = try_geometry(&s);
    assert_eq!(st, S::InvalidArgument, "after a failed query");
    // A failed query_all (NULL out_count) too.
    all(&s);
    let mut p: *const GlcolPair = std::ptr::null();
    assert_eq!(
        unsafe { glcol_query_all(s.0, &mut p, std::ptr::null_mut()) },
        S::NullPointer
    );
    assert_eq!(try_geometry(&s).0, S::InvalidArgument);
    // Enable, destroy, filter each make it stale.
    for change in 0..3 {
        all(&s);
        ok(try_geometry(&s).0, "fresh");
        match change {
            0 => s.set_enabled(b, true),
            1 => ok(
                unsafe { glcol_mesh_set_filter(s.0, b, 1, u32::MAX) },
                "filter",
            ),
            _ => s.destroy(b),
        }
        assert_eq!(try_geometry(&s).0, S::InvalidArgument, "change {change}");
    }
}

// ---------------------------------------------------------------------------------------
// Rigid placement (C API only).

#[test]
fn set_transform_places_a_mesh_and_refuses_bad_input_changing_nothing() {
    let parts = overlapping_real_meshes();
    let t = &parts[0];
    // A quarter turn about z, doubled: world positions that are floats (checked), so a
    // second scene can be given them as vertices.
    let m: [f64; 12] = [0., -2., 0., 0., 2., 0., 0., 0., 0., 0., 2., 0.];
    let world: Vec<[f32; 3]> = t
        .pos
        .iter()
        .map(|p| {
            let w = [
                ((m[0] * p[0] as f64 + m[1] * p[1] as f64) + m[2] * p[2] as f64) + m[3],
                ((m[4] * p[0] as f64 + m[5] * p[1] as f64) + m[6] * p[2] as f64) + m[7],
                ((m[8] * p[0] as f64 + m[9] * p[1] as f64) + m[10] * p[2] as f64) + m[11],
            ];
            let f = w.map(|x| x as f32);
            assert!((0..3).all(|k| f[k] as f64 == w[k]), "not floats: {w:?}");
            f
        })
        .collect();
    let other = &parts[0];
    let mut s = scene_with(0.0, 0);
    let a = s.add(other);
    let b = s.add(t);
    ok(
        unsafe { glcol_mesh_set_transform(s.0, b, m.as_ptr()) },
        "glcol_mesh_set_transform",
    );
    let mut given = scene_with(0.0, 0);
    let a2 = given.add(other);
    let b2 = given.add(&TestMesh {
        pos: world.clone(),
        ..t.clone()
    });
    let strip = |h: Vec<(u32, u32, u32)>, other: u32| -> Vec<(u32, u32)> {
        h.into_iter()
            .inspect(|h| assert_eq!(h.0, other))
            .map(|h| (h.1, h.2))
            .collect()
    };
    let want = strip(given.query(a2), b2);
    assert!(!want.is_empty());
    assert_eq!(strip(s.query(a), b), want);
    let (st, g) = try_geometry(&s);
    ok(st, "geometry");
    assert!(!g.is_empty());
    let before_query = s.query(a);
    let before_all = all(&s);
    let unchanged = |s: &mut FfiScene| {
        assert_eq!(s.query(a), before_query);
        assert_eq!(all(s), before_all);
    };
    // Bad input: a NaN or infinite entry, overflowing world positions, an unknown mesh, a
    // NULL scene. Each is refused with a message and changes nothing.
    for (i, bad) in [(0, f64::NAN), (7, f64::INFINITY), (11, f64::NEG_INFINITY)] {
        let mut mm = m;
        mm[i] = bad;
        assert_eq!(
            unsafe { glcol_mesh_set_transform(s.0, b, mm.as_ptr()) },
            S::NonFinite
        );
        assert!(
            last_error().contains(&format!("m[{i}]")),
            "{}",
            last_error()
        );
        unchanged(&mut s);
    }
    let mut huge = m;
    huge[1] = -1e300;
    assert_eq!(
        unsafe { glcol_mesh_set_transform(s.0, b, huge.as_ptr()) },
        S::NonFinite
    );
    assert!(last_error().contains("float range"), "{}", last_error());
    unchanged(&mut s);
    assert_eq!(
        unsafe { glcol_mesh_set_transform(s.0, 0, m.as_ptr()) },
        S::UnknownMesh
    );
    assert_eq!(
        unsafe { glcol_mesh_set_transform(null_mut(), b, m.as_ptr()) },
        S::NullPointer
    );
    unchanged(&mut s);
    // An update whose world positions would overflow under m: refused, nothing changes.
    let mut far = t.pos.clone();
    far[3] = [0.0, 3e38, 0.0]; // twice that overflows
    assert_eq!(
        unsafe { glcol_mesh_update_positions(s.0, b, far.as_ptr().cast(), 0, far.len(), 0) },
        S::NonFinite
    );
    assert_eq!(
        unsafe { glcol_mesh_update_positions(s.0, b, far[3..].as_ptr().cast(), 3, 1, 0) },
        S::NonFinite
    );
    unchanged(&mut s);
    // A changed transform makes the last answer's geometry stale.
    ok(
        unsafe { glcol_mesh_set_transform(s.0, b, m.as_ptr()) },
        "the same matrix",
    );
    assert_eq!(try_geometry(&s).0, S::InvalidArgument);
    // NULL: the identity, the vertices as given.
    ok(
        unsafe { glcol_mesh_set_transform(s.0, b, std::ptr::null()) },
        "NULL m",
    );
    let mut local = scene_with(0.0, 0);
    let a3 = local.add(other);
    let b3 = local.add(t);
    let want_local = strip(local.query(a3), b3);
    let got_local = strip(s.query(a), b);
    assert_eq!(got_local, want_local);
    assert_ne!(got_local, want);
}
