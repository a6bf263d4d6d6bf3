//! An exact answer that shares no code with the library's narrow phase.
//!
//! Two closed triangles T and U meet iff the origin lies in the convex hull of the nine
//! points t_i - u_j (the Minkowski difference). By Carathéodory's theorem that holds iff
//! the origin lies in a point, segment, triangle or tetrahedron spanned by at most four of
//! them; each of those tests is a sign of an exact orient2d/orient3d. Brute force, slow,
//! and obviously right. The differences are checked to be exact in f64.

use robust::{orient2d, orient3d, Coord, Coord3D};

pub type P = [f64; 3];

fn o3(a: &P, b: &P, c: &P, d: &P) -> f64 {
    let p = |p: &P| Coord3D {
        x: p[0],
        y: p[1],
        z: p[2],
    };
    orient3d(p(a), p(b), p(c), p(d))
}

fn proj(p: &P, ax: usize) -> Coord<f64> {
    match ax {
        0 => Coord { x: p[1], y: p[2] },
        1 => Coord { x: p[0], y: p[2] },
        _ => Coord { x: p[0], y: p[1] },
    }
}

fn o2(a: &P, b: &P, c: &P, ax: usize) -> f64 {
    orient2d(proj(a, ax), proj(b, ax), proj(c, ax))
}

const O: P = [0.0; 3];

fn origin_on_segment(a: &P, b: &P) -> bool {
    (0..3).all(|ax| o2(a, b, &O, ax) == 0.0)
        && (0..3).all(|k| a[k].min(b[k]) <= 0.0 && 0.0 <= a[k].max(b[k]))
}

fn origin_in_triangle(a: &P, b: &P, c: &P) -> bool {
    if o3(a, b, c, &O) != 0.0 {
        return false;
    }
    let Some(ax) = (0..3).find(|&ax| o2(a, b, c, ax) != 0.0) else {
        return false; // degenerate: covered by the segments
    };
    let s = [o2(a, b, &O, ax), o2(b, c, &O, ax), o2(c, a, &O, ax)];
    !(s.iter().any(|&v| v > 0.0) && s.iter().any(|&v| v < 0.0))
}

fn origin_in_tetrahedron(a: &P, b: &P, c: &P, d: &P) -> bool {
    let v = o3(a, b, c, d);
    if v == 0.0 {
        return false; // flat: covered by the triangles
    }
    let s = [
        o3(&O, b, c, d),
        o3(a, &O, c, d),
        o3(a, b, &O, d),
        o3(a, b, c, &O),
    ];
    s.iter().all(|&x| x == 0.0 || x.signum() == v.signum())
}

fn exact_sub(a: f64, b: f64) -> f64 {
    let s = a - b;
    // TwoSum error term: zero iff the difference is exact.
    let bb = s - a;
    let err = (a - (s - bb)) + (-b - bb);
    assert_eq!(err, 0.0, "oracle: {a} - {b} is not exact in f64");
    s
}

/// Do the closed triangles meet? (Degenerate ones too.)
pub fn triangles_meet(t: &[P; 3], u: &[P; 3]) -> bool {
    let mut d = [[0.0; 3]; 9];
    for i in 0..3 {
        for j in 0..3 {
            d[i * 3 + j] = [0, 1, 2].map(|k| exact_sub(t[i][k], u[j][k]));
        }
    }
    // Quick exact rejection: an axis-aligned separating plane through the origin.
    for k in 0..3 {
        if d.iter().all(|p| p[k] > 0.0) || d.iter().all(|p| p[k] < 0.0) {
            return false;
        }
    }
    let n = d.len();
    if d.contains(&O) {
        return true;
    }
    for a in 0..n {
        for b in a + 1..n {
            if origin_on_segment(&d[a], &d[b]) {
                return true;
            }
        }
    }
    for a in 0..n {
        for b in a + 1..n {
            for c in b + 1..n {
                if origin_in_triangle(&d[a], &d[b], &d[c]) {
                    return true;
                }
            }
        }
    }
    for a in 0..n {
        for b in a + 1..n {
            for c in b + 1..n {
                for e in c + 1..n {
                    if origin_in_tetrahedron(&d[a], &d[b], &d[c], &d[e]) {
                        return true;
                    }
                }
            }
        }
    }
    false
}

