//! Shared by the integration tests: meshes, deformations and the brute-force answer.
#![allow(dead_code)]

pub mod backends;
pub mod exact;
pub mod oracle;

use glcollide::obj::ObjMesh;
use glcollide::{Contact, MeshId, Positions, Scene, SceneConfig};

/// A mesh by name: from data/ (the meshes bundled with the repository), else from
/// ../shared/meshes (the big ones; a test that needs one first asks [`has_shared`]).
pub fn shared_mesh(name: &str) -> ObjMesh {
    let root = env!("CARGO_MANIFEST_DIR");
    let bundled = format!("{root}/data/{name}.obj");
    let p = if std::path::Path::new(&bundled).exists() {
        bundled
    } else {
        format!("{root}/../shared/meshes/{name}.obj")
    };
    glcollide::obj::load(&p).unwrap_or_else(|e| panic!("{p}: {e}"))
}

/// Part `part` of frame `frame` of a simulation scene of ../shared/meshes/sim (not
/// bundled: ask [`has_shared`] first).
pub fn sim_part(scene: &str, frame: u32, part: u32) -> TestMesh {
    let p = format!(
        "{}/../shared/meshes/sim/{scene}/frame{frame}_part{part:02}.obj",
        env!("CARGO_MANIFEST_DIR")
    );
    TestMesh::from_obj(&glcollide::obj::load(&p).unwrap_or_else(|e| panic!("{p}: {e}")))
}

/// True when `../shared/<what>` (the big shared data beside the clone, as CI has it)
/// exists. Otherwise says `skipped: needs ../shared/<what> (<test>)` on stderr, past the
/// test harness's capture (it captures only the print macros), so that `cargo test` shows
/// it; the test then returns early.
pub fn has_shared(what: &str) -> bool {
    use std::io::Write;
    let p = format!("{}/../shared/{what}", env!("CARGO_MANIFEST_DIR"));
    let there = std::path::Path::new(&p).exists();
    if !there {
        let test = std::thread::current().name().unwrap_or("?").to_string();
        let _ = writeln!(
            std::io::stderr(),
            "skipped: needs ../shared/{what} ({test})"
        );
    }
    there
}

/// Box of a point set.
pub fn bounds(p: &[[f32; 3]]) -> ([f32; 3], [f32; 3]) {
    let mut lo = [f32::INFINITY; 3];
    let mut hi = [f32::NEG_INFINITY; 3];
    for v in p {
        for k in 0..3 {
            lo[k] = lo[k].min(v[k]);
            hi[k] = hi[k].max(v[k]);
        }
    }
    (lo, hi)
}

/// Polygon `i` of a mesh with `k` vertices per polygon as its triangles (f64).
pub fn polygon_triangles(pos: &[[f32; 3]], idx: &[u32], k: usize, i: usize) -> Vec<[[f64; 3]; 3]> {
    let v = |j: usize| {
        let p = pos[idx[i * k + j] as usize];
        [p[0] as f64, p[1] as f64, p[2] as f64]
    };
    if k == 3 {
        vec![[v(0), v(1), v(2)]]
    } else {
        vec![[v(0), v(1), v(2)], [v(0), v(2), v(3)]]
    }
}

/// A mesh as the tests hand it to a scene: positions, indices, vertices per polygon.
#[derive(Clone, Debug)]
pub struct TestMesh {
    pub pos: Vec<[f32; 3]>,
    pub idx: Vec<u32>,
    pub k: usize,
}

impl TestMesh {
    pub fn from_obj(m: &ObjMesh) -> TestMesh {
        TestMesh {
            pos: m.positions.clone(),
            idx: m.triangles.clone(),
            k: 3,
        }
    }
    pub fn polygons(&self) -> usize {
        self.idx.len() / self.k
    }
    pub fn tris(&self, i: usize) -> Vec<[[f64; 3]; 3]> {
        polygon_triangles(&self.pos, &self.idx, self.k, i)
    }
    pub fn poly_box(&self, i: usize) -> ([f32; 3], [f32; 3]) {
        let vs: Vec<[f32; 3]> = (0..self.k)
            .map(|j| self.pos[self.idx[i * self.k + j] as usize])
            .collect();
        bounds(&vs)
    }
}

/// The unit square [dx, dx + 1] x [0, 1] in the plane `z`, two triangles.
pub fn square(z: f32, dx: f32) -> TestMesh {
    TestMesh {
        pos: vec![[dx, 0., z], [dx + 1., 0., z], [dx + 1., 1., z], [dx, 1., z]],
        idx: vec![0, 1, 2, 0, 2, 3],
        k: 3,
    }
}

/// A 1 x 2 rectangle in the plane `x` (y in [-0.5, 0.5], z in [-1, 1]), two triangles: it
/// crosses `square(0.0, 0.0)` when x is in [0, 1].
pub fn wall(x: f32) -> TestMesh {
    TestMesh {
        pos: vec![[x, 0.5, -1.], [x, 0.5, 1.], [x, -0.5, 1.], [x, -0.5, -1.]],
        idx: vec![0, 1, 2, 0, 2, 3],
        k: 3,
    }
}

/// Distance between polygon `a` of `r` and polygon `b` of `o` (the closest of their
/// triangles), 0 when they meet.
pub fn polygon_distance(r: &TestMesh, a: usize, o: &TestMesh, b: usize) -> f64 {
    r.tris(a)
        .iter()
        .flat_map(|t| {
            o.tris(b)
                .into_iter()
                .map(move |u| oracle::triangle_distance(t, &u))
        })
        .fold(f64::INFINITY, f64::min)
}

