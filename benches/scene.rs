//! Whole-scene queries (`Scene::query_all`, CPU backend) on the real simulation frames of
//! ../shared/meshes/sim, on a generated scene of many small bodies, and on flat and jittered
//! cloths (100x100, 300x300): per frame, the update
//! of every mesh (frame N, then N+1, alternately: a real deformation step) and one query with
//! every mesh self-colliding, median over repeated frames, for 1 and 2 threads, exact and
//! within 1e-3 of the scene's extent. Prints a Markdown table.
//! The crumpled cloth (92,450 triangles, one mesh) cycles the four consecutive frames of
//! bench/data/crumpled-cloth (made by `cargo bench --bench make_cloth`, see its README).
//! A second table gives the stages of the median query ([`AllStats`]: broad phase, leaf
//! pairs, polygon box pairs, adjacency decisions, narrow tests, mesh pairs' five steps).
//!   cargo bench --bench scene [-- FRAMES]
//! With `scaling [CSV]`, instead: time per frame against the number of bodies (10 to 5,000
//! spheres, exact, threads 1 and 2), printed and written as CSV for bench/scaling_plot.py:
//!   cargo bench --bench scene -- scaling bench-results/scaling.csv
//! With `self-scaling [CSV]`, instead: one cloth's self-collision against its triangle count
//! (the rolled cloth at 10k..400k triangles, threads 1 and 2):
//!   cargo bench --bench scene -- self-scaling bench-results/self_scaling.csv
//! Environment: `SCENE=substring` keeps the scenes whose name contains it, `EPS=0` or
//! `EPS=1e-3` one epsilon (relative to the extent), `THREADS=1` one thread count,
//! `SPHERES=10,100,1000` the body counts of the spheres scene (default 1000), `DUMP=DIR`
//! writes the scenes' frames as OBJ files under DIR (for the C++ peers), `INTER=1`
//! leaves self-collision off (pairs between bodies only, as `bench/scene_peers` compares).

use std::time::Instant;

use glcollide::obj::load;
use glcollide::{AllStats, MeshId, Positions, Scene, SceneConfig};

/// CPU time of the whole process so far, ns (every thread's time on a core, from
/// /proc/self/task/*/schedstat; 0 where there is none): unlike wall-clock time it does not
/// grow when other processes share the cores.
fn cpu_nanos() -> u64 {
    let Ok(tasks) = std::fs::read_dir("/proc/self/task") else {
        return 0;
    };
    tasks
        .filter_map(|t| std::fs::read_to_string(t.ok()?.path().join("schedstat")).ok())
        .filter_map(|s| s.split_whitespace().next()?.parse::<u64>().ok())
        .sum()
}

fn median(v: &mut [f64]) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

/// Meshes of one scene: topology and frames of positions (every mesh's, per frame), which a
/// run cycles through.
struct Case {
    name: String,
    idx: Vec<Vec<u32>>,
    frames: Vec<Vec<Vec<[f32; 3]>>>,
    extent: f32,
}

fn sim_case(scene: &str, frame: u32) -> Case {
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/../shared/meshes/sim");
    let mut idx = Vec::new();
    let mut frames = vec![Vec::new(), Vec::new()];
    for part in 0.. {
        let p = |f: u32| format!("{dir}/{scene}/frame{f}_part{part:02}.obj");
        if !std::path::Path::new(&p(frame)).exists() {
            break;
        }
        let (a, b) = (load(p(frame)).unwrap(), load(p(frame + 1)).unwrap());
        idx.push(a.triangles.clone());
        frames[0].push(a.positions);
        frames[1].push(b.positions);
    }
    let extent = extent_of(frames[0].iter().flatten());
    Case {
        name: format!("{scene} {frame}/{}", frame + 1),
        idx,
        frames,
        extent,
    }
}

