//! Test-only: the exact penetration depth of two polygons taken as what the contract says
//! they are, unions of triangles (issue 28), in big integers. Independent of the code under
//! test: it shares nothing with `contact` but the definitions.
//!
//! A translation `t` of polygon `a` leaves it meeting `b` iff `t` lies in the Minkowski
//! difference `M = B - A`, the union of the pieces `P_ij = B_j - A_i` (convex polytopes, one
//! per pair of triangles). The depth is `inf { |t| : t not in M }`, the distance from the
//! origin to the closure of the complement `C` of `M`. A piece with no interior (flat) does
//! not change that closure (it is nowhere dense), so only full-dimensional pieces count.
//!
//! `C` is the union, over the choices of one facet per piece, of the open polyhedra
//! `{x : n_f . x > h_f for every chosen f}`; the nearest point `x*` of the closure is the
//! nearest point of one of them, so it is the foot of the origin on the intersection of at
//! most three facet planes of distinct pieces, lies in each of those pieces, and (being the
//! nearest) every such candidate that lies in the closure of `C` is at least as far. The
//! candidates are constructed exactly (homogeneous big integers), ordered by a rounded norm
//! that is monotone in the exact one, and tested in that order: `x` is in the closure of `C`
//! iff some direction `v` leaves every piece holding `x`, i.e. iff for some choice of one
//! facet active at `x` per such piece the open cone `{v : n . v > 0}` is not empty (Gordan:
//! the origin is not in the hull of the chosen normals), decided exactly.
//!
//! The polygons' coordinates are taken exactly as given (`f64`), scaled by one power of two
//! to integers.

use num_bigint::BigInt;
use std::collections::BinaryHeap;

use num_traits::{One, Signed, ToPrimitive, Zero};

use super::P3;

type Z = BigInt;
type ZV = [Z; 3];

fn sub(a: &ZV, b: &ZV) -> ZV {
    [&a[0] - &b[0], &a[1] - &b[1], &a[2] - &b[2]]
}
fn dot(a: &ZV, b: &ZV) -> Z {
    &a[0] * &b[0] + &a[1] * &b[1] + &a[2] * &b[2]
}
fn cross(a: &ZV, b: &ZV) -> ZV {
    [
        &a[1] * &b[2] - &a[2] * &b[1],
        &a[2] * &b[0] - &a[0] * &b[2],
        &a[0] * &b[1] - &a[1] * &b[0],
    ]
}
fn gcd(mut a: Z, mut b: Z) -> Z {
    while !b.is_zero() {
        let r = &a % &b;
        (a, b) = (b, r);
    }
    a
}
fn is_zero(a: &ZV) -> bool {
    a.iter().all(Z::is_zero)
}
/// `s a + t b + u c`.
fn combo(s: &Z, a: &ZV, t: &Z, b: &ZV, u: &Z, c: &ZV) -> ZV {
    [0, 1, 2].map(|k| s * &a[k] + t * &b[k] + u * &c[k])
}

/// A full-dimensional piece `{x : n . x <= h}` over its facets (outward normals, primitive:
/// each facet once).
struct Piece {
    f: Vec<(ZV, Z)>,
}

impl Piece {
    /// `b - a` for two closed triangles (or segments, points), `None` when it has no interior.
    fn of(a: &[ZV; 3], b: &[ZV; 3]) -> Option<Piece> {
        let mut d: Vec<ZV> = Vec::new();
        for q in b {
            for p in a {
                let x = sub(q, p);
                if !d.contains(&x) {
                    d.push(x);
                }
            }
        }
        let mut f: Vec<(ZV, Z)> = Vec::new();
        let mut solid = false;
        for i in 0..d.len() {
            for j in i + 1..d.len() {
                for k in j + 1..d.len() {
                    let n = cross(&sub(&d[j], &d[i]), &sub(&d[k], &d[i]));
                    if is_zero(&n) {
                        continue;
                    }
                    let s: Vec<Z> = d.iter().map(|x| dot(&n, &sub(x, &d[i]))).collect();
                    let (pos, neg) = (s.iter().any(Z::is_positive), s.iter().any(Z::is_negative));
                    solid |= pos || neg;
                    if pos == neg {
                        continue; // not supporting, or every point on it
                    }
                    // Outward: away from the points off the plane.
                    let n = if pos { n.map(|x| -x) } else { n };
                    let g = n.iter().fold(Z::zero(), |g, x| gcd(g, x.abs()));
                    let n = n.map(|x| x / &g);
                    let h = dot(&n, &d[i]);
                    if !f.iter().any(|(m, _)| *m == n) {
                        f.push((n, h));
                    }
                }
            }
        }
        solid.then_some(Piece { f })
    }

    /// `x / w` (`w > 0`) against the piece: `None` outside, else the facets through it
    /// (empty: inside).
    fn active(&self, x: &ZV, w: &Z) -> Option<Vec<usize>> {
        let mut act = Vec::new();
        for (i, (n, h)) in self.f.iter().enumerate() {
            let s = dot(n, x) - h * w;
            if s.is_positive() {
                return None;
            }
            if s.is_zero() {
                act.push(i);
            }
        }
        Some(act)
    }
}

