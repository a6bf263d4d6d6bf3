//! f64 meshes (`Positions::from_points_f64`, `GlcolMeshDesc.positions_f64`): every query
//! answers exactly for the double positions (under the mesh's transform, if any).
//!
//! - Two triangles that miss, touch or cross by one ulp of a double, 1e6 from the origin:
//!   the answer is the exact one (big integers, `common::exact`), where the same triangles
//!   rounded to floats give a wrong one.
//! - Random near-touching pairs (vertex on face, edge on edge, off by -1, 0, +1 ulp), with
//!   and without a random rotation: every engine (CPU at 1 and 2 threads, the step-by-step
//!   engine, and in `mod gl` GL_SELECT and GL_COMPUTE) gives the exact answer, for `query`
//!   and `query_all`, after updates too.
//! - Contact geometry of an f64 mesh is bit for bit that of a placed float mesh whose world
//!   positions are those doubles.
//! - Bad input (C API): every status and message, nothing changed.

mod common;

use common::backends::{last_error, ok, FfiScene, SafeScene, TestScene};
use common::exact::{exact_triangles_meet, random_rotation, world, world_f64, M};
use common::{shared_mesh, Rng, TestMesh};
use glcollide::ffi::*;
use glcollide::{ErrorKind, MeshId, Positions, Scene, SceneConfig};
use GlcolStatus as S;

fn scene(epsilon: f32, threads: u32) -> Scene {
    Scene::new(SceneConfig {
        epsilon,
        threads,
        ..SceneConfig::default()
    })
    .unwrap()
}

/// A triangle mesh of double positions.
#[derive(Clone, Debug)]
struct Mesh64 {
    pos: Vec<[f64; 3]>,
    idx: Vec<u32>,
}

impl Mesh64 {
    fn tri(t: [[f64; 3]; 3]) -> Mesh64 {
        Mesh64 {
            pos: t.to_vec(),
            idx: vec![0, 1, 2],
        }
    }

    fn polygons(&self) -> usize {
        self.idx.len() / 3
    }

    /// Triangle `i` at its world positions under `m`.
    fn world_tri(&self, m: Option<&M>, i: usize) -> [[f64; 3]; 3] {
        [0, 1, 2].map(|j| {
            let p = &self.pos[self.idx[i * 3 + j] as usize];
            m.map_or(*p, |m| world_f64(m, p))
        })
    }

    /// The same positions rounded to the nearest floats.
    fn rounded(&self) -> TestMesh {
        TestMesh {
            pos: self.pos.iter().map(|p| p.map(|x| x as f32)).collect(),
            idx: self.idx.clone(),
            k: 3,
        }
    }
}

fn add64(s: &mut Scene, m: &Mesh64) -> MeshId {
    s.create_mesh(Positions::from_points_f64(&m.pos), &m.idx, 3)
        .unwrap()
}

fn bbox(t: &[[f64; 3]; 3]) -> ([f64; 3], [f64; 3]) {
    let lo = [0, 1, 2].map(|k| t.iter().map(|p| p[k]).fold(f64::INFINITY, f64::min));
    let hi = [0, 1, 2].map(|k| t.iter().map(|p| p[k]).fold(f64::NEG_INFINITY, f64::max));
    (lo, hi)
}

/// The exact whole-scene answer for meshes `ms` (ids `ids`, placed by `place`): every pair
/// of triangles of two different meshes that meet, as (mesh_a, polygon_a, mesh_b,
/// polygon_b), sorted.
fn exact_all(ms: &[Mesh64], ids: &[MeshId], place: &[Option<M>]) -> Vec<(u32, u32, u32, u32)> {
    let tris: Vec<Vec<[[f64; 3]; 3]>> = ms
        .iter()
        .zip(place)
        .map(|(m, p)| {
            (0..m.polygons())
                .map(|i| m.world_tri(p.as_ref(), i))
                .collect()
        })
        .collect();
    let boxes: Vec<Vec<_>> = tris.iter().map(|t| t.iter().map(bbox).collect()).collect();
    let mut out = Vec::new();
    for a in 0..ms.len() {
        for b in a + 1..ms.len() {
            for (i, t) in tris[a].iter().enumerate() {
                let (l1, h1) = boxes[a][i];
                for (j, u) in tris[b].iter().enumerate() {
                    let (l2, h2) = boxes[b][j];
                    if (0..3).all(|k| l2[k] <= h1[k] && l1[k] <= h2[k])
                        && exact_triangles_meet(t, u)
                    {
                        out.push((ids[a], i as u32, ids[b], j as u32));
                    }
                }
            }
        }
    }
    out.sort_unstable();
    out
}

