//! What the contact geometry's tests share: double-double arithmetic and the references
//! built with it, the test polygons and their random families, and the checks against the
//! references.

use std::ops::{Add, Div, Mul, Neg, Sub};

use super::AVX2_ONLY;
use crate::geom::contact::band::sign;
use crate::geom::contact::{
    contact_geometry, contact_geometry_many, polygon_pairs, ContactGeometry, PolygonPairs,
};
use crate::geom::predicates::{collinear, orient3d, P3};
use crate::geom::test_rng::Rng;
use crate::geom::tritri::{segments_intersect, triangles_intersect};
use crate::geom::union_depth;

pub(super) const EPS: f64 = f64::EPSILON;

/// `contact_geometry_many` with each kernel (AVX-512 where the CPU has it, and AVX2),
/// which must answer bit for bit alike.
pub(super) fn both_kernels<P: PolygonPairs + Clone>(
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
pub(super) fn bits(g: &ContactGeometry) -> Vec<u64> {
    let mut v: Vec<u64> = [g.point_a, g.point_b, g.normal]
        .iter()
        .flatten()
        .map(|x| x.to_bits())
        .collect();
    v.extend([g.depth.to_bits(), g.intersecting as u64, g.coplanar as u64]);
    v
}

/// `g` with every -0 made +0 (what adding a zero origin does).
pub(super) fn plus_zero(g: &ContactGeometry) -> ContactGeometry {
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
pub(super) fn fetch_from(
    pairs: &[(Polygon, Polygon)],
) -> impl PolygonPairs<Error = ()> + Clone + '_ {
    polygon_pairs(move |i, a, b| {
        put(a, &pairs[i].0.t);
        put(b, &pairs[i].1.t);
        Ok::<_, ()>((pairs[i].0.n, pairs[i].1.n))
    })
}

// ---------------------------------------------------------------- double-double

/// An unevaluated sum `hi + lo`, about 106 bits.
#[derive(Clone, Copy, Debug, PartialEq, PartialOrd)]
pub(super) struct Dd(f64, f64);

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
    pub(super) fn f(self) -> f64 {
        self.0 + self.1
    }
}

type D3 = [Dd; 3];

