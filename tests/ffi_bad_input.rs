//! Issue 6, part 3: bad input through the C ABI. Every malformed call gets its status and a
//! message naming the argument, leaves its out-parameters alone, and leaves the scene
//! exactly as it was: the same contacts for every mesh as before, and the same answer as
//! the exact oracle. What cannot be detected (dangling pointers, arrays shorter than their
//! counts) is not provoked here; the header says so.

mod common;

use std::ffi::{c_char, c_void, CStr, CString};
use std::ptr::{null, null_mut};

use common::backends::{last_error, ok, FfiScene, Hit, TestScene};
use common::{brute_force_exact, TestMesh};
use glcollide::ffi::*;
use GlcolStatus as S;

/// Two unit quads as triangle pairs crossing each other, and a quad mesh crossing both.
fn meshes() -> Vec<TestMesh> {
    vec![
        TestMesh {
            pos: vec![[0., 0., 0.], [1., 0., 0.], [1., 1., 0.], [0., 1., 0.]],
            idx: vec![0, 1, 2, 0, 2, 3],
            k: 3,
        },
        TestMesh {
            pos: vec![
                [0.5, 0.5, -1.],
                [0.5, 0.5, 1.],
                [0.5, -0.5, 1.],
                [0.5, -0.5, -1.],
            ],
            idx: vec![0, 1, 2, 0, 2, 3],
            k: 3,
        },
        TestMesh {
            pos: vec![
                [0.25, -1., -1.],
                [0.25, 2., -1.],
                [0.25, 2., 1.],
                [0.25, -1., 1.],
                [0.75, -1., 1.],
                [0.75, 2., 1.],
            ],
            idx: vec![0, 1, 2, 3, 3, 2, 5, 4],
            k: 4,
        },
    ]
}

/// A CPU scene with the three meshes, and what it answers.
struct Fixture {
    scene: FfiScene,
    ids: Vec<u32>,
    meshes: Vec<TestMesh>,
    before: Vec<Vec<Hit>>,
}

impl Fixture {
    fn new() -> Fixture {
        let mut scene = FfiScene::new(GlcolBackend::Cpu, 0.0, 0);
        let meshes = meshes();
        let ids: Vec<u32> = meshes.iter().map(|m| scene.add(m)).collect();
        let mut f = Fixture {
            scene,
            ids,
            meshes,
            before: Vec::new(),
        };
        f.before = f.answers();
        f.check_against_oracle();
        assert!(
            f.before.iter().all(|a| !a.is_empty()),
            "fixture meshes must collide"
        );
        f
    }

    fn s(&self) -> *mut GlcolScene {
        self.scene.0
    }

    fn answers(&mut self) -> Vec<Vec<Hit>> {
        let ids = self.ids.clone();
        ids.iter().map(|&id| self.scene.query(id)).collect()
    }

    /// Every query equals the oracle's answer for the meshes as created.
    fn check_against_oracle(&mut self) {
        for (i, &id) in self.ids.clone().iter().enumerate() {
            let got = self.scene.query(id);
            let mut want = Vec::new();
            for (j, &other) in self.ids.iter().enumerate() {
                if i != j {
                    want.extend(
                        brute_force_exact(&self.meshes[i], &self.meshes[j])
                            .into_iter()
                            .map(|(a, b)| (other, a, b)),
                    );
                }
            }
            want.sort_unstable();
            assert_eq!(got, want, "mesh {id} against the oracle");
        }
    }

    /// The call's status is `want`, the message names `needle`, and nothing changed.
    #[track_caller]
    fn expect(&mut self, what: &str, got: GlcolStatus, want: GlcolStatus, needle: &str) {
        let msg = last_error();
        assert_eq!(got, want, "{what}: message \"{msg}\"");
        assert!(
            msg.contains(needle),
            "{what}: message \"{msg}\" does not name \"{needle}\""
        );
        assert_eq!(self.answers(), self.before, "{what} changed the scene");
    }
}

fn mesh_desc(m: &TestMesh) -> GlcolMeshDesc {
    FfiScene::desc(m)
}

fn scene_desc() -> GlcolSceneDesc {
    let mut d = unsafe { std::mem::zeroed::<GlcolSceneDesc>() };
    unsafe { glcol_scene_desc_init_sized(&mut d, std::mem::size_of::<GlcolSceneDesc>()) };
    d
}

const SENTINEL_ID: u32 = 0xDEAD_BEEF;