fn all(s: &mut Scene) -> Vec<(u32, u32, u32, u32)> {
    s.query_all()
        .unwrap()
        .iter()
        .map(|p| (p.mesh_a, p.polygon_a, p.mesh_b, p.polygon_b))
        .collect()
}

/// Every reference query's contacts, as whole-scene tuples (mesh_a < mesh_b), sorted.
fn by_reference(s: &mut Scene, ids: &[MeshId]) -> Vec<(u32, u32, u32, u32)> {
    let mut out = Vec::new();
    for &r in ids {
        for c in s.query(r).unwrap() {
            if r < c.other_mesh {
                out.push((r, c.reference_polygon, c.other_mesh, c.other_polygon));
            }
        }
    }
    out.sort_unstable();
    out
}

/// The next double above `x` (`k` = 1) or below (`k` = -1), or `x`.
fn ulps(x: f64, k: i64) -> f64 {
    match k {
        0 => x,
        1 => x.next_up(),
        -1 => x.next_down(),
        _ => unreachable!(),
    }
}

/// A horizontal triangle at height `c`, 1e6 from the origin, and a spike below it whose
/// apex is at `c` moved by `k` ulps: apart (-1), touching (0), crossing (+1).
fn spike_case(k: i64) -> (Mesh64, Mesh64) {
    let o = 1e6 + 1.0 / 3.0;
    let c = 1e6 + 0.1;
    let flat = Mesh64::tri([[o, o, c], [o + 1.0, o, c], [o, o + 1.0, c]]);
    let apex = [o + 0.25, o + 0.3, ulps(c, k)];
    let spike = Mesh64::tri([
        [o + 0.2, o + 0.2, c - 1.0],
        [o + 0.45, o + 0.2, c - 1.0],
        apex,
    ]);
    (flat, spike)
}

#[test]
fn one_ulp_of_a_double_decides_where_floats_cannot_see_it() {
    for (k, meets) in [(-1, false), (0, true), (1, true)] {
        let (flat, spike) = spike_case(k);
        assert_eq!(
            exact_triangles_meet(&flat.world_tri(None, 0), &spike.world_tri(None, 0)),
            meets,
            "the exact reference, {k} ulp"
        );
        for threads in [1, 2] {
            let mut s = scene(0.0, threads);
            let (a, b) = (add64(&mut s, &flat), add64(&mut s, &spike));
            let want = if meets { vec![(a, 0, b, 0)] } else { vec![] };
            assert_eq!(all(&mut s), want, "{k} ulp, {threads} threads");
            assert_eq!(by_reference(&mut s, &[a, b]), want);
            // Rounded to floats the apex sits on the flat triangle's plane: touching.
            let mut f = scene(0.0, threads);
            let (fa, fb) = (
                common::add(&mut f, &flat.rounded()),
                common::add(&mut f, &spike.rounded()),
            );
            assert_eq!(
                all(&mut f),
                [(fa, 0, fb, 0)],
                "floats see every case as a contact ({k} ulp)"
            );
        }
    }
    // Moving the apex by updates decides the same, and a partial update too.
    let (flat, spike) = spike_case(-1);
    let mut s = scene(0.0, 1);
    let (a, b) = (add64(&mut s, &flat), add64(&mut s, &spike));
    for k in [0, -1, 1, -1] {
        let apex = spike_case(k).1.pos[2];
        s.update_positions_f64(b, 2, &[apex]).unwrap();
        let want = if k >= 0 { vec![(a, 0, b, 0)] } else { vec![] };
        assert_eq!(all(&mut s), want, "updated to {k} ulp");
    }
    // Placed: both by one rotation, the exact reference on the world positions.
    let mut r = Rng(77);
    for round in 0..20 {
        let x = r.range(-1e6, 1e6);
        let m = random_rotation(&mut r, 1.0, [x, 3.5, -2e5]);
        for k in [-1, 0, 1] {
            let (flat, spike) = spike_case(k);
            let ms = [flat, spike];
            let mut s = scene(0.0, 1 + round % 2);
            let ids = [add64(&mut s, &ms[0]), add64(&mut s, &ms[1])];
            for &id in &ids {
                s.set_transform(id, Some(&m)).unwrap();
            }
            let want = exact_all(&ms, &ids, &[Some(m), Some(m)]);
            assert_eq!(all(&mut s), want, "round {round}, {k} ulp");
            assert_eq!(by_reference(&mut s, &ids), want);
        }
    }
}

