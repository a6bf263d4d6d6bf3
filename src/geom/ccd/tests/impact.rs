//! The impact geometry ([`super::super::impact`]) checked exactly, with rationals:
//!
//! * **weights**: each in `[0, 1]`, the unused ones 0, each feature's summing to exactly 1
//!   (exact rational sum: stronger than the `1e-15` the brief allows);
//! * **normal**: finite, unit (`| |n|^2 - 1 | <= 2^-50`);
//! * **distance**: the exact `|point_a - point_b|` at `toi` (exact positions `p(toi)` of the
//!   doubles, the weights as given) at most `2^-19 M + 2^-48 S`, `M` the largest Euclidean
//!   vertex motion of the query, `S` its largest coordinate magnitude (rounding: 16 ulps of
//!   the largest coordinate); and (where affordable: [`check_closest`]) at most the exact
//!   least distance between the features at `toi` plus `2^-48 S`: the closest points are
//!   the closest;
//! * **separating**, unless the pair meets at the start: (1) with the features' normal
//!   ([`NormalFrom::Features`]), exactly: `n` parallel to the exact `e1 x e2` at `toi`
//!   (within `2^-24`) and on the side a is on just before `toi` (the sign, exact, of the
//!   first nonzero Taylor term at `toi` of the cubic `det(e1, e2, w)(t)`, when it is not
//!   identically 0); (2) with any normal: the contact points' relative velocity does not
//!   leave along it, `n . v_rel <= 2^-20 |v_rel|` (the weights held, exact). Since
//!   `point_a - point_b` is linear in `t` with the weights held, (2) is the same as "the
//!   signed gap `n . (point_a - point_b)` just before `toi` is at least the gap at `toi`".
//!
//! A flipped normal fails (1) wherever a's side is known and (2) wherever the approach is
//! not grazing: the tallies count those ("decisive"), and
//! [`the_checks_reject_broken_answers`] shows the checker rejecting flipped normals,
//! unclamped or unnormalized weights and a wrong contact point.
//!
//! Cases: every true query of the ground truth (`../shared/meshes/sim/ccd`, skipped with a
//! message when absent); motions built with a known answer (a vertex hitting a triangle's
//! interior, edge and corner, from either side and either winding; edges crossing; parallel
//! edges end to end and side by side; coplanar sliding; degenerate triangles and edges;
//! pairs meeting at the start with no relative motion), at the scales `2^-100`, 1, `2^100`
//! (bit-identical answers) and the offset 1e6; random deforming motions. (The polygon pair's
//! first primitive pair is the continuous query's: `tests/continuous.rs` checks it.)

use super::super::impact::{ImpactPoint, NormalFrom};
use super::super::predicate::Kind;
use super::super::{decide, edge_edge_impact, vertex_face_impact, Points, Toi};
use super::reference::{dist2_at, inv_pow2, q, Q};
use super::split;
use super::truth::{has_truth, load, SCENES};
use crate::geom::test_rng::Rng;
use crate::geom::P3;
use num_traits::{Signed, ToPrimitive, Zero};

// ---------------------------------------------------------------------------------------
// Exact helpers.

type Q3 = [Q; 3];

fn qv(p: P3) -> Q3 {
    p.map(q)
}

fn qsub(a: &Q3, b: &Q3) -> Q3 {
    [&a[0] - &b[0], &a[1] - &b[1], &a[2] - &b[2]]
}

fn qdot(a: &Q3, b: &Q3) -> Q {
    &a[0] * &b[0] + &a[1] * &b[1] + &a[2] * &b[2]
}

fn qcross(a: &Q3, b: &Q3) -> Q3 {
    [
        &a[1] * &b[2] - &a[2] * &b[1],
        &a[2] * &b[0] - &a[0] * &b[2],
        &a[0] * &b[1] - &a[1] * &b[0],
    ]
}

/// `sum w[k] p[k]`, exactly.
fn qcombine(w: &[f64; 3], p: &[Q3]) -> Q3 {
    std::array::from_fn(|c| {
        p.iter()
            .zip(w)
            .fold(Q::zero(), |s, (p, w)| s + q(*w) * &p[c])
    })
}

/// The points at `t`, exactly.
fn qat(pts: &Points, t: f64) -> [Q3; 4] {
    let t = q(t);
    pts.map(|p| std::array::from_fn(|k| q(p[0][k]) + &t * (q(p[1][k]) - q(p[0][k]))))
}

/// A polynomial in `t` with rational coefficients, lowest first.
type Poly = Vec<Q>;

fn padd(a: &Poly, b: &Poly, sign: i32) -> Poly {
    (0..a.len().max(b.len()))
        .map(|i| {
            let x = a.get(i).cloned().unwrap_or_else(Q::zero);
            let y = b.get(i).cloned().unwrap_or_else(Q::zero);
            if sign > 0 {
                x + y
            } else {
                x - y
            }
        })
        .collect()
}

fn pmul(a: &Poly, b: &Poly) -> Poly {
    let mut out = vec![Q::zero(); a.len() + b.len() - 1];
    for (i, x) in a.iter().enumerate() {
        for (j, y) in b.iter().enumerate() {
            out[i + j] += x * y;
        }
    }
    out
}

type PVec = [Poly; 3];

fn pcross(a: &PVec, b: &PVec) -> PVec {
    std::array::from_fn(|r| {
        let (r1, r2) = ((r + 1) % 3, (r + 2) % 3);
        padd(&pmul(&a[r1], &b[r2]), &pmul(&a[r2], &b[r1]), -1)
    })
}

