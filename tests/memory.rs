//! Issue 6, part 5: creating and destroying thousands of meshes and scenes does not grow
//! memory. A counting global allocator tracks the bytes this thread holds (allocations
//! minus frees, per thread, so the test harness's other threads do not count); after a
//! warm-up cycle every further cycle must end at exactly the same number.
//!
//! The C examples run under valgrind in scripts/test.d/50-valgrind.sh for the C side.

mod common;

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;

use common::backends::{FfiScene, SafeScene, TestScene};
use common::TestMesh;
use glcollide::ffi::*;

struct Counting;

thread_local! {
    static NET: Cell<isize> = const { Cell::new(0) };
}

fn add(n: isize) {
    let _ = NET.try_with(|c| c.set(c.get() + n));
}

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, l: Layout) -> *mut u8 {
        let p = System.alloc(l);
        if !p.is_null() {
            add(l.size() as isize);
        }
        p
    }
    unsafe fn dealloc(&self, p: *mut u8, l: Layout) {
        System.dealloc(p, l);
        add(-(l.size() as isize));
    }
    unsafe fn alloc_zeroed(&self, l: Layout) -> *mut u8 {
        let p = System.alloc_zeroed(l);
        if !p.is_null() {
            add(l.size() as isize);
        }
        p
    }
    unsafe fn realloc(&self, p: *mut u8, l: Layout, new: usize) -> *mut u8 {
        let q = System.realloc(p, l, new);
        if !q.is_null() {
            add(new as isize - l.size() as isize);
        }
        q
    }
}

#[global_allocator]
static A: Counting = Counting;

fn held() -> isize {
    NET.with(|c| c.get())
}

/// A small grid of quads (or triangles), `n` x `n`, bumpy, at height `z`; a vertical one
/// (in the plane y = z instead) when `z` is above 0.1, so that flat and vertical grids cross.
fn grid(n: usize, k: usize, z: f32) -> TestMesh {
    let mut pos = Vec::new();
    for j in 0..=n {
        for i in 0..=n {
            let p = [
                i as f32 * 0.25,
                j as f32 * 0.25,
                z + ((i + j) % 3) as f32 * 0.1,
            ];
            pos.push(if z > 0.1 { [p[0], p[2], p[1]] } else { p });
        }
    }
    let id = |i: usize, j: usize| (j * (n + 1) + i) as u32;
    let mut idx = Vec::new();
    for j in 0..n {
        for i in 0..n {
            if k == 4 {
                idx.extend([id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)]);
            } else {
                idx.extend([id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
                idx.extend([id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
            }
        }
    }
    TestMesh { pos, idx, k }
}

/// One cycle through the C ABI: a scene, meshes made, moved, queried, rejected calls,
/// destroyed; then the scene destroyed.
fn ffi_cycle(meshes: &[TestMesh]) -> usize {
    let mut s = FfiScene::new(
        GlcolBackend::Cpu,
        if meshes.len().is_multiple_of(2) {
            0.0
        } else {
            0.01
        },
        8,
    );
    let ids: Vec<u32> = meshes.iter().map(|m| s.add(m)).collect();
    let mut contacts = 0;
    for (i, &id) in ids.iter().enumerate() {
        let moved: Vec<[f32; 3]> = meshes[i]
            .pos
            .iter()
            .map(|p| [p[0], p[1], p[2] + 0.05])
            .collect();
        s.update(id, 0, &moved);
        s.update(id, 1, &moved[1..5]);
        contacts += s.query(id).len();
        // Rejected calls (their messages are kept per thread: the same text every cycle).
        let mut bad = moved.clone();
        bad[2][1] = f32::NAN;
        let st =
            unsafe { glcol_mesh_update_positions(s.0, id, bad.as_ptr().cast(), 0, bad.len(), 0) };
        assert_eq!(st, GlcolStatus::NonFinite);
        let st =
            unsafe { glcol_mesh_update_positions(s.0, id, bad.as_ptr().cast(), 0, bad.len(), 8) };
        assert_eq!(st, GlcolStatus::InvalidArgument);
    }
    // Destroy half the meshes explicitly, leave the rest to glcol_scene_destroy.
    for &id in ids.iter().step_by(2) {
        s.destroy(id);
    }
    let st = unsafe { glcol_mesh_destroy(s.0, 0) };
    assert_eq!(st, GlcolStatus::UnknownMesh);
    contacts
}

#[test]
fn thousands_of_scenes_and_meshes_do_not_grow_memory() {
    let meshes = vec![
        grid(4, 3, 0.0),
        grid(3, 4, 0.3),
        grid(5, 3, 0.05),
        grid(2, 4, 0.2),
    ];
    // The counter counts.
    let before = held();
    let v = vec![0u8; 100];
    assert_eq!(held() - before, 100);
    drop(v);
    assert_eq!(held(), before);
    // Warm-up: thread-local buffers (the last-error message), lazily made statics.
    let want = ffi_cycle(&meshes);
    assert!(want > 0);
    ffi_cycle(&meshes[..3]);
    let base = held();
    for i in 0..2000 {
        let n = 2 + i % 3;
        ffi_cycle(&meshes[..n]);
    }
    // End on the same message as the warm-up's last cycle.
    ffi_cycle(&meshes[..3]);
    assert_eq!(
        held() - base,
        0,
        "bytes held after 2000 scenes vs after the first"
    );

    // Safe API: the same with scenes of the public Rust type.
    let base = held();
    for _ in 0..500 {
        let mut s = SafeScene::new(0.0, 4);
        let ids: Vec<u32> = meshes.iter().map(|m| s.add(m)).collect();
        assert!(!s.query(ids[0]).is_empty());
        for id in ids {
            s.destroy(id);
        }
    }
    assert_eq!(held() - base, 0);
}

#[test]
fn one_long_lived_scene_does_not_grow_with_mesh_churn() {
    let meshes = [grid(4, 3, 0.0), grid(3, 4, 0.3)];
    let mut s = FfiScene::new(GlcolBackend::Cpu, 0.0, 8);
    let keep = s.add(&meshes[0]);
    // Warm-up: the scene's query workspace reaches its size.
    for _ in 0..3 {
        let id = s.add(&meshes[1]);
        assert!(!s.query(keep).is_empty());
        s.destroy(id);
    }
    let base = held();
    for _ in 0..5000 {
        let id = s.add(&meshes[1]);
        assert!(!s.query(keep).is_empty());
        s.set_enabled(id, false);
        assert!(s.query(keep).is_empty());
        s.destroy(id);
    }
    assert!(s.query(keep).is_empty());
    assert_eq!(
        held() - base,
        0,
        "bytes held after 5000 meshes made and destroyed"
    );
}
