//! Issue 6, part 1: the hard cases, each with the exact answer from the independent oracle
//! (tests/common/oracle.rs).
//!
//! Every case is one reference polygon against one other polygon, written in "base" units
//! (coordinates that are multiples of 1/8 in [-1, 3]) and placed by a [`Frame`]: as written,
//! translated 1e3 and 1e5 from the origin, scaled by 1e-4, 2^-13 and 1e4, and scaled by 1e4
//! at 1e5. Every frame but the 1e-4 one maps base coordinates to f32 values exactly, so a
//! case that touches in base units touches there too (the test checks the oracle agrees
//! with the intended answer); at 1e-4 the coordinates are rounded to f32 and the oracle
//! alone says what the answer is.
//!
//! Near misses move the other polygon away from the touching position by 1e-3, 1e-5 or
//! 1e-7 of the case's size along one axis, rounded to f32 at the case's coordinates but at
//! least one f32 step (1e-7 of a unit-sized object is below the f32 spacing 1e3 or 1e5 from
//! the origin: there the gap is one ulp, 2^-14 or 2^-7). Slivers have an aspect ratio of
//! about 1e6 (width 2^-20 of the size, also at least one ulp).
//!
//! Checks, on every backend of `common::backends::factories()` (and, in
//! `every_case_in_every_frame_on_the_gl_backends`, on the GL backends of `gl_factories()`):
//! - epsilon = 0: exactly the oracle's set of intersecting polygon pairs;
//! - epsilon = e > 0: a superset of that set, and every extra pair within e/2 of each
//!   other (f64 distance from the oracle's closest-point code), plus a rounding slack of
//!   `1e-9 * (e/2 + case size) + 8 * f64::EPSILON * (largest coordinate)`: far below f32
//!   resolution, it only absorbs the f64 rounding of the distance code and the clipper.
//!
//! The cases also run all together as two many-polygon meshes (leaf size 2), so the box
//! steps see them side by side.

mod common;

use common::backends::{factories, gl_factories, Factory};
use common::{brute_force_exact, polygon_distance, TestMesh};

/// Where and how big a case is.
#[derive(Clone, Copy, Debug)]
struct Frame {
    name: &'static str,
    /// Added to x, subtracted from y, half of it added to z.
    offset: f64,
    /// Model units per base unit.
    scale: f64,
    /// Base coordinates (multiples of 1/8 in [-1, 3], plus up to 400 along x in the
    /// combined test) land on f32 values exactly.
    exact: bool,
}

const FRAMES: &[Frame] = &[
    Frame {
        name: "unit",
        offset: 0.0,
        scale: 1.0,
        exact: true,
    },
    Frame {
        name: "at 1e3",
        offset: 1e3,
        scale: 1.0,
        exact: true,
    },
    Frame {
        name: "at 1e5",
        offset: 1e5,
        scale: 1.0,
        exact: true,
    },
    Frame {
        name: "scaled 1e-4",
        offset: 0.0,
        scale: 1e-4,
        exact: false,
    },
    Frame {
        name: "scaled 2^-13",
        offset: 0.0,
        scale: 1.0 / 8192.0,
        exact: true,
    },
    Frame {
        name: "scaled 1e4",
        offset: 0.0,
        scale: 1e4,
        exact: true,
    },
    Frame {
        name: "scaled 1e4 at 1e5",
        offset: 1e5,
        scale: 1e4,
        exact: true,
    },
];

impl Frame {
    fn place(&self, b: [f64; 3]) -> [f32; 3] {
        let o = [self.offset, -self.offset, self.offset / 2.0];
        let p = [0, 1, 2].map(|k| (o[k] + self.scale * b[k]) as f32);
        if self.exact {
            for k in 0..3 {
                assert_eq!(
                    f64::from(p[k]),
                    o[k] + self.scale * b[k],
                    "{}: base {b:?} is not exact",
                    self.name
                );
            }
        }
        p
    }

    /// `c` moved by `rel` of the case size (signed), rounded, but by at least one f32 step.
    fn nudge(&self, c: f32, rel: f64) -> f32 {
        let moved = (f64::from(c) + rel * self.scale) as f32;
        if moved != c {
            moved
        } else if rel > 0.0 {
            next_up(c)
        } else {
            next_down(c)
        }
    }
}

