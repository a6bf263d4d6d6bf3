//! The floating-point filter: decides most queries in interval arithmetic, with every
//! rounding accounted for, and says when it cannot.
//!
//! Intervals are rounded outward (a sum is widened by one ulp only where it was inexact, as
//! the error-free sum tells; a product always, unless a factor is exactly 0), so an exact
//! zero stays an exact zero: positions that share a coordinate, or a planar motion in a
//! coordinate plane, keep their certain zero signs. Positions over a piece `T` of the step
//! lie in the hull of their (tightly enclosed) positions at its ends, and
//! [`super::predicate::meets`] is evaluated with the signs those enclose.
//!
//! * Swept boxes of the whole step apart (exact comparisons): apart.
//! * The coplanarity cubic, enclosed in the Bernstein basis on `[0, 1]` (its coefficients
//!   are determinants of the edge vectors at the start and the end), has its roots isolated
//!   by de Casteljau subdivision, earliest first: a piece whose coefficients all have one
//!   certain sign holds no root (never coplanar there); one whose certain signs vary once
//!   holds exactly one. That root is located in plain doubles and certified by the cubic's
//!   enclosed values `2^-22` either side (or, failing that, by bisecting the enclosed
//!   coefficients); on the certified piece the test once coplanar is certainly false (or the
//!   swept boxes are apart, or a projection onto a coordinate plane separates the
//!   primitives, [`super::predicate::separated`]): no meeting there; certainly true: they
//!   meet at the root, and the piece's start is a time of impact within `2^-20` (every
//!   earlier piece held no meeting).
//! * A cubic identically zero (every coefficient exactly 0): coplanar throughout; the step is
//!   bisected earliest first, a piece apart as above, or certainly meeting throughout: the
//!   time of impact is its start, exactly (`AT_START` when that is 0).
//!
//! The first piece left undecided (a root at a subdivision point or a double one, a sign
//! that is exactly 0 at the root, too deep, too many pieces) leaves the whole query to the
//! exact test.

use super::apart::{apart_along, apart_on_axes, cross, max_abs, sub};
use super::predicate::{meets, separated, Kind, Signs};
use super::{Points, Toi};
use crate::geom::P3;
use crate::geom::{add_down, add_up};

/// An interval `[lo, hi]` of reals.
#[derive(Clone, Copy, Debug)]
pub(super) struct Iv {
    pub(super) lo: f64,
    pub(super) hi: f64,
}

impl Iv {
    #[inline(always)]
    pub(super) fn point(x: f64) -> Iv {
        Iv { lo: x, hi: x }
    }
    #[inline(always)]
    pub(super) fn add(self, o: Iv) -> Iv {
        Iv {
            lo: add_down(self.lo, o.lo),
            hi: add_up(self.hi, o.hi),
        }
    }
    #[inline(always)]
    pub(super) fn sub(self, o: Iv) -> Iv {
        Iv {
            lo: add_down(self.lo, -o.hi),
            hi: add_up(self.hi, -o.lo),
        }
    }
    #[inline(always)]
    pub(super) fn mul(self, o: Iv) -> Iv {
        if (self.lo == 0.0 && self.hi == 0.0) || (o.lo == 0.0 && o.hi == 0.0) {
            return Iv::point(0.0);
        }
        let p = [
            self.lo * o.lo,
            self.lo * o.hi,
            self.hi * o.lo,
            self.hi * o.hi,
        ];
        let lo = p[0].min(p[1]).min(p[2]).min(p[3]);
        let hi = p[0].max(p[1]).max(p[2]).max(p[3]);
        // Each product is within half an ulp (or, underflowed, within the least subnormal).
        Iv {
            lo: lo.next_down(),
            hi: hi.next_up(),
        }
    }
    #[inline(always)]
    fn hull(self, o: Iv) -> Iv {
        Iv {
            lo: self.lo.min(o.lo),
            hi: self.hi.max(o.hi),
        }
    }
    /// The sign of every number inside, if one (NaN bounds: none).
    #[inline(always)]
    pub(super) fn sign(self) -> Option<i8> {
        if self.lo > 0.0 {
            Some(1)
        } else if self.hi < 0.0 {
            Some(-1)
        } else if self.lo == 0.0 && self.hi == 0.0 {
            Some(0)
        } else {
            None
        }
    }
}

/// Enclosures of the four points (over an instant or a piece of the step).
type Box4 = [[Iv; 3]; 4];

/// The signs enclosed by [`Box4`].
struct Enclosed<'a>(&'a Box4);

