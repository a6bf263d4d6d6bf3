//! A scene's meshes: creating, moving, placing, filtering, destroying them, and binding
//! them to host GL buffers.

use super::desc::{init_sized, oldest_size, positions, read_desc, Coordinate};
use super::guard::{guard, invalid, non_null, FfiResult};
use super::scene::{on_scene, scene_mut, GlcolScene};
use super::types::*;
use crate::{Mesh, Positions, Scene};

/// The exported symbol that programs built against glcollide 0.1's header call: it fills
/// 0.1's `GlcolMeshDesc` (everything up to `positions_f64`, which it cannot know the caller
/// has) with the defaults and sets `struct_size` to 0.1's size. This header turns every
/// `glcol_mesh_desc_init(desc)` into `glcol_mesh_desc_init_sized(desc, sizeof *(desc))` (a
/// macro below), so a program compiled against it fills the whole struct; only a call
/// through a function pointer or `dlsym` reaches this symbol, and such callers (language
/// bindings) should call `glcol_mesh_desc_init_sized` instead. NULL is ignored.
///
/// # Safety
/// `desc` is NULL or points to writable, aligned memory of at least 0.1's
/// `sizeof(GlcolMeshDesc)` bytes.
#[no_mangle]
pub unsafe extern "C" fn glcol_mesh_desc_init(desc: *mut GlcolMeshDesc) {
    // SAFETY: the caller's contract: NULL or writable for 0.1's size. A NULL (or
    // misaligned) `desc` is ignored: nothing is written, and no message is set.
    let _ = unsafe { init_sized(desc, oldest_size::<GlcolMeshDesc>()) };
}

/// Fills a `GlcolMeshDesc` of `size` bytes (`sizeof(GlcolMeshDesc)` of the header the
/// caller was compiled with: this one's, or 0.1's) with its defaults: struct_size = `size`,
/// every pointer NULL, every count 0, vertices_per_polygon 3; nothing past `size` bytes is
/// written. C and C++ call it through the `glcol_mesh_desc_init(desc)` macro. Statuses:
/// NULL_POINTER, INVALID_ARGUMENT (a size no version of the struct has, or a misaligned
/// `desc`; nothing written).
///
/// # Safety
/// `desc` is NULL or points to writable memory of `size` bytes.
#[no_mangle]
pub unsafe extern "C" fn glcol_mesh_desc_init_sized(
    desc: *mut GlcolMeshDesc,
    size: usize,
) -> GlcolStatus {
    guard(|| {
        // SAFETY: the caller's contract: NULL (refused) or `size` writable bytes.
        unsafe { init_sized(desc, size) }
    })
}

