//! Tests of the intersection's ends where rounding could move them: shallow crossings, and
//! placed meshes' nearly coplanar pairs and folded neighbours (`f64` world positions).

use super::support::*;
use crate::geom::contact::ContactGeometry;
use crate::geom::predicates::P3;
use crate::geom::test_rng::Rng;

/// Two triangles of one mesh plane (float positions in a plane z = h), placed as a transformed
/// mesh is: turned by a random rotation and moved, in `f64` (world positions that are
/// not floats). The rounding leaves the planes about 1e-16 rad apart: the pair crosses
/// (or misses by about 1e-17) along a line whose direction the cross of the normals
/// gets wrong entirely, and whose crossing points need distances of about 1e-17 that
/// the rounded edge differences cannot give. (Found by contact_check's placed families:
/// ends 1.8e7 float ulps off before the distances took the differences' rounding
/// errors and the ends were ordered along the longer cut.)
#[test]
fn placed_nearly_coplanar_crossings() {
    let mut pairs = Vec::new();
    let w = run("placed, nearly coplanar", 16.0, |r, c, s| {
        // (The plane off the rotation's centre, as a mesh's plane is.)
        let h = f32r(r.f() * s);
        let flat = |r: &mut Rng, at: [f64; 2]| -> [P3; 3] {
            [0, 1, 2].map(|_| {
                let q = r.v(s);
                [f32r(at[0] + q[0]), f32r(at[1] + q[1]), h]
            })
        };
        let (t, u) = (flat(r, [0.0, 0.0]), flat(r, [0.2 * s, 0.1 * s]));
        // A rotation from a random unit quaternion, then the move to `c`.
        let m = random_rotation(r);
        let (a, b) = (placed(&m, c, t), placed(&m, c, u));
        if !meet(&a, &b) {
            return Worst::default();
        }
        pairs.push((a, b));
        placed_ends(&a, &b)
    });
    assert!(w.cases > 500, "{w:?}");
    // The lanes answer them bit for bit as the scalar path.
    #[cfg(target_arch = "x86_64")]
    {
        let mut out: Vec<ContactGeometry> = pairs.iter().map(|(a, b)| geometry(a, b)).collect();
        let want = out.clone();
        both_kernels(&mut out, true, fetch_from(&pairs)).unwrap();
        for (g, h) in out.iter().zip(&want) {
            assert_eq!(bits(g), bits(h), "{g:?} {h:?}");
        }
    }
}

/// The checks of [`check`] that hold for `f64` positions (its depth reference needs
/// exact differences): the flag, the ends on both triangles and on the exact
/// intersection (double-double), for a crossing pair of triangles.
fn placed_ends(a: &Polygon, b: &Polygon) -> Worst {
    let g = geometry(a, b);
    basic(&g);
    assert!(g.intersecting && !g.coplanar, "{g:?}");
    let mag = EPS * magnitude(a, b);
    let (r0, r1) = reference_ends(a, b).expect("meeting polygons have a piece");
    let mut w = Worst {
        cases: 1,
        ..Worst::default()
    };
    for p in [&g.point_a, &g.point_b] {
        w.on_polygons = w
            .on_polygons
            .max(poly_dist(p, a).max(poly_dist(p, b)) / mag);
        let x = d3(p);
        let d = norm3(&sub3(&x, &seg_closest(&x, &r0, &r1))).f();
        w.on_intersection = w.on_intersection.max(d / mag);
    }
    let direct = dist_dd(&g.point_a, &r0).max(dist_dd(&g.point_b, &r1));
    let swapped = dist_dd(&g.point_a, &r1).max(dist_dd(&g.point_b, &r0));
    w.ends = direct.min(swapped) / mag;
    w
}

