//! Exact intersection of closed triangles, degenerate ones included.
//!
//! Two closed convex polygons intersect exactly when an edge of one meets the other (the
//! intersection is convex; in the general case its ends lie on edges, in the coplanar case
//! either the boundaries cross or one contains the other's edges). A degenerate triangle
//! (a segment or a point) is the union of its edges, so the same rule covers it. Every
//! decision below is the sign of an exact `orient3d` / `orient2d`: no epsilon, no NaN.

use super::predicates::{collinear, drop_axis, orient2d, orient2d_filtered, orient3d, P3};

#[cfg(target_arch = "x86_64")]
pub(crate) mod axis_plane;
#[cfg(target_arch = "x86_64")]
pub(crate) mod eight;
#[cfg(target_arch = "x86_64")]
pub(crate) mod four;

/// Do the closed triangles `t` and `u` share at least one point? Touching counts.
pub fn triangles_intersect(t: &[P3; 3], u: &[P3; 3]) -> bool {
    triangles_intersect_with(t, u, [0; 3], [0; 3])
}

/// [`triangles_intersect`] given signs already known for certain: `ut[i]` is the sign of
/// `orient3d(t0, t1, t2, u[i])` (from [`Plane::sides`] of `t`'s plane), `tu[i]` that of
/// `orient3d(u0, u1, u2, t[i])`; 0 means unknown, and the exact predicate is evaluated.
/// Only signs are used below, so a certain sign stands for the exact value.
pub fn triangles_intersect_with(t: &[P3; 3], u: &[P3; 3], ut: [i8; 3], tu: [i8; 3]) -> bool {
    // Both triangles in one coordinate plane (a flat sheet, a box's face, a floor of quads):
    // every orientation below is exactly 0, and the exact predicates pay their slowest
    // stage to say so. Decided in that plane instead (no sign is known then: a hint is
    // never 0 for a vertex on the other's plane).
    if ut == [0; 3] && tu == [0; 3] {
        if let Some(meet) = in_one_axis_plane(t, u) {
            return meet;
        }
    }
    meet_in_3d(t, u, ut, tu)
}

/// When both triangles lie in one coordinate plane (`x_k = c` for all six vertices) and
/// neither is degenerate there: do the closed triangles meet? Exact, and far cheaper than
/// the 3D test, whose orientations are then all exactly 0. None otherwise.
#[inline]
pub fn in_one_axis_plane(t: &[P3; 3], u: &[P3; 3]) -> Option<bool> {
    coplanar_2d(t, u, shared_axis_plane(t, u)?)
}

/// True when the triangles' projections along the axis of `t`'s largest normal component
/// are strictly apart ([`coplanar_2d`]'s exact separation): then the triangles are apart
/// too (a common point would project into both), whatever their planes. A cheap exact
/// answer for the pairs the general test finds hardest, triangles in one slanted plane
/// (the flat sides of a cylinder, a tilted floor): there every orientation is 0 and only
/// the exact arithmetic of `orient3d` says so. False means "ask the general test".
#[inline]
pub fn apart_in_projection(t: &[P3; 3], u: &[P3; 3]) -> bool {
    let e = [0, 1, 2].map(|k| t[1][k] - t[0][k]);
    let f = [0, 1, 2].map(|k| t[2][k] - t[0][k]);
    let n = [
        (e[1] * f[2] - e[2] * f[1]).abs(),
        (e[2] * f[0] - e[0] * f[2]).abs(),
        (e[0] * f[1] - e[1] * f[0]).abs(),
    ];
    // Any axis is sound; the largest component keeps the projection widest.
    let ax = if n[0] >= n[1] && n[0] >= n[2] {
        0
    } else if n[1] >= n[2] {
        1
    } else {
        2
    };
    coplanar_2d(t, u, ax) == Some(false)
}

/// [`triangles_intersect_with`] in 3D, whatever the triangles' planes.
fn meet_in_3d(t: &[P3; 3], u: &[P3; 3], ut: [i8; 3], tu: [i8; 3]) -> bool {
    let side = |hint: i8, a: &P3, b: &P3, c: &P3, d: &P3| {
        if hint != 0 {
            f64::from(hint)
        } else {
            orient3d(a, b, c, d)
        }
    };
    // Plane rejections: every vertex of one strictly on one side of the other's plane.
    // (A degenerate triangle has all orientations 0 and never rejects.)
    let ut = [
        side(ut[0], &t[0], &t[1], &t[2], &u[0]),
        side(ut[1], &t[0], &t[1], &t[2], &u[1]),
        side(ut[2], &t[0], &t[1], &t[2], &u[2]),
    ];
    if strictly_one_side(&ut) {
        return false;
    }
    let tu = [
        side(tu[0], &u[0], &u[1], &u[2], &t[0]),
        side(tu[1], &u[0], &u[1], &u[2], &t[1]),
        side(tu[2], &u[0], &u[1], &u[2], &t[2]),
    ];
    if strictly_one_side(&tu) {
        return false;
    }
    if ut.iter().chain(&tu).all(|&o| o != 0.0) {
        // General position (no vertex on the other's plane, so neither triangle is
        // degenerate): Guigue and Devillers' test, two more exact orientations.
        return general_position(t, u, [-tu[0], -tu[1], -tu[2]], [-ut[0], -ut[1], -ut[2]]);
    }
    let t_flat = collinear(&t[0], &t[1], &t[2]);
    let u_flat = collinear(&u[0], &u[1], &u[2]);
    for i in 0..3 {
        let j = (i + 1) % 3;
        if segment_triangle(&u[i], &u[j], [ut[i], ut[j]], t, t_flat) {
            return true;
        }
        if segment_triangle(&t[i], &t[j], [tu[i], tu[j]], u, u_flat) {
            return true;
        }
    }
    false
}

