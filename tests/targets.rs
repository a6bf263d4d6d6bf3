//! Targets, the end of a continuous step (`Scene::set_target_positions(_f64)`,
//! `set_target_transform`, `clear_target`; `glcol_mesh_set_target_*`,
//! `glcol_mesh_clear_target`):
//!
//! - end positions as the contract says: vertices given move to their target positions
//!   (later ranges replacing earlier ones), the others keep their start positions, all
//!   under the target transform if set, else the current one, evaluated as
//!   `glcol_mesh_set_transform` says (compared bit for bit with `common::exact::world`);
//! - a target is not committed: no discrete answer changes and contact geometry stays
//!   valid;
//! - dropped by an update, a new transform and a clear (and by nothing else);
//! - every bad call rejected whole with a status and a message, nothing changed.

mod common;

use common::backends::{last_error, ok, FfiScene, TestScene};
use common::exact::{world, world_f64, M};
use common::{square, wall, TestMesh};
use glcollide::ffi::*;
use glcollide::{ErrorKind, MeshId, Positions, Scene, SceneConfig};
use GlcolStatus as S;

fn scene() -> Scene {
    Scene::new(SceneConfig {
        threads: 1,
        ..SceneConfig::default()
    })
    .unwrap()
}

/// A 4 x 4 grid of quads split into triangles, 25 vertices, at height `z`.
fn grid(z: f32) -> TestMesh {
    let mut pos = Vec::new();
    for j in 0..5 {
        for i in 0..5 {
            pos.push([i as f32 * 0.25, j as f32 * 0.25, z + (i * j) as f32 * 0.01]);
        }
    }
    let mut idx = Vec::new();
    for j in 0..4u32 {
        for i in 0..4u32 {
            let v = j * 5 + i;
            idx.extend([v, v + 1, v + 6, v, v + 6, v + 5]);
        }
    }
    TestMesh { pos, idx, k: 3 }
}

/// Every vertex's end world position, bit for bit.
fn ends(s: &Scene, id: MeshId) -> Vec<Option<[u64; 3]>> {
    let m = s.mesh(id).unwrap();
    (0..m.vertex_count())
        .map(|v| m.end_world_position(v).map(|p| p.map(f64::to_bits)))
        .collect()
}

const TURN: M = [0., -1., 0., 0.1, 1., 0., 0., 0.2, 0., 0., 1., 0.3];
const SHIFT: M = [1., 0., 0., 0.5, 0., 1., 0., 0., 0., 0., 1., -0.75];

