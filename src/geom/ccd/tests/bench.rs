//! The timing of the primitive tests over the ground truth's queries (ignored: run with
//! `cargo test --release --lib ccd::tests::bench -- --ignored --nocapture`): ns per query,
//! and how many the float filter decided next to the exact test's count. Times are the
//! thread's time on a CPU (`/proc/thread-self/schedstat`), best of three runs of at least
//! 0.2 s each, so that a loaded
//! machine does not inflate them; the wall time is printed beside.

use super::super::predicate::Kind;
use super::super::{decide, exact, Stage};
use super::truth::{has_truth, load, SCENES};
use std::time::Instant;

/// This thread's time on a CPU so far, in ns (Linux), or the wall clock's elsewhere.
fn cpu_ns(wall: Instant) -> f64 {
    std::fs::read_to_string("/proc/thread-self/schedstat")
        .ok()
        .and_then(|s| s.split_whitespace().next()?.parse::<f64>().ok())
        .unwrap_or_else(|| wall.elapsed().as_secs_f64() * 1e9)
}

/// The best of three timings of one call of `f` (CPU ns, wall ns).
pub(super) fn best_of_3(mut f: impl FnMut()) -> (f64, f64) {
    let origin = Instant::now();
    let mut best = (f64::INFINITY, f64::INFINITY);
    for _ in 0..3 {
        // Repeated for at least 0.2 s: the CPU time advances in scheduler ticks.
        let (c0, w0) = (cpu_ns(origin), Instant::now());
        let mut n = 0u32;
        while n == 0 || w0.elapsed().as_secs_f64() < 0.2 {
            f();
            n += 1;
        }
        let c = (cpu_ns(origin) - c0) / f64::from(n);
        let w = w0.elapsed().as_secs_f64() * 1e9 / f64::from(n);
        best = (best.0.min(c), best.1.min(w));
    }
    best
}

#[test]
#[ignore = "timing: run with --ignored --nocapture"]
fn primitive_tests_per_query() {
    if !has_truth("primitive_tests_per_query") {
        return;
    }
    println!(
        "{:<18} {:>3} {:>7} {:>6} | {:>9} {:>9} | {:>7} {:>6} | {:>10} {:>10}",
        "scene",
        "",
        "queries",
        "true",
        "ns/query",
        "(wall)",
        "filter",
        "exact",
        "ns/filter",
        "ns/exact"
    );
    for &(scene, frame, csv_ee) in &SCENES {
        for kind in [Kind::VertexFace, Kind::EdgeEdge] {
            let qs = load(scene, frame, csv_ee, kind);
            let trues = qs.iter().filter(|q| q.truth).count();
            let (filtered, left): (Vec<_>, Vec<_>) = qs
                .iter()
                .partition(|q| decide(kind, &q.pts).1 == Stage::Filter);
            let per = |n: usize, ns: f64| ns / n.max(1) as f64;
            let (all, all_wall) = best_of_3(|| {
                for q in &qs {
                    std::hint::black_box(decide(kind, std::hint::black_box(&q.pts)));
                }
            });
            let (f, _) = best_of_3(|| {
                for q in &filtered {
                    std::hint::black_box(decide(kind, std::hint::black_box(&q.pts)));
                }
            });
            let (e, _) = best_of_3(|| {
                for q in &left {
                    std::hint::black_box(exact::decide(kind, std::hint::black_box(&q.pts)));
                }
            });
            println!(
                "{:<18} {:>3} {:>7} {:>6} | {:>9.0} {:>9.0} | {:>7} {:>6} | {:>10.0} {:>10}",
                scene,
                if kind == Kind::VertexFace { "vf" } else { "ee" },
                qs.len(),
                trues,
                per(qs.len(), all),
                per(qs.len(), all_wall),
                filtered.len(),
                left.len(),
                per(filtered.len(), f),
                if left.is_empty() {
                    "-".to_string()
                } else {
                    format!("{:.0}", per(left.len(), e))
                },
            );
        }
    }
}

/// glcollide's columns of `scripts/bench-ccd-peers.sh`'s table, beside Tight-Inclusion's
/// (ignored: the script runs it): one tab-separated line per scene and kind, after
/// `ccd-peers`: queries, true, ns per query (the whole set, timed as above), false positives
/// and false negatives against the truth, and how many the float filter decided. With
/// `CCD_TOI_DIR` set, also writes every query's toi there (`<scene>_<vf|ee>.toi`, one line a
/// query, `-` when apart) for the peer's driver, which compares its tois with these
/// (certified within `2^-20` below the exact earliest time).
#[test]
#[ignore = "timing: run by scripts/bench-ccd-peers.sh"]
fn peer_columns() {
    if !has_truth("peer_columns") {
        return;
    }
    let toi_dir = std::env::var_os("CCD_TOI_DIR").map(std::path::PathBuf::from);
    for &(scene, frame, csv_ee) in &SCENES {
        for kind in [Kind::VertexFace, Kind::EdgeEdge] {
            let tag = if kind == Kind::VertexFace { "vf" } else { "ee" };
            let qs = load(scene, frame, csv_ee, kind);
            let answers: Vec<_> = qs.iter().map(|q| decide(kind, &q.pts)).collect();
            let (mut trues, mut fp, mut fn_, mut filtered) = (0, 0, 0, 0);
            for (q, (got, stage)) in qs.iter().zip(&answers) {
                trues += usize::from(q.truth);
                fp += usize::from(got.is_some() && !q.truth);
                fn_ += usize::from(got.is_none() && q.truth);
                filtered += usize::from(*stage == Stage::Filter);
            }
            let (ns, _) = best_of_3(|| {
                for q in &qs {
                    std::hint::black_box(decide(kind, std::hint::black_box(&q.pts)));
                }
            });
            if let Some(dir) = &toi_dir {
                // `{:e}` prints the shortest decimal that reads back as the same double.
                let lines: String = answers
                    .iter()
                    .map(|a| a.0.map_or("-\n".to_string(), |t| format!("{:e}\n", t.t)))
                    .collect();
                let path = dir.join(format!("{scene}_{tag}.toi"));
                std::fs::write(&path, lines).unwrap_or_else(|e| panic!("{path:?}: {e}"));
            }
            println!(
                "ccd-peers\t{scene}\t{tag}\t{}\t{trues}\t{:.0}\t{fp}\t{fn_}\t{filtered}",
                qs.len(),
                ns / qs.len().max(1) as f64,
            );
        }
    }
}
