//! Tests of the general path: coplanar pairs, degenerate polygons (segments, points),
//! quads, coarse grids and extreme values.

use super::support::*;
use crate::geom::contact::contact_geometry;
use crate::geom::test_rng::Rng;

#[test]
fn coplanar_overlap_known_answer() {
    let a = Polygon::tri([[0.0, 0.0, 0.0], [2.0, 0.0, 0.0], [0.0, 2.0, 0.0]]);
    let b = Polygon::tri([[0.5, 0.5, 0.0], [3.0, 0.5, 0.0], [0.5, 3.0, 0.0]]);
    let g = geometry(&a, &b);
    assert!(g.intersecting && g.coplanar && g.depth == 0.0);
    assert_eq!(g.normal, [0.0, 0.0, 1.0]);
    assert!(
        ends_are(&g, &[1.5, 0.5, 0.0], &[0.5, 1.5, 0.0], 1e-15),
        "{g:?}"
    );
    // a wound the other way: its normal flips.
    let a2 = Polygon::tri([[0.0, 0.0, 0.0], [0.0, 2.0, 0.0], [2.0, 0.0, 0.0]]);
    assert_eq!(geometry(&a2, &b).normal, [0.0, 0.0, -1.0]);
    // Contained: the inner triangle's longest edge.
    let c = Polygon::tri([[0.1, 0.1, 0.0], [0.5, 0.1, 0.0], [0.1, 0.2, 0.0]]);
    let g = geometry(&a, &c);
    let (c1, c2) = ([0.5, 0.1, 0.0].map(f32r), [0.1, 0.2, 0.0].map(f32r));
    assert!(g.coplanar && ends_are(&g, &c1, &c2, 0.0), "{g:?}");
    // Touching at one vertex, and along part of an edge.
    let d = Polygon::tri([[2.0, 0.0, 0.0], [3.0, 0.0, 0.0], [3.0, 1.0, 0.0]]);
    let g = geometry(&a, &d);
    assert!(g.coplanar && ends_are(&g, &[2.0, 0.0, 0.0], &[2.0, 0.0, 0.0], 0.0));
    let e = Polygon::tri([[1.0, 0.0, 0.0], [3.0, 0.0, 0.0], [2.0, -1.0, 0.0]]);
    let g = geometry(&a, &e);
    assert!(g.coplanar && ends_are(&g, &[1.0, 0.0, 0.0], &[2.0, 0.0, 0.0], 1e-15));
    for (x, y) in [(&a, &b), (&a, &c), (&a, &d), (&a, &e), (&b, &a), (&e, &a)] {
        check(x, y, false);
    }
}

