//! Many pairs at once ([`contact_geometry_many`]): triangle pairs gathered four at a time
//! into AVX2 lanes for the kernel of `four.rs` (compiled for AVX2, and for AVX-512 where
//! the CPU has it), and the lanes it leaves answered one by one.

use std::mem::MaybeUninit;

#[cfg(target_arch = "x86_64")]
use super::band::band_triangles;
#[cfg(target_arch = "x86_64")]
use super::contact_geometry_avx2;
#[cfg(target_arch = "x86_64")]
use super::four;
use super::{contact_geometry, ContactGeometry};
use crate::geom::predicates::P3;

/// Where [`contact_geometry_many`] reads its pairs' polygons: `fetch(i, [a0, a1], [b0,
/// b1])` writes pair `i`'s polygons as triangles (the first ones into `a0` and `b0`, a
/// quad's second into `a1` or `b1`) and returns how many each has, `(na, nb)` as
/// [`contact_geometry`] takes them. A closure of that signature is one; the scene's own
/// (the last answer's pairs, read from its meshes) is a type whose `fetch` is always
/// inlined into the loop (a closure may be compiled as a function called per pair).
pub trait PolygonPairs {
    /// What stops the call.
    type Error;
    /// Pair `i`'s triangles (see the trait).
    fn fetch(
        &mut self,
        i: usize,
        a: [&mut [P3; 3]; 2],
        b: [&mut [P3; 3]; 2],
    ) -> Result<(usize, usize), Self::Error>;
}

impl<E, F> PolygonPairs for F
where
    F: FnMut(usize, [&mut [P3; 3]; 2], [&mut [P3; 3]; 2]) -> Result<(usize, usize), E>,
{
    type Error = E;
    #[inline(always)]
    fn fetch(
        &mut self,
        i: usize,
        a: [&mut [P3; 3]; 2],
        b: [&mut [P3; 3]; 2],
    ) -> Result<(usize, usize), E> {
        self(i, a, b)
    }
}

#[cfg(any(test, feature = "internals"))]
/// A closure as [`PolygonPairs`] (this names the closure's argument types, which Rust
/// would not infer from the trait's blanket implementation).
pub fn polygon_pairs<E, F>(f: F) -> F
where
    F: FnMut(usize, [&mut [P3; 3]; 2], [&mut [P3; 3]; 2]) -> Result<(usize, usize), E>,
{
    f
}

#[cfg(any(test, feature = "internals"))]
/// [`contact_geometry`] of many polygon pairs, entry `i` of `out` for pair `i`, whose
/// triangles `fetch` writes (see [`PolygonPairs`]; an error stops the call and is
/// returned). `known`: every pair is known to intersect (decided by the exact test: the
/// pairs of a query at epsilon 0). The answers are
/// [`contact_geometry`]'s, bit for bit: triangle pairs are gathered four at a time and
/// computed together by the fast path written over lanes (`four.rs`: the same operations
/// on the same values, one AVX2 instruction for four pairs). When `known`, the exact test
/// is skipped; otherwise the four-lane exact test (`tritri::four`) picks the lanes that
/// certainly intersect. A lane that would need one of the fast path's rare branches, a
/// pair that does not intersect (a band pair) or is not decided in the lanes, and every
/// quad go through [`contact_geometry`] itself. (Were a pair wrongly `known`, it is still
/// answered exactly unless it misses by less than the rounding of its cuts: its planes'
/// sides or its cuts on their common line show it.)
pub fn contact_geometry_many<P: PolygonPairs>(
    out: &mut [ContactGeometry],
    known: bool,
    fetch: P,
) -> Result<(), P::Error> {
    // SAFETY: `MaybeUninit<T>` has `T`'s layout, and only initialized values are written
    // through the view.
    let out =
        unsafe { &mut *(out as *mut [ContactGeometry] as *mut [MaybeUninit<ContactGeometry>]) };
    contact_geometry_into(out, known, fetch)
}

/// [`contact_geometry_many`] into entries not initialized yet (a vector's spare capacity:
/// the scene's output is not written twice). When it returns `Ok`, every entry of `out`
/// is initialized; after an error, some may not be.
pub fn contact_geometry_into<P: PolygonPairs>(
    out: &mut [MaybeUninit<ContactGeometry>],
    known: bool,
    mut fetch: P,
) -> Result<(), P::Error> {
    #[cfg(target_arch = "x86_64")]
    if std::is_x86_feature_detected!("avx2") && std::is_x86_feature_detected!("fma") {
        // SAFETY: the CPU has AVX2 and FMA (checked just above).
        return unsafe { many_avx2(out, known, &mut fetch) };
    }
    // Without AVX2: one pair at a time.
    let _ = known;
    let ([mut a0, mut a1], [mut b0, mut b1]) = ([[[0.0; 3]; 3]; 2], [[[0.0; 3]; 3]; 2]);
    for (i, g) in out.iter_mut().enumerate() {
        let (na, nb) = fetch.fetch(i, [&mut a0, &mut a1], [&mut b0, &mut b1])?;
        g.write(contact_geometry(&[a0, a1], na, &[b0, b1], nb));
    }
    Ok(())
}

/// [`band_triangles`] compiled for AVX2 and FMA, out of line (as
/// [`contact_geometry_avx2`]).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
#[inline(never)]
pub(super) unsafe fn band_triangles_avx2(a: &[P3; 3], b: &[P3; 3]) -> ContactGeometry {
    band_triangles(a, b)
}

