//! Rigid placement (`Scene::set_transform`, `glcol_mesh_set_transform`): every query answers
//! for the double world positions `m * (x, y, z, 1)`.
//!
//! - With a matrix whose world positions are `f32` values (axis turns, power-of-two scales,
//!   integer translations of a mesh on a grid; checked), every answer (`query`,
//!   `query_all` with self-collision, contact geometry, epsilon 0 and a band, 1 and 2
//!   threads, the step-by-step engine, the GL backends) equals the answer for a scene given
//!   those world positions as vertices.
//! - With a random rotation (world positions that are not floats), the answer equals a
//!   brute-force exact reference computed on the double world positions with big-integer
//!   arithmetic (no code shared with the library), and the band's answer holds it and stays
//!   within epsilon / 2.
//! - Bad matrices and updates that would overflow change nothing.

mod common;

use common::backends::SafeScene;
use common::exact::{exact_triangles_meet, random_rotation, world, M};
use common::{has_shared, shared_mesh, Rng, TestMesh};
use glcollide::internals::contact::ContactGeometry;
use glcollide::{ErrorKind, MeshId, Pair, Positions, Scene, SceneConfig};

/// The mesh's vertices at their world positions as `f32`, when every one is exactly a
/// float (else None).
fn world_as_f32(m: &M, t: &TestMesh) -> Option<TestMesh> {
    let pos: Option<Vec<[f32; 3]>> = t
        .pos
        .iter()
        .map(|p| {
            let w = world(m, p);
            let f = w.map(|x| x as f32);
            (0..3).all(|k| f[k] as f64 == w[k]).then_some(f)
        })
        .collect();
    Some(TestMesh {
        pos: pos?,
        idx: t.idx.clone(),
        k: t.k,
    })
}

fn scene(epsilon: f32, threads: u32) -> Scene {
    Scene::new(SceneConfig {
        epsilon,
        threads,
        ..SceneConfig::default()
    })
    .unwrap()
}

fn add(s: &mut Scene, m: &TestMesh) -> MeshId {
    s.create_mesh(Positions::from_points(&m.pos), &m.idx, m.k)
        .unwrap()
}

fn teapot() -> TestMesh {
    TestMesh::from_obj(&shared_mesh("teapot"))
}

/// `t` with every coordinate rounded to a multiple of 2^-12 (so integer translations of
/// it stay floats).
fn on_grid(t: &TestMesh) -> TestMesh {
    TestMesh {
        pos: t
            .pos
            .iter()
            .map(|p| p.map(|x| (x * 4096.0).round() / 4096.0))
            .collect(),
        ..t.clone()
    }
}

/// Everything a scene answers about meshes `a` and `b`, with `b`'s own pairs on: both
/// reference queries, the whole-scene query, and each one's contact geometry. Mesh ids
/// are replaced by their position (0 for a, 1 for b).
#[derive(Debug, PartialEq)]
struct Answers {
    query_a: Vec<(u32, u32, u32)>,
    query_b: Vec<(u32, u32, u32)>,
    all: Vec<(u32, u32, u32, u32)>,
    geometry_a: Vec<ContactGeometry>,
    geometry_all: Vec<ContactGeometry>,
}

fn answers(s: &mut Scene, a: MeshId, b: MeshId) -> Answers {
    s.set_self_collision(b, true).unwrap();
    let n = |id: MeshId| u32::from(id == b);
    let q = |s: &mut Scene, r: MeshId| -> Vec<(u32, u32, u32)> {
        s.query(r)
            .unwrap()
            .iter()
            .map(|c| (n(c.other_mesh), c.reference_polygon, c.other_polygon))
            .collect()
    };
    let query_b = q(s, b);
    let query_a = q(s, a);
    let geometry_a = s.contact_geometry().unwrap().to_vec();
    let all: Vec<(u32, u32, u32, u32)> = s
        .query_all()
        .unwrap()
        .iter()
        .map(|p: &Pair| (n(p.mesh_a), p.polygon_a, n(p.mesh_b), p.polygon_b))
        .collect();
    let geometry_all = s.contact_geometry().unwrap().to_vec();
    Answers {
        query_a,
        query_b,
        all,
        geometry_a,
        geometry_all,
    }
}

