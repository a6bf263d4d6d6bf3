//! Which polygons of a self-colliding mesh share a vertex index: fixed by the mesh's
//! topology, so found once (with the mesh's layout, [`super::all::SelfPrep`]) and kept.
//!
//! Two polygons sharing a vertex always have meeting boxes (both hold the vertex), so the
//! box stage need not find them: it leaves them out of each sub-leaf pair's box tests with
//! the masks kept here ([`Neighbours::between`], [`Neighbours::within`]) and lists only
//! the pairs sharing no vertex, for the exact test. The neighbour pairs a fan certificate
//! does not decide are listed from the topology instead, around the few vertices whose fan
//! is not proven ([`Neighbours::pairs_at`]). On a 92k-triangle crumpled cloth that takes
//! the ~440,000 neighbour pairs out of the box stage (they were half the 903,000 box pairs
//! found there, each split by comparing vertex indices), and lists the ~12,000 left to a
//! test from ~2,000 vertices.

/// Polygons of a sub-leaf at most: a mask holds one bit per polygon.
pub(super) const SUB_MAX: usize = 16;

/// The vertex sharing of one mesh's polygons, numbered by position in a layout's order
/// (sub-leaf by sub-leaf).
#[derive(Clone, Debug, Default)]
pub(super) struct Neighbours {
    /// Vertex index `v`'s polygons, ascending, each once: `polys[start[v]..start[v + 1]]`.
    start: Vec<u32>,
    polys: Vec<u32>,
    /// The vertex indices held by two polygons or more, in the order of their first
    /// polygon: listing pairs around some of them in this order reads the polygons' data
    /// nearly in order, not all over the mesh.
    shared_vertices: Vec<u32>,
    /// The sub-leaf of each polygon.
    sub_of: Vec<u32>,
    /// Sub-leaf `a`'s neighbours after it (sub-leaves `b > a` holding a vertex index of
    /// `a`), ascending: `after[after_start[a]..after_start[a + 1]]`; per such pair, per
    /// polygon `c` of `b` (counted from `b`'s first), the polygons of `a` sharing a vertex
    /// index with it as bits (bit `i`: `a`'s polygon `i`), and how many such pairs.
    after_start: Vec<u32>,
    after: Vec<u32>,
    masks: Vec<[u16; SUB_MAX]>,
    shared: Vec<u32>,
    /// Per polygon, the polygons of its own sub-leaf sharing a vertex index with it (bit
    /// `i`: the sub-leaf's polygon `i`); per sub-leaf, how many such unordered pairs.
    own: Vec<u16>,
    own_shared: Vec<u32>,
}

impl Neighbours {
    /// The vertex sharing of polygons `verts` (each polygon's vertex indices, the first
    /// `k` used, all below `vertex_count`), cut into sub-leaves of at most [`SUB_MAX`]
    /// polygons: sub-leaf `s` holds `sub_start[s]..sub_start[s + 1]`.
    pub fn new(verts: &[[u32; 4]], k: usize, vertex_count: usize, sub_start: &[u32]) -> Self {
        let n = verts.len();
        let mut sub_of = vec![0u32; n];
        for (s, w) in sub_start.windows(2).enumerate() {
            assert!(
                w[1] - w[0] <= SUB_MAX as u32,
                "a sub-leaf of {} polygons",
                w[1] - w[0]
            );
            sub_of[w[0] as usize..w[1] as usize].fill(s as u32);
        }
        // Each polygon once per distinct vertex index (a degenerate polygon may repeat one).
        let distinct = |p: usize| {
            let v = &verts[p][..k];
            (0..k)
                .filter(move |&c| !v[..c].contains(&v[c]))
                .map(move |c| v[c])
        };
        let mut start = vec![0u32; vertex_count + 1];
        for p in 0..n {
            distinct(p).for_each(|v| start[v as usize + 1] += 1);
        }
        for v in 0..vertex_count {
            start[v + 1] += start[v];
        }
        let mut polys = vec![0u32; start[vertex_count] as usize];
        let mut at = start.clone();
        for p in 0..n {
            for v in distinct(p) {
                polys[at[v as usize] as usize] = p as u32;
                at[v as usize] += 1;
            }
        }
        let mut shared_vertices: Vec<u32> = (0..vertex_count as u32)
            .filter(|&v| start[v as usize + 1] - start[v as usize] > 1)
            .collect();
        shared_vertices.sort_by_key(|&v| polys[start[v as usize] as usize]);
        let mut nb = Neighbours {
            start,
            polys,
            shared_vertices,
            sub_of,
            own: vec![0; n],
            ..Neighbours::default()
        };
        // The sub-leaf pairs holding a common vertex index, then their masks.
        let subs = sub_start.len().saturating_sub(1);
        let mut pairs: Vec<(u32, u32)> = Vec::new();
        for v in 0..vertex_count {
            let ps = nb.polys(v);
            for &p in ps {
                let a = nb.sub_of[p as usize];
                pairs.extend(
                    ps.iter()
                        .map(|&q| nb.sub_of[q as usize])
                        .filter(|&b| b > a)
                        .map(|b| (a, b)),
                );
            }
        }
        pairs.sort_unstable();
        pairs.dedup();
        nb.after_start = vec![0; subs + 1];
        for &(a, _) in &pairs {
            nb.after_start[a as usize + 1] += 1;
        }
        for s in 0..subs {
            nb.after_start[s + 1] += nb.after_start[s];
        }
        nb.after = pairs.iter().map(|&(_, b)| b).collect();
        nb.masks = vec![[0; SUB_MAX]; pairs.len()];
        for v in 0..vertex_count {
            let r = nb.start[v] as usize..nb.start[v + 1] as usize;
            for &p in &nb.polys[r.clone()] {
                for &q in &nb.polys[r.clone()] {
                    let (a, b) = (nb.sub_of[p as usize], nb.sub_of[q as usize]);
                    let i = p - sub_start[a as usize];
                    if a == b && p != q {
                        nb.own[q as usize] |= 1 << i;
                    } else if a < b {
                        let e = nb.entry(a as usize, b as usize).expect("listed above");
                        nb.masks[e][(q - sub_start[b as usize]) as usize] |= 1 << i;
                    }
                }
            }
        }
        nb.shared = nb
            .masks
            .iter()
            .map(|m| m.iter().map(|x| x.count_ones()).sum())
            .collect();
        nb.own_shared = sub_start
            .windows(2)
            .map(|w| {
                let r = w[0] as usize..w[1] as usize;
                nb.own[r].iter().map(|x| x.count_ones()).sum::<u32>() / 2
            })
            .collect();
        nb
    }

