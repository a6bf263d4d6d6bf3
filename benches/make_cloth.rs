//! Generates bench/data/crumpled-cloth/ (the `crumpled cloth` case of scene.rs): a 216 x 216
//! vertex sheet (92,450 triangles, triangulated as `sheet_case` in scene.rs) dropped over a
//! spinning ball with a simple mass-spring simulation and no self-collision response, so
//! that it drapes, wraps and crumples through itself; four consecutive steps after the
//! crumpling are written as raw little-endian f32 positions (216 * 216 * 3 floats each,
//! vertex `j * 216 + i` at row j, column i).
//!   cargo bench --bench make_cloth
//! Deterministic (double arithmetic with + - * / and sqrt only, one thread, a fixed
//! xorshift for the noise, no parameter read from outside): a run rewrites the files byte
//! for byte. Prints, per saved frame, the polygon pairs that intersect (glcollide's
//! `Scene::query_all`, self-collision, epsilon 0), the polygon box pairs that overlap (a
//! sort-and-sweep of the triangles' closed axis-aligned boxes, independent of glcollide,
//! neighbours included) and how far the vertices moved since the previous frame.
//!
//! The model (units: metres, seconds): Verlet integration, step 1/240 s, the velocity damped
//! by 0.5% a step; gravity 2 m/s^2 down and a pull of 8 m/s^2 towards the ball's centre (the
//! crumpling: the sheet, 2 m square, is about eight times the ball's surface); springs along
//! the grid's edges (stiffness 1), both diagonals of each cell (1) and two cells apart
//! (bending, 1), satisfied by 8 Gauss-Seidel sweeps of position projection a step, each
//! sweep followed by the ball: a ball of radius 0.2 at the origin spinning at 1.5 rad/s about
//! the vertical axis (friction 0.5 against its surface, so the cloth keeps moving). The
//! ball's contact radius grows with the vertex's distance from the sheet's centre, by
//! `LAYER` = 13 cell sizes at the corners: material wrapped over the ball rests in layers
//! rather than all on the one sphere (where pressed layers would coincide and cross
//! wherever rounding says). The sheet starts flat 5 cm above the ball, tilted (cos 0.96,
//! sin 0.28 about x), 7 cm / -4 cm off centre, with a noise of 1e-3 cell sizes across it.

use std::time::Instant;

use glcollide::{Positions, Scene, SceneConfig};

/// Vertices per side.
const N: usize = 216;
/// Side of the sheet, m.
const SIDE: f64 = 2.0;
/// The ball: radius, m; spin about the vertical axis, rad/s; friction (the part of a
/// contact's tangential motion relative to the surface removed per projection).
const RADIUS: f64 = 0.2;
const SPIN: f64 = 1.5;
const FRICTION: f64 = 0.5;
/// Contact radius growth from the sheet's centre to its corners, in cell sizes.
const LAYER: f64 = 13.0;
/// Height of the sheet's lowest point above the ball at the start, m.
const DROP: f64 = 0.05;
/// Time step, s; gravity and the pull towards the ball's centre, m/s^2; velocity damping
/// per step.
const DT: f64 = 1.0 / 240.0;
const GRAVITY: f64 = 2.0;
const PULL: f64 = 8.0;
const DAMPING: f64 = 0.005;
/// Stiffness (fraction of the error corrected per projection) of the structural, shear
/// and bending springs; projection sweeps per step.
const K_STRUCT: f64 = 1.0;
const K_SHEAR: f64 = 1.0;
const K_BEND: f64 = 1.0;
const ITERS: usize = 8;
/// Steps before the first saved frame; saved frames (one step apart).
const SETTLE: usize = 750;
const FRAMES: usize = 4;

