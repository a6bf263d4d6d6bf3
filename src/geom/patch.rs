//! Bulk proofs that a patch of a triangle mesh does not meet itself: whole groups of
//! self-collision pairs decided at once instead of pair by pair.
//!
//! **The certificate.** A set `P` of triangles of one mesh, a coordinate axis `k` and a sign
//! (the bits of [`turn_mask`] common to all triangles of `P`) such that
//! 1. every triangle of `P`, projected along `k` (the coordinate dropped), has strictly the
//!    sign's orientation (exact `orient2d` on the `f64` positions);
//! 2. `P` is consistently oriented by vertex index (every directed edge of the mesh is used
//!    once at most: [`twins`]), and the edges of `P` whose reverse is not in `P` (its
//!    boundary) chain into exactly **one** closed loop;
//! 3. that loop, projected, is a simple polygon (non-consecutive edges do not meet,
//!    consecutive ones meet only at their shared corner; exact tests).
//!
//! Then the projection is one-to-one on `P`, so two triangles of `P` meet only in the
//! vertices and edges they share by index: no pair of `P` meets beyond its joint, and at
//! epsilon 0 no pair of `P` sharing nothing meets at all. Why: for a point `y` of the
//! plane on no projected edge, the number of triangles of `P` whose projection holds `y`
//! (each counts +1, all having the same orientation) is the winding number of the
//! projected boundary around `y` (interior edges cancel), which for a simple loop is 0 or 1.
//! If two distinct points of `P` had the same projection `y`, then near each of them the
//! projection covers a full neighbourhood of `y` (an interior point: the triangles around
//! an interior edge lie on both sides of it, those around an interior vertex turn all the
//! way round it) or a part of one bounded by the projected boundary (a boundary point), so
//! points near `y` on no edge would be covered twice, unless both points lie on the
//! boundary, which the loop's simplicity excludes. Distinct points of `P` thus have
//! distinct projections, hence distinct positions.
//!
//! Every decision is exact (`orient2d` on the input coordinates, comparisons of
//! coordinates); nothing is computed in floating point that a decision depends on.

use super::predicates::{drop_axis, orient2d, orient2d_filtered};
use super::P3;

/// No twin: the edge is on the mesh's border, or its reverse is in no triangle.
pub const NONE: u32 = u32::MAX;

/// For triangle `p` and its edge `e` (corner `e` to corner `e + 1`), the triangle holding
/// the reverse edge, at `3 * p + e`; [`NONE`] where there is none. `None` when some
/// directed edge is used twice (a non-manifold edge or inconsistently oriented neighbours):
/// no certificate is tried on such a mesh.
pub fn twins(verts: &[[u32; 3]]) -> Option<Vec<u32>> {
    let mut edges: Vec<(u32, u32, u32)> = Vec::with_capacity(3 * verts.len());
    for (p, v) in verts.iter().enumerate() {
        for e in 0..3 {
            edges.push((v[e], v[(e + 1) % 3], p as u32));
        }
    }
    edges.sort_unstable();
    if edges
        .windows(2)
        .any(|w| (w[0].0, w[0].1) == (w[1].0, w[1].1))
    {
        return None;
    }
    let mut out = vec![NONE; 3 * verts.len()];
    for (p, v) in verts.iter().enumerate() {
        for e in 0..3 {
            let (a, b) = (v[e], v[(e + 1) % 3]);
            if let Ok(i) = edges.binary_search_by(|x| (x.0, x.1).cmp(&(b, a))) {
                out[3 * p + e] = edges[i].2;
            }
        }
    }
    Some(out)
}

/// The projections in which triangle `t` turns strictly positively (bit `2 k`) or
/// negatively (bit `2 k + 1`) when coordinate `k` is dropped (exact `orient2d`): a
/// patch's usable projections are the common bits of its triangles.
///
/// Each determinant is first taken in floating point under Shewchuk's error bound
/// ([`orient2d_filtered`]); only a projection whose sign that bound leaves uncertain asks
/// the exact predicate.
#[inline]
pub fn turn_mask(t: &[P3; 3]) -> u8 {
    let mut m = 0;
    for k in 0..3 {
        let (a, b, c) = (
            drop_axis(&t[0], k),
            drop_axis(&t[1], k),
            drop_axis(&t[2], k),
        );
        let o = orient2d_filtered(a, b, c);
        m |= ((o > 0.0) as u8) << (2 * k) | ((o < 0.0) as u8) << (2 * k + 1);
    }
    m
}

