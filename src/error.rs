//! The core's error: a kind and a message naming the argument at fault.
//!
//! The kinds are one list, [`with_error_kinds!`]: it declares [`ErrorKind`] here, and any
//! other module that needs one item per kind (the C API's status mapping) derives it from
//! the same list, so no second list can drift from this one.

use std::collections::TryReserveError;
use std::fmt;

/// The one list of error kinds. `with_error_kinds!(m)` expands to
/// `m! { /// doc \n Kind, ... }`: every kind in declaration order with its doc comment.
/// The order means nothing; the C API's status values come from its own enum.
macro_rules! with_error_kinds {
    ($m:ident) => {
        $m! {
            /// An argument is wrong: a size, stride, count, epsilon, struct_size, enum value,
            /// a range past the end, an unreadable file.
            InvalidArgument,
            /// A vertex coordinate is NaN or infinite.
            NonFinite,
            /// A polygon names a vertex that does not exist.
            IndexOutOfRange,
            /// A mesh id not in the scene (destroyed, or never made).
            UnknownMesh,
            /// A GL backend was asked for, but there is no loader, no current context, a
            /// missing entry point or too low a version.
            GlUnavailable,
            /// The GL reported an error during the library's work.
            GlError,
            /// A valid request this build, backend or context cannot do.
            Unsupported,
            /// An allocation failed (told where it is made, by type or code: a failed
            /// `try_reserve`, or GL_OUT_OF_MEMORY after a GL allocation).
            OutOfMemory,
            /// A bug: a caught panic or a broken internal rule.
            Internal,
        }
    };
}
pub(crate) use with_error_kinds;

macro_rules! declare_error_kind {
    ($($(#[$doc:meta])* $kind:ident,)*) => {
        /// What went wrong.
        #[derive(Clone, Copy, Debug, PartialEq, Eq)]
        pub enum ErrorKind {
            $($(#[$doc])* $kind,)*
        }

        impl ErrorKind {
            /// Every kind, in declaration order.
            #[cfg(test)]
            pub(crate) const ALL: &'static [ErrorKind] = &[$(ErrorKind::$kind),*];
        }
    };
}
with_error_kinds!(declare_error_kind);

/// An error: what kind, and a human-readable message naming the argument at fault. A call
/// that fails changes nothing.
///
/// ```
/// use glcollide::{ErrorKind, Positions, Scene, SceneConfig};
///
/// let mut scene = Scene::new(SceneConfig::default())?;
/// let p = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
/// let id = scene.create_mesh(Positions::from_points(&p), &[0, 1, 2], 3)?;
/// // A NaN is refused whole: the mesh keeps its positions.
/// let bad = [[f32::NAN, 0.0, 0.0]];
/// let e = scene.update_positions(id, 0, Positions::from_points(&bad)).unwrap_err();
/// assert_eq!(e.kind, ErrorKind::NonFinite);
/// assert_eq!(scene.mesh(id)?.vertex_position(0), Some([0.0, 0.0, 0.0]));
/// // A polygon naming a vertex that does not exist.
/// let e = scene.create_mesh(Positions::from_points(&p), &[0, 1, 3], 3).unwrap_err();
/// assert_eq!(e.kind, ErrorKind::IndexOutOfRange);
/// # Ok::<(), glcollide::Error>(())
/// ```
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Error {
    /// What kind of failure it is.
    pub kind: ErrorKind,
    /// What was wrong, naming the argument or the value at fault.
    pub message: String,
}

impl Error {
    /// An error of `kind` with `message`.
    pub fn new(kind: ErrorKind, message: impl Into<String>) -> Error {
        Error {
            kind,
            message: message.into(),
        }
    }

    /// An [`ErrorKind::InvalidArgument`] error with `message`.
    pub fn invalid(message: impl Into<String>) -> Error {
        Error::new(ErrorKind::InvalidArgument, message)
    }

    /// An [`ErrorKind::OutOfMemory`] error for a failed reservation of room for `what`.
    pub fn out_of_memory(what: &str, cause: TryReserveError) -> Error {
        Error::new(ErrorKind::OutOfMemory, format!("{what}: {cause}"))
    }
}

/// Reserves room for `additional` more items in `v`; a failed allocation (or a capacity
/// past what a `Vec` can hold) is an [`ErrorKind::OutOfMemory`] error naming `what`, where
/// `Vec`'s own growth would abort the process.
pub(crate) fn try_reserve<T>(v: &mut Vec<T>, additional: usize, what: &str) -> Result<()> {
    v.try_reserve(additional)
        .map_err(|e| Error::out_of_memory(what, e))
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{:?}: {}", self.kind, self.message)
    }
}

impl std::error::Error for Error {}

/// A result whose error is [`Error`].
pub type Result<T> = std::result::Result<T, Error>;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_failed_reservation_is_out_of_memory_by_type() {
        let mut v: Vec<u64> = Vec::new();
        let e = try_reserve(&mut v, usize::MAX, "the contacts").unwrap_err();
        assert_eq!(e.kind, ErrorKind::OutOfMemory);
        assert!(e.message.starts_with("the contacts: "), "{}", e.message);
        assert!(v.capacity() == 0);
        // A size the allocator refuses (not only a capacity overflow).
        let mut bytes: Vec<u8> = Vec::new();
        let e = try_reserve(&mut bytes, isize::MAX as usize, "the positions").unwrap_err();
        assert_eq!(e.kind, ErrorKind::OutOfMemory);
        assert!(e.message.starts_with("the positions: "), "{}", e.message);
        try_reserve(&mut v, 16, "the contacts").unwrap();
        assert!(v.capacity() >= 16);
    }
}
