//! The C ABI: the only `extern "C"` code. Each function checks its pointers, runs its body
//! in `guard::guard` (errors become a status and a thread-local message, panics become
//! `GLCOL_STATUS_INTERNAL`), and writes its outputs only on success.
//!
//! Every `unsafe` operation is in an `unsafe` block with a `// SAFETY:` comment saying
//! which part of the function's `# Safety` contract (or which check) makes it sound.

#![deny(unsafe_op_in_unsafe_fn)]
#![deny(clippy::undocumented_unsafe_blocks)]

mod guard;
mod tables;
mod types;

use std::ffi::{c_char, CStr};

use guard::{guard, guard_or, invalid, non_null, Fail, FfiResult};
pub use types::*;

use crate::error::try_reserve;
use crate::mesh::{check_polygon_count, check_vertex_count, Positions};
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
///
/// A "live scene", in the functions' Safety sections: a pointer made by
/// `glcol_scene_create`, not yet given to `glcol_scene_destroy`, used by no other thread
/// during the call.
///
/// Contexts (GL_SELECT, GL_COMPUTE): the GL-backed calls (`glcol_query`,
/// `glcol_query_all`, `glcol_mesh_bind_gl_buffer`, `glcol_scene_destroy`) need the scene's
/// context, or one sharing its objects, current on the calling thread. Each checks it
/// first, raising no GL error and changing nothing: with no context current it answers
/// GLCOL_STATUS_GL_UNAVAILABLE "no GL context is current ...", with any other context
/// GLCOL_STATUS_GL_UNAVAILABLE "wrong GL context current ..."; the scene is as before and
/// the next call with the right context answers as if the misuse had not happened. (The
/// check calls the loader's entry points with whatever context is current, as EGL and GLX
/// allow.) No call raises a GL error of its own; an error the host left pending is still
/// pending after the call, raised again with GL_DEBUG_OUTPUT off so that the host's debug
/// callback gets no second message.
pub struct GlcolScene {
    scene: Scene,
    contacts: Vec<GlcolContact>,
    pairs: Vec<GlcolPair>,
    geometry: Vec<GlcolContactGeometry>,
}

/// The scene behind a pointer, or `NULL_POINTER`.
///
/// # Safety
/// `p` is NULL or a live scene (made by `glcol_scene_create`, not destroyed) that nothing
/// else uses for `'a`.
unsafe fn scene_mut<'a>(p: *mut GlcolScene) -> Result<&'a mut GlcolScene, Fail> {
    non_null(p, "scene")?;
    // SAFETY: non-null (checked), and the caller's contract: a live scene used by nothing
    // else for 'a.
    Ok(unsafe { &mut *p })
}

/// The scene behind a const pointer, or `NULL_POINTER`.
///
/// # Safety
/// `p` is NULL or a live scene that no one changes for `'a`.
unsafe fn scene_ref<'a>(p: *const GlcolScene) -> Result<&'a GlcolScene, Fail> {
    non_null(p, "scene")?;
    // SAFETY: non-null (checked), and the caller's contract: a live scene no one changes
    // for 'a.
    Ok(unsafe { &*p })
}

/// `Err(INVALID_ARGUMENT)` naming `what` when `p` is not aligned for `T` (C guarantees it
/// for a pointer to a `T`; a misaligned one is refused before anything is read).
fn aligned<T>(p: *const T, what: &str) -> FfiResult {
    if p.is_aligned() {
        Ok(())
    } else {
        Err(invalid(format!(
            "{what} is not {}-byte aligned",
            std::mem::align_of::<T>()
        )))
    }
}