fn next_up(x: f32) -> f32 {
    if x == 0.0 {
        f32::from_bits(1)
    } else if x > 0.0 {
        f32::from_bits(x.to_bits() + 1)
    } else {
        f32::from_bits(x.to_bits() - 1)
    }
}

fn next_down(x: f32) -> f32 {
    -next_up(-x)
}

/// A vertex in base units, optionally nudged along an axis by a fraction of the size
/// (how slivers get their width).
#[derive(Clone, Copy, Debug)]
struct V {
    p: [f64; 3],
    nudge: Option<(usize, f64)>,
}

fn v(x: f64, y: f64, z: f64) -> V {
    V {
        p: [x, y, z],
        nudge: None,
    }
}

/// Sliver width: 2^-20 of the size (aspect ratio about 1e6 for a polygon 2 long).
const SLIVER: f64 = 1.0 / 1048576.0;

fn vn(x: f64, y: f64, z: f64, axis: usize, rel: f64) -> V {
    V {
        p: [x, y, z],
        nudge: Some((axis, rel)),
    }
}

/// One reference polygon against one other polygon. `away` is the axis and direction
/// (+1 / -1) that separates them when the other polygon moves along it (None: no near-miss
/// variant). `meets` is the answer in base units.
#[derive(Clone, Debug)]
struct Case {
    name: &'static str,
    r: Vec<V>,
    o: Vec<V>,
    meets: bool,
    away: Option<(usize, f64)>,
}

const X: usize = 0;
const Y: usize = 1;
const Z: usize = 2;

fn tri(a: V, b: V, c: V) -> Vec<V> {
    vec![a, b, c]
}

fn pt(x: f64, y: f64, z: f64) -> Vec<V> {
    vec![v(x, y, z); 3]
}

fn case(name: &'static str, r: Vec<V>, o: Vec<V>, meets: bool, away: Option<(usize, f64)>) -> Case {
    Case {
        name,
        r,
        o,
        meets,
        away,
    }
}

