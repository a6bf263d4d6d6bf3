//! The GL_SELECT backend: the paper as published. Every viewing volume is an orthographic
//! camera in `glRenderMode(GL_SELECT)`; candidates are drawn with one name each (boxes as
//! triangle strips, polygons as triangles) and the hit records say which were drawn inside.
//! Step 5 uses the polygon viewing volume of section 2.3: an orthographic box around the
//! polygon's 2D bounding box in its own plane, depth `[-h, h]` along its normal, and
//! `glClipPlane` for the slanted edges (a quad is its two triangles; a degenerate polygon is
//! the thin box of `geom::volume`).
//!
//! Precision. Coordinates reach the GL relative to a local origin chosen in `f64` per
//! volume (the volume box's centre, or the reference polygon's first vertex), so float clip
//! maths has the precision of the local size, not of the distance to the world origin.
//! Volumes are padded by `PAD_REL × (local size)` (far above float rounding), so selection
//! never loses a primitive that meets the volume. Hence steps 1-4 give a superset of the
//! exact box tests, and step 5's GL hits are a superset of the pairs that meet the viewing
//! volume; each step-5 hit is then confirmed on the CPU with the same test as the CPU
//! backend (the polygon's viewing volume in `f64`, or exact intersection), as CULLIDE does.
//! The final answer is therefore the CPU backend's answer for the same epsilon: no
//! intersecting pair is ever missed, and extra pairs are within `epsilon / 2`.
//!
//! State: everything goes through [`StateGuard`]; our own 1×1 framebuffer is bound while
//! selecting (selection reports nothing without a complete framebuffer) and deleted after.

use glow::HasContext;

use super::{Backend, Batch, Engine, Hit, QueryMeshes, Selector, Step, StepQuery};
use crate::error::{Error, ErrorKind, Result};
use crate::geom::polygon::polygon_meets;
use crate::geom::predicates::collinear;
use crate::geom::{Aabb, P3};
use crate::gpu::state::{clip_planes, StateGuard, Uses};
use crate::gpu::{unavailable, Gl};

/// Volume padding relative to the local size of a volume and its candidates: 2^-16, about
/// 256 float ulps, well above the rounding of the transform and of clipping.
pub const PAD_REL: f64 = 1.0 / 65536.0;

const SELECT: u32 = 0x1C02;
const RENDER: u32 = 0x1C00;
const MODELVIEW: u32 = 0x1700;
const PROJECTION: u32 = 0x1701;
const NAME_STACK_DEPTH: u32 = 0x0D70;
const TRIANGLES: u32 = 0x0004;
const TRIANGLE_STRIP: u32 = 0x0005;
const LINE_STRIP: u32 = 0x0003;
const POINTS: u32 = 0x0000;

/// The GL_SELECT backend.
pub struct GlSelectSelector {
    gl: Gl,
    s: Scratch,
}

/// Buffers reused from call to call.
#[derive(Default)]
struct Scratch {
    select_buf: Vec<u32>,
    boxes: Vec<Aabb>,
    tris: Vec<([[P3; 3]; 2], usize, [bool; 2])>,
    /// glRenderMode(GL_RENDER) calls (each waits for the GL) since `take_readbacks`.
    readbacks: u32,
}

impl GlSelectSelector {
    /// Needs fixed-function entry points: a compatibility-profile context or GL <= 3.0.
    pub fn new(gl: Gl) -> Result<GlSelectSelector> {
        if !gl.info.fixed_function {
            return Err(unavailable(format!(
                "GLCOL_BACKEND_GL_SELECT needs glRenderMode(GL_SELECT), which a {} context does \
                 not have (\"{}\"); create a compatibility-profile context (or GL <= 3.0), or \
                 use GLCOL_BACKEND_GL_COMPUTE",
                if gl.info.core_profile {
                    "core-profile"
                } else {
                    "context without fixed-function entry points"
                },
                gl.info.version_string
            )));
        }
        if gl.info.version < (3, 0) {
            return Err(unavailable(format!(
                "GLCOL_BACKEND_GL_SELECT needs framebuffer objects (GL 3.0); the context is \"{}\"",
                gl.info.version_string
            )));
        }
        if clip_planes(&gl) < 3 {
            return Err(unavailable("fewer than 3 user clip planes"));
        }
        Ok(GlSelectSelector {
            gl,
            s: Scratch::default(),
        })
    }

