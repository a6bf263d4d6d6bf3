//! Meshes reading their positions from a host's buffer object
//! ([`crate::Scene::bind_gl_buffer`]): the buffers checked before each query, gathered into
//! the arena on the GPU, and read back for contact geometry.

use std::collections::BTreeMap;

use glow::HasContext;

use super::objects::{dispatch, set_u32};
use super::{Bound, Compute, Slot, BINDING, LEAF_VERTS, POS, SRC_BINDING};
use crate::backend::QueryMeshes;
use crate::error::{Error, Result};
use crate::gpu::{buffer, gl_bytes, gl_err, Gl, HostCheck};
use crate::mesh::Mesh;

impl Compute {
    /// Bound mesh `id`'s positions as the last query gathered them from the host's buffer
    /// into the arena (slot order, gather.glsl), read back into `m`'s CPU positions: what
    /// contact geometry needs (the host may have written its buffer since). A sync point.
    pub(super) fn read_gathered(&mut self, gl: &Gl, id: u32, m: &mut Mesh) -> Result<()> {
        let n = m.slot_positions().len();
        let slot = self.slots.get(&id).filter(|s| s.vertices as usize == n);
        let Some(s) = slot.filter(|_| self.gathered.contains(&id)) else {
            // (A GL error since the query dropped the GPU's copy.)
            return Err(Error::invalid(format!(
                "mesh {id} reads its positions from a GL buffer, and the GPU no longer holds \
                those the last query gathered (a GL error since?): query again for its \
                contact geometry"
            )));
        };
        let at = gl_bytes(s.vertex_base.into(), 12, "the positions")?;
        let len = gl_bytes(n as u64, 12, "the positions")?;
        if n == 0 {
            return Ok(());
        }
        let g = &gl.gl;
        let b = self.objects().buffers[POS];
        // SAFETY: as in `rebuild`; the mesh's `n` slots lie at `vertex_base` in the
        // positions buffer (its layout); the mapping is read only within them and unmapped
        // before anything else touches the buffer. The barrier makes the gather's shader
        // writes visible to the mapping.
        unsafe {
            g.memory_barrier(glow::BUFFER_UPDATE_BARRIER_BIT);
            g.bind_buffer(glow::SHADER_STORAGE_BUFFER, Some(b));
            let p = g.map_buffer_range(glow::SHADER_STORAGE_BUFFER, at, len, glow::MAP_READ_BIT);
            if p.is_null() {
                gl.check("mapping the gathered positions")?;
                return Err(gl_err("glMapBufferRange returned NULL".into()));
            }
            let f = std::slice::from_raw_parts(p.cast::<f32>(), 3 * n);
            m.set_slot_positions(f);
            g.unmap_buffer(glow::SHADER_STORAGE_BUFFER);
        }
        self.readbacks += 1;
        gl.check("reading back the positions a query gathered")
    }

    /// Every enabled mesh's host buffer, before anything is touched: still a buffer object,
    /// not mapped, and still holding the mesh's vertices (the host may have re-specified it
    /// smaller or deleted it since `bind_gl_buffer`). INVALID_ARGUMENT naming the mesh and
    /// the sizes otherwise. The guard restores the COPY_READ_BUFFER binding used to ask.
    pub(super) fn check_bound(&self, gl: &Gl, meshes: &BTreeMap<u32, Mesh>) -> Result<()> {
        for (&id, b) in &self.bound {
            if meshes.get(&id).is_some_and(|m| m.enabled) {
                b.host.check(gl, HostCheck::Use(id))?;
            }
        }
        Ok(())
    }

    /// Host buffers of the query's meshes: gathers their positions into the arena on the
    /// GPU, behind a `GL_SHADER_STORAGE_BARRIER_BIT` barrier so that the host's own shader
    /// writes before the call are seen (the host needs no barrier); the query then refits
    /// their leaves.
    pub(super) fn gather_bound(&self, gl: &Gl, q: &QueryMeshes<'_>) -> Result<()> {
        let bound: Vec<(&Bound, &Slot)> = q
            .meshes
            .iter()
            .filter_map(|(id, _)| Some((self.bound.get(id)?, &self.slots[id])))
            .collect();
        if bound.is_empty() {
            return Ok(());
        }
        let g = &gl.gl;
        let o = self.objects();
        // SAFETY: as in `rebuild`; the host's buffer was checked to be a buffer object of
        // this context holding every vertex at its offset and stride, and not mapped, by
        // `check_bound` in this call's `prepare`.
        unsafe {
            g.memory_barrier(glow::SHADER_STORAGE_BARRIER_BIT);
            g.use_program(Some(o.gather));
            for k in [POS, LEAF_VERTS] {
                g.bind_buffer_base(glow::SHADER_STORAGE_BUFFER, BINDING[k], Some(o.buffers[k]));
            }
            for (b, s) in bound {
                g.bind_buffer_base(
                    glow::SHADER_STORAGE_BUFFER,
                    SRC_BINDING,
                    buffer(b.host.buffer),
                );
                set_u32(g, o.gather, "u_src_offset", b.offset);
                set_u32(g, o.gather, "u_src_stride", b.stride);
                set_u32(g, o.gather, "u_dst_vertex", s.vertex_base);
                dispatch(g, o.gather, s.vertices);
            }
            g.memory_barrier(glow::SHADER_STORAGE_BARRIER_BIT);
        }
        gl.check("gathering positions from host buffers")
    }
}
