//! Adversarial motions whose answer is known by construction, judged by the reference.
//!
//! * Translating primitives ([`reference::translated_first_meeting`]: exact answer and
//!   first meeting time): general, coplanar for the whole step (in a coordinate plane and
//!   in a tilted one), parallel and collinear edges, a touch at one instant (a vertex or an
//!   edge's end grazing a corner or an edge), a vertex sliding along an edge, zero motion,
//!   degenerate triangles (segments, points) and edges (points), near misses by 1/64.
//! * Deforming primitives that can only meet at one chosen time `t*` (a triangle or an
//!   edge deforming within a plane, the other primitive crossing that plane once, flat),
//!   at a dyadic `t*` or not, the triangle or edge sometimes degenerate at `t*` (a double
//!   root of the cubic): the truth is the exact static test at `t*`, and the time of impact
//!   is `t*`.
//! * Invariances that hold exactly: scaling by a power of two, offsets (1e6) that keep the
//!   doubles exact, reordering the triangle's or the edges' points, swapping the edges.
//!
//! Every family runs at the scales `2^-100` (about 1e-30), 1 and `2^100` (about 1e30) and at
//! the offset 1e6, every answer goes through [`check_toi`], and the tallies are printed.
//! Random deforming motions run at the literal scales 1e-30 and 1e30, and translating ones
//! at `2^900` and `2^-1000`, beyond the filter's range.

use super::super::predicate::Kind;
use super::super::{decide, edge_edge, vertex_face, Points, Stage, Toi};
use super::reference::{self, dist2_at, inv_pow2, q, Q};
use super::{check_toi, split};
use crate::geom::test_rng::Rng;
use crate::geom::P3;
use num_traits::Zero;

/// A scale and an offset applied to a case built on a coarse grid (both keep it exact).
const FRAMES: [(i32, f64); 4] = [(0, 0.0), (-100, 0.0), (100, 0.0), (0, 1e6)];

/// `x 2^s + offset`, checked exact.
fn place(x: f64, (s, offset): (i32, f64)) -> f64 {
    let y = x * f64::powi(2.0, s) + offset;
    assert_eq!(
        (y - offset) * f64::powi(2.0, -s),
        x,
        "{x} not exact in frame"
    );
    y
}

fn place_all(pts: &Points, frame: (i32, f64)) -> Points {
    pts.map(|p| p.map(|x| x.map(|c| place(c, frame))))
}

/// A grid value: an integer in `[-n, n]` over `den`.
fn g(rng: &mut Rng, n: i64, den: f64) -> f64 {
    (rng.below((2 * n + 1) as usize) as i64 - n) as f64 / den
}

fn gv(rng: &mut Rng, n: i64, den: f64) -> P3 {
    [g(rng, n, den), g(rng, n, den), g(rng, n, den)]
}

fn add(a: P3, b: P3) -> P3 {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}

fn scale(a: P3, s: f64) -> P3 {
    a.map(|x| x * s)
}

/// Tallies of a family.
#[derive(Default, Debug)]
struct Tally {
    cases: usize,
    meet: usize,
    at_start: usize,
    exact: usize,
}

impl Tally {
    fn add(&mut self, r: Option<Toi>, stage: Stage) {
        self.cases += 1;
        self.meet += usize::from(r.is_some());
        self.at_start += usize::from(r.is_some_and(|t| t.at_start));
        self.exact += usize::from(stage == Stage::Exact);
    }
}

/// The flavors of translating cases.
const FLAVORS: [&str; 9] = [
    "general",
    "coplanar",
    "tilted-coplanar",
    "parallel",
    "graze",
    "slide",
    "static",
    "degenerate",
    "near-miss",
];