/// Pairs of contact_check's "coplanar, placed" family (two triangles of a plane
/// z = c, x = c or y = x, turned by one rotation in `f64`): before the fixes above,
/// their ends were off by 1e7 float ulps (the first ones: the distances; the last:
/// the ends' order along the normals' cross).
#[test]
fn placed_nearly_coplanar_known_pairs() {
    let pairs: [([P3; 3], [P3; 3]); 3] = [
        (
            [
                [0.6415250228416145, 0.41072174910681886, 0.42156423799090614],
                [0.8877799692608426, 0.978890268581914, 0.5940424203293131],
                [
                    -0.29167125660734405,
                    -0.9977977622780284,
                    -0.21272112784109543,
                ],
            ],
            [
                [0.6164615079785485, -0.4584403297298992, 0.3829468532453278],
                [
                    -0.07037727566384085,
                    0.3576494968463807,
                    -0.03579236395156003,
                ],
                [0.21845301397630174, -1.20827202667814, 0.10855328039739387],
            ],
        ),
        (
            [
                [
                    -0.025262942234202335,
                    0.6771316536722247,
                    -0.990385546710411,
                ],
                [-1.16150803367982, 0.36613106935855894, 0.4476123701102705],
                [-0.8899243717988565, 0.5829246635892422, 0.2845554115193106],
            ],
            [
                [0.07806352330540456, 0.8145947405791685, -0.9826996137576225],
                [-1.1065813504215143, 0.5352628394309864, 0.5735095868588895],
                [-0.8468570247172413, 0.1986255217816889, -0.2722255995336928],
            ],
        ),
        (
            [
                [
                    -0.024689896145649565,
                    -0.644529359445771,
                    -0.16578366949100914,
                ],
                [-0.4582140774928679, 0.2218794335301869, 0.41626872050820934],
                [0.3618097837562834, -0.580728825287787, 0.6692725810624705],
            ],
            [
                [
                    0.07562157060642033,
                    -0.07215477076570226,
                    0.9508893601924492,
                ],
                [
                    -0.10627038550108411,
                    0.08503394263404604,
                    0.8610265476499976,
                ],
                [
                    0.20229234409488395,
                    -0.9556268316695622,
                    -0.23975195682506575,
                ],
            ],
        ),
    ];
    let mut w = Worst::default();
    for (i, (a, b)) in pairs.into_iter().enumerate() {
        let (a, b) = (Polygon { t: [a, a], n: 1 }, Polygon { t: [b, b], n: 1 });
        assert!(meet(&a, &b), "pair {i}");
        w.merge(&placed_ends(&a, &b));
    }
    report("placed, nearly coplanar, known", &w);
    assert_within(&w, 16.0);
}

/// Neighbours of a folding mesh, placed: b shares a's corner 0 (or its edge 0-1) and
/// lies folded flat onto a, in a plane z = h of float positions, both turned by one
/// rotation in `f64`. The planes come out about 1e-16 rad apart and cross along a
/// line through the shared corner: the cut from that corner (a vertex exactly on the
/// other plane) to the opposite edge needs the accurate distances too (contact_check's
/// "shared corner or edge, folded, placed": ends 1e7 float ulps off in 958 of 3,000
/// pairs before).
#[test]
fn placed_neighbours_folded_flat() {
    let mut i = 0;
    let w = run("placed neighbours, folded flat", 16.0, |r, c, s| {
        i += 1;
        let h = f32r(r.f() * s);
        let a = [
            [0.0, 0.0, h],
            [f32r(s), 0.0, h],
            [
                f32r(s * (0.5 + 0.4 * r.f())),
                f32r(s * (0.65 + 0.35 * r.f())),
                h,
            ],
        ];
        let inside = |r: &mut Rng| {
            let w1 = 0.05 + 0.4 * r.f().abs();
            let w2 = 0.05 + 0.4 * r.f().abs();
            [f32r(w1 * a[1][0] + w2 * a[2][0]), f32r(w2 * a[2][1]), h]
        };
        let b = if i % 2 == 0 {
            [a[0], inside(r), inside(r)]
        } else {
            [a[0], a[1], inside(r)]
        };
        let m = random_rotation(r);
        let (pa, pb) = (placed(&m, c, a), placed(&m, c, b));
        assert!(meet(&pa, &pb));
        if geometry(&pa, &pb).coplanar {
            return Worst::default();
        }
        placed_ends(&pa, &pb)
    });
    assert!(w.cases > 1000, "{w:?}");
}

/// Shallow crossings: b crosses a's plane at dihedral angles down to 1e-6 (the
/// intersection's ends are then ill-conditioned in a naive evaluation).
#[test]
fn shallow_crossings() {
    let mut angles = [1e-2, 1e-3, 1e-4, 1e-5, 1e-6].iter().cycle();
    run("shallow crossings", 16.0, |r, c, s| {
        let angle = angles.next().copied().unwrap_or(1e-3);
        let t = random_tri(r, c, s);
        let x = combo(&t, &r.bary());
        // A direction in a's plane and one out of it, tilted by `angle`.
        let e = [0, 1, 2].map(|k| t[1][k] - t[0][k]);
        let f = [0, 1, 2].map(|k| t[2][k] - t[0][k]);
        let n = [
            e[1] * f[2] - e[2] * f[1],
            e[2] * f[0] - e[0] * f[2],
            e[0] * f[1] - e[1] * f[0],
        ];
        let nl = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
        let el = (e[0] * e[0] + e[1] * e[1] + e[2] * e[2]).sqrt();
        let g = [0, 1, 2].map(|k| f[k] - e[k] * 0.3);
        let u = [
            [0, 1, 2].map(|k| x[k] - e[k] / el * s * 0.4 - n[k] / nl * s * angle),
            [0, 1, 2].map(|k| x[k] + e[k] / el * s * 0.4 + n[k] / nl * s * angle),
            [0, 1, 2].map(|k| x[k] + g[k] * 0.5 + n[k] / nl * s * angle * (r.f() + 0.2)),
        ];
        check(&Polygon::tri(t), &Polygon::tri(u), true)
    });
}