#[test]
fn end_positions_are_the_targets_under_the_end_transform() {
    let g = grid(0.0);
    let mut s = scene();
    let id = common::add(&mut s, &g);
    let start: Vec<[f64; 3]> = g.pos.iter().map(|p| p.map(f64::from)).collect();
    let m = s.mesh(id).unwrap();
    assert!(!m.has_target());
    assert_eq!(
        m.end_world_position(7),
        Some(start[7]),
        "no target: stands still"
    );
    // A range, then an overlapping one.
    let up: Vec<[f32; 3]> = g.pos[3..9]
        .iter()
        .map(|p| [p[0], p[1], p[2] + 1.0])
        .collect();
    s.set_target_positions(id, 3, Positions::from_points(&up))
        .unwrap();
    let down: Vec<[f32; 3]> = g.pos[8..11].iter().map(|p| [p[0], p[1], -2.0]).collect();
    s.set_target_positions(id, 8, Positions::from_points(&down))
        .unwrap();
    let mut want: Vec<[f32; 3]> = g.pos.clone();
    want[3..9].copy_from_slice(&up);
    want[8..11].copy_from_slice(&down);
    let m = s.mesh(id).unwrap();
    assert!(m.has_target() && m.target_transform().is_none());
    assert_eq!(m.target_vertex_count(), 8);
    for (v, w) in want.iter().enumerate() {
        assert_eq!(
            m.end_world_position(v),
            Some(w.map(f64::from)),
            "vertex {v}"
        );
        assert_eq!(m.world_position(v), Some(start[v]), "the start stays");
    }
    // Under the current transform, then under a target transform.
    s.set_transform(id, Some(&TURN)).unwrap();
    assert!(
        !s.mesh(id).unwrap().has_target(),
        "a transform drops the target"
    );
    s.set_target_positions(id, 3, Positions::from_points(&up))
        .unwrap();
    s.set_target_positions(id, 8, Positions::from_points(&down))
        .unwrap();
    let m = s.mesh(id).unwrap();
    for (v, w) in want.iter().enumerate() {
        assert_eq!(m.end_world_position(v), Some(world(&TURN, w)), "vertex {v}");
        assert_eq!(m.world_position(v), Some(world(&TURN, &g.pos[v])));
    }
    s.set_target_transform(id, &SHIFT).unwrap();
    let m = s.mesh(id).unwrap();
    assert_eq!(m.target_transform(), Some(&SHIFT));
    for (v, w) in want.iter().enumerate() {
        assert_eq!(
            m.end_world_position(v),
            Some(world(&SHIFT, w)),
            "vertex {v}"
        );
        assert_eq!(m.world_position(v), Some(world(&TURN, &g.pos[v])));
    }
    // A target transform alone: an instrument that only moves.
    s.clear_target(id).unwrap();
    s.set_target_transform(id, &SHIFT).unwrap();
    let m = s.mesh(id).unwrap();
    assert_eq!(m.target_vertex_count(), 0);
    for (v, p) in g.pos.iter().enumerate() {
        assert_eq!(m.end_world_position(v), Some(world(&SHIFT, p)));
    }
    // An f64 mesh: double targets, exactly.
    let d: Vec<[f64; 3]> = g
        .pos
        .iter()
        .map(|p| p.map(|x| f64::from(x) + 1e-12))
        .collect();
    let f = s
        .create_mesh(Positions::from_points_f64(&d), &g.idx, 3)
        .unwrap();
    let t = [[1.0 / 3.0, 2.0 / 3.0, 1e6 + 0.1]];
    s.set_target_positions_f64(f, 24, &t).unwrap();
    s.set_transform(f, Some(&TURN)).unwrap();
    assert!(!s.mesh(f).unwrap().has_target());
    s.set_target_positions_f64(f, 24, &t).unwrap();
    let m = s.mesh(f).unwrap();
    assert_eq!(m.end_world_position(24), Some(world_f64(&TURN, &t[0])));
    assert_eq!(m.end_world_position(23), Some(world_f64(&TURN, &d[23])));
    s.set_target_transform(f, &SHIFT).unwrap();
    let m = s.mesh(f).unwrap();
    assert_eq!(m.end_world_position(24), Some(world_f64(&SHIFT, &t[0])));
    assert_eq!(m.end_world_position(0), Some(world_f64(&SHIFT, &d[0])));
}