/// A translating case of a flavor: the start points on a grid, one velocity per primitive.
fn translating(rng: &mut Rng, kind: Kind, flavor: &str) -> Points {
    let s = split(kind);
    let flat = |p: P3| [p[0], p[1], 0.0];
    let tilt = |p: P3| [p[0], p[1], -p[0] - p[1]];
    let mut start: [P3; 4] = std::array::from_fn(|_| gv(rng, 4, 1.0));
    let mut vel = [gv(rng, 8, 1.0), gv(rng, 8, 1.0)];
    match flavor {
        "coplanar" => {
            start = start.map(flat);
            vel = vel.map(flat);
        }
        "tilted-coplanar" => {
            start = start.map(tilt);
            vel = vel.map(tilt);
        }
        "parallel" => {
            // The second primitive's points along the first's direction (edges: parallel;
            // a triangle: a segment parallel to the vertex's... the vertex's motion).
            let d = gv(rng, 2, 1.0);
            let k = [1.0, -1.0, 2.0, 0.5][rng.below(4)];
            if kind == Kind::EdgeEdge {
                start[1] = add(start[0], d);
                start[3] = add(start[2], scale(d, k));
            } else {
                start[2] = add(start[1], d);
                start[3] = add(start[1], scale(d, k));
                vel[0] = add(vel[1], scale(d, [1.0, -1.0][rng.below(2)]));
            }
            if rng.below(2) == 0 {
                // In one plane too.
                start = start.map(flat);
                vel = vel.map(flat);
            }
            if rng.below(2) == 0 {
                aim(rng, &mut start, &vel, s);
            }
        }
        "graze" => {
            aim(rng, &mut start, &vel, s);
            if kind == Kind::EdgeEdge && rng.below(2) == 0 {
                start[1] = add(start[0], gv(rng, 3, 1.0));
            }
        }
        "slide" => {
            // Along a line of the other primitive, in it or beside it.
            let (a, b) = (start[s], start[s + 1]);
            let d = add(b, scale(a, -1.0));
            start[0] = add(a, scale(d, g(rng, 4, 2.0)));
            if kind == Kind::EdgeEdge {
                start[1] = add(a, scale(d, g(rng, 4, 2.0)));
            }
            vel[0] = add(vel[1], scale(d, g(rng, 4, 1.0)));
            if rng.below(3) == 0 {
                // A hair beside the line.
                start[0][rng.below(3)] += 1.0 / 64.0;
            }
        }
        "static" => {
            vel[0] = if rng.below(2) == 0 { [0.0; 3] } else { vel[1] };
            vel[1] = if rng.below(2) == 0 { vel[0] } else { [0.0; 3] };
            // Close enough to meet often; or on an edge of the other.
            start = start.map(|p| scale(p, 0.25));
            if rng.below(2) == 0 {
                start[0] = scale(add(start[s], start[s + 1]), 0.5);
            }
        }
        "degenerate" => {
            // A segment or a point for a triangle, a point for an edge.
            if kind == Kind::VertexFace {
                let d = gv(rng, 2, 1.0);
                start[2] = add(start[1], scale(d, g(rng, 2, 1.0)));
                start[3] = if rng.below(3) == 0 {
                    start[1]
                } else {
                    add(start[1], scale(d, g(rng, 2, 1.0)))
                };
            } else {
                start[1] = start[0];
                if rng.below(2) == 0 {
                    start[3] = start[2];
                }
            }
            start = start.map(|p| scale(p, 0.5));
            if rng.below(2) == 0 {
                aim(rng, &mut start, &vel, s);
            }
        }
        "near-miss" => {
            // A point of the first passes 1/64 outside a face or an edge of the second at
            // t* = 1/2 (or just inside).
            let rel = add(vel[0], scale(vel[1], -1.0));
            let w = if rng.below(2) == 0 { -1.0 } else { 1.0 } / 64.0;
            let (i, j) = (s + rng.below(4 - s), s + rng.below(4 - s));
            let base = scale(add(start[i], start[j]), 0.5);
            let centre = scale(add(start[s], start[s + 1]), 0.5);
            // Past the edge midpoint away from the centre by w of the way.
            let out = add(base, scale(add(base, scale(centre, -1.0)), -w * 4.0));
            start[0] = add(out, scale(rel, -0.5));
            if kind == Kind::EdgeEdge {
                start[1] = add(start[0], gv(rng, 3, 1.0));
            }
        }
        _ => {}
    }
    std::array::from_fn(|i| {
        let v = if i < s { vel[0] } else { vel[1] };
        [start[i], add(start[i], v)]
    })
}

/// Starts point 0 where, at `t* = k/8`, it touches a corner of the second primitive or the
/// midpoint of two.
fn aim(rng: &mut Rng, start: &mut [P3; 4], vel: &[P3; 2], s: usize) {
    let tstar = (1 + rng.below(7)) as f64 / 8.0;
    let rel = add(vel[0], scale(vel[1], -1.0));
    let (i, j) = (s + rng.below(4 - s), s + rng.below(4 - s));
    let target = scale(add(start[i], start[j]), 0.5);
    // start[0] + t* vel0 = target + t* vel1.
    start[0] = add(target, scale(rel, -tstar));
}

