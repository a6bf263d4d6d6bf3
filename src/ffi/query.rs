//! Queries and their answers: contacts of one reference mesh, pairs of the whole scene, and
//! the contact geometry of either, copied into the C structs the scene owns.

use super::desc::{try_reserve, write_array};
use super::guard::{guard, non_null, FfiResult};
use super::scene::{scene_mut, GlcolScene};
use super::types::*;

/// Collides `reference` against every other enabled mesh (the paper's five steps). On
/// success `*out_contacts` points at `*out_count` contacts sorted by (other_mesh,
/// reference_polygon, other_polygon), each pair once (NULL when the count is 0). The array
/// is owned by the scene and stays valid until the next call that takes this scene
/// non-const. Meaning: with epsilon e > 0 the other polygon meets the reference polygon's
/// viewing volume (the polygon thickened by e/2 along its normal); with e = 0 the two
/// closed polygons intersect exactly (touching counts).
///
/// GL backends: GLCOL_STATUS_GL_UNAVAILABLE without the scene's context current (see
/// GlcolScene); a mesh bound to a GL buffer that is no longer a buffer, is mapped, or now
/// holds fewer bytes than its vertices need: GLCOL_STATUS_INVALID_ARGUMENT naming the mesh
/// and the sizes. Either way nothing changed and the last answer stays valid.
///
/// # Safety
/// `scene` is NULL or a live scene; `out_contacts` and `out_count` are NULL or writable
/// and aligned.
#[no_mangle]
pub unsafe extern "C" fn glcol_query(
    scene: *mut GlcolScene,
    reference: GlcolMeshId,
    out_contacts: *mut *const GlcolContact,
    out_count: *mut usize,
) -> GlcolStatus {
    guard(|| {
        // SAFETY: the caller's contract: NULL (refused) or a live scene.
        let s = unsafe { scene_mut(scene) }?;
        let r = query_one(s, reference, out_contacts, out_count);
        if r.is_err() {
            s.scene.forget_query();
        }
        r
    })
}

/// `glcol_query`'s body once the scene is known.
fn query_one(
    s: &mut GlcolScene,
    reference: GlcolMeshId,
    out_contacts: *mut *const GlcolContact,
    out_count: *mut usize,
) -> FfiResult {
    non_null(out_contacts, "out_contacts")?;
    non_null(out_count, "out_count")?;
    let found = s.scene.query(reference)?;
    // Room first: a failed allocation leaves the last answer's array as it was.
    let more = found.len().saturating_sub(s.contacts.len());
    try_reserve(&mut s.contacts, more, "the query's contacts")?;
    s.contacts.clear();
    s.contacts.extend(found.iter().map(|c| GlcolContact {
        reference_polygon: c.reference_polygon,
        other_mesh: c.other_mesh,
        other_polygon: c.other_polygon,
    }));
    // SAFETY: the glcol_query caller's contract: both non-null (checked), writable and
    // aligned.
    unsafe { write_array(&s.contacts, out_contacts, out_count) };
    Ok(())
}

/// Every pair of polygons that meet, in one call (the meaning of `glcol_query`: exact at
/// epsilon 0, the viewing-volume band at epsilon > 0), from two different enabled meshes
/// whose filters pass, or from one enabled mesh whose self-collision is on. At epsilon > 0
/// a pair is reported when EITHER polygon meets the OTHER's viewing volume (so the answer
/// does not depend on which mesh is which). Each pair
/// once, (mesh_a, polygon_a) < (mesh_b, polygon_b). On success `*out_pairs` points at
/// `*out_count` pairs sorted by (mesh_a, polygon_a, mesh_b, polygon_b) (NULL when the count
/// is 0); the array is owned by the scene and stays valid until the next call that takes
/// this scene non-const (`glcol_query_geometry` excepted: it leaves it alone). The answer
/// does not depend on the backend, the thread count or the order meshes were created in;
/// meshes whose root boxes are apart cost next to nothing. On failure nothing is written
/// and `glcol_query_geometry` refuses until the next successful query.
///
/// # Safety
/// `scene` is NULL or a live scene; `out_pairs` and `out_count` are NULL or writable and
/// aligned.
#[no_mangle]
pub unsafe extern "C" fn glcol_query_all(
    scene: *mut GlcolScene,
    out_pairs: *mut *const GlcolPair,
    out_count: *mut usize,
) -> GlcolStatus {
    guard(|| {
        // SAFETY: the caller's contract: NULL (refused) or a live scene.
        let s = unsafe { scene_mut(scene) }?;
        let r = query_all(s, out_pairs, out_count);
        if r.is_err() {
            s.scene.forget_query();
        }
        r
    })
}

/// `glcol_query_all`'s body once the scene is known.
fn query_all(
    s: &mut GlcolScene,
    out_pairs: *mut *const GlcolPair,
    out_count: *mut usize,
) -> FfiResult {
    non_null(out_pairs, "out_pairs")?;
    non_null(out_count, "out_count")?;
    let found = s.scene.query_all()?;
    let more = found.len().saturating_sub(s.pairs.len());
    try_reserve(&mut s.pairs, more, "the query's pairs")?;
    s.pairs.clear();
    s.pairs.extend(found.iter().map(|p| GlcolPair {
        mesh_a: p.mesh_a,
        polygon_a: p.polygon_a,
        mesh_b: p.mesh_b,
        polygon_b: p.polygon_b,
    }));
    // SAFETY: the glcol_query_all caller's contract: both non-null (checked), writable and
    // aligned.
    unsafe { write_array(&s.pairs, out_pairs, out_count) };
    Ok(())
}