    pub fn gl(&self) -> &Gl {
        &self.gl
    }
}

/// A volume as the GL sees it: projection (column-major, f64) with the modelview the
/// identity, up to three clip planes (eye = local coordinates), and the local origin.
struct Volume {
    origin: P3,
    projection: [f64; 16],
    planes: Vec<[f64; 4]>,
}

/// Orthographic projection of the box `[lo, hi]` of the frame with orthonormal rows `r`
/// (local coordinates -> clip cube).
fn ortho(r: [P3; 3], lo: P3, hi: P3) -> [f64; 16] {
    let mut m = [0.0; 16];
    for (row, axis) in r.iter().enumerate() {
        let s = 2.0 / (hi[row] - lo[row]);
        let t = -(hi[row] + lo[row]) / (hi[row] - lo[row]);
        for (col, a) in axis.iter().enumerate() {
            m[col * 4 + row] = s * a;
        }
        m[12 + row] = t;
    }
    m[15] = 1.0;
    m
}

fn sub(a: &P3, b: &P3) -> P3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
fn dot(a: &P3, b: &P3) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
fn cross(a: &P3, b: &P3) -> P3 {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}
fn unit(a: &P3) -> P3 {
    let l = dot(a, a).sqrt();
    [a[0] / l, a[1] / l, a[2] / l]
}
fn widen(p: &[f32; 3]) -> P3 {
    [f64::from(p[0]), f64::from(p[1]), f64::from(p[2])]
}

const AXES: [P3; 3] = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];

/// A box volume grown by `h + pad` on every side, around its centre.
fn box_volume(b: &Aabb, h: f64, reach: f64) -> Volume {
    let lo = widen(&b.min);
    let hi = widen(&b.max);
    let origin = [0, 1, 2].map(|k| (lo[k] + hi[k]) / 2.0);
    let half = [0, 1, 2].map(|k| (hi[k] - lo[k]) / 2.0);
    let size = half.iter().fold(reach, |a, &b| a.max(b));
    let pad = h + PAD_REL * size + f64::MIN_POSITIVE;
    Volume {
        origin,
        projection: ortho(
            AXES,
            [0, 1, 2].map(|k| -half[k] - pad),
            [0, 1, 2].map(|k| half[k] + pad),
        ),
        planes: Vec::new(),
    }
}

/// The section 2.3 volume of triangle `t`, half-depth `h`, padded for a local size `reach`.
fn triangle_volume(t: &[P3; 3], h: f64, reach: f64) -> Volume {
    let origin = t[0];
    let v = [[0.0; 3], sub(&t[1], &origin), sub(&t[2], &origin)];
    let size = v
        .iter()
        .flat_map(|p| p.iter())
        .fold(reach, |a, &b| a.max(b.abs()));
    let pad = PAD_REL * size + f64::MIN_POSITIVE;
    if collinear(&t[0], &t[1], &t[2]) {
        return degenerate_volume(origin, &v, h, pad);
    }
    let n = unit(&cross(&v[1], &v[2]));
    let u = unit(&v[1]);
    let w = cross(&n, &u);
    // 2D bounding box in the plane (u, w), depth along n.
    let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
    for p in &v {
        for (k, a) in [u, w].iter().enumerate() {
            let c = dot(a, p);
            lo[k] = lo[k].min(c);
            hi[k] = hi[k].max(c);
        }
    }
    lo = [lo[0] - pad, lo[1] - pad, -h - pad];
    hi = [hi[0] + pad, hi[1] + pad, h + pad];
    // Clip planes along the edges (n x e points inwards), moved out by pad.
    let planes = (0..3)
        .map(|i| {
            let p = v[i];
            let e = sub(&v[(i + 1) % 3], &p);
            let m = unit(&cross(&n, &e));
            [m[0], m[1], m[2], -dot(&m, &p) + pad]
        })
        .collect();
    Volume {
        origin,
        projection: ortho([u, w, n], lo, hi),
        planes,
    }
}

