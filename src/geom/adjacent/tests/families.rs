//! Random families of adjacent polygon pairs against the oracle: small integer grids, folds
//! onto the neighbour, vertices pushed through it, pinched fans and sliver fans.

use super::support::*;
use crate::geom::predicates::P3;

/// xorshift64: deterministic cases.
use crate::geom::test_rng::Rng;

/// A polygon pair on a small integer grid: shapes `k` in {3, 4}, `shared` common
/// indices, random repeats and coincident positions.
fn grid_case(r: &mut Rng, half: i32) -> Case {
    let na = r.pick(&[3usize, 4]);
    let nb = r.pick(&[3usize, 4]);
    let mut a: Vec<u32> = (0..na as u32).collect();
    if r.below(12) == 0 {
        let (x, y) = (r.below(na), r.below(na));
        a[x] = a[y];
    }
    let mut distinct = a.clone();
    distinct.sort_unstable();
    distinct.dedup();
    r.shuffle(&mut distinct);
    let shared = 1 + r.below(distinct.len().min(nb));
    let mut b: Vec<u32> = distinct[..shared].to_vec();
    b.extend((0..(nb - shared) as u32).map(|k| 4 + k));
    match r.below(3) {
        // Consecutive shared indices in reversed order, as a consistent mesh has them.
        0 => {
            b.reverse();
            let rot = r.below(nb);
            b.rotate_left(rot);
        }
        _ => r.shuffle(&mut b),
    }
    if r.below(12) == 0 {
        let (x, y) = (r.below(nb), r.below(nb));
        b[x] = b[y];
    }
    let mut pos = [[0.0; 3]; 8];
    for i in 0..8 {
        pos[i] = if i > 0 && r.below(8) == 0 {
            pos[r.below(i)]
        } else {
            [0; 3].map(|_| f64::from(r.below(2 * half as usize + 1) as i32 - half))
        };
    }
    Case::new(&a, &b, &pos)
}

#[test]
fn grid_cases_match_the_oracle() {
    let mut r = Rng(0x9E37_79B9_7F4A_7C15);
    let mut tally = Tally::default();
    for n in 0..120_000 {
        tally.check(&grid_case(&mut r, if n % 3 == 0 { 1 } else { 2 }));
    }
    tally.finish("grid", 120_000);
}

/// Where a family puts its local configuration: a rotation (none, to keep exact
/// coplanarity, or random), a scale (1, 1e-4, 1e4) and an offset (none or 1e5), then
/// each coordinate rounded to `f32` as the library stores it.
struct Place {
    rot: Option<[[f64; 3]; 3]>,
    scale: f64,
    offset: P3,
}

impl Place {
    fn random(r: &mut Rng) -> Place {
        let rot = (r.below(3) != 0).then(|| {
            // A random unit quaternion.
            let q = loop {
                let q = [0; 4].map(|_| r.range(-1.0, 1.0));
                let n = q.iter().map(|x| x * x).sum::<f64>();
                if n > 0.01 && n < 1.0 {
                    break q.map(|x| x / n.sqrt());
                }
            };
            crate::geom::test_rng::rotation_of(q)
        });
        let scale = r.pick(&[1.0, 1e-4, 1e4]);
        let offset = match r.below(3) {
            0 => [1e5; 3],
            1 => [1e5, -1e5 * r.range(0.0, 1.0), 0.5e5],
            _ => [0.0; 3],
        };
        Place { rot, scale, offset }
    }

    fn at(&self, p: [f64; 3]) -> P3 {
        let q = match &self.rot {
            Some(m) => [0, 1, 2].map(|i| m[i][0] * p[0] + m[i][1] * p[1] + m[i][2] * p[2]),
            None => p,
        };
        [0, 1, 2].map(|k| (q[k] * self.scale + self.offset[k]) as f32 as f64)
    }
}