/// Matrices whose world positions of `t` are floats.
fn float_exact_matrices() -> Vec<(&'static str, M, bool)> {
    vec![
        // (name, matrix, needs the grid mesh)
        (
            "turn about z, scale 2",
            [0., -2., 0., 0., 2., 0., 0., 0., 0., 0., 2., 0.],
            false,
        ),
        (
            "axes permuted, one flipped",
            [0., 0., 1., 0., -1., 0., 0., 0., 0., 1., 0., 0.],
            false,
        ),
        (
            "integer translation",
            [1., 0., 0., 3., 0., 1., 0., -2., 0., 0., 1., 1.],
            true,
        ),
        (
            "turn and translation",
            [0., 1., 0., 1., 0., 0., -1., 0., 1., 0., 0., -1.],
            true,
        ),
    ]
}

#[test]
fn a_transform_answers_as_the_same_world_positions_given_as_vertices() {
    let raw = teapot();
    let grid = on_grid(&raw);
    for (name, m, needs_grid) in float_exact_matrices() {
        let t = if needs_grid { &grid } else { &raw };
        let moved = world_as_f32(&m, t).unwrap_or_else(|| panic!("{name}: not floats"));
        // The unplaced mesh in the same frame as the placed one meets it a lot.
        let extent = 6.5f32;
        for epsilon in [0.0, 1e-3 * extent] {
            for threads in [1, 2] {
                let mut placed = scene(epsilon, threads);
                let a = add(&mut placed, t);
                let b = add(&mut placed, t);
                placed.set_transform(b, Some(&m)).unwrap();
                assert_eq!(placed.mesh(b).unwrap().transform(), Some(&m));
                let mut given = scene(epsilon, threads);
                let a2 = add(&mut given, t);
                let b2 = add(&mut given, &moved);
                let (x, y) = (answers(&mut placed, a, b), answers(&mut given, a2, b2));
                assert!(!x.query_a.is_empty(), "{name}: no contacts");
                assert!(
                    x.all.iter().any(|p| p.0 == 1 && p.2 == 1),
                    "{name}: no self pairs"
                );
                assert_eq!(x, y, "{name}, epsilon {epsilon}, {threads} threads");
            }
        }
    }
}

#[test]
fn the_step_by_step_engine_sees_world_positions_too() {
    let t = teapot();
    let (_, m, _) = float_exact_matrices()[0];
    let moved = world_as_f32(&m, &t).unwrap();
    let mut placed = SafeScene::step_by_step(0.0, 0).0;
    let a = add(&mut placed, &t);
    let b = add(&mut placed, &t);
    placed.set_transform(b, Some(&m)).unwrap();
    let mut given = SafeScene::step_by_step(0.0, 0).0;
    let a2 = add(&mut given, &t);
    let b2 = add(&mut given, &moved);
    let x = placed.query(a).unwrap().len();
    assert!(x > 0);
    assert_eq!(answers(&mut placed, a, b), answers(&mut given, a2, b2));
}

#[test]
fn positions_updated_under_a_transform_stay_in_the_mesh_frame() {
    let t = on_grid(&teapot());
    let m: M = [0., 1., 0., 1., 0., 0., -1., 0., 1., 0., 0., -1.];
    let mut placed = scene(0.0, 1);
    let a = add(&mut placed, &t);
    let b = add(&mut placed, &t);
    placed.set_transform(b, Some(&m)).unwrap();
    // New local positions (still on the grid): the transform applies to them.
    let shifted = TestMesh {
        pos: t.pos.iter().map(|p| [p[0] + 0.25, p[1], p[2]]).collect(),
        ..t.clone()
    };
    placed
        .update_positions(b, 0, Positions::from_points(&shifted.pos))
        .unwrap();
    placed
        .update_positions(b, 10, Positions::from_points(&t.pos[10..50]))
        .unwrap();
    let mut expect = shifted.clone();
    expect.pos[10..50].copy_from_slice(&t.pos[10..50]);
    let mut given = scene(0.0, 1);
    let a2 = add(&mut given, &t);
    let b2 = add(&mut given, &world_as_f32(&m, &expect).unwrap());
    assert_eq!(answers(&mut placed, a, b), answers(&mut given, a2, b2));
    // Back to the identity: the local positions again.
    placed.set_transform(b, None).unwrap();
    assert_eq!(placed.mesh(b).unwrap().transform(), None);
    let mut local = scene(0.0, 1);
    let a3 = add(&mut local, &t);
    let b3 = add(&mut local, &expect);
    assert_eq!(answers(&mut placed, a, b), answers(&mut local, a3, b3));
}

