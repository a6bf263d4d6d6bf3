//! Named cases against the oracle, sharing by index, adjacency through a real mesh, and the
//! cloth timing (ignored: `--ignored --nocapture`).

use super::support::*;
use crate::geom::adjacent::{adjacent_polygons_meet, shares_vertex};
use crate::geom::predicates::P3;

/// The predicate on polygons `a`, `b` over `pos`, checked against the oracle.
fn meets(a: &[u32], b: &[u32], pos: &[P3]) -> bool {
    let c = Case::new(a, b, pos);
    let r = c.predicate(true);
    assert_eq!(r, c.oracle(), "oracle disagrees on {c:?}");
    r
}

#[test]
fn named_cases() {
    let f = |x: f64| x as f32 as f64;
    // Cloth: flat neighbours, and folded by a tiny angle (they meet along the edge only:
    // a fold meets the neighbour's face only when exactly flat onto it).
    let mut pos = vec![
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.3, 1.0, 0.0],
        [0.6, -1.0, 0.0],
    ];
    assert!(!meets(&[0, 1, 2], &[1, 0, 3], &pos));
    pos[3] = [0.6, 1.0, f(1e-7)];
    assert!(!meets(&[0, 1, 2], &[1, 0, 3], &pos));
    pos[3] = [0.6, 1.0, 0.0];
    assert!(
        meets(&[0, 1, 2], &[1, 0, 3], &pos),
        "folded flat onto the neighbour"
    );
    // Sharing a vertex: apart, the next triangle's edge pushed through, pinched flat.
    let mut pos = vec![
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [-1.0, 0.0, 0.5],
        [0.0, -1.0, 0.5],
    ];
    assert!(!meets(&[0, 1, 2], &[0, 3, 4], &pos));
    pos[3] = [0.3, 0.3, -0.5];
    pos[4] = [0.3, 0.3, 0.5];
    assert!(
        meets(&[0, 1, 2], &[0, 3, 4], &pos),
        "edge through the neighbour"
    );
    pos[3] = [-1.0, 0.0, 0.0];
    pos[4] = [0.0, -1.0, 0.0];
    assert!(
        !meets(&[0, 1, 2], &[0, 3, 4], &pos),
        "opposite sectors touch at the vertex"
    );
    pos[4] = [1.0, 1.0, 0.0];
    assert!(meets(&[0, 1, 2], &[0, 3, 4], &pos), "overlapping sectors");
    // A quad's diagonal is not an edge: a triangle on it meets the quad along it.
    let pos = vec![
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [1.0, 1.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.5, 0.5, 1.0],
        [0.5, -1.0, 0.0],
    ];
    assert!(meets(&[0, 1, 2, 3], &[2, 0, 4], &pos), "on the diagonal");
    assert!(!meets(&[0, 1, 2, 3], &[1, 0, 5], &pos), "on an edge");
    assert!(
        !meets(&[0, 1, 2, 3], &[0, 4, 1], &pos),
        "on an edge, folded up"
    );
    assert!(
        !meets(&[0, 1, 2, 3], &[1, 0, 5, 4], &pos),
        "two quads on an edge"
    );
    // Duplicates meet unless degenerate; a degenerate polygon on a shared edge does not.
    let pos = vec![
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [2.0, 0.0, 0.0],
    ];
    assert!(meets(&[0, 1, 2], &[2, 1, 0], &pos));
    assert!(!meets(&[0, 1, 3], &[3, 1, 0], &pos), "collinear duplicates");
    assert!(
        !meets(&[0, 1, 1], &[1, 0, 2], &pos),
        "a segment on the shared edge"
    );
    // The same position under another index is not shared: meeting there counts.
    let pos = vec![
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [1.0, 0.0, 0.0],
        [1.0, -1.0, 1.0],
    ];
    assert!(meets(&[0, 1, 2], &[0, 3, 4], &pos));
    // Collinear shared edges: quads (0, 1, 2, 3) and (2, 1, 0, 4) with 1 on 0-2 share
    // the edges {0, 1} and {1, 2}; their union covers the segment 0-2 where they meet.
    let pos = vec![
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [2.0, 0.0, 0.0],
        [1.0, 1.0, 0.0],
        [1.0, -1.0, 0.0],
    ];
    assert!(!meets(&[0, 1, 2, 3], &[2, 1, 0, 4], &pos));
    assert!(meets(&[0, 1, 2, 3], &[2, 1, 0, 3], &pos), "same side");
}

