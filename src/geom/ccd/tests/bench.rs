//! The timing of the primitive tests over the ground truth's queries (ignored: run with
//! `cargo test --release --lib ccd::tests::bench -- --ignored --nocapture`): ns per query,
//! and how many the float filter decided next to the exact test's count.

use super::super::predicate::Kind;
use super::super::{decide, exact, Stage};
use super::truth::{has_truth, load, SCENES};
use std::time::Instant;

#[test]
#[ignore = "timing: run with --ignored --nocapture"]
fn primitive_tests_per_query() {
    if !has_truth("primitive_tests_per_query") {
        return;
    }
    println!(
        "{:<18} {:>3} {:>7} {:>7} | {:>9} {:>9} {:>9} | {:>11} {:>11}",
        "scene", "", "queries", "true", "ns/query", "filter", "exact", "ns/exact", "ns/filtered"
    );
    for &(scene, frame, csv_ee) in &SCENES {
        for kind in [Kind::VertexFace, Kind::EdgeEdge] {
            let qs = load(scene, frame, csv_ee, kind);
            let trues = qs.iter().filter(|q| q.truth).count();
            // Best of 3 runs over the whole set.
            let mut best = f64::INFINITY;
            let mut exact_count = 0;
            for _ in 0..3 {
                let t0 = Instant::now();
                exact_count = 0;
                for q in &qs {
                    let (r, s) = decide(kind, std::hint::black_box(&q.pts));
                    std::hint::black_box(r);
                    exact_count += usize::from(s == Stage::Exact);
                }
                best = best.min(t0.elapsed().as_secs_f64());
            }
            // The exact test alone, over the queries the filter left to it, and over all.
            let left: Vec<_> = qs
                .iter()
                .filter(|q| decide(kind, &q.pts).1 == Stage::Exact)
                .collect();
            let t0 = Instant::now();
            for q in &left {
                std::hint::black_box(exact::decide(kind, std::hint::black_box(&q.pts)));
            }
            let per_exact = t0.elapsed().as_secs_f64() * 1e9 / left.len().max(1) as f64;
            let t0 = Instant::now();
            let filtered: Vec<_> = qs
                .iter()
                .filter(|q| decide(kind, &q.pts).1 == Stage::Filter)
                .collect();
            let sel = t0.elapsed();
            let t0 = Instant::now();
            for q in &filtered {
                std::hint::black_box(decide(kind, std::hint::black_box(&q.pts)));
            }
            let _ = sel;
            let per_filtered = t0.elapsed().as_secs_f64() * 1e9 / filtered.len().max(1) as f64;
            println!(
                "{:<18} {:>3} {:>7} {:>7} | {:>9.0} {:>9} {:>9} | {:>11.0} {:>11.0}",
                scene,
                if kind == Kind::VertexFace { "vf" } else { "ee" },
                qs.len(),
                trues,
                best * 1e9 / qs.len() as f64,
                qs.len() - exact_count,
                exact_count,
                per_exact,
                per_filtered,
            );
        }
    }
}
