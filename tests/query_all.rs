//! Whole-scene queries (`Scene::query_all`): every mesh pair and self-collision, against
//! brute force with the independent exact oracle (non-adjacent pairs) and the exact
//! adjacency predicate (pairs sharing a vertex; it is checked against exact rational
//! arithmetic in its own unit tests), on real simulation frames (../shared/meshes/sim, where it is
//! present) and generated scenes; the same answer for every thread count and creation order; filters.

mod common;
use common::*;
use glcollide::internals::adjacent::adjacent_polygons_meet;
use glcollide::{MeshId, Pair, Positions, Scene, SceneConfig};

fn scene(epsilon: f32, threads: u32) -> Scene {
    Scene::new(SceneConfig {
        epsilon,
        threads,
        ..SceneConfig::default()
    })
    .unwrap()
}

/// Polygon pairs (i < j) of one mesh that meet by the rule of docs/API.md, brute force: pairs
/// sharing a vertex index by the exact adjacency predicate, the others by the oracle (at
/// `band > 0`, within `band` of each other by the f64 distance).
fn brute_self(m: &TestMesh, band: f64) -> Vec<(u32, u32)> {
    let boxes: Vec<_> = (0..m.polygons()).map(|i| m.poly_box(i)).collect();
    let mut order: Vec<usize> = (0..boxes.len()).collect();
    order.sort_by(|&a, &b| boxes[a].0[0].total_cmp(&boxes[b].0[0]));
    let idx = |i: usize| &m.idx[i * m.k..(i + 1) * m.k];
    let tris2 = |i: usize| {
        let t = m.tris(i);
        let mut a = [[[0.0; 3]; 3]; 2];
        a[..t.len()].copy_from_slice(&t);
        (a, t.len())
    };
    let mut out = Vec::new();
    for (oi, &i) in order.iter().enumerate() {
        let (lo, hi) = boxes[i];
        for &j in &order[oi + 1..] {
            let (olo, ohi) = boxes[j];
            if f64::from(olo[0]) > f64::from(hi[0]) + band {
                break;
            }
            let overlap = (0..3).all(|k| {
                f64::from(olo[k]) <= f64::from(hi[k]) + band
                    && f64::from(lo[k]) <= f64::from(ohi[k]) + band
            });
            if !overlap {
                continue;
            }
            let adjacent = idx(i).iter().any(|v| idx(j).contains(v));
            let meets = if adjacent {
                let ((ti, ni), (tj, nj)) = (tris2(i), tris2(j));
                adjacent_polygons_meet(idx(i), &ti, ni, idx(j), &tj, nj)
            } else if band == 0.0 {
                m.tris(i)
                    .iter()
                    .any(|t| m.tris(j).iter().any(|u| oracle::triangles_meet(t, u)))
            } else {
                m.tris(i).iter().any(|t| {
                    m.tris(j)
                        .iter()
                        .any(|u| oracle::triangle_distance(t, u) <= band)
                })
            };
            if meets {
                out.push((i.min(j) as u32, i.max(j) as u32));
            }
        }
    }
    out.sort_unstable();
    out
}

/// The pairs of meshes `a` and `b` (positions in `ids`), as (polygon of a, polygon of b).
fn between(pairs: &[Pair], a: MeshId, b: MeshId) -> Vec<(u32, u32)> {
    pairs
        .iter()
        .filter(|p| p.mesh_a == a && p.mesh_b == b)
        .map(|p| (p.polygon_a, p.polygon_b))
        .collect()
}

fn check_sorted_unique(pairs: &[Pair]) {
    assert!(pairs.windows(2).all(|w| w[0] < w[1]), "not sorted/unique");
    assert!(pairs
        .iter()
        .all(|p| (p.mesh_a, p.polygon_a) < (p.mesh_b, p.polygon_b)));
}