/// Random near-touching pairs, each pair at its own place (1e6 from the origin, 10 apart):
/// a vertex of `u` on `t`'s face with `u`'s other corners above it, or `u`'s edge through a
/// point of `t`'s edge; the point computed in doubles, then moved by -1, 0 or +1 ulp on one
/// coordinate, so that whether they meet is decided at the last bit.
fn near_pairs(r: &mut Rng, n: usize) -> Vec<Mesh64> {
    let mut out = Vec::new();
    for i in 0..n {
        let base = [1e6 + 10.0 * i as f64, -1e6 + r.range(0.0, 1.0), 1e6 / 3.0];
        let p = |r: &mut Rng| [0, 1, 2].map(|k| base[k] + r.range(-1.0, 1.0));
        let t = [p(r), p(r), p(r)];
        let sub = |a: [f64; 3], b: [f64; 3]| [0, 1, 2].map(|k| a[k] - b[k]);
        let (e1, e2) = (sub(t[1], t[0]), sub(t[2], t[0]));
        let nrm = [
            e1[1] * e2[2] - e1[2] * e2[1],
            e1[2] * e2[0] - e1[0] * e2[2],
            e1[0] * e2[1] - e1[1] * e2[0],
        ];
        let (s, w) = (r.range(0.05, 0.5), r.range(0.05, 0.45));
        let mut hit = if i % 2 == 0 {
            [0, 1, 2].map(|k| t[0][k] + s * e1[k] + w * e2[k])
        } else {
            [0, 1, 2].map(|k| t[0][k] + s * e1[k])
        };
        let k = (r.next_u64() % 3) as usize;
        hit[k] = ulps(hit[k], (r.next_u64() % 3) as i64 - 1);
        let above = |r: &mut Rng| {
            let h = r.range(0.2, 1.0);
            [0, 1, 2].map(|k| hit[k] + h * nrm[k] + r.range(-0.3, 0.3))
        };
        let u = if i % 2 == 0 {
            [hit, above(r), above(r)]
        } else {
            // An edge through `hit`, crossing t's edge, and a corner above.
            let d = [0, 1, 2].map(|_| r.range(-0.5, 0.5));
            [
                [0, 1, 2].map(|k| hit[k] - d[k]),
                [0, 1, 2].map(|k| hit[k] + d[k]),
                above(r),
            ]
        };
        out.push(Mesh64::tri(t));
        out.push(Mesh64::tri(u));
    }
    out
}

/// Whole-scene tuples with mesh ids replaced by their index in `ids`.
fn by_index(v: Vec<(u32, u32, u32, u32)>, ids: &[MeshId]) -> Vec<(u32, u32, u32, u32)> {
    let at = |id: u32| ids.iter().position(|&x| x == id).unwrap() as u32;
    v.into_iter()
        .map(|(a, i, b, j)| (at(a), i, at(b), j))
        .collect()
}

