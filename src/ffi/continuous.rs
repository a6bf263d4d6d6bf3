//! The continuous query of a step (0.3): the pairs that meet at some time between the
//! meshes' current state and their targets, copied into the C structs the scene owns.

use super::desc::{try_reserve, write_array};
use super::guard::{guard, non_null, FfiResult};
use super::scene::{scene_mut, GlcolScene};
use super::types::*;
use crate::ImpactFeature;

/// Continuous detection over the step from every mesh's current state (t = 0) to its target
/// (t = 1; see glcol_mesh_set_target_positions; a mesh without one stands still), each
/// vertex on the straight line between its start and end world positions: every pair that
/// glcol_query_all would report at SOME time t in [0, 1], with the same pairs taken into
/// account (enabled meshes, filters, self-collision, the adjacency rule applied at each t),
/// each pair once, with its earliest time toi (a certified lower bound: never later than
/// the exact time, at most 2^-20 earlier; 0 with GLCOL_IMPACT_AT_START exactly when the
/// pair meets at t = 0). Exact at epsilon 0 for the double world positions, degenerate
/// polygons and motions included. For adjacent polygons (a vertex index in common) after
/// t = 0: a vertex of one that the other does not have meets the other, or an edge of one
/// meets an edge of the other with which it shares no vertex (this differs from the
/// point-set rule only when such a feature meets the other polygon exactly at a shared
/// vertex's position). On success `*out_impacts` points at `*out_count` impacts sorted by
/// (mesh_a, polygon_a, mesh_b, polygon_b) (NULL when 0), owned by the scene as
/// glcol_query_all's pairs (valid until the next non-const call on it). The same answer for
/// every backend (it runs on the CPU), thread count and creation order. At epsilon e > 0
/// the band is a distance: a pair is also reported when at some t a vertex of one polygon
/// that the other does not share comes within e / 2 of the other polygon, or an edge of one
/// within e / 2 of an edge of the other with which it shares no vertex (a polygon's edges
/// are its triangles'); every such pair is reported, a reported pair comes within
/// (e / 2) * (1 + 2^-20) at some t, and toi is never later than the earliest time within
/// e / 2 (AT_START: within e / 2 at t = 0). With no target anywhere this is a thickness
/// query: the pairs within e / 2 (glcol_query_all's band is the paper's viewing volume).
/// A GL backend with an enabled mesh bound to a host GL buffer: GLCOL_STATUS_UNSUPPORTED.
/// On failure nothing is written and the last answer stays as it was. Added in 0.3.
///
/// # Safety
/// `scene` is NULL or a live scene; `out_impacts` and `out_count` are NULL or writable and
/// aligned.
#[no_mangle]
pub unsafe extern "C" fn glcol_query_continuous(
    scene: *mut GlcolScene,
    out_impacts: *mut *const GlcolImpact,
    out_count: *mut usize,
) -> GlcolStatus {
    guard(|| {
        // SAFETY: the caller's contract: NULL (refused) or a live scene.
        let s = unsafe { scene_mut(scene) }?;
        query_continuous(s, out_impacts, out_count)
    })
}

/// `glcol_query_continuous`'s body once the scene is known.
fn query_continuous(
    s: &mut GlcolScene,
    out_impacts: *mut *const GlcolImpact,
    out_count: *mut usize,
) -> FfiResult {
    non_null(out_impacts, "out_impacts")?;
    non_null(out_count, "out_count")?;
    let found = s.scene.query_continuous()?;
    let more = found.len().saturating_sub(s.impacts.len());
    try_reserve(&mut s.impacts, more, "the continuous query's pairs")?;
    s.impacts.clear();
    s.impacts.extend(found.iter().map(|i| GlcolImpact {
        mesh_a: i.mesh_a,
        polygon_a: i.polygon_a,
        mesh_b: i.mesh_b,
        polygon_b: i.polygon_b,
        toi: i.toi,
        flags: if i.at_start { GLCOL_IMPACT_AT_START } else { 0 },
    }));
    // SAFETY: the glcol_query_continuous caller's contract: both non-null (checked),
    // writable and aligned.
    unsafe { write_array(&s.impacts, out_impacts, out_count) };
    Ok(())
}

/// Where each pair of the scene's last successful glcol_query_continuous meets first, in the
/// same order: entry i for impact i. The primitive pair (a vertex of one and a triangle of the
/// other, or an edge of each) that met first, its vertex indices, the barycentric weights of
/// its contact points and the unit normal from b towards a at the reported toi: what an
/// impulse-based response pushes on (the vertex and the face's three vertices, or the four
/// vertices of two edges, weighted, along the normal). Computed at this call, in double
/// (a step that does not ask pays nothing): point_a and point_b are within 2^-19 times the
/// step's largest vertex motion of each other. A pair that meets at t = 0 gets
/// GLCOL_FEATURE_NONE (its crossing geometry is glcol_query_geometry's, for the start). On
/// success `*out_geometry` points at `*out_count` entries (NULL when 0), owned by the scene
/// like the impacts (valid until the next non-const call; the impacts stay valid).
/// GLCOL_STATUS_INVALID_ARGUMENT, with a message, before any continuous query, after a
/// failed one, or after any change to the meshes or their targets since. Added in 0.3.
///
/// # Safety
/// `scene` is NULL or a live scene; `out_geometry` and `out_count` are NULL or writable and
/// aligned.
#[no_mangle]
pub unsafe extern "C" fn glcol_query_impact_geometry(
    scene: *mut GlcolScene,
    out_geometry: *mut *const GlcolImpactGeometry,
    out_count: *mut usize,
) -> GlcolStatus {
    guard(|| {
        // SAFETY: the caller's contract: NULL (refused) or a live scene.
        let s = unsafe { scene_mut(scene) }?;
        impact_geometry(s, out_geometry, out_count)
    })
}

/// `glcol_query_impact_geometry`'s body once the scene is known.
fn impact_geometry(
    s: &mut GlcolScene,
    out_geometry: *mut *const GlcolImpactGeometry,
    out_count: *mut usize,
) -> FfiResult {
    non_null(out_geometry, "out_geometry")?;
    non_null(out_count, "out_count")?;
    let found = s.scene.impact_geometry()?;
    let more = found.len().saturating_sub(s.impact_geometry.len());
    try_reserve(&mut s.impact_geometry, more, "the impact geometry")?;
    s.impact_geometry.clear();
    s.impact_geometry
        .extend(found.iter().map(|g| GlcolImpactGeometry {
            kind: match g.kind {
                ImpactFeature::None => GLCOL_FEATURE_NONE,
                ImpactFeature::VertexFace => GLCOL_FEATURE_VERTEX_FACE,
                ImpactFeature::FaceVertex => GLCOL_FEATURE_FACE_VERTEX,
                ImpactFeature::EdgeEdge => GLCOL_FEATURE_EDGE_EDGE,
            },
            vertices_a: g.vertices_a,
            vertices_b: g.vertices_b,
            weights_a: g.weights_a,
            weights_b: g.weights_b,
            normal: g.normal,
        }));
    // SAFETY: the glcol_query_impact_geometry caller's contract: both non-null (checked),
    // writable and aligned.
    unsafe { write_array(&s.impact_geometry, out_geometry, out_count) };
    Ok(())
}
