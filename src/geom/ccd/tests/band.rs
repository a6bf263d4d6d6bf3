//! The distance-band tests ([`super::super::band`]) against answers they do not compute:
//!
//! * constructed motions whose squared distance `f(t)` is known in closed form (a point
//!   passing over a triangle's interior, beside an edge, beside a corner, with a turning
//!   closest direction; edges passing skew, parallel, end to interior, end to end,
//!   coplanar; degenerate triangles and edges; no motion), each checked against the
//!   independent reference ([`reference::dist2_at`]) where it is used, at bands just below
//!   and above the closest distance `h`: `h (1 - 2^-18)` and `h (1 - 2^-20)` (`D < h`:
//!   never reported), `h` and `h (1 + 2^-18)` (always reported, the toi within
//!   `[t_D - 2^-20, t_d]` by `f`, exactly in rationals), moved by exact changes (axes
//!   permuted and flipped, a common velocity, reordered points, scales `2^-100`, `2^100`,
//!   offset 1e6);
//! * `t = 0` at its exact boundary: static pairs at distances whose square is not a double,
//!   bands one ulp either side;
//! * random motions (grid and literal scales 1e-30, 1e30) against the reference at
//!   sampled times, and at the distance they have at a sampled time (often a tangency);
//! * thin bands (a point or a short edge sliding a little above a face or a long edge,
//!   rotated so that nothing rounds exactly, offsets 1e6): the bounds' rounding terms
//!   decide there;
//! * scales `2^900` and `2^-1000`;
//! * the ground truth's touching pairs, reported at any band with a toi no later than the
//!   zero-distance one;
//! * the timing over the ground truth (ignored).

use super::super::band::{decide_within, edge_edge_within, vertex_face_within, Route};
use super::super::predicate::Kind;
use super::super::{decide, Points, Toi};
use super::bench::best_of_3;
use super::reference::{dist2_at, inv_pow2, q, speed_bound, Q};
use super::split;
use super::truth::{has_truth, load, SCENES};
use crate::geom::test_rng::Rng;
use crate::geom::P3;
use num_traits::{One, Zero};

/// `n / d` as a rational.
fn r(n: i64, d: i64) -> Q {
    Q::new(n.into(), d.into())
}

/// `x0 + t (x1 - x0)`.
fn lin(x0: f64, x1: f64, t: &Q) -> Q {
    q(x0) + t * (q(x1) - q(x0))
}

fn pos(x: Q) -> Q {
    if x > Q::zero() {
        x
    } else {
        Q::zero()
    }
}

/// A motion built with a known squared distance.
struct Built {
    name: &'static str,
    kind: Kind,
    pts: Points,
    /// The closest distance (a double).
    h: f64,
    /// The first time the distance is `h`; `f` does not increase before it, and is at least
    /// `h^2` after.
    t_c: Q,
    /// The squared distance at `t`.
    f: Box<dyn Fn(&Q) -> Q>,
}

/// The squared distance of a motion that passes at `h` while it falls through z = 0 at
/// t = 1/2 (z from 2 to -2): `h^2 + z(t)^2`.
fn falling_by(h: f64) -> Box<dyn Fn(&Q) -> Q> {
    Box::new(move |t| {
        let z = lin(2.0, -2.0, t);
        q(h) * q(h) + &z * &z
    })
}

/// A still point.
fn still(p: P3) -> [P3; 2] {
    [p, p]
}

