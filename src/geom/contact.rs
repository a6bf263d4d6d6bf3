//! Contact geometry of one polygon pair: where two polygons meet and how far apart to move
//! them, or how close they come (issue 13).
//!
//! A polygon is one triangle or a quad given as its two triangles `(v0,v1,v2)`, `(v0,v2,v3)`
//! (as `Mesh::triangles` fills them), in `f64` coordinates that are `f32` values widened (so
//! exact), or the `f64` world positions of a placed mesh (within the `f32` range; there the
//! differences below round once more, within the accuracy stated). The decisions (do they intersect, are they coplanar) are the exact predicates
//! the query uses. The constructions are `f64` and use only differences of the pair's own
//! vertices (exact for `f32` input; the general path subtracts the first vertex of `a`
//! first, a frame local to the pair), so a pair far from the world origin is computed as
//! well as one at it: the world's magnitude enters once, when a point is placed.
//!
//! Two triangles take a fast path (crossing or apart, no structures, the exact test's
//! permutation by table, no data-dependent branches in the separating-axis search), built
//! for AVX2 when the CPU has it (the same operations, so the same bits). Many pairs known
//! to intersect take that fast path four at a time in AVX2 lanes (`four.rs`, through
//! [`contact_geometry_many`]), again bit for bit. See [`contact_geometry`] for the
//! meaning of every output.

use std::mem::MaybeUninit;

use nalgebra::Vector3;

#[cfg(target_arch = "x86_64")]
use super::lanes::TriLanes;
use super::predicates::{collinear, orient2d, orient3d, orient3d_filtered, P3};
use super::tritri::{segments_intersect_2d, separated, triangles_intersect_with, Plane};

#[cfg(target_arch = "x86_64")]
mod edges;
#[cfg(target_arch = "x86_64")]
mod four;

type V = Vector3<f64>;

/// The geometry of one polygon pair (see [`contact_geometry`] for the exact rules).
/// (`repr(C)`: the four-lane kernel writes the ten `f64` as one run.)
#[derive(Clone, Copy, Debug, PartialEq)]
#[repr(C)]
pub struct ContactGeometry {
    /// Intersecting: one end of the intersection's longest extent. Otherwise: the point of
    /// polygon `a` closest to polygon `b`.
    pub point_a: [f64; 3],
    /// Intersecting: the other end (equal to `point_a` when they meet in one point).
    /// Otherwise: the point of polygon `b` closest to polygon `a`.
    pub point_b: [f64; 3],
    /// Unit length, always. Intersecting: moving polygon `a` by `depth * normal` separates
    /// the pair. Otherwise: the direction from `point_b` towards `point_a`.
    pub normal: [f64; 3],
    /// Intersecting: the penetration depth, `>= 0`. Otherwise: minus the distance.
    pub depth: f64,
    /// The closed polygons share at least one point (exact, as the query decides).
    pub intersecting: bool,
    /// Intersecting, and all vertices of both polygons lie in one plane (exact). Then
    /// `depth` is 0 and `normal` is `a`'s normal. Always false when not intersecting.
    pub coplanar: bool,
}

// What `four::crossing` relies on: the ten f64 fields in one run, in this order.
const _: () = {
    use std::mem::offset_of;
    assert!(offset_of!(ContactGeometry, point_a) == 0);
    assert!(offset_of!(ContactGeometry, point_b) == 24);
    assert!(offset_of!(ContactGeometry, normal) == 48);
    assert!(offset_of!(ContactGeometry, depth) == 72);
};

/// The contact geometry of polygon `a` (`a[..na]`, one or two triangles) and polygon `b`
/// (`b[..nb]`). `na` and `nb` are 1 (a triangle) or 2 (a quad `(v0,v1,v2,v3)` given as
/// `(v0,v1,v2)`, `(v0,v2,v3)`); other values are clamped to that range. Coordinates are
/// expected to be finite `f32` values widened to `f64`. A polygon's vertices are the
/// distinct vertices of its triangles (four for a quad).
///
/// **Decisions (exact).** `intersecting`: some triangle of `a` meets some triangle of `b`
/// (closed triangles, touching counts): the query's own test, so the answer is the query's.
/// `coplanar`: intersecting, and every vertex of both polygons lies on one plane (exact
/// `orient3d`). So two crossing segments, a segment or a point lying in a triangle, and
/// vertices that are all collinear or all equal are coplanar. A pair that does not
/// intersect is never flagged coplanar (its geometry is the band's).
///
/// **Intersecting, not coplanar.**
/// * `point_a`, `point_b`: the two points of the intersection of the closed polygons that
///   are farthest apart. For two triangles the intersection is a segment or a point (then
///   both are that point). For a quad, the intersection is the union of its triangles'
///   intersections with the other polygon's (segments, or for a triangle pair that happens
///   to be coplanar, a convex polygon), and the two points are the farthest pair among
///   their ends and vertices.
/// * `depth`, `normal`: the smallest translation of `a` that separates the convex hulls of
///   the two polygons (the distance from the origin to the boundary of their Minkowski
///   difference `B - A`), by the separating-axis theorem over every facet normal of that
///   difference: the hulls' face normals and the crosses of their edges. For two triangles
///   these are the two face normals and the nine edge-edge crosses, so they get the exact
///   penetration depth. A quad's hull is the quad when it is planar and convex, else the
///   triangle or tetrahedron its four vertices span; its candidate axes are the normals of
///   all four vertex triples and its edge directions all six vertex pairs (a superset of
///   the hull's; a quad-quad pair tries 44 axes). For a non-planar or non-convex quad this
///   is an upper bound of the polygons' own penetration depth (their union of triangles
///   may come apart sooner) and `depth * normal` still separates them. At exactly
///   `depth` the two touch; any longer translation along `normal` separates. Touching
///   pairs get `depth` 0 and the normal of the facet through the origin. A segment
///   crossing a triangle gets the segment-triangle difference's depth (the way out through
///   the triangle's edges or along the segment).
///
/// **Intersecting and coplanar.** `depth` = 0 and `normal` = `a`'s normal (see the chain
/// below): any translation along it separates them. `point_a`, `point_b`: the two
/// farthest-apart points of the overlap (the union of the triangle pairs' overlaps, each a
/// convex polygon, a segment or a point), i.e. the ends of its longest extent.
///
/// If rounding loses a triangle pair's contact that the exact test sees (a touch within
/// the coordinates' rounding), that piece is the midpoint of the pair's closest points.
///
/// **Not intersecting** (pairs reported only within the query's band). `point_a`,
/// `point_b`: a pair of closest points of the polygons (when not unique, one of them);
/// `depth` = minus their distance; `normal`: the unit direction from `point_b` to
/// `point_a`, evaluated from the closest features (vertex-face: the face normal;
/// edge-edge: the edges' cross; vertex-edge: the perpendicular from the edge; vertex-
/// vertex: the difference) with exact orientation signs, so it stays accurate even when
/// the distance is far below the coordinates' rounding.
///
/// **Normals are always unit length, never NaN.** Where a rule above yields a zero vector
/// (coplanar with a degenerate `a`, or a construction that rounds to zero), the normal is
/// the first non-zero of: `a`'s normal (the normalized sum of its triangles' area vectors),
/// `b`'s normal, the normalized cross of the directions of `a` and `b` (each its two
/// farthest vertices: two crossing segments), a unit vector perpendicular to the line
/// holding every vertex (the longer direction crossed with the coordinate axis it is least
/// aligned with), and `+z` (all vertices coincide). In the band, if the feature rule yields
/// zero: the normalized `point_a - point_b`, then the normalized difference of the
/// polygons' vertex means, then that chain. (For `f32` input the rules above never yield
/// zero; a last guard would answer `a`'s first vertex, `+z` and 0 rather than a NaN.)
///
/// **Accuracy** (this module's tests, against double-double references built another way,
/// over random pairs at scales 1e-4 to 1e4 and up to 1e5 from the origin, slivers, near
/// misses 1e-3 to 1e-7, crossings at dihedral angles down to 1e-6, degenerate grids and
/// the benchmarks' heavy case; `eps` = 2^-52, `M` the pair's largest coordinate
/// magnitude, `E` its extent): the points lie within 1.3 eps M of both polygons, within
/// 1.6 eps M of the exact intersection and within 1.8 eps M of its exact ends (an end's
/// signed distances are evaluated with error-free transformations whenever rounding could
/// move it by more than 2 eps M, as at shallow crossings); `depth` is within 1 eps E of
/// the exact penetration depth of the hulls, and moving `a` by `(depth + eps E) * normal`
/// separates the pair (checked exactly); band distances are within 1.1 eps E and band
/// normals within 0.9 eps radian of the exact direction. (A distance far below the
/// coordinates' rounding, `eps E`, leaves the direction undetermined at that precision:
/// there the normal separates the two nearest triangles by the distance to within it.)
///
/// **Cost**: two triangles crossing, about 1700 instructions (AVX2 build) including the
/// exact test; on the heavy case (about 700 crossing pairs) about 160 to 205 ns per pair,
/// 17 to 20% of the query's time. Pairs known to intersect (a query's at epsilon 0) go
/// four at a time through [`contact_geometry_many`] instead (what
/// `Scene::contact_geometry` does): about 40 to 55 ns per pair, 8 to 9% of the query on the
/// heavy case, 15% on an instrument's 95 pairs, 21 to 27% of the 2.4 us queries that find
/// 8 to 10 (`tests/contact_heavy.rs`, `bench-results/contact.md`).
pub fn contact_geometry(
    a: &[[P3; 3]; 2],
    na: usize,
    b: &[[P3; 3]; 2],
    nb: usize,
) -> ContactGeometry {
    #[cfg(target_arch = "x86_64")]
    if std::is_x86_feature_detected!("avx2") && std::is_x86_feature_detected!("fma") {
        // SAFETY: the CPU has AVX2 and FMA (checked just above).
        return unsafe { contact_geometry_avx2(a, na, b, nb) };
    }
    contact_geometry_any(a, na, b, nb)
}

/// [`contact_geometry`] compiled for AVX2 and FMA (three-operand and wider instructions;
/// the same IEEE operations in the same order, so the same results: the only fused
/// multiply-adds are the explicit `mul_add`s, which are fused everywhere).
///
/// Never inlined: the four-lane kernel calls it for its rare lanes, and keeping this
/// (large) code out of the kernel's keeps the kernel's instructions few enough to stay in
/// the instruction cache between a query and its geometry.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
#[inline(never)]
unsafe fn contact_geometry_avx2(
    a: &[[P3; 3]; 2],
    na: usize,
    b: &[[P3; 3]; 2],
    nb: usize,
) -> ContactGeometry {
    contact_geometry_any(a, na, b, nb)
}

#[inline(always)]
fn contact_geometry_any(
    a: &[[P3; 3]; 2],
    na: usize,
    b: &[[P3; 3]; 2],
    nb: usize,
) -> ContactGeometry {
    let (na, nb) = (na.clamp(1, 2), nb.clamp(1, 2));
    if na == 1 && nb == 1 {
        // One of them a segment (two equal corners), the other not: the segment path.
        let (ta, tb) = (twin(&a[0]), twin(&b[0]));
        if ta != tb {
            let seg = if ta {
                segment_crossing(&a[0], &b[0], 1.0)
            } else {
                segment_crossing(&b[0], &a[0], -1.0)
            };
            if let Some(world) = seg {
                return finish(&world, &[0.0; 3], &a[0][0]);
            }
        }
        match triangles(&a[0], &b[0]) {
            Fast::Done(world) => return finish(&world, &[0.0; 3], &a[0][0]),
            Fast::Apart => return band_triangles(&a[0], &b[0]),
            Fast::Other => {}
        }
    }
    general(a, na, b, nb)
}

/// Where [`contact_geometry_many`] reads its pairs' polygons: `fetch(i, [a0, a1], [b0,
/// b1])` writes pair `i`'s polygons as triangles (the first ones into `a0` and `b0`, a
/// quad's second into `a1` or `b1`) and returns how many each has, `(na, nb)` as
/// [`contact_geometry`] takes them. A closure of that signature is one; the scene's own
/// (the last answer's pairs, read from its meshes) is a type whose `fetch` is always
/// inlined into the loop (a closure may be compiled as a function called per pair).
pub trait PolygonPairs {
    /// What stops the call.
    type Error;
    /// Pair `i`'s triangles (see the trait).
    fn fetch(
        &mut self,
        i: usize,
        a: [&mut [P3; 3]; 2],
        b: [&mut [P3; 3]; 2],
    ) -> Result<(usize, usize), Self::Error>;
}

impl<E, F> PolygonPairs for F
where
    F: FnMut(usize, [&mut [P3; 3]; 2], [&mut [P3; 3]; 2]) -> Result<(usize, usize), E>,
{
    type Error = E;
    #[inline(always)]
    fn fetch(
        &mut self,
        i: usize,
        a: [&mut [P3; 3]; 2],
        b: [&mut [P3; 3]; 2],
    ) -> Result<(usize, usize), E> {
        self(i, a, b)
    }
}

/// A closure as [`PolygonPairs`] (this names the closure's argument types, which Rust
/// would not infer from the trait's blanket implementation).
pub fn polygon_pairs<E, F>(f: F) -> F
where
    F: FnMut(usize, [&mut [P3; 3]; 2], [&mut [P3; 3]; 2]) -> Result<(usize, usize), E>,
{
    f
}

/// [`contact_geometry`] of many polygon pairs, entry `i` of `out` for pair `i`, whose
/// triangles `fetch` writes (see [`PolygonPairs`]; an error stops the call and is
/// returned). `known`: every pair is known to intersect (decided by the exact test: the
/// pairs of a query at epsilon 0). The answers are
/// [`contact_geometry`]'s, bit for bit: triangle pairs are gathered four at a time and
/// computed together by the fast path written over lanes (`four.rs`: the same operations
/// on the same values, one AVX2 instruction for four pairs). When `known`, the exact test
/// is skipped; otherwise the four-lane exact test (`tritri::four`) picks the lanes that
/// certainly intersect. A lane that would need one of the fast path's rare branches, a
/// pair that does not intersect (a band pair) or is not decided in the lanes, and every
/// quad go through [`contact_geometry`] itself. (Were a pair wrongly `known`, it is still
/// answered exactly unless it misses by less than the rounding of its cuts: its planes'
/// sides or its cuts on their common line show it.)
pub fn contact_geometry_many<P: PolygonPairs>(
    out: &mut [ContactGeometry],
    known: bool,
    fetch: P,
) -> Result<(), P::Error> {
    // SAFETY: `MaybeUninit<T>` has `T`'s layout, and only initialized values are written
    // through the view.
    let out =
        unsafe { &mut *(out as *mut [ContactGeometry] as *mut [MaybeUninit<ContactGeometry>]) };
    contact_geometry_into(out, known, fetch)
}

/// [`contact_geometry_many`] into entries not initialized yet (a vector's spare capacity:
/// the scene's output is not written twice). When it returns `Ok`, every entry of `out`
/// is initialized; after an error, some may not be.
pub fn contact_geometry_into<P: PolygonPairs>(
    out: &mut [MaybeUninit<ContactGeometry>],
    known: bool,
    mut fetch: P,
) -> Result<(), P::Error> {
    #[cfg(target_arch = "x86_64")]
    if std::is_x86_feature_detected!("avx2") && std::is_x86_feature_detected!("fma") {
        // SAFETY: the CPU has AVX2 and FMA (checked just above).
        return unsafe { many_avx2(out, known, &mut fetch) };
    }
    // Without AVX2: one pair at a time.
    let _ = known;
    let ([mut a0, mut a1], [mut b0, mut b1]) = ([[[0.0; 3]; 3]; 2], [[[0.0; 3]; 3]; 2]);
    for (i, g) in out.iter_mut().enumerate() {
        let (na, nb) = fetch.fetch(i, [&mut a0, &mut a1], [&mut b0, &mut b1])?;
        g.write(contact_geometry(&[a0, a1], na, &[b0, b1], nb));
    }
    Ok(())
}

/// [`band_triangles`] compiled for AVX2 and FMA, out of line (as
/// [`contact_geometry_avx2`]).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
#[inline(never)]
unsafe fn band_triangles_avx2(a: &[P3; 3], b: &[P3; 3]) -> ContactGeometry {
    band_triangles(a, b)
}

/// One batch of [`many_avx2`]: lane `l < n` is the pair `(a, b)` lane `l`, whose answer
/// goes to `out[at[l]]`; once padded, the other lanes repeat lane 0.
#[cfg(target_arch = "x86_64")]
struct Batch {
    a: TriLanes,
    b: TriLanes,
    at: [usize; four::LANES],
    n: usize,
}

#[cfg(target_arch = "x86_64")]
impl Batch {
    const EMPTY: Batch = Batch {
        a: TriLanes::ZERO,
        b: TriLanes::ZERO,
        at: [0; four::LANES],
        n: 0,
    };

    /// Pair `i`'s triangles into the next lane; true when the batch is full.
    #[inline(always)]
    fn push(&mut self, i: usize, a: &[P3; 3], b: &[P3; 3]) -> bool {
        self.a.set(self.n, a);
        self.b.set(self.n, b);
        self.at[self.n] = i;
        self.n += 1;
        self.n == four::LANES
    }

    /// The unused lanes repeat the first (their answers are dropped).
    fn pad(&mut self) {
        let (a0, b0) = (self.a.get(0), self.b.get(0));
        for l in self.n..four::LANES {
            self.a.set(l, &a0);
            self.b.set(l, &b0);
        }
    }
}

/// A batch's computation ([`flush`]) compiled for one instruction set.
#[cfg(target_arch = "x86_64")]
type Flush = unsafe fn(&Batch, bool, &mut [MaybeUninit<ContactGeometry>]);

/// [`contact_geometry_many`] on a CPU with AVX2 and FMA.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
unsafe fn many_avx2<P: PolygonPairs>(
    out: &mut [MaybeUninit<ContactGeometry>],
    known: bool,
    fetch: &mut P,
) -> Result<(), P::Error> {
    // The same kernel compiled for AVX-512 where the CPU has it: the same 256-bit
    // arithmetic (so the same answers; only copies of whole entries may use 512-bit
    // moves), with 32 vector registers instead of 16, which spares the kernel most of its
    // spills to the stack. (AVX-512 target features need Rust 1.89: Cargo.toml's
    // `rust-version`.)
    #[cfg(test)]
    let avx2_only = tests::AVX2_ONLY.with(|c| c.get());
    #[cfg(not(test))]
    let avx2_only = false;
    let flush: Flush = if std::is_x86_feature_detected!("avx512f")
        && std::is_x86_feature_detected!("avx512vl")
        && !avx2_only
    {
        flush_avx512
    } else {
        flush_avx2
    };
    let mut batch = Batch::EMPTY;
    // The pair being read (a quad's second triangles in `a1`, `b1`).
    let ([mut a0, mut a1], [mut b0, mut b1]) = ([[[0.0; 3]; 3]; 2], [[[0.0; 3]; 3]; 2]);
    for i in 0..out.len() {
        let (na, nb) = fetch.fetch(i, [&mut a0, &mut a1], [&mut b0, &mut b1])?;
        if na == 1 && nb == 1 {
            if batch.push(i, &a0, &b0) {
                // SAFETY: this function runs only on a CPU with AVX2 and FMA (and the
                // AVX-512 kernel where it has AVX-512 too).
                unsafe { flush(&batch, known, out) };
                batch.n = 0;
            }
        } else {
            // SAFETY: this function runs only on a CPU with AVX2 and FMA.
            out[i].write(unsafe { contact_geometry_avx2(&[a0, a1], na, &[b0, b1], nb) });
        }
    }
    if batch.n > 0 {
        batch.pad();
        // SAFETY: as above.
        unsafe { flush(&batch, known, out) };
    }
    Ok(())
}

/// [`flush`] compiled for the target features `$features` (one wrapper per instruction
/// set the kernel is built for; the body is inlined into each).
macro_rules! flush_for {
    ($name:ident, $features:literal, $doc:literal) => {
        #[doc = $doc]
        #[cfg(target_arch = "x86_64")]
        #[target_feature(enable = $features)]
        unsafe fn $name(batch: &Batch, known: bool, out: &mut [MaybeUninit<ContactGeometry>]) {
            // SAFETY: the caller's promise.
            unsafe { flush(batch, known, out) }
        }
    };
}

flush_for!(flush_avx2, "avx2,fma", "[`flush`] for AVX2 and FMA.");
flush_for!(
    flush_avx512,
    "avx2,fma,avx512f,avx512vl",
    "[`flush`] for AVX-512 (F and VL: 32 vector registers, mask registers for the blends)."
);

/// One batch of [`many_avx2`]: the kernel on the lanes, and the lanes it leaves one by
/// one.
///
/// # Safety
/// The CPU has AVX2 and FMA; the caller is compiled for them; `batch.at[l]` is in `out`
/// for `l < batch.n`.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
unsafe fn flush(batch: &Batch, known: bool, out: &mut [MaybeUninit<ContactGeometry>]) {
    let Batch { a, b, at, n } = batch;
    // SAFETY: the caller's promise.
    let (ta, tb) = unsafe { (a.load(), b.load()) };
    // The lanes that intersect: all when known, else those the exact test's lanes
    // certify.
    let (crossing, apart) = if known {
        (u32::MAX, 0)
    } else {
        // SAFETY: the caller's promise.
        let (decided, meets) = unsafe { super::tritri::four::intersect_loaded(&ta, &tb) };
        (decided & meets, decided & !meets)
    };
    // No crossing lane (a batch of band pairs): no geometry kernel.
    let lanes = (1 << n) - 1;
    let answered = if crossing & lanes != 0 {
        // SAFETY: the caller's promise.
        unsafe { four::crossing(&ta, &tb, crossing & lanes, at, out) }
    } else {
        0
    };
    for l in 0..*n {
        if answered & crossing & (1 << l) != 0 {
            continue;
        }
        let g = &mut out[at[l]];
        let (ta, tb) = (a.get(l), b.get(l));
        if apart & (1 << l) != 0 {
            // Decided apart: what `contact_geometry` does once its own exact test has
            // found the triangles apart (the only way it answers a pair that does not
            // intersect), without that test.
            // SAFETY: the caller's promise.
            g.write(unsafe { band_triangles_avx2(&ta, &tb) });
        } else {
            // SAFETY: the caller's promise.
            g.write(unsafe { contact_geometry_avx2(&[ta; 2], 1, &[tb; 2], 1) });
        }
    }
}

/// Every case, through the polygons' structures in the local frame.
#[inline(never)]
fn general(a: &[[P3; 3]; 2], na: usize, b: &[[P3; 3]; 2], nb: usize) -> ContactGeometry {
    let origin = a[0][0];
    let pa = Poly::new(a, na, &origin);
    let pb = Poly::new(b, nb, &origin);
    let mut hit = [[None; 2]; 2];
    let mut intersecting = false;
    for (i, t) in pa.tris().iter().enumerate() {
        for (j, u) in pb.tris().iter().enumerate() {
            hit[i][j] = meets(t, u);
            intersecting |= hit[i][j].is_some();
        }
    }
    let local = if intersecting {
        let coplanar = all_coplanar(&pa, &pb);
        let origin_mag = origin.iter().fold(0.0, |m: f64, x| m.max(x.abs()));
        let (p, q) = intersection_ends(&pa, &pb, &hit, origin_mag);
        let (normal, depth) = if coplanar {
            (fallback_normal(&pa, &pb), 0.0)
        } else {
            sat(&pa, &pb).unwrap_or_else(|| (fallback_normal(&pa, &pb), 0.0))
        };
        Local {
            p,
            q,
            normal,
            depth,
            intersecting: true,
            coplanar,
        }
    } else {
        band(&pa, &pb)
    };
    finish(&local, &origin, &origin)
}

/// What the triangle-pair fast path found.
enum Fast {
    /// Crossing transversally (both non-flat, not coplanar): the geometry.
    Done(Local),
    /// Not intersecting.
    Apart,
    /// Intersecting, coplanar or with a flat triangle: the general path.
    Other,
}

/// Two triangles: the common case (crossing transversally) without the general path's
/// structures, in world coordinates: every quantity is built from differences of the
/// pair's own vertices (exact for `f32` input), so the only rounding at the world's
/// magnitude is the final one of the points. The decision is the same as [`meets`].
#[inline(always)]
fn triangles(a: &[P3; 3], b: &[P3; 3]) -> Fast {
    let v = |p: &P3| V::new(p[0], p[1], p[2]);
    let ta = [v(&a[0]), v(&a[1]), v(&a[2])];
    let tb = [v(&b[0]), v(&b[1]), v(&b[2])];
    let fa = Face::of(&ta, a);
    let (db, hb, scale_b) = fa.sides(&tb);
    if separated(hb) {
        return Fast::Apart;
    }
    let fb = Face::of(&tb, b);
    let (da, ha, scale_a) = fb.sides(&ta);
    if separated(ha) {
        return Fast::Apart;
    }
    let su = exact_sides(hb, a, b);
    let st = exact_sides(ha, b, a);
    if separated(su) || separated(st) {
        return Fast::Apart;
    }
    if su.contains(&0) || st.contains(&0) {
        if !triangles_intersect_with(a, b, su, st) {
            return Fast::Apart;
        }
        if su == [0; 3] || st == [0; 3] {
            // Coplanar, or a flat triangle (a non-flat one has a vertex of the other off
            // it).
            return Fast::Other;
        }
    } else if !general_position(a, b, su, st) {
        return Fast::Apart;
    }
    let (da, db) = (signed_like(da, st), signed_like(db, su));
    // The pair's magnitude, to within its extent (enough for the refinement's test).
    let mag = max(ta[0].amax(), tb[0].amax());
    let (cut_a, cut_b) = (
        Cutting::new(&ta, a, &da, &scale_a, &fb, mag),
        Cutting::new(&tb, b, &db, &scale_b, &fa, mag),
    );
    let Some((p, q)) = transverse(&cut_a, &cut_b) else {
        return Fast::Other;
    };
    let Some((normal, depth)) = triangles_sat(&ta, &tb, &fa.n, &fb.n, &da, &db).result() else {
        return Fast::Other;
    };
    Fast::Done(Local {
        p,
        q,
        normal,
        depth,
        intersecting: true,
        coplanar: false,
    })
}

/// Two of the triangle's corners are the same point.
#[inline(always)]
fn twin(t: &[P3; 3]) -> bool {
    t[0] == t[1] || t[1] == t[2] || t[2] == t[0]
}

