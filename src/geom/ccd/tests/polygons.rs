//! Moving polygon pairs and whole scenes against the independent reference: for polygons
//! that each move by one translation, the exact first meeting of every triangle pair
//! (rational hull distances, bisection of the meeting interval), the union's the earliest.

use super::super::{polygons_first_meet, MovingPolygon, Toi};
use super::reference::{inv_pow2, q, translated_hulls_first_meeting, Q, Q3};
use crate::geom::test_rng::Rng;
use crate::geom::P3;
use crate::{Positions, Scene, SceneConfig};
use num_traits::Zero;

/// Corners of a polygon's triangles.
const TRIS: [[usize; 3]; 2] = [[0, 1, 2], [0, 2, 3]];

fn qp(p: &P3) -> Q3 {
    p.map(q)
}

/// A polygon of `k` corners at `start`, translated by `v`.
fn translating(k: usize, start: [P3; 4], v: P3, first_id: u32) -> MovingPolygon {
    MovingPolygon {
        k,
        ids: std::array::from_fn(|i| first_id + i as u32),
        p: [
            start,
            start.map(|p| [p[0] + v[0], p[1] + v[1], p[2] + v[2]]),
        ],
    }
}

/// The reference's first meeting of two translating polygons (the earliest over their
/// triangle pairs).
fn reference(a: &MovingPolygon, b: &MovingPolygon, bits: u32) -> Option<(Q, Q)> {
    let vel =
        |m: &MovingPolygon| -> Q3 { std::array::from_fn(|k| q(m.p[1][0][k]) - q(m.p[0][0][k])) };
    let (va, vb) = (vel(a), vel(b));
    let tri = |m: &MovingPolygon, t: &[usize; 3]| -> Vec<Q3> {
        t.iter().map(|&c| qp(&m.p[0][c])).collect()
    };
    let mut best: Option<(Q, Q)> = None;
    for ta in &TRIS[..a.k - 2] {
        for tb in &TRIS[..b.k - 2] {
            if let Some(r) =
                translated_hulls_first_meeting(&tri(a, ta), &va, &tri(b, tb), &vb, bits)
            {
                if best.as_ref().is_none_or(|b| r.1 < b.1) {
                    best = Some(r);
                }
            }
        }
    }
    best
}

fn g(rng: &mut Rng, n: i64, den: f64) -> f64 {
    (rng.below((2 * n + 1) as usize) as i64 - n) as f64 / den
}

fn gv(rng: &mut Rng, n: i64, den: f64) -> P3 {
    [g(rng, n, den), g(rng, n, den), g(rng, n, den)]
}

/// A polygon's start corners of a flavor: general (on a grid), flat (z = 0), collinear
/// (corners on a line: a segment), a point, or aimed so that at `t* = k/8` its first
/// corner reaches a corner or edge midpoint of the other.
fn corners(rng: &mut Rng, flavor: &str) -> [P3; 4] {
    let mut c: [P3; 4] = std::array::from_fn(|_| gv(rng, 4, 1.0));
    match flavor {
        "flat" => c = c.map(|p| [p[0], p[1], 0.0]),
        "collinear" => {
            let (o, d) = (c[0], gv(rng, 2, 1.0));
            c = std::array::from_fn(|_| {
                let s = g(rng, 3, 1.0);
                [o[0] + s * d[0], o[1] + s * d[1], o[2] + s * d[2]]
            });
        }
        "point" => c = [c[0]; 4],
        _ => {}
    }
    c
}

/// Checks `polygons_first_meet` against the reference on one pair.
fn judge(a: &MovingPolygon, b: &MovingPolygon) -> Option<Toi> {
    let got = polygons_first_meet(a, b, false, 0.0).map(|r| r.0);
    let truth = reference(a, b, 26);
    match (got, &truth) {
        (None, None) => {}
        (Some(toi), Some((lo, hi))) => {
            let t = q(toi.t);
            assert!(
                t <= *hi,
                "late: {toi:?}, first meeting in [{lo}, {hi}]: {a:?} {b:?}"
            );
            assert!(
                t >= lo - inv_pow2(20),
                "early: {toi:?}, first meeting in [{lo}, {hi}]: {a:?} {b:?}"
            );
            assert_eq!(toi.at_start, hi.is_zero(), "AT_START {toi:?}: {a:?} {b:?}");
            assert_eq!(toi.at_start, toi.t == 0.0);
        }
        _ => panic!("got {got:?}, the reference says {truth:?}: {a:?} {b:?}"),
    }
    // The same question with the polygons swapped gets the same time, to the bit.
    let swapped = polygons_first_meet(b, a, false, 0.0).map(|r| r.0);
    assert_eq!(got, swapped, "{a:?} {b:?}");
    got
}

#[test]
fn translating_polygon_pairs_against_the_reference() {
    let mut rng = Rng(0xc0117_5ca1e);
    let flavors = ["general", "flat", "collinear", "point", "aimed"];
    for fa in flavors {
        for fb in flavors {
            let (mut meet, mut start, mut cases) = (0, 0, 0);
            for _ in 0..12 {
                let (ka, kb) = (3 + rng.below(2), 3 + rng.below(2));
                let mut ca = corners(&mut rng, fa);
                let cb = corners(&mut rng, fb);
                let flat = fa == "flat" && fb == "flat";
                let mut v = [gv(&mut rng, 8, 1.0), gv(&mut rng, 8, 1.0)];
                if flat {
                    v = v.map(|p| [p[0], p[1], 0.0]);
                }
                if fa == "aimed" {
                    // At t* = k/8 corner 0 of a sits on a corner or edge midpoint of b.
                    let tstar = (1 + rng.below(7)) as f64 / 8.0;
                    let (i, j) = (rng.below(kb), rng.below(kb));
                    let target: P3 = std::array::from_fn(|k| (cb[i][k] + cb[j][k]) / 2.0);
                    let rel: P3 = std::array::from_fn(|k| v[0][k] - v[1][k]);
                    let (d, c0): (P3, P3) =
                        (ca[0], std::array::from_fn(|k| target[k] - tstar * rel[k]));
                    for c in &mut ca {
                        *c = std::array::from_fn(|k| c[k] - d[k] + c0[k]);
                    }
                }
                let a = translating(ka, ca, v[0], 0);
                let b = translating(kb, cb, v[1], 10);
                let got = judge(&a, &b);
                cases += 1;
                meet += usize::from(got.is_some());
                start += usize::from(got.is_some_and(|t| t.at_start));
            }
            eprintln!("{fa} vs {fb}: {cases} cases, {meet} meet, {start} at the start");
        }
    }
}