/// One batch of [`many_avx2`]: lane `l < n` is the pair `(a, b)` lane `l`, whose answer
/// goes to `out[at[l]]`; once padded, the other lanes repeat lane 0.
#[cfg(target_arch = "x86_64")]
type Batch = crate::geom::batch::Batch<usize, { four::LANES }>;

/// A batch's computation ([`flush`]) compiled for one instruction set.
#[cfg(target_arch = "x86_64")]
type Flush = unsafe fn(&Batch, bool, &mut [MaybeUninit<ContactGeometry>]);

/// [`contact_geometry_many`] on a CPU with AVX2 and FMA.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
unsafe fn many_avx2<P: PolygonPairs>(
    out: &mut [MaybeUninit<ContactGeometry>],
    known: bool,
    fetch: &mut P,
) -> Result<(), P::Error> {
    // The same kernel compiled for AVX-512 where the CPU has it: the same 256-bit
    // arithmetic (so the same answers; only copies of whole entries may use 512-bit
    // moves), with 32 vector registers instead of 16, which spares the kernel most of its
    // spills to the stack. (AVX-512 target features need Rust 1.89: Cargo.toml's
    // `rust-version`.)
    #[cfg(test)]
    let avx2_only = super::tests::AVX2_ONLY.with(|c| c.get());
    #[cfg(not(test))]
    let avx2_only = false;
    let flush: Flush = if std::is_x86_feature_detected!("avx512f")
        && std::is_x86_feature_detected!("avx512vl")
        && !avx2_only
    {
        flush_avx512
    } else {
        flush_avx2
    };
    let mut batch = Batch::new();
    // The pair being read (a quad's second triangles in `a1`, `b1`).
    let ([mut a0, mut a1], [mut b0, mut b1]) = ([[[0.0; 3]; 3]; 2], [[[0.0; 3]; 3]; 2]);
    for i in 0..out.len() {
        let (na, nb) = fetch.fetch(i, [&mut a0, &mut a1], [&mut b0, &mut b1])?;
        if na == 1 && nb == 1 {
            if batch.push(i, &a0, &b0) {
                // SAFETY: this function runs only on a CPU with AVX2 and FMA (and the
                // AVX-512 kernel where it has AVX-512 too).
                unsafe { flush(&batch, known, out) };
                batch.n = 0;
            }
        } else {
            // SAFETY: this function runs only on a CPU with AVX2 and FMA.
            out[i].write(unsafe { contact_geometry_avx2(&[a0, a1], na, &[b0, b1], nb) });
        }
    }
    if batch.n > 0 {
        batch.pad();
        // SAFETY: as above.
        unsafe { flush(&batch, known, out) };
    }
    Ok(())
}

/// [`flush`] compiled for the target features `$features` (one wrapper per instruction
/// set the kernel is built for; the body is inlined into each).
macro_rules! flush_for {
    ($name:ident, $features:literal, $doc:literal) => {
        #[doc = $doc]
        #[cfg(target_arch = "x86_64")]
        #[target_feature(enable = $features)]
        unsafe fn $name(batch: &Batch, known: bool, out: &mut [MaybeUninit<ContactGeometry>]) {
            // SAFETY: the caller's promise.
            unsafe { flush(batch, known, out) }
        }
    };
}

flush_for!(flush_avx2, "avx2,fma", "[`flush`] for AVX2 and FMA.");
flush_for!(
    flush_avx512,
    "avx2,fma,avx512f,avx512vl",
    "[`flush`] for AVX-512 (F and VL: 32 vector registers, mask registers for the blends)."
);

/// One batch of [`many_avx2`]: the kernel on the lanes, and the lanes it leaves one by
/// one.
///
/// # Safety
/// The CPU has AVX2 and FMA; the caller is compiled for them; `batch.at[l]` is in `out`
/// for `l < batch.n`.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
unsafe fn flush(batch: &Batch, known: bool, out: &mut [MaybeUninit<ContactGeometry>]) {
    let Batch { a, b, at, n } = batch;
    // SAFETY: the caller's promise.
    let (ta, tb) = unsafe { (a.load(), b.load()) };
    // The lanes that intersect: all when known, else those the exact test's lanes
    // certify.
    let (crossing, apart) = if known {
        (u32::MAX, 0)
    } else {
        // SAFETY: the caller's promise.
        let (decided, meets) = unsafe { crate::geom::tritri::four::intersect_loaded(&ta, &tb) };
        (decided & meets, decided & !meets)
    };
    // No crossing lane (a batch of band pairs): no geometry kernel.
    let lanes = (1 << n) - 1;
    let answered = if crossing & lanes != 0 {
        // SAFETY: the caller's promise.
        unsafe { four::crossing(&ta, &tb, crossing & lanes, at, out) }
    } else {
        0
    };
    for l in 0..*n {
        if answered & crossing & (1 << l) != 0 {
            continue;
        }
        let g = &mut out[at[l]];
        let (ta, tb) = (a.get(l), b.get(l));
        if apart & (1 << l) != 0 {
            // Decided apart: what `contact_geometry` does once its own exact test has
            // found the triangles apart (the only way it answers a pair that does not
            // intersect), without that test.
            // SAFETY: the caller's promise.
            g.write(unsafe { band_triangles_avx2(&ta, &tb) });
        } else {
            // SAFETY: the caller's promise.
            g.write(unsafe { contact_geometry_avx2(&[ta; 2], 1, &[tb; 2], 1) });
        }
    }
}
