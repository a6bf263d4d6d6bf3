//! Tests of pairs apart (the band): known answers, near misses, the closest points'
//! shortcut and edge lanes against the full search, band normals and distances.

use super::support::*;
use crate::geom::contact::band::{closest, closest_search, vertex_over_face};
#[cfg(target_arch = "x86_64")]
use crate::geom::contact::band::{
    nearest_edge_pair, nearest_edge_pair_scalar, segment_params, EdgePair,
};
#[cfg(target_arch = "x86_64")]
use crate::geom::contact::edges;
use crate::geom::contact::poly::{local, unit, Tri};
use crate::geom::contact::{contact_geometry, V};
use crate::geom::predicates::P3;
use crate::geom::test_rng::Rng;

#[test]
fn band_known_answers() {
    // Parallel faces 0.5 apart: any pair of facing points; normal from b (above) to a.
    let a = Polygon::tri([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]);
    let b = Polygon::tri([[0.0, 0.0, 0.5], [1.0, 0.0, 0.5], [0.0, 1.0, 0.5]]);
    let g = geometry(&a, &b);
    assert!(!g.intersecting && g.depth == -0.5 && g.normal == [0.0, 0.0, -1.0]);
    // Coplanar but apart: the band geometry, not flagged coplanar.
    let c = Polygon::tri([[2.0, 0.0, 0.0], [3.0, 0.0, 0.0], [3.0, 1.0, 0.0]]);
    let g = geometry(&a, &c);
    assert!(!g.intersecting && !g.coplanar && g.depth == -1.0);
    assert_eq!(g.normal, [-1.0, 0.0, 0.0]);
    assert_eq!((g.point_a, g.point_b), ([1.0, 0.0, 0.0], [2.0, 0.0, 0.0]));
    // Edge over edge, crossing at right angles one f32 ulp apart at 1e5.
    let o = 1e5;
    let e1 = Polygon::tri([[o - 1.0, o, o], [o + 1.0, o, o], [o, o - 1.0, o - 1.0]]);
    let gap = 2f64.powi(-7);
    let e2 = Polygon::tri([
        [o, o - 1.0, o + gap],
        [o, o + 1.0, o + gap],
        [o + 1.0, o, o + 1.0],
    ]);
    let g = geometry(&e2, &e1);
    assert!(!g.intersecting && g.depth == -gap, "{g:?}");
    assert_eq!(g.normal, [0.0, 0.0, 1.0]);
    for (x, y) in [(&a, &b), (&a, &c), (&e1, &e2)] {
        check(x, y, true);
        check(y, x, true);
    }
}

/// Near misses at 1e-3 .. 1e-7 of the size: b's nearest vertex (or edge) that far
/// above a's face, or a moved off b by depth + gap along the separating normal.
#[test]
fn near_misses() {
    let mut gaps = [1e-3, 1e-4, 1e-5, 1e-6, 1e-7].iter().cycle();
    run("near misses", 16.0, |r, c, s| {
        let gap = gaps.next().copied().unwrap_or(1e-3) * s;
        let (a, b) = crossing_pair(r, c, s);
        if r.next() % 2 == 0 {
            let g = geometry(&a, &b);
            let d = g.normal.map(|x| x * (g.depth + gap));
            let moved = Polygon::tri(a.moved(&d).t[0]);
            check(&moved, &b, true)
        } else {
            let t = a.t[0];
            let x = combo(&t, &r.bary());
            let n = {
                let e = [0, 1, 2].map(|k| t[1][k] - t[0][k]);
                let f = [0, 1, 2].map(|k| t[2][k] - t[0][k]);
                let n = [
                    e[1] * f[2] - e[2] * f[1],
                    e[2] * f[0] - e[0] * f[2],
                    e[0] * f[1] - e[1] * f[0],
                ];
                let l = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
                n.map(|v| v / l)
            };
            let at = |h: f64, r: &mut Rng| {
                let lat = r.v(s);
                [0, 1, 2].map(|k| x[k] + n[k] * h + lat[k])
            };
            let near = [0, 1, 2].map(|k| x[k] + n[k] * gap);
            let b = Polygon::tri([near, at(s, r), at(s * 0.7, r)]);
            check(&a, &b, true)
        }
    });
}