impl Enclosed<'_> {
    #[inline(always)]
    fn diff(&self, i: usize, j: usize, ax: usize) -> Iv {
        self.0[j][ax].sub(self.0[i][ax])
    }
    fn o3_iv(&self) -> Iv {
        let e = |j: usize| [self.diff(0, j, 0), self.diff(0, j, 1), self.diff(0, j, 2)];
        let (a, b, c) = (e(1), e(2), e(3));
        let minor = |r: usize, s: usize| b[r].mul(c[s]).sub(b[s].mul(c[r]));
        a[0].mul(minor(1, 2))
            .add(a[1].mul(minor(2, 0)))
            .add(a[2].mul(minor(0, 1)))
    }
}

impl Signs for Enclosed<'_> {
    fn o3(&mut self) -> Option<i8> {
        self.o3_iv().sign()
    }
    fn o2(&mut self, i: usize, j: usize, k: usize, plane: usize) -> Option<i8> {
        let (u, v) = ((plane + 1) % 3, (plane + 2) % 3);
        self.diff(i, j, u)
            .mul(self.diff(i, k, v))
            .sub(self.diff(i, j, v).mul(self.diff(i, k, u)))
            .sign()
    }
    fn d(&mut self, i: usize, j: usize, axis: usize) -> Option<i8> {
        self.diff(i, j, axis).sign()
    }
}

/// What the filter found.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum Verdict {
    /// Certainly never meet.
    Apart,
    /// Certainly meet; the time of impact.
    Meets(Toi),
    /// Left to the exact test.
    Undecided,
}

/// Coordinates beyond this (in magnitude) go to the exact test: products of three
/// differences stay far from overflow below it.
const MAX_COORD: f64 = 1e90;
/// Pieces of the step at most this deep while isolating the cubic's roots.
const MAX_ISOLATE_DEPTH: u32 = 12;
/// A root's interval is narrowed at most to this depth (`2^-24`).
const MAX_ROOT_DEPTH: u32 = 24;
/// A piece at most this long may certify a crossing (`2^-20`).
const TOI_DEPTH: u32 = 20;
/// Half the width of a root's certified interval (`2^-22`).
const ROOT_HALF_WIDTH: f64 = 1.0 / (1u32 << 22) as f64;
/// Pieces visited at most by the search of a step coplanar throughout.
const MAX_PIECES: u32 = 160;

/// `(a + b) / 2`, rounded outward.
#[inline(always)]
fn mid(a: Iv, b: Iv) -> Iv {
    let s = a.add(b);
    let h = Iv {
        lo: 0.5 * s.lo,
        hi: 0.5 * s.hi,
    };
    // Halving is exact unless it lands among the subnormals.
    if h.lo.abs() < f64::MIN_POSITIVE || h.hi.abs() < f64::MIN_POSITIVE {
        Iv {
            lo: h.lo.next_down(),
            hi: h.hi.next_up(),
        }
    } else {
        h
    }
}

/// Bernstein coefficients of the cubic on a piece, enclosed.
type Bern = [Iv; 4];

/// The coefficients on the two halves (de Casteljau at the midpoint).
fn split_bern(b: &Bern) -> (Bern, Bern) {
    let (b01, b12, b23) = (mid(b[0], b[1]), mid(b[1], b[2]), mid(b[2], b[3]));
    let (b012, b123) = (mid(b01, b12), mid(b12, b23));
    let m = mid(b012, b123);
    ([b[0], b01, b012, m], [m, b123, b23, b[3]])
}

/// The cubic at `t` from its Bernstein coefficients on `[0, 1]`, roughly (the enclosures'
/// midpoints, plain floats): only to guess where a root is.
fn eval_plain(b: &Bern, t: f64) -> f64 {
    let c = b.map(|x| 0.5 * x.lo + 0.5 * x.hi);
    let lerp = |a: f64, b: f64| a + t * (b - a);
    let (c01, c12, c23) = (lerp(c[0], c[1]), lerp(c[1], c[2]), lerp(c[2], c[3]));
    lerp(lerp(c01, c12), lerp(c12, c23))
}

/// The cubic at `t` from its Bernstein coefficients on `[0, 1]`, enclosed (de Casteljau).
fn eval_iv(b: &Bern, t: f64) -> Iv {
    let t = Iv::point(t);
    let lerp = |a: Iv, b: Iv| a.add(t.mul(b.sub(a)));
    let (c01, c12, c23) = (lerp(b[0], b[1]), lerp(b[1], b[2]), lerp(b[2], b[3]));
    lerp(lerp(c01, c12), lerp(c12, c23))
}

