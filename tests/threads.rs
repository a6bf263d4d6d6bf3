//! Issue 6, part 6: different scenes used from several threads at once give the same
//! answers as the same work done serially (CPU backend, through the safe API and the C ABI).
//! The contract (include/glcollide.h): a scene is used by one thread at a time; different
//! scenes may be used on different threads at once; the last-error message is per thread.

mod common;

use common::backends::{factories, last_error, Factory, Hit, TestScene};
use common::{bounds, shared_mesh, wave, TestMesh};

/// One scene's work: two copies of an organ, the second moved by a third of its size so
/// the surfaces cross; each frame deforms both and queries each as the reference.
struct Job {
    organ: &'static str,
    epsilon_rel: f32,
    leaf: u32,
    factory: usize,
}

const FRAMES: usize = 6;

fn run(job: &Job) -> Vec<Vec<Hit>> {
    let f: Factory = factories().swap_remove(job.factory);
    let a = TestMesh::from_obj(&shared_mesh(job.organ));
    let (lo, hi) = bounds(&a.pos);
    let size = (0..3).map(|k| hi[k] - lo[k]).fold(0.0f32, f32::max);
    let shift = size / 3.0;
    let mut b = a.clone();
    for p in &mut b.pos {
        p[0] += shift;
        p[1] += shift * 0.5;
    }
    let mut s = (f.make)(job.epsilon_rel * size, job.leaf);
    let (ia, ib) = (s.add(&a), s.add(&b));
    let mut out = Vec::new();
    for frame in 0..FRAMES {
        let amp = size * 0.02;
        let ph = frame as f32 * 0.7;
        s.update(ia, 0, &wave(&a.pos, amp, 6.0 / size, ph));
        s.update(ib, 0, &wave(&b.pos, amp, 5.0 / size, -ph));
        // Mesh ids are unique in the process: name the other mesh by creation order.
        let local = |hits: Vec<Hit>| -> Vec<Hit> {
            hits.into_iter()
                .map(|(o, a, b)| (if o == ia { 1 } else { 2 }, a, b))
                .collect()
        };
        out.push(local(s.query(ia)));
        out.push(local(s.query(ib)));
    }
    out
}

fn jobs() -> Vec<Job> {
    let organs = ["gallbladder_glt", "bunny", "teapot", "face"];
    let mut v = Vec::new();
    for (i, organ) in organs.iter().enumerate() {
        for factory in 0..factories().len() {
            v.push(Job {
                organ,
                epsilon_rel: if i % 2 == 0 { 0.0 } else { 1e-3 },
                leaf: [0, 16, 64, 200][i],
                factory,
            });
        }
    }
    v
}

#[test]
fn scenes_on_several_threads_answer_as_serially() {
    let jobs = jobs();
    let serial: Vec<Vec<Vec<Hit>>> = jobs.iter().map(run).collect();
    assert!(
        serial.iter().all(|r| r.iter().any(|q| !q.is_empty())),
        "every job must have contacts"
    );
    // All at once, each job on its own thread, three rounds.
    for round in 0..3 {
        let results: Vec<Vec<Vec<Hit>>> = std::thread::scope(|sc| {
            let hs: Vec<_> = jobs.iter().map(|j| sc.spawn(move || run(j))).collect();
            hs.into_iter().map(|h| h.join().unwrap()).collect()
        });
        for (i, (got, want)) in results.iter().zip(&serial).enumerate() {
            assert!(
                got == want,
                "round {round}: job {i} ({}) differs from the serial run",
                jobs[i].organ
            );
        }
    }
}