/// Is the origin in the convex hull of these (at most four) vectors? Exact (Caratheodory:
/// a pair opposite, a triple around it in a plane through it, or a tetrahedron around it).
fn zero_in_hull(v: &[&ZV]) -> bool {
    let n = v.len();
    for i in 0..n {
        if is_zero(v[i]) {
            return true;
        }
        for j in i + 1..n {
            if is_zero(&cross(v[i], v[j])) && dot(v[i], v[j]).is_negative() {
                return true;
            }
            for k in j + 1..n {
                let (a, b, c) = (v[i], v[j], v[k]);
                let (ab, bc, ca) = (cross(a, b), cross(b, c), cross(c, a));
                if !dot(&ab, c).is_zero() {
                    continue;
                }
                let Some(w) = [&ab, &bc, &ca].into_iter().find(|x| !is_zero(x)) else {
                    continue;
                };
                let s = [dot(w, &bc), dot(w, &ca), dot(w, &ab)];
                if s.iter().all(|x| !x.is_negative()) || s.iter().all(|x| !x.is_positive()) {
                    return true;
                }
            }
        }
    }
    if n == 4 {
        let det = |p: &ZV, q: &ZV, r: &ZV| dot(p, &cross(q, r));
        let o = [Z::zero(), Z::zero(), Z::zero()];
        let (a, b, c, d) = (v[0], v[1], v[2], v[3]);
        let orient = |p: &ZV, q: &ZV, r: &ZV, s: &ZV| det(&sub(q, p), &sub(r, p), &sub(s, p));
        let total = orient(a, b, c, d);
        if !total.is_zero() {
            let l = [
                orient(&o, b, c, d),
                orient(a, &o, c, d),
                orient(a, b, &o, d),
                orient(a, b, c, &o),
            ];
            let same = |x: &Z| x.is_zero() || x.is_positive() == total.is_positive();
            if l.iter().all(same) {
                return true;
            }
        }
    }
    false
}

/// Is `x / w` in the closure of the complement of the pieces' union?
fn outside(pieces: &[Piece], x: &ZV, w: &Z) -> bool {
    let mut holding: Vec<(usize, Vec<usize>)> = Vec::new();
    for (k, p) in pieces.iter().enumerate() {
        match p.active(x, w) {
            None => {}
            Some(a) if a.is_empty() => return false, // interior
            Some(a) => holding.push((k, a)),
        }
    }
    // Some choice of one active facet per holding piece whose normals the origin is not
    // among (then a direction leaves all of them).
    fn any_choice(pieces: &[Piece], holding: &[(usize, Vec<usize>)], chosen: &mut Vec<ZV>) -> bool {
        let Some(((k, act), rest)) = holding.split_first() else {
            let refs: Vec<&ZV> = chosen.iter().collect();
            return !zero_in_hull(&refs);
        };
        for &f in act {
            chosen.push(pieces[*k].f[f].0.clone());
            let found = any_choice(pieces, rest, chosen);
            chosen.pop();
            if found {
                return true;
            }
        }
        false
    }
    any_choice(pieces, &holding, &mut Vec::new())
}

/// All coordinates as integers, scaled by one power of two (`2^e0` each).
fn integers(coords: &[f64]) -> (Vec<Z>, i32) {
    let parts: Vec<(u64, i32, i8)> = coords
        .iter()
        .map(|&x| {
            let (m, e, s) = num_traits::Float::integer_decode(x);
            let z = if m == 0 { 0 } else { m.trailing_zeros() };
            (m >> z, i32::from(e) + z as i32, s)
        })
        .collect();
    let e0 = parts
        .iter()
        .filter(|p| p.0 != 0)
        .map(|p| p.1)
        .min()
        .unwrap_or(0);
    let z = parts
        .iter()
        .map(|&(m, e, s)| {
            let z = Z::from(m) << (e - e0) as usize;
            if s < 0 {
                -z
            } else {
                z
            }
        })
        .collect();
    (z, e0)
}

/// `n / d` to within a few ulps (both shifted to about 64 significant bits first).
fn ratio(n: &Z, d: &Z) -> f64 {
    let s = d.bits().saturating_sub(64);
    let t = n.bits().saturating_sub(64).max(s);
    let (nf, df) = ((n >> t).to_f64().unwrap(), (d >> s).to_f64().unwrap());
    nf / df * 2f64.powi((t - s) as i32)
}

/// The exact depth of two intersecting polygons as unions of their triangles.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Depth {
    /// The depth (the exact value's square root, rounded: within 2 ulps).
    pub depth: f64,
    /// A nearest point of the complement's closure, `depth * direction` (zero when the
    /// depth is 0), rounded.
    pub at: P3,
}

/// A candidate: the point `x / w` (`w > 0`).
struct Cand {
    x: ZV,
    w: Z,
}

/// A candidate in the queue: on the facet planes `g` (indices into the list of planes),
/// `key` its squared norm (rounded) once built (`built`: its index), before that a lower
/// bound of it.
struct Item {
    key: std::cmp::Reverse<Key>,
    g: Vec<usize>,
    built: Option<usize>,
}

/// An `f64` ordered by `total_cmp`.
struct Key(f64);
impl PartialEq for Key {
    fn eq(&self, o: &Key) -> bool {
        self.cmp(o).is_eq()
    }
}
impl Eq for Key {}
impl PartialOrd for Key {
    fn partial_cmp(&self, o: &Key) -> Option<std::cmp::Ordering> {
        Some(self.cmp(o))
    }
}
impl Ord for Key {
    fn cmp(&self, o: &Key) -> std::cmp::Ordering {
        self.0.total_cmp(&o.0)
    }
}

impl Item {
    fn new(key: f64, g: Vec<usize>, built: Option<usize>) -> Item {
        Item {
            key: std::cmp::Reverse(Key(key)),
            g,
            built,
        }
    }
}
impl PartialEq for Item {
    fn eq(&self, o: &Item) -> bool {
        self.key == o.key
    }
}
impl Eq for Item {}
impl PartialOrd for Item {
    fn partial_cmp(&self, o: &Item) -> Option<std::cmp::Ordering> {
        Some(self.cmp(o))
    }
}
impl Ord for Item {
    fn cmp(&self, o: &Item) -> std::cmp::Ordering {
        self.key.cmp(&o.key)
    }
}

