//! Viewing volumes (paper section 2.3) and the selection test against them.
//!
//! A polygon's viewing volume is the polygon thickened by `h = epsilon / 2` along its normal:
//! the orthographic box around the polygon's 2D bounding box in its own plane, depth
//! `[-h, h]`, cut by clip planes along the slanted edges. For a triangle that is the right
//! prism over the triangle (two caps, three edge planes), which is how it is stored here.
//! A degenerate triangle has no plane; its volume is the box of half-width `h/sqrt(2)` around
//! its segment (or `h/sqrt(3)` around its point), so every point of every volume lies within
//! `h` of the polygon. So has, in `f64`, a sliver so thin that the rounding of its normal
//! leaves its own corners outside the prism built on it (a collinear quad placed by a
//! rotation: corners a rounding off one line): its volume is the box around its longest
//! edge, widened to hold its corners ([`Cell::of_triangle`]). Every volume holds its
//! triangle (to rounding), which [`Cell::far_from`] relies on.
//!
//! "A primitive is selected when any part of it survives clipping against the volume's
//! planes": [`Cell::meets_triangle`] clips the candidate (Sutherland-Hodgman, closed
//! half-spaces) in `f64`, in a frame whose origin is the reference polygon's first vertex, so
//! the answer does not depend on the distance from the world origin.

use super::predicates::{collinear, P3};

#[cfg(target_arch = "x86_64")]
pub(crate) mod four;

/// A convex viewing volume: the points `x` with `n . (x - origin) + d >= 0` for every plane.
#[derive(Clone, Debug)]
pub struct Cell {
    origin: P3,
    /// The volume's planes (`shown` of them: [`Cell::planes`]), then, for a prism over a
    /// triangle with a sharp corner, the supporting plane at each such corner (up to two):
    /// redundant in exact arithmetic, they keep clipping exact to rounding at a needle's
    /// tip, where its two long sides' planes nearly coincide and clipping against them
    /// alone keeps a sliver about ulp / angle long past the tip.
    planes: [[f64; 4]; 8],
    count: usize,
    shown: usize,
}

/// A needle reference (a 1e-10 edge next to a right angle), a triangle 1.1e-7 past its tip
/// (by an exact rational computation) that the needle's volume once kept, and the epsilon
/// they were found at (by review): for the tests here and of the lanes.
#[cfg(test)]
pub(crate) const NEEDLE_PAST_TIP: ([P3; 3], [P3; 3], f32) = (
    [
        [0.0, 0.0, 0.0],
        [
            -4.016898272340974e-11,
            -2.6028002669820083e-11,
            -8.780088461834978e-11,
        ],
        [-0.6565284132957458, 0.7502625584602356, 0.07795185595750809],
    ],
    [
        [-0.6400055289268494, 0.7659923434257507, 0.06572958081960678],
        [-0.6660141944885254, 0.7412342429161072, 0.08496793359518051],
        [-0.40299293398857117, 0.8378798365592957, 0.3872389793395996],
    ],
    (2.0 * 1.0726893320679665e-2) as f32,
);

/// A corner is sharp below this cosine of its angle (about 1e-2 radian): the position of
/// its two sides' crossing is then a hundred times less accurate than the sides.
const COS_SHARP: f64 = 0.99995;

#[inline]
fn sub(a: &P3, b: &P3) -> P3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
#[inline]
fn dot(a: &P3, b: &P3) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
#[inline]
fn cross(a: &P3, b: &P3) -> P3 {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}
#[inline]
fn scale(a: &P3, s: f64) -> P3 {
    [a[0] * s, a[1] * s, a[2] * s]
}
#[inline]
fn unit(a: &P3) -> P3 {
    scale(a, 1.0 / dot(a, a).sqrt())
}