fn peval(p: &Poly, t: &Q) -> Q {
    p.iter().rev().fold(Q::zero(), |s, c| s * t + c)
}

/// The features' vectors `e1`, `e2` (the normal `e1 x e2`: the triangle's, the edges') and
/// `w` (from b's feature to a's) as polynomials in `t`.
fn feature_vectors(kind: Kind, pts: &Points) -> [PVec; 3] {
    let lin = |i: usize| -> PVec {
        std::array::from_fn(|k| vec![q(pts[i][0][k]), q(pts[i][1][k]) - q(pts[i][0][k])])
    };
    let vec = |i: usize, j: usize| -> PVec {
        let (a, b) = (lin(i), lin(j));
        std::array::from_fn(|k| padd(&b[k], &a[k], -1))
    };
    match kind {
        Kind::VertexFace => [vec(1, 2), vec(1, 3), vec(1, 0)],
        Kind::EdgeEdge => [vec(0, 1), vec(2, 3), vec(2, 0)],
    }
}

/// The sign of the polynomial just before `t` (`None`: identically 0).
fn sign_just_before(p: &Poly, t: &Q) -> Option<i32> {
    // Taylor coefficients at t: d_k = sum_j C(j, k) c_j t^(j - k).
    let n = p.len();
    for k in 0..n {
        let mut d = Q::zero();
        for (j, c) in p.iter().enumerate().skip(k) {
            let binom = (1..=k).fold(1i64, |b, i| b * (j - i + 1) as i64 / i as i64);
            let mut term = c * Q::from_integer(binom.into());
            for _ in 0..j - k {
                term *= t;
            }
            d += term;
        }
        if !d.is_zero() {
            let s = if d.is_positive() { 1 } else { -1 };
            return Some(if k % 2 == 0 { s } else { -s });
        }
    }
    None
}

// ---------------------------------------------------------------------------------------
// The checker.

/// What the checker measured on a correct answer.
#[derive(Debug, Default, Clone, Copy)]
struct Seen {
    /// The side was known (exactly) and checked.
    side_checked: bool,
    /// `n . v_rel < -2^-20 |v_rel|`: a flipped normal fails (2).
    approaching: bool,
    /// `(|point_a - point_b| - 2^-19 M) / (eps S)`, the distance's excess over the motion
    /// term in units of rounding (negative: within the motion term).
    excess: f64,
    /// `n . v_rel / |v_rel|` (0 without relative motion).
    leaving: f64,
}

