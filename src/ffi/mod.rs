//! The C ABI: the only `extern "C"` code. Each function checks its pointers, runs its body
//! in [`guard::guard`] (errors become a status and a thread-local message, panics become
//! `GLCOL_STATUS_INTERNAL`), and writes its outputs only on success.

#![allow(clippy::missing_safety_doc)]

mod guard;
mod types;

use std::ffi::{c_char, CStr};

use guard::{guard, guard_or, invalid, non_null, Fail, FfiResult};
pub use types::*;

use crate::backend::{Backend, Request};
use crate::mesh::Positions;
use crate::scene::{Scene, SceneConfig};

/// ABI version: bumps on any incompatible change of the C API (and with it the soname).
pub const GLCOL_ABI_VERSION: u32 = 1;

/// A scene: meshes, a backend, and the last query's contacts. Opaque; made by
/// `glcol_scene_create`, freed by `glcol_scene_destroy`.
///
/// Threads: a scene is used by one thread at a time; the caller synchronises (calls on
/// one scene from two threads at once are undefined behaviour, not detected). Different
/// scenes may be used on different threads at the same time without locking (CPU backend;
/// GL-backed scenes also need their context current on that thread). Nothing else is
/// shared between scenes; the last-error message is per thread.
///
/// Misuse the library cannot detect (undefined behaviour): a dangling, freed or foreign
/// pointer passed as a scene (or used after `glcol_scene_destroy`); arrays shorter than
/// their counts and stride say (positions, indices); a contacts array read after the next
/// non-const call on its scene. (Mesh ids are unique in the process, so an id made by
/// another scene, or destroyed, is always detected: GLCOL_STATUS_UNKNOWN_MESH.)
pub struct GlcolScene {
    scene: Scene,
    contacts: Vec<GlcolContact>,
}

/// The scene behind a pointer, or `NULL_POINTER`.
unsafe fn scene_mut<'a>(p: *mut GlcolScene) -> Result<&'a mut GlcolScene, Fail> {
    non_null(p, "scene")?;
    Ok(&mut *p)
}

/// Checks a caller struct's `struct_size` (the first field) against the one we know.
fn check_struct_size(got: u32, want: usize, what: &str) -> FfiResult {
    if got as usize != want {
        return Err(invalid(format!(
            "{what}.struct_size is {got}, expected {want} (sizeof({what}) of this glcollide; call the _init function or set it)"
        )));
    }
    Ok(())
}

/// `Positions` over the caller's array after every check that can be made.
unsafe fn positions<'a>(p: *const f32, count: usize, stride: usize) -> Result<Positions<'a>, Fail> {
    non_null(p, "positions")?;
    if count == 0 {
        return Err(invalid("vertex_count is 0"));
    }
    if (p as usize) % std::mem::align_of::<f32>() != 0 {
        return Err(invalid("positions is not 4-byte aligned"));
    }
    let s = if stride == 0 { 12 } else { stride };
    let len = Positions::byte_len(count, s)
        .filter(|&n| n <= isize::MAX as usize)
        .ok_or_else(|| {
            invalid(format!(
                "vertex_count {count} times position_stride {stride} overflows"
            ))
        })?;
    // The stride itself (>= 12, multiple of 4) is checked by Positions::new.
    let bytes = if s >= 12 {
        std::slice::from_raw_parts(p.cast::<u8>(), len)
    } else {
        &[]
    };
    Ok(Positions::new(bytes, count, stride)?)
}

/// Name of a status, e.g. "GLCOL_STATUS_NON_FINITE". A static string, never NULL
/// ("GLCOL_STATUS_UNKNOWN" for values not in the enum).
#[no_mangle]
pub extern "C" fn glcol_status_name(s: raw::GlcolStatus) -> *const c_char {
    let name: &'static [u8] = match s {
        0 => b"GLCOL_STATUS_OK\0",
        1 => b"GLCOL_STATUS_NULL_POINTER\0",
        2 => b"GLCOL_STATUS_INVALID_ARGUMENT\0",
        3 => b"GLCOL_STATUS_NON_FINITE\0",
        4 => b"GLCOL_STATUS_INDEX_OUT_OF_RANGE\0",
        5 => b"GLCOL_STATUS_UNKNOWN_MESH\0",
        6 => b"GLCOL_STATUS_GL_UNAVAILABLE\0",
        7 => b"GLCOL_STATUS_GL_ERROR\0",
        8 => b"GLCOL_STATUS_UNSUPPORTED\0",
        9 => b"GLCOL_STATUS_OUT_OF_MEMORY\0",
        10 => b"GLCOL_STATUS_INTERNAL\0",
        _ => b"GLCOL_STATUS_UNKNOWN\0",
    };
    name.as_ptr().cast()
}

