//! Two moving polygons (triangles or quads, each the union of its triangles): do they meet
//! at some time in `[0, 1]`, when first, and which primitive pair meets first.
//!
//! Why the primitives suffice. Two closed triangles that do not meet at `t = 0` and meet
//! at some later time first meet at a time `t*` where a vertex of one touches the other
//! triangle or an edge of one touches an edge of the other: at `t*` take a point `p` they
//! share; if it lies on neither triangle's boundary, both interiors meet there, which
//! either is a transversal crossing (it already existed just before `t*`: not the first
//! time) or the triangles are coplanar there, and then the boundaries of the overlap hold
//! a vertex-in-triangle or an edge-edge contact; if it lies on an edge of one and inside
//! the other, the same argument on that edge gives an end of it in the other triangle or
//! its crossing of the other's edge. Degenerate triangles (segments, points) are unions of
//! their edges and vertices: the same holds. So a pair meets first when the earliest of
//! its 6 vertex-face and 9 edge-edge primitive pairs (per pair of triangles) meets, and
//! [`super::vertex_face`] / [`super::edge_edge`] decide each exactly.
//!
//! Adjacent polygons (one mesh, a vertex index in common) count only where they meet
//! beyond what they share (the discrete queries' rule): at `t = 0` that rule is decided
//! exactly ([`adjacent_polygons_meet`]); after `t = 0`, by the primitives that do not
//! contain a shared vertex index (a vertex the other polygon does not have, against the
//! other's triangles; edges with no common index). Those are the band's primitives
//! (API.md); they agree with the point-set rule except where a moving feature meets the
//! other polygon exactly at a shared vertex's position (a vertex of one coinciding with
//! the joint): the primitives report it, the point-set rule does not.

use super::apart::{apart_along, apart_on_axes, cross, max_abs, sub};
use super::band::{edge_edge_within, vertex_face_within};
use super::{edge_edge_before, vertex_face_before, Toi};
use crate::geom::adjacent::adjacent_polygons_meet;
use crate::geom::tritri::triangles_intersect;
use crate::geom::P3;

/// A moving polygon: `k` (3 or 4) corners, their vertex indices (adjacency is decided by
/// them) and positions at the start and the end of the step.
#[derive(Clone, Copy, Debug)]
pub struct MovingPolygon {
    pub k: usize,
    pub ids: [u32; 4],
    /// `[0 = start, 1 = end][corner]`.
    pub p: [[P3; 4]; 2],
}

/// Which primitive pair meets first, as vertex indices of each polygon.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum First {
    /// The polygons already meet at `t = 0`.
    AtStart,
    /// Vertex `v` of polygon a on triangle `f` of polygon b.
    VertexFace { v: u32, f: [u32; 3] },
    /// Triangle `f` of polygon a and vertex `v` of polygon b.
    FaceVertex { f: [u32; 3], v: u32 },
    /// Edge `a` of polygon a and edge `b` of polygon b.
    EdgeEdge { a: [u32; 2], b: [u32; 2] },
}

impl First {
    /// The same contact seen from the other polygon.
    pub fn swapped(self) -> First {
        match self {
            First::AtStart => First::AtStart,
            First::VertexFace { v, f } => First::FaceVertex { f, v },
            First::FaceVertex { f, v } => First::VertexFace { v, f },
            First::EdgeEdge { a, b } => First::EdgeEdge { a: b, b: a },
        }
    }
}

/// Corners of a polygon's triangles: (0, 1, 2), and (0, 2, 3) for a quad.
const TRIS: [[usize; 3]; 2] = [[0, 1, 2], [0, 2, 3]];
/// Edges of a polygon's triangles, each once: a triangle's three; a quad's four sides
/// and its diagonal (a bent quad's crease can be what touches first).
const EDGES3: [[usize; 2]; 3] = [[0, 1], [1, 2], [2, 0]];
const EDGES4: [[usize; 2]; 5] = [[0, 1], [1, 2], [2, 0], [2, 3], [3, 0]];

impl MovingPolygon {
    fn tris(&self) -> &'static [[usize; 3]] {
        &TRIS[..self.k - 2]
    }

    fn edges(&self) -> &'static [[usize; 2]] {
        if self.k == 3 {
            &EDGES3
        } else {
            &EDGES4
        }
    }

    /// Triangle `t` at time `w` (0 start, 1 end).
    fn triangle(&self, t: &[usize; 3], w: usize) -> [P3; 3] {
        t.map(|c| self.p[w][c])
    }

    /// The polygon's triangles at the start, as the discrete tests take them.
    fn start_triangles(&self) -> [[P3; 3]; 2] {
        [
            self.triangle(&TRIS[0], 0),
            if self.k == 4 {
                self.triangle(&TRIS[1], 0)
            } else {
                self.triangle(&TRIS[0], 0)
            },
        ]
    }

    /// Does the polygon have vertex index `v`?
    fn has(&self, v: u32) -> bool {
        self.ids[..self.k].contains(&v)
    }

    /// The box swept by corners `cs` (lower, upper).
    fn swept_box(&self, cs: &[usize]) -> ([f64; 3], [f64; 3]) {
        let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
        for &c in cs {
            for w in 0..2 {
                for k in 0..3 {
                    lo[k] = lo[k].min(self.p[w][c][k]);
                    hi[k] = hi[k].max(self.p[w][c][k]);
                }
            }
        }
        (lo, hi)
    }
}

