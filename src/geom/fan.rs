//! Vertex-fan certificates: every pair of triangles around one vertex decided at once.
//!
//! In a self-colliding triangle mesh most polygon box pairs are neighbours (they share a
//! vertex index), and each one needs the adjacency rule ("reported only when they meet
//! beyond what they share"). Every neighbour pair shares some vertex `v`, so both lie in the
//! *fan* of `v` (the triangles holding `v`); one proof per vertex settles all its pairs.
//!
//! **The certificate.** Vertex `v` whose incident triangles form one closed fan (walking
//! from each triangle to the one across its edge into `v` by the mesh's twins, every
//! triangle holding `v` is met once before the walk comes back), a coordinate axis `k`
//! dropped and a sign such that
//! 1. every triangle of the fan, projected along `k`, turns strictly with that sign
//!    (exact `orient2d`, the [`turn_mask`](super::patch::turn_mask) bits common to all);
//! 2. the projected link (the fan's outer vertices in walking order) winds around the
//!    projected `v` exactly once.
//!
//! Then no two triangles of the fan meet beyond what they share. Why: write `a_0 .. a_m`
//! for the link, `d_i = a_i - v` projected. Condition 1 says each turn from `d_i` to
//! `d_{i+1}` is by an angle strictly between 0 and pi in one direction; condition 2 that the
//! turns add up to one full turn. So the triangles' projections lie in angular sectors
//! around `v` whose interiors are disjoint: two triangles that are not consecutive project
//! to sets meeting at `v` alone, consecutive ones to sets meeting along the projected edge
//! `v a_i`. A triangle of nonzero projected area projects one-to-one, so a point the two
//! triangles have in common projects to `v` (then it is `v`) or onto edge `v a_i`, which
//! both hold (then it lies on that edge): they meet only in `v` or in their shared edge. A
//! pair sharing two vertex indices shares the edge between them, and in a consistently
//! oriented mesh (twins exist) the two are consecutive in the fan of either.
//!
//! **Counting the turns exactly.** With positive turns (each under pi), the walk crosses
//! the half-line `{v + (t, 0), t > 0}` going up exactly once per full turn: count the `i`
//! with `y(a_i) <= y(v) < y(a_{i+1})` (a turn under pi from the lower half-plane, or from
//! the ray itself, into the upper one passes the ray, never the opposite ray). Negative
//! turns mirror it: `y(a_i) >= y(v) > y(a_{i+1})`. Only comparisons of input coordinates:
//! no rounding anywhere.
//!
//! Open fans (a border vertex) and pinched vertices (two fans through one index) get no
//! certificate: their pairs keep the pair-by-pair test.

use super::patch::{mask_axis, NONE};
use super::predicates::drop_axis;
use super::P3;

/// The closed fans of a mesh's vertices: the triangles in walking order, each as
/// `3 * triangle + corner` (the corner holding the vertex; triangles numbered as the
/// twins and the positions are). Depends on vertex indices only: made once per mesh.
/// Fans are stored in the order of their vertices' first triangle (the triangles' order:
/// a mesh's leaf order), so that proving them one after the other reads the triangles'
/// positions nearly in order rather than all over the mesh.
#[derive(Clone, Debug, Default)]
pub struct Fans {
    /// Fan `i` belongs to vertex `vertex[i]` and is `ring[start[i]..start[i + 1]]`;
    /// vertices with no closed fan have none.
    vertex: Vec<u32>,
    start: Vec<u32>,
    ring: Vec<u32>,
    vertex_count: usize,
    /// Where the triangles' corners are points of one array ([`Fans::set_points`]): per
    /// ring entry, the point of its link vertex (the corner after the fan's vertex); per
    /// fan, the point of its vertex. Empty otherwise.
    link: Vec<u32>,
    centre: Vec<u32>,
}

