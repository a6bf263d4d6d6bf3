//! Fuzz target (a): a sequence of C API calls decoded from the input: scenes, mesh creation
//! (valid or not), updates (whole, ranges, bad ones), enabling, destroying, self-collision,
//! filters, translations, queries, whole-scene queries, contact geometry, f64 meshes
//! (creation, updates with either call), targets (positions with either call, transforms,
//! clears: none changes an answer or invalidates the geometry), continuous queries (their
//! pairs meeting at the start are exactly the whole-scene query's) and their impact geometry, and malformed calls, on 1,
//! 2 or one-per-core threads. A model of the scene predicts every status, and every query is checked:
//! sorted, each pair once, only live enabled meshes; with coordinates on the 1/4 grid the
//! answer must equal the exact oracle's (epsilon = 0) or contain it with extras only within
//! epsilon/2 (epsilon > 0). Any panic aborts (libFuzzer's panic hook), so even a panic the
//! C boundary would catch counts as a crash.

use std::ptr::{null, null_mut};

use super::oracle;
use glcollide::ffi::*;

struct Bytes<'a>(&'a [u8]);

impl Bytes<'_> {
    fn u8(&mut self) -> u8 {
        match self.0.split_first() {
            Some((&b, rest)) => {
                self.0 = rest;
                b
            }
            None => 0,
        }
    }
    fn below(&mut self, n: usize) -> usize {
        if n == 0 {
            0
        } else {
            self.u8() as usize % n
        }
    }
    fn f32_raw(&mut self) -> f32 {
        f32::from_le_bytes([self.u8(), self.u8(), self.u8(), self.u8()])
    }
    /// Mostly a multiple of 1/4 in [-3, 3]; now and then any f32 bit pattern.
    /// Returns the value and whether it is on the grid.
    fn coord(&mut self) -> (f32, bool) {
        let b = self.u8();
        if b >= 250 {
            (self.f32_raw(), false)
        } else {
            ((f32::from(b % 25) - 12.0) * 0.25, true)
        }
    }
    /// For an f64 mesh: mostly a 1/4-grid value moved by -2..2 times 2^-40 (exact for the
    /// oracle, invisible to floats); now and then any f64 bit pattern.
    fn coord64(&mut self) -> f64 {
        let b = self.u8();
        if b >= 250 {
            f64::from_le_bytes([0; 8].map(|_| self.u8()))
        } else {
            let tiny = (f64::from(self.u8() % 5) - 2.0) * 2f64.powi(-40);
            (f64::from(b % 25) - 12.0) * 0.25 + tiny
        }
    }
    fn is_empty(&self) -> bool {
        self.0.is_empty()
    }
}

#[derive(Clone)]
struct Model {
    id: u32,
    /// Positions as the mesh holds them (a float mesh's widened).
    pos: Vec<[f64; 3]>,
    /// Made from double positions.
    f64: bool,
    /// A target was given positions off the grid (huge ones may make a later target
    /// transform's end positions leave the float range: NON_FINITE).
    wild_target: bool,
    idx: Vec<u32>,
    k: usize,
    enabled: bool,
    /// Every coordinate is on the grid ([`on_grid`]: the oracle's differences are then exact).
    grid: bool,
    /// Translation of `glcol_mesh_set_transform` (multiples of 1/4: world stays on the grid).
    t: [f32; 3],
    self_collision: bool,
    group: u32,
    mask: u32,
}

impl Model {
    /// Polygon `p`'s triangles in world coordinates (exact: grid values plus a grid shift).
    fn tris(&self, p: usize) -> Vec<[[f64; 3]; 3]> {
        let v = |j: usize| {
            let x = self.pos[self.idx[p * self.k + j] as usize];
            [0, 1, 2].map(|a| x[a] + f64::from(self.t[a]))
        };
        if self.k == 3 {
            vec![[v(0), v(1), v(2)]]
        } else {
            vec![[v(0), v(1), v(2)], [v(0), v(2), v(3)]]
        }
    }
    fn polygons(&self) -> usize {
        self.idx.len() / self.k
    }
    /// docs/API.md's filter: are meshes `self` and `o` collided at all?
    fn collides_with(&self, o: &Model) -> bool {
        self.group & o.mask != 0 && o.group & self.mask != 0
    }
    fn shares_vertex(&self, a: usize, b: usize) -> bool {
        let va = &self.idx[a * self.k..(a + 1) * self.k];
        let vb = &self.idx[b * self.k..(b + 1) * self.k];
        va.iter().any(|v| vb.contains(v))
    }
}