#[test]
fn scene_creation_rejects_bad_descriptions() {
    let sentinel = 0x1234usize as *mut GlcolScene;
    let create = |d: *const GlcolSceneDesc| {
        let mut out = sentinel;
        let s = unsafe { glcol_scene_create(d, &mut out) };
        assert_eq!(out, sentinel, "a failed create wrote *out_scene");
        (s, last_error())
    };
    let d = scene_desc();
    let (s, m) = create(null());
    assert_eq!((s, m.contains("desc")), (S::NullPointer, true), "{m}");
    let s = unsafe { glcol_scene_create(&d, null_mut()) };
    assert_eq!(s, S::NullPointer);
    assert!(last_error().contains("out_scene"));

    let size = std::mem::size_of::<GlcolSceneDesc>() as u32;
    for bad in [0, 4, size - 4, size + 4, u32::MAX] {
        let mut d = scene_desc();
        d.struct_size = bad;
        let (s, m) = create(&d);
        assert_eq!(s, S::InvalidArgument, "struct_size {bad}");
        assert!(m.contains("struct_size"), "{m}");
    }
    for bad in [4u32, 7, 1000, u32::MAX] {
        let mut d = scene_desc();
        d.backend = bad;
        let (s, m) = create(&d);
        assert_eq!(s, S::InvalidArgument, "backend {bad}");
        assert!(m.contains("backend"), "{m}");
    }
    for bad in [-1.0f32, -0.0001, f32::NAN, f32::INFINITY, f32::NEG_INFINITY] {
        let mut d = scene_desc();
        d.epsilon = bad;
        let (s, m) = create(&d);
        assert_eq!(s, S::InvalidArgument, "epsilon {bad}");
        assert!(m.contains("epsilon"), "{m}");
    }
    // GL backends with no loader.
    for b in [GlcolBackend::GlSelect, GlcolBackend::GlCompute] {
        let mut d = scene_desc();
        d.backend = b as u32;
        let (s, m) = create(&d);
        assert_eq!(s, S::GlUnavailable, "{b:?} without a loader");
        assert!(m.contains("get_proc_address"), "{m}");
    }
}

unsafe extern "C" fn null_loader(_user: *mut c_void, _name: *const c_char) -> *mut c_void {
    null_mut()
}

/// A loader that finds nothing (no context current): a GL backend must refuse, not crash.
#[test]
fn gl_backend_with_a_loader_that_finds_nothing_fails_cleanly() {
    for b in [GlcolBackend::GlSelect, GlcolBackend::GlCompute] {
        let mut d = scene_desc();
        d.backend = b as u32;
        d.get_proc_address = Some(null_loader);
        let mut out = null_mut();
        let s = unsafe { glcol_scene_create(&d, &mut out) };
        assert!(
            s == S::GlUnavailable || s == S::Unsupported,
            "{b:?} with a loader that finds nothing: {s:?} {}",
            last_error()
        );
        assert!(out.is_null());
        assert!(!last_error().is_empty());
    }
}

/// The API's word for a loader that finds no entry point (no current context) is
/// GL_UNAVAILABLE.
#[test]
fn gl_backend_with_a_loader_that_finds_nothing_is_gl_unavailable() {
    for b in [GlcolBackend::GlSelect, GlcolBackend::GlCompute] {
        let mut d = scene_desc();
        d.backend = b as u32;
        d.get_proc_address = Some(null_loader);
        let mut out = null_mut();
        assert_eq!(
            unsafe { glcol_scene_create(&d, &mut out) },
            S::GlUnavailable
        );
    }
}

