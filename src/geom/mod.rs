//! Geometry: boxes, exact predicates, the exact triangle test, viewing volumes and the exact
//! primitive tests of continuous detection.

pub mod adjacent;
pub mod affine;
#[cfg(target_arch = "x86_64")]
pub(crate) mod batch;
pub mod ccd;
pub mod contact;
pub mod fan;
#[cfg(target_arch = "x86_64")]
pub(crate) mod lanes;
#[cfg(target_arch = "x86_64")]
pub(crate) mod lanes8;
pub mod patch;
pub mod polygon;
pub mod predicates;
pub mod sweep;
#[cfg(test)]
pub(crate) mod test_rng;
pub mod tritri;
#[cfg(test)]
pub(crate) mod union_depth;
pub mod volume;

pub use predicates::P3;

/// An axis-aligned box in `f32`, as the vertices are stored. Built by `min`/`max` over
/// vertex coordinates, so it is exact: no rounding, no padding needed; or, for a placed
/// mesh ([`affine`]), holding `f64` world positions with its bounds rounded outward (a
/// conservative box: culling only).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Aabb {
    /// Lower corner.
    pub min: [f32; 3],
    /// Upper corner.
    pub max: [f32; 3],
}

impl Default for Aabb {
    fn default() -> Self {
        Aabb::EMPTY
    }
}

impl Aabb {
    /// Every finite point.
    pub const EVERYTHING: Aabb = Aabb {
        min: [-f32::MAX; 3],
        max: [f32::MAX; 3],
    };

    /// The empty box (min = +inf, max = -inf); growing it by a point gives that point.
    pub const EMPTY: Aabb = Aabb {
        min: [f32::INFINITY; 3],
        max: [f32::NEG_INFINITY; 3],
    };

    /// Grows the box to hold `p` (plain comparisons: coordinates are finite here).
    #[inline]
    pub fn grow(&mut self, p: &[f32; 3]) {
        for ((lo, hi), &x) in self.min.iter_mut().zip(&mut self.max).zip(p) {
            *lo = if x < *lo { x } else { *lo };
            *hi = if x > *hi { x } else { *hi };
        }
    }

    /// Grows the box to hold `o`.
    #[inline]
    pub fn merge(&mut self, o: &Aabb) {
        for k in 0..3 {
            self.min[k] = self.min[k].min(o.min[k]);
            self.max[k] = self.max[k].max(o.max[k]);
        }
    }

    /// Do the closed boxes overlap once `self` is grown by `h` on every side? The
    /// differences of two `f32` are computed in `f64`; rounding is monotone and `-h` is a
    /// float, so an overlap is never lost (at worst a pair at exactly distance `h` is kept).
    #[inline]
    pub fn overlaps(&self, o: &Aabb, h: f64) -> bool {
        (0..3).all(|k| {
            f64::from(o.max[k]) - f64::from(self.min[k]) >= -h
                && f64::from(self.max[k]) - f64::from(o.min[k]) >= -h
        })
    }

    /// Do the closed boxes overlap? Exact (plain `f32` comparisons, all six combined with
    /// `&` so the test has no branches).
    #[inline]
    pub fn meets(&self, o: &Aabb) -> bool {
        (o.max[0] >= self.min[0])
            & (o.min[0] <= self.max[0])
            & (o.max[1] >= self.min[1])
            & (o.min[1] <= self.max[1])
            & (o.max[2] >= self.min[2])
            & (o.min[2] <= self.max[2])
    }

    /// The box grown by `h` on every side with its bounds rounded outward to `f32`. An
    /// `f32` box [`meets`](Aabb::meets) it exactly when `self.overlaps(box, h)`: a float is
    /// at least a real number exactly when it is at least the smallest float above that
    /// number.
    #[inline]
    pub fn grown(&self, h: f64) -> Aabb {
        if h == 0.0 {
            return *self;
        }
        Aabb {
            min: self.min.map(|x| f32_up(f64::from(x) - h)),
            max: self.max.map(|x| f32_down(f64::from(x) + h)),
        }
    }

    /// Largest extent along any axis (0 for the empty box).
    pub fn extent(&self) -> f32 {
        (0..3)
            .map(|k| self.max[k] - self.min[k])
            .fold(0.0, f32::max)
    }

    /// Is this the empty box (holding no point)?
    pub fn is_empty(&self) -> bool {
        self.min[0] > self.max[0]
    }
}

/// `a + b` as the rounded sum and its exact error (Knuth's two-sum; contact geometry's
/// error-free arithmetic and the continuous filter's rounding).
#[inline(always)]
pub(crate) fn two_sum(a: f64, b: f64) -> (f64, f64) {
    let s = a + b;
    let bb = s - a;
    (s, (a - (s - bb)) + (b - bb))
}

/// `a + b` rounded down (the continuous filters' interval ends).
#[inline(always)]
pub(crate) fn add_down(a: f64, b: f64) -> f64 {
    let (s, e) = two_sum(a, b);
    if e < 0.0 {
        s.next_down()
    } else {
        s
    }
}

/// `a + b` rounded up.
#[inline(always)]
pub(crate) fn add_up(a: f64, b: f64) -> f64 {
    let (s, e) = two_sum(a, b);
    if e > 0.0 {
        s.next_up()
    } else {
        s
    }
}

