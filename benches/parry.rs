//! parry3d-f64 0.31 against glcollide in one process, on the scenes and frames that
//! `bench/peers/build/glcol_peers --dump DIR` wrote (the same frames the C++ peers saw), and
//! the bytes each library holds per polygon.
//!   cargo bench --bench parry -- DIR [OUT.csv]
//! DIR holds `*.scene` files; OUT.csv (default bench-results/parry.csv) gets one row per
//! scene and library, in the columns of `bench-results/peers.csv`, and OUT's directory gets
//! `memory.csv`.
//!
//! parry: `TriMesh::with_flags(.., DEFORMABLE)`, `set_vertices` per frame (refits its BVH),
//! `bvh().leaf_pairs(..)` then `intersection_test_support_map_support_map` (GJK, f64): the
//! sound configuration of ../shared/peers/REPORT.md §5.

use std::io::Read;
use std::time::Instant;

use glcollide::{Positions, Scene, SceneConfig};
use parry3d_f64::math::{Pose, Vector};
use parry3d_f64::query::details::intersection_test_support_map_support_map;
use parry3d_f64::shape::{TriMesh, TriMeshFlags};

struct Dump {
    name: String,
    group: String,
    extent: f64,
    ta: Vec<[u32; 3]>,
    tb: Vec<[u32; 3]>,
    nva: usize,
    nvb: usize,
    frames_a: Vec<Vec<[f32; 3]>>,
    frames_b: Vec<Vec<[f32; 3]>>,
    checks: Vec<(usize, Vec<(u32, u32)>)>,
}

fn read_dump(path: &std::path::Path) -> Dump {
    let mut bytes = Vec::new();
    std::fs::File::open(path)
        .unwrap()
        .read_to_end(&mut bytes)
        .unwrap();
    assert_eq!(
        &bytes[..8],
        b"GLCSCN01",
        "{}: not a scene dump",
        path.display()
    );
    let mut at = 8;
    let mut u64_ = || {
        let v = u64::from_le_bytes(bytes[at..at + 8].try_into().unwrap());
        at += 8;
        v as usize
    };
    let (nva, nta, nvb, ntb, frames, nchk) = (u64_(), u64_(), u64_(), u64_(), u64_(), u64_());
    let extent = f64::from_le_bytes(bytes[at..at + 8].try_into().unwrap());
    at += 8;
    let group = String::from_utf8_lossy(&bytes[at..at + 16])
        .trim()
        .to_string();
    at += 16;
    let u32s = |at: &mut usize, n: usize| -> Vec<u32> {
        let v = bytes[*at..*at + 4 * n]
            .chunks_exact(4)
            .map(|c| u32::from_le_bytes(c.try_into().unwrap()))
            .collect();
        *at += 4 * n;
        v
    };
    let tri = |v: Vec<u32>| v.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect();
    let ta = tri(u32s(&mut at, 3 * nta));
    let tb = tri(u32s(&mut at, 3 * ntb));
    let pts = |at: &mut usize, n: usize| -> Vec<[f32; 3]> {
        let v: Vec<[f32; 3]> = bytes[*at..*at + 12 * n]
            .chunks_exact(12)
            .map(|c| [0, 1, 2].map(|k| f32::from_le_bytes(c[4 * k..4 * k + 4].try_into().unwrap())))
            .collect();
        *at += 12 * n;
        v
    };
    let (mut frames_a, mut frames_b) = (Vec::new(), Vec::new());
    for _ in 0..frames {
        frames_a.push(pts(&mut at, nva));
        frames_b.push(pts(&mut at, nvb));
    }
    let mut checks = Vec::new();
    for _ in 0..nchk {
        let f = u64::from_le_bytes(bytes[at..at + 8].try_into().unwrap()) as usize;
        let n = u64::from_le_bytes(bytes[at + 8..at + 16].try_into().unwrap()) as usize;
        at += 16;
        let v = u32s(&mut at, 2 * n);
        checks.push((f, v.chunks_exact(2).map(|c| (c[0], c[1])).collect()));
    }
    Dump {
        name: path.file_stem().unwrap().to_string_lossy().into(),
        group,
        extent,
        ta,
        tb,
        nva,
        nvb,
        frames_a,
        frames_b,
        checks,
    }
}

fn median(v: &mut [f64]) -> f64 {
    v.sort_by(f64::total_cmp);
    let n = v.len();
    if n % 2 == 1 {
        v[n / 2]
    } else {
        0.5 * (v[n / 2 - 1] + v[n / 2])
    }
}

trait Lib {
    fn name(&self) -> &'static str;
    /// Untimed: the frame's positions in the library's own type.
    fn prepare(&mut self, a: &[[f32; 3]], b: &[[f32; 3]]);
    fn update(&mut self, a: &[[f32; 3]], b: &[[f32; 3]]);
    fn query(&mut self, out: &mut Vec<(u32, u32)>);
}

struct Glcol {
    scene: Scene,
    ia: u32,
    ib: u32,
}