/// The penetration depth of polygons `a` and `b` (each a list of triangles, a quad's two),
/// which must meet (not checked: polygons apart get 0, as touching ones).
pub(crate) fn depth(a: &[[P3; 3]], b: &[[P3; 3]]) -> Depth {
    let flat: Vec<f64> = a.iter().chain(b).flatten().flatten().copied().collect();
    let (z, e0) = integers(&flat);
    let tri = |k: usize| -> [ZV; 3] {
        [0, 1, 2].map(|v| [0, 1, 2].map(|c| z[9 * k + 3 * v + c].clone()))
    };
    let (ta, tb): (Vec<_>, Vec<_>) = (
        (0..a.len()).map(tri).collect(),
        (a.len()..a.len() + b.len()).map(tri).collect(),
    );
    let pieces: Vec<Piece> = ta
        .iter()
        .flat_map(|t| tb.iter().filter_map(move |u| Piece::of(t, u)))
        .collect();
    let zero = [Z::zero(), Z::zero(), Z::zero()];
    let scale = 2f64.powi(e0);
    let done = |x: &ZV, w: &Z| {
        let at = [0, 1, 2].map(|k| ratio(&x[k], w) * scale);
        let xx = dot(x, x);
        let depth = ratio(&xx, &(w * w)).sqrt() * scale;
        Depth { depth, at }
    };
    let one = Z::one();
    if outside(&pieces, &zero, &one) {
        return done(&zero, &one);
    }
    // Every facet plane (piece, facet) and its squared distance from the origin, a lower
    // bound of the norm of every candidate on it.
    let fs: Vec<(usize, usize)> = pieces
        .iter()
        .enumerate()
        .flat_map(|(k, p)| (0..p.f.len()).map(move |i| (k, i)))
        .collect();
    let plane = |g: usize| &pieces[fs[g].0].f[fs[g].1];
    let lb: Vec<f64> = (0..fs.len())
        .map(|g| {
            let (n, h) = plane(g);
            ratio(&(h * h), &dot(n, n))
        })
        .collect();
    // Candidates on 1, 2 or 3 planes of distinct pieces, built when the queue (by the least
    // norm they can have) reaches them.
    let mut q = BinaryHeap::new();
    let nf = fs.len();
    for a in 0..nf {
        q.push(Item::new(lb[a], vec![a], None));
        for b in a + 1..nf {
            if fs[b].0 == fs[a].0 {
                continue;
            }
            q.push(Item::new(lb[a].max(lb[b]), vec![a, b], None));
            for c in b + 1..nf {
                if fs[c].0 != fs[b].0 && fs[c].0 != fs[a].0 {
                    q.push(Item::new(lb[a].max(lb[b]).max(lb[c]), vec![a, b, c], None));
                }
            }
        }
    }
    let mut cands: Vec<Cand> = Vec::new();
    let mut best: Option<(usize, f64)> = None;
    while let Some(it) = q.pop() {
        let key = it.key.0 .0;
        if best.is_some_and(|(_, k)| key > k * (1.0 + 1e-12)) {
            break;
        }
        let Some(built) = it.built else {
            let (x, w) = match it.g[..] {
                [a] => {
                    let (n, h) = plane(a);
                    (n.clone().map(|c| c * h), dot(n, n))
                }
                [a, b] => {
                    let ((n1, h1), (n2, h2)) = (plane(a), plane(b));
                    let m = cross(n1, n2);
                    if is_zero(&m) {
                        continue;
                    }
                    // The foot on the line: h1 (n2 x m) + h2 (m x n1), over m . m.
                    let x = combo(h1, &cross(n2, &m), h2, &cross(&m, n1), &Z::zero(), &m);
                    (x, dot(&m, &m))
                }
                _ => {
                    let ((n1, h1), (n2, h2), (n3, h3)) =
                        (plane(it.g[0]), plane(it.g[1]), plane(it.g[2]));
                    let c23 = cross(n2, n3);
                    let det = dot(n1, &c23);
                    if det.is_zero() {
                        continue;
                    }
                    (combo(h1, &c23, h2, &cross(n3, n1), h3, &cross(n1, n2)), det)
                }
            };
            let (x, w) = if w.is_negative() {
                (x.map(|c| -c), -w)
            } else {
                (x, w)
            };
            let key = ratio(&dot(&x, &x), &(&w * &w));
            cands.push(Cand { x, w });
            q.push(Item::new(key, it.g, Some(cands.len() - 1)));
            continue;
        };
        let c = &cands[built];
        let on =
            it.g.iter()
                .all(|&g| pieces[fs[g].0].active(&c.x, &c.w).is_some());
        if !on || !outside(&pieces, &c.x, &c.w) {
            continue;
        }
        let closer = best.is_none_or(|(b, _)| {
            let b = &cands[b];
            dot(&c.x, &c.x) * (&b.w * &b.w) < dot(&b.x, &b.x) * (&c.w * &c.w)
        });
        if closer {
            best = Some((built, key));
        }
    }
    let b = &cands[best
        .expect("the complement's closure has a nearest point")
        .0];
    done(&b.x, &b.w)
}

#[cfg(test)]
mod tests {
    //! The reference against what it must agree with (the hull's depth where the union is
    //! convex, translations just short of and just past it), then `contact_geometry` on
    //! quads that are not convex and planar against the reference (issue 28).

    use super::*;
    use crate::geom::contact::{contact_geometry, ContactGeometry};
    use crate::geom::test_rng::{rotation_of, Rng};
    use crate::geom::tritri::triangles_intersect;

    const EPS: f64 = f64::EPSILON;

