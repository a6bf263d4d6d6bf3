//! Headless GL for the GL tests: an EGL context on Mesa's surfaceless platform (llvmpipe
//! when there is no GPU), made current on the calling test's thread, and the C API driven
//! the way a host drives it.
#![allow(dead_code)]

use std::ffi::{c_char, c_void, CStr};

use glcollide::ffi::*;
use khronos_egl as egl;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Profile {
    /// GL 4.5 core.
    Core,
    /// The highest compatibility-profile version (4.5 on llvmpipe).
    Compat,
}

pub struct Ctx {
    egl: egl::Instance<egl::Static>,
    display: egl::Display,
    context: egl::Context,
}

const PLATFORM_SURFACELESS_MESA: egl::Enum = 0x31DD;

impl Ctx {
    /// A new context, current on this thread until dropped.
    pub fn new(profile: Profile) -> Ctx {
        let egl = egl::Instance::new(egl::Static);
        let display = unsafe {
            egl.get_platform_display(
                PLATFORM_SURFACELESS_MESA,
                egl::DEFAULT_DISPLAY,
                &[egl::ATTRIB_NONE],
            )
        }
        .expect("EGL surfaceless display (Mesa)");
        egl.initialize(display).expect("eglInitialize");
        egl.bind_api(egl::OPENGL_API).expect("eglBindAPI(OpenGL)");
        let config = egl
            .choose_first_config(
                display,
                &[
                    egl::RENDERABLE_TYPE,
                    egl::OPENGL_BIT,
                    egl::SURFACE_TYPE,
                    egl::PBUFFER_BIT,
                    egl::NONE,
                ],
            )
            .expect("eglChooseConfig")
            .expect("an OpenGL config");
        let attribs: Vec<egl::Int> = match profile {
            Profile::Core => vec![
                egl::CONTEXT_MAJOR_VERSION,
                4,
                egl::CONTEXT_MINOR_VERSION,
                5,
                egl::CONTEXT_OPENGL_PROFILE_MASK,
                egl::CONTEXT_OPENGL_CORE_PROFILE_BIT,
                egl::NONE,
            ],
            Profile::Compat => vec![
                egl::CONTEXT_OPENGL_PROFILE_MASK,
                egl::CONTEXT_OPENGL_COMPATIBILITY_PROFILE_BIT,
                egl::NONE,
            ],
        };
        let context = egl
            .create_context(display, config, None, &attribs)
            .expect("eglCreateContext");
        egl.make_current(display, None, None, Some(context))
            .expect("eglMakeCurrent (surfaceless)");
        Ctx {
            egl,
            display,
            context,
        }
    }

    /// glow on the current context (for the tests' own GL calls).
    pub fn glow(&self) -> glow::Context {
        unsafe {
            glow::Context::from_loader_function_cstr(|name| {
                get_proc_address(std::ptr::null_mut(), name.as_ptr()) as *const c_void
            })
        }
    }

    /// The fixed-function entry points (compatibility contexts).
    pub fn compat(&self) -> glcollide::internals::compat::Gl {
        glcollide::internals::compat::Gl::load_with(|name| {
            let c = std::ffi::CString::new(name).unwrap();
            unsafe { get_proc_address(std::ptr::null_mut(), c.as_ptr()) as *const c_void }
        })
    }
}

impl Drop for Ctx {
    fn drop(&mut self) {
        let _ = self.egl.make_current(self.display, None, None, None);
        let _ = self.egl.destroy_context(self.display, self.context);
    }
}

extern "C" {
    fn eglGetProcAddress(name: *const c_char) -> *mut c_void;
}

/// The loader a host hands to glcollide.
pub unsafe extern "C" fn get_proc_address(_user: *mut c_void, name: *const c_char) -> *mut c_void {
    eglGetProcAddress(name)
}

pub fn last_error() -> String {
    unsafe { CStr::from_ptr(glcol_last_error_message()) }
        .to_string_lossy()
        .into_owned()
}

/// A scene through the C API; `Err((status, message))` on failure.
pub fn try_scene(
    backend: GlcolBackend,
    epsilon: f32,
    leaf: u32,
) -> Result<*mut GlcolScene, (GlcolStatus, String)> {
    unsafe {
        let mut d = std::mem::zeroed::<GlcolSceneDesc>();
        glcol_scene_desc_init(&mut d);
        d.backend = backend as u32;
        d.get_proc_address = Some(get_proc_address);
        d.epsilon = epsilon;
        d.max_polygons_per_box = leaf;
        let mut s = std::ptr::null_mut();
        match glcol_scene_create(&d, &mut s) {
            GlcolStatus::Ok => Ok(s),
            st => Err((st, last_error())),
        }
    }
}

pub fn scene(backend: GlcolBackend, epsilon: f32, leaf: u32) -> *mut GlcolScene {
    try_scene(backend, epsilon, leaf).unwrap_or_else(|e| panic!("{backend:?}: {e:?}"))
}

pub fn backend_of(s: *mut GlcolScene) -> u32 {
    let mut b = 99;
    assert_eq!(unsafe { glcol_scene_backend(s, &mut b) }, GlcolStatus::Ok);
    b
}

pub fn ok(st: GlcolStatus) {
    assert_eq!(st, GlcolStatus::Ok, "{}", last_error());
}

pub fn add_mesh(s: *mut GlcolScene, pos: &[[f32; 3]], idx: &[u32], k: usize) -> GlcolMeshId {
    unsafe {
        let mut d = std::mem::zeroed::<GlcolMeshDesc>();
        glcol_mesh_desc_init(&mut d);
        d.positions = pos.as_ptr().cast();
        d.vertex_count = pos.len();
        d.indices = idx.as_ptr();
        d.polygon_count = idx.len() / k;
        d.vertices_per_polygon = k as u32;
        let mut id = 0;
        ok(glcol_mesh_create(s, &d, &mut id));
        id
    }
}

pub fn update(s: *mut GlcolScene, id: GlcolMeshId, pos: &[[f32; 3]]) {
    ok(unsafe { glcol_mesh_update_positions(s, id, pos.as_ptr().cast(), 0, pos.len(), 0) });
}

/// (other mesh, reference polygon, other polygon), as the query returns them.
pub fn query(s: *mut GlcolScene, reference: GlcolMeshId) -> Vec<(u32, u32, u32)> {
    unsafe {
        let mut c = std::ptr::null();
        let mut n = 0;
        ok(glcol_query(s, reference, &mut c, &mut n));
        if n == 0 {
            return Vec::new();
        }
        std::slice::from_raw_parts(c, n)
            .iter()
            .map(|c| (c.other_mesh, c.reference_polygon, c.other_polygon))
            .collect()
    }
}