impl Lib for Glcol {
    fn name(&self) -> &'static str {
        "glcollide"
    }
    fn prepare(&mut self, _: &[[f32; 3]], _: &[[f32; 3]]) {}
    fn update(&mut self, a: &[[f32; 3]], b: &[[f32; 3]]) {
        self.scene
            .update_positions(self.ia, 0, Positions::from_points(a))
            .unwrap();
        self.scene
            .update_positions(self.ib, 0, Positions::from_points(b))
            .unwrap();
    }
    fn query(&mut self, out: &mut Vec<(u32, u32)>) {
        let c = self.scene.query(self.ia).unwrap();
        out.clear();
        out.extend(c.iter().map(|c| (c.reference_polygon, c.other_polygon)));
    }
}

struct Parry {
    a: TriMesh,
    b: TriMesh,
    va: Vec<Vector>,
    vb: Vec<Vector>,
}

fn to_f64(p: &[[f32; 3]], out: &mut Vec<Vector>) {
    out.clear();
    out.extend(
        p.iter()
            .map(|p| Vector::new(p[0] as f64, p[1] as f64, p[2] as f64)),
    );
}

impl Lib for Parry {
    fn name(&self) -> &'static str {
        "parry3d_f64"
    }
    fn prepare(&mut self, a: &[[f32; 3]], b: &[[f32; 3]]) {
        to_f64(a, &mut self.va);
        to_f64(b, &mut self.vb);
    }
    fn update(&mut self, _: &[[f32; 3]], _: &[[f32; 3]]) {
        self.a.set_vertices(&self.va);
        self.b.set_vertices(&self.vb);
    }
    fn query(&mut self, out: &mut Vec<(u32, u32)>) {
        out.clear();
        for (i, j) in self
            .a
            .bvh()
            .leaf_pairs(self.b.bvh(), |n1, n2| n1.intersects(n2))
        {
            let (ta, tb) = (self.a.triangle(i), self.b.triangle(j));
            if intersection_test_support_map_support_map(&Pose::IDENTITY, &ta, &tb) {
                out.push((i, j));
            }
        }
    }
}

/// Bytes glcollide holds for a mesh, counted from its structures (src/mesh.rs, src/bvh):
/// slot positions (12 B) + slot -> vertex (4 B) + vertex -> slots (4 B per slot, 4 B per
/// vertex + 4), polygon slot indices (4 B per corner), leaf order -> polygon id (4 B), per
/// leaf two offsets (8 B) and a box (24 B); and the CPU backend's per-polygon box cache
/// (src/backend/cpu.rs BoxCache: a 24 B box + a 4 B stamp per polygon).
fn glcol_bytes(m: &glcollide::Mesh) -> (usize, usize) {
    let slots = m.slot_positions().len();
    let leaves = m.leaf_count();
    let structure = slots * 12
        + m.slot_vertices().len() * 4
        + slots * 4
        + (m.vertex_count() + 1) * 4
        + m.polygon_slots().len() * 4
        + m.polygon_ids().len() * 4
        + (leaves + 1) * 8
        + leaves * std::mem::size_of::<glcollide::internals::Aabb>();
    let cache = m.polygon_count() * (std::mem::size_of::<glcollide::internals::Aabb>() + 4);
    (structure, cache)
}