/// A multiple of 2^-40 within [-4, 4]: differences of such values (shifted by grid
/// translations) are exact in f64.
fn on_grid(v: f64) -> bool {
    (v * 2f64.powi(40)).fract() == 0.0 && v.abs() <= 4.0
}

/// Finite and within the float range (what a mesh accepts).
fn in_range(v: f64) -> bool {
    v.abs() <= f64::from(f32::MAX)
}

/// The `n` entries of an answer at `p` (none for `n == 0`, where `p` may be null).
fn answer<'a, T>(p: *const T, n: usize) -> &'a [T] {
    if n == 0 {
        &[]
    } else {
        // SAFETY: after an OK query the library promises `n` entries at `p`, valid until
        // the next call on the scene; each caller reads them before that.
        unsafe { std::slice::from_raw_parts(p, n) }
    }
}

fn status(s: GlcolStatus, want: GlcolStatus, what: &str) {
    assert_eq!(s, want, "{what}: {}", unsafe {
        std::ffi::CStr::from_ptr(glcol_last_error_message()).to_string_lossy()
    });
}

/// Double positions as the caller lays them out: packed, or 32 bytes apart with junk in
/// between.
fn layout64(pos: &[[f64; 3]], strided: bool, junk: f64) -> (Vec<f64>, usize) {
    if strided {
        (
            pos.iter().flat_map(|p| [p[0], p[1], p[2], junk]).collect(),
            32,
        )
    } else {
        (pos.iter().flatten().copied().collect(), 0)
    }
}

/// Positions as the caller lays them out: packed, or 16 bytes apart with junk in between.
fn layout(pos: &[[f32; 3]], strided: bool, junk: f32) -> (Vec<f32>, usize) {
    if strided {
        (
            pos.iter().flat_map(|p| [p[0], p[1], p[2], junk]).collect(),
            16,
        )
    } else {
        (pos.iter().flatten().copied().collect(), 0)
    }
}

fn query(scene: *mut GlcolScene, id: u32) -> (GlcolStatus, Vec<GlcolContact>) {
    let mut p: *const GlcolContact = null();
    let mut n = usize::MAX;
    let s = unsafe { glcol_query(scene, id, &mut p, &mut n) };
    if s != GlcolStatus::Ok {
        return (s, Vec::new());
    }
    if n == 0 {
        assert!(p.is_null());
        return (s, Vec::new());
    }
    (s, unsafe { std::slice::from_raw_parts(p, n) }.to_vec())
}

fn check_query(scene: *mut GlcolScene, meshes: &[Model], r: usize, epsilon: f32) -> usize {
    let m = &meshes[r];
    let (s, got) = query(scene, m.id);
    status(s, GlcolStatus::Ok, "query");
    let key = |c: &GlcolContact| (c.other_mesh, c.reference_polygon, c.other_polygon);
    assert!(
        got.windows(2).all(|w| key(&w[0]) < key(&w[1])),
        "contacts not sorted/unique"
    );
    if !m.enabled {
        assert!(got.is_empty(), "a disabled reference has contacts");
        return 0;
    }
    for c in &got {
        let o = meshes
            .iter()
            .find(|o| o.id == c.other_mesh)
            .expect("contact names a dead mesh");
        assert!(
            o.enabled && o.id != m.id && m.collides_with(o),
            "contact with a disabled or filtered-out mesh or itself"
        );
        assert!((c.reference_polygon as usize) < m.polygons());
        assert!((c.other_polygon as usize) < o.polygons());
    }
    if !m.grid {
        return got.len();
    }
    let h = f64::from(epsilon) / 2.0;
    for o in meshes
        .iter()
        .filter(|o| o.id != m.id && o.enabled && o.grid && m.collides_with(o))
    {
        for a in 0..m.polygons() {
            for b in 0..o.polygons() {
                let (ta, tb) = (m.tris(a), o.tris(b));
                let meets = ta
                    .iter()
                    .any(|t| tb.iter().any(|u| oracle::triangles_meet(t, u)));
                let found = got
                    .binary_search_by_key(&(o.id, a as u32, b as u32), key)
                    .is_ok();
                if epsilon == 0.0 {
                    assert_eq!(found, meets, "pair ({a}, {b}) with mesh {}", o.id);
                } else if meets {
                    assert!(
                        found,
                        "intersecting pair ({a}, {b}) missed at epsilon {epsilon}"
                    );
                } else if found {
                    let d = ta
                        .iter()
                        .flat_map(|t| tb.iter().map(move |u| oracle::triangle_distance(t, u)))
                        .fold(f64::INFINITY, f64::min);
                    assert!(d <= h + 1e-9 * (h + 8.0), "extra pair at {d} > {h}");
                }
            }
        }
    }
    got.len()
}

