//! Exact univariate polynomials in time over the integers, and the real algebraic numbers
//! they define: gcd and square-free part (primitive pseudo-remainders), Bernstein
//! coefficients on a rational interval, isolation of the roots in `[0, 1]` (Descartes'
//! rule in the Bernstein basis, de Casteljau subdivision at midpoints), and the exact sign
//! of a polynomial at such a root (a common factor found by the gcd means zero, else the
//! isolating interval is refined until the polynomial's Bernstein coefficients on it share
//! one sign). Two shortcuts in doubles, both checked exactly or enclosed: a root's interval
//! is narrowed to `2^-48` around a guess found in doubles once the exact signs at its new
//! ends confirm it, and a sign is first read from an interval evaluation there.
//!
//! Degrees here are at most 3 (the coplanarity cubic); nothing depends on it but speed.

use super::filter::Iv;
use num_bigint::BigInt;
use num_traits::{One, Signed, ToPrimitive, Zero};

/// An integer.
pub(super) type Int = BigInt;

/// A polynomial with integer coefficients, lowest degree first, with no trailing zero (the
/// zero polynomial has none).
#[derive(Clone, Debug, PartialEq, Eq)]
pub(super) struct Poly(pub(super) Vec<Int>);

/// The sign of an integer as `-1`, `0` or `1`.
#[inline]
pub(super) fn sign(x: &Int) -> i8 {
    if x.is_zero() {
        0
    } else if x.is_negative() {
        -1
    } else {
        1
    }
}

/// `gcd(|a|, |b|)` (Euclid).
fn int_gcd(a: &Int, b: &Int) -> Int {
    let (mut a, mut b) = (a.abs(), b.abs());
    while !b.is_zero() {
        let r = &a % &b;
        a = b;
        b = r;
    }
    a
}

/// The binomial coefficient `C(n, k)` for the small degrees used here.
fn binomial(n: usize, k: usize) -> i64 {
    (0..k).fold(1i64, |acc, i| acc * (n - i) as i64 / (i as i64 + 1))
}

impl Poly {
    /// The polynomial with these coefficients (trailing zeros dropped).
    pub(super) fn new(mut c: Vec<Int>) -> Poly {
        while c.last().is_some_and(Zero::is_zero) {
            c.pop();
        }
        Poly(c)
    }

    /// `a + b t`.
    pub(super) fn linear(a: Int, b: Int) -> Poly {
        Poly::new(vec![a, b])
    }

    /// Is this the zero polynomial?
    pub(super) fn is_zero(&self) -> bool {
        self.0.is_empty()
    }

    /// The degree (0 for the zero polynomial too: only used on nonzero ones).
    pub(super) fn degree(&self) -> usize {
        self.0.len().saturating_sub(1)
    }

    /// `self - o`.
    pub(super) fn sub(&self, o: &Poly) -> Poly {
        let n = self.0.len().max(o.0.len());
        let z = Int::zero();
        Poly::new(
            (0..n)
                .map(|i| self.0.get(i).unwrap_or(&z) - o.0.get(i).unwrap_or(&z))
                .collect(),
        )
    }

    /// `self + o`.
    pub(super) fn add(&self, o: &Poly) -> Poly {
        let n = self.0.len().max(o.0.len());
        let z = Int::zero();
        Poly::new(
            (0..n)
                .map(|i| self.0.get(i).unwrap_or(&z) + o.0.get(i).unwrap_or(&z))
                .collect(),
        )
    }

    /// `self o`.
    pub(super) fn mul(&self, o: &Poly) -> Poly {
        if self.is_zero() || o.is_zero() {
            return Poly(Vec::new());
        }
        let mut c = vec![Int::zero(); self.0.len() + o.0.len() - 1];
        for (i, a) in self.0.iter().enumerate() {
            if a.is_zero() {
                continue;
            }
            for (j, b) in o.0.iter().enumerate() {
                c[i + j] += a * b;
            }
        }
        Poly::new(c)
    }

