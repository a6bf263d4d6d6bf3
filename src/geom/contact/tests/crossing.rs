//! Tests of two triangles crossing: the fast path and the segment path against the
//! references, the decision against the exact test, the AVX2 build against the baseline
//! and both against the general path.

use super::support::*;
use crate::geom::contact::crossing::segment_crossing;
use crate::geom::contact::general::general;
use crate::geom::contact::{contact_geometry_any, finish, ContactGeometry};
use crate::geom::predicates::P3;
use crate::geom::test_rng::Rng;
use crate::geom::tritri::triangles_intersect;

#[test]
fn crossing_triangles_known_answer() {
    for o in [0.0, 1e3, 1e5] {
        let s = [o, o, o];
        let a = Polygon::tri([[-10.0, -10.0, 0.0], [10.0, -10.0, 0.0], [0.0, 10.0, 0.0]]).moved(&s);
        let b = Polygon::tri([[0.0, 0.0, -0.25], [0.5, 0.0, -0.25], [0.0, 0.0, 1.0]]).moved(&s);
        let g = geometry(&a, &b);
        basic(&g);
        assert!(g.intersecting && !g.coplanar);
        assert_eq!(g.depth, 0.25);
        assert_eq!(g.normal, [0.0, 0.0, -1.0]);
        let tol = 4.0 * EPS * (o + 1.0);
        assert!(ends_are(&g, &[o, o, o], &[o + 0.4, o, o], tol), "{g:?}");
        // Swapped: b moves up out of a.
        let g = geometry(&b, &a);
        assert_eq!(g.depth, 0.25);
        assert_eq!(g.normal, [0.0, 0.0, 1.0]);
        assert!(ends_are(&g, &[o, o, o], &[o + 0.4, o, o], tol), "{g:?}");
        check(&a, &b, true);
        check(&b, &a, true);
    }
}

#[test]
fn touching_is_intersecting_with_zero_depth() {
    let t = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
    let cases = [
        // Vertex on the face.
        [[0.25, 0.25, 0.0], [0.2, 0.2, 1.0], [0.3, 0.4, 1.0]],
        // Shared edge, different planes.
        [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.5, 0.0, 1.0]],
        // Shared vertex only.
        [[1.0, 0.0, 0.0], [2.0, 0.0, 1.0], [2.0, 1.0, 1.0]],
        // Vertex on an edge from the other side.
        [[0.5, 0.0, 0.0], [0.5, -1.0, 1.0], [0.5, -1.0, -1.0]],
        // Edge across an edge.
        [[0.5, -0.5, 0.0], [0.5, 0.5, 0.0], [0.5, 0.0, 1.0]],
    ];
    for o in [0.0, 1e5] {
        let s = [o, o, o];
        for u in &cases {
            let (a, b) = (Polygon::tri(t).moved(&s), Polygon::tri(*u).moved(&s));
            for (x, y) in [(&a, &b), (&b, &a)] {
                let g = geometry(x, y);
                assert!(g.intersecting && !g.coplanar, "{u:?}");
                assert_eq!(g.depth, 0.0, "{u:?} {g:?}");
                check(x, y, false);
            }
        }
    }
    // The vertex on the face: the intersection is that point.
    let g = geometry(&Polygon::tri(t), &Polygon::tri(cases[0]));
    assert_eq!(g.point_a, [0.25, 0.25, 0.0]);
    assert_eq!(g.point_b, [0.25, 0.25, 0.0]);
    // The shared edge: its two ends.
    let g = geometry(&Polygon::tri(t), &Polygon::tri(cases[1]));
    assert!(ends_are(&g, &[0.0; 3], &[1.0, 0.0, 0.0], 0.0), "{g:?}");
}

#[test]
fn random_crossing_triangles() {
    let w = run("crossing triangles", 16.0, |r, c, s| {
        let (a, b) = crossing_pair(r, c, s);
        check(&a, &b, true)
    });
    assert!(w.cases > 2000);
}