/// Reads a caller's struct: `struct_size` (its first field) first, since the rest may not
/// be there, then, if it is one of `sizes` (this library's `size_of::<T>()` first, then the
/// sizes of older versions, each a prefix of `T`), that many bytes over `defaults`: the
/// fields an older struct lacks keep their defaults and nothing past `struct_size` is read.
///
/// # Safety
/// `p` is non-null and aligned (checked by the caller), and points to readable memory of
/// at least 4 bytes, and of as many bytes as its first 4 bytes say when that is one of
/// `sizes`. Every size in `sizes` ends at a field boundary of `T`, and the bytes of those
/// fields, as C initialised them, are valid values of the fields' types.
unsafe fn read_desc<T: Copy>(
    p: *const T,
    struct_size: *const u32,
    what: &str,
    sizes: &[(usize, &str)],
    defaults: T,
) -> Result<T, Fail> {
    // SAFETY: `struct_size` is the first field of `*p` (offset 0, so in bounds and aligned
    // as `p` is): an aligned read of the 4 bytes every version of the struct has.
    let got = unsafe { struct_size.read() };
    let n = check_struct_size(got, sizes, what)?;
    debug_assert!(n <= std::mem::size_of::<T>());
    let mut out = defaults;
    // SAFETY: the caller's struct holds `n` readable bytes (its struct_size says so and `n`
    // is one of `sizes`); `out` is a distinct local `T` of at least `n` bytes; the first
    // `n` bytes are whole fields of `T` (the caller's contract), so `out` stays valid.
    unsafe { std::ptr::copy_nonoverlapping(p.cast::<u8>(), std::ptr::addr_of_mut!(out).cast(), n) };
    Ok(out)
}

/// Checks a caller struct's `struct_size` (the first field) against the sizes we know
/// (`sizes[0]` this version's; each with a note saying which version it is); returns it.
fn check_struct_size(got: u32, sizes: &[(usize, &str)], what: &str) -> Result<usize, Fail> {
    if let Some(&(n, _)) = sizes.iter().find(|&&(n, _)| n == got as usize) {
        return Ok(n);
    }
    let want = sizes
        .iter()
        .map(|&(n, note)| format!("{n} ({note})"))
        .collect::<Vec<_>>()
        .join(" or ");
    Err(invalid(format!(
        "{what}.struct_size is {got}, expected {want}; call the _init function or set it"
    )))
}

/// `GlcolSceneDesc` sizes accepted: this version's, and 0.1's (which ends before `threads`).
const SCENE_DESC_SIZES: [(usize, &str); 2] = [
    (
        std::mem::size_of::<GlcolSceneDesc>(),
        "sizeof(GlcolSceneDesc) of this glcollide",
    ),
    (
        std::mem::offset_of!(GlcolSceneDesc, threads),
        "glcollide 0.1's, without threads",
    ),
];

/// `GlcolMeshDesc` sizes accepted (one version so far).
const MESH_DESC_SIZES: [(usize, &str); 1] = [(
    std::mem::size_of::<GlcolMeshDesc>(),
    "sizeof(GlcolMeshDesc) of this glcollide",
)];

/// The most worker threads a scene may ask for (`GlcolSceneDesc::threads`).
const MAX_THREADS: u32 = 1024;

/// The defaults `glcol_scene_desc_init` writes.
fn scene_desc_defaults() -> GlcolSceneDesc {
    GlcolSceneDesc {
        struct_size: std::mem::size_of::<GlcolSceneDesc>() as u32,
        backend: GlcolBackend::Auto as u32,
        get_proc_address: None,
        user_data: std::ptr::null_mut(),
        epsilon: 0.0,
        max_polygons_per_box: 0,
        threads: 0,
    }
}

/// The defaults `glcol_mesh_desc_init` writes.
fn mesh_desc_defaults() -> GlcolMeshDesc {
    GlcolMeshDesc {
        struct_size: std::mem::size_of::<GlcolMeshDesc>() as u32,
        positions: std::ptr::null(),
        vertex_count: 0,
        position_stride: 0,
        indices: std::ptr::null(),
        polygon_count: 0,
        vertices_per_polygon: 3,
    }
}

