//! The exact decision, in big integers.
//!
//! All 24 coordinates (four points, start and end) are scaled by one power of two into
//! integers (exact: every double is an integer times a power of two; a common scale changes
//! no incidence). Each coordinate is then a polynomial `x0 + t (x1 - x0)` with integer
//! coefficients, and so are the signs the static test asks for ([`super::predicate`]):
//! the coplanarity cubic `f` (the orientation of the four points), the 2D orientations
//! (quadratics) and the coordinate differences (linear).
//!
//! The set of times at which the primitives meet is closed, so when it is not empty it has
//! a least element, which is 0 or a time where some sign changes: a root of one of these
//! polynomials. Meeting needs coplanarity, so when `f` is not identically zero the
//! candidates are its (at most three) roots in `[0, 1]`; when it is (coplanar for the whole
//! step, or degenerate), they are 0 and the roots of the others. Each candidate is an
//! algebraic number (a rational, or a root isolated in a rational interval), and the
//! static test is decided there exactly ([`super::poly::Alg::sign_of`]). The earliest
//! meeting candidate gives the time of impact, as the lower end of an isolating interval
//! at most `2^-24` wide.

use super::poly::{roots_in_unit, Alg, Int, Poly};
use super::predicate::{meets, Kind, Signs};
use super::{Points, Toi};
use num_traits::Zero;

/// Bits of the isolating intervals a time of impact is read from (`2^-24`, well within the
/// promised `2^-20`).
const TOI_BITS: u32 = 24;

/// `x = m 2^e` with an integer `m` (0 for 0); also the band's exact stage's.
pub(super) fn decompose(x: f64) -> (i64, i32) {
    let bits = x.to_bits();
    let e = ((bits >> 52) & 0x7ff) as i32;
    let frac = (bits & ((1u64 << 52) - 1)) as i64;
    let (m, e) = if e == 0 {
        (frac, -1074)
    } else {
        (frac | 1i64 << 52, e - 1075)
    };
    (if x < 0.0 { -m } else { m }, e)
}

/// The motion as polynomials in `t`: `pos[i][axis]`.
pub(super) struct Motion {
    pos: [[Poly; 3]; 4],
}

impl Motion {
    /// The exact motion of these points (finite doubles).
    pub(super) fn new(pts: &Points) -> Motion {
        let parts = pts.map(|p| p.map(|x| x.map(decompose)));
        let emin = parts
            .iter()
            .flatten()
            .flatten()
            .filter(|(m, _)| *m != 0)
            .map(|&(_, e)| e)
            .min()
            .unwrap_or(0);
        let int = |(m, e): (i64, i32)| Int::from(m) << (e - emin) as usize;
        let pos = std::array::from_fn(|i| {
            std::array::from_fn(|ax| {
                let x0 = int(parts[i][0][ax]);
                let x1 = int(parts[i][1][ax]);
                let v = &x1 - &x0;
                Poly::linear(x0, v)
            })
        });
        Motion { pos }
    }

    /// `xj - xi` along `axis`.
    fn d(&self, i: usize, j: usize, axis: usize) -> Poly {
        self.pos[j][axis].sub(&self.pos[i][axis])
    }

    /// The 2D orientation of `i, j, k` in the plane without axis `plane`.
    fn o2(&self, i: usize, j: usize, k: usize, plane: usize) -> Poly {
        let (u, v) = ((plane + 1) % 3, (plane + 2) % 3);
        self.d(i, j, u)
            .mul(&self.d(i, k, v))
            .sub(&self.d(i, j, v).mul(&self.d(i, k, u)))
    }

    /// The coplanarity cubic `det(x1 - x0, x2 - x0, x3 - x0)`.
    pub(super) fn o3(&self) -> Poly {
        let e = |j: usize| [self.d(0, j, 0), self.d(0, j, 1), self.d(0, j, 2)];
        let (a, b, c) = (e(1), e(2), e(3));
        let minor = |r: usize, s: usize| b[r].mul(&c[s]).sub(&b[s].mul(&c[r]));
        a[0].mul(&minor(1, 2))
            .add(&a[1].mul(&minor(2, 0)))
            .add(&a[2].mul(&minor(0, 1)))
    }
}

