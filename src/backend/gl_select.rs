//! The GL_SELECT backend: the paper as published. Every viewing volume is an orthographic
//! camera in `glRenderMode(GL_SELECT)`; candidates are drawn with one name each (boxes as
//! triangle strips, polygons as triangles) and the hit records say which were drawn inside.
//! Step 5 uses the polygon viewing volume of section 2.3 as `geom::volume` builds it: an
//! orthographic box around the polygon's 2D bounding box in its own plane, depth `[-h, h]`
//! along its normal, and `glClipPlane` for the slanted edges (a quad is its two triangles; a
//! degenerate polygon is the volume's thin box).
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

#![deny(unsafe_op_in_unsafe_fn)]

use glow::HasContext;
use nalgebra::{Matrix4, Vector3};

use super::{Backend, Batch, Engine, Group, Hit, Prim, QueryMeshes, Selector, Step, StepQuery};
use crate::error::{Error, ErrorKind, Result};
use crate::geom::polygon::polygon_meets;
use crate::geom::predicates::collinear;
use crate::geom::volume::Cell;
use crate::geom::{widen, Aabb, P3};
use crate::gpu::compat;
use crate::gpu::state::{clip_planes, StateGuard, Uses};
use crate::gpu::{gl_err, unavailable, Gl};

/// Volume padding relative to the local size of a volume and its candidates: 2^-16, about
/// 256 float ulps, well above the rounding of the transform and of clipping.
pub const PAD_REL: f64 = 1.0 / 65536.0;

/// The state the guard saves around our work: the common and the fixed-function state.
const USES: Uses = Uses {
    fixed_function: true,
    indexed_bindings: 0,
};

type V3 = Vector3<f64>;

/// The GL_SELECT backend.
pub struct GlSelectSelector {
    gl: Gl,
    s: Scratch,
}

/// A candidate polygon: its triangles (`tris[..n]`) and which of them are degenerate.
type Candidate = ([[P3; 3]; 2], usize, [bool; 2]);

/// Buffers reused from call to call.
#[derive(Default)]
struct Scratch {
    select_buf: Vec<u32>,
    /// The group's candidates' boxes (the boxes themselves in steps 1-2).
    boxes: Vec<Aabb>,
    /// The group's candidate polygons (steps 3-5).
    tris: Vec<Candidate>,
    /// glRenderMode(GL_RENDER) calls (each waits for the GL) since `take_readbacks`.
    readbacks: u32,
}

impl GlSelectSelector {
    /// Needs fixed-function entry points: a compatibility-profile context or GL <= 3.0,
    /// with framebuffer objects (GL 3.0) and 3 user clip planes.
    pub fn new(mut gl: Gl) -> Result<GlSelectSelector> {
        if !gl.info.fixed_function {
            return Err(unavailable(format!(
                "backend GL_SELECT needs glRenderMode(GL_SELECT), which a {} context does not \
                 have (\"{}\"); create a compatibility-profile context (or GL <= 3.0), or use \
                 backend GL_COMPUTE",
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
                "backend GL_SELECT needs framebuffer objects (GL 3.0); the context is \"{}\"",
                gl.info.version_string
            )));
        }
        if clip_planes(&gl) < 3 {
            return Err(unavailable("fewer than 3 user clip planes"));
        }
        gl.adopt_context(USES)?;
        Ok(GlSelectSelector {
            gl,
            s: Scratch::default(),
        })
    }
}

/// A volume as the GL sees it: projection (column-major, f64) with the modelview the
/// identity, up to three clip planes (eye = local coordinates), and the local origin.
struct Volume {
    origin: P3,
    projection: [f64; 16],
    planes: [[f64; 4]; 3],
    n_planes: usize,
}

impl Volume {
    fn planes(&self) -> &[[f64; 4]] {
        &self.planes[..self.n_planes]
    }
}