/// A translating case against the reference's exact first meeting time.
fn judge_translating(kind: Kind, pts: &Points, tally: &mut Tally) {
    let (got, stage) = decide(kind, pts);
    tally.add(got, stage);
    let truth = reference::translated_first_meeting(pts, split(kind), 26);
    match (got, &truth) {
        (None, None) => {}
        (Some(toi), Some((lo, hi))) => {
            let t = q(toi.t);
            assert!(
                t <= *hi,
                "late: {toi:?}, first meeting in [{lo}, {hi}] {pts:?}"
            );
            assert!(
                t >= lo - inv_pow2(20),
                "early: {toi:?}, first meeting in [{lo}, {hi}] {pts:?}"
            );
            check_toi(kind, pts, toi, Some(hi));
        }
        _ => panic!("{kind:?}: got {got:?}, the reference says {truth:?} for {pts:?}"),
    }
}

#[test]
fn translating_primitives_against_the_reference() {
    let mut rng = Rng(0x5eed_cc0d);
    for kind in [Kind::VertexFace, Kind::EdgeEdge] {
        for flavor in FLAVORS {
            let mut tally = Tally::default();
            for _ in 0..30 {
                let pts = translating(&mut rng, kind, flavor);
                for frame in FRAMES {
                    judge_translating(kind, &place_all(&pts, frame), &mut tally);
                }
            }
            eprintln!("{kind:?} {flavor}: {tally:?}");
            assert!(tally.meet > 0, "{flavor}: never meets: {tally:?}");
        }
    }
}

/// A deforming case that can meet only at `t* = num / den`: the second primitive (a
/// triangle, or edge b) deforms within a plane; the first (the vertex, or edge a, kept
/// parallel to the plane) crosses it once, at `t*`. Where the first is at `t*` relative to
/// the second is chosen: a weighted point of its corners (weights on a grid of 1/8, some
/// zero or negative: inside, on an edge or a corner, or outside).
fn crossing_once(rng: &mut Rng, kind: Kind, tilted: bool, num: u32, den: u32) -> Points {
    let s = split(kind);
    let (num, den) = (num as f64, den as f64);
    // In-plane coordinates (u, v) and the height h; the plane maps (u, v, h) to space.
    let to_space = |u: f64, v: f64, h: f64| -> P3 {
        if tilted {
            // The plane x + y + z = 0, h along (0, 0, 1).
            [u, v, -u - v + h]
        } else {
            [u, v, h]
        }
    };
    // The second primitive's corners at t* (in the plane), and every point's velocity.
    let mut corners: Vec<[f64; 2]> = (s..4).map(|_| [g(rng, 8, 2.0), g(rng, 8, 2.0)]).collect();
    if rng.below(4) == 0 {
        // Degenerate at t* (the cubic then has a double root there): the triangle's corners
        // on one line, or edge b a point.
        let last = corners.len() - 1;
        let k = g(rng, 2, 2.0);
        corners[last] =
            std::array::from_fn(|c| corners[0][c] + k * (corners[last - 1][c] - corners[0][c]));
        if kind == Kind::EdgeEdge {
            corners[last] = corners[0];
        }
    }
    let mut at_t: Vec<[f64; 2]> = Vec::new();
    let deg = rng.below(4) == 0;
    for _ in 0..s {
        if kind == Kind::EdgeEdge && rng.below(2) == 0 {
            // Anywhere in the plane.
            at_t.push([g(rng, 8, 2.0), g(rng, 8, 2.0)]);
            continue;
        }
        // Weights over the second's corners, on a grid of 1/8, summing to 1.
        let n = corners.len();
        let mut w: Vec<f64> = (0..n - 1).map(|_| g(rng, 10, 8.0)).collect();
        if rng.below(3) == 0 {
            // Exactly on the boundary: one weight 0 (an edge), or two (a corner).
            let k = rng.below(n - 1);
            w[k] = 0.0;
        }
        let last = 1.0 - w.iter().sum::<f64>();
        w.push(last);
        let p = (0..2).map(|k| (0..n).map(|m| w[m] * corners[m][k]).sum::<f64>());
        let p: Vec<f64> = p.collect();
        at_t.push([p[0], p[1]]);
    }
    if kind == Kind::EdgeEdge && deg {
        at_t[1] = at_t[0];
    }
    // Heights: the first primitive at h(t) = g (t - t*), flat; the second at 0.
    let slope = [1.0, -2.0, 4.0, -0.5][rng.below(4)];
    let mut pts = [[[0.0; 3]; 2]; 4];
    for i in 0..4 {
        let [u, v] = if i < s { at_t[i] } else { corners[i - s] };
        // Velocities den w: the start u - t* den w = u - num w is exact.
        let w = [g(rng, 8, 1.0), g(rng, 8, 1.0)];
        let vel = [den * w[0], den * w[1]];
        let (u0, v0) = (u - num * w[0], v - num * w[1]);
        let (h0, h1) = if i < s {
            (-slope * num, slope * (den - num))
        } else {
            (0.0, 0.0)
        };
        pts[i] = [to_space(u0, v0, h0), to_space(u0 + vel[0], v0 + vel[1], h1)];
    }
    pts
}