/// The constructed motions, `k` the grid unit of the small distances (a power of two).
fn built(k: f64) -> Vec<Built> {
    let mut out = Vec::new();
    // The triangle of the vertex-face cases: in z = 0, its corner a at the origin, edges
    // along +x and +y.
    let tri = [[0.0, 0.0, 0.0], [4.0, 0.0, 0.0], [0.0, 4.0, 0.0]];
    let vf = |v: [P3; 2], t: [P3; 3]| -> Points { [v, still(t[0]), still(t[1]), still(t[2])] };
    let h = 4.0 * k;
    // Over the interior at height h, entering across the edge x = 0 at t = 2/5.
    out.push(Built {
        name: "vf over the face",
        kind: Kind::VertexFace,
        pts: vf([[-2.0, 1.0, h], [3.0, 1.0, h]], tri),
        h,
        t_c: r(2, 5),
        f: Box::new(move |t| {
            let x = lin(-2.0, 3.0, t);
            q(h) * q(h) + pos(-x.clone()) * pos(-x)
        }),
    });
    // Beside the edge y = 0 (outside, y = -3k), falling through z = 0 at t = 1/2.
    let (y, h3) = (-3.0 * k, 3.0 * k);
    out.push(Built {
        name: "vf beside an edge",
        kind: Kind::VertexFace,
        pts: vf([[1.0, y, 2.0], [1.0, y, -2.0]], tri),
        h: h3,
        t_c: r(1, 2),
        f: falling_by(h3),
    });
    // The same, moving along the edge too (the closest direction is not the motion's).
    out.push(Built {
        name: "vf beside an edge, oblique",
        kind: Kind::VertexFace,
        pts: vf([[0.5, y, 2.0], [2.5, y, -2.0]], tri),
        h: h3,
        t_c: r(1, 2),
        f: falling_by(h3),
    });
    // Beside the corner a: (x, y) = (-3k, -4k), at 5k.
    let h5 = 5.0 * k;
    out.push(Built {
        name: "vf beside a corner",
        kind: Kind::VertexFace,
        pts: vf([[-3.0 * k, -4.0 * k, 2.0], [-3.0 * k, -4.0 * k, -2.0]], tri),
        h: h5,
        t_c: r(1, 2),
        f: falling_by(h5),
    });
    // Past the corner on the edge's line, the closest direction turning: (x, z) relative
    // to a is (-(3k + 4 (t - 1/2)), 4k - 3 (t - 1/2)), at 5k at t = 1/2; while x > 0 the
    // point is over the edge (distance |z|).
    let xa = move |t: f64| -(3.0 * k + 4.0 * (t - 0.5));
    let za = move |t: f64| 4.0 * k - 3.0 * (t - 0.5);
    out.push(Built {
        name: "vf turning past a corner",
        kind: Kind::VertexFace,
        pts: vf([[xa(0.0), 0.0, za(0.0)], [xa(1.0), 0.0, za(1.0)]], tri),
        h: h5,
        t_c: r(1, 2),
        f: Box::new(move |t| {
            let (x, z) = (lin(xa(0.0), xa(1.0), t), lin(za(0.0), za(1.0), t));
            pos(-x.clone()) * pos(-x) + &z * &z
        }),
    });
    // Degenerate triangles: a segment (c on ab, or c = a), a point.
    for (name, c) in [
        ("vf segment triangle", [2.0, 0.0, 0.0]),
        ("vf segment triangle, c = a", [0.0, 0.0, 0.0]),
    ] {
        out.push(Built {
            name,
            kind: Kind::VertexFace,
            pts: vf([[1.0, -y, 2.0], [1.0, -y, -2.0]], [tri[0], tri[1], c]),
            h: h3,
            t_c: r(1, 2),
            f: falling_by(h3),
        });
    }
    out.push(Built {
        name: "vf point triangle",
        kind: Kind::VertexFace,
        pts: vf(
            [[-3.0 * k, 4.0 * k, 2.0], [-3.0 * k, 4.0 * k, -2.0]],
            [[0.0; 3]; 3],
        ),
        h: h5,
        t_c: r(1, 2),
        f: falling_by(h5),
    });
    // Coplanar: sliding along the edge x = 0 at h (outside), past the corner a first (and
    // past c at the end).
    out.push(Built {
        name: "vf coplanar slide",
        kind: Kind::VertexFace,
        pts: vf([[-h, -3.0, 0.0], [-h, 6.0, 0.0]], tri),
        h,
        t_c: r(1, 3),
        f: Box::new(move |t| {
            let y = lin(-3.0, 6.0, t);
            let gap = pos(-y.clone()).max(pos(y - r(4, 1)));
            q(h) * q(h) + &gap * &gap
        }),
    });
    // Coplanar: approaching the edge x = 0 head-on, stopping at h.
    out.push(Built {
        name: "vf coplanar approach",
        kind: Kind::VertexFace,
        pts: vf([[-2.0, 1.0, 0.0], [-h, 1.0, 0.0]], tri),
        h,
        t_c: Q::one(),
        f: Box::new(move |t| {
            let x = lin(-2.0, -h, t);
            &x * &x
        }),
    });
    // The triangle tilting (z = s y, s from 0 to 3/4) while the vertex comes down over it
    // to 5k: its distance z / sqrt(1 + s^2) ends at 4k, the normal turning all along.
    let (z0, z1) = (2.0, 5.0 * k);
    let h4 = 4.0 * k;
    out.push(Built {
        name: "vf tilting face",
        kind: Kind::VertexFace,
        pts: [
            [[0.0, 0.0, z0], [0.0, 0.0, z1]],
            [[-4.0, -4.0, 0.0], [-4.0, -4.0, -3.0]],
            [[4.0, -4.0, 0.0], [4.0, -4.0, -3.0]],
            [[0.0, 4.0, 0.0], [0.0, 4.0, 3.0]],
        ],
        h: h4,
        t_c: Q::one(),
        f: Box::new(move |t| {
            let (z, s) = (lin(z0, z1, t), lin(0.0, 0.75, t));
            &z * &z / (Q::one() + &s * &s)
        }),
    });
    out.push(Built {
        name: "vf no motion",
        kind: Kind::VertexFace,
        pts: vf(still([1.0, 1.0, h]), tri),
        h,
        t_c: Q::zero(),
        f: Box::new(move |_| q(h) * q(h)),
    });

    // Edge-edge: a along the x axis, from -4 to 4.
    let ea = [[-4.0, 0.0, 0.0], [4.0, 0.0, 0.0]];
    let ee =
        |a: [P3; 2], b0: [P3; 2], b1: [P3; 2]| -> Points { [still(a[0]), still(a[1]), b0, b1] };
    // b along y at height h, crossing over a along x (skew, then past a's end).
    out.push(Built {
        name: "ee skew",
        kind: Kind::EdgeEdge,
        pts: ee(
            ea,
            [[-6.0, -4.0, h], [6.0, -4.0, h]],
            [[-6.0, 4.0, h], [6.0, 4.0, h]],
        ),
        h,
        t_c: r(1, 6),
        f: Box::new(move |t| {
            let x = lin(-6.0, 6.0, t);
            let gap = pos(-x.clone() - r(4, 1)).max(pos(x - r(4, 1)));
            q(h) * q(h) + &gap * &gap
        }),
    });
    // b along y, 3k beyond a's end, falling through z = 0.
    let bx = 4.0 + 3.0 * k;
    out.push(Built {
        name: "ee end to interior",
        kind: Kind::EdgeEdge,
        pts: ee(
            ea,
            [[bx, -4.0, 2.0], [bx, -4.0, -2.0]],
            [[bx, 4.0, 2.0], [bx, 4.0, -2.0]],
        ),
        h: h3,
        t_c: r(1, 2),
        f: falling_by(h3),
    });
    // b along x too, beyond a's end: end to end.
    out.push(Built {
        name: "ee end to end",
        kind: Kind::EdgeEdge,
        pts: ee(
            ea,
            [[bx, 0.0, 2.0], [bx, 0.0, -2.0]],
            [[bx + 4.0, 0.0, 2.0], [bx + 4.0, 0.0, -2.0]],
        ),
        h: h3,
        t_c: r(1, 2),
        f: falling_by(h3),
    });
    // Parallel, at 5k ((0, 3k, 4k) off), sliding in along x.
    out.push(Built {
        name: "ee parallel",
        kind: Kind::EdgeEdge,
        pts: ee(
            ea,
            [[6.0, 3.0 * k, 4.0 * k], [-2.0, 3.0 * k, 4.0 * k]],
            [[14.0, 3.0 * k, 4.0 * k], [6.0, 3.0 * k, 4.0 * k]],
        ),
        h: h5,
        t_c: r(1, 4),
        f: Box::new(move |t| {
            let gap = pos(lin(6.0, -2.0, t) - r(4, 1));
            q(h5) * q(h5) + &gap * &gap
        }),
    });
    // b along y, passing over a's end with a turning closest direction: (x - 4, z) =
    // (3k + 4 (t - 1/2), 4k - 3 (t - 1/2)); while x < 4, over a's interior (distance |z|).
    let xb = move |t: f64| 4.0 + 3.0 * k + 4.0 * (t - 0.5);
    out.push(Built {
        name: "ee turning past an end",
        kind: Kind::EdgeEdge,
        pts: ee(
            ea,
            [[xb(0.0), -4.0, za(0.0)], [xb(1.0), -4.0, za(1.0)]],
            [[xb(0.0), 4.0, za(0.0)], [xb(1.0), 4.0, za(1.0)]],
        ),
        h: h5,
        t_c: r(1, 2),
        f: Box::new(move |t| {
            let (x, z) = (lin(xb(0.0), xb(1.0), t), lin(za(0.0), za(1.0), t));
            let gap = pos(x - r(4, 1));
            &gap * &gap + &z * &z
        }),
    });
    // Coplanar: b along y from y = h, sliding along x onto a's span.
    out.push(Built {
        name: "ee coplanar",
        kind: Kind::EdgeEdge,
        pts: ee(
            ea,
            [[-7.0, h, 0.0], [0.0, h, 0.0]],
            [[-7.0, h + 4.0, 0.0], [0.0, h + 4.0, 0.0]],
        ),
        h,
        t_c: r(3, 7),
        f: Box::new(move |t| {
            let gap = pos(-lin(-7.0, 0.0, t) - r(4, 1));
            q(h) * q(h) + &gap * &gap
        }),
    });
    // Degenerate: a a point (a's end), b as "end to interior"; both points.
    out.push(Built {
        name: "ee point edge",
        kind: Kind::EdgeEdge,
        pts: ee(
            [ea[1], ea[1]],
            [[bx, -4.0, 2.0], [bx, -4.0, -2.0]],
            [[bx, 4.0, 2.0], [bx, 4.0, -2.0]],
        ),
        h: h3,
        t_c: r(1, 2),
        f: falling_by(h3),
    });
    let pp = [[3.0 * k, 4.0 * k, 2.0], [3.0 * k, 4.0 * k, -2.0]];
    out.push(Built {
        name: "ee two points",
        kind: Kind::EdgeEdge,
        pts: ee([[0.0; 3]; 2], pp, pp),
        h: h5,
        t_c: r(1, 2),
        f: falling_by(h5),
    });
    // b through (0, 0, z), z from 2 down to 5k, along e = (0, 4 - t, 3 + t): the lines'
    // distance z e_y / |e| ends at 3k, their common normal turning all along.
    out.push(Built {
        name: "ee turning edge",
        kind: Kind::EdgeEdge,
        pts: ee(
            ea,
            [[0.0, -4.0, z0 - 3.0], [0.0, -3.0, z1 - 4.0]],
            [[0.0, 4.0, z0 + 3.0], [0.0, 3.0, z1 + 4.0]],
        ),
        h: h3,
        t_c: Q::one(),
        f: Box::new(move |t| {
            let z = lin(z0, z1, t);
            let (ey, ez) = (r(4, 1) - t, r(3, 1) + t);
            &z * &z * &ey * &ey / (&ey * &ey + &ez * &ez)
        }),
    });
    out.push(Built {
        name: "ee no motion",
        kind: Kind::EdgeEdge,
        pts: ee(ea, still([0.0, -4.0, h]), still([0.0, 4.0, h])),
        h,
        t_c: Q::zero(),
        f: Box::new(move |_| q(h) * q(h)),
    });
    out
}