fn cases() -> Vec<Case> {
    // The reference triangle most cases use: in z = 0, legs 2 along x and y.
    let r0 = || tri(v(0., 0., 0.), v(2., 0., 0.), v(0., 2., 0.));
    // A slanted one in the plane z = x + y.
    let r1 = || tri(v(0., 0., 0.), v(2., 0., 2.), v(0., 2., 2.));
    // A non-planar quad: (v0, v1, v2) lies in z = y / 2, (v0, v2, v3) in z = x / 2.
    let q0 = || vec![v(0., 0., 0.), v(2., 0., 0.), v(2., 2., 1.), v(0., 2., 0.)];
    let w = SLIVER;
    vec![
        // Coplanar.
        case(
            "coplanar overlapping",
            r0(),
            tri(v(0.5, 0.5, 0.), v(3., 0.5, 0.), v(0.5, 3., 0.)),
            true,
            None,
        ),
        case(
            "coplanar contained",
            r0(),
            tri(v(0.25, 0.25, 0.), v(0.5, 0.25, 0.), v(0.25, 0.5, 0.)),
            true,
            Some((Z, 1.)),
        ),
        case("coplanar duplicate", r0(), r0(), true, Some((Z, -1.))),
        case(
            "coplanar touching at a vertex",
            r0(),
            tri(v(2., 0., 0.), v(3., -1., 0.), v(3., 1., 0.)),
            true,
            Some((X, 1.)),
        ),
        case(
            "coplanar sharing an edge",
            r0(),
            tri(v(0., 0., 0.), v(2., 0., 0.), v(1., -1., 0.)),
            true,
            Some((Y, -1.)),
        ),
        case(
            "coplanar vertex on an edge",
            r0(),
            tri(v(1., 0., 0.), v(0., -1., 0.), v(2., -1., 0.)),
            true,
            Some((Y, -1.)),
        ),
        case(
            "coplanar along the hypotenuse",
            r0(),
            tri(v(0.5, 1.5, 0.), v(1.5, 0.5, 0.), v(2., 2., 0.)),
            true,
            Some((X, 1.)),
        ),
        // Touching across planes.
        case(
            "sharing an edge, planes apart",
            r0(),
            tri(v(0., 0., 0.), v(2., 0., 0.), v(1., -1., 1.)),
            true,
            Some((Y, -1.)),
        ),
        case(
            "touching at a vertex only",
            r0(),
            tri(v(2., 0., 0.), v(3., -1., 1.), v(3., 1., 1.)),
            true,
            Some((X, 1.)),
        ),
        case(
            "vertex on the face",
            r0(),
            tri(v(0.5, 0.5, 0.), v(1., 0.5, 1.), v(0.5, 1., 1.)),
            true,
            Some((Z, 1.)),
        ),
        case(
            "vertex on an edge from above",
            r0(),
            tri(v(1., 0., 0.), v(1., 0.5, 1.), v(1.5, 0.5, 1.)),
            true,
            Some((Z, 1.)),
        ),
        case(
            "skew edges crossing at a point",
            r0(),
            tri(v(1., -1., -1.), v(1., 1., 1.), v(1., -1., 1.)),
            true,
            Some((Y, -1.)),
        ),
        case(
            "edge lying on the face",
            r0(),
            tri(v(0.25, 0.25, 0.), v(1., 0.25, 0.), v(0.5, 0.25, 1.)),
            true,
            Some((Z, 1.)),
        ),
        case(
            "piercing",
            r0(),
            tri(v(0.5, 0.25, -1.), v(0.5, 0.75, 1.), v(0.75, 0.5, 1.)),
            true,
            None,
        ),
        case(
            "crossing the plane outside",
            r0(),
            tri(v(1.5, 1.5, -1.), v(1.5, 1.5, 1.), v(2., 1.5, 1.)),
            false,
            None,
        ),
        case(
            "vertex on a slanted face",
            r1(),
            tri(v(0.5, 0.25, 0.75), v(0.5, 0.25, 2.), v(1., 0.25, 2.)),
            true,
            Some((Z, 1.)),
        ),
        case(
            "slanted faces sharing an edge",
            r1(),
            tri(v(0., 0., 0.), v(2., 0., 2.), v(1., -1., 0.)),
            true,
            Some((Y, -1.)),
        ),
        // Slivers (aspect about 1e6).
        case(
            "sliver piercing the face",
            r0(),
            tri(v(0.5, 0.5, -1.), v(0.5, 0.5, 1.), vn(0.5, 0.5, 1., X, w)),
            true,
            None,
        ),
        case(
            "coplanar sliver touching an edge with its tip",
            r0(),
            tri(v(1., 0., 0.), v(1., -2., 0.), vn(1., -2., 0., X, w)),
            true,
            Some((Y, -1.)),
        ),
        case(
            "sliver lying on the face",
            r0(),
            tri(v(0.25, 0.25, 0.), v(1.5, 0.25, 0.), vn(1.5, 0.25, 0., Y, w)),
            true,
            Some((Z, 1.)),
        ),
        case(
            "sliver reference crossed by a face",
            tri(v(0., 0., 0.), v(2., 0., 0.), vn(2., 0., 0., Y, w)),
            tri(v(1., -1., -1.), v(1., 1., -1.), v(1., 0., 1.)),
            true,
            None,
        ),
        case(
            "sliver reference touched at its thin end",
            tri(v(0., 0., 0.), v(2., 0., 0.), vn(2., 0., 0., Y, w)),
            tri(v(2., -1., -1.), v(2., 1., -1.), v(2., 0., 1.)),
            true,
            Some((X, 1.)),
        ),
        // Zero-area polygons (repeated or collinear vertices).
        case(
            "point on the face",
            r0(),
            pt(0.5, 0.5, 0.),
            true,
            Some((Z, 1.)),
        ),
        case(
            "point on an edge",
            r0(),
            pt(1., 0., 0.),
            true,
            Some((Y, -1.)),
        ),
        case(
            "point on a vertex",
            r0(),
            pt(2., 0., 0.),
            true,
            Some((X, 1.)),
        ),
        case(
            "point on a slanted face",
            r1(),
            pt(0.5, 0.25, 0.75),
            true,
            Some((Z, 1.)),
        ),
        case(
            "segment (repeated vertex) piercing",
            r0(),
            tri(v(0.5, 0.5, -1.), v(0.5, 0.5, 1.), v(0.5, 0.5, 1.)),
            true,
            None,
        ),
        case(
            "segment (collinear vertices) piercing",
            r0(),
            tri(v(0.5, 0.5, -1.), v(0.5, 0.5, 1.), v(0.5, 0.5, 0.5)),
            true,
            None,
        ),
        case(
            "segment ending on the face",
            r0(),
            tri(v(0.5, 0.5, 0.), v(0.5, 0.5, 1.), v(0.5, 0.5, 1.)),
            true,
            Some((Z, 1.)),
        ),
        case(
            "coplanar segment crossing an edge",
            r0(),
            tri(v(-0.5, 0.5, 0.), v(0.5, 0.5, 0.), v(0., 0.5, 0.)),
            true,
            Some((Z, 1.)),
        ),
        case(
            "coplanar segment ending on an edge",
            r0(),
            tri(v(1., 0., 0.), v(1., -1., 0.), v(1., -1., 0.)),
            true,
            Some((Y, -1.)),
        ),
        case(
            "point reference on a face",
            pt(0.5, 0.5, 0.),
            r0(),
            true,
            Some((Z, -1.)),
        ),
        case(
            "segment reference touched by a vertex",
            tri(v(0.5, 0.5, -1.), v(0.5, 0.5, 1.), v(0.5, 0.5, 1.)),
            tri(v(0.5, 0.5, 0.), v(1.5, 0.5, 0.), v(0.5, 1.5, 0.)),
            true,
            Some((X, 1.)),
        ),
        case(
            "crossing segments",
            tri(v(0., 0., 0.), v(2., 0., 0.), v(2., 0., 0.)),
            tri(v(1., -1., 0.), v(1., 1., 0.), v(1., 1., 0.)),
            true,
            Some((Z, 1.)),
        ),
        case(
            "collinear segments end to end",
            tri(v(0., 0., 0.), v(2., 0., 0.), v(1., 0., 0.)),
            tri(v(2., 0., 0.), v(3., 0., 0.), v(3., 0., 0.)),
            true,
            Some((X, 1.)),
        ),
        case(
            "coincident points",
            pt(1., 1., 1.),
            pt(1., 1., 1.),
            true,
            Some((X, 1.)),
        ),
        // Non-planar quads: the union of (v0, v1, v2) and (v0, v2, v3).
        case(
            "point on a non-planar quad's first triangle",
            q0(),
            pt(1.5, 0.5, 0.25),
            true,
            Some((Z, 1.)),
        ),
        case(
            "point on the other diagonal's surface only",
            q0(),
            pt(0.25, 1.5, 0.),
            false,
            None,
        ),
        case(
            "point on a non-planar quad's fold",
            q0(),
            pt(1., 1., 0.5),
            true,
            Some((Z, 1.)),
        ),
        case(
            "non-planar quads crossing",
            q0(),
            vec![
                v(1., -1., -1.),
                v(1., 3., -1.),
                v(1.25, 3., 2.),
                v(1., -1., 2.),
            ],
            true,
            None,
        ),
        case(
            "non-planar quads sharing an edge",
            q0(),
            vec![v(2., 0., 0.), v(3., 0., 0.), v(3., 2., 1.), v(2., 2., 1.)],
            true,
            Some((X, 1.)),
        ),
        case(
            "triangle above a non-planar quad's fold",
            q0(),
            tri(v(1., 1., 0.5), v(1., 1.5, 2.), v(1.5, 1., 2.)),
            true,
            Some((Z, 1.)),
        ),
    ]
}