impl Cell {
    /// The viewing volume of triangle `t` with half-depth `h` (`h > 0`).
    pub fn of_triangle(t: &[P3; 3], h: f64) -> Cell {
        let origin = t[0];
        let a = sub(&t[1], &origin);
        let b = sub(&t[2], &origin);
        let mut cell = Cell {
            origin,
            planes: [[0.0; 4]; 8],
            count: 0,
            shown: 0,
        };
        if collinear(&t[0], &t[1], &t[2]) {
            cell.set_degenerate(&[[0.0; 3], a, b], h);
            cell.shown = cell.count;
            return cell;
        }
        let c = cross(&a, &b);
        let n = unit(&c);
        cell.push(n, h);
        cell.push(scale(&n, -1.0), h);
        let v = [[0.0; 3], a, b];
        for i in 0..3 {
            let p = v[i];
            let e = sub(&v[(i + 1) % 3], &p);
            // n x e points into the triangle for the winding that gave n.
            let m = unit(&cross(&n, &e));
            cell.push(m, -dot(&m, &p));
        }
        cell.shown = cell.count;
        for i in 0..3 {
            let p = v[i];
            let (u1, u2) = (
                unit(&sub(&v[(i + 1) % 3], &p)),
                unit(&sub(&v[(i + 2) % 3], &p)),
            );
            if dot(&u1, &u2) > COS_SHARP {
                // Along the corner's bisector, into the triangle: the triangle lies on its
                // inner side (both sides leave the corner at less than 90 degrees to it).
                let m = unit(&[u1[0] + u2[0], u1[1] + u2[1], u1[2] + u2[2]]);
                cell.push(m, -dot(&m, &p));
            }
        }
        // A sliver (sine of the angle at the first corner below 1e-3): its computed normal
        // may be off by 2^-50 / sine radian and more (all rounding, for corners a rounding
        // off one line), and a prism on a wrong normal does not hold the triangle (its
        // corners beyond the caps by up to the triangle's size), which both the clipping and
        // `far_from` (the cheap rejection before the exact test) take for granted. Checked
        // there only (a sine of 1e-3 or more keeps the corners within 1e-12 of the size):
        // a prism that misses a corner by more than 1e-11 of the size gives way to the box.
        let nn = dot(&c, &c);
        if nn < 1e-6 * dot(&a, &a) * dot(&b, &b) && !cell.holds(&v, h) {
            cell.count = 0;
            cell.set_degenerate(&v, h);
            cell.shown = cell.count;
        }
        cell
    }

    /// Every corner of `v` (local coordinates) inside every plane to within `1e-11` of the
    /// local size (`h` plus the corners' largest coordinate); false where a plane is NaN.
    fn holds(&self, v: &[P3; 3], h: f64) -> bool {
        let size = v.iter().flatten().fold(h, |m, x| m.max(x.abs()));
        let tol = 1e-11 * size;
        self.planes[..self.count].iter().all(|pl| {
            v.iter()
                .all(|x| pl[0] * x[0] + pl[1] * x[1] + pl[2] * x[2] + pl[3] >= -tol)
        })
    }

    /// Box around a segment or point given in local coordinates: along the longest edge
    /// `u` and two axes across it, each pair of faces `r` beyond the corners' extremes (a
    /// sliver's corners off its longest edge widen the box by as much).
    fn set_degenerate(&mut self, v: &[P3; 3], h: f64) {
        let (mut p, mut q, mut best) = (0, 0, 0.0);
        for i in 0..3 {
            for j in i + 1..3 {
                let d = sub(&v[j], &v[i]);
                let l = dot(&d, &d);
                if l > best {
                    (p, q, best) = (i, j, l);
                }
            }
        }
        let (u, r) = if best > 0.0 {
            (unit(&sub(&v[q], &v[p])), h / 2f64.sqrt())
        } else {
            ([1.0, 0.0, 0.0], h / 3f64.sqrt())
        };
        // Two unit vectors orthogonal to u.
        let k = if u[0].abs() <= u[1].abs() && u[0].abs() <= u[2].abs() {
            [1.0, 0.0, 0.0]
        } else if u[1].abs() <= u[2].abs() {
            [0.0, 1.0, 0.0]
        } else {
            [0.0, 0.0, 1.0]
        };
        let w1 = unit(&cross(&u, &k));
        let w2 = cross(&u, &w1);
        let span = |w: &P3| {
            let d = v.map(|x| dot(w, &x));
            (d[0].min(d[1]).min(d[2]), d[0].max(d[1]).max(d[2]))
        };
        let (lo, hi) = span(&u);
        let along = if best > 0.0 { 0.0 } else { r };
        self.push(u, -lo + along);
        self.push(scale(&u, -1.0), hi + along);
        for w in [w1, w2] {
            let (lo, hi) = span(&w);
            self.push(w, r - lo);
            self.push(scale(&w, -1.0), r + hi);
        }
    }

    /// The origin of the frame the planes are given in (the triangle's first vertex).
    pub fn origin(&self) -> P3 {
        self.origin
    }