/// `Positions` over the caller's array after every check that can be made.
///
/// # Safety
/// `p` is NULL or readable for `count` vertices `stride` bytes apart (0 = 12) for `'a`.
unsafe fn positions<'a>(p: *const f32, count: usize, stride: usize) -> Result<Positions<'a>, Fail> {
    non_null(p, "positions")?;
    if count == 0 {
        return Err(invalid("vertex_count is 0"));
    }
    if !(p as usize).is_multiple_of(std::mem::align_of::<f32>()) {
        return Err(invalid("positions is not 4-byte aligned"));
    }
    let s = Positions::stride_or_packed(stride);
    let len = Positions::byte_len(count, s)
        .filter(|&n| n <= isize::MAX as usize)
        .ok_or_else(|| {
            invalid(format!(
                "vertex_count {count} times position_stride {stride} overflows"
            ))
        })?;
    // The stride itself (>= 12, multiple of 4) is checked by Positions::new.
    let bytes = if s >= 12 {
        // SAFETY: non-null and aligned (checked), `len` <= isize::MAX (checked), and the
        // caller's contract: `count` vertices `s` apart, `len` bytes, are readable for 'a.
        unsafe { std::slice::from_raw_parts(p.cast::<u8>(), len) }
    } else {
        &[]
    };
    Ok(Positions::new(bytes, count, stride)?)
}