/// Adds a mesh: positions and indices are copied, the leaf boxes built. On success
/// `*out_id` gets the new id; on failure nothing changes. Exactly one of `positions` and
/// `positions_f64` is non-NULL (both or neither: INVALID_ARGUMENT; a struct of 0.1's size,
/// without `positions_f64`, answers NULL_POINTER for NULL `positions` as 0.1 did); with
/// `positions_f64` the mesh is an f64 mesh (stride 0 = 24), which keeps its positions as
/// doubles and is queried exactly for them. Statuses: NULL_POINTER (scene, desc, out_id,
/// indices), INVALID_ARGUMENT (struct_size, zero counts, stride, alignment,
/// vertices_per_polygon, overflow, positions), NON_FINITE (a coordinate not finite, or a
/// double beyond the float range, 3.4e38), INDEX_OUT_OF_RANGE.
/// Counts above 2^32 - 1 vertices or 2^32 - 2 polygon corners (polygon_count times
/// vertices_per_polygon), or whose byte size overflows, are refused before the arrays are
/// read. Arrays shorter than the counts say, or dangling pointers, cannot be detected
/// (undefined behaviour).
///
/// # Safety
/// `scene` is NULL or a live scene. `desc` is NULL or points to a readable `GlcolMeshDesc`
/// of `desc->struct_size` bytes, aligned as C aligns it (a misaligned `desc` is refused:
/// INVALID_ARGUMENT), whose `positions` (or `positions_f64`) is NULL or readable for
/// `vertex_count` vertices `position_stride` bytes apart and whose `indices` is NULL or
/// readable for
/// `polygon_count * vertices_per_polygon` values. `out_id` is NULL or writable and aligned.
#[no_mangle]
pub unsafe extern "C" fn glcol_mesh_create(
    scene: *mut GlcolScene,
    desc: *const GlcolMeshDesc,
    out_id: *mut GlcolMeshId,
) -> GlcolStatus {
    guard(|| {
        // SAFETY: the caller's contract: NULL (refused) or a live scene.
        let s = unsafe { scene_mut(scene) }?;
        non_null(desc, "desc")?;
        non_null(out_id, "out_id")?;
        // SAFETY: `desc` is non-null (checked), readable for struct_size bytes (the caller's
        // contract; a misaligned one is refused first).
        let d = unsafe { read_desc(desc) }?;
        let k = d.vertices_per_polygon;
        if k != 3 && k != 4 {
            return Err(invalid(format!(
                "vertices_per_polygon is {k}; it must be 3 or 4"
            )));
        }
        let old = d.struct_size as usize == oldest_size::<GlcolMeshDesc>();
        if old {
            non_null(d.positions, "positions")?;
        } else if d.positions.is_null() == d.positions_f64.is_null() {
            return Err(invalid(format!(
                "positions and positions_f64 are both {}: exactly one of them must be set \
                 (float or double positions)",
                if d.positions.is_null() { "NULL" } else { "set" }
            )));
        }
        non_null(d.indices, "indices")?;
        if d.polygon_count == 0 {
            return Err(invalid("polygon_count is 0"));
        }
        // Counts the library cannot number are refused before any array is touched, by the
        // checks Mesh::new makes.
        Mesh::check_counts(d.vertex_count, d.polygon_count, k as usize)?;
        let pos = if d.positions.is_null() {
            // SAFETY: the caller's contract: `positions_f64` holds `vertex_count` vertices
            // `position_stride` apart.
            unsafe { positions(d.positions_f64, d.vertex_count, d.position_stride) }?
        } else {
            // SAFETY: the caller's contract: `positions` holds `vertex_count` vertices
            // `position_stride` apart.
            unsafe { positions(d.positions, d.vertex_count, d.position_stride) }?
        };
        if !(d.indices as usize).is_multiple_of(std::mem::align_of::<u32>()) {
            return Err(invalid("indices is not 4-byte aligned"));
        }
        let n = d
            .polygon_count
            .checked_mul(k as usize)
            .filter(|&n| n <= isize::MAX as usize / 4)
            .ok_or_else(|| {
                invalid(format!(
                    "polygon_count {} times vertices_per_polygon overflows",
                    d.polygon_count
                ))
            })?;
        // SAFETY: non-null and aligned (checked), n * 4 bytes <= isize::MAX (checked), and
        // the caller's contract: `indices` holds polygon_count * vertices_per_polygon values.
        let indices = unsafe { std::slice::from_raw_parts(d.indices, n) };
        let id = s.scene.create_mesh(pos, indices, k as usize)?;
        // SAFETY: non-null (checked); the caller's contract: writable and aligned.
        unsafe { out_id.write(id) };
        Ok(())
    })
}

