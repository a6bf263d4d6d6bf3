//! A pair's polygons in a frame local to the pair (a triangle with its exact positions and
//! local corners, a polygon with its distinct vertices) and the normal fallback chain.

use super::exact::triangle_normal;
use super::V;
use crate::geom::predicates::{collinear, P3};

/// One triangle of a polygon: input coordinates for the exact predicates, local ones for
/// the constructions.
#[derive(Clone, Copy)]
pub(super) struct Tri {
    pub(super) p: [P3; 3],
    pub(super) v: [V; 3],
    /// `(p1 - p0) x (p2 - p0)`, not normalized, to about an ulp of each component
    /// ([`triangle_normal`]).
    pub(super) n: V,
    /// Exactly collinear (a segment or a point).
    pub(super) flat: bool,
}

impl Tri {
    #[inline(always)]
    pub(super) fn new(p: &[P3; 3], o: &P3) -> Tri {
        let v = p.map(|q| local(&q, o));
        Tri {
            p: *p,
            v,
            n: triangle_normal(&p.map(|q| V::new(q[0], q[1], q[2]))),
            flat: collinear(&p[0], &p[1], &p[2]),
        }
    }

    /// The ends of a flat triangle's segment: its two farthest-apart vertices.
    pub(super) fn segment(&self) -> (usize, usize) {
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

#[inline]
pub(super) fn local(p: &P3, o: &P3) -> V {
    V::new(p[0] - o[0], p[1] - o[1], p[2] - o[2])
}

/// A polygon: its triangles and its distinct vertices (3 or 4 for a well-formed one, whose
/// hull they span).
pub(super) struct Poly {
    pub(super) tris: [Tri; 2],
    pub(super) nt: usize,
    pub(super) v: [V; 6],
    pub(super) nv: usize,
}

impl Poly {
    pub(super) fn new(t: &[[P3; 3]; 2], n: usize, o: &P3) -> Poly {
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

    pub(super) fn tris(&self) -> &[Tri] {
        &self.tris[..self.nt]
    }

    pub(super) fn verts(&self) -> &[V] {
        &self.v[..self.nv]
    }

    /// The sum of the triangles' area vectors (twice the vector area); where they point
    /// apart (a bowtie, or a quad folded onto itself), the larger one: the sum's direction
    /// without its cancellation, which leaves nothing or rounding when the halves are equal
    /// (issue 28: a planar bowtie's normal came out in its plane).
    fn area(&self) -> V {
        let (n0, n1) = (self.tris[0].n, self.tris[1].n);
        if self.nt == 2 && n0.dot(&n1) < 0.0 {
            return if n0.norm_squared() >= n1.norm_squared() {
                n0
            } else {
                n1
            };
        }
        self.tris().iter().map(|t| t.n).sum()
    }

    /// The two farthest-apart vertices (the polygon's direction when it is a segment).
    fn extent(&self) -> V {
        farthest(self.verts()).map_or(V::zeros(), |(p, q)| q - p)
    }

    pub(super) fn mean(&self) -> V {
        self.verts().iter().sum::<V>() / self.nv as f64
    }
}

/// Unit vector along `v`, or `None` when `v` is zero (or not finite). Scaled first, so no
/// intermediate under- or overflows.
pub(super) fn unit(v: &V) -> Option<V> {
    let m = v.amax();
    if !(m > 0.0 && m.is_finite()) {
        return None;
    }
    let w = v / m;
    Some(w / w.norm())
}

/// The two farthest-apart points (`None` for no point).
pub(super) fn farthest(p: &[V]) -> Option<(V, V)> {
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

/// The normal fallback chain (see [`contact_geometry`](super::contact_geometry)): `a`'s
/// normal, `b`'s, the cross of their directions, a perpendicular to the common line, `+z`.
pub(super) fn fallback_normal(pa: &Poly, pb: &Poly) -> V {
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