/// Triangles of polygon `i` of `t` at world positions under `m` (None: the identity).
fn world_triangle(t: &TestMesh, m: Option<&M>, i: usize) -> [[f64; 3]; 3] {
    let v = |j: usize| {
        let p = &t.pos[t.idx[i * 3 + j] as usize];
        match m {
            Some(m) => world(m, p),
            None => p.map(f64::from),
        }
    };
    [v(0), v(1), v(2)]
}

fn bbox(t: &[[f64; 3]; 3]) -> ([f64; 3], [f64; 3]) {
    let lo = [0, 1, 2].map(|k| t.iter().map(|p| p[k]).fold(f64::INFINITY, f64::min));
    let hi = [0, 1, 2].map(|k| t.iter().map(|p| p[k]).fold(f64::NEG_INFINITY, f64::max));
    (lo, hi)
}

/// Every (polygon of a, polygon of b) whose closed triangles meet, exactly, by brute force
/// over the pairs whose exact double boxes overlap.
fn brute_exact(a: &TestMesh, ma: Option<&M>, b: &TestMesh, mb: Option<&M>) -> Vec<(u32, u32)> {
    let ta: Vec<_> = (0..a.polygons())
        .map(|i| world_triangle(a, ma, i))
        .collect();
    let tb: Vec<_> = (0..b.polygons())
        .map(|i| world_triangle(b, mb, i))
        .collect();
    let bb: Vec<_> = tb.iter().map(bbox).collect();
    let mut out = Vec::new();
    for (i, t) in ta.iter().enumerate() {
        let (lo, hi) = bbox(t);
        for (j, u) in tb.iter().enumerate() {
            let (l2, h2) = bb[j];
            if (0..3).all(|k| l2[k] <= hi[k] && lo[k] <= h2[k]) && exact_triangles_meet(t, u) {
                out.push((i as u32, j as u32));
            }
        }
    }
    out
}

#[test]
fn the_big_integer_reference_agrees_with_the_float_oracle_on_floats() {
    let t = teapot();
    let (_, m, _) = float_exact_matrices()[0];
    let moved = world_as_f32(&m, &t).unwrap();
    let want = common::brute_force_exact(&t, &moved);
    assert!(!want.is_empty());
    assert_eq!(brute_exact(&t, None, &t, Some(&m)), want);
}

#[test]
fn a_random_rotation_answers_the_exact_world_positions() {
    let pot = teapot();
    let jaw = TestMesh::from_obj(&shared_mesh("forceps_jaw"));
    let (lo, hi) = common::bounds(&jaw.pos);
    let c = [0, 1, 2].map(|k| (lo[k] + hi[k]) as f64 / 2.0);
    let mut r = Rng(0x5eed_1234);
    let mut total = 0;
    for round in 0..3 {
        // The jaw, centred, scaled to ~3 units, turned at random, placed at a teapot vertex.
        let at = pot.pos[(r.next_u64() % pot.pos.len() as u64) as usize].map(f64::from);
        let mut m = random_rotation(&mut r, 0.15, at);
        for i in 0..3 {
            // Centre first: t' = t - R s c.
            m[i * 4 + 3] -= (0..3).map(|j| m[i * 4 + j] * c[j]).sum::<f64>();
        }
        assert!(
            world_as_f32(&m, &jaw).is_none(),
            "a rotation that happens to be exact"
        );
        let want = brute_exact(&pot, None, &jaw, Some(&m));
        total += want.len();
        for threads in [1, 2] {
            let mut s = scene(0.0, threads);
            let a = add(&mut s, &pot);
            let b = add(&mut s, &jaw);
            s.set_transform(b, Some(&m)).unwrap();
            let got: Vec<(u32, u32)> = s
                .query(a)
                .unwrap()
                .iter()
                .map(|c| (c.reference_polygon, c.other_polygon))
                .collect();
            assert_eq!(got, want, "round {round}, {threads} threads");
            let mut flipped: Vec<(u32, u32)> = s
                .query(b)
                .unwrap()
                .iter()
                .map(|c| (c.other_polygon, c.reference_polygon))
                .collect();
            flipped.sort_unstable();
            assert_eq!(flipped, want);
            let all: Vec<(u32, u32)> = s
                .query_all()
                .unwrap()
                .iter()
                .map(|p| (p.polygon_a, p.polygon_b))
                .collect();
            assert_eq!(all, want);
            // Contact geometry of world positions: its points lie near both triangles.
            let g = s.contact_geometry().unwrap().to_vec();
            for (p, g) in all.iter().zip(&g) {
                assert!(g.intersecting, "{p:?}: {g:?}");
                let ta = world_triangle(&pot, None, p.0 as usize);
                let tb = world_triangle(&jaw, Some(&m), p.1 as usize);
                let (l1, h1) = bbox(&ta);
                let (l2, h2) = bbox(&tb);
                for q in [g.point_a, g.point_b] {
                    for k in 0..3 {
                        let tol = 1e-9;
                        assert!(q[k] >= l1[k].max(l2[k]) - tol && q[k] <= h1[k].min(h2[k]) + tol);
                    }
                }
            }
            // The step-by-step engine too.
            let mut steps = SafeScene::step_by_step(0.0, 0).0;
            let a2 = add(&mut steps, &pot);
            let b2 = add(&mut steps, &jaw);
            steps.set_transform(b2, Some(&m)).unwrap();
            let got2: Vec<(u32, u32)> = steps
                .query(a2)
                .unwrap()
                .iter()
                .map(|c| (c.reference_polygon, c.other_polygon))
                .collect();
            assert_eq!(got2, want);
            // A band: a superset, its extras within epsilon / 2.
            let epsilon = 0.01f32;
            let mut band = scene(epsilon, threads);
            let a3 = add(&mut band, &pot);
            let b3 = add(&mut band, &jaw);
            band.set_transform(b3, Some(&m)).unwrap();
            let got3: Vec<(u32, u32)> = band
                .query(a3)
                .unwrap()
                .iter()
                .map(|c| (c.reference_polygon, c.other_polygon))
                .collect();
            assert!(want.iter().all(|p| got3.binary_search(p).is_ok()));
            assert!(got3.len() > want.len());
            for p in &got3 {
                let (ta, tb) = (
                    world_triangle(&pot, None, p.0 as usize),
                    world_triangle(&jaw, Some(&m), p.1 as usize),
                );
                let d = if exact_triangles_meet(&ta, &tb) {
                    0.0
                } else {
                    common::oracle::apart_distance(&ta, &tb)
                };
                assert!(d <= epsilon as f64 / 2.0 * (1.0 + 1e-9), "{p:?} at {d}");
            }
        }
    }
    assert!(total > 20, "the jaw barely touches the pot: {total} pairs");
}