    /// A polygon as `contact_geometry` takes it.
    #[derive(Clone, Copy, Debug)]
    struct Pg {
        t: [[P3; 3]; 2],
        n: usize,
    }

    impl Pg {
        fn tri(t: [P3; 3]) -> Pg {
            Pg { t: [t, t], n: 1 }
        }
        fn quad(v: [P3; 4]) -> Pg {
            Pg {
                t: [[v[0], v[1], v[2]], [v[0], v[2], v[3]]],
                n: 2,
            }
        }
        fn tris(&self) -> &[[P3; 3]] {
            &self.t[..self.n]
        }
        fn map(&self, f: impl Fn(&P3) -> P3) -> Pg {
            Pg {
                t: self.t.map(|t| t.map(|p| f(&p))),
                n: self.n,
            }
        }
        fn moved(&self, d: &P3) -> Pg {
            self.map(|p| [0, 1, 2].map(|k| p[k] + d[k]))
        }
    }

    fn f32r(p: &P3) -> P3 {
        p.map(|x| x as f32 as f64)
    }

    fn meet(a: &Pg, b: &Pg) -> bool {
        a.tris()
            .iter()
            .any(|t| b.tris().iter().any(|u| triangles_intersect(t, u)))
    }

    fn geometry(a: &Pg, b: &Pg) -> ContactGeometry {
        contact_geometry(&a.t, a.n, &b.t, b.n)
    }

    fn reference(a: &Pg, b: &Pg) -> Depth {
        depth(a.tris(), b.tris())
    }

    /// Largest coordinate difference from `a`'s first vertex (the pair's extent).
    fn extent(a: &Pg, b: &Pg) -> f64 {
        let o = a.t[0][0];
        a.tris()
            .iter()
            .chain(b.tris())
            .flatten()
            .flat_map(|p| (0..3).map(move |k| (p[k] - o[k]).abs()))
            .fold(0.0, f64::max)
    }

    /// Largest coordinate magnitude.
    fn magnitude(a: &Pg, b: &Pg) -> f64 {
        a.tris()
            .iter()
            .chain(b.tris())
            .flatten()
            .flatten()
            .fold(0.0, |m: f64, x| m.max(x.abs()))
    }

    /// Some coordinate is not a float (a placed pair's world positions).
    fn placed(a: &Pg, b: &Pg) -> bool {
        a.tris()
            .iter()
            .chain(b.tris())
            .flatten()
            .flatten()
            .any(|&x| x as f32 as f64 != x)
    }

    /// Both moved so that `a`'s first vertex is the origin (translations then round at the
    /// pair's scale).
    fn localized(a: &Pg, b: &Pg) -> (Pg, Pg) {
        let o = a.t[0][0].map(|x| -x);
        (a.moved(&o), b.moved(&o))
    }

    /// Does moving `a` by `s * dir` leave the pair meeting?
    fn meets_moved(a: &Pg, b: &Pg, dir: &P3, s: f64) -> bool {
        let (la, lb) = localized(a, b);
        meet(&la.moved(&dir.map(|x| x * s)), &lb)
    }

    fn unit(v: &P3) -> P3 {
        let l = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
        v.map(|x| x / l)
    }

    // ---------------------------------------------------------------- the reference itself

    /// On convex polygons the union's depth is the hull's: two triangles crossing.
    #[test]
    fn triangles_known_depth() {
        // A vertical triangle through a horizontal one, its tip 0.25 below.
        let t = vec![[[0.0, 0.0, 0.0], [4.0, 0.0, 0.0], [0.0, 4.0, 0.0]]];
        let u = vec![[[1.0, 1.0, -0.25], [1.0, 1.0, 3.0], [1.5, 1.5, 3.0]]];
        let d = depth(&u, &t);
        assert_eq!(d.depth, 0.25);
        assert_eq!(d.at, [0.0, 0.0, 0.25]);
        // A bent quad (a valley along its diagonal) with a triangle standing in the valley
        // on the diagonal: they touch, and moving the quad down separates them.
        let q = Pg::quad([
            [0.0, 0.0, 0.0],
            [0.5, -1.0, 0.5],
            [1.0, 0.0, 0.0],
            [0.5, 1.0, 0.5],
        ]);
        let s = Pg::tri([[0.5, 0.0, 0.0], [0.4, 0.1, 0.2], [0.6, -0.1, 0.2]]);
        assert!(meet(&q, &s));
        assert_eq!(reference(&q, &s).depth, 0.0);
        assert!(!meets_moved(&q, &s, &[0.0, 0.0, -1.0], 1e-6));
        // Its hull would need 0.2 or so: a triangle poking down into the valley 0.05 below
        // the walls' tops needs only to clear the wall it crosses.
    }

    /// Triangle pairs and planar convex quads (the union is then the hull): the reference
    /// agrees with `contact_geometry`, whose hull depth is within an ulp or so of exact.
    /// And for every pair: moving `a` a little less than the depth in random directions
    /// leaves the pair meeting, a little more along the reference's direction separates.
    #[test]
    fn reference_is_the_hull_depth_where_the_union_is_convex() {
        let mut r = Rng(0x005e_ed28);
        let (mut cases, mut worst) = (0, 0.0f64);
        while cases < 600 {
            let (a, b) = crossing(&mut r, &[0.0; 3], 0);
            let (a, b) = match cases % 3 {
                0 => (a, b),
                1 => (convex_quad(&mut r, &a), b),
                _ => (a, convex_quad(&mut r, &b)),
            };
            if !meet(&a, &b) {
                continue;
            }
            let g = geometry(&a, &b);
            if g.coplanar {
                continue;
            }
            cases += 1;
            let d = reference(&a, &b);
            let e = extent(&a, &b);
            worst = worst.max((g.depth - d.depth).abs() / (EPS * e));
            assert!(
                (g.depth - d.depth).abs() <= 16.0 * EPS * e,
                "{a:?} {b:?} {g:?} {d:?}"
            );
            probe(&mut r, &a, &b, &d);
        }
        println!("reference vs hull depth on convex pairs: worst {worst:.2} eps E");
    }

