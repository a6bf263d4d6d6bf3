//! Continuous detection (`Scene::query_continuous`, `glcol_query_continuous`):
//!
//! - what discrete frames miss: a blade through a membrane between two frames, a hinge
//!   folding through itself (adjacent triangles), with the exact times known;
//! - against the discrete exact answers of the step's two ends: the pairs flagged AT_START
//!   are exactly `query_all`'s at the start, and every pair `query_all` reports at the end
//!   is reported (real meshes, a real deformation);
//! - the public ground truth of three real simulation steps (`../shared/meshes/sim/ccd`):
//!   every true primitive contact, lifted to the polygons holding it, is reported;
//! - the same bytes for every thread count; filters and disabled meshes; the C entry point
//!   (NULL pointers, the band refused with a message, the answer the Rust one).
//!
//! The exactness against an independent rational reference (translating polygons and
//! scenes, degenerate ones included) is in `src/geom/ccd/tests/polygons.rs`.

mod common;

use common::has_shared;
use glcollide::ffi::*;
use glcollide::{ErrorKind, Impact, ImpactFeature, MeshId, Positions, Scene, SceneConfig};
use std::collections::{BTreeSet, HashMap};

fn scene(threads: u32) -> Scene {
    Scene::new(SceneConfig {
        threads,
        ..SceneConfig::default()
    })
    .unwrap()
}

/// `[lo, hi]` holds the reported time: never late, at most 2^-20 early.
fn assert_toi(i: &Impact, exact: f64) {
    assert!(
        i.toi <= exact && i.toi >= exact - 2f64.powi(-20),
        "toi {} for an exact first meeting at {exact}",
        i.toi
    );
    assert!(!i.at_start);
}

#[test]
fn a_blade_through_a_membrane_between_two_frames() {
    let mut s = scene(1);
    // A membrane (a quad) at z = 0, and a blade (a triangle) from z = 1 to z = -1 in one
    // step: both frames are clean, the step crosses it at t = 1/2.
    let membrane = s
        .create_mesh(
            Positions::from_points(&[[0., 0., 0.], [1., 0., 0.], [1., 1., 0.], [0., 1., 0.]]),
            &[0, 1, 2, 3],
            4,
        )
        .unwrap();
    let up = [[0.4, 0.4, 1.0], [0.6, 0.4, 1.0], [0.5, 0.6, 1.5]];
    let blade = s
        .create_mesh(Positions::from_points(&up), &[0, 1, 2], 3)
        .unwrap();
    let down = up.map(|p| [p[0], p[1], p[2] - 2.0]);
    assert!(s.query_all().unwrap().is_empty(), "clean at the start");
    s.set_target_positions(blade, 0, Positions::from_points(&down))
        .unwrap();
    let hits = s.query_continuous().unwrap().to_vec();
    assert_eq!(hits.len(), 1, "{hits:?}");
    assert_eq!((hits[0].mesh_a, hits[0].mesh_b), (membrane, blade));
    assert_toi(&hits[0], 0.5);
    // The target is not committed: the discrete query still sees the start.
    assert!(s.query_all().unwrap().is_empty());
    s.update_positions(blade, 0, Positions::from_points(&down))
        .unwrap();
    assert!(s.query_all().unwrap().is_empty(), "clean at the end");
    // The update dropped the target: the scene stands still now.
    assert!(s.query_continuous().unwrap().is_empty());
    // The same through a target transform (an instrument that only moves).
    s.update_positions(blade, 0, Positions::from_points(&up))
        .unwrap();
    let m = [1., 0., 0., 0., 0., 1., 0., 0., 0., 0., 1., -2.];
    s.set_target_transform(blade, &m).unwrap();
    let hits = s.query_continuous().unwrap().to_vec();
    assert_eq!(hits.len(), 1);
    assert_toi(&hits[0], 0.5);
    // Disabled or filtered out: nothing, at no cost.
    s.set_enabled(membrane, false).unwrap();
    s.set_target_transform(blade, &m).unwrap();
    assert!(s.query_continuous().unwrap().is_empty());
    s.set_enabled(membrane, true).unwrap();
    s.set_filter(membrane, 1, 0).unwrap();
    s.set_target_transform(blade, &m).unwrap();
    assert!(s.query_continuous().unwrap().is_empty());
}

