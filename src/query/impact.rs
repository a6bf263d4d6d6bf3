//! Where the pairs of a continuous query meet first: the primitive pair the query found
//! first for each pair (a vertex and a triangle, or two edges, by vertex index), its contact
//! points' barycentric weights and the normal at the reported time of impact, what an
//! impulse-based response pushes on. Computed on demand from the meshes' step (start and
//! end world positions), in double ([`crate::geom::ccd`]'s `impact.rs`).

use std::collections::BTreeMap;

use super::continuous::Impact;
use crate::error::{try_reserve, Error, ErrorKind, Result};
use crate::geom::ccd::{edge_edge_impact, vertex_face_impact, First};
use crate::geom::P3;
use crate::mesh::{Mesh, MeshId};

/// Which primitive pair meets first (see [`ImpactGeometry`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ImpactFeature {
    /// The pair meets at `t = 0` (its crossing geometry is [`crate::Scene::contact_geometry`]'s).
    None,
    /// A vertex of polygon a and a triangle of polygon b.
    VertexFace,
    /// A triangle of polygon a and a vertex of polygon b.
    FaceVertex,
    /// An edge of each.
    EdgeEdge,
}

/// Where a pair of [`crate::Scene::query_continuous`] meets first.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ImpactGeometry {
    /// The primitive pair that meets first.
    pub kind: ImpactFeature,
    /// `mesh_a`'s vertex indices of a's feature: 1 for a vertex, 2 for an edge, 3 for a
    /// triangle; unused entries repeat the last used one.
    pub vertices_a: [u32; 3],
    /// The same for b.
    pub vertices_b: [u32; 3],
    /// Barycentric weights (each in `[0, 1]`, summing to 1) of the contact point on a's
    /// feature at `toi`: `point_a = sum weights_a[k] * p(toi)` of `vertices_a[k]`; unused
    /// weights are 0.
    pub weights_a: [f64; 3],
    /// The same for b.
    pub weights_b: [f64; 3],
    /// Unit, at `toi`, from b towards a: the triangle's normal turned towards the vertex,
    /// or the edges' common normal. `[0, 0, 0]` for [`ImpactFeature::None`].
    pub normal: P3,
}

/// The moving vertex `v` of `mesh`: its world positions at the start and the end.
fn moving(mesh: &Mesh, v: u32) -> [P3; 2] {
    let v = v as usize;
    // The query found it in a polygon: it is used, so both are there.
    let p0 = mesh.world_position(v).unwrap_or_default();
    [p0, mesh.end_world_position(v).unwrap_or(p0)]
}

/// `[[corners at the start], [at the end]]` of the vertices `ids` of `mesh`.
fn feature<const N: usize>(mesh: &Mesh, ids: [u32; N]) -> [[P3; N]; 2] {
    let m = ids.map(|v| moving(mesh, v));
    [m.map(|p| p[0]), m.map(|p| p[1])]
}

/// Repeats the last of `n` used entries.
fn padded<const N: usize>(ids: [u32; N]) -> [u32; 3] {
    std::array::from_fn(|k| ids[k.min(N - 1)])
}

/// The geometry of `impacts` (whose first primitive pairs are `firsts`) into `out`, entry
/// `i` for impact `i`.
pub fn impact_geometry(
    meshes: &BTreeMap<MeshId, Mesh>,
    impacts: &[Impact],
    firsts: &[First],
    out: &mut Vec<ImpactGeometry>,
) -> Result<()> {
    out.clear();
    try_reserve(out, impacts.len(), "the impact geometry")?;
    let mesh = |id: MeshId| {
        meshes.get(&id).ok_or_else(|| {
            Error::new(
                ErrorKind::Internal,
                format!("mesh {id} of the continuous answer is gone"),
            )
        })
    };
    for (i, f) in impacts.iter().zip(firsts) {
        let (ma, mb) = (mesh(i.mesh_a)?, mesh(i.mesh_b)?);
        let g = match *f {
            First::AtStart => ImpactGeometry {
                kind: ImpactFeature::None,
                vertices_a: [0; 3],
                vertices_b: [0; 3],
                weights_a: [0.0; 3],
                weights_b: [0.0; 3],
                normal: [0.0; 3],
            },
            First::VertexFace { v, f } => {
                let p = vertex_face_impact(moving(ma, v), feature(mb, f), i.toi);
                ImpactGeometry {
                    kind: ImpactFeature::VertexFace,
                    vertices_a: padded([v]),
                    vertices_b: f,
                    weights_a: p.weights_a,
                    weights_b: p.weights_b,
                    normal: p.normal,
                }
            }
            First::FaceVertex { f, v } => {
                // Asked the other way round (b's vertex on a's triangle): its normal points
                // from a towards b.
                let p = vertex_face_impact(moving(mb, v), feature(ma, f), i.toi);
                ImpactGeometry {
                    kind: ImpactFeature::FaceVertex,
                    vertices_a: f,
                    vertices_b: padded([v]),
                    weights_a: p.weights_b,
                    weights_b: p.weights_a,
                    normal: p.normal.map(|x| -x),
                }
            }
            First::EdgeEdge { a, b } => {
                let p = edge_edge_impact(feature(ma, a), feature(mb, b), i.toi);
                ImpactGeometry {
                    kind: ImpactFeature::EdgeEdge,
                    vertices_a: padded(a),
                    vertices_b: padded(b),
                    weights_a: p.weights_a,
                    weights_b: p.weights_b,
                    normal: p.normal,
                }
            }
        };
        out.push(g);
    }
    Ok(())
}