/// A double to the nearest float, saturating at +-FLT_MAX (the values are finite).
fn to_f32(x: f64) -> f32 {
    (x as f32).clamp(-f32::MAX, f32::MAX)
}

/// Geometry of the pairs of the scene's last successful `glcol_query` or
/// `glcol_query_all`, in the same order: entry i describes contact (or pair) i; polygon a
/// is the reference polygon (or polygon_a), b the other. Computed at this call (a query not
/// followed by it costs nothing more), in double precision from the world positions (the
/// float positions, or their `glcol_mesh_set_transform` images) in a frame local to the
/// pair, each value then rounded to the nearest float (normals stay unit within that
/// rounding; no NaN, no infinity). On success `*out_geometry` points at
/// `*out_count` entries (NULL when 0), owned by the scene like the pairs (valid until the
/// next non-const call); the contacts or pairs arrays stay valid.
/// Rules (exact decisions, as the query's):
/// - INTERSECTING: the closed polygons meet. point_a, point_b: the two farthest-apart
///   points of their intersection; depth, normal: the smallest translation of a that
///   separates them (two triangles: separating axes, the face normals and edge-edge
///   crosses; a quad: the union of its two triangles, planar or not, not its hull: the
///   boundary point of the union of the triangle pairs' Minkowski differences nearest the
///   origin; moving a by depth * normal brings the pair to touching, and for a union a
///   longer move along normal need not separate). Touching pairs: depth 0.
/// - COPLANAR (with INTERSECTING): the polygons meet and all their vertices lie in one
///   plane (never on a band-only pair); depth 0, normal = a's normal (a bowtie's: its
///   larger half's), points: the ends of the overlap's longest extent.
/// - Neither (pairs within the epsilon band only): closest points, depth = minus their
///   distance, normal from b towards a.
/// - A quad is its two triangles (v0,v1,v2), (v0,v2,v3). A degenerate polygon (a segment or
///   a point) gets the same meanings. Where a rule gives a zero normal, the fallback is a's
///   normal, then b's, then the cross of the two segments' directions, then a unit vector
///   perpendicular to the line holding every vertex, then +z.
///
/// Statuses: NULL_POINTER; INVALID_ARGUMENT (with a message) before any query, when the
/// last query failed, or when the meshes changed since it: any successful
/// `glcol_mesh_create`, `glcol_mesh_update_positions`, `glcol_mesh_update_positions_f64`,
/// `glcol_mesh_set_enabled`, `glcol_mesh_destroy`, `glcol_mesh_set_transform`,
/// `glcol_mesh_set_filter`, `glcol_mesh_set_self_collision` or `glcol_mesh_bind_gl_buffer`
/// on the scene. A target is no change of the current state: after
/// `glcol_mesh_set_target_positions`, `glcol_mesh_set_target_positions_f64`,
/// `glcol_mesh_set_target_transform` or `glcol_mesh_clear_target` the geometry stays
/// available. A mesh of the answer bound to a
/// GL buffer (glcol_mesh_bind_gl_buffer) is taken at the positions its query read, even if
/// the host has written the buffer since: on GL_COMPUTE they are read back from the GPU
/// (a sync point; the scene's context must be current: GL_UNAVAILABLE otherwise, and
/// GL_ERROR, the answer kept either way), and since that backend's answer for such a mesh
/// has no CPU confirmation, the INTERSECTING flag is exact where the pair list is not (a
/// pair within its rounding band gets closest points).
///
/// # Safety
/// `scene` is NULL or a live scene; `out_geometry` and `out_count` are NULL or writable and
/// aligned.
#[no_mangle]
pub unsafe extern "C" fn glcol_query_geometry(
    scene: *mut GlcolScene,
    out_geometry: *mut *const GlcolContactGeometry,
    out_count: *mut usize,
) -> GlcolStatus {
    guard(|| {
        // SAFETY: the caller's contract: NULL (refused) or a live scene.
        let s = unsafe { scene_mut(scene) }?;
        non_null(out_geometry, "out_geometry")?;
        non_null(out_count, "out_count")?;
        let found = s.scene.contact_geometry()?;
        let more = found.len().saturating_sub(s.geometry.len());
        try_reserve(&mut s.geometry, more, "the contact geometry")?;
        s.geometry.clear();
        s.geometry
            .extend(found.iter().map(|g| GlcolContactGeometry {
                point_a: g.point_a.map(to_f32),
                point_b: g.point_b.map(to_f32),
                normal: g.normal.map(to_f32),
                depth: to_f32(g.depth),
                flags: if g.intersecting {
                    GLCOL_CONTACT_INTERSECTING
                } else {
                    0
                } | if g.coplanar {
                    GLCOL_CONTACT_COPLANAR
                } else {
                    0
                },
            }));
        // SAFETY: both non-null (checked); the caller's contract: writable and aligned.
        unsafe { write_array(&s.geometry, out_geometry, out_count) };
        Ok(())
    })
}