/// The certain signs of the coefficients (all nonzero), if they are.
fn certain_signs(b: &Bern) -> Option<[i8; 4]> {
    let mut s = [0i8; 4];
    for (s, x) in s.iter_mut().zip(b) {
        *s = match x.sign() {
            Some(v) if v != 0 => v,
            _ => return None,
        };
    }
    Some(s)
}

/// The filter's verdict on a query, looking only for meetings before `t_max` (in `(0, 1]`):
/// a query that first meets at `t_max` or later may answer Apart. (A caller that already
/// knows a meeting at `t_max` needs no later one: the continuous query's earliest primitive
/// pair of a polygon pair.)
pub(super) fn filter_before(kind: Kind, pts: &Points, t_max: f64) -> Verdict {
    let finite_small = pts.iter().flatten().flatten().all(|x| x.abs() <= MAX_COORD);
    if !finite_small {
        return Verdict::Undecided;
    }
    let split = match kind {
        Kind::VertexFace => 1,
        Kind::EdgeEdge => 2,
    };
    // Swept boxes, exactly (the whole step): most candidate pairs of a broad phase end here.
    let extents: Box4 = std::array::from_fn(|i| {
        std::array::from_fn(|ax| Iv {
            lo: pts[i][0][ax].min(pts[i][1][ax]),
            hi: pts[i][0][ax].max(pts[i][1][ax]),
        })
    });
    if swept_apart(&extents, split) || fixed_axes_apart(pts, split) {
        return Verdict::Apart;
    }
    let vel: [[Iv; 3]; 4] = std::array::from_fn(|i| {
        std::array::from_fn(|ax| Iv::point(pts[i][1][ax]).sub(Iv::point(pts[i][0][ax])))
    });
    let at = |t: f64| -> Box4 {
        std::array::from_fn(|i| {
            std::array::from_fn(|ax| {
                if t == 0.0 {
                    Iv::point(pts[i][0][ax])
                } else if t == 1.0 {
                    Iv::point(pts[i][1][ax])
                } else {
                    Iv::point(pts[i][0][ax]).add(Iv::point(t).mul(vel[i][ax]))
                }
            })
        })
    };
    let (p0, p1) = (at(0.0), at(1.0));
    let bern = cubic_bernstein(&p0, &p1);
    let mut search = Search {
        kind,
        whole: bern,
        split,
        pieces: 0,
        at: &at,
        t_max,
    };
    if bern.iter().all(|b| b.sign() == Some(0)) {
        // Coplanar throughout (exactly, as the enclosures show).
        return match search.piece(0.0, 1.0, &p0, &p1, 0) {
            Piece::Apart => Verdict::Apart,
            Piece::Meets(t) => Verdict::Meets(t),
            Piece::Undecided => Verdict::Undecided,
        };
    }
    match search.roots(&bern, 0.0, 1.0, 0) {
        Piece::Apart => Verdict::Apart,
        Piece::Meets(t) => Verdict::Meets(t),
        Piece::Undecided => Verdict::Undecided,
    }
}

/// Are the boxes of the points `0..split` and `split..4`, each point in `b`'s box, apart?
fn swept_apart(b: &Box4, split: usize) -> bool {
    (0..3).any(|ax| {
        let range = |r: std::ops::Range<usize>| {
            r.map(|i| b[i][ax])
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), x| {
                    (lo.min(x.lo), hi.max(x.hi))
                })
        };
        let (a, c) = (range(0..split), range(split..4));
        a.1 < c.0 || c.1 < a.0
    })
}

/// Are the points `0..split` and `split..4` apart for the whole step along a coordinate
/// axis or one of a few other fixed directions (the face's normals at both ends and its
/// edges' in-plane normals at the start; the edges' common normals at both ends, the
/// direction between their midpoints and each edge's perpendicular towards the other)?
/// See [`super::apart`]: separated at both ends of the step on the same side means apart
/// throughout, however far both move. Ends the pairs whose cubic has roots but which never
/// come near (nearly coplanar neighbours of a smooth mesh, parallel layers of cloth, a
/// body moving as a whole) before any root is looked for.
fn fixed_axes_apart(pts: &Points, split: usize) -> bool {
    let (a, b) = pts.split_at(split);
    if apart_on_axes(a, b, 0.0) {
        return true;
    }
    let maxabs = max_abs(a, b);
    let apart = |n: &P3| apart_along(n, a, b, maxabs, 0.0);
    let at = |i: usize, w: usize| &pts[i][w];
    let mid = |p: &P3, q: &P3| -> P3 { std::array::from_fn(|k| 0.5 * p[k] + 0.5 * q[k]) };
    if split == 1 {
        let normal = |w: usize| cross(&sub(at(2, w), at(1, w)), &sub(at(3, w), at(1, w)));
        let n0 = normal(0);
        apart(&n0)
            || apart(&normal(1))
            || (1..4).any(|j| {
                let k = if j == 3 { 1 } else { j + 1 };
                apart(&cross(&n0, &sub(at(k, 0), at(j, 0))))
            })
    } else {
        let edges = |w: usize| (sub(at(1, w), at(0, w)), sub(at(3, w), at(2, w)));
        let (ea, eb) = edges(0);
        let d = sub(&mid(at(2, 0), at(3, 0)), &mid(at(0, 0), at(1, 0)));
        let (ea1, eb1) = edges(1);
        apart(&cross(&ea, &eb))
            || apart(&cross(&ea1, &eb1))
            || apart(&d)
            || apart(&cross(&ea, &cross(&ea, &d)))
            || apart(&cross(&eb, &cross(&eb, &d)))
    }
}