/// The coordinate a patch is projected along: that of the lowest bit of its mask.
pub fn mask_axis(mask: u8) -> u8 {
    debug_assert!(mask != 0);
    mask.trailing_zeros() as u8 / 2
}

/// One boundary edge, projected, and its extent.
#[derive(Clone, Copy)]
struct Seg {
    a: [f64; 2],
    b: [f64; 2],
    lo: [f64; 2],
    hi: [f64; 2],
}

/// A patch's boundary as one closed loop (conditions 2 of the certificate, which depend on
/// vertex indices only, so a loop can be kept while the mesh moves): its edges
/// (`3 * triangle + edge`) and, for each, the position of the edge that follows it.
#[derive(Clone, Debug, Default)]
pub struct Loop {
    pub edges: Vec<u32>,
    pub next: Vec<u32>,
}

/// Scratch of the certificates (reused; no allocation once grown).
#[derive(Default)]
pub struct PatchCheck {
    /// Boundary edges as (start vertex, `3 * triangle + edge`), sorted by start.
    keys: Vec<(u32, u32)>,
    segs: Vec<Seg>,
    by_x: Vec<(f64, u32)>,
}

impl PatchCheck {
    /// Condition 2b alone: the loop the boundary edges `edges` chain into, if one.
    pub fn boundary_loop(
        &mut self,
        edges: impl Iterator<Item = u32>,
        verts: &[[u32; 4]],
    ) -> Option<Loop> {
        let mut l = Loop::default();
        self.chain(edges, verts, &mut l).then_some(l)
    }

    /// The edges sorted by their start, no start twice, and following each edge to the
    /// one starting at its end comes back to the first after all of them: into `l`.
    fn chain(
        &mut self,
        edges: impl Iterator<Item = u32>,
        verts: &[[u32; 4]],
        l: &mut Loop,
    ) -> bool {
        self.keys.clear();
        self.keys
            .extend(edges.map(|x| (verts[x as usize / 3][x as usize % 3], x)));
        let n = self.keys.len();
        if n < 3 {
            return false;
        }
        self.keys.sort_unstable_by_key(|k| k.0);
        if self.keys.windows(2).any(|w| w[0].0 == w[1].0) {
            return false;
        }
        let to = |x: u32| verts[x as usize / 3][(x as usize % 3 + 1) % 3];
        l.next.clear();
        l.next.resize(n, 0);
        let mut at = 0usize;
        for step in 1..=n {
            let end = to(self.keys[at].1);
            let Ok(nx) = self.keys.binary_search_by_key(&end, |k| k.0) else {
                return false;
            };
            l.next[at] = nx as u32;
            at = nx;
            if at == 0 {
                if step != n {
                    return false;
                }
                break;
            }
        }
        if at != 0 {
            return false;
        }
        l.edges.clear();
        l.edges.extend(self.keys.iter().map(|k| k.1));
        true
    }

    /// Condition 3: loop `l` projected along `axis` is a simple polygon (exact).
    pub fn simple(&mut self, l: &Loop, axis: u8, tris: &[[P3; 3]]) -> bool {
        let axis = axis as usize;
        self.segs.clear();
        for &x in &l.edges {
            let (p, e) = (x as usize / 3, x as usize % 3);
            let (a, b) = (
                drop_axis(&tris[p][e], axis),
                drop_axis(&tris[p][(e + 1) % 3], axis),
            );
            self.segs.push(Seg {
                a,
                b,
                lo: [a[0].min(b[0]), a[1].min(b[1])],
                hi: [a[0].max(b[0]), a[1].max(b[1])],
            });
        }
        // A sweep along the first coordinate over the edges' extents.
        self.by_x.clear();
        self.by_x.extend(
            self.segs
                .iter()
                .enumerate()
                .map(|(i, g)| (g.lo[0], i as u32)),
        );
        self.by_x.sort_unstable_by(|x, y| x.0.total_cmp(&y.0));
        let segs = &self.segs;
        for (ii, &(_, i)) in self.by_x.iter().enumerate() {
            let s = &segs[i as usize];
            for &(tx, j) in &self.by_x[ii + 1..] {
                if tx > s.hi[0] {
                    break;
                }
                let t = &segs[j as usize];
                if t.lo[1] > s.hi[1] || t.hi[1] < s.lo[1] {
                    continue;
                }
                let bad = if l.next[i as usize] == j {
                    folds_back(s.a, s.b, t.b)
                } else if l.next[j as usize] == i {
                    folds_back(t.a, t.b, s.b)
                } else {
                    segments_meet(s.a, s.b, t.a, t.b)
                };
                if bad {
                    return false;
                }
            }
        }
        true
    }
}

