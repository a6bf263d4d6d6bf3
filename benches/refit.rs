//! Refit and update cost per mesh of ../shared/meshes (paper section 2.4).
//!   cargo bench --bench refit [-- FRAMES]
//! Prints a Markdown table: median over FRAMES frames (default 200) of
//! - refit: `Mesh::refit` alone (every leaf box and the root, one pass over the leaves'
//!   vertex lists);
//! - update: `glcol_mesh_update_positions`' work (copy + finiteness check + refit) for the
//!   whole mesh, the vertices changing every frame.

use std::time::Instant;

use glcollide::{Positions, Scene, SceneConfig};

fn median(v: &mut [f64]) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn main() {
    let frames: usize = std::env::args()
        .skip(1)
        .find_map(|a| a.parse().ok())
        .unwrap_or(200);
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/../shared/meshes");
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .expect("../shared/meshes")
        .filter_map(|e| e.ok()?.file_name().into_string().ok())
        .filter(|n| n.ends_with(".obj"))
        .collect();
    names.sort();
    println!("| mesh | vertices | triangles | leaves | refit µs | update µs | update ns/vertex |");
    println!("|---|---:|---:|---:|---:|---:|---:|");
    for name in names {
        let m = glcollide::obj::load(format!("{dir}/{name}")).unwrap();
        let mut scene = Scene::new(SceneConfig::default()).unwrap();
        let id = scene
            .create_mesh(Positions::from_points(&m.positions), &m.triangles, 3)
            .unwrap();
        // Two alternating deformed copies, so every update really changes the vertices.
        let frames_pos: Vec<Vec<[f32; 3]>> = (0..2)
            .map(|f| {
                m.positions
                    .iter()
                    .map(|p| [p[0] + 0.001 * (f as f32 + p[1]).sin(), p[1], p[2]])
                    .collect()
            })
            .collect();
        let mut refit = Vec::with_capacity(frames);
        let mut update = Vec::with_capacity(frames);
        for f in 0..frames {
            let src = Positions::from_points(&frames_pos[f % 2]);
            let t = Instant::now();
            scene.update_positions(id, 0, src).unwrap();
            update.push(t.elapsed().as_secs_f64() * 1e6);
        }
        let mut mesh = scene.mesh(id).unwrap().clone();
        for _ in 0..frames {
            let t = Instant::now();
            mesh.refit();
            refit.push(t.elapsed().as_secs_f64() * 1e6);
            std::hint::black_box(mesh.root());
        }
        let (r, u) = (median(&mut refit), median(&mut update));
        println!(
            "| {} | {} | {} | {} | {:.1} | {:.1} | {:.2} |",
            name.trim_end_matches(".obj"),
            m.positions.len(),
            m.triangle_count(),
            mesh.leaf_count(),
            r,
            u,
            u * 1e3 / m.positions.len() as f64
        );
    }
}