/// The largest Euclidean motion of the query's points and its largest coordinate magnitude.
fn motion_and_size(pts: &Points) -> (f64, f64) {
    let m = pts
        .iter()
        .map(|p| {
            let d = [p[1][0] - p[0][0], p[1][1] - p[0][1], p[1][2] - p[0][2]];
            (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt()
        })
        .fold(0.0, f64::max);
    let s = pts
        .iter()
        .flatten()
        .flatten()
        .fold(0.0f64, |s, x| s.max(x.abs()));
    (m, s)
}

fn check_weights(w: &[f64; 3], used: usize, which: &str) -> Result<(), String> {
    if !w.iter().all(|x| (0.0..=1.0).contains(x)) {
        return Err(format!("{which} weights {w:?} outside [0, 1]"));
    }
    if w[used..].iter().any(|&x| x != 0.0) {
        return Err(format!("{which} weights {w:?}: unused ones not 0"));
    }
    let sum = w.iter().fold(Q::zero(), |s, x| s + q(*x));
    if sum != Q::from_integer(1.into()) {
        return Err(format!("{which} weights {w:?} sum to {sum}, not 1"));
    }
    Ok(())
}

/// Checks the impact geometry `ip` of the primitive pair `pts` at `toi` (the module's
/// notes): `Err` with the reason.
fn check(kind: Kind, pts: &Points, toi: Toi, ip: &ImpactPoint) -> Result<Seen, String> {
    let s = split(kind);
    check_weights(&ip.weights_a, s, "a's")?;
    check_weights(&ip.weights_b, 4 - s, "b's")?;
    let n = ip.normal;
    if !n.iter().all(|x| x.is_finite()) {
        return Err(format!("normal {n:?} not finite"));
    }
    let nn = n[0] * n[0] + n[1] * n[1] + n[2] * n[2];
    if (nn - 1.0).abs() > 1.0 / (1u64 << 50) as f64 {
        return Err(format!("normal {n:?} not unit"));
    }
    // The distance at toi, exactly.
    let x = qat(pts, toi.t);
    let d = qsub(
        &qcombine(&ip.weights_a, &x[..s]),
        &qcombine(&ip.weights_b, &x[s..]),
    );
    let d2 = qdot(&d, &d);
    let (m, size) = motion_and_size(pts);
    let motion_term = m / (1u64 << 19) as f64;
    let bound = (motion_term + size / (1u64 << 48) as f64) * (1.0 + 1e-12);
    if d2 > q(bound) * q(bound) {
        return Err(format!(
            "points {} apart at toi, more than {bound}",
            d2.to_f64().unwrap_or(f64::NAN).sqrt()
        ));
    }
    let dist = d2.to_f64().unwrap_or(f64::NAN).sqrt();
    let mut seen = Seen {
        excess: (dist - motion_term) / (f64::EPSILON * size.max(f64::MIN_POSITIVE)),
        ..Seen::default()
    };
    if toi.at_start {
        return Ok(seen);
    }
    let qn = qv(n);
    // (1) The features' normal: its direction and a's side just before toi.
    if ip.normal_from == NormalFrom::Features {
        let [e1, e2, w] = feature_vectors(kind, pts);
        let big_n = pcross(&e1, &e2);
        let cubic = (0..3).fold(vec![Q::zero()], |c, k| padd(&c, &pmul(&big_n[k], &w[k]), 1));
        let t = q(toi.t);
        let nt: Q3 = std::array::from_fn(|k| peval(&big_n[k], &t));
        let nt2 = qdot(&nt, &nt);
        if nt2.is_zero() {
            return Err("the features' normal is 0 at toi, yet used".into());
        }
        let c = qcross(&qn, &nt);
        if qdot(&c, &c) > inv_pow2(48) * &nt2 {
            return Err(format!("normal {n:?} not along the features' normal"));
        }
        if let Some(side) = sign_just_before(&cubic, &t) {
            seen.side_checked = true;
            let got = qdot(&qn, &nt);
            if got.is_positive() != (side > 0) {
                return Err(format!(
                    "normal {n:?} on the wrong side: a is on side {side} just before toi"
                ));
            }
        }
    }
    // (2) The relative velocity does not leave along the normal.
    let v: [Q3; 4] = pts.map(|p| qsub(&qv(p[1]), &qv(p[0])));
    let v_rel = qsub(
        &qcombine(&ip.weights_a, &v[..s]),
        &qcombine(&ip.weights_b, &v[s..]),
    );
    let vv = qdot(&v_rel, &v_rel);
    let nv = qdot(&qn, &v_rel);
    let tau = inv_pow2(20);
    if nv.is_positive() && &nv * &nv > &tau * &tau * &vv {
        return Err(format!(
            "normal {n:?} along the relative motion: n . v_rel = {} > 2^-20 |v_rel|",
            nv.to_f64().unwrap_or(f64::NAN)
        ));
    }
    seen.approaching = nv.is_negative() && &nv * &nv > &tau * &tau * &vv;
    if !vv.is_zero() {
        seen.leaving = nv.to_f64().unwrap_or(0.0) / vv.to_f64().unwrap_or(1.0).sqrt();
    }
    Ok(seen)
}

/// The closest points are the closest, to rounding: `|point_a - point_b|` at `toi` at most
/// the exact least distance between the features there ([`dist2_at`], about
/// 3 ms a query) plus `2^-48 S`. The excess over that distance, in units of `eps S`.
fn check_closest(kind: Kind, pts: &Points, toi: Toi, ip: &ImpactPoint) -> Result<f64, String> {
    let s = split(kind);
    let x = qat(pts, toi.t);
    let d = qsub(
        &qcombine(&ip.weights_a, &x[..s]),
        &qcombine(&ip.weights_b, &x[s..]),
    );
    let d2 = qdot(&d, &d);
    let least = dist2_at(pts, s, &q(toi.t))
        .to_f64()
        .unwrap_or(f64::NAN)
        .sqrt();
    let (_, size) = motion_and_size(pts);
    let bound = (least + size / (1u64 << 48) as f64) * (1.0 + 1e-12);
    if d2 > q(bound) * q(bound) {
        return Err(format!(
            "points {} apart at toi, the features {least}",
            d2.to_f64().unwrap_or(f64::NAN).sqrt()
        ));
    }
    let dist = d2.to_f64().unwrap_or(f64::NAN).sqrt();
    Ok((dist - least) / (f64::EPSILON * size.max(f64::MIN_POSITIVE)))
}

/// The primitive's geometry for the query.
fn geometry(kind: Kind, pts: &Points, t: f64) -> ImpactPoint {
    match kind {
        Kind::VertexFace => {
            vertex_face_impact(pts[0], [0, 1].map(|e| [1, 2, 3].map(|i| pts[i][e])), t)
        }
        Kind::EdgeEdge => edge_edge_impact(
            [0, 1].map(|e| [pts[0][e], pts[1][e]]),
            [0, 1].map(|e| [pts[2][e], pts[3][e]]),
            t,
        ),
    }
}

/// Tallies of a family.
#[derive(Debug)]
struct Tally {
    cases: usize,
    at_start: usize,
    from: [usize; 5],
    side_checked: usize,
    approaching: usize,
    /// The largest distance excess seen (units of `eps S`, over the motion term).
    max_excess: f64,
    /// The largest `n . v_rel / |v_rel|` seen.
    max_leaving: f64,
    /// Queries whose closest points were checked against the exact least distance.
    closest_checked: usize,
    /// The largest excess over the exact least distance seen (units of `eps S`).
    max_closest_excess: f64,
}

impl Default for Tally {
    fn default() -> Self {
        Tally {
            cases: 0,
            at_start: 0,
            from: [0; 5],
            side_checked: 0,
            approaching: 0,
            max_excess: f64::NEG_INFINITY,
            max_leaving: f64::NEG_INFINITY,
            closest_checked: 0,
            max_closest_excess: f64::NEG_INFINITY,
        }
    }
}

impl Tally {
    fn add(&mut self, toi: Toi, ip: &ImpactPoint, seen: &Seen) {
        self.cases += 1;
        self.at_start += usize::from(toi.at_start);
        self.from[ip.normal_from as usize] += 1;
        self.side_checked += usize::from(seen.side_checked);
        self.approaching += usize::from(seen.approaching);
        self.max_excess = self.max_excess.max(seen.excess);
        self.max_leaving = self.max_leaving.max(seen.leaving);
    }

    fn add_closest(&mut self, excess: f64) {
        self.closest_checked += 1;
        self.max_closest_excess = self.max_closest_excess.max(excess);
    }
}

/// Decides the query (it must meet), computes and checks its geometry: the time of impact
/// and the geometry; panics with the reason on a failure.
fn judge(kind: Kind, pts: &Points, tally: &mut Tally) -> (Toi, ImpactPoint) {
    let toi = decide(kind, pts)
        .0
        .unwrap_or_else(|| panic!("{kind:?} apart: {pts:?}"));
    let ip = geometry(kind, pts, toi.t);
    match check(kind, pts, toi, &ip)
        .and_then(|seen| Ok((seen, check_closest(kind, pts, toi, &ip)?)))
    {
        Ok((seen, excess)) => {
            tally.add(toi, &ip, &seen);
            tally.add_closest(excess);
        }
        Err(e) => panic!("{kind:?} {e}: {toi:?} {ip:?} {pts:?}"),
    }
    (toi, ip)
}

/// The geometry at a chosen time of impact `t` (the exact meeting time, say), checked.
fn judge_at(kind: Kind, pts: &Points, t: f64) -> ImpactPoint {
    let toi = Toi { t, at_start: false };
    let ip = geometry(kind, pts, t);
    if let Err(e) = check(kind, pts, toi, &ip).and_then(|_| check_closest(kind, pts, toi, &ip)) {
        panic!("{kind:?} at {t}: {e}: {ip:?} {pts:?}");
    }
    ip
}

// ---------------------------------------------------------------------------------------
// The ground truth.

fn ground_truth(name: &str, test: &str) {
    if !has_truth(test) {
        return;
    }
    let &(scene, frame, csv_ee) = SCENES.iter().find(|s| s.0 == name).expect("scene");
    for kind in [Kind::VertexFace, Kind::EdgeEdge] {
        let mut tally = Tally::default();
        let mut failures = Vec::new();
        // The exact least distance costs about 3 ms a query: every 4th query's of the
        // larger steps.
        let stride = if scene == "cloth-funnel" { 1 } else { 4 };
        for (i, query) in load(scene, frame, csv_ee, kind).iter().enumerate() {
            if !query.truth {
                continue;
            }
            let toi = decide(kind, &query.pts).0.expect("a true query meets");
            let ip = geometry(kind, &query.pts, toi.t);
            match check(kind, &query.pts, toi, &ip) {
                Ok(seen) => tally.add(toi, &ip, &seen),
                Err(e) => failures.push(format!("#{i}: {e}")),
            }
            if tally.cases % stride == 0 {
                match check_closest(kind, &query.pts, toi, &ip) {
                    Ok(excess) => tally.add_closest(excess),
                    Err(e) => failures.push(format!("#{i}: {e}")),
                }
            }
        }
        eprintln!("{scene} {kind:?}: {tally:?}");
        assert!(
            failures.is_empty(),
            "{scene} {kind:?}: {} failures, the first: {:?}",
            failures.len(),
            &failures[..failures.len().min(5)]
        );
        assert!(tally.cases > 0);
    }
}

#[test]
fn cloth_funnel_impact_geometry() {
    ground_truth("cloth-funnel", "cloth_funnel_impact_geometry");
}

#[test]
fn rod_twist_impact_geometry() {
    ground_truth("rod-twist", "rod_twist_impact_geometry");
}

#[test]
fn armadillo_rollers_impact_geometry() {
    ground_truth("armadillo-rollers", "armadillo_rollers_impact_geometry");
}

// ---------------------------------------------------------------------------------------
// Motions built with a known answer.

/// Scales and offsets that keep the doubles exact (`(power of two, offset)`).
const FRAMES: [(i32, f64); 3] = [(-100, 0.0), (100, 0.0), (0, 1e6)];

fn place(pts: &Points, (s, offset): (i32, f64)) -> Points {
    pts.map(|p| {
        p.map(|x| {
            x.map(|c| {
                let y = c * f64::powi(2.0, s) + offset;
                assert_eq!((y - offset) * f64::powi(2.0, -s), c, "{c} not exact");
                y
            })
        })
    })
}

fn vf_pts(v: [P3; 2], f: [[P3; 3]; 2]) -> Points {
    [
        v,
        [f[0][0], f[1][0]],
        [f[0][1], f[1][1]],
        [f[0][2], f[1][2]],
    ]
}

fn ee_pts(a: [[P3; 2]; 2], b: [[P3; 2]; 2]) -> Points {
    [
        [a[0][0], a[1][0]],
        [a[0][1], a[1][1]],
        [b[0][0], b[1][0]],
        [b[0][1], b[1][1]],
    ]
}

fn close(a: &[f64], b: &[f64], tol: f64) -> bool {
    a.iter().zip(b).all(|(x, y)| (x - y).abs() <= tol)
}

/// Judges a built case in every frame (the checks pass in each): the answers at the scales
/// `2^k` bit-identical to the unscaled one (at the same time), the offset one close.
fn judge_everywhere(kind: Kind, pts: &Points, tally: &mut Tally) -> (Toi, ImpactPoint) {
    judge_in_frames(kind, pts, tally, true)
}

/// As [`judge_everywhere`]; `offset_close`: also compare the answer at the offset 1e6 (not
/// for random cases: 1e6 costs 20 bits, and a nearly degenerate feature normal at toi may
/// then be uncertain and give way to the next rule).
fn judge_in_frames(
    kind: Kind,
    pts: &Points,
    tally: &mut Tally,
    offset_close: bool,
) -> (Toi, ImpactPoint) {
    let (toi, ip) = judge(kind, pts, tally);
    for frame in FRAMES {
        let placed = place(pts, frame);
        judge(kind, &placed, tally);
        let same_time = geometry(kind, &placed, toi.t);
        if frame.1 == 0.0 {
            assert_eq!(same_time, ip, "scaled by 2^{}: {pts:?}", frame.0);
        } else if offset_close {
            assert!(
                close(&same_time.normal, &ip.normal, 1e-6)
                    && close(&same_time.weights_a, &ip.weights_a, 1e-6)
                    && close(&same_time.weights_b, &ip.weights_b, 1e-6),
                "offset: {same_time:?} vs {ip:?} for {pts:?}"
            );
        }
    }
    (toi, ip)
}

/// The triangle `(0,0,0), (4,0,0), (0,4,0)`, standing still (or wound the other way).
fn flat_triangle(wound: bool) -> [[P3; 3]; 2] {
    let t = if wound {
        [[0.0, 0.0, 0.0], [4.0, 0.0, 0.0], [0.0, 4.0, 0.0]]
    } else {
        [[0.0, 0.0, 0.0], [0.0, 4.0, 0.0], [4.0, 0.0, 0.0]]
    };
    [t, t]
}

#[test]
fn a_vertex_hits_a_triangle_inside_on_an_edge_and_at_a_corner() {
    let mut tally = Tally::default();
    // (x, y) and the expected weights of the (0,0,0), (4,0,0), (0,4,0) corners.
    let targets = [
        ([1.0, 1.0], [0.5, 0.25, 0.25]),
        ([2.0, 0.0], [0.5, 0.5, 0.0]),
        ([0.0, 0.0], [1.0, 0.0, 0.0]),
        ([0.0, 4.0], [0.0, 0.0, 1.0]),
        ([2.0, 2.0], [0.0, 0.5, 0.5]),
    ];
    for (xy, expected) in targets {
        for from_above in [true, false] {
            for wound in [true, false] {
                let h = if from_above { 1.0 } else { -1.0 };
                let v = [[xy[0], xy[1], h], [xy[0], xy[1], -3.0 * h]];
                let f = flat_triangle(wound);
                let (toi, ip) = judge_everywhere(Kind::VertexFace, &vf_pts(v, f), &mut tally);
                assert!((toi.t - 0.25).abs() <= 1.0 / (1 << 20) as f64, "{toi:?}");
                assert_eq!(ip.normal_from, NormalFrom::Features);
                assert_eq!(ip.normal, [0.0, 0.0, h], "{xy:?} {wound}");
                assert_eq!(ip.weights_a, [1.0, 0.0, 0.0]);
                let mut w = ip.weights_b;
                if !wound {
                    w.swap(1, 2);
                }
                assert!(close(&w, &expected, 1e-12), "{w:?} vs {expected:?}");
                // At the exact meeting time (a valid time of impact too): the vertex in the
                // plane, its side from just before.
                let at_meeting = judge_at(Kind::VertexFace, &vf_pts(v, f), 0.25);
                assert_eq!(at_meeting.normal, [0.0, 0.0, h]);
                assert!(close(&at_meeting.weights_b, &ip.weights_b, 1e-12));
            }
        }
    }
    // The vertex still, the triangle moving onto it (tilted as it goes).
    let v = [[1.0, 1.0, 0.5], [1.0, 1.0, 0.5]];
    let f = [
        [[0.0, 0.0, 0.0], [4.0, 0.0, 0.0], [0.0, 4.0, 0.0]],
        [[0.0, 0.0, 1.0], [4.0, 0.0, 0.5], [0.0, 4.0, 2.0]],
    ];
    let (_, ip) = judge_everywhere(Kind::VertexFace, &vf_pts(v, f), &mut tally);
    assert_eq!(ip.normal_from, NormalFrom::Features);
    assert!(ip.normal[2] > 0.9, "{ip:?}");
    eprintln!("vertex-face built: {tally:?}");
}

#[test]
fn a_tangential_touch() {
    // The triangle tilts about its edge on the x axis (f2 from (0, 4, 1) to (0, 4, -1));
    // the vertex (1, 1 + t, 3/8 - 3t/4) stays above its plane, touching it at t = 1/2 only,
    // at (1, 3/2, 0), inside: det(t) = 8 (t - 1/2)^2, a double root. At that time the
    // vertex is in the plane and its relative velocity along the plane: only "just before"
    // tells the side (above, +z), whichever way the triangle is wound.
    let mut tally = Tally::default();
    let v = [[1.0, 1.0, 0.375], [1.0, 2.0, -0.375]];
    let (f0, f1) = ([0.0, 0.0, 0.0], [4.0, 0.0, 0.0]);
    let f2 = [[0.0, 4.0, 1.0], [0.0, 4.0, -1.0]];
    for wound in [true, false] {
        let f = if wound {
            [[f0, f1, f2[0]], [f0, f1, f2[1]]]
        } else {
            [[f0, f2[0], f1], [f0, f2[1], f1]]
        };
        let pts = vf_pts(v, f);
        let (toi, ip) = judge_everywhere(Kind::VertexFace, &pts, &mut tally);
        assert!((toi.t - 0.5).abs() <= 1.0 / (1 << 20) as f64, "{toi:?}");
        assert!(ip.normal[2] > 0.99, "{ip:?}");
        let at_touch = judge_at(Kind::VertexFace, &pts, 0.5);
        assert!(
            close(&at_touch.normal, &[0.0, 0.0, 1.0], 1e-12),
            "{wound} {at_touch:?}"
        );
    }
    eprintln!("tangential: {tally:?}");
}

#[test]
fn edges_crossing_parallel_and_end_to_end() {
    let mut tally = Tally::default();
    // Crossing: a (along x) comes down onto b (along y, either direction).
    for flip in [false, true] {
        let b0 = [[0.0, -1.0, 0.0], [0.0, 1.0, 0.0]];
        let b0 = if flip { [b0[1], b0[0]] } else { b0 };
        let a = [
            [[-1.0, 0.5, 1.0], [1.0, 0.5, 1.0]],
            [[-1.0, 0.5, -1.0], [1.0, 0.5, -1.0]],
        ];
        let (toi, ip) = judge_everywhere(Kind::EdgeEdge, &ee_pts(a, [b0, b0]), &mut tally);
        assert!((toi.t - 0.5).abs() <= 1.0 / (1 << 20) as f64);
        assert_eq!(ip.normal, [0.0, 0.0, 1.0]);
        assert_eq!(ip.normal_from, NormalFrom::Features);
        assert!(close(&ip.weights_a, &[0.5, 0.5, 0.0], 1e-12), "{ip:?}");
        let wb = if flip {
            [0.75, 0.25, 0.0]
        } else {
            [0.25, 0.75, 0.0]
        };
        assert!(close(&ip.weights_b, &wb, 1e-12), "{ip:?}");
        let at_meeting = judge_at(Kind::EdgeEdge, &ee_pts(a, [b0, b0]), 0.5);
        assert_eq!(at_meeting.normal, [0.0, 0.0, 1.0]);
        assert_eq!(at_meeting.weights_b, wb);
    }
    // Parallel, side by side: a above b, coming down.
    let b = [[0.0, 0.0, 0.0], [2.0, 0.0, 0.0]];
    let a = [
        [[0.5, 0.0, 1.0], [1.5, 0.0, 1.0]],
        [[0.5, 0.0, -1.0], [1.5, 0.0, -1.0]],
    ];
    let (_, ip) = judge_everywhere(Kind::EdgeEdge, &ee_pts(a, [b, b]), &mut tally);
    assert_ne!(ip.normal_from, NormalFrom::Features);
    assert!(close(&ip.normal, &[0.0, 0.0, 1.0], 1e-9), "{ip:?}");
    // Collinear, end to end: a slides along x into b's end.
    let short = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0]];
    let a = [
        [[2.0, 0.0, 0.0], [3.0, 0.0, 0.0]],
        [[0.5, 0.0, 0.0], [1.5, 0.0, 0.0]],
    ];
    let (toi, ip) = judge_everywhere(Kind::EdgeEdge, &ee_pts(a, [short, short]), &mut tally);
    assert!((toi.t - 2.0 / 3.0).abs() <= 1.0 / (1 << 20) as f64);
    assert_ne!(ip.normal_from, NormalFrom::Features);
    assert!(close(&ip.normal, &[1.0, 0.0, 0.0], 1e-9), "{ip:?}");
    assert_eq!(ip.weights_a, [1.0, 0.0, 0.0]);
    assert_eq!(ip.weights_b, [0.0, 1.0, 0.0]);
    // Collinear, b moving into a standing still (from b towards a: -x now).
    let a_still = [[-2.0, 0.0, 0.0], [-1.0, 0.0, 0.0]];
    let b_moving = [
        [[1.0, 0.0, 0.0], [3.0, 0.0, 0.0]],
        [[-1.5, 0.0, 0.0], [0.5, 0.0, 0.0]],
    ];
    let (_, ip) = judge_everywhere(
        Kind::EdgeEdge,
        &ee_pts([a_still, a_still], b_moving),
        &mut tally,
    );
    assert!(close(&ip.normal, &[-1.0, 0.0, 0.0], 1e-9), "{ip:?}");
    // An edge that is a point hitting an edge's middle from above.
    let p = [
        [[1.0, 0.0, 1.0], [1.0, 0.0, 1.0]],
        [[1.0, 0.0, -1.0], [1.0, 0.0, -1.0]],
    ];
    let (_, ip) = judge_everywhere(Kind::EdgeEdge, &ee_pts(p, [b, b]), &mut tally);
    assert!(close(&ip.normal, &[0.0, 0.0, 1.0], 1e-9), "{ip:?}");
    assert!(close(&ip.weights_b, &[0.5, 0.5, 0.0], 1e-12), "{ip:?}");
    eprintln!("edge-edge built: {tally:?}");
}