// ---------------------------------------------------------------------------------------
// A placed collinear quad (contact_check's "quads degenerate vs quads, placed" pair 437).

/// A C99 hex float (`-0x1.8p-3`, `0`), exactly.
fn hex(s: &str) -> f64 {
    let (neg, s) = s.strip_prefix('-').map_or((false, s), |r| (true, r));
    let Some(s) = s.strip_prefix("0x") else {
        return s.parse().unwrap();
    };
    let (mant, exp) = s.split_once('p').unwrap_or((s, "0"));
    let (int, frac) = mant.split_once('.').unwrap_or((mant, ""));
    let digits = format!("{int}{frac}");
    let m = u64::from_str_radix(&digits, 16).unwrap();
    let e = exp.parse::<i32>().unwrap() - 4 * frac.len() as i32;
    let v = m as f64 * 2f64.powi(e); // exact: m below 2^53, no subnormals here
    if neg {
        -v
    } else {
        v
    }
}

fn hexes<const N: usize>(s: &str) -> [f64; N] {
    let v: Vec<f64> = s.split_whitespace().map(hex).collect();
    v.try_into().unwrap()
}

/// With the reference an all-collinear quad (a segment) placed by a rotation, its world
/// positions a near-collinear sliver, and the other a quad that crosses it: the pair
/// intersects exactly, so it is reported at epsilon 0 and at 0.05 (a polygon lies in its
/// own viewing volume), by `query` with either mesh as the reference and by `query_all`.
/// Variants: unplaced, the quad's first and second triangles alone (a triangle of three
/// collinear points), the other as a triangle. The exact answer is the big-integer one on
/// the double world positions.
#[test]
fn a_placed_collinear_quad_is_reported_in_a_band() {
    let m: M = hexes(
        "0x1.dc2e3b187bcep-4 0x1.52ba9ebc3cdfbp-1 0x1.7b4b3249449abp-1 0 \
         0x1.73d089d388c1fp-1 0x1.cf11e5fc0a366p-2 -0x1.091f215cbfcfp-1 0 \
         -0x1.5aec10b390559p-1 0x1.3243d5c4186d8p-1 -0x1.b622d38db2e28p-2 0",
    );
    let a: [f64; 12] = hexes("0 0 0 0x1.b4e496p-1 0 0 0x1p+0 0 0 0x1.026f88p-1 0 0");
    let b: [f64; 12] = hexes(
        "0x1.c39572p-2 -0x1.e0b198p-9 0x1.7f172p-6 0x1.57c8cap+0 -0x1.dc2564p-3 \
         0x1.06007cp-2 0x1.640988p+0 0x1.fc357p-5 -0x1.215f26p-2 0x1.0f5a9p+0 \
         0x1.f4c9a2p-2 -0x1.98a5f2p-2",
    );
    let pts = |v: &[f64; 12], which: &[usize]| -> Vec<[f32; 3]> {
        which
            .iter()
            .map(|&i| {
                let p = [v[3 * i], v[3 * i + 1], v[3 * i + 2]].map(|x| x as f32);
                assert_eq!(p.map(f64::from), [v[3 * i], v[3 * i + 1], v[3 * i + 2]]);
                p
            })
            .collect()
    };
    let mesh = |pos: Vec<[f32; 3]>| TestMesh {
        idx: (0..pos.len() as u32).collect(),
        k: pos.len(),
        pos,
    };
    // The polygon's triangles at its world positions, as the library makes a quad's.
    let tris = |t: &TestMesh, m: Option<&M>| -> Vec<[[f64; 3]; 3]> {
        let w = |i: usize| match m {
            Some(m) => world(m, &t.pos[i]),
            None => t.pos[i].map(f64::from),
        };
        if t.k == 3 {
            vec![[w(0), w(1), w(2)]]
        } else {
            vec![[w(0), w(1), w(2)], [w(0), w(2), w(3)]]
        }
    };
    let mut crossing = 0;
    for (name, wa, wb) in [
        ("quad vs quad", &[0, 1, 2, 3][..], &[0, 1, 2, 3][..]),
        ("first triangle vs quad", &[0, 1, 2][..], &[0, 1, 2, 3][..]),
        ("second triangle vs quad", &[0, 2, 3][..], &[0, 1, 2, 3][..]),
        ("quad vs triangle", &[0, 1, 2, 3][..], &[0, 1, 2][..]),
        ("quad vs triangle 023", &[0, 1, 2, 3][..], &[0, 2, 3][..]),
    ] {
        let (ta, tb) = (mesh(pts(&a, wa)), mesh(pts(&b, wb)));
        for placed in [true, false] {
            let mm = placed.then_some(&m);
            let want = tris(&ta, mm)
                .iter()
                .any(|t| tris(&tb, mm).iter().any(|u| exact_triangles_meet(t, u)));
            crossing += usize::from(want);
            for epsilon in [0.05, 0.0] {
                let mut s = scene(epsilon, 1);
                let (ia, ib) = (add(&mut s, &ta), add(&mut s, &tb));
                if placed {
                    s.set_transform(ia, Some(&m)).unwrap();
                    s.set_transform(ib, Some(&m)).unwrap();
                }
                let by_a = !s.query(ia).unwrap().is_empty();
                let by_b = !s.query(ib).unwrap().is_empty();
                let all = !s.query_all().unwrap().is_empty();
                let what = format!("{name}, placed {placed}, epsilon {epsilon}: exact {want}");
                if want || epsilon == 0.0 {
                    // Exact at epsilon 0; a superset of the exact answer in a band.
                    assert_eq!(
                        (by_a, by_b, all),
                        (want, want, want),
                        "{what}: (query a, query b, query_all)"
                    );
                }
                // query_all is the union of both ways round.
                assert!(all == (by_a || by_b), "{what}: {by_a} {by_b} {all}");
            }
        }
    }
    assert!(crossing >= 2, "only {crossing} variants cross");
}