/// The nearest edge pair found in AVX2 lanes (`edges.rs`) is the scalar search's, bit
/// for bit and the same pair among equals: on random pairs at every scale and offset,
/// on degenerate ones (edges of length 0, triangles that are points or segments,
/// parallel and collinear edges, a shared vertex, a triangle and its copy moved along
/// its normal: many pairs equally near), and at coordinates near the f64 range's end
/// (NaN distances: left to the scalar search).
#[cfg(target_arch = "x86_64")]
#[test]
fn nearest_edge_pair_in_lanes_is_the_scalar_one() {
    if !(std::is_x86_feature_detected!("avx2") && std::is_x86_feature_detected!("fma")) {
        return;
    }
    let key = |(i, j, e): (usize, usize, EdgePair)| {
        let mut v = vec![i as u64, j as u64];
        v.extend(
            [e.d2, e.s, e.r]
                .iter()
                .chain(e.p.iter())
                .chain(e.q.iter())
                // Bits as they are (-0 is not 0 here).
                .map(|x| x.to_bits()),
        );
        v
    };
    let mut r = Rng(4242);
    let (mut n, mut ties, mut left) = (0, 0, 0);
    for &(o, s) in FRAMES.iter().chain(&[(0.0, 1e155), (1e154, 1.0)]) {
        let c = [o, 0.7 * o, -0.4 * o];
        for i in 0..900 {
            let mut t = random_tri(&mut r, &c, s);
            let mut u = random_tri(&mut r, &c, s);
            match i % 9 {
                // Repeated corners: an edge of length 0, a segment, a point.
                1 => t[1] = t[0],
                2 => u[2] = u[1],
                3 => (t[1], t[2]) = (t[0], t[0]),
                4 => (u[1], u[2]) = (u[0], u[0]),
                // Parallel edges (u's first edge a shifted copy of t's), collinear
                // corners, a shared vertex, a copy along the normal.
                5 => {
                    let d = r.v(s);
                    (u[0], u[1]) = (plus(&t[0], &d), plus(&t[1], &d));
                }
                6 => t[2] = combo(&[t[0], t[1], t[1]], &[0.25, 0.75, 0.0]),
                7 => u[0] = t[2],
                8 => {
                    let (e, f) = (local(&t[1], &t[0]), local(&t[2], &t[0]));
                    let up = e.cross(&f) * (0.1 / e.norm().max(f.norm()));
                    u = t.map(|p| [p[0] + up.x, p[1] + up.y, p[2] + up.z]);
                }
                _ => {}
            }
            let o3 = t[0];
            let (ta, tb) = (Tri::new(&t, &o3), Tri::new(&u, &o3));
            let scalar = nearest_edge_pair_scalar(&ta, &tb);
            // SAFETY: the CPU has AVX2 and FMA (checked above).
            match unsafe { edges::nearest_edge_pair(&ta, &tb) } {
                Some(lanes) => assert_eq!(key(lanes), key(scalar), "{t:?} {u:?}"),
                None => {
                    left += 1;
                    assert!(scalar.2.d2.is_nan() || s > 1e150 || o > 1e150);
                }
            }
            assert_eq!(key(nearest_edge_pair(&ta, &tb)), key(scalar));
            // Pairs as near as the nearest, after it in the order.
            let all = {
                let mut d = Vec::new();
                for i in 0..3 {
                    for j in 0..3 {
                        let (p0, p1) = (ta.v[i], ta.v[(i + 1) % 3]);
                        let (q0, q1) = (tb.v[j], tb.v[(j + 1) % 3]);
                        let (s, r) = segment_params(&p0, &p1, &q0, &q1);
                        d.push(((p0 + (p1 - p0) * s) - (q0 + (q1 - q0) * r)).norm_squared());
                    }
                }
                d
            };
            ties += usize::from(all.iter().filter(|&&d| d == scalar.2.d2).count() > 1);
            n += 1;
        }
    }
    assert!(n > 8000 && ties > 500 && left > 0, "{n} {ties} {left}");
}