    /// Moving `a` by 1 - 1e-9 of the depth along random directions (and the reference's)
    /// leaves the pair meeting; by 1 + 1e-9 along the reference's direction separates.
    fn probe(r: &mut Rng, a: &Pg, b: &Pg, d: &Depth) {
        let e = extent(a, b);
        if d.depth > 1e-6 * e {
            let dir = unit(&d.at);
            assert!(
                meets_moved(a, b, &dir, d.depth * (1.0 - 1e-9)),
                "{a:?} {b:?} {d:?}"
            );
            assert!(
                !meets_moved(a, b, &dir, d.depth * (1.0 + 1e-9) + 1e-12 * e),
                "{a:?} {b:?} {d:?}"
            );
            for _ in 0..20 {
                assert!(
                    meets_moved(a, b, &r.dir(), d.depth * (1.0 - 1e-9)),
                    "{a:?} {b:?} {d:?}"
                );
            }
        }
    }

    /// A random triangle of size 1 about `c` and a random partner (a triangle, a quad or one
    /// of the odd quads, by `kind`) moved so that a point of each coincides (before
    /// rounding to floats).
    fn crossing(r: &mut Rng, c: &P3, kind: usize) -> (Pg, Pg) {
        let t = [0; 3].map(|_| f32r(&plus(c, &r.v(1.0))));
        let u = match kind {
            0 => Pg::tri([0; 3].map(|_| r.v(1.0))),
            1 => Pg::quad([0; 4].map(|_| r.v(1.0))),
            _ => {
                let k = r.below(ODD.len());
                odd_quad(r, k)
            }
        };
        let x = point_of(r, &Pg::tri(t));
        let y = point_of(r, &u);
        let d = [0, 1, 2].map(|k| x[k] - y[k]);
        (Pg::tri(t), u.moved(&d).map(f32r))
    }