/// An exact change of a case that keeps its distances (times `2^scale`): axes permuted and
/// flipped, a common velocity added to every point, the primitives' points reordered,
/// then scaled by `2^scale` and offset.
struct Change {
    axes: [usize; 3],
    signs: [f64; 3],
    velocity: P3,
    order: [usize; 4],
    scale: i32,
    offset: f64,
}

impl Change {
    fn random(rng: &mut Rng, kind: Kind, scale: i32, offset: f64) -> Change {
        let mut axes = [0, 1, 2];
        rng.shuffle(&mut axes);
        let signs = std::array::from_fn(|_| rng.pick(&[1.0, -1.0]));
        let velocity = if rng.below(3) == 0 {
            [0.0; 3]
        } else {
            std::array::from_fn(|_| (rng.below(17) as f64 - 8.0) / 4.0)
        };
        let order = match kind {
            Kind::VertexFace => rng.pick(&[[0, 1, 2, 3], [0, 2, 3, 1], [0, 3, 2, 1], [0, 1, 3, 2]]),
            Kind::EdgeEdge => rng.pick(&[[0, 1, 2, 3], [1, 0, 2, 3], [2, 3, 0, 1], [3, 2, 1, 0]]),
        };
        Change {
            axes,
            signs,
            velocity,
            order,
            scale,
            offset,
        }
    }

