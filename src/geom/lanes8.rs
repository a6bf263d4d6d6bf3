//! Eight `f64` lanes in AVX-512 registers (x86-64 only), with mask registers for the lane
//! masks: the [`Float`] and [`Mask`] of the kernels written for any lane width
//! ([`crate::geom::tritri::four`]'s exact test, which [`crate::geom::tritri::eight`] runs
//! on eight lanes, and [`crate::geom::tritri::axis_plane`]'s). Every operation is one IEEE
//! operation per lane, the same as on the four lanes of [`super::lanes`], so a kernel
//! gives each lane the same answer at either width. Only AVX-512F instructions are used. As in [`super::lanes`], a kernel must not use
//! closures (a closure is compiled without AVX-512, and every intrinsic in it then becomes
//! a call).

use std::arch::x86_64::*;
use std::ops::{Add, Mul, Neg, Sub};

use super::lanes::{Float, Mask};

/// Eight `f64` lanes. **Invariant**: a value of this type exists only on a CPU with
/// AVX-512F (and so AVX2 and FMA): the only ways to make one are `unsafe` functions whose
/// callers promise that, so the safe operations below may use those instructions.
#[derive(Clone, Copy)]
pub(crate) struct F8(__m512d);

/// Eight lane masks, a bit per lane (a mask register). Only [`F8`]'s comparisons make one,
/// so one exists only under [`F8`]'s invariant too.
#[derive(Clone, Copy)]
pub(crate) struct M8(__mmask8);

impl Float for F8 {
    const LANES: usize = 8;
    type Mask = M8;

    #[inline(always)]
    fn like(&self, x: f64) -> F8 {
        // SAFETY: `self` exists, so the CPU has AVX-512F (the type's invariant).
        unsafe { F8(_mm512_set1_pd(x)) }
    }

    #[inline(always)]
    fn abs(self) -> F8 {
        // SAFETY: the invariant.
        unsafe { F8(_mm512_abs_pd(self.0)) }
    }

    #[inline(always)]
    fn lt(self, y: F8) -> M8 {
        // SAFETY: the invariant.
        unsafe { M8(_mm512_cmp_pd_mask::<_CMP_LT_OQ>(self.0, y.0)) }
    }

    #[inline(always)]
    fn eq(self, y: F8) -> M8 {
        // SAFETY: the invariant.
        unsafe { M8(_mm512_cmp_pd_mask::<_CMP_EQ_OQ>(self.0, y.0)) }
    }

    #[inline(always)]
    fn max(self, y: F8) -> F8 {
        // SAFETY: the invariant.
        unsafe { F8(_mm512_max_pd(self.0, y.0)) }
    }

    #[inline(always)]
    unsafe fn load(row: *const f64) -> F8 {
        // SAFETY: the caller's promise.
        unsafe { F8(_mm512_load_pd(row)) }
    }
}

macro_rules! binary {
    ($tr:ident, $f:ident, $op:ident) => {
        impl $tr for F8 {
            type Output = F8;
            #[inline(always)]
            fn $f(self, y: F8) -> F8 {
                // SAFETY: the invariant.
                unsafe { F8($op(self.0, y.0)) }
            }
        }
    };
}
binary!(Add, add, _mm512_add_pd);
binary!(Sub, sub, _mm512_sub_pd);
binary!(Mul, mul, _mm512_mul_pd);

impl Neg for F8 {
    type Output = F8;
    /// The sign bit flipped (`-x`), by an integer xor (`_mm512_xor_pd` needs AVX-512DQ).
    #[inline(always)]
    fn neg(self) -> F8 {
        // SAFETY: the invariant.
        unsafe {
            let sign = _mm512_set1_epi64(i64::MIN);
            F8(_mm512_castsi512_pd(_mm512_xor_si512(
                _mm512_castpd_si512(self.0),
                sign,
            )))
        }
    }
}

impl Mask for M8 {
    type Float = F8;

    #[inline(always)]
    fn and(self, o: M8) -> M8 {
        M8(self.0 & o.0)
    }

    #[inline(always)]
    fn or(self, o: M8) -> M8 {
        M8(self.0 | o.0)
    }

    #[inline(always)]
    fn xor(self, o: M8) -> M8 {
        M8(self.0 ^ o.0)
    }

    #[inline(always)]
    fn not(self) -> M8 {
        M8(!self.0)
    }

    #[inline(always)]
    fn bits(self) -> u32 {
        u32::from(self.0)
    }

    #[inline(always)]
    fn sel(self, x: F8, y: F8) -> F8 {
        // SAFETY: the invariant (a mask exists only under it).
        unsafe { F8(_mm512_mask_blend_pd(self.0, y.0, x.0)) }
    }

    #[inline(always)]
    fn selm(self, x: M8, y: M8) -> M8 {
        M8((self.0 & x.0) | (!self.0 & y.0))
    }
}
