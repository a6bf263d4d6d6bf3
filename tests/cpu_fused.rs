//! The CPU backend's query against the step-by-step path (each step through a batch,
//! answered by the brute-force test adapter `BruteSelector`), on the real meshes of data/
//! (and spine_pelvis of ../shared/meshes where it is present) deforming over several
//! frames: the same contacts and the same tests and hits per step, exact (epsilon 0) and
//! with a viewing-volume depth, for the benchmarks' cases; and the heavy case's answers
//! against brute force with the independent oracle.

mod common;
use common::*;
use glcollide::internals::{BruteSelector, CpuSelector, Selector};
use glcollide::{Contact, MeshId, Positions, QueryStats, Scene, SceneConfig};

fn scene(epsilon: f32, leaf: u32, fused: bool) -> Scene {
    let sel: Box<dyn Selector> = if fused {
        Box::new(CpuSelector::new())
    } else {
        Box::new(BruteSelector)
    };
    let config = SceneConfig {
        epsilon,
        max_polygons_per_box: leaf,
        ..SceneConfig::default()
    };
    Scene::with_selector(config, sel).unwrap()
}

/// Meshes moved frame by frame: `frames[f][m]` holds mesh `m`'s positions in frame `f`.
struct Case {
    name: String,
    meshes: Vec<TestMesh>,
    frames: Vec<Vec<Vec<[f32; 3]>>>,
    extent: f32,
}

fn extent(p: &[[f32; 3]]) -> f32 {
    let (lo, hi) = bounds(p);
    (0..3).map(|k| hi[k] - lo[k]).fold(0.0, f32::max)
}

/// Two organs that overlap at rest, deforming with opposite warps (benches/frame.rs).
fn organ_case(a: &str, b: &str, frames: usize) -> Case {
    let (ma, mb) = (
        TestMesh::from_obj(&shared_mesh(a)),
        TestMesh::from_obj(&shared_mesh(b)),
    );
    let e = extent(&ma.pos);
    let frames = (0..frames)
        .map(|f| {
            let t = f as f32 * 0.1;
            vec![
                wave(&ma.pos, 0.004 * e, 8.0 / e, t),
                wave(&mb.pos, -0.004 * e, 8.0 / e, t),
            ]
        })
        .collect();
    Case {
        name: format!("{a} vs {b}"),
        meshes: vec![ma, mb],
        frames,
        extent: e,
    }
}

/// An instrument (the reference) pushed into a deforming organ (benches/frame.rs).
fn instrument_case(instrument: &str, organ: &str, frames: usize) -> Case {
    let (ins, org) = (
        TestMesh::from_obj(&shared_mesh(instrument)),
        TestMesh::from_obj(&shared_mesh(organ)),
    );
    let e = extent(&org.pos);
    let far = org.pos.iter().copied().fold(
        [f32::NEG_INFINITY; 3],
        |a, p| if p[0] > a[0] { p } else { a },
    );
    let scale = 0.15 * e / extent(&ins.pos);
    let frames = (0..frames)
        .map(|f| {
            let t = f as f32 * 0.4;
            let depth = (0.5 + 0.5 * (t * 3.0).sin()) * 0.02 * e;
            vec![
                place_scaled(&ins.pos, [far[0] - depth, far[1], far[2]], 1.3, scale),
                wave(&org.pos, 0.005 * e, 6.0 / e, t),
            ]
        })
        .collect();
    Case {
        name: format!("{instrument} vs {organ}"),
        meshes: vec![ins, org],
        frames,
        extent: e,
    }
}

/// Contacts with the other mesh named by its position in the case (ids differ by scene).
type Found = Vec<(usize, u32, u32)>;

/// Runs `case` on a scene; per frame, mesh 0's contacts and stats.
fn run(case: &Case, epsilon: f32, leaf: u32, fused: bool) -> Vec<(Found, QueryStats)> {
    let mut s = scene(epsilon, leaf, fused);
    let ids: Vec<MeshId> = case.meshes.iter().map(|m| add(&mut s, m)).collect();
    case.frames
        .iter()
        .map(|frame| {
            for (&id, p) in ids.iter().zip(frame) {
                s.update_positions(id, 0, Positions::from_points(p))
                    .unwrap();
            }
            let at = |id: MeshId| ids.iter().position(|&i| i == id).unwrap();
            let found = s
                .query(ids[0])
                .unwrap()
                .iter()
                .map(|c: &Contact| (at(c.other_mesh), c.reference_polygon, c.other_polygon))
                .collect();
            (found, s.stats())
        })
        .collect()
}

