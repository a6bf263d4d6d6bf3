//! What the header promises in words, held against what the library does, so that a gap
//! between the two fails here. Both gaps below were found by a simulator written from the
//! README and the header alone (issue 26): the header's list of changes after which
//! `glcol_query_geometry` refuses left out `glcol_mesh_set_transform`, and nothing said that
//! a band pair of `glcol_query_all` counts either polygon's viewing volume.
mod common;

use std::collections::BTreeSet;
use std::ptr::null;

use common::backends::gl_support::{add_mesh, host_buffer, last_error, ok, scene, Ctx, Profile};
use glcollide::ffi::*;

fn header() -> String {
    let p = concat!(env!("CARGO_MANIFEST_DIR"), "/include/glcollide.h");
    std::fs::read_to_string(p).expect("include/glcollide.h")
}

/// Each function the header declares: (name, its declaration's first line, its doc comment).
fn declarations(h: &str) -> Vec<(String, String, String)> {
    let lines: Vec<&str> = h.lines().collect();
    let mut out = Vec::new();
    for (i, l) in lines.iter().enumerate() {
        let is_decl = l.contains("glcol_")
            && l.contains('(')
            && !l.starts_with("//")
            && !l.starts_with(' ')
            && !l.starts_with('#')
            && !l.starts_with("typedef");
        if !is_decl {
            continue;
        }
        let name = l
            .split('(')
            .next()
            .unwrap()
            .split_whitespace()
            .last()
            .unwrap();
        let name = name.trim_start_matches('*').to_string();
        let mut doc = Vec::new();
        let mut j = i;
        while j > 0 && lines[j - 1].starts_with("//") {
            j -= 1;
            doc.push(lines[j].trim_start_matches('/').trim());
        }
        doc.reverse();
        out.push((name, l.to_string(), doc.join(" ")));
    }
    out
}