/// A tiny signed offset: 0 or ±1e-3 .. ±1e-7.
fn tiny(r: &mut Rng) -> f64 {
    let m = r.pick(&[0.0, 1e-3, 1e-4, 1e-5, 1e-6, 1e-7]);
    if r.below(2) == 0 {
        m
    } else {
        -m
    }
}

fn lerp(a: [f64; 3], b: [f64; 3], s: f64) -> [f64; 3] {
    [0, 1, 2].map(|k| a[k] + s * (b[k] - a[k]))
}

/// Two polygons hinged on the edge `{0, 1}`: folded onto each other by a tiny angle,
/// lying flat (angle π, the ordinary cloth), or at a random angle; triangles or quads.
fn fold_case(r: &mut Rng) -> Case {
    let at_angle = |x: f64, h: f64, th: f64| [x, h * th.cos(), h * th.sin()];
    let th = match r.below(4) {
        0 | 1 => tiny(r),
        2 => std::f64::consts::PI + tiny(r),
        _ => r.range(0.0, 6.3),
    };
    let mut v = [[0.0; 3]; 6];
    v[1] = [1.0, 0.0, 0.0];
    v[2] = [r.range(-0.5, 1.5), r.range(0.05, 1.0), 0.0];
    v[3] = [r.range(-0.5, 1.5), r.range(0.05, 1.0), 0.0];
    let (x4, h4) = (r.range(-0.5, 1.5), r.range(0.05, 1.0));
    let th4 = th + 0.3 * tiny(r);
    v[4] = at_angle(x4, h4, th4);
    let (x5, h5) = (r.range(-0.5, 1.5), r.range(0.05, 1.0));
    v[5] = at_angle(x5, h5, th);
    if r.below(4) == 0 {
        // One apex of the fold exactly onto the other polygon's plane, inside or out.
        v[4] = [r.range(-0.5, 1.5), r.range(-0.2, 1.0), 0.0];
    }
    let place = Place::random(r);
    let pos = v.map(|p| place.at(p));
    // Quads (0, 1, 2, 3) / (1, 0, 4, 5) go around their corners in order: the far
    // corners are sorted so that 2 is nearer to 1, 5 nearer to 0 (mostly convex).
    let a: &[u32] = if r.below(2) == 0 {
        &[0, 1, 2]
    } else {
        &[0, 1, 2, 3]
    };
    let b: &[u32] = if r.below(2) == 0 {
        &[1, 0, 4]
    } else {
        &[1, 0, 4, 5]
    };
    Case::new(a, b, &pos)
}

/// A vertex pushed through its neighbour: `u` shares the edge `{0, 2}` or the vertex
/// `0` of `t = (0, 1, 2)`, with its other vertices at a tiny height over points of
/// `t`'s plane inside or near `t`.
fn push_case(r: &mut Rng) -> Case {
    let mut v = [[0.0; 3]; 6];
    v[1] = [1.0, 0.0, 0.0];
    v[2] = [r.range(-0.5, 1.0), r.range(0.1, 1.0), 0.0];
    let near = |r: &mut Rng, v: &[[f64; 3]; 6]| {
        let (al, be) = (r.range(-0.3, 1.1), r.range(-0.3, 1.1));
        let h = tiny(r);
        [al * v[1][0] + be * v[2][0], al * v[1][1] + be * v[2][1], h]
    };
    v[3] = near(r, &v);
    v[4] = if r.below(2) == 0 {
        near(r, &v)
    } else {
        [r.range(-1.0, 1.0), r.range(-1.0, 1.0), r.range(-1.0, 1.0)]
    };
    v[5] = near(r, &v);
    let place = Place::random(r);
    let pos = v.map(|p| place.at(p));
    let a: &[u32] = if r.below(3) == 0 {
        &[0, 1, 2, 5]
    } else {
        &[0, 1, 2]
    };
    let b: &[u32] = match r.below(4) {
        0 => &[2, 0, 3],
        1 => &[0, 3, 4],
        2 => &[0, 2, 3, 4],
        _ => &[3, 0, 4],
    };
    Case::new(a, b, &pos)
}