#[test]
fn coplanar_sliding() {
    let mut tally = Tally::default();
    // A vertex sliding in the triangle's plane into its long edge at (3, 1, 0).
    for wound in [true, false] {
        let v = [[5.0, 1.0, 0.0], [1.0, 1.0, 0.0]];
        let (toi, ip) = judge_everywhere(
            Kind::VertexFace,
            &vf_pts(v, flat_triangle(wound)),
            &mut tally,
        );
        assert!((toi.t - 0.5).abs() <= 1.0 / (1 << 20) as f64);
        // No side: the triangle's normal as wound.
        assert_eq!(ip.normal_from, NormalFrom::Features);
        assert_eq!(ip.normal, [0.0, 0.0, if wound { 1.0 } else { -1.0 }]);
        let mut w = ip.weights_b;
        if !wound {
            w.swap(1, 2);
        }
        assert!(close(&w, &[0.0, 0.75, 0.25], 1e-6), "{w:?}");
    }
    // Edges in one plane, a's end sliding into b's middle.
    let b = [[0.0, 0.0, 0.0], [0.0, 2.0, 0.0]];
    let a = [
        [[1.0, 1.0, 0.0], [3.0, 3.0, 0.0]],
        [[-1.0, 1.0, 0.0], [1.0, 3.0, 0.0]],
    ];
    let (_, ip) = judge_everywhere(Kind::EdgeEdge, &ee_pts(a, [b, b]), &mut tally);
    assert!(close(&ip.normal, &[0.0, 0.0, 1.0], 0.0) || close(&ip.normal, &[0.0, 0.0, -1.0], 0.0));
    // In the tilted plane x + y + z = 0, crossing edges.
    let tilt = |x: f64, y: f64| [x, y, -x - y];
    let b = [tilt(0.0, -1.0), tilt(0.0, 1.0)];
    let a = [
        [tilt(2.0, 0.0), tilt(3.0, 0.5)],
        [tilt(-1.0, 0.0), tilt(0.0, 0.5)],
    ];
    let (_, ip) = judge_everywhere(Kind::EdgeEdge, &ee_pts(a, [b, b]), &mut tally);
    let s = 1.0 / 3f64.sqrt();
    assert!(close(&ip.normal, &[s, s, s], 1e-12) || close(&ip.normal, &[-s, -s, -s], 1e-12));
    eprintln!("coplanar built: {tally:?}");
}