/// A small soup of random triangles or quads, each polygon its own vertices.
fn soup(rng: &mut Rng, n: usize, k: usize, spread: i64) -> (Vec<[f64; 3]>, Vec<u32>) {
    let mut pos = Vec::new();
    let mut idx = Vec::new();
    for _ in 0..n {
        let o = gv(rng, spread, 1.0);
        for _ in 0..k {
            let d = gv(rng, 2, 2.0);
            idx.push(pos.len() as u32);
            pos.push([o[0] + d[0], o[1] + d[1], o[2] + d[2]]);
        }
    }
    (pos, idx)
}

/// A mesh of a scene: positions, polygons, vertices per polygon, its translation.
type SoupMesh = (Vec<[f64; 3]>, Vec<u32>, usize, P3);

/// Whole scenes of meshes that each translate: the continuous query against the reference
/// over every polygon pair (what a dropped broad-phase pair or a late time would fail),
/// for 1 and 2 threads and both creation orders, to the bit.
#[test]
fn translating_scenes_against_the_reference() {
    let mut rng = Rng(0x0005_ce7e_0001);
    for round in 0..6 {
        let meshes: Vec<SoupMesh> = (0..3)
            .map(|_| {
                let k = 3 + rng.below(2);
                let (p, i) = soup(&mut rng, 6, k, 3);
                (p, i, k, gv(&mut rng, 6, 1.0))
            })
            .collect();
        let mut answers = Vec::new();
        for (threads, reversed) in [(1, false), (2, false), (1, true)] {
            let mut scene = Scene::new(SceneConfig {
                threads,
                ..SceneConfig::default()
            })
            .unwrap();
            let order: Vec<usize> = if reversed {
                vec![2, 1, 0]
            } else {
                vec![0, 1, 2]
            };
            let mut ids = [0; 3];
            for &m in &order {
                let (p, i, k, v) = &meshes[m];
                ids[m] = scene
                    .create_mesh(Positions::from_points_f64(p), i, *k)
                    .unwrap();
                let end: Vec<[f64; 3]> = p
                    .iter()
                    .map(|x| std::array::from_fn(|c| x[c] + v[c]))
                    .collect();
                scene.set_target_positions_f64(ids[m], 0, &end).unwrap();
            }
            let got = scene.query_continuous().unwrap().to_vec();
            // In mesh order 0, 1, 2 (not ids) for comparing creation orders.
            let rank = |id: u32| ids.iter().position(|&x| x == id).unwrap();
            let mut mine: Vec<_> = got
                .iter()
                .map(|c| {
                    let (a, b) = ((rank(c.mesh_a), c.polygon_a), (rank(c.mesh_b), c.polygon_b));
                    let (a, b) = if a < b { (a, b) } else { (b, a) };
                    (a, b, c.toi.to_bits(), c.at_start)
                })
                .collect();
            mine.sort();
            answers.push(mine);
        }
        assert_eq!(answers[0], answers[1], "threads 1 and 2 differ");
        assert_eq!(answers[0], answers[2], "creation orders differ");
        // The reference over every polygon pair of two different meshes.
        let mut expected = Vec::new();
        for ma in 0..3 {
            for mb in ma + 1..3 {
                let (pa, ia, ka, va) = &meshes[ma];
                let (pb, ib, kb, vb) = &meshes[mb];
                for (x, ca) in ia.chunks(*ka).enumerate() {
                    for (y, cb) in ib.chunks(*kb).enumerate() {
                        let poly = |p: &[[f64; 3]], c: &[u32], k: usize, v: P3| {
                            let mut s = [[0.0; 3]; 4];
                            for (n, &i) in c.iter().enumerate() {
                                s[n] = p[i as usize];
                            }
                            translating(k, s, v, 0)
                        };
                        let (a, b) = (poly(pa, ca, *ka, *va), poly(pb, cb, *kb, *vb));
                        if let Some((lo, hi)) = reference(&a, &b, 26) {
                            expected.push(((ma, x as u32), (mb, y as u32), lo, hi));
                        }
                    }
                }
            }
        }
        expected.sort_by_key(|x| (x.0, x.1));
        let got = &answers[0];
        assert_eq!(
            got.iter().map(|g| (g.0, g.1)).collect::<Vec<_>>(),
            expected.iter().map(|e| (e.0, e.1)).collect::<Vec<_>>(),
            "round {round}: pairs differ from the reference"
        );
        for (g, e) in got.iter().zip(&expected) {
            let t = q(f64::from_bits(g.2));
            assert!(
                t <= e.3 && t >= &e.2 - inv_pow2(20),
                "round {round}: toi {t} vs [{}, {}]",
                e.2,
                e.3
            );
        }
        eprintln!("round {round}: {} pairs", expected.len());
    }
}