/// Human-readable detail of the last failing call on this thread ("" if none). The
/// pointer stays valid until the next failing glcol_ call on this thread. Never NULL.
#[no_mangle]
pub extern "C" fn glcol_last_error_message() -> *const c_char {
    guard::last_error_ptr()
}

/// ABI version of the loaded library; bumps on any incompatible change.
#[no_mangle]
pub extern "C" fn glcol_abi_version() -> u32 {
    GLCOL_ABI_VERSION
}

/// Version of the loaded library ("0.1.0"), a static string.
#[no_mangle]
pub extern "C" fn glcol_version() -> *const c_char {
    concat!(env!("CARGO_PKG_VERSION"), "\0").as_ptr().cast()
}

/// Fills every field of `desc` with its default: struct_size, GLCOL_BACKEND_AUTO, no
/// loader, epsilon 0 (exact), max_polygons_per_box 0 (rule of thumb). NULL is ignored.
#[no_mangle]
pub unsafe extern "C" fn glcol_scene_desc_init(desc: *mut GlcolSceneDesc) {
    if desc.is_null() {
        return;
    }
    desc.write(GlcolSceneDesc {
        struct_size: std::mem::size_of::<GlcolSceneDesc>() as u32,
        backend: GlcolBackend::Auto as u32,
        get_proc_address: None,
        user_data: std::ptr::null_mut(),
        epsilon: 0.0,
        max_polygons_per_box: 0,
    });
}

/// Fills every field of `desc` with its default (struct_size set, everything else 0/NULL,
/// vertices_per_polygon 3). NULL is ignored.
#[no_mangle]
pub unsafe extern "C" fn glcol_mesh_desc_init(desc: *mut GlcolMeshDesc) {
    if desc.is_null() {
        return;
    }
    desc.write(GlcolMeshDesc {
        struct_size: std::mem::size_of::<GlcolMeshDesc>() as u32,
        positions: std::ptr::null(),
        vertex_count: 0,
        position_stride: 0,
        indices: std::ptr::null(),
        polygon_count: 0,
        vertices_per_polygon: 3,
    });
}

