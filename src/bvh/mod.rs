//! The leaf-only AABB structure of paper section 2.1: a root box and leaf boxes of at most N
//! polygons each, no internal nodes. Each polygon lies in exactly one leaf.
//!
//! Layout for the per-frame refit (section 2.4): each leaf keeps the sorted list of distinct
//! vertices its polygons use, all leaves' lists in one array, so a refit is one linear pass
//! over that array with a gather of positions: no tree walk, no allocation.

mod build;
mod refit;

pub use build::{partition, rule_of_thumb};

use crate::geom::Aabb;

/// Leaf boxes of one mesh. Leaf `l` holds the polygons `leaf_polys[l]..leaf_polys[l + 1]` of
/// the mesh's leaf-ordered polygon array.
#[derive(Clone, Debug, Default)]
pub struct LeafBoxes {
    /// `leaves + 1` offsets into the leaf-ordered polygons.
    pub leaf_polys: Vec<u32>,
    /// `leaves + 1` offsets into `verts`.
    pub leaf_verts: Vec<u32>,
    /// Distinct vertex ids of each leaf, leaf after leaf, ascending within a leaf.
    pub verts: Vec<u32>,
    /// One box per leaf, refitted by [`LeafBoxes::refit`].
    pub boxes: Vec<Aabb>,
    /// The union of the leaf boxes.
    pub root: Aabb,
}

impl LeafBoxes {
    /// Builds the per-leaf vertex lists for leaf-ordered polygons (`k` indices each) cut at
    /// `leaf_polys`, and fits the boxes around `positions`.
    pub fn new(leaf_polys: Vec<u32>, polys: &[u32], k: usize, positions: &[[f32; 3]]) -> LeafBoxes {
        let leaves = leaf_polys.len() - 1;
        let mut leaf_verts = Vec::with_capacity(leaves + 1);
        let mut verts = Vec::new();
        leaf_verts.push(0);
        for l in 0..leaves {
            let start = verts.len();
            let (a, b) = (leaf_polys[l] as usize, leaf_polys[l + 1] as usize);
            verts.extend_from_slice(&polys[a * k..b * k]);
            verts[start..].sort_unstable();
            let mut w = start;
            for r in start..verts.len() {
                if r == start || verts[r] != verts[w - 1] {
                    verts[w] = verts[r];
                    w += 1;
                }
            }
            verts.truncate(w);
            leaf_verts.push(verts.len() as u32);
        }
        verts.shrink_to_fit();
        let mut lb = LeafBoxes {
            leaf_polys,
            leaf_verts,
            verts,
            boxes: vec![Aabb::EMPTY; leaves],
            root: Aabb::EMPTY,
        };
        lb.refit(positions);
        lb
    }

    /// Number of leaves.
    pub fn len(&self) -> usize {
        self.boxes.len()
    }

    pub fn is_empty(&self) -> bool {
        self.boxes.is_empty()
    }

    /// Leaf-ordered polygon range of leaf `l`.
    #[inline]
    pub fn polys(&self, l: usize) -> std::ops::Range<usize> {
        self.leaf_polys[l] as usize..self.leaf_polys[l + 1] as usize
    }

    /// Checks the structure's invariants against the polygons it was built for (tests).
    pub fn assert_well_formed(&self, polys: &[u32], k: usize, positions: &[[f32; 3]]) {
        assert_eq!(self.leaf_polys.first(), Some(&0));
        assert_eq!(*self.leaf_polys.last().unwrap() as usize * k, polys.len());
        let mut root = Aabb::EMPTY;
        for l in 0..self.len() {
            let r = self.polys(l);
            assert!(!r.is_empty(), "empty leaf {l}");
            let mut b = Aabb::EMPTY;
            for &v in &polys[r.start * k..r.end * k] {
                b.grow(&positions[v as usize]);
            }
            assert_eq!(b, self.boxes[l], "leaf {l} is not fitted to its polygons");
            root.merge(&b);
        }
        assert_eq!(root, self.root);
    }
}
