//! The fast paths for a triangle pair (see the module documentation): the common cloth
//! pair, decided in one to a few `orient3d` (or `orient2d` in one plane).

use super::general::projection_axis;
use super::joint::{SharedEdges, Tri};
use crate::geom::predicates::{drop_axis, orient2d, orient3d, P3};
use crate::geom::tritri::triangles_intersect;

/// The fast paths for a triangle pair (see the module documentation): `Some(answer)` to
/// "is `t ∩ u` not inside the joint?", `None` when they cannot tell. `whole` says that
/// the two triangles are the two polygons.
pub(super) fn fast(t: &Tri, u: &Tri, edges: &SharedEdges, whole: bool) -> Option<bool> {
    let mut common = [0u32; 3];
    let mut nc = 0;
    for k in 0..3 {
        let i = t.i[k];
        if u.i.contains(&i) && !common[..nc].contains(&i) {
            common[nc] = i;
            nc += 1;
        }
    }
    if nc == 2 && edges.has(common[0], common[1]) {
        // A shared edge `[p, q]` of both triangles. If the third vertex `w` of `u` is off
        // `t`'s plane, both are proper (`t` has an orientation, and `w` is off the edge's
        // line, which lies in `t`'s plane), their planes differ, and `C` lies on the
        // common line, which meets `t` along the edge only.
        let not_common = |x: &Tri| (0..3).find(|&k| !common[..2].contains(&x.i[k]));
        let w = u.p[not_common(u)?];
        if orient3d(&t.p[0], &t.p[1], &t.p[2], &w) != 0.0 {
            return Some(false);
        }
        // In `t`'s plane (flat cloth): `t` proper, `w` strictly across the edge from `t`'s
        // third vertex `v`. Then the closed half-planes of the edge's line hold one each,
        // and `C` is the edge.
        let v = t.p[not_common(t)?];
        let ax = projection_axis(&t.p[0], &t.p[1], &t.p[2])?;
        let at = |i: u32| {
            (0..3)
                .find(|&k| t.i[k] == i)
                .map(|k| drop_axis(&t.p[k], ax))
        };
        let (p, q) = (at(common[0])?, at(common[1])?);
        let sv = orient2d(p, q, drop_axis(&v, ax));
        let sw = orient2d(p, q, drop_axis(&w, ax));
        if (sv > 0.0 && sw < 0.0) || (sv < 0.0 && sw > 0.0) {
            return Some(false);
        }
    } else if nc == 0 {
        // No common vertex (a quad's other triangle): apart is the common answer.
        if !triangles_intersect(&t.p, &u.p) {
            return Some(false);
        }
    } else if nc == 1 {
        let c = common[0];
        // `u`'s other vertices strictly on one side of `t`'s plane: `u` meets the plane at
        // the common vertex only, so `C` is that vertex.
        let ou = sides(t, u, c);
        if ou.one_side() {
            return Some(false);
        }
        let ot = sides(u, t, c);
        if ot.one_side() {
            return Some(false);
        }
        // "More than `p`" answers the pair only when `p` is the whole joint.
        let r = if ou.n == 2 && ou.o[0] == 0.0 && ou.o[1] == 0.0 {
            coplanar_vertex(t, u, c)
        } else {
            vertex_rule(&ou, &ot, t, u)
        };
        match r {
            Some(false) => return Some(false),
            Some(true) if whole => return Some(true),
            _ => {}
        }
    }
    None
}