/// The signs at one algebraic time.
struct AtTime<'a> {
    motion: &'a Motion,
    t: &'a mut Alg,
}

impl Signs for AtTime<'_> {
    fn o3(&mut self) -> Option<i8> {
        Some(self.t.sign_of(&self.motion.o3()))
    }
    fn o2(&mut self, i: usize, j: usize, k: usize, plane: usize) -> Option<i8> {
        Some(self.t.sign_of(&self.motion.o2(i, j, k, plane)))
    }
    fn d(&mut self, i: usize, j: usize, axis: usize) -> Option<i8> {
        Some(self.t.sign_of(&self.motion.d(i, j, axis)))
    }
}

/// Do the primitives meet at time `t`, where the four points are coplanar?
fn meets_at(kind: Kind, motion: &Motion, t: &mut Alg) -> bool {
    meets(kind, &mut AtTime { motion, t }, true).expect("exact signs decide")
}

/// The exact answer: the earliest meeting time (as [`Toi`] says), or `None`.
pub(super) fn decide(kind: Kind, pts: &Points) -> Option<Toi> {
    let motion = Motion::new(pts);
    let f = motion.o3();
    if !f.is_zero() {
        // Meeting needs coplanarity: only the roots of f, earliest first.
        for mut t in roots_in_unit(&f) {
            if meets_at(kind, &motion, &mut t) {
                return Some(toi_of(&mut t));
            }
        }
        return None;
    }
    // Coplanar for the whole step: 0 and every root of the other signs' polynomials.
    let mut polys = Vec::new();
    for plane in 0..3 {
        for (i, j, k) in [(0, 1, 2), (0, 1, 3), (0, 2, 3), (1, 2, 3)] {
            polys.push(motion.o2(i, j, k, plane));
        }
        for (i, j) in [(0, 1), (0, 2), (0, 3), (1, 2), (1, 3), (2, 3)] {
            polys.push(motion.d(i, j, plane));
        }
    }
    let mut cands = vec![Alg::Rat {
        n: Int::zero(),
        d: Int::from(1),
    }];
    for p in polys.iter().filter(|p| !p.is_zero()) {
        for r in roots_in_unit(p) {
            let dup = match &r {
                Alg::Rat { n, d } => cands
                    .iter()
                    .any(|c| matches!(c, Alg::Rat { n: n2, d: d2 } if n * d2 == n2 * d)),
                Alg::Root { .. } => false,
            };
            if !dup {
                cands.push(r);
            }
        }
    }
    // Lower bounds within 2^-TOI_BITS; the least over the meeting candidates is one of
    // the earliest meeting time. A candidate whose bound is no less than the best so far
    // cannot lower it.
    let mut keyed: Vec<(f64, Alg)> = cands
        .into_iter()
        .map(|mut c| (c.lower_bound(TOI_BITS), c))
        .collect();
    keyed.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut best: Option<Toi> = None;
    for (lb, mut t) in keyed {
        if best.is_some_and(|b| lb >= b.t) {
            break;
        }
        if meets_at(kind, &motion, &mut t) {
            let at_start = t.is_zero();
            best = Some(Toi {
                t: if at_start { 0.0 } else { lb },
                at_start,
            });
            if at_start {
                break;
            }
        }
    }
    best
}

/// The time of impact read from a meeting time `t`.
fn toi_of(t: &mut Alg) -> Toi {
    if t.is_zero() {
        Toi {
            t: 0.0,
            at_start: true,
        }
    } else {
        Toi {
            t: t.lower_bound(TOI_BITS),
            at_start: false,
        }
    }
}