impl Fans {
    /// The fans of a triangle mesh of `vertex_count` vertex indices: `verts[p]` the first
    /// three entries are triangle `p`'s vertex indices, `tw` its twins
    /// ([`super::patch::twins`] order: `3 * p + e` for the edge from corner `e` to `e + 1`).
    pub fn new(vertex_count: usize, verts: &[[u32; 4]], tw: &[u32]) -> Fans {
        // Each vertex's incidence count and one triangle holding it.
        let mut count = vec![0u32; vertex_count];
        let mut first = vec![NONE; vertex_count];
        for (p, v) in verts.iter().enumerate() {
            for (c, &x) in v[..3].iter().enumerate() {
                let x = x as usize;
                count[x] += 1;
                if first[x] == NONE {
                    first[x] = (3 * p + c) as u32;
                }
            }
        }
        let mut fans = Fans {
            vertex: Vec::with_capacity(vertex_count),
            start: Vec::with_capacity(vertex_count + 1),
            ring: Vec::with_capacity(3 * verts.len()),
            vertex_count,
            ..Fans::default()
        };
        fans.start.push(0);
        let mut by_first: Vec<u32> = (0..vertex_count as u32)
            .filter(|&v| first[v as usize] != NONE)
            .collect();
        by_first.sort_unstable_by_key(|&v| first[v as usize]);
        for v in by_first {
            let from = fans.ring.len();
            let at = first[v as usize];
            if fans.walk(v, at, count[v as usize], verts, tw) {
                fans.vertex.push(v);
                fans.start.push(fans.ring.len() as u32);
            } else {
                fans.ring.truncate(from);
            }
        }
        fans
    }

    /// Walks around `v` from `3 * p + c` into `ring`: true when the walk closes after
    /// exactly `count` triangles.
    fn walk(&mut self, v: u32, at: u32, count: u32, verts: &[[u32; 4]], tw: &[u32]) -> bool {
        let mut x = at;
        for steps in 1..=count {
            self.ring.push(x);
            let (p, c) = (x as usize / 3, x as usize % 3);
            // The edge into `v` (corner c + 2 to corner c); its twin holds `v` next.
            let q = tw[3 * p + (c + 2) % 3];
            if q == NONE {
                return false;
            }
            let Some(cq) = verts[q as usize][..3].iter().position(|&y| y == v) else {
                return false;
            };
            x = 3 * q + cq as u32;
            if x == at {
                return steps == count;
            }
            if steps == count {
                return false;
            }
        }
        false
    }

    /// The same fans with triangle `p` renumbered `at[p]` (a permutation), stored in the
    /// order of their first triangle's new number.
    pub fn renumber(&mut self, at: &[u32]) {
        for x in &mut self.ring {
            *x = 3 * at[*x as usize / 3] + *x % 3;
        }
        let mut by_first: Vec<usize> = (0..self.vertex.len()).collect();
        by_first.sort_unstable_by_key(|&i| self.ring[self.start[i] as usize]);
        let mut fans = Fans {
            vertex: Vec::with_capacity(self.vertex.len()),
            start: Vec::with_capacity(self.start.len()),
            ring: Vec::with_capacity(self.ring.len()),
            vertex_count: self.vertex_count,
            ..Fans::default()
        };
        fans.start.push(0);
        for i in by_first {
            fans.vertex.push(self.vertex[i]);
            let r = self.start[i] as usize..self.start[i + 1] as usize;
            fans.ring.extend_from_slice(&self.ring[r]);
            fans.start.push(fans.ring.len() as u32);
        }
        *self = fans;
    }

    /// Triangle `p`'s corners are the points `corners[p]` of one array (a float mesh's
    /// slots, by the triangles' current numbers): [`Fans::prove`] then reads the link
    /// vertices there (12 bytes a point, ~0.6 MB for a 92k-triangle cloth, read nearly in
    /// order) rather than in the triangles (24 bytes a corner in `f64`, 6.6 MB).
    pub fn set_points(&mut self, corners: &[[u32; 3]]) {
        let point = |x: u32, next: usize| corners[x as usize / 3][(x as usize % 3 + next) % 3];
        self.link.clear();
        self.link.extend(self.ring.iter().map(|&x| point(x, 1)));
        self.centre.clear();
        self.centre.extend(
            self.start[..self.vertex.len()]
                .iter()
                .map(|&s| point(self.ring[s as usize], 0)),
        );
    }

    /// Each vertex's verdict for these positions into `ok` (by vertex index; false where
    /// there is no closed fan): `tris[p]` triangle `p`'s corners, `turns[p]` its
    /// [`turn_mask`](super::patch::turn_mask); `points`, where [`Fans::set_points`] was
    /// given the triangles' corners, the points they name (the same values as `tris`,
    /// read there instead). With `par`, shared between the caller's rayon workers.
    /// `scratch` holds the verdicts in fan order.
    pub fn prove(
        &self,
        tris: &[[P3; 3]],
        points: Option<&[[f32; 3]]>,
        turns: &[u8],
        par: bool,
        scratch: &mut Vec<bool>,
        ok: &mut Vec<bool>,
    ) {
        use rayon::prelude::*;
        // (The points are read only where `set_points` gave their indices.)
        let points = points.filter(|_| !self.link.is_empty());
        let one = |i: usize| match points {
            Some(pts) => self.fan_proven_by(
                i,
                turns,
                |r, k| pts[self.link[r] as usize][k],
                |k| pts[self.centre[i] as usize][k],
            ),
            None => self.fan_proven(i, tris, turns),
        };
        scratch.clear();
        if par {
            // Jobs of 1,024 fans: a worker done early takes over a slower one's.
            scratch.par_extend(
                (0..self.vertex.len())
                    .into_par_iter()
                    .with_max_len(1024)
                    .map(one),
            );
        } else {
            scratch.extend((0..self.vertex.len()).map(one));
        }
        ok.clear();
        ok.resize(self.vertex_count, false);
        for (&v, &x) in self.vertex.iter().zip(scratch.iter()) {
            ok[v as usize] = x;
        }
    }