#[test]
fn mesh_creation_rejects_bad_descriptions_and_changes_nothing() {
    let mut f = Fixture::new();
    let m = f.meshes[0].clone();
    let good = mesh_desc(&m);
    let s = f.s();
    let mut id = SENTINEL_ID;
    macro_rules! create {
        ($what:expr, $desc:expr, $want:expr, $needle:expr) => {{
            let d: GlcolMeshDesc = $desc;
            let st = unsafe { glcol_mesh_create(s, &d, &mut id) };
            f.expect($what, st, $want, $needle);
            assert_eq!(id, SENTINEL_ID, "{}: a failed create wrote *out_id", $what);
        }};
    }
    // NULL pointers.
    let st = unsafe { glcol_mesh_create(null_mut(), &good, &mut id) };
    f.expect("NULL scene", st, S::NullPointer, "scene");
    let st = unsafe { glcol_mesh_create(s, null(), &mut id) };
    f.expect("NULL desc", st, S::NullPointer, "desc");
    let st = unsafe { glcol_mesh_create(s, &good, null_mut()) };
    f.expect("NULL out_id", st, S::NullPointer, "out_id");
    // Neither positions nor positions_f64 (0.3's struct): INVALID_ARGUMENT; 0.1's struct,
    // which has no positions_f64, keeps 0.1's NULL_POINTER.
    create!(
        "NULL positions",
        GlcolMeshDesc {
            positions: null(),
            ..good
        },
        S::InvalidArgument,
        "positions"
    );
    create!(
        "NULL positions in 0.1's struct",
        GlcolMeshDesc {
            struct_size: std::mem::offset_of!(GlcolMeshDesc, positions_f64) as u32,
            positions: null(),
            ..good
        },
        S::NullPointer,
        "positions"
    );
    create!(
        "NULL indices",
        GlcolMeshDesc {
            indices: null(),
            ..good
        },
        S::NullPointer,
        "indices"
    );
    // struct_size.
    let size = std::mem::size_of::<GlcolMeshDesc>() as u32;
    for bad in [0, 4, size - 16, size - 4, size + 8, u32::MAX] {
        create!(
            &format!("struct_size {bad}"),
            GlcolMeshDesc {
                struct_size: bad,
                ..good
            },
            S::InvalidArgument,
            "struct_size"
        );
    }
    // Zero counts.
    create!(
        "0 vertices",
        GlcolMeshDesc {
            vertex_count: 0,
            ..good
        },
        S::InvalidArgument,
        "vertex_count"
    );
    create!(
        "0 polygons",
        GlcolMeshDesc {
            polygon_count: 0,
            ..good
        },
        S::InvalidArgument,
        "polygon_count"
    );
    // vertices_per_polygon.
    for k in [0, 1, 2, 5, 6, 100, u32::MAX] {
        create!(
            &format!("vertices_per_polygon {k}"),
            GlcolMeshDesc {
                vertices_per_polygon: k,
                ..good
            },
            S::InvalidArgument,
            "vertices_per_polygon"
        );
    }
    // Strides below 12 or not a multiple of 4.
    for st in [1, 4, 8, 11, 13, 14, 15, 17, 18] {
        create!(
            &format!("stride {st}"),
            GlcolMeshDesc {
                position_stride: st,
                ..good
            },
            S::InvalidArgument,
            "stride"
        );
    }
    // Misaligned arrays.
    let raw: Vec<u8> = vec![0; 64];
    let odd = raw
        .as_ptr()
        .wrapping_add(if (raw.as_ptr() as usize).is_multiple_of(4) {
            2
        } else {
            1
        });
    create!(
        "misaligned positions",
        GlcolMeshDesc {
            positions: odd.cast(),
            ..good
        },
        S::InvalidArgument,
        "positions is not 4-byte aligned"
    );
    create!(
        "misaligned indices",
        GlcolMeshDesc {
            indices: odd.cast(),
            ..good
        },
        S::InvalidArgument,
        "indices is not 4-byte aligned"
    );
    // Huge counts: count * stride overflows, or more than the library can number.
    create!(
        "vertex_count * stride overflows",
        GlcolMeshDesc {
            vertex_count: usize::MAX / 4,
            position_stride: 64,
            ..good
        },
        S::InvalidArgument,
        "vertex_count"
    );
    create!(
        "vertex_count SIZE_MAX",
        GlcolMeshDesc {
            vertex_count: usize::MAX,
            ..good
        },
        S::InvalidArgument,
        "vertex_count"
    );
    create!(
        "vertex_count * stride past isize::MAX",
        GlcolMeshDesc {
            vertex_count: usize::MAX / 16,
            position_stride: 12,
            ..good
        },
        S::InvalidArgument,
        "vertex_count"
    );
    create!(
        "polygon_count SIZE_MAX / 2",
        GlcolMeshDesc {
            polygon_count: usize::MAX / 2,
            ..good
        },
        S::InvalidArgument,
        "polygon_count"
    );
    create!(
        "polygon_count * 4 overflows",
        GlcolMeshDesc {
            polygon_count: usize::MAX / 4 + 1,
            vertices_per_polygon: 4,
            ..good
        },
        S::InvalidArgument,
        "polygon_count"
    );
    create!(
        "vertex_count 2^33",
        GlcolMeshDesc {
            vertex_count: 1 << 33,
            ..good
        },
        S::InvalidArgument,
        "vertex_count"
    );
    create!(
        "polygon_count 2^33",
        GlcolMeshDesc {
            polygon_count: 1 << 33,
            ..good
        },
        S::InvalidArgument,
        "polygon_count"
    );
    // Indices out of range.
    for bad in [4u32, 5, 1000, u32::MAX] {
        let idx = [0, 1, 2, 0, 2, bad];
        create!(
            &format!("index {bad}"),
            GlcolMeshDesc {
                indices: idx.as_ptr(),
                ..good
            },
            S::IndexOutOfRange,
            &format!("vertex {bad}")
        );
    }
    // NaN and infinities, first and last vertex, every coordinate.
    for bad in [f32::NAN, f32::INFINITY, f32::NEG_INFINITY, -f32::NAN] {
        for at in [0usize, 5, 11] {
            let mut p = m.pos.clone();
            p[at / 3][at % 3] = bad;
            create!(
                &format!("{bad} at coordinate {at}"),
                GlcolMeshDesc {
                    positions: p.as_ptr().cast(),
                    ..good
                },
                S::NonFinite,
                &format!("vertex {}", at / 3)
            );
        }
    }
    // A NaN in the padding of a strided array is not a coordinate: accepted.
    let padded: Vec<[f32; 4]> = m.pos.iter().map(|p| [p[0], p[1], p[2], f32::NAN]).collect();
    let d = GlcolMeshDesc {
        positions: padded.as_ptr().cast(),
        position_stride: 16,
        ..good
    };
    let mut new_id = 0;
    ok(
        unsafe { glcol_mesh_create(s, &d, &mut new_id) },
        "padded positions",
    );
    // It collides like mesh 0 does, then goes away again.
    let first = f.ids[0];
    let b = f.scene.query(f.ids[1]);
    let via_new: Vec<(u32, u32)> = b
        .iter()
        .filter(|h| h.0 == new_id)
        .map(|h| (h.1, h.2))
        .collect();
    let via_old: Vec<(u32, u32)> = b
        .iter()
        .filter(|h| h.0 == first)
        .map(|h| (h.1, h.2))
        .collect();
    assert_eq!(via_new, via_old);
    f.scene.destroy(new_id);
    assert_eq!(f.answers(), f.before);
    f.check_against_oracle();
}