// ---------------------------------------------------------------------------------------
// Bad input changes nothing.

#[test]
fn bad_matrices_and_overflowing_updates_change_nothing() {
    let t = teapot();
    let mut s = scene(0.0, 1);
    let a = add(&mut s, &t);
    let b = add(&mut s, &t);
    let good: M = [0., -2., 0., 0., 2., 0., 0., 0., 0., 0., 2., 0.];
    s.set_transform(b, Some(&good)).unwrap();
    let before = s.query(a).unwrap().to_vec();
    assert!(!before.is_empty());
    let root = s.mesh(b).unwrap().root();
    let check_unchanged = |s: &mut Scene| {
        assert_eq!(s.mesh(b).unwrap().transform(), Some(&good));
        assert_eq!(s.mesh(b).unwrap().root(), root);
        assert_eq!(s.query(a).unwrap(), &before[..]);
    };
    for (i, bad) in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY]
        .into_iter()
        .enumerate()
    {
        let mut m = good;
        m[3 + 4 * i] = bad;
        let e = s.set_transform(b, Some(&m)).unwrap_err();
        assert_eq!(e.kind, ErrorKind::NonFinite);
        assert!(
            e.message.contains(&format!("m[{}]", 3 + 4 * i)),
            "{}",
            e.message
        );
        check_unchanged(&mut s);
    }
    // Overflow: a huge scale, a huge translation, and one just past the float range.
    let big = |k: usize| t.pos.iter().fold(0f32, |a, p| a.max(p[k].abs())) as f64;
    let (xmax, ymax, zmax) = (big(0), big(1), big(2));
    for m in [
        [1e300, 0., 0., 0., 0., 1., 0., 0., 0., 0., 1., 0.],
        [1., 0., 0., 0., 0., 1., 0., 0., 0., 0., 1., 3.5e38],
        [1., 0., 0., 0., 0., 3.5e38 / ymax, 0., 0., 0., 0., 1., 0.],
        [1., 0., 0., 0., 0., 1., 0., 0., 0., 0., 1e38 / zmax, 3e38],
    ] {
        let e = s.set_transform(b, Some(&m)).unwrap_err();
        assert_eq!(e.kind, ErrorKind::NonFinite, "{m:?}");
        assert!(e.message.contains("float range"), "{}", e.message);
        check_unchanged(&mut s);
    }
    // Unknown mesh: refused, nothing changes.
    let e = s.set_transform(0, Some(&good)).unwrap_err();
    assert_eq!(e.kind, ErrorKind::UnknownMesh);
    check_unchanged(&mut s);
    // Just inside the range is accepted.
    let edge = 3.0e38 / xmax;
    let mut s2 = scene(0.0, 1);
    let c = add(&mut s2, &t);
    s2.set_transform(c, Some(&[edge, 0., 0., 0., 0., 1., 0., 0., 0., 0., 1., 0.]))
        .unwrap();
    let r = s2.mesh(c).unwrap().root();
    assert!(r.max[0].is_finite() && r.min[0].is_finite());
    // Updates whose world positions would overflow are refused, whole or partial.
    let mut far = t.pos.clone();
    far[7][0] = (xmax * 2.0) as f32;
    let e = s2
        .update_positions(c, 0, Positions::from_points(&far))
        .unwrap_err();
    assert_eq!(e.kind, ErrorKind::NonFinite);
    let e = s2
        .update_positions(c, 5, Positions::from_points(&far[5..9]))
        .unwrap_err();
    assert_eq!(e.kind, ErrorKind::NonFinite);
    assert_eq!(s2.mesh(c).unwrap().root(), r);
    assert_eq!(
        s2.mesh(c).unwrap().vertex_position(7),
        Some(t.pos[7]),
        "an undone partial update"
    );
    // A partial update that moves the farthest vertex inwards: the quick bound (old box
    // and new positions) allows it too.
    let (imax, _) = t
        .pos
        .iter()
        .enumerate()
        .max_by(|x, y| x.1[0].abs().total_cmp(&y.1[0].abs()))
        .unwrap();
    s2.update_positions(c, imax, Positions::from_points(&[[0.0, 0.0, 0.0]]))
        .unwrap();
    // NULL is the identity again.
    s.set_transform(b, None).unwrap();
    assert_eq!(s.mesh(b).unwrap().transform(), None);
    // The identity matrix is no placement at all.
    s.set_transform(b, Some(&[1., 0., 0., 0., 0., 1., 0., 0., 0., 0., 1., 0.]))
        .unwrap();
    assert_eq!(s.mesh(b).unwrap().transform(), None);
}

