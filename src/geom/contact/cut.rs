//! Where two crossing triangles meet: a triangle's plane, the triangle's cut by the other's
//! plane (its vertices' signed distances, evaluated accurately where rounding could move a
//! cut's end) and the overlap of two cuts on the planes' common line.

use super::exact::{triangle_normal, two_prod, two_sum};
use super::{max, min, pattern, LONELY, NEXT, PREV, V};
use crate::geom::predicates::P3;

/// Relative error allowed for in [`Face::sides`], as the query's plane filter
/// (`tritri::Plane`): thousands of times the worst rounding of the few operations.
pub(super) const FACE_SLACK: f64 = 1e-12;

/// A triangle's plane: `n = (t1 - t0) x (t2 - t0)` and, per component, the sum of the
/// magnitudes of the two products behind it (the scale of its rounding error).
pub(super) struct Face<'w> {
    o: V,
    pub(super) n: V,
    perm: V,
    /// The triangle's corners as given (world positions): what
    /// [`Face::distance_accurately`] works from.
    world: &'w [P3; 3],
}

impl<'w> Face<'w> {
    /// The plane of `t`, whose corners are at world positions `world` (`t` is `world` or
    /// its image in a local frame).
    #[inline(always)]
    pub(super) fn of(t: &[V; 3], world: &'w [P3; 3]) -> Face<'w> {
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
    pub(super) fn sides(&self, p: &[V; 3]) -> ([f64; 3], [i8; 3], [f64; 3]) {
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
    pub(super) fn distance_accurately(&self, p: &P3) -> f64 {
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
pub(super) struct Cutting<'a> {
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
    pub(super) fn new(
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
pub(super) const REFINE: f64 = 2.0;

/// Distances `d` made to agree with the exact signs `s` of `orient3d` (`d ~ -orient3d`):
/// a rounded value of the wrong sign becomes a tiny one of the right sign, and an exact
/// zero is zero.
#[inline(always)]
pub(super) fn signed_like(mut d: [f64; 3], s: [i8; 3]) -> [f64; 3] {
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
pub(super) fn transverse(t: &Cutting, u: &Cutting) -> Option<(V, V)> {
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
pub(super) fn lerp_from_nearer(p: &V, q: &V, dp: f64, dq: f64) -> V {
    if dp.abs() <= dq.abs() {
        p + (q - p) * (dp / (dp - dq)).clamp(0.0, 1.0)
    } else {
        q + (p - q) * (dq / (dq - dp)).clamp(0.0, 1.0)
    }
}