/// Errors on one thread never show in another thread's message, even while both fail
/// and succeed at once.
#[test]
fn error_messages_stay_on_their_thread() {
    use glcollide::ffi::*;
    std::thread::scope(|sc| {
        for t in 0..4u32 {
            sc.spawn(move || {
                let mut s = common::backends::FfiScene::new(GlcolBackend::Cpu, 0.0, 0);
                for i in 0..200u32 {
                    let id = 1000 * (t + 1) + i;
                    let st = unsafe { glcol_mesh_destroy(s.0, id) };
                    assert_eq!(st, GlcolStatus::UnknownMesh);
                    let msg = last_error();
                    assert!(msg.contains(&format!("mesh id {id} ")), "thread {t}: {msg}");
                    let m = TestMesh {
                        pos: vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
                        idx: vec![0, 1, 2],
                        k: 3,
                    };
                    let mid = s.add(&m);
                    s.destroy(mid);
                    // A success leaves the last failure's message in place.
                    assert_eq!(last_error(), msg);
                }
            });
        }
    });
}

/// Issue 12, item 5: `glcol_query` (the reference query), and `glcol_query_all` for a big
/// mesh pair, share their leaf pairs out between the scene's workers; the answer (and every
/// per-step count of the reference query) is the same for 1, 2 and one thread per core, on a real organ pair in deep contact (both deformed), at epsilon 0 and
/// in a band, and with the second organ placed by a transform.
#[test]
fn the_reference_query_answers_the_same_for_every_thread_count() {
    use glcollide::{Positions, Scene, SceneConfig};
    let colon = TestMesh::from_obj(&shared_mesh("colon"));
    let bowel = TestMesh::from_obj(&shared_mesh("small_intestine"));
    let (lo, hi) = bounds(&colon.pos);
    let extent = (0..3).map(|k| hi[k] - lo[k]).fold(0.0f32, f32::max);
    let a_pos = wave(&colon.pos, 0.004 * extent, 8.0 / extent, 0.3);
    let b_pos = wave(&bowel.pos, -0.004 * extent, 8.0 / extent, 0.3);
    // A quarter turn about z of the second organ's centre-free frame, back in place.
    let m: [f64; 12] = [0., -1., 0., 0., 1., 0., 0., 0., 0., 0., 1., 0.];
    let mut turned = b_pos.clone();
    for p in &mut turned {
        *p = [p[1], -p[0], p[2]];
    }
    for epsilon in [0.0, 1e-3 * extent] {
        for placed in [false, true] {
            let mut answers = Vec::new();
            for threads in [1, 2, 0] {
                let mut s = Scene::new(SceneConfig {
                    epsilon,
                    threads,
                    ..SceneConfig::default()
                })
                .unwrap();
                let a = s
                    .create_mesh(Positions::from_points(&a_pos), &colon.idx, 3)
                    .unwrap();
                let b_local = if placed { &turned } else { &b_pos };
                let b = s
                    .create_mesh(Positions::from_points(b_local), &bowel.idx, 3)
                    .unwrap();
                if placed {
                    s.set_transform(b, Some(&m)).unwrap();
                }
                // Mesh ids differ from scene to scene: the polygons only.
                let polys = |c: &[glcollide::Contact]| -> Vec<(u32, u32)> {
                    c.iter()
                        .map(|c| (c.reference_polygon, c.other_polygon))
                        .collect()
                };
                let qa = polys(s.query(a).unwrap());
                let sa = s.stats();
                let qb = polys(s.query(b).unwrap());
                let sb = s.stats();
                assert!(!qa.is_empty() && !qb.is_empty());
                // The whole-scene query shares the big pair out the same way.
                let all: Vec<(bool, u32, bool, u32)> = s
                    .query_all()
                    .unwrap()
                    .iter()
                    .map(|p| (p.mesh_a == a, p.polygon_a, p.mesh_b == a, p.polygon_b))
                    .collect();
                assert!(all.len() >= qa.len());
                answers.push((qa, qb, sa.tests, sa.hits, sb.tests, sb.hits, all));
            }
            for w in answers.windows(2) {
                assert!(
                    w[0].0 == w[1].0,
                    "epsilon {epsilon}, placed {placed}: contacts of a"
                );
                assert!(
                    w[0].1 == w[1].1,
                    "epsilon {epsilon}, placed {placed}: contacts of b"
                );
                assert!(
                    w[0].6 == w[1].6,
                    "epsilon {epsilon}, placed {placed}: query_all"
                );
                assert_eq!(
                    (w[0].2, w[0].3, w[0].4, w[0].5),
                    (w[1].2, w[1].3, w[1].4, w[1].5),
                    "epsilon {epsilon}, placed {placed}: per-step counts"
                );
            }
        }
    }
}

