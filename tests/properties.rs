//! Issue 6, part 2: properties of the answer, on random small scenes (proptest).
//!
//! Coordinates are multiples of 1/4 in [-1.5, 1.5], so random polygons often touch,
//! share vertices, lie in one plane or collapse to segments and points: the degenerate
//! situations are the common case here. Every transformation used is exact in f32
//! (translations by multiples of 1/4 below 2^12, permutations and reflections of the axes),
//! so with epsilon = 0 the answer must not change at all; it is also checked against the
//! oracle. With epsilon > 0 each answer must hold the exact pairs and only extras within
//! epsilon/2 (see tests/hard_cases.rs for the slack), and translation must not change it
//! either (the CPU backend works in each reference polygon's own frame).
//!
//! Runs on every backend of `common::backends::factories()`. Case counts are kept small
//! (`CASES`) so the file runs in a few seconds in release; raise PROPTEST_CASES to search
//! longer.

mod common;

use common::backends::{factories, Factory, Hit};
use common::{brute_force_exact, polygon_distance, TestMesh};
use proptest::prelude::*;

const CASES: u32 = 48;

fn config() -> ProptestConfig {
    ProptestConfig {
        cases: std::env::var("PROPTEST_CASES")
            .ok()
            .and_then(|v| v.parse().ok())
            .unwrap_or(CASES),
        failure_persistence: None,
        ..ProptestConfig::default()
    }
}

fn coord() -> impl Strategy<Value = f32> {
    (-6i8..=6).prop_map(|i| f32::from(i) * 0.25)
}

fn mesh() -> impl Strategy<Value = TestMesh> {
    (
        prop_oneof![Just(3usize), Just(4usize)],
        3usize..9,
        1usize..7,
    )
        .prop_flat_map(|(k, nv, np)| {
            (
                proptest::collection::vec([coord(), coord(), coord()], nv),
                proptest::collection::vec(0..nv as u32, np * k),
            )
                .prop_map(move |(pos, idx)| TestMesh { pos, idx, k })
        })
}

fn scene_meshes() -> impl Strategy<Value = Vec<TestMesh>> {
    proptest::collection::vec(mesh(), 2..4)
}

/// Every mesh's contacts, with every mesh as the reference in turn.
fn answers(f: &Factory, epsilon: f32, ms: &[TestMesh], leaf: u32) -> Vec<Vec<Hit>> {
    let mut s = (f.make)(epsilon, leaf);
    let ids: Vec<u32> = ms.iter().map(|m| s.add(m)).collect();
    ids.iter().map(|&id| renumber(&ids, s.query(id))).collect()
}

/// Mesh ids are unique in the process, so two scenes give their meshes different ids:
/// name each other mesh by its creation order instead (1, 2, ...), as the oracle does.
fn renumber(ids: &[u32], hits: Vec<Hit>) -> Vec<Hit> {
    hits.into_iter()
        .map(|(o, a, b)| {
            (
                ids.iter()
                    .position(|&i| i == o)
                    .expect("contact with an unknown mesh") as u32
                    + 1,
                a,
                b,
            )
        })
        .collect()
}

/// The oracle's answer in the same form (ids are 1, 2, ... in creation order).
fn oracle_answers(ms: &[TestMesh]) -> Vec<Vec<Hit>> {
    (0..ms.len())
        .map(|i| {
            let mut v: Vec<Hit> = Vec::new();
            for j in 0..ms.len() {
                if i != j {
                    v.extend(
                        brute_force_exact(&ms[i], &ms[j])
                            .into_iter()
                            .map(|(a, b)| (j as u32 + 1, a, b)),
                    );
                }
            }
            v.sort_unstable();
            v
        })
        .collect()
}

fn map_points(ms: &[TestMesh], f: impl Fn([f32; 3]) -> [f32; 3]) -> Vec<TestMesh> {
    ms.iter()
        .map(|m| TestMesh {
            pos: m.pos.iter().map(|&p| f(p)).collect(),
            ..m.clone()
        })
        .collect()
}