/// Moves vertices `first_vertex .. first_vertex + vertex_count` to `positions` (x, y, z
/// each, `position_stride` bytes apart, 0 = packed) and refits the mesh's boxes. Rejected
/// whole on any error (the mesh keeps its previous positions): UNKNOWN_MESH, NULL_POINTER,
/// INVALID_ARGUMENT (zero count, range past the end, stride, alignment, overflow; a
/// partial update of a mesh bound to a GL buffer), NON_FINITE (also: positions whose world
/// positions under the mesh's `glcol_mesh_set_transform` matrix could overflow the float
/// range). A mesh bound with `glcol_mesh_bind_gl_buffer` takes only a full update
/// (first_vertex 0, all its vertices): it unbinds the buffer, and from then on the mesh's
/// positions are exactly the ones given (the buffer is no longer read). A partial one is
/// refused, since the CPU holds no current positions for the other vertices. Makes no GL
/// call. The range is checked against the mesh before the array is read; an array shorter
/// than `vertex_count` vertices `position_stride` apart cannot be detected (undefined
/// behaviour).
///
/// # Safety
/// `scene` is NULL or a live scene; `positions` is NULL or readable for `vertex_count`
/// vertices `position_stride` bytes apart.
#[no_mangle]
pub unsafe extern "C" fn glcol_mesh_update_positions(
    scene: *mut GlcolScene,
    mesh: GlcolMeshId,
    positions: *const f32,
    first_vertex: usize,
    vertex_count: usize,
    position_stride: usize,
) -> GlcolStatus {
    // SAFETY: the caller's contract, passed on.
    unsafe {
        hand_over(
            scene,
            mesh,
            positions,
            first_vertex,
            vertex_count,
            position_stride,
            "glcol_mesh_update_positions",
            |s, pos| s.update_positions(mesh, first_vertex, pos),
        )
    }
}