/// Orthographic projection of the box `[lo, hi]` of the frame with orthonormal `axes`
/// (local coordinates -> clip cube).
fn ortho(axes: [V3; 3], lo: V3, hi: V3) -> [f64; 16] {
    let mut m = Matrix4::identity();
    for (row, a) in axes.iter().enumerate() {
        let s = 2.0 / (hi[row] - lo[row]);
        for col in 0..3 {
            m[(row, col)] = s * a[col];
        }
        m[(row, 3)] = -(hi[row] + lo[row]) / (hi[row] - lo[row]);
    }
    let mut out = [0.0; 16];
    out.copy_from_slice(m.as_slice()); // column-major, as glLoadMatrixd takes it
    out
}

/// A box volume grown by `h + pad` on every side, around its centre.
fn box_volume(b: &Aabb, h: f64, reach: f64) -> Volume {
    let (lo, hi) = (V3::from(widen(&b.min)), V3::from(widen(&b.max)));
    let origin = (lo + hi) / 2.0;
    let half = (hi - lo) / 2.0;
    let pad = h + PAD_REL * half.max().max(reach) + f64::MIN_POSITIVE;
    let grown = half.add_scalar(pad);
    Volume {
        origin: origin.into(),
        projection: ortho([V3::x(), V3::y(), V3::z()], -grown, grown),
        planes: [[0.0; 4]; 3],
        n_planes: 0,
    }
}

/// The section 2.3 volume of triangle `t` with half-depth `h`, as `geom::volume` builds it
/// ([`Cell`]: the prism over the triangle, or the thin box around a degenerate one), padded
/// for a local size `reach`.
fn triangle_volume(t: &[P3; 3], h: f64, reach: f64) -> Volume {
    let cell = Cell::of_triangle(t, h);
    let o = V3::from(cell.origin());
    let v = t.map(|p| V3::from(p) - o);
    let size = v.iter().map(|p| p.amax()).fold(reach, f64::max);
    let pad = PAD_REL * size + f64::MIN_POSITIVE;
    let p = cell.planes();
    let normal = |k: usize| V3::new(p[k][0], p[k][1], p[k][2]);
    let mut volume = Volume {
        origin: cell.origin(),
        projection: [0.0; 16],
        planes: [[0.0; 4]; 3],
        n_planes: 0,
    };
    if cell.is_prism() {
        // Caps (n, -n) give the depth; the 2D bounding box in the plane (u, w) the sides;
        // the edges become clip planes, moved out by pad.
        let n = normal(0);
        let u = v[1].normalize();
        let w = n.cross(&u);
        let (mut lo, mut hi) = (V3::repeat(f64::INFINITY), V3::repeat(f64::NEG_INFINITY));
        for q in &v {
            let c = V3::new(u.dot(q), w.dot(q), 0.0);
            lo = lo.inf(&c);
            hi = hi.sup(&c);
        }
        lo.z = -p[0][3];
        hi.z = p[1][3];
        volume.projection = ortho([u, w, n], lo.add_scalar(-pad), hi.add_scalar(pad));
        for (dst, e) in volume.planes.iter_mut().zip(&p[2..5]) {
            *dst = [e[0], e[1], e[2], e[3] + pad];
        }
        volume.n_planes = 3;
    } else {
        // Three pairs of opposite faces: axis a, then -a (a . x in [-d_a, d_-a]).
        let axes = [normal(0), normal(2), normal(4)];
        let lo = V3::from_fn(|k, _| -p[2 * k][3]);
        let hi = V3::from_fn(|k, _| p[2 * k + 1][3]);
        volume.projection = ortho(axes, lo.add_scalar(-pad), hi.add_scalar(pad));
    }
    volume
}

