//! The suites' hook for running on every backend: a [`Factory`] makes an empty scene for an
//! epsilon and a leaf size, behind the small [`TestScene`] interface, so a suite written
//! once (`for f in factories() { ... }`) runs on each of them.
//!
//! Today: the CPU backend through the safe API (fused query and step by step) and through
//! the C ABI. A GL backend adds a `Factory` here (a C ABI scene made with
//! `GLCOL_BACKEND_GL_*` and a loader for a current headless context); every suite that
//! loops over [`factories`] then covers it.

use glcollide::ffi::*;
use glcollide::internals::BruteSelector;
use glcollide::{Positions, Scene, SceneConfig};

use super::TestMesh;

/// (other mesh, reference polygon, other polygon), sorted like the API's contacts.
pub type Hit = (u32, u32, u32);

/// What the suites need of a scene.
pub trait TestScene {
    /// Adds a mesh; panics on failure (the suites only add valid meshes).
    fn add(&mut self, m: &TestMesh) -> u32;
    /// Moves vertices `first..first + pos.len()`.
    fn update(&mut self, id: u32, first: usize, pos: &[[f32; 3]]);
    fn set_enabled(&mut self, id: u32, on: bool);
    fn destroy(&mut self, id: u32);
    /// Every contact of `reference`, as the API returns them.
    fn query(&mut self, reference: u32) -> Vec<Hit>;
    /// (reference polygon, other polygon) pairs against `other`, sorted.
    fn pairs(&mut self, reference: u32, other: u32) -> Vec<(u32, u32)> {
        self.query(reference)
            .into_iter()
            .filter(|h| h.0 == other)
            .map(|h| (h.1, h.2))
            .collect()
    }
}

/// Makes a scene for (epsilon, max_polygons_per_box).
pub struct Factory {
    pub name: &'static str,
    pub make: fn(f32, u32) -> Box<dyn TestScene>,
    /// Whether epsilon = 0 (exact intersection) is available on this backend.
    pub exact: bool,
}

/// The GL backends, each scene made on this thread's own headless EGL context (Mesa
/// llvmpipe; compatibility profile, so both GL backends run). Their GL tests use at least
/// 2^-20 of the meshes' extent, then confirm with the CPU's test at the epsilon asked for:
/// exact at 0.
pub fn gl_factories() -> Vec<Factory> {
    vec![
        Factory {
            name: "GL_SELECT (C ABI, EGL)",
            make: |e, leaf| gl_scene(GlcolBackend::GlSelect, e, leaf),
            exact: true,
        },
        Factory {
            name: "GL_COMPUTE (C ABI, EGL)",
            make: |e, leaf| gl_scene(GlcolBackend::GlCompute, e, leaf),
            exact: true,
        },
    ]
}

/// Headless GL contexts (tests/gl_support), also for the GL suites that use `common`.
#[path = "../gl_support/mod.rs"]
pub mod gl_support;

thread_local! {
    /// A context per test thread, current from first use until the thread ends (after
    /// the thread's scenes are dropped).
    static GL_CONTEXT: gl_support::Ctx = gl_support::Ctx::new(gl_support::Profile::Compat);
}

fn gl_scene(backend: GlcolBackend, epsilon: f32, leaf: u32) -> Box<dyn TestScene> {
    GL_CONTEXT.with(|_| ());
    Box::new(FfiScene(gl_support::scene(backend, epsilon, leaf)))
}

/// Every backend this build can run here without a GL context.
pub fn factories() -> Vec<Factory> {
    vec![
        Factory {
            name: "cpu (safe API)",
            make: |e, leaf| Box::new(SafeScene::new(e, leaf)),
            exact: true,
        },
        Factory {
            name: "cpu step by step (safe API)",
            make: |e, leaf| Box::new(SafeScene::step_by_step(e, leaf)),
            exact: true,
        },
        Factory {
            name: "cpu (C ABI)",
            make: |e, leaf| Box::new(FfiScene::new(GlcolBackend::Cpu, e, leaf)),
            exact: true,
        },
    ]
}

/// The safe API's scene.
pub struct SafeScene(pub Scene);

impl SafeScene {
    pub fn new(epsilon: f32, leaf: u32) -> SafeScene {
        SafeScene(
            Scene::new(SceneConfig {
                epsilon,
                max_polygons_per_box: leaf,
                ..SceneConfig::default()
            })
            .unwrap(),
        )
    }

    /// The five steps asked one batch at a time of the brute-force test adapter
    /// (`BruteSelector`), not the CPU backend's own whole query.
    pub fn step_by_step(epsilon: f32, leaf: u32) -> SafeScene {
        let sel = BruteSelector;
        let config = SceneConfig {
            epsilon,
            max_polygons_per_box: leaf,
            ..SceneConfig::default()
        };
        SafeScene(Scene::with_selector(config, Box::new(sel)).unwrap())
    }
}