    fn apply(&self, pts: &Points) -> Points {
        let s = f64::powi(2.0, self.scale);
        let place = |x: f64| {
            let y = x * s + self.offset;
            assert_eq!((y - self.offset) / s, x, "not exact: {x}");
            y
        };
        let map = |p: P3, time: f64| -> P3 {
            std::array::from_fn(|k| {
                let a = self.axes[k];
                place(self.signs[k] * (p[a] + time * self.velocity[a]))
            })
        };
        self.order
            .map(|i| [map(pts[i][0], 0.0), map(pts[i][1], 1.0)])
    }
}

/// The frames of the changes: scale exponent, offset.
const FRAMES: [(i32, f64); 4] = [(0, 0.0), (-100, 0.0), (100, 0.0), (0, 1e6)];

/// Checks one band `d` on a built case (its changed points `pts`, `f` and `h` scaled by
/// `4^scale` and `2^scale`): reported exactly when it must be, the toi where it must be.
fn judge(b: &Built, pts: &Points, scale: i32, d: f64) -> Option<Toi> {
    let kind = b.kind;
    let (got, route) = decide_within(kind, pts, d);
    let ctx = || {
        format!(
            "{} d = {d:e} h = {:e}: {got:?} {route:?} {pts:?}",
            b.name, b.h
        )
    };
    assert_ne!(route, Route::Capped, "capped: {}", ctx());
    let s2 = if scale >= 0 {
        Q::from_integer(num_bigint::BigInt::one() << (2 * scale) as usize)
    } else {
        inv_pow2((-2 * scale) as u32)
    };
    let f = |t: &Q| (b.f)(t) * &s2;
    let h = q(b.h * f64::powi(2.0, scale));
    let (dq, big) = (q(d), q(d) * (Q::one() + inv_pow2(20)));
    let (d2, big2) = (&dq * &dq, &big * &big);
    // The analytic distance is the reference's (the construction is what it says).
    for t in [Q::zero(), b.t_c.clone(), Q::one()] {
        assert_eq!(f(&t), dist2_at(pts, split(kind), &t), "f at {t}: {}", ctx());
    }
    if h <= dq {
        assert!(got.is_some(), "missed: {}", ctx());
    }
    if big < h {
        assert!(got.is_none(), "never within D: {}", ctx());
    }
    let toi = got?;
    assert_eq!(toi.at_start, f(&Q::zero()) <= d2, "at_start: {}", ctx());
    if toi.at_start {
        assert_eq!(toi.t, 0.0);
        return got;
    }
    let t = q(toi.t);
    assert_eq!(f(&t), dist2_at(pts, split(kind), &t), "f at toi: {}", ctx());
    if h <= dq {
        // t_d: f decreases to h^2 at t_c, so toi <= t_d iff toi <= t_c and f(toi) >= d^2.
        assert!(t <= b.t_c && f(&t) >= d2, "late: {}", ctx());
    }
    // t_D <= toi + 2^-20: f is within D^2 there (or at t_c, before).
    let later = (&t + inv_pow2(20)).min(b.t_c.clone());
    assert!(f(&later) <= big2, "early: {}", ctx());
    got
}