/// The reference query's wall time on 1 and 2 threads, heavy case (colon vs small
/// intestine, both deformed anew every frame). Prints a table, asserts nothing about time:
/// `cargo test --release --test threads -- --ignored --nocapture reference_query_speed`
#[test]
#[ignore]
fn reference_query_speed() {
    use glcollide::{Positions, Scene, SceneConfig};
    use std::time::Instant;
    let colon = TestMesh::from_obj(&shared_mesh("colon"));
    let bowel = TestMesh::from_obj(&shared_mesh("small_intestine"));
    let (lo, hi) = bounds(&colon.pos);
    let extent = (0..3).map(|k| hi[k] - lo[k]).fold(0.0f32, f32::max);
    type Frame = (Vec<[f32; 3]>, Vec<[f32; 3]>);
    let frames: Vec<Frame> = (0..8)
        .map(|f| {
            let t = f as f32 * 0.1;
            (
                wave(&colon.pos, 0.004 * extent, 8.0 / extent, t),
                wave(&bowel.pos, -0.004 * extent, 8.0 / extent, t),
            )
        })
        .collect();
    // CPU time of the whole process (all threads), in clock ticks, from /proc: sampled by
    // the kernel, so summed over many queries it estimates the CPU the queries used.
    let cpu_ticks = || -> u64 {
        let s = std::fs::read_to_string("/proc/self/stat").unwrap_or_default();
        let rest = s.rsplit(')').next().unwrap_or("");
        let f: Vec<&str> = rest.split_whitespace().collect();
        f.get(11).and_then(|u| u.parse::<u64>().ok()).unwrap_or(0)
            + f.get(12).and_then(|u| u.parse::<u64>().ok()).unwrap_or(0)
    };
    println!(
        "| threads | epsilon | contacts | query median µs | query min µs | CPU µs per query (all threads) |"
    );
    println!("|---:|---:|---:|---:|---:|---:|");
    for epsilon in [0.0, 1e-3 * extent] {
        for round in 0..3 {
            for threads in [1, 2] {
                let mut s = Scene::new(SceneConfig {
                    epsilon,
                    threads,
                    ..SceneConfig::default()
                })
                .unwrap();
                let a = s
                    .create_mesh(Positions::from_points(&frames[0].0), &colon.idx, 3)
                    .unwrap();
                let b = s
                    .create_mesh(Positions::from_points(&frames[0].1), &bowel.idx, 3)
                    .unwrap();
                let mut times = Vec::new();
                let (mut n, mut ticks) = (0, 0);
                let queries = 400;
                for i in 0..queries {
                    let (fa, fb) = &frames[i % frames.len()];
                    s.update_positions(a, 0, Positions::from_points(fa))
                        .unwrap();
                    s.update_positions(b, 0, Positions::from_points(fb))
                        .unwrap();
                    let c0 = cpu_ticks();
                    let t = Instant::now();
                    n = s.query(a).unwrap().len();
                    times.push(t.elapsed().as_secs_f64() * 1e6);
                    ticks += cpu_ticks() - c0;
                }
                times.sort_by(f64::total_cmp);
                // Clock ticks are 10 ms on Linux (USER_HZ = 100).
                let cpu = ticks as f64 * 1e4 / queries as f64;
                println!(
                    "| {threads} | {epsilon} | {n} | {:.0} | {:.0} | {cpu:.0} |{}",
                    times[times.len() / 2],
                    times[0],
                    if round == 0 { " (warm-up round)" } else { "" }
                );
            }
        }
    }
}