    /// The planes `[nx, ny, nz, d]`, unit normals pointing inwards (`n . (x - origin) + d >=
    /// 0` inside). A prism ([`Cell::is_prism`]): its two caps, normal `n` then `-n` (`d` the
    /// half depth), then its three edges. A degenerate triangle's box: three pairs of
    /// opposite faces, `a` then `-a` for each of three orthonormal axes `a`. A GL viewing
    /// volume is built from these (the GL_SELECT backend), so both test the same volume
    /// (the supporting planes at sharp corners, redundant, are not listed: the GL volume
    /// finds candidates, which [`Cell::meets_triangle`] confirms).
    pub fn planes(&self) -> &[[f64; 4]] {
        &self.planes[..self.shown]
    }

    /// The prism over a triangle (5 planes), rather than the box of a degenerate one (6).
    pub fn is_prism(&self) -> bool {
        self.shown == 5
    }

    fn push(&mut self, n: P3, d: f64) {
        self.planes[self.count] = [n[0], n[1], n[2], d];
        self.count += 1;
    }

    /// Is every point of triangle `u` certainly farther than `h` from the polygon this
    /// volume was made for (its half depth being `h`)? True when all three corners lie
    /// beyond one of the volume's planes by more than `h` plus a margin (`1e-9` of the
    /// magnitudes involved, millions of times the rounding of these few operations): the
    /// polygon lies inside every plane, so such a triangle is more than `h` away from it.
    /// Then `u` misses this volume (clipping against that plane alone empties it:
    /// [`Cell::meets_triangle`] computes the same plane values), does not intersect the
    /// polygon, and no point of the polygon lies in a volume of half depth `h` made for `u`
    /// (every point of such a volume lies within `h` of `u`). A cheap rejection before
    /// clipping, both ways round.
    #[inline]
    pub fn far_from(&self, u: &[P3; 3], h: f64) -> bool {
        let w = u.map(|p| sub(&p, &self.origin));
        self.planes[..self.count].iter().any(|pl| {
            w.iter().all(|x| {
                let v = pl[0] * x[0] + pl[1] * x[1] + pl[2] * x[2] + pl[3];
                let scale = h + pl[3].abs() + x[0].abs() + x[1].abs() + x[2].abs();
                v < -(h + 1e-9 * scale)
            })
        })
    }

    /// Does any part of the closed triangle `u` (world coordinates) survive clipping
    /// against this volume?
    pub fn meets_triangle(&self, u: &[P3; 3]) -> bool {
        let mut buf = [[[0.0f64; 3]; 12]; 2];
        let mut n = 3;
        for (i, p) in u.iter().enumerate() {
            buf[0][i] = sub(p, &self.origin);
        }
        let mut src = 0;
        for pl in &self.planes[..self.count] {
            let dist = |x: &P3| pl[0] * x[0] + pl[1] * x[1] + pl[2] * x[2] + pl[3];
            let dst = 1 - src;
            let mut m = 0;
            for i in 0..n {
                let c = buf[src][i];
                let nx = buf[src][(i + 1) % n];
                let (dc, dn) = (dist(&c), dist(&nx));
                if dc >= 0.0 {
                    buf[dst][m] = c;
                    m += 1;
                }
                if (dc >= 0.0) != (dn >= 0.0) {
                    let t = dc / (dc - dn);
                    buf[dst][m] = [
                        c[0] + (nx[0] - c[0]) * t,
                        c[1] + (nx[1] - c[1]) * t,
                        c[2] + (nx[2] - c[2]) * t,
                    ];
                    m += 1;
                }
            }
            if m == 0 {
                return false;
            }
            n = m;
            src = dst;
        }
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const T: [P3; 3] = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];

    #[test]
    fn prism_depth_and_edges() {
        let c = Cell::of_triangle(&T, 0.01);
        let flat = |z: f64, x: f64, y: f64| [[x, y, z], [x + 0.01, y, z], [x, y + 0.01, z]];
        assert!(c.meets_triangle(&flat(0.009, 0.2, 0.2)));
        assert!(c.meets_triangle(&flat(-0.009, 0.2, 0.2)));
        assert!(!c.meets_triangle(&flat(0.011, 0.2, 0.2)));
        // Beyond the hypotenuse, inside the triangle's 2D bounding box: the clip plane cuts it.
        assert!(!c.meets_triangle(&flat(0.0, 0.6, 0.6)));
        assert!(c.meets_triangle(&flat(0.0, 0.45, 0.45)));
    }