/// Two triangles sharing the edge (0,0,0)-(1,0,0): the first in z = 0 (y > 0), the second's
/// free vertex moving from `from` to `to`.
fn hinge(from: [f64; 3], to: [f64; 3]) -> Vec<Impact> {
    let mut s = scene(1);
    let p = [[0., 0., 0.], [1., 0., 0.], [0.5, 1., 0.], from];
    let m = s
        .create_mesh(Positions::from_points_f64(&p), &[0, 1, 2, 0, 1, 3], 3)
        .unwrap();
    s.set_self_collision(m, true).unwrap();
    s.set_target_positions_f64(m, 3, &[to]).unwrap();
    s.query_continuous().unwrap().to_vec()
}

#[test]
fn a_hinge_folding_through_itself() {
    // Folding through its neighbour (coplanar and overlapping at t = 1/2).
    let hits = hinge([0.5, 0.5, 1.0], [0.5, 0.5, -1.0]);
    assert_eq!(hits.len(), 1, "{hits:?}");
    assert_eq!((hits[0].polygon_a, hits[0].polygon_b), (0, 1));
    assert_toi(&hits[0], 0.5);
    // Opening the other way: in the plane at t = 1/2 only on the far side of the joint.
    assert!(hinge([0.5, -0.5, 1.0], [0.5, -0.5, -1.0]).is_empty());
    // Folding down onto the neighbour without passing (touching it at the end only).
    let hits = hinge([0.5, 0.5, 1.0], [0.5, 0.5, 0.0]);
    assert_eq!(hits.len(), 1);
    assert_toi(&hits[0], 1.0);
    // Standing still next to each other: adjacent, never reported.
    assert!(hinge([0.5, -0.5, 1.0], [0.5, -0.5, 1.0]).is_empty());
}

/// Reads an OBJ's vertices as doubles (the simulation frames hold exact doubles, which the
/// float OBJ reader would round) and its triangles.
fn obj_f64(path: &str) -> (Vec<[f64; 3]>, Vec<u32>) {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{path}: {e}"));
    let (mut v, mut f) = (Vec::new(), Vec::new());
    for line in text.lines() {
        let mut w = line.split_whitespace();
        match w.next() {
            Some("v") => {
                let x: Vec<f64> = w.take(3).map(|t| t.parse().unwrap()).collect();
                v.push([x[0], x[1], x[2]]);
            }
            Some("f") => {
                f.extend(w.map(|t| t.split('/').next().unwrap().parse::<u32>().unwrap() - 1))
            }
            _ => {}
        }
    }
    (v, f)
}

/// A simulation step of ../shared/meshes/sim: every part an f64 mesh at frame `n` with
/// frame `n + 1` as its target, self-collision on. Returns the scene, the ids and each
/// part's triangles.
fn sim_step(name: &str, n: u32, threads: u32) -> (Scene, Vec<MeshId>, Vec<Vec<u32>>) {
    let dir = format!("{}/../shared/meshes/sim/{name}", env!("CARGO_MANIFEST_DIR"));
    let mut s = scene(threads);
    let (mut ids, mut tris) = (Vec::new(), Vec::new());
    for part in 0.. {
        let at = |f: u32| format!("{dir}/frame{f}_part{part:02}.obj");
        if !std::path::Path::new(&at(n)).exists() {
            break;
        }
        let (p0, t) = obj_f64(&at(n));
        let (p1, t1) = obj_f64(&at(n + 1));
        assert_eq!(t, t1);
        let id = s
            .create_mesh(Positions::from_points_f64(&p0), &t, 3)
            .unwrap();
        s.set_self_collision(id, true).unwrap();
        s.set_target_positions_f64(id, 0, &p1).unwrap();
        ids.push(id);
        tris.push(t);
    }
    (s, ids, tris)
}

const STEPS: [(&str, u32); 3] = [
    ("cloth-funnel", 227),
    ("rod-twist", 3036),
    ("armadillo-rollers", 326),
];