#[test]
fn a_target_changes_no_discrete_answer_and_keeps_geometry_valid() {
    let mut s = scene();
    let a = common::add(&mut s, &square(0.0, 0.0));
    let b = common::add(&mut s, &wall(0.5));
    let pairs = s.query_all().unwrap().to_vec();
    assert!(!pairs.is_empty());
    let geometry = format!("{:?}", s.contact_geometry().unwrap());
    let far = [[9.0f32, 9.0, 9.0]; 4];
    s.set_target_positions(b, 0, Positions::from_points(&far))
        .unwrap();
    s.set_target_transform(a, &SHIFT).unwrap();
    assert_eq!(
        format!("{:?}", s.contact_geometry().unwrap()),
        geometry,
        "a target does not invalidate the geometry"
    );
    assert_eq!(s.query_all().unwrap(), &pairs[..]);
    assert!(!s.query(a).unwrap().is_empty());
    // Other changes keep the target; an update, a transform and a clear drop it.
    s.set_enabled(b, false).unwrap();
    s.set_enabled(b, true).unwrap();
    s.set_filter(b, 1, u32::MAX).unwrap();
    s.set_self_collision(b, true).unwrap();
    assert!(s.mesh(b).unwrap().has_target());
    let e = s
        .update_positions(b, 3, Positions::from_points(&far))
        .unwrap_err();
    assert_eq!(e.kind, ErrorKind::InvalidArgument);
    assert!(
        s.mesh(b).unwrap().has_target(),
        "a failed update changes nothing"
    );
    s.update_positions(b, 0, Positions::from_points(&wall(0.5).pos))
        .unwrap();
    assert!(!s.mesh(b).unwrap().has_target(), "an update drops it");
    s.set_transform(a, None).unwrap();
    assert!(
        !s.mesh(a).unwrap().has_target(),
        "a transform (the identity too) drops it"
    );
    s.set_target_transform(a, &SHIFT).unwrap();
    s.clear_target(a).unwrap();
    assert!(!s.mesh(a).unwrap().has_target());
    s.clear_target(a).unwrap();
}

/// Every bad call, through the Rust API: an error of the right kind naming the fault, and
/// nothing changed (every vertex's end position, whether there is a target).
#[test]
fn bad_target_calls_change_nothing() {
    let g = grid(0.0);
    let mut s = scene();
    let f = common::add(&mut s, &g);
    let d: Vec<[f64; 3]> = g.pos.iter().map(|p| p.map(f64::from)).collect();
    let id64 = s
        .create_mesh(Positions::from_points_f64(&d), &g.idx, 3)
        .unwrap();
    s.set_target_positions(f, 2, Positions::from_points(&[[0.5, 0.5, 4.0]]))
        .unwrap();
    let before = (ends(&s, f), ends(&s, id64));
    let check = |s: &mut Scene, r: glcollide::Result<()>, kind: ErrorKind, needle: &str| {
        let e = r.unwrap_err();
        assert_eq!(e.kind, kind, "{}", e.message);
        assert!(
            e.message.contains(needle),
            "\"{}\" lacks \"{needle}\"",
            e.message
        );
        assert_eq!((ends(s, f), ends(s, id64)), before);
        assert!(s.mesh(f).unwrap().has_target() && !s.mesh(id64).unwrap().has_target());
    };
    let p1 = [[0.0f32; 3]; 2];
    let r = s.set_target_positions(f, 24, Positions::from_points(&p1));
    check(&mut s, r, ErrorKind::InvalidArgument, "runs past");
    let r = s.set_target_positions(f, usize::MAX, Positions::from_points(&p1));
    check(&mut s, r, ErrorKind::InvalidArgument, "runs past");
    let r = s.set_target_positions(f, 0, Positions::from_points(&[[0.0, f32::NAN, 0.0]]));
    check(&mut s, r, ErrorKind::NonFinite, "vertex 0");
    let r = s.set_target_positions(
        f,
        5,
        Positions::from_points(&[[0.0; 3], [f32::INFINITY; 3]]),
    );
    check(&mut s, r, ErrorKind::NonFinite, "vertex 6");
    let r = s.set_target_positions_f64(f, 0, &[[0.0; 3]]);
    check(&mut s, r, ErrorKind::InvalidArgument, "float mesh");
    let r = s.set_target_positions(id64, 0, Positions::from_points(&[[0.0; 3]]));
    check(&mut s, r, ErrorKind::InvalidArgument, "f64 mesh");
    let r = s.set_target_positions_f64(id64, 1, &[[0.0; 3], [4e38, 0.0, 0.0]]);
    check(&mut s, r, ErrorKind::NonFinite, "float range");
    let r = s.set_target_positions_f64(id64, 1, &[[f64::NAN; 3]]);
    check(&mut s, r, ErrorKind::NonFinite, "vertex 1");
    let r = s.set_target_positions(0, 0, Positions::from_points(&[[0.0; 3]]));
    check(&mut s, r, ErrorKind::UnknownMesh, "mesh id 0");
    let mut bad = SHIFT;
    bad[6] = f64::NAN;
    let r = s.set_target_transform(f, &bad);
    check(&mut s, r, ErrorKind::NonFinite, "m[6]");
    let huge: M = [1e38, 0., 0., 0., 0., 1e38, 0., 0., 0., 0., 1e38, 0.];
    let r = s.set_target_transform(f, &huge);
    check(&mut s, r, ErrorKind::NonFinite, "float range");
    let r = s.set_target_transform(0, &SHIFT);
    check(&mut s, r, ErrorKind::UnknownMesh, "mesh id 0");
    let r = s.clear_target(0);
    check(&mut s, r, ErrorKind::UnknownMesh, "mesh id 0");
    // Under a transform: target positions whose end world positions could overflow.
    s.set_transform(
        id64,
        Some(&[1e30, 0., 0., 0., 0., 1e30, 0., 0., 0., 0., 1e30, 0.]),
    )
    .unwrap();
    let before_placed = ends(&s, id64);
    let e = s
        .set_target_positions_f64(id64, 0, &[[1e9, 0.0, 0.0]])
        .unwrap_err();
    assert_eq!(e.kind, ErrorKind::NonFinite, "{}", e.message);
    assert!(e.message.contains("float range"), "{}", e.message);
    assert_eq!(ends(&s, id64), before_placed);
    assert!(!s.mesh(id64).unwrap().has_target());
    s.set_target_positions_f64(id64, 0, &[[1.0, 0.0, 0.0]])
        .unwrap();
}