/// [`vertex_over_face`], the band's shortcut, against the full search it skips: on
/// nearly parallel pairs apart by 1e-1..1e-7 of their size (tilted up to 1e-2, at
/// every scale and offset), whenever it answers, the same distance as
/// [`closest_search`] to within its rounding and, to within the check's tolerance, the
/// exact one (`check`); it answers many of them (43%); and it declines a triangle with a
/// vertex on the other's plane (exactly) or crossing it.
#[test]
fn vertex_over_face_is_the_full_search() {
    let mut r = Rng(77);
    let (mut hits, mut cases) = (0, 0);
    for &(o, s) in FRAMES.iter() {
        let c = [o, 0.7 * o, -0.4 * o];
        for i in 0..600 {
            let t = random_tri(&mut r, &c, s);
            let gap = s * [1e-1, 1e-3, 1e-5, 1e-7][i % 4];
            let tilt = [0.0, 1e-6, 1e-2][i % 3];
            // u: t shrunk or grown about a random point, shifted sideways and off the
            // plane by `gap`, each vertex tilted by up to `tilt`.
            let x = combo(&t, &r.bary());
            let (g, shrink) = (r.v(s * 0.3), 0.3 + r.unit());
            let n = unit(&local(&t[1], &t[0]).cross(&local(&t[2], &t[0]))).unwrap();
            let u = t.map(|p| {
                let h = gap + tilt * s * r.f();
                [0, 1, 2].map(|k| x[k] + (p[k] - x[k]) * shrink + g[k] + n[k] * h)
            });
            let (a, b) = if i % 2 == 0 {
                (Polygon::tri(t), Polygon::tri(u))
            } else {
                (Polygon::tri(u), Polygon::tri(t))
            };
            if meet(&a, &b) {
                continue;
            }
            cases += 1;
            let o3 = a.t[0][0];
            let (ta, tb) = (Tri::new(&a.t[0], &o3), Tri::new(&b.t[0], &o3));
            let full = closest_search(&ta, &tb);
            let short =
                vertex_over_face(&ta, &tb, false).or_else(|| vertex_over_face(&tb, &ta, true));
            if let Some(c) = short {
                hits += 1;
                let e = extent(&a, &b);
                assert!(
                    (c.d2.sqrt() - full.d2.sqrt()).abs() <= 8.0 * EPS * (e + o.abs()),
                    "{a:?} {b:?}: {} vs {}",
                    c.d2,
                    full.d2
                );
                let w = check(&a, &b, true);
                assert_within(&w, 16.0);
            }
        }
    }
    assert!(hits * 4 > cases, "{hits} of {cases}");
    // Slivers given in f64 (a placed mesh's world positions, not rounded to f32): the
    // rounding of a sliver's normal turns its plane by eps over its width, so the
    // shortcut must not take a vertex over a sliver's face unless its lever is short;
    // whenever it answers, the full search's distance. (A pair found in a review:
    // the shortcut had answered it 3.8e7 eps off; reference 9.99999977648215e-3.)
    let mut slivers = 0;
    let mut tried = 0;
    for &(o, s) in FRAMES.iter() {
        let c = [o, 0.7 * o, -0.4 * o];
        for i in 0..600 {
            let (u0, u1) = (plus(&c, &r.v(s)), plus(&c, &r.v(s)));
            let width = s * [1e-3, 1e-6, 1e-9][i % 3];
            let side = r.v(1.0);
            let u2 = [0, 1, 2].map(|k| u0[k] + (u1[k] - u0[k]) * 0.7 + side[k] * width);
            // A triangle on one side of the sliver, its nearest vertex over the
            // sliver's interior at 1e-2 of the size, the others farther (the review's
            // pair's shape).
            let d = local(&u1, &u0);
            let up = unit(&d.cross(&V::new(side[0], side[1], side[2]))).unwrap();
            let x = combo(&[u0, u1, u2], &[0.15, 0.45, 0.4]);
            let at = |h: f64, lat: P3| [0, 1, 2].map(|k| x[k] + up[k] * h + lat[k]);
            let t = [
                at(1e-2 * s, [0.0; 3]),
                at(0.3 * s, r.v(s)),
                at(0.5 * s, r.v(s)),
            ];
            let (a, b) = (
                Polygon { t: [t, t], n: 1 },
                Polygon {
                    t: [[u0, u1, u2]; 2],
                    n: 1,
                },
            );
            let (a, b) = if i % 2 == 0 { (a, b) } else { (b, a) };
            if meet(&a, &b) {
                continue;
            }
            tried += 1;
            let o3 = a.t[0][0];
            let (ta, tb) = (Tri::new(&a.t[0], &o3), Tri::new(&b.t[0], &o3));
            let short =
                vertex_over_face(&ta, &tb, false).or_else(|| vertex_over_face(&tb, &ta, true));
            if let Some(c) = short {
                let full = closest_search(&ta, &tb);
                let e = extent(&a, &b);
                assert!(
                    (c.d2.sqrt() - full.d2.sqrt()).abs() <= 8.0 * EPS * (e + o.abs()),
                    "{a:?} {b:?}: {} vs {}",
                    c.d2.sqrt(),
                    full.d2.sqrt()
                );
                slivers += 1;
            }
        }
    }
    // (It declines nearly all of them: its vertex is over the sliver's face.)
    assert!(tried > 3000 && slivers < tried / 10, "{slivers} of {tried}");
    let a = [
        [10.145236234003264, -3.779050464868244, 2.83189447170406],
        [10.413764037492902, -4.1052915769243485, 2.3961617531574735],
        [10.51528265759951, -4.002821221684266, 2.8195922233804005],
    ];
    let b = [
        [10.0, -4.0, 2.0],
        [10.171717171717171, -3.7373737373737375, 2.9494949494949494],
        [10.137176906555084, -3.790200023445166, 2.75850760577517],
    ];
    let g = contact_geometry(&[a, a], 1, &[b, b], 1);
    assert!((-g.depth - 9.99999977648215e-3).abs() < 8.0 * EPS, "{g:?}");
    // A vertex exactly on the other's plane, the rest above it; and a triangle whose
    // nearest vertex is over the face at 0.3 but which crosses the plane just beyond
    // the face's edge (0.084 from it): declined (the full search decides).
    let f = [[0.0, 0.0, 0.0], [4.0, 0.0, 0.0], [0.0, 4.0, 0.0]];
    let on = [[1.0, 1.0, 0.0], [1.0, 1.5, 1.0], [1.5, 1.0, 2.0]];
    let across = [[3.9, 0.01, 0.3], [4.3, 0.01, -0.3], [5.0, 1.0, 2.0]];
    let o3 = f[0];
    let face = Tri::new(&f, &o3);
    for t in [on, across] {
        let t = Tri::new(&t, &o3);
        assert!(vertex_over_face(&t, &face, false).is_none());
        assert!(vertex_over_face(&face, &t, true).is_none());
    }
    let near = closest(&Tri::new(&across, &o3), &face).d2.sqrt();
    assert!(near < 0.09, "{near}");
}

