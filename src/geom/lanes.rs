//! Four `f64` lanes in AVX2 registers (x86-64 only): the types the geometry kernels that
//! work on four triangle pairs at once are written with (`contact/four.rs`: contact
//! geometry; `tritri/four.rs`: the exact intersection test, `tritri/axis_plane.rs`: the
//! same for two triangles in one coordinate plane, and `volume/four.rs`: the band test,
//! where floating point certifies them). Every operation is one IEEE operation per lane
//! (no fused multiply-add unless asked for), so a kernel gives in each lane what the same
//! scalar code gives.
//!
//! Written with `std::arch` rather than arrays left to the compiler's vectorizer: an array
//! version of the contact kernel came out half scalar (shuffles and spills) and slower than
//! the scalar code it copies. A kernel must not use closures: a closure is compiled as its
//! own function, without AVX2, and every intrinsic in it then becomes a call.
//!
//! A kernel written for any lane width ([`crate::geom::tritri::four`]'s exact test and
//! [`crate::geom::tritri::axis_plane`]'s, which run on eight AVX-512 lanes too) is
//! written with the traits [`Float`] and [`Mask`], which these types and those of
//! [`super::lanes8`] implement, and with [`W`] and [`Plane`] over them.

use std::arch::x86_64::*;
use std::ops::{Add, Div, Mul, Neg, Sub};

use super::predicates::{drop_axis, P3};

/// Lanes per vector.
pub(crate) const LANES: usize = 4;

/// What a kernel written for any lane width asks of a vector of `f64` lanes ([`F`], or
/// [`super::lanes8::F8`]): each operation one IEEE operation per lane, the same whatever the
/// width, so the kernel gives the same lanes the same answers.
pub(crate) trait Float:
    Copy + Add<Output = Self> + Sub<Output = Self> + Mul<Output = Self> + Neg<Output = Self>
{
    /// Lanes per vector.
    const LANES: usize;
    /// The vector's lane masks.
    type Mask: Mask<Float = Self>;
    /// Another value under the type's invariant (so no promise needed): `x` in every lane.
    fn like(&self, x: f64) -> Self;
    fn abs(self) -> Self;
    /// `self < y` per lane (ordered: false where either is NaN).
    fn lt(self, y: Self) -> Self::Mask;
    /// `self > y` per lane (ordered).
    #[inline(always)]
    fn gt(self, y: Self) -> Self::Mask {
        y.lt(self)
    }
    /// `self == y` per lane (ordered: false where either is NaN).
    fn eq(self, y: Self) -> Self::Mask;
    /// `self > y ? self : y` per lane (`maxpd`: `y` where either is NaN).
    fn max(self, y: Self) -> Self;
    /// [`Float::LANES`] values from `row`.
    ///
    /// # Safety
    /// The CPU has the vector's instructions; `row` points to `LANES` `f64` aligned to the
    /// vector's size.
    unsafe fn load(row: *const f64) -> Self;
}

/// The lane masks of a [`Float`] (set or clear per lane).
pub(crate) trait Mask: Copy {
    /// The vectors whose lanes the mask selects.
    type Float: Float<Mask = Self>;
    fn and(self, o: Self) -> Self;
    fn or(self, o: Self) -> Self;
    /// Lanes where the two masks differ.
    fn xor(self, o: Self) -> Self;
    fn not(self) -> Self;
    /// Bit `l` set when lane `l` is.
    fn bits(self) -> u32;
    /// `if self { x } else { y }` per lane.
    fn sel(self, x: Self::Float, y: Self::Float) -> Self::Float;
    /// `if self { x } else { y }` per lane, of masks.
    fn selm(self, x: Self, y: Self) -> Self;

    /// `if self { x } else { y }` per lane, of 3-vectors.
    #[inline(always)]
    fn selw(self, x: &W<Self::Float>, y: &W<Self::Float>) -> W<Self::Float> {
        W {
            x: self.sel(x.x, y.x),
            y: self.sel(x.y, y.y),
            z: self.sel(x.z, y.z),
        }
    }
}

/// Four `f64` lanes. **Invariant**: a value of this type (or of [`M`]) exists only on a
/// CPU with AVX2 and FMA: the only ways to make one are `unsafe` functions whose callers
/// promise that, so the safe operations below may use those instructions.
#[derive(Clone, Copy)]
pub(crate) struct F(__m256d);

