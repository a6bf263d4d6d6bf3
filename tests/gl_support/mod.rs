//! Headless GL for the GL tests: a glutin EGL context on an EGL device (Mesa's software
//! device, llvmpipe, when there is no GPU), made current with no surface on the calling
//! test's thread, and the C API driven the way a host drives it.
#![allow(dead_code)]

use std::ffi::{c_char, c_void, CStr};
use std::sync::OnceLock;

use glcollide::ffi::*;
use glutin::api::egl::config::Config;
use glutin::api::egl::context::PossiblyCurrentContext;
use glutin::api::egl::device::Device;
use glutin::api::egl::display::Display;
use glutin::config::{Api, ConfigSurfaceTypes, ConfigTemplateBuilder};
use glutin::context::{ContextApi, ContextAttributesBuilder, GlProfile, Version};
use glutin::prelude::*;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Profile {
    /// GL 4.5 core.
    Core,
    /// The highest compatibility-profile version (4.5 on llvmpipe).
    Compat,
}

pub struct Ctx {
    context: PossiblyCurrentContext,
}

/// The process's EGL display and the config its contexts are made with: initialized once,
/// on first use, and never terminated (contexts live on several test threads at once, and
/// thread-local ones are dropped as their threads end).
static EGL: OnceLock<Result<(Display, Config), String>> = OnceLock::new();

fn egl() -> Result<&'static (Display, Config), &'static str> {
    EGL.get_or_init(|| {
        let mut devices: Vec<Device> = Device::query_devices()
            .map_err(|e| format!("no EGL devices: {e}"))?
            .collect();
        // A GPU's device before Mesa's software one (llvmpipe only when there is no GPU), as
        // Mesa's surfaceless platform picks.
        devices.sort_by_key(|d| d.extensions().contains("EGL_MESA_device_software"));
        let mut tried = Vec::new();
        for device in &devices {
            let display = match unsafe { Display::with_device(device, None) } {
                Ok(d) => d,
                Err(e) => {
                    tried.push(format!("{device:?}: {e}"));
                    continue;
                }
            };
            let template = ConfigTemplateBuilder::new()
                .with_api(Api::OPENGL)
                .with_surface_type(ConfigSurfaceTypes::PBUFFER)
                .build();
            match unsafe { display.find_configs(template) }.map(|mut c| c.next()) {
                Ok(Some(config)) => return Ok((display, config)),
                Ok(None) => tried.push(format!("{device:?}: no OpenGL config")),
                Err(e) => tried.push(format!("{device:?}: eglChooseConfig: {e}")),
            }
        }
        Err(format!("no EGL device with an OpenGL config: {tried:?}"))
    })
    .as_ref()
    .map_err(String::as_str)
}

impl Ctx {
    /// A new context, current on this thread until dropped.
    pub fn new(profile: Profile) -> Ctx {
        Ctx::make(profile, None)
    }

    /// A new context sharing `other`'s objects, current on this thread until dropped.
    pub fn new_shared(profile: Profile, other: &Ctx) -> Ctx {
        Ctx::make(profile, Some(other))
    }

    /// Makes this context current on this thread (surfaceless).
    pub fn make_current(&self) {
        self.context
            .make_current_surfaceless()
            .expect("eglMakeCurrent (surfaceless)");
    }

    /// Leaves no context current on this thread.
    pub fn release_current(&self) {
        self.context
            .make_not_current_in_place()
            .expect("eglMakeCurrent (no context)");
    }

    fn make(profile: Profile, share: Option<&Ctx>) -> Ctx {
        let (display, config) = egl().unwrap_or_else(|e| panic!("headless EGL: {e}"));
        let attributes = match profile {
            Profile::Core => ContextAttributesBuilder::new()
                .with_context_api(ContextApi::OpenGl(Some(Version::new(4, 5))))
                .with_profile(GlProfile::Core),
            // No version: glutin asks for 2.1, and Mesa gives its highest compatibility
            // version.
            Profile::Compat => ContextAttributesBuilder::new()
                .with_context_api(ContextApi::OpenGl(None))
                .with_profile(GlProfile::Compatibility),
        };
        let attributes = match share {
            Some(other) => attributes.with_sharing(&other.context),
            None => attributes,
        }
        .build(None);
        let context = unsafe { display.create_context(config, &attributes) }
            .expect("eglCreateContext")
            .make_current_surfaceless()
            .expect("eglMakeCurrent (surfaceless)");
        Ctx { context }
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
    /// Leaves no context current on this thread (as eglMakeCurrent(NO_CONTEXT) does, whichever
    /// context was current); glutin then destroys the context.
    fn drop(&mut self) {
        let _ = self.context.make_not_current_in_place();
    }
}

/// The loader a host hands to glcollide (eglGetProcAddress through glutin's display; null
/// if there is no EGL).
pub unsafe extern "C" fn get_proc_address(_user: *mut c_void, name: *const c_char) -> *mut c_void {
    match egl() {
        Ok((display, _)) => display.get_proc_address(CStr::from_ptr(name)) as *mut c_void,
        Err(_) => std::ptr::null_mut(),
    }
}

/// A host buffer object (GL_ARRAY_BUFFER data, static) holding `pos` packed, three floats a
/// vertex: what the tests bind meshes to. The current context's; the binding is restored
/// to none.
pub fn host_buffer(g: &glow::Context, pos: &[[f32; 3]]) -> glow::NativeBuffer {
    use glow::HasContext;
    // SAFETY: a test's context is current on this thread; the buffer is made here, and the
    // bytes are `pos`'s own (`[f32; 3]` has no padding).
    unsafe {
        let h = g.create_buffer().unwrap();
        let bytes =
            std::slice::from_raw_parts(pos.as_ptr().cast::<u8>(), std::mem::size_of_val(pos));
        g.bind_buffer(glow::ARRAY_BUFFER, Some(h));
        g.buffer_data_u8_slice(glow::ARRAY_BUFFER, bytes, glow::STATIC_DRAW);
        g.bind_buffer(glow::ARRAY_BUFFER, None);
        h
    }
}

/// The same loader for the Rust API (`Scene::with_backend`, `GlLoader`).
pub fn gl_loader(name: &CStr) -> *const c_void {
    match egl() {
        Ok((display, _)) => display.get_proc_address(name),
        Err(_) => std::ptr::null(),
    }
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
        glcol_scene_desc_init_sized(&mut d, std::mem::size_of::<GlcolSceneDesc>());
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
        glcol_mesh_desc_init_sized(&mut d, std::mem::size_of::<GlcolMeshDesc>());
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
