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