/// A scene (AUTO in a GL context: the CPU on llvmpipe, which can bind host buffers) with two
/// crossing triangles; a successful `glcol_query_all` and `glcol_query_geometry` done.
fn crossing_scene() -> (*mut GlcolScene, GlcolMeshId, GlcolMeshId) {
    let s = scene(GlcolBackend::Auto, 0.0, 0);
    let a = add_mesh(
        s,
        &[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
        &[0, 1, 2],
        3,
    );
    let b = add_mesh(
        s,
        &[[0.2, 0.2, -0.5], [0.2, 0.2, 0.5], [0.8, 0.8, 0.0]],
        &[0, 1, 2],
        3,
    );
    let (mut pairs, mut n) = (null(), 0);
    // SAFETY: `s` is a live scene; the out-pointers are locals.
    ok(unsafe { glcol_query_all(s, &mut pairs, &mut n) });
    assert_eq!(n, 1);
    assert_eq!(geometry(s), GlcolStatus::Ok);
    (s, a, b)
}

fn geometry(s: *mut GlcolScene) -> GlcolStatus {
    let (mut g, mut n) = (null(), 0);
    // SAFETY: `s` is a live scene; the out-pointers are locals.
    unsafe { glcol_query_geometry(s, &mut g, &mut n) }
}

/// Every call the header lets change a scene (a non-const scene, not a query, not destroy)
/// is named in `glcol_query_geometry`'s list of changes after which it refuses, and does make
/// it refuse (INVALID_ARGUMENT) when it succeeds; except the target calls, which are no
/// change of the current state: the header names them as such, and the geometry stays
/// available after each.
#[test]
fn geometry_refuses_after_every_change_the_header_lists() {
    let decls = declarations(&header());
    let changes: BTreeSet<String> = decls
        .iter()
        .filter(|(name, decl, _)| {
            decl.contains("(struct GlcolScene *scene")
                && !name.starts_with("glcol_query")
                && name != "glcol_scene_destroy"
        })
        .map(|(name, _, _)| name.clone())
        .collect();
    // The f64 calls need an f64 mesh made before the query: checked at the end.
    let f64_calls = [
        "glcol_mesh_update_positions_f64",
        "glcol_mesh_set_target_positions_f64",
    ];
    for name in f64_calls {
        assert!(changes.contains(name), "{name} declared");
    }
    let (targets, changes): (BTreeSet<String>, BTreeSet<String>) = changes
        .into_iter()
        .filter(|n| !f64_calls.contains(&n.as_str()))
        .partition(|n| n.contains("_target"));
    assert_eq!(targets.len(), 3, "{targets:?}");
    let doc = &decls
        .iter()
        .find(|(name, _, _)| name == "glcol_query_geometry")
        .expect("glcol_query_geometry declared")
        .2;
    for name in &changes {
        assert!(
            doc.contains(name.as_str()),
            "glcol_query_geometry's header comment does not list {name} among the changes \
             after which it refuses"
        );
    }
    let _ctx = Ctx::new(Profile::Core);
    let g = _ctx.glow();
    // One successful call of each change, on mesh `b` of a fresh crossing scene.
    type Change = Box<dyn Fn(*mut GlcolScene, GlcolMeshId) -> GlcolStatus>;
    // SAFETY (every closure): `s` is a live scene of this test, the arrays are locals.
    let calls: Vec<(&str, Change)> = vec![
        (
            "glcol_mesh_create",
            Box::new(|s, _| unsafe {
                let p = [0.0f32, 0.0, 5.0, 1.0, 0.0, 5.0, 0.0, 1.0, 5.0];
                let idx = [0u32, 1, 2];
                let mut d = std::mem::zeroed::<GlcolMeshDesc>();
                glcol_mesh_desc_init_sized(&mut d, std::mem::size_of::<GlcolMeshDesc>());
                d.positions = p.as_ptr();
                d.vertex_count = 3;
                d.indices = idx.as_ptr();
                d.polygon_count = 1;
                let mut id = 0;
                glcol_mesh_create(s, &d, &mut id)
            }),
        ),
        (
            "glcol_mesh_update_positions",
            Box::new(|s, b| unsafe {
                let p = [0.2f32, 0.2, -0.4];
                glcol_mesh_update_positions(s, b, p.as_ptr(), 0, 1, 0)
            }),
        ),
        (
            "glcol_mesh_set_enabled",
            Box::new(|s, b| unsafe { glcol_mesh_set_enabled(s, b, true) }),
        ),
        (
            "glcol_mesh_destroy",
            Box::new(|s, b| unsafe { glcol_mesh_destroy(s, b) }),
        ),
        (
            "glcol_mesh_set_self_collision",
            Box::new(|s, b| unsafe { glcol_mesh_set_self_collision(s, b, true) }),
        ),
        (
            "glcol_mesh_set_filter",
            Box::new(|s, b| unsafe { glcol_mesh_set_filter(s, b, 1, u32::MAX) }),
        ),
        (
            "glcol_mesh_set_transform",
            Box::new(|s, b| unsafe {
                let m = [1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 1e-3];
                glcol_mesh_set_transform(s, b, m.as_ptr())
            }),
        ),
        (
            "glcol_mesh_bind_gl_buffer",
            Box::new(move |s, b| unsafe {
                let buf = host_buffer(&g, &[[0.2, 0.2, -0.5], [0.2, 0.2, 0.5], [0.8, 0.8, 0.0]]);
                glcol_mesh_bind_gl_buffer(s, b, buf.0.get(), 0, 0)
            }),
        ),
    ];
    let tested: BTreeSet<String> = calls.iter().map(|(n, _)| n.to_string()).collect();
    assert_eq!(
        tested, changes,
        "a call that changes the scene is declared in the header but not tested here (or the \
         other way round)"
    );
    for (name, call) in &calls {
        let (s, _a, b) = crossing_scene();
        assert_eq!(call(s, b), GlcolStatus::Ok, "{name}: {}", last_error());
        assert_eq!(geometry(s), GlcolStatus::InvalidArgument, "after {name}");
        // SAFETY: a live scene of this test; its context is current.
        unsafe { glcol_scene_destroy(s) };
    }
    // The target calls: named as no change, and the geometry stays available.
    let keep = doc
        .split("A target is no change of the current state")
        .nth(1)
        .expect("glcol_query_geometry's header comment says what a target is");
    // SAFETY (every closure): as above.
    let target_calls: Vec<(&str, Change)> = vec![
        (
            "glcol_mesh_set_target_positions",
            Box::new(|s, b| unsafe {
                let p = [0.2f32, 0.2, 4.0];
                glcol_mesh_set_target_positions(s, b, p.as_ptr(), 0, 1, 0)
            }),
        ),
        (
            "glcol_mesh_set_target_transform",
            Box::new(|s, b| unsafe {
                let m = [1.0, 0.0, 0.0, 9.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0];
                glcol_mesh_set_target_transform(s, b, m.as_ptr())
            }),
        ),
        (
            "glcol_mesh_clear_target",
            Box::new(|s, b| unsafe { glcol_mesh_clear_target(s, b) }),
        ),
    ];
    let tested: BTreeSet<String> = target_calls.iter().map(|(n, _)| n.to_string()).collect();
    assert_eq!(tested, targets);
    for (name, call) in &target_calls {
        assert!(keep.contains(name), "{name} is not named as no change");
        let (s, _a, b) = crossing_scene();
        assert_eq!(call(s, b), GlcolStatus::Ok, "{name}: {}", last_error());
        assert_eq!(geometry(s), GlcolStatus::Ok, "after {name}");
        // SAFETY: a live scene of this test; its context is current.
        unsafe { glcol_scene_destroy(s) };
    }
    // The f64 calls on an f64 mesh of a scene whose geometry is available.
    for name in f64_calls {
        assert!(doc.contains(name), "{name} is not named");
    }
    assert!(keep.contains(f64_calls[1]) && !keep.contains(f64_calls[0]));
    let (s, _a, _b) = crossing_scene();
    let p = [0.0f64, 0.0, 7.0, 1.0, 0.0, 7.0, 0.0, 1.0, 7.0];
    let idx = [0u32, 1, 2];
    // SAFETY: a live scene; locals.
    let c = unsafe {
        let mut d = std::mem::zeroed::<GlcolMeshDesc>();
        glcol_mesh_desc_init_sized(&mut d, std::mem::size_of::<GlcolMeshDesc>());
        d.positions_f64 = p.as_ptr();
        d.vertex_count = 3;
        d.indices = idx.as_ptr();
        d.polygon_count = 1;
        let mut id = 0;
        ok(glcol_mesh_create(s, &d, &mut id));
        id
    };
    let (mut pairs, mut n) = (null(), 0);
    // SAFETY: a live scene; locals.
    ok(unsafe { glcol_query_all(s, &mut pairs, &mut n) });
    assert_eq!(geometry(s), GlcolStatus::Ok);
    // SAFETY: a live scene; locals.
    ok(unsafe { glcol_mesh_set_target_positions_f64(s, c, p.as_ptr(), 0, 3, 0) });
    assert_eq!(
        geometry(s),
        GlcolStatus::Ok,
        "after glcol_mesh_set_target_positions_f64"
    );
    // And glcol_mesh_update_positions_f64 is a change.
    // SAFETY: a live scene; locals.
    ok(unsafe { glcol_mesh_update_positions_f64(s, c, p.as_ptr(), 0, 3, 0) });
    assert_eq!(geometry(s), GlcolStatus::InvalidArgument);
    // SAFETY: a live scene of this test; its context is current.
    unsafe { glcol_scene_destroy(s) };
}

/// At epsilon > 0 a pair of `glcol_query_all` is reported when either polygon meets the
/// other's viewing volume (the header says so): here only b's volume holds part of a, so
/// `glcol_query` with a as reference finds nothing, with b finds the pair, and
/// `glcol_query_all` reports it.
#[test]
fn band_pairs_count_either_viewing_volume() {
    let decls = declarations(&header());
    let doc = &decls
        .iter()
        .find(|(name, _, _)| name == "glcol_query_all")
        .expect("glcol_query_all declared")
        .2;
    assert!(
        doc.contains("EITHER polygon meets the OTHER's viewing volume"),
        "glcol_query_all's header comment does not say which viewing volumes count: {doc}"
    );
    let mut d = unsafe { std::mem::zeroed::<GlcolSceneDesc>() };
    // SAFETY: `d` is a local of the size given.
    ok(unsafe { glcol_scene_desc_init_sized(&mut d, std::mem::size_of::<GlcolSceneDesc>()) });
    d.backend = GlcolBackend::Cpu as u32;
    d.epsilon = 0.02;
    let mut s = std::ptr::null_mut();
    // SAFETY: `d` is initialised; `s` a local.
    ok(unsafe { glcol_scene_create(&d, &mut s) });
    // a: flat at z = 0, x >= 0. b: upright in the plane x = -0.001, beside a's edge x = 0:
    // b's volume (x in [-0.011, 0.009]) holds a strip of a; a's volume (over x >= 0) holds
    // nothing of b.
    let a = add_mesh(
        s,
        &[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
        &[0, 1, 2],
        3,
    );
    let b = add_mesh(
        s,
        &[[-0.001, 0.1, -0.5], [-0.001, 0.5, -0.5], [-0.001, 0.3, 0.5]],
        &[0, 1, 2],
        3,
    );
    let one = |r| {
        let (mut c, mut n) = (null(), 0);
        // SAFETY: a live scene; locals.
        ok(unsafe { glcol_query(s, r, &mut c, &mut n) });
        n
    };
    assert_eq!(one(a), 0, "b does not meet a's viewing volume");
    assert_eq!(one(b), 1, "a meets b's viewing volume");
    let (mut p, mut n) = (null(), 0);
    // SAFETY: a live scene; locals.
    ok(unsafe { glcol_query_all(s, &mut p, &mut n) });
    assert_eq!(n, 1, "glcol_query_all counts either polygon's volume");
    // SAFETY: a live scene.
    unsafe { glcol_scene_destroy(s) };
}