#[test]
fn constructed_motions_at_bands_around_their_closest_distance() {
    let mut rng = Rng(0xba4d_0001);
    let mut counts = [0usize; 2];
    for k in [1.0 / 16.0, 1.0 / 64.0, 3.0 / 128.0] {
        for b in built(k) {
            for (scale, offset) in FRAMES {
                for _ in 0..3 {
                    let change = Change::random(&mut rng, b.kind, scale, offset);
                    let pts = change.apply(&b.pts);
                    let h = b.h * f64::powi(2.0, scale);
                    for d in [
                        h * (1.0 - inv18()),
                        (h * (1.0 - inv20())).next_down(),
                        h,
                        h * (1.0 + inv18()),
                    ] {
                        let got = judge(&b, &pts, scale, d);
                        counts[usize::from(got.is_some())] += 1;
                    }
                }
            }
        }
    }
    eprintln!(
        "constructed: {} not reported, {} reported",
        counts[0], counts[1]
    );
}

/// Far beyond the brief's scales: `2^900` and `2^-1000` (the scaling to `[1, 2)` keeps
/// them exact), the same checks.
#[test]
fn extreme_scales_keep_the_answers() {
    let mut rng = Rng(0xba4d_0007);
    for b in built(1.0 / 16.0) {
        for scale in [900, -1000] {
            let pts = Change::random(&mut rng, b.kind, scale, 0.0).apply(&b.pts);
            let h = b.h * f64::powi(2.0, scale);
            for d in [h * (1.0 - inv18()), h, h * (1.0 + inv18())] {
                judge(&b, &pts, scale, d);
            }
        }
    }
}

fn inv18() -> f64 {
    1.0 / (1u32 << 18) as f64
}

fn inv20() -> f64 {
    1.0 / (1u32 << 20) as f64
}

/// The tolerance's sliver is used, not exceeded: at `d = h (1 - 2^-22)` (`h` within `D`
/// but not `d`) the answer may go either way, and a reported toi is still no earlier than
/// `t_D - 2^-20`.
#[test]
fn inside_the_sliver_either_answer_keeps_the_toi_promise() {
    let mut rng = Rng(0xba4d_0002);
    for b in built(1.0 / 16.0) {
        for (scale, offset) in FRAMES {
            let pts = Change::random(&mut rng, b.kind, scale, offset).apply(&b.pts);
            let h = b.h * f64::powi(2.0, scale);
            judge(&b, &pts, scale, h * (1.0 - 1.0 / (1u32 << 22) as f64));
        }
    }
}

/// Static pairs on an integer grid (their distance mostly irrational): within at `t = 0`
/// exactly when `d^2 >= dist^2`, for `d` the double nearest the distance and its two
/// neighbours; the float bounds cannot tell these apart, the exact test decides.
#[test]
fn at_start_is_exact_at_the_boundary() {
    let mut rng = Rng(0xba4d_0003);
    let mut exact = 0;
    for kind in [Kind::VertexFace, Kind::EdgeEdge] {
        for case in 0..300 {
            let pts: Points = std::array::from_fn(|_| still(gv(&mut rng, 6, 1.0)));
            let lit = [1.0, f64::powi(2.0, -100), f64::powi(2.0, 100)][case % 3];
            let pts = pts.map(|p| p.map(|x| x.map(|c| c * lit)));
            let dist2 = dist2_at(&pts, split(kind), &Q::zero());
            if dist2.is_zero() {
                continue;
            }
            let near = num_traits::ToPrimitive::to_f64(&dist2)
                .expect("finite")
                .sqrt();
            for d in [near.next_down(), near, near.next_up()] {
                let (got, route) = decide_within(kind, &pts, d);
                exact += usize::from(route == Route::ExactStart);
                let within = q(d) * q(d) >= dist2;
                assert_eq!(
                    got.is_some_and(|t| t.at_start),
                    within,
                    "{kind:?} d = {d:e}: {got:?} {route:?} {pts:?}"
                );
                // Static: within D (in the sliver) or not at all.
                if !within && got.is_some() {
                    let big = q(d) * (Q::one() + inv_pow2(20));
                    assert!(&big * &big >= dist2, "{kind:?} d = {d:e} {pts:?}");
                }
            }
        }
    }
    eprintln!("{exact} decided at t = 0 by the exact test");
    assert!(exact > 0);
}

fn gv(rng: &mut Rng, n: i64, den: f64) -> P3 {
    std::array::from_fn(|_| (rng.below((2 * n + 1) as usize) as i64 - n) as f64 / den)
}