/// Four lane masks (all bits set or clear), under [`F`]'s invariant.
#[derive(Clone, Copy)]
pub(crate) struct M(__m256d);

impl F {
    /// # Safety
    /// The CPU has AVX2 and FMA.
    #[inline(always)]
    pub(crate) unsafe fn splat(x: f64) -> F {
        // SAFETY: the caller's promise.
        unsafe { F(_mm256_set1_pd(x)) }
    }

    /// # Safety
    /// The CPU has AVX2 and FMA.
    #[inline(always)]
    pub(crate) unsafe fn new(x: [f64; 4]) -> F {
        // SAFETY: the caller's promise; `x` holds four f64.
        unsafe { F(_mm256_loadu_pd(x.as_ptr())) }
    }

    /// Stores the four lanes at `p`.
    ///
    /// # Safety
    /// `p` is valid for writing four `f64`.
    #[inline(always)]
    pub(crate) unsafe fn store(&self, p: *mut f64) {
        // SAFETY: the caller's promise; the invariant.
        unsafe { _mm256_storeu_pd(p, self.0) }
    }

    /// `x < y ? x : y` per lane (`minpd`), the scalar path's `min`.
    #[inline(always)]
    pub(crate) fn min(self, y: F) -> F {
        // SAFETY: the invariant.
        unsafe { F(_mm256_min_pd(self.0, y.0)) }
    }

    /// `x > y ? x : y` per lane (`maxpd`), the scalar path's `max`.
    #[inline(always)]
    pub(crate) fn max(self, y: F) -> F {
        // SAFETY: the invariant.
        unsafe { F(_mm256_max_pd(self.0, y.0)) }
    }

    #[inline(always)]
    pub(crate) fn sqrt(self) -> F {
        // SAFETY: the invariant.
        unsafe { F(_mm256_sqrt_pd(self.0)) }
    }

    /// `self * b + c` rounded once.
    #[inline(always)]
    pub(crate) fn mul_add(self, b: F, c: F) -> F {
        // SAFETY: the invariant.
        unsafe { F(_mm256_fmadd_pd(self.0, b.0, c.0)) }
    }

    /// `+-1` with the sign of `self`.
    #[inline(always)]
    pub(crate) fn sign_one(self) -> F {
        // SAFETY: the invariant.
        unsafe {
            let sign = _mm256_and_pd(self.0, _mm256_set1_pd(-0.0));
            F(_mm256_or_pd(sign, _mm256_set1_pd(1.0)))
        }
    }

    #[inline(always)]
    pub(crate) fn le(self, y: F) -> M {
        // SAFETY: the invariant.
        unsafe { M(_mm256_cmp_pd::<_CMP_LE_OQ>(self.0, y.0)) }
    }

    #[inline(always)]
    pub(crate) fn ge(self, y: F) -> M {
        y.le(self)
    }
}

impl Float for F {
    const LANES: usize = LANES;
    type Mask = M;

    #[inline(always)]
    fn like(&self, x: f64) -> F {
        // SAFETY: `self` exists, so the CPU has AVX2 (the type's invariant).
        unsafe { F::splat(x) }
    }

    #[inline(always)]
    fn abs(self) -> F {
        // SAFETY: the invariant.
        unsafe { F(_mm256_andnot_pd(_mm256_set1_pd(-0.0), self.0)) }
    }

    #[inline(always)]
    fn lt(self, y: F) -> M {
        // SAFETY: the invariant.
        unsafe { M(_mm256_cmp_pd::<_CMP_LT_OQ>(self.0, y.0)) }
    }

    #[inline(always)]
    fn eq(self, y: F) -> M {
        // SAFETY: the invariant.
        unsafe { M(_mm256_cmp_pd::<_CMP_EQ_OQ>(self.0, y.0)) }
    }

    #[inline(always)]
    fn max(self, y: F) -> F {
        // SAFETY: the invariant.
        unsafe { F(_mm256_max_pd(self.0, y.0)) }
    }

    #[inline(always)]
    unsafe fn load(row: *const f64) -> F {
        // SAFETY: the caller's promise.
        unsafe { F(_mm256_load_pd(row)) }
    }
}