#[test]
fn near_touching_pairs_get_the_exact_answer_from_every_cpu_engine() {
    let mut r = Rng(0xf64);
    let ms = near_pairs(&mut r, 150);
    let index: Vec<MeshId> = (0..ms.len() as u32).collect();
    for placed in [false, true] {
        let m = random_rotation(&mut r, 2.0, [1.0, -1e5, 7.0]);
        let place: Vec<Option<M>> = ms.iter().map(|_| placed.then_some(m)).collect();
        let want = exact_all(&ms, &index, &place);
        let meeting = want.len();
        assert!(
            meeting > 20 && meeting < 140,
            "not adversarial: {meeting} of 150 pairs meet"
        );
        assert!(want.iter().all(|p| p.0 % 2 == 0 && p.2 == p.0 + 1));
        let engines: [Box<dyn Fn() -> Scene>; 3] = [
            Box::new(|| scene(0.0, 1)),
            Box::new(|| scene(0.0, 2)),
            Box::new(|| SafeScene::step_by_step(0.0, 0).0),
        ];
        for (e, make) in engines.iter().enumerate() {
            let mut s = make();
            let ids: Vec<MeshId> = ms.iter().map(|m| add64(&mut s, m)).collect();
            if placed {
                for &id in &ids {
                    s.set_transform(id, Some(&m)).unwrap();
                }
            }
            if e < 2 {
                assert_eq!(
                    by_index(all(&mut s), &ids),
                    want,
                    "placed {placed}, engine {e}"
                );
            }
            assert_eq!(
                by_index(by_reference(&mut s, &ids), &ids),
                want,
                "engine {e}"
            );
            // Moved away by a partial update, and back: the answer follows.
            s.update_positions_f64(ids[1], 0, &[[0.0; 3]]).unwrap();
            s.update_positions_f64(ids[1], 0, &ms[1].pos[..1]).unwrap();
            assert_eq!(by_index(by_reference(&mut s, &ids), &ids), want);
            // Full updates: every mesh moved by 1 unit along x, then back.
            for (id, m) in ids.iter().zip(&ms) {
                let moved: Vec<[f64; 3]> = m.pos.iter().map(|p| [p[0] + 1.0, p[1], p[2]]).collect();
                s.update_positions_f64(*id, 0, &moved).unwrap();
            }
            for (id, m) in ids.iter().zip(&ms) {
                s.update_positions_f64(*id, 0, &m.pos).unwrap();
            }
            assert_eq!(by_index(by_reference(&mut s, &ids), &ids), want);
        }
    }
}

/// Contact geometry of an f64 mesh equals, bit for bit, that of a placed float mesh whose
/// world positions are the f64 mesh's doubles (and so do the pairs).
#[test]
fn contact_geometry_is_the_placed_float_meshs_bit_for_bit() {
    let jaw = TestMesh::from_obj(&shared_mesh("forceps_jaw"));
    let pot = TestMesh::from_obj(&shared_mesh("teapot"));
    let (lo, hi) = common::bounds(&jaw.pos);
    let c = [0, 1, 2].map(|k| (lo[k] + hi[k]) as f64 / 2.0);
    let mut r = Rng(0x6e0);
    let mut compared = 0;
    for round in 0..3 {
        let at = pot.pos[(r.next_u64() % pot.pos.len() as u64) as usize].map(f64::from);
        let mut m = random_rotation(&mut r, 0.15, at);
        for i in 0..3 {
            m[i * 4 + 3] -= (0..3).map(|j| m[i * 4 + j] * c[j]).sum::<f64>();
        }
        let doubles = Mesh64 {
            pos: jaw.pos.iter().map(|p| world(&m, p)).collect(),
            idx: jaw.idx.clone(),
        };
        for epsilon in [0.0, 0.01] {
            let answer = |f64_mesh: bool| {
                let mut s = scene(epsilon, 2);
                let a = common::add(&mut s, &pot);
                let b = if f64_mesh {
                    add64(&mut s, &doubles)
                } else {
                    let b = common::add(&mut s, &jaw);
                    s.set_transform(b, Some(&m)).unwrap();
                    b
                };
                s.set_self_collision(b, true).unwrap();
                let pairs: Vec<_> = all(&mut s)
                    .into_iter()
                    .map(|(x, i, y, j)| (x == a, i, y == a, j))
                    .collect();
                let g = format!("{:?}", s.contact_geometry().unwrap());
                let reference: Vec<_> = s
                    .query(b)
                    .unwrap()
                    .iter()
                    .map(|c| (c.reference_polygon, c.other_polygon))
                    .collect();
                let g2 = format!("{:?}", s.contact_geometry().unwrap());
                (pairs, g, reference, g2)
            };
            let (want, got) = (answer(false), answer(true));
            assert!(!want.0.is_empty(), "round {round}: no contact");
            compared += want.0.len();
            // `{:?}` of an f64 prints the shortest string that reads back to the same
            // bits: equal strings are equal bits.
            assert_eq!(got, want, "round {round}, epsilon {epsilon}");
        }
    }
    assert!(compared > 20);
}