/// The fused query and the step path agree frame by frame on contacts and on every step's
/// tests and hits; returns the fused answers.
fn same_as_steps(case: &Case, epsilon_rel: f32, leaf: u32) -> Vec<Found> {
    let eps = epsilon_rel * case.extent;
    let fused = run(case, eps, leaf, true);
    let steps = run(case, eps, leaf, false);
    let mut out = Vec::new();
    for (f, ((a, sa), (b, sb))) in fused.into_iter().zip(steps).enumerate() {
        let what = format!("{}, eps {eps}, leaf {leaf}, frame {f}", case.name);
        assert_eq!(a.len(), b.len(), "{what}: contact counts differ");
        assert!(a == b, "{what}: contacts differ");
        assert_eq!(sa.tests, sb.tests, "{what}: tests per step differ");
        assert_eq!(sa.hits, sb.hits, "{what}: hits per step differ");
        assert_eq!(sa.hits[4], a.len(), "{what}");
        out.push(a);
    }
    out
}

#[test]
fn heavy_case_fused_equals_steps_and_brute_force() {
    let case = organ_case("colon", "small_intestine", 2);
    let exact = same_as_steps(&case, 0.0, 0);
    assert!(exact[0].len() > 500, "{} contacts", exact[0].len());
    // Frame 0 against the oracle.
    let (mut r, mut o) = (case.meshes[0].clone(), case.meshes[1].clone());
    r.pos = case.frames[0][0].clone();
    o.pos = case.frames[0][1].clone();
    let got: Vec<(u32, u32)> = exact[0].iter().map(|&(_, a, b)| (a, b)).collect();
    assert_eq!(got, brute_force_exact(&r, &o));
    // With a viewing-volume depth: a superset, extras within epsilon / 2.
    let within = same_as_steps(&case, 1e-3, 0);
    let eps = 1e-3 * case.extent;
    let got: Vec<(u32, u32)> = within[0].iter().map(|&(_, a, b)| (a, b)).collect();
    assert!(got.len() > exact[0].len());
    let exact_pairs: Vec<(u32, u32)> = exact[0].iter().map(|&(_, a, b)| (a, b)).collect();
    assert!(exact_pairs.iter().all(|p| got.binary_search(p).is_ok()));
    let band = brute_force_within(&r, &o, f64::from(eps) / 2.0 * (1.0 + 1e-9));
    assert!(got.iter().all(|p| band.binary_search(p).is_ok()));
    // Smaller leaves; very large ones (leaf pairs big enough to be swept in step 5).
    same_as_steps(&case, 0.0, 64);
    same_as_steps(&case, 0.0, 4096);
}

#[test]
fn instrument_cases_fused_equal_steps() {
    for (ins, org) in [
        ("scissors_blade", "gallbladder_glt"),
        ("scissors_blade", "spine_pelvis"),
        ("forceps_jaw", "colon"),
    ] {
        if org == "spine_pelvis" && !has_shared("meshes/spine_pelvis.obj") {
            continue;
        }
        let case = instrument_case(ins, org, 4);
        for leaf in [0, 32] {
            let found = same_as_steps(&case, 0.0, leaf);
            assert!(
                found.iter().any(|f| !f.is_empty()),
                "{ins} vs {org}: no contact"
            );
            same_as_steps(&case, 2e-3, leaf);
        }
    }
}

