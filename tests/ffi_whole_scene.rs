//! Whole scenes through the C API only: `glcol_query_all` (the union of the per-mesh
//! queries), self-collision and the adjacency rule, filters, threads, contact geometry
//! (`glcol_query_geometry`: its meaning, and when it refuses) and rigid placement
//! (`glcol_mesh_set_transform`).

#![allow(clippy::missing_safety_doc)]

mod common;

use std::ptr::null_mut;

use common::backends::{last_error, ok, FfiScene, TestScene};
use common::{has_shared, sim_part, square, wall, TestMesh};
use glcollide::ffi::*;
use GlcolStatus as S;

type P = (u32, u32, u32, u32);

fn scene_with(epsilon: f32, threads: u32) -> FfiScene {
    let mut d = unsafe { std::mem::zeroed::<GlcolSceneDesc>() };
    unsafe { glcol_scene_desc_init_sized(&mut d, std::mem::size_of::<GlcolSceneDesc>()) };
    d.backend = GlcolBackend::Cpu as u32;
    d.epsilon = epsilon;
    d.threads = threads;
    let mut s = null_mut();
    ok(
        unsafe { glcol_scene_create(&d, &mut s) },
        "glcol_scene_create",
    );
    FfiScene(s)
}

fn try_all(s: &FfiScene) -> (GlcolStatus, Vec<P>) {
    let mut p: *const GlcolPair = std::ptr::null();
    let mut n = usize::MAX;
    let st = unsafe { glcol_query_all(s.0, &mut p, &mut n) };
    if st != S::Ok {
        return (st, Vec::new());
    }
    if n == 0 {
        assert!(p.is_null());
        return (st, Vec::new());
    }
    let v = unsafe { std::slice::from_raw_parts(p, n) };
    (
        st,
        v.iter()
            .map(|q| (q.mesh_a, q.polygon_a, q.mesh_b, q.polygon_b))
            .collect(),
    )
}

fn all(s: &FfiScene) -> Vec<P> {
    let (st, v) = try_all(s);
    ok(st, "glcol_query_all");
    v
}

fn try_geometry(s: &FfiScene) -> (GlcolStatus, Vec<GlcolContactGeometry>) {
    let mut p: *const GlcolContactGeometry = std::ptr::null();
    let mut n = usize::MAX;
    let st = unsafe { glcol_query_geometry(s.0, &mut p, &mut n) };
    if st != S::Ok || n == 0 {
        return (st, Vec::new());
    }
    (st, unsafe { std::slice::from_raw_parts(p, n) }.to_vec())
}

fn funnel() -> Vec<TestMesh> {
    (0..4).map(|p| sim_part("cloth-funnel", 227, p)).collect()
}

/// Three teapots overlapping each other (moved by a fraction of their size) and a bunny.
fn overlapping_real_meshes() -> Vec<TestMesh> {
    let t = TestMesh::from_obj(&common::shared_mesh("teapot"));
    let (lo, hi) = common::bounds(&t.pos);
    let size = (0..3).map(|i| hi[i] - lo[i]).fold(0.0f32, f32::max);
    let moved = |d: [f32; 3]| TestMesh {
        pos: t
            .pos
            .iter()
            .map(|p| [p[0] + d[0] * size, p[1] + d[1] * size, p[2] + d[2] * size])
            .collect(),
        idx: t.idx.clone(),
        k: t.k,
    };
    vec![
        moved([0.0, 0.0, 0.0]),
        moved([0.2, 0.05, 0.0]),
        moved([0.1, 0.0, 0.25]),
        moved([3.0, 0.0, 0.0]),
    ]
}

/// query_all equals the union of glcol_query over every mesh (epsilon 0), normalised.
#[test]
fn query_all_is_the_union_of_the_per_mesh_queries() {
    let parts = overlapping_real_meshes();
    let mut s = scene_with(0.0, 0);
    let ids: Vec<u32> = parts.iter().map(|m| s.add(m)).collect();
    let got = all(&s);
    let mut want = Vec::new();
    for &r in &ids {
        for (o, rp, op) in s.query(r) {
            want.push(if r < o {
                (r, rp, o, op)
            } else {
                (o, op, r, rp)
            });
        }
    }
    want.sort_unstable();
    want.dedup();
    assert!(!got.is_empty());
    assert_eq!(got, want);
    // Sorted, each once, a < b.
    assert!(got.windows(2).all(|w| w[0] < w[1]));
    assert!(got.iter().all(|p| (p.0, p.1) < (p.2, p.3)));
}