/// The thin box around a segment or point (as `geom::volume` builds it), padded.
fn degenerate_volume(origin: P3, v: &[P3; 3], h: f64, pad: f64) -> Volume {
    let (mut p, mut q, mut best) = (0, 0, 0.0);
    for i in 0..3 {
        for j in i + 1..3 {
            let d = sub(&v[j], &v[i]);
            if dot(&d, &d) > best {
                (p, q, best) = (i, j, dot(&d, &d));
            }
        }
    }
    let (u, r) = if best > 0.0 {
        (unit(&sub(&v[q], &v[p])), h / 2f64.sqrt())
    } else {
        ([1.0, 0.0, 0.0], h / 3f64.sqrt())
    };
    let k = if u[0].abs() <= u[1].abs() && u[0].abs() <= u[2].abs() {
        AXES[0]
    } else if u[1].abs() <= u[2].abs() {
        AXES[1]
    } else {
        AXES[2]
    };
    let w1 = unit(&cross(&u, &k));
    let w2 = cross(&u, &w1);
    let along = if best > 0.0 { 0.0 } else { r };
    let c = v[p];
    let lo = [
        dot(&u, &v[p]) - along - pad,
        dot(&w1, &c) - r - pad,
        dot(&w2, &c) - r - pad,
    ];
    let hi = [
        dot(&u, &v[q]) + along + pad,
        dot(&w1, &c) + r + pad,
        dot(&w2, &c) + r + pad,
    ];
    Volume {
        origin,
        projection: ortho([u, w1, w2], lo, hi),
        planes: Vec::new(),
    }
}

/// Largest coordinate distance from `o` of a set of boxes (the local size of a group).
fn reach(o: &P3, boxes: &[Aabb]) -> f64 {
    boxes.iter().fold(0.0, |a, b| {
        (0..3).fold(a, |a, k| {
            a.max((f64::from(b.min[k]) - o[k]).abs())
                .max((f64::from(b.max[k]) - o[k]).abs())
        })
    })
}

impl Selector for GlSelectSelector {
    fn backend(&self) -> Backend {
        Backend::GlSelect
    }

    fn take_readbacks(&mut self) -> u32 {
        std::mem::take(&mut self.s.readbacks)
    }

    fn engine(&mut self) -> Engine<'_> {
        Engine::Steps(self)
    }
}

