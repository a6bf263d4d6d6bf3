//! Exact orientation predicates (Shewchuk's adaptive arithmetic, through the `robust` crate).
//!
//! Every coordinate the library sees is an `f32` widened to `f64` (exact), or the `f64` world
//! position of a placed mesh ([`super::affine`]), whose magnitude stays within the `f32`
//! range. The adaptive predicates are exact for any such doubles (their expansions neither
//! overflow nor, short of matrices that scale coordinates below about 1e-80, underflow), so
//! these signs are the true signs of the determinants for the geometry queried.

use robust::{Coord, Coord3D};

/// A point in `f64`.
pub type P3 = [f64; 3];

/// Sign of the orientation of `d` against the plane through `a`, `b`, `c`
/// (positive, negative or exactly zero when the four points are coplanar): Shewchuk's
/// floating-point filter here, the adaptive stages only when it cannot decide
/// ([`orient3d_filtered`], not inlined: one call per predicate, as before).
#[inline(never)]
pub fn orient3d(a: &P3, b: &P3, c: &P3, d: &P3) -> f64 {
    orient3d_filtered(a, b, c, d)
}

/// The adaptive stages of [`orient3d`], where its filter could not decide.
///
/// Two equal points make the determinant exactly zero; the adaptive predicate would find
/// that only at its last, exact stage (a zero is never certified by an error bound), which
/// costs about a microsecond: a flat triangle whose `f32` corners coincide (common on
/// instrument meshes moved in `f32`) made every test against it that slow. So equal points
/// answer zero at once.
#[cold]
#[inline(never)]
fn orient3d_adaptive(a: &P3, b: &P3, c: &P3, d: &P3) -> f64 {
    if a == b || a == c || a == d || b == c || b == d || c == d {
        return 0.0;
    }
    let p = |p: &P3| Coord3D {
        x: p[0],
        y: p[1],
        z: p[2],
    };
    robust::orient3d(p(a), p(b), p(c), p(d))
}

/// [`orient3d`] with its first stage inlined: Shewchuk's floating-point filter (the same
/// operations and error bound as `robust::orient3d`'s, so the same value whenever it
/// certifies the sign), calling the adaptive predicate only when it cannot. For hot loops
/// where the call itself costs more than the filter.
#[inline(always)]
pub fn orient3d_filtered(a: &P3, b: &P3, c: &P3, d: &P3) -> f64 {
    // (7 + 56 eps) eps, eps = 2^-53: Shewchuk's `o3derrboundA`, as `robust` spells it.
    const EPS: f64 = 0.000_000_000_000_000_111_022_302_462_515_65;
    const BOUND_A: f64 = (7.0 + 56.0 * EPS) * EPS;
    let (adx, bdx, cdx) = (a[0] - d[0], b[0] - d[0], c[0] - d[0]);
    let (ady, bdy, cdy) = (a[1] - d[1], b[1] - d[1], c[1] - d[1]);
    let (adz, bdz, cdz) = (a[2] - d[2], b[2] - d[2], c[2] - d[2]);
    let (bdxcdy, cdxbdy) = (bdx * cdy, cdx * bdy);
    let (cdxady, adxcdy) = (cdx * ady, adx * cdy);
    let (adxbdy, bdxady) = (adx * bdy, bdx * ady);
    let det = adz * (bdxcdy - cdxbdy) + bdz * (cdxady - adxcdy) + cdz * (adxbdy - bdxady);
    let permanent = (bdxcdy.abs() + cdxbdy.abs()) * adz.abs()
        + (cdxady.abs() + adxcdy.abs()) * bdz.abs()
        + (adxbdy.abs() + bdxady.abs()) * cdz.abs();
    let errbound = BOUND_A * permanent;
    // One comparison, not `det > errbound || -det > errbound`: the sign is random in the
    // hot loops, and a branch on it mispredicts half the time (no NaN reaches here).
    if det.abs() > errbound {
        det
    } else {
        orient3d_adaptive(a, b, c, d)
    }
}