/// Bernstein coefficients on `[0, 1]` of the coplanarity cubic `det(U, V, W)` (the edge
/// vectors from point 0, each linear in time), times 3: the determinant is multilinear, so
/// they are the (sums of) determinants of the vectors at the start and the end.
fn cubic_bernstein(p0: &Box4, p1: &Box4) -> Bern {
    let e = |p: &Box4, j: usize| -> [Iv; 3] { std::array::from_fn(|ax| p[j][ax].sub(p[0][ax])) };
    let (u, v, w) = (
        [e(p0, 1), e(p1, 1)],
        [e(p0, 2), e(p1, 2)],
        [e(p0, 3), e(p1, 3)],
    );
    // det(u, v, w) = u . (v x w), the four crosses shared.
    let cross = |b: &[Iv; 3], c: &[Iv; 3]| -> [Iv; 3] {
        std::array::from_fn(|r| {
            let (r1, r2) = ((r + 1) % 3, (r + 2) % 3);
            b[r1].mul(c[r2]).sub(b[r2].mul(c[r1]))
        })
    };
    let vw = [
        [cross(&v[0], &w[0]), cross(&v[0], &w[1])],
        [cross(&v[1], &w[0]), cross(&v[1], &w[1])],
    ];
    let det = |i: usize, j: usize, k: usize| {
        let (a, m) = (&u[i], &vw[j][k]);
        a[0].mul(m[0]).add(a[1].mul(m[1])).add(a[2].mul(m[2]))
    };
    let three = Iv::point(3.0);
    [
        three.mul(det(0, 0, 0)),
        det(1, 0, 0).add(det(0, 1, 0)).add(det(0, 0, 1)),
        det(1, 1, 0).add(det(1, 0, 1)).add(det(0, 1, 1)),
        three.mul(det(1, 1, 1)),
    ]
}

/// A piece's outcome.
enum Piece {
    Apart,
    Meets(Toi),
    Undecided,
}

/// The bisection's state.
struct Search<'a, F: Fn(f64) -> Box4> {
    kind: Kind,
    /// The cubic's Bernstein coefficients on `[0, 1]`.
    whole: Bern,
    split: usize,
    pieces: u32,
    at: &'a F,
    /// Meetings from this time on are not looked for (see [`filter_before`]).
    t_max: f64,
}