impl StepQuery for GlSelectSelector {
    fn select(&mut self, q: &QueryMeshes<'_>, batch: &Batch, hits: &mut Vec<Hit>) -> Result<()> {
        let guard = StateGuard::enter(
            &self.gl,
            Uses {
                fixed_function: true,
                indexed_bindings: 0,
            },
        )?;
        let h = q.gl_half_depth();
        let sc = &mut self.s;
        let gl = &self.gl;
        let g = &self.gl.gl;
        let f = self.gl.ff();
        let n_planes = clip_planes(&self.gl);
        let (fbo, rbo) = unsafe {
            let rbo = g.create_renderbuffer().map_err(gl_err)?;
            g.bind_renderbuffer(glow::RENDERBUFFER, Some(rbo));
            g.renderbuffer_storage(glow::RENDERBUFFER, glow::RGBA8, 1, 1);
            let fbo = g.create_framebuffer().map_err(gl_err)?;
            g.bind_framebuffer(glow::FRAMEBUFFER, Some(fbo));
            g.framebuffer_renderbuffer(
                glow::FRAMEBUFFER,
                glow::COLOR_ATTACHMENT0,
                glow::RENDERBUFFER,
                Some(rbo),
            );
            (fbo, rbo)
        };
        let res = (|| -> Result<()> {
            unsafe {
                let status = g.check_framebuffer_status(glow::FRAMEBUFFER);
                if status != glow::FRAMEBUFFER_COMPLETE {
                    return Err(Error::new(
                        ErrorKind::GlError,
                        format!("our 1x1 selection framebuffer is incomplete (0x{status:x})"),
                    ));
                }
                g.viewport(0, 0, 1, 1);
                for cap in [
                    glow::CULL_FACE,
                    glow::DEPTH_CLAMP,
                    glow::RASTERIZER_DISCARD,
                    glow::PRIMITIVE_RESTART,
                ] {
                    g.disable(cap);
                }
                for k in 0..n_planes {
                    g.disable(glow::CLIP_DISTANCE0 + k);
                }
                g.polygon_mode(glow::FRONT_AND_BACK, glow::FILL);
                g.use_program(None);
                if gl.info.program_pipelines {
                    f.BindProgramPipeline(0); // the guard gives the host's back
                }
                g.bind_vertex_array(None);
                f.MatrixMode(MODELVIEW);
                f.LoadIdentity();
            }
            gl.check("setting up selection")?;
            let mut depth = 0;
            unsafe { f.GetIntegerv(NAME_STACK_DEPTH, &mut depth) };
            let record = 3 + depth.max(0) as usize + 1;
            for grp in &batch.groups {
                let cands =
                    &batch.candidates[grp.candidates.start as usize..grp.candidates.end as usize];
                sc.boxes.clear();
                match batch.step {
                    Step::BoxesInBoxes => sc.boxes.extend(cands.iter().map(|&c| q.boxed(c))),
                    _ => sc
                        .boxes
                        .extend(cands.iter().map(|&c| q.mesh(c).poly_box(c.index as usize))),
                }
                if batch.step != Step::BoxesInBoxes {
                    sc.tris.clear();
                    sc.tris.extend(cands.iter().map(|&c| {
                        let mut t = [[[0.0; 3]; 3]; 2];
                        let n = q.mesh(c).triangles(c.index as usize, &mut t);
                        let flat = [0, 1].map(|i| i < n && collinear(&t[i][0], &t[i][1], &t[i][2]));
                        (t, n, flat)
                    }));
                }
                let need = cands.len() * record + 16;
                if sc.select_buf.len() < need {
                    sc.select_buf = vec![0; need];
                }
                unsafe {
                    f.SelectBuffer(sc.select_buf.len() as i32, sc.select_buf.as_mut_ptr());
                }
                for vi in grp.volumes.clone() {
                    let v = batch.volumes[vi as usize];
                    let first = hits.len();
                    match batch.step {
                        Step::BoxesInBoxes | Step::PolygonsInBoxes => {
                            let vb = q.boxed(v);
                            let centre = [0, 1, 2]
                                .map(|k| (f64::from(vb.min[k]) + f64::from(vb.max[k])) / 2.0);
                            let vol = box_volume(&vb, h, reach(&centre, &sc.boxes));
                            run_volume(
                                gl,
                                sc,
                                &vol,
                                batch.step,
                                record,
                                vi,
                                grp.candidates.start,
                                hits,
                            )?;
                        }
                        Step::PolygonsInPolygons => {
                            let m = q.mesh(v);
                            let mut vt = [[[0.0; 3]; 3]; 2];
                            let nv = m.triangles(v.index as usize, &mut vt);
                            for t in &vt[..nv] {
                                let vol = triangle_volume(t, h, reach(&t[0], &sc.boxes));
                                run_volume(
                                    gl,
                                    sc,
                                    &vol,
                                    batch.step,
                                    record,
                                    vi,
                                    grp.candidates.start,
                                    hits,
                                )?;
                            }
                            // Quads: a candidate may be in both triangles' volumes.
                            hits[first..].sort_unstable();
                            let mut w = first;
                            for r in first..hits.len() {
                                if r == first || hits[r] != hits[w - 1] {
                                    hits[w] = hits[r];
                                    w += 1;
                                }
                            }
                            hits.truncate(w);
                            // Confirm on the CPU with the CPU backend's test at the epsilon
                            // asked for (the GL used at least the minimum depth, so it lost
                            // nothing): exact at epsilon 0.
                            let tris = &sc.tris;
                            let base = grp.candidates.start;
                            let mut w = first;
                            for r in first..hits.len() {
                                let hit = hits[r];
                                let (ct, nc, _) = &tris[(hit.candidate - base) as usize];
                                if polygon_meets(&vt, nv, ct, *nc, q.half_depth) {
                                    hits[w] = hit;
                                    w += 1;
                                }
                            }
                            hits.truncate(w);
                        }
                    }
                }
            }
            gl.check("selection")
        })();
        unsafe {
            g.delete_framebuffer(fbo);
            g.delete_renderbuffer(rbo);
        }
        let done = guard.finish();
        res?;
        done
    }
}

fn gl_err(e: String) -> Error {
    Error::new(ErrorKind::GlError, e)
}

