//! Building the partition: AABB-tree splits (longest axis of the centroids, at the median)
//! until a box holds at most N polygons; only the leaves are kept. Then the paper's extra
//! split: a leaf whose polygons fall in two groups with empty space between them is cut
//! there, and the halves are kept only because their boxes are disjoint.

use crate::geom::Aabb;

/// The paper's rule of thumb (section 3.1): 50-150 polygons per box below 5000 polygons,
/// 300-600 above. We take the middles, 100 and 450.
pub fn rule_of_thumb(polygons: usize) -> usize {
    if polygons < 5000 {
        100
    } else {
        450
    }
}

/// A gap is "large empty space" when it is at least this fraction of the leaf's extent
/// along the axis of the cut.
const GAP_FRACTION: f32 = 0.1;

/// Orders the polygons (given by their boxes) leaf by leaf. Returns the polygon order and
/// the `leaves + 1` offsets of the leaves in it.
pub fn partition(boxes: &[Aabb], max_per_leaf: usize) -> (Vec<u32>, Vec<u32>) {
    let max_per_leaf = max_per_leaf.max(1);
    let mut order: Vec<u32> = (0..boxes.len() as u32).collect();
    let centroid: Vec<[f32; 3]> = boxes
        .iter()
        .map(|b| [0, 1, 2].map(|k| b.min[k] * 0.5 + b.max[k] * 0.5))
        .collect();
    let mut leaves = vec![0u32];
    let mut stack = vec![(0usize, order.len())];
    let mut scratch = Vec::new();
    // Depth-first, left half first, so leaves come out in spatial order.
    while let Some((a, b)) = stack.pop() {
        let items = &mut order[a..b];
        if items.len() <= max_per_leaf {
            gap_split(items, a, boxes, &mut leaves, &mut scratch);
            continue;
        }
        let mut lo = [f32::INFINITY; 3];
        let mut hi = [f32::NEG_INFINITY; 3];
        for &i in items.iter() {
            for k in 0..3 {
                lo[k] = lo[k].min(centroid[i as usize][k]);
                hi[k] = hi[k].max(centroid[i as usize][k]);
            }
        }
        let axis = (0..3).fold(0, |best, k| {
            if hi[k] - lo[k] > hi[best] - lo[best] {
                k
            } else {
                best
            }
        });
        let mid = items.len() / 2;
        items.select_nth_unstable_by(mid, |&x, &y| {
            centroid[x as usize][axis].total_cmp(&centroid[y as usize][axis])
        });
        stack.push((a + mid, b));
        stack.push((a, a + mid));
    }
    (order, leaves)
}

/// Emits `items` (starting at `offset` in the order) as one leaf, or as several when the
/// polygons split into groups with disjoint boxes separated by a large gap.
fn gap_split(
    items: &mut [u32],
    offset: usize,
    boxes: &[Aabb],
    leaves: &mut Vec<u32>,
    scratch: &mut Vec<u32>,
) {
    let n = items.len();
    if n >= 2 {
        let mut whole = Aabb::EMPTY;
        for &i in items.iter() {
            whole.merge(&boxes[i as usize]);
        }
        // (gap / extent, axis, cut)
        let mut best: Option<(f32, usize, usize)> = None;
        for axis in 0..3 {
            let extent = whole.max[axis] - whole.min[axis];
            // Also skips a NaN extent.
            if extent.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) {
                continue;
            }
            scratch.clear();
            scratch.extend_from_slice(items);
            scratch.sort_unstable_by(|&x, &y| {
                boxes[x as usize].min[axis].total_cmp(&boxes[y as usize].min[axis])
            });
            let mut reach = f32::NEG_INFINITY;
            for c in 1..n {
                reach = reach.max(boxes[scratch[c - 1] as usize].max[axis]);
                let gap = (boxes[scratch[c] as usize].min[axis] - reach) / extent;
                if gap >= GAP_FRACTION && best.is_none_or(|b| gap > b.0) {
                    best = Some((gap, axis, c));
                }
            }
        }
        if let Some((_, axis, cut)) = best {
            items.sort_unstable_by(|&x, &y| {
                boxes[x as usize].min[axis].total_cmp(&boxes[y as usize].min[axis])
            });
            let (left, right) = items.split_at_mut(cut);
            gap_split(left, offset, boxes, leaves, scratch);
            gap_split(right, offset + cut, boxes, leaves, scratch);
            return;
        }
    }
    leaves.push((offset + n) as u32);
}

#[cfg(test)]
mod tests {
    use super::*;

    fn unit_box(x: f32, y: f32, z: f32) -> Aabb {
        Aabb {
            min: [x, y, z],
            max: [x + 1.0, y + 1.0, z + 1.0],
        }
    }

    #[test]
    fn every_polygon_in_exactly_one_leaf_of_bounded_size() {
        let boxes: Vec<Aabb> = (0..1000)
            .map(|i| unit_box((i % 10) as f32, (i / 10 % 10) as f32, (i / 100) as f32))
            .collect();
        for max in [1, 7, 100, 450, 5000] {
            let (order, leaves) = partition(&boxes, max);
            let mut seen = order.clone();
            seen.sort_unstable();
            assert_eq!(seen, (0..1000).collect::<Vec<u32>>());
            assert_eq!(*leaves.last().unwrap(), 1000);
            for w in leaves.windows(2) {
                assert!(w[1] > w[0] && (w[1] - w[0]) as usize <= max);
            }
        }
    }

    #[test]
    fn separated_clusters_get_disjoint_leaves() {
        // Two clusters far apart, fewer polygons than one leaf holds.
        let mut boxes: Vec<Aabb> = (0..20)
            .map(|i| unit_box(i as f32 * 0.1, 0.0, 0.0))
            .collect();
        boxes.extend((0..20).map(|i| unit_box(100.0 + i as f32 * 0.1, 0.0, 0.0)));
        let (order, leaves) = partition(&boxes, 100);
        assert_eq!(leaves, vec![0, 20, 40]);
        assert!(order[..20].iter().all(|&i| i < 20));
    }

    #[test]
    fn identical_polygons_still_terminate() {
        let boxes = vec![unit_box(0.0, 0.0, 0.0); 257];
        let (_, leaves) = partition(&boxes, 16);
        assert!(leaves.windows(2).all(|w| w[1] - w[0] <= 16));
    }
}