/// Checks the band property of an epsilon > 0 answer against the exact one.
fn check_band(ms: &[TestMesh], exact: &[Vec<Hit>], got: &[Vec<Hit>], e: f32) {
    let h = f64::from(e) / 2.0;
    for (i, (ex, g)) in exact.iter().zip(got).enumerate() {
        for p in ex {
            assert!(
                g.binary_search(p).is_ok(),
                "mesh {}: {p:?} missed at epsilon {e}",
                i + 1
            );
        }
        for &(o, a, b) in g {
            if ex.binary_search(&(o, a, b)).is_ok() {
                continue;
            }
            let (r, om) = (&ms[i], &ms[o as usize - 1]);
            let d = polygon_distance(r, a as usize, om, b as usize);
            assert!(
                d <= h + 1e-9 * (h + 4.0) + 1e-12,
                "mesh {}: extra ({o}, {a}, {b}) at distance {d} > epsilon/2 = {h}",
                i + 1
            );
        }
    }
}

fn exact_factories() -> Vec<Factory> {
    factories().into_iter().filter(|f| f.exact).collect()
}

proptest! {
    #![proptest_config(config())]

    #[test]
    fn exact_answer_is_the_oracles(ms in scene_meshes(), leaf in 1u32..4) {
        let want = oracle_answers(&ms);
        for f in exact_factories() {
            prop_assert_eq!(&answers(&f, 0.0, &ms, leaf), &want, "{}", f.name);
        }
    }

    #[test]
    fn translation_changes_nothing(
        ms in scene_meshes(),
        t in [-16384i32..16384, -16384i32..16384, -16384i32..16384],
        e in prop_oneof![Just(0.0f32), Just(0.25f32), Just(1e-3f32)],
    ) {
        let d = t.map(|v| v as f32 * 0.25);
        let moved = map_points(&ms, |p| [p[0] + d[0], p[1] + d[1], p[2] + d[2]]);
        for f in factories().into_iter().filter(|f| f.exact || e > 0.0) {
            prop_assert_eq!(answers(&f, e, &ms, 1), answers(&f, e, &moved, 1), "{} by {:?}", f.name, d);
        }
    }

    #[test]
    fn axis_permutations_and_reflections_change_nothing(
        ms in scene_meshes(),
        perm in 0usize..6,
        flip in [any::<bool>(), any::<bool>(), any::<bool>()],
    ) {
        const P: [[usize; 3]; 6] = [[0, 1, 2], [0, 2, 1], [1, 0, 2], [1, 2, 0], [2, 0, 1], [2, 1, 0]];
        let ax = P[perm];
        let moved = map_points(&ms, |p| {
            [0, 1, 2].map(|k| if flip[k] { -p[ax[k]] } else { p[ax[k]] })
        });
        for f in exact_factories() {
            prop_assert_eq!(answers(&f, 0.0, &ms, 2), answers(&f, 0.0, &moved, 2), "{}", f.name);
        }
        // With epsilon > 0 the answer may differ only within the band, both ways.
        for f in factories() {
            let exact = oracle_answers(&ms);
            check_band(&moved, &exact, &answers(&f, 0.25, &moved, 2), 0.25);
        }
    }

    #[test]
    fn vertex_order_reversal_changes_nothing(ms in scene_meshes()) {
        // (v0, v1, .., vk) -> (v0, vk, .., v1): the same triangles (v0, v1, v2), (v0, v2, v3)
        // with the other winding.
        let rev: Vec<TestMesh> = ms
            .iter()
            .map(|m| TestMesh {
                idx: m
                    .idx
                    .chunks(m.k)
                    .flat_map(|p| std::iter::once(p[0]).chain(p[1..].iter().rev().copied()))
                    .collect(),
                ..m.clone()
            })
            .collect();
        for f in exact_factories() {
            prop_assert_eq!(answers(&f, 0.0, &ms, 2), answers(&f, 0.0, &rev, 2), "{}", f.name);
        }
        for f in factories() {
            check_band(&rev, &oracle_answers(&ms), &answers(&f, 1e-3, &rev, 2), 1e-3);
        }
    }

    #[test]
    fn polygon_reordering_renumbers_only(ms in scene_meshes(), seed in any::<u64>()) {
        // new_of[m][old polygon] = new polygon.
        let mut rng = common::Rng(seed | 1);
        let mut new_of = Vec::new();
        let shuffled: Vec<TestMesh> = ms
            .iter()
            .map(|m| {
                let n = m.polygons();
                let mut order: Vec<usize> = (0..n).collect();
                for i in (1..n).rev() {
                    order.swap(i, (rng.next_u64() % (i as u64 + 1)) as usize);
                }
                let mut inv = vec![0u32; n];
                for (new, &old) in order.iter().enumerate() {
                    inv[old] = new as u32;
                }
                new_of.push(inv);
                TestMesh {
                    idx: order.iter().flat_map(|&p| m.idx[p * m.k..(p + 1) * m.k].to_vec()).collect(),
                    ..m.clone()
                }
            })
            .collect();
        for f in exact_factories() {
            let before = answers(&f, 0.0, &ms, 1);
            let after = answers(&f, 0.0, &shuffled, 1);
            for (i, (b, a)) in before.iter().zip(&after).enumerate() {
                let mut mapped: Vec<Hit> = b
                    .iter()
                    .map(|&(o, r, p)| (o, new_of[i][r as usize], new_of[o as usize - 1][p as usize]))
                    .collect();
                mapped.sort_unstable();
                prop_assert_eq!(&mapped, a, "{}: mesh {}", f.name, i + 1);
            }
        }
    }

    #[test]
    fn swapping_reference_and_other_mirrors_the_pairs(ms in scene_meshes()) {
        for f in exact_factories() {
            let all = answers(&f, 0.0, &ms, 2);
            for i in 0..ms.len() {
                for j in 0..ms.len() {
                    if i == j {
                        continue;
                    }
                    let fwd: Vec<(u32, u32)> = all[i]
                        .iter()
                        .filter(|h| h.0 == j as u32 + 1)
                        .map(|h| (h.1, h.2))
                        .collect();
                    let mut back: Vec<(u32, u32)> = all[j]
                        .iter()
                        .filter(|h| h.0 == i as u32 + 1)
                        .map(|h| (h.2, h.1))
                        .collect();
                    back.sort_unstable();
                    prop_assert_eq!(fwd, back, "{}: meshes {} and {}", f.name, i + 1, j + 1);
                }
            }
        }
    }

    #[test]
    fn a_refit_equals_a_fresh_mesh(
        ms in scene_meshes(),
        moves in proptest::collection::vec([coord(), coord(), coord()], 0..40),
        first in 0usize..8,
        e in prop_oneof![Just(0.0f32), Just(0.25f32)],
        leaf in 1u32..4,
    ) {
        // New positions for every mesh: drawn from `moves` (cycled), all or a range of them.
        let mut next = ms.clone();
        let mut c = 0;
        for m in next.iter_mut() {
            for p in m.pos.iter_mut() {
                if !moves.is_empty() {
                    *p = moves[c % moves.len()];
                    c += 1;
                }
            }
        }
        for f in factories().into_iter().filter(|f| f.exact || e > 0.0) {
            let mut s = (f.make)(e, leaf);
            let ids: Vec<u32> = ms.iter().map(|m| s.add(m)).collect();
            let _ = ids.iter().map(|&id| s.query(id)).count();
            for (i, &id) in ids.iter().enumerate() {
                let n = ms[i].pos.len();
                let a = first.min(n - 1);
                if i % 2 == 0 {
                    s.update(id, 0, &next[i].pos);
                } else {
                    // Two range updates that together cover every vertex.
                    s.update(id, a, &next[i].pos[a..]);
                    if a > 0 {
                        s.update(id, 0, &next[i].pos[..a]);
                    }
                }
            }
            let refit: Vec<Vec<Hit>> = ids.iter().map(|&id| renumber(&ids, s.query(id))).collect();
            prop_assert_eq!(&refit, &answers(&f, e, &next, leaf), "{}", f.name);
            if e == 0.0 {
                prop_assert_eq!(&refit, &oracle_answers(&next), "{}", f.name);
            }
        }
    }

    #[test]
    fn epsilon_answers_stay_in_the_band(
        ms in scene_meshes(),
        e in prop_oneof![Just(1e-3f32), Just(0.1f32), Just(0.3f32), Just(1.0f32)],
    ) {
        let exact = oracle_answers(&ms);
        for f in factories() {
            check_band(&ms, &exact, &answers(&f, e, &ms, 2), e);
        }
    }
}