/// Largest coordinate distance from `o` of a set of boxes (the local size of a group).
fn reach(o: &P3, boxes: &[Aabb]) -> f64 {
    let o = V3::from(*o);
    boxes.iter().fold(0.0, |a, b| {
        let lo = (V3::from(widen(&b.min)) - o).amax();
        let hi = (V3::from(widen(&b.max)) - o).amax();
        a.max(lo).max(hi)
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

    /// Holds nothing to refresh, but a query is a GL-backed call: refused (GL_UNAVAILABLE)
    /// without the scene's context current, even one that would ask the GL nothing.
    fn prepare(
        &mut self,
        _meshes: &mut std::collections::BTreeMap<u32, crate::mesh::Mesh>,
    ) -> Result<()> {
        self.gl.check_current()
    }

    fn release(&mut self) {
        self.gl.release_sentinel();
    }
}

impl StepQuery for GlSelectSelector {
    fn select(&mut self, q: &QueryMeshes<'_>, batch: &Batch, hits: &mut Vec<Hit>) -> Result<()> {
        let gl = &self.gl;
        let guard = StateGuard::enter(gl, USES)?;
        let res = Target::create(gl).and_then(|target| {
            let r = select_batch(gl, &mut self.s, q, batch, hits);
            target.delete(gl);
            r
        });
        let done = guard.finish();
        res?;
        done
    }
}

/// Our 1×1 framebuffer: selection reports nothing without a complete one.
struct Target {
    fbo: glow::NativeFramebuffer,
    rbo: glow::NativeRenderbuffer,
}

impl Target {
    /// Makes and binds it (the guard gives the host's bindings back).
    fn create(gl: &Gl) -> Result<Target> {
        let g = &gl.gl;
        // SAFETY: `gl` is loaded for the context current on this thread (every GL-backed
        // call's contract); the objects are ours, made here, and deleted on every path.
        unsafe {
            let rbo = g.create_renderbuffer().map_err(gl_err)?;
            let fbo = match g.create_framebuffer() {
                Ok(f) => f,
                Err(e) => {
                    g.delete_renderbuffer(rbo);
                    return Err(gl_err(e));
                }
            };
            let target = Target { fbo, rbo };
            g.bind_renderbuffer(glow::RENDERBUFFER, Some(rbo));
            g.renderbuffer_storage(glow::RENDERBUFFER, glow::RGBA8, 1, 1);
            g.bind_framebuffer(glow::FRAMEBUFFER, Some(fbo));
            g.framebuffer_renderbuffer(
                glow::FRAMEBUFFER,
                glow::COLOR_ATTACHMENT0,
                glow::RENDERBUFFER,
                Some(rbo),
            );
            let status = g.check_framebuffer_status(glow::FRAMEBUFFER);
            if status != glow::FRAMEBUFFER_COMPLETE {
                target.delete(gl);
                return Err(Error::new(
                    ErrorKind::GlError,
                    format!("our 1x1 selection framebuffer is incomplete (0x{status:x})"),
                ));
            }
            Ok(target)
        }
    }

    fn delete(self, gl: &Gl) {
        // SAFETY: as in `create`; ours, deleted once (`self` is consumed).
        unsafe {
            gl.gl.delete_framebuffer(self.fbo);
            gl.gl.delete_renderbuffer(self.rbo);
        }
    }
}

/// Every state selection relies on, set each call: a 1×1 viewport, no culling, clamping,
/// discard, restart or clip planes, filled polygons, no program, pipeline or VAO, and an
/// identity modelview.
fn set_up_selection(gl: &Gl) -> Result<()> {
    let (g, f) = (&gl.gl, gl.ff());
    // SAFETY: as in `Target::create`; fixed-function entry points exist (checked at
    // creation); the guard restores every state set here.
    unsafe {
        g.viewport(0, 0, 1, 1);
        for cap in [
            glow::CULL_FACE,
            glow::DEPTH_CLAMP,
            glow::RASTERIZER_DISCARD,
            glow::PRIMITIVE_RESTART,
        ] {
            g.disable(cap);
        }
        for k in 0..clip_planes(gl) {
            g.disable(glow::CLIP_DISTANCE0 + k);
        }
        g.polygon_mode(glow::FRONT_AND_BACK, glow::FILL);
        g.use_program(None);
        if gl.info.program_pipelines {
            f.BindProgramPipeline(0);
        }
        g.bind_vertex_array(None);
        f.MatrixMode(compat::MODELVIEW);
        f.LoadIdentity();
    }
    gl.check("setting up selection")
}

/// Words one hit record takes: hits, min depth, max depth, the host's names and ours.
fn hit_record_words(gl: &Gl) -> usize {
    // SAFETY: as in `set_up_selection`; a GL 1.0 query.
    let depth = unsafe { gl.gl.get_parameter_i32(compat::NAME_STACK_DEPTH) };
    3 + depth.max(0) as usize + 1
}

/// Answers a batch: for each group, its candidates are loaded once and drawn into each of
/// its volumes.
fn select_batch(
    gl: &Gl,
    sc: &mut Scratch,
    q: &QueryMeshes<'_>,
    batch: &Batch,
    hits: &mut Vec<Hit>,
) -> Result<()> {
    set_up_selection(gl)?;
    let pass = Pass {
        gl,
        step: batch.step,
        record: hit_record_words(gl),
        h: q.gl_half_depth(),
    };
    for grp in &batch.groups {
        sc.load_candidates(q, batch, grp);
        pass.size_select_buffer(sc)?;
        for vi in grp.volumes.clone() {
            let v = batch.volumes[vi as usize];
            let at = (vi, grp.candidates.start);
            match batch.step {
                Step::BoxesInBoxes | Step::PolygonsInBoxes => {
                    pass.select_in_box(sc, q.boxed(v), at, hits)?
                }
                Step::PolygonsInPolygons => pass.select_in_polygon(sc, q, v, at, hits)?,
            }
        }
    }
    gl.check("selection")
}

impl Scratch {
    /// The group's candidates: their boxes, and (steps 3-5) their triangles.
    fn load_candidates(&mut self, q: &QueryMeshes<'_>, batch: &Batch, grp: &Group) {
        let cands = &batch.candidates[grp.candidates.start as usize..grp.candidates.end as usize];
        self.boxes.clear();
        if batch.step == Step::BoxesInBoxes {
            self.boxes.extend(cands.iter().map(|&c| q.boxed(c)));
            return;
        }
        self.boxes
            .extend(cands.iter().map(|&c| q.mesh(c).poly_box(c.index as usize)));
        self.tris.clear();
        self.tris.extend(cands.iter().map(|&c| {
            let mut t = [[[0.0; 3]; 3]; 2];
            let n = q.mesh(c).triangles(c.index as usize, &mut t);
            let flat = [0, 1].map(|i| i < n && collinear(&t[i][0], &t[i][1], &t[i][2]));
            (t, n, flat)
        }));
    }
}

/// One step's selection passes: the GL, what is drawn, the hit record size and the half
/// depth.
struct Pass<'a> {
    gl: &'a Gl,
    step: Step,
    record: usize,
    h: f64,
}

impl Pass<'_> {
    /// A selection buffer with room for every candidate of the group, handed to the GL
    /// (its size is a `GLsizei`: a group too large for it is refused, not wrapped).
    fn size_select_buffer(&self, sc: &mut Scratch) -> Result<()> {
        let n = sc.boxes.len();
        let need = n
            .checked_mul(self.record)
            .and_then(|w| w.checked_add(16))
            .filter(|&w| i32::try_from(w).is_ok())
            .ok_or_else(|| {
                Error::new(
                    ErrorKind::Unsupported,
                    format!(
                        "a selection group of {n} candidates needs a selection buffer of more \
                         than 2^31 words"
                    ),
                )
            })?;
        if sc.select_buf.len() < need {
            sc.select_buf = vec![0; need];
        }
        // SAFETY: as in `set_up_selection`; the buffer lives in the scratch, unmoved until
        // the next call resizes it (after which this is called again), and the guard gives
        // the host's buffer back before the scratch is touched again.
        unsafe {
            self.gl
                .ff()
                .SelectBuffer(need as i32, sc.select_buf.as_mut_ptr());
        }
        Ok(())
    }

    /// Steps 1-4: the group's candidates drawn into the box `vb`; `at` is (volume index,
    /// first candidate index) in the batch.
    fn select_in_box(
        &self,
        sc: &mut Scratch,
        vb: Aabb,
        at: (u32, u32),
        hits: &mut Vec<Hit>,
    ) -> Result<()> {
        let centre = (V3::from(widen(&vb.min)) + V3::from(widen(&vb.max))) / 2.0;
        let vol = box_volume(&vb, self.h, reach(&centre.into(), &sc.boxes));
        self.run(sc, &vol, at, hits)
    }

    /// Step 5: the group's candidates drawn into the viewing volume of each triangle of
    /// polygon `v`, each hit once, then confirmed on the CPU with the CPU backend's test
    /// at the epsilon asked for (the GL used at least the minimum depth, so it lost
    /// nothing): exact at epsilon 0.
    fn select_in_polygon(
        &self,
        sc: &mut Scratch,
        q: &QueryMeshes<'_>,
        v: Prim,
        at: (u32, u32),
        hits: &mut Vec<Hit>,
    ) -> Result<()> {
        let first = hits.len();
        let mut vt = [[[0.0; 3]; 3]; 2];
        let nv = q.mesh(v).triangles(v.index as usize, &mut vt);
        for t in &vt[..nv] {
            let vol = triangle_volume(t, self.h, reach(&t[0], &sc.boxes));
            self.run(sc, &vol, at, hits)?;
        }
        // Quads: a candidate may be in both triangles' volumes.
        hits[first..].sort_unstable();
        let mut last = None;
        retain_from(hits, first, |hit| last.replace(*hit) != Some(*hit));
        let base = at.1;
        retain_from(hits, first, |hit| {
            let (ct, nc, _) = &sc.tris[(hit.candidate - base) as usize];
            polygon_meets(&vt, nv, ct, *nc, q.half_depth)
        });
        Ok(())
    }

    /// One selection pass: the group's candidates drawn into one volume; a hit per
    /// candidate drawn inside, named by its position in the batch.
    fn run(
        &self,
        sc: &mut Scratch,
        vol: &Volume,
        at: (u32, u32),
        hits: &mut Vec<Hit>,
    ) -> Result<()> {
        let f = self.gl.ff();
        // SAFETY: as in `set_up_selection`; the selection buffer holds a record for every
        // candidate drawn (`size_select_buffer`), and each Begin has its End.
        let n = unsafe {
            f.MatrixMode(compat::PROJECTION);
            f.LoadMatrixd(vol.projection.as_ptr());
            f.MatrixMode(compat::MODELVIEW);
            for (k, eq) in vol.planes().iter().enumerate() {
                f.ClipPlane(compat::CLIP_PLANE0 + k as u32, eq.as_ptr());
                self.gl.gl.enable(compat::CLIP_PLANE0 + k as u32);
            }
            f.RenderMode(compat::SELECT);
            f.PushName(0);
            match self.step {
                Step::BoxesInBoxes => draw_boxes(f, &sc.boxes, &vol.origin),
                _ => draw_polygons(f, &sc.tris, &vol.origin),
            }
            f.PopName();
            let n = f.RenderMode(compat::RENDER);
            for k in 0..vol.planes().len() {
                self.gl.gl.disable(compat::CLIP_PLANE0 + k as u32);
            }
            n
        };
        sc.readbacks += 1;
        read_hits(&sc.select_buf, n, self.record, at, hits)
    }
}