/// A flat grid folded over itself: self pairs only when self-collision is on, never
/// between adjacent polygons that merely share their edge.
#[test]
fn self_collision_on_a_folded_grid() {
    let n = 8usize;
    let mut pos = Vec::new();
    for j in 0..=n {
        for i in 0..=n {
            // x in 0..n folds back at n/2 onto the lower half, 0.001 apart... then pushed
            // through: the upper half dips below the lower one at its far end.
            let x = i as f32;
            let (px, pz) = if i <= n / 2 {
                (x, 0.0)
            } else {
                let back = x - (n / 2) as f32;
                ((n / 2) as f32 - back, 0.3 - 0.2 * back)
            };
            pos.push([px, j as f32, pz]);
        }
    }
    let id = |i: usize, j: usize| (j * (n + 1) + i) as u32;
    let mut idx = Vec::new();
    for j in 0..n {
        for i in 0..n {
            idx.extend([id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)]);
        }
    }
    let m = TestMesh { pos, idx, k: 4 };
    let mut s = scene_with(0.0, 1);
    let a = s.add(&m);
    assert!(all(&s).is_empty(), "self-collision is off by default");
    ok(
        unsafe { glcol_mesh_set_self_collision(s.0, a, true) },
        "set_self_collision",
    );
    let got = all(&s);
    assert!(!got.is_empty());
    for p in &got {
        assert_eq!((p.0, p.2), (a, a));
        assert!(p.1 < p.3);
        // Quads sharing a vertex that only meet where joined are never reported: the flat
        // half has no pair of its own.
        let flat = |q: u32| (q as usize % n) < n / 2 - 1;
        assert!(!(flat(p.1) && flat(p.3)), "{p:?}");
    }
    ok(
        unsafe { glcol_mesh_set_self_collision(s.0, a, false) },
        "set_self_collision off",
    );
    assert!(all(&s).is_empty());
    assert_eq!(
        unsafe { glcol_mesh_set_self_collision(s.0, 0, true) },
        S::UnknownMesh
    );
    assert_eq!(
        unsafe { glcol_mesh_set_self_collision(null_mut(), a, true) },
        S::NullPointer
    );
}

#[test]
fn filters_choose_the_mesh_pairs() {
    let mut s = scene_with(0.0, 0);
    let a = s.add(&square(0., 0.));
    let b = s.add(&wall(0.5));
    let c = s.add(&wall(0.25));
    let meshes_of = |v: &[P]| {
        let mut m: Vec<(u32, u32)> = v.iter().map(|p| (p.0, p.2)).collect();
        m.sort_unstable();
        m.dedup();
        m
    };
    assert_eq!(meshes_of(&all(&s)), [(a, b), (a, c)]);
    // b in group 2, a accepts only group 1: a-b filtered out, both ways.
    ok(
        unsafe { glcol_mesh_set_filter(s.0, b, 2, u32::MAX) },
        "filter b",
    );
    ok(unsafe { glcol_mesh_set_filter(s.0, a, 1, 1) }, "filter a");
    assert_eq!(meshes_of(&all(&s)), [(a, c)]);
    assert!(s.query(a).iter().all(|h| h.0 == c));
    assert!(s.query(b).is_empty());
    ok(
        unsafe { glcol_mesh_set_filter(s.0, a, 1, u32::MAX) },
        "filter a back",
    );
    assert_eq!(meshes_of(&all(&s)), [(a, b), (a, c)]);
    assert_eq!(
        unsafe { glcol_mesh_set_filter(s.0, 0, 1, 1) },
        S::UnknownMesh
    );
    assert_eq!(
        unsafe { glcol_mesh_set_filter(null_mut(), a, 1, 1) },
        S::NullPointer
    );
}

