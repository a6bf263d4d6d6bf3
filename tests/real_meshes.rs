//! The query's contact set against brute force with the independent exact oracle, on the
//! real meshes of data/ (and of ../shared/meshes where it is present), deforming over several
//! frames.
//! epsilon = 0: equal sets. epsilon > 0: a superset whose extra pairs are within epsilon/2.

mod common;
use common::*;

/// Checks one frame: `scene` holds `r` (id `rid`) and `o` (id `oid`) at their current
/// positions; returns the number of exact pairs.
fn check_frame(
    scene: &mut glcollide::Scene,
    rid: u32,
    oid: u32,
    r: &TestMesh,
    o: &TestMesh,
    what: &str,
) -> usize {
    let got = scene_pairs(scene, rid, oid);
    let eps = scene.config().epsilon as f64;
    let exact = brute_force_exact(r, o);
    if eps == 0.0 {
        if got != exact {
            let missed: Vec<_> = exact
                .iter()
                .filter(|p| got.binary_search(p).is_err())
                .take(5)
                .collect();
            let extra: Vec<_> = got
                .iter()
                .filter(|p| exact.binary_search(p).is_err())
                .take(5)
                .collect();
            panic!(
                "{what}: {} contacts, {} exact; missed {missed:?}, extra {extra:?}",
                got.len(),
                exact.len()
            );
        }
    } else {
        let missed: Vec<_> = exact
            .iter()
            .filter(|p| got.binary_search(p).is_err())
            .collect();
        assert!(
            missed.is_empty(),
            "{what}: missed exact pairs {:?}",
            &missed[..missed.len().min(5)]
        );
        let (lo, hi) = bounds(&r.pos);
        let scale = (0..3)
            .map(|k| (hi[k] as f64).abs().max(lo[k] as f64).abs())
            .fold(1.0, f64::max);
        for &(a, b) in got.iter().filter(|p| exact.binary_search(p).is_err()) {
            let d = polygon_distance(r, a as usize, o, b as usize);
            assert!(
                d <= eps / 2.0 + 1e-12 * scale,
                "{what}: extra pair ({a},{b}) is {d} apart, band is {}",
                eps / 2.0
            );
        }
    }
    exact.len()
}

/// Runs `frames` frames of an instrument moving through a deforming organ.
fn instrument_in_organ(
    instrument: &str,
    organ: &str,
    epsilon_rel: f32,
    leaf: u32,
    frames: usize,
) -> usize {
    let org = TestMesh::from_obj(&shared_mesh(organ));
    let ins0 = TestMesh::from_obj(&shared_mesh(instrument));
    let (lo, hi) = bounds(&org.pos);
    let extent = (0..3).map(|k| hi[k] - lo[k]).fold(0.0, f32::max);
    // The organ's vertex farthest along +x is on its surface: the instrument works there.
    let far = org.pos.iter().copied().fold(
        [f32::NEG_INFINITY; 3],
        |a, p| if p[0] > a[0] { p } else { a },
    );
    let eps = epsilon_rel * extent;
    let mut scene = cpu_scene(eps, leaf);
    let mut o = org.clone();
    // The instrument is scaled to a fifth of the organ (the meshes come in different units).
    let (ilo, ihi) = bounds(&ins0.pos);
    let scale = 0.2 * extent / (0..3).map(|k| ihi[k] - ilo[k]).fold(0.0, f32::max);
    let mut ins = ins0.clone();
    ins.pos = place_scaled(&ins0.pos, far, 1.3, scale);
    let oid = add(&mut scene, &o);
    let rid = add(&mut scene, &ins);
    let mut total = 0;
    for f in 0..frames {
        let t = f as f32 * 0.37;
        o.pos = wave(&org.pos, 0.01 * extent, 6.0 / extent, t);
        let depth = (0.5 + 0.5 * (t * 0.9).sin()) * 0.05 * extent;
        ins.pos = place_scaled(
            &ins0.pos,
            [far[0] - depth, far[1], far[2]],
            1.3 + 0.2 * t.sin(),
            scale,
        );
        scene
            .update_positions(oid, 0, glcollide::Positions::from_points(&o.pos))
            .unwrap();
        scene
            .update_positions(rid, 0, glcollide::Positions::from_points(&ins.pos))
            .unwrap();
        total += check_frame(
            &mut scene,
            rid,
            oid,
            &ins,
            &o,
            &format!("{instrument} in {organ}, frame {f}, eps {eps}"),
        );
    }
    total
}

#[test]
fn blade_in_gallbladder_exact() {
    assert!(instrument_in_organ("scissors_blade", "gallbladder_glt", 0.0, 0, 12) > 0);
}

#[test]
fn blade_in_gallbladder_small_leaves_and_band() {
    assert!(instrument_in_organ("scissors_blade", "gallbladder_glt", 0.0, 7, 4) > 0);
    assert!(instrument_in_organ("scissors_blade", "gallbladder_glt", 1e-3, 0, 6) > 0);
    assert!(instrument_in_organ("scissors_blade", "gallbladder_glt", 1e-2, 1, 3) > 0);
}