/// Gaps of the near misses, as fractions of the case size.
const GAPS: [f64; 3] = [1e-3, 1e-5, 1e-7];

/// The case's two meshes in `frame`, moved apart by `gap` when given. `dx` shifts the
/// case along x in base units (the combined test lays cases side by side).
fn realize(c: &Case, frame: &Frame, gap: Option<f64>, dx: f64) -> (Vec<[f32; 3]>, Vec<[f32; 3]>) {
    let put = |vs: &[V]| -> Vec<[f32; 3]> {
        vs.iter()
            .map(|w| {
                let mut p = frame.place([w.p[0] + dx, w.p[1], w.p[2]]);
                if let Some((axis, rel)) = w.nudge {
                    p[axis] = frame.nudge(p[axis], rel);
                }
                p
            })
            .collect()
    };
    let r = put(&c.r);
    let mut o = put(&c.o);
    if let Some(g) = gap {
        let (axis, sign) = c.away.expect("near miss of a case without a direction");
        for p in &mut o {
            p[axis] = frame.nudge(p[axis], sign * g);
        }
    }
    (r, o)
}

fn mesh(pos: Vec<[f32; 3]>) -> TestMesh {
    let k = pos.len();
    TestMesh {
        idx: (0..k as u32).collect(),
        pos,
        k,
    }
}

/// The epsilons each case runs with, as fractions of the case size.
const EPSILONS: [f64; 3] = [0.25, 1e-3, 1e-6];