#[test]
fn an_update_is_checked_against_the_exact_box_when_the_quick_bound_fails() {
    // World x = k (x + y): vertex v sits at x = far, the rest of the teapot within 4.
    let mut t = teapot();
    let far = 1000.0f32;
    let v = t.idx[0] as usize;
    let w = t.idx.iter().map(|&i| i as usize).find(|&i| i != v).unwrap();
    t.pos[v] = [far, 0.0, 0.0];
    let mut s = scene(0.0, 1);
    let id = add(&mut s, &t);
    let k = 3.0e38 / far as f64;
    s.set_transform(id, Some(&[k, k, 0., 0., 0., 1., 0., 0., 0., 0., 1., 0.]))
        .unwrap();
    let (lo, hi) = (v.min(w), v.max(w));
    let mut upd: Vec<[f32; 3]> = t.pos[lo..=hi].to_vec();
    // v moves in, w out to y = 1.2 far: 3.6e38 after the update, refused (exactly).
    upd[v - lo] = [0.0, 0.0, 0.0];
    upd[w - lo] = [0.0, far * 1.2, 0.0];
    let e = s
        .update_positions(id, lo, Positions::from_points(&upd))
        .unwrap_err();
    assert_eq!(e.kind, ErrorKind::NonFinite);
    assert_eq!(
        s.mesh(id).unwrap().vertex_position(v),
        Some([far, 0.0, 0.0])
    );
    assert_eq!(s.mesh(id).unwrap().vertex_position(w), Some(t.pos[w]));
    // w only to y = far: the old box joined with the new positions (x and y both far)
    // would reach 6e38, the mesh after the update reaches 3.0e38 (plus a little): accepted.
    upd[w - lo] = [0.0, far, 0.0];
    s.update_positions(id, lo, Positions::from_points(&upd))
        .unwrap();
    assert_eq!(
        s.mesh(id).unwrap().vertex_position(w),
        Some([0.0, far, 0.0])
    );
    assert!(s.mesh(id).unwrap().root().max[0] <= f32::MAX);
}