/// The C calls: every status with its message; the scene's answer unchanged.
#[test]
fn bad_target_calls_through_the_c_api() {
    let mut s = FfiScene::new(GlcolBackend::Cpu, 0.0, 0);
    let a = s.add(&square(0.0, 0.0));
    let b = s.add(&wall(0.5));
    let d: Vec<[f64; 3]> = grid(0.5).pos.iter().map(|p| p.map(f64::from)).collect();
    let idx = grid(0.5).idx;
    let mut desc = unsafe { std::mem::zeroed::<GlcolMeshDesc>() };
    ok(
        unsafe { glcol_mesh_desc_init_sized(&mut desc, std::mem::size_of::<GlcolMeshDesc>()) },
        "init",
    );
    desc.positions_f64 = d.as_ptr().cast();
    desc.vertex_count = d.len();
    desc.indices = idx.as_ptr();
    desc.polygon_count = idx.len() / 3;
    let mut c = 0;
    ok(unsafe { glcol_mesh_create(s.0, &desc, &mut c) }, "f64 mesh");
    let before = (s.query(a), s.query(c));
    let check = |s: &mut FfiScene, what: &str, st: GlcolStatus, want: GlcolStatus, needle: &str| {
        let msg = last_error();
        assert_eq!(st, want, "{what}: {msg}");
        assert!(msg.contains(needle), "{what}: \"{msg}\" lacks \"{needle}\"");
        assert_eq!((s.query(a), s.query(c)), before, "{what}");
    };
    let p = [[0.0f32; 3]; 2];
    let q = [[0.0f64; 3]; 2];
    let (pf, pd) = (p.as_ptr().cast::<f32>(), q.as_ptr().cast::<f64>());
    let st = unsafe { glcol_mesh_set_target_positions(s.0, b, pf, 0, 2, 0) };
    ok(st, "a good call");
    let st = unsafe { glcol_mesh_set_target_positions(std::ptr::null_mut(), b, pf, 0, 2, 0) };
    check(&mut s, "NULL scene", st, S::NullPointer, "scene");
    let st = unsafe { glcol_mesh_set_target_positions(s.0, b, std::ptr::null(), 0, 2, 0) };
    check(&mut s, "NULL positions", st, S::NullPointer, "positions");
    let st = unsafe { glcol_mesh_set_target_positions(s.0, 0, pf, 0, 2, 0) };
    check(&mut s, "unknown mesh", st, S::UnknownMesh, "mesh id 0");
    let st = unsafe { glcol_mesh_set_target_positions(s.0, b, pf, 3, 2, 0) };
    check(&mut s, "past the end", st, S::InvalidArgument, "runs past");
    let st = unsafe { glcol_mesh_set_target_positions(s.0, b, pf, 0, 0, 0) };
    check(
        &mut s,
        "zero count",
        st,
        S::InvalidArgument,
        "vertex_count is 0",
    );
    let st = unsafe { glcol_mesh_set_target_positions(s.0, b, pf, 0, 1, 8) };
    check(&mut s, "stride", st, S::InvalidArgument, "position_stride");
    let nan = [[0.0, 0.0, f32::NAN]];
    let st = unsafe { glcol_mesh_set_target_positions(s.0, b, nan.as_ptr().cast(), 1, 1, 0) };
    check(&mut s, "NaN", st, S::NonFinite, "vertex 1");
    let st = unsafe { glcol_mesh_set_target_positions(s.0, c, pf, 0, 1, 0) };
    check(
        &mut s,
        "float call, f64 mesh",
        st,
        S::InvalidArgument,
        "_f64",
    );
    let st = unsafe { glcol_mesh_set_target_positions_f64(s.0, b, pd, 0, 1, 0) };
    check(
        &mut s,
        "f64 call, float mesh",
        st,
        S::InvalidArgument,
        "float mesh",
    );
    let big = [[0.0, -3.5e38, 0.0]];
    let st = unsafe { glcol_mesh_set_target_positions_f64(s.0, c, big.as_ptr().cast(), 0, 1, 0) };
    check(
        &mut s,
        "beyond the float range",
        st,
        S::NonFinite,
        "float range",
    );
    let st = unsafe { glcol_mesh_set_target_positions_f64(s.0, c, pd, 0, 1, 16) };
    check(
        &mut s,
        "f64 stride",
        st,
        S::InvalidArgument,
        "position_stride",
    );
    let st = unsafe { glcol_mesh_set_target_positions_f64(s.0, c, pd, 0, 2, 0) };
    ok(st, "a good f64 call");
    let st = unsafe { glcol_mesh_set_target_transform(s.0, c, std::ptr::null()) };
    check(&mut s, "NULL m", st, S::NullPointer, "m");
    let mut bad = SHIFT;
    bad[11] = f64::INFINITY;
    let st = unsafe { glcol_mesh_set_target_transform(s.0, c, bad.as_ptr()) };
    check(&mut s, "infinite m", st, S::NonFinite, "m[11]");
    let huge: M = [1e39, 0., 0., 0., 0., 1., 0., 0., 0., 0., 1., 0.];
    let st = unsafe { glcol_mesh_set_target_transform(s.0, c, huge.as_ptr()) };
    check(&mut s, "overflowing m", st, S::NonFinite, "float range");
    let st = unsafe { glcol_mesh_set_target_transform(s.0, 0, SHIFT.as_ptr()) };
    check(&mut s, "unknown mesh", st, S::UnknownMesh, "mesh id 0");
    ok(
        unsafe { glcol_mesh_set_target_transform(s.0, c, SHIFT.as_ptr()) },
        "a good transform",
    );
    let st = unsafe { glcol_mesh_clear_target(std::ptr::null_mut(), c) };
    check(&mut s, "NULL scene", st, S::NullPointer, "scene");
    let st = unsafe { glcol_mesh_clear_target(s.0, 0) };
    check(&mut s, "unknown mesh", st, S::UnknownMesh, "mesh id 0");
    ok(unsafe { glcol_mesh_clear_target(s.0, c) }, "clear");
    ok(unsafe { glcol_mesh_clear_target(s.0, c) }, "clear again");
}