macro_rules! binary {
    ($tr:ident, $f:ident, $op:ident) => {
        impl $tr for F {
            type Output = F;
            #[inline(always)]
            fn $f(self, y: F) -> F {
                // SAFETY: the invariant.
                unsafe { F($op(self.0, y.0)) }
            }
        }
    };
}
binary!(Add, add, _mm256_add_pd);
binary!(Sub, sub, _mm256_sub_pd);
binary!(Mul, mul, _mm256_mul_pd);
binary!(Div, div, _mm256_div_pd);

impl Neg for F {
    type Output = F;
    #[inline(always)]
    fn neg(self) -> F {
        // SAFETY: the invariant.
        unsafe { F(_mm256_xor_pd(self.0, _mm256_set1_pd(-0.0))) }
    }
}

impl Mask for M {
    type Float = F;

    #[inline(always)]
    fn and(self, o: M) -> M {
        // SAFETY: the invariant.
        unsafe { M(_mm256_and_pd(self.0, o.0)) }
    }

    #[inline(always)]
    fn or(self, o: M) -> M {
        // SAFETY: the invariant.
        unsafe { M(_mm256_or_pd(self.0, o.0)) }
    }

    #[inline(always)]
    fn xor(self, o: M) -> M {
        // SAFETY: the invariant.
        unsafe { M(_mm256_xor_pd(self.0, o.0)) }
    }

    #[inline(always)]
    fn not(self) -> M {
        // SAFETY: the invariant.
        unsafe {
            M(_mm256_xor_pd(
                self.0,
                _mm256_castsi256_pd(_mm256_set1_epi64x(-1)),
            ))
        }
    }

    #[inline(always)]
    fn bits(self) -> u32 {
        // SAFETY: the invariant.
        unsafe { _mm256_movemask_pd(self.0) as u32 }
    }

    #[inline(always)]
    fn sel(self, x: F, y: F) -> F {
        // SAFETY: the invariant.
        unsafe { F(_mm256_blendv_pd(y.0, x.0, self.0)) }
    }

    #[inline(always)]
    fn selm(self, x: M, y: M) -> M {
        // SAFETY: the invariant.
        unsafe { M(_mm256_blendv_pd(y.0, x.0, self.0)) }
    }
}

/// One of three per lane: `x` where `m0`, else `y` where `m1`, else `z`.
#[inline(always)]
pub(crate) fn sel3(m0: M, m1: M, x: F, y: F, z: F) -> F {
    m0.sel(x, m1.sel(y, z))
}

#[inline(always)]
pub(crate) fn sel3w<T: Float>(m0: T::Mask, m1: T::Mask, x: &W<T>, y: &W<T>, z: &W<T>) -> W<T> {
    m0.selw(x, &m1.selw(y, z))
}

/// A 3-vector per lane (of four lanes unless said otherwise).
#[derive(Clone, Copy)]
pub(crate) struct W<T = F> {
    pub(crate) x: T,
    pub(crate) y: T,
    pub(crate) z: T,
}

impl<T: Float> W<T> {
    #[inline(always)]
    pub(crate) fn sub(&self, o: &W<T>) -> W<T> {
        W {
            x: self.x - o.x,
            y: self.y - o.y,
            z: self.z - o.z,
        }
    }

    /// `self + o * t` (nalgebra's `p + v * t`: the product rounded, then the sum).
    #[inline(always)]
    pub(crate) fn add_scaled(&self, o: &W<T>, t: T) -> W<T> {
        W {
            x: self.x + o.x * t,
            y: self.y + o.y * t,
            z: self.z + o.z * t,
        }
    }

    #[inline(always)]
    pub(crate) fn scale(&self, t: T) -> W<T> {
        W {
            x: self.x * t,
            y: self.y * t,
            z: self.z * t,
        }
    }

    /// nalgebra's `cross`, component by component.
    #[inline(always)]
    pub(crate) fn cross(&self, o: &W<T>) -> W<T> {
        W {
            x: self.y * o.z - self.z * o.y,
            y: self.z * o.x - self.x * o.z,
            z: self.x * o.y - self.y * o.x,
        }
    }

    /// nalgebra's `dot` for 3-vectors: `(x x' + y y') + z z'`.
    #[inline(always)]
    pub(crate) fn dot(&self, o: &W<T>) -> T {
        self.x * o.x + self.y * o.y + self.z * o.z
    }

    /// `self . |o|`.
    #[inline(always)]
    pub(crate) fn dot_abs(&self, o: &W<T>) -> T {
        self.x * o.x.abs() + self.y * o.y.abs() + self.z * o.z.abs()
    }