/// `glcol_query_all`: sorted, each pair once, (mesh_a, polygon_a) < (mesh_b, polygon_b),
/// only enabled meshes that pass the filter, same-mesh pairs only with self-collision on and
/// never a polygon with itself; on the grid at epsilon 0: every pair of two meshes and every
/// non-adjacent pair of one mesh exactly as the oracle says, adjacent ones only if they meet.
fn check_query_all(scene: *mut GlcolScene, meshes: &[Model], epsilon: f32) -> usize {
    let mut p: *const GlcolPair = null();
    let mut n = usize::MAX;
    status(
        unsafe { glcol_query_all(scene, &mut p, &mut n) },
        GlcolStatus::Ok,
        "query_all",
    );
    let got = answer(p, n).to_vec();
    let key = |q: &GlcolPair| (q.mesh_a, q.polygon_a, q.mesh_b, q.polygon_b);
    assert!(
        got.windows(2).all(|w| key(&w[0]) < key(&w[1])),
        "pairs not sorted/unique"
    );
    let model = |id: u32| {
        meshes
            .iter()
            .find(|m| m.id == id)
            .expect("pair names a dead mesh")
    };
    for q in &got {
        let (a, b) = (model(q.mesh_a), model(q.mesh_b));
        assert!((q.mesh_a, q.polygon_a) < (q.mesh_b, q.polygon_b));
        assert!(a.enabled && b.enabled, "pair with a disabled mesh");
        assert!((q.polygon_a as usize) < a.polygons() && (q.polygon_b as usize) < b.polygons());
        if a.id == b.id {
            assert!(a.self_collision, "same-mesh pair without self-collision");
        } else {
            assert!(a.collides_with(b), "pair of filtered-out meshes");
        }
    }
    if epsilon != 0.0 {
        return got.len();
    }
    let on = |m: &&Model| m.enabled && m.grid;
    for a in meshes.iter().filter(on) {
        for b in meshes.iter().filter(on).filter(|b| b.id >= a.id) {
            let same = a.id == b.id;
            if same && !a.self_collision || !same && !a.collides_with(b) {
                continue;
            }
            for pa in 0..a.polygons() {
                for pb in if same { pa + 1 } else { 0 }..b.polygons() {
                    let meets = a
                        .tris(pa)
                        .iter()
                        .any(|t| b.tris(pb).iter().any(|u| oracle::triangles_meet(t, u)));
                    let found = got
                        .binary_search_by_key(&(a.id, pa as u32, b.id, pb as u32), key)
                        .is_ok();
                    if same && a.shares_vertex(pa, pb) {
                        assert!(
                            !found || meets,
                            "adjacent pair ({pa}, {pb}) apart but reported"
                        );
                    } else {
                        assert_eq!(found, meets, "pair {}:{pa} {}:{pb}", a.id, b.id);
                    }
                }
            }
        }
    }
    got.len()
}