/// Every true primitive contact of the ground truth's step, lifted to the polygons that
/// hold its features, is a reported pair (except where the two features share a vertex
/// of one part: no contact counts there).
#[test]
fn real_steps_report_every_true_primitive_contact() {
    if !has_shared("meshes/sim/ccd") {
        return;
    }
    for (name, n) in STEPS {
        let (mut s, ids, tris) = sim_step(name, n, 0);
        let found: BTreeSet<(MeshId, u32, MeshId, u32)> = s
            .query_continuous()
            .unwrap()
            .iter()
            .map(|i| (i.mesh_a, i.polygon_a, i.mesh_b, i.polygon_b))
            .collect();
        let st = s.continuous_stats();
        // Polygons of each part holding each vertex.
        let holding: Vec<HashMap<u32, Vec<u32>>> = tris
            .iter()
            .map(|t| {
                let mut h: HashMap<u32, Vec<u32>> = HashMap::new();
                for (p, c) in t.chunks(3).enumerate() {
                    for &v in c {
                        h.entry(v).or_default().push(p as u32);
                    }
                }
                h
            })
            .collect();
        let has = |part: usize, p: u32, v: u32| tris[part][3 * p as usize..][..3].contains(&v);
        let pair = |pa: usize, a: u32, pb: usize, b: u32| {
            let (x, y) = ((ids[pa], a), (ids[pb], b));
            let (x, y) = if x < y { (x, y) } else { (y, x) };
            (x.0, x.1, y.0, y.1)
        };
        let dir = format!(
            "{}/../shared/meshes/sim/ccd/{name}",
            env!("CARGO_MANIFEST_DIR")
        );
        let (mut checked, mut missing) = (0, Vec::new());
        for kind in ["vf", "ee"] {
            let text = std::fs::read_to_string(format!("{dir}/{n}{kind}_parts.tsv")).unwrap();
            for line in text.lines().filter(|l| !l.starts_with('#')) {
                let c: Vec<u32> = line
                    .split('\t')
                    .map(|x| x.trim().parse().unwrap())
                    .collect();
                if *c.last().unwrap() != 1 {
                    continue;
                }
                let mut want = Vec::new();
                if kind == "vf" {
                    let (pv, v, pf, f) = (c[0] as usize, c[1], c[2] as usize, c[3]);
                    if pv == pf && has(pf, f, v) {
                        continue;
                    }
                    for &p in &holding[pv][&v] {
                        if !(pv == pf && p == f) {
                            want.push(pair(pv, p, pf, f));
                        }
                    }
                } else {
                    let (pa, a, pb, b) = (c[0] as usize, [c[1], c[2]], c[3] as usize, [c[4], c[5]]);
                    if pa == pb && a.iter().any(|v| b.contains(v)) {
                        continue;
                    }
                    let with_edge = |part: usize, e: [u32; 2]| -> Vec<u32> {
                        holding[part][&e[0]]
                            .iter()
                            .copied()
                            .filter(|&p| has(part, p, e[1]))
                            .collect()
                    };
                    for p in with_edge(pa, a) {
                        for q in with_edge(pb, b) {
                            if !(pa == pb && p == q) {
                                want.push(pair(pa, p, pb, q));
                            }
                        }
                    }
                }
                for w in want {
                    checked += 1;
                    if !found.contains(&w) {
                        missing.push((kind, line.to_string(), w));
                    }
                }
            }
        }
        eprintln!(
            "{name}: {} pairs reported, {checked} lifted true contacts checked, {} missing; \
             {} leaf pairs, {} polygon pairs tested",
            found.len(),
            missing.len(),
            st.leaf_pairs,
            st.polygon_pairs
        );
        assert!(
            missing.is_empty(),
            "{name}: missing {:?}",
            &missing[..missing.len().min(5)]
        );
        assert!(checked > 0);
    }
}

