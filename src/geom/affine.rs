//! Rigid (or affine) placement of a mesh: a row-major 3x4 matrix `m`, a vertex `(x, y, z)`
//! of the mesh's own frame sits at the world position `m * (x, y, z, 1)`.
//!
//! World positions are `f64`, each coordinate evaluated as
//! `m[r*4+0]*x + m[r*4+1]*y + m[r*4+2]*z + m[r*4+3]`, left to right, every product and sum
//! rounded on its own ([`Affine::apply`]). Rust never contracts a multiply and an add into a
//! fused multiply-add unless asked (`mul_add`), so this is the same double on every machine
//! and every build: the exact tests of the query run on it.
//!
//! Boxes follow the matrix without touching the vertices: [`Affine::world_box`] carries a
//! local `f32` box to a world `f32` box that holds every world position of every point of the
//! local box, as computed above (interval arithmetic, padded for its own rounding and the
//! rounding of [`Affine::apply`], rounded outward to `f32`). Such boxes are looser than
//! boxes fitted to the world positions (a rotated box's box), which only costs culling.

use super::{Aabb, P3};

/// A placement matrix, row-major 3x4, every entry finite.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Affine(pub [f64; 12]);

/// Relative padding of [`Affine::world_box`], against the sum `S` of the magnitudes of a
/// world coordinate's terms. The box's own centre, half extent and bounds carry a few
/// roundings of 2^-53 S; [`Affine::apply`]'s result is within 2^-51 S of the exact value;
/// the final rounding to `f32` moves a bound by at most 2^-24 of its magnitude (<= S) plus
/// half the smallest subnormal step. 2^-21 S (plus [`TINY`]) covers all of it with room.
const PAD: f64 = 1.0 / (1u64 << 21) as f64;

/// Absolute padding: the `f32` subnormal step (2^-149) twice over, and products rounded
/// in the `f64` subnormal range.
const TINY: f64 = 2.0 * 1.401_298_464_324_817e-45;

/// The identity: `m * p = p` exactly.
pub(crate) const IDENTITY: [f64; 12] = [1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0];

impl Affine {
    /// The world position of local point `p` (see the module's documentation: this exact
    /// order of operations, no fused multiply-add).
    #[inline]
    pub fn apply(&self, p: &[f32; 3]) -> P3 {
        self.apply_f64(&[f64::from(p[0]), f64::from(p[1]), f64::from(p[2])])
    }

    /// The world position of the local double point `p` (an f64 mesh's vertex): the same
    /// operations as [`Affine::apply`], which widens a float point to this.
    #[inline]
    pub fn apply_f64(&self, p: &P3) -> P3 {
        let m = &self.0;
        let (x, y, z) = (p[0], p[1], p[2]);
        let row = |r: usize| {
            let a = m[r * 4] * x;
            let b = m[r * 4 + 1] * y;
            let c = m[r * 4 + 2] * z;
            ((a + b) + c) + m[r * 4 + 3]
        };
        [row(0), row(1), row(2)]
    }

    /// Is this exactly the identity (whose world positions are the local ones)?
    pub fn is_identity(&self) -> bool {
        self.0 == IDENTITY
    }

    /// The index of the first entry that is NaN or infinite.
    pub fn first_non_finite(m: &[f64; 12]) -> Option<usize> {
        m.iter().position(|x| !x.is_finite())
    }

    /// Per world axis, an upper bound of the magnitude of every world coordinate of every
    /// point of local box `b` as [`Affine::apply`] computes it:
    /// `|m0| X + |m1| Y + |m2| Z + |t|` with `X` the largest magnitude along local x (and so
    /// on), evaluated in the order of `apply` (rounding is monotone, so it bounds `apply`'s
    /// rounded result; `+inf` when it overflows `f64`).
    pub fn magnitude_bound(&self, b: &Aabb) -> [f64; 3] {
        let big = |k: usize| f64::from(b.min[k].abs().max(b.max[k].abs()));
        let (x, y, z) = (big(0), big(1), big(2));
        let m = &self.0;
        [0, 1, 2].map(|r| {
            ((m[r * 4].abs() * x + m[r * 4 + 1].abs() * y) + m[r * 4 + 2].abs() * z)
                + m[r * 4 + 3].abs()
        })
    }