/// The smallest `f32` at or above `x` (not NaN); `+inf` above `f32::MAX`.
#[inline]
pub fn f32_up(x: f64) -> f32 {
    let f = x as f32;
    if f64::from(f) >= x {
        f
    } else if f == 0.0 {
        f32::from_bits(1)
    } else if f > 0.0 {
        f32::from_bits(f.to_bits() + 1)
    } else {
        // Negative (`-inf` included): one step towards zero.
        f32::from_bits(f.to_bits() - 1)
    }
}

/// The largest `f32` at or below `x` (not NaN); `-inf` below `-f32::MAX`.
#[inline]
pub fn f32_down(x: f64) -> f32 {
    -f32_up(-x)
}

/// An order-preserving map of `f32` to `u32` (not NaN): `a < b` exactly when
/// `sortable_key(a) < sortable_key(b)` (and `-0.0` sorts just before `0.0`), so sorting the
/// keys sorts the floats with integer comparisons.
#[inline]
pub fn sortable_key(x: f32) -> u32 {
    let u = x.to_bits();
    if u >> 31 == 1 {
        !u
    } else {
        u | 1 << 31
    }
}

/// Widen an `f32` point to `f64` (exact).
#[inline]
pub fn widen(p: &[f32; 3]) -> P3 {
    [f64::from(p[0]), f64::from(p[1]), f64::from(p[2])]
}

/// Asks for the cache lines of `items[i]` (when there is one) ahead of its use: a hint.
#[inline(always)]
pub(crate) fn prefetch_item<T>(items: &[T], i: usize) {
    #[cfg(target_arch = "x86_64")]
    if let Some(x) = items.get(i) {
        use std::arch::x86_64::{_mm_prefetch, _MM_HINT_T0};
        let at = std::ptr::from_ref(x).cast::<i8>();
        // SAFETY: a prefetch is a hint (no access, no fault); both addresses lie within
        // the item (its first and last byte).
        unsafe {
            _mm_prefetch::<_MM_HINT_T0>(at);
            _mm_prefetch::<_MM_HINT_T0>(at.add(std::mem::size_of::<T>().max(1) - 1));
        }
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = (items, i);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn box_overlap_is_closed_and_inflates() {
        let a = Aabb {
            min: [0.0; 3],
            max: [1.0; 3],
        };
        let touching = Aabb {
            min: [1.0, 0.0, 0.0],
            max: [2.0, 1.0, 1.0],
        };
        let gap = Aabb {
            min: [1.5, 0.0, 0.0],
            max: [2.0, 1.0, 1.0],
        };
        assert!(a.overlaps(&touching, 0.0));
        assert!(!a.overlaps(&gap, 0.0));
        assert!(a.overlaps(&gap, 0.5));
        assert!(!a.overlaps(&gap, 0.49));
    }

    #[test]
    fn tiny_gap_far_away_is_seen() {
        let x = 1.0e5f32;
        let next = f32::from_bits(x.to_bits() + 1);
        let a = Aabb {
            min: [0.0; 3],
            max: [x; 3],
        };
        let b = Aabb {
            min: [next, 0.0, 0.0],
            max: [2e5, 1.0, 1.0],
        };
        assert!(!a.overlaps(&b, 0.0));
        assert!(a.overlaps(&b, f64::from(next - x)));
    }

    #[test]
    fn outward_rounding_is_tight() {
        // The float just below a finite `f32` (as f64).
        let below = |f: f32| {
            let b = f.to_bits();
            f64::from(if f == 0.0 {
                -f32::from_bits(1)
            } else if f > 0.0 {
                f32::from_bits(b - 1)
            } else {
                f32::from_bits(b + 1)
            })
        };
        for x in [
            0.0, 1.0, -1.0, 0.1, -0.1, 1e-45, -1e-45, 1e-50, 3e38, -3e38, -1e300,
        ] {
            let (u, d) = (f32_up(x), f32_down(-x));
            assert!(f64::from(u) >= x && below(u) < x, "{x}");
            assert_eq!(d, -u, "{x}");
        }
        assert_eq!(f32_up(1e300), f32::INFINITY);
        assert_eq!(f32_up(-1e300), -f32::MAX);
        assert_eq!(f32_down(1e300), f32::MAX);
        assert_eq!(
            f32_up(f64::from(f32::MIN_POSITIVE) / 4.0),
            f32::MIN_POSITIVE / 4.0
        );
        assert_eq!(f32_up(1e-50), f32::from_bits(1));
        assert_eq!(f32_up(-1e-50), -0.0);
    }

    #[test]
    fn grown_boxes_keep_what_the_f64_test_keeps() {
        // Boxes at distances around h, near f32 ties: the f32 test against the rounded-out
        // box agrees with Aabb-style f64 arithmetic on every one.
        let mut s = 99u64;
        let mut rnd = || {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            (s >> 40) as f32 / (1u64 << 24) as f32
        };
        for h in [0.0, 1e-7, 0.3, 0.5, 1.0 / 3.0] {
            for _ in 0..20000 {
                let v = Aabb {
                    min: [rnd(), rnd(), rnd()],
                    max: [1.0 + rnd(), 1.0 + rnd(), 1.0 + rnd()],
                };
                let o = rnd() * 0.001;
                let c = Aabb {
                    min: v.max.map(|x| x + (h as f32) - 0.0005 + o),
                    max: v.max.map(|x| x + 2.0 + o),
                };
                let f64_test = (0..3).all(|k| {
                    f64::from(c.max[k]) >= f64::from(v.min[k]) - h
                        && f64::from(c.min[k]) <= f64::from(v.max[k]) + h
                });
                assert_eq!(v.grown(h).meets(&c), f64_test, "h = {h}");
            }
        }
    }
}