    #[inline(always)]
    pub(crate) fn norm_squared(&self) -> T {
        self.dot(self)
    }
}

impl W {
    /// The largest magnitude of a component.
    #[inline(always)]
    pub(crate) fn amax(&self) -> F {
        self.x.abs().max(self.y.abs()).max(self.z.abs())
    }
}

/// `N` triangles (four unless said otherwise) stored lane by lane (vertex, coordinate,
/// lane): what a kernel loads as [`W`]s with one aligned load per coordinate. Filled one
/// triangle at a time by whoever gathers the batch (each coordinate stored once, where the
/// kernel reads it), rather than as `[[P3; 3]; N]` copied into lanes through the stack.
/// Each row of `N` lanes starts at a multiple of `8 N` bytes from the start, which is
/// aligned to 64 bytes: a row of four or eight lanes is aligned for a 256-bit or 512-bit
/// load.
#[derive(Clone, Copy)]
#[repr(C, align(64))]
pub(crate) struct TriLanes<const N: usize = LANES>(pub(super) [[[f64; N]; 3]; 3]);

impl<const N: usize> TriLanes<N> {
    pub(crate) const ZERO: TriLanes<N> = TriLanes([[[0.0; N]; 3]; 3]);

    /// The triangles `t` in lanes.
    #[cfg(test)]
    pub(crate) fn of(t: &[[P3; 3]; N]) -> TriLanes<N> {
        let mut v = TriLanes::ZERO;
        for (l, t) in t.iter().enumerate() {
            v.set(l, t);
        }
        v
    }

    /// Lane `l`'s triangle becomes `t`.
    #[inline(always)]
    pub(crate) fn set(&mut self, l: usize, t: &[P3; 3]) {
        for (k, v) in t.iter().enumerate() {
            for (m, x) in v.iter().enumerate() {
                self.0[k][m][l] = *x;
            }
        }
    }

    /// Lane `l`'s triangle becomes `t` projected on the coordinate plane that drops axis
    /// `ax` (a triangle in that plane, as [`drop_axis`] projects it), its two coordinates
    /// as `x` and `y`; `z` is left as it was. For the kernels of pairs in one coordinate
    /// plane, which load `x` and `y` only.
    #[inline(always)]
    pub(crate) fn set_plane(&mut self, l: usize, t: &[P3; 3], ax: usize) {
        for (k, v) in t.iter().enumerate() {
            let [x, y] = drop_axis(v, ax);
            self.0[k][0][l] = x;
            self.0[k][1][l] = y;
        }
    }

    /// Lane `l`'s triangle.
    #[inline(always)]
    pub(crate) fn get(&self, l: usize) -> [P3; 3] {
        [0, 1, 2].map(|k| [self.0[k][0][l], self.0[k][1][l], self.0[k][2][l]])
    }

    /// Lane `l` becomes lane 0's triangle for every `l` from `n` on (padding: lanes whose
    /// answers are dropped).
    #[inline]
    pub(crate) fn pad(&mut self, n: usize) {
        let t = self.get(0);
        for l in n..N {
            self.set(l, &t);
        }
    }
}

impl<const N: usize> TriLanes<N> {
    /// The lanes as vectors of `V` (`N` lanes: checked at compile time).
    ///
    /// # Safety
    /// The CPU has `V`'s instructions (AVX2 and FMA for [`F`]; AVX-512F for
    /// [`super::lanes8::F8`]).
    #[inline(always)]
    pub(crate) unsafe fn load<V: Float>(&self) -> [W<V>; 3] {
        // (No closures: see the module's note.)
        // SAFETY: the caller's promise.
        unsafe { [self.vertex(0), self.vertex(1), self.vertex(2)] }
    }

    /// The lanes' `x` and `y` as vectors of `V`, per vertex (triangles stored by
    /// [`TriLanes::set_plane`]).
    ///
    /// # Safety
    /// As [`TriLanes::load`].
    #[inline(always)]
    pub(crate) unsafe fn load_plane<V: Float>(&self) -> [[V; 2]; 3] {
        const { assert!(V::LANES == N) };
        let v = &self.0;
        // SAFETY: the caller's promise; each row is `N` f64 aligned to `8 N` bytes (as in
        // `vertex`).
        unsafe {
            [
                [V::load(v[0][0].as_ptr()), V::load(v[0][1].as_ptr())],
                [V::load(v[1][0].as_ptr()), V::load(v[1][1].as_ptr())],
                [V::load(v[2][0].as_ptr()), V::load(v[2][1].as_ptr())],
            ]
        }
    }