/// Slivers (aspect up to 1e7) against ordinary triangles and each other.
#[test]
fn slivers() {
    run("slivers", 16.0, |r, c, s| {
        let (a, b) = crossing_pair(r, c, s);
        let thin = |p: &Polygon, r: &mut Rng| {
            let t = p.t[0];
            let f = [1e-3, 1e-5, 1e-7][(r.next() % 3) as usize];
            let m = combo(&t, &[0.0, 0.5, 0.5]);
            let apex = [0, 1, 2].map(|k| m[k] + (t[0][k] - m[k]) * f);
            Polygon::tri([apex, t[1], t[2]])
        };
        let (a, b) = match r.next() % 3 {
            0 => (thin(&a, r), b),
            1 => (a, thin(&b, r)),
            _ => (thin(&a, r), thin(&b, r)),
        };
        check(&a, &b, false)
    });
}

/// The decision is the query's: `intersecting` against `triangles_intersect` on many
/// random triangle pairs, in general position and on small grids (ties, shared
/// vertices, coplanar and flat triangles), and on touching pairs far from the origin.
#[test]
fn decision_is_the_exact_test() {
    let mut r = Rng(0x5151_2024);
    let mut hits = [0usize; 2];
    for i in 0..300_000 {
        let grid = i % 3 == 0;
        let off = [0.0, 1e3, 1e5][i % 3 / 2 + (i % 7 == 0) as usize];
        let mut c = || {
            if grid {
                off + (r.next() % 4) as f64
            } else {
                off + r.f()
            }
        };
        let mut t = || [[c(), c(), c()], [c(), c(), c()], [c(), c(), c()]];
        let (a, b) = (Polygon::tri(t()), Polygon::tri(t()));
        let g = geometry(&a, &b);
        let want = triangles_intersect(&a.t[0], &b.t[0]);
        assert_eq!(g.intersecting, want, "{a:?} {b:?}");
        hits[usize::from(want)] += 1;
    }
    assert!(hits[0] > 50_000 && hits[1] > 50_000, "{hits:?}");
}

/// The AVX2 build of the function answers bit for bit as the baseline build, and the
/// triangle fast path as the general path (same flags; same geometry up to rounding).
#[test]
fn builds_and_paths_agree() {
    let mut r = Rng(0xABCD_EF01);
    let mut compared = 0;
    for i in 0..40_000 {
        let (o, sc) = FRAMES[i % FRAMES.len()];
        let c = [o, 0.5 * o, -o];
        let (a, b) = match i % 4 {
            0 | 1 => crossing_pair(&mut r, &c, sc),
            2 => {
                let (a, b) = crossing_pair(&mut r, &c, sc);
                let d = r.v(sc);
                (a.moved(&d.map(f32r)), b)
            }
            _ => {
                let grid = |r: &mut Rng| [0, 1, 2].map(|k| c[k] + sc * (r.next() % 3) as f64 / 2.0);
                let mut t = || [grid(&mut r), grid(&mut r), grid(&mut r)];
                (Polygon::tri(t()), Polygon::tri(t()))
            }
        };
        let g = geometry(&a, &b);
        let any = contact_geometry_any(&a.t, a.n, &b.t, b.n);
        let bits = |g: &ContactGeometry| {
            let f = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
            (
                f(&g.point_a),
                f(&g.point_b),
                f(&g.normal),
                g.depth.to_bits(),
            )
        };
        assert_eq!(bits(&g), bits(&any), "{a:?} {b:?}");
        let h = general(&a.t, 1, &b.t, 1);
        assert_eq!((g.intersecting, g.coplanar), (h.intersecting, h.coplanar));
        let ext = EPS * extent(&a, &b);
        let mag = EPS * magnitude(&a, &b);
        assert!((g.depth - h.depth).abs() <= 16.0 * ext, "{g:?} {h:?}");
        let same = |p: &P3, q: &P3| close(p, q, 64.0 * (mag + ext));
        assert!(
            (same(&g.point_a, &h.point_a) && same(&g.point_b, &h.point_b))
                || (same(&g.point_a, &h.point_b) && same(&g.point_b, &h.point_a)),
            "{g:?} {h:?}"
        );
        if !g.intersecting {
            assert_eq!(
                (g.point_a, g.point_b, g.normal),
                (h.point_a, h.point_b, h.normal)
            );
        }
        if g.intersecting && !g.coplanar && g.depth > 1e-3 * extent(&a, &b) {
            let dot: f64 = (0..3).map(|k| g.normal[k] * h.normal[k]).sum();
            // Ties between axes may pick different normals of (nearly) equal depth.
            if dot < 1.0 - 1e-9 {
                assert!((g.depth - h.depth).abs() <= 16.0 * ext, "{g:?} {h:?}");
            } else {
                compared += 1;
            }
        }
    }
    assert!(compared > 10_000, "{compared}");
}