/// Do two swept boxes come within `d` on every axis? Never loses a pair: `hi - lo` is
/// rounded monotonically and `-d` is a double.
#[inline]
fn near(a: &([f64; 3], [f64; 3]), b: &([f64; 3], [f64; 3]), d: f64) -> bool {
    (0..3).all(|k| a.1[k] - b.0[k] >= -d && b.1[k] - a.0[k] >= -d)
}

/// Where the remaining primitive pairs need to look: before the earliest time found so far.
/// A primitive pair that first meets at that time or later changes nothing: the time found
/// is at most `2^-20` below the exact time of its own primitive pair, so also below that of
/// the pair's first meeting, which is no later.
fn before(best: &Option<(Toi, First)>) -> f64 {
    best.as_ref()
        .map_or(1.0, |(t, _)| t.t.max(f64::MIN_POSITIVE))
}

/// The earlier of two answers (the first one kept on a tie: the order of the calls below
/// is fixed, so the choice is too).
fn keep_earlier(best: &mut Option<(Toi, First)>, t: Option<Toi>, f: impl FnOnce() -> First) {
    if let Some(t) = t {
        if best.as_ref().is_none_or(|(b, _)| t.t < b.t) {
            *best = Some((t, f()));
        }
    }
}

/// A moving edge as the primitive takes it: `[[end 0, end 1] at start, at end]`.
type MovingEdge = [[P3; 2]; 2];

/// A canonical order of a moving edge's ends and of two edges, so that the primitive is
/// asked the same question whichever polygon comes first (its time is a bound whose last
/// bits could depend on the order; the answer must not depend on mesh creation order).
fn canonical(e: MovingEdge) -> MovingEdge {
    let key = |i: usize| [e[0][i], e[1][i]].map(|p| p.map(f64::to_bits));
    if key(1) < key(0) {
        [[e[0][1], e[0][0]], [e[1][1], e[1][0]]]
    } else {
        e
    }
}

/// [`edge_edge_before`] of two moving edges, asked in the canonical order.
fn edge_pair(a: MovingEdge, b: MovingEdge, t_max: f64) -> Option<Toi> {
    let (a, b) = (canonical(a), canonical(b));
    let key = |e: &MovingEdge| e.map(|w| w.map(|p| p.map(f64::to_bits)));
    if key(&b) < key(&a) {
        edge_edge_before(b, a, t_max)
    } else {
        edge_edge_before(a, b, t_max)
    }
}

/// When do polygons `a` and `b` first meet in `[0, 1]`, and through which primitives?
/// `adjacent`: they are polygons of one mesh that share a vertex index (see the module's
/// documentation for what counts then). Exact (the time a certified lower bound, at most
/// `2^-20` early, 0 exactly when they meet at the start).
pub fn polygons_first_meet(
    a: &MovingPolygon,
    b: &MovingPolygon,
    adjacent: bool,
    d: f64,
) -> Option<(Toi, First)> {
    if !adjacent && polygons_apart(a, b, d) {
        return None;
    }
    let (ta, tb) = (a.start_triangles(), b.start_triangles());
    let (na, nb) = (a.k - 2, b.k - 2);
    let at_start = if adjacent {
        adjacent_polygons_meet(&a.ids[..a.k], &ta, na, &b.ids[..b.k], &tb, nb)
    } else {
        ta[..na]
            .iter()
            .any(|t| tb[..nb].iter().any(|u| triangles_intersect(t, u)))
    };
    if at_start {
        return Some((
            Toi {
                t: 0.0,
                at_start: true,
            },
            First::AtStart,
        ));
    }
    let mut best = None;
    vertices_on_faces(a, b, adjacent, false, &mut best);
    vertices_on_faces(b, a, adjacent, true, &mut best);
    for ea in a.edges() {
        let ia = ea.map(|c| a.ids[c]);
        let ba = a.swept_box(ea);
        for eb in b.edges() {
            let ib = eb.map(|c| b.ids[c]);
            if adjacent && ia.iter().any(|v| ib.contains(v)) {
                continue;
            }
            if !near(&ba, &b.swept_box(eb), 0.0) {
                continue;
            }
            let edge = |p: &MovingPolygon, e: &[usize; 2]| -> MovingEdge {
                [e.map(|c| p.p[0][c]), e.map(|c| p.p[1][c])]
            };
            let hit = edge_pair(edge(a, ea), edge(b, eb), before(&best));
            keep_earlier(&mut best, hit, || First::EdgeEdge { a: ia, b: ib });
        }
    }
    if d > 0.0 {
        within_band(a, b, adjacent, d, &mut best);
    }
    best
}

