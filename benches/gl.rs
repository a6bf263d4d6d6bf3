//! GL backends against the CPU backend, no host drawing in between (headless EGL, Mesa's
//! llvmpipe when there is no GPU): median update + query per frame, GL read-backs per
//! query, and whether the contacts equal the CPU backend's, frame by frame.
//!   cargo bench --bench gl [-- FRAMES]
//! GL_COMPUTE runs the whole query on the GPU (one read-back). On llvmpipe every GL call is
//! CPU work, so this measures overheads, not what a GPU would do; AUTO picks the CPU there.
//! Exits 1 if a GL backend's contacts differ from the CPU backend's in any frame.

use std::time::Instant;

use glcollide::internals::Gl;
use glcollide::internals::GlComputeSelector;
use glcollide::internals::GlSelectSelector;
use glcollide::internals::Selector;
use glcollide::obj::load;
use glcollide::{Positions, Scene, SceneConfig};

#[path = "../tests/common/mod.rs"]
mod common;

use common::backends::gl_support::{gl_loader, Ctx, Profile};
use common::{bounds, wave};

fn median(v: &mut [f64]) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

struct Case {
    name: &'static str,
    meshes: [(Vec<[f32; 3]>, Vec<u32>); 2],
    /// frames[f] = positions of mesh 0 (the reference) and mesh 1.
    frames: Vec<[Vec<[f32; 3]>; 2]>,
}

/// The README demo's scene: the scissors blade pushed into the deforming gallbladder.
fn demo(frames: usize) -> Case {
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/data");
    let blade = load(format!("{dir}/scissors_blade.obj")).unwrap();
    let organ = load(format!("{dir}/gallbladder_glt.obj")).unwrap();
    let far = organ
        .positions
        .iter()
        .copied()
        .fold(
            [f32::NEG_INFINITY; 3],
            |a, p| if p[0] > a[0] { p } else { a },
        );
    let (c, s) = (1.57f32.cos(), 1.57f32.sin());
    let n = blade.positions.len() as f32;
    let mid = blade.positions.iter().fold([0.0; 3], |a, p| {
        [a[0] + p[0] / n, a[1] + p[1] / n, a[2] + p[2] / n]
    });
    let frames = (0..frames)
        .map(|f| {
            let push = (f % 8) as f32 * 0.25;
            let b = blade
                .positions
                .iter()
                .map(|p| {
                    let q = [p[0] - mid[0], p[1] - mid[1], p[2] - mid[2]];
                    [
                        c * q[0] + s * q[2] + far[0] - push,
                        q[1] + far[1],
                        -s * q[0] + c * q[2] + far[2],
                    ]
                })
                .collect();
            [b, wave(&organ.positions, 0.3, 0.1, f as f32 * 0.1)]
        })
        .collect();
    Case {
        name: "blade in gallbladder (README demo)",
        meshes: [
            (blade.positions, blade.triangles),
            (organ.positions, organ.triangles),
        ],
        frames,
    }
}

/// Two organs deformed against each other: hundreds of contacts a frame.
fn organs(frames: usize) -> Case {
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/data");
    let a = load(format!("{dir}/colon.obj")).unwrap();
    let b = load(format!("{dir}/small_intestine.obj")).unwrap();
    let (lo, hi) = bounds(&a.positions);
    let e = (0..3).map(|k| hi[k] - lo[k]).fold(0.0, f32::max);
    let frames = (0..frames)
        .map(|f| {
            let t = f as f32 * 0.1;
            [
                wave(&a.positions, 0.004 * e, 8.0 / e, t),
                wave(&b.positions, -0.004 * e, 8.0 / e, t),
            ]
        })
        .collect();
    Case {
        name: "colon vs small intestine",
        meshes: [(a.positions, a.triangles), (b.positions, b.triangles)],
        frames,
    }
}

type Frame = Vec<(u32, u32)>;

/// Median ms per frame, read-backs per query (median), contacts per frame.
fn run(case: &Case, sel: Option<Box<dyn Selector>>) -> (f64, u32, Vec<Frame>) {
    let config = SceneConfig {
        epsilon: 0.001,
        max_polygons_per_box: 0,
        ..SceneConfig::default()
    };
    let mut s = match sel {
        Some(sel) => Scene::with_selector(config, sel).unwrap(),
        None => Scene::new(config).unwrap(),
    };
    let ids: Vec<u32> = case
        .meshes
        .iter()
        .map(|(p, i)| s.create_mesh(Positions::from_points(p), i, 3).unwrap())
        .collect();
    let (mut ms, mut rb, mut out) = (Vec::new(), Vec::new(), Vec::new());
    for frame in &case.frames {
        let t = Instant::now();
        for (id, p) in ids.iter().zip(frame) {
            s.update_positions(*id, 0, Positions::from_points(p))
                .unwrap();
        }
        let c: Frame = s
            .query(ids[0])
            .unwrap()
            .iter()
            .map(|c| (c.reference_polygon, c.other_polygon))
            .collect();
        ms.push(t.elapsed().as_secs_f64() * 1e3);
        rb.push(s.stats().readbacks);
        out.push(c);
    }
    s.release_gl();
    rb.sort_unstable();
    (median(&mut ms), rb[rb.len() / 2], out)
}

fn main() {
    let frames: usize = std::env::args()
        .skip(1)
        .find_map(|a| a.parse().ok())
        .unwrap_or(40);
    // A compatibility-profile context on an EGL device (glutin; llvmpipe without a GPU),
    // current from here on.
    let _ctx = Ctx::new(Profile::Compat);
    // SAFETY: the context made above is current on this thread; the loader serves it.
    let info = unsafe { Gl::load(&gl_loader) }.unwrap().info;
    let what = format!("{} / {}", info.version_string, info.renderer);
    println!("context: {what}; {frames} frames, epsilon 0.001, median of update + query\n");
    println!(
        "| scene | backend | ms per frame | read-backs per query | contacts per frame | = CPU |"
    );
    println!("|---|---|---:|---:|---:|---|");
    // SAFETY: the context made above is current on this thread; the loader serves it.
    let load_gl = || unsafe { Gl::load(&gl_loader) }.unwrap();
    let mut differ = 0;
    for case in [demo(frames), organs(frames.min(20))] {
        let (cpu_ms, _, cpu) = run(&case, None);
        let per = cpu.iter().map(Vec::len).sum::<usize>() / cpu.len();
        println!("| {} | CPU | {cpu_ms:.3} | 0 | {per} | - |", case.name);
        let whole = GlComputeSelector::new(load_gl()).unwrap();
        let select = GlSelectSelector::new(load_gl()).unwrap();
        let rows: [(&str, Box<dyn Selector>); 2] = [
            ("GL_COMPUTE, whole query", Box::new(whole)),
            ("GL_SELECT", Box::new(select)),
        ];
        for (name, sel) in rows {
            let (ms, rb, got) = run(&case, Some(sel));
            let same = if got == cpu { "yes" } else { "NO" };
            differ += usize::from(got != cpu);
            println!(
                "| {} | {name} | {ms:.3} | {rb} | {per} | {same} |",
                case.name
            );
        }
    }
    if differ > 0 {
        eprintln!("{differ} GL runs differ from the CPU backend");
        std::process::exit(1);
    }
}
