//! The independent reference: exact squared distances between convex hulls of rational
//! points, and from them the static test at a rational time and the exact meeting time of
//! primitives whose relative motion is a translation.
//!
//! It shares nothing with the library's test but the definitions: the distance is the least
//! over pairs of faces (subsets of the two point sets) of the distance between their
//! affine hulls, where the closest points (the normal equations, solved exactly) lie in both
//! faces; pairs whose equations are singular are skipped (a smaller pair attains the same
//! distance).

use super::super::Points;
use num_bigint::BigInt;
use num_rational::BigRational;
use num_traits::{One, Signed, Zero};

/// A rational.
pub type Q = BigRational;
/// A rational point.
pub type Q3 = [Q; 3];

/// A double, exactly.
pub fn q(x: f64) -> Q {
    Q::from_float(x).expect("finite")
}

/// `2^-k`.
pub fn inv_pow2(k: u32) -> Q {
    Q::new(BigInt::one(), BigInt::one() << k as usize)
}

fn dot(a: &Q3, b: &Q3) -> Q {
    &a[0] * &b[0] + &a[1] * &b[1] + &a[2] * &b[2]
}

fn sub(a: &Q3, b: &Q3) -> Q3 {
    [&a[0] - &b[0], &a[1] - &b[1], &a[2] - &b[2]]
}

/// Solves `g z = r` (a small square system), `None` when singular.
fn solve(mut g: Vec<Vec<Q>>, mut r: Vec<Q>) -> Option<Vec<Q>> {
    let n = r.len();
    for c in 0..n {
        let p = (c..n).find(|&i| !g[i][c].is_zero())?;
        g.swap(c, p);
        r.swap(c, p);
        for i in 0..n {
            if i != c && !g[i][c].is_zero() {
                let f = &g[i][c] / &g[c][c];
                let pivot = g[c].clone();
                for (x, p) in g[i].iter_mut().zip(&pivot).skip(c) {
                    *x -= &f * p;
                }
                let v = &f * &r[c];
                r[i] -= v;
            }
        }
    }
    Some((0..n).map(|i| &r[i] / &g[i][i]).collect())
}

/// Are `z` (with the implied first weight `1 - sum z`) the weights of a point of the face?
fn in_face(z: &[Q]) -> bool {
    let sum: Q = z.iter().fold(Q::zero(), |s, x| s + x);
    z.iter().all(|x| !x.is_negative()) && sum <= Q::one()
}

/// The squared distance between the convex hulls of `a` and `b` (nonempty).
pub fn dist2(a: &[Q3], b: &[Q3]) -> Q {
    let subsets = |n: usize| -> Vec<Vec<usize>> {
        (1u32..1 << n)
            .map(|m| (0..n).filter(|i| m >> i & 1 == 1).collect())
            .collect()
    };
    let mut best: Option<Q> = None;
    for sa in subsets(a.len()) {
        for sb in subsets(b.len()) {
            if sa.len() + sb.len() > 5 {
                continue;
            }
            let r = sub(&a[sa[0]], &b[sb[0]]);
            let mut cols: Vec<Q3> = sa[1..].iter().map(|&i| sub(&a[i], &a[sa[0]])).collect();
            cols.extend(sb[1..].iter().map(|&j| sub(&b[sb[0]], &b[j])));
            let m = cols.len();
            let g = (0..m)
                .map(|i| (0..m).map(|j| dot(&cols[i], &cols[j])).collect())
                .collect();
            let rhs = (0..m).map(|i| -dot(&cols[i], &r)).collect();
            let Some(z) = solve(g, rhs) else { continue };
            let (za, zb) = z.split_at(sa.len() - 1);
            if !in_face(za) || !in_face(zb) {
                continue;
            }
            let mut diff = r.clone();
            for (c, w) in cols.iter().zip(&z) {
                for k in 0..3 {
                    diff[k] += &c[k] * w;
                }
            }
            let d = dot(&diff, &diff);
            if d.is_zero() {
                return d;
            }
            if best.as_ref().is_none_or(|b| d < *b) {
                best = Some(d);
            }
        }
    }
    best.expect("point pairs always qualify")
}

/// The four points at rational time `t`.
pub fn at(pts: &Points, t: &Q) -> [Q3; 4] {
    std::array::from_fn(|i| {
        std::array::from_fn(|k| {
            let (x0, x1) = (q(pts[i][0][k]), q(pts[i][1][k]));
            &x0 + t * (&x1 - &x0)
        })
    })
}

/// The squared distance between the primitives at time `t` (`split`: how many of the
/// points are the first primitive's: 1 for a vertex, 2 for an edge).
pub fn dist2_at(pts: &Points, split: usize, t: &Q) -> Q {
    let p = at(pts, t);
    dist2(&p[..split], &p[split..])
}

/// An upper bound of how fast the distance between the primitives can change (sum of the
/// largest L1 motion of each side).
pub fn speed_bound(pts: &Points, split: usize) -> Q {
    let l1 = |i: usize| -> Q {
        (0..3).fold(Q::zero(), |s, k| {
            s + (q(pts[i][1][k]) - q(pts[i][0][k])).abs()
        })
    };
    let side = |r: std::ops::Range<usize>| r.map(l1).max().expect("nonempty");
    side(0..split) + side(split..4)
}

/// For primitives each moving by one translation: the exact meeting set's earliest time,
/// bracketed in `[lo, hi]` with `hi - lo <= 2^-bits` (`lo == hi == 0` when they meet at
/// the start), or `None` when they never meet. The meeting set is an interval (the
/// preimage of a convex set under an affine map of `t`), and they meet during `[0, m]`
/// exactly when the first primitive meets the hull of the second at 0 and at `m` relative
/// to it.
pub fn translated_first_meeting(pts: &Points, split: usize, bits: u32) -> Option<(Q, Q)> {
    let start: Vec<Q3> = (0..4)
        .map(|i| std::array::from_fn(|k| q(pts[i][0][k])))
        .collect();
    let vel = |i: usize| -> Q3 { std::array::from_fn(|k| q(pts[i][1][k]) - q(pts[i][0][k])) };
    for r in [0..split, split..4] {
        let v = vel(r.start);
        assert!(r.clone().all(|i| vel(i) == v), "not a translation");
    }
    translated_hulls_first_meeting(&start[..split], &vel(0), &start[split..], &vel(split), bits)
}

/// For the hulls of the points `a0` and `b0` moving by the translations `a0 + t va` and
/// `b0 + t vb`: the earliest meeting time bracketed as [`translated_first_meeting`]'s, or
/// `None`.
pub fn translated_hulls_first_meeting(
    a0: &[Q3],
    va: &Q3,
    b0: &[Q3],
    vb: &Q3,
    bits: u32,
) -> Option<(Q, Q)> {
    // The second's motion relative to the first.
    let u = sub(vb, va);
    let during = |m: &Q| -> bool {
        let mut b: Vec<Q3> = b0.to_vec();
        b.extend(b0.iter().map(|p| {
            let mut s = p.clone();
            for k in 0..3 {
                s[k] += m * &u[k];
            }
            s
        }));
        dist2(a0, &b).is_zero()
    };
    if dist2(a0, b0).is_zero() {
        return Some((Q::zero(), Q::zero()));
    }
    if !during(&Q::one()) {
        return None;
    }
    let (mut lo, mut hi) = (Q::zero(), Q::one());
    for _ in 0..bits {
        let mid = (&lo + &hi) / Q::from_integer(BigInt::from(2));
        if during(&mid) {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    Some((lo, hi))
}
