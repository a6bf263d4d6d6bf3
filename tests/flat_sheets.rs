//! Flat meshes in self-collision (issue 27: "a flat or piecewise-flat mesh must cost no more
//! than a curved one"): a sheet folded exactly flat onto itself, every vertex in one
//! coordinate plane, so every polygon pair is coplanar and the exact predicates' slowest
//! cases are the common ones. The answer of `query_all` against the independent oracle
//! (tests/common/oracle.rs), for triangles and quads, in each coordinate plane, at the origin
//! and 1e3 off.
mod common;

use common::oracle::triangles_meet;
use common::polygon_triangles;
use glcollide::{Positions, Scene, SceneConfig};

/// Two n x n grids of cell `h`, the second shifted by `shift` within the plane, as one mesh
/// (so its pairs across the layers are same-mesh pairs sharing no vertex); every vertex at
/// coordinate `c` along `axis`.
fn folded(n: u32, k: usize, axis: usize, c: f32, shift: [f32; 2]) -> (Vec<[f32; 3]>, Vec<u32>) {
    let mut pos = Vec::new();
    let mut idx = Vec::new();
    for layer in 0..2u32 {
        let base = pos.len() as u32;
        let s = if layer == 0 { [0.0, 0.0] } else { shift };
        for j in 0..=n {
            for i in 0..=n {
                let mut p = [0.0; 3];
                p[axis] = c;
                p[(axis + 1) % 3] = c + s[0] + i as f32 * 0.125;
                p[(axis + 2) % 3] = c + s[1] + j as f32 * 0.125;
                pos.push(p);
            }
        }
        for j in 0..n {
            for i in 0..n {
                let v = base + j * (n + 1) + i;
                let w = n + 1;
                if k == 4 {
                    idx.extend([v, v + 1, v + w + 1, v + w]);
                } else {
                    idx.extend([v, v + 1, v + w + 1, v, v + w + 1, v + w]);
                }
            }
        }
    }
    (pos, idx)
}

/// The oracle's answer: pairs of polygons sharing no vertex that meet (a flat sheet's
/// neighbours only touch where they are joined, which the adjacency rule leaves out).
fn oracle(pos: &[[f32; 3]], idx: &[u32], k: usize) -> Vec<(u32, u32)> {
    let n = idx.len() / k;
    let tris: Vec<_> = (0..n).map(|i| polygon_triangles(pos, idx, k, i)).collect();
    let mut out = Vec::new();
    for a in 0..n {
        for b in a + 1..n {
            let (pa, pb) = (&idx[a * k..a * k + k], &idx[b * k..b * k + k]);
            if pa.iter().any(|v| pb.contains(v)) {
                continue;
            }
            if tris[a]
                .iter()
                .any(|t| tris[b].iter().any(|u| triangles_meet(t, u)))
            {
                out.push((a as u32, b as u32));
            }
        }
    }
    out
}

#[test]
fn a_sheet_folded_flat_onto_itself_against_the_oracle() {
    let mut total = 0;
    for k in [3, 4] {
        for axis in 0..3 {
            for c in [0.0f32, 1e3] {
                // Shifts on the grid (edges on edges, corners on corners) and off it.
                for shift in [[0.25, 0.125], [0.3, 0.2]] {
                    let (pos, idx) = folded(6, k, axis, c, shift);
                    let mut s = Scene::new(SceneConfig {
                        max_polygons_per_box: 8,
                        ..SceneConfig::default()
                    })
                    .unwrap();
                    let id = s
                        .create_mesh(Positions::from_points(&pos), &idx, k)
                        .unwrap();
                    s.set_self_collision(id, true).unwrap();
                    let got: Vec<(u32, u32)> = s
                        .query_all()
                        .unwrap()
                        .iter()
                        .map(|p| (p.polygon_a, p.polygon_b))
                        .collect();
                    let want = oracle(&pos, &idx, k);
                    assert_eq!(got, want, "k {k}, axis {axis}, at {c}, shift {shift:?}");
                    total += want.len();
                }
            }
        }
    }
    assert!(total > 1000, "{total} pairs: the layers must overlap");
}
