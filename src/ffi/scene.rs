//! `GlcolScene`: making, asking about and destroying a scene.

use super::desc::{init_sized, oldest_size, read_desc};
use super::guard::{guard, guard_or, invalid, non_null, Fail};
use super::types::*;
use std::ffi::CStr;

use crate::{BackendRequest, GlLoader, Scene, SceneConfig};

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
    pub(super) scene: Scene,
    pub(super) contacts: Vec<GlcolContact>,
    pub(super) pairs: Vec<GlcolPair>,
    pub(super) geometry: Vec<GlcolContactGeometry>,
    pub(super) impacts: Vec<GlcolImpact>,
    pub(super) impact_geometry: Vec<GlcolImpactGeometry>,
}

/// The scene behind a pointer, or `NULL_POINTER`.
///
/// # Safety
/// `p` is NULL or a live scene (made by `glcol_scene_create`, not destroyed) that nothing
/// else uses for `'a`.
pub(super) unsafe fn scene_mut<'a>(p: *mut GlcolScene) -> Result<&'a mut GlcolScene, Fail> {
    non_null(p, "scene")?;
    // SAFETY: non-null (checked), and the caller's contract: a live scene used by nothing
    // else for 'a.
    Ok(unsafe { &mut *p })
}

/// A C function's whole body when it is one call of the Rust API on the scene: NULL_POINTER
/// for a NULL scene, else `f`'s outcome as a status (and message).
///
/// # Safety
/// `p` is NULL or a live scene that nothing else uses during the call.
pub(super) unsafe fn on_scene(
    p: *mut GlcolScene,
    f: impl FnOnce(&mut Scene) -> crate::Result<()>,
) -> GlcolStatus {
    guard(|| {
        // SAFETY: the caller's contract: NULL (refused) or a live scene.
        let s = unsafe { scene_mut(p) }?;
        Ok(f(&mut s.scene)?)
    })
}

/// The scene behind a const pointer, or `NULL_POINTER`.
///
/// # Safety
/// `p` is NULL or a live scene that no one changes for `'a`.
pub(super) unsafe fn scene_ref<'a>(p: *const GlcolScene) -> Result<&'a GlcolScene, Fail> {
    non_null(p, "scene")?;
    // SAFETY: non-null (checked), and the caller's contract: a live scene no one changes
    // for 'a.
    Ok(unsafe { &*p })
}

/// The most worker threads a scene may ask for (`GlcolSceneDesc::threads`).
const MAX_THREADS: u32 = 1024;

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
    // SAFETY: the caller's contract: NULL or writable for 0.1's size. A NULL (or
    // misaligned) `desc` is ignored: nothing is written, and no message is set.
    let _ = unsafe { init_sized(desc, oldest_size::<GlcolSceneDesc>()) };
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
        // SAFETY: the caller's contract: NULL (refused) or `size` writable bytes.
        unsafe { init_sized(desc, size) }
    })
}

/// Makes a scene. On success `*out_scene` owns it (free with `glcol_scene_destroy`); on
/// failure `*out_scene` is untouched.
///
/// GL backends load their entry points through `desc->get_proc_address` for the context
/// current on the calling thread, and every later GL-backed call of the scene must run
/// with that context (or one sharing its objects) current. Every GL-backed call leaves the
/// host's GL state as it found it (the list: docs/API.md, "GL state is left as it was found") and answers
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
/// - `desc->threads`: workers for the scene's queries, started once, at its first query
///   that needs them (0 = one per core; at most 1024, else INVALID_ARGUMENT).
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
        // SAFETY: `desc` is non-null (checked), readable for struct_size bytes (the caller's
        // contract; a misaligned one is refused first).
        let d = unsafe { read_desc(desc) }?;
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
        let (gpa, user_data) = (d.get_proc_address, d.user_data);
        if gpa.is_none() && !matches!(request, BackendRequest::Auto | BackendRequest::Cpu) {
            let name = GlcolBackend::from_raw(d.backend).map_or(c"", GlcolBackend::name);
            return Err(Fail(
                GlcolStatus::GlUnavailable,
                format!(
                    "{} needs get_proc_address (it is NULL)",
                    name.to_string_lossy()
                ),
            ));
        }
        // The caller's loader as the Rust API takes it.
        let lookup = |name: &CStr| {
            gpa.map_or(std::ptr::null(), |f| {
                // SAFETY: the caller's contract: a non-NULL `get_proc_address` is a loader
                // for the current context, called with `user_data`; `name` is NUL-terminated
                // and outlives the call.
                unsafe { f(user_data, name.as_ptr()) }.cast_const()
            })
        };
        let loader: Option<GlLoader<'_>> = gpa.is_some().then_some(&lookup as GlLoader<'_>);
        // SAFETY: `loader` serves the context current on this thread (above).
        let scene = unsafe { Scene::with_backend(config, request, loader) }?;
        let scene = Box::into_raw(Box::new(GlcolScene {
            scene,
            contacts: Vec::new(),
            pairs: Vec::new(),
            geometry: Vec::new(),
            impacts: Vec::new(),
            impact_geometry: Vec::new(),
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