    fn plus(a: &P3, b: &P3) -> P3 {
        [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
    }

    /// A random point of one of `p`'s triangles.
    fn point_of(r: &mut Rng, p: &Pg) -> P3 {
        let t = p.t[r.below(p.n)];
        let w = r.bary();
        [0, 1, 2].map(|k| w[0] * t[0][k] + w[1] * t[1][k] + w[2] * t[2][k])
    }

    /// Triangle `a` extended to a planar convex quad (a fourth vertex in its plane beyond
    /// the edge v0-v2, exact in floats when the plane is an axis plane: here any plane, so
    /// it is planar only to within rounding unless `a` lies in z = const; made so).
    fn convex_quad(r: &mut Rng, a: &Pg) -> Pg {
        let mut t = a.t[0];
        let z = t[0][2];
        for p in &mut t {
            p[2] = z;
        }
        // v3 = v0 + v2 - v1 scaled towards the v0-v2 midpoint side away from v1: convex.
        let s = 0.3 + 0.6 * r.unit();
        let m = [0, 1, 2].map(|k| 0.5 * (t[0][k] + t[2][k]));
        let v3 = f32r(&[0, 1, 2].map(|k| m[k] + s * (m[k] - t[1][k])));
        Pg::quad([t[0], t[1], t[2], [v3[0], v3[1], z]])
    }

    // ---------------------------------------------------------------- odd quads

    /// The kinds of quads whose union of triangles is not their hull (or is degenerate).
    const ODD: [&str; 4] = ["bent", "bowtie", "dart", "degenerate"];

    /// A quad of kind `ODD[k]` of size about 1 at the origin, before rounding, in a frame
    /// where its diagonal v0-v2 is the x axis from 0 to 1 (then turned at random, but for
    /// the degenerate ones).
    fn odd_quad(r: &mut Rng, k: usize) -> Pg {
        let q = odd_local(r, k);
        if ODD[k] == "degenerate" {
            // Not turned: the collinear vertices stay exactly on their line.
            return Pg::quad(q);
        }
        let m = random_rotation(r);
        Pg::quad(q.map(|p| turn(&m, &p)))
    }

    fn odd_local(r: &mut Rng, k: usize) -> [P3; 4] {
        let side = |r: &mut Rng| r.range(0.3, 1.0);
        match ODD[k] {
            // v1, v3 on either side of the diagonal, raised or lowered.
            "bent" => [
                [0.0, 0.0, 0.0],
                [r.range(0.1, 0.9), -side(r), r.range(-0.6, 0.6)],
                [1.0, 0.0, 0.0],
                [r.range(0.1, 0.9), side(r), r.range(-0.6, 0.6)],
            ],
            // Edges v0-v1 and v2-v3 cross; planar half the time.
            "bowtie" => {
                let h = if r.next().is_multiple_of(2) { 0.0 } else { 0.5 };
                [
                    [0.0, 0.0, 0.0],
                    [r.range(0.6, 1.2), side(r), r.range(-h, h)],
                    [1.0, 0.0, 0.0],
                    [r.range(-0.2, 0.4), side(r), r.range(-h, h)],
                ]
            }
            // Reflex at v0 (inside the triangle v1 v2 v3): the diagonal stays inside, the
            // union is the dart; planar half the time.
            "dart" => {
                let h = if r.next().is_multiple_of(2) { 0.0 } else { 0.3 };
                let y = side(r);
                [
                    [0.0, 0.0, 0.0],
                    [r.range(-1.0, -0.5), -y, r.range(-h, h)],
                    [1.0, 0.0, 0.0],
                    [r.range(-1.0, -0.5), y, r.range(-h, h)],
                ]
            }
            // Repeated or collinear vertices (collinear ones on the x axis: exact).
            _ => {
                let p = |r: &mut Rng| r.v(1.0);
                let (v0, v1, v3) = (p(r), p(r), p(r));
                let (o, v2) = ([0.0; 3], [1.0, 0.0, 0.0]);
                let (x1, x3) = ([r.unit(), 0.0, 0.0], [r.unit(), 0.0, 0.0]);
                match r.below(6) {
                    0 => [v0, v1, v0, v3], // two segments from v0
                    1 => [o, x1, v2, v3],  // v1 on the diagonal
                    2 => [v0, v1, v2, v2], // v3 = v2
                    3 => [v0, v1, v2, v1], // v3 = v1: one triangle twice
                    4 => [v0, v0, v0, v3], // a segment
                    _ => [o, x1, v2, x3],  // all collinear
                }
            }
        }
    }

    fn random_rotation(r: &mut Rng) -> [[f64; 3]; 3] {
        let q = [r.f(), r.f(), r.f(), r.f()];
        let l = q.iter().map(|x| x * x).sum::<f64>().sqrt();
        rotation_of(q.map(|v| v / l))
    }

    fn turn(m: &[[f64; 3]; 3], p: &P3) -> P3 {
        [0, 1, 2].map(|k| m[k][0] * p[0] + m[k][1] * p[1] + m[k][2] * p[2])
    }

    /// A pair: an odd quad `a` of kind `k` and a partner (a triangle or a quad; random, or
    /// odd too), crossing (a point of each made to coincide) or touching (the partner's
    /// first vertex on `a`'s diagonal or at its v0, its others on the concave side when
    /// there is one, so that the pair often only touches although it enters the hull).
    /// Unrounded, at the origin, size 1.
    fn odd_pair(r: &mut Rng, k: usize, touching: bool) -> (Pg, Pg) {
        let partner = |r: &mut Rng| match r.below(3) {
            0 => Pg::tri([0; 3].map(|_| r.v(1.0))),
            1 => Pg::quad([0; 4].map(|_| r.v(1.0))),
            _ => {
                let k = r.below(ODD.len());
                odd_quad(r, k)
            }
        };
        if !touching {
            let a = odd_quad(r, k);
            let b = partner(r);
            let (x, y) = (point_of(r, &a), point_of(r, &b));
            return (a, b.moved(&[0, 1, 2].map(|i| x[i] - y[i])));
        }
        // In the local frame (diagonal on the x axis): the touching point and a direction
        // into the concave side (bent: between the halves, towards the raised corners;
        // otherwise up), the partner's other vertices around it.
        let q = odd_local(r, k);
        let at = if r.next().is_multiple_of(4) {
            q[0]
        } else {
            [r.range(0.05, 0.95), 0.0, 0.0]
        };
        let up = match ODD[k] {
            "bent" => unit(&[0.0, 0.0, q[1][2] + q[3][2]]),
            _ => [0.0, 0.0, 1.0],
        };
        let up = if up[2].is_nan() { [0.0, 0.0, 1.0] } else { up };
        let around = |r: &mut Rng| {
            let v = r.v(0.8);
            let h = 0.05 + 0.5 * r.unit();
            [0, 1, 2].map(|i| at[i] + v[i] + h * up[i])
        };
        let b = if r.next().is_multiple_of(2) {
            Pg::tri([at, around(r), around(r)])
        } else {
            Pg::quad([at, around(r), around(r), around(r)])
        };
        let m = random_rotation(r);
        let a = Pg::quad(q);
        // Turned only half the time: unturned, the touching point stays exact in floats.
        if r.next().is_multiple_of(2) {
            (a.map(|p| turn(&m, p)), b.map(|p| turn(&m, p)))
        } else {
            (a, b)
        }
    }

    /// Where a pair is put: scaled by `s`, moved to `c` and rounded to floats; or placed
    /// (turned by a random rotation and moved in f64, world positions that are not floats).
    #[derive(Clone, Copy, Debug)]
    struct Frame {
        c: P3,
        s: f64,
        placed: bool,
    }

    const FRAMES: [Frame; 4] = [
        Frame {
            c: [0.0; 3],
            s: 1.0,
            placed: false,
        },
        Frame {
            c: [1e3, 700.0, -400.0],
            s: 1.0,
            placed: false,
        },
        Frame {
            c: [0.0; 3],
            s: 1.0,
            placed: true,
        },
        Frame {
            c: [1e3, 700.0, -400.0],
            s: 1.0,
            placed: true,
        },
    ];

    fn put(r: &mut Rng, f: &Frame, (a, b): (Pg, Pg)) -> (Pg, Pg) {
        let at =
            |p: &P3| f32r(&[0, 1, 2].map(|k| p[k] * f.s + if f.placed { 0.0 } else { f.c[k] }));
        let (a, b) = (a.map(at), b.map(at));
        if !f.placed {
            return (a, b);
        }
        let m = random_rotation(r);
        let w = |p: &P3| plus(&turn(&m, p), &f.c);
        (a.map(w), b.map(w))
    }

    /// What [`judge`] saw over a family.
    #[derive(Debug, Default)]
    struct Tally {
        pairs: usize,
        judged: usize,
        touching: usize,
        /// Depth off the reference by more than the limit.
        wrong: usize,
        /// Worst |depth - reference| / (eps E).
        worst: f64,
        /// Worst |depth - reference| / E (how far off, in the pair's size).
        worst_rel: f64,
        /// The excess over the reference of the wrong ones that do not only touch, relative
        /// to the reference.
        excess: Vec<f64>,
        /// Touching pairs (reference 0) given a depth above the limit, and the largest / E.
        touching_wrong: usize,
        touching_worst: f64,
        /// Least extra translation (in eps E: 0, 1, 2, 4... up to `LIMIT`) after which
        /// depth * normal separates, worst.
        margin: f64,
        /// Pairs that moving farther along the normal does not separate: the union is apart
        /// only in a wedge of directions at the nearest point, which the radial direction
        /// misses (the pair moved by depth * normal must then touch: the union's depth of
        /// the moved pair within `LIMIT` eps E).
        wedge: usize,
        /// Pairs whose depth * normal leaves them meeting by more than that.
        no_separation: usize,
    }

    /// The depth limit, in eps E (eps (E + M) for placed pairs).
    const LIMIT: f64 = 64.0;

    fn judge(t: &mut Tally, a: &Pg, b: &Pg) {
        t.pairs += 1;
        let g = geometry(a, b);
        assert_eq!(g.intersecting, meet(a, b), "{a:?} {b:?}");
        if !g.intersecting || g.coplanar {
            return;
        }
        t.judged += 1;
        let d = reference(a, b);
        // The error unit: eps E; for placed pairs (world positions that are not floats, whose
        // differences round) eps (E + M), M the largest coordinate magnitude.
        let e = extent(a, b) + if placed(a, b) { magnitude(a, b) } else { 0.0 };
        if d.depth == 0.0 {
            t.touching += 1;
        }
        let err = (g.depth - d.depth).abs();
        t.worst = t.worst.max(err / (EPS * e));
        t.worst_rel = t.worst_rel.max(err / e);
        if err > LIMIT * EPS * e {
            if std::env::var("UNION_DEBUG").is_ok() {
                eprintln!("WRONG {a:?}\n  {b:?}\n  {g:?}\n  {d:?}");
            }
            t.wrong += 1;
            if d.depth == 0.0 {
                t.touching_wrong += 1;
                t.touching_worst = t.touching_worst.max(g.depth / e);
            } else {
                t.excess.push((g.depth - d.depth) / d.depth);
            }
        }
        // depth * normal separates, within a few eps E; or brings the pair to touching,
        // where farther along the normal does not separate.
        let mut m = 0.0;
        while meets_moved(a, b, &g.normal, g.depth + m * EPS * e) {
            m = if m == 0.0 { 1.0 } else { m * 2.0 };
            if m > LIMIT {
                let (la, lb) = localized(a, b);
                let moved = la.moved(&g.normal.map(|x| x * g.depth));
                let rest = reference(&moved, &lb).depth;
                if rest > LIMIT * EPS * e {
                    if std::env::var("UNION_DEBUG").is_ok() {
                        eprintln!("NOSEP {a:?}\n  {b:?}\n  {g:?}\n  {d:?}\n  rest {rest:e}");
                    }
                    t.no_separation += 1;
                } else {
                    t.wedge += 1;
                }
                m = 0.0;
                break;
            }
        }
        t.margin = t.margin.max(m);
    }

    fn report(name: &str, t: &Tally) {
        let mut ex = t.excess.clone();
        ex.sort_by(f64::total_cmp);
        let median = ex.get(ex.len() / 2).copied().unwrap_or(0.0);
        println!(
            "{name:>34}: {:>5} pairs, {:>5} judged ({:>4} touching) | wrong depth {:>4} \
             (median excess {:>6.1}%, worst {:.3e} E; touching given depth: {}, up to {:.3} E) \
             | worst {:>9.3e} eps E | margin {:>3} | wedge {} | not separating {}",
            t.pairs,
            t.judged,
            t.touching,
            t.wrong,
            100.0 * median,
            t.worst_rel,
            t.touching_wrong,
            t.touching_worst,
            t.worst,
            t.margin,
            t.wedge,
            t.no_separation
        );
    }

    fn family(name: &str, seed: u64, n: usize, mut make: impl FnMut(&mut Rng) -> (Pg, Pg)) {
        let mut all = Tally::default();
        for (i, f) in FRAMES.iter().enumerate() {
            let mut r = Rng(seed ^ ((i as u64 + 1) * 0x9E37_79B9));
            let mut t = Tally::default();
            for _ in 0..n {
                let p = make(&mut r);
                let (a, b) = put(&mut r, f, p);
                judge(&mut t, &a, &b);
                // Swapped: the odd quad as b.
                judge(&mut t, &b, &a);
            }
            let tag = match (f.placed, f.c[0] != 0.0) {
                (false, false) => "",
                (false, true) => " @1e3",
                (true, false) => " placed",
                (true, true) => " placed @1e3",
            };
            report(&format!("{name}{tag}"), &t);
            all.pairs += t.pairs;
            all.judged += t.judged;
            all.touching += t.touching;
            all.wrong += t.wrong;
            all.worst = all.worst.max(t.worst);
            all.worst_rel = all.worst_rel.max(t.worst_rel);
            all.excess.extend(t.excess);
            all.touching_wrong += t.touching_wrong;
            all.touching_worst = all.touching_worst.max(t.touching_worst);
            all.margin = all.margin.max(t.margin);
            all.no_separation += t.no_separation;
            all.wedge += t.wedge;
        }
        report(name, &all);
        assert!(all.judged > n, "{name}: too few judged: {all:?}");
        assert!(
            all.wrong == 0 && all.no_separation == 0 && all.margin <= LIMIT,
            "{name}: {} of {} depths off the union's by more than {LIMIT} eps E (worst {:.3e} \
             E), {} not separating",
            all.wrong,
            all.judged,
            all.worst_rel,
            all.no_separation
        );
    }

    // ---------------------------------------------------------------- the library

    fn quad(v: [P3; 4]) -> Pg {
        Pg::quad(v.map(|p| f32r(&p)))
    }

    /// Issue 28's first pair: a bent quad and a triangle; 0.0165407863 was the hull's.
    #[test]
    fn issue_bent_quad_and_triangle() {
        let a = quad([
            [0.833284736, 0.563280046, 0.469137639],
            [0.845061004, 0.580085456, 0.231902003],
            [0.746003568, 0.728380203, 0.263473541],
            [0.743429899, 0.709550977, 0.487849951],
        ]);
        let b = Pg::tri(
            [
                [0.750003099, 0.68365562, 0.345634073],
                [0.888942957, 0.681875646, 0.254946679],
                [0.749886692, 0.824581861, 0.345702291],
            ]
            .map(|p| f32r(&p)),
        );
        let d = reference(&a, &b);
        assert!((d.depth - 0.0153659206).abs() < 1e-10, "{d:?}");
        let g = geometry(&a, &b);
        assert!(g.intersecting && !g.coplanar);
        assert!((g.depth - d.depth).abs() < 1e-15, "{g:?} vs {d:?}");
        let n = unit(&d.at);
        let cos: f64 = (0..3).map(|k| n[k] * g.normal[k]).sum();
        assert!(cos > 1.0 - 1e-12, "{g:?} vs {n:?}");
        assert!(!meets_moved(&a, &b, &g.normal, g.depth * 1.000001));
    }

    /// Issue 28's second pair: a triangle touching a bent quad from its concave side; 0.11
    /// was the hull's depth.
    #[test]
    fn issue_triangle_touching_bent_quad() {
        let a = Pg::tri([[0.5, 0.75, 0.0], [0.5, 0.75, 0.25], [0.0, 0.5, 0.0]]);
        let b = quad([
            [0.25, 0.75, 0.75],
            [0.75, 0.0, 0.25],
            [0.0, 0.25, 0.25],
            [0.25, 0.75, 0.0],
        ]);
        assert_eq!(reference(&a, &b).depth, 0.0);
        assert!(!meets_moved(&a, &b, &[1.0, 0.0, 0.0], 1e-6));
        let g = geometry(&a, &b);
        assert!(g.intersecting && !g.coplanar);
        assert_eq!(g.depth, 0.0, "{g:?}");
        assert!(!meets_moved(&a, &b, &g.normal, 1e-9), "{g:?}");
    }

    /// Issue 28's third pair: a planar bowtie and a point in its plane: coplanar, depth 0,
    /// and the normal across the plane (the halves' area vectors cancel: their sum was
    /// (0.7, -0.7, 0), in the plane, along which a move of 0.177 does not separate).
    #[test]
    fn issue_planar_bowtie_normal() {
        let a = quad([
            [0.0, 0.0, 0.0],
            [1.0, 1.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
        ]);
        let b = Pg::tri([[0.75, 0.5, 0.0]; 3]);
        for (x, y) in [(&a, &b), (&b, &a)] {
            let g = geometry(x, y);
            assert!(g.intersecting && g.coplanar && g.depth == 0.0, "{g:?}");
            assert_eq!(g.normal[2].abs(), 1.0, "{g:?}");
        }
        // Bowties whose halves do not cancel exactly: still their plane's normal (a proper
        // half's), in any plane.
        let mut r = Rng(28);
        for _ in 0..200 {
            let q = odd_local(&mut r, 1).map(|mut p| {
                p[2] = 0.0;
                p
            });
            let m = random_rotation(&mut r);
            let a = Pg::quad(q).map(|p| f32r(&turn(&m, p)));
            let x = point_of(&mut r, &Pg::quad(q));
            let b = Pg::tri([f32r(&turn(&m, &x)); 3]);
            let g = geometry(&a, &b);
            if !g.intersecting || !g.coplanar {
                continue;
            }
            // Both halves' normals: the answer is one of them, up to sign (within
            // rounding: the halves are planar to within the floats' rounding only when
            // exactly coplanar, which `coplanar` says they are).
            let h = [&a.t[0], &a.t[1]].map(|t| {
                let (e, f) = (
                    [0, 1, 2].map(|k| t[1][k] - t[0][k]),
                    [0, 1, 2].map(|k| t[2][k] - t[0][k]),
                );
                unit(&[
                    e[1] * f[2] - e[2] * f[1],
                    e[2] * f[0] - e[0] * f[2],
                    e[0] * f[1] - e[1] * f[0],
                ])
            });
            let ok = h.iter().any(|n| {
                let c: f64 = (0..3).map(|k| n[k] * g.normal[k]).sum();
                c.abs() > 1.0 - 1e-6
            });
            assert!(ok, "{a:?} {b:?} {g:?}");
        }
    }

    #[test]
    fn bent_quads_crossing() {
        family("bent, crossing", 0xb1, 150, |r| odd_pair(r, 0, false));
    }

    #[test]
    fn bowtie_quads_crossing() {
        family("bowtie, crossing", 0xb2, 150, |r| odd_pair(r, 1, false));
    }

    #[test]
    fn dart_quads_crossing() {
        family("dart, crossing", 0xb3, 150, |r| odd_pair(r, 2, false));
    }

    #[test]
    fn degenerate_quads_crossing() {
        family("degenerate, crossing", 0xb4, 150, |r| odd_pair(r, 3, false));
    }

    #[test]
    fn odd_quads_touching() {
        family("bent/bowtie/dart, touching", 0xb5, 200, |r| {
            let k = r.below(3);
            odd_pair(r, k, true)
        });
    }
}