    /// The derivative.
    fn derivative(&self) -> Poly {
        Poly::new(
            self.0
                .iter()
                .enumerate()
                .skip(1)
                .map(|(i, c)| c * Int::from(i))
                .collect(),
        )
    }

    /// The sign of the value at `n / d` (`d > 0`): of `sum c_i n^i d^(deg - i)`.
    pub(super) fn sign_at(&self, n: &Int, d: &Int) -> i8 {
        // Horner on the homogenized form.
        let mut acc = Int::zero();
        let mut dpow = Int::one();
        for c in self.0.iter().rev() {
            acc = acc * n + c * &dpow;
            dpow *= d;
        }
        sign(&acc)
    }

    /// The primitive part, leading coefficient made positive (the zero polynomial stays).
    fn primitive(mut self) -> Poly {
        let g = self.0.iter().fold(Int::zero(), |g, c| int_gcd(&g, c));
        if g.is_zero() {
            return self;
        }
        let g = if self.0.last().is_some_and(Signed::is_negative) {
            -g
        } else {
            g
        };
        for c in &mut self.0 {
            *c /= &g;
        }
        self
    }

    /// Pseudo-division by a nonzero `b`: `(q, r)` with `lc(b)^k self = q b + r`, `deg r <
    /// deg b`, for some `k >= 0`.
    fn pseudo_divide(&self, b: &Poly) -> (Poly, Poly) {
        let db = b.degree();
        let lb = b.0.last().expect("nonzero divisor");
        let mut r = self.clone();
        let mut q = Poly(Vec::new());
        while !r.is_zero() && r.degree() >= db {
            let shift = r.degree() - db;
            let lr = r.0.last().expect("nonzero").clone();
            // r = lb r - lr t^shift b, q = lb q + lr t^shift.
            let scale = |p: &Poly| Poly::new(p.0.iter().map(|c| c * lb).collect());
            let mut sb = vec![Int::zero(); shift];
            sb.extend(b.0.iter().map(|c| c * &lr));
            r = scale(&r).sub(&Poly::new(sb));
            let mut st = vec![Int::zero(); shift];
            st.push(lr);
            q = scale(&q).add(&Poly::new(st));
        }
        (q, r)
    }

    /// The polynomial divided by the largest power of two dividing every coefficient (cheap,
    /// where the full content's gcd is not: it keeps pseudo-remainders from growing by the
    /// common scale of the coordinates).
    fn without_twos(self) -> Poly {
        let z = self.0.iter().filter_map(|c| c.trailing_zeros()).min();
        match z {
            Some(z) if z > 0 => Poly(self.0.into_iter().map(|c| c >> z as usize).collect()),
            _ => self,
        }
    }

    /// A greatest common divisor (up to a constant factor; of two zero polynomials: zero).
    /// Degrees are small, so the pseudo-remainders' coefficients stay small enough without
    /// taking primitive parts at each step.
    pub(super) fn gcd(&self, o: &Poly) -> Poly {
        let (mut a, mut b) = (self.clone().without_twos(), o.clone().without_twos());
        if a.0.len() < b.0.len() {
            std::mem::swap(&mut a, &mut b);
        }
        while !b.is_zero() {
            let r = a.pseudo_divide(&b).1.without_twos();
            a = b;
            b = r;
        }
        a
    }

    /// The square-free part: the same real roots, each simple (nonzero `self`).
    pub(super) fn square_free(&self) -> Poly {
        let g = self.gcd(&self.derivative());
        if g.degree() == 0 {
            return self.clone().without_twos();
        }
        self.pseudo_divide(&g.primitive()).0.primitive()
    }