#[test]
fn several_meshes_and_quads_fused_equal_steps() {
    // A quad grid folded through two organs; the gallbladder disabled half way.
    let liver = TestMesh::from_obj(&shared_mesh("liver_glt"));
    let gall = TestMesh::from_obj(&shared_mesh("gallbladder_glt"));
    let (lo, hi) = bounds(&gall.pos);
    let e = extent(&liver.pos);
    let n = 40;
    let mut grid = TestMesh {
        pos: Vec::new(),
        idx: Vec::new(),
        k: 4,
    };
    for j in 0..=n {
        for i in 0..=n {
            let (u, v) = (i as f32 / n as f32, j as f32 / n as f32);
            grid.pos.push([
                lo[0] + (hi[0] - lo[0]) * u,
                (lo[1] + hi[1]) / 2.0 + 0.05 * e * (7.0 * u).sin() * (5.0 * v).cos(),
                lo[2] + (hi[2] - lo[2]) * v,
            ]);
        }
    }
    for j in 0..n {
        for i in 0..n {
            let id = |i: usize, j: usize| (j * (n + 1) + i) as u32;
            grid.idx
                .extend([id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)]);
        }
    }
    for eps in [0.0, 1e-3 * e] {
        let mut s = [scene(eps, 0, true), scene(eps, 0, false)];
        let ids: Vec<Vec<MeshId>> = s
            .iter_mut()
            .map(|s| [&grid, &liver, &gall].map(|m| add(s, m)).to_vec())
            .collect();
        let mut seen = 0;
        for f in 0..4 {
            let t = f as f32 * 0.3;
            let g = wave(&grid.pos, 0.01 * e, 6.0 / e, t);
            let l = wave(&liver.pos, 0.004 * e, 8.0 / e, t);
            let mut answers = Vec::new();
            for (s, ids) in s.iter_mut().zip(&ids) {
                s.update_positions(ids[0], 0, Positions::from_points(&g))
                    .unwrap();
                s.update_positions(ids[1], 0, Positions::from_points(&l))
                    .unwrap();
                s.set_enabled(ids[2], f < 2).unwrap();
                for reference in 0..3 {
                    let at = |id: MeshId| ids.iter().position(|&i| i == id).unwrap();
                    let c: Found = s
                        .query(ids[reference])
                        .unwrap()
                        .iter()
                        .map(|c| (at(c.other_mesh), c.reference_polygon, c.other_polygon))
                        .collect();
                    answers.push((c, s.stats()));
                }
            }
            let (fused, steps) = answers.split_at(3);
            for (r, (a, b)) in fused.iter().zip(steps).enumerate() {
                assert!(
                    a.0 == b.0,
                    "eps {eps}, frame {f}, reference {r}: contacts differ"
                );
                assert_eq!(a.1.tests, b.1.tests, "eps {eps}, frame {f}, reference {r}");
                assert_eq!(a.1.hits, b.1.hits, "eps {eps}, frame {f}, reference {r}");
                seen += a.0.len();
            }
        }
        assert!(seen > 0);
    }
}

/// A needle (a 1e-10 edge next to a right angle) and a triangle 1.1e-7 past its tip
/// (found by review): the CPU engine (lanes, first-stage rejection, clipping) and the
/// brute-force step answerer agree with either mesh as the reference; with the needle as
/// the reference, also with the exact answer (the other misses its volume, which once kept
/// a sliver past its tip).
#[test]
fn needle_tip_cpu_equals_brute_force() {
    let a: [[f64; 3]; 3] = [
        [0.0, 0.0, 0.0],
        [
            -4.016898272340974e-11,
            -2.6028002669820083e-11,
            -8.780088461834978e-11,
        ],
        [-0.6565284132957458, 0.7502625584602356, 0.07795185595750809],
    ];
    let b: [[f64; 3]; 3] = [
        [-0.6400055289268494, 0.7659923434257507, 0.06572958081960678],
        [-0.6660141944885254, 0.7412342429161072, 0.08496793359518051],
        [-0.40299293398857117, 0.8378798365592957, 0.3872389793395996],
    ];
    let eps = (2.0 * 1.0726893320679665e-2f64) as f32;
    let f = |t: &[[f64; 3]; 3]| t.map(|p| p.map(|x| x as f32)).to_vec();
    for reference_is_a in [true, false] {
        let count = |fused: bool| {
            let mut s = scene(eps, 0, fused);
            let ra = s
                .create_mesh(Positions::from_points(&f(&a)), &[0, 1, 2], 3)
                .unwrap();
            let rb = s
                .create_mesh(Positions::from_points(&f(&b)), &[0, 1, 2], 3)
                .unwrap();
            let r = if reference_is_a { ra } else { rb };
            s.query(r).unwrap().len()
        };
        let (cpu, brute) = (count(true), count(false));
        assert_eq!(cpu, brute, "reference a: {reference_is_a}");
        if reference_is_a {
            assert_eq!(cpu, 0);
        }
    }
}
