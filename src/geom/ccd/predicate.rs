//! The static tests (does a point lie in a closed triangle, do two closed segments meet) as
//! Boolean functions of the signs of a few polynomials in the four points' coordinates,
//! degenerate cases included: the orientation of the four ([`Signs::o3`]), the 2D
//! orientations of three of them in a coordinate plane ([`Signs::o2`]) and coordinate
//! differences ([`Signs::d`]). The exact test evaluates the signs at an algebraic time, the
//! float filter over a time interval, where a sign may be unknown: the answer is then
//! three-valued (`None`: undecided), and a decided answer holds at every time of the
//! interval.
//!
//! Because the answer depends on these signs only, it is constant between consecutive
//! roots of the polynomials (the exact test's candidate times rest on this).

/// The sign oracle: each sign as `-1`, `0` or `1`, `None` when unknown. Points are `0..4`:
/// `p, a, b, c` for a vertex and a triangle, `a0, a1, b0, b1` for two edges.
pub(super) trait Signs {
    /// `det(x1 - x0, x2 - x0, x3 - x0)`.
    fn o3(&mut self) -> Option<i8>;
    /// `(xj - xi) x (xk - xi)` in the coordinate plane without axis `plane` (its axes
    /// `plane + 1`, `plane + 2`, cyclically).
    fn o2(&mut self, i: usize, j: usize, k: usize, plane: usize) -> Option<i8>;
    /// `xj - xi` along `axis`.
    fn d(&mut self, i: usize, j: usize, axis: usize) -> Option<i8>;
}

/// Which pair of primitives.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Kind {
    /// A vertex (point 0) and a triangle (points 1, 2, 3).
    VertexFace,
    /// An edge (points 0, 1) and an edge (points 2, 3).
    EdgeEdge,
}

/// Do the two primitives meet? With `coplanar`, the four points are taken to be coplanar
/// (the caller knows it) and [`Signs::o3`] is not asked.
pub(super) fn meets<S: Signs>(kind: Kind, s: &mut S, coplanar: bool) -> Option<bool> {
    if !coplanar {
        match s.o3() {
            Some(0) => {}
            Some(_) => return Some(false),
            // Apart even if coplanar: apart.
            None => {
                return match meets(kind, s, true) {
                    Some(false) => Some(false),
                    _ => None,
                }
            }
        }
    }
    match kind {
        Kind::VertexFace => vertex_face(s),
        Kind::EdgeEdge => edge_edge(s),
    }
}

/// Are the primitives certainly apart by a projection onto a coordinate plane (which keeps a
/// meeting a meeting)? In that plane: the point strictly beyond an edge's line from the
/// triangle's third corner, or off the line of a triangle whose corners are on it; an edge
/// with both ends strictly on one side of the other's line. Decides, with unknown signs,
/// near the times a triangle is degenerate or edges are parallel, where [`meets`] cannot
/// choose a plane; the exact test does not need it.
pub(super) fn separated<S: Signs>(kind: Kind, s: &mut S) -> bool {
    for k in 0..3 {
        match kind {
            Kind::VertexFace => {
                for (i, j, m) in [(1, 2, 3), (2, 3, 1), (3, 1, 2)] {
                    if let (Some(sp), Some(sm)) = (s.o2(i, j, 0, k), s.o2(i, j, m, k)) {
                        if sp != 0 && sm != sp {
                            return true;
                        }
                    }
                }
            }
            Kind::EdgeEdge => {
                for (i, j, l, m) in [(0, 1, 2, 3), (2, 3, 0, 1)] {
                    if let (Some(a), Some(b)) = (s.o2(i, j, l, k), s.o2(i, j, m, k)) {
                        if a * b > 0 {
                            return true;
                        }
                    }
                }
            }
        }
    }
    false
}

/// A coplanar point (0) and triangle (1, 2, 3).
fn vertex_face<S: Signs>(s: &mut S) -> Option<bool> {
    let mut unknown = false;
    for k in 0..3 {
        match s.o2(1, 2, 3, k) {
            Some(0) => {}
            None => unknown = true,
            // A proper triangle whose plane this projection keeps: the 2D test is the 3D one.
            Some(n) => return inside_2d(s, k, n),
        }
    }
    if unknown {
        return None;
    }
    // A segment or a point: the point must lie on it.
    let Some(line) = distinct_pair(s, &[(1, 2), (1, 3), (2, 3)])? else {
        // One point: equal to it.
        return all_zero(s, &[(1, 0)]);
    };
    if !on_line(s, line, 0)? {
        return Some(false);
    }
    let ax = line.2;
    // min <= x_p <= max along an axis the line is not orthogonal to.
    let mut below = false;
    let mut above = false;
    for i in 1..4 {
        let d = s.d(i, 0, ax)?;
        below |= d >= 0;
        above |= d <= 0;
    }
    Some(below && above)
}