/// A triangle with two equal corners (a segment, as meshes moved in `f32` make of
/// slivers) crossing the other triangle's interior transversally: the common case of a
/// degenerate pair, answered without the general path's structures (which took about
/// 600 ns a pair). `None` for anything else (the general path decides). Exact decision:
/// the segment's ends strictly on opposite sides of the triangle's plane and its line
/// strictly inside the triangle's three edges (`orient3d`). Its intersection is one point,
/// built from the end nearer the plane with the distances evaluated accurately (as a cut
/// is). The depth is the separating-axis minimum over what the Minkowski difference of a
/// segment and a triangle has as facets: the triangle's normal and the segment crossed
/// with each of its edges (the segment's own normal and its other edges are zero), in a
/// frame at the segment's first end. `seg` has two equal corners, `tri` none; `flip` (+-1)
/// turns a translation of `seg` into one of polygon `a` (-1 when `seg` is `b`).
fn segment_crossing(seg: &[P3; 3], tri: &[P3; 3], flip: f64) -> Option<Local> {
    let (p, q) = if seg[0] == seg[1] {
        (seg[0], seg[2])
    } else {
        (seg[0], seg[1])
    };
    if p == q {
        return None;
    }
    let (sp, sq) = (
        orient3d(&tri[0], &tri[1], &tri[2], &p),
        orient3d(&tri[0], &tri[1], &tri[2], &q),
    );
    if !((sp > 0.0 && sq < 0.0) || (sp < 0.0 && sq > 0.0)) {
        return None;
    }
    let e = [
        orient3d(&p, &q, &tri[0], &tri[1]),
        orient3d(&p, &q, &tri[1], &tri[2]),
        orient3d(&p, &q, &tri[2], &tri[0]),
    ];
    if !(e.iter().all(|&x| x > 0.0) || e.iter().all(|&x| x < 0.0)) {
        return None;
    }
    let v = |x: &P3| V::new(x[0], x[1], x[2]);
    let (vp, vq, t) = (v(&p), v(&q), [v(&tri[0]), v(&tri[1]), v(&tri[2])]);
    let face = Face::of(&t, tri);
    let (dp, dq) = (face.distance_accurately(&p), face.distance_accurately(&q));
    let x = lerp_from_nearer(&vp, &vq, dp, dq);
    // The separating axes, in a frame at `p` (differences of the input: exact for `f32`).
    let s = vq - vp;
    let w = [t[0] - vp, t[1] - vp, t[2] - vp];
    let mut best = Axis::default();
    // On the triangle's normal: the triangle at 0, the segment's ends at their distances.
    best.offer_intervals(&face.n, min_max2(dp, dq), (0.0, 0.0));
    for j in 0..3 {
        // `c = s x e_j` is normal to the segment (which projects to 0) and to edge j
        // (whose ends project alike): the triangle spans edge j's and the third corner's.
        let c = s.cross(&(w[NEXT[j]] - w[j]));
        best.offer_intervals(&c, (0.0, 0.0), min_max2(c.dot(&w[j]), c.dot(&w[PREV[j]])));
    }
    let (normal, depth) = best.result()?;
    Some(Local {
        p: x,
        q: x,
        normal: normal * flip,
        depth,
        intersecting: true,
        coplanar: false,
    })
}

/// The query's exact test ([`triangles_intersect_with`]) for a pair in general position
/// (no vertex on the other's plane, neither triangle on one side of it): Guigue and
/// Devillers' two orientations, after the same permutation of the vertices as
/// `tritri::general_position`, found here by table from the sign patterns rather than by
/// branches (the patterns are random: branches on them mispredict). `su`, `st`: the signs
/// of `orient3d` of `b`'s vertices against `a`'s plane and of `a`'s against `b`'s.
#[inline(always)]
fn general_position(a: &[P3; 3], b: &[P3; 3], su: [i8; 3], st: [i8; 3]) -> bool {
    // The paper's signs are minus orient3d's: bit k of the pattern is "vertex k positive".
    let neg = |s: &[i8; 3]| {
        usize::from(s[0] < 0) | usize::from(s[1] < 0) << 1 | usize::from(s[2] < 0) << 2
    };
    // a's lone vertex first (p1, q1, r1); when it is negative, b's q and r swap.
    let k1 = LONELY[neg(&st)];
    let (p1, q1, r1) = (&a[k1 % 3], &a[NEXT[k1]], &a[PREV[k1]]);
    let swap_b = st[k1 % 3] > 0;
    let order = if swap_b { [0, 2, 1] } else { [0, 1, 2] };
    let lb = [b[order[0]], b[order[1]], b[order[2]]];
    let sb = [su[order[0]], su[order[1]], su[order[2]]];
    // Then b's lone vertex first (p2, q2, r2); when it is negative, q1 and r1 swap.
    let k2 = LONELY[neg(&sb)];
    if k1 == 3 || k2 == 3 {
        // Not in general position after all (cannot happen: no sign is zero and neither
        // triangle is on one side); the query's test decides.
        return triangles_intersect_with(a, b, su, st);
    }
    let (p2, q2, r2) = (&lb[k2], &lb[NEXT[k2]], &lb[PREV[k2]]);
    let (q1, r1) = if sb[k2] > 0 { (r1, q1) } else { (q1, r1) };
    // The paper's CHECK_MIN_MAX, as tritri::gd_check.
    orient3d_filtered(p2, p1, q2, q1) <= 0.0 && orient3d_filtered(p2, r1, r2, p1) <= 0.0
}

/// Relative error allowed for in [`Face::sides`], as the query's plane filter
/// (`tritri::Plane`): thousands of times the worst rounding of the few operations.
const FACE_SLACK: f64 = 1e-12;

/// A triangle's plane: `n = (t1 - t0) x (t2 - t0)` and, per component, the sum of the
/// magnitudes of the two products behind it (the scale of its rounding error).
struct Face<'w> {
    o: V,
    n: V,
    perm: V,
    /// The triangle's corners as given (world positions): what
    /// [`Face::distance_accurately`] works from.
    world: &'w [P3; 3],
}

impl<'w> Face<'w> {
    /// The plane of `t`, whose corners are at world positions `world` (`t` is `world` or
    /// its image in a local frame).
    #[inline(always)]
    fn of(t: &[V; 3], world: &'w [P3; 3]) -> Face<'w> {
        let e = t[1] - t[0];
        let f = t[2] - t[0];
        Face {
            world,
            o: t[0],
            // To the ulp, even on a sliver (its plane turned by eps over its width would
            // move a depth or a distance by that times its lever).
            n: triangle_normal(t),
            perm: V::new(
                (e.y * f.z).abs() + (e.z * f.y).abs(),
                (e.z * f.x).abs() + (e.x * f.z).abs(),
                (e.x * f.y).abs() + (e.y * f.x).abs(),
            ),
        }
    }

    /// The points' signed distances to the plane (times `|n|`); the signs of
    /// `orient3d(t0, t1, t2, p)` (the opposite of the distance's) where the rounding
    /// cannot have flipped them, 0 where only the exact predicate can tell; and the scale
    /// of each distance's rounding error (it is below `2.5 eps` times that).
    #[inline(always)]
    fn sides(&self, p: &[V; 3]) -> ([f64; 3], [i8; 3], [f64; 3]) {
        let mut d = [0.0; 3];
        let mut h = [0; 3];
        let mut scale = [0.0; 3];
        for k in 0..3 {
            let w = p[k] - self.o;
            d[k] = self.n.dot(&w);
            scale[k] = self.perm.dot(&w.abs());
            let bound = FACE_SLACK * scale[k];
            h[k] = i8::from(d[k] < -bound) - i8::from(d[k] > bound);
        }
        (d, h, scale)
    }

    /// The signed distance of the point at world position `p` (times `|n|`),
    /// `det(t1 - t0, t2 - t0, p - t0)` of the world positions, to within a few units in its
    /// last place: the differences with their rounding errors (none for `f32` positions;
    /// a placed mesh's `f64` ones have them), `n`'s components and the products by `p - t0`
    /// carried with theirs (error-free transformations), the terms of second order in
    /// `eps` kept, the one of third order (`al bl xl`) dropped.
    #[inline(always)]
    fn distance_accurately(&self, p: &P3) -> f64 {
        let [t0, t1, t2] = self.world;
        let diff = |a: &P3, b: &P3| {
            let (x, y, z) = (
                two_sum(a[0], -b[0]),
                two_sum(a[1], -b[1]),
                two_sum(a[2], -b[2]),
            );
            (V::new(x.0, y.0, z.0), V::new(x.1, y.1, z.1))
        };
        let ((e, el), (f, fl), (w, wl)) = (diff(t1, t0), diff(t2, t0), diff(p, t0));
        let mut hi = 0.0;
        let mut lo = 0.0;
        for ((a, al), (b, bl), (c, cl), (d, dl), (x, xl)) in [
            (
                (e.y, el.y),
                (f.z, fl.z),
                (e.z, el.z),
                (f.y, fl.y),
                (w.x, wl.x),
            ),
            (
                (e.z, el.z),
                (f.x, fl.x),
                (e.x, el.x),
                (f.z, fl.z),
                (w.y, wl.y),
            ),
            (
                (e.x, el.x),
                (f.y, fl.y),
                (e.y, el.y),
                (f.x, fl.x),
                (w.z, wl.z),
            ),
        ] {
            // n_k = (a + al)(b + bl) - (c + cl)(d + dl) = nh + nl.
            let (p1, e1) = two_prod(a, b);
            let (p2, e2) = two_prod(c, d);
            let (nh, e3) = two_sum(p1, -p2);
            let nl =
                (e3 + (e1 - e2)) + (((a * bl + al * b) - (c * dl + cl * d)) + (al * bl - cl * dl));
            // n_k (x + xl) = t + tl + nl x + nh xl + nl xl.
            let (t, tl) = two_prod(nh, x);
            let (s, e4) = two_sum(hi, t);
            hi = s;
            lo += ((e4 + tl) + nl * x) + (nh * xl + nl * xl);
        }
        hi + lo
    }
}

/// A triangle about to be cut by the other's plane: its vertices, their signed distances
/// to that plane (with the exact signs) and the scales of their rounding errors.
struct Cutting<'a> {
    v: &'a [V; 3],
    /// The same corners at their world positions.
    world: &'a [P3; 3],
    d: &'a [f64; 3],
    scale: &'a [f64; 3],
    plane: &'a Face<'a>,
    /// The largest coordinate magnitude of the pair.
    mag: f64,
}

impl<'a> Cutting<'a> {
    #[inline(always)]
    fn new(
        v: &'a [V; 3],
        world: &'a [P3; 3],
        d: &'a [f64; 3],
        scale: &'a [f64; 3],
        plane: &'a Face<'a>,
        mag: f64,
    ) -> Self {
        Cutting {
            v,
            world,
            d,
            scale,
            plane,
            mag,
        }
    }

    /// The cut ([`cut`]); when rounding could move one of its ends along its edge by more
    /// than `REFINE` units of `eps` times the pair's largest coordinate (the distances'
    /// errors are below `2.5 eps` times their scales), with the distances evaluated
    /// accurately first ([`Face::distance_accurately`], keeping the exact signs). Far from
    /// the origin the points' final rounding dominates, and this is rarely needed.
    #[inline(always)]
    fn cut(&self) -> Option<(V, V)> {
        let (d, s, v) = (self.d, self.scale, self.v);
        let k = LONELY[pattern(d)];
        if k == 3 || d[0] == 0.0 || d[1] == 0.0 || d[2] == 0.0 {
            // A vertex on the plane (exactly: a zero is exact): its edges straddling the
            // plane get the same test and refinement as below (two triangles of a placed
            // mesh sharing a corner, nearly coplanar, cross along a line through it).
            let limit = REFINE * self.mag;
            let shaky = (0..3).any(|i| {
                let j = NEXT[i];
                (d[i] > 0.0) != (d[j] > 0.0)
                    && d[i] != 0.0
                    && d[j] != 0.0
                    && 2.5 * (s[i] + s[j]) * (v[j] - v[i]).amax() > limit * (d[i] - d[j]).abs()
            });
            if shaky {
                return self.cut_accurately();
            }
            return cut(v, d);
        }
        let (i, j) = (NEXT[k], PREV[k]);
        let (ei, ej) = (v[i] - v[k], v[j] - v[k]);
        let (di, dj) = (d[k] - d[i], d[k] - d[j]);
        let limit = REFINE * self.mag;
        let shaky_i = 2.5 * (s[k] + s[i]) * ei.amax() > limit * di.abs();
        let shaky_j = 2.5 * (s[k] + s[j]) * ej.amax() > limit * dj.abs();
        if shaky_i | shaky_j {
            return self.cut_accurately();
        }
        // As `cut`, reusing the edges and differences.
        Some((
            v[k] + ei * max(0.0, min(d[k] / di, 1.0)),
            v[k] + ej * max(0.0, min(d[k] / dj, 1.0)),
        ))
    }

    /// [`Cutting::cut`] with the distances evaluated accurately (rare: out of line).
    #[cold]
    #[inline(never)]
    fn cut_accurately(&self) -> Option<(V, V)> {
        let mut fine = *self.d;
        for (x, p) in fine.iter_mut().zip(self.world) {
            let y = self.plane.distance_accurately(p);
            // Only with the exact sign (see `signed_like`) and finite; an exact zero stays.
            if (y > 0.0) == (*x > 0.0) && y != 0.0 && *x != 0.0 && y.is_finite() {
                *x = y;
            }
        }
        cut(self.v, &fine)
    }
}

/// How far (in `eps` of the pair's largest coordinate) rounding may move a crossing
/// before the distances behind it are evaluated accurately ([`Cutting::cut`]).
const REFINE: f64 = 2.0;

/// `a + b` as the rounded sum and its exact error (Knuth).
#[inline(always)]
fn two_sum(a: f64, b: f64) -> (f64, f64) {
    let s = a + b;
    let bb = s - a;
    (s, (a - (s - bb)) + (b - bb))
}

/// `a b` as the rounded product and its exact error (a fused multiply-add: one
/// instruction where the CPU has it, a correctly rounded library call elsewhere).
#[inline(always)]
fn two_prod(a: f64, b: f64) -> (f64, f64) {
    let p = a * b;
    (p, a.mul_add(b, -p))
}

/// Distances `d` made to agree with the exact signs `s` of `orient3d` (`d ~ -orient3d`):
/// a rounded value of the wrong sign becomes a tiny one of the right sign, and an exact
/// zero is zero.
#[inline(always)]
fn signed_like(mut d: [f64; 3], s: [i8; 3]) -> [f64; 3] {
    for (d, s) in d.iter_mut().zip(s) {
        let want = -f64::from(s);
        if want == 0.0 {
            *d = 0.0;
        } else if *d * want <= 0.0 {
            *d = want * f64::MIN_POSITIVE;
        }
    }
    d
}

/// [`sat`] for two triangles. On a face normal, the face's own vertices project to one
/// value and the other's are the signed distances already computed (`da`: `a`'s vertices
/// against `b`'s plane, `db`: `b`'s against `a`'s). With edges `e_k = v_{k+1} - v_k` (so
/// `e_{k+2} x e_k = n`), `c = ea_i x eb_j` is a facet normal of the Minkowski difference
/// `B - A` only when `a`'s third vertex lies ahead of its edge along `c` and `b`'s behind,
/// or the reverse: `c . (va_{i+2} - va_i) = -eb_j . na` and `c . (vb_{j+2} - vb_j) =
/// ea_i . nb` of opposite signs. Other edge pairs are not facets, and the minimum over the
/// facets is the penetration depth, so they are skipped; on a facet, the translation is
/// the edges' offset `c . (vb_j - va_i)`, signed towards the facet's side. (When a sign is
/// zero, an edge parallel to the other's plane, [`triangles_sat_all`] tries every axis.)
#[inline(always)]
fn triangles_sat(va: &[V; 3], vb: &[V; 3], na: &V, nb: &V, da: &[f64; 3], db: &[f64; 3]) -> Axis {
    let ea = [va[1] - va[0], va[2] - va[1], va[0] - va[2]];
    let eb = [vb[1] - vb[0], vb[2] - vb[1], vb[0] - vb[2]];
    let a3 = [-eb[0].dot(na), -eb[1].dot(na), -eb[2].dot(na)];
    let b3 = [ea[0].dot(nb), ea[1].dot(nb), ea[2].dot(nb)];
    // Which pairs are facets follows the triangles' random orientation: a branch on it
    // would mispredict half the time, so they are listed from the sign patterns instead.
    // The three a3 sum to 0 (the edges of b close), so one has the minority sign, at `ja`
    // (likewise `ib` for b3); a pair (i, j) is a facet when the signs of b3_i and a3_j
    // differ, and a moves along +c when a3_j > 0 (a ahead, b behind).
    let (ja, ib) = (LONELY[pattern(&a3)], LONELY[pattern(&b3)]);
    if ja == 3 || ib == 3 || a3.contains(&0.0) || b3.contains(&0.0) {
        // A zero or rounding-level sign (an edge along the other's plane): every axis,
        // with both projections in full.
        return triangles_sat_all(va, vb, na, nb, da, db, &ea, &eb, &a3, &b3);
    }
    let (j1, j2, i1, i2) = (NEXT[ja], PREV[ja], NEXT[ib], PREV[ib]);
    let five = usize::from((a3[ja] > 0.0) != (b3[ib] > 0.0));
    let pairs = [
        // Four facets (the first one repeated).
        [(ib, j1), (ib, j2), (i1, ja), (i2, ja), (ib, j1)],
        [(ib, ja), (i1, j1), (i1, j2), (i2, j1), (i2, j2)],
    ][five];
    // The two faces first: on na, relative to a's plane, a lies at 0 and b at db; on nb,
    // b at 0 and a at da. Moving a along +n by (bmax - amin), or along -n by (amax - bmin).
    // Each candidate's axis `c`, translation `s`, direction and ranking key `s |s| / |c|^2`
    // (numerator and denominator; the seven divisions are done together below, as
    // independent lanes). Every candidate is kept and the winner taken by index: a `match`
    // on it would mispredict. (No `array::map`: a generic closure is not inlined into the
    // AVX2 build.)
    let mut cs = [V::zeros(); 7];
    let mut ss = [0.0; 7];
    let mut dirs = [0.0; 7];
    let mut num = [0.0; 8];
    let mut den = [1.0; 8];
    let mut face = |slot: usize, n: &V, (amin, amax): (f64, f64), (bmin, bmax): (f64, f64)| {
        let (up, down) = (bmax - amin, amax - bmin);
        let s = min(up, down);
        num[slot] = s * s.abs();
        den[slot] = n.norm_squared();
        (cs[slot], ss[slot]) = (*n, s);
        dirs[slot] = if up <= down { 1.0 } else { -1.0 };
    };
    face(0, na, (0.0, 0.0), min_max(db));
    face(1, nb, min_max(da), (0.0, 0.0));
    // The five facets: `c = ea_i x eb_j`, `s` the edges' offset `c . (vb_j - va_i)` signed
    // by `a3_j` (a moves along `+c` when it is positive; no `a3` is zero here).
    for (m, &(i, j)) in pairs.iter().enumerate() {
        let c = ea[i].cross(&eb[j]);
        // +-1 exactly: `s` is `t` or `-t`, chosen without a branch.
        let dir = 1.0f64.copysign(a3[j]);
        let s = dir * c.dot(&(vb[j] - va[i]));
        num[m + 2] = s * s.abs();
        den[m + 2] = c.norm_squared();
        (cs[m + 2], ss[m + 2], dirs[m + 2]) = (c, s, dir);
    }
    let mut keys = [0.0; 8];
    for m in 0..8 {
        keys[m] = num[m] / den[m];
    }
    let mut key = f64::INFINITY;
    let mut at = usize::MAX;
    for m in 0..7 {
        // NaN (|c|^2 = 0) loses every comparison.
        let k = if den[m] > 0.0 { keys[m] } else { f64::INFINITY };
        take_min(&mut key, &mut at, k, m);
    }
    if at < 7 {
        Axis {
            c: cs[at],
            s: ss[at],
            dir: dirs[at],
            key,
        }
    } else {
        Axis::default()
    }
}

/// [`triangles_sat`] when an edge lies along the other's plane (or its side is not
/// certain): the two normals and the nine edge crosses with both projections in full
/// (relative to `va[i]`: `a`'s edge at 0 and its third vertex at `a3_j`; `b`'s edge at
/// `c . (vb_j - va_i)` and its third vertex `b3_i` further).
#[cold]
#[allow(clippy::too_many_arguments)]
fn triangles_sat_all(
    va: &[V; 3],
    vb: &[V; 3],
    na: &V,
    nb: &V,
    da: &[f64; 3],
    db: &[f64; 3],
    ea: &[V; 3],
    eb: &[V; 3],
    a3: &[f64; 3],
    b3: &[f64; 3],
) -> Axis {
    let mut best = Axis::default();
    best.offer_intervals(na, (0.0, 0.0), min_max(db));
    best.offer_intervals(nb, min_max(da), (0.0, 0.0));
    for i in 0..3 {
        for j in 0..3 {
            let c = ea[i].cross(&eb[j]);
            let b0 = c.dot(&(vb[j] - va[i]));
            best.offer_intervals(&c, min_max2(0.0, a3[j]), min_max2(b0, b0 + b3[i]));
        }
    }
    best
}

/// `x < y ? x : y` (what `minsd` computes; no NaN reaches it).
#[inline(always)]
fn min(x: f64, y: f64) -> f64 {
    if x < y {
        x
    } else {
        y
    }
}

#[inline(always)]
fn max(x: f64, y: f64) -> f64 {
    if x > y {
        x
    } else {
        y
    }
}

/// The next and the previous vertex of a triangle (index 3 maps anywhere valid): tables,
/// cheaper than `% 3`.
const NEXT: [usize; 4] = [1, 2, 0, 0];
const PREV: [usize; 4] = [2, 0, 1, 0];

/// The vertex alone on its side, by the pattern of the three signs (bit k: `d_k > 0`);
/// 3 when all are on one side.
const LONELY: [usize; 8] = [3, 0, 1, 2, 2, 1, 0, 3];

#[inline(always)]
fn pattern(d: &[f64; 3]) -> usize {
    usize::from(d[0] > 0.0) | usize::from(d[1] > 0.0) << 1 | usize::from(d[2] > 0.0) << 2
}

/// `best = min(best, key)`, remembering `at`, without a branch.
#[inline(always)]
fn take_min(best: &mut f64, at: &mut usize, key: f64, here: usize) {
    let mask = usize::from(key < *best).wrapping_neg();
    *at = (here & mask) | (*at & !mask);
    *best = best.min(key);
}

#[inline(always)]
fn min_max2(x: f64, y: f64) -> (f64, f64) {
    if x <= y {
        (x, y)
    } else {
        (y, x)
    }
}

#[inline(always)]
fn min_max(d: &[f64; 3]) -> (f64, f64) {
    let (lo, hi) = min_max2(d[0], d[1]);
    (
        if d[2] < lo { d[2] } else { lo },
        if d[2] > hi { d[2] } else { hi },
    )
}

/// The result in the local frame.
struct Local {
    p: V,
    q: V,
    normal: V,
    depth: f64,
    intersecting: bool,
    coplanar: bool,
}

/// Back to world coordinates (adding `o`); a last guard keeps NaN and non-unit normals out
/// (answering `home`, +z and 0; it never fires for finite `f32`-range input: the tests
/// fuzz that it does not).
#[inline(always)]
fn finish(l: &Local, o: &P3, home: &P3) -> ContactGeometry {
    let world = |v: &V| [v[0] + o[0], v[1] + o[1], v[2] + o[2]];
    let g = ContactGeometry {
        point_a: world(&l.p),
        point_b: world(&l.q),
        normal: [l.normal[0], l.normal[1], l.normal[2]],
        depth: l.depth,
        intersecting: l.intersecting,
        coplanar: l.coplanar,
    };
    // A sum is finite only if every term is (an infinity or NaN stays; f32-range terms
    // cannot overflow it).
    let finite =
        (l.p.sum() + l.q.sum() + l.normal.sum() + l.depth + o[0] + o[1] + o[2]).is_finite();
    let unit = (l.normal.norm_squared() - 1.0).abs() < 1e-12;
    debug_assert!(finite && unit, "contact geometry not finite/unit: {g:?}");
    if finite && unit {
        g
    } else {
        ContactGeometry {
            point_a: *home,
            point_b: *home,
            normal: [0.0, 0.0, 1.0],
            depth: 0.0,
            ..g
        }
    }
}

/// One triangle of a polygon: input coordinates for the exact predicates, local ones for
/// the constructions.
#[derive(Clone, Copy)]
struct Tri {
    p: [P3; 3],
    v: [V; 3],
    /// `(p1 - p0) x (p2 - p0)`, not normalized, to about an ulp of each component
    /// ([`triangle_normal`]).
    n: V,
    /// Exactly collinear (a segment or a point).
    flat: bool,
}

impl Tri {
    #[inline(always)]
    fn new(p: &[P3; 3], o: &P3) -> Tri {
        let v = p.map(|q| local(&q, o));
        Tri {
            p: *p,
            v,
            n: triangle_normal(&p.map(|q| V::new(q[0], q[1], q[2]))),
            flat: collinear(&p[0], &p[1], &p[2]),
        }
    }

    /// The ends of a flat triangle's segment: its two farthest-apart vertices.
    fn segment(&self) -> (usize, usize) {
        let d = |i: usize, j: usize| (self.v[i] - self.v[j]).norm_squared();
        let (d01, d12, d20) = (d(0, 1), d(1, 2), d(2, 0));
        if d01 >= d12 && d01 >= d20 {
            (0, 1)
        } else if d12 >= d20 {
            (1, 2)
        } else {
            (2, 0)
        }
    }
}

/// `a b - c d` by Kahan's method: within 1.5 ulps (see [`accurate_cross`]).
#[inline(always)]
fn kahan(a: f64, b: f64, c: f64, d: f64) -> f64 {
    let w = c * d;
    let err = (-c).mul_add(d, w);
    a.mul_add(b, -w) + err
}