/// Band pairs with a quad that is bent, or planar but not convex (a dart), and the
/// other's vertex just off it on the concave side: the closest points' direction does
/// not separate the quad's hull, only its nearest triangle. A review found the first
/// version of `separating` checking the hull: the normal came out 0.34 rad (bent) and
/// 0.87 rad (dart) off the exact direction, and the pair 13 times slower.
#[test]
fn band_normals_of_bent_and_dart_quads() {
    let third = f32r(1.0 / 6.0);
    let above = f32::from_bits((third as f32).to_bits() + 1) as f64;
    let cases = [
        (
            Polygon::quad([
                [0.0, 0.0, 0.0],
                [1.0, 0.0, 0.25],
                [1.0, 1.0, 0.0],
                [0.0, 1.0, 0.25],
            ]),
            Polygon::tri([
                [0.5, 0.5, 5.960464477539063e-8],
                [0.3, 0.5, 1.0],
                [0.5, 0.7, 1.0],
            ]),
        ),
        (
            Polygon::quad([
                [0.0, 0.0, 0.0],
                [1.0, 0.0, 0.0],
                [0.25, 0.25, 0.0],
                [0.0, 1.0, 0.0],
            ]),
            Polygon::tri([[0.5, above, 0.0], [0.6, 0.6, 0.3], [0.7, 0.5, -0.2]]),
        ),
    ];
    for (a, b) in cases {
        for (a, b, flip) in [(&a, &b, 1.0), (&b, &a, -1.0)] {
            assert!(!meet(a, b));
            let g = geometry(a, b);
            basic(&g);
            let (dist, ra, rb) = poly_poly_closest(a, b);
            let r = to_f(&scale3(&sub3(&ra, &rb), Dd::from(1.0) / dist));
            let cos: f64 = (0..3).map(|k| r[k] * g.normal[k]).sum();
            assert!(
                cos > 1.0 - 1e-12,
                "{flip}: normal {:?} vs exact {r:?}",
                g.normal
            );
        }
    }
}