#[test]
fn forceps_in_face_with_degenerate_triangles() {
    // forceps_jaw has zero-area triangles, slivers and two parts that cut each other.
    assert!(instrument_in_organ("forceps_jaw", "face", 0.0, 0, 8) > 0);
    assert!(instrument_in_organ("forceps_jaw", "face", 1e-3, 0, 4) > 0);
}

#[test]
fn dental_probe_in_skull() {
    if !has_shared("meshes/dental_instrument.obj") {
        return;
    }
    assert!(instrument_in_organ("dental_instrument", "skull_teeth", 0.0, 0, 6) > 0);
}

#[test]
fn blade_in_heart_with_duplicate_vertices() {
    if !has_shared("meshes/heart_vena_cava.obj") {
        return;
    }
    assert!(instrument_in_organ("scissors_blade", "heart_vena_cava", 0.0, 0, 6) > 0);
}

/// Organs that overlap at rest (same patient frame), both deforming with opposite warps.
fn organ_pair(a: &str, b: &str, epsilon_rel: f32, frames: usize) {
    let a0 = TestMesh::from_obj(&shared_mesh(a));
    let b0 = TestMesh::from_obj(&shared_mesh(b));
    let (lo, hi) = bounds(&a0.pos);
    let extent = (0..3).map(|k| hi[k] - lo[k]).fold(0.0, f32::max);
    let mut scene = cpu_scene(epsilon_rel * extent, 0);
    let (mut ma, mut mb) = (a0.clone(), b0.clone());
    let ia = add(&mut scene, &ma);
    let ib = add(&mut scene, &mb);
    for f in 0..frames {
        let t = f as f32 * 0.5;
        ma.pos = wave(&a0.pos, 0.004 * extent, 8.0 / extent, t);
        mb.pos = wave(&b0.pos, -0.004 * extent, 8.0 / extent, t);
        scene
            .update_positions(ia, 0, glcollide::Positions::from_points(&ma.pos))
            .unwrap();
        scene
            .update_positions(ib, 0, glcollide::Positions::from_points(&mb.pos))
            .unwrap();
        let n = check_frame(
            &mut scene,
            ia,
            ib,
            &ma,
            &mb,
            &format!("{a} vs {b}, frame {f}"),
        );
        assert!(
            n > 50,
            "{a} and {b} overlap at rest: expected many pairs, got {n}"
        );
        // And the other way round: the mirrored set.
        let ab = scene_pairs(&mut scene, ia, ib);
        let mut ba: Vec<(u32, u32)> = scene_pairs(&mut scene, ib, ia)
            .into_iter()
            .map(|(x, y)| (y, x))
            .collect();
        ba.sort_unstable();
        if epsilon_rel == 0.0 {
            assert_eq!(
                ab, ba,
                "{a} vs {b}: swapping the reference changed the exact answer"
            );
        }
    }
}

#[test]
fn colon_against_small_intestine() {
    organ_pair("colon", "small_intestine", 0.0, 2);
}

#[test]
fn liver_against_gallbladder() {
    organ_pair("liver_glt", "gallbladder_glt", 0.0, 2);
    organ_pair("liver_glt", "gallbladder_glt", 1e-4, 1);
}

#[test]
fn spine_parts_touch_each_other() {
    if !has_shared("meshes/spine_pelvis.obj") {
        return;
    }
    // spine_pelvis holds seven bones that overlap their neighbours; split it in two meshes.
    let m = shared_mesh("spine_pelvis");
    let all = TestMesh::from_obj(&m);
    let half = all.polygons() / 2 * 3;
    let a = TestMesh {
        pos: all.pos.clone(),
        idx: all.idx[..half].to_vec(),
        k: 3,
    };
    let b = TestMesh {
        pos: all.pos.clone(),
        idx: all.idx[half..].to_vec(),
        k: 3,
    };
    let mut scene = cpu_scene(0.0, 0);
    let ia = add(&mut scene, &a);
    let ib = add(&mut scene, &b);
    check_frame(&mut scene, ia, ib, &a, &b, "spine halves");
}