/// Makes a scene. On success `*out_scene` owns it (free with `glcol_scene_destroy`); on
/// failure `*out_scene` is untouched.
///
/// GL backends load their entry points through `desc->get_proc_address` for the context
/// current on the calling thread, and every later GL-backed call of the scene must run
/// with that context (or one sharing its objects) current. Every GL-backed call leaves the
/// host's GL state as it found it (see README "GL backends") and answers
/// GLCOL_STATUS_GL_ERROR, naming the GL error, if the GL reports one during its work.
/// - GLCOL_BACKEND_AUTO: GLCOL_BACKEND_GL_COMPUTE on a hardware GL 4.3+ context; the CPU
///   backend when there is no loader or no current context, or on a software renderer
///   (llvmpipe, softpipe, SwiftShader: the CPU is faster there). `glcol_scene_backend`
///   tells which.
/// - GLCOL_BACKEND_GL_SELECT: needs a compatibility-profile context (or GL 3.0) and 3 clip
///   planes; GLCOL_BACKEND_GL_COMPUTE needs GL 4.3+ (core or compatibility) with 12 shader
///   storage buffer bindings (GL's minimum is 8; desktop drivers have 16 or more).
///   Otherwise, or without a loader or a current context: GLCOL_STATUS_GL_UNAVAILABLE, the
///   message says why.
/// - A GL-backed call made while the host's transform feedback is running (not paused), or
///   while a compatibility context is in GL_SELECT/GL_FEEDBACK render mode, answers
///   GLCOL_STATUS_GL_UNAVAILABLE and changes nothing.
/// - GL backends: the GL's own tests use a depth of at least 2^-20 times the largest extent
///   of the meshes in a query (float clip precision), then each hit is confirmed with the
///   CPU backend's test at `epsilon`, so the contacts are the CPU backend's, exact at
///   epsilon 0. Exception: a query with a mesh bound by glcol_mesh_bind_gl_buffer has no
///   positions on the CPU; there an epsilon below that minimum (0 included) is raised to it.
#[no_mangle]
pub unsafe extern "C" fn glcol_scene_create(
    desc: *const GlcolSceneDesc,
    out_scene: *mut *mut GlcolScene,
) -> GlcolStatus {
    guard(|| {
        non_null(desc, "desc")?;
        non_null(out_scene, "out_scene")?;
        // struct_size first: the rest may not be there.
        let size = std::ptr::addr_of!((*desc).struct_size).read_unaligned();
        check_struct_size(
            size,
            std::mem::size_of::<GlcolSceneDesc>(),
            "GlcolSceneDesc",
        )?;
        let d = desc.read();
        let request = match d.backend {
            0 => Request::Auto,
            1 => Request::Cpu,
            2 => Request::GlSelect,
            3 => Request::GlCompute,
            v => {
                return Err(invalid(format!(
                    "backend is {v}; it must be a GlcolBackend value (0 to 3)"
                )))
            }
        };
        let config = SceneConfig {
            epsilon: d.epsilon,
            max_polygons_per_box: d.max_polygons_per_box,
            ..SceneConfig::default()
        };
        config.validate()?;
        let selector = crate::backend::create(request, d.get_proc_address, d.user_data)?;
        let scene = Scene::with_selector(config, selector)?;
        out_scene.write(Box::into_raw(Box::new(GlcolScene {
            scene,
            contacts: Vec::new(),
        })));
        Ok(())
    })
}

/// Frees a scene and everything in it. NULL is fine. GL backends: deletes the scene's GL
/// objects, so the scene's context (or one sharing its objects) must be current; the
/// host's GL state is left as it was. Using the pointer afterwards is undefined (not
/// detectable).
#[no_mangle]
pub unsafe extern "C" fn glcol_scene_destroy(scene: *mut GlcolScene) {
    if !scene.is_null() {
        let mut s = Box::from_raw(scene);
        guard_or((), || s.scene.release_gl());
        guard_or((), || drop(s));
    }
}

/// The backend the scene runs on (what AUTO chose).
#[no_mangle]
pub unsafe extern "C" fn glcol_scene_backend(
    scene: *const GlcolScene,
    out: *mut raw::GlcolBackend,
) -> GlcolStatus {
    guard(|| {
        non_null(scene, "scene")?;
        non_null(out, "out")?;
        let b = match (*scene).scene.backend() {
            Backend::Cpu => GlcolBackend::Cpu,
            Backend::GlSelect => GlcolBackend::GlSelect,
            Backend::GlCompute => GlcolBackend::GlCompute,
        };
        out.write(b as u32);
        Ok(())
    })
}