/// Quads too (each the union of its two triangles, bent ones included): an f64 quad mesh
/// answers, with its geometry, as the placed float quad mesh of the same world positions.
#[test]
fn quads_answer_as_the_placed_float_quads() {
    let pot = TestMesh::from_obj(&shared_mesh("teapot"));
    let n = 12;
    let mut quads = TestMesh {
        pos: Vec::new(),
        idx: Vec::new(),
        k: 4,
    };
    for j in 0..=n {
        for i in 0..=n {
            let bump = ((i * 7 + j * 3) % 5) as f32 * 0.05;
            quads
                .pos
                .push([i as f32 * 0.25 - 1.5, j as f32 * 0.25 - 1.5, bump]);
        }
    }
    for j in 0..n as u32 {
        for i in 0..n as u32 {
            let v = j * (n as u32 + 1) + i;
            quads
                .idx
                .extend([v, v + 1, v + n as u32 + 2, v + n as u32 + 1]);
        }
    }
    let (lo, hi) = common::bounds(&pot.pos);
    let centre = [0, 1, 2].map(|k| (lo[k] + hi[k]) as f64 / 2.0);
    let mut r = Rng(0x4);
    let mut compared = 0;
    for _ in 0..3 {
        let m = random_rotation(&mut r, 1.0, centre);
        let doubles: Vec<[f64; 3]> = quads.pos.iter().map(|p| world(&m, p)).collect();
        let answer = |f64_mesh: bool| {
            let mut s = scene(0.0, 2);
            let a = common::add(&mut s, &pot);
            let b = if f64_mesh {
                s.create_mesh(Positions::from_points_f64(&doubles), &quads.idx, 4)
                    .unwrap()
            } else {
                let b = common::add(&mut s, &quads);
                s.set_transform(b, Some(&m)).unwrap();
                b
            };
            let pairs: Vec<_> = all(&mut s)
                .into_iter()
                .map(|(x, i, y, j)| (x == a, i, y == b, j))
                .collect();
            (pairs, format!("{:?}", s.contact_geometry().unwrap()))
        };
        let want = answer(false);
        compared += want.0.len();
        assert_eq!(answer(true), want);
    }
    assert!(compared > 20, "{compared} pairs");
}

// ---------------------------------------------------------------------------------------
// The C API: creating, updating, refusing.

fn desc64(pos: &[[f64; 3]], idx: &[u32]) -> GlcolMeshDesc {
    let mut d = unsafe { std::mem::zeroed::<GlcolMeshDesc>() };
    ok(
        unsafe { glcol_mesh_desc_init_sized(&mut d, std::mem::size_of::<GlcolMeshDesc>()) },
        "init",
    );
    d.positions_f64 = pos.as_ptr().cast();
    d.vertex_count = pos.len();
    d.indices = idx.as_ptr();
    d.polygon_count = idx.len() / 3;
    d.vertices_per_polygon = 3;
    d
}

fn create(s: &FfiScene, d: &GlcolMeshDesc) -> Result<GlcolMeshId, (GlcolStatus, String)> {
    let mut id = 0;
    match unsafe { glcol_mesh_create(s.0, d, &mut id) } {
        S::Ok => Ok(id),
        st => Err((st, last_error())),
    }
}

fn ffi_all(s: &FfiScene) -> Vec<(u32, u32, u32, u32)> {
    let (mut p, mut n) = (std::ptr::null(), 0usize);
    ok(unsafe { glcol_query_all(s.0, &mut p, &mut n) }, "query_all");
    if n == 0 {
        return Vec::new();
    }
    unsafe { std::slice::from_raw_parts(p, n) }
        .iter()
        .map(|p| (p.mesh_a, p.polygon_a, p.mesh_b, p.polygon_b))
        .collect()
}