#[test]
fn one_thread_and_one_per_core_answer_the_same() {
    if !has_shared("meshes/sim/cloth-funnel") {
        return;
    }
    let parts = funnel();
    let mut answers = Vec::new();
    for threads in [1, 0, 3] {
        let mut s = scene_with(0.001, threads);
        let ids: Vec<u32> = parts.iter().map(|m| s.add(m)).collect();
        let cloth = (0..4).max_by_key(|&p| parts[p].polygons()).unwrap();
        ok(
            unsafe { glcol_mesh_set_self_collision(s.0, ids[cloth], true) },
            "self",
        );
        // Ids differ per scene: compare by position in `ids`.
        let at = |m: u32| ids.iter().position(|&i| i == m).unwrap() as u32;
        let v: Vec<P> = all(&s)
            .into_iter()
            .map(|p| (at(p.0), p.1, at(p.2), p.3))
            .collect();
        answers.push(v);
    }
    assert!(!answers[0].is_empty());
    assert_eq!(answers[0], answers[1]);
    assert_eq!(answers[0], answers[2]);
}

/// The checks every geometry answer passes, against the pairs it describes.
fn check_geometry(s: &FfiScene, meshes: &[(u32, &TestMesh)], pairs: &[P]) -> usize {
    use glcollide::internals::tritri::triangles_intersect;
    let (st, g) = try_geometry(s);
    ok(st, "glcol_query_geometry");
    assert_eq!(g.len(), pairs.len());
    let mesh = |id: u32| meshes.iter().find(|m| m.0 == id).unwrap().1;
    let mut checked = 0;
    for (p, g) in pairs.iter().zip(&g) {
        let (ma, mb) = (mesh(p.0), mesh(p.2));
        let (ta, tb) = (ma.tris(p.1 as usize), mb.tris(p.3 as usize));
        let meets = ta
            .iter()
            .any(|t| tb.iter().any(|u| triangles_intersect(t, u)));
        let flagged = g.flags & GLCOL_CONTACT_INTERSECTING != 0;
        assert_eq!(meets, flagged, "{p:?} {g:?}");
        assert_eq!(
            g.flags & !(GLCOL_CONTACT_INTERSECTING | GLCOL_CONTACT_COPLANAR),
            0
        );
        if g.flags & GLCOL_CONTACT_COPLANAR != 0 {
            assert!(flagged);
        }
        let floats = g.point_a.iter().chain(&g.point_b).chain(&g.normal);
        assert!(floats.chain([&g.depth]).all(|x| x.is_finite()), "{g:?}");
        let n: f64 = g
            .normal
            .iter()
            .map(|&x| f64::from(x).powi(2))
            .sum::<f64>()
            .sqrt();
        assert!((n - 1.0).abs() < 1e-6, "|normal| = {n}: {g:?}");
        if flagged {
            assert!(g.depth >= 0.0, "{g:?}");
        } else {
            assert!(g.depth <= 0.0, "{g:?}");
        }
        // Depth 0 (touching): no translation to check.
        if flagged && g.flags & GLCOL_CONTACT_COPLANAR == 0 && g.depth > 0.0 {
            let d = f64::from(g.depth) * (1.0 + 1e-6);
            let t = g.normal.map(|x| f64::from(x) * d);
            let moved: Vec<[[f64; 3]; 3]> = ta
                .iter()
                .map(|tri| tri.map(|v| [v[0] + t[0], v[1] + t[1], v[2] + t[2]]))
                .collect();
            let still = moved
                .iter()
                .any(|t| tb.iter().any(|u| triangles_intersect(t, u)));
            assert!(!still, "{p:?}: moved by depth * normal, still meets: {g:?}");
            checked += 1;
        }
    }
    checked
}