fn extent_of<'a>(p: impl Iterator<Item = &'a [f32; 3]>) -> f32 {
    let (mut lo, mut hi) = ([f32::INFINITY; 3], [f32::NEG_INFINITY; 3]);
    for q in p {
        for k in 0..3 {
            lo[k] = lo[k].min(q[k]);
            hi[k] = hi[k].max(q[k]);
        }
    }
    (0..3).map(|k| hi[k] - lo[k]).fold(0.0, f32::max)
}

/// `n` spheres of about 500 triangles in a box, packed so that neighbours touch; the
/// second frame moves each by a small random step.
fn spheres_case(n: usize) -> Case {
    // A UV sphere with one vertex per pole: 2 + 22 * 11 vertices, 22 * 2 + 22 * 10 * 2 =
    // 484 triangles.
    let (rings, segs) = (12u32, 22u32);
    let mut unit = vec![[0.0, 0.0, 1.0f32], [0.0, 0.0, -1.0]];
    for r in 1..rings {
        let th = std::f32::consts::PI * r as f32 / rings as f32;
        for s in 0..segs {
            let ph = 2.0 * std::f32::consts::PI * s as f32 / segs as f32;
            unit.push([th.sin() * ph.cos(), th.sin() * ph.sin(), th.cos()]);
        }
    }
    let at = |r: u32, s: u32| 2 + (r - 1) * segs + s % segs;
    let mut tris = Vec::new();
    for s in 0..segs {
        tris.extend([0, at(1, s), at(1, s + 1)]);
        tris.extend([1, at(rings - 1, s + 1), at(rings - 1, s)]);
    }
    for r in 1..rings - 1 {
        for s in 0..segs {
            let (a, b, c, d) = (at(r, s), at(r, s + 1), at(r + 1, s), at(r + 1, s + 1));
            tris.extend([a, c, d, a, d, b]);
        }
    }
    let side = (n as f32).cbrt().ceil() as usize;
    let mut seed = 7u64;
    let mut rnd = move || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        (seed >> 40) as f32 / (1u64 << 24) as f32 - 0.5
    };
    let mut frames = vec![Vec::new(), Vec::new()];
    for i in 0..n {
        let c = [
            (i % side) as f32,
            (i / side % side) as f32,
            (i / side / side) as f32,
        ]
        .map(|x| x * 1.9);
        let j = [rnd(), rnd(), rnd()].map(|x| x * 0.05);
        for (f, frame) in frames.iter_mut().enumerate() {
            let o = [0, 1, 2].map(|k| c[k] + f as f32 * j[k]);
            frame.push(
                unit.iter()
                    .map(|p| [0, 1, 2].map(|k| o[k] + p[k]))
                    .collect(),
            );
        }
    }
    let extent = extent_of(frames[0].iter().flatten());
    Case {
        name: format!("{n} spheres of {} triangles", tris.len() / 3),
        idx: vec![tris; n],
        frames,
        extent,
    }
}

/// A large cloth in heavy self-contact, the size of the UNC cloth-ball benchmark (92k
/// triangles), wrapped around a ball: a 216 x 216 vertex sheet rolled into a spiral of
/// three turns whose layers carry a wave that is out of phase from one layer to the next,
/// so that neighbouring layers cross along thin bands and come within a fraction of their
/// spacing elsewhere (the contact pattern of a crumpled cloth); the innermost layer rests on
/// the ball. The second frame shifts the wave's phase (every vertex moves, as in a
/// simulation step). Generated, not recorded: the recorded cloth of ../shared is 14k.
fn rolled_cloth_case() -> Case {
    rolled_cloth(216)
}

