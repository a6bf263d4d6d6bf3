//! The contact geometry of an answer: the positions it reads (meshes read from host GL
//! buffers at the positions their query used), whether its pairs are known to intersect,
//! and the work shared out over the workers.

use std::collections::BTreeMap;
use std::mem::MaybeUninit;

use super::{unknown, Planner};
use crate::backend::{Backend, Contact, Pair};
use crate::error::{try_reserve, Error, ErrorKind, Result};
use crate::geom::contact::{contact_geometry_into, ContactGeometry, PolygonPairs};
use crate::geom::P3;
use crate::mesh::Mesh;
use crate::mesh::MeshId;

/// The pairs of an answer: a reference query's contacts, or a whole-scene query's pairs.
#[derive(Clone, Copy)]
pub(crate) enum Answer<'a> {
    /// The contacts of reference mesh `.0`.
    One(MeshId, &'a [Contact]),
    /// A whole-scene query's pairs.
    All(&'a [Pair]),
}

impl Answer<'_> {
    /// How many pairs.
    pub fn len(&self) -> usize {
        match self {
            Answer::One(_, c) => c.len(),
            Answer::All(p) => p.len(),
        }
    }

    /// Pair `k` as (mesh a, polygon a, mesh b, polygon b).
    #[inline(always)]
    fn item(&self, k: usize) -> (MeshId, u32, MeshId, u32) {
        match *self {
            Answer::One(r, contacts) => {
                let c = &contacts[k];
                (r, c.reference_polygon, c.other_mesh, c.other_polygon)
            }
            Answer::All(pairs) => {
                let p = &pairs[k];
                (p.mesh_a, p.polygon_a, p.mesh_b, p.polygon_b)
            }
        }
    }
}

/// Contact geometry is shared between the workers above this many pairs, in chunks of
/// `GEOMETRY_CHUNK`.
const PAR_GEOMETRY: usize = 256;
const GEOMETRY_CHUNK: usize = 64;

impl Planner {
    /// The contact geometry of `answer` into `out` (entry `i` for pair `i`), the meshes at
    /// the positions the answer's query used; `exact_answer`: the answer was decided exactly
    /// at epsilon 0, so its pairs are known to intersect.
    pub fn contact_geometry(
        &mut self,
        meshes: &mut BTreeMap<MeshId, Mesh>,
        answer: Answer<'_>,
        exact_answer: bool,
        out: &mut Vec<ContactGeometry>,
    ) -> Result<()> {
        let n = answer.len();
        let bound = self.selector.any_gl_bound();
        if bound {
            self.positions_for_geometry(meshes, answer)?;
        }
        if n > PAR_GEOMETRY {
            self.workers.start()?;
        }
        out.clear();
        try_reserve(out, n, "the contact geometry")?;
        // Written once, by the fill below, in the vector's spare capacity.
        let spare = &mut out.spare_capacity_mut()[..n];
        // Four triangle pairs at a time. At epsilon 0 every pair of the answer intersects
        // (the exact test decided it), so the geometry skips that test; not where a mesh
        // reads a host GL buffer on a GL backend (GL_COMPUTE's answer for it has no CPU
        // confirmation and may hold pairs within its rounding band: the geometry decides
        // them exactly). A CPU scene reads the buffer in and answers exactly.
        let unconfirmed = bound && self.selector.backend() != Backend::Cpu;
        let known = exact_answer && !unconfirmed;
        let meshes = &*meshes;
        // Entries `out` from pair `base` on.
        let fill = |out: &mut [MaybeUninit<ContactGeometry>], base: usize| -> Result<()> {
            contact_geometry_into(
                out,
                known,
                AnswerPairs {
                    answer,
                    meshes,
                    base,
                    seen: [None; 2],
                },
            )
        };
        match &self.workers.pool {
            Some(pool) if n > PAR_GEOMETRY => pool.install(|| {
                use rayon::prelude::*;
                spare
                    .par_chunks_mut(GEOMETRY_CHUNK)
                    .enumerate()
                    .try_for_each(|(c, chunk)| fill(chunk, c * GEOMETRY_CHUNK))
            })?,
            _ => fill(spare, 0)?,
        }
        // SAFETY: the fill succeeded, so it initialized every one of the first `n` entries
        // (capacity reserved above).
        unsafe { out.set_len(n) };
        Ok(())
    }

    /// Meshes of the answer read from a host GL buffer: their positions as the query used
    /// them, into their CPU positions (each mesh once per run of pairs: the pairs of an
    /// answer come from a few meshes, in runs).
    fn positions_for_geometry(
        &mut self,
        meshes: &mut BTreeMap<MeshId, Mesh>,
        answer: Answer<'_>,
    ) -> Result<()> {
        let mut ids: Vec<MeshId> = Vec::new();
        let mut last_seen = [None; 2];
        for k in 0..answer.len() {
            let (a, _, b, _) = answer.item(k);
            for (side, id) in [a, b].into_iter().enumerate() {
                if last_seen[side] != Some(id) {
                    last_seen[side] = Some(id);
                    if self.selector.gl_bound(id) && !ids.contains(&id) {
                        ids.push(id);
                    }
                }
            }
        }
        self.selector.positions_for_geometry(meshes, &ids)
    }
}

/// The pairs of an answer from `base` on, as [`contact_geometry_into`] reads them.
struct AnswerPairs<'m> {
    answer: Answer<'m>,
    meshes: &'m BTreeMap<MeshId, Mesh>,
    base: usize,
    /// The mesh of each side last read.
    seen: Last<'m>,
}

impl PolygonPairs for AnswerPairs<'_> {
    type Error = Error;
    #[inline(always)]
    fn fetch(
        &mut self,
        i: usize,
        ta: [&mut [P3; 3]; 2],
        tb: [&mut [P3; 3]; 2],
    ) -> Result<(usize, usize)> {
        let (a, pa, b, pb) = self.answer.item(self.base + i);
        let na = polygon(self.meshes, &mut self.seen, 0, a, pa, ta)?;
        let nb = polygon(self.meshes, &mut self.seen, 1, b, pb, tb)?;
        Ok((na, nb))
    }
}

/// The last mesh looked up for each side of a run of pairs (consecutive pairs mostly
/// share them).
type Last<'m> = [Option<(MeshId, &'m Mesh)>; 2];

/// Fills `out` with polygon `p` of mesh `id` (its triangles in world positions), returning
/// how many.
#[inline(always)]
fn polygon<'m>(
    meshes: &'m BTreeMap<MeshId, Mesh>,
    last: &mut Last<'m>,
    side: usize,
    id: MeshId,
    p: u32,
    out: [&mut [P3; 3]; 2],
) -> Result<usize> {
    let m = match last[side] {
        Some((at, m)) if at == id => m,
        _ => {
            let m = meshes.get(&id).ok_or_else(|| unknown(id))?;
            last[side] = Some((id, m));
            m
        }
    };
    m.polygon_triangles_into(p, out)
        .ok_or_else(|| Error::new(ErrorKind::Internal, format!("mesh {id} has no polygon {p}")))
}