impl<F: Fn(f64) -> Box4> Search<'_, F> {
    /// The static test, once coplanar, over the piece `[ta, tb]`.
    fn coplanar_test(&self, ta: f64, tb: f64) -> Option<bool> {
        let (pa, pb) = ((self.at)(ta), (self.at)(tb));
        let hull: Box4 =
            std::array::from_fn(|i| std::array::from_fn(|ax| pa[i][ax].hull(pb[i][ax])));
        let mut s = Enclosed(&hull);
        // The static test first (it decides most pieces); the cheaper exclusions where not.
        match meets(self.kind, &mut s, true) {
            None if swept_apart(&hull, self.split) || separated(self.kind, &mut s) => Some(false),
            r => r,
        }
    }

    /// The piece `[ta, tb]` of a step whose cubic is not identically zero, its Bernstein
    /// coefficients `b`: its roots isolated (earliest first) and the test decided at each.
    fn roots(&mut self, b: &Bern, ta: f64, tb: f64, depth: u32) -> Piece {
        if ta >= self.t_max {
            // Every root here is at t_max or later.
            return Piece::Apart;
        }
        if let Some(s) = certain_signs(b) {
            if s.iter().all(|&x| x == s[0]) {
                // No root: never coplanar here.
                return Piece::Apart;
            }
            let variations = s.windows(2).filter(|w| w[0] != w[1]).count();
            if variations == 1
                && tb > self.t_max
                && eval_iv(&self.whole, self.t_max).sign() == Some(s[0])
            {
                // The one root is after t_max: the cubic still has its sign at ta there.
                return Piece::Apart;
            }
            if variations == 1 {
                // Exactly one root, simple, inside.
                return self.root(*b, ta, tb, depth);
            }
        }
        if depth >= MAX_ISOLATE_DEPTH {
            return Piece::Undecided;
        }
        let tm = 0.5 * (ta + tb);
        let (l, r) = split_bern(b);
        match self.roots(&l, ta, tm, depth + 1) {
            Piece::Apart => self.roots(&r, tm, tb, depth + 1),
            found => found,
        }
    }

    /// The piece `[ta, tb]` holding exactly one root of the cubic, inside, where the
    /// coefficients' end signs differ: narrowed around it until the test is decided there.
    fn root(&mut self, mut b: Bern, mut ta: f64, mut tb: f64, mut depth: u32) -> Piece {
        let s_lo = b[0].sign();
        // Where the root is, roughly (plain floats), then certified: the cubic's enclosed
        // values `2^-22` either side have the end signs, so the root is between them.
        let sign = s_lo.unwrap_or(0);
        let (mut lo, mut hi) = (ta, tb);
        for _ in 0..24 {
            let m = 0.5 * (lo + hi);
            let v = eval_plain(&self.whole, m);
            if v == 0.0 {
                break;
            }
            if (v > 0.0) == (sign > 0) {
                lo = m;
            } else {
                hi = m;
            }
        }
        let r = 0.5 * (lo + hi);
        let (ca, cb) = ((r - ROOT_HALF_WIDTH).max(ta), (r + ROOT_HALF_WIDTH).min(tb));
        if ca < cb
            && eval_iv(&self.whole, ca).sign() == s_lo
            && eval_iv(&self.whole, cb).sign() == Some(-sign)
        {
            match self.coplanar_test(ca, cb) {
                Some(false) => return Piece::Apart,
                Some(true) => {
                    return Piece::Meets(Toi {
                        t: ca,
                        at_start: false,
                    })
                }
                None => {}
            }
        }
        // Else by bisection of the enclosed coefficients.
        loop {
            if depth >= 6 && (depth % 7 == 6 || depth >= TOI_DEPTH) {
                match self.coplanar_test(ta, tb) {
                    Some(false) => return Piece::Apart,
                    Some(true) if depth >= TOI_DEPTH => {
                        return Piece::Meets(Toi {
                            t: ta,
                            at_start: false,
                        })
                    }
                    _ => {}
                }
            }
            if depth >= MAX_ROOT_DEPTH {
                return Piece::Undecided;
            }
            let (l, r) = split_bern(&b);
            let tm = 0.5 * (ta + tb);
            match l[3].sign() {
                Some(m) if m != 0 && Some(m) == s_lo => {
                    (b, ta) = (r, tm);
                }
                Some(m) if m != 0 => {
                    (b, tb) = (l, tm);
                }
                _ => return Piece::Undecided,
            }
            depth += 1;
        }
    }

    /// The piece `[ta, tb]` of a step coplanar throughout, the points enclosed at its ends
    /// by `pa`, `pb`: bisected, earliest first, until decided.
    fn piece(&mut self, ta: f64, tb: f64, pa: &Box4, pb: &Box4, depth: u32) -> Piece {
        if ta >= self.t_max {
            return Piece::Apart;
        }
        self.pieces += 1;
        let hull: Box4 =
            std::array::from_fn(|i| std::array::from_fn(|ax| pa[i][ax].hull(pb[i][ax])));
        let mut s = Enclosed(&hull);
        if swept_apart(&hull, self.split) || separated(self.kind, &mut s) {
            return Piece::Apart;
        }
        match meets(self.kind, &mut s, true) {
            Some(false) => return Piece::Apart,
            // Meeting throughout the piece: at its start.
            Some(true) => {
                return Piece::Meets(Toi {
                    t: ta,
                    at_start: ta == 0.0,
                })
            }
            None => {}
        }
        if depth >= MAX_ROOT_DEPTH || self.pieces >= MAX_PIECES {
            return Piece::Undecided;
        }
        let tm = 0.5 * (ta + tb);
        let pm = (self.at)(tm);
        match self.piece(ta, tm, pa, &pm, depth + 1) {
            Piece::Apart => self.piece(tm, tb, &pm, pb, depth + 1),
            found => found,
        }
    }
}
