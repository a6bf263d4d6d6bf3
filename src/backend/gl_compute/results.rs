//! The query's answer: the one read-back (the result header and the step-5 hits), the
//! header's failures, and the hits as contacts (each confirmed by the CPU backend's test
//! when every position is on the CPU).

use glow::HasContext;

use super::steps::Plan;
use super::{Caps, Compute, HEADER, H_HITS, H_NONFINITE, H_TOO_MANY, RESULT};
use crate::backend::{Contact, QueryMeshes};
use crate::error::{Error, ErrorKind, Result};
use crate::geom::polygon::polygon_meets;
use crate::gpu::{gl_bytes, gl_err, Gl};
use crate::mesh::Mesh;

impl Compute {
    /// The one read-back: maps the result, copies the header and the hits it counts into
    /// `raw`.
    pub(super) fn read_back(&mut self, gl: &Gl, caps: Caps, raw: &mut Vec<u32>) -> Result<()> {
        gl.check("the query dispatches")?;
        let len = gl_bytes(HEADER as u64 + 2 * u64::from(caps.hits), 4, "contacts")?;
        let g = &gl.gl;
        let b = self.objects().buffers[RESULT];
        // SAFETY: as in `rebuild`; the result buffer holds `len` bytes (sized for `caps`);
        // the mapping is read only within them (the hit count is clamped to the room) and
        // unmapped before anything else touches the buffer.
        unsafe {
            g.bind_buffer(glow::SHADER_STORAGE_BUFFER, Some(b));
            let p = g.map_buffer_range(glow::SHADER_STORAGE_BUFFER, 0, len, glow::MAP_READ_BIT);
            if p.is_null() {
                gl.check("mapping the query's result")?;
                return Err(gl_err("glMapBufferRange returned NULL".into()));
            }
            let words = p.cast::<u32>();
            let n = (*words.add(H_HITS)).min(caps.hits) as usize;
            raw.clear();
            raw.extend_from_slice(std::slice::from_raw_parts(words, HEADER + 2 * n));
            g.unmap_buffer(glow::SHADER_STORAGE_BUFFER);
        }
        self.readbacks += 1;
        gl.check("reading the query's result")
    }

    /// The header's failures: a NaN or infinity in a host buffer (naming the mesh), or a
    /// step of 2^31 tests or more.
    pub(super) fn check_header(&self, raw: &[u32]) -> Result<()> {
        if raw[H_NONFINITE] != 0 {
            let id = self
                .slots
                .iter()
                .find(|(_, s)| s.index == raw[H_NONFINITE] - 1)
                .map_or(0, |(id, _)| *id);
            return Err(Error::new(
                ErrorKind::NonFinite,
                format!("mesh {id}: its bound GL buffer holds a NaN or infinite coordinate"),
            ));
        }
        if raw[H_TOO_MANY] != 0 {
            return Err(Error::new(
                ErrorKind::Unsupported,
                "a step of this query asks 2^31 tests or more, more than one dispatch takes",
            ));
        }
        Ok(())
    }
}

/// The step-5 hits (global reference polygon, global other polygon) as contacts. When
/// every position is on the CPU, each hit is confirmed with the CPU backend's test at the
/// epsilon asked for (the GPU used at least the minimum depth: it lost nothing).
pub(super) fn contacts(q: &QueryMeshes<'_>, plan: &Plan, hits: &[u32], out: &mut Vec<Contact>) {
    // Global polygon id -> (mesh position, leaf-ordered polygon).
    let locate = |gp: u32| {
        let i = plan.bases.partition_point(|&(b, _)| b <= gp) - 1;
        let (base, mi) = plan.bases[i];
        (mi, gp - base)
    };
    let confirm = plan.refit.is_empty().then_some(q.half_depth);
    let ref_mesh = q.meshes[0].1;
    for hit in hits.chunks_exact(2) {
        let (rm, rp) = locate(hit[0]);
        let (cm, cp) = locate(hit[1]);
        debug_assert_eq!(rm, 0);
        let (other_id, other) = q.meshes[cm as usize];
        if let Some(h) = confirm {
            if !confirmed(ref_mesh, rp as usize, other, cp as usize, h) {
                continue;
            }
        }
        out.push(Contact {
            other_mesh: other_id,
            reference_polygon: ref_mesh.poly_ids[rp as usize],
            other_polygon: other.poly_ids[cp as usize],
        });
    }
}

/// The CPU backend's step-5 test ([`polygon_meets`]) for polygon `v` of `vm` and polygon
/// `c` of `cm` at half depth `h` (exact intersection at 0).
fn confirmed(vm: &Mesh, v: usize, cm: &Mesh, c: usize, h: f64) -> bool {
    let mut vt = [[[0.0; 3]; 3]; 2];
    let nv = vm.triangles(v, &mut vt);
    let mut ct = [[[0.0; 3]; 3]; 2];
    let nc = cm.triangles(c, &mut ct);
    polygon_meets(&vt, nv, &ct, nc, h)
}