/// Every polygon pair (reference polygon, other polygon) whose closed polygons meet, by
/// brute force over the pairs whose boxes (grown by `pad`) overlap, with the exact oracle.
pub fn brute_force_exact(r: &TestMesh, o: &TestMesh) -> Vec<(u32, u32)> {
    brute_force(r, o, 0.0, |a, b| {
        a.iter()
            .any(|t| b.iter().any(|u| oracle::triangles_meet(t, u)))
    })
}

/// Pairs whose polygons are within `d` of each other (f64 distance).
pub fn brute_force_within(r: &TestMesh, o: &TestMesh, d: f64) -> Vec<(u32, u32)> {
    brute_force(r, o, d, |a, b| {
        a.iter()
            .any(|t| b.iter().any(|u| oracle::triangle_distance(t, u) <= d))
    })
}

fn brute_force(
    r: &TestMesh,
    o: &TestMesh,
    pad: f64,
    meets: impl Fn(&[[[f64; 3]; 3]], &[[[f64; 3]; 3]]) -> bool,
) -> Vec<(u32, u32)> {
    let rb: Vec<_> = (0..r.polygons()).map(|i| r.poly_box(i)).collect();
    let ob: Vec<_> = (0..o.polygons()).map(|i| o.poly_box(i)).collect();
    // Sort the other mesh's boxes along x and sweep.
    let mut order: Vec<usize> = (0..ob.len()).collect();
    order.sort_by(|&a, &b| ob[a].0[0].total_cmp(&ob[b].0[0]));
    let mut out = Vec::new();
    for (i, (lo, hi)) in rb.iter().enumerate() {
        let rt = r.tris(i);
        for &j in &order {
            let (olo, ohi) = ob[j];
            if olo[0] as f64 > hi[0] as f64 + pad {
                break;
            }
            let overlap = (0..3).all(|k| {
                olo[k] as f64 <= hi[k] as f64 + pad && lo[k] as f64 <= ohi[k] as f64 + pad
            });
            if overlap && meets(&rt, &o.tris(j)) {
                out.push((i as u32, j as u32));
            }
        }
    }
    out.sort_unstable();
    out
}

/// Builds a scene with the reference first, runs one query, returns (ref poly, other poly)
/// pairs against `other`.
pub fn scene_pairs(scene: &mut Scene, reference: MeshId, other: MeshId) -> Vec<(u32, u32)> {
    let c: Vec<Contact> = scene.query(reference).unwrap().to_vec();
    let mut v: Vec<(u32, u32)> = c
        .iter()
        .filter(|c| c.other_mesh == other)
        .map(|c| (c.reference_polygon, c.other_polygon))
        .collect();
    v.sort_unstable();
    v
}

pub fn add(scene: &mut Scene, m: &TestMesh) -> MeshId {
    scene
        .create_mesh(Positions::from_points(&m.pos), &m.idx, m.k)
        .unwrap()
}

pub fn cpu_scene(epsilon: f32, leaf: u32) -> Scene {
    Scene::new(SceneConfig {
        epsilon,
        max_polygons_per_box: leaf,
        ..SceneConfig::default()
    })
    .unwrap()
}

/// Deterministic pseudo-random numbers (xorshift), so failures reproduce.
pub struct Rng(pub u64);
impl Rng {
    pub fn next_u64(&mut self) -> u64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        self.0
    }
    /// Uniform in [0, 1).
    pub fn f(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }
    pub fn range(&mut self, a: f64, b: f64) -> f64 {
        a + (b - a) * self.f()
    }
}

/// A smooth deformation: every vertex moves by `amp * sin(phase + freq * position)`
/// along each axis, with a different phase per axis.
pub fn wave(rest: &[[f32; 3]], amp: f32, freq: f32, phase: f32) -> Vec<[f32; 3]> {
    rest.iter()
        .map(|p| {
            [
                p[0] + amp * (phase + freq * p[1]).sin(),
                p[1] + amp * (phase * 1.3 + freq * p[2]).sin(),
                p[2] + amp * (phase * 0.7 + freq * p[0]).sin(),
            ]
        })
        .collect()
}

/// Moves and rotates a mesh (about y by `angle`: 0 keeps its z axis, pi/2 turns z onto x)
/// so that its box centre lands at `to`.
pub fn place(rest: &[[f32; 3]], to: [f32; 3], angle: f32) -> Vec<[f32; 3]> {
    place_scaled(rest, to, angle, 1.0)
}

/// As [`place`], scaling about the box centre first.
pub fn place_scaled(rest: &[[f32; 3]], to: [f32; 3], angle: f32, scale: f32) -> Vec<[f32; 3]> {
    let (lo, hi) = bounds(rest);
    let c = [0, 1, 2].map(|k| (lo[k] + hi[k]) / 2.0);
    let (s, co) = angle.sin_cos();
    rest.iter()
        .map(|p| {
            let (x, y, z) = (
                (p[0] - c[0]) * scale,
                (p[1] - c[1]) * scale,
                (p[2] - c[2]) * scale,
            );
            [to[0] + co * x + s * z, to[1] + y, to[2] - s * x + co * z]
        })
        .collect()
}