#[test]
fn deforming_primitives_meet_only_when_built_to() {
    let mut rng = Rng(0xdef0_4a11);
    for kind in [Kind::VertexFace, Kind::EdgeEdge] {
        for tilted in [false, true] {
            let mut tally = Tally::default();
            for case in 0..150 {
                // t* dyadic (a point where the filter splits) or not.
                let den = [16, 13][case % 2];
                let num = 1 + (case / 2 % (den - 1)) as u32;
                let built = crossing_once(&mut rng, kind, tilted, num, den as u32);
                let tstar = Q::new((num as i64).into(), (den as i64).into());
                for frame in FRAMES {
                    let pts = place_all(&built, frame);
                    let truth = dist2_at(&pts, split(kind), &tstar).is_zero();
                    let (got, stage) = decide(kind, &pts);
                    tally.add(got, stage);
                    assert_eq!(got.is_some(), truth, "{kind:?}: {got:?} {pts:?}");
                    if let Some(toi) = got {
                        let t = q(toi.t);
                        assert!(t <= tstar, "late: {toi:?} {pts:?}");
                        assert!(t >= &tstar - inv_pow2(20), "early: {toi:?} {pts:?}");
                        check_toi(kind, &pts, toi, Some(&tstar));
                    }
                }
            }
            eprintln!("{kind:?} tilted {tilted}: {tally:?}");
            assert!(tally.meet > 0 && tally.meet < tally.cases, "{tally:?}");
        }
    }
}

/// The answers of every reordering and exact rescaling of a case agree.
fn invariant(kind: Kind, pts: &Points) {
    let base = decide(kind, pts).0;
    let mut variants: Vec<Points> = Vec::new();
    for frame in FRAMES {
        variants.push(place_all(pts, frame));
    }
    match kind {
        Kind::VertexFace => {
            for perm in [[0, 2, 3, 1], [0, 3, 2, 1], [0, 1, 3, 2]] {
                variants.push(perm.map(|i| pts[i]));
            }
        }
        Kind::EdgeEdge => {
            for perm in [[1, 0, 2, 3], [0, 1, 3, 2], [2, 3, 0, 1], [3, 2, 1, 0]] {
                variants.push(perm.map(|i| pts[i]));
            }
        }
    }
    for v in &variants {
        assert_eq!(decide(kind, v).0, base, "{pts:?} vs {v:?}");
    }
}

#[test]
fn answers_are_invariant_under_exact_changes() {
    let mut rng = Rng(0x1a7e_0005);
    for kind in [Kind::VertexFace, Kind::EdgeEdge] {
        for flavor in FLAVORS {
            for _ in 0..20 {
                invariant(kind, &translating(&mut rng, kind, flavor));
            }
        }
        for tilted in [false, true] {
            for num in 1..16 {
                invariant(kind, &crossing_once(&mut rng, kind, tilted, num, 16));
                invariant(
                    kind,
                    &crossing_once(&mut rng, kind, tilted, num % 12 + 1, 13),
                );
            }
        }
    }
}