/// Adds a mesh: positions and indices are copied, the leaf boxes built. On success
/// `*out_id` gets the new id; on failure nothing changes. Statuses: NULL_POINTER (scene,
/// desc, out_id, positions, indices), INVALID_ARGUMENT (struct_size, zero counts, stride,
/// alignment, vertices_per_polygon, overflow), NON_FINITE, INDEX_OUT_OF_RANGE.
/// Counts above 2^32 - 1 vertices or 2^32 - 2 polygons, or whose byte size overflows, are
/// refused before the arrays are read. Arrays shorter than the counts say, or dangling
/// pointers, cannot be detected (undefined behaviour).
#[no_mangle]
pub unsafe extern "C" fn glcol_mesh_create(
    scene: *mut GlcolScene,
    desc: *const GlcolMeshDesc,
    out_id: *mut GlcolMeshId,
) -> GlcolStatus {
    guard(|| {
        let s = scene_mut(scene)?;
        non_null(desc, "desc")?;
        non_null(out_id, "out_id")?;
        let size = std::ptr::addr_of!((*desc).struct_size).read_unaligned();
        check_struct_size(size, std::mem::size_of::<GlcolMeshDesc>(), "GlcolMeshDesc")?;
        let d = desc.read();
        let k = d.vertices_per_polygon;
        if k != 3 && k != 4 {
            return Err(invalid(format!(
                "vertices_per_polygon is {k}; it must be 3 or 4"
            )));
        }
        non_null(d.positions, "positions")?;
        non_null(d.indices, "indices")?;
        if d.polygon_count == 0 {
            return Err(invalid("polygon_count is 0"));
        }
        // Counts the library cannot number are refused before any array is touched.
        if d.vertex_count > u32::MAX as usize {
            return Err(invalid(format!(
                "vertex_count {} overflows the 32-bit vertex numbers (at most 2^32 - 1)",
                d.vertex_count
            )));
        }
        if d.polygon_count > u32::MAX as usize - 1 {
            return Err(invalid(format!(
                "polygon_count {} overflows the 32-bit polygon numbers (at most 2^32 - 2)",
                d.polygon_count
            )));
        }
        let pos = positions(d.positions, d.vertex_count, d.position_stride)?;
        if (d.indices as usize) % std::mem::align_of::<u32>() != 0 {
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
        let indices = std::slice::from_raw_parts(d.indices, n);
        let id = s.scene.create_mesh(pos, indices, k as usize)?;
        out_id.write(id);
        Ok(())
    })
}

/// Moves vertices `first_vertex .. first_vertex + vertex_count` to `positions` (x, y, z
/// each, `position_stride` bytes apart, 0 = packed) and refits the mesh's boxes. Rejected
/// whole on any error (the mesh keeps its previous positions): UNKNOWN_MESH, NULL_POINTER,
/// INVALID_ARGUMENT (zero count, range past the end, stride, alignment, overflow),
/// NON_FINITE. The range is checked against the mesh before the array is read; an array
/// shorter than `vertex_count` vertices `position_stride` apart cannot be detected
/// (undefined behaviour).
#[no_mangle]
pub unsafe extern "C" fn glcol_mesh_update_positions(
    scene: *mut GlcolScene,
    mesh: GlcolMeshId,
    positions: *const f32,
    first_vertex: usize,
    vertex_count: usize,
    position_stride: usize,
) -> GlcolStatus {
    guard(|| {
        let s = scene_mut(scene)?;
        let n = s.scene.mesh(mesh)?.vertex_count();
        non_null(positions, "positions")?;
        // The range first, so that no count larger than the mesh reaches the array.
        if vertex_count != 0 && first_vertex.checked_add(vertex_count).is_none_or(|e| e > n) {
            return Err(invalid(format!(
                "first_vertex {first_vertex} + vertex_count {vertex_count} runs past the mesh's {n} vertices"
            )));
        }
        let pos = self::positions(positions, vertex_count, position_stride)?;
        s.scene.update_positions(mesh, first_vertex, pos)?;
        Ok(())
    })
}

/// Enables or disables a mesh. A disabled mesh costs nothing in a query and has no
/// contacts (as reference or as other).
#[no_mangle]
pub unsafe extern "C" fn glcol_mesh_set_enabled(
    scene: *mut GlcolScene,
    mesh: GlcolMeshId,
    enabled: bool,
) -> GlcolStatus {
    guard(|| Ok(scene_mut(scene)?.scene.set_enabled(mesh, enabled)?))
}

/// Removes a mesh from the scene. Its id is never reused.
#[no_mangle]
pub unsafe extern "C" fn glcol_mesh_destroy(
    scene: *mut GlcolScene,
    mesh: GlcolMeshId,
) -> GlcolStatus {
    guard(|| Ok(scene_mut(scene)?.scene.destroy_mesh(mesh)?))
}

/// Collides `reference` against every other enabled mesh (the paper's five steps). On
/// success `*out_contacts` points at `*out_count` contacts sorted by (other_mesh,
/// reference_polygon, other_polygon), each pair once (NULL when the count is 0). The array
/// is owned by the scene and stays valid until the next call that takes this scene
/// non-const. Meaning: with epsilon e > 0 the other polygon meets the reference polygon's
/// viewing volume (the polygon thickened by e/2 along its normal); with e = 0 the two
/// closed polygons intersect exactly (touching counts).
#[no_mangle]
pub unsafe extern "C" fn glcol_query(
    scene: *mut GlcolScene,
    reference: GlcolMeshId,
    out_contacts: *mut *const GlcolContact,
    out_count: *mut usize,
) -> GlcolStatus {
    guard(|| {
        let s = scene_mut(scene)?;
        non_null(out_contacts, "out_contacts")?;
        non_null(out_count, "out_count")?;
        let found = s.scene.query(reference)?;
        s.contacts.clear();
        s.contacts.extend(found.iter().map(|c| GlcolContact {
            reference_polygon: c.reference_polygon,
            other_mesh: c.other_mesh,
            other_polygon: c.other_polygon,
        }));
        out_contacts.write(if s.contacts.is_empty() {
            std::ptr::null()
        } else {
            s.contacts.as_ptr()
        });
        out_count.write(s.contacts.len());
        Ok(())
    })
}

/// GL_COMPUTE backend only: from now on the mesh reads its positions from the host's GL
/// buffer object `gl_buffer` at each query, with no copy through the CPU; the host keeps
/// ownership and must keep the buffer alive (and `vertex_count` vertices in it) while it
/// is bound. Vertex `i` is three floats at byte `offset + i * stride` (`stride` 0 = 12;
/// `offset` and `stride` multiples of 4, stride >= 12). The positions the mesh was created
/// with (or last given by `glcol_mesh_update_positions`, which unbinds the buffer) are not
/// used while bound. Needs the scene's context current. Statuses: UNKNOWN_MESH,
/// INVALID_ARGUMENT (buffer 0 or not a buffer, offset/stride, buffer too small),
/// GL_ERROR; other backends answer GLCOL_STATUS_UNSUPPORTED.
#[no_mangle]
pub unsafe extern "C" fn glcol_mesh_bind_gl_buffer(
    scene: *mut GlcolScene,
    mesh: GlcolMeshId,
    gl_buffer: u32,
    offset: usize,
    stride: usize,
) -> GlcolStatus {
    guard(|| {
        let s = scene_mut(scene)?;
        Ok(s.scene.bind_gl_buffer(mesh, gl_buffer, offset, stride)?)
    })
}

/// Reads a Wavefront OBJ file (`v` and `f` lines; larger faces split into triangle fans)
/// for examples and tests. On success `*out` owns arrays to release with `glcol_obj_free`.
#[no_mangle]
pub unsafe extern "C" fn glcol_obj_load(
    path: *const c_char,
    out: *mut GlcolObjMesh,
) -> GlcolStatus {
    guard(|| {
        non_null(path, "path")?;
        non_null(out, "out")?;
        let p = CStr::from_ptr(path)
            .to_str()
            .map_err(|_| invalid("path is not UTF-8"))?;
        let m = crate::obj::load(p)?;
        let positions: Box<[f32]> = m.positions.into_iter().flatten().collect();
        let indices: Box<[u32]> = m.triangles.into_boxed_slice();
        let (vc, pc) = (positions.len() / 3, indices.len() / 3);
        out.write(GlcolObjMesh {
            positions: Box::into_raw(positions).cast(),
            vertex_count: vc,
            indices: Box::into_raw(indices).cast(),
            polygon_count: pc,
            vertices_per_polygon: 3,
        });
        Ok(())
    })
}

/// Releases the arrays of a mesh read by `glcol_obj_load` and zeroes it. NULL is fine.
#[no_mangle]
pub unsafe extern "C" fn glcol_obj_free(mesh: *mut GlcolObjMesh) {
    if mesh.is_null() {
        return;
    }
    let m = mesh.read();
    if !m.positions.is_null() {
        drop(Box::from_raw(std::ptr::slice_from_raw_parts_mut(
            m.positions,
            m.vertex_count * 3,
        )));
    }
    if !m.indices.is_null() {
        drop(Box::from_raw(std::ptr::slice_from_raw_parts_mut(
            m.indices,
            m.polygon_count * 3,
        )));
    }
    mesh.write(GlcolObjMesh {
        positions: std::ptr::null_mut(),
        vertex_count: 0,
        indices: std::ptr::null_mut(),
        polygon_count: 0,
        vertices_per_polygon: 0,
    });
}