/// One selection pass: the group's candidates drawn into one volume.
fn run_volume(
    gl: &Gl,
    sc: &mut Scratch,
    vol: &Volume,
    step: Step,
    record: usize,
    vi: u32,
    cand_base: u32,
    hits: &mut Vec<Hit>,
) -> Result<()> {
    let f = gl.ff();
    let o = vol.origin;
    let l = |p: &[f32; 3]| {
        [
            f64::from(p[0]) - o[0],
            f64::from(p[1]) - o[1],
            f64::from(p[2]) - o[2],
        ]
    };
    let n = unsafe {
        f.MatrixMode(PROJECTION);
        f.LoadMatrixd(vol.projection.as_ptr());
        f.MatrixMode(MODELVIEW);
        for (k, eq) in vol.planes.iter().enumerate() {
            f.ClipPlane(glow::CLIP_DISTANCE0 + k as u32, eq.as_ptr());
            gl.gl.enable(glow::CLIP_DISTANCE0 + k as u32);
        }
        f.RenderMode(SELECT);
        f.PushName(0);
        match step {
            Step::BoxesInBoxes => {
                // The volume's centre in local coordinates is the origin for box volumes.
                for (i, b) in sc.boxes.iter().enumerate() {
                    f.LoadName(i as u32);
                    let lo = l(&b.min);
                    let hi = l(&b.max);
                    let c = |x: usize, y: usize, z: usize| {
                        [[lo[0], hi[0]][x], [lo[1], hi[1]][y], [lo[2], hi[2]][z]]
                    };
                    let strip = |pts: &[[f64; 3]]| {
                        f.Begin(TRIANGLE_STRIP);
                        for p in pts {
                            f.Vertex3d(p[0], p[1], p[2]);
                        }
                        f.End();
                    };
                    // The four sides, then bottom and top.
                    strip(&[
                        c(0, 0, 0),
                        c(0, 0, 1),
                        c(1, 0, 0),
                        c(1, 0, 1),
                        c(1, 1, 0),
                        c(1, 1, 1),
                        c(0, 1, 0),
                        c(0, 1, 1),
                        c(0, 0, 0),
                        c(0, 0, 1),
                    ]);
                    strip(&[c(0, 0, 0), c(1, 0, 0), c(0, 1, 0), c(1, 1, 0)]);
                    strip(&[c(0, 0, 1), c(1, 0, 1), c(0, 1, 1), c(1, 1, 1)]);
                    // A volume wholly inside the box meets no face: a cross-section of
                    // the box through the volume's centre (local z = 0, clamped into the
                    // box) catches that case.
                    let z = 0f64.clamp(lo[2], hi[2]);
                    strip(&[
                        [lo[0], lo[1], z],
                        [hi[0], lo[1], z],
                        [lo[0], hi[1], z],
                        [hi[0], hi[1], z],
                    ]);
                }
            }
            _ => {
                for (i, (t, nt, flat)) in sc.tris.iter().enumerate() {
                    f.LoadName(i as u32);
                    let lt = |p: &P3| [p[0] - o[0], p[1] - o[1], p[2] - o[2]];
                    f.Begin(TRIANGLES);
                    for tri in &t[..*nt] {
                        for p in tri {
                            let p = lt(p);
                            f.Vertex3d(p[0], p[1], p[2]);
                        }
                    }
                    f.End();
                    // Degenerate triangles: also as a segment and a point, so a
                    // zero-area primitive is never dropped by the rasteriser's setup.
                    for (tri, _) in t[..*nt].iter().zip(flat).filter(|(_, &fl)| fl) {
                        f.Begin(LINE_STRIP);
                        for p in tri.iter().chain(std::iter::once(&tri[0])) {
                            let p = lt(p);
                            f.Vertex3d(p[0], p[1], p[2]);
                        }
                        f.End();
                        f.Begin(POINTS);
                        for p in tri {
                            let p = lt(p);
                            f.Vertex3d(p[0], p[1], p[2]);
                        }
                        f.End();
                    }
                }
            }
        }
        f.PopName();
        let n = f.RenderMode(RENDER);
        sc.readbacks += 1;
        for k in 0..vol.planes.len() {
            gl.gl.disable(glow::CLIP_DISTANCE0 + k as u32);
        }
        n
    };
    if n < 0 {
        return Err(Error::new(
            ErrorKind::Internal,
            "selection buffer overflow (sized for every candidate: a bug)",
        ));
    }
    let mut at = 0;
    for _ in 0..n {
        let names = sc.select_buf[at] as usize;
        if names + 3 > record || names == 0 {
            return Err(Error::new(
                ErrorKind::Internal,
                format!("unexpected selection hit record with {names} names"),
            ));
        }
        let name = sc.select_buf[at + 2 + names];
        at += 3 + names;
        hits.push(Hit {
            volume: vi,
            candidate: cand_base + name,
        });
    }
    Ok(())
}
