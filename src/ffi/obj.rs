//! Reading OBJ files for examples and tests (`GlcolObjMesh`).

use std::ffi::{c_char, CStr};

use super::desc::try_reserve;
use super::guard::{guard, invalid, non_null};
use super::types::*;
use crate::ObjMesh;

/// Reads a Wavefront OBJ file (`v` and `f` lines; larger faces split into triangle fans)
/// for examples and tests. On success `*out` owns arrays to release with `glcol_obj_free`.
///
/// # Safety
/// `path` is NULL or a NUL-terminated string; `out` is NULL or writable and aligned.
#[no_mangle]
pub unsafe extern "C" fn glcol_obj_load(
    path: *const c_char,
    out: *mut GlcolObjMesh,
) -> GlcolStatus {
    guard(|| {
        non_null(path, "path")?;
        non_null(out, "out")?;
        // SAFETY: non-null (checked); the caller's contract: NUL-terminated.
        let p = unsafe { CStr::from_ptr(path) }
            .to_str()
            .map_err(|_| invalid("path is not UTF-8"))?;
        let m = ObjMesh::load(p)?;
        let mut positions = Vec::new();
        try_reserve(
            &mut positions,
            3 * m.positions.len(),
            "the OBJ file's positions",
        )?;
        positions.extend(m.positions.into_iter().flatten());
        let positions = positions.into_boxed_slice();
        let indices: Box<[u32]> = m.triangles.into_boxed_slice();
        let (vc, pc) = (positions.len() / 3, indices.len() / 3);
        let mesh = GlcolObjMesh {
            positions: Box::into_raw(positions).cast(),
            vertex_count: vc,
            indices: Box::into_raw(indices).cast(),
            polygon_count: pc,
            vertices_per_polygon: 3,
        };
        // SAFETY: non-null (checked); the caller's contract: writable and aligned.
        unsafe { out.write(mesh) };
        Ok(())
    })
}

/// Releases the arrays of a mesh read by `glcol_obj_load` and zeroes it. NULL is fine.
///
/// # Safety
/// `mesh` is NULL, or a writable `GlcolObjMesh` filled by `glcol_obj_load` (or zeroed by
/// `glcol_obj_free`) whose fields the caller has not changed.
#[no_mangle]
pub unsafe extern "C" fn glcol_obj_free(mesh: *mut GlcolObjMesh) {
    if mesh.is_null() {
        return;
    }
    // SAFETY: non-null (checked); the caller's contract: an aligned, initialised
    // GlcolObjMesh.
    let m = unsafe { mesh.read() };
    if !m.positions.is_null() {
        // SAFETY: the caller's contract: `positions` is the Box<[f32]> of
        // 3 * vertex_count floats glcol_obj_load leaked, not freed yet.
        drop(unsafe {
            Box::from_raw(std::ptr::slice_from_raw_parts_mut(
                m.positions,
                m.vertex_count * 3,
            ))
        });
    }
    if !m.indices.is_null() {
        // SAFETY: the caller's contract: `indices` is the Box<[u32]> of
        // 3 * polygon_count values glcol_obj_load leaked, not freed yet.
        drop(unsafe {
            Box::from_raw(std::ptr::slice_from_raw_parts_mut(
                m.indices,
                m.polygon_count * 3,
            ))
        });
    }
    let zeroed = GlcolObjMesh {
        positions: std::ptr::null_mut(),
        vertex_count: 0,
        indices: std::ptr::null_mut(),
        polygon_count: 0,
        vertices_per_polygon: 0,
    };
    // SAFETY: non-null (checked); the caller's contract: writable and aligned.
    unsafe { mesh.write(zeroed) };
}