/// [`rolled_cloth_case`] with an `n` x `n` vertex sheet (`2 (n - 1)^2` triangles): the
/// same scene at another resolution.
fn rolled_cloth(n: u32) -> Case {
    let (turns, r0, d, len) = (3.0f64, 0.2f64, 0.02f64, 4.0f64);
    let mut tris = Vec::new();
    let at = |i: u32, j: u32| j * n + i;
    for j in 0..n - 1 {
        for i in 0..n - 1 {
            let (a, b, c, e) = (at(i, j), at(i + 1, j), at(i, j + 1), at(i + 1, j + 1));
            tris.extend([a, b, e, a, e, c]);
        }
    }
    let tau = std::f64::consts::TAU;
    let sheet = |phase: f64| -> Vec<[f32; 3]> {
        let mut p = Vec::with_capacity((n * n) as usize);
        for j in 0..n {
            let v = j as f64 / (n - 1) as f64;
            for i in 0..n {
                let th = turns * tau * i as f64 / (n - 1) as f64;
                // Consecutive layers (th and th + tau) get opposite waves (2.5 cycles per
                // turn): amplitude 0.52 d, so they cross where both peak.
                let w = 0.52 * d * (8.0 * tau * v + 2.5 * th + phase).sin();
                let r = r0 + d * th / tau + w;
                p.push([
                    (r * th.cos()) as f32,
                    (r * th.sin()) as f32,
                    (len * (v - 0.5)) as f32,
                ]);
            }
        }
        p
    };
    let ball = spheres_case(1);
    let ball_at = |f: usize| -> Vec<[f32; 3]> {
        let c = ball.frames[f][0][0]; // north pole: the unit sphere's centre + (0, 0, 1)
        let centre = [c[0], c[1], c[2] - 1.0];
        ball.frames[f][0]
            .iter()
            .map(|q| [0, 1, 2].map(|k| (q[k] - centre[k]) * (r0 as f32 - 0.002)))
            .collect()
    };
    let frames = vec![vec![sheet(0.0), ball_at(0)], vec![sheet(0.05), ball_at(1)]];
    let extent = extent_of(frames[0].iter().flatten());
    Case {
        name: format!("rolled cloth of {} triangles + ball", tris.len() / 3),
        idx: vec![tris, ball.idx[0].clone()],
        frames,
        extent,
    }
}

/// An n x n cloth of 2 n^2 triangles over [0, 1]^2 in the plane z = 0 (the usual first frame
/// of a cloth simulation: every z equal), or with z jittered by up to `jitter` (the same
/// cloth, not flat); both frames the same positions. Issue 27: a flat mesh must cost no more
/// than a curved one of its size.
fn sheet_case(n: u32, jitter: f32) -> Case {
    let mut pos = Vec::new();
    let mut r = 0x2545_F491_4F6C_DD1Du64;
    for j in 0..=n {
        for i in 0..=n {
            r ^= r << 13;
            r ^= r >> 7;
            r ^= r << 17;
            let z = jitter * ((r >> 40) as f32 / (1u64 << 24) as f32 - 0.5);
            pos.push([i as f32 / n as f32, j as f32 / n as f32, z]);
        }
    }
    let mut tris = Vec::new();
    let w = n + 1;
    for j in 0..n {
        for i in 0..n {
            let v = j * w + i;
            tris.extend([v, v + 1, v + w + 1, v, v + w + 1, v + w]);
        }
    }
    let what = if jitter == 0.0 {
        "flat".to_string()
    } else {
        format!("jittered {jitter:e}")
    };
    Case {
        name: format!("{what} cloth {n}x{n}"),
        idx: vec![tris],
        frames: vec![vec![pos.clone()], vec![pos]],
        extent: 1.0,
    }
}