#[test]
fn updates_are_rejected_whole() {
    let mut f = Fixture::new();
    let s = f.s();
    let a = f.ids[0];
    let n = f.meshes[0].pos.len();
    // Moves that would end every contact if applied.
    let far: Vec<[f32; 3]> = f.meshes[0]
        .pos
        .iter()
        .map(|p| [p[0] + 10.0, p[1], p[2]])
        .collect();
    let fp = far.as_ptr().cast::<f32>();
    let up = |mesh: u32, p: *const f32, first: usize, count: usize, stride: usize| unsafe {
        glcol_mesh_update_positions(s, mesh, p, first, count, stride)
    };
    let st = unsafe { glcol_mesh_update_positions(null_mut(), a, fp, 0, n, 0) };
    f.expect("NULL scene", st, S::NullPointer, "scene");
    f.expect(
        "NULL positions",
        up(a, null(), 0, n, 0),
        S::NullPointer,
        "positions",
    );
    for id in [0, 999, u32::MAX] {
        f.expect(
            &format!("unknown id {id}"),
            up(id, fp, 0, n, 0),
            S::UnknownMesh,
            &id.to_string(),
        );
    }
    f.expect(
        "0 vertices",
        up(a, fp, 0, 0, 0),
        S::InvalidArgument,
        "vertex_count",
    );
    f.expect(
        "past the end",
        up(a, fp, 1, n, 0),
        S::InvalidArgument,
        "past",
    );
    f.expect(
        "first past the end",
        up(a, fp, n, 1, 0),
        S::InvalidArgument,
        "past",
    );
    f.expect(
        "first overflows",
        up(a, fp, usize::MAX, 2, 0),
        S::InvalidArgument,
        "past",
    );
    f.expect(
        "huge count",
        up(a, fp, 0, 1 << 40, 0),
        S::InvalidArgument,
        "past",
    );
    f.expect(
        "count * stride overflows",
        up(a, fp, 0, usize::MAX / 8, 64),
        S::InvalidArgument,
        "vertex_count",
    );
    for st in [1, 4, 8, 11, 13, 14] {
        f.expect(
            &format!("stride {st}"),
            up(a, fp, 0, n, st),
            S::InvalidArgument,
            "stride",
        );
    }
    let raw = [0u8; 64];
    let odd = raw
        .as_ptr()
        .wrapping_add(if (raw.as_ptr() as usize).is_multiple_of(4) {
            2
        } else {
            1
        });
    f.expect(
        "misaligned",
        up(a, odd.cast(), 0, 1, 0),
        S::InvalidArgument,
        "aligned",
    );
    for bad in [f32::NAN, f32::INFINITY, f32::NEG_INFINITY] {
        for v in 0..n {
            let mut p = far.clone();
            p[v][(v + 1) % 3] = bad;
            let pp = p.as_ptr().cast::<f32>();
            f.expect(
                &format!("{bad} at vertex {v}, full"),
                up(a, pp, 0, n, 0),
                S::NonFinite,
                &format!("vertex {v}"),
            );
            // A partial update that contains it, starting at vertex 1.
            if v >= 1 {
                let st = up(a, p[1..].as_ptr().cast(), 1, n - 1, 0);
                f.expect(
                    &format!("{bad} at vertex {v}, range"),
                    st,
                    S::NonFinite,
                    &format!("vertex {v}"),
                );
            }
        }
    }
    // A strided update whose NaN is in the padding: accepted, and it moves the mesh.
    let padded: Vec<[f32; 4]> = far.iter().map(|p| [p[0], p[1], p[2], f32::NAN]).collect();
    ok(up(a, padded.as_ptr().cast(), 0, n, 16), "padded update");
    assert!(f.scene.query(a).is_empty());
    let back: Vec<[f32; 4]> = f.meshes[0]
        .pos
        .iter()
        .map(|p| [p[0], p[1], p[2], 0.0])
        .collect();
    ok(up(a, back.as_ptr().cast(), 0, n, 16), "padded update back");
    assert_eq!(f.answers(), f.before);
    f.check_against_oracle();
}