/// The step's ends against the discrete exact query: AT_START pairs are exactly
/// `query_all`'s at the start; `query_all`'s at the end are all reported. On a real mesh
/// folding (bundled: a cloth-like sheet of the face mesh pushed through itself) and two
/// bodies (the bunny moved through the teapot), threads 1 and 2 the same bytes.
#[test]
fn the_step_holds_both_ends_discrete_answers() {
    let face = common::shared_mesh("face");
    let bunny = common::shared_mesh("bunny");
    let (lo, hi) = common::bounds(&face.positions);
    let c: [f32; 3] = std::array::from_fn(|k| (lo[k] + hi[k]) / 2.0);
    let size = (0..3).map(|k| hi[k] - lo[k]).fold(0.0, f32::max);
    // The face folded: points on one side of the middle plane pushed across it.
    let folded: Vec<[f32; 3]> = face
        .positions
        .iter()
        .map(|p| {
            let mut q = *p;
            if p[0] > c[0] {
                // Mirrored over the middle, onto the other half, a little in front.
                q[0] = c[0] - 0.9 * (p[0] - c[0]);
                q[2] += 0.03 * size;
            }
            q
        })
        .collect();
    let (blo, bhi) = common::bounds(&bunny.positions);
    let bsize = (0..3).map(|k| bhi[k] - blo[k]).fold(0.0, f32::max);
    let scale = 0.5 * size / bsize;
    let place = |p: &[f32; 3], dx: f32| -> [f32; 3] {
        std::array::from_fn(|k| (p[k] - blo[k]) * scale + lo[k] + if k == 0 { dx } else { 0.0 })
    };
    let b0: Vec<[f32; 3]> = bunny
        .positions
        .iter()
        .map(|p| place(p, -0.3 * size))
        .collect();
    let b1: Vec<[f32; 3]> = bunny
        .positions
        .iter()
        .map(|p| place(p, 0.2 * size))
        .collect();
    let mut answers = Vec::new();
    for threads in [1, 2] {
        let mut s = scene(threads);
        let f = s
            .create_mesh(Positions::from_points(&face.positions), &face.triangles, 3)
            .unwrap();
        let b = s
            .create_mesh(Positions::from_points(&b0), &bunny.triangles, 3)
            .unwrap();
        s.set_self_collision(f, true).unwrap();
        let start: BTreeSet<_> = s.query_all().unwrap().iter().copied().collect();
        s.set_target_positions(f, 0, Positions::from_points(&folded))
            .unwrap();
        s.set_target_positions(b, 0, Positions::from_points(&b1))
            .unwrap();
        let step = s.query_continuous().unwrap().to_vec();
        let key = |i: &Impact| (i.mesh_a, i.polygon_a, i.mesh_b, i.polygon_b);
        let at_start: BTreeSet<_> = step
            .iter()
            .filter(|i| i.at_start)
            .map(|i| glcollide::Pair {
                mesh_a: i.mesh_a,
                polygon_a: i.polygon_a,
                mesh_b: i.mesh_b,
                polygon_b: i.polygon_b,
            })
            .collect();
        assert_eq!(at_start, start, "AT_START vs query_all at the start");
        assert!(step
            .iter()
            .all(|i| (i.toi == 0.0) == i.at_start && (0.0..=1.0).contains(&i.toi)));
        assert!(
            step.windows(2).all(|w| key(&w[0]) < key(&w[1])),
            "sorted, once each"
        );
        s.update_positions(f, 0, Positions::from_points(&folded))
            .unwrap();
        s.update_positions(b, 0, Positions::from_points(&b1))
            .unwrap();
        let end = s.query_all().unwrap().to_vec();
        let all: BTreeSet<_> = step.iter().map(key).collect();
        let lost: Vec<_> = end
            .iter()
            .filter(|p| !all.contains(&(p.mesh_a, p.polygon_a, p.mesh_b, p.polygon_b)))
            .collect();
        assert!(
            lost.is_empty(),
            "pairs of the end not in the step: {lost:?}"
        );
        eprintln!(
            "threads {threads}: {} pairs in the step ({} at the start, {} at the end)",
            step.len(),
            start.len(),
            end.len()
        );
        assert!(end.len() > start.len() && step.len() > end.len());
        // Mesh ids differ between the scenes: compared as face = 0, bunny = 1.
        let rank = |id: MeshId| u32::from(id == b);
        answers.push(
            step.iter()
                .map(|i| {
                    let (a, _, c, _) = key(i);
                    (
                        (rank(a), i.polygon_a, rank(c), i.polygon_b),
                        i.toi.to_bits(),
                        i.at_start,
                    )
                })
                .collect::<Vec<_>>(),
        );
    }
    assert!(answers[0] == answers[1], "threads 1 and 2 differ");
}

