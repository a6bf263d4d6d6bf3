//! glcollide: which polygons of deformable meshes collide, by the method of "Collision
//! Detection Algorithm for Deformable Objects Using OpenGL": a leaf-only AABB structure
//! refitted every frame and a five-step query that asks "which primitives lie in this
//! viewing volume", answered by a backend (the CPU, the GL's selection mode, or GL compute
//! dispatches).
//!
//! The Rust API is [`Scene`]: meshes by [`MeshId`] made from [`Positions`] (floats, or
//! doubles for an f64 mesh queried exactly for them), moved every frame, given a target
//! (the end of a continuous step, [`Scene::set_target_positions`]), queried against one
//! reference mesh ([`Scene::query`], giving [`Contact`]s) or as a whole scene with
//! self-collision ([`Scene::query_all`], giving [`Pair`]s), then, on demand, the [`ContactGeometry`] of the answer. [`Scene::new`] makes a CPU scene;
//! [`Scene::with_backend`] any backend, inside the caller's GL context. Failures are
//! [`Error`]s with an [`ErrorKind`] and a message; [`obj`] reads meshes.
//!
//! ```
//! use glcollide::{Positions, Scene, SceneConfig};
//!
//! // Two triangles crossing each other, on the CPU, exact (epsilon 0).
//! let mut scene = Scene::new(SceneConfig::default())?;
//! let a = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
//! let b = [[0.2, 0.2, -0.5], [0.2, 0.2, 0.5], [0.8, 0.8, 0.0]];
//! let ta = scene.create_mesh(Positions::from_points(&a), &[0, 1, 2], 3)?;
//! let tb = scene.create_mesh(Positions::from_points(&b), &[0, 1, 2], 3)?;
//! let contacts = scene.query(ta)?;
//! assert_eq!(contacts.len(), 1);
//! assert_eq!((contacts[0].other_mesh, contacts[0].reference_polygon), (tb, 0));
//! # Ok::<(), glcollide::Error>(())
//! ```
//!
//! The C API (`include/glcollide.h`, the [`ffi`] module) is a thin layer over this one: it
//! uses nothing else of the crate.
//!
//! Layout, top-down (a module imports only from those below it):
//! - `ffi`: the C ABI, the only `extern "C"` code, over the public API alone;
//! - `scene`: meshes by id and the last answer; it hands each query to `plan`;
//! - `plan`: which engine answers which part of a query (the CPU engine or a GL backend;
//!   placed meshes, meshes read from host GL buffers), and the worker threads;
//! - `query`: the five steps, sequenced for a backend that answers step by step, and the
//!   whole-scene machinery (broad phase, self-collision);
//! - `backend`: what a backend is (the `Selector` trait) and the three backends;
//! - `gpu` (GL loading and the one state guard), `mesh`, `bvh` (the leaf boxes), `geom`
//!   (boxes, exact predicates, the narrow tests, contact geometry).

#![warn(missing_docs)]
// Doc links from public items into the private modules document the design for readers of
// the source (`cargo doc --document-private-items`); the public docs stand without them.
#![allow(rustdoc::private_intra_doc_links)]
#![deny(unsafe_op_in_unsafe_fn)]
#![warn(clippy::undocumented_unsafe_blocks)]

mod backend;
mod bvh;
mod error;
mod geom;
mod gpu;
mod mesh;
pub mod obj;
mod plan;
mod query;
mod scene;

pub mod ffi;

pub use backend::{Backend, BackendRequest, Contact, Pair, QueryStats};
pub use error::{Error, ErrorKind, Result};
pub use geom::contact::ContactGeometry;
pub use gpu::Lookup as GlLoader;
pub use mesh::{Mesh, Positions};
pub use obj::ObjMesh;
pub use query::all::AllStats;
pub use query::continuous::{ContinuousStats, Impact};
pub use query::impact::{ImpactFeature, ImpactGeometry};
pub use scene::{MeshId, Scene, SceneConfig};

// The one list of each concept, for the C layer's tables (see `ffi::tables`).
pub(crate) use backend::with_backends;
pub(crate) use error::with_error_kinds;

/// Internals for the crate's own tests, benchmarks and fuzz targets: not an API, no
/// stability promise. Only with the `internals` feature, which the crate's dev-dependency on
/// itself turns on: the shipped library does not have it.
#[cfg(feature = "internals")]
#[doc(hidden)]
pub mod internals {
    pub use crate::backend::brute::BruteSelector;
    pub use crate::backend::{
        create, CpuSelector, Engine, GlComputeSelector, GlSelectSelector, Selector,
    };
    pub use crate::geom::{adjacent, contact, predicates, tritri, Aabb};
    pub use crate::gpu::{buffer, compat, Gl, MIN_RELATIVE_EPSILON};
}