pub(super) fn d3(p: &P3) -> D3 {
    p.map(Dd::from)
}
pub(super) fn sub3(a: &D3, b: &D3) -> D3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
fn add3(a: &D3, b: &D3) -> D3 {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}
pub(super) fn scale3(a: &D3, s: Dd) -> D3 {
    [a[0] * s, a[1] * s, a[2] * s]
}
pub(super) fn dot3(a: &D3, b: &D3) -> Dd {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
fn cross3(a: &D3, b: &D3) -> D3 {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}
pub(super) fn norm3(a: &D3) -> Dd {
    dot3(a, a).sqrt()
}
fn zero3(a: &D3) -> bool {
    a.iter().all(|x| x.0 == 0.0)
}
pub(super) fn to_f(a: &D3) -> P3 {
    a.map(Dd::f)
}
/// |p - q| with `q` in double-double.
pub(super) fn dist_dd(p: &P3, q: &D3) -> f64 {
    norm3(&sub3(&d3(p), q)).f()
}

// ---------------------------------------------------------------- references

/// Closest point to `x` on the closed segment `a`-`b`, double-double.
pub(super) fn seg_closest(x: &D3, a: &D3, b: &D3) -> D3 {
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

pub(super) fn poly_dist(x: &P3, p: &Polygon) -> f64 {
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
pub(super) fn poly_poly_closest(a: &Polygon, b: &Polygon) -> (Dd, D3, D3) {
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
pub(super) fn reference_ends(a: &Polygon, b: &Polygon) -> Option<(D3, D3)> {
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
pub(super) struct Polygon {
    pub(super) t: [[P3; 3]; 2],
    pub(super) n: usize,
}

impl Polygon {
    pub(super) fn tri(p: [P3; 3]) -> Polygon {
        let p = p.map(|v| v.map(f32r));
        Polygon { t: [p, p], n: 1 }
    }
    pub(super) fn quad(v: [P3; 4]) -> Polygon {
        let v = v.map(|v| v.map(f32r));
        Polygon {
            t: [[v[0], v[1], v[2]], [v[0], v[2], v[3]]],
            n: 2,
        }
    }
    pub(super) fn tris(&self) -> &[[P3; 3]] {
        &self.t[..self.n]
    }
    pub(super) fn verts(&self) -> Vec<P3> {
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
    pub(super) fn moved(&self, d: &P3) -> Polygon {
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

pub(super) fn f32r(x: f64) -> f64 {
    x as f32 as f64
}

pub(super) fn geometry(a: &Polygon, b: &Polygon) -> ContactGeometry {
    contact_geometry(&a.t, a.n, &b.t, b.n)
}

pub(super) fn meet(a: &Polygon, b: &Polygon) -> bool {
    a.tris()
        .iter()
        .any(|t| b.tris().iter().any(|u| triangles_intersect(t, u)))
}

/// Largest coordinate magnitude (the world scale of the points' errors).
pub(super) fn magnitude(a: &Polygon, b: &Polygon) -> f64 {
    a.verts()
        .iter()
        .chain(&b.verts())
        .flat_map(|p| p.iter().map(|x| x.abs()))
        .fold(0.0, f64::max)
}

/// Largest coordinate magnitude relative to `a`'s first vertex (the pair's own scale,
/// that of the depth's and distances' errors).
pub(super) fn extent(a: &Polygon, b: &Polygon) -> f64 {
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

pub(super) fn plus(o: &P3, v: &P3) -> P3 {
    [o[0] + v[0], o[1] + v[1], o[2] + v[2]]
}

pub(super) fn combo(t: &[P3; 3], w: &[f64; 3]) -> P3 {
    [0, 1, 2].map(|k| w[0] * t[0][k] + w[1] * t[1][k] + w[2] * t[2][k])
}

/// A random triangle of size `s` about `c`.
pub(super) fn random_tri(r: &mut Rng, c: &P3, s: f64) -> [P3; 3] {
    [plus(c, &r.v(s)), plus(c, &r.v(s)), plus(c, &r.v(s))]
}

/// A random pair of size `s` at `c` that (before rounding) shares an interior point.
pub(super) fn crossing_pair(r: &mut Rng, c: &P3, s: f64) -> (Polygon, Polygon) {
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
pub(super) struct Worst {
    /// Reported points off either polygon.
    pub(super) on_polygons: f64,
    /// Reported points off the exact intersection (two triangles crossing).
    pub(super) on_intersection: f64,
    /// Reported ends against the reference ends (general position only).
    pub(super) ends: f64,
    /// Depth against the reference hull depth.
    pub(super) depth: f64,
    /// Smallest extra translation along the normal that separates.
    pub(super) margin: f64,
    /// Distance against the reference distance (band).
    pub(super) distance: f64,
    /// Band normal against the direction between the points (radians / EPS), when
    /// the distance is well above the rounding.
    pub(super) band_normal: f64,
    pub(super) cases: usize,
}

impl Worst {
    pub(super) fn merge(&mut self, o: &Worst) {
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

pub(super) fn basic(g: &ContactGeometry) {
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
/// `(depth + m EPS extent) * normal` separates the polygons, exactly. A pair with a quad
/// (a union of triangles) may be apart only in a wedge of directions at the nearest point
/// that the normal's ray misses, or grazes (a face of the wedge along the ray, as on a
/// grid): if `m` up to 16 does not separate it, moving `a` by `depth * normal` must bring
/// it to touching, and `m` is the moved pair's exact union depth (in the same unit,
/// rounded up).
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
        if m >= 16.0 && (a.n == 2 || b.n == 2) {
            let moved = la.moved(&g.normal.map(|x| x * g.depth));
            let rest = union_depth::depth(moved.tris(), lb.tris()).depth / unit;
            assert!(
                rest < 1e9,
                "depth * normal does not reach the boundary: {g:?}"
            );
            return rest.ceil();
        }
        assert!(m < 1e9, "depth * normal does not separate: {g:?}");
        m = if m == 0.0 { 1.0 } else { m * 2.0 };
    }
}

/// Every check that applies to the pair, returning the errors seen. `general` says
/// the pair is in general position (unique ends and facet: compare them directly).
pub(super) fn check(a: &Polygon, b: &Polygon, general: bool) -> Worst {
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
            // Two triangles: the hulls' depth (double-double); a quad: the union of its
            // triangles' (exact, big integers; issue 28).
            let reference = if a.n == 1 && b.n == 1 {
                reference_depth(a, b)
            } else {
                let r = union_depth::depth(a.tris(), b.tris());
                let l = r.at.iter().map(|x| x * x).sum::<f64>().sqrt();
                Some((r.depth, r.at.map(|x| if l > 0.0 { x / l } else { 0.0 })))
            };
            if let Some((depth, n)) = reference {
                w.depth = (g.depth - depth).abs() / ext;
                if general && depth > 1e-3 * extent(a, b) {
                    let cos: f64 = (0..3).map(|k| n[k] * g.normal[k]).sum();
                    assert!(cos > 1.0 - 1e-9, "normal {:?} vs {n:?}", g.normal);
                }
            }
            // Less than the depth along the normal leaves them meeting (the ball of
            // radius depth lies in the Minkowski difference).
            if g.depth > 1e-3 * extent(a, b) {
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

pub(super) fn report(name: &str, w: &Worst) {
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

pub(super) fn assert_within(w: &Worst, limit: f64) {
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

pub(super) fn close(p: &P3, q: &P3, tol: f64) -> bool {
    (0..3).all(|k| (p[k] - q[k]).abs() <= tol)
}

pub(super) fn ends_are(g: &ContactGeometry, p: &P3, q: &P3, tol: f64) -> bool {
    (close(&g.point_a, p, tol) && close(&g.point_b, q, tol))
        || (close(&g.point_a, q, tol) && close(&g.point_b, p, tol))
}

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

// ---------------------------------------------------------------- random families

/// Scales and offsets the accuracy is measured at: (offset, size).
pub(super) const FRAMES: [(f64, f64); 7] = [
    (0.0, 1.0),
    (0.0, 1e-4),
    (0.0, 1e4),
    (1e3, 1.0),
    (1e5, 1.0),
    (1e5, 100.0),
    (-3e4, 0.3),
];

pub(super) fn run(
    name: &str,
    limit: f64,
    mut case: impl FnMut(&mut Rng, &P3, f64) -> Worst,
) -> Worst {
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

/// A random rotation (from a random unit quaternion), as a placement's matrix.
pub(super) fn random_rotation(r: &mut Rng) -> [[f64; 3]; 3] {
    let q = [r.f(), r.f(), r.f(), r.f()];
    let l = q.iter().map(|x| x * x).sum::<f64>().sqrt();
    crate::geom::test_rng::rotation_of(q.map(|v| v / l))
}

/// Triangle `t` turned by `m` and moved to `c` in `f64`, as a placed mesh's world
/// positions (not rounded to floats, unlike `Polygon::tri`).
pub(super) fn placed(m: &[[f64; 3]; 3], c: &P3, t: [P3; 3]) -> Polygon {
    let t = t.map(|p| [0, 1, 2].map(|k| m[k][0] * p[0] + m[k][1] * p[1] + m[k][2] * p[2] + c[k]));
    Polygon { t: [t, t], n: 1 }
}
