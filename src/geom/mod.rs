//! Geometry: boxes, exact predicates, the exact triangle test and viewing volumes.

pub mod contact;
pub mod predicates;
pub mod tritri;
pub mod volume;

pub use predicates::P3;

/// An axis-aligned box in `f32`, as the vertices are stored. Built only by `min`/`max` over
/// vertex coordinates, so it is exact: no rounding, no padding needed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Aabb {
    pub min: [f32; 3],
    pub max: [f32; 3],
}

impl Default for Aabb {
    fn default() -> Self {
        Aabb::EMPTY
    }
}

impl Aabb {
    /// The empty box (min = +inf, max = -inf); growing it by a point gives that point.
    pub const EMPTY: Aabb = Aabb {
        min: [f32::INFINITY; 3],
        max: [f32::NEG_INFINITY; 3],
    };

    /// Grows the box to hold `p` (plain comparisons: coordinates are finite here).
    #[inline]
    pub fn grow(&mut self, p: &[f32; 3]) {
        for k in 0..3 {
            self.min[k] = if p[k] < self.min[k] {
                p[k]
            } else {
                self.min[k]
            };
            self.max[k] = if p[k] > self.max[k] {
                p[k]
            } else {
                self.max[k]
            };
        }
    }

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

    /// Largest extent along any axis (0 for the empty box).
    pub fn extent(&self) -> f32 {
        (0..3)
            .map(|k| self.max[k] - self.min[k])
            .fold(0.0, f32::max)
    }

    pub fn is_empty(&self) -> bool {
        self.min[0] > self.max[0]
    }
}

/// Widen an `f32` point to `f64` (exact).
#[inline]
pub fn widen(p: &[f32; 3]) -> P3 {
    [f64::from(p[0]), f64::from(p[1]), f64::from(p[2])]
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
}
