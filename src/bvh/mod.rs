//! The leaf-only AABB structure of paper section 2.1: a root box and leaf boxes of at most N
//! polygons each, no internal nodes. Each polygon lies in exactly one leaf.
//!
//! Layout for the per-frame refit (section 2.4): the mesh stores its vertices leaf by leaf
//! ("slots": a vertex shared by several leaves has a slot in each), so a leaf's vertices are
//! one contiguous run and a refit is a linear, vectorised min/max over the whole array: no
//! tree walk, no gather, no allocation.

mod build;
mod refit;

pub use build::{partition, rule_of_thumb};

use crate::geom::Aabb;

/// Leaf boxes of one mesh. Leaf `l` holds the polygons `leaf_polys[l]..leaf_polys[l + 1]`
/// of the mesh's leaf-ordered polygon array, whose vertices are the slots
/// `leaf_slots[l]..leaf_slots[l + 1]` of the mesh's slot array.
#[derive(Clone, Debug, Default)]
pub struct LeafBoxes {
    /// `leaves + 1` offsets into the leaf-ordered polygons.
    pub leaf_polys: Vec<u32>,
    /// `leaves + 1` offsets into the slot array.
    pub leaf_slots: Vec<u32>,
    /// One box per leaf, refitted by [`LeafBoxes::refit`].
    pub boxes: Vec<Aabb>,
    /// The union of the leaf boxes.
    pub root: Aabb,
}

impl LeafBoxes {
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

    /// Slot range of leaf `l`.
    #[inline]
    pub fn slots(&self, l: usize) -> std::ops::Range<usize> {
        self.leaf_slots[l] as usize..self.leaf_slots[l + 1] as usize
    }

    /// Checks the structure's invariants against the polygons it was built for (tests):
    /// every leaf non-empty, its polygons index only its own slots, its box fitted to them.
    pub fn assert_well_formed(&self, polys: &[u32], k: usize, slots: &[[f32; 3]]) {
        assert_eq!(self.leaf_polys.first(), Some(&0));
        assert_eq!(*self.leaf_polys.last().unwrap() as usize * k, polys.len());
        assert_eq!(*self.leaf_slots.last().unwrap() as usize, slots.len());
        let mut root = Aabb::EMPTY;
        for l in 0..self.len() {
            let r = self.polys(l);
            assert!(!r.is_empty(), "empty leaf {l}");
            let s = self.slots(l);
            let mut b = Aabb::EMPTY;
            for &v in &polys[r.start * k..r.end * k] {
                assert!(
                    s.contains(&(v as usize)),
                    "leaf {l} uses slot {v} outside {s:?}"
                );
                b.grow(&slots[v as usize]);
            }
            assert_eq!(b, self.boxes[l], "leaf {l} is not fitted to its polygons");
            root.merge(&b);
        }
        assert_eq!(root, self.root);
    }
}