/// The axis `k` along which all six vertices have exactly the same coordinate, if any: the
/// two triangles then lie in the plane `x_k = c`.
#[inline]
pub fn shared_axis_plane(t: &[P3; 3], u: &[P3; 3]) -> Option<usize> {
    (0..3).find(|&k| {
        let c = t[0][k];
        t[1][k] == c && t[2][k] == c && u[0][k] == c && u[1][k] == c && u[2][k] == c
    })
}

/// Closed triangles `t` and `u` lying in the coordinate plane that drops axis `ax`, both of
/// non-zero area there: do they meet? (None when either is degenerate: the general test
/// decides those.) Two compact convex sets of the plane are disjoint exactly when a line
/// parallel to an edge of one of them strictly separates them, and a triangle's extreme in
/// an edge's normal direction is that edge's line: so they are disjoint exactly when, for
/// some edge, the other triangle lies strictly outside the edge's line. Exact `orient2d`
/// signs only.
fn coplanar_2d(t: &[P3; 3], u: &[P3; 3], ax: usize) -> Option<bool> {
    let t2 = [
        drop_axis(&t[0], ax),
        drop_axis(&t[1], ax),
        drop_axis(&t[2], ax),
    ];
    let u2 = [
        drop_axis(&u[0], ax),
        drop_axis(&u[1], ax),
        drop_axis(&u[2], ax),
    ];
    let ot = orient2d_filtered(t2[0], t2[1], t2[2]);
    let ou = orient2d_filtered(u2[0], u2[1], u2[2]);
    if ot == 0.0 || ou == 0.0 {
        return None;
    }
    // Is `b` strictly outside some edge of `a` (whose orientation has the sign of `o`)?
    let separates = |a: &[[f64; 2]; 3], o: f64, b: &[[f64; 2]; 3]| {
        (0..3).any(|i| {
            let (p, q) = (a[i], a[(i + 1) % 3]);
            // Opposite strict signs (compared, not multiplied: a product of two tiny
            // determinants could underflow to 0).
            b.iter().all(|&x| {
                let v = orient2d_filtered(p, q, x);
                (v > 0.0 && o < 0.0) || (v < 0.0 && o > 0.0)
            })
        })
    };
    Some(!separates(&t2, ot, &u2) && !separates(&u2, ou, &t2))
}

/// A triangle's plane for a quick floating-point rejection before the exact test.
#[derive(Clone, Copy, Debug)]
pub struct Plane {
    o: P3,
    n: P3,
    /// Per component, the sum of the magnitudes of the two products behind `n`: the scale
    /// of its rounding error (large against `n` for a sliver).
    perm: P3,
}

/// Relative error allowed for in [`Plane::separates`]: thousands of times the worst
/// rounding of the few operations involved (a few units of 2^-53).
const PLANE_SLACK: f64 = 1e-12;

impl Plane {
    /// All zero: a placeholder, to be overwritten (the plane of a triangle of one point).
    pub(crate) const ZERO: Plane = Plane {
        o: [0.0; 3],
        n: [0.0; 3],
        perm: [0.0; 3],
    };

    /// The plane of triangle `t`: a vertex, the unnormalised normal and the scale of its
    /// rounding error.
    pub fn of(t: &[P3; 3]) -> Plane {
        let o = t[0];
        let e = [t[1][0] - o[0], t[1][1] - o[1], t[1][2] - o[2]];
        let f = [t[2][0] - o[0], t[2][1] - o[1], t[2][2] - o[2]];
        let n = [
            e[1] * f[2] - e[2] * f[1],
            e[2] * f[0] - e[0] * f[2],
            e[0] * f[1] - e[1] * f[0],
        ];
        let perm = [
            (e[1] * f[2]).abs() + (e[2] * f[1]).abs(),
            (e[2] * f[0]).abs() + (e[0] * f[2]).abs(),
            (e[0] * f[1]).abs() + (e[1] * f[0]).abs(),
        ];
        Plane { o, n, perm }
    }

    #[cfg(any(test, feature = "internals"))]
    /// True only when the three points are certainly all strictly on one side of the plane
    /// (then the triangles cannot meet). False means "ask the exact test".
    #[inline]
    pub fn separates(&self, u: &[P3; 3]) -> bool {
        separated(self.sides(u))
    }

    /// Per point of `u`: the sign of `orient3d(t0, t1, t2, p)` for the plane's triangle
    /// `t` when the floating-point distance is certain of it (beyond its error bound), 0
    /// when only the exact predicate can tell.
    #[inline]
    pub fn sides(&self, u: &[P3; 3]) -> [i8; 3] {
        u.map(|p| self.side(&p))
    }

    /// [`Plane::sides`] for one point.
    #[inline]
    pub fn side(&self, p: &P3) -> i8 {
        let w = [p[0] - self.o[0], p[1] - self.o[1], p[2] - self.o[2]];
        let s = self.n[0] * w[0] + self.n[1] * w[1] + self.n[2] * w[2];
        let bound = PLANE_SLACK
            * (self.perm[0] * w[0].abs() + self.perm[1] * w[1].abs() + self.perm[2] * w[2].abs());
        // orient3d(t0, t1, t2, p) = -((t1 - t0) x (t2 - t0)) . (p - t0). Without branches:
        // the sign is random where this is called (neighbours' far vertices, step 5's
        // candidates), and branches on it mispredicted half the time.
        i8::from(s < -bound) - i8::from(s > bound)
    }
}