/// Checks one configuration on one backend against the oracle. Returns the exact answer.
fn check(
    f: &Factory,
    label: &str,
    r: &TestMesh,
    o: &TestMesh,
    size: f64,
    leaf: u32,
) -> Vec<(u32, u32)> {
    let exact = brute_force_exact(r, o);
    if f.exact {
        let mut s = (f.make)(0.0, leaf);
        let (ri, oi) = (s.add(r), s.add(o));
        let got = s.pairs(ri, oi);
        assert_eq!(
            got, exact,
            "{}: {label}, epsilon 0: library vs oracle",
            f.name
        );
    }
    let max_coord = r
        .pos
        .iter()
        .chain(&o.pos)
        .flat_map(|p| p.iter())
        .fold(0.0f64, |m, &c| m.max(f64::from(c).abs()));
    for rel in EPSILONS {
        let e = (rel * size) as f32;
        let h = f64::from(e) / 2.0;
        let slack = 1e-9 * (h + size) + 8.0 * f64::EPSILON * max_coord;
        let mut s = (f.make)(e, leaf);
        let (ri, oi) = (s.add(r), s.add(o));
        let got = s.pairs(ri, oi);
        for p in &exact {
            assert!(
                got.binary_search(p).is_ok(),
                "{}: {label}, epsilon {e}: intersecting pair {p:?} missed",
                f.name
            );
        }
        for &(a, b) in &got {
            if exact.binary_search(&(a, b)).is_ok() {
                continue;
            }
            let d = polygon_distance(r, a as usize, o, b as usize);
            assert!(
                d <= h + slack,
                "{}: {label}, epsilon {e}: extra pair ({a}, {b}) at distance {d:e}, beyond epsilon/2 = {h:e}",
                f.name
            );
        }
    }
    exact
}

#[test]
fn the_cases_say_what_they_mean() {
    // Sanity of the suite itself: in the exact frames the oracle agrees with the intent,
    // and every near miss is a miss.
    for frame in FRAMES.iter().filter(|f| f.exact) {
        for c in cases() {
            let (r, o) = realize(&c, frame, None, 0.0);
            let (r, o) = (mesh(r), mesh(o));
            let meets = !brute_force_exact(&r, &o).is_empty();
            assert_eq!(meets, c.meets, "{} in {}", c.name, frame.name);
            if c.away.is_some() {
                for g in GAPS {
                    let (r, o) = realize(&c, frame, Some(g), 0.0);
                    assert!(
                        brute_force_exact(&mesh(r), &mesh(o)).is_empty(),
                        "{} in {} moved by {g}",
                        c.name,
                        frame.name
                    );
                }
            }
        }
    }
}

#[test]
fn every_case_in_every_frame_matches_the_oracle() {
    let mut checked = 0;
    for f in factories() {
        for frame in FRAMES {
            for c in cases() {
                let variants = std::iter::once(None)
                    .chain(c.away.iter().flat_map(|_| GAPS.iter().map(|&g| Some(g))));
                for gap in variants {
                    let (r, o) = realize(&c, frame, gap, 0.0);
                    let label = format!("{} in {} (gap {gap:?})", c.name, frame.name);
                    check(&f, &label, &mesh(r), &mesh(o), 2.0 * frame.scale, 0);
                    checked += 1;
                }
            }
        }
    }
    assert!(checked > 500, "{checked}");
    eprintln!("checked {checked}");
}