impl TestScene for SafeScene {
    fn add(&mut self, m: &TestMesh) -> u32 {
        self.0
            .create_mesh(Positions::from_points(&m.pos), &m.idx, m.k)
            .unwrap()
    }
    fn update(&mut self, id: u32, first: usize, pos: &[[f32; 3]]) {
        self.0
            .update_positions(id, first, Positions::from_points(pos))
            .unwrap()
    }
    fn set_enabled(&mut self, id: u32, on: bool) {
        self.0.set_enabled(id, on).unwrap()
    }
    fn destroy(&mut self, id: u32) {
        self.0.destroy_mesh(id).unwrap()
    }
    fn query(&mut self, reference: u32) -> Vec<Hit> {
        self.0
            .query(reference)
            .unwrap()
            .iter()
            .map(|c| (c.other_mesh, c.reference_polygon, c.other_polygon))
            .collect()
    }
}

/// A scene made and used through the C ABI. Dropping it destroys the scene.
pub struct FfiScene(pub *mut GlcolScene);

// Used by one thread at a time, as the C API's threading contract asks.
unsafe impl Send for FfiScene {}

/// Panics with the status and the thread's last error message unless `s` is OK.
pub fn ok(s: GlcolStatus, what: &str) {
    assert_eq!(s, GlcolStatus::Ok, "{what}: {}", last_error());
}

/// The calling thread's last error message.
pub fn last_error() -> String {
    unsafe { std::ffi::CStr::from_ptr(glcol_last_error_message()) }
        .to_string_lossy()
        .into_owned()
}

impl FfiScene {
    pub fn new(backend: GlcolBackend, epsilon: f32, leaf: u32) -> FfiScene {
        unsafe {
            let mut d = std::mem::zeroed::<GlcolSceneDesc>();
            glcol_scene_desc_init_sized(&mut d, std::mem::size_of::<GlcolSceneDesc>());
            d.backend = backend as u32;
            d.epsilon = epsilon;
            d.max_polygons_per_box = leaf;
            let mut s = std::ptr::null_mut();
            ok(glcol_scene_create(&d, &mut s), "glcol_scene_create");
            FfiScene(s)
        }
    }

    /// A mesh description over `m`'s arrays (valid while `m` lives).
    pub fn desc(m: &TestMesh) -> GlcolMeshDesc {
        unsafe {
            let mut d = std::mem::zeroed::<GlcolMeshDesc>();
            glcol_mesh_desc_init_sized(&mut d, std::mem::size_of::<GlcolMeshDesc>());
            d.positions = m.pos.as_ptr().cast();
            d.vertex_count = m.pos.len();
            d.indices = m.idx.as_ptr();
            d.polygon_count = m.polygons();
            d.vertices_per_polygon = m.k as u32;
            d
        }
    }

    /// The query through the C ABI, as a status and the copied contacts.
    pub fn try_query(&mut self, reference: u32) -> (GlcolStatus, Vec<Hit>) {
        unsafe {
            let mut p: *const GlcolContact = std::ptr::null();
            let mut n = 0usize;
            let s = glcol_query(self.0, reference, &mut p, &mut n);
            if s != GlcolStatus::Ok || n == 0 {
                return (s, Vec::new());
            }
            let c = std::slice::from_raw_parts(p, n);
            (
                s,
                c.iter()
                    .map(|c| (c.other_mesh, c.reference_polygon, c.other_polygon))
                    .collect(),
            )
        }
    }
}

impl Drop for FfiScene {
    fn drop(&mut self) {
        unsafe { glcol_scene_destroy(self.0) }
    }
}

impl TestScene for FfiScene {
    fn add(&mut self, m: &TestMesh) -> u32 {
        let d = FfiScene::desc(m);
        let mut id = 0;
        ok(
            unsafe { glcol_mesh_create(self.0, &d, &mut id) },
            "glcol_mesh_create",
        );
        id
    }
    fn update(&mut self, id: u32, first: usize, pos: &[[f32; 3]]) {
        ok(
            unsafe {
                glcol_mesh_update_positions(self.0, id, pos.as_ptr().cast(), first, pos.len(), 0)
            },
            "glcol_mesh_update_positions",
        )
    }
    fn set_enabled(&mut self, id: u32, on: bool) {
        ok(
            unsafe { glcol_mesh_set_enabled(self.0, id, on) },
            "glcol_mesh_set_enabled",
        )
    }
    fn destroy(&mut self, id: u32) {
        ok(
            unsafe { glcol_mesh_destroy(self.0, id) },
            "glcol_mesh_destroy",
        )
    }
    fn query(&mut self, reference: u32) -> Vec<Hit> {
        let (s, v) = self.try_query(reference);
        ok(s, "glcol_query");
        v
    }
}