/// `e x f` with each component `a b - c d` evaluated by Kahan's method (two fused
/// multiply-adds): within 1.5 ulps of its exact value, however much the two products
/// cancel. The plain cross is off by a few eps of `|e| |f|`, which on a sliver (`|n|` far
/// below `|e| |f|`) turns its plane by eps over its width and moves a distance to it by
/// that times the lever. (The differences of `f32` positions are exact, so the normal of
/// such a triangle is then right to the ulp.)
#[inline(always)]
fn accurate_cross(e: &V, f: &V) -> V {
    V::new(
        kahan(e.y, f.z, e.z, f.y),
        kahan(e.z, f.x, e.x, f.z),
        kahan(e.x, f.y, e.y, f.x),
    )
}

/// The normal `(t1 - t0) x (t2 - t0)` of the exact differences: [`accurate_cross`] of the
/// rounded ones plus, to first order, what their rounding left out (zero for `f32`
/// positions, whose differences are exact; for `f64` ones, a placed mesh's, the rounding
/// of an edge would turn a sliver's plane by eps over its width all the same).
#[inline(always)]
fn triangle_normal(t: &[V; 3]) -> V {
    let (e, f) = (t[1] - t[0], t[2] - t[0]);
    let lost = |a: &V, b: &V| {
        V::new(
            two_sum(a.x, -b.x).1,
            two_sum(a.y, -b.y).1,
            two_sum(a.z, -b.z).1,
        )
    };
    let (el, fl) = (lost(&t[1], &t[0]), lost(&t[2], &t[0]));
    let n = accurate_cross(&e, &f);
    if el == V::zeros() && fl == V::zeros() {
        // Exact differences (f32 positions, the common case).
        return n;
    }
    V::new(
        n.x + ((e.y * fl.z + el.y * f.z) - (e.z * fl.y + el.z * f.y)),
        n.y + ((e.z * fl.x + el.z * f.x) - (e.x * fl.z + el.x * f.z)),
        n.z + ((e.x * fl.y + el.x * f.y) - (e.y * fl.x + el.y * f.x)),
    )
}

#[inline]
fn local(p: &P3, o: &P3) -> V {
    V::new(p[0] - o[0], p[1] - o[1], p[2] - o[2])
}

/// A polygon: its triangles and its distinct vertices (3 or 4 for a well-formed one, whose
/// hull they span).
struct Poly {
    tris: [Tri; 2],
    nt: usize,
    v: [V; 6],
    nv: usize,
}

impl Poly {
    fn new(t: &[[P3; 3]; 2], n: usize, o: &P3) -> Poly {
        let tri0 = Tri::new(&t[0], o);
        let tri1 = if n == 2 { Tri::new(&t[1], o) } else { tri0 };
        let mut v = [V::zeros(); 6];
        let mut nv = 0;
        for tri in [&tri0, &tri1].into_iter().take(n) {
            for q in &tri.v {
                if !v[..nv].contains(q) {
                    v[nv] = *q;
                    nv += 1;
                }
            }
        }
        Poly {
            tris: [tri0, tri1],
            nt: n,
            v,
            nv,
        }
    }

    fn tris(&self) -> &[Tri] {
        &self.tris[..self.nt]
    }

    fn verts(&self) -> &[V] {
        &self.v[..self.nv]
    }

    /// The sum of the triangles' area vectors (twice the vector area).
    fn area(&self) -> V {
        self.tris().iter().map(|t| t.n).sum()
    }

    /// The two farthest-apart vertices (the polygon's direction when it is a segment).
    fn extent(&self) -> V {
        farthest(self.verts()).map_or(V::zeros(), |(p, q)| q - p)
    }

    fn mean(&self) -> V {
        self.verts().iter().sum::<V>() / self.nv as f64
    }
}

/// Exact orientation signs of a meeting triangle pair `(t, u)`: `[0]` of `u`'s vertices
/// against `t`'s plane, `[1]` of `t`'s against `u`'s (the signs of `orient3d`, -1, 0, 1).
type Signs = [[i8; 3]; 2];

/// The query's decision for one triangle pair (plane rejections, then the exact test),
/// with the exact orientation signs when they meet.
fn meets(t: &Tri, u: &Tri) -> Option<Signs> {
    let su = Plane::of(&t.p).sides(&u.p);
    if separated(su) {
        return None;
    }
    let st = Plane::of(&u.p).sides(&t.p);
    if separated(st) {
        return None;
    }
    // The uncertain signs exactly; the test then evaluates only exact zeros again.
    let su = exact_sides(su, &t.p, &u.p);
    let st = exact_sides(st, &u.p, &t.p);
    triangles_intersect_with(&t.p, &u.p, su, st).then_some([su, st])
}

/// Completes certain signs `h` of `orient3d(t, u_k)` with the exact predicate.
#[inline(always)]
fn exact_sides(mut h: [i8; 3], t: &[P3; 3], u: &[P3; 3]) -> [i8; 3] {
    for (h, p) in h.iter_mut().zip(u) {
        if *h == 0 {
            let o = orient3d(&t[0], &t[1], &t[2], p);
            *h = i8::from(o > 0.0) - i8::from(o < 0.0);
        }
    }
    h
}

#[inline]
fn sign(x: f64) -> f64 {
    if x > 0.0 {
        1.0
    } else if x < 0.0 {
        -1.0
    } else {
        0.0
    }
}

/// Unit vector along `v`, or `None` when `v` is zero (or not finite). Scaled first, so no
/// intermediate under- or overflows.
fn unit(v: &V) -> Option<V> {
    let m = v.amax();
    if !(m > 0.0 && m.is_finite()) {
        return None;
    }
    let w = v / m;
    Some(w / w.norm())
}

/// Is every vertex of both polygons on one plane? (Exact.)
fn all_coplanar(pa: &Poly, pb: &Poly) -> bool {
    let all = || pa.tris().iter().chain(pb.tris()).flat_map(|t| t.p.iter());
    let reference = pa.tris().iter().chain(pb.tris()).find(|t| !t.flat);
    let on = |t: &[P3; 3]| all().all(|x| orient3d(&t[0], &t[1], &t[2], x) == 0.0);
    match reference {
        Some(t) => {
            // Certain signs spare most exact evaluations.
            let plane = Plane::of(&t.p);
            for u in pa.tris().iter().chain(pb.tris()) {
                if plane.sides(&u.p) != [0; 3] {
                    return false;
                }
            }
            on(&t.p)
        }
        None => {
            // Only segments and points: look for three vertices spanning a plane.
            let mut pts = [[0.0; 3]; 12];
            let mut n = 0;
            for p in all() {
                pts[n] = *p;
                n += 1;
            }
            for i in 0..n {
                for j in i + 1..n {
                    for k in j + 1..n {
                        if !collinear(&pts[i], &pts[j], &pts[k]) {
                            return on(&[pts[i], pts[j], pts[k]]);
                        }
                    }
                }
            }
            true
        }
    }
}

/// Up to `N` points, on the stack.
struct Pts<const N: usize> {
    p: [V; N],
    n: usize,
}

impl<const N: usize> Pts<N> {
    fn new() -> Self {
        Pts {
            p: [V::zeros(); N],
            n: 0,
        }
    }

    #[inline]
    fn push(&mut self, v: V) {
        debug_assert!(self.n < self.p.len());
        if self.n < self.p.len() {
            self.p[self.n] = v;
            self.n += 1;
        }
    }

    fn all(&self) -> &[V] {
        &self.p[..self.n]
    }
}

/// The two farthest-apart points (`None` for no point).
fn farthest(p: &[V]) -> Option<(V, V)> {
    let first = *p.first()?;
    let mut best = (first, first, -1.0);
    for i in 0..p.len() {
        for j in i + 1..p.len() {
            let d = (p[i] - p[j]).norm_squared();
            if d > best.2 {
                best = (p[i], p[j], d);
            }
        }
    }
    Some((best.0, best.1))
}

/// The ends of the longest extent of the polygons' intersection: the farthest pair among
/// the pieces (one per meeting triangle pair).
fn intersection_ends(
    pa: &Poly,
    pb: &Poly,
    hit: &[[Option<Signs>; 2]; 2],
    origin_mag: f64,
) -> (V, V) {
    if pa.nt == 1 && pb.nt == 1 {
        let mut pts = Pts::<16>::new();
        pieces(pa, pb, hit, origin_mag, &mut pts);
        return farthest(pts.all()).unwrap_or((V::zeros(), V::zeros()));
    }
    let mut pts = Pts::<64>::new();
    pieces(pa, pb, hit, origin_mag, &mut pts);
    farthest(pts.all()).unwrap_or((V::zeros(), V::zeros()))
}

fn pieces<const N: usize>(
    pa: &Poly,
    pb: &Poly,
    hit: &[[Option<Signs>; 2]; 2],
    origin_mag: f64,
    pts: &mut Pts<N>,
) {
    for (i, t) in pa.tris().iter().enumerate() {
        for (j, u) in pb.tris().iter().enumerate() {
            if let Some(signs) = &hit[i][j] {
                let before = pts.n;
                piece(t, u, signs, origin_mag, pts);
                if pts.n == before {
                    // Rounding lost a touching contact: the closest points, which the exact
                    // test says are (within rounding) one point.
                    let c = closest(t, u);
                    pts.push((c.p + c.q) * 0.5);
                }
            }
        }
    }
}

/// The intersection of two meeting triangles, as its ends or vertices.
fn piece<const N: usize>(t: &Tri, u: &Tri, signs: &Signs, origin_mag: f64, out: &mut Pts<N>) {
    let [su, st] = *signs;
    let coplanar = if !t.flat {
        su == [0; 3]
    } else if !u.flat {
        st == [0; 3]
    } else {
        // Two meeting segments (or points) always share a plane.
        true
    };
    if coplanar {
        if t.flat && u.flat {
            segments(t, u, out);
        } else {
            coplanar_piece(t, u, out);
        }
        return;
    }
    // Signed distances to the other's plane, with the exact signs (d = -orient3d).
    // (Their normals from the positions themselves, not the rounded local ones.)
    let (mut ft, mut fu) = (Face::of(&t.v, &t.p), Face::of(&u.v, &u.p));
    (ft.n, fu.n) = (t.n, u.n);
    let (dt, _, scale_t) = fu.sides(&t.v);
    let (du, _, scale_u) = ft.sides(&u.v);
    let (dt, du) = (signed_like(dt, st), signed_like(du, su));
    if t.flat || u.flat {
        // A segment through the other's plane: the single crossing point.
        let (s, d) = if t.flat { (&t.v, &dt) } else { (&u.v, &du) };
        if let Some(p) = crossing(s, d) {
            out.push(p);
        }
        return;
    }
    // Local coordinates: the world's magnitude is that of the first vertex of a, added
    // back at the end.
    let mag =
        t.v.iter()
            .chain(&u.v)
            .map(|p| p.amax())
            .fold(origin_mag, max);
    let (cut_t, cut_u) = (
        Cutting::new(&t.v, &t.p, &dt, &scale_t, &fu, mag),
        Cutting::new(&u.v, &u.p, &du, &scale_u, &ft, mag),
    );
    if let Some((lo, hi)) = transverse(&cut_t, &cut_u) {
        out.push(lo);
        if hi != lo {
            out.push(hi);
        }
    }
}

/// A flat triangle (a segment) crossing a plane it is not in: the crossing point, from its
/// vertices' signed distances `d` (a vertex on the plane, else an edge straddling it).
fn crossing(t: &[V; 3], d: &[f64; 3]) -> Option<V> {
    if let Some(i) = (0..3).find(|&i| d[i] == 0.0) {
        return Some(t[i]);
    }
    (0..3).find_map(|i| {
        let j = (i + 1) % 3;
        ((d[i] > 0.0) != (d[j] > 0.0)).then(|| lerp_from_nearer(&t[i], &t[j], d[i], d[j]))
    })
}

/// Two non-flat triangles crossing each other's plane: the overlap of their cuts by the
/// other's plane (`dt`, `du`: signed distances of their vertices to it), which both lie on
/// the planes' common line, compared by their projections on it. The choices are blends,
/// not branches (they follow the pair's random orientation).
///
/// The line's direction is taken from the longer cut, not from the cross of the two
/// normals: two nearly parallel planes (say 1e-16 rad apart: a placed mesh's triangle
/// lying on another) have a common line whose direction that cross gets wrong entirely,
/// which could order the ends wrongly; the ends themselves lie on the line to within
/// their rounding, so the longer cut's direction is right to that rounding over its
/// length (two cuts shorter than their rounding are answered within it either way).
#[inline(always)]
fn transverse(t: &Cutting, u: &Cutting) -> Option<(V, V)> {
    let (t0, t1) = t.cut()?;
    let (u0, u1) = u.cut()?;
    let (dt, du) = (t1 - t0, u1 - u0);
    let line = pick(dt.norm_squared() >= du.norm_squared(), &dt, &du);
    let (kt0, kt1, ku0, ku1) = (line.dot(&t0), line.dot(&t1), line.dot(&u0), line.dot(&u1));
    // Each cut's low and high end, then the higher low and the lower high.
    let (lt, ht, klt, kht) = (
        pick(kt0 <= kt1, &t0, &t1),
        pick(kt0 <= kt1, &t1, &t0),
        kt0.min(kt1),
        kt0.max(kt1),
    );
    let (lu, hu, klu, khu) = (
        pick(ku0 <= ku1, &u0, &u1),
        pick(ku0 <= ku1, &u1, &u0),
        ku0.min(ku1),
        ku0.max(ku1),
    );
    let lo = pick(klt >= klu, &lt, &lu);
    let hi = pick(kht <= khu, &ht, &hu);
    // Touching, with the ends rounded past each other: their midpoint.
    let m = (lo + hi) * 0.5;
    let apart = klt.max(klu) > kht.min(khu);
    Some((pick(apart, &m, &lo), pick(apart, &m, &hi)))
}

/// `if c { x } else { y }` as arithmetic (exact for finite vectors), without a branch.
#[inline(always)]
fn pick(c: bool, x: &V, y: &V) -> V {
    let w = f64::from(u8::from(c));
    x * w + y * (1.0 - w)
}

/// The cut of a non-flat triangle `t` by a plane that does not hold it, from its
/// vertices' signed distances `d` (a vertex on the plane has exactly 0): the ends of the
/// segment it is (equal when it is a point), `None` if it misses the plane.
#[inline(always)]
fn cut(t: &[V; 3], d: &[f64; 3]) -> Option<(V, V)> {
    if d[0] != 0.0 && d[1] != 0.0 && d[2] != 0.0 {
        // No vertex on the plane: the vertex alone on its side and its two edges, found
        // by table (the pattern is random: a branch on it would mispredict).
        let k = LONELY[pattern(d)];
        if k == 3 {
            return None;
        }
        let (i, j) = (NEXT[k], PREV[k]);
        return Some((
            lerp(&t[k], &t[i], d[k], d[i]),
            lerp(&t[k], &t[j], d[k], d[j]),
        ));
    }
    cut_touching(t, d)
}

/// [`cut`] when a vertex lies on the plane.
fn cut_touching(t: &[V; 3], d: &[f64; 3]) -> Option<(V, V)> {
    let mut ends = [V::zeros(); 2];
    let mut n = 0;
    for i in 0..3 {
        let j = if i == 2 { 0 } else { i + 1 };
        if d[i] == 0.0 {
            ends[n & 1] = t[i];
            n += 1;
        } else if (d[i] > 0.0 && d[j] < 0.0) || (d[i] < 0.0 && d[j] > 0.0) {
            ends[n & 1] = lerp_from_nearer(&t[i], &t[j], d[i], d[j]);
            n += 1;
        }
    }
    // At most two: a vertex on the plane or the crossing of the edge it starts.
    match n {
        0 => None,
        1 => Some((ends[0], ends[0])),
        _ => Some((ends[0], ends[1])),
    }
}

/// The point where the value interpolating `dp` at `p` and `dq` at `q` (opposite signs)
/// vanishes, without a branch.
#[inline(always)]
fn lerp(p: &V, q: &V, dp: f64, dq: f64) -> V {
    let r = dp / (dp - dq);
    p + (q - p) * max(0.0, min(r, 1.0))
}

/// The point where the value interpolating `dp` at `p` and `dq` at `q` (opposite signs)
/// vanishes, stepped from the end nearer to it (the shorter step rounds less).
#[inline]
fn lerp_from_nearer(p: &V, q: &V, dp: f64, dq: f64) -> V {
    if dp.abs() <= dq.abs() {
        p + (q - p) * (dp / (dp - dq)).clamp(0.0, 1.0)
    } else {
        q + (p - q) * (dq / (dq - dp)).clamp(0.0, 1.0)
    }
}

/// Coplanar pair, not both flat: the vertices of the intersection of the closed
/// triangles, found by exact tests in the coordinate plane where a non-flat one keeps
/// the most area (vertices of either inside the other, crossings of their edges); each
/// crossing is built from the input vertices, not from earlier clipped points, so its
/// error does not grow with the angles involved.
fn coplanar_piece<const N: usize>(t: &Tri, u: &Tri, out: &mut Pts<N>) {
    let n = if t.flat { u.n } else { t.n };
    let ax = n.iamax();
    let (i, j) = [(1, 2), (2, 0), (0, 1)][ax];
    let two = |p: &P3| [p[i], p[j]];
    let (t2, u2) = (t.p.map(|p| two(&p)), u.p.map(|p| two(&p)));
    for (s, s2, c2, c_flat) in [(t, &t2, &u2, u.flat), (u, &u2, &t2, t.flat)] {
        for (x, v) in s2.iter().zip(&s.v) {
            if inside_2d(x, c2, c_flat) {
                out.push(*v);
            }
        }
    }
    for k in 0..3 {
        let k1 = (k + 1) % 3;
        for l in 0..3 {
            let l1 = (l + 1) % 3;
            if !segments_intersect_2d(t2[k], t2[k1], u2[l], u2[l1]) {
                continue;
            }
            let (p, e, r, f) = (t.v[k], t.v[k1] - t.v[k], u.v[l], u.v[l1] - u.v[l]);
            let cross = |a: &V, b: &V| a[i] * b[j] - a[j] * b[i];
            let den = cross(&e, &f);
            if den != 0.0 {
                // Parallel edges that meet overlap; their ends are inside, found above.
                out.push(p + e * (cross(&(r - p), &f) / den).clamp(0.0, 1.0));
            }
        }
    }
}

/// Is the 2D point `x` in the closed triangle `c` (a segment or a point when `flat`)?
fn inside_2d(x: &[f64; 2], c: &[[f64; 2]; 3], flat: bool) -> bool {
    if flat {
        return (0..3).any(|k| segments_intersect_2d(*x, *x, c[k], c[(k + 1) % 3]));
    }
    let o = [0, 1, 2].map(|k| orient2d(c[k], c[(k + 1) % 3], *x));
    !(o.iter().any(|&v| v > 0.0) && o.iter().any(|&v| v < 0.0))
}

/// Coplanar pair, both flat (segments or points) and meeting.
fn segments<const N: usize>(t: &Tri, u: &Tri, out: &mut Pts<N>) {
    let (i0, i1) = t.segment();
    let (j0, j1) = u.segment();
    let (p1, q1, p2, q2) = (t.v[i0], t.v[i1], u.v[j0], u.v[j1]);
    if t.p[i0] == t.p[i1] {
        out.push(p1);
        return;
    }
    if u.p[j0] == u.p[j1] {
        out.push(p2);
        return;
    }
    let d1 = q1 - p1;
    if collinear(&t.p[i0], &t.p[i1], &u.p[j0]) && collinear(&t.p[i0], &t.p[i1], &u.p[j1]) {
        // One line: the overlap of the two intervals along it.
        let key = |x: &V| d1.dot(&(x - p1));
        let (mut lo, mut hi) = (p1, q1);
        let (a, b) = if key(&p2) <= key(&q2) {
            (p2, q2)
        } else {
            (q2, p2)
        };
        if key(&a) > key(&lo) {
            lo = a;
        }
        if key(&b) < key(&hi) {
            hi = b;
        }
        if key(&lo) <= key(&hi) {
            out.push(lo);
            out.push(hi);
        } else {
            out.push((lo + hi) * 0.5);
        }
        return;
    }
    // Crossing: p1 + s d1 = p2 + r d2.
    let d2 = q2 - p2;
    let c = d1.cross(&d2);
    let cc = c.norm_squared();
    if cc > 0.0 {
        let s = ((p2 - p1).cross(&d2).dot(&c) / cc).clamp(0.0, 1.0);
        out.push(p1 + d1 * s);
    }
}

/// Separating-axis penetration of the polygons' convex hulls: the smallest translation of
/// `a`, as (unit normal, depth >= 0); `None` if every axis is zero.
fn sat(pa: &Poly, pb: &Poly) -> Option<(V, f64)> {
    let (va, vb) = (pa.verts(), pb.verts());
    let mut best = Axis::default();
    // A triangle's only facet normal is its own.
    if pa.nt == 1 && pa.nv == 3 {
        best.offer(&pa.tris[0].n, va, vb);
    } else {
        for_triples(va, |c| best.offer(&c, va, vb));
    }
    if pb.nt == 1 && pb.nv == 3 {
        best.offer(&pb.tris[0].n, va, vb);
    } else {
        for_triples(vb, |c| best.offer(&c, va, vb));
    }
    for_pairs(va, |e| for_pairs(vb, |f| best.offer(&e.cross(&f), va, vb)));
    best.result()
}

/// The best axis so far: moving `a` by `s / |c|` along `dir * c`, ranked by
/// `key = s |s| / |c|^2` (the signed square of that distance; no root per axis).
struct Axis {
    c: V,
    s: f64,
    dir: f64,
    key: f64,
}

impl Default for Axis {
    fn default() -> Self {
        Axis {
            c: V::zeros(),
            s: 0.0,
            dir: 1.0,
            key: f64::INFINITY,
        }
    }
}

impl Axis {
    /// (unit normal, depth >= 0), if some axis was non-zero.
    #[inline(always)]
    fn result(&self) -> Option<(V, f64)> {
        let len = self.c.norm();
        (self.key.is_finite() && len > 0.0).then(|| {
            let depth = (self.s / len).max(0.0);
            (self.c * (self.dir / len), depth)
        })
    }

    #[inline]
    fn offer(&mut self, c: &V, va: &[V], vb: &[V]) {
        // (offer_intervals skips a zero axis.)
        self.offer_intervals(c, interval(va, c), interval(vb, c));
    }

    /// Axis `c` on which `a` projects to `[amin, amax]` and `b` to `[bmin, bmax]`.
    #[inline(always)]
    fn offer_intervals(&mut self, c: &V, (amin, amax): (f64, f64), (bmin, bmax): (f64, f64)) {
        let cc = c.norm_squared();
        if cc.is_nan() || cc <= 0.0 {
            return;
        }
        // Moving a along +c by (bmax - amin), or along -c by (amax - bmin).
        let up = bmax - amin;
        let down = amax - bmin;
        let (s, dir) = if up <= down { (up, 1.0) } else { (down, -1.0) };
        // s |s| / cc < key without a division per axis (both sides are of degree 6 in
        // the coordinates: within f64's range for f32 inputs).
        if s * s.abs() < self.key * cc {
            *self = Axis {
                c: *c,
                s,
                dir,
                key: s * s.abs() / cc,
            };
        }
    }
}

/// The projection interval of points on `c`.
#[inline]
fn interval(v: &[V], c: &V) -> (f64, f64) {
    let x = c.dot(&v[0]);
    let (mut lo, mut hi) = (x, x);
    for p in &v[1..] {
        let x = c.dot(p);
        if x < lo {
            lo = x;
        }
        if x > hi {
            hi = x;
        }
    }
    (lo, hi)
}

/// The normal of every vertex triple (the hull's facets are among them).
#[inline]
fn for_triples(v: &[V], mut f: impl FnMut(V)) {
    for i in 0..v.len() {
        for j in i + 1..v.len() {
            for k in j + 1..v.len() {
                f((v[j] - v[i]).cross(&(v[k] - v[i])));
            }
        }
    }
}

/// The direction of every vertex pair (the hull's edges are among them).
#[inline]
fn for_pairs(v: &[V], mut f: impl FnMut(V)) {
    for i in 0..v.len() {
        for j in i + 1..v.len() {
            f(v[j] - v[i]);
        }
    }
}

/// The normal fallback chain (see [`contact_geometry`]): `a`'s normal, `b`'s, the cross of
/// their directions, a perpendicular to the common line, `+z`.
fn fallback_normal(pa: &Poly, pb: &Poly) -> V {
    if let Some(n) = unit(&pa.area()).or_else(|| unit(&pb.area())) {
        return n;
    }
    let (da, db) = (pa.extent(), pb.extent());
    if let Some(n) = unit(&da.cross(&db)) {
        return n;
    }
    let d = if da.norm_squared() >= db.norm_squared() {
        da
    } else {
        db
    };
    let k = d.iamin();
    unit(&d.cross(&V::ith(k, 1.0))).unwrap_or(V::z())
}

/// Closest points of two triangles (meeting or not), with the features that realize them.
struct Closest {
    /// On the first triangle.
    p: V,
    /// On the second.
    q: V,
    d2: f64,
    feature: Feature,
}

#[derive(Clone, Copy)]
enum Feature {
    /// Vertex `k` of the first triangle over the interior of the second's face.
    VertexFace { k: usize },
    /// Vertex `k` of the second triangle over the interior of the first's face.
    FaceVertex { k: usize },
    /// Edge `i` of the first (`v[i]`-`v[i+1]`) at parameter `s`, edge `j` of the second at
    /// parameter `r`.
    EdgeEdge { i: usize, j: usize, s: f64, r: f64 },
}

/// The closest points of two triangles: the vertex-face candidates (a vertex over the
/// interior of the other, non-flat, triangle) and the nine edge-edge ones (which include
/// vertex-edge and vertex-vertex). The vertex-face winner must also be certain of its
/// side (exact); else the edge-edge winner, which then realizes the same distance.
///
/// First the common case of triangles within a band, nearly parallel, each wholly on one
/// side of the other's plane: [`vertex_over_face`] answers it without the nine edge pairs.
#[inline(always)]
fn closest(t: &Tri, u: &Tri) -> Closest {
    vertex_over_face(t, u, false)
        .or_else(|| vertex_over_face(u, t, true))
        .unwrap_or_else(|| closest_search(t, u))
}