#[test]
fn degenerate_triangles() {
    let mut tally = Tally::default();
    // A segment (collinear corners) and a point, the vertex coming down onto them.
    let segment = [[0.0, 0.0, 0.0], [2.0, 0.0, 0.0], [4.0, 0.0, 0.0]];
    let point = [[1.0, 0.0, 0.0]; 3];
    for f in [segment, point] {
        let v = [[1.0, 0.0, 1.0], [1.0, 0.0, -1.0]];
        let (_, ip) = judge_everywhere(Kind::VertexFace, &vf_pts(v, [f, f]), &mut tally);
        assert_ne!(ip.normal_from, NormalFrom::Features);
        assert!(close(&ip.normal, &[0.0, 0.0, 1.0], 1e-9), "{ip:?}");
    }
    // A triangle collapsing to a segment as the vertex reaches it (degenerate at the
    // contact): the vertex comes in sideways, within the plane y = 0.
    let f = [
        [[0.0, 0.0, 0.0], [4.0, 0.0, 0.0], [2.0, 0.0, 2.0]],
        [[0.0, 0.0, 0.0], [4.0, 0.0, 0.0], [2.0, 0.0, -2.0]],
    ];
    let v = [[2.0, 1.0, 0.0], [2.0, -1.0, 0.0]];
    judge_everywhere(Kind::VertexFace, &vf_pts(v, f), &mut tally);
    eprintln!("degenerate built: {tally:?}");
}