/// The closed 2D triangle test in plane `k`, the triangle's orientation there `n != 0`.
fn inside_2d<S: Signs>(s: &mut S, k: usize, n: i8) -> Option<bool> {
    let mut unknown = false;
    for (i, j) in [(1, 2), (2, 3), (3, 1)] {
        match s.o2(i, j, 0, k) {
            Some(0) => {}
            Some(e) if e == n => {}
            Some(_) => return Some(false),
            None => unknown = true,
        }
    }
    if unknown {
        None
    } else {
        Some(true)
    }
}

/// Coplanar segments (0, 1) and (2, 3).
fn edge_edge<S: Signs>(s: &mut S) -> Option<bool> {
    const TRIPLES: [(usize, usize, usize); 4] = [(0, 1, 2), (0, 1, 3), (2, 3, 0), (2, 3, 1)];
    let mut unknown = false;
    for k in 0..3 {
        for &(i, j, l) in &TRIPLES {
            match s.o2(i, j, l, k) {
                Some(0) => {}
                None => unknown = true,
                // Not all collinear, and the plane is kept by this projection.
                Some(_) => return crossing_2d(s, k),
            }
        }
    }
    if unknown {
        return None;
    }
    // All four on one line (or one point).
    let Some((_, _, ax)) = distinct_pair(s, &[(0, 1), (0, 2), (0, 3), (1, 2), (1, 3), (2, 3)])?
    else {
        return Some(true);
    };
    // The intervals along `ax` overlap: max a >= min b and max b >= min a.
    let mut a_reaches = false;
    let mut b_reaches = false;
    for i in 0..2 {
        for j in 2..4 {
            let d = s.d(j, i, ax)?;
            a_reaches |= d >= 0;
            b_reaches |= d <= 0;
        }
    }
    Some(a_reaches && b_reaches)
}

/// The closed 2D segment test in plane `k`, where the four points are not all collinear:
/// they meet exactly when neither segment has both ends of the other strictly on one side
/// of its line.
fn crossing_2d<S: Signs>(s: &mut S, k: usize) -> Option<bool> {
    let o1 = s.o2(0, 1, 2, k);
    let o2 = s.o2(0, 1, 3, k);
    let o3 = s.o2(2, 3, 0, k);
    let o4 = s.o2(2, 3, 1, k);
    let same_side = |a: Option<i8>, b: Option<i8>| match (a, b) {
        (Some(a), Some(b)) => Some(a * b > 0),
        _ => None,
    };
    match (same_side(o1, o2), same_side(o3, o4)) {
        (Some(true), _) | (_, Some(true)) => Some(false),
        (Some(false), Some(false)) => Some(true),
        _ => None,
    }
}

/// A pair of the given points that differ, with an axis along which they do (`None`: all
/// equal; the outer `None`: unknown).
fn distinct_pair<S: Signs>(
    s: &mut S,
    pairs: &[(usize, usize)],
) -> Option<Option<(usize, usize, usize)>> {
    for &(i, j) in pairs {
        for ax in 0..3 {
            if s.d(i, j, ax)? != 0 {
                return Some(Some((i, j, ax)));
            }
        }
    }
    Some(None)
}

/// Are the points of each pair equal?
fn all_zero<S: Signs>(s: &mut S, pairs: &[(usize, usize)]) -> Option<bool> {
    for &(i, j) in pairs {
        for ax in 0..3 {
            if s.d(i, j, ax)? != 0 {
                return Some(false);
            }
        }
    }
    Some(true)
}

/// Is point `p` on the line through the distinct points of `line`?
fn on_line<S: Signs>(s: &mut S, line: (usize, usize, usize), p: usize) -> Option<bool> {
    for k in 0..3 {
        if s.o2(line.0, line.1, p, k)? != 0 {
            return Some(false);
        }
    }
    Some(true)
}