/// `glcol_query_continuous` right after a successful `glcol_query_all` (whose answer the
/// model has checked): sorted, each pair once, live enabled meshes, filters, times in
/// [0, 1] with AT_START exactly at 0, and at epsilon 0 the pairs meeting at the start are
/// exactly `glcol_query_all`'s (the same exact decisions, the adjacency rule included); at
/// epsilon > 0 (the distance band) the same checks but the last. Then its impact geometry.
fn check_continuous(scene: *mut GlcolScene, meshes: &[Model], epsilon: f32) {
    let mut p: *const GlcolPair = null();
    let mut n = usize::MAX;
    status(
        unsafe { glcol_query_all(scene, &mut p, &mut n) },
        GlcolStatus::Ok,
        "query_all",
    );
    let start: Vec<(u32, u32, u32, u32)> = answer(p, n)
        .iter()
        .map(|q| (q.mesh_a, q.polygon_a, q.mesh_b, q.polygon_b))
        .collect();
    let mut ip: *const GlcolImpact = null();
    let mut m = usize::MAX;
    let s = unsafe { glcol_query_continuous(scene, &mut ip, &mut m) };
    status(s, GlcolStatus::Ok, "query_continuous");
    let got = answer(ip, m).to_vec();
    let key = |q: &GlcolImpact| (q.mesh_a, q.polygon_a, q.mesh_b, q.polygon_b);
    assert!(
        got.windows(2).all(|w| key(&w[0]) < key(&w[1])),
        "impacts not sorted/unique"
    );
    for q in &got {
        let model = |id: u32| meshes.iter().find(|m| m.id == id).expect("dead mesh");
        let (a, b) = (model(q.mesh_a), model(q.mesh_b));
        assert!(a.enabled && b.enabled, "impact with a disabled mesh");
        assert!((q.polygon_a as usize) < a.polygons() && (q.polygon_b as usize) < b.polygons());
        if a.id == b.id {
            assert!(a.self_collision && q.polygon_a < q.polygon_b);
        } else {
            assert!(
                a.collides_with(b) && a.id < b.id,
                "impact of filtered-out meshes"
            );
        }
        assert!((0.0..=1.0).contains(&q.toi), "toi {}", q.toi);
        assert_eq!(q.toi == 0.0, q.flags & GLCOL_IMPACT_AT_START != 0, "{q:?}");
    }
    // The impact geometry of the answer: one entry each, NONE exactly for AT_START, weights
    // in [0, 1] summing to 1, a unit normal (0 for NONE), vertices of the polygons' meshes.
    let mut gp: *const GlcolImpactGeometry = null();
    let mut gn = usize::MAX;
    status(
        unsafe { glcol_query_impact_geometry(scene, &mut gp, &mut gn) },
        GlcolStatus::Ok,
        "query_impact_geometry",
    );
    assert_eq!(gn, got.len());
    let geo = answer(gp, gn);
    for (q, g) in got.iter().zip(geo) {
        let at_start = q.flags & GLCOL_IMPACT_AT_START != 0;
        assert_eq!(g.kind == GLCOL_FEATURE_NONE, at_start, "{q:?} {g:?}");
        assert!(g.kind <= GLCOL_FEATURE_EDGE_EDGE);
        let len = g.normal.iter().map(|x| x * x).sum::<f64>().sqrt();
        if at_start {
            assert_eq!(len, 0.0);
            continue;
        }
        assert!((len - 1.0).abs() < 1e-9, "normal {g:?}");
        for w in [&g.weights_a, &g.weights_b] {
            assert!(w.iter().all(|x| (0.0..=1.0).contains(x)), "{g:?}");
            assert!((w.iter().sum::<f64>() - 1.0).abs() < 1e-12, "{g:?}");
        }
        let model = |id: u32| meshes.iter().find(|m| m.id == id).expect("dead mesh");
        let (a, b) = (model(q.mesh_a), model(q.mesh_b));
        let own = |m: &Model, p: u32, v: &[u32; 3]| {
            let c = &m.idx[p as usize * m.k..(p as usize + 1) * m.k];
            v.iter().all(|x| c.contains(x))
        };
        assert!(own(a, q.polygon_a, &g.vertices_a) && own(b, q.polygon_b, &g.vertices_b));
    }
    if epsilon != 0.0 {
        // The distance band is not glcol_query_all's viewing volume: only the pairs that
        // meet at the start are common to both.
        return;
    }
    let at_start: Vec<_> = got
        .iter()
        .filter(|q| q.flags & GLCOL_IMPACT_AT_START != 0)
        .map(key)
        .collect();
    assert_eq!(
        at_start, start,
        "AT_START pairs differ from glcol_query_all's"
    );
}