#[test]
fn the_c_api_makes_and_moves_f64_meshes_exactly() {
    let s = FfiScene::new(GlcolBackend::Cpu, 0.0, 0);
    let (flat, spike) = spike_case(-1);
    let a = create(&s, &desc64(&flat.pos, &flat.idx)).unwrap();
    // A strided array: each vertex followed by one unrelated double.
    let strided: Vec<f64> = spike
        .pos
        .iter()
        .flat_map(|p| [p[0], p[1], p[2], 9e99])
        .collect();
    let mut d = desc64(&spike.pos, &spike.idx);
    d.positions_f64 = strided.as_ptr();
    d.position_stride = 32;
    let b = create(&s, &d).unwrap();
    assert!(ffi_all(&s).is_empty(), "one ulp apart");
    let up = spike_case(1).1.pos[2];
    ok(
        unsafe { glcol_mesh_update_positions_f64(s.0, b, up.as_ptr(), 2, 1, 0) },
        "update_f64",
    );
    assert_eq!(ffi_all(&s), [(a, 0, b, 0)], "one ulp through");
}

#[test]
fn bad_f64_input_is_refused_with_a_message_and_changes_nothing() {
    let mut s = FfiScene::new(GlcolBackend::Cpu, 0.0, 0);
    let (flat, spike) = spike_case(0);
    let a = create(&s, &desc64(&flat.pos, &flat.idx)).unwrap();
    let b = create(&s, &desc64(&spike.pos, &spike.idx)).unwrap();
    let float_mesh = s.add(&common::square(0.0, 0.0));
    let before = ffi_all(&s);
    assert_eq!(before, [(a, 0, b, 0)]);
    let expect = |what: &str, st: GlcolStatus, want: GlcolStatus, needle: &str| {
        let msg = last_error();
        assert_eq!(st, want, "{what}: {msg}");
        assert!(msg.contains(needle), "{what}: \"{msg}\" lacks \"{needle}\"");
        assert_eq!(ffi_all(&s), before, "{what} changed the answer");
    };
    // Creating.
    let fpos: Vec<[f32; 3]> = flat.rounded().pos;
    let mut d = desc64(&flat.pos, &flat.idx);
    d.positions = fpos.as_ptr().cast();
    let e = create(&s, &d).unwrap_err();
    expect("both positions", e.0, S::InvalidArgument, "positions_f64");
    let mut d = desc64(&flat.pos, &flat.idx);
    d.positions_f64 = std::ptr::null();
    let e = create(&s, &d).unwrap_err();
    expect(
        "neither positions",
        e.0,
        S::InvalidArgument,
        "positions_f64",
    );
    for (bad, needle) in [
        (f64::NAN, "NaN"),
        (f64::INFINITY, "infinite"),
        (3.5e38, "float range"),
        (-1e300, "float range"),
    ] {
        let mut pos = flat.pos.clone();
        pos[1][2] = bad;
        let e = create(&s, &desc64(&pos, &flat.idx)).unwrap_err();
        expect(&format!("create with {bad}"), e.0, S::NonFinite, needle);
        assert!(e.1.contains("vertex 1"), "{}", e.1);
    }
    // The float range's edge itself is fine.
    let mut pos = flat.pos.clone();
    pos[0][0] = f32::MAX as f64;
    let edge = create(&s, &desc64(&pos, &flat.idx)).unwrap();
    ok(unsafe { glcol_mesh_destroy(s.0, edge) }, "destroy");
    for (stride, needle) in [(12, "position_stride"), (28, "position_stride")] {
        let mut d = desc64(&flat.pos, &flat.idx);
        d.position_stride = stride;
        let e = create(&s, &d).unwrap_err();
        expect(&format!("stride {stride}"), e.0, S::InvalidArgument, needle);
    }
    let words = [0.0f64; 11];
    let mut d = desc64(&flat.pos, &flat.idx);
    d.positions_f64 = unsafe { words.as_ptr().cast::<u8>().add(4) }.cast();
    let e = create(&s, &d).unwrap_err();
    expect("misaligned", e.0, S::InvalidArgument, "aligned");
    // Updating: each call for its own kind of mesh.
    let p32 = [[0.0f32; 3]];
    let p64 = [[0.0f64; 3]];
    let st = unsafe { glcol_mesh_update_positions(s.0, b, p32.as_ptr().cast(), 0, 1, 0) };
    expect(
        "float update of an f64 mesh",
        st,
        S::InvalidArgument,
        "_f64",
    );
    let st =
        unsafe { glcol_mesh_update_positions_f64(s.0, float_mesh, p64.as_ptr().cast(), 0, 1, 0) };
    expect(
        "f64 update of a float mesh",
        st,
        S::InvalidArgument,
        "float mesh",
    );
    let st = unsafe { glcol_mesh_update_positions_f64(s.0, b, std::ptr::null(), 0, 1, 0) };
    expect("NULL", st, S::NullPointer, "positions");
    let st = unsafe { glcol_mesh_update_positions_f64(s.0, 0, p64.as_ptr().cast(), 0, 1, 0) };
    expect("unknown mesh", st, S::UnknownMesh, "mesh id 0");
    let st = unsafe { glcol_mesh_update_positions_f64(s.0, b, p64.as_ptr().cast(), 3, 1, 0) };
    expect("past the end", st, S::InvalidArgument, "runs past");
    for bad in [f64::NAN, 1e39, f64::NEG_INFINITY] {
        let mut pos = spike.pos.clone();
        pos[0] = [0.0, 0.0, 0.0]; // would move the spike away, were it taken
        pos[2][0] = bad;
        let st = unsafe { glcol_mesh_update_positions_f64(s.0, b, pos.as_ptr().cast(), 0, 3, 0) };
        expect(&format!("update with {bad}"), st, S::NonFinite, "vertex 2");
    }
    // Under a transform: world positions beyond the float range.
    let scale = [1e30, 0., 0., 0., 0., 1e30, 0., 0., 0., 0., 1e30, 0.];
    ok(
        unsafe { glcol_mesh_set_transform(s.0, a, scale.as_ptr()) },
        "scale",
    );
    let big = [[1e9f64, 0.0, 0.0]];
    let st = unsafe { glcol_mesh_update_positions_f64(s.0, a, big.as_ptr().cast(), 0, 1, 0) };
    let msg = last_error();
    assert_eq!(st, S::NonFinite, "{msg}");
    ok(
        unsafe { glcol_mesh_set_transform(s.0, a, std::ptr::null()) },
        "identity",
    );
    assert_eq!(ffi_all(&s), before);
    // No GL buffer for an f64 mesh (UNSUPPORTED on every scene).
    let st = unsafe { glcol_mesh_bind_gl_buffer(s.0, b, 1, 0, 0) };
    expect("bind an f64 mesh", st, S::Unsupported, "f64 mesh");
}