    /// Vertex index `v`'s polygons, ascending.
    #[inline]
    pub fn polys(&self, v: usize) -> &[u32] {
        &self.polys[self.start[v] as usize..self.start[v + 1] as usize]
    }

    /// Asks for vertex index `v`'s polygon list ahead of its use (a hint).
    #[inline]
    pub fn prefetch_polys(&self, v: usize) {
        if let Some(&at) = self.start.get(v) {
            crate::geom::prefetch_item(&self.polys, at as usize);
        }
    }

    /// The vertex indices held by two polygons or more, in the order of their first
    /// polygon.
    #[inline]
    pub fn shared_vertices(&self) -> &[u32] {
        &self.shared_vertices
    }

    /// The sub-leaf of polygon `p`.
    #[inline]
    pub fn sub_of(&self, p: usize) -> usize {
        self.sub_of[p] as usize
    }

    /// The position of sub-leaf pair `(a, b)`, `a < b`, among `after`, if they share a
    /// vertex index.
    #[inline]
    fn entry(&self, a: usize, b: usize) -> Option<usize> {
        let from = self.after_start[a] as usize;
        let list = &self.after[from..self.after_start[a + 1] as usize];
        // A handful of entries (about nine on a cloth): a scan beats a binary search.
        list.iter().position(|&x| x == b as u32).map(|i| from + i)
    }

    /// For sub-leaves `a < b` holding a common vertex index: per polygon of `b`, the
    /// polygons of `a` sharing one with it (bit `i`: `a`'s polygon `i`), and how many such
    /// pairs; `None` where no polygon of `a` shares a vertex index with one of `b`.
    #[inline]
    pub fn between(&self, a: usize, b: usize) -> Option<(&[u16; SUB_MAX], usize)> {
        debug_assert!(a < b);
        self.entry(a, b)
            .map(|e| (&self.masks[e], self.shared[e] as usize))
    }

    /// For sub-leaf `s` of polygons `range`: per polygon, the polygons of `s` sharing a
    /// vertex index with it (bit `i`: `s`'s polygon `i`), and how many unordered such pairs.
    #[inline]
    pub fn within(&self, s: usize, range: std::ops::Range<usize>) -> (&[u16], usize) {
        (&self.own[range], self.own_shared[s] as usize)
    }