/// `glcol_query_geometry` after a successful query of `n` contacts or pairs: one entry
/// each, all finite, unit normals, depth >= 0 exactly for intersecting pairs (all of them at
/// epsilon 0).
fn check_geometry(scene: *mut GlcolScene, n: usize, epsilon: f32) {
    let mut p: *const GlcolContactGeometry = null();
    let mut m = usize::MAX;
    status(
        unsafe { glcol_query_geometry(scene, &mut p, &mut m) },
        GlcolStatus::Ok,
        "query_geometry",
    );
    assert_eq!(m, n, "one geometry entry per pair");
    if n == 0 {
        return;
    }
    for g in answer(p, n) {
        let all = g.point_a.iter().chain(&g.point_b).chain(&g.normal);
        assert!(
            all.chain([&g.depth]).all(|v| v.is_finite()),
            "non-finite geometry"
        );
        let len = g
            .normal
            .iter()
            .map(|v| f64::from(*v).powi(2))
            .sum::<f64>()
            .sqrt();
        assert!((len - 1.0).abs() < 1e-5, "normal of length {len}");
        let meets = g.flags & GLCOL_CONTACT_INTERSECTING != 0;
        assert!(
            meets || epsilon > 0.0,
            "a pair only within the band at epsilon 0"
        );
        assert!(
            if meets {
                g.depth >= 0.0
            } else {
                g.depth <= 0.0
            },
            "depth {}",
            g.depth
        );
    }
}