#[test]
fn the_rust_api_refuses_the_other_precision() {
    let mut s = scene(0.0, 1);
    let (flat, _) = spike_case(0);
    let a = add64(&mut s, &flat);
    let f = common::add(&mut s, &common::square(0.0, 0.0));
    let e = s
        .update_positions(a, 0, Positions::from_points(&[[0.0f32; 3]]))
        .unwrap_err();
    assert_eq!(e.kind, ErrorKind::InvalidArgument);
    let e = s.update_positions_f64(f, 0, &[[0.0; 3]]).unwrap_err();
    assert_eq!(e.kind, ErrorKind::InvalidArgument);
    assert!(s.mesh(a).unwrap().is_f64() && !s.mesh(f).unwrap().is_f64());
    assert_eq!(s.mesh(a).unwrap().vertex_position_f64(1), Some(flat.pos[1]));
    assert_eq!(
        s.mesh(a).unwrap().world_position(1),
        Some(flat.pos[1]),
        "an f64 mesh's world positions are its doubles"
    );
}

// ---------------------------------------------------------------------------------------
// The GL backends (C API, headless EGL context): pairs with an f64 mesh are answered by the
// CPU engine; the answer is the CPU backend's.

mod gl {
    use super::*;
    use common::backends::gl_support::{self, host_buffer, Ctx, Profile};

