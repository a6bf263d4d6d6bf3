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
//!
//! The files, one a stage:
//! * `mod.rs`: [`ContactGeometry`], [`contact_geometry`] (one pair: which path it takes),
//!   the way back to world coordinates (`finish`) and the small branch-free helpers every
//!   stage uses.
//! * `batch.rs`: many pairs ([`contact_geometry_many`], [`contact_geometry_into`],
//!   [`PolygonPairs`]): triangle pairs gathered four at a time for the lanes, the kernel
//!   compiled for AVX2 or AVX-512, the lanes it leaves one by one.
//! * `four.rs`: the crossing fast path over AVX2 lanes, four pairs at once.
//! * `crossing.rs`: the fast path of two triangles (crossing transversally, or apart; its
//!   separating-axis search over their facets), and a segment (a triangle with two equal
//!   corners) crossing a triangle.
//! * `cut.rs`: a triangle's plane, its cut by the other's plane and the overlap of two cuts
//!   (the intersection's ends; distances evaluated accurately where rounding could move
//!   them), for the fast path and the general one.
//! * `depth.rs`: the penetration depth and normal by the separating-axis theorem over the
//!   polygons' hulls' candidate axes, and the best axis so far (both paths).
//! * `pieces.rs`: the penetration depth of a pair with a quad, the quad the union of its
//!   triangles: the boundary of the union of the triangle pairs' Minkowski differences.
//! * `general.rs`: every other intersecting case (coplanar pairs, flat triangles, quads),
//!   through the polygons' structures in a frame local to the pair.
//! * `poly.rs`: those structures (a triangle, a polygon) and the normal fallback chain.
//! * `band.rs`: pairs that do not intersect (a query within a band): the closest points of
//!   two triangles and the normal from their features.
//! * `edges.rs`: the band's nine edge pairs, three at a time in AVX2 lanes.
//! * `exact.rs`: error-free arithmetic (two-sum, two-product, exact differences) and the
//!   accurate crosses and triangle normals built on it.
//! * `tests/`: the tests, a file a stage, on the references and helpers of
//!   `tests/support.rs`.

use nalgebra::Vector3;

use super::predicates::P3;

mod band;
mod batch;
mod crossing;
mod cut;
mod depth;
#[cfg(target_arch = "x86_64")]
mod edges;
mod exact;
#[cfg(target_arch = "x86_64")]
mod four;
mod general;
mod pieces;
mod poly;
#[cfg(test)]
mod tests;

use band::band_triangles;
pub use batch::{contact_geometry_into, PolygonPairs};
#[cfg(any(test, feature = "internals"))]
pub use batch::{contact_geometry_many, polygon_pairs};
use crossing::{segment_crossing, triangles, twin, Fast};
use general::general;

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
/// * `depth`, `normal`: the smallest translation of `a` that separates the two polygons
///   (the distance from the origin to the boundary of their Minkowski difference `B - A`).
///   Two triangles: by the separating-axis theorem over every facet normal of that
///   difference, the two face normals and the nine edge-edge crosses, so the exact
///   penetration depth; at exactly `depth` the two touch, any longer translation along
///   `normal` separates. Touching pairs get `depth` 0 and the normal of the facet through
///   the origin. A segment crossing a triangle gets the segment-triangle difference's depth
///   (the way out through the triangle's edges or along the segment).
/// * A quad is the union of its two triangles, planar or not (bent, a bowtie, a dart,
///   degenerate), not its hull (issue 28): `B - A` is then the union of the convex pieces
///   `B_j - A_i`, one per pair of triangles (`pieces.rs`), and `depth * normal` is the
///   point of the boundary of that union nearest the origin: the foot of the origin on one
///   facet plane, on the line of two or at the point of three, of distinct pieces, that
///   lies on them and outside the union's interior (some direction leaves every piece
///   holding it: Gordan's test on the planes through it). Touching pairs (the origin
///   itself on the boundary, with the exact decisions of which triangle pairs meet) get
///   `depth` 0 and the direction that leaves the pieces by the widest margin. Unlike a
///   convex difference's, a union's boundary point may be one the pair leaves only within
///   a wedge of directions that the ray along `normal` misses: moving `a` by
///   `depth * normal` always brings the pair to touching (a translation within rounding of
///   it separates), but a longer one along `normal` need not separate. (The constructions
///   are `f64`; a point is on a plane within 16 eps E times its construction's condition,
///   and candidates from planes nearer parallel than 1e-4 are not taken. If none passed,
///   the depth would be the hulls', an upper bound.)
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
/// the first non-zero of: `a`'s normal (the normalized sum of its triangles' area vectors;
/// where they point apart, a bowtie's, the larger one's, so a planar bowtie whose halves
/// cancel still gets its plane's normal),
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
/// the exact penetration depth of two triangles, and moving `a` by
/// `(depth + eps E) * normal` separates the pair (checked exactly); with a quad (against
/// an exact big-integer reference of the union's depth, `geom::union_depth`, over bent,
/// bowtie, dart and degenerate quads, crossing and touching, at 1e3 and placed), within
/// 16 eps E (eps (E + M) for placed positions, whose differences round), and moving `a` by
/// `depth * normal` leaves the pair within that of apart; band distances are within 1.1 eps E and band
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
/// 8 to 10 (`tests/contact_heavy.rs`, `bench-results/contact.md`). A pair with a quad
/// (the general path, one at a time): about 1 us against a triangle, 4 us against a
/// quad (the union's pieces, 2 or 4 of 22 planes at most each; the hulls' axes, before,
/// 0.6 and 0.9 us).
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