#[test]
fn meeting_at_the_start_without_relative_motion() {
    let mut tally = Tally::default();
    // A vertex resting on a triangle, nothing moving: the triangle's normal as wound.
    let v = [[1.0, 1.0, 0.0]; 2];
    let (toi, ip) = judge_everywhere(
        Kind::VertexFace,
        &vf_pts(v, flat_triangle(true)),
        &mut tally,
    );
    assert!(toi.at_start);
    assert_eq!(
        (ip.normal, ip.normal_from),
        ([0.0, 0.0, 1.0], NormalFrom::Features)
    );
    // A vertex on a point triangle, both still or moving together: the last resort.
    for d in [[0.0; 3], [0.5, -0.25, 2.0]] {
        let p = [1.0, 2.0, 3.0];
        let q = [p[0] + d[0], p[1] + d[1], p[2] + d[2]];
        let (toi, ip) = judge_everywhere(
            Kind::VertexFace,
            &vf_pts([p, q], [[p; 3], [q; 3]]),
            &mut tally,
        );
        assert!(toi.at_start);
        assert_eq!(
            (ip.normal, ip.normal_from),
            ([0.0, 0.0, 1.0], NormalFrom::LastResort)
        );
        assert_eq!(ip.weights_b, [1.0, 0.0, 0.0]);
    }
    // Overlapping collinear edges, still.
    let a = [[0.0, 0.0, 0.0], [2.0, 0.0, 0.0]];
    let b = [[1.0, 0.0, 0.0], [3.0, 0.0, 0.0]];
    let (toi, ip) = judge_everywhere(Kind::EdgeEdge, &ee_pts([a, a], [b, b]), &mut tally);
    assert!(toi.at_start);
    assert_eq!(
        (ip.normal, ip.normal_from),
        ([0.0, 0.0, 1.0], NormalFrom::LastResort)
    );
    // Touching at the start, the vertex leaving: the feature normal turned against the
    // motion (a approaches from the side the normal points to; here it leaves upwards).
    let v = [[1.0, 1.0, 0.0], [1.0, 1.0, 1.0]];
    let (toi, ip) = judge_everywhere(
        Kind::VertexFace,
        &vf_pts(v, flat_triangle(true)),
        &mut tally,
    );
    assert!(toi.at_start);
    assert_eq!(ip.normal, [0.0, 0.0, -1.0]);
    eprintln!("at the start: {tally:?}");
}

