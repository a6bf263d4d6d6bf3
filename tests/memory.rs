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

/// Bytes a mesh holds per polygon (its structure, counted by the allocator at creation),
/// and what a target adds: at most its positions in the mesh's precision (12 or 24 bytes a
/// vertex given) and a few dozen bytes; nothing without one; all of it back at a clear.
/// `cargo test --release --test memory -- --nocapture` prints the figures.
#[test]
fn a_target_costs_its_positions_and_no_target_costs_nothing() {
    use glcollide::{Positions, Scene, SceneConfig};
    let g = grid(200, 3, 0.0);
    let polys = g.idx.len() / 3;
    let nv = g.pos.len();
    let d: Vec<[f64; 3]> = g.pos.iter().map(|p| p.map(f64::from)).collect();
    let mut s = Scene::new(SceneConfig {
        threads: 1,
        ..SceneConfig::default()
    })
    .unwrap();
    for f64_mesh in [false, true] {
        let before = held();
        let id = if f64_mesh {
            s.create_mesh(Positions::from_points_f64(&d), &g.idx, 3)
        } else {
            s.create_mesh(Positions::from_points(&g.pos), &g.idx, 3)
        }
        .unwrap();
        let mesh = held() - before;
        let word = if f64_mesh { 24 } else { 12 };
        let target = |s: &mut Scene, first: usize, n: usize| {
            let at = held();
            if f64_mesh {
                s.set_target_positions_f64(id, first, &d[first..first + n])
            } else {
                s.set_target_positions(id, first, Positions::from_points(&g.pos[first..first + n]))
            }
            .unwrap();
            held() - at
        };
        let tenth = target(&mut s, nv / 2, nv / 10);
        s.clear_target(id).unwrap();
        let full = target(&mut s, 0, nv);
        // The continuous query's scratch, kept by the scene for the next step (the step's
        // positions and boxes; the answer is empty here).
        let at = held();
        assert!(s.query_continuous().unwrap().is_empty());
        let step = held() - at;
        let at = held();
        assert!(s.query_continuous().unwrap().is_empty());
        assert_eq!(held(), at, "the next step allocates nothing");
        let at = held();
        s.clear_target(id).unwrap();
        assert_eq!(held() - at, -full, "a clear gives every byte back");
        let transform = {
            let at = held();
            s.set_target_transform(id, &[1., 0., 0., 1., 0., 1., 0., 0., 0., 0., 1., 0.])
                .unwrap();
            held() - at
        };
        s.clear_target(id).unwrap();
        let kind = if f64_mesh { "f64" } else { "float" };
        eprintln!(
            "{kind} mesh, {polys} triangles, {nv} vertices: {:.1} bytes/polygon without a target \
             (mesh structure; the CPU box cache adds 28 at the first query); a full target \
             +{:.1} bytes/polygon, a tenth of the vertices +{:.1}, a target transform alone \
             +{transform} bytes; the continuous query's scratch +{:.1} bytes/polygon",
            mesh as f64 / polys as f64,
            full as f64 / polys as f64,
            tenth as f64 / polys as f64,
            step as f64 / polys as f64,
        );
        assert!(
            full as usize <= word * nv + 512,
            "{full} bytes for {nv} vertices"
        );
        assert!(tenth as usize <= word * (nv / 10) + 512);
        assert!(transform <= 256);
        s.destroy_mesh(id).unwrap();
    }
}