#[test]
fn cloth_funnel_self_and_pairs_exact_and_within_a_band() {
    if !has_shared("meshes/sim/cloth-funnel") {
        return;
    }
    let parts: Vec<TestMesh> = (0..4).map(|p| sim_part("cloth-funnel", 227, p)).collect();
    let all: Vec<[f32; 3]> = parts.iter().flat_map(|m| m.pos.iter().copied()).collect();
    let (lo, hi) = bounds(&all);
    let extent = (0..3).map(|k| hi[k] - lo[k]).fold(0.0, f32::max);
    let cloth = (0..4).max_by_key(|&p| parts[p].polygons()).unwrap();
    for eps in [0.0, 1e-3 * extent] {
        let mut s = scene(eps, 0);
        let ids: Vec<MeshId> = parts.iter().map(|m| add(&mut s, m)).collect();
        s.set_self_collision(ids[cloth], true).unwrap();
        let pairs = s.query_all().unwrap().to_vec();
        check_sorted_unique(&pairs);
        let band = f64::from(eps) / 2.0 * (1.0 + 1e-9);
        // Self pairs of the cloth.
        let got = between(&pairs, ids[cloth], ids[cloth]);
        let exact = brute_self(&parts[cloth], 0.0);
        if eps == 0.0 {
            assert_eq!(got, exact, "cloth self pairs, exact");
        } else {
            let within = brute_self(&parts[cloth], band);
            assert!(
                got.len() > exact.len(),
                "{} self pairs in the band",
                got.len()
            );
            assert!(exact.iter().all(|p| got.binary_search(p).is_ok()), "missed");
            assert!(
                got.iter().all(|p| within.binary_search(p).is_ok()),
                "outside the band"
            );
        }
        // Every mesh pair.
        for a in 0..4 {
            for b in a + 1..4 {
                let got = between(&pairs, ids[a], ids[b]);
                let want = brute_force_exact(&parts[a], &parts[b]);
                if eps == 0.0 {
                    assert_eq!(got, want, "parts {a}, {b}");
                } else {
                    let within = brute_force_within(&parts[a], &parts[b], band);
                    assert!(want.iter().all(|p| got.binary_search(p).is_ok()));
                    assert!(got.iter().all(|p| within.binary_search(p).is_ok()));
                }
            }
        }
        // No self pairs for the meshes whose self-collision is off.
        for (i, &id) in ids.iter().enumerate() {
            if i != cloth {
                assert!(between(&pairs, id, id).is_empty());
            }
        }
    }
}

/// The pairs with mesh ids replaced by the meshes' positions in creation order.
fn by_position(pairs: &[Pair], ids: &[MeshId]) -> Vec<(usize, u32, usize, u32)> {
    let at = |id: MeshId| ids.iter().position(|&i| i == id).unwrap();
    let mut v: Vec<_> = pairs
        .iter()
        .map(|p| {
            let (a, b) = ((at(p.mesh_a), p.polygon_a), (at(p.mesh_b), p.polygon_b));
            let (a, b) = if a <= b { (a, b) } else { (b, a) };
            (a.0, a.1, b.0, b.1)
        })
        .collect();
    v.sort_unstable();
    v
}

#[test]
fn same_answer_for_every_thread_count_and_creation_order() {
    if !has_shared("meshes/sim/armadillo-rollers") {
        return;
    }
    let parts: Vec<TestMesh> = (0..7)
        .map(|p| sim_part("armadillo-rollers", 326, p))
        .collect();
    let all: Vec<[f32; 3]> = parts.iter().flat_map(|m| m.pos.iter().copied()).collect();
    let (lo, hi) = bounds(&all);
    let extent = (0..3).map(|k| hi[k] - lo[k]).fold(0.0, f32::max);
    for eps in [0.0, 1e-3 * extent] {
        let mut answers = Vec::new();
        for threads in [1, 2, 3] {
            for reversed in [false, true] {
                let mut s = scene(eps, threads);
                let order: Vec<usize> = if reversed {
                    (0..7).rev().collect()
                } else {
                    (0..7).collect()
                };
                let mut ids = vec![0; 7];
                for &p in &order {
                    ids[p] = add(&mut s, &parts[p]);
                }
                for &id in &ids {
                    s.set_self_collision(id, true).unwrap();
                }
                let pairs = s.query_all().unwrap().to_vec();
                check_sorted_unique(&pairs);
                answers.push(by_position(&pairs, &ids));
                // A second query with nothing changed gives the same answer.
                assert_eq!(s.query_all().unwrap(), &pairs[..]);
            }
        }
        assert!(!answers[0].is_empty() || eps == 0.0);
        for a in &answers[1..] {
            assert_eq!(a, &answers[0], "eps {eps}");
        }
    }
}