/// A triangle with two equal corners crossing another (`segment_crossing`, what moved
/// `f32` slivers become): against the double-double references (`check`: the point on
/// the exact intersection, the depth, the separating margin) and next to the general
/// path it replaces (the same flags and, but at ties between axes, the same normal;
/// points and depths within 4 eps of each other); the segment either side, its twin
/// corners in every position, at every scale and offset.
#[test]
fn segment_crossing_is_the_general_path() {
    let mut r = Rng(0x5E6_0001);
    let (mut fast, mut all) = (0, 0);
    let mut worst = Worst::default();
    let mut apart_from_general = 0.0f64;
    for i in 0..20_000 {
        let (o, sc) = FRAMES[i % FRAMES.len()];
        let c = [o, -0.5 * o, 0.25 * o];
        let (a, b) = crossing_pair(&mut r, &c, sc);
        // `a` becomes a segment from its first corner through the crossing and on.
        let t = a.t[0];
        let x = combo(&b.t[0], &r.bary());
        let far = [0, 1, 2].map(|k| f32r(t[0][k] + (x[k] - t[0][k]) * (1.5 + r.f())));
        let (p, q) = (t[0], far);
        let seg = match i % 3 {
            0 => [p, p, q],
            1 => [p, q, p],
            _ => [q, p, p],
        };
        let (sa, sb) = if i % 2 == 0 {
            (Polygon::tri(seg), b)
        } else {
            (b, Polygon::tri(seg))
        };
        if !meet(&sa, &sb) {
            continue;
        }
        all += 1;
        let local = if i % 2 == 0 {
            segment_crossing(&sa.t[0], &sb.t[0], 1.0)
        } else {
            segment_crossing(&sb.t[0], &sa.t[0], -1.0)
        };
        let Some(local) = local else {
            continue;
        };
        fast += 1;
        let got = finish(&local, &[0.0; 3], &sa.t[0][0]);
        assert_eq!(got, geometry(&sa, &sb), "contact_geometry takes this path");
        worst.merge(&check(&sa, &sb, true));
        let want = general(&sa.t, 1, &sb.t, 1);
        let (m, e) = (magnitude(&sa, &sb), extent(&sa, &sb));
        assert!(want.intersecting && !want.coplanar && !got.coplanar);
        assert!(got.point_a == got.point_b);
        for k in 0..3 {
            let d = (got.point_a[k] - want.point_a[k]).abs() / (EPS * m);
            apart_from_general = apart_from_general.max(d);
        }
        let d = (got.depth - want.depth).abs() / (EPS * e);
        apart_from_general = apart_from_general.max(d);
        let same = (0..3).all(|k| (got.normal[k] - want.normal[k]).abs() < 1e-9);
        assert!(same || got.depth < 1e-6 * e, "{got:?} {want:?}");
    }
    report("segments crossing triangles", &worst);
    println!(
        "segment path answered {fast} of {all} crossing segment pairs; points and depths \
         within {apart_from_general:.2} eps of the general path's"
    );
    assert_within(&worst, 4.0);
    assert!(all > 5_000 && fast * 10 > all * 9, "{fast} of {all}");
}