#[test]
fn the_c_entry_point() {
    // SAFETY: valid pointers throughout; the scene is destroyed at the end.
    unsafe {
        let mut d = std::mem::zeroed::<GlcolSceneDesc>();
        glcol_scene_desc_init_sized(&mut d, std::mem::size_of::<GlcolSceneDesc>());
        d.threads = 1;
        let mut scene = std::ptr::null_mut();
        assert_eq!(glcol_scene_create(&d, &mut scene), GlcolStatus::Ok);
        let (mut out, mut n) = (std::ptr::null(), usize::MAX);
        assert_eq!(
            glcol_query_continuous(std::ptr::null_mut(), &mut out, &mut n),
            GlcolStatus::NullPointer
        );
        assert_eq!(
            glcol_query_continuous(scene, std::ptr::null_mut(), &mut n),
            GlcolStatus::NullPointer
        );
        assert_eq!(n, usize::MAX, "nothing written on failure");
        // The impact geometry: refused before a continuous query (nothing written).
        let (mut g, mut ng) = (std::ptr::null(), usize::MAX);
        assert_eq!(
            glcol_query_impact_geometry(scene, &mut g, &mut ng),
            GlcolStatus::InvalidArgument
        );
        assert_eq!(ng, usize::MAX);
        assert_eq!(
            glcol_query_continuous(scene, &mut out, &mut n),
            GlcolStatus::Ok
        );
        assert_eq!((out, n), (std::ptr::null(), 0));
        assert_eq!(
            glcol_query_impact_geometry(scene, std::ptr::null_mut(), &mut ng),
            GlcolStatus::NullPointer
        );
        assert_eq!(
            glcol_query_impact_geometry(scene, &mut g, &mut ng),
            GlcolStatus::Ok
        );
        assert_eq!((g, ng), (std::ptr::null(), 0));
        // A blade through a membrane: one impact, its geometry, then a target change makes
        // the geometry refuse until the next continuous query.
        let quad = [0f32, 0., 0., 1., 0., 0., 1., 1., 0., 0., 1., 0.];
        let tri = [0.4f32, 0.4, 1.0, 0.6, 0.4, 1.0, 0.5, 0.6, 1.5];
        let add = |p: &[f32], idx: &[u32], k: u32| {
            let mut md = std::mem::zeroed::<GlcolMeshDesc>();
            glcol_mesh_desc_init_sized(&mut md, std::mem::size_of::<GlcolMeshDesc>());
            md.positions = p.as_ptr();
            md.vertex_count = p.len() / 3;
            md.indices = idx.as_ptr();
            md.polygon_count = idx.len() / k as usize;
            md.vertices_per_polygon = k;
            let mut id = 0;
            assert_eq!(glcol_mesh_create(scene, &md, &mut id), GlcolStatus::Ok);
            id
        };
        let _membrane = add(&quad, &[0, 1, 2, 3], 4);
        let blade = add(&tri, &[0, 1, 2], 3);
        let m = [1., 0., 0., 0., 0., 1., 0., 0., 0., 0., 1., -2.];
        assert_eq!(
            glcol_mesh_set_target_transform(scene, blade, m.as_ptr()),
            GlcolStatus::Ok
        );
        assert_eq!(
            glcol_query_continuous(scene, &mut out, &mut n),
            GlcolStatus::Ok
        );
        assert_eq!(n, 1);
        let hit = *out;
        assert!(hit.toi <= 0.5 && hit.toi >= 0.5 - 2f64.powi(-20) && hit.flags == 0);
        assert_eq!(
            glcol_query_impact_geometry(scene, &mut g, &mut ng),
            GlcolStatus::Ok
        );
        assert_eq!(ng, 1);
        let geo = *g;
        assert_ne!(geo.kind, GLCOL_FEATURE_NONE);
        assert!(geo.normal[2] < -0.99, "{geo:?}");
        assert_eq!(glcol_mesh_clear_target(scene, blade), GlcolStatus::Ok);
        assert_eq!(
            glcol_query_impact_geometry(scene, &mut g, &mut ng),
            GlcolStatus::InvalidArgument
        );
        glcol_scene_destroy(scene);
    }
}