/// Random motions against the reference at sampled times: within `d` at a sample (or at
/// the start) means reported no later; a reported toi has the pair farther than `d` before
/// it (at it and at samples before), and no farther than `D` plus what it can close in
/// `2^-20` at it.
#[test]
fn random_motions_are_consistent_with_the_reference() {
    let mut rng = Rng(0xba4d_0004);
    for kind in [Kind::VertexFace, Kind::EdgeEdge] {
        for lit in [1.0, 1e-30, 1e30] {
            let (mut reported, mut cases) = (0, 0);
            for case in 0..150 {
                let pts: Points = std::array::from_fn(|_| {
                    let a = gv(&mut rng, 6, 2.0);
                    let b: P3 = std::array::from_fn(|k| a[k] + gv(&mut rng, 6, 2.0)[k]);
                    if lit == 1.0 {
                        [a, b]
                    } else {
                        // Not on a grid: random doubles.
                        [
                            a.map(|x| (x + rng.f()) * lit),
                            b.map(|x| (x + rng.f()) * lit),
                        ]
                    }
                });
                let d = [1.0 / 64.0, 1.0 / 8.0, 0.5, 1.5][case % 4] * lit;
                let (got, route) = decide_within(kind, &pts, d);
                assert_ne!(route, Route::Capped, "{kind:?} {d:e} {pts:?}");
                cases += 1;
                reported += usize::from(got.is_some());
                check_random(kind, &pts, d, got);
            }
            eprintln!("{kind:?} scale {lit:e}: {reported} of {cases} reported");
            assert!(reported > 0 && reported < cases);
        }
    }
}

/// The band at the distance the pair has at a sampled time (rounded up to a double): the
/// pair must be reported no later, often at a tangency (when the sample is near the
/// closest approach). Offsets 1e6, and random doubles (not a grid) at scale 1.
#[test]
fn random_motions_at_a_distance_they_reach() {
    let mut rng = Rng(0xba4d_0005);
    for kind in [Kind::VertexFace, Kind::EdgeEdge] {
        for (offset, grid) in [(0.0, true), (1e6, true), (0.0, false)] {
            for _ in 0..150 {
                let pts: Points = std::array::from_fn(|_| {
                    let a = gv(&mut rng, 6, 2.0);
                    let b: P3 = std::array::from_fn(|k| a[k] + gv(&mut rng, 6, 2.0)[k]);
                    let jitter = |x: f64, rng: &mut Rng| if grid { x } else { x + rng.f() };
                    [
                        a.map(|x| jitter(x, &mut rng) + offset),
                        b.map(|x| jitter(x, &mut rng) + offset),
                    ]
                });
                let ts = r(rng.below(17) as i64, 16);
                let dist2 = dist2_at(&pts, split(kind), &ts);
                if dist2.is_zero() {
                    continue;
                }
                let mut d = num_traits::ToPrimitive::to_f64(&dist2)
                    .expect("finite")
                    .sqrt();
                while q(d) * q(d) < dist2 {
                    d = d.next_up();
                }
                let (got, route) = decide_within(kind, &pts, d);
                assert_ne!(route, Route::Capped, "{kind:?} {d:e} {pts:?}");
                let toi = got.unwrap_or_else(|| panic!("missed at {ts}: {d:e} {pts:?}"));
                assert!(q(toi.t) <= ts, "late: {toi:?}, within at {ts} {pts:?}");
                check_random(kind, &pts, d, got);
            }
        }
    }
}

/// A random rotation (Gram-Schmidt on random vectors; rounded: the rotated points are
/// just other doubles, judged exactly by the reference).
fn rotation(rng: &mut Rng) -> [P3; 3] {
    let norm = |v: P3| {
        let n = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
        v.map(|x| x / n)
    };
    let dot = |a: P3, b: P3| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    let a = norm([rng.f(), rng.f(), rng.f()]);
    let b = [rng.f(), rng.f(), rng.f()];
    let b = norm(std::array::from_fn(|k| b[k] - dot(a, b) * a[k]));
    let c = [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ];
    [a, b, c]
}

/// A point or a short edge sliding at a small height `h` (relative to features of size
/// about 4) over a triangle or across a long edge, rotated at random (so nothing rounds
/// exactly), offset by `offset`.
fn thin(rng: &mut Rng, kind: Kind, h: f64, offset: f64) -> Points {
    let m = rotation(rng);
    let rot = |p: P3| -> P3 {
        std::array::from_fn(|k| m[k][0] * p[0] + m[k][1] * p[1] + m[k][2] * p[2] + offset)
    };
    let (x0, x1) = (rng.range(-3.0, 0.0), rng.range(0.5, 3.0));
    let y = rng.range(-1.0, 1.0);
    let canon: Points = match kind {
        Kind::VertexFace => [
            [[x0, y, h], [x1, y + rng.f(), h]],
            still([-1.0, -4.0, 0.0]),
            still([4.0, 0.0, 0.0]),
            still([-1.0, 4.0, 0.0]),
        ],
        Kind::EdgeEdge => {
            let tilt = rng.f() * h;
            [
                [[x0, y - 0.5, h], [x1, y - 0.5, h + tilt]],
                [[x0 + 0.2, y + 0.5, h], [x1 + 0.2, y + 0.5, h]],
                still([-4.0, 0.1, 0.0]),
                still([4.0, -0.1, 0.0]),
            ]
        }
    };
    canon.map(|p| p.map(rot))
}