// ---------------------------------------------------------------------------------------
// Random motions.

fn grid(rng: &mut Rng, n: i64, den: f64) -> f64 {
    (rng.below((2 * n + 1) as usize) as i64 - n) as f64 / den
}

fn grid_point(rng: &mut Rng, n: i64, den: f64) -> P3 {
    std::array::from_fn(|_| grid(rng, n, den))
}

/// A deforming motion: every point's start and end on a grid; some degenerate (a triangle
/// a segment, an edge a point, edges parallel), nearly so (`2^-30` off), or flat (in the
/// plane z = 0).
fn deforming(rng: &mut Rng) -> Points {
    let mut pts: Points =
        std::array::from_fn(|_| [grid_point(rng, 4, 4.0), grid_point(rng, 4, 4.0)]);
    let tiny = 1.0 / (1u64 << 30) as f64;
    let which = rng.below(8);
    match which {
        0 => {
            // Degenerate throughout: points 2 and 3 coincide (the triangle a segment, edge
            // b a point).
            pts[3] = pts[2];
        }
        1 | 4 => {
            // Parallel edges (a triangle's edge parallel to the vertex's... nothing in
            // particular), or (4) nearly: `2^-30` off.
            pts[3] = std::array::from_fn(|e| {
                std::array::from_fn(|k| pts[2][e][k] + 0.5 * (pts[1][e][k] - pts[0][e][k]))
            });
            if which == 4 {
                pts[3][0][rng.below(3)] += tiny;
                pts[3][1][rng.below(3)] += tiny;
            }
        }
        2 => {
            for p in pts.iter_mut().flatten() {
                p[2] = 0.0;
            }
        }
        3 => {
            // Nearly degenerate: a sliver triangle, a very short edge b.
            pts[3] = pts[2].map(|p| p.map(|x| x + tiny));
        }
        _ => {}
    }
    pts
}