/// Deforming motions with no construction (the coplanar ones deforming within a plane),
/// at the literal scales 1e-30 and 1e30: every answer's time checked by the reference, and
/// every sampled time at which the reference sees a meeting is no earlier than the answer.
#[test]
fn random_deforming_motions_are_consistent() {
    let mut rng = Rng(0xc0ff_ee11);
    for kind in [Kind::VertexFace, Kind::EdgeEdge] {
        for (coplanar, lit) in [(false, 1.0), (true, 1.0), (false, 1e-30), (true, 1e30)] {
            let mut tally = Tally::default();
            for _ in 0..120 {
                let pts: Points = std::array::from_fn(|_| {
                    let mut a = gv(&mut rng, 6, 2.0);
                    let mut b = add(a, gv(&mut rng, 6, 2.0));
                    if coplanar {
                        a[2] = 0.0;
                        b[2] = 0.0;
                    }
                    [a.map(|x| x * lit), b.map(|x| x * lit)]
                });
                let (got, stage) = decide(kind, &pts);
                tally.add(got, stage);
                let s = split(kind);
                for k in 0..=16 {
                    let t = Q::new(k.into(), 16.into());
                    if dist2_at(&pts, s, &t).is_zero() {
                        let toi = got.unwrap_or_else(|| panic!("missed at {t}: {pts:?}"));
                        assert!(q(toi.t) <= t, "late {toi:?}: they meet at {t} {pts:?}");
                        break;
                    }
                }
                if let Some(toi) = got {
                    check_toi(kind, &pts, toi, None);
                }
            }
            eprintln!("{kind:?} coplanar {coplanar} scale {lit}: {tally:?}");
        }
    }
}

#[test]
fn the_public_calls_take_start_and_end() {
    // A vertex falling through the middle of a unit triangle at t = 1/4.
    let tri = [[0.0, 0.0, 0.0], [4.0, 0.0, 0.0], [0.0, 4.0, 0.0]];
    let got = vertex_face([[1.0, 1.0, 1.0], [1.0, 1.0, -3.0]], [tri, tri]).expect("meets");
    assert!(!got.at_start && got.t <= 0.25 && got.t >= 0.25 - 1.0 / (1 << 20) as f64);
    assert_eq!(
        vertex_face([[1.0, 1.0, 0.0], [1.0, 1.0, 0.0]], [tri, tri]),
        Some(Toi {
            t: 0.0,
            at_start: true
        })
    );
    // Edges crossing at t = 1/2, then the same edges apart.
    let a = [[-1.0, 0.0, 0.0], [1.0, 0.0, 0.0]];
    let b0 = [[0.0, -1.0, 1.0], [0.0, 1.0, 1.0]];
    let b1 = [[0.0, -1.0, -1.0], [0.0, 1.0, -1.0]];
    let got = edge_edge([a, a], [b0, b1]).expect("meets");
    assert!(got.t <= 0.5 && got.t >= 0.5 - 1.0 / (1 << 20) as f64);
    let b2 = [[4.0, -1.0, -1.0], [4.0, 1.0, -1.0]];
    assert_eq!(edge_edge([a, a], [b0, b2]), None);
}

/// Scales far beyond the filter's range (2^900: past its overflow guard; 2^-1000: its
/// products underflow) leave the answer to the exact test, on integers of thousands of
/// bits: the same answers as at scale 1, the times within `2^-20` of each other.
#[test]
fn extreme_scales_give_the_same_answers() {
    let mut rng = Rng(0xe7e7_0001);
    for kind in [Kind::VertexFace, Kind::EdgeEdge] {
        let mut met = 0;
        for flavor in FLAVORS {
            for _ in 0..4 {
                let pts = translating(&mut rng, kind, flavor);
                let base = decide(kind, &pts).0;
                met += usize::from(base.is_some());
                for s in [900, -1000] {
                    let scaled = place_all(&pts, (s, 0.0));
                    let got = decide(kind, &scaled).0;
                    assert_eq!(got.is_some(), base.is_some(), "2^{s}: {scaled:?}");
                    if let (Some(a), Some(b)) = (got, base) {
                        assert_eq!(a.at_start, b.at_start, "2^{s}: {scaled:?}");
                        assert!((a.t - b.t).abs() <= 1.0 / (1 << 20) as f64, "2^{s}");
                    }
                }
            }
        }
        assert!(met > 0);
    }
}