    /// The coefficients in the Bernstein basis of degree `deg` on `[lo / den, hi / den]`
    /// (`lo < hi`, `den > 0`), all times one positive factor: their signs bound the
    /// polynomial's on the interval (all positive: positive throughout), the first and the
    /// last are its values at the ends (times that factor).
    pub(super) fn bernstein(&self, lo: &Int, hi: &Int, den: &Int) -> Vec<Int> {
        let d = self.degree();
        // G(u) = den^d p((lo + w u) / den), w = hi - lo, in powers of u.
        let w = hi - lo;
        let mut g = vec![Int::zero(); d + 1];
        // (lo + w u)^i, and den^(d - i), built up.
        let mut pow = vec![Int::one()];
        let mut dens = vec![Int::one(); d + 1];
        for i in 1..=d {
            dens[i] = &dens[i - 1] * den;
        }
        for (i, c) in self.0.iter().enumerate() {
            if !c.is_zero() {
                let f = c * &dens[d - i];
                for (k, pk) in pow.iter().enumerate() {
                    g[k] += &f * pk;
                }
            }
            // pow *= (lo + w u).
            let mut next = vec![Int::zero(); pow.len() + 1];
            for (k, pk) in pow.iter().enumerate() {
                next[k] += pk * lo;
                next[k + 1] += pk * &w;
            }
            pow = next;
        }
        // b_k = sum_{i <= k} C(k, i) / C(d, i) g_i, times d!: C(d, i) divides d!.
        let fact: i64 = (1..=d as i64).product();
        (0..=d)
            .map(|k| {
                (0..=k).fold(Int::zero(), |acc, i| {
                    acc + &g[i] * Int::from(binomial(k, i) * (fact / binomial(d, i)))
                })
            })
            .collect()
    }
}

/// The coefficients enclosed in doubles, all divided by one power of two (which changes no
/// sign): each magnitude cut to its 62 leading bits of the largest, `[m, m + 1] 2^shift`.
fn coefficient_enclosures(p: &Poly) -> Vec<Iv> {
    let bits = p.0.iter().map(|c| c.bits()).max().unwrap_or(0);
    let shift = bits.saturating_sub(62);
    p.0.iter()
        .map(|c| {
            let m = (c.magnitude() >> shift).to_u64().expect("62 bits");
            // u64 to f64 rounds to nearest: one step out covers it.
            let (lo, hi) = ((m as f64).next_down().max(0.0), ((m + 1) as f64).next_up());
            if c.is_negative() {
                Iv { lo: -hi, hi: -lo }
            } else {
                Iv { lo, hi }
            }
        })
        .collect()
}

/// The polynomial's values over `t` (a subinterval of `[0, 1]`), enclosed, divided by a
/// positive power of two (Horner in interval arithmetic).
fn enclose(c: &[Iv], t: Iv) -> Iv {
    c.iter()
        .rev()
        .fold(Iv::point(0.0), |acc, &x| acc.mul(t).add(x))
}

/// `[lo / den, hi / den]` enclosed in doubles (within `2^-52`; `0 <= lo < hi <= den`).
fn time_enclosure(lo: &Int, hi: &Int, den: &Int) -> Iv {
    Iv {
        lo: floor_f64(lo, den),
        hi: (floor_f64(hi, den) + f64::powi(2.0, -52)).min(1.0),
    }
}

/// Sign variations of a sequence, zeros skipped.
fn variations(c: &[Int]) -> usize {
    let mut last = 0i8;
    let mut v = 0;
    for x in c {
        let s = sign(x);
        if s != 0 {
            if last != 0 && s != last {
                v += 1;
            }
            last = s;
        }
    }
    v
}

/// Bernstein coefficients (times one positive factor) of the two halves of their interval
/// (de Casteljau at the midpoint, sums in place of averages, then scaled to one factor).
fn split(b: &[Int]) -> (Vec<Int>, Vec<Int>) {
    let d = b.len() - 1;
    let mut rows = vec![b.to_vec()];
    for r in 1..=d {
        let prev = &rows[r - 1];
        let row: Vec<Int> = (0..=d - r).map(|i| &prev[i] + &prev[i + 1]).collect();
        rows.push(row);
    }
    let left = (0..=d).map(|i| &rows[i][0] << (d - i)).collect();
    let right = (0..=d).map(|i| &rows[d - i][i] << i).collect();
    (left, right)
}

