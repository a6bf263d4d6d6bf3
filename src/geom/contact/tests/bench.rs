//! Nanoseconds per pair, an ignored test (no timing asserted): `BENCH_SET=band cargo test
//! --release --lib geom::contact::tests::bench -- --ignored --nocapture` (`BENCH_SET` picks
//! the sets by the start of their names, `BENCH_REPS` the repetitions).

use super::support::*;
#[cfg(target_arch = "x86_64")]
use crate::geom::contact::batch::band_triangles_avx2;
use crate::geom::contact::{contact_geometry, contact_geometry_many};
use crate::geom::test_rng::Rng;

/// Nanoseconds per pair (no timing asserted): `cargo test --release --lib
/// geom::contact::tests::bench -- --ignored --nocapture`.
#[test]
#[ignore]
fn bench_ns_per_pair() {
    use std::hint::black_box;
    use std::time::Instant;
    let mut r = Rng(2024);
    let mut sets: Vec<(&str, Vec<(Polygon, Polygon)>)> = Vec::new();
    let mut crossing = Vec::new();
    let mut band = Vec::new();
    while crossing.len() < 1000 {
        let (a, b) = crossing_pair(&mut r, &[100.0, 50.0, -20.0], 1.0);
        if meet(&a, &b) {
            crossing.push((a, b));
            // Moved apart by up to a tenth of their size: a band pair.
            let g = geometry(&a, &b);
            let d = g.normal.map(|x| x * (g.depth + 0.1 * (r.f() + 0.5)));
            let moved = Polygon::tri(a.moved(&d).t[0]);
            if !meet(&moved, &b) {
                band.push((moved, b));
            }
        }
    }
    let quads: Vec<(Polygon, Polygon)> = crossing
        .iter()
        .map(|(a, b)| {
            let q = |p: &Polygon| {
                let t = p.t[0];
                let v3 = [0, 1, 2].map(|k| t[0][k] + t[2][k] - t[1][k] + 0.05);
                Polygon::quad([t[0], t[1], t[2], v3])
            };
            (q(a), q(b))
        })
        .filter(|(a, b)| meet(a, b))
        .collect();
    // Quads bent (issue 28: the union of their triangles is not their hull): the fourth
    // vertex beyond the diagonal v0-v2, lifted off the plane by a third of the size, against
    // a triangle and against a quad bent the same way.
    let bent = |p: &Polygon| {
        let t = p.t[0];
        let lift = [0.3, -0.2, 0.25];
        let v3 = [0, 1, 2].map(|k| t[0][k] + t[2][k] - t[1][k] + lift[k]);
        Polygon::quad([t[0], t[1], t[2], v3])
    };
    let bent_tri: Vec<(Polygon, Polygon)> = crossing
        .iter()
        .map(|(a, b)| (bent(a), *b))
        .filter(|(a, b)| meet(a, b))
        .collect();
    let bent_both: Vec<(Polygon, Polygon)> = crossing
        .iter()
        .map(|(a, b)| (bent(a), bent(b)))
        .filter(|(a, b)| meet(a, b))
        .collect();
    sets.push(("crossing triangles", crossing));
    sets.push(("band triangles", band));
    sets.push(("crossing quads", quads));
    sets.push(("quads bent vs triangles", bent_tri));
    sets.push(("quads bent, both", bent_both));
    let only = std::env::var("BENCH_SET").unwrap_or_default();
    // This thread's CPU time (ns) where Linux tells it, else wall time: the machine may
    // be shared, and waiting for a core is not the function's cost.
    let cpu_ns = || {
        std::fs::read_to_string("/proc/thread-self/schedstat")
            .ok()
            .and_then(|s| s.split_whitespace().next()?.parse::<f64>().ok())
    };
    let clock = |f: &mut dyn FnMut()| {
        let (w0, c0) = (Instant::now(), cpu_ns());
        f();
        let wall = w0.elapsed().as_nanos() as f64;
        match (c0, cpu_ns()) {
            (Some(c0), Some(c1)) => c1 - c0,
            _ => wall,
        }
    };
    for (name, pairs) in sets.iter().filter(|(n, _)| n.starts_with(&only)) {
        let reps: usize = std::env::var("BENCH_REPS")
            .ok()
            .and_then(|s| s.parse().ok())
            .unwrap_or(200);
        let n = (reps * pairs.len()) as f64;
        let mut best = f64::INFINITY;
        let mut base = f64::INFINITY;
        for _ in 0..5 {
            best = best.min(
                clock(&mut || {
                    for _ in 0..reps {
                        for (a, b) in pairs {
                            black_box(contact_geometry(black_box(&a.t), a.n, black_box(&b.t), b.n));
                        }
                    }
                }) / n,
            );
            base = base.min(
                clock(&mut || {
                    for _ in 0..reps {
                        for (a, b) in pairs {
                            black_box(meet(black_box(a), black_box(b)));
                        }
                    }
                }) / n,
            );
        }
        println!(
            "{name:>20}: {best:7.1} ns/pair of CPU time ({} pairs; the exact test \
             alone: {base:.1} ns)",
            pairs.len()
        );
    }
    // What a band pair of a query within a band gets once the exact lanes have found
    // it apart: `band_triangles` alone (its AVX2 build, as the scene calls it).
    #[cfg(target_arch = "x86_64")]
    if std::is_x86_feature_detected!("avx2") && std::is_x86_feature_detected!("fma") {
        let band = &sets[1].1;
        let mut best = f64::INFINITY;
        for _ in 0..50 {
            let t0 = Instant::now();
            for _ in 0..10 {
                for (a, b) in band {
                    // SAFETY: the CPU has AVX2 and FMA (checked above).
                    black_box(unsafe {
                        band_triangles_avx2(black_box(&a.t[0]), black_box(&b.t[0]))
                    });
                }
            }
            best = best.min(t0.elapsed().as_nanos() as f64 / (10 * band.len()) as f64);
        }
        println!("  band_triangles alone: {best:7.1} ns/pair");
    }
    // What a query's answer at epsilon 0 gets: the crossing pairs through
    // `contact_geometry_many` (four at a time), all at once and in calls of 10 pairs
    // (an instrument's answer).
    let crossing = &sets[0].1;
    let mut out = vec![geometry(&crossing[0].0, &crossing[0].1); crossing.len()];
    // (The least wall time of many short runs: steadier here than CPU time, which
    // this machine's scheduler reports in coarse steps.)
    for chunk in [crossing.len(), 10] {
        let reps = 10;
        let n = (reps * crossing.len()) as f64;
        let mut best = f64::INFINITY;
        for _ in 0..100 {
            let t0 = Instant::now();
            {
                for _ in 0..reps {
                    for (c, o) in crossing.chunks(chunk).zip(out.chunks_mut(chunk)) {
                        contact_geometry_many(black_box(o), true, fetch_from(c)).unwrap();
                    }
                }
            }
            best = best.min(t0.elapsed().as_nanos() as f64 / n);
        }
        println!("  four at a time, calls of {chunk:>4}: {best:7.1} ns/pair of CPU time");
    }
}
