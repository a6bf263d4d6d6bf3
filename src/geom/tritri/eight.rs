//! The exact triangle test of eight pairs at once, on a CPU with AVX-512F: the kernel of
//! [`super::four`] (the planes' filter of [`super::Plane::side`] with the same bound,
//! Guigue and Devillers' permutation by blends, Shewchuk's static filter on their two
//! orientations, or their exact zeros by a shared coordinate) on eight lanes of 512-bit
//! vectors, whose blends take mask registers. A
//! lane is decided only from signs that are certain, and every other lane (a vertex on or
//! near the other's plane, a flat triangle, an orientation within its error bound) is left
//! undecided, for the scalar exact test: so the answer is always the exact one, the same as
//! [`super::triangles_intersect`]'s. The operations of each lane are those of the four-lane
//! kernel (the same source, [`super::four::intersect_lanes`], over
//! [`crate::geom::lanes8::F8`]), so a pair is decided, or not, as there.
//!
//! Twice the pairs per instruction where the CPU executes 512-bit vectors at full width.
//! The early returns (a batch all apart by the planes) are rarer with eight pairs than with
//! four, which costs little: on the crumpled cloth of the benchmarks, 84% of the batches of
//! eight and 69% of those of four run the whole kernel.

use crate::geom::lanes::TriLanes;

/// Pair `l` is (lane `l` of `a`, lane `l` of `b`). Returns (decided, meets) as lane bit
/// masks, as [`super::four::intersect`] does: bit `l` of `decided` when lane `l`'s answer
/// was certain here, bit `l` of `meets` when, moreover, the closed triangles intersect.
/// Undecided lanes need the scalar exact test.
///
/// # Safety
/// The CPU has AVX-512F (and so AVX2 and FMA).
#[target_feature(enable = "avx2,fma,avx512f")]
pub(crate) unsafe fn intersect(a: &TriLanes<8>, b: &TriLanes<8>) -> (u32, u32) {
    // SAFETY: the caller's promise.
    let (ta, tb) = unsafe {
        (
            a.load::<crate::geom::lanes8::F8>(),
            b.load::<crate::geom::lanes8::F8>(),
        )
    };
    super::four::intersect_lanes(&ta, &tb)
}