#[test]
fn geometry_of_query_all_and_of_query() {
    if !has_shared("meshes/sim/cloth-funnel") {
        return;
    }
    let parts = funnel();
    let mut s = scene_with(0.001, 0);
    let ids: Vec<u32> = parts.iter().map(|m| s.add(m)).collect();
    let real = overlapping_real_meshes();
    let mut r = scene_with(0.0, 0);
    let rids: Vec<u32> = real.iter().map(|m| r.add(m)).collect();
    let rmeshes: Vec<(u32, &TestMesh)> = rids.iter().copied().zip(real.iter()).collect();
    let rpairs = all(&r);
    assert!(!rpairs.is_empty());
    assert!(
        check_geometry(&r, &rmeshes, &rpairs) > 0,
        "no penetrating pair checked"
    );
    let cloth = (0..4).max_by_key(|&p| parts[p].polygons()).unwrap();
    ok(
        unsafe { glcol_mesh_set_self_collision(s.0, ids[cloth], true) },
        "self",
    );
    let meshes: Vec<(u32, &TestMesh)> = ids.iter().copied().zip(parts.iter()).collect();
    let pairs = all(&s);
    assert!(!pairs.is_empty());
    check_geometry(&s, &meshes, &pairs);
    // The pairs array survives glcol_query_geometry (read it again through the pointer).
    for &r in &ids {
        let hits = s.query(r);
        let as_pairs: Vec<P> = hits.iter().map(|&(o, rp, op)| (r, rp, o, op)).collect();
        check_geometry(&s, &meshes, &as_pairs);
    }
    // Two crossing squares: one intersecting pair per triangle pair that meets.
    let mut t = scene_with(0.0, 1);
    let (qa, qb) = (square(0., 0.), wall(0.5));
    let a = t.add(&qa);
    let b = t.add(&qb);
    let pairs = all(&t);
    check_geometry(&t, &[(a, &qa), (b, &qb)], &pairs);
    let (_, g) = try_geometry(&t);
    assert!(g.iter().all(|g| g.flags == GLCOL_CONTACT_INTERSECTING));
}

#[test]
fn geometry_errors() {
    let mut s = scene_with(0.0, 1);
    let (st, _) = try_geometry(&s);
    assert_eq!(st, S::InvalidArgument, "before any query");
    assert!(!last_error().is_empty());
    let q = square(0., 0.);
    let a = s.add(&q);
    let b = s.add(&wall(0.5));
    let n = all(&s).len();
    let (st, g) = try_geometry(&s);
    ok(st, "after query_all");
    assert_eq!(g.len(), n);
    // NULL out-parameters.
    let mut cnt = 7usize;
    assert_eq!(
        unsafe { glcol_query_geometry(s.0, std::ptr::null_mut(), &mut cnt) },
        S::NullPointer
    );
    assert_eq!(cnt, 7);
    assert_eq!(
        unsafe { glcol_query_geometry(null_mut(), std::ptr::null_mut(), &mut cnt) },
        S::NullPointer
    );
    // After an update.
    s.update(a, 0, &q.pos);
    let (st, _) = try_geometry(&s);
    assert_eq!(st, S::InvalidArgument, "after an update");
    assert!(last_error().contains("query"), "{}", last_error());
    // After a successful glcol_query, then a failed one (unknown mesh).
    let hits = s.query(a);
    let (st, g) = try_geometry(&s);
    ok(st, "after glcol_query");
    assert_eq!(g.len(), hits.len());
    let (st, _) = s.try_query(0);
    assert_eq!(st, S::UnknownMesh);
    let (st, _) = try_geometry(&s);
    assert_eq!(st, S::InvalidArgument, "after a failed query");
    // A failed query_all (NULL out_count) too.
    all(&s);
    let mut p: *const GlcolPair = std::ptr::null();
    assert_eq!(
        unsafe { glcol_query_all(s.0, &mut p, std::ptr::null_mut()) },
        S::NullPointer
    );
    assert_eq!(try_geometry(&s).0, S::InvalidArgument);
    // Enable, destroy, filter each make it stale.
    for change in 0..3 {
        all(&s);
        ok(try_geometry(&s).0, "fresh");
        match change {
            0 => s.set_enabled(b, true),
            1 => ok(
                unsafe { glcol_mesh_set_filter(s.0, b, 1, u32::MAX) },
                "filter",
            ),
            _ => s.destroy(b),
        }
        assert_eq!(try_geometry(&s).0, S::InvalidArgument, "change {change}");
    }
}