#[test]
fn several_meshes_disabled_and_destroyed() {
    let blade = TestMesh::from_obj(&shared_mesh("scissors_blade"));
    let organ = TestMesh::from_obj(&shared_mesh("gallbladder_glt"));
    let far =
        organ.pos.iter().copied().fold(
            [f32::NEG_INFINITY; 3],
            |a, p| if p[0] > a[0] { p } else { a },
        );
    let mut scene = cpu_scene(0.0, 0);
    let o1 = add(&mut scene, &organ);
    let mut shifted = organ.clone();
    shifted.pos.iter_mut().for_each(|p| p[1] += 0.5);
    let o2 = add(&mut scene, &shifted);
    let mut b = blade.clone();
    b.pos = place(&blade.pos, [far[0] - 2.0, far[1], far[2]], 1.5);
    let r = add(&mut scene, &b);
    let e1 = brute_force_exact(&b, &organ);
    let e2 = brute_force_exact(&b, &shifted);
    assert!(!e1.is_empty() && !e2.is_empty());
    let all = scene.query(r).unwrap().to_vec();
    // Sorted by (other mesh, reference polygon, other polygon), each pair once.
    let keys: Vec<_> = all
        .iter()
        .map(|c| (c.other_mesh, c.reference_polygon, c.other_polygon))
        .collect();
    let mut sorted = keys.clone();
    sorted.sort_unstable();
    sorted.dedup();
    assert_eq!(keys, sorted);
    assert_eq!(scene_pairs(&mut scene, r, o1), e1);
    assert_eq!(scene_pairs(&mut scene, r, o2), e2);
    scene.set_enabled(o1, false).unwrap();
    assert!(scene_pairs(&mut scene, r, o1).is_empty());
    assert_eq!(scene_pairs(&mut scene, r, o2), e2);
    scene.set_enabled(r, false).unwrap();
    assert!(scene.query(r).unwrap().is_empty());
    scene.set_enabled(r, true).unwrap();
    scene.set_enabled(o1, true).unwrap();
    scene.destroy_mesh(o2).unwrap();
    assert_eq!(scene.query(r).unwrap().len(), e1.len());
}

/// Quads: a wavy (non-planar) quad grid against a triangle mesh, both ways.
#[test]
fn non_planar_quads() {
    let n = 24usize;
    let mut pos = Vec::new();
    for j in 0..=n {
        for i in 0..=n {
            let (x, y) = (i as f32 / n as f32, j as f32 / n as f32);
            pos.push([
                x,
                y,
                0.05 * ((x * 9.0).sin() + (y * 7.0).cos())
                    + if (i + j) % 2 == 0 { 0.01 } else { -0.01 },
            ]);
        }
    }
    let id = |i: usize, j: usize| (j * (n + 1) + i) as u32;
    let mut idx = Vec::new();
    for j in 0..n {
        for i in 0..n {
            idx.extend([id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)]);
        }
    }
    let quads = TestMesh { pos, idx, k: 4 };
    let sphere = TestMesh::from_obj(&shared_mesh("bunny"));
    let (lo, hi) = bounds(&sphere.pos);
    let size = (0..3).map(|k| hi[k] - lo[k]).fold(0.0, f32::max);
    let mut bunny = sphere.clone();
    bunny.pos = place_scaled(&sphere.pos, [0.5, 0.5, 0.0], 0.4, 0.6 / size);
    for eps in [0.0, 0.01] {
        let mut scene = cpu_scene(eps, 16);
        let q = add(&mut scene, &quads);
        let b = add(&mut scene, &bunny);
        assert!(check_frame(&mut scene, q, b, &quads, &bunny, "quads vs bunny") > 0);
        check_frame(&mut scene, b, q, &bunny, &quads, "bunny vs quads");
    }
}

/// Random per-vertex jitter (about an edge length), several seeds: crumpled, self-crossing
/// meshes against each other.
#[test]
fn random_jitter_bunny_against_teapot() {
    let bunny0 = TestMesh::from_obj(&shared_mesh("bunny"));
    let teapot0 = TestMesh::from_obj(&shared_mesh("teapot"));
    let (tlo, thi) = bounds(&teapot0.pos);
    let text = (0..3).map(|k| thi[k] - tlo[k]).fold(0.0, f32::max);
    let (blo, bhi) = bounds(&bunny0.pos);
    let bext = (0..3).map(|k| bhi[k] - blo[k]).fold(0.0, f32::max);
    let centre = [0, 1, 2].map(|k| (tlo[k] + thi[k]) / 2.0);
    for seed in 1..=4u64 {
        let mut rng = Rng(seed * 0x9E37_79B9_7F4A_7C15);
        let mut bunny = bunny0.clone();
        let to = [
            centre[0] + rng.range(-0.3, 0.3) as f32 * text,
            centre[1],
            centre[2] + rng.range(-0.2, 0.2) as f32 * text,
        ];
        bunny.pos = place_scaled(
            &bunny0.pos,
            to,
            rng.range(0.0, std::f64::consts::TAU) as f32,
            0.5 * text / bext,
        );
        let mut teapot = teapot0.clone();
        for p in bunny.pos.iter_mut().chain(teapot.pos.iter_mut()) {
            for c in p.iter_mut() {
                *c += (rng.range(-1.0, 1.0) * 0.004 * text as f64) as f32;
            }
        }
        for (eps, leaf) in [(0.0, 0), (0.0, 3), (0.002 * text, 0)] {
            let mut scene = cpu_scene(eps, leaf);
            let t = add(&mut scene, &teapot);
            let b = add(&mut scene, &bunny);
            let n = check_frame(
                &mut scene,
                b,
                t,
                &bunny,
                &teapot,
                &format!("seed {seed} eps {eps} leaf {leaf}"),
            );
            assert!(n > 0, "seed {seed}: no contact");
        }
    }
}