    /// f64 meshes (two placed) and a float mesh: every query's answer with ids as
    /// positions.
    fn run(
        s: &mut FfiScene,
        ms: &[Mesh64],
        m: &M,
        floats: &TestMesh,
    ) -> Vec<Vec<(u32, u32, u32, u32)>> {
        let mut ids: Vec<GlcolMeshId> = ms
            .iter()
            .map(|x| create(s, &desc64(&x.pos, &x.idx)).unwrap())
            .collect();
        for &id in &ids[..2] {
            ok(
                unsafe { glcol_mesh_set_transform(s.0, id, m.as_ptr()) },
                "place",
            );
        }
        ids.push(s.add(floats));
        ok(
            unsafe { glcol_mesh_set_self_collision(s.0, ids[ids.len() - 1], true) },
            "self",
        );
        let n = |id: u32| ids.iter().position(|&x| x == id).unwrap() as u32;
        let mut out: Vec<Vec<_>> = ids
            .iter()
            .map(|&r| {
                s.query(r)
                    .iter()
                    .map(|h| (n(r), h.1, n(h.0), h.2))
                    .collect()
            })
            .collect();
        out.push(
            ffi_all(s)
                .into_iter()
                .map(|p| (n(p.0), p.1, n(p.2), p.3))
                .collect(),
        );
        out
    }

    #[test]
    fn gl_backends_give_the_cpu_answer_for_f64_meshes() {
        let _ctx = Ctx::new(Profile::Compat);
        let mut r = Rng(0x91);
        let ms = near_pairs(&mut r, 40);
        let m = random_rotation(&mut r, 1.0, [0.5, 0.25, 0.0]);
        // A float mesh where the pairs are: 1e6 from the origin, a grid of squares.
        let mut floats = common::square(0.0, 0.0);
        for p in &mut floats.pos {
            *p = [p[0] * 400.0 + 1e6, p[1] * 2e6 - 1e6, 1e6 / 3.0];
        }
        for epsilon in [0.0, 0.01] {
            let mut cpu = FfiScene::new(GlcolBackend::Cpu, epsilon, 0);
            let want = run(&mut cpu, &ms, &m, &floats);
            assert!(want.iter().filter(|v| !v.is_empty()).count() > 10);
            for backend in [GlcolBackend::GlSelect, GlcolBackend::GlCompute] {
                let mut s = FfiScene(gl_support::scene(backend, epsilon, 0));
                assert_eq!(
                    run(&mut s, &ms, &m, &floats),
                    want,
                    "{backend:?}, epsilon {epsilon}"
                );
            }
        }
    }

    /// A query that would pair an f64 mesh (answered on the CPU) with a mesh read from a GL
    /// buffer on GL_COMPUTE (whose positions are on the GPU only) is refused, UNSUPPORTED
    /// naming both, as for a transformed mesh; disabling one side answers again.
    #[test]
    fn an_f64_mesh_and_a_gl_buffer_mesh_are_not_paired() {
        use glow::HasContext;
        let ctx = Ctx::new(Profile::Core);
        let g = ctx.glow();
        let sq = common::square(0.0, 0.0);
        let mut s = FfiScene(gl_support::scene(GlcolBackend::GlCompute, 0.0, 0));
        let a = s.add(&sq);
        let host = host_buffer(&g, &sq.pos);
        ok(
            unsafe { glcol_mesh_bind_gl_buffer(s.0, a, host.0.get(), 0, 12) },
            "bind",
        );
        let wall: Vec<[f64; 3]> = common::wall(0.5)
            .pos
            .iter()
            .map(|p| p.map(f64::from))
            .collect();
        let b = create(&s, &desc64(&wall, &[0, 1, 2, 0, 2, 3])).unwrap();
        let st = unsafe { glcol_mesh_bind_gl_buffer(s.0, b, host.0.get(), 0, 12) };
        assert_eq!(st, S::Unsupported, "{}", last_error());
        let (st, _) = s.try_query(b);
        assert_eq!(st, S::Unsupported);
        let msg = last_error();
        assert!(
            msg.contains(&a.to_string()) && msg.contains(&b.to_string()),
            "{msg}"
        );
        ok(unsafe { glcol_mesh_set_enabled(s.0, a, false) }, "disable");
        assert!(s.query(b).is_empty());
        // SAFETY: as above.
        unsafe { g.delete_buffer(host) };
    }
}