/// What the calls that hand over positions for vertices `first..first + count` of `mesh`
/// share: the checks of [`before_positions`], the array read as [`positions`] reads it,
/// then `apply` with them.
///
/// # Safety
/// `scene` is NULL or a live scene; `p` is NULL or readable for `count` vertices `stride`
/// bytes apart.
#[allow(clippy::too_many_arguments)]
unsafe fn hand_over<T: Coordinate>(
    scene: *mut GlcolScene,
    mesh: GlcolMeshId,
    p: *const T,
    first: usize,
    count: usize,
    stride: usize,
    what: &str,
    apply: impl FnOnce(&mut Scene, Positions<'_>) -> crate::Result<()>,
) -> GlcolStatus {
    guard(|| {
        // SAFETY: the caller's contract: NULL (refused) or a live scene.
        let s = unsafe { scene_mut(scene) }?;
        before_positions(s, mesh, p, first, count, T::F64, what)?;
        // SAFETY: the caller's contract: `p` holds `count` vertices `stride` apart.
        let pos = unsafe { positions(p, count, stride) }?;
        Ok(apply(&mut s.scene, pos)?)
    })
}

/// Before an array of positions for vertices `first..first + count` of `mesh` is read:
/// the mesh exists, `p` is not NULL, the mesh's precision is `f64` (else INVALID_ARGUMENT
/// naming the call `what`), and the range lies in the mesh (so that no count larger than
/// the mesh reaches the array).
fn before_positions<T>(
    s: &GlcolScene,
    mesh: GlcolMeshId,
    p: *const T,
    first: usize,
    count: usize,
    f64: bool,
    what: &str,
) -> FfiResult {
    let m = s.scene.mesh(mesh)?;
    non_null(p, "positions")?;
    if m.is_f64() != f64 {
        return Err(invalid(if f64 {
            format!(
                "{what}: mesh {mesh} is a float mesh: it takes float positions \
                 (the call without _f64)"
            )
        } else {
            format!(
                "{what}: mesh {mesh} is an f64 mesh (made from positions_f64): it takes \
                 double positions (the _f64 call)"
            )
        }));
    }
    let n = m.vertex_count();
    if count != 0 && first.checked_add(count).is_none_or(|e| e > n) {
        return Err(invalid(format!(
            "first_vertex {first} + vertex_count {count} runs past the mesh's {n} vertices"
        )));
    }
    Ok(())
}

/// `glcol_mesh_update_positions` for an f64 mesh: moves vertices `first_vertex ..
/// first_vertex + vertex_count` to `positions` (x, y, z doubles each, `position_stride`
/// bytes apart, 0 = packed = 24; 8-byte aligned) and refits the mesh's boxes. Rejected
/// whole on any error (the mesh keeps its previous positions): UNKNOWN_MESH, NULL_POINTER,
/// INVALID_ARGUMENT (a float mesh, zero count, range past the end, stride, alignment,
/// overflow), NON_FINITE (a coordinate not finite or beyond the float range, 3.4e38; also
/// world positions under the mesh's transform that could overflow the float range). Drops
/// the mesh's target. Makes no GL call.
///
/// # Safety
/// `scene` is NULL or a live scene; `positions` is NULL or readable for `vertex_count`
/// vertices `position_stride` bytes apart.
#[no_mangle]
pub unsafe extern "C" fn glcol_mesh_update_positions_f64(
    scene: *mut GlcolScene,
    mesh: GlcolMeshId,
    positions: *const f64,
    first_vertex: usize,
    vertex_count: usize,
    position_stride: usize,
) -> GlcolStatus {
    // SAFETY: the caller's contract, passed on.
    unsafe {
        hand_over(
            scene,
            mesh,
            positions,
            first_vertex,
            vertex_count,
            position_stride,
            "glcol_mesh_update_positions_f64",
            |s, pos| s.update_positions(mesh, first_vertex, pos),
        )
    }
}

/// The end of a continuous step for a float mesh: vertices `first_vertex .. first_vertex +
/// vertex_count` get the target positions `positions` (x, y, z floats each in the mesh's
/// own frame, `position_stride` bytes apart, 0 = packed), replacing any they had; the other
/// vertices keep theirs, or their start positions. The mesh's current state is the start
/// (t = 0); each vertex's world position moves on the straight line to its end world
/// position (t = 1), under the target transform if one was set, else the current one. A
/// target is not committed: no other query's answer changes, and `glcol_query_geometry`
/// stays valid. It lasts until `glcol_mesh_update_positions(_f64)`,
/// `glcol_mesh_set_transform` or `glcol_mesh_clear_target` on the mesh. Rejected whole,
/// nothing changed: NULL_POINTER, UNKNOWN_MESH, INVALID_ARGUMENT (an f64 mesh, zero count,
/// range past the end, stride, alignment, overflow), NON_FINITE (a coordinate not finite,
/// or end world positions that could overflow the float range), UNSUPPORTED (a mesh
/// bound to a GL buffer: the start of its step is in the host's buffer).
///
/// # Safety
/// `scene` is NULL or a live scene; `positions` is NULL or readable for `vertex_count`
/// vertices `position_stride` bytes apart.
#[no_mangle]
pub unsafe extern "C" fn glcol_mesh_set_target_positions(
    scene: *mut GlcolScene,
    mesh: GlcolMeshId,
    positions: *const f32,
    first_vertex: usize,
    vertex_count: usize,
    position_stride: usize,
) -> GlcolStatus {
    // SAFETY: the caller's contract, passed on.
    unsafe {
        hand_over(
            scene,
            mesh,
            positions,
            first_vertex,
            vertex_count,
            position_stride,
            "glcol_mesh_set_target_positions",
            |s, pos| s.set_target_positions(mesh, first_vertex, pos),
        )
    }
}

/// `glcol_mesh_set_target_positions` for an f64 mesh: the target positions are doubles
/// (`position_stride` 0 = 24, 8-byte aligned). INVALID_ARGUMENT for a float mesh; a
/// coordinate not finite or beyond the float range (3.4e38): NON_FINITE. Otherwise as
/// `glcol_mesh_set_target_positions`.
///
/// # Safety
/// `scene` is NULL or a live scene; `positions` is NULL or readable for `vertex_count`
/// vertices `position_stride` bytes apart.
#[no_mangle]
pub unsafe extern "C" fn glcol_mesh_set_target_positions_f64(
    scene: *mut GlcolScene,
    mesh: GlcolMeshId,
    positions: *const f64,
    first_vertex: usize,
    vertex_count: usize,
    position_stride: usize,
) -> GlcolStatus {
    // SAFETY: the caller's contract, passed on.
    unsafe {
        hand_over(
            scene,
            mesh,
            positions,
            first_vertex,
            vertex_count,
            position_stride,
            "glcol_mesh_set_target_positions_f64",
            |s, pos| s.set_target_positions(mesh, first_vertex, pos),
        )
    }
}

/// The transform `mesh` takes at the end of a continuous step (a row-major 3x4 matrix,
/// evaluated as `glcol_mesh_set_transform` says): an instrument that only moves needs
/// nothing else. Its target positions, if any, stay. Not committed, as
/// `glcol_mesh_set_target_positions`. Rejected, nothing changed: NULL_POINTER (scene, m),
/// UNKNOWN_MESH, NON_FINITE (an entry not finite, or end world positions that could
/// overflow the float range), UNSUPPORTED (a mesh bound to a GL buffer).
///
/// # Safety
/// `scene` is NULL or a live scene; `m` is NULL or points at 12 readable doubles.
#[no_mangle]
pub unsafe extern "C" fn glcol_mesh_set_target_transform(
    scene: *mut GlcolScene,
    mesh: GlcolMeshId,
    m: *const f64,
) -> GlcolStatus {
    guard(|| {
        // SAFETY: the caller's contract: NULL (refused) or a live scene.
        let s = unsafe { scene_mut(scene) }?;
        s.scene.mesh(mesh)?;
        non_null(m, "m")?;
        // SAFETY: the caller's contract: non-null `m` points at 12 readable doubles (read
        // unaligned: a caller's `double[12]` is aligned, this costs nothing).
        let m = unsafe { m.cast::<[f64; 12]>().read_unaligned() };
        Ok(s.scene.set_target_transform(mesh, &m)?)
    })
}

/// Drops `mesh`'s target (its target positions and transform): it stands still in a
/// continuous step. Statuses: NULL_POINTER, UNKNOWN_MESH.
///
/// # Safety
/// `scene` is NULL or a live scene.
#[no_mangle]
pub unsafe extern "C" fn glcol_mesh_clear_target(
    scene: *mut GlcolScene,
    mesh: GlcolMeshId,
) -> GlcolStatus {
    // SAFETY: the caller's contract: NULL (refused) or a live scene.
    unsafe { on_scene(scene, |s| s.clear_target(mesh)) }
}

/// Enables or disables a mesh. A disabled mesh costs nothing in a query and has no
/// contacts (as reference or as other).
///
/// # Safety
/// `scene` is NULL or a live scene.
#[no_mangle]
pub unsafe extern "C" fn glcol_mesh_set_enabled(
    scene: *mut GlcolScene,
    mesh: GlcolMeshId,
    enabled: bool,
) -> GlcolStatus {
    // SAFETY: the caller's contract: NULL (refused) or a live scene.
    unsafe { on_scene(scene, |s| s.set_enabled(mesh, enabled)) }
}

/// Removes a mesh from the scene. Its id is never reused.
///
/// # Safety
/// `scene` is NULL or a live scene.
#[no_mangle]
pub unsafe extern "C" fn glcol_mesh_destroy(
    scene: *mut GlcolScene,
    mesh: GlcolMeshId,
) -> GlcolStatus {
    // SAFETY: the caller's contract: NULL (refused) or a live scene.
    unsafe { on_scene(scene, |s| s.destroy_mesh(mesh)) }
}

/// Whole-scene queries (`glcol_query_all`) also collide `mesh` with itself when `on` (off
/// by default). Two polygons of one mesh that share a vertex index are adjacent: such a
/// pair is reported only when the closed polygons meet somewhere other than their shared
/// vertices and edges (a fold onto a neighbour, a vertex pushed through the next
/// triangle), at every epsilon. The two triangles of a quad are one polygon, never a pair;
/// vertices at one position with different indices are not shared. `glcol_query` never
/// reports same-mesh pairs. Statuses: NULL_POINTER, UNKNOWN_MESH.
///
/// # Safety
/// `scene` is NULL or a live scene.
#[no_mangle]
pub unsafe extern "C" fn glcol_mesh_set_self_collision(
    scene: *mut GlcolScene,
    mesh: GlcolMeshId,
    on: bool,
) -> GlcolStatus {
    // SAFETY: the caller's contract: NULL (refused) or a live scene.
    unsafe { on_scene(scene, |s| s.set_self_collision(mesh, on)) }
}

/// Pair filtering: two different meshes a and b are collided (by `glcol_query` and
/// `glcol_query_all`) only if `(a.group & b.mask) != 0 && (b.group & a.mask) != 0`.
/// Default group 1, mask 0xFFFFFFFF (everything collides). Self-collision is switched by
/// `glcol_mesh_set_self_collision` alone. Statuses: NULL_POINTER, UNKNOWN_MESH.
///
/// # Safety
/// `scene` is NULL or a live scene.
#[no_mangle]
pub unsafe extern "C" fn glcol_mesh_set_filter(
    scene: *mut GlcolScene,
    mesh: GlcolMeshId,
    group: u32,
    mask: u32,
) -> GlcolStatus {
    // SAFETY: the caller's contract: NULL (refused) or a live scene.
    unsafe { on_scene(scene, |s| s.set_filter(mesh, group, mask)) }
}

/// Places `mesh` rigidly (or affinely): `m` is a row-major 3x4 matrix and a vertex's world
/// position is `m * (x, y, z, 1)`, each coordinate evaluated in double precision as
/// `m[r*4+0]*x + m[r*4+1]*y + m[r*4+2]*z + m[r*4+3]` in that order, without fused
/// multiply-add. Every query (`glcol_query`, `glcol_query_all`, `glcol_query_geometry`, all
/// backends) answers for those double world positions, exact at epsilon 0: the same answer
/// as for the same world positions given as vertices. Positions given by
/// `glcol_mesh_create` and `glcol_mesh_update_positions` stay in the mesh's own frame.
/// NULL `m` (or the identity matrix): back to the identity, the default. Cost: a few
/// operations per leaf box (about one box per 450 polygons), no vertex is read or written,
/// so moving an instrument costs far less than updating its vertices. The mesh's boxes
/// follow the matrix conservatively (a rotated mesh's boxes are looser, which costs
/// culling, never an answer). The GL backends answer the pairs that involve a transformed
/// mesh with the CPU engine (a query that would collide a transformed mesh with a mesh
/// bound to a GL buffer answers UNSUPPORTED). Statuses: NULL_POINTER (scene),
/// UNKNOWN_MESH; NON_FINITE when an entry is NaN or infinite, or when world positions
/// could overflow the float range (|m| times the largest local coordinates plus
/// |translation| above FLT_MAX, judged from the mesh's bounding box;
/// `glcol_mesh_update_positions` then refuses positions that would overflow under the
/// mesh's matrix); UNSUPPORTED for a mesh bound to a GL buffer (`glcol_mesh_bind_gl_buffer`).
/// On failure nothing changes.
///
/// # Safety
/// `scene` is NULL or a live scene; `m` is NULL or points at 12 readable doubles.
#[no_mangle]
pub unsafe extern "C" fn glcol_mesh_set_transform(
    scene: *mut GlcolScene,
    mesh: GlcolMeshId,
    m: *const f64,
) -> GlcolStatus {
    guard(|| {
        // SAFETY: the caller's contract: NULL (refused) or a live scene.
        let s = unsafe { scene_mut(scene) }?;
        let m = if m.is_null() {
            None
        } else {
            // SAFETY: the caller's contract: non-null `m` points at 12 readable doubles
            // (read unaligned: a caller's `double[12]` is aligned, this costs nothing).
            Some(unsafe { m.cast::<[f64; 12]>().read_unaligned() })
        };
        Ok(s.scene.set_transform(mesh, m.as_ref())?)
    })
}

/// GL_COMPUTE backend (and a CPU scene that AUTO chose on a GL context, see below): from
/// now on the mesh reads its positions from the host's GL buffer object `gl_buffer` at
/// each query, with no copy through the CPU on GL_COMPUTE; the host keeps ownership. Vertex `i` is three floats at byte `offset + i * stride` (`stride` 0 = 12;
/// `offset` and `stride` multiples of 4, stride >= 12). The positions the mesh was created
/// with (or last given by `glcol_mesh_update_positions`) are not used while bound.
/// Statuses: UNKNOWN_MESH, INVALID_ARGUMENT (buffer 0 or not a buffer, offset/stride,
/// buffer too small), GL_UNAVAILABLE (no or the wrong context current), GL_ERROR; scenes
/// created for GLCOL_BACKEND_CPU or GL_SELECT (or by AUTO without a loader) answer
/// GLCOL_STATUS_UNSUPPORTED, and so does a mesh that has a target (clear it first).
///
/// Rules while bound:
/// - Each `glcol_query` / `glcol_query_all` checks the buffer again (it may be re-specified
///   or deleted at any time): not a buffer any more, mapped, or smaller than `offset` +
///   the vertices need: GLCOL_STATUS_INVALID_ARGUMENT naming the mesh and the sizes.
/// - Synchronisation: the host needs no glMemoryBarrier. Writes made in the same context
///   before the call (by its shaders, glBufferSubData, copies, transform feedback) are
///   seen: glcollide issues glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT) itself before
///   it reads the buffer as a shader storage block. Writes made in another (sharing)
///   context need the usual cross-context synchronisation (a fence) before the call.
/// - The buffer is read only during a query that uses the mesh, and when that query
///   answers OK the reads are complete (it waits for its one read-back, which comes after
///   them): the host may overwrite the buffer as soon as the call returns.
/// - `glcol_mesh_update_positions` takes only a full update, which unbinds the buffer.
/// - Contact geometry (`glcol_query_geometry`) describes the positions the last query
///   read (GL_COMPUTE reads them back from the GPU at that call, with the context current;
///   after a GL error since the query: INVALID_ARGUMENT, query again).
/// - Self-collision (`glcol_mesh_set_self_collision`) of a bound mesh runs on the CPU, from
///   positions GL_COMPUTE keeps on the GPU: `glcol_query_all` answers UNSUPPORTED naming
///   the mesh (a CPU scene, which reads the buffer in, answers it).
/// - Accuracy: with positions only on the GPU the GL_COMPUTE answer is final (no CPU
///   confirmation): every intersecting pair, extras within max(epsilon, 2^-20 of the
///   largest extent) / 2 (plus 2^-40 of the local size).
/// - AUTO, so that a host needs one code path: where AUTO picks the CPU on a GL context
///   (software renderers such as llvmpipe, GL below 4.3), binding works too. Each query
///   that needs the mesh then reads the buffer back (glMemoryBarrier
///   (GL_BUFFER_UPDATE_BARRIER_BIT), then glGetBufferSubData): a sync point, which waits for
///   the GPU work writing the buffer; the answer is the CPU's, exact, for those positions
///   (and so is contact geometry). The context current at the
///   first bind becomes the scene's: from then on queries and `glcol_scene_destroy` need
///   it (or one sharing its objects), as on the GL backends.
///
/// # Safety
/// `scene` is NULL or a live scene.
#[no_mangle]
pub unsafe extern "C" fn glcol_mesh_bind_gl_buffer(
    scene: *mut GlcolScene,
    mesh: GlcolMeshId,
    gl_buffer: u32,
    offset: usize,
    stride: usize,
) -> GlcolStatus {
    // SAFETY: the caller's contract: NULL (refused) or a live scene.
    unsafe { on_scene(scene, |s| s.bind_gl_buffer(mesh, gl_buffer, offset, stride)) }
}
