//! Fuzz target (a): a sequence of C API calls decoded from the input: scenes, mesh creation
//! (valid or not), updates (whole, ranges, bad ones), enabling, destroying, queries, and
//! malformed calls. A model of the scene predicts every status, and every query is checked:
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
    fn is_empty(&self) -> bool {
        self.0.is_empty()
    }
}

#[derive(Clone)]
struct Model {
    id: u32,
    pos: Vec<[f32; 3]>,
    idx: Vec<u32>,
    k: usize,
    enabled: bool,
    /// Every coordinate is on the 1/4 grid (the oracle's differences are then exact).
    grid: bool,
}

impl Model {
    fn tris(&self, p: usize) -> Vec<[[f64; 3]; 3]> {
        let v = |j: usize| self.pos[self.idx[p * self.k + j] as usize].map(f64::from);
        if self.k == 3 {
            vec![[v(0), v(1), v(2)]]
        } else {
            vec![[v(0), v(1), v(2)], [v(0), v(2), v(3)]]
        }
    }
    fn polygons(&self) -> usize {
        self.idx.len() / self.k
    }
}

fn status(s: GlcolStatus, want: GlcolStatus, what: &str) {
    assert_eq!(s, want, "{what}: {}", unsafe {
        std::ffi::CStr::from_ptr(glcol_last_error_message()).to_string_lossy()
    });
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

fn check_query(scene: *mut GlcolScene, meshes: &[Model], r: usize, epsilon: f32) {
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
        return;
    }
    for c in &got {
        let o = meshes
            .iter()
            .find(|o| o.id == c.other_mesh)
            .expect("contact names a dead mesh");
        assert!(
            o.enabled && o.id != m.id,
            "contact with a disabled mesh or itself"
        );
        assert!((c.reference_polygon as usize) < m.polygons());
        assert!((c.other_polygon as usize) < o.polygons());
    }
    if !m.grid {
        return;
    }
    let h = f64::from(epsilon) / 2.0;
    for o in meshes
        .iter()
        .filter(|o| o.id != m.id && o.enabled && o.grid)
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
}

pub fn run(data: &[u8]) {
    let mut c = Bytes(data);
    let mut d = unsafe { std::mem::zeroed::<GlcolSceneDesc>() };
    unsafe { glcol_scene_desc_init(&mut d) };
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
        match c.below(8) {
            0 | 1 => {
                // Create a mesh, valid or not.
                let k = [3usize, 4, 3, 4, 3, 4, 5, 0][c.below(8)];
                let nv = 1 + c.below(8);
                let np = c.below(6);
                let mut grid = true;
                let pos: Vec<[f32; 3]> = (0..nv)
                    .map(|_| {
                        [0, 1, 2].map(|_| {
                            let (v, g) = c.coord();
                            grid &= g;
                            v
                        })
                    })
                    .collect();
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
                let (buf, stride) = layout(&pos, strided, f32::NAN);
                let mut md = unsafe { std::mem::zeroed::<GlcolMeshDesc>() };
                unsafe { glcol_mesh_desc_init(&mut md) };
                md.positions = buf.as_ptr();
                md.vertex_count = nv;
                md.position_stride = stride;
                md.indices = if idx.is_empty() {
                    [0u32].as_ptr()
                } else {
                    idx.as_ptr()
                };
                md.polygon_count = np;
                md.vertices_per_polygon = k as u32;
                let finite = pos.iter().flatten().all(|v| v.is_finite());
                let in_range = idx.iter().all(|&i| (i as usize) < nv);
                let want = if k != 3 && k != 4 || np == 0 {
                    GlcolStatus::InvalidArgument
                } else if !finite {
                    GlcolStatus::NonFinite
                } else if !in_range {
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
                        idx,
                        k,
                        enabled: true,
                        grid,
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
                let mut grid = true;
                let new: Vec<[f32; 3]> = (0..count.max(1))
                    .map(|_| {
                        [0, 1, 2].map(|_| {
                            let (v, g) = c.coord();
                            grid &= g;
                            v
                        })
                    })
                    .collect();
                let strided = c.below(3) == 0;
                let (buf, stride) = layout(&new, strided, f32::INFINITY);
                let finite = new[..count].iter().flatten().all(|v| v.is_finite());
                let want = if i.is_none() {
                    GlcolStatus::UnknownMesh
                } else if count == 0 || first + count > n {
                    GlcolStatus::InvalidArgument
                } else if !finite {
                    GlcolStatus::NonFinite
                } else {
                    GlcolStatus::Ok
                };
                let s = unsafe {
                    glcol_mesh_update_positions(scene, id, buf.as_ptr(), first, count, stride)
                };
                status(s, want, "update");
                if let (GlcolStatus::Ok, Some(i)) = (s, i) {
                    let m = &mut meshes[i];
                    m.pos[first..first + count].copy_from_slice(&new[..count]);
                    m.grid = m
                        .pos
                        .iter()
                        .flatten()
                        .all(|v| (v * 4.0).fract() == 0.0 && v.abs() <= 3.0);
                    let _ = grid;
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
                    Some(i) => check_query(scene, &meshes, i, epsilon),
                    None => status(
                        query(scene, id).0,
                        GlcolStatus::UnknownMesh,
                        "query unknown",
                    ),
                }
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
    // Every live mesh's answer at the end.
    for i in 0..meshes.len() {
        check_query(scene, &meshes, i, epsilon);
    }
    unsafe { glcol_scene_destroy(scene) };
}
