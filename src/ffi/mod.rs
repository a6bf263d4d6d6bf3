//! The C ABI: the only `extern "C"` code, a thin layer over the crate's public Rust API (it
//! uses nothing else of the crate). Each function checks its pointers, runs its body in
//! `guard::guard` (errors become a status and a thread-local message, panics become
//! `GLCOL_STATUS_INTERNAL`), and writes its outputs only on success.
//!
//! One file per C object, as rustls-ffi does over rustls: `scene.rs` (`GlcolScene`),
//! `mesh.rs` (a scene's meshes), `query.rs` (queries and their answers), `continuous.rs`
//! (the continuous query of a step and where its contacts happen), `obj.rs`
//! (`GlcolObjMesh`); then `types.rs` (the C structs and enums cbindgen reads), `tables.rs`
//! (the C enums against the core's lists), `desc.rs` (reading the caller's structs and
//! arrays), `guard.rs` (statuses, the last error, panics).
//!
//! Every `unsafe` operation is in an `unsafe` block with a `// SAFETY:` comment saying
//! which part of the function's `# Safety` contract (or which check) makes it sound.

#![deny(unsafe_op_in_unsafe_fn)]
#![deny(clippy::undocumented_unsafe_blocks)]

// The C objects, in the order cbindgen writes them into the header (a reader's order:
// the scene, its meshes, queries, then OBJ files); kept apart so rustfmt keeps the order.
mod scene;

mod mesh;

mod query;

mod continuous;

mod obj;

mod desc;
mod guard;
mod tables;
mod types;

use std::ffi::c_char;

pub use continuous::*;
pub use mesh::*;
pub use obj::*;
pub use query::*;
pub use scene::*;
pub use types::*;

/// ABI version: bumps on any incompatible change of the C API (and with it the soname).
pub const GLCOL_ABI_VERSION: u32 = 1;

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