/// The band's primitive pairs (API.md): a vertex of one polygon that the other does not
/// have, within `d` of a triangle of the other; an edge of one within `d` of an edge of the
/// other with which it shares no vertex. Each earlier than `best` replaces it; one within
/// `d` at the start makes the pair meet at the start.
fn within_band(
    a: &MovingPolygon,
    b: &MovingPolygon,
    adjacent: bool,
    d: f64,
    best: &mut Option<(Toi, First)>,
) {
    let mut keep = |t: Option<Toi>, f: &dyn Fn() -> First| {
        keep_earlier(best, t, || {
            if t.is_some_and(|t| t.at_start) {
                First::AtStart
            } else {
                f()
            }
        })
    };
    for (v, f, swapped) in [(a, b, false), (b, a, true)] {
        for c in 0..v.k {
            let id = v.ids[c];
            if adjacent && f.has(id) {
                continue;
            }
            for t in f.tris() {
                let hit = vertex_face_within(
                    [v.p[0][c], v.p[1][c]],
                    [f.triangle(t, 0), f.triangle(t, 1)],
                    d,
                );
                let fi = t.map(|k| f.ids[k]);
                keep(hit, &|| {
                    if swapped {
                        First::FaceVertex { f: fi, v: id }
                    } else {
                        First::VertexFace { v: id, f: fi }
                    }
                });
            }
        }
    }
    for ea in a.edges() {
        let ia = ea.map(|c| a.ids[c]);
        for eb in b.edges() {
            let ib = eb.map(|c| b.ids[c]);
            if adjacent && ia.iter().any(|v| ib.contains(v)) {
                continue;
            }
            let edge = |p: &MovingPolygon, e: &[usize; 2]| -> MovingEdge {
                canonical([e.map(|c| p.p[0][c]), e.map(|c| p.p[1][c])])
            };
            let (x, y) = (edge(a, ea), edge(b, eb));
            let key = |e: &MovingEdge| e.map(|w| w.map(|p| p.map(f64::to_bits)));
            let hit = if key(&y) < key(&x) {
                edge_edge_within(y, x, d)
            } else {
                edge_edge_within(x, y, d)
            };
            keep(hit, &|| First::EdgeEdge { a: ia, b: ib });
        }
    }
}

/// Are the polygons more than `d` apart for the whole step along a coordinate axis or a triangle's
/// normal at either end (see [`super::apart`])? One test instead of fifteen primitive
/// pairs for most candidates.
fn polygons_apart(a: &MovingPolygon, b: &MovingPolygon, d: f64) -> bool {
    let moving =
        |m: &MovingPolygon| -> [[P3; 2]; 4] { std::array::from_fn(|c| [m.p[0][c], m.p[1][c]]) };
    let (pa, pb) = (moving(a), moving(b));
    let (pa, pb) = (&pa[..a.k], &pb[..b.k]);
    if apart_on_axes(pa, pb, d) {
        return true;
    }
    let maxabs = max_abs(pa, pb);
    [a, b].iter().any(|m| {
        m.tris().iter().any(|t| {
            (0..2).any(|w| {
                let [p, q, r] = m.triangle(t, w);
                apart_along(&cross(&sub(&q, &p), &sub(&r, &p)), pa, pb, maxabs, d)
            })
        })
    })
}

/// The vertices of `v` (those `f` does not share when `adjacent`) against the triangles of
/// `f`; `swapped`: `v` is polygon b.
fn vertices_on_faces(
    v: &MovingPolygon,
    f: &MovingPolygon,
    adjacent: bool,
    swapped: bool,
    best: &mut Option<(Toi, First)>,
) {
    for c in 0..v.k {
        let id = v.ids[c];
        if adjacent && f.has(id) {
            continue;
        }
        let bv = v.swept_box(&[c]);
        for t in f.tris() {
            if !near(&bv, &f.swept_box(t), 0.0) {
                continue;
            }
            let hit = vertex_face_before(
                [v.p[0][c], v.p[1][c]],
                [f.triangle(t, 0), f.triangle(t, 1)],
                before(best),
            );
            let fi = t.map(|k| f.ids[k]);
            keep_earlier(best, hit, || {
                if swapped {
                    First::FaceVertex { f: fi, v: id }
                } else {
                    First::VertexFace { v: id, f: fi }
                }
            });
        }
    }
}
