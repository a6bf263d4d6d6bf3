//! A backend for tests: it answers each step's batch by testing every (volume, candidate)
//! pair of every group directly with the definitions (grown boxes, then the narrow polygon
//! test), with no caches, sweeps or lanes. Run through [`crate::query::run`], it gives the
//! per-step tests and hits the backends that run whole queries must match.

use super::{Backend, Batch, Engine, Hit, QueryMeshes, Selector, Step, StepQuery};
use crate::error::Result;
use crate::geom::polygon::polygon_meets;
use crate::geom::Aabb;

/// The brute-force step answerer (see the module doc).
#[derive(Debug, Default)]
pub struct BruteSelector;

impl Selector for BruteSelector {
    /// Its answers are the CPU backend's.
    fn backend(&self) -> Backend {
        Backend::Cpu
    }

    fn engine(&mut self) -> Engine<'_> {
        Engine::Steps(self)
    }
}

impl StepQuery for BruteSelector {
    fn select(&mut self, q: &QueryMeshes<'_>, batch: &Batch, hits: &mut Vec<Hit>) -> Result<()> {
        let h = q.half_depth;
        let poly_box = |p: super::Prim| -> Aabb { q.mesh(p).poly_box(p.index as usize) };
        for g in &batch.groups {
            for v in g.volumes.clone() {
                let vp = batch.volumes[v as usize];
                let vbox = match batch.step {
                    Step::PolygonsInPolygons => poly_box(vp),
                    _ => q.boxed(vp),
                };
                for c in g.candidates.clone() {
                    let cp = batch.candidates[c as usize];
                    let meets = match batch.step {
                        Step::BoxesInBoxes => vbox.overlaps(&q.boxed(cp), h),
                        Step::PolygonsInBoxes => vbox.overlaps(&poly_box(cp), h),
                        Step::PolygonsInPolygons => {
                            vbox.overlaps(&poly_box(cp), h) && {
                                let (mut vt, mut ct) = ([[[0.0; 3]; 3]; 2], [[[0.0; 3]; 3]; 2]);
                                let nv = q.mesh(vp).triangles(vp.index as usize, &mut vt);
                                let nc = q.mesh(cp).triangles(cp.index as usize, &mut ct);
                                polygon_meets(&vt, nv, &ct, nc, h)
                                    || (q.symmetric && polygon_meets(&ct, nc, &vt, nv, h))
                            }
                        }
                    };
                    if meets {
                        hits.push(Hit {
                            volume: v,
                            candidate: c,
                        });
                    }
                }
            }
        }
        Ok(())
    }
}