#[test]
fn filters_skip_mesh_pairs_in_both_queries() {
    let organ = TestMesh::from_obj(&shared_mesh("gallbladder_glt"));
    let blade = TestMesh::from_obj(&shared_mesh("scissors_blade"));
    let (lo, hi) = bounds(&organ.pos);
    let e = (0..3).map(|k| hi[k] - lo[k]).fold(0.0, f32::max);
    let far =
        organ.pos.iter().copied().fold(
            [f32::NEG_INFINITY; 3],
            |a, p| if p[0] > a[0] { p } else { a },
        );
    let ins = place_scaled(
        &blade.pos,
        [far[0] - 0.01 * e, far[1], far[2]],
        1.3,
        0.15 * e / {
            let (l, h) = bounds(&blade.pos);
            (0..3).map(|k| h[k] - l[k]).fold(0.0, f32::max)
        },
    );
    let mut s = scene(0.0, 1);
    let o = add(&mut s, &organ);
    let b = s
        .create_mesh(Positions::from_points(&ins), &blade.idx, blade.k)
        .unwrap();
    let before = s.query_all().unwrap().to_vec();
    assert!(!before.is_empty());
    assert_eq!(s.query(b).unwrap().len(), before.len());
    // The blade's group is not in the organ's mask: nothing, in either query.
    s.set_filter(b, 2, u32::MAX).unwrap();
    s.set_filter(o, 1, 1).unwrap();
    assert!(s.query_all().unwrap().is_empty());
    assert!(s.query(b).unwrap().is_empty());
    assert!(s.query(o).unwrap().is_empty());
    // Back in the mask: the same answer as before.
    s.set_filter(o, 1, 3).unwrap();
    assert_eq!(s.query_all().unwrap(), &before[..]);
    // A folded quad grid colliding with itself: quads are single polygons.
    let n = 12;
    let mut grid = TestMesh {
        pos: Vec::new(),
        idx: Vec::new(),
        k: 4,
    };
    for j in 0..=n {
        for i in 0..=n {
            // Folded in half along x = n/2: the second half waves through the first.
            let x = i as f32;
            let (x, z) = if x <= n as f32 / 2.0 {
                (x, 0.0)
            } else {
                (n as f32 - x, 1e-3 * (0.9 * j as f32 + 0.7 * x).sin())
            };
            grid.pos.push([x, j as f32, z]);
        }
    }
    for j in 0..n as u32 {
        for i in 0..n as u32 {
            let v = j * (n as u32 + 1) + i;
            grid.idx
                .extend([v, v + 1, v + n as u32 + 2, v + n as u32 + 1]);
        }
    }
    let mut s = scene(0.0, 2);
    let g = add(&mut s, &grid);
    s.set_self_collision(g, true).unwrap();
    let got = between(s.query_all().unwrap(), g, g);
    let exact = brute_self(&grid, 0.0);
    assert_eq!(got, exact);
    assert!(!got.is_empty());
    // Within a band (quads go to the scalar test, their volumes made on demand): a
    // superset of the exact pairs, each within the band.
    let eps = 4e-3f32;
    let mut s = scene(eps, 2);
    let g = add(&mut s, &grid);
    s.set_self_collision(g, true).unwrap();
    let got = between(s.query_all().unwrap(), g, g);
    let within = brute_self(&grid, f64::from(eps) / 2.0 * (1.0 + 1e-9));
    assert!(got.len() > exact.len(), "{} pairs in the band", got.len());
    assert!(exact.iter().all(|p| got.binary_search(p).is_ok()));
    assert!(got.iter().all(|p| within.binary_search(p).is_ok()));
}