fn sub(a: &P, b: &P) -> P {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
fn dot(a: &P, b: &P) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
fn lerp(a: &P, b: &P, t: f64) -> P {
    [
        a[0] + (b[0] - a[0]) * t,
        a[1] + (b[1] - a[1]) * t,
        a[2] + (b[2] - a[2]) * t,
    ]
}
fn dist(a: &P, b: &P) -> f64 {
    let d = sub(a, b);
    dot(&d, &d).sqrt()
}

/// Closest point on segment `a`-`b` to `p`.
fn closest_on_segment(p: &P, a: &P, b: &P) -> P {
    let ab = sub(b, a);
    let l = dot(&ab, &ab);
    if l == 0.0 {
        return *a;
    }
    lerp(a, b, (dot(&sub(p, a), &ab) / l).clamp(0.0, 1.0))
}

/// Closest point on the triangle to `p` (Ericson, Real-Time Collision Detection 5.1.5),
/// falling back to the edges for a degenerate triangle.
fn closest_on_triangle(p: &P, t: &[P; 3]) -> P {
    let (a, b, c) = (&t[0], &t[1], &t[2]);
    let ab = sub(b, a);
    let ac = sub(c, a);
    let n = [
        ab[1] * ac[2] - ab[2] * ac[1],
        ab[2] * ac[0] - ab[0] * ac[2],
        ab[0] * ac[1] - ab[1] * ac[0],
    ];
    let nn = dot(&n, &n);
    let mut best = closest_on_segment(p, a, b);
    for q in [closest_on_segment(p, b, c), closest_on_segment(p, c, a)] {
        if dist(p, &q) < dist(p, &best) {
            best = q;
        }
    }
    if nn > 0.0 {
        // Projection onto the plane, if inside.
        let s = dot(&sub(p, a), &n) / nn;
        let q = [p[0] - n[0] * s, p[1] - n[1] * s, p[2] - n[2] * s];
        let inside = (0..3).all(|i| {
            let (u, v) = (&t[i], &t[(i + 1) % 3]);
            let e = sub(v, u);
            let w = sub(&q, u);
            let c = [
                e[1] * w[2] - e[2] * w[1],
                e[2] * w[0] - e[0] * w[2],
                e[0] * w[1] - e[1] * w[0],
            ];
            dot(&c, &n) >= 0.0
        });
        if inside && dist(p, &q) < dist(p, &best) {
            best = q;
        }
    }
    best
}

/// Closest points of two segments (Ericson 5.1.9), as a distance.
fn segment_distance(p1: &P, q1: &P, p2: &P, q2: &P) -> f64 {
    let d1 = sub(q1, p1);
    let d2 = sub(q2, p2);
    let r = sub(p1, p2);
    let (a, e, f) = (dot(&d1, &d1), dot(&d2, &d2), dot(&d2, &r));
    let (s, t);
    if a == 0.0 && e == 0.0 {
        return dist(p1, p2);
    }
    if a == 0.0 {
        s = 0.0;
        t = (f / e).clamp(0.0, 1.0);
    } else {
        let c = dot(&d1, &r);
        if e == 0.0 {
            t = 0.0;
            s = (-c / a).clamp(0.0, 1.0);
        } else {
            let b = dot(&d1, &d2);
            let den = a * e - b * b;
            let mut s0 = if den > 0.0 {
                ((b * f - c * e) / den).clamp(0.0, 1.0)
            } else {
                0.0
            };
            let mut t0 = (b * s0 + f) / e;
            if t0 < 0.0 {
                t0 = 0.0;
                s0 = (-c / a).clamp(0.0, 1.0);
            } else if t0 > 1.0 {
                t0 = 1.0;
                s0 = ((b - c) / a).clamp(0.0, 1.0);
            }
            s = s0;
            t = t0;
        }
    }
    dist(&lerp(p1, q1, s), &lerp(p2, q2, t))
}

/// Distance between two closed triangles (0 when they meet), in f64.
pub fn triangle_distance(t: &[P; 3], u: &[P; 3]) -> f64 {
    if triangles_meet(t, u) {
        return 0.0;
    }
    apart_distance(t, u)
}

/// Distance between two closed triangles known not to meet (vertex-face and edge-edge
/// closest points), in f64; the coordinates need not be floats.
pub fn apart_distance(t: &[P; 3], u: &[P; 3]) -> f64 {
    let mut d = f64::INFINITY;
    for i in 0..3 {
        d = d.min(dist(&t[i], &closest_on_triangle(&t[i], u)));
        d = d.min(dist(&u[i], &closest_on_triangle(&u[i], t)));
        for j in 0..3 {
            d = d.min(segment_distance(
                &t[i],
                &t[(i + 1) % 3],
                &u[j],
                &u[(j + 1) % 3],
            ));
        }
    }
    d
}