/// Checks `Scene::impact_geometry` against the answer: one entry per impact; NONE exactly
/// for AT_START; the features' vertices are the polygons' (`polys(mesh, polygon)`); weights
/// in [0, 1] summing to 1 (unused ones 0); the two contact points at toi within 2^-19 of
/// the features' largest motion (plus rounding); a unit normal, which a's feature
/// approaches along: the relative velocity of the contact points has no component along
/// +normal beyond rounding (a comes from the normal's side). Returns how many were checked.
fn check_impact_geometry(s: &mut Scene, polys: &dyn Fn(MeshId, u32) -> Vec<u32>) -> usize {
    let impacts = s.impacts().to_vec();
    let geo = s.impact_geometry().unwrap().to_vec();
    assert_eq!(geo.len(), impacts.len());
    for (i, g) in impacts.iter().zip(&geo) {
        assert_eq!(g.kind == ImpactFeature::None, i.at_start, "{i:?} {g:?}");
        if i.at_start {
            continue;
        }
        let used = |k: ImpactFeature, a: bool| match (k, a) {
            (ImpactFeature::VertexFace, true) | (ImpactFeature::FaceVertex, false) => 1,
            (ImpactFeature::EdgeEdge, _) => 2,
            _ => 3,
        };
        let pos = |id: MeshId, v: u32, t: f64| -> [f64; 3] {
            let m = s.mesh(id).unwrap();
            let (p0, p1) = (
                m.world_position(v as usize).unwrap(),
                m.end_world_position(v as usize).unwrap(),
            );
            std::array::from_fn(|k| p0[k] + t * (p1[k] - p0[k]))
        };
        let mut motion: f64 = 0.0;
        let mut scale: f64 = 0.0;
        let mut point = |id: MeshId, poly: u32, vs: &[u32; 3], w: &[f64; 3], n: usize, t: f64| {
            let own = polys(id, poly);
            let mut p = [0.0; 3];
            let sum: f64 = w.iter().sum();
            assert!((sum - 1.0).abs() <= 1e-15, "weights {w:?} sum to {sum}");
            for k in 0..3 {
                assert!((0.0..=1.0).contains(&w[k]), "weight {w:?}");
                if k >= n {
                    assert_eq!((vs[k], w[k]), (vs[n - 1], 0.0), "unused entry {vs:?} {w:?}");
                    continue;
                }
                assert!(
                    own.contains(&vs[k]),
                    "vertex {} not in polygon {poly} {own:?}",
                    vs[k]
                );
                let (a, b) = (pos(id, vs[k], 0.0), pos(id, vs[k], 1.0));
                motion = motion.max((0..3).map(|c| (b[c] - a[c]).abs()).fold(0.0, f64::max));
                let q = pos(id, vs[k], t);
                for c in 0..3 {
                    p[c] += w[k] * q[c];
                    scale = scale.max(q[c].abs());
                }
            }
            p
        };
        let (na, nb) = (used(g.kind, true), used(g.kind, false));
        let pa = point(
            i.mesh_a,
            i.polygon_a,
            &g.vertices_a,
            &g.weights_a,
            na,
            i.toi,
        );
        let pb = point(
            i.mesh_b,
            i.polygon_b,
            &g.vertices_b,
            &g.weights_b,
            nb,
            i.toi,
        );
        // The contact points' relative velocity (over the step, the weights held).
        let pa0 = point(i.mesh_a, i.polygon_a, &g.vertices_a, &g.weights_a, na, 0.0);
        let pa1 = point(i.mesh_a, i.polygon_a, &g.vertices_a, &g.weights_a, na, 1.0);
        let pb0 = point(i.mesh_b, i.polygon_b, &g.vertices_b, &g.weights_b, nb, 0.0);
        let pb1 = point(i.mesh_b, i.polygon_b, &g.vertices_b, &g.weights_b, nb, 1.0);
        let gap = (0..3).map(|c| (pa[c] - pb[c]).powi(2)).sum::<f64>().sqrt();
        assert!(
            gap <= 2f64.powi(-19) * motion * 3f64.sqrt() + 1e-12 * scale,
            "contact points {gap} apart at toi (motion {motion}): {i:?} {g:?}"
        );
        let len = g.normal.iter().map(|x| x * x).sum::<f64>().sqrt();
        assert!((len - 1.0).abs() < 1e-12, "normal {:?}", g.normal);
        let closing: f64 = (0..3)
            .map(|c| ((pa1[c] - pa0[c]) - (pb1[c] - pb0[c])) * g.normal[c])
            .sum();
        assert!(
            closing <= 1e-9 * motion + 1e-12 * scale,
            "a moves away along the normal ({closing}): {i:?} {g:?}"
        );
    }
    geo.len()
}