/// Consecutive edges `p`-`q` and `q`-`r` (distinct points: each is an edge of a triangle
/// of nonzero projected area) meet beyond `q`: collinear with `r` on `p`'s side of `q`.
fn folds_back(p: [f64; 2], q: [f64; 2], r: [f64; 2]) -> bool {
    if orient2d(p, q, r) != 0.0 {
        return false;
    }
    let c = if p[0] != q[0] { 0 } else { 1 };
    (p[c] > q[c]) == (r[c] > q[c])
}

/// The closed segments `a`-`b` and `c`-`d` meet (exact).
fn segments_meet(a: [f64; 2], b: [f64; 2], c: [f64; 2], d: [f64; 2]) -> bool {
    let sign = |x: f64| (x > 0.0) as i8 - (x < 0.0) as i8;
    let (o1, o2) = (sign(orient2d(a, b, c)), sign(orient2d(a, b, d)));
    let (o3, o4) = (sign(orient2d(c, d, a)), sign(orient2d(c, d, b)));
    if o1 * o2 < 0 && o3 * o4 < 0 {
        return true;
    }
    // Collinear cases: the point lies within the other segment's extent.
    let within = |p: [f64; 2], q: [f64; 2], r: [f64; 2]| {
        (0..2).all(|k| p[k].min(q[k]) <= r[k] && r[k] <= p[k].max(q[k]))
    };
    (o1 == 0 && within(a, b, c))
        || (o2 == 0 && within(a, b, d))
        || (o3 == 0 && within(c, d, a))
        || (o4 == 0 && within(c, d, b))
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::geom::adjacent::adjacent_polygons_meet_at;
    use crate::geom::tritri::triangles_intersect;

    /// The whole mesh as one patch: the certificate's verdict.
    fn certified(verts: &[[u32; 3]], pos: &[P3]) -> bool {
        let Some(tw) = twins(verts) else {
            return false;
        };
        let tris: Vec<[P3; 3]> = verts.iter().map(|v| v.map(|i| pos[i as usize])).collect();
        let v4: Vec<[u32; 4]> = verts.iter().map(|v| [v[0], v[1], v[2], 0]).collect();
        let mask = tris.iter().fold(0x3f, |m, t| m & turn_mask(t));
        if mask == 0 {
            return false;
        }
        let edges = (0..3 * verts.len() as u32).filter(|&x| tw[x as usize] == NONE);
        let mut check = PatchCheck::default();
        check
            .boundary_loop(edges, &v4)
            .is_some_and(|l| check.simple(&l, mask_axis(mask), &tris))
    }

    /// Some pair meets beyond what it shares (exact predicates, pair by pair).
    fn brute_meets(verts: &[[u32; 3]], pos: &[P3]) -> bool {
        let tri = |v: &[u32; 3]| v.map(|i| pos[i as usize]);
        (0..verts.len()).any(|i| {
            (i + 1..verts.len()).any(|j| {
                let (a, b) = (&verts[i], &verts[j]);
                if a.iter().any(|x| b.contains(x)) {
                    adjacent_polygons_meet_at(a, &tri(a), b, &tri(b))
                } else {
                    triangles_intersect(&tri(a), &tri(b))
                }
            })
        })
    }

    /// Sound on every case: a certificate never covers a meeting pair.
    fn check(verts: &[[u32; 3]], pos: &[P3]) -> bool {
        let c = certified(verts, pos);
        if c {
            assert!(!brute_meets(verts, pos), "certified, but a pair meets");
        }
        c
    }

    /// An n x n grid over [0, 1]^2 (positions by `f`), `(n + 1)^2` vertices, each cell two
    /// triangles turning the same way (also the fans' tests' sheet).
    pub(crate) fn grid(n: u32, f: impl Fn(f64, f64) -> P3) -> (Vec<[u32; 3]>, Vec<P3>) {
        let mut pos = Vec::new();
        for j in 0..=n {
            for i in 0..=n {
                pos.push(f(i as f64 / n as f64, j as f64 / n as f64));
            }
        }
        let at = |i: u32, j: u32| j * (n + 1) + i;
        let mut verts = Vec::new();
        for j in 0..n {
            for i in 0..n {
                let (a, b, c, d) = (at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
                verts.extend([[a, b, c], [a, c, d]]);
            }
        }
        (verts, pos)
    }

    /// The filtered mask against the exact predicate, projection by projection: random
    /// triangles, nearly collinear ones, tiny, huge and far from the origin.
    #[test]
    fn turn_mask_is_the_exact_predicates() {
        let exact = |t: &[P3; 3]| {
            let mut m = 0;
            for k in 0..3 {
                let o = orient2d(
                    drop_axis(&t[0], k),
                    drop_axis(&t[1], k),
                    drop_axis(&t[2], k),
                );
                m |= ((o > 0.0) as u8) << (2 * k) | ((o < 0.0) as u8) << (2 * k + 1);
            }
            m
        };
        let mut rng = crate::geom::test_rng::Rng(0x1234_5678_9ABC_DEF1);
        let mut uncertain = 0;
        for round in 0..200_000 {
            let (scale, offset) = [
                (1.0, 0.0),
                (2f64.powi(-600), 0.0),
                (2f64.powi(600), 0.0),
                (1.0, 1e6),
                (2f64.powi(-10), 1e3),
            ][round % 5];
            let t: [P3; 3] = if round / 5 % 2 == 0 {
                // Exactly collinear in every projection (small integers, powers of two):
                // all three determinants 0, most of them past the filter.
                let mut int = || (rng.next() % 2001) as f64 - 1000.0;
                let a: P3 = std::array::from_fn(|_| int() * scale + offset);
                let d: P3 = std::array::from_fn(|_| int() * scale);
                let (s, u) = ((rng.next() % 7) as f64 - 3.0, (rng.next() % 7) as f64 - 3.0);
                [0.0, s, u].map(|f| std::array::from_fn(|k| a[k] + f * d[k]))
            } else {
                // Nearly collinear: b and c up to `tiny` off the line, rounded to float.
                let a: P3 = std::array::from_fn(|_| rng.f() * scale + offset);
                let d: P3 = std::array::from_fn(|_| rng.f() * scale);
                let tiny = [1.0, 1e-7, 1e-12, 1e-16][round / 10 % 4];
                let (s, u) = (rng.f(), rng.f());
                let b: P3 = std::array::from_fn(|k| a[k] + s * d[k] + tiny * rng.f() * scale);
                let c: P3 = std::array::from_fn(|k| a[k] + u * d[k] + tiny * rng.f() * scale);
                // (Rounded to float where float holds the scale.)
                let float = (1e-30..1e30).contains(&scale);
                [a, b, c].map(|p| p.map(|x| if float { x as f32 as f64 } else { x }))
            };
            let (want, got) = (exact(&t), turn_mask(&t));
            assert_eq!(got, want, "{t:?}");
            uncertain += (want.count_ones() < 3) as u32;
        }
        assert!(
            uncertain > 1000,
            "{uncertain} triangles with a zero projection"
        );
    }

    #[test]
    fn flat_and_gently_curved_grids_are_proven_in_any_frame() {
        for (scale, offset) in [(1.0, 0.0), (1e-4, 0.0), (1e4, 0.0), (1.0, 1e5), (1e-4, 1e5)] {
            let (v, p) = grid(8, |x, y| [x * scale + offset, y * scale + offset, offset]);
            assert!(check(&v, &p), "flat, scale {scale}, offset {offset}");
            let (v, p) = grid(8, |x, y| {
                [
                    x * scale + offset,
                    y * scale - offset,
                    (0.2 * (3.0 * x).sin() * y) * scale,
                ]
            });
            assert!(check(&v, &p), "curved, scale {scale}, offset {offset}");
        }
        // Reversed winding: proven in the negative projection.
        let (mut v, p) = grid(6, |x, y| [x, y, 0.1 * x * y]);
        for t in &mut v {
            t.swap(1, 2);
        }
        assert!(check(&v, &p));
        // Standing on its side (projected along x) and a single triangle.
        let (v, p) = grid(5, |x, y| [0.01 * x * y, x, y]);
        assert!(check(&v, &p));
        assert!(check(
            &[[0, 1, 2]],
            &[[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]
        ));
    }

    #[test]
    fn folds_and_pushed_vertices_are_not_proven() {
        // Folded back over itself at slopes down to 1e-7.
        for slope in [1e-1, 1e-3, 1e-7, 0.0] {
            let (v, p) = grid(8, |x, y| {
                if x > 0.5 {
                    [1.0 - x, y, (x - 0.5) * slope]
                } else {
                    [x, y, 0.0]
                }
            });
            assert!(!check(&v, &p), "fold at slope {slope}");
        }
        // An interior vertex pushed past its neighbours, in the plane and through it.
        for push in [[1.5, 0.0, 0.0], [1.5, 0.3, 0.2], [0.0, 0.0, 0.0001]] {
            let (v, mut p) = grid(6, |x, y| [x, y, 0.0]);
            let c = 3 * 7 + 3;
            for k in 0..3 {
                p[c][k] += push[k] / 6.0;
            }
            let proven = check(&v, &p);
            if push[0] != 0.0 {
                assert!(!proven, "pushed {push:?}");
            }
        }
    }

    #[test]
    fn fans_winding_twice_and_bad_topology_are_not_proven() {
        // A fan around a vertex turning twice (a helix: no two vertices coincide), closed
        // (the centre inside) and open.
        for closed in [true, false] {
            let k = 12u32;
            let mut p = vec![[0.0, 0.0, 0.0]];
            for i in 0..k {
                let a = 4.0 * std::f64::consts::PI * i as f64 / k as f64;
                p.push([a.cos(), a.sin(), 0.1 * i as f64]);
            }
            let mut v: Vec<[u32; 3]> = (1..k).map(|i| [0, i, i + 1]).collect();
            if closed {
                v.push([0, k, 1]);
            }
            assert!(!check(&v, &p), "fan turning twice, closed {closed}");
        }
        // Two disks sharing one vertex index (pinched): two boundary loops through it.
        let p = vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, 1.0, 0.0],
            [-1.0, 0.0, 0.0],
            [-1.0, -1.0, 0.0],
        ];
        assert!(!check(&[[0, 1, 2], [0, 3, 4]], &p));
        // One triangle turned the other way: a directed edge twice, no twins at all.
        let (mut v, p) = grid(4, |x, y| [x, y, 0.0]);
        v[5].swap(1, 2);
        assert!(twins(&v).is_none());
        assert!(!check(&v, &p));
        // An annulus: two boundary loops.
        let (v, p) = grid(6, |x, y| [x, y, 0.0]);
        let hole = |t: &[u32; 3]| {
            t.iter()
                .all(|&i| (2..=4).contains(&(i % 7)) && (2..=4).contains(&(i / 7)))
        };
        let ring: Vec<[u32; 3]> = v.iter().copied().filter(|t| !hole(t)).collect();
        assert!(!check(&ring, &p));
        // A zero-area (collinear) triangle in the patch.
        let (v, mut p) = grid(4, |x, y| [x, y, 0.0]);
        p[6] = [0.25 * 1.0, 0.25 * 1.0, 0.0];
        p[12] = [0.5, 0.5, 0.0];
        p[18] = [0.75, 0.75, 0.0];
        let _ = check(&v, &p);
        let degenerate = vec![[0, 1, 2]];
        let line = vec![[0.0; 3], [1.0, 1.0, 1.0], [2.0, 2.0, 2.0]];
        assert!(!check(&degenerate, &line));
    }

    #[test]
    fn boundaries_that_touch_themselves_are_not_proven() {
        // An annular strip turning 1.1 times round (its end a little above its start in
        // 3D): all triangles turn the same way, but the projected boundary crosses itself.
        let mut p = Vec::new();
        let n = 16;
        for i in 0..=n {
            let a = 2.2 * std::f64::consts::PI * i as f64 / n as f64;
            let z = 0.01 * i as f64;
            p.push([a.cos(), a.sin(), z]);
            p.push([2.0 * a.cos(), 2.0 * a.sin(), z]);
        }
        let mut v = Vec::new();
        for i in 0..n as u32 {
            let (a, b, c, d) = (2 * i, 2 * i + 2, 2 * i + 3, 2 * i + 1);
            v.extend([[a, b, c], [a, c, d]]);
        }
        assert!(!check(&v, &p), "spiral strip overlapping its start");
    }

    #[test]
    fn random_patches_are_proven_only_when_no_pair_meets() {
        let mut rng = crate::geom::test_rng::Rng(0x2545F4914F6CDD1Du64);
        let mut rnd = move || rng.f();
        let (mut proven, mut refused) = (0, 0);
        for round in 0..400 {
            let jitter = [0.1, 0.5, 1.0, 2.0][round % 4];
            let (v, mut p) = grid(5, |x, y| [x, y, 0.0]);
            for q in &mut p {
                for c in q.iter_mut() {
                    *c += jitter * rnd() / 5.0;
                }
            }
            if check(&v, &p) {
                proven += 1;
            } else {
                refused += 1;
            }
        }
        assert!(
            proven > 50 && refused > 50,
            "{proven} proven, {refused} refused"
        );
    }
}