/// Guigue and Devillers, "Fast and robust triangle-triangle overlap test using orientation
/// predicates" (JGT 2003), for triangles whose vertices all lie strictly off the other's
/// plane. `d1[i]` is the orientation of `t[i]` against `u`'s plane and `d2[i]` that of
/// `u[i]` against `t`'s, both with the paper's sign (`det[q-p, r-p, x-p]`), none zero.
/// The vertices are permuted so that one vertex of each triangle is alone on its side;
/// the intervals the two triangles cut on the planes' common line then overlap exactly
/// when two orientations are not positive.
fn general_position(t: &[P3; 3], u: &[P3; 3], d1: [f64; 3], d2: [f64; 3]) -> bool {
    let (p1, q1, r1) = (&t[0], &t[1], &t[2]);
    let (p2, q2, r2) = (&u[0], &u[1], &u[2]);
    if d1[0] > 0.0 {
        if d1[1] > 0.0 {
            gd_second(r1, p1, q1, p2, r2, q2, d2[0], d2[2], d2[1])
        } else if d1[2] > 0.0 {
            gd_second(q1, r1, p1, p2, r2, q2, d2[0], d2[2], d2[1])
        } else {
            gd_second(p1, q1, r1, p2, q2, r2, d2[0], d2[1], d2[2])
        }
    } else if d1[1] < 0.0 {
        gd_second(r1, p1, q1, p2, q2, r2, d2[0], d2[1], d2[2])
    } else if d1[2] < 0.0 {
        gd_second(q1, r1, p1, p2, q2, r2, d2[0], d2[1], d2[2])
    } else {
        gd_second(p1, q1, r1, p2, r2, q2, d2[0], d2[2], d2[1])
    }
}

/// The paper's TRI_TRI_3D: permutes the second triangle, then CHECK_MIN_MAX.
#[allow(clippy::too_many_arguments)]
fn gd_second(
    p1: &P3,
    q1: &P3,
    r1: &P3,
    p2: &P3,
    q2: &P3,
    r2: &P3,
    dp2: f64,
    dq2: f64,
    dr2: f64,
) -> bool {
    if dp2 > 0.0 {
        if dq2 > 0.0 {
            gd_check(p1, r1, q1, r2, p2, q2)
        } else if dr2 > 0.0 {
            gd_check(p1, r1, q1, q2, r2, p2)
        } else {
            gd_check(p1, q1, r1, p2, q2, r2)
        }
    } else if dq2 < 0.0 {
        gd_check(p1, q1, r1, r2, p2, q2)
    } else if dr2 < 0.0 {
        gd_check(p1, q1, r1, q2, r2, p2)
    } else {
        gd_check(p1, r1, q1, p2, q2, r2)
    }
}

/// The paper's CHECK_MIN_MAX: `det[p2-q1, p1-q1, q2-q1] <= 0` and
/// `det[p2-p1, r1-p1, r2-p1] <= 0`.
#[inline]
fn gd_check(p1: &P3, q1: &P3, r1: &P3, p2: &P3, q2: &P3, r2: &P3) -> bool {
    orient3d(p2, p1, q2, q1) <= 0.0 && orient3d(p2, r1, r2, p1) <= 0.0
}

/// All three sides certain and the same (see [`Plane::sides`]).
#[inline]
pub fn separated(s: [i8; 3]) -> bool {
    s == [1, 1, 1] || s == [-1, -1, -1]
}

#[inline]
fn strictly_one_side(o: &[f64; 3]) -> bool {
    (o[0] > 0.0 && o[1] > 0.0 && o[2] > 0.0) || (o[0] < 0.0 && o[1] < 0.0 && o[2] < 0.0)
}

/// Does the closed segment `a`-`b` meet the closed triangle `t`? `o` holds the orientations of
/// `a` and `b` against `t`'s plane; `t_flat` says whether `t` is degenerate.
fn segment_triangle(a: &P3, b: &P3, o: [f64; 2], t: &[P3; 3], t_flat: bool) -> bool {
    if t_flat {
        // A segment or a point: the union of its edges.
        return (0..3).any(|i| segments_intersect(a, b, &t[i], &t[(i + 1) % 3]));
    }
    if (o[0] > 0.0 && o[1] > 0.0) || (o[0] < 0.0 && o[1] < 0.0) {
        return false;
    }
    if o[0] == 0.0 && o[1] == 0.0 {
        // Coplanar: decide in a coordinate plane where the triangle keeps its area.
        let ax = (0..3)
            .find(|&ax| {
                orient2d(
                    drop_axis(&t[0], ax),
                    drop_axis(&t[1], ax),
                    drop_axis(&t[2], ax),
                ) != 0.0
            })
            .expect("a non-degenerate triangle has a projection with area");
        let p = |q: &P3| drop_axis(q, ax);
        let tt = [p(&t[0]), p(&t[1]), p(&t[2])];
        return point_in_triangle_2d(p(a), &tt)
            || point_in_triangle_2d(p(b), &tt)
            || (0..3).any(|i| segments_intersect_2d(p(a), p(b), tt[i], tt[(i + 1) % 3]));
    }
    // The segment crosses (or touches) the plane at one point; the line a-b is not in the
    // plane, so it passes through the closed triangle iff the three edge orientations agree.
    let s = [
        orient3d(a, b, &t[0], &t[1]),
        orient3d(a, b, &t[1], &t[2]),
        orient3d(a, b, &t[2], &t[0]),
    ];
    let pos = s.iter().any(|&v| v > 0.0);
    let neg = s.iter().any(|&v| v < 0.0);
    !(pos && neg)
}