#[test]
fn impact_geometry_of_the_blade_and_the_hinge() {
    let mut s = scene(1);
    let quad = [[0., 0., 0.], [1., 0., 0.], [1., 1., 0.], [0., 1., 0.]];
    let membrane = s
        .create_mesh(Positions::from_points(&quad), &[0, 1, 2, 3], 4)
        .unwrap();
    let up = [[0.4, 0.4, 1.0], [0.6, 0.4, 1.0], [0.5, 0.6, 1.5]];
    let blade = s
        .create_mesh(Positions::from_points(&up), &[0, 1, 2], 3)
        .unwrap();
    // Before any continuous query: refused with a message.
    let e = s.impact_geometry().unwrap_err();
    assert_eq!(e.kind, ErrorKind::InvalidArgument);
    let m = [1., 0., 0., 0., 0., 1., 0., 0., 0., 0., 1., -2.];
    s.set_target_transform(blade, &m).unwrap();
    assert_eq!(s.query_continuous().unwrap().len(), 1);
    let polys = |id: MeshId, _p: u32| -> Vec<u32> {
        if id == membrane {
            vec![0, 1, 2, 3]
        } else {
            vec![0, 1, 2]
        }
    };
    assert_eq!(check_impact_geometry(&mut s, &polys), 1);
    let g = s.impact_geometry().unwrap()[0];
    // The blade's lowest edge (z = 1 at the start) lands on the membrane: an edge of the
    // blade (a's feature is the membrane's? no: a is the membrane, the lower id) on the
    // membrane's face, or its corner; the normal points from the blade down towards the
    // membrane (from b towards a).
    assert!(g.normal[2] < -0.99, "{g:?}");
    // A change of the targets: the geometry is refused until the next query.
    s.clear_target(blade).unwrap();
    assert_eq!(
        s.impact_geometry().unwrap_err().kind,
        ErrorKind::InvalidArgument
    );
    // The hinge folding through itself: the free vertex's edges or the vertex itself hit
    // the neighbour; the normal is the neighbour's (z), turned towards the folding one,
    // which comes from above.
    let mut h = scene(1);
    let p = [[0., 0., 0.], [1., 0., 0.], [0.5, 1., 0.], [0.5, 0.5, 1.0]];
    let id = h
        .create_mesh(Positions::from_points_f64(&p), &[0, 1, 2, 0, 1, 3], 3)
        .unwrap();
    h.set_self_collision(id, true).unwrap();
    h.set_target_positions_f64(id, 3, &[[0.5, 0.5, -1.0]])
        .unwrap();
    assert_eq!(h.query_continuous().unwrap().len(), 1);
    let tri = |_: MeshId, p: u32| -> Vec<u32> {
        if p == 0 {
            vec![0, 1, 2]
        } else {
            vec![0, 1, 3]
        }
    };
    assert_eq!(check_impact_geometry(&mut h, &tri), 1);
    let g = h.impact_geometry().unwrap()[0];
    assert_eq!(g.kind, ImpactFeature::FaceVertex, "{g:?}");
    assert_eq!(g.vertices_b, [3; 3]);
    // From b (the folding triangle, above) towards a: down.
    assert!(g.normal[2] < -0.99, "{g:?}");
}

#[test]
fn impact_geometry_of_the_real_steps() {
    if !has_shared("meshes/sim") {
        return;
    }
    for (name, n) in STEPS {
        let (mut s, ids, tris) = sim_step(name, n, 0);
        s.query_continuous().unwrap();
        let polys = |id: MeshId, p: u32| -> Vec<u32> {
            let part = ids.iter().position(|&x| x == id).unwrap();
            tris[part][3 * p as usize..][..3].to_vec()
        };
        let checked = check_impact_geometry(&mut s, &polys);
        eprintln!("{name}: the impact geometry of {checked} pairs checked");
        assert!(checked > 0);
    }
}