#[test]
fn enable_destroy_query_bind_and_backend_reject_bad_calls() {
    let mut f = Fixture::new();
    let s = f.s();
    let a = f.ids[0];
    for id in [0u32, 999, u32::MAX] {
        let st = unsafe { glcol_mesh_set_enabled(s, id, false) };
        f.expect("set_enabled unknown", st, S::UnknownMesh, &id.to_string());
        let st = unsafe { glcol_mesh_destroy(s, id) };
        f.expect("destroy unknown", st, S::UnknownMesh, &id.to_string());
        let (mut p, mut n) = (0x10 as *const GlcolContact, 77usize);
        let st = unsafe { glcol_query(s, id, &mut p, &mut n) };
        assert_eq!(
            (p as usize, n),
            (0x10, 77),
            "a failed query wrote its outputs"
        );
        f.expect("query unknown", st, S::UnknownMesh, &id.to_string());
        let st = unsafe { glcol_mesh_bind_gl_buffer(s, id, 1, 0, 12) };
        f.expect("bind unknown", st, S::UnknownMesh, &id.to_string());
    }
    let st = unsafe { glcol_mesh_set_enabled(null_mut(), a, false) };
    f.expect("set_enabled NULL", st, S::NullPointer, "scene");
    let st = unsafe { glcol_mesh_destroy(null_mut(), a) };
    f.expect("destroy NULL", st, S::NullPointer, "scene");
    let (mut p, mut n) = (null(), 0usize);
    let st = unsafe { glcol_query(null_mut(), a, &mut p, &mut n) };
    f.expect("query NULL scene", st, S::NullPointer, "scene");
    let st = unsafe { glcol_query(s, a, null_mut(), &mut n) };
    f.expect(
        "query NULL out_contacts",
        st,
        S::NullPointer,
        "out_contacts",
    );
    let st = unsafe { glcol_query(s, a, &mut p, null_mut()) };
    f.expect("query NULL out_count", st, S::NullPointer, "out_count");
    let st = unsafe { glcol_mesh_bind_gl_buffer(null_mut(), a, 1, 0, 12) };
    f.expect("bind NULL", st, S::NullPointer, "scene");
    let st = unsafe { glcol_mesh_bind_gl_buffer(s, a, 1, 0, 12) };
    f.expect("bind on CPU", st, S::Unsupported, "GL_COMPUTE");
    let mut b = 99u32;
    let st = unsafe { glcol_scene_backend(null(), &mut b) };
    f.expect("backend NULL scene", st, S::NullPointer, "scene");
    let st = unsafe { glcol_scene_backend(s, null_mut()) };
    f.expect("backend NULL out", st, S::NullPointer, "out");
    assert_eq!(b, 99);
    ok(unsafe { glcol_scene_backend(s, &mut b) }, "backend");
    assert_eq!(b, GlcolBackend::Cpu as u32);

    // A destroyed mesh: every call on it says UNKNOWN_MESH, its id is not reused.
    let c = f.ids[2];
    let mut g = FfiScene(s);
    g.destroy(c);
    std::mem::forget(g);
    f.ids.pop();
    f.meshes.pop();
    f.before = f.answers();
    f.check_against_oracle();
    let pos = [0f32; 18];
    let st = unsafe { glcol_mesh_update_positions(s, c, pos.as_ptr(), 0, 6, 0) };
    f.expect("update destroyed", st, S::UnknownMesh, "not in this scene");
    let st = unsafe { glcol_mesh_set_enabled(s, c, true) };
    f.expect("enable destroyed", st, S::UnknownMesh, "not in this scene");
    let st = unsafe { glcol_mesh_destroy(s, c) };
    f.expect("destroy destroyed", st, S::UnknownMesh, "not in this scene");
    let st = unsafe { glcol_query(s, c, &mut p, &mut n) };
    f.expect("query destroyed", st, S::UnknownMesh, "not in this scene");
    let again = f.scene.add(&meshes()[2]);
    assert!(
        again > c,
        "id {again} reused or going backwards (destroyed {c})"
    );
    f.scene.destroy(again);
}

/// Ids from another scene that this scene never made are unknown here.
#[test]
fn a_second_scene_is_independent_and_its_ids_are_unknown_here() {
    let mut f = Fixture::new();
    let mut other = FfiScene::new(GlcolBackend::Cpu, 0.5, 1);
    let ms = meshes();
    // More meshes than the fixture has, so some ids exist only over there.
    let theirs: Vec<u32> = (0..6).map(|i| other.add(&ms[i % 3])).collect();
    let their_answers: Vec<Vec<Hit>> = theirs.iter().map(|&id| other.query(id)).collect();
    let s = f.s();
    let mine = f.ids.clone();
    for &id in theirs.iter().filter(|id| !mine.contains(id)) {
        let st = unsafe { glcol_mesh_set_enabled(s, id, false) };
        f.expect("foreign id", st, S::UnknownMesh, &id.to_string());
        let st = unsafe { glcol_mesh_destroy(s, id) };
        f.expect("foreign id", st, S::UnknownMesh, &id.to_string());
    }
    // Work on the other scene does not touch this one, and the other way round.
    other.set_enabled(theirs[0], false);
    other.destroy(theirs[1]);
    assert_eq!(f.answers(), f.before);
    f.scene.set_enabled(f.ids[0], false);
    f.scene.set_enabled(f.ids[0], true);
    assert_eq!(other.query(theirs[5]).len(), {
        // Mesh 5 (a copy of mesh 2) against the enabled copies of meshes 0 and 1 (3, 4)
        // and mesh 2 (5 itself excluded), from the answers before the changes.
        their_answers[5]
            .iter()
            .filter(|h| h.0 != theirs[0] && h.0 != theirs[1])
            .count()
    });
    f.check_against_oracle();
}