/// The real cloth tangled: every vertex of the cloth-funnel cloth moved by a pseudo-random
/// step of up to 0.6 of its mean edge length (folds onto neighbours, vertices pushed
/// through the next triangle, crossings between neighbours on real connectivity): self
/// pairs equal to brute force at epsilon 0 (thousands, hundreds of them between
/// neighbours), within the band above it, the same for one and two threads, and the same
/// with every other triangle turned over (no consistent orientation: no certificate).
#[test]
fn tangled_real_cloth_self_pairs_against_brute_force() {
    if !has_shared("meshes/sim/cloth-funnel") {
        return;
    }
    let mut cloth = (0..4)
        .map(|p| sim_part("cloth-funnel", 227, p))
        .max_by_key(|m| m.polygons())
        .unwrap();
    let mut sum = 0.0f64;
    for t in cloth.idx.chunks(3) {
        for k in 0..3 {
            let (a, b) = (cloth.pos[t[k] as usize], cloth.pos[t[(k + 1) % 3] as usize]);
            sum += (0..3)
                .map(|c| f64::from(a[c] - b[c]).powi(2))
                .sum::<f64>()
                .sqrt();
        }
    }
    let step = 0.6 * sum / cloth.idx.len() as f64;
    let mut seed = 0x9E37_79B9_7F4A_7C15u64;
    for p in &mut cloth.pos {
        for x in p.iter_mut() {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            let r = (seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5;
            *x = (f64::from(*x) + step * 2.0 * r) as f32;
        }
    }
    let (lo, hi) = bounds(&cloth.pos);
    let extent = (0..3).map(|k| hi[k] - lo[k]).fold(0.0, f32::max);
    let exact = brute_self(&cloth, 0.0);
    let neighbours = exact
        .iter()
        .filter(|&&(a, b)| {
            let (a, b) = (a as usize, b as usize);
            cloth.idx[3 * a..3 * a + 3]
                .iter()
                .any(|v| cloth.idx[3 * b..3 * b + 3].contains(v))
        })
        .count();
    assert!(
        exact.len() > 1000 && neighbours > 100,
        "{} pairs, {neighbours} between neighbours",
        exact.len()
    );
    // The same cloth with every other triangle turned over: the same geometry, but its
    // edges no longer consistently oriented (no twins), so no vertex fan or patch is
    // proven and every pair sharing a vertex is listed from the topology and tested.
    let mut flipped = cloth.clone();
    for t in flipped.idx.chunks_mut(6) {
        t.swap(1, 2);
    }
    for eps in [0.0, 1e-3 * extent] {
        let mut answers = Vec::new();
        for (threads, m) in [(1, &cloth), (2, &cloth), (1, &flipped), (2, &flipped)] {
            let mut s = scene(eps, threads);
            let id = add(&mut s, m);
            s.set_self_collision(id, true).unwrap();
            answers.push(between(s.query_all().unwrap(), id, id));
            let st = s.all_stats();
            let certified = st.self_cert_fans + st.self_cert_patches;
            assert_eq!(certified == 0, std::ptr::eq(m, &flipped), "{st:?}");
        }
        assert_eq!(answers[0], answers[1], "threads 1 and 2");
        assert_eq!(answers[0], answers[2], "every other triangle turned over");
        assert_eq!(answers[0], answers[3], "turned over, two threads");
        let got = &answers[0];
        if eps == 0.0 {
            assert_eq!(got, &exact);
        } else {
            let within = brute_self(&cloth, f64::from(eps) / 2.0 * (1.0 + 1e-9));
            assert!(got.len() > exact.len());
            assert!(exact.iter().all(|p| got.binary_search(p).is_ok()), "missed");
            assert!(
                got.iter().all(|p| within.binary_search(p).is_ok()),
                "outside the band"
            );
        }
    }
}

/// The self-collision layout (pieces, sub-leaf split, boundary loops) is made at a mesh's
/// first query and kept: the certificates' exact tests must follow the positions of every
/// later query. Real cloth -> tangled -> real -> tangled in one scene, each answer against
/// brute force, threads 1 and 2.
#[test]
fn kept_layout_follows_the_mesh_between_queries() {
    if !has_shared("meshes/sim/cloth-funnel") {
        return;
    }
    let real = (0..4)
        .map(|p| sim_part("cloth-funnel", 227, p))
        .max_by_key(|m| m.polygons())
        .unwrap();
    let mut tangled = real.clone();
    let mut seed = 0x2545_F491_4F6C_DD1Du64;
    for p in &mut tangled.pos {
        for x in p.iter_mut() {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            let r = (seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5;
            *x = (f64::from(*x) + 0.02 * r) as f32;
        }
    }
    let (want_real, want_tangled) = (brute_self(&real, 0.0), brute_self(&tangled, 0.0));
    assert!(want_tangled.len() > 100, "{} pairs", want_tangled.len());
    for threads in [1, 2] {
        let mut s = scene(0.0, threads);
        let id = add(&mut s, &real);
        s.set_self_collision(id, true).unwrap();
        for (round, (m, want)) in [(&real, &want_real), (&tangled, &want_tangled)]
            .into_iter()
            .cycle()
            .take(4)
            .enumerate()
        {
            s.update_positions(id, 0, Positions::from_points(&m.pos))
                .unwrap();
            let got = between(s.query_all().unwrap(), id, id);
            assert_eq!(&got, want, "threads {threads}, round {round}");
        }
    }
}