fn main() {
    let args: Vec<String> = std::env::args()
        .skip(1)
        .filter(|a| !a.starts_with("--"))
        .collect();
    let dir = args
        .first()
        .map(String::as_str)
        .unwrap_or("/tmp/glcol-scenes");
    let out = args
        .get(1)
        .cloned()
        .unwrap_or_else(|| concat!(env!("CARGO_MANIFEST_DIR"), "/bench-results/parry.csv").into());
    let mut names: Vec<_> = std::fs::read_dir(dir)
        .unwrap_or_else(|e| panic!("{dir}: {e} (run glcol_peers --dump {dir} first)"))
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|e| e == "scene"))
        .collect();
    names.sort();
    let mut csv = String::from(
        "scene,group,engine,eps_rel,eps_abs,leaf,tris_a,tris_b,frames,update_us,query_us,total_us,pairs_median,\
         check_frames,ref_pairs,missed,extra,max_extra_dist,max_extra_dist_rel,bytes,bytes_per_polygon,note\n",
    );
    let mut mem = String::from(
        "scene,library,polygons,structure_bytes,cache_bytes,bytes_per_polygon,refit_b_us,note\n",
    );
    for path in names {
        let d = read_dump(&path);
        let polys = d.ta.len() + d.tb.len();
        eprintln!(
            "== {} ({}): {} vs {} triangles, {} frames",
            d.name,
            d.group,
            d.ta.len(),
            d.tb.len(),
            d.frames_a.len()
        );
        let flat = |t: &[[u32; 3]]| t.iter().flatten().copied().collect::<Vec<u32>>();
        // One thread, like parry's loop here.
        let mut scene = Scene::new(SceneConfig {
            threads: 1,
            ..SceneConfig::default()
        })
        .unwrap();
        let ia = scene
            .create_mesh(Positions::from_points(&d.frames_a[0]), &flat(&d.ta), 3)
            .unwrap();
        let ib = scene
            .create_mesh(Positions::from_points(&d.frames_b[0]), &flat(&d.tb), 3)
            .unwrap();
        let (mut gs, mut gc) = (0, 0);
        for id in [ia, ib] {
            let (s, c) = glcol_bytes(scene.mesh(id).unwrap());
            gs += s;
            gc += c;
        }
        // refit alone (no copy, no finiteness check) of the other mesh, median of 200
        let refit_b = {
            let mut m = scene.mesh(ib).unwrap().clone();
            let mut t: Vec<f64> = (0..200)
                .map(|_| {
                    let t0 = Instant::now();
                    m.refit();
                    std::hint::black_box(m.root());
                    t0.elapsed().as_secs_f64() * 1e6
                })
                .collect();
            median(&mut t)
        };
        mem += &format!(
            "{},glcollide,{},{},{},{:.2},{:.2},\"slots, slot/vertex maps, polygon corners and ids, leaf offsets and boxes; cache = CPU backend's per-polygon box cache (28 B/polygon)\"\n",
            d.name,
            polys,
            gs,
            gc,
            (gs + gc) as f64 / polys as f64,
            refit_b
        );
        let glcol = Glcol { scene, ia, ib };
        let mk = |v: &[[f32; 3]], t: &[[u32; 3]]| {
            let mut vv = Vec::new();
            to_f64(v, &mut vv);
            TriMesh::with_flags(vv, t.to_vec(), TriMeshFlags::DEFORMABLE).unwrap()
        };
        let parry = Parry {
            a: mk(&d.frames_a[0], &d.ta),
            b: mk(&d.frames_b[0], &d.tb),
            va: Vec::new(),
            vb: Vec::new(),
        };
        let pbytes: usize = [&parry.a, &parry.b]
            .iter()
            .map(|m| {
                m.bvh().total_memory_size()
                    + std::mem::size_of_val(m.vertices())
                    + m.indices().len() * 12
            })
            .sum();
        mem += &format!(
            "{},parry3d_f64,{},{},0,{:.2},,\"Bvh::total_memory_size() + vertices (24 B) + indices (12 B)\"\n",
            d.name,
            polys,
            pbytes,
            pbytes as f64 / polys as f64
        );
        let libs: Vec<(Box<dyn Lib>, usize)> =
            vec![(Box::new(glcol), gs + gc), (Box::new(parry), pbytes)];
        for (mut lib, bytes) in libs {
            let (mut up, mut q, mut tot, mut np) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
            let mut out = Vec::new();
            let (mut nchk, mut refn, mut missed, mut extra) = (0, 0, 0, 0);
            for f in 0..d.frames_a.len().min(2) {
                lib.prepare(&d.frames_a[f], &d.frames_b[f]);
                lib.update(&d.frames_a[f], &d.frames_b[f]);
                lib.query(&mut out);
            }
            for f in 0..d.frames_a.len() {
                let (a, b) = (&d.frames_a[f], &d.frames_b[f]);
                lib.prepare(a, b);
                let t0 = Instant::now();
                lib.update(a, b);
                let t1 = Instant::now();
                lib.query(&mut out);
                let t2 = Instant::now();
                up.push((t1 - t0).as_secs_f64() * 1e6);
                q.push((t2 - t1).as_secs_f64() * 1e6);
                tot.push((t2 - t0).as_secs_f64() * 1e6);
                out.sort_unstable();
                out.dedup();
                np.push(out.len() as f64);
                if let Some((_, r)) = d.checks.iter().find(|c| c.0 == f) {
                    nchk += 1;
                    refn += r.len();
                    missed += r.iter().filter(|p| out.binary_search(p).is_err()).count();
                    extra += out.iter().filter(|p| r.binary_search(p).is_err()).count();
                }
            }
            let (u, qq, t, n) = (
                median(&mut up),
                median(&mut q),
                median(&mut tot),
                median(&mut np),
            );
            eprintln!(
                "  {:<14} update {:>10.1} us  query {:>10.1} us  total {:>10.1} us  pairs {:>6}  missed {} extra {}",
                lib.name(),
                u,
                qq,
                t,
                n,
                missed,
                extra
            );
            csv += &format!(
                "{},{},{},0,0,0,{},{},{},{:.3},{:.3},{:.3},{:.1},{},{},{},{},0,0,{},{:.2},\"extent {}\"\n",
                d.name,
                d.group,
                lib.name(),
                d.ta.len(),
                d.tb.len(),
                d.frames_a.len(),
                u,
                qq,
                t,
                n,
                nchk,
                refn,
                missed,
                extra,
                bytes,
                bytes as f64 / polys as f64,
                d.extent
            );
        }
        let _ = (d.nva, d.nvb);
    }
    std::fs::write(&out, csv).unwrap();
    let mem_path = std::path::Path::new(&out).with_file_name("memory_rust.csv");
    std::fs::write(&mem_path, mem).unwrap();
    eprintln!("wrote {out} and {}", mem_path.display());
}