/// A real algebraic number in `[0, 1]`: a rational `n / d` (`d > 0`), or the one root of
/// the square-free `s` strictly between `lo / den` and `hi / den`, where `s` has opposite
/// nonzero signs (`s_lo` at `lo`).
#[derive(Clone, Debug)]
pub(super) enum Alg {
    /// Exactly `n / d`.
    Rat { n: Int, d: Int },
    /// The root of `s` in `(lo / den, hi / den)`.
    Root {
        s: Poly,
        lo: Int,
        hi: Int,
        den: Int,
        s_lo: i8,
    },
}

impl Alg {
    /// Halves the isolating interval (a root found at the midpoint makes it rational).
    pub(super) fn refine(&mut self) {
        if let Alg::Root {
            s,
            lo,
            hi,
            den,
            s_lo,
        } = self
        {
            let mid = &*lo + &*hi;
            let den2: Int = &*den << 1;
            let sm = s.sign_at(&mid, &den2);
            if sm == 0 {
                *self = Alg::Rat { n: mid, d: den2 };
                return;
            }
            if sm == *s_lo {
                *lo = mid;
                *hi = &*hi << 1;
            } else {
                *lo = &*lo << 1;
                *hi = mid;
            }
            *den = den2;
        }
    }

    /// Narrows the isolating interval to about `2^-48` at once: the root found in doubles
    /// (bisection on the coefficients rounded), and the interval kept only where the exact
    /// signs at its ends confirm it. Nothing changes when they do not.
    pub(super) fn narrow(&mut self) {
        let Alg::Root {
            s,
            lo,
            hi,
            den,
            s_lo,
        } = self
        else {
            return;
        };
        const BITS: usize = 50;
        let one: Int = Int::one() << BITS;
        if *den >= one {
            return;
        }
        let c: Vec<f64> = coefficient_enclosures(s)
            .iter()
            .map(|x| 0.5 * x.lo + 0.5 * x.hi)
            .collect();
        let eval = |t: f64| c.iter().rev().fold(0.0, |acc, &x| acc * t + x);
        let t = time_enclosure(lo, hi, den);
        let (mut a, mut b) = (t.lo, t.hi);
        for _ in 0..60 {
            let m = 0.5 * (a + b);
            if m <= a || m >= b {
                break;
            }
            let v = eval(m);
            if v == 0.0 {
                (a, b) = (m, m);
                break;
            }
            if (v > 0.0) == (*s_lo > 0) {
                a = m;
            } else {
                b = m;
            }
        }
        // [k - 2, k + 2] 2^-BITS around the guess, inside the interval, signs confirmed.
        let k = Int::from((0.5 * (a + b) * (1u64 << BITS) as f64) as u64);
        let (na, nb) = (&k - 2, &k + 2);
        let scale = &one / &*den;
        if &scale * &*den != one || na < &*lo * &scale || nb > &*hi * &scale {
            return;
        }
        if s.sign_at(&na, &one) == *s_lo && s.sign_at(&nb, &one) == -*s_lo {
            (*lo, *hi, *den) = (na, nb, one);
        }
    }

    /// The exact sign of `g` at this number (refining the interval as needed).
    pub(super) fn sign_of(&mut self, g: &Poly) -> i8 {
        if g.is_zero() {
            return 0;
        }
        if g.degree() == 0 {
            return sign(&g.0[0]);
        }
        self.narrow();
        if let Alg::Root { lo, hi, den, .. } = self {
            // In doubles first: decided unless g nearly vanishes here.
            if let Some(v) = enclose(&coefficient_enclosures(g), time_enclosure(lo, hi, den))
                .sign()
                .filter(|&v| v != 0)
            {
                return v;
            }
        }
        let mut checked_gcd = false;
        loop {
            match self {
                Alg::Rat { n, d } => return g.sign_at(n, d),
                Alg::Root { s, lo, hi, den, .. } => {
                    let b = g.bernstein(lo, hi, den);
                    if b.iter().all(Signed::is_positive) {
                        return 1;
                    }
                    if b.iter().all(Signed::is_negative) {
                        return -1;
                    }
                    if !checked_gcd {
                        checked_gcd = true;
                        // A common factor with a root here: `g` vanishes at the root (the
                        // factor's roots are simple and among `s`'s, one of which is here).
                        let h = s.gcd(g);
                        if h.degree() > 0 && h.sign_at(lo, den) != h.sign_at(hi, den) {
                            return 0;
                        }
                    }
                }
            }
            self.refine();
        }
    }