/// The 92k cloth crumpled over a ball by benches/make_cloth.rs: its four consecutive frames
/// of bench/data/crumpled-cloth (raw little-endian f32, 216 x 216 vertices), triangulated as
/// [`sheet_case`]. The ball is not part of it.
fn crumpled_cloth_case() -> Case {
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/bench/data/crumpled-cloth");
    let w = 216u32;
    let mut tris = Vec::new();
    for j in 0..w - 1 {
        for i in 0..w - 1 {
            let v = j * w + i;
            tris.extend([v, v + 1, v + w + 1, v, v + w + 1, v + w]);
        }
    }
    let frames: Vec<Vec<Vec<[f32; 3]>>> = (0..4)
        .map(|f| {
            let path = format!("{dir}/frame{f}.f32");
            let bytes = std::fs::read(&path)
                .unwrap_or_else(|e| panic!("{path}: {e} (cargo bench --bench make_cloth)"));
            assert_eq!(bytes.len(), (w * w * 12) as usize, "{path}: size");
            let p = bytes
                .chunks_exact(12)
                .map(|v| {
                    [0, 1, 2].map(|k| f32::from_le_bytes(v[4 * k..4 * k + 4].try_into().unwrap()))
                })
                .collect();
            vec![p]
        })
        .collect();
    let extent = extent_of(frames[0].iter().flatten());
    Case {
        name: format!("crumpled cloth of {} triangles", tris.len() / 3),
        idx: vec![tris],
        frames,
        extent,
    }
}

/// Median ms per frame (update every mesh + query_all), pairs in the last frame, the
/// stages of the median query.
fn run(case: &Case, epsilon: f32, threads: u32, frames: usize) -> (f64, f64, f64, usize, AllStats) {
    let mut s = Scene::new(SceneConfig {
        epsilon,
        threads,
        ..SceneConfig::default()
    })
    .unwrap();
    let ids: Vec<MeshId> = case
        .idx
        .iter()
        .zip(&case.frames[0])
        .map(|(idx, p)| s.create_mesh(Positions::from_points(p), idx, 3).unwrap())
        .collect();
    // INTER=1: pairs between bodies only (what the peers of bench/scene_peers answer).
    if std::env::var("INTER").map_or(true, |v| v != "1") {
        for &id in &ids {
            s.set_self_collision(id, true).unwrap();
        }
    }
    let (mut total, mut query, mut pairs) = (Vec::new(), Vec::new(), 0);
    let mut stats = Vec::new();
    let mut cpu = Vec::new();
    for f in 0..frames {
        let t = Instant::now();
        for (&id, p) in ids.iter().zip(&case.frames[f % case.frames.len()]) {
            s.update_positions(id, 0, Positions::from_points(p))
                .unwrap();
        }
        let q = Instant::now();
        let c = cpu_nanos();
        pairs = s.query_all().unwrap().len();
        cpu.push((cpu_nanos() - c) as f64 * 1e-6);
        total.push(t.elapsed().as_secs_f64() * 1e3);
        query.push(q.elapsed().as_secs_f64() * 1e3);
        stats.push(s.all_stats());
    }
    stats.sort_by_key(|s| s.total_nanos);
    let mid = stats[stats.len() / 2];
    (
        median(&mut total),
        median(&mut query),
        median(&mut cpu),
        pairs,
        mid,
    )
}

/// Writes `case` as OBJ files `DIR/NAME/frame{0,1,..}_partNN.obj` (the layout of
/// ../shared/meshes/sim), for the C++ peers (`DUMP=DIR`).
fn dump(case: &Case, dir: &str) {
    use std::fmt::Write;
    let slug: String = case
        .name
        .chars()
        .map(|c| if c.is_ascii_alphanumeric() { c } else { '-' })
        .collect();
    let out = format!("{dir}/{slug}");
    std::fs::create_dir_all(&out).expect("creating the dump directory");
    for (f, frame) in case.frames.iter().enumerate() {
        for (part, (p, idx)) in frame.iter().zip(&case.idx).enumerate() {
            let mut s = String::new();
            for q in p {
                writeln!(s, "v {:?} {:?} {:?}", q[0], q[1], q[2]).unwrap();
            }
            for t in idx.chunks(3) {
                writeln!(s, "f {} {} {}", t[0] + 1, t[1] + 1, t[2] + 1).unwrap();
            }
            let path = format!("{out}/frame{f}_part{part:02}.obj");
            std::fs::write(&path, s).expect("writing an OBJ");
        }
    }
    println!(
        "wrote {out}/frame{{0..{}}}_part*.obj",
        case.frames.len() - 1
    );
}

fn ms(n: u64) -> String {
    format!("{:.2}", n as f64 * 1e-6)
}