/// Name of a status, e.g. "GLCOL_STATUS_NON_FINITE". A static string, never NULL
/// ("GLCOL_STATUS_UNKNOWN" for values not in the enum).
#[no_mangle]
pub extern "C" fn glcol_status_name(s: raw::GlcolStatus) -> *const c_char {
    GlcolStatus::from_raw(s)
        .map_or(c"GLCOL_STATUS_UNKNOWN", GlcolStatus::name)
        .as_ptr()
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

/// Version of the loaded library (e.g. "0.1.1"), a static string.
#[no_mangle]
pub extern "C" fn glcol_version() -> *const c_char {
    concat!(env!("CARGO_PKG_VERSION"), "\0").as_ptr().cast()
}

/// The exported symbol that programs built against glcollide 0.1's header call: it fills
/// 0.1's `GlcolSceneDesc` (everything up to `threads`, which it cannot know the caller
/// has) with the defaults and sets `struct_size` to 0.1's size, so `threads` keeps its
/// default (0: one per core). This header turns every `glcol_scene_desc_init(desc)` into
/// `glcol_scene_desc_init_sized(desc, sizeof *(desc))` (a macro below), so a program
/// compiled against it fills the whole struct; only a call through a function pointer or
/// `dlsym` reaches this symbol, and such callers (language bindings) should call
/// `glcol_scene_desc_init_sized` instead. NULL is ignored.
///
/// # Safety
/// `desc` is NULL or points to writable, aligned memory of at least 0.1's
/// `sizeof(GlcolSceneDesc)` bytes.
#[no_mangle]
pub unsafe extern "C" fn glcol_scene_desc_init(desc: *mut GlcolSceneDesc) {
    if desc.is_null() {
        return;
    }
    let n = SCENE_DESC_SIZES[1].0;
    let mut d = scene_desc_defaults();
    d.struct_size = n as u32;
    // SAFETY: non-null (checked); the caller's contract: writable and aligned for 0.1's
    // size `n`, a prefix of whole fields of `d` (a distinct local).
    unsafe { std::ptr::copy_nonoverlapping(std::ptr::addr_of!(d).cast::<u8>(), desc.cast(), n) };
}

/// Fills a `GlcolSceneDesc` of `size` bytes (`sizeof(GlcolSceneDesc)` of the header the
/// caller was compiled with: this one's, or 0.1's) with its defaults: struct_size = `size`,
/// GLCOL_BACKEND_AUTO, no loader, epsilon 0 (exact), max_polygons_per_box 0 (rule of
/// thumb), threads 0 (one per core); nothing past `size` bytes is written. C and C++ call it
/// through the `glcol_scene_desc_init(desc)` macro. Statuses: NULL_POINTER, INVALID_ARGUMENT
/// (a size no version of the struct has, or a misaligned `desc`; nothing written).
///
/// # Safety
/// `desc` is NULL or points to writable memory of `size` bytes.
#[no_mangle]
pub unsafe extern "C" fn glcol_scene_desc_init_sized(
    desc: *mut GlcolSceneDesc,
    size: usize,
) -> GlcolStatus {
    guard(|| {
        non_null(desc, "desc")?;
        aligned(desc, "desc")?;
        let Some(&(n, _)) = SCENE_DESC_SIZES.iter().find(|&&(n, _)| n == size) else {
            let want = SCENE_DESC_SIZES
                .iter()
                .map(|&(n, note)| format!("{n} ({note})"))
                .collect::<Vec<_>>()
                .join(" or ");
            return Err(invalid(format!(
                "size is {size}, expected {want}: pass sizeof(GlcolSceneDesc)"
            )));
        };
        let mut d = scene_desc_defaults();
        d.struct_size = n as u32;
        // SAFETY: non-null and aligned (checked); the caller's contract: `size` == `n`
        // writable bytes; `n` is one of SCENE_DESC_SIZES, a prefix of whole fields of `d`.
        unsafe {
            std::ptr::copy_nonoverlapping(std::ptr::addr_of!(d).cast::<u8>(), desc.cast(), n)
        };
        Ok(())
    })
}

/// Fills every field of `desc` with its default (struct_size set, everything else 0/NULL,
/// vertices_per_polygon 3). NULL is ignored.
///
/// # Safety
/// `desc` is NULL or points to a writable, aligned `GlcolMeshDesc`.
#[no_mangle]
pub unsafe extern "C" fn glcol_mesh_desc_init(desc: *mut GlcolMeshDesc) {
    if desc.is_null() {
        return;
    }
    // SAFETY: non-null (checked); the caller's contract: writable and aligned.
    unsafe { desc.write(mesh_desc_defaults()) };
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
///
/// - `desc->struct_size`: `sizeof(GlcolSceneDesc)` of this header, or of 0.1's (without
///   `threads`, which then is 0): a program built against 0.1 keeps working. Nothing past
///   struct_size is read. Any other size: INVALID_ARGUMENT, the message names both sizes.
/// - `desc->threads`: workers started here, once for the scene (0 = one per core; at most
///   1024, else INVALID_ARGUMENT).
///
/// # Safety
/// `desc` is NULL or points to a readable `GlcolSceneDesc` of `desc->struct_size` bytes,
/// aligned as C aligns it (a misaligned `desc` is refused: INVALID_ARGUMENT). `out_scene` is
/// NULL or writable and aligned. A non-NULL `get_proc_address` is a loader for the context
/// current on this thread, callable with `user_data`.
#[no_mangle]
pub unsafe extern "C" fn glcol_scene_create(
    desc: *const GlcolSceneDesc,
    out_scene: *mut *mut GlcolScene,
) -> GlcolStatus {
    guard(|| {
        non_null(desc, "desc")?;
        non_null(out_scene, "out_scene")?;
        aligned(desc, "desc")?;
        // SAFETY: `desc` is non-null and aligned (checked), readable for struct_size bytes
        // (the caller's contract); addr_of! makes no reference to the whole struct.
        let d = unsafe {
            read_desc(
                desc,
                std::ptr::addr_of!((*desc).struct_size),
                "GlcolSceneDesc",
                &SCENE_DESC_SIZES,
                scene_desc_defaults(),
            )
        }?;
        let request = GlcolBackend::request(d.backend).ok_or_else(|| {
            invalid(format!(
                "backend is {}; it must be a GlcolBackend value (0 to {})",
                d.backend,
                GlcolBackend::max_value()
            ))
        })?;
        if d.threads > MAX_THREADS {
            return Err(invalid(format!(
                "threads is {}; it must be 0 (one per core) to {MAX_THREADS}",
                d.threads
            )));
        }
        let config = SceneConfig {
            epsilon: d.epsilon,
            max_polygons_per_box: d.max_polygons_per_box,
            threads: d.threads,
        };
        config.validate()?;
        // SAFETY: the caller's contract: a non-NULL loader loads for the current context
        // with `user_data`.
        let selector = unsafe { crate::backend::create(request, d.get_proc_address, d.user_data) }?;
        let scene = Scene::with_selector(config, selector)?;
        let scene = Box::into_raw(Box::new(GlcolScene {
            scene,
            contacts: Vec::new(),
            pairs: Vec::new(),
            geometry: Vec::new(),
        }));
        // SAFETY: non-null (checked); the caller's contract: writable and aligned.
        unsafe { out_scene.write(scene) };
        Ok(())
    })
}

/// Frees a scene and everything in it. NULL is fine. GL backends: deletes the scene's GL
/// objects when the scene's context (or one sharing its objects) is current; the host's
/// GL state is left as it was. With no or another context current the scene is freed but
/// its GL objects are left to the context's destruction (deleting names in another context
/// could delete the host's objects). Using the pointer afterwards is undefined (not
/// detectable).
///
/// # Safety
/// `scene` is NULL or a live scene (see GlcolScene).
#[no_mangle]
pub unsafe extern "C" fn glcol_scene_destroy(scene: *mut GlcolScene) {
    if !scene.is_null() {
        // SAFETY: the caller's contract: a live scene, so a pointer from Box::into_raw in
        // glcol_scene_create, not freed yet, that no one else uses.
        let mut s = unsafe { Box::from_raw(scene) };
        guard_or((), || s.scene.release_gl());
        guard_or((), || drop(s));
    }
}

/// The backend the scene runs on (what AUTO chose).
///
/// # Safety
/// `scene` is NULL or a live scene; `out` is NULL or writable and aligned.
#[no_mangle]
pub unsafe extern "C" fn glcol_scene_backend(
    scene: *const GlcolScene,
    out: *mut raw::GlcolBackend,
) -> GlcolStatus {
    guard(|| {
        // SAFETY: the caller's contract: NULL (refused) or a live scene.
        let s = unsafe { scene_ref(scene) }?;
        non_null(out, "out")?;
        let b = GlcolBackend::from(s.scene.backend());
        // SAFETY: non-null (checked); the caller's contract: writable and aligned.
        unsafe { out.write(b as u32) };
        Ok(())
    })
}

/// Adds a mesh: positions and indices are copied, the leaf boxes built. On success
/// `*out_id` gets the new id; on failure nothing changes. Statuses: NULL_POINTER (scene,
/// desc, out_id, positions, indices), INVALID_ARGUMENT (struct_size, zero counts, stride,
/// alignment, vertices_per_polygon, overflow), NON_FINITE, INDEX_OUT_OF_RANGE.
/// Counts above 2^32 - 1 vertices or 2^32 - 2 polygon corners (polygon_count times
/// vertices_per_polygon), or whose byte size overflows, are refused before the arrays are
/// read. Arrays shorter than the counts say, or dangling pointers, cannot be detected
/// (undefined behaviour).
///
/// # Safety
/// `scene` is NULL or a live scene. `desc` is NULL or points to a readable `GlcolMeshDesc`
/// of `desc->struct_size` bytes, aligned as C aligns it (a misaligned `desc` is refused:
/// INVALID_ARGUMENT), whose `positions` is NULL or readable for `vertex_count` vertices
/// `position_stride` bytes apart and whose `indices` is NULL or readable for
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
        aligned(desc, "desc")?;
        // SAFETY: `desc` is non-null and aligned (checked), readable for struct_size bytes
        // (the caller's contract); addr_of! makes no reference to the whole struct.
        let d = unsafe {
            read_desc(
                desc,
                std::ptr::addr_of!((*desc).struct_size),
                "GlcolMeshDesc",
                &MESH_DESC_SIZES,
                mesh_desc_defaults(),
            )
        }?;
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
        // Counts the library cannot number are refused before any array is touched, by the
        // checks Mesh::new makes.
        check_vertex_count(d.vertex_count)?;
        check_polygon_count(d.polygon_count, k as usize)?;
        // SAFETY: the caller's contract: `positions` holds `vertex_count` vertices
        // `position_stride` apart.
        let pos = unsafe { positions(d.positions, d.vertex_count, d.position_stride) }?;
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
    guard(|| {
        // SAFETY: the caller's contract: NULL (refused) or a live scene.
        let s = unsafe { scene_mut(scene) }?;
        let n = s.scene.mesh(mesh)?.vertex_count();
        non_null(positions, "positions")?;
        // The range first, so that no count larger than the mesh reaches the array.
        if vertex_count != 0 && first_vertex.checked_add(vertex_count).is_none_or(|e| e > n) {
            return Err(invalid(format!(
                "first_vertex {first_vertex} + vertex_count {vertex_count} runs past the mesh's {n} vertices"
            )));
        }
        // SAFETY: the caller's contract: `positions` holds `vertex_count` vertices
        // `position_stride` apart.
        let pos = unsafe { self::positions(positions, vertex_count, position_stride) }?;
        s.scene.update_positions(mesh, first_vertex, pos)?;
        Ok(())
    })
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
    guard(|| {
        // SAFETY: the caller's contract: NULL (refused) or a live scene.
        let s = unsafe { scene_mut(scene) }?;
        Ok(s.scene.set_enabled(mesh, enabled)?)
    })
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
    guard(|| {
        // SAFETY: the caller's contract: NULL (refused) or a live scene.
        let s = unsafe { scene_mut(scene) }?;
        Ok(s.scene.destroy_mesh(mesh)?)
    })
}

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

/// Writes `v`'s first element (NULL when empty) and length to the out-parameters.
///
/// # Safety
/// Both pointers are non-null, writable and aligned.
unsafe fn write_array<T>(v: &[T], out: *mut *const T, out_count: *mut usize) {
    let first = if v.is_empty() {
        std::ptr::null()
    } else {
        v.as_ptr()
    };
    // SAFETY: the caller's contract: both non-null, writable and aligned.
    unsafe {
        out.write(first);
        out_count.write(v.len());
    }
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
    guard(|| {
        // SAFETY: the caller's contract: NULL (refused) or a live scene.
        let s = unsafe { scene_mut(scene) }?;
        Ok(s.scene.set_self_collision(mesh, on)?)
    })
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
    guard(|| {
        // SAFETY: the caller's contract: NULL (refused) or a live scene.
        let s = unsafe { scene_mut(scene) }?;
        Ok(s.scene.set_filter(mesh, group, mask)?)
    })
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

/// Every pair of polygons that meet, in one call (the meaning of `glcol_query`: exact at
/// epsilon 0, the viewing-volume band at epsilon > 0), from two different enabled meshes
/// whose filters pass, or from one enabled mesh whose self-collision is on. Each pair
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
/// last query failed, or when the meshes changed since it (create, update, enable,
/// destroy, filter, self-collision, GL buffer binding). A mesh of the answer bound to a
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

/// GL_COMPUTE backend (and a CPU scene that AUTO chose on a GL context, see below): from
/// now on the mesh reads its positions from the host's GL buffer object `gl_buffer` at
/// each query, with no copy through the CPU on GL_COMPUTE; the host keeps ownership. Vertex `i` is three floats at byte `offset + i * stride` (`stride` 0 = 12;
/// `offset` and `stride` multiples of 4, stride >= 12). The positions the mesh was created
/// with (or last given by `glcol_mesh_update_positions`) are not used while bound.
/// Statuses: UNKNOWN_MESH, INVALID_ARGUMENT (buffer 0 or not a buffer, offset/stride,
/// buffer too small), GL_UNAVAILABLE (no or the wrong context current), GL_ERROR; scenes
/// created for GLCOL_BACKEND_CPU or GL_SELECT (or by AUTO without a loader) answer
/// GLCOL_STATUS_UNSUPPORTED.
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
    guard(|| {
        // SAFETY: the caller's contract: NULL (refused) or a live scene.
        let s = unsafe { scene_mut(scene) }?;
        Ok(s.scene.bind_gl_buffer(mesh, gl_buffer, offset, stride)?)
    })
}

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
        let m = crate::obj::load(p)?;
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