    /// Refines until the interval is at most `2^-bits` wide; then the largest `f64` at or
    /// below its lower end: a lower bound of the number, within `2^-bits` (plus `2^-52`).
    pub(super) fn lower_bound(&mut self, bits: u32) -> f64 {
        self.narrow();
        loop {
            match self {
                Alg::Rat { n, d } => return floor_f64(n, d),
                Alg::Root { lo, hi, den, .. } => {
                    if (&*hi - &*lo) << bits as usize <= *den {
                        return floor_f64(lo, den);
                    }
                }
            }
            self.refine();
        }
    }

    /// Is this exactly 0?
    pub(super) fn is_zero(&self) -> bool {
        matches!(self, Alg::Rat { n, .. } if n.is_zero())
    }
}

/// The largest multiple of `2^-52` at or below `n / d`, for `0 <= n / d <= 1` (a double).
pub(super) fn floor_f64(n: &Int, d: &Int) -> f64 {
    let q: Int = (n << 52usize) / d;
    let q: u64 = q.try_into().expect("a time in [0, 1]");
    q as f64 * f64::powi(2.0, -52)
}

/// The distinct real roots in `[0, 1]` of a nonzero polynomial, in increasing order.
pub(super) fn roots_in_unit(p: &Poly) -> Vec<Alg> {
    let mut out = Vec::new();
    if p.degree() == 0 {
        return out;
    }
    let s = p.square_free();
    let one = Int::one();
    if s.degree() == 1 {
        // -a / b in [0, 1]: exact.
        let (mut n, mut d) = (-&s.0[0], s.0[1].clone());
        if d.is_negative() {
            n = -n;
            d = -d;
        }
        if !n.is_negative() && n <= d {
            out.push(Alg::Rat { n, d });
        }
        return out;
    }
    let zero = Int::zero();
    if s.0[0].is_zero() {
        out.push(Alg::Rat {
            n: zero.clone(),
            d: one.clone(),
        });
    }
    let b = s.bernstein(&zero, &one, &one);
    isolate(&s, b, zero, one.clone(), one.clone(), &mut out);
    if s.sign_at(&one, &one) == 0 {
        out.push(Alg::Rat {
            n: one.clone(),
            d: one,
        });
    }
    out
}

/// The roots of the square-free `s` strictly inside `(lo / den, hi / den)`, whose Bernstein
/// coefficients there are `b`, in increasing order.
fn isolate(s: &Poly, b: Vec<Int>, lo: Int, hi: Int, den: Int, out: &mut Vec<Alg>) {
    let v = variations(&b);
    if v == 0 {
        return;
    }
    let (first, last) = (sign(&b[0]), sign(&b[b.len() - 1]));
    if v == 1 && first != 0 && last != 0 {
        out.push(Alg::Root {
            s: s.clone(),
            lo,
            hi,
            den,
            s_lo: first,
        });
        return;
    }
    let (l, r) = split(&b);
    let mid = &lo + &hi;
    let den2: Int = den << 1;
    let mid_is_root = r[0].is_zero();
    isolate(s, l, lo << 1, mid.clone(), den2.clone(), out);
    if mid_is_root {
        out.push(Alg::Rat {
            n: mid.clone(),
            d: den2.clone(),
        });
    }
    isolate(s, r, mid, hi << 1, den2, out);
}