/// Writes the CSV `rows` to `csv`, if asked.
fn write_csv(rows: &[String], csv: Option<&str>) {
    if let Some(path) = csv {
        std::fs::write(path, rows.join("\n") + "\n").expect("writing the CSV");
        println!("\nwrote {path}");
    }
}

/// Time per frame against the body count: the broad phase must keep it proportional to the
/// touching pairs (each sphere touches its 6 neighbours), not to the square of the body count.
fn scaling(frames: usize, csv: Option<&str>) {
    let mut rows = vec!["bodies,triangles,threads,ms_per_frame,query_ms,pairs".to_string()];
    println!("{frames} frames per row, median; every sphere self-colliding; exact; CPU backend\n");
    println!("| bodies | triangles | threads | ms per frame (update + query) | query ms | pairs | query us per body |");
    println!("|---:|---:|---:|---:|---:|---:|---:|");
    for n in [10, 30, 100, 300, 1000, 3000, 5000] {
        let case = spheres_case(n);
        let tris: usize = case.idx.iter().map(|i| i.len() / 3).sum();
        for threads in [1, 2] {
            let (t, q, _, pairs, _) = run(&case, 0.0, threads, frames);
            println!(
                "| {n} | {tris} | {threads} | {t:.2} | {q:.2} | {pairs} | {:.1} |",
                q * 1e3 / n as f64
            );
            rows.push(format!("{n},{tris},{threads},{t:.4},{q:.4},{pairs}"));
        }
    }
    write_csv(&rows, csv);
}

