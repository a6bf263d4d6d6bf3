//! glcollide: which polygons of deformable meshes collide, by the method of "Collision
//! Detection Algorithm for Deformable Objects Using OpenGL": a leaf-only AABB structure
//! refitted every frame and a five-step query that asks "which primitives lie in this
//! viewing volume", answered by a backend.
//!
//! Layout: [`geom`] (exact predicates, viewing volumes), [`bvh`] (the leaf boxes),
//! [`mesh`], [`query`] (the five steps), [`backend`] (the question's answerers),
//! [`scene`] (the safe API), and `ffi` (the C ABI, the only `extern "C"` code).

pub mod backend;
pub mod bvh;
pub mod error;
pub mod geom;
pub mod gpu;
pub mod mesh;
pub mod obj;
pub mod query;
pub mod scene;

pub mod ffi;

pub use backend::Backend;
pub use error::{Error, ErrorKind, Result};
pub use mesh::{Mesh, Positions};
pub use query::{Contact, QueryStats};
pub use scene::{MeshId, Scene, SceneConfig};
