//! An exact reference on double coordinates, sharing no code with the library: big
//! integers (every double is an integer times a power of two), and world positions written
//! out as docs/API.md defines them.

use super::Rng;
use num_bigint::BigInt;
use num_traits::{Signed, Zero};

/// A row-major 3x4 placement matrix.
pub type M = [f64; 12];

/// The world position, written out as docs/API.md defines it.
pub fn world(m: &M, p: &[f32; 3]) -> [f64; 3] {
    world_f64(m, &p.map(f64::from))
}

/// The world position of a double point (an f64 mesh's vertex), the same way.
pub fn world_f64(m: &M, p: &[f64; 3]) -> [f64; 3] {
    let (x, y, z) = (p[0], p[1], p[2]);
    let mut w = [0.0; 3];
    for (r, out) in w.iter_mut().enumerate() {
        let a = m[r * 4] * x;
        let b = m[r * 4 + 1] * y;
        let c = m[r * 4 + 2] * z;
        let s = a + b;
        let s = s + c;
        *out = s + m[r * 4 + 3];
    }
    w
}

/// Exact integer coordinates of doubles scaled by one common power of two.
pub fn to_ints(points: &[[f64; 3]]) -> Vec<[BigInt; 3]> {
    // Every finite double is m * 2^e with an integer m; scale all by 2^-(smallest e).
    let parts = |x: f64| -> (i64, i32) {
        if x == 0.0 {
            return (0, 0);
        }
        let bits = x.to_bits();
        let exp = ((bits >> 52) & 0x7ff) as i32;
        let frac = (bits & ((1u64 << 52) - 1)) as i64;
        let (mant, e) = if exp == 0 {
            (frac, -1074)
        } else {
            (frac | 1 << 52, exp - 1075)
        };
        (if x < 0.0 { -mant } else { mant }, e)
    };
    let emin = points
        .iter()
        .flatten()
        .filter(|x| **x != 0.0)
        .map(|&x| parts(x).1)
        .min()
        .unwrap_or(0);
    points
        .iter()
        .map(|p| {
            p.map(|x| {
                let (m, e) = parts(x);
                BigInt::from(m) << ((e - emin) as usize)
            })
        })
        .collect()
}

type I3 = [BigInt; 3];

fn isub(a: &I3, b: &I3) -> I3 {
    [&a[0] - &b[0], &a[1] - &b[1], &a[2] - &b[2]]
}

fn det3(a: &I3, b: &I3, c: &I3) -> BigInt {
    &a[0] * (&b[1] * &c[2] - &b[2] * &c[1]) - &a[1] * (&b[0] * &c[2] - &b[2] * &c[0])
        + &a[2] * (&b[0] * &c[1] - &b[1] * &c[0])
}

fn sign(x: &BigInt) -> i32 {
    if x.is_zero() {
        0
    } else if x.is_positive() {
        1
    } else {
        -1
    }
}

/// Orientation of d against a, b, c.
fn o3(a: &I3, b: &I3, c: &I3, d: &I3) -> i32 {
    sign(&det3(&isub(a, d), &isub(b, d), &isub(c, d)))
}

/// 2D orientation dropping axis `ax`.
fn o2(a: &I3, b: &I3, c: &I3, ax: usize) -> i32 {
    let (i, j) = ((ax + 1) % 3, (ax + 2) % 3);
    let v = (&b[i] - &a[i]) * (&c[j] - &a[j]) - (&b[j] - &a[j]) * (&c[i] - &a[i]);
    sign(&v)
}

/// Does the origin lie in the convex hull of `d`? (Carathéodory: in a point, segment,
/// triangle or tetrahedron of them; each decided by exact signs.)
pub fn origin_in_hull(d: &[I3]) -> bool {
    let z: I3 = [BigInt::zero(), BigInt::zero(), BigInt::zero()];
    let on_segment = |a: &I3, b: &I3| {
        (0..3).all(|ax| o2(a, b, &z, ax) == 0)
            && (0..3).all(|k| {
                a[k].clone().min(b[k].clone()) <= z[k] && z[k] <= a[k].clone().max(b[k].clone())
            })
    };
    let in_triangle = |a: &I3, b: &I3, c: &I3| {
        if o3(a, b, c, &z) != 0 {
            return false;
        }
        let Some(ax) = (0..3).find(|&ax| o2(a, b, c, ax) != 0) else {
            return false;
        };
        let s = [o2(a, b, &z, ax), o2(b, c, &z, ax), o2(c, a, &z, ax)];
        !(s.contains(&1) && s.contains(&-1))
    };
    let in_tet = |a: &I3, b: &I3, c: &I3, e: &I3| {
        let v = o3(a, b, c, e);
        v != 0 && {
            let s = [
                o3(&z, b, c, e),
                o3(a, &z, c, e),
                o3(a, b, &z, e),
                o3(a, b, c, &z),
            ];
            s.iter().all(|&x| x == 0 || x == v)
        }
    };
    let n = d.len();
    if d.contains(&z) {
        return true;
    }
    for a in 0..n {
        for b in a + 1..n {
            if on_segment(&d[a], &d[b]) {
                return true;
            }
            for c in b + 1..n {
                if in_triangle(&d[a], &d[b], &d[c]) {
                    return true;
                }
                for e in c + 1..n {
                    if in_tet(&d[a], &d[b], &d[c], &d[e]) {
                        return true;
                    }
                }
            }
        }
    }
    false
}

/// Do the closed triangles (double coordinates) meet? Exactly: the origin in the hull of
/// their Minkowski difference, in big integers.
pub fn exact_triangles_meet(t: &[[f64; 3]; 3], u: &[[f64; 3]; 3]) -> bool {
    let pts: Vec<[f64; 3]> = t.iter().chain(u).copied().collect();
    let i = to_ints(&pts);
    let mut d = Vec::with_capacity(9);
    for a in &i[..3] {
        for b in &i[3..] {
            d.push(isub(a, b));
        }
    }
    // An axis-aligned separating plane through the origin rules most pairs out.
    for k in 0..3 {
        if d.iter().all(|p| p[k].is_positive()) || d.iter().all(|p| p[k].is_negative()) {
            return false;
        }
    }
    origin_in_hull(&d)
}

/// A rotation matrix from a random unit quaternion, times `s`, then translation `t`.
pub fn random_rotation(r: &mut Rng, s: f64, t: [f64; 3]) -> M {
    let q = loop {
        let q = [0; 4].map(|_| r.range(-1.0, 1.0));
        let n = q.iter().map(|x| x * x).sum::<f64>();
        if n > 0.1 && n < 1.0 {
            break q.map(|x| x / n.sqrt());
        }
    };
    let [w, x, y, z] = q;
    let rm = [
        [
            1. - 2. * (y * y + z * z),
            2. * (x * y - w * z),
            2. * (x * z + w * y),
        ],
        [
            2. * (x * y + w * z),
            1. - 2. * (x * x + z * z),
            2. * (y * z - w * x),
        ],
        [
            2. * (x * z - w * y),
            2. * (y * z + w * x),
            1. - 2. * (x * x + y * y),
        ],
    ];
    let mut m = [0.0; 12];
    for i in 0..3 {
        for j in 0..3 {
            m[i * 4 + j] = rm[i][j] * s;
        }
        m[i * 4 + 3] = t[i];
    }
    m
}
