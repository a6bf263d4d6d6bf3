//! The CPU backend: selection semantics computed exactly or in `f64`.
//!
//! Box volumes (steps 1-4) keep a candidate when its box meets the volume grown by `h`
//! (closed, exact comparisons): for polygons that is a superset of what clipping keeps,
//! which only costs step 5 some work. Polygon volumes (step 5) give the final answer:
//! - `h = 0`: the closed polygons intersect, decided by exact predicates;
//! - `h > 0`: the candidate survives clipping against the reference polygon's volume
//!   ([`Cell`]) in `f64` in the volume's own frame, or intersects the polygon exactly (so
//!   rounding in the clipper can never lose a true intersection).

use super::{Backend, Batch, Hit, Prim, QueryMeshes, Selector, Step};
use crate::error::Result;
use crate::geom::tritri::triangles_intersect;
use crate::geom::volume::Cell;
use crate::geom::{Aabb, P3};

/// The CPU backend. Holds scratch space only.
#[derive(Default)]
pub struct CpuSelector {
    boxes: Vec<Aabb>,
    tris: Vec<([[P3; 3]; 2], usize)>,
}

impl CpuSelector {
    pub fn new() -> CpuSelector {
        CpuSelector::default()
    }
}

impl Selector for CpuSelector {
    fn backend(&self) -> Backend {
        Backend::Cpu
    }

    fn select(&mut self, q: &QueryMeshes<'_>, batch: &Batch, hits: &mut Vec<Hit>) -> Result<()> {
        let h = q.half_depth;
        for g in &batch.groups {
            let cands = &batch.candidates[g.candidates.start as usize..g.candidates.end as usize];
            // Candidate boxes once per group.
            self.boxes.clear();
            match batch.step {
                Step::BoxesInBoxes => self.boxes.extend(cands.iter().map(|&c| q.boxed(c))),
                _ => self
                    .boxes
                    .extend(cands.iter().map(|&c| q.mesh(c).poly_box(c.index as usize))),
            }
            if batch.step == Step::PolygonsInPolygons {
                self.tris.clear();
                self.tris.extend(cands.iter().map(|&c| {
                    let mut t = [[[0.0; 3]; 3]; 2];
                    let n = q.mesh(c).triangles(c.index as usize, &mut t);
                    (t, n)
                }));
            }
            for vi in g.volumes.clone() {
                let v = batch.volumes[vi as usize];
                let hit = |ci: usize| Hit {
                    volume: vi,
                    candidate: g.candidates.start + ci as u32,
                };
                match batch.step {
                    Step::BoxesInBoxes | Step::PolygonsInBoxes => {
                        let vb = q.boxed(v);
                        hits.extend(
                            self.boxes
                                .iter()
                                .enumerate()
                                .filter(|(_, b)| vb.overlaps(b, h))
                                .map(|(i, _)| hit(i)),
                        );
                    }
                    Step::PolygonsInPolygons => {
                        polygon_volume(q, v, h, &self.boxes, &self.tris, |i| hits.push(hit(i)))
                    }
                }
            }
        }
        Ok(())
    }
}

/// Step 5 for one reference polygon `v` against the group's candidates.
fn polygon_volume(
    q: &QueryMeshes<'_>,
    v: Prim,
    h: f64,
    boxes: &[Aabb],
    tris: &[([[P3; 3]; 2], usize)],
    mut hit: impl FnMut(usize),
) {
    let m = q.mesh(v);
    let vb = m.poly_box(v.index as usize);
    let mut vt = [[[0.0; 3]; 3]; 2];
    let nv = m.triangles(v.index as usize, &mut vt);
    let cells: Option<[Cell; 2]> = (h > 0.0).then(|| {
        [
            Cell::of_triangle(&vt[0], h),
            Cell::of_triangle(&vt[nv - 1], h),
        ]
    });
    for (i, (b, (ct, nc))) in boxes.iter().zip(tris).enumerate() {
        if !vb.overlaps(b, h) {
            continue;
        }
        let meets = (0..nv).any(|a| {
            (0..*nc).any(|c| {
                cells
                    .as_ref()
                    .is_some_and(|cells| cells[a].meets_triangle(&ct[c]))
                    || triangles_intersect(&vt[a], &ct[c])
            })
        });
        if meets {
            hit(i);
        }
    }
}
