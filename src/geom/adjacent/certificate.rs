//! A cheap sufficient condition for two neighbour triangles not to meet beyond their joint
//! ([`triangles_touch_only_at_joint`]): one or two exact `orient3d`, or the same rules on
//! a projection, and no setup.

use super::general::normal_axis_guess;
use crate::geom::predicates::{drop_axis, orient2d, P3};
#[cfg(any(test, feature = "internals"))]
use crate::geom::predicates::orient3d;
use crate::geom::tritri::Plane;

#[cfg(any(test, feature = "internals"))]
/// A cheap sufficient condition for two triangles sharing vertex indices *not* to meet
/// beyond their joint: `true` proves
/// [`adjacent_polygons_meet`](super::adjacent_polygons_meet) false for them; `false` tells
/// nothing. One or two exact `orient3d` and no setup, for the common neighbours of a
/// triangle mesh (it is two of the fast paths of the [module documentation](super),
/// without building the polygons' joint):
///
/// * exactly two shared indices `{i, j}` (an edge of both) and the third vertex `w` of `b`
///   off `a`'s plane: then `a` is proper, and the points of `b = conv(i, j, w)` in `a`'s
///   plane are those with no weight on `w`, the shared edge; so `a ∩ b` lies in it;
/// * exactly one shared index `s`, and the other two vertices of one triangle strictly on
///   one side of the other's plane (which is then a plane: the triangle is proper): the
///   orientation is affine and vanishes at `s` only, so the first triangle meets that
///   plane at `s` alone, and `a ∩ b ⊆ {s}`.
///
/// When those fail (neighbours in one plane, or nearly), the same conclusions from a
/// projection onto the coordinate plane across `a`'s largest normal component, if both
/// triangles project to proper triangles there (exact `orient2d`; the projection is then
/// one-to-one on each triangle), whether or not they are in one plane:
///
/// * shared edge, the third vertices strictly on either side of its projected line: the
///   projections meet on that line only, whose preimage in each triangle is the edge;
/// * shared vertex `s`, the projected sectors at `s` (convex, below π) sharing no ray
///   (no boundary ray of one in the other's closed sector): the projections meet at `s`'s
///   image only, whose preimage in each triangle is `s`.
///
/// A triangle with a repeated index, or two triangles with all three indices in common,
/// get `false`.
#[inline]
pub fn triangles_touch_only_at_joint(
    ai: &[u32; 3],
    a: &[P3; 3],
    bi: &[u32; 3],
    b: &[P3; 3],
) -> bool {
    let sign = |x: f64| (x > 0.0) as i8 - (x < 0.0) as i8;
    touch_only_at_joint(
        ai,
        a,
        bi,
        b,
        |k| sign(orient3d(&a[0], &a[1], &a[2], &b[k])),
        |k| sign(orient3d(&b[0], &b[1], &b[2], &a[k])),
    )
}

/// [`triangles_touch_only_at_joint`] with the triangles' planes made beforehand
/// ([`Plane::of`]): each orientation is read from the plane when its floating-point value
/// is certain of the sign ([`Plane::side`]) and taken as unknown otherwise (no exact
/// `orient3d`, which is slow exactly where points are coplanar: the projected rules decide
/// those). `true` only where [`triangles_touch_only_at_joint`] is `true`.
#[inline]
pub fn triangles_touch_only_at_joint_planes(
    ai: &[u32; 3],
    a: &[P3; 3],
    pa: &Plane,
    bi: &[u32; 3],
    b: &[P3; 3],
    pb: &Plane,
) -> bool {
    touch_only_at_joint(ai, a, bi, b, |k| pa.side(&b[k]), |k| pb.side(&a[k]))
}

/// The rule of [`triangles_touch_only_at_joint`], given the signs `ob(k)` of `orient3d` of
/// `b`'s vertex `k` against `a`'s plane and `oa(k)` of `a`'s vertex `k` against `b`'s (0:
/// zero or unknown; a nonzero sign must be the true one).
#[inline(always)]
fn touch_only_at_joint(
    ai: &[u32; 3],
    a: &[P3; 3],
    bi: &[u32; 3],
    b: &[P3; 3],
    ob: impl Fn(usize) -> i8,
    oa: impl Fn(usize) -> i8,
) -> bool {
    let distinct = |i: &[u32; 3]| i[0] != i[1] && i[1] != i[2] && i[0] != i[2];
    if !distinct(ai) || !distinct(bi) {
        return false;
    }
    let shared = ai.iter().filter(|i| bi.contains(i)).count();
    // The two vertices of `x` whose index is not in `y`.
    let others = |xi: &[u32; 3], yi: &[u32; 3]| -> [usize; 2] {
        let mut o = [0; 2];
        let mut n = 0;
        for (k, i) in xi.iter().enumerate() {
            if !yi.contains(i) && n < 2 {
                o[n] = k;
                n += 1;
            }
        }
        o
    };
    // The projection of the projected rules: across `a`'s largest normal component, where
    // both triangles must project to proper triangles.
    let projected = || -> Option<usize> {
        let axis = normal_axis_guess(&a[0], &a[1], &a[2]);
        let proper = |t: &[P3; 3]| {
            orient2d(
                drop_axis(&t[0], axis),
                drop_axis(&t[1], axis),
                drop_axis(&t[2], axis),
            ) != 0.0
        };
        (proper(a) && proper(b)).then_some(axis)
    };
    match shared {
        2 => {
            let Some(w) = (0..3).find(|&k| !ai.contains(&bi[k])) else {
                return false;
            };
            if ob(w) != 0 {
                return true;
            }
            let Some(axis) = projected() else {
                return false;
            };
            // `a`'s vertex off the shared edge, and the edge's ends.
            let Some(v) = (0..3).find(|&k| !bi.contains(&ai[k])) else {
                return false;
            };
            let (i, j) = ((v + 1) % 3, (v + 2) % 3);
            let p = |x: &P3| drop_axis(x, axis);
            let sv = orient2d(p(&a[i]), p(&a[j]), p(&a[v]));
            let sw = orient2d(p(&a[i]), p(&a[j]), p(&b[w]));
            (sv > 0.0 && sw < 0.0) || (sv < 0.0 && sw > 0.0)
        }
        1 => {
            let [c, d] = others(bi, ai);
            let s = ob(c);
            if s != 0 && ob(d) == s {
                return true;
            }
            let [e, f] = others(ai, bi);
            let s = oa(e);
            if s != 0 && oa(f) == s {
                return true;
            }
            let Some(axis) = projected() else {
                return false;
            };
            let p = |x: &P3| drop_axis(x, axis);
            let apex = p(&a[3 - e - f]);
            // The sectors' rays, counterclockwise (both triangles are proper there).
            let ccw = |x: [f64; 2], y: [f64; 2]| {
                if orient2d(apex, x, y) > 0.0 {
                    [x, y]
                } else {
                    [y, x]
                }
            };
            let sa = ccw(p(&a[e]), p(&a[f]));
            let sb = ccw(p(&b[c]), p(&b[d]));
            let inside = |r: [f64; 2], s: &[[f64; 2]; 2]| {
                orient2d(apex, s[0], r) >= 0.0 && orient2d(apex, r, s[1]) >= 0.0
            };
            !(inside(sb[0], &sa) || inside(sb[1], &sa) || inside(sa[0], &sb) || inside(sa[1], &sb))
        }
        _ => false,
    }
}