    /// # Safety
    /// As [`TriLanes::load`].
    #[inline(always)]
    unsafe fn vertex<V: Float>(&self, k: usize) -> W<V> {
        const { assert!(V::LANES == N) };
        let v = &self.0[k];
        // SAFETY: the caller's promise; each row is `N` f64 aligned to `8 N` bytes (rows
        // at multiples of `8 N` bytes from the start, which the type aligns to 64, and
        // `8 N` divides 64).
        unsafe {
            W {
                x: V::load(v[0].as_ptr()),
                y: V::load(v[1].as_ptr()),
                z: V::load(v[2].as_ptr()),
            }
        }
    }
}

/// Four rows of four lanes, transposed: element `l` of the result is lane `l`'s four
/// values (row 0's first).
#[inline(always)]
pub(crate) fn transpose(r: [F; 4]) -> [F; 4] {
    // SAFETY: the invariant.
    unsafe {
        let t0 = _mm256_unpacklo_pd(r[0].0, r[1].0);
        let t1 = _mm256_unpackhi_pd(r[0].0, r[1].0);
        let t2 = _mm256_unpacklo_pd(r[2].0, r[3].0);
        let t3 = _mm256_unpackhi_pd(r[2].0, r[3].0);
        [
            F(_mm256_permute2f128_pd::<0x20>(t0, t2)),
            F(_mm256_permute2f128_pd::<0x20>(t1, t3)),
            F(_mm256_permute2f128_pd::<0x31>(t0, t2)),
            F(_mm256_permute2f128_pd::<0x31>(t1, t3)),
        ]
    }
}

/// Stores two `f64` at `p`.
///
/// # Safety
/// `p` is valid for writing two `f64`; the CPU has AVX2.
#[inline(always)]
pub(crate) unsafe fn store2(p: *mut f64, v: __m128d) {
    // SAFETY: the caller's promise.
    unsafe { _mm_storeu_pd(p, v) }
}

/// Two rows of four lanes, transposed: element `l` of the result is lane `l`'s two values
/// (row 0's first).
#[inline(always)]
pub(crate) fn transpose2(r0: F, r1: F) -> [__m128d; 4] {
    // SAFETY: the invariant.
    unsafe {
        let lo = _mm256_unpacklo_pd(r0.0, r1.0);
        let hi = _mm256_unpackhi_pd(r0.0, r1.0);
        [
            _mm256_castpd256_pd128(lo),
            _mm256_castpd256_pd128(hi),
            _mm256_extractf128_pd::<1>(lo),
            _mm256_extractf128_pd::<1>(hi),
        ]
    }
}

/// A triangle's plane per lane, as `tritri::Plane` and the contact fast path make it: a
/// vertex `o`, the edges `e = t1 - t0` and `f = t2 - t0`, the normal `n = e x f` (not
/// normalized) and, per component, the sum of the magnitudes of the two products behind it
/// (`perm`: the scale of its rounding error).
pub(crate) struct Plane<T = F> {
    pub(crate) o: W<T>,
    pub(crate) e: W<T>,
    pub(crate) f: W<T>,
    pub(crate) n: W<T>,
    pub(crate) perm: W<T>,
}

impl<T: Float> Plane<T> {
    #[inline(always)]
    pub(crate) fn of(t: &[W<T>; 3]) -> Plane<T> {
        let e = t[1].sub(&t[0]);
        let f = t[2].sub(&t[0]);
        Plane {
            o: t[0],
            e,
            f,
            n: e.cross(&f),
            perm: W {
                x: (e.y * f.z).abs() + (e.z * f.y).abs(),
                y: (e.z * f.x).abs() + (e.x * f.z).abs(),
                z: (e.x * f.y).abs() + (e.y * f.x).abs(),
            },
        }
    }

    /// `p`'s signed distance `n . (p - o)` (times `|n|`; of the sign opposite to
    /// `orient3d(t0, t1, t2, p)`) and the scale of its rounding error, `perm . |p - o|`.
    #[inline(always)]
    pub(crate) fn distance(&self, p: &W<T>) -> (T, T) {
        let w = p.sub(&self.o);
        (self.n.dot(&w), self.perm.dot_abs(&w))
    }
}