    #[test]
    fn slanted_polygon_far_from_origin() {
        let o = [1e5, -1e5, 1e5];
        let t = [
            o,
            [o[0] + 1.0, o[1], o[2] + 1.0],
            [o[0], o[1] + 1.0, o[2] + 1.0],
        ];
        let c = Cell::of_triangle(&t, 5e-4); // epsilon 1e-3
                                             // A needle through the centroid, perpendicular to the triangle.
        let g = [o[0] + 1.0 / 3.0, o[1] + 1.0 / 3.0, o[2] + 2.0 / 3.0];
        let n = [1.0, 1.0, -1.0];
        let needle = |s: f64, t: f64| {
            let a = [g[0] + n[0] * s, g[1] + n[1] * s, g[2] + n[2] * s];
            let b = [g[0] + n[0] * t, g[1] + n[1] * t, g[2] + n[2] * t];
            [a, b, b]
        };
        assert!(c.meets_triangle(&needle(-1.0, 1.0)));
        // |n| = sqrt(3): the needle starts 2.5e-4 * sqrt(3) = 4.3e-4 above the plane.
        assert!(c.meets_triangle(&needle(2.5e-4, 1.0)));
        assert!(!c.meets_triangle(&needle(3.0e-4, 1.0)));
    }

    #[test]
    fn planes_are_caps_and_edges_or_opposite_pairs() {
        let unit =
            |p: &[f64; 4]| (dot(&[p[0], p[1], p[2]], &[p[0], p[1], p[2]]) - 1.0).abs() < 1e-12;
        let c = Cell::of_triangle(&T, 0.01);
        assert!(c.is_prism());
        let p = c.planes();
        assert_eq!(p.len(), 5);
        assert_eq!(p[0], [0.0, 0.0, 1.0, 0.01]);
        assert_eq!(p[1], [-0.0, -0.0, -1.0, 0.01]);
        assert!(p.iter().all(unit));
        let seg = [[0.0, 0.0, 0.0], [2.0, 0.0, 0.0], [1.0, 0.0, 0.0]];
        let d = Cell::of_triangle(&seg, 0.1);
        assert!(!d.is_prism());
        let p = d.planes();
        assert_eq!(p.len(), 6);
        for k in 0..3 {
            let (a, b) = (p[2 * k], p[2 * k + 1]);
            assert!(unit(&a));
            assert_eq!([a[0], a[1], a[2]], [-b[0], -b[1], -b[2]]);
            assert!(-a[3] <= b[3], "an empty slab"); // a . x in [-a[3], b[3]]
        }
        assert_eq!(d.origin(), seg[0]);
    }

    /// A needle (tip angle about 1e-10) rounds its volume's two long sides into nearly one
    /// plane: past the tip, clipping against them alone kept a sliver about ulp / angle
    /// long (found by review with this triangle). The volume's supporting plane at a sharp
    /// corner cuts it there: points 1e-8 to 1e-5 past the tip miss, points just inside
    /// meet.
    #[test]
    fn needle_tip_is_sharp() {
        let (needle, b, eps) = NEEDLE_PAST_TIP;
        let mut rng = crate::geom::test_rng::Rng(0x7E3D_1E5E_u64);
        for (o, scale) in [(0.0, 1.0), (1e3, 1.0), (0.0, 1e-3), (1e5, 1e2)] {
            let t = needle.map(|p| p.map(|x| o + x * scale));
            let h = 0.0107 * scale;
            let c = Cell::of_triangle(&t, h);
            assert!(c.planes().len() == 5 && c.is_prism());
            let tip = t[2];
            let d = unit(&sub(&t[2], &t[0]));
            let mut missed = 0;
            for _ in 0..2000 {
                // Past the tip along the needle, a little to the side, within the depth.
                let past = 10f64.powf(-8.0 + 3.0 * rng.unit()) * scale;
                let side = rng.dir();
                let p: P3 = std::array::from_fn(|i| {
                    tip[i] + d[i] * past + (side[i] - d[i] * dot(&side, &d)) * past * 0.5
                });
                missed += usize::from(!c.meets_triangle(&[p; 3]));
            }
            assert_eq!(missed, 2000, "offset {o} scale {scale}");
            // Just inside: a tenth of the way from the tip to the base, on the long side's
            // bisector of the two long sides, within the depth.
            let m: P3 = std::array::from_fn(|i| 0.9 * t[2][i] + 0.05 * t[0][i] + 0.05 * t[1][i]);
            let n = unit(&cross(&sub(&t[1], &t[0]), &sub(&t[2], &t[0])));
            let q: P3 = std::array::from_fn(|i| m[i] + n[i] * h * 0.5);
            assert!(c.meets_triangle(&[q; 3]), "offset {o} scale {scale}");
        }
        // The review's triangle just past the tip: clipped against the long sides alone it
        // kept a sliver.
        let h = f64::from(eps) / 2.0;
        assert!(!Cell::of_triangle(&needle, h).meets_triangle(&b));
        let rot = [needle[1], needle[2], needle[0]];
        assert!(!Cell::of_triangle(&rot, h).meets_triangle(&b));
    }