/// The GL backends on every case in every frame (and each case moved away by the largest
/// gap): exactly the oracle's pairs at epsilon 0, and at every epsilon of the CPU runs
/// (below the GL's minimum depth too) every intersecting pair found, extras within
/// epsilon/2. One scene per backend, frame and epsilon (shaders compile once), meshes made
/// and destroyed per case.
#[test]
fn every_case_in_every_frame_on_the_gl_backends() {
    let mut checked = 0;
    for f in gl_factories() {
        for frame in FRAMES {
            let size = 2.0 * frame.scale;
            for rel in std::iter::once(0.0).chain(EPSILONS) {
                let e = (rel * size) as f32;
                let h = f64::from(e) / 2.0;
                let mut s = (f.make)(e, 0);
                for c in cases() {
                    for gap in std::iter::once(None).chain(c.away.map(|_| Some(GAPS[0]))) {
                        let (r, o) = realize(&c, frame, gap, 0.0);
                        let (r, o) = (mesh(r), mesh(o));
                        let max_coord = r
                            .pos
                            .iter()
                            .chain(&o.pos)
                            .flat_map(|p| p.iter())
                            .fold(0.0f64, |m, &c| m.max(f64::from(c).abs()));
                        let slack = 1e-9 * (h + size) + 8.0 * f64::EPSILON * max_coord;
                        let label = format!(
                            "{}: {} in {} (gap {gap:?}), epsilon {e}",
                            f.name, c.name, frame.name
                        );
                        let exact = brute_force_exact(&r, &o);
                        let (ri, oi) = (s.add(&r), s.add(&o));
                        let got = s.pairs(ri, oi);
                        s.destroy(ri);
                        s.destroy(oi);
                        if rel == 0.0 {
                            assert_eq!(got, exact, "{label}: not the exact answer");
                        }
                        for p in &exact {
                            assert!(
                                got.binary_search(p).is_ok(),
                                "{label}: intersecting pair {p:?} missed"
                            );
                        }
                        for &(a, b) in got.iter().filter(|p| exact.binary_search(p).is_err()) {
                            let d = polygon_distance(&r, a as usize, &o, b as usize);
                            assert!(
                                d <= h + slack,
                                "{label}: extra pair ({a}, {b}) at distance {d:e} > {h:e}"
                            );
                        }
                        checked += 1;
                    }
                }
            }
        }
    }
    assert!(checked > 200, "{checked}");
}

/// Reference and other swapped: the same pairs, mirrored, at epsilon = 0.
#[test]
fn every_case_swapped_gives_the_mirrored_answer() {
    for f in factories().into_iter().filter(|f| f.exact) {
        for frame in FRAMES {
            for c in cases() {
                let (r, o) = realize(&c, frame, None, 0.0);
                let (r, o) = (mesh(r), mesh(o));
                let mut s = (f.make)(0.0, 0);
                let (ri, oi) = (s.add(&r), s.add(&o));
                let fwd = s.pairs(ri, oi);
                let mut back: Vec<(u32, u32)> =
                    s.pairs(oi, ri).into_iter().map(|(a, b)| (b, a)).collect();
                back.sort_unstable();
                assert_eq!(fwd, back, "{}: {} in {}", f.name, c.name, frame.name);
            }
        }
    }
}

/// Joins single-polygon meshes with the same vertices per polygon into one mesh.
fn join(parts: &[Vec<[f32; 3]>]) -> TestMesh {
    let k = parts[0].len();
    let mut m = TestMesh {
        pos: Vec::new(),
        idx: Vec::new(),
        k,
    };
    for p in parts {
        assert_eq!(p.len(), k);
        let base = m.pos.len() as u32;
        m.idx.extend((0..k as u32).map(|i| base + i));
        m.pos.extend_from_slice(p);
    }
    m
}

#[test]
fn all_cases_side_by_side_as_two_meshes() {
    for f in factories() {
        for frame in FRAMES {
            for gap in [None, Some(1e-5)] {
                // Group by (reference k, other k): a mesh has one polygon size.
                for (kr, ko) in [(3, 3), (4, 3), (4, 4), (3, 4)] {
                    let mut rs = Vec::new();
                    let mut os = Vec::new();
                    let mut want_meets = Vec::new();
                    for (i, c) in cases().iter().enumerate() {
                        if c.r.len() != kr || c.o.len() != ko || (gap.is_some() && c.away.is_none())
                        {
                            continue;
                        }
                        let (r, o) = realize(c, frame, gap, 8.0 * i as f64);
                        rs.push(r);
                        os.push(o);
                        want_meets.push(c.meets && gap.is_none());
                    }
                    if rs.is_empty() {
                        continue;
                    }
                    let (r, o) = (join(&rs), join(&os));
                    let label = format!(
                        "{} cases ({kr}, {ko}) in {} (gap {gap:?})",
                        rs.len(),
                        frame.name
                    );
                    let exact = check(&f, &label, &r, &o, 2.0 * frame.scale, 2);
                    if frame.exact {
                        // Cases 8 base units apart never reach each other.
                        let diag: Vec<(u32, u32)> = want_meets
                            .iter()
                            .enumerate()
                            .filter(|(_, &m)| m)
                            .map(|(i, _)| (i as u32, i as u32))
                            .collect();
                        assert_eq!(exact, diag, "{label}");
                    }
                }
            }
        }
    }
}
