//! Growing structs, through the C API only: a program built against glcollide 0.1.0's
//! header passes its smaller `GlcolSceneDesc` (no `threads`), which is accepted with
//! `threads` defaulted and nothing past it read; the `_init` functions write no byte past
//! the caller's struct; a size no version has is refused.

#![allow(clippy::missing_safety_doc)]

mod common;

use std::ffi::c_void;
use std::ptr::null_mut;

use common::backends::{last_error, ok, FfiScene, TestScene};
use common::{square, wall};
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

/// GlcolMeshDesc as glcollide 0.1's header declares it (no `positions_f64`).
#[repr(C)]
#[derive(Clone, Copy)]
struct MeshDescV01 {
    struct_size: u32,
    positions: *const f32,
    vertex_count: usize,
    position_stride: usize,
    indices: *const u32,
    polygon_count: usize,
    vertices_per_polygon: u32,
}

/// A 0.1 `GlcolMeshDesc` is accepted as a float mesh and nothing past it is read (the bytes
/// after it would be a non-NULL `positions_f64`: both set, refused, were they read); the
/// `_init` functions write 0.1's struct (the exported symbol) or exactly the size given.
#[test]
fn a_v01_mesh_desc_is_accepted_and_the_inits_write_no_byte_past_it() {
    let size = std::mem::size_of::<GlcolMeshDesc>();
    let old = std::mem::size_of::<MeshDescV01>();
    assert_eq!(old, std::mem::offset_of!(GlcolMeshDesc, positions_f64));
    assert!(old < size);
    #[repr(C)]
    struct WithTail {
        d: MeshDescV01,
        tail: [usize; 2],
    }
    let sq = square(0., 0.);
    let mut scene = FfiScene::new(GlcolBackend::Cpu, 0.0, 0);
    let w = WithTail {
        d: MeshDescV01 {
            struct_size: old as u32,
            positions: sq.pos.as_ptr().cast(),
            vertex_count: sq.pos.len(),
            position_stride: 0,
            indices: sq.idx.as_ptr(),
            polygon_count: sq.polygons(),
            vertices_per_polygon: 3,
        },
        tail: [8, 8],
    };
    let mut a = 0;
    ok(
        unsafe { glcol_mesh_create(scene.0, (&w.d as *const MeshDescV01).cast(), &mut a) },
        "0.1-sized mesh desc",
    );
    let b = scene.add(&wall(0.5));
    assert!(scene.query(a).iter().all(|h| h.0 == b) && !scene.query(a).is_empty());
    // The full size reads positions_f64: both set is refused.
    let mut full = unsafe { std::mem::zeroed::<GlcolMeshDesc>() };
    ok(
        unsafe { glcol_mesh_desc_init_sized(&mut full, size) },
        "init_sized",
    );
    let p64 = [[0.0f64; 3]; 4];
    full.positions = sq.pos.as_ptr().cast();
    full.positions_f64 = p64.as_ptr().cast();
    full.vertex_count = 4;
    full.indices = sq.idx.as_ptr();
    full.polygon_count = 2;
    let mut c = 0;
    assert_eq!(
        unsafe { glcol_mesh_create(scene.0, &full, &mut c) },
        S::InvalidArgument
    );
    assert!(last_error().contains("positions_f64"), "{}", last_error());

    // What the init functions write: bytes not 0xA5 after the call.
    #[repr(C)]
    struct Room {
        d: GlcolMeshDesc,
        tail: [u8; 64],
    }
    let written = |f: &dyn Fn(*mut GlcolMeshDesc)| -> (Vec<u8>, usize) {
        let mut room: Room = unsafe { std::mem::zeroed() };
        let p = (&mut room as *mut Room).cast::<u8>();
        let total = std::mem::size_of::<Room>();
        unsafe { std::ptr::write_bytes(p, 0xA5, total) };
        f(&mut room.d);
        let all = unsafe { std::slice::from_raw_parts(p, total) }.to_vec();
        let end = all.iter().rposition(|&b| b != 0xA5).map_or(0, |i| i + 1);
        (all, end)
    };
    let (b01, end) = written(&|d| unsafe { glcol_mesh_desc_init(d) });
    assert!(
        end <= old,
        "glcol_mesh_desc_init wrote {end} bytes, 0.1's has {old}"
    );
    let d = unsafe { std::ptr::read_unaligned(b01.as_ptr().cast::<MeshDescV01>()) };
    assert_eq!(d.struct_size as usize, old);
    assert!(d.positions.is_null() && d.indices.is_null());
    assert_eq!(d.vertices_per_polygon, 3);
    for n in [old, size] {
        let (b, end) = written(&|d| ok(unsafe { glcol_mesh_desc_init_sized(d, n) }, "sized"));
        assert!(end <= n, "init_sized({n}) wrote {end} bytes");
        assert_eq!(u32::from_ne_bytes(b[..4].try_into().unwrap()) as usize, n);
        if n == size {
            assert!(
                b[old..size].iter().all(|&x| x == 0),
                "positions_f64 is NULL"
            );
        }
    }
    for bad in [0, 4, old - 4, old + 4, size + 8, usize::MAX] {
        let (_, end) = written(&|d| {
            assert_eq!(
                unsafe { glcol_mesh_desc_init_sized(d, bad) },
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
        unsafe { glcol_mesh_desc_init_sized(null_mut(), size) },
        S::NullPointer
    );
}