/// Thin bands, where the rounding of the features' coordinates is about `2^-32` of `d`:
/// at `t = 0` (still) and over the step, with `d` the distance the pair has at a sampled
/// time rounded up (reported, no later) or down (then any answer, consistent). Here the
/// bounds' rounding terms decide: a bound that drops one wrongly excludes a time the pair
/// is within `d`.
#[test]
fn thin_bands_at_a_distance_they_reach() {
    let mut rng = Rng(0xba4d_0006);
    let mut counts = [0usize; 2];
    for kind in [Kind::VertexFace, Kind::EdgeEdge] {
        for h in [1.0 / 256.0, f64::powi(2.0, -16), f64::powi(2.0, -24)] {
            for offset in [0.0, 1e6] {
                for case in 0..60 {
                    let mut pts = thin(&mut rng, kind, h, offset);
                    if case % 3 == 0 {
                        pts = pts.map(|p| [p[0], p[0]]);
                    }
                    let ts = r(rng.below(17) as i64, 16);
                    let dist2 = dist2_at(&pts, split(kind), &ts);
                    let near = num_traits::ToPrimitive::to_f64(&dist2)
                        .expect("finite")
                        .sqrt();
                    let mut up = near;
                    while q(up) * q(up) < dist2 {
                        up = up.next_up();
                    }
                    for d in [up, near.next_down()] {
                        let (got, route) = decide_within(kind, &pts, d);
                        assert_ne!(route, Route::Capped, "{kind:?} {d:e} {pts:?}");
                        counts[usize::from(route == Route::ExactStart)] += 1;
                        if d == up {
                            let toi = got.unwrap_or_else(|| panic!("missed at {ts}: {pts:?}"));
                            assert!(q(toi.t) <= ts, "late: {toi:?}, within at {ts} {pts:?}");
                        }
                        check_random(kind, &pts, d, got);
                    }
                }
            }
        }
    }
    eprintln!(
        "thin bands: {} in floats, {} exact at t = 0",
        counts[0], counts[1]
    );
}

/// The checks of [`random_motions_are_consistent_with_the_reference`].
fn check_random(kind: Kind, pts: &Points, d: f64, got: Option<Toi>) {
    let s = split(kind);
    let d2 = q(d) * q(d);
    for j in 0..=32 {
        let t = r(j, 32);
        if dist2_at(pts, s, &t) <= d2 {
            let toi = got.unwrap_or_else(|| panic!("missed at {t}: {d:e} {pts:?}"));
            assert!(q(toi.t) <= t, "late: {toi:?}, within at {t}: {d:e} {pts:?}");
            break;
        }
    }
    let Some(toi) = got else { return };
    assert_eq!(toi.at_start, dist2_at(pts, s, &Q::zero()) <= d2, "{pts:?}");
    if toi.at_start {
        assert_eq!(toi.t, 0.0);
        return;
    }
    let t = q(toi.t);
    for before in [t.clone(), &t - inv_pow2(30), &t / r(2, 1)] {
        if before >= Q::zero() {
            assert!(
                dist2_at(pts, s, &before) >= d2,
                "late: within at {before} before {toi:?} {d:e} {pts:?}"
            );
        }
    }
    let reach = q(d) * (Q::one() + inv_pow2(20)) + speed_bound(pts, s) * inv_pow2(20);
    assert!(
        dist2_at(pts, s, &t) <= &reach * &reach,
        "early: {toi:?} {d:e} {pts:?}"
    );
}

/// The ground truth's touching pairs come within any band, no later than they touch: the
/// band's toi is at most the zero-distance one, `AT_START` when that one is. Bands from
/// `2^-60` of the scene (below the rounding of its coordinates: answered conservatively,
/// but reported) to the scene's size.
#[test]
fn ground_truth_touching_pairs_are_within_every_band() {
    if !has_truth("ground_truth_touching_pairs_are_within_every_band") {
        return;
    }
    for &(scene, frame, csv_ee) in &SCENES {
        for kind in [Kind::VertexFace, Kind::EdgeEdge] {
            let queries = load(scene, frame, csv_ee, kind);
            let size = scene_size(queries.iter().map(|q| &q.pts));
            for rel in [1.0, 1e-3, f64::powi(2.0, -30), f64::powi(2.0, -60)] {
                let d = rel * size;
                let (mut trues, mut reported, mut capped) = (0, 0, 0);
                for (i, qy) in queries.iter().enumerate() {
                    let (got, route) = decide_within(kind, &qy.pts, d);
                    reported += usize::from(got.is_some());
                    capped += usize::from(route == Route::Capped);
                    if !qy.truth {
                        continue;
                    }
                    trues += 1;
                    let zero = decide(kind, &qy.pts).0.expect("the truth touches");
                    let band = got.unwrap_or_else(|| panic!("{scene} {kind:?} #{i} missed"));
                    assert!(band.t <= zero.t, "{scene} {kind:?} #{i}: {band:?} {zero:?}");
                    assert!(!zero.at_start || band.at_start, "{scene} {kind:?} #{i}");
                }
                eprintln!(
                    "{scene} {kind:?} d = {rel:e} size: {trues} touching, {reported} of {} \
                     reported, {capped} capped",
                    queries.len()
                );
                if rel >= 1e-3 {
                    assert_eq!(capped, 0, "{scene} {kind:?} {rel:e}");
                }
            }
        }
    }
}