    /// The pairs of polygons around vertex index `v` to decide by a test, appended to
    /// `out` as `[p, q]`, `p < q`: those not `together` (in a patch proven free of
    /// self-intersection) sharing no vertex index whose fan is proven (`fan_ok`, by vertex
    /// index; empty: none is) and sharing none below `v` (a pair sharing several is listed
    /// once, at the least). `verts`: the polygons' vertex indices, the first `k` used.
    pub fn pairs_at(
        &self,
        v: u32,
        verts: &[[u32; 4]],
        k: usize,
        fan_ok: &[bool],
        together: impl Fn(u32, u32) -> bool,
        out: &mut Vec<[u32; 2]>,
    ) {
        let proven = |w: u32| fan_ok.get(w as usize).copied().unwrap_or(false);
        if proven(v) {
            return;
        }
        let ps = self.polys(v as usize);
        for (x, &p) in ps.iter().enumerate() {
            let vp = &verts[p as usize][..k];
            for &q in &ps[x + 1..] {
                let vq = &verts[q as usize][..k];
                let listed_here = vp
                    .iter()
                    .filter(|w| vq.contains(w))
                    .all(|&w| w >= v && !proven(w));
                if listed_here && !together(p, q) {
                    out.push([p, q]);
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::test_rng::Rng;

    /// Polygons of `k` corners over a small pool of vertex indices (so that pairs share
    /// one, two or all corners; some corners repeated), cut into sub-leaves of 1 to 16.
    fn mesh(rng: &mut Rng, n: usize, k: usize) -> (Vec<[u32; 4]>, Vec<u32>) {
        let verts = (0..n)
            .map(|i| {
                let mut v = [u32::MAX; 4];
                for x in &mut v[..k] {
                    *x = (i / 3 + rng.below(9)) as u32;
                }
                v
            })
            .collect();
        let mut sub_start = vec![0u32];
        while (*sub_start.last().unwrap() as usize) < n {
            let at = *sub_start.last().unwrap() as usize;
            sub_start.push((at + 1 + rng.below(16)).min(n) as u32);
        }
        (verts, sub_start)
    }

    fn share(verts: &[[u32; 4]], k: usize, p: usize, q: usize) -> bool {
        verts[p][..k].iter().any(|v| verts[q][..k].contains(v))
    }

    /// Every mask bit and count against comparing every two polygons' vertex indices.
    #[test]
    fn masks_name_exactly_the_polygons_sharing_a_vertex() {
        let mut rng = Rng(5);
        let mut checked = [0usize; 3];
        for k in [3, 4] {
            let (verts, sub_start) = mesh(&mut rng, 300, k);
            let vertex_count = 300 / 3 + 10;
            let nb = Neighbours::new(&verts, k, vertex_count, &sub_start);
            let sub = |s: usize| sub_start[s] as usize..sub_start[s + 1] as usize;
            let subs = sub_start.len() - 1;
            for a in 0..subs {
                let (own, count) = nb.within(a, sub(a));
                let mut want_count = 0;
                for (c, q) in sub(a).enumerate() {
                    for (i, p) in sub(a).enumerate() {
                        let want = p != q && share(&verts, k, p, q);
                        assert_eq!(own[c] >> i & 1 == 1, want, "{p} {q} within {a}");
                        want_count += usize::from(want && p < q);
                    }
                }
                assert_eq!(count, want_count, "sub-leaf {a}");
                checked[0] += count;
                for b in a + 1..subs {
                    let mut want_count = 0;
                    let got = nb.between(a, b);
                    for (c, q) in sub(b).enumerate() {
                        for (i, p) in sub(a).enumerate() {
                            let want = share(&verts, k, p, q);
                            want_count += usize::from(want);
                            let bit = got.is_some_and(|(m, _)| m[c] >> i & 1 == 1);
                            assert_eq!(bit, want, "{p} {q} between {a} {b}");
                        }
                    }
                    assert_eq!(got.map_or(0, |g| g.1), want_count, "{a} {b}");
                    assert_eq!(got.is_some(), want_count > 0, "{a} {b}");
                    checked[1] += want_count;
                    checked[2] += usize::from(got.is_none());
                }
            }
            for v in 0..vertex_count {
                let want: Vec<u32> = (0..verts.len() as u32)
                    .filter(|&p| verts[p as usize][..k].contains(&(v as u32)))
                    .collect();
                assert_eq!(nb.polys(v), &want[..], "vertex {v}");
            }
        }
        assert!(checked.iter().all(|&c| c > 100), "{checked:?}");
    }

    /// The pairs listed over all vertices against a brute force: every pair sharing a
    /// vertex index, none of them proven, not together, each once.
    #[test]
    fn pairs_at_lists_each_undecided_neighbour_pair_once() {
        let mut rng = Rng(9);
        for k in [3, 4] {
            let (verts, sub_start) = mesh(&mut rng, 200, k);
            let vertex_count = 200 / 3 + 10;
            let nb = Neighbours::new(&verts, k, vertex_count, &sub_start);
            let together = |p: u32, q: u32| (p / 40 == q / 40) && (p / 40) % 2 == 1;
            for fan_ok in [
                Vec::new(),
                (0..vertex_count)
                    .map(|_| rng.below(3) == 0)
                    .collect::<Vec<_>>(),
            ] {
                let proven = |w: u32| fan_ok.get(w as usize).copied().unwrap_or(false);
                let mut got = Vec::new();
                for v in 0..vertex_count as u32 {
                    nb.pairs_at(v, &verts, k, &fan_ok, together, &mut got);
                }
                got.sort_unstable();
                let mut want = Vec::new();
                let (mut fans, mut kept) = (0, 0);
                for p in 0..verts.len() {
                    for q in p + 1..verts.len() {
                        let shared: Vec<u32> = verts[p][..k]
                            .iter()
                            .copied()
                            .filter(|w| verts[q][..k].contains(w))
                            .collect();
                        if shared.is_empty() || together(p as u32, q as u32) {
                            continue;
                        }
                        if shared.iter().any(|&w| proven(w)) {
                            fans += 1;
                        } else {
                            want.push([p as u32, q as u32]);
                        }
                    }
                }
                kept += want.len();
                assert_eq!(got, want, "k {k}, {} fans proven", fan_ok.len());
                assert!(
                    kept > 50 && (fan_ok.is_empty() || fans > 50),
                    "{kept} {fans}"
                );
            }
        }
    }
}
