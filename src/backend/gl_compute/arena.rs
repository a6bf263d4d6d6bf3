//! The meshes laid out one after the other in the arenas (positions, polygons, leaves,
//! boxes, all meshes in one buffer each), laid out again when meshes come or go, and their
//! CPU positions and leaf boxes uploaded before each query when they changed.

use std::collections::BTreeMap;

use glow::HasContext;

use super::objects::{allocate, bytes, upload};
use super::{Compute, Slot, BOXES, LEAF_POLYS, LEAF_RANGE, LEAF_VERTS, POLYS, POS, ROOTS};
use crate::error::{Error, ErrorKind, Result};
use crate::gpu::{gl_bytes, Gl};
use crate::mesh::Mesh;

fn arena_too_big(what: &str) -> Error {
    Error::new(
        ErrorKind::Unsupported,
        format!("the scene's meshes have 2^32 {what} or more in all; GL_COMPUTE numbers them in 32 bits"),
    )
}

/// The arenas' index arrays for a set of meshes, and where each mesh lives in them.
#[derive(Default)]
struct Arena {
    slots: BTreeMap<u32, Slot>,
    /// 4 global slot ids per polygon (the 4th u32::MAX for a triangle).
    polys: Vec<u32>,
    /// (first slot, end slot, arena index) per global leaf.
    range: Vec<u32>,
    /// Slot -> the caller's vertex index, all meshes.
    verts: Vec<u32>,
    /// (first, end) global polygon per global leaf.
    leaf_polys: Vec<u32>,
    vertices: u32,
    leaves: u32,
}

impl Arena {
    /// Lays `meshes` out one after the other; counts past 32 bits are refused.
    fn of(meshes: &BTreeMap<u32, Mesh>) -> Result<Arena> {
        let mut a = Arena::default();
        let mut polys_total = 0u32;
        for (index, (&id, m)) in meshes.iter().enumerate() {
            let (vb, pb, lb) = (a.vertices, polys_total, a.leaves);
            let count = |n: usize, what| u32::try_from(n).map_err(|_| arena_too_big(what));
            let nslots = count(m.slot_positions().len(), "vertex slots")?;
            let npolys = count(m.polygon_count(), "polygons")?;
            let nleaves = count(m.leaf_count(), "leaves")?;
            // Every id below is below these ends, so no sum below can wrap.
            a.vertices = vb
                .checked_add(nslots)
                .ok_or_else(|| arena_too_big("vertex slots"))?;
            polys_total = pb
                .checked_add(npolys)
                .ok_or_else(|| arena_too_big("polygons"))?;
            a.leaves = lb
                .checked_add(nleaves)
                .ok_or_else(|| arena_too_big("leaves"))?;
            for p in 0..m.polygon_count() {
                let v = m.poly(p);
                a.polys.extend(v.iter().map(|&x| x + vb));
                if m.k == 3 {
                    a.polys.push(u32::MAX);
                }
            }
            let lv = &m.leaves;
            for l in 0..lv.len() {
                a.range.extend([
                    lv.leaf_slots[l] + vb,
                    lv.leaf_slots[l + 1] + vb,
                    index as u32,
                ]);
                a.leaf_polys
                    .extend([lv.leaf_polys[l] + pb, lv.leaf_polys[l + 1] + pb]);
            }
            a.verts.extend_from_slice(m.slot_vertices());
            a.slots.insert(
                id,
                Slot {
                    index: index as u32,
                    vertex_base: vb,
                    poly_base: pb,
                    leaf_base: lb,
                    vertices: nslots,
                    leaves: nleaves,
                    polys: npolys,
                    uploaded: None,
                },
            );
        }
        Ok(a)
    }
}

impl Compute {
    fn layout_matches(&self, meshes: &BTreeMap<u32, Mesh>) -> bool {
        self.slots.len() == meshes.len()
            && self.slots.iter().zip(meshes).all(|((a, s), (b, m))| {
                a == b
                    && s.vertices as usize == m.slot_positions().len()
                    && s.polys as usize == m.polygon_count()
            })
    }

    /// Before each query: checks the host buffers, lays the meshes out again if they
    /// changed, uploads positions and boxes that changed on the CPU. (Host buffers are
    /// gathered by the query that uses them, whose read-back then waits for the gather: a
    /// call that answers has finished reading them.)
    pub(super) fn prepare(&mut self, gl: &Gl, meshes: &BTreeMap<u32, Mesh>) -> Result<()> {
        self.gathered.clear();
        self.check_bound(gl, meshes)?;
        if !self.layout_matches(meshes) {
            self.rebuild(gl, meshes)?;
        }
        self.upload_changed(gl, meshes)?;
        gl.check("uploading positions")
    }

    /// Lays every mesh out in the arenas again (meshes were added or removed).
    fn rebuild(&mut self, gl: &Gl, meshes: &BTreeMap<u32, Mesh>) -> Result<()> {
        self.slots.clear();
        let a = Arena::of(meshes)?;
        let sizes = [
            (POS, gl_bytes(a.vertices.into(), 12, "the positions")?),
            (BOXES, gl_bytes(a.leaves.into(), 24, "the leaf boxes")?),
            (ROOTS, gl_bytes(meshes.len() as u64, 24, "the root boxes")?),
        ];
        let g = &gl.gl;
        let b = &self.objects().buffers;
        // SAFETY: `gl` is loaded for the context current on this thread (every GL-backed
        // call's contract); the buffers are ours, the sizes checked.
        unsafe {
            for (k, size) in sizes {
                allocate(g, b[k], size, glow::DYNAMIC_DRAW);
            }
            upload(g, b[POLYS], bytes(&a.polys));
            upload(g, b[LEAF_RANGE], bytes(&a.range));
            upload(g, b[LEAF_VERTS], bytes(&a.verts));
            upload(g, b[LEAF_POLYS], bytes(&a.leaf_polys));
        }
        self.slots = a.slots;
        Ok(())
    }

    /// CPU-side positions that changed, and their CPU-refitted boxes.
    fn upload_changed(&mut self, gl: &Gl, meshes: &BTreeMap<u32, Mesh>) -> Result<()> {
        let g = &gl.gl;
        let bufs = self
            .obj
            .as_ref()
            .expect("GL objects exist until release")
            .buffers;
        for (id, m) in meshes {
            let s = self.slots.get_mut(id).expect("laid out");
            if self.bound.contains_key(id) || s.uploaded == Some(m.generation) {
                continue;
            }
            let at = gl_bytes(s.vertex_base.into(), 12, "the positions")?;
            self.box_words.clear();
            for b in &m.leaves.boxes {
                self.box_words.extend(b.min.iter().chain(&b.max));
            }
            let boxes_at = gl_bytes(s.leaf_base.into(), 24, "the leaf boxes")?;
            // SAFETY: as in `rebuild`; the ranges lie in the buffers as `rebuild` sized them
            // (the mesh's slots and leaves are where its layout put them).
            unsafe {
                g.bind_buffer(glow::SHADER_STORAGE_BUFFER, Some(bufs[POS]));
                g.buffer_sub_data_u8_slice(
                    glow::SHADER_STORAGE_BUFFER,
                    at,
                    bytes(m.slot_positions()),
                );
                g.bind_buffer(glow::SHADER_STORAGE_BUFFER, Some(bufs[BOXES]));
                g.buffer_sub_data_u8_slice(
                    glow::SHADER_STORAGE_BUFFER,
                    boxes_at,
                    bytes(&self.box_words),
                );
            }
            s.uploaded = Some(m.generation);
        }
        Ok(())
    }
}