/// An id made by another scene that happens to equal a live id of this scene: the C API
/// says such an id is "not in this scene", but ids are numbered per scene from 1, so a
/// foreign id is indistinguishable from this scene's own mesh with the same number.
#[test]
fn a_foreign_id_equal_to_a_live_id_is_unknown() {
    let mut f = Fixture::new();
    let mut other = FfiScene::new(GlcolBackend::Cpu, 0.0, 0);
    let theirs = other.add(&meshes()[0]);
    let st = unsafe { glcol_mesh_set_enabled(f.s(), theirs, false) };
    f.expect("foreign id", st, S::UnknownMesh, &theirs.to_string());
}

#[test]
fn status_names_and_versions() {
    let name = |s: u32| {
        unsafe { CStr::from_ptr(glcol_status_name(s)) }
            .to_str()
            .unwrap()
            .to_owned()
    };
    let want = [
        "GLCOL_STATUS_OK",
        "GLCOL_STATUS_NULL_POINTER",
        "GLCOL_STATUS_INVALID_ARGUMENT",
        "GLCOL_STATUS_NON_FINITE",
        "GLCOL_STATUS_INDEX_OUT_OF_RANGE",
        "GLCOL_STATUS_UNKNOWN_MESH",
        "GLCOL_STATUS_GL_UNAVAILABLE",
        "GLCOL_STATUS_GL_ERROR",
        "GLCOL_STATUS_UNSUPPORTED",
        "GLCOL_STATUS_OUT_OF_MEMORY",
        "GLCOL_STATUS_INTERNAL",
    ];
    for (i, w) in want.iter().enumerate() {
        assert_eq!(name(i as u32), *w);
    }
    for bad in [11, 12, 1000, u32::MAX] {
        assert_eq!(name(bad), "GLCOL_STATUS_UNKNOWN");
    }
    assert_eq!(glcol_abi_version(), GLCOL_ABI_VERSION);
    let v = unsafe { CStr::from_ptr(glcol_version()) }.to_str().unwrap();
    assert_eq!(v, env!("CARGO_PKG_VERSION"));
    // The init functions ignore NULL.
    unsafe {
        glcol_scene_desc_init(null_mut());
        glcol_mesh_desc_init(null_mut());
        glcol_scene_destroy(null_mut());
        glcol_obj_free(null_mut());
    }
}

#[test]
fn last_error_is_per_thread_and_never_null() {
    std::thread::spawn(|| {
        // A fresh thread has no message.
        assert_eq!(last_error(), "");
        let st = unsafe { glcol_scene_create(null(), null_mut()) };
        assert_eq!(st, S::NullPointer);
        assert!(last_error().contains("desc"));
        std::thread::spawn(|| assert_eq!(last_error(), ""))
            .join()
            .unwrap();
        assert!(last_error().contains("desc"));
    })
    .join()
    .unwrap();
}