#[test]
fn degenerate_polygons() {
    let t = Polygon::tri([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]);
    // A segment piercing the face: one point; depth: out through the nearest edges.
    let s = Polygon::tri([[0.2, 0.2, -1.0], [0.2, 0.2, 1.0], [0.2, 0.2, 0.5]]);
    for (x, y) in [(&s, &t), (&t, &s)] {
        let g = geometry(x, y);
        assert!(g.intersecting && !g.coplanar);
        let m = [0.2, 0.2, 0.0].map(f32r);
        assert!(ends_are(&g, &m, &m, 0.0), "{g:?}");
        assert_eq!(g.depth, f32r(0.2), "{g:?}");
        check(x, y, false);
    }
    // A point on the face: coplanar, normal = the face's (the point has none).
    let p = Polygon::tri([[0.2, 0.2, 0.0]; 3]);
    let g = geometry(&p, &t);
    assert!(g.intersecting && g.coplanar && g.depth == 0.0);
    assert_eq!(g.normal, [0.0, 0.0, 1.0]);
    let q = [0.2, 0.2, 0.0].map(f32r);
    assert_eq!((g.point_a, g.point_b), (q, q));
    // Two crossing segments: coplanar, meeting in a point; normal across both.
    let sa = Polygon::tri([[-1.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 0.0, 0.0]]);
    let sb = Polygon::tri([[0.0, -1.0, 0.0], [0.0, 1.0, 0.0], [0.0, 1.0, 0.0]]);
    let g = geometry(&sa, &sb);
    assert!(g.intersecting && g.coplanar && g.depth == 0.0);
    assert_eq!((g.point_a, g.point_b), ([0.0; 3], [0.0; 3]));
    assert_eq!(g.normal[2].abs(), 1.0);
    // Collinear overlapping segments: the overlap's ends; normal across the line.
    let sc = Polygon::tri([[0.5, 0.0, 0.0], [3.0, 0.0, 0.0], [3.0, 0.0, 0.0]]);
    let g = geometry(&sa, &sc);
    assert!(g.intersecting && g.coplanar);
    assert!(
        ends_are(&g, &[0.5, 0.0, 0.0], &[1.0, 0.0, 0.0], 0.0),
        "{g:?}"
    );
    assert_eq!(g.normal[0], 0.0);
    // The same point twice: +z.
    let g = geometry(&p, &p);
    assert!(g.intersecting && g.coplanar && g.normal == [0.0, 0.0, 1.0]);
    // A point on a segment.
    let on = Polygon::tri([[0.25, 0.0, 0.0]; 3]);
    let g = geometry(&on, &sa);
    assert!(g.intersecting && g.coplanar && g.point_a == [0.25, 0.0, 0.0]);
    assert_eq!(g.normal[0], 0.0);
    // A segment in the triangle's plane across it: the clipped segment.
    let across = Polygon::tri([[-1.0, 0.25, 0.0], [2.0, 0.25, 0.0], [2.0, 0.25, 0.0]]);
    let g = geometry(&across, &t);
    assert!(g.intersecting && g.coplanar);
    assert!(
        ends_are(&g, &[0.0, 0.25, 0.0], &[0.75, 0.25, 0.0], 1e-16),
        "{g:?}"
    );
    assert_eq!(g.normal, [0.0, 0.0, 1.0]); // t's, the segment having none
                                           // Skew segments 0.5 apart: band, normal along their cross, from b to a.
    let up = Polygon::tri([[0.0, -1.0, 0.5], [0.0, 1.0, 0.5], [0.0, 1.0, 0.5]]);
    let g = geometry(&up, &sa);
    assert!(!g.intersecting && g.depth == -0.5);
    assert_eq!(g.normal, [0.0, 0.0, 1.0]);
    assert_eq!((g.point_a, g.point_b), ([0.0, 0.0, 0.5], [0.0; 3]));
    let g = geometry(&sa, &up);
    assert_eq!(g.normal, [0.0, 0.0, -1.0]);
    // A point under the face.
    let below = Polygon::tri([[0.25, 0.25, -1e-7]; 3]);
    let g = geometry(&below, &t);
    assert!(!g.intersecting && g.normal == [0.0, 0.0, -1.0]);
    assert_eq!(g.depth, -f32r(1e-7));
    let g = geometry(&t, &below);
    assert!(!g.intersecting && g.normal == [0.0, 0.0, 1.0]);
    // A quad whose second triangle is a segment (v3 = v2), and one that is a point.
    let q = Polygon::quad([
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [1.0, 1.0, 0.0],
        [1.0, 1.0, 0.0],
    ]);
    let pierce = Polygon::tri([[0.5, 0.25, -1.0], [0.5, 0.25, 1.0], [0.6, 0.25, 1.0]]);
    let g = geometry(&q, &pierce);
    assert!(g.intersecting && !g.coplanar);
    let flatq = Polygon::quad([[0.0; 3]; 4]);
    let g = geometry(&flatq, &t);
    assert!(g.intersecting && g.coplanar && g.normal == [0.0, 0.0, 1.0]);
    for (x, y) in [
        (&s, &t),
        (&p, &t),
        (&sa, &sb),
        (&sa, &sc),
        (&on, &sa),
        (&across, &t),
        (&up, &sa),
        (&below, &t),
        (&q, &pierce),
        (&flatq, &t),
        (&p, &p),
    ] {
        check(x, y, false);
        check(y, x, false);
    }
}

#[test]
fn random_crossing_quads_and_mixed() {
    run("crossing quads/mixed", 16.0, |r, c, s| {
        let (t, u) = crossing_pair(r, c, s);
        // Extend either triangle to a quad by a fourth vertex beyond an edge (planar or
        // not, convex or not).
        let extend = |r: &mut Rng, p: &Polygon| {
            let t = p.t[0];
            let w = [r.f() + 0.5, 0.0, 0.0];
            let mid = combo(&t, &[0.0, 1.0 - w[0], w[0]]);
            let away = [0, 1, 2].map(|k| mid[k] + (mid[k] - t[0][k]) * (r.f() + 0.6));
            let h = [0.0, 0.1, 1.0][(r.next() % 3) as usize];
            let lift = r.v(s * h);
            Polygon::quad([t[0], t[1], t[2], plus(&away, &lift)])
        };
        let (a, b) = match r.next() % 3 {
            0 => (extend(r, &t), u),
            1 => (t, extend(r, &u)),
            _ => (extend(r, &t), extend(r, &u)),
        };
        check(&a, &b, true)
    });
}

