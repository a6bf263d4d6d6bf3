//! A pair's polygons and their joint: a polygon's vertices and triangles (indices and
//! positions), the shared edges, and the joint as points (the shared positions and the
//! merged intervals of collinear shared edges).

use crate::geom::predicates::{collinear, P3};
use crate::geom::tritri::segments_intersect;

/// A triangle or quad: its vertices (indices and positions), `n` of them.
#[derive(Clone, Copy, Debug)]
pub(super) struct Polygon {
    idx: [u32; 4],
    pos: [P3; 4],
    pub(super) n: usize,
}

impl Polygon {
    pub(super) fn new(idx: &[u32], tris: &[[P3; 3]; 2], ntri: usize) -> Polygon {
        assert!(ntri == 1 || ntri == 2, "a polygon has 1 or 2 triangles");
        let n = ntri + 2;
        let mut p = Polygon {
            idx: [0; 4],
            pos: [tris[0][0], tris[0][1], tris[0][2], tris[0][2]],
            n,
        };
        assert_eq!(
            idx.len(),
            n,
            "a polygon with {ntri} triangles has {n} vertices"
        );
        p.idx[..n].copy_from_slice(idx);
        if n == 4 {
            p.pos[3] = tris[1][2];
        }
        p
    }

    #[cfg(any(test, feature = "internals"))]
    pub(super) fn from_vertices(idx: &[u32], pos: &[P3]) -> Polygon {
        let n = idx.len();
        assert!(
            (n == 3 || n == 4) && pos.len() == n,
            "3 or 4 vertices, one position each"
        );
        let mut p = Polygon {
            idx: [0; 4],
            pos: [pos[0]; 4],
            n,
        };
        p.idx[..n].copy_from_slice(idx);
        p.pos[..n].copy_from_slice(pos);
        p
    }

    /// Triangle `k` (0, or 1 for a quad) with its vertex indices.
    #[inline]
    pub(super) fn tri(&self, k: usize) -> Tri {
        let c = if k == 0 { [0, 1, 2] } else { [0, 2, 3] };
        Tri {
            i: c.map(|c| self.idx[c]),
            p: c.map(|c| self.pos[c]),
        }
    }

    /// Boundary edge `k` as an index pair.
    #[inline]
    fn edge(&self, k: usize) -> (u32, u32) {
        (self.idx[k], self.idx[(k + 1) % self.n])
    }

    fn has_edge(&self, i: u32, j: u32) -> bool {
        (0..self.n).any(|k| {
            let (a, b) = self.edge(k);
            (a == i && b == j) || (a == j && b == i)
        })
    }
}

/// One triangle of a polygon: vertex indices and positions.
#[derive(Clone, Copy, Debug)]
pub(super) struct Tri {
    pub(super) i: [u32; 3],
    pub(super) p: [P3; 3],
}

/// The shared edges of two polygons, as index pairs (all the fast paths need).
#[derive(Clone, Copy, Debug)]
pub(super) struct SharedEdges {
    e: [(u32, u32); 4],
    n: usize,
}

impl SharedEdges {
    pub(super) fn of(a: &Polygon, b: &Polygon) -> SharedEdges {
        let mut s = SharedEdges {
            e: [(0, 0); 4],
            n: 0,
        };
        for k in 0..a.n {
            let (u, v) = a.edge(k);
            if u != v && b.has_edge(u, v) && !s.has(u, v) {
                s.e[s.n] = (u, v);
                s.n += 1;
            }
        }
        s
    }

    #[inline]
    pub(super) fn has(&self, u: u32, v: u32) -> bool {
        self.e[..self.n]
            .iter()
            .any(|&(a, b)| (a == u && b == v) || (a == v && b == u))
    }
}

/// The joint of two polygons as points: the shared vertices' positions and the merged
/// intervals of the shared edges (see the module documentation).
#[derive(Clone, Debug)]
pub(super) struct Joint {
    /// Positions of the shared vertices.
    pub(super) pts: [P3; 4],
    pub(super) n_pts: usize,
    /// Merged intervals: segments between two shared positions (never a single point).
    pub(super) segs: [[P3; 2]; 4],
    pub(super) n_segs: usize,
}

impl Joint {
    /// The positions are `a`'s (equal indices are one vertex, at one position).
    pub(super) fn of(a: &Polygon, b: &Polygon, edges: &SharedEdges) -> Joint {
        let mut j = Joint {
            pts: [[0.0; 3]; 4],
            n_pts: 0,
            segs: [[[0.0; 3]; 2]; 4],
            n_segs: 0,
        };
        for k in 0..a.n {
            let i = a.idx[k];
            if !a.idx[..k].contains(&i) && b.idx[..b.n].contains(&i) {
                j.pts[j.n_pts] = a.pos[k];
                j.n_pts += 1;
            }
        }
        for &(u, v) in &edges.e[..edges.n] {
            let at = |i: u32| (0..a.n).find(|&k| a.idx[k] == i).map(|k| a.pos[k]);
            if let (Some(pu), Some(pv)) = (at(u), at(v)) {
                if pu != pv {
                    j.segs[j.n_segs] = [pu, pv];
                    j.n_segs += 1;
                }
            }
        }
        j.merge();
        j
    }

    /// Replaces collinear shared edges that meet (overlap or touch) by their union, until
    /// the intervals left are the connected components of the collinear unions.
    fn merge(&mut self) {
        'again: loop {
            for x in 0..self.n_segs {
                for y in x + 1..self.n_segs {
                    let [a, b] = self.segs[x];
                    let [c, d] = self.segs[y];
                    if collinear(&a, &b, &c)
                        && collinear(&a, &b, &d)
                        && segments_intersect(&a, &b, &c, &d)
                    {
                        self.segs[x] = hull_on_line(&[a, b, c, d]);
                        self.segs[y] = self.segs[self.n_segs - 1];
                        self.n_segs -= 1;
                        continue 'again;
                    }
                }
            }
            return;
        }
    }
}

/// The two extreme points of collinear points, not all equal (ordered by a coordinate on
/// which they differ, which orders a line).
pub(super) fn hull_on_line(p: &[P3]) -> [P3; 2] {
    let k = (0..3)
        .find(|&k| p.iter().any(|q| q[k] != p[0][k]))
        .unwrap_or(0);
    let (mut lo, mut hi) = (p[0], p[0]);
    for q in p {
        if q[k] < lo[k] {
            lo = *q;
        }
        if q[k] > hi[k] {
            hi = *q;
        }
    }
    [lo, hi]
}