/// Two triangles in one plane, sharing the single vertex index `c` (position `p`): does
/// `t ∩ u` hold more than `p`? `None` when one of them is not proper. Near `p` each is
/// its sector at `p`, a convex cone of angle below π, and `C` is convex, so `C ≠ {p}` iff
/// the sectors share a ray; then a bounding ray of their intersection bounds one of them
/// and lies in the other. So: is an edge direction at `p` of one inside the other's
/// sector? Eight `orient2d`.
fn coplanar_vertex(t: &Tri, u: &Tri, c: u32) -> Option<bool> {
    let ax = projection_axis(&t.p[0], &t.p[1], &t.p[2])?;
    let q = |x: &P3| drop_axis(x, ax);
    // The common vertex first, then the other two.
    let corner = |x: &Tri| -> Option<[[f64; 2]; 3]> {
        let k = (0..3).find(|&k| x.i[k] == c)?;
        Some([q(&x.p[k]), q(&x.p[(k + 1) % 3]), q(&x.p[(k + 2) % 3])])
    };
    let (ct, cu) = (corner(t)?, corner(u)?);
    let (st, su) = (orient2d(ct[0], ct[1], ct[2]), orient2d(cu[0], cu[1], cu[2]));
    if st == 0.0 || su == 0.0 {
        return None;
    }
    // Direction `x - p` in the sector `(p, a, b)` of orientation `s`.
    let inside = |x: [f64; 2], k: &[[f64; 2]; 3], s: f64| {
        orient2d(k[0], k[1], x) * s >= 0.0 && orient2d(k[0], x, k[2]) * s >= 0.0
    };
    Some(
        inside(cu[1], &ct, st)
            || inside(cu[2], &ct, st)
            || inside(ct[1], &cu, su)
            || inside(ct[2], &cu, su),
    )
}

/// Orientations of the vertices of `u` other than index `c` against `t`'s plane.
struct Sides {
    o: [f64; 3],
    /// Positions of those vertices.
    p: [P3; 3],
    n: usize,
}

impl Sides {
    /// All strictly on one side (vacuously when there are none: `u` is the common point).
    fn one_side(&self) -> bool {
        let o = &self.o[..self.n];
        o.iter().all(|&x| x > 0.0) || o.iter().all(|&x| x < 0.0)
    }

    /// Two vertices strictly on either side.
    fn straddles(&self) -> bool {
        self.n == 2
            && ((self.o[0] > 0.0 && self.o[1] < 0.0) || (self.o[0] < 0.0 && self.o[1] > 0.0))
    }
}

fn sides(t: &Tri, u: &Tri, c: u32) -> Sides {
    let mut s = Sides {
        o: [0.0; 3],
        p: [[0.0; 3]; 3],
        n: 0,
    };
    for k in 0..3 {
        if u.i[k] != c {
            s.o[s.n] = orient3d(&t.p[0], &t.p[1], &t.p[2], &u.p[k]);
            s.p[s.n] = u.p[k];
            s.n += 1;
        }
    }
    s
}

/// Two triangles sharing the single vertex index `c` (position `p`), with the orientations
/// `ou` of `u`'s other vertices against `t`'s plane and `ot` the other way: does `t ∩ u`
/// hold more than `p`? When one has its two other vertices strictly on either side of the
/// other's plane and the other is proper, both are proper, `p` is a corner of each, and
/// the answer is whether the edge opposite `p` in one meets the other (rule 1 with the
/// triangles as the pieces). `None`: not that case.
fn vertex_rule(ou: &Sides, ot: &Sides, t: &Tri, u: &Tri) -> Option<bool> {
    // Straddling makes the plane's triangle proper; a vertex off the other plane makes the
    // other proper (straddling alone does not: `p` may lie between the two).
    let off = |s: &Sides| s.o[..s.n].iter().any(|&x| x != 0.0);
    if !((ou.straddles() && off(ot)) || (ot.straddles() && off(ou))) || ou.n != 2 || ot.n != 2 {
        return None;
    }
    Some(
        crossing_segment_meets(&ou.p[0], &ou.p[1], ou, &t.p)
            || crossing_segment_meets(&ot.p[0], &ot.p[1], ot, &u.p),
    )
}

/// Does the segment `a`-`b` meet the proper triangle `t`, given the orientations `s` of
/// `a` and `b` against `t`'s plane?
fn crossing_segment_meets(a: &P3, b: &P3, s: &Sides, t: &[P3; 3]) -> bool {
    if s.straddles() {
        // The segment crosses the plane at one point, inside the closed triangle iff the
        // three edge orientations have no two strictly opposite signs.
        let o = [
            orient3d(a, b, &t[0], &t[1]),
            orient3d(a, b, &t[1], &t[2]),
            orient3d(a, b, &t[2], &t[0]),
        ];
        let pos = o.iter().any(|&x| x > 0.0);
        let neg = o.iter().any(|&x| x < 0.0);
        !(pos && neg)
    } else if s.one_side() {
        false
    } else {
        triangles_intersect(&[*a, *b, *b], t)
    }
}