/// Keeps, of `hits[first..]`, those `keep` accepts, in order.
fn retain_from(hits: &mut Vec<Hit>, first: usize, mut keep: impl FnMut(&Hit) -> bool) {
    let mut w = first;
    for r in first..hits.len() {
        if keep(&hits[r]) {
            hits.swap(w, r);
            w += 1;
        }
    }
    hits.truncate(w);
}

/// Boxes as triangle strips, named by their position, relative to origin `o`.
///
/// # Safety
/// `f` was loaded for the context current on this thread, in selection mode with a name
/// pushed.
unsafe fn draw_boxes(f: &compat::Gl, boxes: &[Aabb], o: &P3) {
    let o = V3::from(*o);
    // SAFETY: the caller's contract; each Begin has its End.
    unsafe {
        let strip = |pts: &[V3]| {
            f.Begin(compat::TRIANGLE_STRIP);
            for p in pts {
                f.Vertex3d(p.x, p.y, p.z);
            }
            f.End();
        };
        for (i, b) in boxes.iter().enumerate() {
            f.LoadName(i as u32);
            let lo = V3::from(widen(&b.min)) - o;
            let hi = V3::from(widen(&b.max)) - o;
            let c = |x: usize, y: usize, z: usize| {
                V3::new([lo.x, hi.x][x], [lo.y, hi.y][y], [lo.z, hi.z][z])
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
            // A volume wholly inside the box meets no face: a cross-section of the box
            // through the volume's centre (local z = 0, clamped into the box) catches that.
            let z = 0f64.clamp(lo.z, hi.z);
            strip(&[
                V3::new(lo.x, lo.y, z),
                V3::new(hi.x, lo.y, z),
                V3::new(lo.x, hi.y, z),
                V3::new(hi.x, hi.y, z),
            ]);
        }
    }
}

/// Polygons as triangles, named by their position, relative to origin `o`; degenerate
/// triangles also as a segment and points, so a zero-area primitive is never dropped by
/// the rasteriser's setup.
///
/// # Safety
/// As [`draw_boxes`].
unsafe fn draw_polygons(f: &compat::Gl, polys: &[Candidate], o: &P3) {
    let o = V3::from(*o);
    // SAFETY: the caller's contract; each Begin has its End.
    unsafe {
        let vertex = |p: &P3| {
            let p = V3::from(*p) - o;
            f.Vertex3d(p.x, p.y, p.z);
        };
        for (i, (t, nt, flat)) in polys.iter().enumerate() {
            f.LoadName(i as u32);
            f.Begin(compat::TRIANGLES);
            t[..*nt].iter().flatten().for_each(vertex);
            f.End();
            for (tri, _) in t[..*nt].iter().zip(flat).filter(|(_, &fl)| fl) {
                f.Begin(compat::LINE_STRIP);
                tri.iter().chain(std::iter::once(&tri[0])).for_each(vertex);
                f.End();
                f.Begin(compat::POINTS);
                tri.iter().for_each(vertex);
                f.End();
            }
        }
    }
}

/// The hits of `n` selection records (glRenderMode's answer) as (volume, candidate) pairs,
/// `at` the volume's index and the group's first candidate in the batch.
fn read_hits(
    buf: &[u32],
    n: i32,
    record: usize,
    (volume, cand_base): (u32, u32),
    hits: &mut Vec<Hit>,
) -> Result<()> {
    if n < 0 {
        return Err(Error::new(
            ErrorKind::Internal,
            "selection buffer overflow (sized for every candidate: a bug)",
        ));
    }
    let mut at = 0;
    for _ in 0..n {
        let names = buf[at] as usize;
        if names + 3 > record || names == 0 {
            return Err(Error::new(
                ErrorKind::Internal,
                format!("unexpected selection hit record with {names} names"),
            ));
        }
        let name = buf[at + 2 + names];
        at += 3 + names;
        hits.push(Hit {
            volume,
            candidate: cand_base + name,
        });
    }
    Ok(())
}