    /// A world `f32` box holding the world position ([`Affine::apply`]) of every point of
    /// the non-empty local box `b`. Needs [`Affine::magnitude_bound`] of `b` finite.
    ///
    /// Centre and half extent: `c' = m c + t`, `e' = |m| e`, bounds `c' -+ (e' + pad)`,
    /// then converted to `f32` by plain rounding: `pad` ([`PAD`] of the magnitude of the
    /// terms, about four `f32` steps) covers every rounding of this computation, of
    /// [`Affine::apply`] and of the conversion, so no branch is needed (see the test).
    #[inline]
    pub fn world_box(&self, b: &Aabb) -> Aabb {
        let m = &self.0;
        let c = [0, 1, 2].map(|k| (f64::from(b.min[k]) + f64::from(b.max[k])) * 0.5);
        let e = [0, 1, 2].map(|k| (f64::from(b.max[k]) - f64::from(b.min[k])) * 0.5);
        let mut out = Aabb::EMPTY;
        for r in 0..3 {
            let row = [m[r * 4], m[r * 4 + 1], m[r * 4 + 2]];
            let cw = ((row[0] * c[0] + row[1] * c[1]) + row[2] * c[2]) + m[r * 4 + 3];
            let ew = (row[0].abs() * e[0] + row[1].abs() * e[1]) + row[2].abs() * e[2];
            // Every term's magnitude: |m| (|c| + e) + |t| >= the largest |world| of the box.
            let mag = ((row[0].abs() * c[0].abs() + row[1].abs() * c[1].abs())
                + row[2].abs() * c[2].abs())
                + ew
                + m[r * 4 + 3].abs();
            let reach = ew + (mag * PAD + TINY);
            out.min[r] = (cw - reach) as f32;
            out.max[r] = (cw + reach) as f32;
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    use crate::geom::test_rng::Rng;

    #[test]
    fn apply_rounds_each_operation_in_order() {
        // 0.1 * 3 + 0.2 * 3: the rounded products summed, then rounded (no FMA, no
        // reassociation). With FMA the first product would not be rounded.
        let a = Affine([0.1, 0.2, 0.0, 1e-17, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0]);
        let w = a.apply(&[3.0, 3.0, 0.0]);
        let want = ((0.1f64 * 3.0 + 0.2f64 * 3.0) + 0.0 * 0.0) + 1e-17;
        assert_eq!(w[0].to_bits(), want.to_bits());
        assert!(Affine(IDENTITY).is_identity());
        let p = [1.5e-30f32, -3.25e30, 7.0];
        assert_eq!(Affine(IDENTITY).apply(&p), p.map(f64::from));
    }

    #[test]
    fn world_boxes_hold_every_world_point() {
        let mut r = Rng(12345);
        for round in 0..6000 {
            let wild = round >= 2000;
            let scale = if wild {
                10f64.powf(r.unit() * 40.0 - 20.0)
            } else {
                [1e-4, 1.0, 1e4, 1e5][round % 4]
            };
            let mut m = [0.0; 12];
            for e in &mut m {
                *e = (r.unit() * 2.0 - 1.0)
                    * if wild {
                        10f64.powf(r.unit() * 40.0 - 20.0)
                    } else if round % 3 == 0 {
                        1.0
                    } else {
                        1e3
                    };
            }
            let a = Affine(m);
            let c = [0; 3].map(|_| ((r.unit() * 2.0 - 1.0) * scale) as f32);
            let e = [0; 3].map(|_| (r.unit() * scale * 0.1) as f32);
            let b = Aabb {
                min: [0, 1, 2].map(|k| c[k] - e[k]),
                max: [0, 1, 2].map(|k| c[k] + e[k]),
            };
            let bound = a.magnitude_bound(&b);
            if bound.iter().any(|&x| x > f64::from(f32::MAX)) {
                continue; // refused by the mesh
            }
            let w = a.world_box(&b);
            for i in 0..64 {
                let p = [0, 1, 2].map(|k| {
                    let t = match (i >> (2 * k)) & 3 {
                        0 => 0.0,
                        1 => 1.0,
                        _ => r.unit(),
                    };
                    (f64::from(b.min[k]) + t * f64::from(b.max[k] - b.min[k])) as f32
                });
                let p = [0, 1, 2].map(|k| p[k].clamp(b.min[k], b.max[k]));
                let q = a.apply(&p);
                for k in 0..3 {
                    assert!(
                        f64::from(w.min[k]) <= q[k] && q[k] <= f64::from(w.max[k]),
                        "{q:?} outside {w:?}"
                    );
                    assert!(q[k].abs() <= bound[k]);
                }
            }
        }
    }
}