/// Closed segments in 3D (either may be a single point).
pub fn segments_intersect(a: &P3, b: &P3, c: &P3, d: &P3) -> bool {
    if orient3d(a, b, c, d) != 0.0 {
        return false;
    }
    // Coplanar (or lower-dimensional): at least one coordinate projection is one-to-one on
    // the points' affine hull, and every projection of meeting segments meets, so requiring
    // all three is exact.
    (0..3).all(|ax| {
        segments_intersect_2d(
            drop_axis(a, ax),
            drop_axis(b, ax),
            drop_axis(c, ax),
            drop_axis(d, ax),
        )
    })
}

/// Closed point-in-triangle for a triangle of non-zero area.
fn point_in_triangle_2d(p: [f64; 2], t: &[[f64; 2]; 3]) -> bool {
    let o = [
        orient2d(t[0], t[1], p),
        orient2d(t[1], t[2], p),
        orient2d(t[2], t[0], p),
    ];
    let pos = o.iter().any(|&v| v > 0.0);
    let neg = o.iter().any(|&v| v < 0.0);
    !(pos && neg)
}

/// Closed segments in 2D (either may be a single point).
pub fn segments_intersect_2d(a: [f64; 2], b: [f64; 2], c: [f64; 2], d: [f64; 2]) -> bool {
    let d1 = orient2d(c, d, a);
    let d2 = orient2d(c, d, b);
    let d3 = orient2d(a, b, c);
    let d4 = orient2d(a, b, d);
    if ((d1 > 0.0 && d2 < 0.0) || (d1 < 0.0 && d2 > 0.0))
        && ((d3 > 0.0 && d4 < 0.0) || (d3 < 0.0 && d4 > 0.0))
    {
        return true;
    }
    (d1 == 0.0 && in_box(c, d, a))
        || (d2 == 0.0 && in_box(c, d, b))
        || (d3 == 0.0 && in_box(a, b, c))
        || (d4 == 0.0 && in_box(a, b, d))
}