#[test]
fn random_deforming_motions() {
    let mut rng = Rng(0x1a9c_7e0d);
    for kind in [Kind::VertexFace, Kind::EdgeEdge] {
        let mut tally = Tally::default();
        let mut tried = 0;
        while tally.cases < 1500 && tried < 200_000 {
            tried += 1;
            let pts = deforming(&mut rng);
            if decide(kind, &pts).0.is_some() {
                judge(kind, &pts, &mut tally);
                if tally.cases % 50 == 0 {
                    judge_in_frames(kind, &pts, &mut Tally::default(), false);
                }
            }
        }
        eprintln!("{kind:?} random ({tried} tried): {tally:?}");
        assert!(tally.cases >= 1500 && tally.approaching > 0 && tally.side_checked > 0);
    }
}

// ---------------------------------------------------------------------------------------
// The checker is a real one.

#[test]
fn the_checks_reject_broken_answers() {
    let flat = flat_triangle(true);
    let cases: Vec<(Kind, Points)> = vec![
        (
            Kind::VertexFace,
            vf_pts([[1.0, 1.0, 1.0], [1.0, 1.0, -3.0]], flat),
        ),
        (
            Kind::VertexFace,
            vf_pts([[5.0, 1.0, 1.0], [1.0, 1.0, -1.0]], flat),
        ),
        (
            Kind::EdgeEdge,
            ee_pts(
                [
                    [[-1.0, 0.5, 1.0], [1.0, 0.5, 1.0]],
                    [[-1.0, 0.5, -1.0], [1.0, 0.5, -1.0]],
                ],
                [[[0.0, -1.0, 0.0], [0.0, 1.0, 0.0]]; 2],
            ),
        ),
        (
            Kind::EdgeEdge,
            ee_pts(
                [
                    [[2.0, 0.0, 0.0], [3.0, 0.0, 0.0]],
                    [[0.5, 0.0, 0.0], [1.5, 0.0, 0.0]],
                ],
                [[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0]]; 2],
            ),
        ),
        (
            // Parallel edges side by side (a degenerate feature normal).
            Kind::EdgeEdge,
            ee_pts(
                [
                    [[0.5, 0.0, 1.0], [1.5, 0.0, 1.0]],
                    [[0.5, 0.0, -1.0], [1.5, 0.0, -1.0]],
                ],
                [[[0.0, 0.0, 0.0], [2.0, 0.0, 0.0]]; 2],
            ),
        ),
    ];
    for (kind, pts) in cases {
        let toi = decide(kind, &pts).0.expect("meets");
        let ip = geometry(kind, &pts, toi.t);
        check(kind, &pts, toi, &ip).expect("the answer passes");
        let broken = |f: &dyn Fn(&mut ImpactPoint)| {
            let mut b = ip;
            f(&mut b);
            b
        };
        let flipped = broken(&|b| b.normal = b.normal.map(|x| -x));
        assert!(check(kind, &pts, toi, &flipped).is_err(), "flipped {pts:?}");
        let unclamped = broken(&|b| {
            b.weights_b[0] -= 0.25;
            b.weights_b[1] += 0.25;
        });
        if unclamped.weights_b.iter().any(|w| !(0.0..=1.0).contains(w)) {
            assert!(check(kind, &pts, toi, &unclamped).is_err());
        }
        let unnormalized = broken(&|b| b.weights_b[0] *= 1.0 - f64::EPSILON);
        if ip.weights_b[0] != 0.0 {
            assert!(check(kind, &pts, toi, &unnormalized).is_err());
        }
        let elsewhere = broken(&|b| b.weights_b = [0.0, 0.0, 0.0]);
        assert!(check(kind, &pts, toi, &elsewhere).is_err());
        let off_corner = broken(&|b| {
            b.weights_b = if kind == Kind::VertexFace {
                [0.0, 0.0, 1.0]
            } else {
                [1.0, 0.0, 0.0]
            }
        });
        if off_corner.weights_b != ip.weights_b {
            assert!(
                check(kind, &pts, toi, &off_corner).is_err(),
                "{off_corner:?}"
            );
        }
        let tilted = broken(&|b| {
            b.normal = [b.normal[0] + 1e-3, b.normal[1], b.normal[2]];
            let l = b.normal.iter().map(|x| x * x).sum::<f64>().sqrt();
            b.normal = b.normal.map(|x| x / l);
        });
        if ip.normal_from == NormalFrom::Features {
            assert!(check(kind, &pts, toi, &tilted).is_err());
        }
        let long = broken(&|b| b.normal = b.normal.map(|x| 2.0 * x));
        assert!(check(kind, &pts, toi, &long).is_err());
    }
}