/// A vertex of b on an edge or a corner of a (float positions in a plane z = h, b's
/// other corners above it), both placed by one rotation in `f64`: the rounding leaves
/// them apart by about 1e-17 (or meeting). Apart, the normal must separate them by
/// their distance (double-double, against the reference distance): the nearest edge
/// parameters are then a rounding away from their ends, and the features' own normal
/// pointed anywhere (contact_check's "touching, placed": separations 0.3 short of the
/// distance in 226 of 2,996 pairs before `separating`).
#[test]
fn placed_touching_band_normals() {
    let mut i = 0;
    let w = run("placed touching, band normals", 16.0, |r, c, s| {
        i += 1;
        let h = f32r(r.f() * s);
        let t = [
            [0.0, 0.0, h],
            [f32r(s), 0.0, h],
            [f32r(0.25 * s), f32r(s), h],
        ];
        let q = if i % 2 == 0 {
            [f32r(s * (0.1 + 0.8 * r.f().abs())), 0.0, h]
        } else {
            t[1]
        };
        let up = |r: &mut Rng| {
            let d = r.v(0.5 * s);
            [
                f32r(q[0] + d[0]),
                f32r(q[1] + d[1]),
                f32r(h + s * (0.1 + r.f().abs())),
            ]
        };
        let u = [q, up(r), up(r)];
        let m = random_rotation(r);
        let (a, b) = (placed(&m, c, t), placed(&m, c, u));
        let g = geometry(&a, &b);
        basic(&g);
        assert_eq!(g.intersecting, meet(&a, &b));
        if g.intersecting {
            return Worst::default();
        }
        let n = d3(&g.normal);
        let proj = |p: &P3| dot3(&n, &d3(p));
        let amin = a.t[0]
            .iter()
            .map(proj)
            .fold(Dd::from(f64::INFINITY), |m, x| if x < m { x } else { m });
        let bmax =
            b.t[0].iter().map(proj).fold(
                Dd::from(f64::NEG_INFINITY),
                |m, x| if x > m { x } else { m },
            );
        let gap = (amin - bmax).f();
        let dist = poly_poly_closest(&a, &b).0.f();
        let unit = EPS * extent(&a, &b);
        assert!(
            gap >= dist - 16.0 * unit,
            "gap {gap:e} < distance {dist:e}: {g:?}"
        );
        Worst {
            cases: 1,
            distance: (-g.depth - dist).abs() / unit,
            ..Worst::default()
        }
    });
    assert!(w.cases > 200, "{w:?}");
}

/// Band distances against brute force: the distance of random point pairs on the two
/// polygons is never below the reported distance, and the best of them comes close.
#[test]
fn band_distance_against_sampling() {
    let mut r = Rng(777);
    let mut cases = 0;
    let mut worst_gap: f64 = 0.0;
    while cases < 100 {
        let (a, b) = crossing_pair(&mut r, &[0.0; 3], 1.0);
        let g = geometry(&a, &b);
        if !g.intersecting {
            continue;
        }
        // Apart by up to a quarter of their size, as quads half the time.
        let d = g.normal.map(|x| x * (g.depth + 0.25 * (r.f() + 0.5)));
        let a = a.moved(&d);
        let a = if cases % 2 == 0 {
            let t = a.t[0];
            Polygon::quad([t[0], t[1], t[2], combo(&t, &[-0.5, 0.8, 0.7])])
        } else {
            Polygon::tri(a.t[0])
        };
        let g = geometry(&a, &b);
        if g.intersecting {
            continue;
        }
        cases += 1;
        // Closest points lie on edges or at vertices of one of the two at least: sample
        // those often.
        let sample = |r: &mut Rng, p: &Polygon| {
            let t = p.t[(r.next() % p.n as u64) as usize];
            let mut w = r.bary();
            match r.next() % 4 {
                0 => w = [1.0, 0.0, 0.0],
                1 | 2 => {
                    let k = (r.next() % 3) as usize;
                    w[k] = 0.0;
                    let sum = w[0] + w[1] + w[2];
                    w = w.map(|x| x / sum);
                }
                _ => {}
            }
            let k = (r.next() % 3) as usize;
            combo(&[t[k], t[(k + 1) % 3], t[(k + 2) % 3]], &w)
        };
        let mut best = f64::INFINITY;
        for _ in 0..100_000 {
            let (x, y) = (sample(&mut r, &a), sample(&mut r, &b));
            let d = ((x[0] - y[0]).powi(2) + (x[1] - y[1]).powi(2) + (x[2] - y[2]).powi(2)).sqrt();
            assert!(d >= -g.depth - 1e-12, "sampled {d} below {}", -g.depth);
            best = best.min(d);
        }
        worst_gap = worst_gap.max(best + g.depth);
    }
    println!("best sampled distance minus reported, worst: {worst_gap:e}");
    assert!(worst_gap < 1e-2, "{worst_gap}");
}
