//! The benchmarks' heavy case (the meshes bundled in `data/`): every pair its queries
//! report, against the references.

use super::support::*;

/// Every pair the query reports on the benchmarks' heavy case (colon against small
/// intestine, overlapping, opposite warps), with epsilon 0 and within a band: every
/// check, against the references.
#[test]
fn heavy_case_pairs_against_references() {
    use crate::{Positions, Scene, SceneConfig};
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/data");
    let ma = crate::obj::load(format!("{dir}/colon.obj")).unwrap();
    let mb = crate::obj::load(format!("{dir}/small_intestine.obj")).unwrap();
    let extent = (0..3)
        .map(|k| {
            let (lo, hi) = ma
                .positions
                .iter()
                .fold((f32::MAX, f32::MIN), |(l, h), p| (l.min(p[k]), h.max(p[k])));
            hi - lo
        })
        .fold(0.0, f32::max);
    let wave = |rest: &[[f32; 3]], amp: f32, phase: f32| -> Vec<[f32; 3]> {
        let freq = 8.0 / extent;
        rest.iter()
            .map(|p| {
                [
                    p[0] + amp * (phase + freq * p[1]).sin(),
                    p[1] + amp * (phase * 1.3 + freq * p[2]).sin(),
                    p[2] + amp * (phase * 0.7 + freq * p[0]).sin(),
                ]
            })
            .collect()
    };
    let pa = wave(&ma.positions, 0.004 * extent, 0.1);
    let pb = wave(&mb.positions, -0.004 * extent, 0.1);
    let mut all = Worst::default();
    for eps in [0.0, 0.001 * extent] {
        let mut scene = Scene::new(SceneConfig {
            epsilon: eps,
            max_polygons_per_box: 0,
            threads: 1,
        })
        .unwrap();
        let ia = scene
            .create_mesh(Positions::from_points(&pa), &ma.triangles, 3)
            .unwrap();
        scene
            .create_mesh(Positions::from_points(&pb), &mb.triangles, 3)
            .unwrap();
        let contacts = scene.query(ia).unwrap().to_vec();
        let tri = |pos: &[[f32; 3]], idx: &[u32], p: u32| {
            let v = |k: usize| pos[idx[3 * p as usize + k] as usize].map(f64::from);
            Polygon {
                t: [[v(0), v(1), v(2)]; 2],
                n: 1,
            }
        };
        let mut w = Worst::default();
        for c in &contacts {
            let a = tri(&pa, &ma.triangles, c.reference_polygon);
            let b = tri(&pb, &mb.triangles, c.other_polygon);
            w.merge(&check(&a, &b, true));
        }
        report(&format!("heavy case eps {eps:.3}"), &w);
        all.merge(&w);
    }
    assert!(all.cases > 1000);
    assert_within(&all, 16.0);
}
