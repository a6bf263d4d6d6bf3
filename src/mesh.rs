//! A deformable mesh: positions (copied), fixed topology, and its leaf-only AABB structure.

use crate::bvh::{partition, rule_of_thumb, LeafBoxes};
use crate::error::{Error, ErrorKind, Result};
use crate::geom::{widen, Aabb, P3};

/// Vertex positions as the caller lays them out: three `f32` per vertex (native endianness),
/// `stride` bytes apart in a byte slice, or tightly packed points. Reading it is safe; the
/// FFI builds the byte form from the caller's pointer.
#[derive(Clone, Copy, Debug)]
pub struct Positions<'a>(Src<'a>);

#[derive(Clone, Copy, Debug)]
enum Src<'a> {
    Bytes {
        bytes: &'a [u8],
        stride: usize,
        count: usize,
    },
    Points(&'a [[f32; 3]]),
}

impl<'a> Positions<'a> {
    /// `count` vertices `stride` bytes apart (0 means tightly packed, 12). Fails when the
    /// stride is below 12 or not a multiple of 4, or `bytes` is too short.
    pub fn new(bytes: &'a [u8], count: usize, stride: usize) -> Result<Positions<'a>> {
        let stride = if stride == 0 { 12 } else { stride };
        if stride < 12 || stride % 4 != 0 {
            return Err(Error::invalid(format!(
                "position_stride {stride} must be 0 or a multiple of 4 that is at least 12"
            )));
        }
        let need = Self::byte_len(count, stride).ok_or_else(|| {
            Error::invalid(format!(
                "vertex_count {count} times position_stride {stride} overflows"
            ))
        })?;
        if bytes.len() < need {
            return Err(Error::invalid(format!(
                "{} bytes of positions, {need} needed",
                bytes.len()
            )));
        }
        Ok(Positions(Src::Bytes {
            bytes,
            stride,
            count,
        }))
    }

    /// From tightly packed points.
    pub fn from_points(points: &'a [[f32; 3]]) -> Positions<'a> {
        Positions(Src::Points(points))
    }

    /// Bytes a strided array of `count` vertices spans (`None` on overflow).
    pub fn byte_len(count: usize, stride: usize) -> Option<usize> {
        if count == 0 {
            return Some(0);
        }
        (count - 1).checked_mul(stride)?.checked_add(12)
    }

    pub fn len(&self) -> usize {
        match self.0 {
            Src::Bytes { count, .. } => count,
            Src::Points(p) => p.len(),
        }
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Vertex `i`.
    #[inline]
    pub fn get(&self, i: usize) -> [f32; 3] {
        match self.0 {
            Src::Bytes { bytes, stride, .. } => read3(&bytes[i * stride..i * stride + 12]),
            Src::Points(p) => p[i],
        }
    }

    /// Copies every vertex into `dst` (of the same length); false if any coordinate is NaN
    /// or infinite (`dst` is then partly written).
    pub fn copy_checked(&self, dst: &mut [[f32; 3]]) -> bool {
        let mut finite = true;
        let mut put = |d: &mut [f32; 3], p: [f32; 3]| {
            finite &= p[0].is_finite() & p[1].is_finite() & p[2].is_finite();
            *d = p;
        };
        match self.0 {
            Src::Bytes {
                bytes,
                stride,
                count,
            } => {
                if stride == 12 {
                    for (d, b) in dst.iter_mut().zip(bytes[..count * 12].chunks_exact(12)) {
                        put(d, read3(b));
                    }
                } else {
                    for (i, d) in dst.iter_mut().enumerate() {
                        put(d, read3(&bytes[i * stride..i * stride + 12]));
                    }
                }
            }
            Src::Points(p) => {
                for (d, &s) in dst.iter_mut().zip(p) {
                    put(d, s);
                }
            }
        }
        finite
    }

    /// Index of the first vertex with a NaN or infinite coordinate.
    pub fn first_non_finite(&self) -> Option<usize> {
        (0..self.len()).find(|&i| !self.get(i).iter().all(|c| c.is_finite()))
    }
}

#[inline]
fn read3(b: &[u8]) -> [f32; 3] {
    let f = |o: usize| f32::from_ne_bytes([b[o], b[o + 1], b[o + 2], b[o + 3]]);
    [f(0), f(4), f(8)]
}

/// A mesh as the scene holds it.
#[derive(Clone, Debug)]
pub struct Mesh {
    pub(crate) positions: Vec<[f32; 3]>,
    /// Second buffer for a full update: filled and checked, then swapped in.
    staging: Vec<[f32; 3]>,
    /// Vertices per polygon: 3 or 4.
    pub(crate) k: usize,
    /// Polygons in leaf order, `k` vertex indices each.
    pub(crate) polys: Vec<u32>,
    /// Leaf-order position -> the caller's polygon index.
    pub(crate) poly_ids: Vec<u32>,
    pub(crate) leaves: LeafBoxes,
    pub(crate) enabled: bool,
    /// Bumped at every position change (lets GPU copies know they are stale).
    pub(crate) generation: u64,
}

impl Mesh {
    /// Validates and builds a mesh. `indices` holds `k` vertex indices per polygon, in the
    /// caller's polygon order; `max_per_leaf` of 0 applies the paper's rule of thumb.
    pub fn new(
        positions: Positions<'_>,
        indices: &[u32],
        k: usize,
        max_per_leaf: usize,
    ) -> Result<Mesh> {
        if k != 3 && k != 4 {
            return Err(Error::invalid(format!(
                "vertices_per_polygon is {k}; it must be 3 or 4"
            )));
        }
        if positions.is_empty() {
            return Err(Error::invalid("vertex_count is 0"));
        }
        if indices.is_empty() {
            return Err(Error::invalid("polygon_count is 0"));
        }
        if indices.len() % k != 0 {
            return Err(Error::invalid(
                "index count is not a multiple of vertices_per_polygon",
            ));
        }
        let n_polys = indices.len() / k;
        if n_polys > u32::MAX as usize - 1 || positions.len() > u32::MAX as usize {
            return Err(Error::invalid("more than 2^32 - 2 polygons or vertices"));
        }
        if let Some(v) = positions.first_non_finite() {
            return Err(Error::new(
                ErrorKind::NonFinite,
                format!("positions: vertex {v} has a NaN or infinite coordinate"),
            ));
        }
        if let Some(i) = indices.iter().position(|&i| i as usize >= positions.len()) {
            return Err(Error::new(
                ErrorKind::IndexOutOfRange,
                format!(
                    "indices: polygon {} names vertex {}, but vertex_count is {}",
                    i / k,
                    indices[i],
                    positions.len()
                ),
            ));
        }
        let pos: Vec<[f32; 3]> = (0..positions.len()).map(|i| positions.get(i)).collect();
        let boxes: Vec<Aabb> = indices
            .chunks_exact(k)
            .map(|p| {
                let mut b = Aabb::EMPTY;
                p.iter().for_each(|&v| b.grow(&pos[v as usize]));
                b
            })
            .collect();
        let max = if max_per_leaf == 0 {
            rule_of_thumb(n_polys)
        } else {
            max_per_leaf
        };
        let (order, leaf_polys) = partition(&boxes, max);
        let mut polys = Vec::with_capacity(indices.len());
        for &p in &order {
            polys.extend_from_slice(&indices[p as usize * k..(p as usize + 1) * k]);
        }
        let leaves = LeafBoxes::new(leaf_polys, &polys, k, &pos);
        Ok(Mesh {
            staging: Vec::new(),
            positions: pos,
            k,
            polys,
            poly_ids: order,
            leaves,
            enabled: true,
            generation: 0,
        })
    }

    pub fn vertex_count(&self) -> usize {
        self.positions.len()
    }

    pub fn polygon_count(&self) -> usize {
        self.poly_ids.len()
    }

    pub fn vertices_per_polygon(&self) -> usize {
        self.k
    }

    pub fn leaf_count(&self) -> usize {
        self.leaves.len()
    }

    pub fn leaves(&self) -> &LeafBoxes {
        &self.leaves
    }

    pub fn root(&self) -> Aabb {
        self.leaves.root
    }

    pub fn positions(&self) -> &[[f32; 3]] {
        &self.positions
    }

    /// Replaces vertices `first..first + src.len()` and refits. Rejected whole (nothing
    /// changes) when the range runs past the end or a coordinate is not finite.
    pub fn update_positions(&mut self, first: usize, src: Positions<'_>) -> Result<()> {
        let n = self.positions.len();
        let end = first
            .checked_add(src.len())
            .filter(|&e| e <= n)
            .ok_or_else(|| {
                Error::invalid(format!(
                    "first_vertex {first} + vertex_count {} runs past the mesh's {n} vertices",
                    src.len()
                ))
            })?;
        if first == 0 && end == n {
            // Full update: copy into the staging buffer while checking, swap on success.
            self.staging.resize(n, [0.0; 3]);
            if !src.copy_checked(&mut self.staging) {
                let v = src.first_non_finite().unwrap_or(0);
                return Err(Error::new(
                    ErrorKind::NonFinite,
                    format!("positions: vertex {v} has a NaN or infinite coordinate"),
                ));
            }
            std::mem::swap(&mut self.positions, &mut self.staging);
        } else {
            if let Some(v) = src.first_non_finite() {
                return Err(Error::new(
                    ErrorKind::NonFinite,
                    format!(
                        "positions: vertex {} has a NaN or infinite coordinate",
                        first + v
                    ),
                ));
            }
            src.copy_checked(&mut self.positions[first..end]);
        }
        self.leaves.refit(&self.positions);
        self.generation += 1;
        Ok(())
    }

    /// Refits the leaf boxes to the current positions (what an update does after copying).
    pub fn refit(&mut self) {
        self.leaves.refit(&self.positions);
    }

    /// Vertex ids of leaf-ordered polygon `p`.
    #[inline]
    pub fn poly(&self, p: usize) -> &[u32] {
        &self.polys[p * self.k..(p + 1) * self.k]
    }

    /// Box of leaf-ordered polygon `p`.
    #[inline]
    pub fn poly_box(&self, p: usize) -> Aabb {
        let mut b = Aabb::EMPTY;
        for &v in self.poly(p) {
            b.grow(&self.positions[v as usize]);
        }
        b
    }

    /// The triangles of leaf-ordered polygon `p`: one for a triangle, (v0,v1,v2) and
    /// (v0,v2,v3) for a quad. Returns how many were written.
    #[inline]
    pub fn triangles(&self, p: usize, out: &mut [[P3; 3]; 2]) -> usize {
        let v = self.poly(p);
        let w = |i: usize| widen(&self.positions[v[i] as usize]);
        out[0] = [w(0), w(1), w(2)];
        if self.k == 4 {
            out[1] = [w(0), w(2), w(3)];
            2
        } else {
            1
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn grid(n: usize) -> (Vec<[f32; 3]>, Vec<u32>) {
        let mut v = Vec::new();
        for j in 0..=n {
            for i in 0..=n {
                v.push([i as f32, j as f32, ((i * 7 + j * 3) % 5) as f32 * 0.1]);
            }
        }
        let mut t = Vec::new();
        let id = |i: usize, j: usize| (j * (n + 1) + i) as u32;
        for j in 0..n {
            for i in 0..n {
                t.extend([
                    id(i, j),
                    id(i + 1, j),
                    id(i + 1, j + 1),
                    id(i, j),
                    id(i + 1, j + 1),
                    id(i, j + 1),
                ]);
            }
        }
        (v, t)
    }

    #[test]
    fn build_and_refit_keep_boxes_fitted() {
        let (v, t) = grid(40);
        let mut m = Mesh::new(Positions::from_points(&v), &t, 3, 64).unwrap();
        m.leaves.assert_well_formed(&m.polys, 3, &m.positions);
        let mut ids = m.poly_ids.clone();
        ids.sort_unstable();
        assert_eq!(ids, (0..t.len() as u32 / 3).collect::<Vec<_>>());
        let moved: Vec<[f32; 3]> = v
            .iter()
            .map(|p| [p[0] * 1.5, p[1] - 3.0, p[2] + p[0].sin()])
            .collect();
        m.update_positions(0, Positions::from_points(&moved))
            .unwrap();
        m.leaves.assert_well_formed(&m.polys, 3, &m.positions);
        // A range update.
        m.update_positions(10, Positions::from_points(&v[10..100]))
            .unwrap();
        assert_eq!(m.positions[10], v[10]);
        assert_eq!(m.positions[100], moved[100]);
        m.leaves.assert_well_formed(&m.polys, 3, &m.positions);
    }

    #[test]
    fn rejected_updates_change_nothing() {
        let (v, t) = grid(8);
        let mut m = Mesh::new(Positions::from_points(&v), &t, 3, 16).unwrap();
        let before = (m.positions.clone(), m.leaves.boxes.clone());
        let mut bad = v.clone();
        bad[17][1] = f32::NAN;
        let e = m
            .update_positions(0, Positions::from_points(&bad))
            .unwrap_err();
        assert_eq!(e.kind, ErrorKind::NonFinite);
        assert!(e.message.contains("vertex 17"));
        let e = m
            .update_positions(3, Positions::from_points(&bad[..20]))
            .unwrap_err();
        assert_eq!(e.kind, ErrorKind::NonFinite);
        assert!(e.message.contains("vertex 20"), "{}", e.message);
        let e = m
            .update_positions(v.len() - 2, Positions::from_points(&v[..3]))
            .unwrap_err();
        assert_eq!(e.kind, ErrorKind::InvalidArgument);
        assert_eq!(before, (m.positions.clone(), m.leaves.boxes.clone()));
    }

    #[test]
    fn bad_meshes_are_rejected_with_the_argument_named() {
        let (v, t) = grid(2);
        let p = Positions::from_points(&v);
        assert!(Mesh::new(p, &t, 5, 0)
            .unwrap_err()
            .message
            .contains("vertices_per_polygon"));
        let mut t2 = t.clone();
        t2[4] = 999;
        let e = Mesh::new(p, &t2, 3, 0).unwrap_err();
        assert_eq!(e.kind, ErrorKind::IndexOutOfRange);
        assert!(e.message.contains("polygon 1") && e.message.contains("999"));
        assert!(Positions::new(&[0u8; 24], 2, 8).is_err());
        assert!(Positions::new(&[0u8; 23], 2, 0).is_err());
        assert!(Positions::new(&[0u8; 24], usize::MAX, 16).is_err());
    }
}
