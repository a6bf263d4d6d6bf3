//! glcollide: which polygons of deformable meshes collide, by the method of "Collision
//! Detection Algorithm for Deformable Objects Using OpenGL": a leaf-only AABB structure
//! refitted every frame and a five-step query that asks "which primitives lie in this
//! viewing volume", answered by a backend.
//!
//! The safe Rust API is [`Scene`] (meshes by [`MeshId`], a backend, queries returning
//! [`Contact`]s) with [`Positions`] for vertex data, [`Error`] for failures and [`obj`] to
//! read meshes. The C API (`include/glcollide.h`) is the `ffi` module's.
//!
//! Layout, top-down (a module imports only from those below it):
//! - `ffi`: the C ABI, the only `extern "C"` code;
//! - `scene`: meshes by id, a backend, the last answer;
//! - `query`: the five steps, sequenced for a backend that answers step by step;
//! - `backend`: what a backend is (the `Selector` trait) and the three backends;
//! - `gpu` (GL loading and the one state guard), `mesh`, `bvh` (the leaf boxes), `geom`
//!   (boxes, exact predicates, the narrow tests).

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
mod query;
mod scene;

pub mod ffi;

pub use backend::{Backend, Contact, Pair, QueryStats};
pub use error::{Error, ErrorKind, Result};
pub use mesh::{Mesh, Positions};
pub use query::all::AllStats;
pub use scene::{MeshId, Scene, SceneConfig};

/// Internals for the crate's own tests, benchmarks and fuzz targets: not a stable API.
#[doc(hidden)]
pub mod internals {
    pub use crate::backend::brute::BruteSelector;
    pub use crate::backend::{
        create, CpuSelector, Engine, GlComputeSelector, GlSelectSelector, Request, Selector,
    };
    pub use crate::geom::{adjacent, contact, predicates, tritri, Aabb};
    pub use crate::gpu::{buffer, compat, Gl, MIN_RELATIVE_EPSILON};
}