/// docs/API.md: `glcol_query_geometry` refuses after any successful change since the
/// query, the ones `geometry_errors` leaves out included (a mesh created, self-collision,
/// a transform, also NULL = the identity it already had); a call that fails changed
/// nothing and leaves it answering.
#[test]
fn geometry_refuses_after_any_change_and_not_after_a_failed_call() {
    let mut s = scene_with(0.0, 1);
    let q = square(0., 0.);
    let a = s.add(&q);
    let b = s.add(&wall(0.5));
    let identity = std::ptr::null::<f64>();
    for change in 0..4 {
        let n = all(&s).len();
        assert_eq!(try_geometry(&s).1.len(), n, "fresh before change {change}");
        match change {
            0 => {
                s.add(&square(5., 0.));
            }
            1 => ok(
                unsafe { glcol_mesh_set_self_collision(s.0, a, false) },
                "self-collision",
            ),
            2 => ok(
                unsafe { glcol_mesh_set_transform(s.0, b, identity) },
                "transform",
            ),
            _ => {
                let m: [f64; 12] = [1., 0., 0., 0.25, 0., 1., 0., 0., 0., 0., 1., 0.];
                ok(
                    unsafe { glcol_mesh_set_transform(s.0, b, m.as_ptr()) },
                    "transform",
                )
            }
        }
        assert_eq!(try_geometry(&s).0, S::InvalidArgument, "change {change}");
    }
    // Failed calls: a NaN transform, an unknown mesh, an update with a NaN.
    let n = all(&s).len();
    let nan: [f64; 12] = [f64::NAN; 12];
    assert_eq!(
        unsafe { glcol_mesh_set_transform(s.0, b, nan.as_ptr()) },
        S::NonFinite
    );
    assert_eq!(
        unsafe { glcol_mesh_set_filter(s.0, 0, 1, 1) },
        S::UnknownMesh
    );
    let bad = [[f32::NAN, 0., 0.]; 4];
    let st = unsafe { glcol_mesh_update_positions(s.0, a, bad.as_ptr().cast(), 0, 4, 0) };
    assert_eq!(st, S::NonFinite);
    let (st, g) = try_geometry(&s);
    ok(st, "geometry after failed calls");
    assert_eq!(g.len(), n);
}

/// docs/API.md: within a band (epsilon > 0) `glcol_query_all` reports a pair when either
/// polygon meets the other's viewing volume. Here the wall (x = 1 + d, d < epsilon/2) meets
/// nothing of the square's thin volume (x <= 1), while the square's edge x = 1 lies in the
/// wall's volume: `glcol_query` with the square as reference finds nothing, with the wall
/// as reference it finds the pair, and `glcol_query_all` reports it. Never COPLANAR, and
/// not INTERSECTING.
#[test]
fn a_band_pair_is_reported_when_either_polygon_meets_the_others_volume() {
    let eps = 0.1f32;
    let mut s = scene_with(eps, 1);
    let flat = s.add(&square(0., 0.));
    let upright = s.add(&wall(1.0 + eps / 4.0));
    assert!(
        s.query(flat).is_empty(),
        "the square's volume holds no wall polygon"
    );
    let from_wall = s.query(upright);
    assert!(!from_wall.is_empty());
    let pairs = all(&s);
    let want: Vec<P> = from_wall
        .iter()
        .map(|&(o, rp, op)| (o, op, upright, rp))
        .collect();
    assert_eq!(pairs, want);
    let (st, g) = try_geometry(&s);
    ok(st, "geometry");
    assert!(g.iter().all(|g| g.flags == 0 && g.depth < 0.0), "{g:?}");
}

// ---------------------------------------------------------------------------------------
// Rigid placement (C API only).