/// `p` (known collinear with `a`-`b`) lies within the segment's bounding box.
#[inline]
fn in_box(a: [f64; 2], b: [f64; 2], p: [f64; 2]) -> bool {
    p[0] >= a[0].min(b[0])
        && p[0] <= a[0].max(b[0])
        && p[1] >= a[1].min(b[1])
        && p[1] <= a[1].max(b[1])
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tri(a: [f64; 3], b: [f64; 3], c: [f64; 3]) -> [P3; 3] {
        [a, b, c]
    }

    fn both_ways(t: &[P3; 3], u: &[P3; 3]) -> bool {
        let r = triangles_intersect(t, u);
        assert_eq!(r, triangles_intersect(u, t), "asymmetric answer");
        r
    }

    #[test]
    fn crossing_and_separated() {
        let t = tri([0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]);
        assert!(both_ways(
            &t,
            &tri([0.2, 0.2, -1.0], [0.2, 0.2, 1.0], [0.3, 0.3, 1.0])
        ));
        assert!(!both_ways(
            &t,
            &tri([0.2, 0.2, 0.1], [0.2, 0.2, 1.0], [0.3, 0.3, 1.0])
        ));
        // Crosses the plane outside the triangle.
        assert!(!both_ways(
            &t,
            &tri([0.8, 0.8, -1.0], [0.8, 0.8, 1.0], [0.9, 0.9, 1.0])
        ));
    }

    #[test]
    fn touching_counts() {
        let t = tri([0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]);
        // Vertex on the face.
        assert!(both_ways(
            &t,
            &tri([0.25, 0.25, 0.0], [0.2, 0.2, 1.0], [0.3, 0.4, 1.0])
        ));
        // Shared edge, different planes.
        assert!(both_ways(
            &t,
            &tri([0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.5, 0.0, 1.0])
        ));
        // Shared vertex only.
        assert!(both_ways(
            &t,
            &tri([1.0, 0.0, 0.0], [2.0, 0.0, 1.0], [2.0, 1.0, 1.0])
        ));
        // Vertex on an edge from the other side.
        assert!(both_ways(
            &t,
            &tri([0.5, 0.0, 0.0], [0.5, -1.0, 1.0], [0.5, -1.0, -1.0])
        ));
    }

    #[test]
    fn coplanar_cases() {
        let t = tri([0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]);
        // Overlapping.
        assert!(both_ways(
            &t,
            &tri([0.2, 0.2, 0.0], [2.0, 0.2, 0.0], [0.2, 2.0, 0.0])
        ));
        // Contained.
        assert!(both_ways(
            &t,
            &tri([0.1, 0.1, 0.0], [0.2, 0.1, 0.0], [0.1, 0.2, 0.0])
        ));
        // Sharing an edge segment, on the other side.
        assert!(both_ways(
            &t,
            &tri([0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.5, -1.0, 0.0])
        ));
        // Apart, with a gap of one f32 ulp at 1.
        let g = 1.0 + f64::from(f32::EPSILON);
        assert!(!both_ways(
            &t,
            &tri([g, 0.0, 0.0], [2.0, 0.0, 0.0], [2.0, 1.0, 0.0])
        ));
    }

    /// Triangles in one coordinate plane, with coordinates on a coarse grid (ties,
    /// collinear vertices, shared corners and edges, touching, containment, slivers): the
    /// 2D shortcut decides as the 3D test does, in each of the three planes and far from
    /// the origin.
    #[test]
    fn coordinate_plane_shortcut_decides_as_the_3d_test() {
        let mut rng = crate::geom::test_rng::Rng(0x9E37_79B9_7F4A_7C15);
        let (mut met, mut apart, mut shortcut) = (0, 0, 0);
        for n in 0..60_000 {
            let grid = [2.0, 4.0, 9.0][n % 3];
            let off = [0.0, 1e3, -7.5e6][n / 3 % 3];
            let ax = n / 9 % 3;
            let c = off + (n % 5) as f64;
            let mut p = || {
                let mut q = [0.0; 3];
                q[ax] = c;
                q[(ax + 1) % 3] = off + (rng.unit() * grid).floor() / 2.0;
                q[(ax + 2) % 3] = off + (rng.unit() * grid).floor() / 2.0;
                q
            };
            let t = [p(), p(), p()];
            let u = [p(), p(), p()];
            let want = meet_in_3d(&t, &u, [0; 3], [0; 3]);
            // (On a grid line the six may share another axis too: the first is taken.)
            let found = shared_axis_plane(&t, &u).expect("one plane");
            if coplanar_2d(&t, &u, found).is_some() {
                shortcut += 1;
            }
            assert_eq!(triangles_intersect(&t, &u), want, "{t:?} {u:?}");
            assert_eq!(triangles_intersect(&u, &t), want, "{u:?} {t:?}");
            if want {
                met += 1;
            } else {
                apart += 1;
            }
        }
        assert!(
            met > 10_000 && apart > 10_000 && shortcut > 30_000,
            "{met} {apart} {shortcut}"
        );
    }

    /// The projected separation never calls a meeting pair apart, and decides most of
    /// the apart pairs of one slanted plane: snapped to a grid in a plane through a
    /// rotated frame (exactly coplanar only sometimes after rounding), nearly coplanar,
    /// crossing, and random, far from the origin too.
    #[test]
    fn apart_in_projection_never_separates_a_meeting_pair() {
        let mut rng = crate::geom::test_rng::Rng(0x2545_F491_4F6C_DD1D);
        let (mut met, mut apart, mut decided) = (0, 0, 0);
        for n in 0..100_000 {
            let off = [0.0, 1e3, -7.5e6][n % 3];
            // A plane spanned by two integer directions (exact coplanarity at small
            // integers), or random points.
            let (d1, d2) = ([1.0, 2.0, -1.0], [0.0, 1.0, 3.0]);
            let mut p = |flat: bool| -> P3 {
                let (a, b) = ((rng.unit() * 8.0).floor(), (rng.unit() * 8.0).floor());
                let lift = if flat { 0.0 } else { rng.f() * 1e-3 };
                [0, 1, 2].map(|k| off + a * d1[k] + b * d2[k] + lift)
            };
            let flat = n % 4 != 3;
            let t = [p(flat), p(flat), p(flat)];
            let u = [p(flat), p(flat), p(flat)];
            let want = triangles_intersect(&t, &u);
            let sep = apart_in_projection(&t, &u);
            assert!(!(want && sep), "{t:?} {u:?}: meet, but called apart");
            assert!(!(want && apart_in_projection(&u, &t)), "{u:?} {t:?}");
            if want {
                met += 1;
            } else {
                apart += 1;
                decided += sep as usize;
            }
        }
        assert!(
            met > 10_000 && apart > 10_000 && decided * 2 > apart,
            "{met} met, {apart} apart, {decided} of them by projection"
        );
    }

    #[test]
    fn degenerate_triangles() {
        let t = tri([0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]);
        // A segment piercing the face.
        assert!(both_ways(
            &t,
            &tri([0.2, 0.2, -1.0], [0.2, 0.2, 1.0], [0.2, 0.2, 0.5])
        ));
        // A point on the face, and one just above it.
        assert!(both_ways(
            &t,
            &tri([0.2, 0.2, 0.0], [0.2, 0.2, 0.0], [0.2, 0.2, 0.0])
        ));
        assert!(!both_ways(
            &t,
            &tri([0.2, 0.2, 1e-30], [0.2, 0.2, 1e-30], [0.2, 0.2, 1e-30])
        ));
        // Two crossing segments, and two parallel ones.
        let s = tri([-1.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 0.0]);
        assert!(both_ways(
            &s,
            &tri([0.0, -1.0, 0.0], [0.0, 1.0, 0.0], [0.0, 1.0, 0.0])
        ));
        assert!(!both_ways(
            &s,
            &tri([-1.0, 1e-9, 0.0], [1.0, 1e-9, 0.0], [1.0, 1e-9, 0.0])
        ));
        // Collinear overlapping segments, and collinear disjoint ones.
        assert!(both_ways(
            &s,
            &tri([0.5, 0.0, 0.0], [3.0, 0.0, 0.0], [3.0, 0.0, 0.0])
        ));
        assert!(!both_ways(
            &s,
            &tri([1.5, 0.0, 0.0], [3.0, 0.0, 0.0], [3.0, 0.0, 0.0])
        ));
        // Segment lying in the triangle's plane, crossing it.
        assert!(both_ways(
            &t,
            &tri([-1.0, 0.3, 0.0], [2.0, 0.3, 0.0], [2.0, 0.3, 0.0])
        ));
    }

    /// The general-position path against the edge-by-edge test on many random pairs,
    /// in general position and on small integer grids (where ties send it elsewhere).
    #[test]
    fn general_position_agrees_with_the_edge_test() {
        let mut s = 0x2545_F491_4F6C_DD1Du64;
        let mut next = || {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            s
        };
        let (mut fast, mut hits) = (0, 0);
        for i in 0..200_000 {
            let grid = i % 2 == 0;
            let mut c = || {
                let r = next();
                if grid {
                    f64::from((r % 5) as u32)
                } else {
                    f64::from(((r >> 11) % 1_000_000) as f32 / 250_000.0)
                }
            };
            let t = [[c(), c(), c()], [c(), c(), c()], [c(), c(), c()]];
            let u = [[c(), c(), c()], [c(), c(), c()], [c(), c(), c()]];
            let ut = [0, 1, 2].map(|k| orient3d(&t[0], &t[1], &t[2], &u[k]));
            let tu = [0, 1, 2].map(|k| orient3d(&u[0], &u[1], &u[2], &t[k]));
            if strictly_one_side(&ut)
                || strictly_one_side(&tu)
                || ut.iter().chain(&tu).any(|&o| o == 0.0)
            {
                continue;
            }
            fast += 1;
            let want = (0..3).any(|k| {
                segment_triangle(&u[k], &u[(k + 1) % 3], [ut[k], ut[(k + 1) % 3]], &t, false)
                    || segment_triangle(&t[k], &t[(k + 1) % 3], [tu[k], tu[(k + 1) % 3]], &u, false)
            });
            let got = general_position(&t, &u, tu.map(|x| -x), ut.map(|x| -x));
            assert_eq!(got, want, "t {t:?} u {u:?}");
            hits += usize::from(want);
        }
        assert!(
            fast > 10_000 && hits > 1_000,
            "{fast} general-position pairs, {hits} meeting"
        );
    }

    #[test]
    fn plane_sides_agree_with_orient3d_when_certain() {
        let mut s = 12345u64;
        let mut rnd = || {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            (s >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        };
        let mut certain = 0;
        for i in 0..20000 {
            // Random triangles, slivers and near-coplanar points, at several scales.
            let scale = [1.0, 1e-4, 1e4, 1e6][i % 4];
            let mut t = [[0.0; 3]; 3];
            for v in &mut t {
                *v = [rnd() * scale, rnd() * scale, rnd() * scale].map(|x| x as f32 as f64);
            }
            if i % 3 == 1 {
                t[2] = [
                    t[0][0] + (t[1][0] - t[0][0]) * 0.5 + rnd() * scale * 1e-7,
                    t[0][1] + (t[1][1] - t[0][1]) * 0.5,
                    t[0][2] + (t[1][2] - t[0][2]) * 0.5,
                ]
                .map(|x| x as f32 as f64);
            }
            let mut u = [[0.0; 3]; 3];
            for v in &mut u {
                let a = rnd() + 0.5;
                let b = rnd() + 0.5;
                let off = if i % 5 == 0 {
                    rnd() * scale * 1e-7
                } else {
                    rnd() * scale
                };
                *v = [
                    t[0][0] + a * (t[1][0] - t[0][0]) + b * (t[2][0] - t[0][0]) + off,
                    t[0][1] + a * (t[1][1] - t[0][1]) + b * (t[2][1] - t[0][1]) + off,
                    t[0][2] + a * (t[1][2] - t[0][2]) + b * (t[2][2] - t[0][2]),
                ]
                .map(|x| x as f32 as f64);
            }
            let sides = Plane::of(&t).sides(&u);
            for k in 0..3 {
                let o = orient3d(&t[0], &t[1], &t[2], &u[k]);
                if sides[k] != 0 {
                    certain += 1;
                    assert_eq!(f64::from(sides[k]), o.signum(), "{t:?} {u:?} {k}");
                }
            }
            let exact = triangles_intersect(&t, &u);
            let su = Plane::of(&t).sides(&u);
            let st = Plane::of(&u).sides(&t);
            assert_eq!(triangles_intersect_with(&t, &u, su, st), exact);
        }
        assert!(certain > 20000, "{certain}");
    }

    #[test]
    fn plane_filter_never_rejects_a_meeting_pair() {
        // Touching, coplanar and sliver cases: the filter must say "ask the exact test".
        let t = tri([0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]);
        let cases = [
            tri([0.25, 0.25, 0.0], [0.2, 0.2, 1.0], [0.3, 0.4, 1.0]),
            tri([0.2, 0.2, 0.0], [2.0, 0.2, 0.0], [0.2, 2.0, 0.0]),
            tri([1.0, 0.0, 0.0], [2.0, 0.0, 1.0], [2.0, 1.0, 1.0]),
        ];
        for u in &cases {
            assert!(triangles_intersect(&t, u));
            assert!(!Plane::of(&t).separates(u) && !Plane::of(u).separates(&t));
        }
        // A sliver of aspect 1e7 far from the origin, and a point on it.
        let o = 1e5;
        let s = tri([o, o, o], [o + 1.0, o, o], [o + 0.5, o + 1e-7, o]);
        let p = [[o + 0.5, o + 0.5e-7, o]; 3];
        assert!(triangles_intersect(&s, &p));
        assert!(!Plane::of(&s).separates(&p));
        // And it does reject what is clearly apart.
        assert!(Plane::of(&t).separates(&tri([0.2, 0.2, 0.5], [0.2, 0.2, 1.0], [0.3, 0.3, 1.0])));
    }

    #[test]
    fn far_from_origin_is_decided_exactly() {
        let o = 1e5;
        let t = tri([o, o, o], [o + 1.0, o, o], [o, o + 1.0, o]);
        let ulp = 2f64.powi(-7); // one f32 ulp at 1e5
        assert!(both_ways(
            &t,
            &tri(
                [o + 0.25, o + 0.25, o],
                [o + 0.25, o + 0.25, o + 1.0],
                [o + 0.5, o + 0.25, o + 1.0]
            )
        ));
        assert!(!both_ways(
            &t,
            &tri(
                [o + 0.25, o + 0.25, o + ulp],
                [o + 0.25, o + 0.25, o + 1.0],
                [o + 0.5, o + 0.25, o + 1.0]
            )
        ));
    }

    /// The four-lane test decides only what floating point certifies, and then as the
    /// exact test: random pairs (crossing, apart, near misses), on small grids (shared
    /// vertices, coplanar and flat triangles, exact ties) and far from the origin; most
    /// random pairs are decided in the lanes.
    #[cfg(target_arch = "x86_64")]
    #[test]
    fn four_lanes_decide_as_the_exact_test() {
        use crate::geom::lanes::TriLanes;
        if !(std::is_x86_feature_detected!("avx2") && std::is_x86_feature_detected!("fma")) {
            return;
        }
        let mut rng = crate::geom::test_rng::Rng(0x7A1E_5EED_u64);
        let mut f = move || rng.f();
        let (mut decided, mut total, mut meets) = ([0usize; 3], [0usize; 3], 0usize);
        for i in 0..60_000 {
            let kind = i % 3;
            let off = [0.0, 1e3, 1e5][i % 5 % 3];
            let mut pair = || {
                let mut c = || match kind {
                    0 => off + f(),
                    1 => off + (((f() + 0.5) * 4.0) as i32) as f64 * 0.5,
                    _ => off + f() * 0.01 + 0.3,
                };
                let t = [[c(), c(), c()], [c(), c(), c()], [c(), c(), c()]];
                t.map(|p| p.map(|x| x as f32 as f64))
            };
            let a: [[P3; 3]; 4] = [pair(), pair(), pair(), pair()];
            let b: [[P3; 3]; 4] = [pair(), pair(), pair(), pair()];
            // SAFETY: AVX2 and FMA checked above.
            let (d, m) = unsafe { four::intersect(&TriLanes::of(&a), &TriLanes::of(&b)) };
            for l in 0..4 {
                let want = triangles_intersect(&a[l], &b[l]);
                total[kind] += 1;
                meets += usize::from(want);
                if d & (1 << l) != 0 {
                    decided[kind] += 1;
                    assert_eq!(m & (1 << l) != 0, want, "{:?} {:?}", a[l], b[l]);
                } else {
                    assert_eq!(m & (1 << l), 0);
                }
            }
        }
        println!("decided in the lanes (random, grid, clustered): {decided:?} of {total:?}; {meets} meet");
        assert!(decided[0] * 10 > total[0] * 9 && decided[2] * 10 > total[2] * 8 && meets > 20_000);
    }

    /// The eight-lane test (AVX-512) decides only what floating point certifies, and then
    /// as the exact test, on pairs of every kind mixed in each batch: random (crossing,
    /// apart, near misses), exactly coplanar in a slanted plane, touching (a shared vertex,
    /// a vertex on an edge or on the face, exact), slivers, degenerate triangles (a
    /// segment, a point, three collinear points), far from the origin (1e7), at huge and
    /// tiny scales, and with an edge of each in one coordinate plane (where the edges
    /// cross, an orientation of Guigue and Devillers' is exactly 0). Every lane is decided
    /// as by the four-lane test (the same kernel), and most random pairs whose triangles
    /// cross each other's planes (Guigue and Devillers' general position) and most pairs
    /// with edges in one coordinate plane are decided in the lanes.
    #[cfg(target_arch = "x86_64")]
    #[test]
    fn eight_lanes_decide_as_the_exact_test() {
        use crate::geom::lanes::TriLanes;
        if !std::is_x86_feature_detected!("avx512f") {
            println!("no AVX-512F: the eight lanes are not used");
            return;
        }
        const KINDS: usize = 8;
        let mut rng = crate::geom::test_rng::Rng(0x8E16_7A11_5EED_u64);
        // On a grid of 1/64 in [-1, 1): sums, halves and quarters of these are exact.
        let grid = |rng: &mut crate::geom::test_rng::Rng| -> P3 {
            [0, 1, 2].map(|_| (rng.f() * 128.0).floor() / 64.0)
        };
        let pair = |rng: &mut crate::geom::test_rng::Rng, kind: usize| -> ([P3; 3], [P3; 3]) {
            let random =
                |rng: &mut crate::geom::test_rng::Rng| [rng.v(1.0), rng.v(1.0), rng.v(1.0)];
            match kind {
                // Random, about half crossing.
                0 => (random(rng), random(rng)),
                // Exactly coplanar, in a plane spanned by two integer directions.
                1 => {
                    let (d1, d2) = ([1.0, 2.0, -1.0], [0.0, 1.0, 3.0]);
                    let mut p = || -> P3 {
                        let (a, b) = (rng.below(6) as f64, rng.below(6) as f64);
                        [0, 1, 2].map(|k| a * d1[k] + b * d2[k])
                    };
                    ([p(), p(), p()], [p(), p(), p()])
                }
                // Touching: `u`'s first vertex a vertex of `t`, the midpoint of an edge or
                // a point of the face (exact on the grid), or (one time in four) moved off
                // it by about 1e-12; the others random.
                2 => {
                    let t = [grid(rng), grid(rng), grid(rng)];
                    let mut at: P3 = match rng.below(3) {
                        0 => t[rng.below(3)],
                        1 => [0, 1, 2].map(|k| (t[0][k] + t[1][k]) / 2.0),
                        _ => [0, 1, 2].map(|k| {
                            t[0][k] + (t[1][k] - t[0][k]) / 4.0 + (t[2][k] - t[0][k]) / 4.0
                        }),
                    };
                    if rng.below(4) == 0 {
                        let e = rng.v(1e-12);
                        at = [0, 1, 2].map(|k| at[k] + e[k]);
                    }
                    (t, [at, grid(rng), grid(rng)])
                }
                // A sliver (aspect about 1e9) and a random triangle, or two slivers.
                3 => {
                    let sliver = |rng: &mut crate::geom::test_rng::Rng| {
                        let (a, b, e) = (rng.v(1.0), rng.v(1.0), rng.v(1e-9));
                        [a, b, [0, 1, 2].map(|k| (a[k] + b[k]) / 2.0 + e[k])]
                    };
                    let u = if rng.below(2) == 0 {
                        sliver(rng)
                    } else {
                        random(rng)
                    };
                    (sliver(rng), u)
                }
                // Degenerate: a segment, a point or three collinear points, against a
                // random triangle or another degenerate one.
                4 => {
                    let flat = |rng: &mut crate::geom::test_rng::Rng| {
                        let (a, b) = (grid(rng), grid(rng));
                        match rng.below(3) {
                            0 => [a, b, a],
                            1 => [a, a, a],
                            _ => [a, b, [0, 1, 2].map(|k| 2.0 * b[k] - a[k])],
                        }
                    };
                    let u = if rng.below(3) == 0 {
                        flat(rng)
                    } else {
                        random(rng)
                    };
                    (flat(rng), u)
                }
                // Far from the origin, size about 1.
                5 => {
                    let o = [1e7, -1e7, 1e7];
                    let far = |t: [P3; 3]| t.map(|p| [0, 1, 2].map(|k| o[k] + p[k]));
                    (far(random(rng)), far(random(rng)))
                }
                // Huge and tiny.
                6 => {
                    let s = [1e-30, 1e-8, 1e8, 1e30][rng.below(4)];
                    let scaled = |t: [P3; 3]| t.map(|p| p.map(|x| x * s));
                    (scaled(random(rng)), scaled(random(rng)))
                }
                // An edge of each in one coordinate plane (`x_k = 1/4`), the triangles on
                // either side of it: they meet exactly where the edges cross (a point).
                _ => {
                    let ax = rng.below(3);
                    let mut p = |side: f64| -> P3 {
                        let mut p = rng.v(1.0);
                        p[ax] = 0.25 + side * rng.range(0.01, 0.5);
                        p
                    };
                    let (mut t, mut u) = ([p(-1.0), p(0.0), p(0.0)], [p(0.0), p(0.0), p(1.0)]);
                    rng.shuffle(&mut t);
                    rng.shuffle(&mut u);
                    (t, u)
                }
            }
        };
        let (mut decided, mut total, mut meets) =
            ([0usize; KINDS], [0usize; KINDS], [0usize; KINDS]);
        let (mut general, mut general_decided) = (0usize, 0usize);
        for _ in 0..20_000 {
            let kinds: [usize; 8] = std::array::from_fn(|_| rng.below(KINDS));
            let pairs = kinds.map(|k| pair(&mut rng, k));
            let (a, b) = (pairs.map(|p| p.0), pairs.map(|p| p.1));
            // SAFETY: AVX-512F checked above (and with it AVX2 and FMA).
            let (d, m) = unsafe { eight::intersect(&TriLanes::of(&a), &TriLanes::of(&b)) };
            // The same lanes decided, the same way, four at a time.
            let half = |h: usize| -> [[P3; 3]; 4] { std::array::from_fn(|l| a[4 * h + l]) };
            let halb = |h: usize| -> [[P3; 3]; 4] { std::array::from_fn(|l| b[4 * h + l]) };
            // SAFETY: as above.
            let ((d0, m0), (d1, m1)) = unsafe {
                (
                    four::intersect(&TriLanes::of(&half(0)), &TriLanes::of(&halb(0))),
                    four::intersect(&TriLanes::of(&half(1)), &TriLanes::of(&halb(1))),
                )
            };
            assert_eq!((d, m), (d0 | d1 << 4, m0 | m1 << 4), "{a:?} {b:?}");
            for l in 0..8 {
                let (t, u, kind) = (&a[l], &b[l], kinds[l]);
                let want = triangles_intersect(t, u);
                total[kind] += 1;
                meets[kind] += usize::from(want);
                if d & (1 << l) != 0 {
                    decided[kind] += 1;
                    assert_eq!(m & (1 << l) != 0, want, "kind {kind}: {t:?} {u:?}");
                } else {
                    assert_eq!(m & (1 << l), 0);
                }
                if kind == 0 {
                    let ut = [0, 1, 2].map(|k| orient3d(&t[0], &t[1], &t[2], &u[k]));
                    let tu = [0, 1, 2].map(|k| orient3d(&u[0], &u[1], &u[2], &t[k]));
                    if !strictly_one_side(&ut)
                        && !strictly_one_side(&tu)
                        && ut.iter().chain(&tu).all(|&o| o != 0.0)
                    {
                        general += 1;
                        general_decided += usize::from(d & (1 << l) != 0);
                    }
                }
            }
        }
        println!(
            "decided in eight lanes (random, coplanar, touching, sliver, degenerate, far, \
             scaled, crossing edges): {decided:?} of {total:?}, {meets:?} meet; general \
             position {general_decided} of {general}"
        );
        // Every kind seen, meeting and apart; most random pairs and most of those in
        // general position decided in the lanes.
        assert!(
            (0..KINDS).all(|k| meets[k] > 100 && meets[k] < total[k]),
            "{meets:?}"
        );
        assert!(decided[0] * 10 > total[0] * 9 && decided[5] * 10 > total[5] * 9);
        assert!(decided[7] * 10 > total[7] * 9);
        assert!(general > 5_000 && general_decided * 10 > general * 9);
    }
}
