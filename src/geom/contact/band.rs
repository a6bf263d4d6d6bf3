//! Pairs that do not intersect (a query within a band, epsilon > 0): the closest points of
//! two triangles with the features that realize them, and the normal from those features
//! (checked to separate the nearest triangles where the distance is tiny).

use super::cut::FACE_SLACK;
#[cfg(target_arch = "x86_64")]
use super::edges;
use super::exact::{cross_accurately, exact_diff};
use super::poly::{fallback_normal, unit, Poly, Tri};
use super::{finish, ContactGeometry, Local, V};
use crate::geom::predicates::{orient3d, P3};

#[inline]
pub(super) fn sign(x: f64) -> f64 {
    if x > 0.0 {
        1.0
    } else if x < 0.0 {
        -1.0
    } else {
        0.0
    }
}

/// Closest points of two triangles (meeting or not), with the features that realize them.
pub(super) struct Closest {
    /// On the first triangle.
    pub(super) p: V,
    /// On the second.
    pub(super) q: V,
    pub(super) d2: f64,
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
pub(super) fn closest(t: &Tri, u: &Tri) -> Closest {
    vertex_over_face(t, u, false)
        .or_else(|| vertex_over_face(u, t, true))
        .unwrap_or_else(|| closest_search(t, u))
}

/// [`closest`] by the full search: every edge pair, every vertex over a face.
#[inline(always)]
pub(super) fn closest_search(t: &Tri, u: &Tri) -> Closest {
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
pub(super) fn vertex_over_face(t: &Tri, u: &Tri, swapped: bool) -> Option<Closest> {
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
pub(super) struct EdgePair {
    /// On the first triangle's edge, at parameter `s`.
    pub(super) p: V,
    /// On the second's, at parameter `r`.
    pub(super) q: V,
    pub(super) d2: f64,
    pub(super) s: f64,
    pub(super) r: f64,
}

/// The nearest edge pair of `t` and `u`, as `(i, j, pair)` for edge `i` of `t`
/// (`v[i]`-`v[i+1]`) and edge `j` of `u`: the first in order (`i`, then `j`) among those of
/// least `d2`. Three pairs at a time where the CPU has AVX2 (`edges.rs`, bit for bit the
/// same answer).
#[inline(always)]
pub(super) fn nearest_edge_pair(t: &Tri, u: &Tri) -> (usize, usize, EdgePair) {
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
pub(super) fn nearest_edge_pair_scalar(t: &Tri, u: &Tri) -> (usize, usize, EdgePair) {
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
pub(super) fn segment_params(p0: &V, p1: &V, q0: &V, q1: &V) -> (f64, f64) {
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
pub(super) fn band_triangles(a: &[P3; 3], b: &[P3; 3]) -> ContactGeometry {
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
pub(super) fn band(pa: &Poly, pb: &Poly) -> Local {
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