struct Cloth {
    x: Vec<[f64; 3]>,
    prev: Vec<[f64; 3]>,
    /// (a, b, rest length, stiffness)
    springs: Vec<(u32, u32, f64, f64)>,
    /// The ball's contact radius per vertex.
    contact: Vec<f64>,
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

impl Cloth {
    fn new() -> Cloth {
        let h = SIDE / (N - 1) as f64;
        // Tilt: the rotation about x with cos 0.96, sin 0.28 (a Pythagorean triple, exact).
        let (ct, st) = (0.96, 0.28);
        let mut seed = 0x9E37_79B9_7F4A_7C15u64;
        let mut rnd = move || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        };
        let mut x = Vec::with_capacity(N * N);
        let mut contact = Vec::with_capacity(N * N);
        let c = (N - 1) as f64 / 2.0;
        for j in 0..N {
            for i in 0..N {
                let (u, v) = (
                    i as f64 * h - SIDE / 2.0 + 0.07,
                    j as f64 * h - SIDE / 2.0 - 0.04,
                );
                let w = 1e-3 * h * rnd();
                let (y, z) = (ct * v - st * w, st * v + ct * w);
                x.push([u, y, z + RADIUS + DROP + st * SIDE / 2.0]);
                let (di, dj) = (i as f64 - c, j as f64 - c);
                let s = (di * di + dj * dj).sqrt() / (c * std::f64::consts::SQRT_2);
                contact.push(RADIUS + 0.5 * h + LAYER * h * s);
            }
        }
        let at = |i: usize, j: usize| j * N + i;
        let mut springs = Vec::new();
        let mut add = |a: usize, b: usize, k: f64| {
            let d = [0, 1, 2].map(|c| x[a][c] - x[b][c]);
            springs.push((a as u32, b as u32, dot(d, d).sqrt(), k));
        };
        for j in 0..N {
            for i in 0..N {
                if i + 1 < N {
                    add(at(i, j), at(i + 1, j), K_STRUCT);
                }
                if j + 1 < N {
                    add(at(i, j), at(i, j + 1), K_STRUCT);
                }
                if i + 1 < N && j + 1 < N {
                    add(at(i, j), at(i + 1, j + 1), K_SHEAR);
                    add(at(i + 1, j), at(i, j + 1), K_SHEAR);
                }
                if i + 2 < N {
                    add(at(i, j), at(i + 2, j), K_BEND);
                }
                if j + 2 < N {
                    add(at(i, j), at(i, j + 2), K_BEND);
                }
            }
        }
        Cloth {
            prev: x.clone(),
            x,
            springs,
            contact,
        }
    }

    fn step(&mut self) {
        for (p, q) in self.x.iter_mut().zip(&mut self.prev) {
            let v = [0, 1, 2].map(|c| (p[c] - q[c]) * (1.0 - DAMPING));
            *q = *p;
            let s = PULL / dot(*p, *p).sqrt();
            let a = [-s * p[0], -s * p[1], -s * p[2] - GRAVITY];
            for c in 0..3 {
                p[c] += v[c] + a[c] * DT * DT;
            }
        }
        let x = &mut self.x;
        for _ in 0..ITERS {
            for &(a, b, r, k) in &self.springs {
                let (a, b) = (a as usize, b as usize);
                let d = [0, 1, 2].map(|c| x[b][c] - x[a][c]);
                let l = dot(d, d).sqrt();
                if l > 0.0 {
                    let s = 0.5 * k * (l - r) / l;
                    for c in 0..3 {
                        x[a][c] += s * d[c];
                        x[b][c] -= s * d[c];
                    }
                }
            }
            for ((p, q), &r) in x.iter_mut().zip(&self.prev).zip(&self.contact) {
                let l2 = dot(*p, *p);
                if l2 < r * r {
                    let n = p.map(|c| c / l2.sqrt());
                    *p = n.map(|c| c * r);
                    // Friction: the step's motion relative to the spinning surface shrinks.
                    let ball = [-SPIN * DT * p[1], SPIN * DT * p[0], 0.0];
                    let rel = [0, 1, 2].map(|c| p[c] - q[c] - ball[c]);
                    let rn = dot(rel, n);
                    for c in 0..3 {
                        p[c] -= FRICTION * (rel[c] - rn * n[c]);
                    }
                }
            }
        }
    }
}