#[test]
fn set_transform_places_a_mesh_and_refuses_bad_input_changing_nothing() {
    let parts = overlapping_real_meshes();
    let t = &parts[0];
    // A quarter turn about z, doubled: world positions that are floats (checked), so a
    // second scene can be given them as vertices.
    let m: [f64; 12] = [0., -2., 0., 0., 2., 0., 0., 0., 0., 0., 2., 0.];
    let world: Vec<[f32; 3]> = t
        .pos
        .iter()
        .map(|p| {
            let w = [
                ((m[0] * p[0] as f64 + m[1] * p[1] as f64) + m[2] * p[2] as f64) + m[3],
                ((m[4] * p[0] as f64 + m[5] * p[1] as f64) + m[6] * p[2] as f64) + m[7],
                ((m[8] * p[0] as f64 + m[9] * p[1] as f64) + m[10] * p[2] as f64) + m[11],
            ];
            let f = w.map(|x| x as f32);
            assert!((0..3).all(|k| f[k] as f64 == w[k]), "not floats: {w:?}");
            f
        })
        .collect();
    let other = &parts[0];
    let mut s = scene_with(0.0, 0);
    let a = s.add(other);
    let b = s.add(t);
    ok(
        unsafe { glcol_mesh_set_transform(s.0, b, m.as_ptr()) },
        "glcol_mesh_set_transform",
    );
    let mut given = scene_with(0.0, 0);
    let a2 = given.add(other);
    let b2 = given.add(&TestMesh {
        pos: world.clone(),
        ..t.clone()
    });
    let strip = |h: Vec<(u32, u32, u32)>, other: u32| -> Vec<(u32, u32)> {
        h.into_iter()
            .inspect(|h| assert_eq!(h.0, other))
            .map(|h| (h.1, h.2))
            .collect()
    };
    let want = strip(given.query(a2), b2);
    assert!(!want.is_empty());
    assert_eq!(strip(s.query(a), b), want);
    let (st, g) = try_geometry(&s);
    ok(st, "geometry");
    assert!(!g.is_empty());
    let before_query = s.query(a);
    let before_all = all(&s);
    let unchanged = |s: &mut FfiScene| {
        assert_eq!(s.query(a), before_query);
        assert_eq!(all(s), before_all);
    };
    // Bad input: a NaN or infinite entry, overflowing world positions, an unknown mesh, a
    // NULL scene. Each is refused with a message and changes nothing.
    for (i, bad) in [(0, f64::NAN), (7, f64::INFINITY), (11, f64::NEG_INFINITY)] {
        let mut mm = m;
        mm[i] = bad;
        assert_eq!(
            unsafe { glcol_mesh_set_transform(s.0, b, mm.as_ptr()) },
            S::NonFinite
        );
        assert!(
            last_error().contains(&format!("m[{i}]")),
            "{}",
            last_error()
        );
        unchanged(&mut s);
    }
    let mut huge = m;
    huge[1] = -1e300;
    assert_eq!(
        unsafe { glcol_mesh_set_transform(s.0, b, huge.as_ptr()) },
        S::NonFinite
    );
    assert!(last_error().contains("float range"), "{}", last_error());
    unchanged(&mut s);
    assert_eq!(
        unsafe { glcol_mesh_set_transform(s.0, 0, m.as_ptr()) },
        S::UnknownMesh
    );
    assert_eq!(
        unsafe { glcol_mesh_set_transform(null_mut(), b, m.as_ptr()) },
        S::NullPointer
    );
    unchanged(&mut s);
    // An update whose world positions would overflow under m: refused, nothing changes.
    let mut far = t.pos.clone();
    far[3] = [0.0, 3e38, 0.0]; // twice that overflows
    assert_eq!(
        unsafe { glcol_mesh_update_positions(s.0, b, far.as_ptr().cast(), 0, far.len(), 0) },
        S::NonFinite
    );
    assert_eq!(
        unsafe { glcol_mesh_update_positions(s.0, b, far[3..].as_ptr().cast(), 3, 1, 0) },
        S::NonFinite
    );
    unchanged(&mut s);
    // A changed transform makes the last answer's geometry stale.
    ok(
        unsafe { glcol_mesh_set_transform(s.0, b, m.as_ptr()) },
        "the same matrix",
    );
    assert_eq!(try_geometry(&s).0, S::InvalidArgument);
    // NULL: the identity, the vertices as given.
    ok(
        unsafe { glcol_mesh_set_transform(s.0, b, std::ptr::null()) },
        "NULL m",
    );
    let mut local = scene_with(0.0, 0);
    let a3 = local.add(other);
    let b3 = local.add(t);
    let want_local = strip(local.query(a3), b3);
    let got_local = strip(s.query(a), b);
    assert_eq!(got_local, want_local);
    assert_ne!(got_local, want);
}
