//! Tests of slivers, whose planes need the accurate crosses and normals: a vertex of the
//! other triangle just over their interior, at `f32` and at `f64` positions.

use super::support::*;
use crate::geom::contact::poly::{local, unit};
use crate::geom::contact::ContactGeometry;
use crate::geom::predicates::P3;
use crate::geom::test_rng::Rng;

/// A sliver `b` of `width` (its positions rounded to f32 or not) about `c`, and a
/// triangle `a` with a vertex `gap` (1e-3 to 1e-7 of `s`, either side) off the sliver's
/// interior and its others sideways and farther up (wholly above when that vertex is);
/// `a` and `b` swapped at random. `None` when the sliver is flat.
fn sliver_under_vertex(
    r: &mut Rng,
    c: &P3,
    s: f64,
    width: f64,
    f32_positions: bool,
) -> Option<(Polygon, Polygon, f64)> {
    let (u0, u1) = (plus(c, &r.v(s)), plus(c, &r.v(s)));
    let side = r.v(1.0);
    let u2 = [0, 1, 2].map(|k| u0[k] + (u1[k] - u0[k]) * 0.7 + side[k] * width);
    let tri = |t: [P3; 3]| {
        if f32_positions {
            Polygon::tri(t)
        } else {
            Polygon { t: [t, t], n: 1 }
        }
    };
    let b = tri([u0, u1, u2]);
    let [u0, u1, u2] = b.t[0];
    let up = unit(&local(&u1, &u0).cross(&local(&u2, &u0)))?;
    let x = combo(&[u0, u1, u2], &[0.15, 0.45, 0.4]);
    let sign = if r.next().is_multiple_of(2) {
        1.0
    } else {
        -1.0
    };
    let gap = sign * s * [1e-3, 1e-5, 1e-7][(r.next() % 3) as usize];
    let mut sideways = || {
        let v = r.v(s);
        let d = v[0] * up.x + v[1] * up.y + v[2] * up.z;
        [v[0] - d * up.x, v[1] - d * up.y, v[2] - d * up.z]
    };
    let (l1, l2) = (sideways(), sideways());
    let at = |h: f64, lat: P3| [0, 1, 2].map(|k| x[k] + up[k] * h + lat[k]);
    let a = tri([at(gap, [0.0; 3]), at(0.3 * s, l1), at(0.5 * s, l2)]);
    Some(if r.next().is_multiple_of(2) {
        (a, b, gap)
    } else {
        (b, a, gap)
    })
}

/// Slivers (f32 positions, off the origin) with a vertex of the other triangle 1e-3 to
/// 1e-7 of the size above their interior or through it: the distances and depths of
/// both paths against the double-double reference, at every scale and offset. A
/// sliver's plane must be right to the ulp (`accurate_cross`): the plain cross turns it
/// by eps over its width, which put depths 4.4e4 eps off (the translation by them not
/// separating) and distances 4.6e4 eps off (checked to fail so).
#[test]
fn slivers_with_a_vertex_over_them() {
    // Slivers at f32 positions, off the origin, a vertex 1e-3 to 1e-7 of the size above
    // their interior or through it: distances and depths (the sliver's normal to the
    // ulp: `accurate_cross`) against the double-double reference (`check`). (The plain
    // cross had put the review's pair 5.9e4 eps off.)
    let w = run("f32 slivers, vertex over the face", 16.0, |r, c, s| {
        match sliver_under_vertex(r, c, s, s * 1e-5, true) {
            Some((a, b, _)) => check(&a, &b, true),
            // Flat once rounded to f32 (far from the origin).
            None => Worst::default(),
        }
    });
    assert!(w.cases > 2000);
    let (a, b) = (
        Polygon::tri([
            [
                -0.45679670572280884,
                -0.456404447555542,
                -0.06319279223680496,
            ],
            [-0.790017306804657, -0.6577766537666321, 0.092563696205616],
            [
                0.08552992343902588,
                -0.5739572644233704,
                -0.2628408372402191,
            ],
        ]),
        Polygon::tri([
            [
                0.01438096072524786,
                -0.15112130343914032,
                -0.2996201813220978,
            ],
            [-0.75848788022995, -0.6519943475723267, 0.08999492973089218],
            [
                -0.5492968559265137,
                -0.5164228081703186,
                -0.015461691655218601,
            ],
        ]),
    );
    let g = geometry(&a, &b);
    assert!((-g.depth - 9.999989339757912e-4).abs() < 4.0 * EPS, "{g:?}");
}

/// The same at f64 positions (a placed mesh's world positions, not rounded to f32),
/// where the edges' differences round too (`triangle_normal` adds back what they leave
/// out): band pairs against the reference (its exact differences need f32 positions
/// for a depth), and crossing and band pairs through the four lanes bit for bit the
/// one-pair answer.
#[test]
fn f64_slivers_with_a_vertex_over_them() {
    let mut pairs = Vec::new();
    let w = run("f64 slivers, vertex over the face", 16.0, |r, c, s| {
        let width = s * [1e-4, 1e-6][(r.next() % 2) as usize];
        let Some((a, b, gap)) = sliver_under_vertex(r, c, s, width, false) else {
            return Worst::default();
        };
        pairs.push((a, b));
        // (The references take exact differences: f32 positions. A crossing pair is
        // compared with the lanes only, below.)
        if gap < 0.0 {
            return Worst::default();
        }
        check(&a, &b, true)
    });
    assert!(w.cases > 1000);
    #[cfg(target_arch = "x86_64")]
    {
        let mut out: Vec<ContactGeometry> = pairs.iter().map(|(a, b)| geometry(a, b)).collect();
        let want = out.clone();
        both_kernels(&mut out, false, fetch_from(&pairs)).unwrap();
        for (g, h) in out.iter().zip(&want) {
            assert_eq!(bits(g), bits(h), "{g:?} {h:?}");
        }
    }
}
