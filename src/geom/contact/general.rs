//! The general path: every intersecting case the fast path leaves (coplanar pairs, flat
//! triangles, quads), through the polygons' structures in a frame local to the pair: the
//! exact decision per triangle pair, the intersection's pieces and their farthest ends,
//! the depth over the hulls' axes (two triangles) or of the union of a quad's triangles
//! (`pieces.rs`).

use super::band::{band, closest};
use super::cut::{lerp_from_nearer, signed_like, transverse, Cutting, Face};
use super::depth::sat;
use super::pieces::union_depth;
use super::poly::{fallback_normal, farthest, Poly, Tri};
use super::{finish, max, ContactGeometry, Local, V};
use crate::geom::predicates::{collinear, orient2d, orient3d, P3};
use crate::geom::tritri::{segments_intersect_2d, separated, triangles_intersect_with, Plane};

/// Every case, through the polygons' structures in the local frame.
#[inline(never)]
pub(super) fn general(a: &[[P3; 3]; 2], na: usize, b: &[[P3; 3]; 2], nb: usize) -> ContactGeometry {
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
        } else if pa.nt == 2 || pb.nt == 2 {
            // A quad: the union of its triangles, not its hull (issue 28).
            union_depth(&pa, &pb, &hit)
                .or_else(|| sat(&pa, &pb))
                .unwrap_or_else(|| (fallback_normal(&pa, &pb), 0.0))
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
pub(super) fn exact_sides(mut h: [i8; 3], t: &[P3; 3], u: &[P3; 3]) -> [i8; 3] {
    for (h, p) in h.iter_mut().zip(u) {
        if *h == 0 {
            let o = orient3d(&t[0], &t[1], &t[2], p);
            *h = i8::from(o > 0.0) - i8::from(o < 0.0);
        }
    }
    h
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
