//! Apart for the whole step along a fixed direction: the cheap test that ends most
//! candidate pairs of a continuous query before any root of a cubic is looked for.
//!
//! Along a direction `n`, every point of a primitive (or polygon) whose vertices move on
//! straight lines projects, at time `t`, between the least and the greatest projection of
//! its vertices at `t`, each linear in `t`. So the gap `min_j n.b_j(t) - max_i n.a_i(t)` is
//! a concave function of `t` (a minimum of linear functions minus a maximum of linear
//! functions), and it is positive on all of `[0, 1]` exactly when it is positive at `t = 0`
//! and at `t = 1`. Two point sets separated along `n` at both ends of the step, on the same
//! side, are apart for the whole step, however far each moves: a mesh moving as a whole
//! does not make its own triangles candidates of each other.
//!
//! The direction need not be exact: only the projections' rounding matters. A dot product
//! of `n` with a point `p` is within `gamma_3 * sum |n_k| |p_k| <= 3.4e-16 * |n|_1 * max|p|`
//! of its value (no underflow: an absolute `1e-290` covers it), and each comparison rounds
//! once more (`2^-53` relative): the margin `2e-15 * |n|_1 * max|p| + 1e-290` on each side
//! covers both. Coordinates of at most 1e90 (the filter's range): no overflow.

use crate::geom::P3;

/// Side of `b` relative to `a` along `n` at one instant, certain: `1` when `b` lies wholly
/// above `a` by more than `gap`, `-1` below, `0` when not certain. `a` and `b` are the
/// points at that instant; `bound` the rounding of one projection.
fn side<'p>(
    n: &P3,
    bound: f64,
    gap: f64,
    a: impl Iterator<Item = &'p P3>,
    b: impl Iterator<Item = &'p P3>,
) -> i8 {
    let range = |it: &mut dyn Iterator<Item = &'p P3>| {
        it.map(|p| n[0] * p[0] + n[1] * p[1] + n[2] * p[2])
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), x| {
                (lo.min(x), hi.max(x))
            })
    };
    let (a, b) = (range(&mut { a }), range(&mut { b }));
    // A difference of the rounded projections rounds monotonically: when it exceeds the
    // rounding of both plus the gap, so does the exact one.
    let need = 2.0 * bound + gap;
    if b.0 - a.1 > need {
        1
    } else if a.0 - b.1 > need {
        -1
    } else {
        0
    }
}

/// Are the moving points `a` and `b` (each `[start, end]`) more than `d` apart for the whole
/// step along direction `n` (see the module's documentation)? `maxabs`: the largest
/// magnitude of any of their coordinates. The gap along `n` is measured in units of `|n|`:
/// `d |n|_1 >= d |n|_2` stands for `d` (and `1e-15` more for its own rounding).
pub fn apart_along(n: &P3, a: &[[P3; 2]], b: &[[P3; 2]], maxabs: f64, d: f64) -> bool {
    let l1 = n[0].abs() + n[1].abs() + n[2].abs();
    if !(l1 > 0.0 && l1.is_finite()) {
        return false;
    }
    let bound = 2e-15 * l1 * maxabs + 1e-290;
    let gap = d * l1 * (1.0 + 1e-15);
    let s0 = side(
        n,
        bound,
        gap,
        a.iter().map(|p| &p[0]),
        b.iter().map(|p| &p[0]),
    );
    s0 != 0
        && side(
            n,
            bound,
            gap,
            a.iter().map(|p| &p[1]),
            b.iter().map(|p| &p[1]),
        ) == s0
}

/// Are the moving points `a` and `b` more than `d` apart for the whole step along a
/// coordinate axis? Exact for `d = 0` (plain comparisons of the given doubles); for `d > 0`
/// the difference of two doubles rounds monotonically and `d` is a double.
pub fn apart_on_axes(a: &[[P3; 2]], b: &[[P3; 2]], d: f64) -> bool {
    (0..3).any(|k| {
        let side = |w: usize| {
            let range = |s: &[[P3; 2]]| {
                s.iter()
                    .map(|p| p[w][k])
                    .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), x| {
                        (lo.min(x), hi.max(x))
                    })
            };
            let (ra, rb) = (range(a), range(b));
            if rb.0 - ra.1 > d {
                1
            } else if ra.0 - rb.1 > d {
                -1
            } else {
                0
            }
        };
        let s0 = side(0);
        s0 != 0 && side(1) == s0
    })
}

/// The largest magnitude of the coordinates of `a` and `b`.
pub fn max_abs(a: &[[P3; 2]], b: &[[P3; 2]]) -> f64 {
    a.iter()
        .chain(b)
        .flatten()
        .flatten()
        .fold(0f64, |m, x| m.max(x.abs()))
}

pub fn sub(a: &P3, b: &P3) -> P3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

pub fn cross(a: &P3, b: &P3) -> P3 {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}