/// The distance band (epsilon e > 0) with no target anywhere: a thickness query, pairs
/// within e / 2 (toi 0, AT_START), against the brute-force distances of every polygon pair
/// of two real meshes placed side by side (not touching). Pairs whose f64 distance is
/// within 1e-6 of e / 2 are not judged (the band's promise is exact below e / 2 and allows
/// up to (e / 2)(1 + 2^-20)).
#[test]
fn the_band_without_targets_is_a_thickness_query() {
    let a = common::shared_mesh("forceps_jaw");
    let (lo, hi) = common::bounds(&a.positions);
    let size = (0..3).map(|k| hi[k] - lo[k]).fold(0.0, f32::max);
    // A second copy moved by 1.02 of its extent along x, and a little along y: apart, but
    // many polygons within a few percent of the size.
    let shift = [1.02 * (hi[0] - lo[0]), 0.01 * size, 0.0];
    let b: Vec<[f32; 3]> = a
        .positions
        .iter()
        .map(|p| [p[0] + shift[0], p[1] + shift[1], p[2]])
        .collect();
    let (ta, tb) = (
        common::TestMesh::from_obj(&a),
        common::TestMesh {
            pos: b.clone(),
            idx: a.triangles.clone(),
            k: 3,
        },
    );
    for rel in [0.02f32, 0.05] {
        let e = rel * size;
        let half = f64::from(e) / 2.0;
        let mut s = Scene::new(SceneConfig {
            epsilon: e,
            threads: 1,
            ..SceneConfig::default()
        })
        .unwrap();
        let ia = s
            .create_mesh(Positions::from_points(&a.positions), &a.triangles, 3)
            .unwrap();
        let ib = s
            .create_mesh(Positions::from_points(&b), &a.triangles, 3)
            .unwrap();
        assert!(ia < ib);
        let got: BTreeSet<(u32, u32)> = s
            .query_continuous()
            .unwrap()
            .iter()
            .map(|i| {
                assert!(i.at_start && i.toi == 0.0, "{i:?}");
                (i.polygon_a, i.polygon_b)
            })
            .collect();
        let (mut within, mut judged) = (0, 0);
        for p in 0..ta.polygons() {
            for q in 0..tb.polygons() {
                let d = common::polygon_distance(&ta, p, &tb, q);
                let reported = got.contains(&(p as u32, q as u32));
                if (d - half).abs() <= 1e-6 * half {
                    continue;
                }
                judged += 1;
                within += usize::from(d < half);
                assert_eq!(reported, d < half, "pair ({p}, {q}) at {d}, band {half}");
            }
        }
        eprintln!("band {half}: {within} pairs within of {judged} judged");
        assert!(within > 0);
    }
}

/// The band with a target: a triangle passing a membrane's edge at a distance h, never
/// touching it: reported at e / 2 a little above h (toi at the closest approach, at most
/// 2^-20 early), not at e / 2 a little below.
#[test]
fn the_band_in_a_step() {
    let run = |half: f64| -> Vec<Impact> {
        let mut s = Scene::new(SceneConfig {
            epsilon: (2.0 * half) as f32,
            threads: 1,
            ..SceneConfig::default()
        })
        .unwrap();
        let sheet = [[0., 0., 0.], [1., 0., 0.], [1., 1., 0.], [0., 1., 0.]];
        s.create_mesh(Positions::from_points_f64(&sheet), &[0, 1, 2, 3], 4)
            .unwrap();
        // A small triangle at height 0.25 above the plane z = 0, beside the sheet (x > 1.25),
        // sweeping along y: its lowest corner passes the sheet's edge x = 1 at distance
        // sqrt(0.25^2 + 0.25^2) at every y in [0, 1].
        let tri = [[1.25, -1.0, 0.25], [1.5, -1.0, 0.25], [1.25, -1.0, 0.5]];
        let t = s
            .create_mesh(Positions::from_points_f64(&tri), &[0, 1, 2], 3)
            .unwrap();
        let end: Vec<[f64; 3]> = tri.iter().map(|p| [p[0], p[1] + 4.0, p[2]]).collect();
        s.set_target_positions_f64(t, 0, &end).unwrap();
        s.query_continuous().unwrap().to_vec()
    };
    let h = (0.125f64).sqrt(); // 0.3535...
                               // e is a float: the band's half is what the float e gives.
    let above = f64::from((2.0 * h * (1.0 + 1e-5)) as f32) / 2.0;
    let below = f64::from((2.0 * h * (1.0 - 1e-5)) as f32) / 2.0;
    assert!(above > h && below < h);
    let hits = run(above);
    assert_eq!(hits.len(), 1, "{hits:?}");
    // The corner (1.25, y, 0.25) comes within `above` of the edge x = 1, z = 0 (y in [0, 1])
    // once y reaches 0 - a little: y(t) = -1 + 4 t, the earliest t a little before 1/4.
    let dy = (above * above - h * h).max(0.0).sqrt();
    let exact = (1.0 - dy) / 4.0;
    assert!(
        hits[0].toi <= exact && hits[0].toi >= exact - 2f64.powi(-20) - 1e-9,
        "{hits:?} {exact}"
    );
    assert!(run(below).is_empty());
}
