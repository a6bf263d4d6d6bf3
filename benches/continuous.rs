//! Continuous detection per step (`Scene::query_continuous`, CPU) on the real simulation
//! steps of ../shared/meshes/sim (every part an f64 mesh with self-collision, frame N to
//! frame N+1), next to the discrete `Scene::query_all` of the same frame: median over
//! repeated steps, threads 1 and 2, with the stages of the continuous query. The work per
//! step is what a simulator pays: the update committing frame N (which drops the target),
//! the target (frame N+1), the query. Prints a Markdown table.
//!   cargo bench --bench continuous [-- REPS]
//! Environment: `SCENE=substring`, `THREADS=1`.

use std::time::Instant;

use glcollide::{MeshId, Positions, Scene, SceneConfig};

/// An OBJ's vertices as doubles (the frames hold exact doubles) and its triangles.
fn obj_f64(path: &str) -> (Vec<[f64; 3]>, Vec<u32>) {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{path}: {e}"));
    let (mut v, mut f) = (Vec::new(), Vec::new());
    for line in text.lines() {
        let mut w = line.split_whitespace();
        match w.next() {
            Some("v") => {
                let x: Vec<f64> = w.take(3).map(|t| t.parse().unwrap()).collect();
                v.push([x[0], x[1], x[2]]);
            }
            Some("f") => {
                f.extend(w.map(|t| t.split('/').next().unwrap().parse::<u32>().unwrap() - 1))
            }
            _ => {}
        }
    }
    (v, f)
}

struct Step {
    name: &'static str,
    idx: Vec<Vec<u32>>,
    frames: [Vec<Vec<[f64; 3]>>; 2],
}

fn load(name: &'static str, n: u32) -> Option<Step> {
    let dir = format!("{}/../shared/meshes/sim/{name}", env!("CARGO_MANIFEST_DIR"));
    let mut s = Step {
        name,
        idx: Vec::new(),
        frames: [Vec::new(), Vec::new()],
    };
    for part in 0.. {
        let at = |f: u32| format!("{dir}/frame{f}_part{part:02}.obj");
        if !std::path::Path::new(&at(n)).exists() {
            break;
        }
        let (a, t) = obj_f64(&at(n));
        let (b, _) = obj_f64(&at(n + 1));
        s.idx.push(t);
        s.frames[0].push(a);
        s.frames[1].push(b);
    }
    (!s.idx.is_empty()).then_some(s)
}

fn median(v: &mut [f64]) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn main() {
    let reps: usize = std::env::args()
        .skip(1)
        .find_map(|a| a.parse().ok())
        .unwrap_or(7);
    let only = std::env::var("SCENE").unwrap_or_default();
    let threads: Vec<u32> = match std::env::var("THREADS") {
        Ok(t) => vec![t.parse().unwrap()],
        Err(_) => vec![1, 2],
    };
    let steps = [
        ("cloth-funnel", 227),
        ("rod-twist", 3036),
        ("armadillo-rollers", 326),
    ];
    println!(
        "| step | polygons | threads | discrete query_all ms | continuous step ms | ratio | \
         pairs (discrete / step) | sweep ms | broad ms | narrow ms (CPU) | leaf pairs | polygon pairs |"
    );
    println!("|---|---:|---:|---:|---:|---:|---|---:|---:|---:|---:|---:|");
    for (name, n) in steps {
        if !name.contains(only.as_str()) {
            continue;
        }
        let Some(step) = load(name, n) else {
            println!("| {name} | skipped: needs ../shared/meshes/sim/{name} |");
            continue;
        };
        let polys: usize = step.idx.iter().map(|i| i.len() / 3).sum();
        for &t in &threads {
            let mut s = Scene::new(SceneConfig {
                threads: t,
                ..SceneConfig::default()
            })
            .unwrap();
            let ids: Vec<MeshId> = step
                .idx
                .iter()
                .zip(&step.frames[0])
                .map(|(i, p)| {
                    let id = s.create_mesh(Positions::from_points_f64(p), i, 3).unwrap();
                    s.set_self_collision(id, true).unwrap();
                    id
                })
                .collect();
            let (mut disc, mut cont) = (Vec::new(), Vec::new());
            let (mut nd, mut nc) = (0, 0);
            let mut stats = Vec::new();
            for _ in 0..reps {
                let t0 = Instant::now();
                for (id, p) in ids.iter().zip(&step.frames[0]) {
                    s.update_positions_f64(*id, 0, p).unwrap();
                }
                nd = s.query_all().unwrap().len();
                disc.push(t0.elapsed().as_secs_f64() * 1e3);
                let t0 = Instant::now();
                for (id, p) in ids.iter().zip(&step.frames[0]) {
                    s.update_positions_f64(*id, 0, p).unwrap();
                }
                for (id, p) in ids.iter().zip(&step.frames[1]) {
                    s.set_target_positions_f64(*id, 0, p).unwrap();
                }
                nc = s.query_continuous().unwrap().len();
                cont.push(t0.elapsed().as_secs_f64() * 1e3);
                stats.push(s.continuous_stats());
            }
            let (d, c) = (median(&mut disc), median(&mut cont));
            stats.sort_by_key(|s| s.total_nanos);
            let st = stats[stats.len() / 2];
            let ms = |x: u64| x as f64 / 1e6;
            println!(
                "| {} {n}->{} | {polys} | {t} | {d:.2} | {c:.2} | {:.1}x | {nd} / {nc} | {:.2} | {:.2} | {:.2} | {} | {} |",
                step.name,
                n + 1,
                c / d,
                ms(st.sweep_nanos),
                ms(st.broad_nanos),
                ms(st.narrow_nanos),
                st.leaf_pairs,
                st.polygon_pairs
            );
        }
    }
}
