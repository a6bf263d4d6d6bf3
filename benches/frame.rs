//! Per-frame cost of glcollide alone (CPU backend): update (both meshes) and query, median
//! over the frames, with the contact counts and what each step asked.
//!   cargo bench --bench frame [-- FRAMES]
//! Environment: FRAME_CASE (a substring of the case names), FRAME_LEAVES (leaf sizes,
//! default "0,32"), FRAME_THREADS (worker threads, default "1"; step times are summed over
//! the workers).

use std::time::Instant;

use glcollide::obj::load;
use glcollide::{Positions, Scene, SceneConfig};

#[path = "../tests/common/mod.rs"]
mod common;

use common::{bounds, wave};

fn median(v: &mut [f64]) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

struct Case {
    name: String,
    a: (Vec<[f32; 3]>, Vec<u32>),
    b: (Vec<[f32; 3]>, Vec<u32>),
    frames_a: Vec<Vec<[f32; 3]>>,
    frames_b: Vec<Vec<[f32; 3]>>,
}

fn instrument_case(instrument: &str, organ: &str, frames: usize) -> Case {
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/../shared/meshes");
    let o = load(format!("{dir}/{organ}.obj")).unwrap();
    let i = load(format!("{dir}/{instrument}.obj")).unwrap();
    let (lo, hi) = bounds(&o.positions);
    let extent = (0..3).map(|k| hi[k] - lo[k]).fold(0.0, f32::max);
    let far =
        o.positions.iter().copied().fold(
            [f32::NEG_INFINITY; 3],
            |a, p| if p[0] > a[0] { p } else { a },
        );
    let (ilo, ihi) = bounds(&i.positions);
    let ic = [0, 1, 2].map(|k| (ilo[k] + ihi[k]) / 2.0);
    let ilen = (0..3).map(|k| ihi[k] - ilo[k]).fold(0.0, f32::max);
    let scale = 0.15 * extent / ilen;
    let mut fa: Vec<Vec<[f32; 3]>> = Vec::new();
    let mut fb = Vec::new();
    for f in 0..frames {
        let t = f as f32 * 0.05;
        fb.push(wave(&o.positions, 0.005 * extent, 6.0 / extent, t));
        let depth = (0.5 + 0.5 * (t * 3.0).sin()) * 0.02 * extent;
        let (s, c) = (1.3f32).sin_cos();
        fa.push(
            i.positions
                .iter()
                .map(|p| {
                    let (x, y, z) = (
                        (p[0] - ic[0]) * scale,
                        (p[1] - ic[1]) * scale,
                        (p[2] - ic[2]) * scale,
                    );
                    [
                        far[0] - depth + c * x + s * z,
                        far[1] + y,
                        far[2] - s * x + c * z,
                    ]
                })
                .collect(),
        );
    }
    Case {
        name: format!("{instrument} vs {organ}"),
        a: (fa[0].clone(), i.triangles),
        b: (o.positions, o.triangles),
        frames_a: fa,
        frames_b: fb,
    }
}

fn organ_case(a: &str, b: &str, frames: usize) -> Case {
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/../shared/meshes");
    let ma = load(format!("{dir}/{a}.obj")).unwrap();
    let mb = load(format!("{dir}/{b}.obj")).unwrap();
    let (lo, hi) = bounds(&ma.positions);
    let extent = (0..3).map(|k| hi[k] - lo[k]).fold(0.0, f32::max);
    let fa = (0..frames)
        .map(|f| wave(&ma.positions, 0.004 * extent, 8.0 / extent, f as f32 * 0.1))
        .collect();
    let fb = (0..frames)
        .map(|f| wave(&mb.positions, -0.004 * extent, 8.0 / extent, f as f32 * 0.1))
        .collect();
    Case {
        name: format!("{a} vs {b}"),
        a: (ma.positions, ma.triangles),
        b: (mb.positions, mb.triangles),
        frames_a: fa,
        frames_b: fb,
    }
}

fn run(c: &Case, leaf: u32, eps: f32, threads: u32) {
    let mut scene = Scene::new(SceneConfig {
        epsilon: eps,
        max_polygons_per_box: leaf,
        threads,
    })
    .unwrap();
    let ia = scene
        .create_mesh(Positions::from_points(&c.a.0), &c.a.1, 3)
        .unwrap();
    let ib = scene
        .create_mesh(Positions::from_points(&c.b.0), &c.b.1, 3)
        .unwrap();
    let (mut up, mut q, mut n) = (Vec::new(), Vec::new(), Vec::new());
    let mut tests = [0usize; 5];
    let mut nanos = [0u64; 5];
    for (fa, fb) in c.frames_a.iter().zip(&c.frames_b) {
        let t = Instant::now();
        scene
            .update_positions(ia, 0, Positions::from_points(fa))
            .unwrap();
        scene
            .update_positions(ib, 0, Positions::from_points(fb))
            .unwrap();
        let t1 = Instant::now();
        let k = scene.query(ia).unwrap().len();
        let t2 = Instant::now();
        up.push((t1 - t).as_secs_f64() * 1e6);
        q.push((t2 - t1).as_secs_f64() * 1e6);
        n.push(k as f64);
        let s = scene.stats();
        for i in 0..5 {
            tests[i] += s.tests[i];
            nanos[i] += s.nanos[i];
        }
    }
    let frames = c.frames_a.len();
    let (u, qq) = (median(&mut up), median(&mut q));
    println!(
        "| {} | {threads} | {} | {} | {:.0} | {:.1} | {:.1} | {:.1} | {} | {} |",
        c.name,
        if leaf == 0 {
            "auto".to_string()
        } else {
            leaf.to_string()
        },
        eps,
        median(&mut n),
        u,
        qq,
        u + qq,
        tests
            .map(|t| t / frames)
            .iter()
            .map(|t| t.to_string())
            .collect::<Vec<_>>()
            .join(" / "),
        nanos
            .map(|t| t as f64 / frames as f64 / 1e3)
            .iter()
            .map(|t| format!("{t:.1}"))
            .collect::<Vec<_>>()
            .join(" / ")
    );
}

fn main() {
    let frames: usize = std::env::args()
        .skip(1)
        .find_map(|a| a.parse().ok())
        .unwrap_or(100);
    println!(
        "| scene | threads | leaf | eps | contacts | update µs | query µs | frame µs | tests per step 1-5 | µs per step 1-5 |"
    );
    println!("|---|---:|---|---|---:|---:|---:|---:|---|---|");
    let cases = [
        instrument_case("scissors_blade", "gallbladder_glt", frames),
        instrument_case("scissors_blade", "spine_pelvis", frames),
        instrument_case("forceps_jaw", "colon", frames),
        organ_case("colon", "small_intestine", frames.min(30)),
    ];
    let only = std::env::var("FRAME_CASE").unwrap_or_default();
    for c in cases.iter().filter(|c| c.name.contains(&only)) {
        let leaves: Vec<u32> = std::env::var("FRAME_LEAVES")
            .ok()
            .map(|v| v.split(',').filter_map(|x| x.parse().ok()).collect())
            .unwrap_or_else(|| vec![0, 32]);
        let threads: Vec<u32> = std::env::var("FRAME_THREADS")
            .ok()
            .map(|v| v.split(',').filter_map(|x| x.parse().ok()).collect())
            .unwrap_or_else(|| vec![1]);
        for &leaf in &leaves {
            for &t in &threads {
                run(c, leaf, 0.0, t);
            }
        }
    }
}