#[test]
fn obj_loading_rejects_bad_files_and_leaves_the_output_alone() {
    let dir = std::env::temp_dir().join(format!("glcol-ffi-obj-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let sentinel = GlcolObjMesh {
        positions: 0x20 as *mut f32,
        vertex_count: 5,
        indices: 0x40 as *mut u32,
        polygon_count: 6,
        vertices_per_polygon: 7,
    };
    let load = |text: &[u8], name: &str| {
        let p = dir.join(name);
        std::fs::write(&p, text).unwrap();
        let c = CString::new(p.to_str().unwrap()).unwrap();
        let mut out = sentinel;
        let s = unsafe { glcol_obj_load(c.as_ptr(), &mut out) };
        (s, out, last_error())
    };
    let bad: &[(&[u8], &str)] = &[
        (b"", "no faces"),
        (b"v 0 0 0\nv 1 0 0\nv 0 1 0\n", "no faces"),
        (b"v 0 0 0\nv 1 0 0\nf 1 2 3\n", "line 3"),
        (b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 0\n", "line 4"),
        (b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 -4\n", "line 4"),
        (b"v 0 0\n", "line 1"),
        (b"v 0 0 nan\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", "line 1"),
        (b"v 0 0 1e39\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", "line 1"),
        (b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2\n", "line 4"),
        (b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 x\n", "line 4"),
        (
            b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 99999999999999999999\n",
            "line 4",
        ),
        (b"v 0 0 \xff\n", "line 1"),
    ];
    for (i, (text, needle)) in bad.iter().enumerate() {
        let (s, out, msg) = load(text, &format!("bad{i}.obj"));
        assert_eq!(s, S::InvalidArgument, "case {i}: {msg}");
        assert!(
            msg.contains(needle),
            "case {i}: \"{msg}\" lacks \"{needle}\""
        );
        assert_eq!(
            (
                out.positions as usize,
                out.vertex_count,
                out.indices as usize
            ),
            (0x20, 5, 0x40),
            "case {i} wrote *out"
        );
    }
    let (s, mut out, _) = load(
        b"v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 4 3\n",
        "good.obj",
    );
    assert_eq!(s, S::Ok);
    assert_eq!(
        (
            out.vertex_count,
            out.polygon_count,
            out.vertices_per_polygon
        ),
        (4, 2, 3)
    );
    unsafe { glcol_obj_free(&mut out) };
    assert!(out.positions.is_null() && out.indices.is_null());
    unsafe { glcol_obj_free(&mut out) }; // twice is fine: it was zeroed

    let mut out = sentinel;
    let st = unsafe { glcol_obj_load(null(), &mut out) };
    assert_eq!(st, S::NullPointer);
    assert!(last_error().contains("path"));
    let c = CString::new("/nonexistent/x.obj").unwrap();
    let st = unsafe { glcol_obj_load(c.as_ptr(), null_mut()) };
    assert_eq!(st, S::NullPointer);
    assert!(last_error().contains("out"));
    let st = unsafe { glcol_obj_load(c.as_ptr(), &mut out) };
    assert_eq!(st, S::InvalidArgument);
    assert!(last_error().contains("/nonexistent/x.obj"));
    let not_utf8 = [0xffu8, 0xfe, b'.', b'o', 0];
    let st = unsafe { glcol_obj_load(not_utf8.as_ptr().cast(), &mut out) };
    assert_eq!(st, S::InvalidArgument);
    assert!(last_error().contains("path"));
    assert_eq!(out.vertex_count, 5);
    std::fs::remove_dir_all(&dir).ok();
}

/// After every kind of rejected call, the scene still works: meshes can be added, moved,
/// disabled and queried, with the oracle's answers.
#[test]
fn the_scene_stays_usable_after_a_storm_of_bad_calls() {
    let mut f = Fixture::new();
    let s = f.s();
    let m = f.meshes[1].clone();
    let good = mesh_desc(&m);
    let mut id = SENTINEL_ID;
    for i in 0..200usize {
        let mut d = good;
        match i % 8 {
            0 => d.struct_size = 1000 + i as u32,
            1 => d.vertices_per_polygon = 5 + i as u32,
            2 => d.position_stride = 1 + i % 11,
            3 => d.vertex_count = usize::MAX - i,
            4 => d.polygon_count = usize::MAX / 3 - i,
            5 => d.positions = null(),
            6 => d.indices = null(),
            _ => d.vertex_count = 0,
        }
        let st = unsafe { glcol_mesh_create(s, &d, &mut id) };
        assert_ne!(st, S::Ok, "bad create {i} accepted");
        assert_ne!(st, S::Internal, "bad create {i}: {}", last_error());
    }
    assert_eq!(id, SENTINEL_ID);
    assert_eq!(f.answers(), f.before);
    let extra = f.scene.add(&m);
    f.ids.push(extra);
    f.meshes.push(m.clone());
    f.check_against_oracle();
    let moved: Vec<[f32; 3]> = m.pos.iter().map(|p| [p[0] + 0.125, p[1], p[2]]).collect();
    f.scene.update(extra, 0, &moved);
    f.meshes.last_mut().unwrap().pos = moved;
    f.check_against_oracle();
    f.scene.set_enabled(extra, false);
    assert!(f.scene.query(extra).is_empty());
    assert!(f.scene.query(f.ids[0]).iter().all(|h| h.0 != extra));
}

/// A copy of `value`'s bytes at an address 4 bytes past an 8-byte boundary, in `buf`: a
/// pointer no C compiler would make for an 8-aligned struct.
fn misaligned_copy<T: Copy>(value: &T, buf: &mut Vec<u64>) -> *const T {
    let size = std::mem::size_of::<T>();
    assert!(std::mem::align_of::<T>() == 8, "the structs hold pointers");
    buf.clear();
    buf.resize(size / 8 + 2, 0);
    let at = buf.as_mut_ptr().cast::<u8>().wrapping_add(4);
    // SAFETY: `buf` holds size + 16 bytes, so size bytes fit from offset 4; byte copies
    // need no alignment.
    unsafe { std::ptr::copy_nonoverlapping((value as *const T).cast::<u8>(), at, size) };
    at.cast()
}

/// Regression ("struct_size read unaligned but the struct aligned"): a desc is read with
/// aligned reads only, its struct_size first; a misaligned desc pointer (which C never
/// makes) is refused before anything is read, naming `desc`, and changes nothing.
#[test]
fn a_misaligned_desc_is_refused_before_anything_is_read() {
    let mut buf = Vec::new();
    let sentinel = 0x1234usize as *mut GlcolScene;
    let mut out = sentinel;
    let d = misaligned_copy(&scene_desc(), &mut buf);
    let st = unsafe { glcol_scene_create(d, &mut out) };
    let msg = last_error();
    assert_eq!(st, S::InvalidArgument, "{msg}");
    assert!(msg.contains("desc is not 8-byte aligned"), "{msg}");
    assert_eq!(out, sentinel, "a failed create wrote *out_scene");

    let mut f = Fixture::new();
    let good = mesh_desc(&f.meshes[0]);
    let d = misaligned_copy(&good, &mut buf);
    let mut id = SENTINEL_ID;
    let st = unsafe { glcol_mesh_create(f.s(), d, &mut id) };
    f.expect(
        "misaligned mesh desc",
        st,
        S::InvalidArgument,
        "desc is not 8-byte aligned",
    );
    assert_eq!(id, SENTINEL_ID);
    // The same bytes, aligned, make a mesh: only the address was wrong.
    let aligned: GlcolMeshDesc = unsafe { d.read_unaligned() };
    ok(
        unsafe { glcol_mesh_create(f.s(), &aligned, &mut id) },
        "the aligned copy",
    );
    f.scene.destroy(id);
}

/// Regression ("the vertex-count limits of ffi and mesh.rs disagree"): one limit, 2^32 - 1
/// vertices (the header's), refused or accepted alike by the C API and the Rust API, with
/// the same message. A count at the limit passes the count check and fails on what is
/// checked next (here a bad stride, or the Rust slice's length: a real array of 2^32 - 1
/// vertices is 48 GiB); one above it is refused as a count.
#[cfg(target_pointer_width = "64")]
#[test]
fn the_vertex_limit_is_one_for_the_c_and_the_rust_api() {
    use glcollide::{ErrorKind, Positions};
    const LIMIT: usize = u32::MAX as usize;
    let mut f = Fixture::new();
    let good = mesh_desc(&f.meshes[0]);
    let s = f.s();
    let mut id = SENTINEL_ID;
    let mut create = |f: &mut Fixture, what: &str, d: GlcolMeshDesc, needle: &str| {
        let st = unsafe { glcol_mesh_create(s, &d, &mut id) };
        f.expect(what, st, S::InvalidArgument, needle);
        last_error()
    };
    let above = GlcolMeshDesc {
        vertex_count: LIMIT + 1,
        position_stride: 4,
        ..good
    };
    let c_above = create(&mut f, "C, one above", above, "vertex_count 4294967296");
    assert!(c_above.contains("2^32 - 1"), "{c_above}");
    let at = GlcolMeshDesc {
        vertex_count: LIMIT,
        ..above
    };
    let c_at = create(&mut f, "C, at the limit", at, "position_stride 4");
    assert!(!c_at.contains("vertex_count"), "{c_at}");
    assert_eq!(id, SENTINEL_ID);

    let bytes = [0u8; 12];
    let e = Positions::new(&bytes, LIMIT + 1, 0).unwrap_err();
    assert_eq!((e.kind, &e.message), (ErrorKind::InvalidArgument, &c_above));
    let e = Positions::new(&bytes, LIMIT + 1, 4).unwrap_err();
    assert!(e.message.contains("position_stride 4"), "{}", e.message);
    let e = Positions::new(&bytes, LIMIT, 4).unwrap_err();
    assert_eq!(e.message, c_at);
    let e = Positions::new(&bytes, LIMIT, 0).unwrap_err();
    assert!(
        e.message.contains("bytes of positions") && !e.message.contains("vertex_count"),
        "{}",
        e.message
    );
    assert_eq!(f.answers(), f.before);
}

/// The polygon limit is the mesh's too: 2^32 - 2 corners (polygon_count times
/// vertices_per_polygon), refused by the C API before any array is read.
#[cfg(target_pointer_width = "64")]
#[test]
fn the_corner_limit_is_checked_before_the_arrays_are_read() {
    const CORNERS: usize = u32::MAX as usize - 1;
    let mut f = Fixture::new();
    let good = mesh_desc(&f.meshes[0]);
    let s = f.s();
    let mut id = SENTINEL_ID;
    for (k, polygons) in [(3u32, CORNERS / 3), (4, CORNERS / 4)] {
        // One polygon more is past the limit: refused as a count.
        let d = GlcolMeshDesc {
            vertices_per_polygon: k,
            polygon_count: polygons + 1,
            ..good
        };
        let st = unsafe { glcol_mesh_create(s, &d, &mut id) };
        f.expect("one polygon above", st, S::InvalidArgument, "polygon_count");
        assert!(
            last_error().contains("2^32 - 2 corners"),
            "{}",
            last_error()
        );
        // At the limit the count passes; the bad stride, checked next, is refused before
        // the indices (4 * 2^32 bytes) would be read.
        let d = GlcolMeshDesc {
            position_stride: 4,
            polygon_count: polygons,
            ..d
        };
        let st = unsafe { glcol_mesh_create(s, &d, &mut id) };
        f.expect("at the limit", st, S::InvalidArgument, "position_stride 4");
    }
    assert_eq!(id, SENTINEL_ID);
}