/// Pairs p < q of triangles whose closed axis-aligned boxes meet (neighbours included): sort
/// by the boxes' low x, sweep.
fn box_pairs(p: &[[f32; 3]], tris: &[u32]) -> usize {
    let mut boxes: Vec<([f32; 3], [f32; 3])> = tris
        .chunks(3)
        .map(|t| {
            let (mut lo, mut hi) = (p[t[0] as usize], p[t[0] as usize]);
            for &v in &t[1..] {
                for c in 0..3 {
                    lo[c] = lo[c].min(p[v as usize][c]);
                    hi[c] = hi[c].max(p[v as usize][c]);
                }
            }
            (lo, hi)
        })
        .collect();
    boxes.sort_by(|a, b| a.0[0].total_cmp(&b.0[0]));
    let mut n = 0;
    for (i, a) in boxes.iter().enumerate() {
        for b in &boxes[i + 1..] {
            if b.0[0] > a.1[0] {
                break;
            }
            if b.0[1] <= a.1[1] && a.0[1] <= b.1[1] && b.0[2] <= a.1[2] && a.0[2] <= b.1[2] {
                n += 1;
            }
        }
    }
    n
}

fn main() {
    let t0 = Instant::now();
    let out = concat!(env!("CARGO_MANIFEST_DIR"), "/bench/data/crumpled-cloth");
    let w = N as u32;
    let mut tris = Vec::new();
    for j in 0..w - 1 {
        for i in 0..w - 1 {
            let v = j * w + i;
            tris.extend([v, v + 1, v + w + 1, v, v + w + 1, v + w]);
        }
    }
    let mut cloth = Cloth::new();
    let f32s =
        |x: &[[f64; 3]]| -> Vec<[f32; 3]> { x.iter().map(|p| p.map(|c| c as f32)).collect() };
    let mut scene = Scene::new(SceneConfig::default()).unwrap();
    let id = scene
        .create_mesh(Positions::from_points(&f32s(&cloth.x)), &tris, 3)
        .unwrap();
    scene.set_self_collision(id, true).unwrap();
    let mut count = |p: &[[f32; 3]]| -> (usize, usize) {
        scene
            .update_positions(id, 0, Positions::from_points(p))
            .unwrap();
        (scene.query_all().unwrap().len(), box_pairs(p, &tris))
    };
    for s in 1..=SETTLE {
        cloth.step();
        if s % 150 == 0 {
            let (hits, boxes) = count(&f32s(&cloth.x));
            println!(
                "step {s}: {hits} polygon pairs intersect, {boxes} box pairs overlap ({:.1} s)",
                t0.elapsed().as_secs_f64()
            );
        }
    }
    std::fs::create_dir_all(out).expect("creating bench/data/crumpled-cloth");
    println!("\n| frame | step | intersecting pairs | box pairs | moved max, m | moved mean, m |");
    println!("|---|---:|---:|---:|---:|---:|");
    let mut last: Option<Vec<[f32; 3]>> = None;
    for f in 0..FRAMES {
        if f > 0 {
            cloth.step();
        }
        let p = f32s(&cloth.x);
        let (hits, boxes) = count(&p);
        let (max, mean) = match &last {
            None => ("-".to_string(), "-".to_string()),
            Some(q) => {
                let d: Vec<f64> = p
                    .iter()
                    .zip(q)
                    .map(|(a, b)| {
                        let d = [0, 1, 2].map(|c| a[c] as f64 - b[c] as f64);
                        dot(d, d).sqrt()
                    })
                    .collect();
                let max = d.iter().copied().fold(0.0, f64::max);
                let mean = d.iter().sum::<f64>() / d.len() as f64;
                (format!("{max:.2e}"), format!("{mean:.2e}"))
            }
        };
        println!(
            "| {f} | {} | {hits} | {boxes} | {max} | {mean} |",
            SETTLE + f
        );
        let bytes: Vec<u8> = p.iter().flatten().flat_map(|c| c.to_le_bytes()).collect();
        std::fs::write(format!("{out}/frame{f}.f32"), bytes).expect("writing a frame");
        last = Some(p);
    }
    println!(
        "\nwrote {out}/frame{{0..{}}}.f32 ({:.1} s)",
        FRAMES - 1,
        t0.elapsed().as_secs_f64()
    );
}
