//! The per-frame refit (paper section 2.4): every leaf box and the root refitted around the
//! vertices its polygons use, in one linear pass over the leaves' vertex lists.

use super::LeafBoxes;
use crate::geom::Aabb;

impl LeafBoxes {
    /// Refits every leaf and the root to `positions`. No allocation.
    pub fn refit(&mut self, positions: &[[f32; 3]]) {
        let mut root = Aabb::EMPTY;
        for (l, out) in self.boxes.iter_mut().enumerate() {
            let ids = &self.verts[self.leaf_verts[l] as usize..self.leaf_verts[l + 1] as usize];
            let (mut lo, mut hi) = ([f32::INFINITY; 3], [f32::NEG_INFINITY; 3]);
            for &v in ids {
                let p = positions[v as usize];
                lo = [lo[0].min(p[0]), lo[1].min(p[1]), lo[2].min(p[2])];
                hi = [hi[0].max(p[0]), hi[1].max(p[1]), hi[2].max(p[2])];
            }
            *out = Aabb { min: lo, max: hi };
            root.merge(out);
        }
        self.root = root;
    }
}