/// Wavy cloth, `n` x `n` cells: vertex positions and polygons (two triangles or one
/// quad per cell).
fn cloth(n: usize, quads: bool) -> (Vec<P3>, Vec<Vec<u32>>) {
    let id = |i: usize, j: usize| (j * (n + 1) + i) as u32;
    let mut pos = Vec::new();
    for j in 0..=n {
        for i in 0..=n {
            let (x, y) = (i as f64 * 0.01, j as f64 * 0.01);
            let z = 0.02 * (x * 9.0).sin() * (y * 7.0).cos();
            pos.push([x, y, z].map(|c| c as f32 as f64));
        }
    }
    let mut polys = Vec::new();
    for j in 0..n {
        for i in 0..n {
            let (a, b, c, d) = (id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
            if quads {
                polys.push(vec![a, b, c, d]);
            } else {
                polys.push(vec![a, b, c]);
                polys.push(vec![a, c, d]);
            }
        }
    }
    (pos, polys)
}

/// ns per call on the adjacent pairs of a wavy cloth (none meets). Not a test of
/// speed: run with `--ignored --nocapture` and read.
#[test]
#[ignore]
fn cloth_pair_timing() {
    for quads in [false, true] {
        let (pos, polys) = cloth(60, quads);
        let prepared: Vec<(Vec<u32>, [[P3; 3]; 2], usize)> = polys
            .iter()
            .map(|p| {
                let v: Vec<P3> = p.iter().map(|&i| pos[i as usize]).collect();
                let (t, n) = Case::tris(&v);
                (p.clone(), t, n)
            })
            .collect();
        let mut by_edge = Vec::new();
        let mut by_vertex = Vec::new();
        for x in 0..polys.len() {
            // Neighbours are at most two rows of cells apart in this order.
            for y in x + 1..polys.len().min(x + 2 * 60 + 4) {
                let shared = polys[x].iter().filter(|i| polys[y].contains(i)).count();
                match shared {
                    0 => {}
                    1 => by_vertex.push((x, y)),
                    _ => by_edge.push((x, y)),
                }
            }
        }
        for (name, pairs) in [("an edge", &by_edge), ("a vertex only", &by_vertex)] {
            let run = || {
                pairs
                    .iter()
                    .filter(|&&(x, y)| {
                        let (a, b) = (&prepared[x], &prepared[y]);
                        adjacent_polygons_meet(&a.0, &a.1, a.2, &b.0, &b.1, b.2)
                    })
                    .count()
            };
            assert_eq!(run(), 0, "a wavy cloth does not fold onto itself");
            // The fastest of many passes: the machine may be shared, and a pass that
            // was not interrupted is the measure of the code.
            let t0 = std::time::Instant::now();
            let mut best = f64::INFINITY;
            while t0.elapsed().as_secs_f64() < 1.0 {
                let t = std::time::Instant::now();
                std::hint::black_box(run());
                best = best.min(t.elapsed().as_secs_f64());
            }
            let ns = best * 1e9 / pairs.len() as f64;
            let kind = if quads { "quads" } else { "triangles" };
            println!(
                "{kind} sharing {name}: {} pairs, {ns:.1} ns per call",
                pairs.len()
            );
        }
    }
}

#[test]
fn sharing_is_by_index() {
    assert!(shares_vertex(&[0, 1, 2], &[2, 3, 4]));
    assert!(!shares_vertex(&[0, 1, 2], &[3, 4, 5, 6]));
}

/// Through a real mesh: its polygons index per-leaf slots, so adjacency must go by the
/// caller's vertex indices (`slot_vertices`). A flat sheet has no meeting neighbours;
/// folding one corner onto the next triangle makes that pair meet.
#[test]
fn through_a_mesh() {
    use crate::mesh::{Mesh, Positions};
    let n = 6usize;
    let mut pos: Vec<[f32; 3]> = Vec::new();
    for j in 0..=n {
        for i in 0..=n {
            pos.push([i as f32, j as f32, 0.0]);
        }
    }
    let id = |i: usize, j: usize| (j * (n + 1) + i) as u32;
    let mut idx = Vec::new();
    for j in 0..n {
        for i in 0..n {
            idx.extend([id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
            idx.extend([id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
        }
    }
    let reported = |pos: &[[f32; 3]]| {
        let mesh = Mesh::new(Positions::from_points(pos), &idx, 3, 4).expect("valid mesh");
        assert!(
            mesh.leaf_count() > 1,
            "vertices are split over several leaves"
        );
        let verts = |p: usize| -> Vec<u32> {
            mesh.poly(p)
                .iter()
                .map(|&s| mesh.slot_vertices()[s as usize])
                .collect()
        };
        let mut out = Vec::new();
        let mut tris = [[[0.0; 3]; 3]; 2];
        let mut uris = [[[0.0; 3]; 3]; 2];
        for x in 0..mesh.polygon_count() {
            for y in x + 1..mesh.polygon_count() {
                let (vx, vy) = (verts(x), verts(y));
                if !shares_vertex(&vx, &vy) {
                    continue;
                }
                let nx = mesh.triangles(x, &mut tris);
                let ny = mesh.triangles(y, &mut uris);
                if adjacent_polygons_meet(&vx, &tris, nx, &vy, &uris, ny) {
                    let (a, b) = (mesh.polygon_ids()[x], mesh.polygon_ids()[y]);
                    out.push((a.min(b), a.max(b)));
                }
            }
        }
        out.sort_unstable();
        out
    };
    assert_eq!(reported(&pos), vec![]);
    // Fold the far corner of the last cell's first triangle flat onto its second.
    let last = id(n, n - 1) as usize;
    pos[last] = [n as f32 - 0.8, n as f32 - 0.1, 0.0];
    let r = reported(&pos);
    let (t0, t1) = ((2 * n * n - 2) as u32, (2 * n * n - 1) as u32);
    assert!(r.contains(&(t0, t1)), "{r:?}");
}