/// [`closest`] by the full search: every edge pair, every vertex over a face.
#[inline(always)]
fn closest_search(t: &Tri, u: &Tri) -> Closest {
    let (i, j, EdgePair { p, q, d2, s, r }) = nearest_edge_pair(t, u);
    let mut best = Closest {
        p,
        q,
        d2,
        feature: Feature::EdgeEdge { i, j, s, r },
    };
    let mut vf: Option<Closest> = None;
    for k in 0..3 {
        // A candidate is taken only when nearer than the best so far (the nearest edge
        // pair, then the nearest vertex over a face): `over_face_below` drops the others
        // before testing their feet, the common case (the answer unchanged).
        let below = vf.as_ref().map_or(best.d2, |c| c.d2);
        if let Some((q, d2)) = over_face_below(&t.v[k], u, below) {
            if d2 < best.d2 && vf.as_ref().is_none_or(|c| d2 < c.d2) {
                vf = Some(Closest {
                    p: t.v[k],
                    q,
                    d2,
                    feature: Feature::VertexFace { k },
                });
            }
        }
        let below = vf.as_ref().map_or(best.d2, |c| c.d2);
        if let Some((p, d2)) = over_face_below(&u.v[k], t, below) {
            if d2 < best.d2 && vf.as_ref().is_none_or(|c| d2 < c.d2) {
                vf = Some(Closest {
                    p,
                    q: u.v[k],
                    d2,
                    feature: Feature::FaceVertex { k },
                });
            }
        }
    }
    if let Some(c) = vf {
        let certain = match c.feature {
            Feature::VertexFace { k } => orient3d(&u.p[0], &u.p[1], &u.p[2], &t.p[k]) != 0.0,
            Feature::FaceVertex { k } => orient3d(&t.p[0], &t.p[1], &t.p[2], &u.p[k]) != 0.0,
            Feature::EdgeEdge { .. } => false,
        };
        if certain {
            best = c;
        }
    }
    best
}

/// The closest points of `t` and `u` when they are certainly a vertex of `t` and its foot
/// on `u`: `u` is not flat, every vertex of `t` lies on one side of `u`'s plane (each
/// distance beyond its rounding), and the foot of the nearest one lies inside `u`. No point
/// of `t` is then nearer `u`'s plane than that vertex, so nothing of the two triangles is
/// nearer than the vertex and its foot: [`closest`]'s answer, found without its edge
/// pairs. (`swapped`: `t` and `u` are [`closest`]'s second and first triangles.) Among
/// vertices equally near, the first, as `closest` takes.
#[inline(always)]
fn vertex_over_face(t: &Tri, u: &Tri, swapped: bool) -> Option<Closest> {
    if u.flat {
        return None;
    }
    let n = &u.n;
    // The rounding of `n`'s components is below a few eps of the products behind them
    // (`|e| |f|`), of the dot product below a few eps of its terms: FACE_SLACK (1e-12)
    // leaves a margin of thousands.
    let (e, f) = (u.v[1] - u.v[0], u.v[2] - u.v[0]);
    let ef = e.amax() * f.amax();
    let n_scale = n.abs().sum() + 6.0 * ef;
    let (mut h, mut wmax) = ([0.0; 3], 0.0f64);
    for (h, v) in h.iter_mut().zip(&t.v) {
        let w = v - u.v[0];
        *h = n.dot(&w);
        wmax = wmax.max(w.amax());
        if h.abs() <= FACE_SLACK * n_scale * w.amax() {
            return None;
        }
    }
    if (h[0] > 0.0) != (h[1] > 0.0) || (h[1] > 0.0) != (h[2] > 0.0) {
        return None;
    }
    // That rounding also turns `n` by up to a few eps of `|e| |f| / |n|`, which moves a
    // vertex's distance by that times its lever `|w|`: on a sliver (`|n|` far below
    // `|e| |f|`) far more than the full search's error (its edge pairs do not use `n`).
    // Taken only where the turn moves it by a few eps of the pair's size: `u` not a
    // sliver (sin of its angle above about 1/4 here), or the lever short.
    let size = e.amax().max(f.amax()).max(wmax);
    if ef * wmax > 4.0 * n.amax() * size {
        return None;
    }
    let mut k = 0;
    for j in 1..3 {
        if h[j].abs() < h[k].abs() {
            k = j;
        }
    }
    let (foot, d2) = over_face(&t.v[k], u)?;
    // The feature's side, exactly (as `closest` requires of a vertex over a face); and a
    // finite distance (coordinates near the f64 range's end: the full search decides).
    if !d2.is_finite() || orient3d(&u.p[0], &u.p[1], &u.p[2], &t.p[k]) == 0.0 {
        return None;
    }
    Some(if swapped {
        Closest {
            p: foot,
            q: t.v[k],
            d2,
            feature: Feature::FaceVertex { k },
        }
    } else {
        Closest {
            p: t.v[k],
            q: foot,
            d2,
            feature: Feature::VertexFace { k },
        }
    })
}

/// [`over_face`] when its squared distance is below `limit` (`None` otherwise, or when
/// `limit` is NaN): the distance to the plane first, the three edge tests only for a
/// vertex near enough to matter. The same values as `over_face` where it answers.
#[inline(always)]
fn over_face_below(x: &V, f: &Tri, limit: f64) -> Option<(V, f64)> {
    if f.flat {
        return None;
    }
    let n = &f.n;
    let nn = n.norm_squared();
    if nn.is_nan() || nn <= 0.0 {
        return None;
    }
    let h = n.dot(&(x - f.v[0]));
    let d2 = h * h / nn;
    // (A NaN on either side drops the candidate, as the callers' comparisons would.)
    if d2 >= limit || d2.is_nan() || limit.is_nan() {
        return None;
    }
    let inside = (0..3).all(|e| {
        let (c0, c1) = (f.v[e], f.v[(e + 1) % 3]);
        (c1 - c0).cross(&(x - c0)).dot(n) >= 0.0
    });
    inside.then(|| (x - n * (h / nn), d2))
}

/// The foot of `x` on the plane of the non-flat triangle `f` and the squared distance,
/// when the foot lies inside the closed triangle (`None` otherwise or when `f` is flat).
#[inline(always)]
fn over_face(x: &V, f: &Tri) -> Option<(V, f64)> {
    if f.flat {
        return None;
    }
    let n = &f.n;
    let inside = (0..3).all(|e| {
        let (c0, c1) = (f.v[e], f.v[(e + 1) % 3]);
        (c1 - c0).cross(&(x - c0)).dot(n) >= 0.0
    });
    if !inside {
        return None;
    }
    let nn = n.norm_squared();
    if nn.is_nan() || nn <= 0.0 {
        return None;
    }
    let h = n.dot(&(x - f.v[0]));
    Some((x - n * (h / nn), h * h / nn))
}

/// The closest points of an edge of each triangle ([`segment_params`]).
#[derive(Clone, Copy, Default)]
struct EdgePair {
    /// On the first triangle's edge, at parameter `s`.
    p: V,
    /// On the second's, at parameter `r`.
    q: V,
    d2: f64,
    s: f64,
    r: f64,
}

/// The nearest edge pair of `t` and `u`, as `(i, j, pair)` for edge `i` of `t`
/// (`v[i]`-`v[i+1]`) and edge `j` of `u`: the first in order (`i`, then `j`) among those of
/// least `d2`. Three pairs at a time where the CPU has AVX2 (`edges.rs`, bit for bit the
/// same answer).
#[inline(always)]
fn nearest_edge_pair(t: &Tri, u: &Tri) -> (usize, usize, EdgePair) {
    #[cfg(target_arch = "x86_64")]
    if std::is_x86_feature_detected!("avx2") && std::is_x86_feature_detected!("fma") {
        // SAFETY: the CPU has AVX2 and FMA (checked just above).
        if let Some(n) = unsafe { edges::nearest_edge_pair(t, u) } {
            return n;
        }
    }
    nearest_edge_pair_scalar(t, u)
}

/// [`nearest_edge_pair`] one pair at a time.
#[inline(always)]
fn nearest_edge_pair_scalar(t: &Tri, u: &Tri) -> (usize, usize, EdgePair) {
    let mut best: Option<(usize, usize, EdgePair)> = None;
    for i in 0..3 {
        for j in 0..3 {
            let (p0, p1) = (t.v[i], t.v[(i + 1) % 3]);
            let (q0, q1) = (u.v[j], u.v[(j + 1) % 3]);
            let (s, r) = segment_params(&p0, &p1, &q0, &q1);
            let p = p0 + (p1 - p0) * s;
            let q = q0 + (q1 - q0) * r;
            let d2 = (p - q).norm_squared();
            if best.as_ref().is_none_or(|(_, _, b)| d2 < b.d2) {
                best = Some((i, j, EdgePair { p, q, d2, s, r }));
            }
        }
    }
    // (Nine pairs: never empty.)
    best.unwrap_or((0, 0, EdgePair::default()))
}

/// Parameters `(s, r)` of the closest points of segments `p0`-`p1` and `q0`-`q1` (either
/// may be a point), after Ericson, "Real-Time Collision Detection", 5.1.9. Parallel
/// segments take `s = 0` (then the closest point of the other).
#[inline(always)]
fn segment_params(p0: &V, p1: &V, q0: &V, q1: &V) -> (f64, f64) {
    let d1 = p1 - p0;
    let d2 = q1 - q0;
    let w = p0 - q0;
    let a = d1.norm_squared();
    let e = d2.norm_squared();
    let f = d2.dot(&w);
    if a == 0.0 && e == 0.0 {
        return (0.0, 0.0);
    }
    if a == 0.0 {
        return (0.0, (f / e).clamp(0.0, 1.0));
    }
    let c = d1.dot(&w);
    if e == 0.0 {
        return ((-c / a).clamp(0.0, 1.0), 0.0);
    }
    let b = d1.dot(&d2);
    let denom = a * e - b * b;
    let mut s = if denom > 0.0 {
        ((b * f - c * e) / denom).clamp(0.0, 1.0)
    } else {
        0.0
    };
    let r = (b * s + f) / e;
    let r = if r < 0.0 {
        s = (-c / a).clamp(0.0, 1.0);
        0.0
    } else if r > 1.0 {
        s = ((b - c) / a).clamp(0.0, 1.0);
        1.0
    } else {
        r
    };
    (s, r)
}

/// Two triangles known not to meet: [`band`] without the polygons' structures.
#[inline(always)]
fn band_triangles(a: &[P3; 3], b: &[P3; 3]) -> ContactGeometry {
    let o = a[0];
    let (t, u) = (Tri::new(a, &o), Tri::new(b, &o));
    let c = closest(&t, &u);
    let normal = feature_normal(&t, &u, &c)
        .and_then(|n| unit(&n))
        .or_else(|| unit(&(c.p - c.q)))
        .unwrap_or_else(|| {
            // Never for f32 input; the polygons' chain all the same.
            let a2 = [*a, *a];
            let b2 = [*b, *b];
            let (pa, pb) = (Poly::new(&a2, 1, &o), Poly::new(&b2, 1, &o));
            unit(&(pa.mean() - pb.mean())).unwrap_or_else(|| fallback_normal(&pa, &pb))
        });
    let depth = -(c.p - c.q).norm();
    let normal = separating(&t, &u, normal, -depth);
    let local = Local {
        p: c.p,
        q: c.q,
        normal,
        depth,
        intersecting: false,
        coplanar: false,
    };
    finish(&local, &o, &o)
}

/// Pairs within the band: the closest points over every triangle pair, and the normal
/// from their features.
fn band(pa: &Poly, pb: &Poly) -> Local {
    let mut best: Option<(Closest, usize, usize)> = None;
    for (i, t) in pa.tris().iter().enumerate() {
        for (j, u) in pb.tris().iter().enumerate() {
            let c = closest(t, u);
            if best.as_ref().is_none_or(|(b, _, _)| c.d2 < b.d2) {
                best = Some((c, i, j));
            }
        }
    }
    let Some((c, i, j)) = best else {
        // Unreachable (each polygon has a triangle); a defined answer all the same.
        return Local {
            p: pa.v[0],
            q: pb.v[0],
            normal: fallback_normal(pa, pb),
            depth: -(pa.v[0] - pb.v[0]).norm(),
            intersecting: false,
            coplanar: false,
        };
    };
    let normal = feature_normal(&pa.tris[i], &pb.tris[j], &c)
        .and_then(|n| unit(&n))
        .or_else(|| unit(&(c.p - c.q)))
        .or_else(|| unit(&(pa.mean() - pb.mean())))
        .unwrap_or_else(|| fallback_normal(pa, pb));
    let depth = -(c.p - c.q).norm();
    // (Checked on the nearest triangles, convex, not on the polygons: a quad bent or
    // not convex is not separated by its closest points' direction as its hull would be.)
    let normal = separating(&pa.tris[i], &pb.tris[j], normal, -depth);
    Local {
        p: c.p,
        q: c.q,
        normal,
        depth,
        intersecting: false,
        coplanar: false,
    }
}

/// A band pair's normal `n` (unit), checked where the distance `d` is so small against the
/// pair's size that the closest features may have been mistaken: below `1e-6` of it (a
/// placed mesh's vertex 1e-17 from the other's edge, whose `f64` positions put the nearest
/// edge parameters a rounding away from their ends). There, `n` must separate the two
/// triangles (the nearest two of the polygons: convex, so the direction of their closest
/// points separates them by exactly `d`) by about `d`; if it does not, the direction that
/// separates them most among every feature's, each built from the world positions with
/// the differences' rounding errors (the faces' normals, the edge-edge crosses, the
/// perpendiculars from each edge to each vertex of the other, the vertex-vertex
/// differences, either way round): the true direction is one of them. (Where `d` is far
/// below the coordinates' rounding, `eps` times the size, the gaps cannot tell the
/// candidates apart: the answer then separates the pair by `d` to within that rounding.)
#[cold]
fn separating_search(t: &Tri, u: &Tri, n: V, d: f64, size: f64) -> V {
    let gap = |n: &V| {
        let amin = t.v.iter().map(|v| n.dot(v)).fold(f64::INFINITY, f64::min);
        let bmax =
            u.v.iter()
                .map(|v| n.dot(v))
                .fold(f64::NEG_INFINITY, f64::max);
        amin - bmax
    };
    let mut best = (gap(&n), n);
    if best.0 >= d - 1e-9 * size {
        return n;
    }
    let mut offer = |c: V| {
        if let Some(m) = unit(&c) {
            for m in [m, -m] {
                let g = gap(&m);
                if g > best.0 {
                    best = (g, m);
                }
            }
        }
    };
    offer(t.n);
    offer(u.n);
    for i in 0..3 {
        let de = exact_diff(&t.p[(i + 1) % 3], &t.p[i]);
        for j in 0..3 {
            let df = exact_diff(&u.p[(j + 1) % 3], &u.p[j]);
            offer(cross_accurately(&de, &df));
            // u's vertex j against t's edge i, t's vertex i against u's edge j.
            offer(de.0.cross(&cross_accurately(&exact_diff(&u.p[j], &t.p[i]), &de)));
            offer(df.0.cross(&cross_accurately(&exact_diff(&t.p[i], &u.p[j]), &df)));
            let (h, l) = exact_diff(&t.p[i], &u.p[j]);
            offer(h + l);
        }
    }
    best.1
}

/// [`separating_search`] where the distance is below `1e-6` of the pair's size (else `n`).
#[inline(always)]
fn separating(t: &Tri, u: &Tri, n: V, d: f64) -> V {
    let size = t.v.iter().chain(&u.v).map(|v| v.amax()).fold(0.0, f64::max);
    if d < 1e-6 * size {
        separating_search(t, u, n, d, size)
    } else {
        n
    }
}

/// The direction from `c.q` (on `u`) to `c.p` (on `t`) computed from the features, with
/// exact signs where they decide: accurate however small the distance.
#[inline(always)]
fn feature_normal(t: &Tri, u: &Tri, c: &Closest) -> Option<V> {
    match c.feature {
        Feature::VertexFace { k } => {
            // t's vertex k over u's face: along u.n, on t's vertex's side (d = -orient3d).
            let o = orient3d(&u.p[0], &u.p[1], &u.p[2], &t.p[k]);
            (o != 0.0).then(|| u.n * -sign(o))
        }
        Feature::FaceVertex { k } => {
            // u's vertex k under t's face: from u's vertex towards t, against its side.
            let o = orient3d(&t.p[0], &t.p[1], &t.p[2], &u.p[k]);
            (o != 0.0).then(|| t.n * sign(o))
        }
        Feature::EdgeEdge { i, j, s, r } => {
            let (i1, j1) = ((i + 1) % 3, (j + 1) % 3);
            let (p0, p1, q0, q1) = (t.v[i], t.v[i1], u.v[j], u.v[j1]);
            let (e, f) = (p1 - p0, q1 - q0);
            let s_in = s > 0.0 && s < 1.0 && e != V::zeros();
            let r_in = r > 0.0 && r < 1.0 && f != V::zeros();
            // The vertex at an end of an edge, by its parameter.
            let tv = if s >= 1.0 { p1 } else { p0 };
            let uv = if r >= 1.0 { q1 } else { q0 };
            if s_in && r_in {
                // ((p1-p0) x (q1-q0)) . (p0-q0) = -orient3d(p0, p1, q0, q1).
                let o = orient3d(&t.p[i], &t.p[i1], &u.p[j], &u.p[j1]);
                let n = e.cross(&f);
                if o != 0.0 && n != V::zeros() {
                    return Some(n * -sign(o));
                }
                // Coplanar lines (or parallel in f64): the plain difference.
                return Some(c.p - c.q);
            }
            if s_in {
                // u's vertex against t's edge: the perpendicular from the edge, reversed.
                return Some(-e.cross(&(uv - p0).cross(&e)));
            }
            if r_in {
                return Some(f.cross(&(tv - q0).cross(&f)));
            }
            Some(tv - uv)
        }
    }
}

/// `a - b` as the rounded difference and its exact error (zero for `f32` positions).
#[inline(always)]
fn exact_diff(a: &P3, b: &P3) -> (V, V) {
    let (x, y, z) = (
        two_sum(a[0], -b[0]),
        two_sum(a[1], -b[1]),
        two_sum(a[2], -b[2]),
    );
    (V::new(x.0, y.0, z.0), V::new(x.1, y.1, z.1))
}

/// The cross product of two vectors given as unevaluated sums `hi + lo` (the
/// [`exact_diff`] of positions), each component to within about an ulp: the products of
/// the high parts error-free, the terms of first order in the low parts added (those of
/// second order are below the result's ulp unless it cancels to that level). A vertex
/// 1e-17 from an edge's line crossed with the edge, say, where the plain cross of the
/// rounded differences would be all rounding.
#[inline(always)]
fn cross_accurately((a, al): &(V, V), (b, bl): &(V, V)) -> V {
    let component =
        |(x, xl): (f64, f64), (y, yl): (f64, f64), (z, zl): (f64, f64), (w, wl): (f64, f64)| {
            // (x + xl)(y + yl) - (z + zl)(w + wl).
            let (p1, e1) = two_prod(x, y);
            let (p2, e2) = two_prod(z, w);
            let (h, e3) = two_sum(p1, -p2);
            h + ((e3 + (e1 - e2)) + ((x * yl + xl * y) - (z * wl + zl * w)))
        };
    V::new(
        component((a.y, al.y), (b.z, bl.z), (a.z, al.z), (b.y, bl.y)),
        component((a.z, al.z), (b.x, bl.x), (a.x, al.x), (b.z, bl.z)),
        component((a.x, al.x), (b.y, bl.y), (a.y, al.y), (b.x, bl.x)),
    )
}

#[cfg(test)]
mod tests {
    //! Every check here is independent of the code under test: exact predicates
    //! (`triangles_intersect`, `orient3d`) and double-double (about 106-bit) references built
    //! another way (the Minkowski difference's hull for the depth, edge/face incidences for
    //! the intersection, brute force over features for distances).

    use super::*;
    use crate::geom::tritri::{segments_intersect, triangles_intersect};
    use std::ops::{Add, Div, Mul, Neg, Sub};

    const EPS: f64 = f64::EPSILON;

    thread_local! {
        /// This thread's `contact_geometry_many` uses the AVX2 kernel even where the CPU
        /// has AVX-512 (both are tested where it has).
        pub(super) static AVX2_ONLY: std::cell::Cell<bool> = const { std::cell::Cell::new(false) };
    }

    /// `contact_geometry_many` with each kernel (AVX-512 where the CPU has it, and AVX2),
    /// which must answer bit for bit alike.
    fn both_kernels<P: PolygonPairs + Clone>(
        out: &mut [ContactGeometry],
        known: bool,
        fetch: P,
    ) -> Result<(), P::Error>
    where
        P::Error: std::fmt::Debug,
    {
        let mut other = out.to_vec();
        AVX2_ONLY.with(|c| c.set(true));
        let avx2 = contact_geometry_many(&mut other, known, fetch.clone());
        AVX2_ONLY.with(|c| c.set(false));
        avx2.unwrap();
        contact_geometry_many(out, known, fetch)?;
        for (g, h) in out.iter().zip(&other) {
            assert_eq!(bits(g), bits(h), "{g:?} {h:?}");
        }
        Ok(())
    }

    /// A polygon's triangles into the places `contact_geometry_many`'s fetch is given.
    fn put(dst: [&mut [P3; 3]; 2], src: &[[P3; 3]; 2]) {
        let [first, second] = dst;
        (*first, *second) = (src[0], src[1]);
    }

    /// Every field's bits, for comparisons bit for bit.
    fn bits(g: &ContactGeometry) -> Vec<u64> {
        let mut v: Vec<u64> = [g.point_a, g.point_b, g.normal]
            .iter()
            .flatten()
            .map(|x| x.to_bits())
            .collect();
        v.extend([g.depth.to_bits(), g.intersecting as u64, g.coplanar as u64]);
        v
    }

    /// `g` with every -0 made +0 (what adding a zero origin does).
    fn plus_zero(g: &ContactGeometry) -> ContactGeometry {
        let z = |v: [f64; 3]| v.map(|x| x + 0.0);
        ContactGeometry {
            point_a: z(g.point_a),
            point_b: z(g.point_b),
            normal: z(g.normal),
            depth: g.depth + 0.0,
            ..*g
        }
    }