// ---------------------------------------------------------------------------------------
// Cost.

/// `set_transform` on a ~100k-triangle mesh against a full position update of it (which
/// it replaces for an instrument that only moves). Prints a table; asserts nothing about
/// time. `cargo test --release --test transform -- --ignored --nocapture set_transform_cost`
#[test]
#[ignore]
fn set_transform_cost() {
    if !has_shared("meshes/colon_100k.obj") {
        return;
    }
    let t = TestMesh::from_obj(&shared_mesh("colon_100k"));
    let mut s = scene(0.0, 1);
    let id = add(&mut s, &t);
    let leaves = s.mesh(id).unwrap().leaf_count();
    let mut r = Rng(7);
    let ms: Vec<M> = (0..1000)
        .map(|_| {
            let t = [r.f(), r.f(), r.f()];
            random_rotation(&mut r, 1.0, t)
        })
        .collect();
    let reps = 5;
    let mut best = f64::INFINITY;
    for _ in 0..reps {
        let t0 = std::time::Instant::now();
        for m in &ms {
            s.set_transform(id, Some(m)).unwrap();
        }
        best = best.min(t0.elapsed().as_secs_f64() / ms.len() as f64);
    }
    let mut upd = f64::INFINITY;
    for _ in 0..reps {
        let t0 = std::time::Instant::now();
        s.update_positions(id, 0, Positions::from_points(&t.pos))
            .unwrap();
        upd = upd.min(t0.elapsed().as_secs_f64());
    }
    println!("| mesh | triangles | leaves | set_transform | update_positions (all vertices) |");
    println!("|---|---:|---:|---:|---:|");
    println!(
        "| colon_100k | {} | {leaves} | {:.2} us | {:.1} us |",
        t.polygons(),
        best * 1e6,
        upd * 1e6
    );
}

// ---------------------------------------------------------------------------------------
// The GL backends (C API, headless EGL context): pairs with a placed mesh are answered by
// the CPU engine, the others by the GL; the answer is the CPU backend's.

mod gl {
    use super::*;
    use common::backends::gl_support::{self, host_buffer, Ctx, Profile};
    use common::backends::{ok, FfiScene, TestScene};
    use glcollide::ffi::*;

    fn all(s: &FfiScene) -> Vec<(u32, u32, u32, u32)> {
        let (mut p, mut n) = (std::ptr::null(), 0usize);
        ok(
            unsafe { glcol_query_all(s.0, &mut p, &mut n) },
            "glcol_query_all",
        );
        if n == 0 {
            return Vec::new();
        }
        unsafe { std::slice::from_raw_parts(p, n) }
            .iter()
            .map(|p| (p.mesh_a, p.polygon_a, p.mesh_b, p.polygon_b))
            .collect()
    }