/// The largest extent of the points of these queries, over the three axes.
fn scene_size<'a>(pts: impl Iterator<Item = &'a Points>) -> f64 {
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for p in pts.flatten().flatten() {
        for k in 0..3 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    (0..3).map(|k| hi[k] - lo[k]).fold(0.0, f64::max)
}

#[test]
fn the_public_calls_take_start_and_end() {
    let tri = [[0.0, 0.0, 0.0], [4.0, 0.0, 0.0], [0.0, 4.0, 0.0]];
    // Falling toward the middle of the triangle from height 1 to -3: within 1/4 from
    // t = 3/16 on.
    let got =
        vertex_face_within([[1.0, 1.0, 1.0], [1.0, 1.0, -3.0]], [tri, tri], 0.25).expect("within");
    let t_d = 0.1875;
    assert!(
        !got.at_start && got.t <= t_d && got.t >= t_d - 2.0 * inv20(),
        "{got:?}"
    );
    assert_eq!(
        vertex_face_within([[1.0, 1.0, 0.25], [1.0, 1.0, 3.0]], [tri, tri], 0.25),
        Some(Toi {
            t: 0.0,
            at_start: true
        })
    );
    // Edges passing at 1/2 (b at height 1/2 sliding along x over a).
    let a = [[-1.0, 0.0, 0.0], [1.0, 0.0, 0.0]];
    let b0 = [[-3.0, -1.0, 0.5], [-3.0, 1.0, 0.5]];
    let b1 = [[3.0, -1.0, 0.5], [3.0, 1.0, 0.5]];
    assert!(edge_edge_within([a, a], [b0, b1], 0.5).is_some());
    assert_eq!(
        edge_edge_within([a, a], [b0, b1], 0.5 * (1.0 - inv18())),
        None
    );
    // No extent at all, and a band beyond any distance: within at the start.
    let at_start = Some(Toi {
        t: 0.0,
        at_start: true,
    });
    let origin = [[0.0; 3]; 2];
    assert_eq!(
        edge_edge_within([origin, origin], [origin, origin], 1e-300),
        at_start
    );
    assert_eq!(edge_edge_within([a, a], [b0, b1], 1e300), at_start);
    assert_eq!(
        vertex_face_within([[1e-300; 3]; 2], [tri, tri], 1e300),
        at_start
    );
}

/// The band tests' timing over the ground truth's queries at `d = 1e-3` of the scene's
/// size (ignored: `cargo test --release --lib ccd::tests::band -- --ignored --nocapture`),
/// with how each query ended.
#[test]
#[ignore = "timing: run with --ignored --nocapture"]
fn band_tests_per_query() {
    if !has_truth("band_tests_per_query") {
        return;
    }
    println!(
        "{:<18} {:>3} {:>7} {:>7} | {:>9} {:>9} | {:>7} {:>7} {:>6} {:>6}",
        "scene",
        "",
        "queries",
        "within",
        "ns/query",
        "(wall)",
        "boxes",
        "float",
        "exact0",
        "capped"
    );
    for &(scene, frame, csv_ee) in &SCENES {
        for kind in [Kind::VertexFace, Kind::EdgeEdge] {
            let qs = load(scene, frame, csv_ee, kind);
            let d = 1e-3 * scene_size(qs.iter().map(|q| &q.pts));
            let mut tally = [0usize; 4];
            let mut within = 0;
            for qy in &qs {
                let (got, route) = decide_within(kind, &qy.pts, d);
                within += usize::from(got.is_some());
                tally[route as usize] += 1;
            }
            let (all, wall) = best_of_3(|| {
                for qy in &qs {
                    std::hint::black_box(decide_within(kind, std::hint::black_box(&qy.pts), d));
                }
            });
            let per = |ns: f64| ns / qs.len().max(1) as f64;
            println!(
                "{:<18} {:>3} {:>7} {:>7} | {:>9.0} {:>9.0} | {:>7} {:>7} {:>6} {:>6}",
                scene,
                if kind == Kind::VertexFace { "vf" } else { "ee" },
                qs.len(),
                within,
                per(all),
                per(wall),
                tally[0],
                tally[1],
                tally[2],
                tally[3],
            );
        }
    }
}