    /// The pairs of a slice, as `contact_geometry_many` reads them.
    fn fetch_from(pairs: &[(Polygon, Polygon)]) -> impl PolygonPairs<Error = ()> + Clone + '_ {
        polygon_pairs(move |i, a, b| {
            put(a, &pairs[i].0.t);
            put(b, &pairs[i].1.t);
            Ok::<_, ()>((pairs[i].0.n, pairs[i].1.n))
        })
    }

    // ---------------------------------------------------------------- double-double

    /// An unevaluated sum `hi + lo`, about 106 bits.
    #[derive(Clone, Copy, Debug, PartialEq, PartialOrd)]
    struct Dd(f64, f64);

    fn two_sum(a: f64, b: f64) -> (f64, f64) {
        let s = a + b;
        let bb = s - a;
        (s, (a - (s - bb)) + (b - bb))
    }

    fn quick(a: f64, b: f64) -> Dd {
        let s = a + b;
        Dd(s, b - (s - a))
    }

    impl From<f64> for Dd {
        fn from(x: f64) -> Dd {
            Dd(x, 0.0)
        }
    }

    impl Add for Dd {
        type Output = Dd;
        fn add(self, y: Dd) -> Dd {
            let (s, e) = two_sum(self.0, y.0);
            let (t, f) = two_sum(self.1, y.1);
            let r = quick(s, e + t);
            quick(r.0, r.1 + f)
        }
    }

    impl Neg for Dd {
        type Output = Dd;
        fn neg(self) -> Dd {
            Dd(-self.0, -self.1)
        }
    }

    impl Sub for Dd {
        type Output = Dd;
        fn sub(self, y: Dd) -> Dd {
            self + -y
        }
    }

    impl Mul for Dd {
        type Output = Dd;
        fn mul(self, y: Dd) -> Dd {
            let p = self.0 * y.0;
            let e = self.0.mul_add(y.0, -p);
            quick(p, e + (self.0 * y.1 + self.1 * y.0))
        }
    }

    impl Div for Dd {
        type Output = Dd;
        fn div(self, y: Dd) -> Dd {
            let q1 = self.0 / y.0;
            let r = self - y * Dd::from(q1);
            let q2 = r.0 / y.0;
            let r = r - y * Dd::from(q2);
            let q3 = r.0 / y.0;
            let q = quick(q1, q2);
            q + Dd::from(q3)
        }
    }

    impl Dd {
        fn sqrt(self) -> Dd {
            if self.0 <= 0.0 {
                return Dd(0.0, 0.0);
            }
            let s = self.0.sqrt();
            let s = Dd::from(s);
            s + (self - s * s) / (Dd::from(2.0) * s)
        }
        fn abs(self) -> Dd {
            if self.0 < 0.0 {
                -self
            } else {
                self
            }
        }
        fn f(self) -> f64 {
            self.0 + self.1
        }
    }

    type D3 = [Dd; 3];

    fn d3(p: &P3) -> D3 {
        p.map(Dd::from)
    }
    fn sub3(a: &D3, b: &D3) -> D3 {
        [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
    }
    fn add3(a: &D3, b: &D3) -> D3 {
        [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
    }
    fn scale3(a: &D3, s: Dd) -> D3 {
        [a[0] * s, a[1] * s, a[2] * s]
    }
    fn dot3(a: &D3, b: &D3) -> Dd {
        a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
    }
    fn cross3(a: &D3, b: &D3) -> D3 {
        [
            a[1] * b[2] - a[2] * b[1],
            a[2] * b[0] - a[0] * b[2],
            a[0] * b[1] - a[1] * b[0],
        ]
    }
    fn norm3(a: &D3) -> Dd {
        dot3(a, a).sqrt()
    }
    fn zero3(a: &D3) -> bool {
        a.iter().all(|x| x.0 == 0.0)
    }
    fn to_f(a: &D3) -> P3 {
        a.map(Dd::f)
    }
    /// |p - q| with `q` in double-double.
    fn dist_dd(p: &P3, q: &D3) -> f64 {
        norm3(&sub3(&d3(p), q)).f()
    }

    // ---------------------------------------------------------------- references

    /// Closest point to `x` on the closed segment `a`-`b`, double-double.
    fn seg_closest(x: &D3, a: &D3, b: &D3) -> D3 {
        let e = sub3(b, a);
        let ee = dot3(&e, &e);
        let t = if ee.0 == 0.0 {
            Dd::from(0.0)
        } else {
            let t = dot3(&sub3(x, a), &e) / ee;
            if t.0 < 0.0 {
                Dd::from(0.0)
            } else if t.0 > 1.0 {
                Dd::from(1.0)
            } else {
                t
            }
        };
        add3(a, &scale3(&e, t))
    }

    /// Closest point to `x` on the closed triangle `t`, double-double: the foot on the
    /// plane when it is inside, else the nearest point of the edges.
    fn tri_closest(x: &D3, t: &[P3; 3]) -> D3 {
        let v = t.map(|p| d3(&p));
        if !collinear(&t[0], &t[1], &t[2]) {
            let n = cross3(&sub3(&v[1], &v[0]), &sub3(&v[2], &v[0]));
            let inside = (0..3).all(|i| {
                let e = sub3(&v[(i + 1) % 3], &v[i]);
                dot3(&cross3(&e, &sub3(x, &v[i])), &n).0 >= 0.0
            });
            if inside {
                let h = dot3(&n, &sub3(x, &v[0])) / dot3(&n, &n);
                return sub3(x, &scale3(&n, h));
            }
        }
        let mut best = (Dd::from(f64::INFINITY), *x);
        for i in 0..3 {
            let c = seg_closest(x, &v[i], &v[(i + 1) % 3]);
            let d = norm3(&sub3(x, &c));
            if d < best.0 {
                best = (d, c);
            }
        }
        best.1
    }

    fn tri_dist(x: &D3, t: &[P3; 3]) -> Dd {
        norm3(&sub3(x, &tri_closest(x, t)))
    }

    fn poly_dist(x: &P3, p: &Polygon) -> f64 {
        p.tris()
            .iter()
            .map(|t| tri_dist(&d3(x), t).f())
            .fold(f64::INFINITY, f64::min)
    }

    /// Closest points of closed segments, double-double (each end against the other
    /// segment, and the lines' closest points when both are interior).
    fn seg_seg_closest(p0: &D3, p1: &D3, q0: &D3, q1: &D3) -> (Dd, D3, D3) {
        let mut best = (Dd::from(f64::INFINITY), *p0, *q0);
        let mut offer = |p: D3, q: D3| {
            let d = norm3(&sub3(&p, &q));
            if d < best.0 {
                best = (d, p, q);
            }
        };
        offer(*p0, seg_closest(p0, q0, q1));
        offer(*p1, seg_closest(p1, q0, q1));
        offer(seg_closest(q0, p0, p1), *q0);
        offer(seg_closest(q1, p0, p1), *q1);
        let e = sub3(p1, p0);
        let f = sub3(q1, q0);
        let w = sub3(p0, q0);
        let (a, b, c) = (dot3(&e, &e), dot3(&e, &f), dot3(&e, &w));
        let (ee, ff) = (dot3(&f, &f), dot3(&f, &w));
        let den = a * ee - b * b;
        if den.0 > 0.0 {
            let s = (b * ff - c * ee) / den;
            let r = (a * ff - b * c) / den;
            if s.0 > 0.0 && s.0 < 1.0 && r.0 > 0.0 && r.0 < 1.0 {
                offer(add3(p0, &scale3(&e, s)), add3(q0, &scale3(&f, r)));
            }
        }
        best
    }

    /// Distance and closest points of two polygons, double-double, over all feature
    /// pairs (vertex-triangle both ways, edge-edge).
    fn poly_poly_closest(a: &Polygon, b: &Polygon) -> (Dd, D3, D3) {
        let mut best = (
            Dd::from(f64::INFINITY),
            [Dd::from(0.0); 3],
            [Dd::from(0.0); 3],
        );
        let mut offer = |p: D3, q: D3| {
            let d = norm3(&sub3(&p, &q));
            if d < best.0 {
                best = (d, p, q);
            }
        };
        for t in a.tris() {
            for u in b.tris() {
                for k in 0..3 {
                    offer(d3(&t[k]), tri_closest(&d3(&t[k]), u));
                    offer(tri_closest(&d3(&u[k]), t), d3(&u[k]));
                    for l in 0..3 {
                        let (_, p, q) = seg_seg_closest(
                            &d3(&t[k]),
                            &d3(&t[(k + 1) % 3]),
                            &d3(&u[l]),
                            &d3(&u[(l + 1) % 3]),
                        );
                        offer(p, q);
                    }
                }
            }
        }
        best
    }

    /// The vertices of the intersection of two meeting closed triangles (exact incidence
    /// tests, double-double constructions): vertices of one in the other, crossings of
    /// coplanar edges, and edges piercing the other's plane inside it.
    fn reference_piece(t: &[P3; 3], u: &[P3; 3], out: &mut Vec<D3>) {
        let point_in = |x: &P3, w: &[P3; 3]| triangles_intersect(&[*x; 3], w);
        for (s, w) in [(t, u), (u, t)] {
            for x in s {
                if point_in(x, w) {
                    out.push(d3(x));
                }
            }
            // s's edges piercing w's plane inside w.
            if !collinear(&w[0], &w[1], &w[2]) {
                let wv = w.map(|p| d3(&p));
                let n = cross3(&sub3(&wv[1], &wv[0]), &sub3(&wv[2], &wv[0]));
                for i in 0..3 {
                    let (p, q) = (s[i], s[(i + 1) % 3]);
                    let dp = dot3(&n, &sub3(&d3(&p), &wv[0]));
                    let dq = dot3(&n, &sub3(&d3(&q), &wv[0]));
                    if (dp.0 > 0.0 && dq.0 < 0.0) || (dp.0 < 0.0 && dq.0 > 0.0) {
                        let x = add3(&d3(&p), &scale3(&sub3(&d3(&q), &d3(&p)), dp / (dp - dq)));
                        if triangles_intersect(&[p, q, q], w) {
                            out.push(x);
                        }
                    }
                }
            }
        }
        // Crossing edges (coplanar, not parallel).
        for i in 0..3 {
            for j in 0..3 {
                let (p, q) = (t[i], t[(i + 1) % 3]);
                let (r, s) = (u[j], u[(j + 1) % 3]);
                if !segments_intersect(&p, &q, &r, &s) {
                    continue;
                }
                let (p, q, r, s) = (d3(&p), d3(&q), d3(&r), d3(&s));
                let d1 = sub3(&q, &p);
                let d2 = sub3(&s, &r);
                let c = cross3(&d1, &d2);
                if !zero3(&c) {
                    let k = dot3(&cross3(&sub3(&r, &p), &d2), &c) / dot3(&c, &c);
                    out.push(add3(&p, &scale3(&d1, k)));
                }
            }
        }
    }

    /// The reference intersection ends: the farthest pair of every meeting triangle
    /// pair's piece vertices. `None` if the polygons do not meet.
    fn reference_ends(a: &Polygon, b: &Polygon) -> Option<(D3, D3)> {
        let mut pts = Vec::new();
        for t in a.tris() {
            for u in b.tris() {
                if triangles_intersect(t, u) {
                    reference_piece(t, u, &mut pts);
                }
            }
        }
        let mut best: Option<(D3, D3, Dd)> = None;
        for i in 0..pts.len() {
            for j in i..pts.len() {
                let d = norm3(&sub3(&pts[i], &pts[j]));
                if best.is_none_or(|(_, _, b)| d > b) {
                    best = Some((pts[i], pts[j], d));
                }
            }
        }
        best.map(|(p, q, _)| (p, q))
    }

    /// The penetration depth of the polygons' convex hulls, from the hull of their
    /// Minkowski difference `B - A` (every triple of its points spanning a supporting
    /// plane, exact orientation; distances double-double): (depth, outward unit normal).
    /// `None` when the difference is flat (no supporting triple with points off it).
    fn reference_depth(a: &Polygon, b: &Polygon) -> Option<(f64, P3)> {
        let mut d: Vec<P3> = Vec::new();
        for x in b.verts() {
            for y in a.verts() {
                let p = [0, 1, 2].map(|k| {
                    let (s, e) = two_sum(x[k], -y[k]);
                    assert_eq!(e, 0.0, "inexact difference");
                    s
                });
                if !d.contains(&p) {
                    d.push(p);
                }
            }
        }
        let mut best: Option<(Dd, P3)> = None;
        for i in 0..d.len() {
            for j in i + 1..d.len() {
                for k in j + 1..d.len() {
                    if collinear(&d[i], &d[j], &d[k]) {
                        continue;
                    }
                    let o: Vec<f64> = d.iter().map(|x| orient3d(&d[i], &d[j], &d[k], x)).collect();
                    let pos = o.iter().any(|&x| x > 0.0);
                    let neg = o.iter().any(|&x| x < 0.0);
                    if pos == neg {
                        continue; // both sides (not supporting) or all on it (flat)
                    }
                    let (p, q, r) = (d3(&d[i]), d3(&d[j]), d3(&d[k]));
                    let n = cross3(&sub3(&q, &p), &sub3(&r, &p));
                    let len = norm3(&n);
                    // Outward: away from the points off the plane. orient3d(p,q,r,x) > 0
                    // means x is on the side opposite to n.
                    let outward = if pos { 1.0 } else { -1.0 };
                    let dist = dot3(&n, &p) * Dd::from(outward) / len;
                    let unitn = to_f(&scale3(&n, Dd::from(outward) / len));
                    if best.is_none_or(|(b, _)| dist < b) {
                        best = Some((dist, unitn));
                    }
                }
            }
        }
        best.map(|(d, n)| (d.f(), n))
    }

    // ---------------------------------------------------------------- test polygons

    #[derive(Clone, Copy, Debug)]
    struct Polygon {
        t: [[P3; 3]; 2],
        n: usize,
    }

    impl Polygon {
        fn tri(p: [P3; 3]) -> Polygon {
            let p = p.map(|v| v.map(f32r));
            Polygon { t: [p, p], n: 1 }
        }
        fn quad(v: [P3; 4]) -> Polygon {
            let v = v.map(|v| v.map(f32r));
            Polygon {
                t: [[v[0], v[1], v[2]], [v[0], v[2], v[3]]],
                n: 2,
            }
        }
        fn tris(&self) -> &[[P3; 3]] {
            &self.t[..self.n]
        }
        fn verts(&self) -> Vec<P3> {
            let mut v: Vec<P3> = Vec::new();
            for t in self.tris() {
                for p in t {
                    if !v.contains(p) {
                        v.push(*p);
                    }
                }
            }
            v
        }
        fn moved(&self, d: &P3) -> Polygon {
            let mut p = *self;
            for t in &mut p.t {
                for v in t.iter_mut() {
                    for k in 0..3 {
                        v[k] += d[k];
                    }
                }
            }
            p
        }
    }

    fn f32r(x: f64) -> f64 {
        x as f32 as f64
    }

    fn geometry(a: &Polygon, b: &Polygon) -> ContactGeometry {
        contact_geometry(&a.t, a.n, &b.t, b.n)
    }

    fn meet(a: &Polygon, b: &Polygon) -> bool {
        a.tris()
            .iter()
            .any(|t| b.tris().iter().any(|u| triangles_intersect(t, u)))
    }

    /// Largest coordinate magnitude (the world scale of the points' errors).
    fn magnitude(a: &Polygon, b: &Polygon) -> f64 {
        a.verts()
            .iter()
            .chain(&b.verts())
            .flat_map(|p| p.iter().map(|x| x.abs()))
            .fold(0.0, f64::max)
    }

    /// Largest coordinate magnitude relative to `a`'s first vertex (the pair's own scale,
    /// that of the depth's and distances' errors).
    fn extent(a: &Polygon, b: &Polygon) -> f64 {
        let o = a.t[0][0];
        a.verts()
            .iter()
            .chain(&b.verts())
            .flat_map(|p| (0..3).map(move |k| (p[k] - o[k]).abs()))
            .fold(0.0, f64::max)
    }

    /// Both polygons shifted so that `a`'s first vertex is the origin (exact for these
    /// inputs), so translations round at the pair's scale.
    fn localized(a: &Polygon, b: &Polygon) -> (Polygon, Polygon) {
        let o = a.t[0][0].map(|x| -x);
        (a.moved(&o), b.moved(&o))
    }

    use crate::geom::test_rng::Rng;

    fn plus(o: &P3, v: &P3) -> P3 {
        [o[0] + v[0], o[1] + v[1], o[2] + v[2]]
    }

    fn combo(t: &[P3; 3], w: &[f64; 3]) -> P3 {
        [0, 1, 2].map(|k| w[0] * t[0][k] + w[1] * t[1][k] + w[2] * t[2][k])
    }

    /// A random triangle of size `s` about `c`.
    fn random_tri(r: &mut Rng, c: &P3, s: f64) -> [P3; 3] {
        [plus(c, &r.v(s)), plus(c, &r.v(s)), plus(c, &r.v(s))]
    }

    /// A random pair of size `s` at `c` that (before rounding) shares an interior point.
    fn crossing_pair(r: &mut Rng, c: &P3, s: f64) -> (Polygon, Polygon) {
        let t = random_tri(r, c, s);
        let x = combo(&t, &r.bary());
        let u = random_tri(r, c, s);
        let y = combo(&u, &r.bary());
        let u = u.map(|p| [0, 1, 2].map(|k| p[k] + x[k] - y[k]));
        (Polygon::tri(t), Polygon::tri(u))
    }

    // ---------------------------------------------------------------- the checks

    /// Worst errors seen by [`check`], in units of `EPS * magnitude` (points) or
    /// `EPS * extent` (depth, distance, separation margin).
    #[derive(Default, Debug)]
    struct Worst {
        /// Reported points off either polygon.
        on_polygons: f64,
        /// Reported points off the exact intersection (two triangles crossing).
        on_intersection: f64,
        /// Reported ends against the reference ends (general position only).
        ends: f64,
        /// Depth against the reference hull depth.
        depth: f64,
        /// Smallest extra translation along the normal that separates.
        margin: f64,
        /// Distance against the reference distance (band).
        distance: f64,
        /// Band normal against the direction between the points (radians / EPS), when
        /// the distance is well above the rounding.
        band_normal: f64,
        cases: usize,
    }

    impl Worst {
        fn merge(&mut self, o: &Worst) {
            self.on_polygons = self.on_polygons.max(o.on_polygons);
            self.on_intersection = self.on_intersection.max(o.on_intersection);
            self.ends = self.ends.max(o.ends);
            self.depth = self.depth.max(o.depth);
            self.margin = self.margin.max(o.margin);
            self.distance = self.distance.max(o.distance);
            self.band_normal = self.band_normal.max(o.band_normal);
            self.cases += o.cases;
        }
    }

    fn basic(g: &ContactGeometry) {
        let all = g.point_a.iter().chain(&g.point_b).chain(&g.normal);
        assert!(
            all.clone().all(|x| x.is_finite()) && g.depth.is_finite(),
            "{g:?}"
        );
        let n2: f64 = g.normal.iter().map(|x| x * x).sum();
        assert!((n2 - 1.0).abs() < 8.0 * EPS, "normal not unit: {g:?}");
        if g.intersecting {
            assert!(g.depth >= 0.0, "{g:?}");
        } else {
            assert!(g.depth <= 0.0 && !g.coplanar, "{g:?}");
        }
        if g.coplanar {
            assert_eq!(g.depth, 0.0);
        }
    }

    /// Smallest `m` (0, 1, 2, 4, ...) such that moving `a` by
    /// `(depth + m EPS extent) * normal` separates the polygons, exactly.
    fn separation_margin(a: &Polygon, b: &Polygon, g: &ContactGeometry) -> f64 {
        let (la, lb) = localized(a, b);
        let unit = EPS * extent(a, b);
        let mut m = 0.0;
        loop {
            let d = (g.depth + m * unit).max(0.0);
            let moved = la.moved(&g.normal.map(|x| x * d));
            if !meet(&moved, &lb) {
                return m;
            }
            assert!(m < 1e9, "depth * normal does not separate: {g:?}");
            m = if m == 0.0 { 1.0 } else { m * 2.0 };
        }
    }

    /// Every check that applies to the pair, returning the errors seen. `general` says
    /// the pair is in general position (unique ends and facet: compare them directly).
    fn check(a: &Polygon, b: &Polygon, general: bool) -> Worst {
        let g = geometry(a, b);
        basic(&g);
        let mut w = Worst {
            cases: 1,
            ..Worst::default()
        };
        assert_eq!(g.intersecting, meet(a, b), "{a:?} {b:?}");
        let mag = EPS * magnitude(a, b).max(f64::MIN_POSITIVE);
        let ext = EPS * extent(a, b).max(f64::MIN_POSITIVE);
        w.on_polygons = poly_dist(&g.point_a, a) / mag;
        if g.intersecting {
            for d in [
                poly_dist(&g.point_b, a),
                poly_dist(&g.point_a, b),
                poly_dist(&g.point_b, b),
            ] {
                w.on_polygons = w.on_polygons.max(d / mag);
            }
            let (r0, r1) = reference_ends(a, b).expect("meeting polygons have a piece");
            let len_ref = norm3(&sub3(&r0, &r1)).f();
            let len = (0..3)
                .map(|k| (g.point_a[k] - g.point_b[k]).powi(2))
                .sum::<f64>()
                .sqrt();
            let ends = if general {
                let direct = dist_dd(&g.point_a, &r0).max(dist_dd(&g.point_b, &r1));
                let swapped = dist_dd(&g.point_a, &r1).max(dist_dd(&g.point_b, &r0));
                direct.min(swapped)
            } else {
                // Ties between extents of equal length: compare lengths only.
                (len - len_ref).abs()
            };
            w.ends = ends / mag;
            if a.n == 1 && b.n == 1 && !g.coplanar {
                for p in [&g.point_a, &g.point_b] {
                    let x = d3(p);
                    let d = norm3(&sub3(&x, &seg_closest(&x, &r0, &r1))).f();
                    w.on_intersection = w.on_intersection.max(d / mag);
                }
            }
            if g.coplanar {
                assert_eq!(g.depth, 0.0);
            } else {
                let m = separation_margin(a, b, &g);
                w.margin = m;
                if let Some((depth, n)) = reference_depth(a, b) {
                    w.depth = (g.depth - depth).abs() / ext;
                    if general && depth > 1e-3 * extent(a, b) {
                        let cos: f64 = (0..3).map(|k| n[k] * g.normal[k]).sum();
                        assert!(cos > 1.0 - 1e-9, "normal {:?} vs {n:?}", g.normal);
                    }
                }
                // Less than the depth along the normal leaves them meeting (triangles: the
                // ball of radius depth lies in the Minkowski difference).
                if a.n == 1 && b.n == 1 && g.depth > 1e-3 * extent(a, b) {
                    let (la, lb) = localized(a, b);
                    let moved = la.moved(&g.normal.map(|x| x * g.depth * (1.0 - 1e-9)));
                    assert!(meet(&moved, &lb), "depth too large along its normal: {g:?}");
                }
            }
        } else {
            w.on_polygons = w.on_polygons.max(poly_dist(&g.point_b, b) / mag);
            let (dist, ra, rb) = poly_poly_closest(a, b);
            w.distance = (-g.depth - dist.f()).abs() / ext;
            let d: P3 = [0, 1, 2].map(|k| g.point_a[k] - g.point_b[k]);
            let len = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
            assert!((len + g.depth).abs() <= 4.0 * (mag + ext), "{g:?}");
            if general && dist.0 > 0.0 {
                // The angle between the normal and the reference direction (exact b to a).
                let r = to_f(&scale3(&sub3(&ra, &rb), Dd::from(1.0) / dist));
                let n = &g.normal;
                let c = [
                    r[1] * n[2] - r[2] * n[1],
                    r[2] * n[0] - r[0] * n[2],
                    r[0] * n[1] - r[1] * n[0],
                ];
                let dot: f64 = (0..3).map(|k| r[k] * n[k]).sum();
                assert!(dot > 0.0, "band normal points the wrong way: {g:?}");
                w.band_normal = (c[0] * c[0] + c[1] * c[1] + c[2] * c[2]).sqrt() / EPS;
            }
        }
        w
    }

    fn report(name: &str, w: &Worst) {
        println!(
            "{name:>28}: {:>5} cases | on polygons {:>5.2} | on intersection {:>5.2} | ends \
             {:>5.2} | depth {:>5.2} | margin {:>2} | distance {:>5.2} | band normal {:>5.2}",
            w.cases,
            w.on_polygons,
            w.on_intersection,
            w.ends,
            w.depth,
            w.margin,
            w.distance,
            w.band_normal
        );
    }

    fn assert_within(w: &Worst, limit: f64) {
        for (what, x) in [
            ("on polygons", w.on_polygons),
            ("on intersection", w.on_intersection),
            ("ends", w.ends),
            ("depth", w.depth),
            ("margin", w.margin),
            ("distance", w.distance),
        ] {
            assert!(x <= limit, "{what} error {x} > {limit} units: {w:?}");
        }
    }

    fn close(p: &P3, q: &P3, tol: f64) -> bool {
        (0..3).all(|k| (p[k] - q[k]).abs() <= tol)
    }

    fn ends_are(g: &ContactGeometry, p: &P3, q: &P3, tol: f64) -> bool {
        (close(&g.point_a, p, tol) && close(&g.point_b, q, tol))
            || (close(&g.point_a, q, tol) && close(&g.point_b, p, tol))
    }

    // ---------------------------------------------------------------- known answers

    #[test]
    fn double_double_reference_is_sound() {
        let two = Dd::from(2.0);
        let r = two.sqrt();
        assert!((r * r - two).abs().f() < 1e-30);
        let third = Dd::from(1.0) / Dd::from(3.0);
        assert!((third * Dd::from(3.0) - Dd::from(1.0)).abs().f() < 1e-30);
        // The hull depth of a unit cube's corner configuration: a = triangle in z = 0,
        // b = a small tetrahedron-like triangle poking 0.25 below it.
        let a = Polygon::tri([[-10.0, -10.0, 0.0], [10.0, -10.0, 0.0], [0.0, 10.0, 0.0]]);
        let b = Polygon::tri([[0.0, 0.0, -0.25], [0.5, 0.0, -0.25], [0.0, 0.0, 1.0]]);
        let (d, n) = reference_depth(&a, &b).unwrap();
        assert!((d - 0.25).abs() < 1e-15 && close(&n, &[0.0, 0.0, -1.0], 1e-15));
        // The orientation identity the edge-edge band normal relies on.
        let mut r = Rng(99);
        for _ in 0..100 {
            let [p0, p1, q0, q1] = [r.v(1.0), r.v(1.0), r.v(1.0), r.v(1.0)];
            let (p0v, p1v, q0v, q1v) = (d3(&p0), d3(&p1), d3(&q0), d3(&q1));
            let x = dot3(
                &cross3(&sub3(&p1v, &p0v), &sub3(&q1v, &q0v)),
                &sub3(&p0v, &q0v),
            );
            assert_eq!(sign(x.f()), -sign(orient3d(&p0, &p1, &q0, &q1)));
        }
    }

    #[test]
    fn crossing_triangles_known_answer() {
        for o in [0.0, 1e3, 1e5] {
            let s = [o, o, o];
            let a =
                Polygon::tri([[-10.0, -10.0, 0.0], [10.0, -10.0, 0.0], [0.0, 10.0, 0.0]]).moved(&s);
            let b = Polygon::tri([[0.0, 0.0, -0.25], [0.5, 0.0, -0.25], [0.0, 0.0, 1.0]]).moved(&s);
            let g = geometry(&a, &b);
            basic(&g);
            assert!(g.intersecting && !g.coplanar);
            assert_eq!(g.depth, 0.25);
            assert_eq!(g.normal, [0.0, 0.0, -1.0]);
            let tol = 4.0 * EPS * (o + 1.0);
            assert!(ends_are(&g, &[o, o, o], &[o + 0.4, o, o], tol), "{g:?}");
            // Swapped: b moves up out of a.
            let g = geometry(&b, &a);
            assert_eq!(g.depth, 0.25);
            assert_eq!(g.normal, [0.0, 0.0, 1.0]);
            assert!(ends_are(&g, &[o, o, o], &[o + 0.4, o, o], tol), "{g:?}");
            check(&a, &b, true);
            check(&b, &a, true);
        }
    }

    #[test]
    fn coplanar_overlap_known_answer() {
        let a = Polygon::tri([[0.0, 0.0, 0.0], [2.0, 0.0, 0.0], [0.0, 2.0, 0.0]]);
        let b = Polygon::tri([[0.5, 0.5, 0.0], [3.0, 0.5, 0.0], [0.5, 3.0, 0.0]]);
        let g = geometry(&a, &b);
        assert!(g.intersecting && g.coplanar && g.depth == 0.0);
        assert_eq!(g.normal, [0.0, 0.0, 1.0]);
        assert!(
            ends_are(&g, &[1.5, 0.5, 0.0], &[0.5, 1.5, 0.0], 1e-15),
            "{g:?}"
        );
        // a wound the other way: its normal flips.
        let a2 = Polygon::tri([[0.0, 0.0, 0.0], [0.0, 2.0, 0.0], [2.0, 0.0, 0.0]]);
        assert_eq!(geometry(&a2, &b).normal, [0.0, 0.0, -1.0]);
        // Contained: the inner triangle's longest edge.
        let c = Polygon::tri([[0.1, 0.1, 0.0], [0.5, 0.1, 0.0], [0.1, 0.2, 0.0]]);
        let g = geometry(&a, &c);
        let (c1, c2) = ([0.5, 0.1, 0.0].map(f32r), [0.1, 0.2, 0.0].map(f32r));
        assert!(g.coplanar && ends_are(&g, &c1, &c2, 0.0), "{g:?}");
        // Touching at one vertex, and along part of an edge.
        let d = Polygon::tri([[2.0, 0.0, 0.0], [3.0, 0.0, 0.0], [3.0, 1.0, 0.0]]);
        let g = geometry(&a, &d);
        assert!(g.coplanar && ends_are(&g, &[2.0, 0.0, 0.0], &[2.0, 0.0, 0.0], 0.0));
        let e = Polygon::tri([[1.0, 0.0, 0.0], [3.0, 0.0, 0.0], [2.0, -1.0, 0.0]]);
        let g = geometry(&a, &e);
        assert!(g.coplanar && ends_are(&g, &[1.0, 0.0, 0.0], &[2.0, 0.0, 0.0], 1e-15));
        for (x, y) in [(&a, &b), (&a, &c), (&a, &d), (&a, &e), (&b, &a), (&e, &a)] {
            check(x, y, false);
        }
    }

    #[test]
    fn touching_is_intersecting_with_zero_depth() {
        let t = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
        let cases = [
            // Vertex on the face.
            [[0.25, 0.25, 0.0], [0.2, 0.2, 1.0], [0.3, 0.4, 1.0]],
            // Shared edge, different planes.
            [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.5, 0.0, 1.0]],
            // Shared vertex only.
            [[1.0, 0.0, 0.0], [2.0, 0.0, 1.0], [2.0, 1.0, 1.0]],
            // Vertex on an edge from the other side.
            [[0.5, 0.0, 0.0], [0.5, -1.0, 1.0], [0.5, -1.0, -1.0]],
            // Edge across an edge.
            [[0.5, -0.5, 0.0], [0.5, 0.5, 0.0], [0.5, 0.0, 1.0]],
        ];
        for o in [0.0, 1e5] {
            let s = [o, o, o];
            for u in &cases {
                let (a, b) = (Polygon::tri(t).moved(&s), Polygon::tri(*u).moved(&s));
                for (x, y) in [(&a, &b), (&b, &a)] {
                    let g = geometry(x, y);
                    assert!(g.intersecting && !g.coplanar, "{u:?}");
                    assert_eq!(g.depth, 0.0, "{u:?} {g:?}");
                    check(x, y, false);
                }
            }
        }
        // The vertex on the face: the intersection is that point.
        let g = geometry(&Polygon::tri(t), &Polygon::tri(cases[0]));
        assert_eq!(g.point_a, [0.25, 0.25, 0.0]);
        assert_eq!(g.point_b, [0.25, 0.25, 0.0]);
        // The shared edge: its two ends.
        let g = geometry(&Polygon::tri(t), &Polygon::tri(cases[1]));
        assert!(ends_are(&g, &[0.0; 3], &[1.0, 0.0, 0.0], 0.0), "{g:?}");
    }

    #[test]
    fn degenerate_polygons() {
        let t = Polygon::tri([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]);
        // A segment piercing the face: one point; depth: out through the nearest edges.
        let s = Polygon::tri([[0.2, 0.2, -1.0], [0.2, 0.2, 1.0], [0.2, 0.2, 0.5]]);
        for (x, y) in [(&s, &t), (&t, &s)] {
            let g = geometry(x, y);
            assert!(g.intersecting && !g.coplanar);
            let m = [0.2, 0.2, 0.0].map(f32r);
            assert!(ends_are(&g, &m, &m, 0.0), "{g:?}");
            assert_eq!(g.depth, f32r(0.2), "{g:?}");
            check(x, y, false);
        }
        // A point on the face: coplanar, normal = the face's (the point has none).
        let p = Polygon::tri([[0.2, 0.2, 0.0]; 3]);
        let g = geometry(&p, &t);
        assert!(g.intersecting && g.coplanar && g.depth == 0.0);
        assert_eq!(g.normal, [0.0, 0.0, 1.0]);
        let q = [0.2, 0.2, 0.0].map(f32r);
        assert_eq!((g.point_a, g.point_b), (q, q));
        // Two crossing segments: coplanar, meeting in a point; normal across both.
        let sa = Polygon::tri([[-1.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 0.0, 0.0]]);
        let sb = Polygon::tri([[0.0, -1.0, 0.0], [0.0, 1.0, 0.0], [0.0, 1.0, 0.0]]);
        let g = geometry(&sa, &sb);
        assert!(g.intersecting && g.coplanar && g.depth == 0.0);
        assert_eq!((g.point_a, g.point_b), ([0.0; 3], [0.0; 3]));
        assert_eq!(g.normal[2].abs(), 1.0);
        // Collinear overlapping segments: the overlap's ends; normal across the line.
        let sc = Polygon::tri([[0.5, 0.0, 0.0], [3.0, 0.0, 0.0], [3.0, 0.0, 0.0]]);
        let g = geometry(&sa, &sc);
        assert!(g.intersecting && g.coplanar);
        assert!(
            ends_are(&g, &[0.5, 0.0, 0.0], &[1.0, 0.0, 0.0], 0.0),
            "{g:?}"
        );
        assert_eq!(g.normal[0], 0.0);
        // The same point twice: +z.
        let g = geometry(&p, &p);
        assert!(g.intersecting && g.coplanar && g.normal == [0.0, 0.0, 1.0]);
        // A point on a segment.
        let on = Polygon::tri([[0.25, 0.0, 0.0]; 3]);
        let g = geometry(&on, &sa);
        assert!(g.intersecting && g.coplanar && g.point_a == [0.25, 0.0, 0.0]);
        assert_eq!(g.normal[0], 0.0);
        // A segment in the triangle's plane across it: the clipped segment.
        let across = Polygon::tri([[-1.0, 0.25, 0.0], [2.0, 0.25, 0.0], [2.0, 0.25, 0.0]]);
        let g = geometry(&across, &t);
        assert!(g.intersecting && g.coplanar);
        assert!(
            ends_are(&g, &[0.0, 0.25, 0.0], &[0.75, 0.25, 0.0], 1e-16),
            "{g:?}"
        );
        assert_eq!(g.normal, [0.0, 0.0, 1.0]); // t's, the segment having none
                                               // Skew segments 0.5 apart: band, normal along their cross, from b to a.
        let up = Polygon::tri([[0.0, -1.0, 0.5], [0.0, 1.0, 0.5], [0.0, 1.0, 0.5]]);
        let g = geometry(&up, &sa);
        assert!(!g.intersecting && g.depth == -0.5);
        assert_eq!(g.normal, [0.0, 0.0, 1.0]);
        assert_eq!((g.point_a, g.point_b), ([0.0, 0.0, 0.5], [0.0; 3]));
        let g = geometry(&sa, &up);
        assert_eq!(g.normal, [0.0, 0.0, -1.0]);
        // A point under the face.
        let below = Polygon::tri([[0.25, 0.25, -1e-7]; 3]);
        let g = geometry(&below, &t);
        assert!(!g.intersecting && g.normal == [0.0, 0.0, -1.0]);
        assert_eq!(g.depth, -f32r(1e-7));
        let g = geometry(&t, &below);
        assert!(!g.intersecting && g.normal == [0.0, 0.0, 1.0]);
        // A quad whose second triangle is a segment (v3 = v2), and one that is a point.
        let q = Polygon::quad([
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, 1.0, 0.0],
            [1.0, 1.0, 0.0],
        ]);
        let pierce = Polygon::tri([[0.5, 0.25, -1.0], [0.5, 0.25, 1.0], [0.6, 0.25, 1.0]]);
        let g = geometry(&q, &pierce);
        assert!(g.intersecting && !g.coplanar);
        let flatq = Polygon::quad([[0.0; 3]; 4]);
        let g = geometry(&flatq, &t);
        assert!(g.intersecting && g.coplanar && g.normal == [0.0, 0.0, 1.0]);
        for (x, y) in [
            (&s, &t),
            (&p, &t),
            (&sa, &sb),
            (&sa, &sc),
            (&on, &sa),
            (&across, &t),
            (&up, &sa),
            (&below, &t),
            (&q, &pierce),
            (&flatq, &t),
            (&p, &p),
        ] {
            check(x, y, false);
            check(y, x, false);
        }
    }

    #[test]
    fn band_known_answers() {
        // Parallel faces 0.5 apart: any pair of facing points; normal from b (above) to a.
        let a = Polygon::tri([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]);
        let b = Polygon::tri([[0.0, 0.0, 0.5], [1.0, 0.0, 0.5], [0.0, 1.0, 0.5]]);
        let g = geometry(&a, &b);
        assert!(!g.intersecting && g.depth == -0.5 && g.normal == [0.0, 0.0, -1.0]);
        // Coplanar but apart: the band geometry, not flagged coplanar.
        let c = Polygon::tri([[2.0, 0.0, 0.0], [3.0, 0.0, 0.0], [3.0, 1.0, 0.0]]);
        let g = geometry(&a, &c);
        assert!(!g.intersecting && !g.coplanar && g.depth == -1.0);
        assert_eq!(g.normal, [-1.0, 0.0, 0.0]);
        assert_eq!((g.point_a, g.point_b), ([1.0, 0.0, 0.0], [2.0, 0.0, 0.0]));
        // Edge over edge, crossing at right angles one f32 ulp apart at 1e5.
        let o = 1e5;
        let e1 = Polygon::tri([[o - 1.0, o, o], [o + 1.0, o, o], [o, o - 1.0, o - 1.0]]);
        let gap = 2f64.powi(-7);
        let e2 = Polygon::tri([
            [o, o - 1.0, o + gap],
            [o, o + 1.0, o + gap],
            [o + 1.0, o, o + 1.0],
        ]);
        let g = geometry(&e2, &e1);
        assert!(!g.intersecting && g.depth == -gap, "{g:?}");
        assert_eq!(g.normal, [0.0, 0.0, 1.0]);
        for (x, y) in [(&a, &b), (&a, &c), (&e1, &e2)] {
            check(x, y, true);
            check(y, x, true);
        }
    }

    // ---------------------------------------------------------------- random families

    /// Scales and offsets the accuracy is measured at: (offset, size).
    const FRAMES: [(f64, f64); 7] = [
        (0.0, 1.0),
        (0.0, 1e-4),
        (0.0, 1e4),
        (1e3, 1.0),
        (1e5, 1.0),
        (1e5, 100.0),
        (-3e4, 0.3),
    ];

    fn run(name: &str, limit: f64, mut case: impl FnMut(&mut Rng, &P3, f64) -> Worst) -> Worst {
        let mut all = Worst::default();
        for (f, &(o, s)) in FRAMES.iter().enumerate() {
            let mut r = Rng(0x9E37_79B9_7F4A_7C15 ^ ((f as u64 + 1) * 0x1234_5678));
            let mut w = Worst::default();
            let c = [o, 0.7 * o, -0.4 * o];
            for _ in 0..400 {
                w.merge(&case(&mut r, &c, s));
            }
            report(&format!("{name} @{o:e} x{s:e}"), &w);
            all.merge(&w);
        }
        report(name, &all);
        assert_within(&all, limit);
        all
    }

    #[test]
    fn random_crossing_triangles() {
        let w = run("crossing triangles", 16.0, |r, c, s| {
            let (a, b) = crossing_pair(r, c, s);
            check(&a, &b, true)
        });
        assert!(w.cases > 2000);
    }

    #[test]
    fn random_crossing_quads_and_mixed() {
        run("crossing quads/mixed", 16.0, |r, c, s| {
            let (t, u) = crossing_pair(r, c, s);
            // Extend either triangle to a quad by a fourth vertex beyond an edge (planar or
            // not, convex or not).
            let extend = |r: &mut Rng, p: &Polygon| {
                let t = p.t[0];
                let w = [r.f() + 0.5, 0.0, 0.0];
                let mid = combo(&t, &[0.0, 1.0 - w[0], w[0]]);
                let away = [0, 1, 2].map(|k| mid[k] + (mid[k] - t[0][k]) * (r.f() + 0.6));
                let h = [0.0, 0.1, 1.0][(r.next() % 3) as usize];
                let lift = r.v(s * h);
                Polygon::quad([t[0], t[1], t[2], plus(&away, &lift)])
            };
            let (a, b) = match r.next() % 3 {
                0 => (extend(r, &t), u),
                1 => (t, extend(r, &u)),
                _ => (extend(r, &t), extend(r, &u)),
            };
            check(&a, &b, true)
        });
    }

    #[test]
    fn random_coplanar_pairs() {
        run("coplanar", 16.0, |r, c, s| {
            // In an axis plane (exact after rounding), overlapping or nearly touching.
            let ax = (r.next() % 3) as usize;
            let z = c[ax] + r.f() * s;
            let pt = |r: &mut Rng, spread: f64| {
                let mut p = plus(c, &r.v(spread));
                p[ax] = z;
                p
            };
            let a = if r.next() % 2 == 0 {
                Polygon::tri([pt(r, s), pt(r, s), pt(r, s)])
            } else {
                Polygon::quad([pt(r, s), pt(r, s), pt(r, s), pt(r, s)])
            };
            let b = Polygon::tri([pt(r, s), pt(r, s), pt(r, s)]);
            let g = geometry(&a, &b);
            assert!(g.coplanar == g.intersecting, "{g:?}");
            let w = check(&a, &b, false);
            assert!(w.on_polygons < 16.0, "{a:?} {b:?} {g:?} {w:?}");
            w
        });
    }

    /// Near misses at 1e-3 .. 1e-7 of the size: b's nearest vertex (or edge) that far
    /// above a's face, or a moved off b by depth + gap along the separating normal.
    #[test]
    fn near_misses() {
        let mut gaps = [1e-3, 1e-4, 1e-5, 1e-6, 1e-7].iter().cycle();
        run("near misses", 16.0, |r, c, s| {
            let gap = gaps.next().copied().unwrap_or(1e-3) * s;
            let (a, b) = crossing_pair(r, c, s);
            if r.next() % 2 == 0 {
                let g = geometry(&a, &b);
                let d = g.normal.map(|x| x * (g.depth + gap));
                let moved = Polygon::tri(a.moved(&d).t[0]);
                check(&moved, &b, true)
            } else {
                let t = a.t[0];
                let x = combo(&t, &r.bary());
                let n = {
                    let e = [0, 1, 2].map(|k| t[1][k] - t[0][k]);
                    let f = [0, 1, 2].map(|k| t[2][k] - t[0][k]);
                    let n = [
                        e[1] * f[2] - e[2] * f[1],
                        e[2] * f[0] - e[0] * f[2],
                        e[0] * f[1] - e[1] * f[0],
                    ];
                    let l = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
                    n.map(|v| v / l)
                };
                let at = |h: f64, r: &mut Rng| {
                    let lat = r.v(s);
                    [0, 1, 2].map(|k| x[k] + n[k] * h + lat[k])
                };
                let near = [0, 1, 2].map(|k| x[k] + n[k] * gap);
                let b = Polygon::tri([near, at(s, r), at(s * 0.7, r)]);
                check(&a, &b, true)
            }
        });
    }

    /// The nearest edge pair found in AVX2 lanes (`edges.rs`) is the scalar search's, bit
    /// for bit and the same pair among equals: on random pairs at every scale and offset,
    /// on degenerate ones (edges of length 0, triangles that are points or segments,
    /// parallel and collinear edges, a shared vertex, a triangle and its copy moved along
    /// its normal: many pairs equally near), and at coordinates near the f64 range's end
    /// (NaN distances: left to the scalar search).
    #[cfg(target_arch = "x86_64")]
    #[test]
    fn nearest_edge_pair_in_lanes_is_the_scalar_one() {
        if !(std::is_x86_feature_detected!("avx2") && std::is_x86_feature_detected!("fma")) {
            return;
        }
        let key = |(i, j, e): (usize, usize, EdgePair)| {
            let mut v = vec![i as u64, j as u64];
            v.extend(
                [e.d2, e.s, e.r]
                    .iter()
                    .chain(e.p.iter())
                    .chain(e.q.iter())
                    // Bits as they are (-0 is not 0 here).
                    .map(|x| x.to_bits()),
            );
            v
        };
        let mut r = Rng(4242);
        let (mut n, mut ties, mut left) = (0, 0, 0);
        for &(o, s) in FRAMES.iter().chain(&[(0.0, 1e155), (1e154, 1.0)]) {
            let c = [o, 0.7 * o, -0.4 * o];
            for i in 0..900 {
                let mut t = random_tri(&mut r, &c, s);
                let mut u = random_tri(&mut r, &c, s);
                match i % 9 {
                    // Repeated corners: an edge of length 0, a segment, a point.
                    1 => t[1] = t[0],
                    2 => u[2] = u[1],
                    3 => (t[1], t[2]) = (t[0], t[0]),
                    4 => (u[1], u[2]) = (u[0], u[0]),
                    // Parallel edges (u's first edge a shifted copy of t's), collinear
                    // corners, a shared vertex, a copy along the normal.
                    5 => {
                        let d = r.v(s);
                        (u[0], u[1]) = (plus(&t[0], &d), plus(&t[1], &d));
                    }
                    6 => t[2] = combo(&[t[0], t[1], t[1]], &[0.25, 0.75, 0.0]),
                    7 => u[0] = t[2],
                    8 => {
                        let (e, f) = (local(&t[1], &t[0]), local(&t[2], &t[0]));
                        let up = e.cross(&f) * (0.1 / e.norm().max(f.norm()));
                        u = t.map(|p| [p[0] + up.x, p[1] + up.y, p[2] + up.z]);
                    }
                    _ => {}
                }
                let o3 = t[0];
                let (ta, tb) = (Tri::new(&t, &o3), Tri::new(&u, &o3));
                let scalar = nearest_edge_pair_scalar(&ta, &tb);
                // SAFETY: the CPU has AVX2 and FMA (checked above).
                match unsafe { edges::nearest_edge_pair(&ta, &tb) } {
                    Some(lanes) => assert_eq!(key(lanes), key(scalar), "{t:?} {u:?}"),
                    None => {
                        left += 1;
                        assert!(scalar.2.d2.is_nan() || s > 1e150 || o > 1e150);
                    }
                }
                assert_eq!(key(nearest_edge_pair(&ta, &tb)), key(scalar));
                // Pairs as near as the nearest, after it in the order.
                let all = {
                    let mut d = Vec::new();
                    for i in 0..3 {
                        for j in 0..3 {
                            let (p0, p1) = (ta.v[i], ta.v[(i + 1) % 3]);
                            let (q0, q1) = (tb.v[j], tb.v[(j + 1) % 3]);
                            let (s, r) = segment_params(&p0, &p1, &q0, &q1);
                            d.push(((p0 + (p1 - p0) * s) - (q0 + (q1 - q0) * r)).norm_squared());
                        }
                    }
                    d
                };
                ties += usize::from(all.iter().filter(|&&d| d == scalar.2.d2).count() > 1);
                n += 1;
            }
        }
        assert!(n > 8000 && ties > 500 && left > 0, "{n} {ties} {left}");
    }

    /// [`vertex_over_face`], the band's shortcut, against the full search it skips: on
    /// nearly parallel pairs apart by 1e-1..1e-7 of their size (tilted up to 1e-2, at
    /// every scale and offset), whenever it answers, the same distance as
    /// [`closest_search`] to within its rounding and, to within the check's tolerance, the
    /// exact one (`check`); it answers many of them (43%); and it declines a triangle with a
    /// vertex on the other's plane (exactly) or crossing it.
    #[test]
    fn vertex_over_face_is_the_full_search() {
        let mut r = Rng(77);
        let (mut hits, mut cases) = (0, 0);
        for &(o, s) in FRAMES.iter() {
            let c = [o, 0.7 * o, -0.4 * o];
            for i in 0..600 {
                let t = random_tri(&mut r, &c, s);
                let gap = s * [1e-1, 1e-3, 1e-5, 1e-7][i % 4];
                let tilt = [0.0, 1e-6, 1e-2][i % 3];
                // u: t shrunk or grown about a random point, shifted sideways and off the
                // plane by `gap`, each vertex tilted by up to `tilt`.
                let x = combo(&t, &r.bary());
                let (g, shrink) = (r.v(s * 0.3), 0.3 + r.unit());
                let n = unit(&local(&t[1], &t[0]).cross(&local(&t[2], &t[0]))).unwrap();
                let u = t.map(|p| {
                    let h = gap + tilt * s * r.f();
                    [0, 1, 2].map(|k| x[k] + (p[k] - x[k]) * shrink + g[k] + n[k] * h)
                });
                let (a, b) = if i % 2 == 0 {
                    (Polygon::tri(t), Polygon::tri(u))
                } else {
                    (Polygon::tri(u), Polygon::tri(t))
                };
                if meet(&a, &b) {
                    continue;
                }
                cases += 1;
                let o3 = a.t[0][0];
                let (ta, tb) = (Tri::new(&a.t[0], &o3), Tri::new(&b.t[0], &o3));
                let full = closest_search(&ta, &tb);
                let short =
                    vertex_over_face(&ta, &tb, false).or_else(|| vertex_over_face(&tb, &ta, true));
                if let Some(c) = short {
                    hits += 1;
                    let e = extent(&a, &b);
                    assert!(
                        (c.d2.sqrt() - full.d2.sqrt()).abs() <= 8.0 * EPS * (e + o.abs()),
                        "{a:?} {b:?}: {} vs {}",
                        c.d2,
                        full.d2
                    );
                    let w = check(&a, &b, true);
                    assert_within(&w, 16.0);
                }
            }
        }
        assert!(hits * 4 > cases, "{hits} of {cases}");
        // Slivers given in f64 (a placed mesh's world positions, not rounded to f32): the
        // rounding of a sliver's normal turns its plane by eps over its width, so the
        // shortcut must not take a vertex over a sliver's face unless its lever is short;
        // whenever it answers, the full search's distance. (A pair found in a review:
        // the shortcut had answered it 3.8e7 eps off; reference 9.99999977648215e-3.)
        let mut slivers = 0;
        let mut tried = 0;
        for &(o, s) in FRAMES.iter() {
            let c = [o, 0.7 * o, -0.4 * o];
            for i in 0..600 {
                let (u0, u1) = (plus(&c, &r.v(s)), plus(&c, &r.v(s)));
                let width = s * [1e-3, 1e-6, 1e-9][i % 3];
                let side = r.v(1.0);
                let u2 = [0, 1, 2].map(|k| u0[k] + (u1[k] - u0[k]) * 0.7 + side[k] * width);
                // A triangle on one side of the sliver, its nearest vertex over the
                // sliver's interior at 1e-2 of the size, the others farther (the review's
                // pair's shape).
                let d = local(&u1, &u0);
                let up = unit(&d.cross(&V::new(side[0], side[1], side[2]))).unwrap();
                let x = combo(&[u0, u1, u2], &[0.15, 0.45, 0.4]);
                let at = |h: f64, lat: P3| [0, 1, 2].map(|k| x[k] + up[k] * h + lat[k]);
                let t = [
                    at(1e-2 * s, [0.0; 3]),
                    at(0.3 * s, r.v(s)),
                    at(0.5 * s, r.v(s)),
                ];
                let (a, b) = (
                    Polygon { t: [t, t], n: 1 },
                    Polygon {
                        t: [[u0, u1, u2]; 2],
                        n: 1,
                    },
                );
                let (a, b) = if i % 2 == 0 { (a, b) } else { (b, a) };
                if meet(&a, &b) {
                    continue;
                }
                tried += 1;
                let o3 = a.t[0][0];
                let (ta, tb) = (Tri::new(&a.t[0], &o3), Tri::new(&b.t[0], &o3));
                let short =
                    vertex_over_face(&ta, &tb, false).or_else(|| vertex_over_face(&tb, &ta, true));
                if let Some(c) = short {
                    let full = closest_search(&ta, &tb);
                    let e = extent(&a, &b);
                    assert!(
                        (c.d2.sqrt() - full.d2.sqrt()).abs() <= 8.0 * EPS * (e + o.abs()),
                        "{a:?} {b:?}: {} vs {}",
                        c.d2.sqrt(),
                        full.d2.sqrt()
                    );
                    slivers += 1;
                }
            }
        }
        // (It declines nearly all of them: its vertex is over the sliver's face.)
        assert!(tried > 3000 && slivers < tried / 10, "{slivers} of {tried}");
        let a = [
            [10.145236234003264, -3.779050464868244, 2.83189447170406],
            [10.413764037492902, -4.1052915769243485, 2.3961617531574735],
            [10.51528265759951, -4.002821221684266, 2.8195922233804005],
        ];
        let b = [
            [10.0, -4.0, 2.0],
            [10.171717171717171, -3.7373737373737375, 2.9494949494949494],
            [10.137176906555084, -3.790200023445166, 2.75850760577517],
        ];
        let g = contact_geometry(&[a, a], 1, &[b, b], 1);
        assert!((-g.depth - 9.99999977648215e-3).abs() < 8.0 * EPS, "{g:?}");
        // A vertex exactly on the other's plane, the rest above it; and a triangle whose
        // nearest vertex is over the face at 0.3 but which crosses the plane just beyond
        // the face's edge (0.084 from it): declined (the full search decides).
        let f = [[0.0, 0.0, 0.0], [4.0, 0.0, 0.0], [0.0, 4.0, 0.0]];
        let on = [[1.0, 1.0, 0.0], [1.0, 1.5, 1.0], [1.5, 1.0, 2.0]];
        let across = [[3.9, 0.01, 0.3], [4.3, 0.01, -0.3], [5.0, 1.0, 2.0]];
        let o3 = f[0];
        let face = Tri::new(&f, &o3);
        for t in [on, across] {
            let t = Tri::new(&t, &o3);
            assert!(vertex_over_face(&t, &face, false).is_none());
            assert!(vertex_over_face(&face, &t, true).is_none());
        }
        let near = closest(&Tri::new(&across, &o3), &face).d2.sqrt();
        assert!(near < 0.09, "{near}");
    }

    /// A sliver `b` of `width` (its positions rounded to f32 or not) about `c`, and a
    /// triangle `a` with a vertex `gap` (1e-3 to 1e-7 of `s`, either side) off the sliver's
    /// interior and its others sideways and farther up (wholly above when that vertex is);
    /// `a` and `b` swapped at random. `None` when the sliver is flat.
    fn sliver_under_vertex(
        r: &mut Rng,
        c: &P3,
        s: f64,
        width: f64,
        f32_positions: bool,
    ) -> Option<(Polygon, Polygon, f64)> {
        let (u0, u1) = (plus(c, &r.v(s)), plus(c, &r.v(s)));
        let side = r.v(1.0);
        let u2 = [0, 1, 2].map(|k| u0[k] + (u1[k] - u0[k]) * 0.7 + side[k] * width);
        let tri = |t: [P3; 3]| {
            if f32_positions {
                Polygon::tri(t)
            } else {
                Polygon { t: [t, t], n: 1 }
            }
        };
        let b = tri([u0, u1, u2]);
        let [u0, u1, u2] = b.t[0];
        let up = unit(&local(&u1, &u0).cross(&local(&u2, &u0)))?;
        let x = combo(&[u0, u1, u2], &[0.15, 0.45, 0.4]);
        let sign = if r.next().is_multiple_of(2) {
            1.0
        } else {
            -1.0
        };
        let gap = sign * s * [1e-3, 1e-5, 1e-7][(r.next() % 3) as usize];
        let mut sideways = || {
            let v = r.v(s);
            let d = v[0] * up.x + v[1] * up.y + v[2] * up.z;
            [v[0] - d * up.x, v[1] - d * up.y, v[2] - d * up.z]
        };
        let (l1, l2) = (sideways(), sideways());
        let at = |h: f64, lat: P3| [0, 1, 2].map(|k| x[k] + up[k] * h + lat[k]);
        let a = tri([at(gap, [0.0; 3]), at(0.3 * s, l1), at(0.5 * s, l2)]);
        Some(if r.next().is_multiple_of(2) {
            (a, b, gap)
        } else {
            (b, a, gap)
        })
    }

    /// Slivers (f32 positions, off the origin) with a vertex of the other triangle 1e-3 to
    /// 1e-7 of the size above their interior or through it: the distances and depths of
    /// both paths against the double-double reference, at every scale and offset. A
    /// sliver's plane must be right to the ulp (`accurate_cross`): the plain cross turns it
    /// by eps over its width, which put depths 4.4e4 eps off (the translation by them not
    /// separating) and distances 4.6e4 eps off (checked to fail so).
    #[test]
    fn slivers_with_a_vertex_over_them() {
        // Slivers at f32 positions, off the origin, a vertex 1e-3 to 1e-7 of the size above
        // their interior or through it: distances and depths (the sliver's normal to the
        // ulp: `accurate_cross`) against the double-double reference (`check`). (The plain
        // cross had put the review's pair 5.9e4 eps off.)
        let w = run("f32 slivers, vertex over the face", 16.0, |r, c, s| {
            match sliver_under_vertex(r, c, s, s * 1e-5, true) {
                Some((a, b, _)) => check(&a, &b, true),
                // Flat once rounded to f32 (far from the origin).
                None => Worst::default(),
            }
        });
        assert!(w.cases > 2000);
        let (a, b) = (
            Polygon::tri([
                [
                    -0.45679670572280884,
                    -0.456404447555542,
                    -0.06319279223680496,
                ],
                [-0.790017306804657, -0.6577766537666321, 0.092563696205616],
                [
                    0.08552992343902588,
                    -0.5739572644233704,
                    -0.2628408372402191,
                ],
            ]),
            Polygon::tri([
                [
                    0.01438096072524786,
                    -0.15112130343914032,
                    -0.2996201813220978,
                ],
                [-0.75848788022995, -0.6519943475723267, 0.08999492973089218],
                [
                    -0.5492968559265137,
                    -0.5164228081703186,
                    -0.015461691655218601,
                ],
            ]),
        );
        let g = geometry(&a, &b);
        assert!((-g.depth - 9.999989339757912e-4).abs() < 4.0 * EPS, "{g:?}");
    }

    /// The same at f64 positions (a placed mesh's world positions, not rounded to f32),
    /// where the edges' differences round too (`triangle_normal` adds back what they leave
    /// out): band pairs against the reference (its exact differences need f32 positions
    /// for a depth), and crossing and band pairs through the four lanes bit for bit the
    /// one-pair answer.
    #[test]
    fn f64_slivers_with_a_vertex_over_them() {
        let mut pairs = Vec::new();
        let w = run("f64 slivers, vertex over the face", 16.0, |r, c, s| {
            let width = s * [1e-4, 1e-6][(r.next() % 2) as usize];
            let Some((a, b, gap)) = sliver_under_vertex(r, c, s, width, false) else {
                return Worst::default();
            };
            pairs.push((a, b));
            // (The references take exact differences: f32 positions. A crossing pair is
            // compared with the lanes only, below.)
            if gap < 0.0 {
                return Worst::default();
            }
            check(&a, &b, true)
        });
        assert!(w.cases > 1000);
        #[cfg(target_arch = "x86_64")]
        {
            let mut out: Vec<ContactGeometry> = pairs.iter().map(|(a, b)| geometry(a, b)).collect();
            let want = out.clone();
            both_kernels(&mut out, false, fetch_from(&pairs)).unwrap();
            for (g, h) in out.iter().zip(&want) {
                assert_eq!(bits(g), bits(h), "{g:?} {h:?}");
            }
        }
    }

    /// A random rotation (from a random unit quaternion), as a placement's matrix.
    fn random_rotation(r: &mut Rng) -> [[f64; 3]; 3] {
        let q = [r.f(), r.f(), r.f(), r.f()];
        let l = q.iter().map(|x| x * x).sum::<f64>().sqrt();
        crate::geom::test_rng::rotation_of(q.map(|v| v / l))
    }

    /// Triangle `t` turned by `m` and moved to `c` in `f64`, as a placed mesh's world
    /// positions (not rounded to floats, unlike `Polygon::tri`).
    fn placed(m: &[[f64; 3]; 3], c: &P3, t: [P3; 3]) -> Polygon {
        let t =
            t.map(|p| [0, 1, 2].map(|k| m[k][0] * p[0] + m[k][1] * p[1] + m[k][2] * p[2] + c[k]));
        Polygon { t: [t, t], n: 1 }
    }

    /// Two triangles of one mesh plane (float positions in a plane z = h), placed as a transformed
    /// mesh is: turned by a random rotation and moved, in `f64` (world positions that are
    /// not floats). The rounding leaves the planes about 1e-16 rad apart: the pair crosses
    /// (or misses by about 1e-17) along a line whose direction the cross of the normals
    /// gets wrong entirely, and whose crossing points need distances of about 1e-17 that
    /// the rounded edge differences cannot give. (Found by contact_check's placed families:
    /// ends 1.8e7 float ulps off before the distances took the differences' rounding
    /// errors and the ends were ordered along the longer cut.)
    #[test]
    fn placed_nearly_coplanar_crossings() {
        let mut pairs = Vec::new();
        let w = run("placed, nearly coplanar", 16.0, |r, c, s| {
            // (The plane off the rotation's centre, as a mesh's plane is.)
            let h = f32r(r.f() * s);
            let flat = |r: &mut Rng, at: [f64; 2]| -> [P3; 3] {
                [0, 1, 2].map(|_| {
                    let q = r.v(s);
                    [f32r(at[0] + q[0]), f32r(at[1] + q[1]), h]
                })
            };
            let (t, u) = (flat(r, [0.0, 0.0]), flat(r, [0.2 * s, 0.1 * s]));
            // A rotation from a random unit quaternion, then the move to `c`.
            let m = random_rotation(r);
            let (a, b) = (placed(&m, c, t), placed(&m, c, u));
            if !meet(&a, &b) {
                return Worst::default();
            }
            pairs.push((a, b));
            placed_ends(&a, &b)
        });
        assert!(w.cases > 500, "{w:?}");
        // The lanes answer them bit for bit as the scalar path.
        #[cfg(target_arch = "x86_64")]
        {
            let mut out: Vec<ContactGeometry> = pairs.iter().map(|(a, b)| geometry(a, b)).collect();
            let want = out.clone();
            both_kernels(&mut out, true, fetch_from(&pairs)).unwrap();
            for (g, h) in out.iter().zip(&want) {
                assert_eq!(bits(g), bits(h), "{g:?} {h:?}");
            }
        }
    }

    /// The checks of [`check`] that hold for `f64` positions (its depth reference needs
    /// exact differences): the flag, the ends on both triangles and on the exact
    /// intersection (double-double), for a crossing pair of triangles.
    fn placed_ends(a: &Polygon, b: &Polygon) -> Worst {
        let g = geometry(a, b);
        basic(&g);
        assert!(g.intersecting && !g.coplanar, "{g:?}");
        let mag = EPS * magnitude(a, b);
        let (r0, r1) = reference_ends(a, b).expect("meeting polygons have a piece");
        let mut w = Worst {
            cases: 1,
            ..Worst::default()
        };
        for p in [&g.point_a, &g.point_b] {
            w.on_polygons = w
                .on_polygons
                .max(poly_dist(p, a).max(poly_dist(p, b)) / mag);
            let x = d3(p);
            let d = norm3(&sub3(&x, &seg_closest(&x, &r0, &r1))).f();
            w.on_intersection = w.on_intersection.max(d / mag);
        }
        let direct = dist_dd(&g.point_a, &r0).max(dist_dd(&g.point_b, &r1));
        let swapped = dist_dd(&g.point_a, &r1).max(dist_dd(&g.point_b, &r0));
        w.ends = direct.min(swapped) / mag;
        w
    }

    /// Pairs of contact_check's "coplanar, placed" family (two triangles of a plane
    /// z = c, x = c or y = x, turned by one rotation in `f64`): before the fixes above,
    /// their ends were off by 1e7 float ulps (the first ones: the distances; the last:
    /// the ends' order along the normals' cross).
    #[test]
    fn placed_nearly_coplanar_known_pairs() {
        let pairs: [([P3; 3], [P3; 3]); 3] = [
            (
                [
                    [0.6415250228416145, 0.41072174910681886, 0.42156423799090614],
                    [0.8877799692608426, 0.978890268581914, 0.5940424203293131],
                    [
                        -0.29167125660734405,
                        -0.9977977622780284,
                        -0.21272112784109543,
                    ],
                ],
                [
                    [0.6164615079785485, -0.4584403297298992, 0.3829468532453278],
                    [
                        -0.07037727566384085,
                        0.3576494968463807,
                        -0.03579236395156003,
                    ],
                    [0.21845301397630174, -1.20827202667814, 0.10855328039739387],
                ],
            ),
            (
                [
                    [
                        -0.025262942234202335,
                        0.6771316536722247,
                        -0.990385546710411,
                    ],
                    [-1.16150803367982, 0.36613106935855894, 0.4476123701102705],
                    [-0.8899243717988565, 0.5829246635892422, 0.2845554115193106],
                ],
                [
                    [0.07806352330540456, 0.8145947405791685, -0.9826996137576225],
                    [-1.1065813504215143, 0.5352628394309864, 0.5735095868588895],
                    [-0.8468570247172413, 0.1986255217816889, -0.2722255995336928],
                ],
            ),
            (
                [
                    [
                        -0.024689896145649565,
                        -0.644529359445771,
                        -0.16578366949100914,
                    ],
                    [-0.4582140774928679, 0.2218794335301869, 0.41626872050820934],
                    [0.3618097837562834, -0.580728825287787, 0.6692725810624705],
                ],
                [
                    [
                        0.07562157060642033,
                        -0.07215477076570226,
                        0.9508893601924492,
                    ],
                    [
                        -0.10627038550108411,
                        0.08503394263404604,
                        0.8610265476499976,
                    ],
                    [
                        0.20229234409488395,
                        -0.9556268316695622,
                        -0.23975195682506575,
                    ],
                ],
            ),
        ];
        let mut w = Worst::default();
        for (i, (a, b)) in pairs.into_iter().enumerate() {
            let (a, b) = (Polygon { t: [a, a], n: 1 }, Polygon { t: [b, b], n: 1 });
            assert!(meet(&a, &b), "pair {i}");
            w.merge(&placed_ends(&a, &b));
        }
        report("placed, nearly coplanar, known", &w);
        assert_within(&w, 16.0);
    }

    /// Band pairs with a quad that is bent, or planar but not convex (a dart), and the
    /// other's vertex just off it on the concave side: the closest points' direction does
    /// not separate the quad's hull, only its nearest triangle. A review found the first
    /// version of `separating` checking the hull: the normal came out 0.34 rad (bent) and
    /// 0.87 rad (dart) off the exact direction, and the pair 13 times slower.
    #[test]
    fn band_normals_of_bent_and_dart_quads() {
        let third = f32r(1.0 / 6.0);
        let above = f32::from_bits((third as f32).to_bits() + 1) as f64;
        let cases = [
            (
                Polygon::quad([
                    [0.0, 0.0, 0.0],
                    [1.0, 0.0, 0.25],
                    [1.0, 1.0, 0.0],
                    [0.0, 1.0, 0.25],
                ]),
                Polygon::tri([
                    [0.5, 0.5, 5.960464477539063e-8],
                    [0.3, 0.5, 1.0],
                    [0.5, 0.7, 1.0],
                ]),
            ),
            (
                Polygon::quad([
                    [0.0, 0.0, 0.0],
                    [1.0, 0.0, 0.0],
                    [0.25, 0.25, 0.0],
                    [0.0, 1.0, 0.0],
                ]),
                Polygon::tri([[0.5, above, 0.0], [0.6, 0.6, 0.3], [0.7, 0.5, -0.2]]),
            ),
        ];
        for (a, b) in cases {
            for (a, b, flip) in [(&a, &b, 1.0), (&b, &a, -1.0)] {
                assert!(!meet(a, b));
                let g = geometry(a, b);
                basic(&g);
                let (dist, ra, rb) = poly_poly_closest(a, b);
                let r = to_f(&scale3(&sub3(&ra, &rb), Dd::from(1.0) / dist));
                let cos: f64 = (0..3).map(|k| r[k] * g.normal[k]).sum();
                assert!(
                    cos > 1.0 - 1e-12,
                    "{flip}: normal {:?} vs exact {r:?}",
                    g.normal
                );
            }
        }
    }

    /// Neighbours of a folding mesh, placed: b shares a's corner 0 (or its edge 0-1) and
    /// lies folded flat onto a, in a plane z = h of float positions, both turned by one
    /// rotation in `f64`. The planes come out about 1e-16 rad apart and cross along a
    /// line through the shared corner: the cut from that corner (a vertex exactly on the
    /// other plane) to the opposite edge needs the accurate distances too (contact_check's
    /// "shared corner or edge, folded, placed": ends 1e7 float ulps off in 958 of 3,000
    /// pairs before).
    #[test]
    fn placed_neighbours_folded_flat() {
        let mut i = 0;
        let w = run("placed neighbours, folded flat", 16.0, |r, c, s| {
            i += 1;
            let h = f32r(r.f() * s);
            let a = [
                [0.0, 0.0, h],
                [f32r(s), 0.0, h],
                [
                    f32r(s * (0.5 + 0.4 * r.f())),
                    f32r(s * (0.65 + 0.35 * r.f())),
                    h,
                ],
            ];
            let inside = |r: &mut Rng| {
                let w1 = 0.05 + 0.4 * r.f().abs();
                let w2 = 0.05 + 0.4 * r.f().abs();
                [f32r(w1 * a[1][0] + w2 * a[2][0]), f32r(w2 * a[2][1]), h]
            };
            let b = if i % 2 == 0 {
                [a[0], inside(r), inside(r)]
            } else {
                [a[0], a[1], inside(r)]
            };
            let m = random_rotation(r);
            let (pa, pb) = (placed(&m, c, a), placed(&m, c, b));
            assert!(meet(&pa, &pb));
            if geometry(&pa, &pb).coplanar {
                return Worst::default();
            }
            placed_ends(&pa, &pb)
        });
        assert!(w.cases > 1000, "{w:?}");
    }

    /// A vertex of b on an edge or a corner of a (float positions in a plane z = h, b's
    /// other corners above it), both placed by one rotation in `f64`: the rounding leaves
    /// them apart by about 1e-17 (or meeting). Apart, the normal must separate them by
    /// their distance (double-double, against the reference distance): the nearest edge
    /// parameters are then a rounding away from their ends, and the features' own normal
    /// pointed anywhere (contact_check's "touching, placed": separations 0.3 short of the
    /// distance in 226 of 2,996 pairs before `separating`).
    #[test]
    fn placed_touching_band_normals() {
        let mut i = 0;
        let w = run("placed touching, band normals", 16.0, |r, c, s| {
            i += 1;
            let h = f32r(r.f() * s);
            let t = [
                [0.0, 0.0, h],
                [f32r(s), 0.0, h],
                [f32r(0.25 * s), f32r(s), h],
            ];
            let q = if i % 2 == 0 {
                [f32r(s * (0.1 + 0.8 * r.f().abs())), 0.0, h]
            } else {
                t[1]
            };
            let up = |r: &mut Rng| {
                let d = r.v(0.5 * s);
                [
                    f32r(q[0] + d[0]),
                    f32r(q[1] + d[1]),
                    f32r(h + s * (0.1 + r.f().abs())),
                ]
            };
            let u = [q, up(r), up(r)];
            let m = random_rotation(r);
            let (a, b) = (placed(&m, c, t), placed(&m, c, u));
            let g = geometry(&a, &b);
            basic(&g);
            assert_eq!(g.intersecting, meet(&a, &b));
            if g.intersecting {
                return Worst::default();
            }
            let n = d3(&g.normal);
            let proj = |p: &P3| dot3(&n, &d3(p));
            let amin = a.t[0]
                .iter()
                .map(proj)
                .fold(Dd::from(f64::INFINITY), |m, x| if x < m { x } else { m });
            let bmax = b.t[0]
                .iter()
                .map(proj)
                .fold(
                    Dd::from(f64::NEG_INFINITY),
                    |m, x| if x > m { x } else { m },
                );
            let gap = (amin - bmax).f();
            let dist = poly_poly_closest(&a, &b).0.f();
            let unit = EPS * extent(&a, &b);
            assert!(
                gap >= dist - 16.0 * unit,
                "gap {gap:e} < distance {dist:e}: {g:?}"
            );
            Worst {
                cases: 1,
                distance: (-g.depth - dist).abs() / unit,
                ..Worst::default()
            }
        });
        assert!(w.cases > 200, "{w:?}");
    }

    /// Shallow crossings: b crosses a's plane at dihedral angles down to 1e-6 (the
    /// intersection's ends are then ill-conditioned in a naive evaluation).
    #[test]
    fn shallow_crossings() {
        let mut angles = [1e-2, 1e-3, 1e-4, 1e-5, 1e-6].iter().cycle();
        run("shallow crossings", 16.0, |r, c, s| {
            let angle = angles.next().copied().unwrap_or(1e-3);
            let t = random_tri(r, c, s);
            let x = combo(&t, &r.bary());
            // A direction in a's plane and one out of it, tilted by `angle`.
            let e = [0, 1, 2].map(|k| t[1][k] - t[0][k]);
            let f = [0, 1, 2].map(|k| t[2][k] - t[0][k]);
            let n = [
                e[1] * f[2] - e[2] * f[1],
                e[2] * f[0] - e[0] * f[2],
                e[0] * f[1] - e[1] * f[0],
            ];
            let nl = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
            let el = (e[0] * e[0] + e[1] * e[1] + e[2] * e[2]).sqrt();
            let g = [0, 1, 2].map(|k| f[k] - e[k] * 0.3);
            let u = [
                [0, 1, 2].map(|k| x[k] - e[k] / el * s * 0.4 - n[k] / nl * s * angle),
                [0, 1, 2].map(|k| x[k] + e[k] / el * s * 0.4 + n[k] / nl * s * angle),
                [0, 1, 2].map(|k| x[k] + g[k] * 0.5 + n[k] / nl * s * angle * (r.f() + 0.2)),
            ];
            check(&Polygon::tri(t), &Polygon::tri(u), true)
        });
    }

    /// Slivers (aspect up to 1e7) against ordinary triangles and each other.
    #[test]
    fn slivers() {
        run("slivers", 16.0, |r, c, s| {
            let (a, b) = crossing_pair(r, c, s);
            let thin = |p: &Polygon, r: &mut Rng| {
                let t = p.t[0];
                let f = [1e-3, 1e-5, 1e-7][(r.next() % 3) as usize];
                let m = combo(&t, &[0.0, 0.5, 0.5]);
                let apex = [0, 1, 2].map(|k| m[k] + (t[0][k] - m[k]) * f);
                Polygon::tri([apex, t[1], t[2]])
            };
            let (a, b) = match r.next() % 3 {
                0 => (thin(&a, r), b),
                1 => (a, thin(&b, r)),
                _ => (thin(&a, r), thin(&b, r)),
            };
            check(&a, &b, false)
        });
    }

    /// Random triangles and quads with coordinates on a coarse grid (ties, shared and
    /// repeated vertices, flat triangles, coplanar sets) at every scale: every output
    /// finite, normals unit, and every check that applies.
    #[test]
    fn fuzz_degenerate_grids() {
        let mut r = Rng(0xDEAD_BEEF_1234_5678);
        let mut w = Worst::default();
        let mut counts = [0usize; 3];
        for i in 0..30_000 {
            let (o, s) = FRAMES[i % FRAMES.len()];
            let grid = [2u64, 3, 5][i % 3];
            let c = [o, o, -o];
            let pt = |r: &mut Rng| {
                let mut p = [0.0; 3];
                for k in 0..3 {
                    p[k] = c[k] + s * (r.next() % grid) as f64 / grid as f64;
                }
                p
            };
            let poly = |r: &mut Rng| {
                let mut v = [pt(r), pt(r), pt(r), pt(r)];
                // Often repeat vertices: segments and points.
                if r.next().is_multiple_of(4) {
                    v[1] = v[0];
                }
                if r.next().is_multiple_of(6) {
                    v[2] = v[(r.next() % 2) as usize];
                }
                if r.next().is_multiple_of(2) {
                    Polygon::tri([v[0], v[1], v[2]])
                } else {
                    Polygon::quad(v)
                }
            };
            let (a, b) = (poly(&mut r), poly(&mut r));
            let g = geometry(&a, &b);
            basic(&g);
            counts[usize::from(g.intersecting) + usize::from(g.coplanar)] += 1;
            if i % 5 == 0 {
                w.merge(&check(&a, &b, false));
            }
        }
        report("degenerate grids", &w);
        println!("band / crossing / coplanar: {counts:?}");
        assert!(counts.iter().all(|&c| c > 1000), "{counts:?}");
        assert_within(&w, 16.0);
    }

    /// The decision is the query's: `intersecting` against `triangles_intersect` on many
    /// random triangle pairs, in general position and on small grids (ties, shared
    /// vertices, coplanar and flat triangles), and on touching pairs far from the origin.
    #[test]
    fn decision_is_the_exact_test() {
        let mut r = Rng(0x5151_2024);
        let mut hits = [0usize; 2];
        for i in 0..300_000 {
            let grid = i % 3 == 0;
            let off = [0.0, 1e3, 1e5][i % 3 / 2 + (i % 7 == 0) as usize];
            let mut c = || {
                if grid {
                    off + (r.next() % 4) as f64
                } else {
                    off + r.f()
                }
            };
            let mut t = || [[c(), c(), c()], [c(), c(), c()], [c(), c(), c()]];
            let (a, b) = (Polygon::tri(t()), Polygon::tri(t()));
            let g = geometry(&a, &b);
            let want = triangles_intersect(&a.t[0], &b.t[0]);
            assert_eq!(g.intersecting, want, "{a:?} {b:?}");
            hits[usize::from(want)] += 1;
        }
        assert!(hits[0] > 50_000 && hits[1] > 50_000, "{hits:?}");
    }

    /// Every pair the query reports on the benchmarks' heavy case (colon against small
    /// intestine, overlapping, opposite warps), with epsilon 0 and within a band: every
    /// check, against the references. Skipped when ../shared/meshes is absent.
    #[test]
    fn heavy_case_pairs_against_references() {
        use crate::{Positions, Scene, SceneConfig};
        let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/../shared/meshes");
        let (Ok(ma), Ok(mb)) = (
            crate::obj::load(format!("{dir}/colon.obj")),
            crate::obj::load(format!("{dir}/small_intestine.obj")),
        ) else {
            println!("shared meshes not found: skipped");
            return;
        };
        let extent = (0..3)
            .map(|k| {
                let (lo, hi) = ma
                    .positions
                    .iter()
                    .fold((f32::MAX, f32::MIN), |(l, h), p| (l.min(p[k]), h.max(p[k])));
                hi - lo
            })
            .fold(0.0, f32::max);
        let wave = |rest: &[[f32; 3]], amp: f32, phase: f32| -> Vec<[f32; 3]> {
            let freq = 8.0 / extent;
            rest.iter()
                .map(|p| {
                    [
                        p[0] + amp * (phase + freq * p[1]).sin(),
                        p[1] + amp * (phase * 1.3 + freq * p[2]).sin(),
                        p[2] + amp * (phase * 0.7 + freq * p[0]).sin(),
                    ]
                })
                .collect()
        };
        let pa = wave(&ma.positions, 0.004 * extent, 0.1);
        let pb = wave(&mb.positions, -0.004 * extent, 0.1);
        let mut all = Worst::default();
        for eps in [0.0, 0.001 * extent] {
            let mut scene = Scene::new(SceneConfig {
                epsilon: eps,
                max_polygons_per_box: 0,
                threads: 1,
            })
            .unwrap();
            let ia = scene
                .create_mesh(Positions::from_points(&pa), &ma.triangles, 3)
                .unwrap();
            scene
                .create_mesh(Positions::from_points(&pb), &mb.triangles, 3)
                .unwrap();
            let contacts = scene.query(ia).unwrap().to_vec();
            let tri = |pos: &[[f32; 3]], idx: &[u32], p: u32| {
                let v = |k: usize| pos[idx[3 * p as usize + k] as usize].map(f64::from);
                Polygon {
                    t: [[v(0), v(1), v(2)]; 2],
                    n: 1,
                }
            };
            let mut w = Worst::default();
            for c in &contacts {
                let a = tri(&pa, &ma.triangles, c.reference_polygon);
                let b = tri(&pb, &mb.triangles, c.other_polygon);
                w.merge(&check(&a, &b, true));
            }
            report(&format!("heavy case eps {eps:.3}"), &w);
            all.merge(&w);
        }
        assert!(all.cases > 1000);
        assert_within(&all, 16.0);
    }

    /// The AVX2 build of the function answers bit for bit as the baseline build, and the
    /// triangle fast path as the general path (same flags; same geometry up to rounding).
    #[test]
    fn builds_and_paths_agree() {
        let mut r = Rng(0xABCD_EF01);
        let mut compared = 0;
        for i in 0..40_000 {
            let (o, sc) = FRAMES[i % FRAMES.len()];
            let c = [o, 0.5 * o, -o];
            let (a, b) = match i % 4 {
                0 | 1 => crossing_pair(&mut r, &c, sc),
                2 => {
                    let (a, b) = crossing_pair(&mut r, &c, sc);
                    let d = r.v(sc);
                    (a.moved(&d.map(f32r)), b)
                }
                _ => {
                    let grid =
                        |r: &mut Rng| [0, 1, 2].map(|k| c[k] + sc * (r.next() % 3) as f64 / 2.0);
                    let mut t = || [grid(&mut r), grid(&mut r), grid(&mut r)];
                    (Polygon::tri(t()), Polygon::tri(t()))
                }
            };
            let g = geometry(&a, &b);
            let any = contact_geometry_any(&a.t, a.n, &b.t, b.n);
            let bits = |g: &ContactGeometry| {
                let f = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
                (
                    f(&g.point_a),
                    f(&g.point_b),
                    f(&g.normal),
                    g.depth.to_bits(),
                )
            };
            assert_eq!(bits(&g), bits(&any), "{a:?} {b:?}");
            let h = general(&a.t, 1, &b.t, 1);
            assert_eq!((g.intersecting, g.coplanar), (h.intersecting, h.coplanar));
            let ext = EPS * extent(&a, &b);
            let mag = EPS * magnitude(&a, &b);
            assert!((g.depth - h.depth).abs() <= 16.0 * ext, "{g:?} {h:?}");
            let same = |p: &P3, q: &P3| close(p, q, 64.0 * (mag + ext));
            assert!(
                (same(&g.point_a, &h.point_a) && same(&g.point_b, &h.point_b))
                    || (same(&g.point_a, &h.point_b) && same(&g.point_b, &h.point_a)),
                "{g:?} {h:?}"
            );
            if !g.intersecting {
                assert_eq!(
                    (g.point_a, g.point_b, g.normal),
                    (h.point_a, h.point_b, h.normal)
                );
            }
            if g.intersecting && !g.coplanar && g.depth > 1e-3 * extent(&a, &b) {
                let dot: f64 = (0..3).map(|k| g.normal[k] * h.normal[k]).sum();
                // Ties between axes may pick different normals of (nearly) equal depth.
                if dot < 1.0 - 1e-9 {
                    assert!((g.depth - h.depth).abs() <= 16.0 * ext, "{g:?} {h:?}");
                } else {
                    compared += 1;
                }
            }
        }
        assert!(compared > 10_000, "{compared}");
    }

    /// A triangle with two equal corners crossing another (`segment_crossing`, what moved
    /// `f32` slivers become): against the double-double references (`check`: the point on
    /// the exact intersection, the depth, the separating margin) and next to the general
    /// path it replaces (the same flags and, but at ties between axes, the same normal;
    /// points and depths within 4 eps of each other); the segment either side, its twin
    /// corners in every position, at every scale and offset.
    #[test]
    fn segment_crossing_is_the_general_path() {
        let mut r = Rng(0x5E6_0001);
        let (mut fast, mut all) = (0, 0);
        let mut worst = Worst::default();
        let mut apart_from_general = 0.0f64;
        for i in 0..20_000 {
            let (o, sc) = FRAMES[i % FRAMES.len()];
            let c = [o, -0.5 * o, 0.25 * o];
            let (a, b) = crossing_pair(&mut r, &c, sc);
            // `a` becomes a segment from its first corner through the crossing and on.
            let t = a.t[0];
            let x = combo(&b.t[0], &r.bary());
            let far = [0, 1, 2].map(|k| f32r(t[0][k] + (x[k] - t[0][k]) * (1.5 + r.f())));
            let (p, q) = (t[0], far);
            let seg = match i % 3 {
                0 => [p, p, q],
                1 => [p, q, p],
                _ => [q, p, p],
            };
            let (sa, sb) = if i % 2 == 0 {
                (Polygon::tri(seg), b)
            } else {
                (b, Polygon::tri(seg))
            };
            if !meet(&sa, &sb) {
                continue;
            }
            all += 1;
            let local = if i % 2 == 0 {
                segment_crossing(&sa.t[0], &sb.t[0], 1.0)
            } else {
                segment_crossing(&sb.t[0], &sa.t[0], -1.0)
            };
            let Some(local) = local else {
                continue;
            };
            fast += 1;
            let got = finish(&local, &[0.0; 3], &sa.t[0][0]);
            assert_eq!(got, geometry(&sa, &sb), "contact_geometry takes this path");
            worst.merge(&check(&sa, &sb, true));
            let want = general(&sa.t, 1, &sb.t, 1);
            let (m, e) = (magnitude(&sa, &sb), extent(&sa, &sb));
            assert!(want.intersecting && !want.coplanar && !got.coplanar);
            assert!(got.point_a == got.point_b);
            for k in 0..3 {
                let d = (got.point_a[k] - want.point_a[k]).abs() / (EPS * m);
                apart_from_general = apart_from_general.max(d);
            }
            let d = (got.depth - want.depth).abs() / (EPS * e);
            apart_from_general = apart_from_general.max(d);
            let same = (0..3).all(|k| (got.normal[k] - want.normal[k]).abs() < 1e-9);
            assert!(same || got.depth < 1e-6 * e, "{got:?} {want:?}");
        }
        report("segments crossing triangles", &worst);
        println!(
            "segment path answered {fast} of {all} crossing segment pairs; points and depths \
             within {apart_from_general:.2} eps of the general path's"
        );
        assert_within(&worst, 4.0);
        assert!(all > 5_000 && fast * 10 > all * 9, "{fast} of {all}");
    }

    /// `contact_geometry_into` writes every entry of memory it is given uninitialized (a
    /// vector's spare capacity filled with a poison first): crossing, apart, quad, segment
    /// and point pairs mixed, every batch remainder and the 64-pair chunks' sizes, known or
    /// not, each kernel; every entry is then `contact_geometry`'s answer bit for bit. (From
    /// a review of the lanes' unsafe writes.)
    #[test]
    fn every_entry_of_spare_capacity_is_written() {
        let mut r = Rng(0xBEEF5);
        let mut pairs: Vec<(Polygon, Polygon)> = Vec::new();
        for i in 0..3000 {
            let (o, sc) = FRAMES[i % FRAMES.len()];
            let c = [o, -0.5 * o, 0.25 * o];
            let (a, b) = crossing_pair(&mut r, &c, sc);
            let (a, b) = match i % 6 {
                0 => (Polygon::tri([a.t[0][0], a.t[0][0], a.t[0][1]]), b),
                1 => (a, Polygon::tri([b.t[0][2], b.t[0][1], b.t[0][1]])),
                2 => (a, b.moved(&[0.0, 0.0, 3.0 * sc])),
                3 => {
                    let t = a.t[0];
                    (Polygon::quad([t[0], t[1], t[2], plus(&t[0], &r.v(sc))]), b)
                }
                4 => (Polygon::tri([a.t[0][0]; 3]), b),
                _ => (a, b),
            };
            pairs.push((a, b));
        }
        let poison = ContactGeometry {
            point_a: [f64::from_bits(0x7ff8_dead_beef_0001); 3],
            point_b: [f64::NAN; 3],
            normal: [f64::NAN; 3],
            depth: f64::NAN,
            intersecting: true,
            coplanar: true,
        };
        let bits = |g: &ContactGeometry| bits(&plus_zero(g));
        for known in [false, true] {
            for len in [1usize, 2, 3, 4, 5, 7, 9, 63, 64, 65, 257, 3000] {
                for avx2 in [false, true] {
                    let mut v = vec![poison; len];
                    v.clear();
                    AVX2_ONLY.with(|c| c.set(avx2));
                    let spare = &mut v.spare_capacity_mut()[..len];
                    contact_geometry_into(spare, known, fetch_from(&pairs)).unwrap();
                    AVX2_ONLY.with(|c| c.set(false));
                    // SAFETY: the call returned Ok, so it wrote the first `len` entries.
                    unsafe { v.set_len(len) };
                    for (k, g) in v.iter().enumerate() {
                        let want = geometry(&pairs[k].0, &pairs[k].1);
                        // (`known` with a pair apart is a caller's error: not compared.)
                        if known && !want.intersecting {
                            continue;
                        }
                        assert_eq!(bits(g), bits(&want), "known {known} len {len} pair {k}");
                    }
                }
            }
        }
    }

    /// Pairs known to intersect, four at a time (`four.rs`), answer as `contact_geometry`
    /// bit for bit: random crossings at every scale and offset, crossings at shallow
    /// angles, touching and grid pairs (vertices on planes, edges along planes: lanes left
    /// to the scalar path), quads among them; and the lanes do take most crossing pairs.
    #[test]
    fn intersecting_four_at_a_time_is_contact_geometry() {
        let mut r = Rng(0x4C41_4E45);
        let mut pairs = Vec::new();
        for i in 0..60_000 {
            let (o, sc) = FRAMES[i % FRAMES.len()];
            let c = [o, 0.5 * o, -o];
            let (a, b) = match i % 6 {
                0..=2 => crossing_pair(&mut r, &c, sc),
                3 => {
                    // Nearly parallel planes: long thin intersections, shaky cut ends.
                    let (a, mut b) = crossing_pair(&mut r, &c, sc);
                    let t = a.t[0];
                    let x = combo(&t, &r.bary());
                    let tilt = 10f64.powi(-((r.next() % 7) as i32));
                    for (k, v) in b.t[0].iter_mut().enumerate() {
                        let w = [0, 1, 2].map(|m| t[k][m] - t[0][m]);
                        let h = r.v(sc * tilt);
                        *v = [0, 1, 2]
                            .map(|m| f32r(x[m] + (w[m] - 0.3 * (t[1][m] - t[0][m])) + h[m]));
                    }
                    (a, b)
                }
                4 => {
                    let grid =
                        |r: &mut Rng| [0, 1, 2].map(|k| c[k] + sc * (r.next() % 3) as f64 / 2.0);
                    let mut t = || [grid(&mut r), grid(&mut r), grid(&mut r)];
                    (Polygon::tri(t()), Polygon::tri(t()))
                }
                _ => {
                    let (t, u) = crossing_pair(&mut r, &c, sc);
                    let q = t.t[0];
                    let far = [0, 1, 2].map(|k| q[1][k] + q[2][k] - q[0][k]);
                    (Polygon::quad([q[0], q[1], far, q[2]]), u)
                }
            };
            if meet(&a, &b) {
                pairs.push((a, b));
            }
        }
        let mut out = vec![geometry(&pairs[0].0, &pairs[0].1); pairs.len()];
        both_kernels(&mut out, true, fetch_from(&pairs)).unwrap();
        let bits = |g: &ContactGeometry| bits(&plus_zero(g));
        for ((a, b), g) in pairs.iter().zip(&out) {
            assert_eq!(bits(g), bits(&geometry(a, b)), "{a:?} {b:?}");
        }
        // Were a caller wrong about its pairs (pairs apart by more than rounding), the
        // answers are still the exact ones: such lanes go to the scalar path.
        let mut apart = Vec::new();
        while apart.len() < 4000 {
            let (a, b) = crossing_pair(&mut r, &[0.0; 3], 1.0);
            let b = b.moved(&r.v(0.8).map(f32r));
            if !meet(&a, &b) {
                apart.push((a, b));
            }
        }
        let mut out = vec![geometry(&apart[0].0, &apart[0].1); apart.len()];
        both_kernels(&mut out, true, fetch_from(&apart)).unwrap();
        for ((a, b), g) in apart.iter().zip(&out) {
            assert!(!g.intersecting, "{a:?} {b:?}");
            assert_eq!(bits(g), bits(&geometry(a, b)), "{a:?} {b:?}");
        }
        // Not known (a query within a band): intersecting and apart pairs mixed, the
        // lanes' exact test picks the crossing ones.
        let mixed: Vec<_> = pairs
            .iter()
            .zip(apart.iter().cycle())
            .flat_map(|(p, q)| [*p, *q])
            .collect();
        let mut out = vec![geometry(&mixed[0].0, &mixed[0].1); mixed.len()];
        both_kernels(&mut out, false, fetch_from(&mixed)).unwrap();
        for ((a, b), g) in mixed.iter().zip(&out) {
            assert_eq!(bits(g), bits(&geometry(a, b)), "{a:?} {b:?}");
        }
        // The lanes themselves: how many crossing pairs they answer.
        #[cfg(target_arch = "x86_64")]
        {
            if !(std::is_x86_feature_detected!("avx2") && std::is_x86_feature_detected!("fma")) {
                println!("no AVX2: the lanes are not used");
                return;
            }
            let tris: Vec<_> = pairs
                .iter()
                .filter(|(a, b)| a.n == 1 && b.n == 1)
                .map(|(a, b)| (a.t[0], b.t[0]))
                .collect();
            let (mut fast, mut all) = (0, 0);
            for chunk in tris.chunks_exact(four::LANES) {
                let (mut a, mut b) = (TriLanes::ZERO, TriLanes::ZERO);
                for (l, (t, u)) in chunk.iter().enumerate() {
                    a.set(l, t);
                    b.set(l, u);
                }
                // (Every field overwritten where answered: none of these survives.)
                let unset = ContactGeometry {
                    point_a: [f64::NAN; 3],
                    point_b: [f64::NAN; 3],
                    normal: [f64::NAN; 3],
                    depth: f64::NAN,
                    intersecting: false,
                    coplanar: true,
                };
                let mut out = [MaybeUninit::new(unset); four::LANES];
                // SAFETY: the CPU has AVX2 and FMA (checked above); `at` is in `out`.
                let ok = unsafe {
                    let (ta, tb) = (a.load(), b.load());
                    four::crossing(&ta, &tb, 0b1111, &[0, 1, 2, 3], &mut out)
                };
                // SAFETY: every entry was initialized (and the kernel writes whole fields).
                let out = out.map(|g| unsafe { g.assume_init() });
                for (l, (t, u)) in chunk.iter().enumerate() {
                    all += 1;
                    if ok & (1 << l) != 0 {
                        fast += 1;
                        let want = contact_geometry(&[*t; 2], 1, &[*u; 2], 1);
                        assert_eq!(bits(&out[l]), bits(&want), "{t:?} {u:?}");
                    } else {
                        assert!(out[l].depth.is_nan(), "lane {l} not answered but written");
                    }
                }
            }
            println!("four lanes answered {fast} of {all} intersecting triangle pairs");
            assert!(
                pairs.len() > 20_000 && fast * 10 > all * 8,
                "{fast} of {all}"
            );
        }
    }

    /// Extreme magnitudes and random bits in the f32 range: finite, unit, no panic.
    #[test]
    fn fuzz_extreme_values() {
        let mut r = Rng(77);
        for i in 0..20_000 {
            let scale = [1e-38, 1e-30, 1e-10, 1.0, 1e10, 1e30, 3e38][i % 7];
            let mut v = || {
                let x = if r.next().is_multiple_of(8) {
                    f32::from_bits(r.next() as u32)
                } else {
                    (r.f() * scale) as f32
                };
                if x.is_finite() {
                    f64::from(x)
                } else {
                    0.0
                }
            };
            let mut p = || [v(), v(), v()];
            let a = [[p(), p(), p()], [p(), p(), p()]];
            let b = [[p(), p(), p()], [p(), p(), p()]];
            let (na, nb) = (1 + i % 2, 1 + (i / 2) % 2);
            let g = contact_geometry(&a, na, &b, nb);
            basic(&g);
        }
        // Counts out of range are clamped.
        let t = [[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]; 2];
        basic(&contact_geometry(&t, 0, &t, 7));
    }

    /// The depth against a direct search: it is at most the overlap of the projections
    /// on any direction (those are separating translations), and a hill-climb from the
    /// best of many sampled directions comes down to it.
    #[test]
    fn depth_against_sampled_directions() {
        let mut r = Rng(4242);
        let mut worst: f64 = 0.0;
        let (mut tight, mut cases) = (0, 0);
        for i in 0..150 {
            let (a, b) = crossing_pair(&mut r, &[0.0; 3], 1.0);
            let (a, b) = if i % 3 == 0 {
                let mut q = a.t[0];
                q[2] = [q[2][0] + 0.3, q[2][1] - 0.2, q[2][2] + 0.1];
                (Polygon::quad([a.t[0][0], a.t[0][1], a.t[0][2], q[2]]), b)
            } else {
                (a, b)
            };
            if !meet(&a, &b) {
                continue;
            }
            let g = geometry(&a, &b);
            let (va, vb) = (a.verts(), b.verts());
            // Translation of a along u that separates the projections.
            let h = |u: &P3| {
                let pr = |p: &P3| p[0] * u[0] + p[1] * u[1] + p[2] * u[2];
                let amin = va.iter().map(pr).fold(f64::INFINITY, f64::min);
                let bmax = vb.iter().map(pr).fold(f64::NEG_INFINITY, f64::max);
                bmax - amin
            };
            let mut samples: Vec<(f64, P3)> = (0..20_000)
                .map(|_| {
                    let u = r.dir();
                    let x = h(&u);
                    assert!(
                        g.depth <= x + 1e-12,
                        "depth {} > overlap {x} along {u:?}",
                        g.depth
                    );
                    (x, u)
                })
                .collect();
            samples.sort_by(|x, y| x.0.total_cmp(&y.0));
            // Hill-climb from the best few (the overlap has a local minimum per facet).
            let mut found = f64::INFINITY;
            for start in samples.iter().take(24) {
                // Pattern search: many random steps per step size, shrink when none helps.
                let mut best = *start;
                let mut step = 0.05;
                while step > 1e-11 {
                    let mut improved = false;
                    for _ in 0..96 {
                        let d = r.dir();
                        let u = [0, 1, 2].map(|k| best.1[k] + d[k] * step);
                        let l = (u[0] * u[0] + u[1] * u[1] + u[2] * u[2]).sqrt();
                        let u = u.map(|x| x / l);
                        let x = h(&u);
                        assert!(g.depth <= x + 1e-12);
                        if x < best.0 {
                            best = (x, u);
                            improved = true;
                        }
                    }
                    if !improved {
                        step *= 0.6;
                    }
                }
                found = found.min(best.0);
            }
            let best = (found, ());
            worst = worst.max(best.0 - g.depth);
            if best.0 - g.depth < 1e-9 {
                tight += 1;
            }
            cases += 1;
        }
        println!(
            "sampled/hill-climbed overlap minus depth: worst {worst:e}, within 1e-9 in \
             {tight} of {cases} cases"
        );
        // The search is only as good as its sampling (the overlap is a max of linear
        // functions with thin valleys); the double-double hull reference in `check` is
        // the tight one.
        assert!(
            worst < 1e-6 && tight * 10 > cases * 9,
            "{worst} {tight}/{cases}"
        );
    }

    /// Band distances against brute force: the distance of random point pairs on the two
    /// polygons is never below the reported distance, and the best of them comes close.
    #[test]
    fn band_distance_against_sampling() {
        let mut r = Rng(777);
        let mut cases = 0;
        let mut worst_gap: f64 = 0.0;
        while cases < 100 {
            let (a, b) = crossing_pair(&mut r, &[0.0; 3], 1.0);
            let g = geometry(&a, &b);
            if !g.intersecting {
                continue;
            }
            // Apart by up to a quarter of their size, as quads half the time.
            let d = g.normal.map(|x| x * (g.depth + 0.25 * (r.f() + 0.5)));
            let a = a.moved(&d);
            let a = if cases % 2 == 0 {
                let t = a.t[0];
                Polygon::quad([t[0], t[1], t[2], combo(&t, &[-0.5, 0.8, 0.7])])
            } else {
                Polygon::tri(a.t[0])
            };
            let g = geometry(&a, &b);
            if g.intersecting {
                continue;
            }
            cases += 1;
            // Closest points lie on edges or at vertices of one of the two at least: sample
            // those often.
            let sample = |r: &mut Rng, p: &Polygon| {
                let t = p.t[(r.next() % p.n as u64) as usize];
                let mut w = r.bary();
                match r.next() % 4 {
                    0 => w = [1.0, 0.0, 0.0],
                    1 | 2 => {
                        let k = (r.next() % 3) as usize;
                        w[k] = 0.0;
                        let sum = w[0] + w[1] + w[2];
                        w = w.map(|x| x / sum);
                    }
                    _ => {}
                }
                let k = (r.next() % 3) as usize;
                combo(&[t[k], t[(k + 1) % 3], t[(k + 2) % 3]], &w)
            };
            let mut best = f64::INFINITY;
            for _ in 0..100_000 {
                let (x, y) = (sample(&mut r, &a), sample(&mut r, &b));
                let d =
                    ((x[0] - y[0]).powi(2) + (x[1] - y[1]).powi(2) + (x[2] - y[2]).powi(2)).sqrt();
                assert!(d >= -g.depth - 1e-12, "sampled {d} below {}", -g.depth);
                best = best.min(d);
            }
            worst_gap = worst_gap.max(best + g.depth);
        }
        println!("best sampled distance minus reported, worst: {worst_gap:e}");
        assert!(worst_gap < 1e-2, "{worst_gap}");
    }

    /// Swapping the polygons negates the normal and keeps the depth (triangles, where the
    /// minimum is unique in general position).
    #[test]
    fn swapping_the_pair() {
        let mut r = Rng(31337);
        for _ in 0..2000 {
            let (a, b) = crossing_pair(&mut r, &[1e3, 0.0, 0.0], 1.0);
            let (g, h) = (geometry(&a, &b), geometry(&b, &a));
            assert_eq!(g.intersecting, h.intersecting);
            if !g.intersecting {
                assert!((g.depth - h.depth).abs() < 1e-12);
                continue;
            }
            assert!((g.depth - h.depth).abs() <= 4.0 * EPS * 1e3, "{g:?} {h:?}");
            if g.depth > 1e-3 {
                let dot: f64 = (0..3).map(|k| g.normal[k] * h.normal[k]).sum();
                assert!(dot < -1.0 + 1e-9, "{g:?} {h:?}");
            }
        }
    }

    /// Nanoseconds per pair (no timing asserted): `cargo test --release --lib
    /// geom::contact::tests::bench -- --ignored --nocapture`.
    #[test]
    #[ignore]
    fn bench_ns_per_pair() {
        use std::hint::black_box;
        use std::time::Instant;
        let mut r = Rng(2024);
        let mut sets: Vec<(&str, Vec<(Polygon, Polygon)>)> = Vec::new();
        let mut crossing = Vec::new();
        let mut band = Vec::new();
        while crossing.len() < 1000 {
            let (a, b) = crossing_pair(&mut r, &[100.0, 50.0, -20.0], 1.0);
            if meet(&a, &b) {
                crossing.push((a, b));
                // Moved apart by up to a tenth of their size: a band pair.
                let g = geometry(&a, &b);
                let d = g.normal.map(|x| x * (g.depth + 0.1 * (r.f() + 0.5)));
                let moved = Polygon::tri(a.moved(&d).t[0]);
                if !meet(&moved, &b) {
                    band.push((moved, b));
                }
            }
        }
        let quads: Vec<(Polygon, Polygon)> = crossing
            .iter()
            .map(|(a, b)| {
                let q = |p: &Polygon| {
                    let t = p.t[0];
                    let v3 = [0, 1, 2].map(|k| t[0][k] + t[2][k] - t[1][k] + 0.05);
                    Polygon::quad([t[0], t[1], t[2], v3])
                };
                (q(a), q(b))
            })
            .filter(|(a, b)| meet(a, b))
            .collect();
        sets.push(("crossing triangles", crossing));
        sets.push(("band triangles", band));
        sets.push(("crossing quads", quads));
        let only = std::env::var("BENCH_SET").unwrap_or_default();
        // This thread's CPU time (ns) where Linux tells it, else wall time: the machine may
        // be shared, and waiting for a core is not the function's cost.
        let cpu_ns = || {
            std::fs::read_to_string("/proc/thread-self/schedstat")
                .ok()
                .and_then(|s| s.split_whitespace().next()?.parse::<f64>().ok())
        };
        let clock = |f: &mut dyn FnMut()| {
            let (w0, c0) = (Instant::now(), cpu_ns());
            f();
            let wall = w0.elapsed().as_nanos() as f64;
            match (c0, cpu_ns()) {
                (Some(c0), Some(c1)) => c1 - c0,
                _ => wall,
            }
        };
        for (name, pairs) in sets.iter().filter(|(n, _)| n.starts_with(&only)) {
            let reps: usize = std::env::var("BENCH_REPS")
                .ok()
                .and_then(|s| s.parse().ok())
                .unwrap_or(200);
            let n = (reps * pairs.len()) as f64;
            let mut best = f64::INFINITY;
            let mut base = f64::INFINITY;
            for _ in 0..5 {
                best = best.min(
                    clock(&mut || {
                        for _ in 0..reps {
                            for (a, b) in pairs {
                                black_box(contact_geometry(
                                    black_box(&a.t),
                                    a.n,
                                    black_box(&b.t),
                                    b.n,
                                ));
                            }
                        }
                    }) / n,
                );
                base = base.min(
                    clock(&mut || {
                        for _ in 0..reps {
                            for (a, b) in pairs {
                                black_box(meet(black_box(a), black_box(b)));
                            }
                        }
                    }) / n,
                );
            }
            println!(
                "{name:>20}: {best:7.1} ns/pair of CPU time ({} pairs; the exact test \
                 alone: {base:.1} ns)",
                pairs.len()
            );
        }
        // What a band pair of a query within a band gets once the exact lanes have found
        // it apart: `band_triangles` alone (its AVX2 build, as the scene calls it).
        #[cfg(target_arch = "x86_64")]
        if std::is_x86_feature_detected!("avx2") && std::is_x86_feature_detected!("fma") {
            let band = &sets[1].1;
            let mut best = f64::INFINITY;
            for _ in 0..50 {
                let t0 = Instant::now();
                for _ in 0..10 {
                    for (a, b) in band {
                        // SAFETY: the CPU has AVX2 and FMA (checked above).
                        black_box(unsafe {
                            band_triangles_avx2(black_box(&a.t[0]), black_box(&b.t[0]))
                        });
                    }
                }
                best = best.min(t0.elapsed().as_nanos() as f64 / (10 * band.len()) as f64);
            }
            println!("  band_triangles alone: {best:7.1} ns/pair");
        }
        // What a query's answer at epsilon 0 gets: the crossing pairs through
        // `contact_geometry_many` (four at a time), all at once and in calls of 10 pairs
        // (an instrument's answer).
        let crossing = &sets[0].1;
        let mut out = vec![geometry(&crossing[0].0, &crossing[0].1); crossing.len()];
        // (The least wall time of many short runs: steadier here than CPU time, which
        // this machine's scheduler reports in coarse steps.)
        for chunk in [crossing.len(), 10] {
            let reps = 10;
            let n = (reps * crossing.len()) as f64;
            let mut best = f64::INFINITY;
            for _ in 0..100 {
                let t0 = Instant::now();
                {
                    for _ in 0..reps {
                        for (c, o) in crossing.chunks(chunk).zip(out.chunks_mut(chunk)) {
                            contact_geometry_many(black_box(o), true, fetch_from(c)).unwrap();
                        }
                    }
                }
                best = best.min(t0.elapsed().as_nanos() as f64 / n);
            }
            println!("  four at a time, calls of {chunk:>4}: {best:7.1} ns/pair of CPU time");
        }
    }
}
