//! What 0.2 adds to the C API, through the C API only: growing structs (a 0.1
//! GlcolSceneDesc is accepted, `threads` defaulted), whole-scene queries, self-collision,
//! filters, threads, and contact geometry.

#![allow(clippy::missing_safety_doc)]

mod common;

use std::ffi::c_void;
use std::ptr::null_mut;

use common::backends::{last_error, ok, FfiScene, TestScene};
use common::TestMesh;
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
    unsafe { glcol_scene_desc_init(&mut full) };
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

#[test]
fn a_size_between_the_versions_is_refused_naming_both() {
    let size = std::mem::size_of::<GlcolSceneDesc>();
    let old = std::mem::offset_of!(GlcolSceneDesc, threads);
    for bad in (old + 1..size).chain([old - 4, old - 8, size + 4, size + 8]) {
        let mut d = unsafe { std::mem::zeroed::<GlcolSceneDesc>() };
        unsafe { glcol_scene_desc_init(&mut d) };
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
