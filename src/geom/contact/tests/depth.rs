//! Tests of the penetration depth: against a search over sampled directions, and with the
//! pair swapped.

use super::support::*;
use crate::geom::predicates::P3;
use crate::geom::test_rng::Rng;

/// The depth against a direct search: it is at most the overlap of the projections
/// on any direction (those are separating translations; for a quad, the largest over its
/// triangles paired with the other's), and for two triangles a hill-climb from the best of
/// many sampled directions comes down to it (a quad's union may come apart along a
/// direction before every pair of triangles' projections do: there the search is only an
/// upper bound, and the exact reference in `check` is the tight one).
#[test]
fn depth_against_sampled_directions() {
    let mut r = Rng(4242);
    let mut worst: f64 = 0.0;
    let (mut tight, mut cases) = (0, 0);
    for i in 0..150 {
        let (a, b) = crossing_pair(&mut r, &[0.0; 3], 1.0);
        let (a, b) = if i % 3 == 0 {
            let mut q = a.t[0];
            q[2] = [q[2][0] + 0.3, q[2][1] - 0.2, q[2][2] + 0.1];
            (Polygon::quad([a.t[0][0], a.t[0][1], a.t[0][2], q[2]]), b)
        } else {
            (a, b)
        };
        if !meet(&a, &b) {
            continue;
        }
        let g = geometry(&a, &b);
        // Translation of a along u that separates the projections of every pair of
        // triangles.
        let h = |u: &P3| {
            let pr = |p: &P3| p[0] * u[0] + p[1] * u[1] + p[2] * u[2];
            let mut most = f64::NEG_INFINITY;
            for ta in a.tris() {
                for tb in b.tris() {
                    let amin = ta.iter().map(pr).fold(f64::INFINITY, f64::min);
                    let bmax = tb.iter().map(pr).fold(f64::NEG_INFINITY, f64::max);
                    most = most.max(bmax - amin);
                }
            }
            most
        };
        let mut samples: Vec<(f64, P3)> = (0..20_000)
            .map(|_| {
                let u = r.dir();
                let x = h(&u);
                assert!(
                    g.depth <= x + 1e-12,
                    "depth {} > overlap {x} along {u:?}",
                    g.depth
                );
                (x, u)
            })
            .collect();
        samples.sort_by(|x, y| x.0.total_cmp(&y.0));
        // Hill-climb from the best few (the overlap has a local minimum per facet).
        let mut found = f64::INFINITY;
        for start in samples.iter().take(24) {
            // Pattern search: many random steps per step size, shrink when none helps.
            let mut best = *start;
            let mut step = 0.05;
            while step > 1e-11 {
                let mut improved = false;
                for _ in 0..96 {
                    let d = r.dir();
                    let u = [0, 1, 2].map(|k| best.1[k] + d[k] * step);
                    let l = (u[0] * u[0] + u[1] * u[1] + u[2] * u[2]).sqrt();
                    let u = u.map(|x| x / l);
                    let x = h(&u);
                    assert!(g.depth <= x + 1e-12);
                    if x < best.0 {
                        best = (x, u);
                        improved = true;
                    }
                }
                if !improved {
                    step *= 0.6;
                }
            }
            found = found.min(best.0);
        }
        if a.n == 2 {
            continue;
        }
        worst = worst.max(found - g.depth);
        if found - g.depth < 1e-9 {
            tight += 1;
        }
        cases += 1;
    }
    println!(
        "sampled/hill-climbed overlap minus depth: worst {worst:e}, within 1e-9 in \
         {tight} of {cases} cases"
    );
    // The search is only as good as its sampling (the overlap is a max of linear
    // functions with thin valleys); the double-double hull reference in `check` is
    // the tight one.
    assert!(
        worst < 1e-6 && tight * 10 > cases * 9,
        "{worst} {tight}/{cases}"
    );
}

/// Swapping the polygons negates the normal and keeps the depth (triangles, where the
/// minimum is unique in general position).
#[test]
fn swapping_the_pair() {
    let mut r = Rng(31337);
    for _ in 0..2000 {
        let (a, b) = crossing_pair(&mut r, &[1e3, 0.0, 0.0], 1.0);
        let (g, h) = (geometry(&a, &b), geometry(&b, &a));
        assert_eq!(g.intersecting, h.intersecting);
        if !g.intersecting {
            assert!((g.depth - h.depth).abs() < 1e-12);
            continue;
        }
        assert!((g.depth - h.depth).abs() <= 4.0 * EPS * 1e3, "{g:?} {h:?}");
        if g.depth > 1e-3 {
            let dot: f64 = (0..3).map(|k| g.normal[k] * h.normal[k]).sum();
            assert!(dot < -1.0 + 1e-9, "{g:?} {h:?}");
        }
    }
}