    /// Collinear points on the x axis placed by a random rotation (as a transform,
    /// [`crate::Scene::set_transform`], places them: no fused multiply-add) are a sliver
    /// whose `f64` normal may be all rounding (contact_check's "quads degenerate vs quads, placed"
    /// pair 437: the prism on it left the triangle's corners a distance 0.6 outside, and
    /// `far_from` dropped a quad crossing it). Every volume holds its triangle's corners
    /// (and `far_from` never rejects them), and a sliver's box stays within `h` of it.
    #[test]
    fn a_placed_collinear_triangle_lies_in_its_volume() {
        let mut rng = crate::geom::test_rng::Rng(0x5_11CE_u64);
        let mut boxes = 0;
        for i in 0..20_000 {
            let q = loop {
                let q = [0; 4].map(|_| rng.range(-1.0, 1.0));
                let n = dot(&[q[0], q[1], q[2]], &[q[0], q[1], q[2]]) + q[3] * q[3];
                if n > 0.1 && n < 1.0 {
                    break q.map(|x| x / n.sqrt());
                }
            };
            let [w, x, y, z] = q;
            let col = [
                1. - 2. * (y * y + z * z),
                2. * (x * y + w * z),
                2. * (x * z - w * y),
            ];
            let off = [0.0, 1.0, 1e3][i % 3];
            let t: [P3; 3] = std::array::from_fn(|_| {
                let s = rng.range(-1.0, 1.0) as f32 as f64;
                // m * (s, 0, 0, 1), the other columns times 0.
                std::array::from_fn(|r| std::hint::black_box(col[r] * s) + 0.0 + 0.0 + off)
            });
            let h = [0.025, 1e-4, 0.5][i / 3 % 3];
            let c = Cell::of_triangle(&t, h);
            boxes += usize::from(!c.is_prism());
            for p in &t {
                // Inside every plane but for rounding (1e-11 of the size: 1e-16 is usual).
                let x = sub(p, &t[0]);
                for pl in &c.planes[..c.count] {
                    let v = pl[0] * x[0] + pl[1] * x[1] + pl[2] * x[2] + pl[3];
                    assert!(v >= -1e-11 * (off + 1.0), "{i}: {t:?} h {h}: {v}");
                }
                assert!(!c.far_from(&[*p; 3], h), "{i}: {t:?} h {h}");
            }
            if !c.is_prism() && off == 0.0 {
                // The box's corners within h (and rounding) of the segment's line.
                let u = unit(&sub(&t[1], &t[0]));
                let u = if u[0].is_nan() {
                    unit(&sub(&t[2], &t[0]))
                } else {
                    u
                };
                for pl in c.planes().chunks(2) {
                    let a = [pl[0][0], pl[0][1], pl[0][2]];
                    let across = 1.0 - dot(&a, &u).abs() > 1e-6;
                    if across {
                        let width = pl[0][3] + pl[1][3];
                        assert!(width <= 2.0 * h / 2f64.sqrt() * (1.0 + 1e-9), "{width}");
                    }
                }
            }
        }
        assert!(boxes > 1000, "{boxes} slivers made boxes");
    }

    #[test]
    fn degenerate_reference_is_a_thin_box() {
        let seg = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.5, 0.0, 0.0]];
        let c = Cell::of_triangle(&seg, 0.1);
        let pt = |x: f64, y: f64, z: f64| [[x, y, z]; 3];
        assert!(c.meets_triangle(&pt(0.5, 0.07, 0.0)));
        assert!(!c.meets_triangle(&pt(0.5, 0.071, 0.0)));
        assert!(!c.meets_triangle(&pt(1.01, 0.0, 0.0)));
        let p = Cell::of_triangle(&[[2.0, 2.0, 2.0]; 3], 0.1);
        assert!(p.meets_triangle(&pt(2.05, 2.05, 2.05)));
        assert!(!p.meets_triangle(&pt(2.06, 2.0, 2.0)));
    }
}