/// Time per frame against the triangle count of one cloth folding onto itself: the rolled
/// cloth at 10k to 400k triangles (the same scene at five resolutions), exact, threads 1
/// and 2; printed and written as CSV.
fn self_scaling(frames: usize, csv: Option<&str>) {
    let mut rows = vec!["triangles,threads,ms_per_frame,query_ms,query_cpu_ms,pairs".to_string()];
    println!("{frames} frames per row, median; the rolled cloth + ball, self-collision, exact\n");
    println!("| triangles | threads | ms per frame (update + query) | query ms | query CPU ms | pairs | query ns per triangle | 2-thread speed-up |");
    println!("|---:|---:|---:|---:|---:|---:|---:|---:|");
    for n in [72, 120, 216, 300, 450] {
        let case = rolled_cloth(n);
        let tris = case.idx[0].len() / 3;
        let mut one = 0.0;
        for threads in [1, 2] {
            let (t, q, c, pairs, _) = run(&case, 0.0, threads, frames);
            if threads == 1 {
                one = q;
            }
            let speedup = if threads == 2 {
                format!("{:.2}x", one / q)
            } else {
                String::new()
            };
            println!(
                "| {tris} | {threads} | {t:.2} | {q:.2} | {c:.2} | {pairs} | {:.0} | {speedup} |",
                q * 1e6 / tris as f64
            );
            rows.push(format!("{tris},{threads},{t:.4},{q:.4},{c:.4},{pairs}"));
        }
    }
    write_csv(&rows, csv);
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let frames: usize = args.iter().find_map(|a| a.parse().ok()).unwrap_or(10);
    if let Some(i) = args.iter().position(|a| a == "self-scaling") {
        let csv = args.get(i + 1).filter(|a| a.ends_with(".csv"));
        return self_scaling(frames, csv.map(String::as_str));
    }
    if let Some(i) = args.iter().position(|a| a == "scaling") {
        let csv = args.get(i + 1).filter(|a| a.ends_with(".csv"));
        return scaling(frames, csv.map(String::as_str));
    }
    let var = |k: &str| std::env::var(k).ok().filter(|v| !v.is_empty());
    let keep = var("SCENE");
    let keep = |name: &str| keep.as_ref().is_none_or(|k| name.contains(k.as_str()));
    let rels: Vec<f32> = match var("EPS") {
        Some(e) => vec![e.parse().expect("EPS: a number")],
        None => vec![0.0, 1e-3],
    };
    let threads: Vec<u32> = match var("THREADS") {
        Some(t) => vec![t.parse().expect("THREADS: a number")],
        None => vec![1, 2],
    };
    let sims = [
        ("cloth-funnel", 227),
        ("armadillo-rollers", 326),
        ("rod-twist", 3036),
    ];
    let mut cases: Vec<Case> = sims
        .iter()
        .filter(|(n, _)| keep(n))
        .map(|&(n, f)| sim_case(n, f))
        .collect();
    if keep("rolled cloth") {
        cases.push(rolled_cloth_case());
    }
    if keep("crumpled cloth of 92450 triangles") {
        cases.push(crumpled_cloth_case());
    }
    for n in [100, 300] {
        for jitter in [0.0, 1e-4] {
            let case = sheet_case(n, jitter);
            if keep(&case.name) {
                cases.push(case);
            }
        }
    }
    if keep("spheres") {
        // SPHERES=10,100,5000: the body counts of the spheres scene (time vs body count).
        let counts: Vec<usize> = match var("SPHERES") {
            Some(v) => v
                .split(',')
                .map(|n| n.parse().expect("SPHERES: numbers"))
                .collect(),
            None => vec![1000],
        };
        cases.extend(counts.into_iter().map(spheres_case));
    }
    if let Some(dir) = var("DUMP") {
        for case in &cases {
            dump(case, &dir);
        }
    }
    println!("{frames} frames per row, median; every mesh self-colliding; CPU backend\n");
    println!(
        "| scene | epsilon | threads | ms per frame (update + query) | query ms | query CPU ms \
         (all threads) | pairs |"
    );
    println!("|---|---|---:|---:|---:|---:|---:|");
    let mut rows = Vec::new();
    for case in &cases {
        for &rel in &rels {
            for &threads in &threads {
                let (t, q, c, n, st) = run(case, rel * case.extent, threads, frames);
                let eps = if rel == 0.0 {
                    "0".to_string()
                } else {
                    format!("{rel:e} extent")
                };
                println!(
                    "| {} | {eps} | {threads} | {t:.2} | {q:.2} | {c:.2} | {n} |",
                    case.name
                );
                rows.push((case.name.clone(), eps, threads, st));
            }
        }
    }
    println!(
        "\nStages of the median query, ms (worker stages: CPU time summed over the workers); \
         counts: mesh pairs, self leaf pairs, self box pairs (adjacent by fans / adjacent tested / quick / apart / apart along a diagonal, not tested), found\n"
    );
    println!(
        "| scene | epsilon | threads | total | broad | self leaf pairs | workers (wall) | \
         self boxes | self adjacent | self apart | mesh pairs steps 1-2 / 3-4 / 5 | merge | \
         counts |"
    );
    println!("|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---|---:|---|");
    for (name, eps, threads, st) in rows {
        let p = st.pair_step_nanos;
        println!(
            "| {name} | {eps} | {threads} | {} | {} | {} | {} | {} | {} | {} | {} / {} / {} | {} | \
             {} mp, {} lp, {} bp ({} / {} / {} / {} / {}), {} + {} found; proven {} patches, {} fans |",
            ms(st.total_nanos),
            ms(st.broad_nanos),
            ms(st.self_leaf_nanos),
            ms(st.tasks_nanos),
            ms(st.self_box_nanos),
            ms(st.self_adjacent_nanos),
            ms(st.self_narrow_nanos),
            ms(p[0] + p[1]),
            ms(p[2] + p[3]),
            ms(p[4]),
            ms(st.merge_nanos),
            st.mesh_pairs,
            st.self_leaf_pairs,
            st.self_box_pairs,
            st.self_adjacent_fans,
            st.self_adjacent_tests,
            st.self_adjacent_quick,
            st.self_narrow_tests,
            st.self_box_culled,
            st.self_found,
            st.pair_found,
            st.self_cert_patches,
            st.self_cert_fans,
        );
    }
}