/// Sign of the 2D orientation of `c` against the line `a`-`b` (exactly zero when collinear;
/// at once when two points are equal, as [`orient3d`]).
#[inline]
pub fn orient2d(a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> f64 {
    if a == b || a == c || b == c {
        return 0.0;
    }
    let p = |p: [f64; 2]| Coord { x: p[0], y: p[1] };
    robust::orient2d(p(a), p(b), p(c))
}

/// [`orient2d`] with Shewchuk's first-stage error bound inline (`(3 + 16 eps) eps` times
/// the sum of the two products' magnitudes, the rounding of the differences included):
/// where the floating-point determinant's sign is certain it is returned as is, elsewhere
/// (and near underflow or overflow) the exact predicate decides. The same sign as
/// [`orient2d`] always; only the sign is meant.
#[inline(always)]
pub fn orient2d_filtered(a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> f64 {
    const EPS: f64 = f64::EPSILON / 2.0;
    const BOUND: f64 = (3.0 + 16.0 * EPS) * EPS;
    // Below this the products may have lost bits to underflow.
    const TINY: f64 = 1e-250;
    let left = (a[0] - c[0]) * (b[1] - c[1]);
    let right = (a[1] - c[1]) * (b[0] - c[0]);
    let det = left - right;
    let sum = left.abs() + right.abs();
    // (NaN or infinite products fail the comparison: the exact predicate.)
    if det.abs() > BOUND * sum && sum > TINY {
        det
    } else {
        orient2d(a, b, c)
    }
}

/// Projection of a 3D point onto the coordinate plane that drops `axis`.
#[inline]
pub fn drop_axis(p: &P3, axis: usize) -> [f64; 2] {
    match axis {
        0 => [p[1], p[2]],
        1 => [p[2], p[0]],
        _ => [p[0], p[1]],
    }
}

/// True when the three points are exactly collinear (or coincide): every coordinate-plane
/// projection of the triangle has zero area.
pub fn collinear(a: &P3, b: &P3, c: &P3) -> bool {
    (0..3).all(|ax| orient2d(drop_axis(a, ax), drop_axis(b, ax), drop_axis(c, ax)) == 0.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn orientation_signs_are_exact_near_degeneracy() {
        // d is on the plane z = 0 up to one ulp of 1e5: naive arithmetic gets this wrong.
        let a = [1e5, 1e5, 0.0];
        let b = [1e5 + 1.0, 1e5, 0.0];
        let c = [1e5, 1e5 + 1.0, 0.0];
        let on = [1e5 + 0.3, 1e5 + 0.7, 0.0];
        assert_eq!(orient3d(&a, &b, &c, &on), 0.0);
        let above = [1e5 + 0.3, 1e5 + 0.7, f64::from(f32::MIN_POSITIVE)];
        let below = [1e5 + 0.3, 1e5 + 0.7, -f64::from(f32::MIN_POSITIVE)];
        let sa = orient3d(&a, &b, &c, &above);
        let sb = orient3d(&a, &b, &c, &below);
        assert!(sa != 0.0 && sb != 0.0 && sa.signum() != sb.signum());
    }

    #[test]
    fn equal_points_answer_zero_as_the_exact_predicate() {
        // The shortcut for equal points gives the adaptive predicate's own answer (zero),
        // in every position of the repeated point; distinct points still reach it.
        let p = [
            [
                265.544_525_146_484_4,
                375.866_790_771_484_4,
                126.908_462_524_414_06,
            ],
            [
                265.251_464_843_75,
                369.864_135_742_187_5,
                124.980_705_261_230_47,
            ],
            [
                267.876_007_080_078_1,
                372.753_387_451_171_9,
                125.180_999_755_859_38,
            ],
            [1e-30, -2.5, 7.0],
        ];
        let exact = |a: &P3, b: &P3, c: &P3, d: &P3| {
            let q = |p: &P3| Coord3D {
                x: p[0],
                y: p[1],
                z: p[2],
            };
            robust::orient3d(q(a), q(b), q(c), q(d))
        };
        for i in 0..4 {
            for j in 0..4 {
                for k in 0..4 {
                    for l in 0..4 {
                        let (a, b, c, d) = (&p[i], &p[j], &p[k], &p[l]);
                        let ours = orient3d(a, b, c, d);
                        let sign = |x: f64| (x > 0.0) as i8 - (x < 0.0) as i8;
                        assert_eq!(sign(ours), sign(exact(a, b, c, d)), "{i}{j}{k}{l}");
                        let distinct = i != j && i != k && i != l && j != k && j != l && k != l;
                        assert_eq!(ours == 0.0, !distinct, "{i}{j}{k}{l}");
                        let two = |x: &P3| [x[0], x[2]];
                        let (a, b, c) = (two(a), two(b), two(c));
                        let q = |p: [f64; 2]| Coord { x: p[0], y: p[1] };
                        let flat = robust::orient2d(q(a), q(b), q(c));
                        assert_eq!(sign(orient2d(a, b, c)), sign(flat), "{i}{j}{k}");
                    }
                }
            }
        }
    }

    #[test]
    fn collinear_detects_exact_degeneracy_only() {
        assert!(collinear(
            &[0.0, 0.0, 0.0],
            &[1.0, 1.0, 1.0],
            &[3.0, 3.0, 3.0]
        ));
        assert!(collinear(
            &[1.0, 2.0, 3.0],
            &[1.0, 2.0, 3.0],
            &[1.0, 2.0, 3.0]
        ));
        assert!(!collinear(
            &[0.0, 0.0, 0.0],
            &[1.0, 1.0, 1.0],
            &[3.0, 3.0, 3.0 + 1e-12]
        ));
    }
}