    /// Vertex `v`'s certificate holds (a test's entry: one vertex, searched for).
    #[cfg(test)]
    fn proven(&self, v: usize, tris: &[[P3; 3]], turns: &[u8]) -> bool {
        self.vertex
            .iter()
            .position(|&x| x as usize == v)
            .is_some_and(|i| self.fan_proven(i, tris, turns))
    }

    /// Fan `i`'s certificate holds, read in the triangles' corners.
    #[inline]
    fn fan_proven(&self, i: usize, tris: &[[P3; 3]], turns: &[u8]) -> bool {
        let corner = |x: u32, next: usize| &tris[x as usize / 3][(x as usize % 3 + next) % 3];
        let x0 = self.ring[self.start[i] as usize];
        self.fan_proven_by(
            i,
            turns,
            |r, k| corner(self.ring[r], 1)[k],
            |k| corner(x0, 0)[k],
        )
    }

    /// Fan `i`'s certificate holds: `link(r, k)` is coordinate `k` of ring entry `r`'s link
    /// vertex, `centre(k)` that of the fan's vertex (exact values: only compared).
    #[inline(always)]
    fn fan_proven_by<T: PartialOrd + Copy>(
        &self,
        i: usize,
        turns: &[u8],
        link: impl Fn(usize, usize) -> T,
        centre: impl Fn(usize) -> T,
    ) -> bool {
        let span = self.start[i] as usize..self.start[i + 1] as usize;
        let mut mask = 0x3f;
        for &x in &self.ring[span.clone()] {
            mask &= turns[x as usize / 3];
        }
        if mask == 0 {
            return false;
        }
        let axis = mask_axis(mask) as usize;
        let positive = mask & (1 << (2 * axis)) != 0;
        // The coordinate kept second once `axis` is dropped ([`drop_axis`]).
        let k = [2, 0, 1][axis];
        debug_assert_eq!(drop_axis(&[0.0, 1.0, 2.0], axis)[1], k as f64);
        let y = |r: usize| link(r, k);
        let yv = centre(k);
        let mut crossings = 0u32;
        let mut prev = y(span.end - 1);
        for r in span {
            let next = y(r);
            let up = if positive {
                prev <= yv && yv < next
            } else {
                prev >= yv && yv > next
            };
            crossings += up as u32;
            prev = next;
        }
        crossings == 1
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::adjacent::adjacent_polygons_meet_at;
    use crate::geom::patch::tests::grid;
    use crate::geom::patch::{turn_mask, twins};
    use crate::geom::test_rng::Rng;

    fn setup(verts: &[[u32; 3]], pos: &[P3]) -> Option<(Fans, Vec<[P3; 3]>, Vec<u8>)> {
        let tw = twins(verts)?;
        let v4: Vec<[u32; 4]> = verts.iter().map(|v| [v[0], v[1], v[2], v[0]]).collect();
        let tris: Vec<[P3; 3]> = verts.iter().map(|v| v.map(|i| pos[i as usize])).collect();
        let turns = tris.iter().map(turn_mask).collect();
        Some((Fans::new(pos.len(), &v4, &tw), tris, turns))
    }

    /// Soundness on one mesh: a proven vertex's triangles meet pairwise only where they
    /// share (the exact adjacency predicate, pair by pair). Returns the proven vertices.
    fn check(verts: &[[u32; 3]], pos: &[P3]) -> Vec<usize> {
        let Some((fans, tris, turns)) = setup(verts, pos) else {
            return Vec::new();
        };
        let mut proven = Vec::new();
        for v in 0..pos.len() {
            if !fans.proven(v, &tris, &turns) {
                continue;
            }
            proven.push(v);
            let around: Vec<usize> = (0..verts.len())
                .filter(|&p| verts[p].contains(&(v as u32)))
                .collect();
            for (i, &p) in around.iter().enumerate() {
                for &q in &around[i + 1..] {
                    assert!(
                        !adjacent_polygons_meet_at(&verts[p], &tris[p], &verts[q], &tris[q]),
                        "vertex {v} proven, but triangles {p} and {q} meet beyond what they share"
                    );
                }
            }
        }
        proven
    }

    fn interior(n: u32) -> impl Iterator<Item = usize> {
        (1..n).flat_map(move |j| (1..n).map(move |i| (j * (n + 1) + i) as usize))
    }

    #[test]
    fn every_interior_vertex_of_a_flat_or_gently_curved_sheet_is_proven() {
        let n = 6;
        let inner: Vec<usize> = interior(n).collect();
        for (scale, offset) in [(1.0, 0.0), (1e-30, 0.0), (1e30, 0.0), (1.0, 1e7)] {
            let (v, p) = grid(n, |x, y| [x * scale + offset, y * scale + offset, offset]);
            assert_eq!(check(&v, &p), inner, "flat, scale {scale}, offset {offset}");
            let (v, p) = grid(n, |x, y| {
                [
                    (0.3 * (2.0 * y).sin() * x) * scale + offset,
                    x * scale,
                    y * scale - offset,
                ]
            });
            assert_eq!(
                check(&v, &p),
                inner,
                "curved, scale {scale}, offset {offset}"
            );
        }
        // Reversed winding: proven with negative turns.
        let (mut v, p) = grid(n, |x, y| [x, y, 0.1 * x * y]);
        for t in &mut v {
            t.swap(1, 2);
        }
        assert_eq!(check(&v, &p), inner);
        // The border's open fans get no certificate.
        let (v, p) = grid(1, |x, y| [x, y, 0.0]);
        assert!(check(&v, &p).is_empty());
    }

    #[test]
    fn folded_and_pushed_vertices_are_not_proven() {
        let n = 6;
        let c = (3 * (n + 1) + 3) as usize;
        // A vertex pushed past its neighbours in the plane: its fan winds over itself.
        for push in [[0.2, 0.0, 0.0], [0.17, 0.17, 0.0], [0.2, 0.05, 0.3]] {
            let (v, mut p) = grid(n, |x, y| [x, y, 0.0]);
            for k in 0..3 {
                p[c][k] += push[k];
            }
            assert!(!check(&v, &p).contains(&c), "pushed {push:?}");
        }
        // Exactly onto a neighbour's position, and onto its edge: a flat sliver, not proven.
        let (v, mut p) = grid(n, |x, y| [x, y, 0.0]);
        p[c] = p[c + 1];
        assert!(!check(&v, &p).contains(&c));
        // A crease folded flat back onto itself along a column of vertices.
        for slope in [1e-1, 1e-9, 0.0] {
            let (v, p) = grid(n, |x, y| {
                if x > 0.5 {
                    [1.0 - x, y, (x - 0.5) * slope]
                } else {
                    [x, y, 0.0]
                }
            });
            let proven = check(&v, &p);
            for j in 1..n {
                let on_crease = (j * (n + 1) + n / 2) as usize;
                assert!(!proven.contains(&on_crease), "crease at slope {slope}");
            }
        }
    }

    #[test]
    fn a_fan_winding_twice_is_not_proven() {
        // Twelve triangles round a vertex turning twice (a helix: no two points coincide),
        // all turning the same way in the projection along z.
        let k = 12u32;
        let mut p = vec![[0.0, 0.0, 0.0]];
        for i in 0..k {
            let a = 4.0 * std::f64::consts::PI * i as f64 / k as f64;
            p.push([a.cos(), a.sin(), 0.1 * i as f64 - 0.5]);
        }
        let v: Vec<[u32; 3]> = (0..k).map(|i| [0, 1 + i, 1 + (i + 1) % k]).collect();
        let (fans, tris, turns) = setup(&v, &p).unwrap();
        assert!(turns.iter().fold(0x3f, |m, t| m & t) != 0);
        assert!(!fans.proven(0, &tris, &turns));
        // The same fan turning once is proven.
        let k = 7u32;
        let mut p = vec![[0.0, 0.0, 0.0]];
        for i in 0..k {
            let a = 2.0 * std::f64::consts::PI * i as f64 / k as f64;
            p.push([a.cos(), a.sin(), 0.3 * (i % 2) as f64]);
        }
        let v: Vec<[u32; 3]> = (0..k).map(|i| [0, 1 + i, 1 + (i + 1) % k]).collect();
        assert_eq!(check(&v, &p), vec![0]);
    }

    #[test]
    fn pinched_and_inconsistent_fans_are_not_proven() {
        // Two closed fans through one vertex index (a double cone): no certificate.
        let mut p = vec![[0.0, 0.0, 0.0]];
        let mut v = Vec::new();
        for side in [1.0, -1.0] {
            let base = p.len() as u32;
            for i in 0..5 {
                let a = 2.0 * std::f64::consts::PI * i as f64 / 5.0;
                p.push([a.cos(), a.sin(), side]);
            }
            for i in 0..5 {
                let (a, b) = (base + i, base + (i + 1) % 5);
                v.push(if side > 0.0 { [0, a, b] } else { [0, b, a] });
            }
        }
        let (fans, tris, turns) = setup(&v, &p).unwrap();
        assert!(!fans.proven(0, &tris, &turns));
        // Two triangles on the same three vertices, opposite windings: no common turn.
        let p = vec![[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
        let (fans, tris, turns) = setup(&[[0, 1, 2], [0, 2, 1]], &p).unwrap();
        assert!((0..3).all(|x| !fans.proven(x, &tris, &turns)));
    }

    /// A grid of `n` by `n` cells crumpled by a noise of round `round`'s amplitude, each
    /// coordinate passed through `round_to`; every third round a vertex snapped onto
    /// another's coordinates (ties in y).
    fn crumpled(
        rng: &mut Rng,
        round: usize,
        n: u32,
        round_to: impl Fn(f64) -> f64,
    ) -> (Vec<[u32; 3]>, Vec<P3>) {
        let amp = [0.05, 0.3, 1.0, 3.0][round % 4];
        let (v, mut p) = grid(n, |x, y| [x, y, 0.0]);
        for q in &mut p {
            for c in q.iter_mut() {
                *c = round_to(*c + amp * rng.f() / f64::from(n));
            }
        }
        if round.is_multiple_of(3) {
            p[8][1] = p[9][1];
            p[15][2] = p[8][2];
        }
        (v, p)
    }

    #[test]
    fn random_crumpled_sheets_never_prove_a_meeting_pair() {
        let mut rng = Rng(0x9E37_79B9_7F4A_7C15);
        let (mut proven, mut refused) = (0, 0);
        for round in 0..300 {
            let n = 5;
            let (v, p) = crumpled(&mut rng, round, n, |c| c);
            let got = check(&v, &p).len();
            proven += got;
            refused += interior(n).count() - got;
        }
        assert!(
            proven > 300 && refused > 300,
            "{proven} proven, {refused} refused"
        );
    }

    /// The verdicts read in an array of points ([`Fans::set_points`]) are those read in
    /// the triangles, vertex by vertex: crumpled sheets of `f32` positions (ties in y
    /// among them), the triangles renumbered, each point stored twice (as a mesh's slots
    /// hold a vertex once per leaf) and the two copies used by different triangles.
    #[test]
    fn verdicts_read_in_points_are_those_read_in_triangles() {
        let mut rng = Rng(77);
        let mut proven = 0;
        for round in 0..100 {
            let (v, p) = crumpled(&mut rng, round, 6, |c| f64::from(c as f32));
            let Some((mut fans, tris, turns)) = setup(&v, &p) else {
                continue;
            };
            // Triangle t becomes at[t]; corners of odd new numbers use the second copy.
            let t = tris.len();
            let at: Vec<u32> = (0..t).map(|x| ((x * 7 + round) % t) as u32).collect();
            assert!(t % 7 != 0);
            let mut new_tris = vec![tris[0]; t];
            let mut new_turns = vec![0; t];
            let mut corners = vec![[0u32; 3]; t];
            for x in 0..t {
                let y = at[x] as usize;
                new_tris[y] = tris[x];
                new_turns[y] = turns[x];
                let copy = (y % 2) as u32 * p.len() as u32;
                corners[y] = v[x].map(|c| c + copy);
            }
            let points: Vec<[f32; 3]> = p.iter().chain(&p).map(|q| q.map(|c| c as f32)).collect();
            fans.renumber(&at);
            let (mut scratch, mut by_tris, mut by_points) = (Vec::new(), Vec::new(), Vec::new());
            fans.prove(
                &new_tris,
                None,
                &new_turns,
                false,
                &mut scratch,
                &mut by_tris,
            );
            fans.set_points(&corners);
            fans.prove(
                &new_tris,
                Some(&points),
                &new_turns,
                false,
                &mut scratch,
                &mut by_points,
            );
            assert_eq!(by_tris, by_points, "round {round}");
            proven += by_points.iter().filter(|&&x| x).count();
        }
        assert!(proven > 500, "{proven} proven");
    }
}