    /// Meshes a (unplaced), b (placed by `m`, self-collision on), c (an unplaced copy of
    /// a, moved): every query's answer, with ids as positions.
    fn run(s: &mut FfiScene, t: &TestMesh, m: &M) -> Vec<Vec<(u32, u32, u32, u32)>> {
        let a = s.add(t);
        let b = s.add(t);
        let moved = TestMesh {
            pos: t
                .pos
                .iter()
                .map(|p| [p[0] + 0.5, p[1] + 0.25, p[2]])
                .collect(),
            ..t.clone()
        };
        let c = s.add(&moved);
        ok(
            unsafe { glcol_mesh_set_transform(s.0, b, m.as_ptr()) },
            "glcol_mesh_set_transform",
        );
        ok(
            unsafe { glcol_mesh_set_self_collision(s.0, b, true) },
            "self-collision",
        );
        let n = |id: u32| [a, b, c].iter().position(|&x| x == id).unwrap() as u32;
        let mut out: Vec<Vec<(u32, u32, u32, u32)>> = [a, b, c]
            .iter()
            .map(|&r| {
                s.query(r)
                    .iter()
                    .map(|h| (n(r), h.1, n(h.0), h.2))
                    .collect()
            })
            .collect();
        out.push(
            all(s)
                .into_iter()
                .map(|p| (n(p.0), p.1, n(p.2), p.3))
                .collect(),
        );
        out
    }

    #[test]
    fn gl_backends_answer_for_world_positions() {
        let _ctx = Ctx::new(Profile::Compat);
        let t = teapot();
        let (_, m, _) = float_exact_matrices()[0];
        for epsilon in [0.0, 0.01] {
            let mut cpu = FfiScene::new(GlcolBackend::Cpu, epsilon, 0);
            let want = run(&mut cpu, &t, &m);
            assert!(want.iter().all(|v| !v.is_empty()));
            for backend in [GlcolBackend::GlSelect, GlcolBackend::GlCompute] {
                let mut s = FfiScene(gl_support::scene(backend, epsilon, 0));
                let got = run(&mut s, &t, &m);
                assert_eq!(got, want, "{backend:?}, epsilon {epsilon}");
            }
        }
    }

    /// A mesh reading its positions from a host GL buffer cannot be placed, a placed mesh
    /// cannot be bound, and a query that would need both on the CPU is refused: each with
    /// UNSUPPORTED and a message, changing nothing.
    #[test]
    fn placement_and_gl_buffers_do_not_mix() {
        use glow::HasContext;
        let ctx = Ctx::new(Profile::Core);
        let g = ctx.glow();
        let t = teapot();
        let (_, m, _) = float_exact_matrices()[0];
        let mut s = FfiScene(gl_support::scene(GlcolBackend::GlCompute, 0.001, 0));
        let a = s.add(&t);
        let b = s.add(&t);
        let host = host_buffer(&g, &t.pos);
        ok(
            unsafe { glcol_mesh_bind_gl_buffer(s.0, a, host.0.get(), 0, 12) },
            "bind",
        );
        let before = s.query(b);
        assert!(!before.is_empty());
        assert_eq!(
            unsafe { glcol_mesh_set_transform(s.0, a, m.as_ptr()) },
            GlcolStatus::Unsupported
        );
        assert!(common::backends::last_error().contains("GL buffer"));
        // The identity is no placement: accepted.
        ok(
            unsafe { glcol_mesh_set_transform(s.0, a, std::ptr::null()) },
            "identity on a bound mesh",
        );
        assert_eq!(s.query(b), before);
        // b placed: a query pairing it with the bound a is refused, naming both.
        ok(
            unsafe { glcol_mesh_set_transform(s.0, b, m.as_ptr()) },
            "place b",
        );
        let (status, _) = s.try_query(b);
        assert_eq!(status, GlcolStatus::Unsupported);
        let msg = common::backends::last_error();
        assert!(
            msg.contains(&a.to_string()) && msg.contains(&b.to_string()),
            "{msg}"
        );
        let (mut p, mut n) = (std::ptr::null(), 0usize);
        assert_eq!(
            unsafe { glcol_query_all(s.0, &mut p, &mut n) },
            GlcolStatus::Unsupported
        );
        // A placed mesh cannot be bound.
        assert_eq!(
            unsafe { glcol_mesh_bind_gl_buffer(s.0, b, host.0.get(), 0, 12) },
            GlcolStatus::Unsupported
        );
        assert!(common::backends::last_error().contains("transform"));
        // Back to the identity: the query answers as before.
        ok(
            unsafe { glcol_mesh_set_transform(s.0, b, std::ptr::null()) },
            "unplace b",
        );
        assert_eq!(s.query(b), before);
        drop(s);
        // SAFETY: as above.
        unsafe { g.delete_buffer(host) };
    }
}