#[test]
fn random_coplanar_pairs() {
    run("coplanar", 16.0, |r, c, s| {
        // In an axis plane (exact after rounding), overlapping or nearly touching.
        let ax = (r.next() % 3) as usize;
        let z = c[ax] + r.f() * s;
        let pt = |r: &mut Rng, spread: f64| {
            let mut p = plus(c, &r.v(spread));
            p[ax] = z;
            p
        };
        let a = if r.next() % 2 == 0 {
            Polygon::tri([pt(r, s), pt(r, s), pt(r, s)])
        } else {
            Polygon::quad([pt(r, s), pt(r, s), pt(r, s), pt(r, s)])
        };
        let b = Polygon::tri([pt(r, s), pt(r, s), pt(r, s)]);
        let g = geometry(&a, &b);
        assert!(g.coplanar == g.intersecting, "{g:?}");
        let w = check(&a, &b, false);
        assert!(w.on_polygons < 16.0, "{a:?} {b:?} {g:?} {w:?}");
        w
    });
}

/// Random triangles and quads with coordinates on a coarse grid (ties, shared and
/// repeated vertices, flat triangles, coplanar sets) at every scale: every output
/// finite, normals unit, and every check that applies.
#[test]
fn fuzz_degenerate_grids() {
    let mut r = Rng(0xDEAD_BEEF_1234_5678);
    let mut w = Worst::default();
    let mut counts = [0usize; 3];
    for i in 0..30_000 {
        let (o, s) = FRAMES[i % FRAMES.len()];
        let grid = [2u64, 3, 5][i % 3];
        let c = [o, o, -o];
        let pt = |r: &mut Rng| {
            let mut p = [0.0; 3];
            for k in 0..3 {
                p[k] = c[k] + s * (r.next() % grid) as f64 / grid as f64;
            }
            p
        };
        let poly = |r: &mut Rng| {
            let mut v = [pt(r), pt(r), pt(r), pt(r)];
            // Often repeat vertices: segments and points.
            if r.next().is_multiple_of(4) {
                v[1] = v[0];
            }
            if r.next().is_multiple_of(6) {
                v[2] = v[(r.next() % 2) as usize];
            }
            if r.next().is_multiple_of(2) {
                Polygon::tri([v[0], v[1], v[2]])
            } else {
                Polygon::quad(v)
            }
        };
        let (a, b) = (poly(&mut r), poly(&mut r));
        let g = geometry(&a, &b);
        basic(&g);
        counts[usize::from(g.intersecting) + usize::from(g.coplanar)] += 1;
        if i % 5 == 0 {
            w.merge(&check(&a, &b, false));
        }
    }
    report("degenerate grids", &w);
    println!("band / crossing / coplanar: {counts:?}");
    assert!(counts.iter().all(|&c| c > 1000), "{counts:?}");
    assert_within(&w, 16.0);
}

/// Extreme magnitudes and random bits in the f32 range: finite, unit, no panic.
#[test]
fn fuzz_extreme_values() {
    let mut r = Rng(77);
    for i in 0..20_000 {
        let scale = [1e-38, 1e-30, 1e-10, 1.0, 1e10, 1e30, 3e38][i % 7];
        let mut v = || {
            let x = if r.next().is_multiple_of(8) {
                f32::from_bits(r.next() as u32)
            } else {
                (r.f() * scale) as f32
            };
            if x.is_finite() {
                f64::from(x)
            } else {
                0.0
            }
        };
        let mut p = || [v(), v(), v()];
        let a = [[p(), p(), p()], [p(), p(), p()]];
        let b = [[p(), p(), p()], [p(), p(), p()]];
        let (na, nb) = (1 + i % 2, 1 + (i / 2) % 2);
        let g = contact_geometry(&a, na, &b, nb);
        basic(&g);
    }
    // Counts out of range are clamped.
    let t = [[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]; 2];
    basic(&contact_geometry(&t, 0, &t, 7));
}