pub fn run(data: &[u8]) {
    let mut c = Bytes(data);
    let mut d = unsafe { std::mem::zeroed::<GlcolSceneDesc>() };
    unsafe { glcol_scene_desc_init_sized(&mut d, std::mem::size_of::<GlcolSceneDesc>()) };
    d.threads = [1, 2, 0][c.below(3)];
    let epsilon = [0.0f32, 0.0, 0.25, 1e-3][c.below(4)];
    d.epsilon = epsilon;
    d.max_polygons_per_box = c.below(6) as u32;
    d.backend = [0, 1, 1, 1, 2, 3, 9][c.below(7)];
    let mut scene = null_mut();
    let s = unsafe { glcol_scene_create(&d, &mut scene) };
    match d.backend {
        0 | 1 => status(s, GlcolStatus::Ok, "scene"),
        2 | 3 => {
            status(s, GlcolStatus::GlUnavailable, "GL scene without a loader");
            return;
        }
        _ => {
            status(s, GlcolStatus::InvalidArgument, "bad backend");
            return;
        }
    }
    let mut meshes: Vec<Model> = Vec::new();
    let mut dead: Vec<u32> = Vec::new();
    let mut ops = 0;
    while !c.is_empty() && ops < 48 {
        ops += 1;
        // An id: live, destroyed, or never made.
        let pick = |c: &mut Bytes, meshes: &[Model], dead: &[u32]| -> (u32, Option<usize>) {
            let i = c.below(meshes.len() + 2);
            if i < meshes.len() {
                (meshes[i].id, Some(i))
            } else if i == meshes.len() && !dead.is_empty() {
                (dead[c.below(dead.len())], None)
            } else {
                // Ids are unique in the process, so 77 may be one of this scene's meshes
                // in a long fuzzing run: ask the model.
                let id = [0, 77, u32::MAX][c.below(3)];
                (id, meshes.iter().position(|m| m.id == id))
            }
        };
        match c.below(12) {
            0 | 1 => {
                // Create a mesh, valid or not.
                let k = [3usize, 4, 3, 4, 3, 4, 5, 0][c.below(8)];
                let nv = 1 + c.below(8);
                let np = c.below(6);
                let doubles = c.below(3) == 0;
                let pos: Vec<[f64; 3]> = (0..nv)
                    .map(|_| {
                        [0, 1, 2].map(|_| {
                            if doubles {
                                c.coord64()
                            } else {
                                f64::from(c.coord().0)
                            }
                        })
                    })
                    .collect();
                let grid = pos.iter().flatten().all(|&v| on_grid(v));
                let idx: Vec<u32> = (0..np * k.max(1))
                    .map(|_| {
                        let i = c.below(nv + 1);
                        if i == nv && c.below(4) != 0 {
                            0
                        } else {
                            i as u32
                        }
                    })
                    .collect();
                let strided = c.below(4) == 0;
                let p32: Vec<[f32; 3]> = pos.iter().map(|p| p.map(|x| x as f32)).collect();
                let (buf, stride) = layout(&p32, strided, f32::NAN);
                let (buf64, stride64) = layout64(&pos, strided, f64::NAN);
                let mut md = unsafe { std::mem::zeroed::<GlcolMeshDesc>() };
                unsafe {
                    glcol_mesh_desc_init_sized(&mut md, std::mem::size_of::<GlcolMeshDesc>())
                };
                if doubles {
                    md.positions_f64 = buf64.as_ptr();
                    md.position_stride = stride64;
                } else {
                    md.positions = buf.as_ptr();
                    md.position_stride = stride;
                }
                md.vertex_count = nv;
                md.indices = if idx.is_empty() {
                    [0u32].as_ptr()
                } else {
                    idx.as_ptr()
                };
                md.polygon_count = np;
                md.vertices_per_polygon = k as u32;
                let finite = pos.iter().flatten().all(|&v| in_range(v));
                let indices_ok = idx.iter().all(|&i| (i as usize) < nv);
                let want = if k != 3 && k != 4 || np == 0 {
                    GlcolStatus::InvalidArgument
                } else if !finite {
                    GlcolStatus::NonFinite
                } else if !indices_ok {
                    GlcolStatus::IndexOutOfRange
                } else {
                    GlcolStatus::Ok
                };
                let mut id = 0xDEAD;
                let s = unsafe { glcol_mesh_create(scene, &md, &mut id) };
                status(s, want, "mesh_create");
                if s == GlcolStatus::Ok {
                    assert!(meshes.iter().all(|m| m.id < id) && dead.iter().all(|&x| x < id));
                    meshes.push(Model {
                        id,
                        pos,
                        f64: doubles,
                        wild_target: false,
                        idx,
                        k,
                        enabled: true,
                        grid,
                        t: [0.0; 3],
                        self_collision: false,
                        group: 1,
                        mask: u32::MAX,
                    });
                } else {
                    assert_eq!(id, 0xDEAD);
                }
            }
            2 => {
                // Update a range (maybe empty, past the end, or with a NaN).
                let (id, i) = pick(&mut c, &meshes, &dead);
                let n = i.map_or(4, |i| meshes[i].pos.len());
                let first = c.below(n + 1);
                let count = c.below(n + 2);
                // The call of the mesh's kind, mostly; the other one now and then.
                let kind = i.is_some_and(|i| meshes[i].f64);
                let doubles = if c.below(8) == 0 { !kind } else { kind };
                let new: Vec<[f64; 3]> = (0..count.max(1))
                    .map(|_| {
                        [0, 1, 2].map(|_| {
                            if doubles {
                                c.coord64()
                            } else {
                                f64::from(c.coord().0)
                            }
                        })
                    })
                    .collect();
                let strided = c.below(3) == 0;
                let n32: Vec<[f32; 3]> = new.iter().map(|p| p.map(|x| x as f32)).collect();
                let (buf, stride) = layout(&n32, strided, f32::INFINITY);
                let (buf64, stride64) = layout64(&new, strided, f64::INFINITY);
                let finite = new[..count].iter().flatten().all(|&v| in_range(v));
                let want = if i.is_none() {
                    GlcolStatus::UnknownMesh
                } else if doubles != kind || count == 0 || first + count > n {
                    GlcolStatus::InvalidArgument
                } else if !finite {
                    GlcolStatus::NonFinite
                } else {
                    GlcolStatus::Ok
                };
                let s = if doubles {
                    unsafe {
                        glcol_mesh_update_positions_f64(
                            scene,
                            id,
                            buf64.as_ptr(),
                            first,
                            count,
                            stride64,
                        )
                    }
                } else {
                    unsafe {
                        glcol_mesh_update_positions(scene, id, buf.as_ptr(), first, count, stride)
                    }
                };
                // A placed mesh refuses positions whose world positions could leave the float
                // range (decided conservatively from its box): NON_FINITE, nothing changed.
                let placed = i.is_some_and(|i| meshes[i].t != [0.0; 3]);
                if !(placed && want == GlcolStatus::Ok && s == GlcolStatus::NonFinite) {
                    status(s, want, "update");
                }
                if let (GlcolStatus::Ok, Some(i)) = (s, i) {
                    let m = &mut meshes[i];
                    m.pos[first..first + count].copy_from_slice(&new[..count]);
                    m.grid = m.pos.iter().flatten().all(|&v| on_grid(v));
                    m.wild_target = false;
                }
            }
            3 => {
                let (id, i) = pick(&mut c, &meshes, &dead);
                let on = c.below(2) == 0;
                let s = unsafe { glcol_mesh_set_enabled(scene, id, on) };
                match i {
                    Some(i) => {
                        status(s, GlcolStatus::Ok, "set_enabled");
                        meshes[i].enabled = on;
                    }
                    None => status(s, GlcolStatus::UnknownMesh, "set_enabled unknown"),
                }
            }
            4 => {
                let (id, i) = pick(&mut c, &meshes, &dead);
                let s = unsafe { glcol_mesh_destroy(scene, id) };
                match i {
                    Some(i) => {
                        status(s, GlcolStatus::Ok, "destroy");
                        dead.push(meshes.remove(i).id);
                    }
                    None => status(s, GlcolStatus::UnknownMesh, "destroy unknown"),
                }
            }
            5 | 6 => {
                let (id, i) = pick(&mut c, &meshes, &dead);
                match i {
                    Some(i) => {
                        let n = check_query(scene, &meshes, i, epsilon);
                        check_geometry(scene, n, epsilon);
                    }
                    None => status(
                        query(scene, id).0,
                        GlcolStatus::UnknownMesh,
                        "query unknown",
                    ),
                }
            }
            8 => {
                // Self-collision, filters, a translation (or back to the identity).
                let (id, i) = pick(&mut c, &meshes, &dead);
                let which = c.below(3);
                let s = match which {
                    0 => {
                        let on = c.below(2) == 0;
                        let s = unsafe { glcol_mesh_set_self_collision(scene, id, on) };
                        if let (GlcolStatus::Ok, Some(i)) = (s, i) {
                            meshes[i].self_collision = on;
                        }
                        s
                    }
                    1 => {
                        let group = [1, 2, 3, 0][c.below(4)];
                        let mask = [u32::MAX, 1, 2, 0][c.below(4)];
                        let s = unsafe { glcol_mesh_set_filter(scene, id, group, mask) };
                        if let (GlcolStatus::Ok, Some(i)) = (s, i) {
                            (meshes[i].group, meshes[i].mask) = (group, mask);
                        }
                        s
                    }
                    _ => {
                        let t = [0, 1, 2].map(|_| (c.below(17) as f32 - 8.0) * 0.25);
                        let identity = c.below(4) == 0;
                        let m: [f64; 12] = [
                            1.0,
                            0.0,
                            0.0,
                            f64::from(t[0]),
                            0.0,
                            1.0,
                            0.0,
                            f64::from(t[1]),
                            0.0,
                            0.0,
                            1.0,
                            f64::from(t[2]),
                        ];
                        let mp = if identity { null() } else { m.as_ptr() };
                        let s = unsafe { glcol_mesh_set_transform(scene, id, mp) };
                        if let (GlcolStatus::Ok, Some(i)) = (s, i) {
                            meshes[i].t = if identity { [0.0; 3] } else { t };
                            meshes[i].wild_target = false;
                        }
                        // Huge local coordinates may leave the float range once moved:
                        // NON_FINITE, nothing changed (the model keeps its translation).
                        if s == GlcolStatus::NonFinite && i.is_some_and(|i| !meshes[i].grid) {
                            GlcolStatus::Ok
                        } else {
                            s
                        }
                    }
                };
                let want = if i.is_some() {
                    GlcolStatus::Ok
                } else {
                    GlcolStatus::UnknownMesh
                };
                status(
                    s,
                    want,
                    ["set_self_collision", "set_filter", "set_transform"][which],
                );
            }
            9 => {
                let n = check_query_all(scene, &meshes, epsilon);
                check_geometry(scene, n, epsilon);
                check_continuous(scene, &meshes, epsilon);
            }
            11 => {
                // Targets: positions (either call, any range, bad values), a transform, a
                // clear. After a whole-scene query: the geometry stays valid whatever the
                // call answers (a target is no change of the current state), and no later
                // answer changes (the model ignores targets).
                let n = check_query_all(scene, &meshes, epsilon);
                let (id, i) = pick(&mut c, &meshes, &dead);
                let known = i.is_some();
                let wild = i.is_some_and(|i| {
                    meshes[i].t != [0.0; 3] || !meshes[i].grid || meshes[i].wild_target
                });
                let mut wild_values = false;
                let (s, want, what) = match c.below(4) {
                    0 | 1 => {
                        let n = i.map_or(4, |i| meshes[i].pos.len());
                        let first = c.below(n + 1);
                        let count = c.below(n + 2);
                        let kind = i.is_some_and(|i| meshes[i].f64);
                        let doubles = if c.below(8) == 0 { !kind } else { kind };
                        let new: Vec<[f64; 3]> = (0..count.max(1))
                            .map(|_| [0, 1, 2].map(|_| c.coord64()))
                            .collect();
                        let n32: Vec<[f32; 3]> = new.iter().map(|p| p.map(|x| x as f32)).collect();
                        wild_values = !new[..count].iter().flatten().all(|&v| on_grid(v));
                        let finite = if doubles {
                            new[..count].iter().flatten().all(|&v| in_range(v))
                        } else {
                            n32[..count].iter().flatten().all(|v| v.is_finite())
                        };
                        let want = if !known {
                            GlcolStatus::UnknownMesh
                        } else if doubles != kind || count == 0 || first + count > n {
                            GlcolStatus::InvalidArgument
                        } else if !finite {
                            GlcolStatus::NonFinite
                        } else {
                            GlcolStatus::Ok
                        };
                        let s = if doubles {
                            let p = new.as_ptr().cast::<f64>();
                            unsafe {
                                glcol_mesh_set_target_positions_f64(scene, id, p, first, count, 0)
                            }
                        } else {
                            let p = n32.as_ptr().cast::<f32>();
                            unsafe {
                                glcol_mesh_set_target_positions(scene, id, p, first, count, 0)
                            }
                        };
                        (s, want, "set_target_positions")
                    }
                    2 => {
                        let mut m = [1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0];
                        m[3] = (c.below(17) as f64 - 8.0) * 0.25;
                        let bad = c.below(6) == 0;
                        if bad {
                            m[c.below(12)] = f64::NAN;
                        }
                        let want = if !known {
                            GlcolStatus::UnknownMesh
                        } else if bad {
                            GlcolStatus::NonFinite
                        } else {
                            GlcolStatus::Ok
                        };
                        let s = unsafe { glcol_mesh_set_target_transform(scene, id, m.as_ptr()) };
                        (s, want, "set_target_transform")
                    }
                    _ => {
                        let s = unsafe { glcol_mesh_clear_target(scene, id) };
                        let want = if known {
                            GlcolStatus::Ok
                        } else {
                            GlcolStatus::UnknownMesh
                        };
                        (s, want, "clear_target")
                    }
                };
                // Huge coordinates under a transform may leave the float range at the end:
                // NON_FINITE (decided conservatively), nothing changed.
                if !((wild || wild_values)
                    && want == GlcolStatus::Ok
                    && s == GlcolStatus::NonFinite)
                {
                    status(s, want, what);
                }
                if let Some(i) = i {
                    match (s, what) {
                        (GlcolStatus::Ok, "set_target_positions") => {
                            meshes[i].wild_target |= wild_values
                        }
                        (GlcolStatus::Ok, "clear_target") => meshes[i].wild_target = false,
                        _ => {}
                    }
                }
                check_geometry(scene, n, epsilon);
            }
            _ => {
                // Malformed calls that must change nothing.
                let (id, i) = pick(&mut c, &meshes, &dead);
                let known = if i.is_some() {
                    GlcolStatus::Ok
                } else {
                    GlcolStatus::UnknownMesh
                };
                let p = [0f32; 12];
                let s = match c.below(6) {
                    0 => unsafe {
                        glcol_mesh_update_positions(null_mut(), id, p.as_ptr(), 0, 1, 0)
                    },
                    1 => unsafe { glcol_mesh_update_positions(scene, id, null(), 0, 1, 0) },
                    2 => unsafe { glcol_mesh_update_positions(scene, id, p.as_ptr(), 0, 1, 4) },
                    3 => unsafe { glcol_mesh_bind_gl_buffer(scene, id, 1, 0, 12) },
                    4 => unsafe { glcol_query(scene, id, null_mut(), null_mut()) },
                    _ => unsafe { glcol_mesh_create(scene, null(), null_mut()) },
                };
                assert_ne!(s, GlcolStatus::Ok, "a malformed call succeeded");
                assert_ne!(s, GlcolStatus::Internal);
                let _ = known;
            }
        }
    }
    // Every live mesh's answer at the end, and the whole scene's.
    for i in 0..meshes.len() {
        check_query(scene, &meshes, i, epsilon);
    }
    check_query_all(scene, &meshes, epsilon);
    unsafe { glcol_scene_destroy(scene) };
}