/// Two fans pinched at one vertex: `u`'s other vertices are combinations of `t`'s
/// edges at the common vertex (inside its wedge, across it, opposite), a tiny height
/// off its plane.
fn pinch_case(r: &mut Rng) -> Case {
    let mut v = [[0.0; 3]; 6];
    v[1] = [r.range(0.2, 1.0), r.range(-0.2, 0.2), 0.0];
    v[2] = [r.range(-0.5, 0.5), r.range(0.2, 1.0), 0.0];
    v[3] = [r.range(-0.8, 0.8), r.range(-0.8, 0.8), r.range(-0.5, 0.5)];
    for k in [4, 5] {
        let (l, m) = (r.range(-1.0, 1.2), r.range(-1.0, 1.2));
        let h = tiny(r);
        v[k] = [l * v[1][0] + m * v[2][0], l * v[1][1] + m * v[2][1], h];
        if r.below(4) == 0 {
            // Exactly along an edge of `t` (inside it, past it, or opposite).
            v[k] = lerp([0.0; 3], v[1 + r.below(2)], r.range(-1.0, 1.5));
        }
    }
    let place = Place::random(r);
    let pos = v.map(|p| place.at(p));
    let a: &[u32] = if r.below(3) == 0 {
        &[0, 1, 3, 2]
    } else {
        &[0, 1, 2]
    };
    let b: &[u32] = if r.below(3) == 0 {
        &[0, 4, 3, 5]
    } else {
        &[0, 4, 5]
    };
    Case::new(a, b, &pos)
}

/// Sliver fans: needle triangles around vertex 0 whose far ends are 1e-3 .. 1e-7 apart
/// (and off the common plane by as little), sharing an edge or the vertex.
fn sliver_case(r: &mut Rng) -> Case {
    let d = [1.0, r.range(-0.3, 0.3), r.range(-0.3, 0.3)];
    let e = [r.range(-1.0, 1.0), 1.0, r.range(-1.0, 1.0)];
    let f = [r.range(-1.0, 1.0), r.range(-1.0, 1.0), 1.0];
    let w = |r: &mut Rng| {
        let (a, b) = (tiny(r), 0.3 * tiny(r));
        let s = r.range(0.5, 1.5);
        [0, 1, 2].map(|k| s * d[k] + a * e[k] + b * f[k])
    };
    let mut v = [[0.0; 3]; 6];
    for p in &mut v[1..] {
        *p = w(r);
    }
    if r.below(3) == 0 {
        v[3] = lerp(v[0], v[1], r.range(0.2, 1.5)); // exactly on a needle's line
    }
    let place = Place::random(r);
    let pos = v.map(|p| place.at(p));
    let a: &[u32] = if r.below(3) == 0 {
        &[0, 1, 2, 5]
    } else {
        &[0, 1, 2]
    };
    let b: &[u32] = match r.below(3) {
        0 => &[0, 2, 3],
        1 => &[2, 0, 3, 4],
        _ => &[0, 3, 4],
    };
    Case::new(a, b, &pos)
}

fn family(name: &str, seed: u64, n: usize, gen: fn(&mut Rng) -> Case) {
    let mut r = Rng(seed);
    let mut tally = Tally::default();
    for _ in 0..n {
        tally.check(&gen(&mut r));
    }
    tally.finish(name, n);
}

#[test]
fn folds_match_the_oracle() {
    family("folds", 0x1234_5678_9ABC_DEF1, 60_000, fold_case);
}

#[test]
fn pushed_vertices_match_the_oracle() {
    family("pushed", 0x0F1E_2D3C_4B5A_6978, 60_000, push_case);
}

#[test]
fn pinched_vertices_match_the_oracle() {
    family("pinched", 0x5555_AAAA_3333_CCCC, 60_000, pinch_case);
}

#[test]
fn sliver_fans_match_the_oracle() {
    family("slivers", 0x7777_1111_9999_4444, 60_000, sliver_case);
}
