//! The C enums against the core's lists, derived, never kept by hand.
//!
//! `GlcolStatus` and `GlcolBackend` are written out literally in `types.rs` because
//! cbindgen reads them there (it does not expand macros); their values are the ABI. What
//! else the boundary needs of them is generated here from the core's one list of each
//! concept:
//! - statuses: the boundary's own statuses (OK, NULL_POINTER, listed in `status_table!`) and one
//!   per [`ErrorKind`] of the same name, from `crate::with_error_kinds!`;
//! - backends: AUTO and one per [`Backend`] (the same names as [`Request`]'s), from
//!   `crate::with_backends!`.
//!
//! The generated matches are exhaustive both ways, so a variant added to a C enum or to a
//! core list without its counterpart is a compile error. Names are cbindgen's
//! (`prefix_with_name`, `ScreamingSnakeCase`) computed at compile time from the Rust names;
//! tests/header.rs checks them and the values against the generated header.

use std::ffi::CStr;

use super::types::{GlcolBackend, GlcolStatus};
use crate::{with_backends, with_error_kinds, Backend, BackendRequest as Request, ErrorKind};

/// Length of `ident` in SCREAMING_SNAKE_CASE (an `_` before each inner capital).
const fn screaming_len(ident: &str) -> usize {
    let b = ident.as_bytes();
    let mut n = b.len();
    let mut i = 1;
    while i < b.len() {
        if b[i].is_ascii_uppercase() {
            n += 1;
        }
        i += 1;
    }
    n
}

/// Bytes of the NUL-terminated name cbindgen gives variant `variant` of enum `enum_name`.
const fn c_name_len(enum_name: &str, variant: &str) -> usize {
    screaming_len(enum_name) + 1 + screaming_len(variant) + 1
}

/// The name cbindgen gives variant `variant` of enum `enum_name` (`prefix_with_name`,
/// `ScreamingSnakeCase`), NUL-terminated: `GlcolStatus::NonFinite` is
/// `GLCOL_STATUS_NON_FINITE`. `N` is [`c_name_len`].
const fn c_name_bytes<const N: usize>(enum_name: &str, variant: &str) -> [u8; N] {
    let mut out = [0u8; N];
    let mut at = 0;
    let mut part = 0;
    while part < 2 {
        let b = if part == 0 { enum_name } else { variant }.as_bytes();
        if part == 1 {
            out[at] = b'_';
            at += 1;
        }
        let mut i = 0;
        while i < b.len() {
            if i > 0 && b[i].is_ascii_uppercase() {
                out[at] = b'_';
                at += 1;
            }
            out[at] = b[i].to_ascii_uppercase();
            at += 1;
            i += 1;
        }
        part += 1;
    }
    assert!(at + 1 == N, "c_name_bytes: N is not c_name_len");
    out
}

/// `c_name!(Enum, Variant)`: the variant's C name as a `&'static CStr`, made at compile
/// time.
macro_rules! c_name {
    ($enum_name:ident, $variant:ident) => {{
        const BYTES: [u8; c_name_len(stringify!($enum_name), stringify!($variant))] =
            c_name_bytes(stringify!($enum_name), stringify!($variant));
        const NAME: &CStr = match CStr::from_bytes_with_nul(&BYTES) {
            Ok(name) => name,
            Err(_) => panic!("an identifier has no NUL"),
        };
        NAME
    }};
}

/// Generates the status items from the error kinds and the boundary's own statuses.
macro_rules! status_table {
    // From `with_error_kinds!`. The boundary's own statuses (no error kind) are listed here.
    ($($(#[$doc:meta])* $kind:ident,)*) => {
        status_table! { @own [Ok, NullPointer] @kinds [$($kind),*] }
    };
    (@own [$($own:ident),*] @kinds [$($kind:ident),*]) => {
        impl GlcolStatus {
            /// Every status (the boundary's own, then one per error kind).
            pub(crate) const ALL: &'static [GlcolStatus] =
                &[$(GlcolStatus::$own,)* $(GlcolStatus::$kind,)*];

            /// The largest value (the values run from 0 without a gap: a unit test checks).
            #[cfg(test)]
            pub(crate) fn max_value() -> u32 {
                Self::ALL.iter().map(|&s| s as u32).max().unwrap_or(0)
            }

            /// The status whose value is `v`, if there is one.
            pub(crate) fn from_raw(v: u32) -> Option<GlcolStatus> {
                Self::ALL.iter().copied().find(|s| *s as u32 == v)
            }

            /// The error kind this status reports (`None` for the boundary's own).
            #[cfg(test)]
            pub(crate) fn kind(self) -> Option<ErrorKind> {
                match self {
                    $(GlcolStatus::$own => None,)*
                    $(GlcolStatus::$kind => Some(ErrorKind::$kind),)*
                }
            }

            /// The header's name of the status, e.g. `GLCOL_STATUS_NON_FINITE`.
            pub(crate) fn name(self) -> &'static CStr {
                match self {
                    $(GlcolStatus::$own => c_name!(GlcolStatus, $own),)*
                    $(GlcolStatus::$kind => c_name!(GlcolStatus, $kind),)*
                }
            }
        }

        /// The boundary's own statuses, for the tests.
        #[cfg(test)]
        const OWN_STATUSES: &[GlcolStatus] = &[$(GlcolStatus::$own,)*];

        impl From<ErrorKind> for GlcolStatus {
            fn from(kind: ErrorKind) -> GlcolStatus {
                match kind {
                    $(ErrorKind::$kind => GlcolStatus::$kind,)*
                }
            }
        }
    };
}
with_error_kinds!(status_table);

/// Generates the backend items from the core's backends.
macro_rules! backend_table {
    ($($(#[$doc:meta])* $backend:ident,)*) => {
        impl GlcolBackend {
            /// Every backend value (AUTO, then one per [`Backend`]).
            pub(crate) const ALL: &'static [GlcolBackend] =
                &[GlcolBackend::Auto, $(GlcolBackend::$backend,)*];

            /// The largest value (the values run from 0 without a gap: a unit test checks).
            pub(crate) fn max_value() -> u32 {
                Self::ALL.iter().map(|&b| b as u32).max().unwrap_or(0)
            }

            /// The backend whose value is `v`, if there is one.
            pub(crate) fn from_raw(v: u32) -> Option<GlcolBackend> {
                Self::ALL.iter().copied().find(|b| *b as u32 == v)
            }

            /// What a `GlcolBackend` value from C asks for, if it is one.
            pub(crate) fn request(v: u32) -> Option<Request> {
                let b = Self::from_raw(v)?;
                Some(match b {
                    GlcolBackend::Auto => Request::Auto,
                    $(GlcolBackend::$backend => Request::$backend,)*
                })
            }

            /// The header's name of the backend, e.g. `GLCOL_BACKEND_GL_SELECT`.
            pub(crate) fn name(self) -> &'static CStr {
                match self {
                    GlcolBackend::Auto => c_name!(GlcolBackend, Auto),
                    $(GlcolBackend::$backend => c_name!(GlcolBackend, $backend),)*
                }
            }
        }

        impl From<Backend> for GlcolBackend {
            fn from(b: Backend) -> GlcolBackend {
                match b {
                    $(Backend::$backend => GlcolBackend::$backend,)*
                }
            }
        }

        /// Every core backend, for the tests.
        #[cfg(test)]
        const CORE_BACKENDS: &[(Backend, Request)] = &[$((Backend::$backend, Request::$backend),)*];
    };
}
with_backends!(backend_table);

#[cfg(test)]
mod tests {
    use super::*;

    /// The values are 0, 1, 2, ... without a gap, each once (in any order: the order of
    /// the core's lists means nothing).
    fn assert_dense(values: impl Iterator<Item = u32>) {
        let mut values: Vec<u32> = values.collect();
        values.sort_unstable();
        let want: Vec<u32> = (0..values.len() as u32).collect();
        assert_eq!(values, want);
    }

    #[test]
    fn status_values_are_dense_and_named_as_the_header() {
        assert_dense(GlcolStatus::ALL.iter().map(|&s| s as u32));
        assert_eq!(GlcolStatus::max_value(), 10);
        let names: Vec<&str> = (0..=GlcolStatus::max_value())
            .map(|v| GlcolStatus::from_raw(v).unwrap().name().to_str().unwrap())
            .collect();
        assert_eq!(
            names,
            [
                "GLCOL_STATUS_OK",
                "GLCOL_STATUS_NULL_POINTER",
                "GLCOL_STATUS_INVALID_ARGUMENT",
                "GLCOL_STATUS_NON_FINITE",
                "GLCOL_STATUS_INDEX_OUT_OF_RANGE",
                "GLCOL_STATUS_UNKNOWN_MESH",
                "GLCOL_STATUS_GL_UNAVAILABLE",
                "GLCOL_STATUS_GL_ERROR",
                "GLCOL_STATUS_UNSUPPORTED",
                "GLCOL_STATUS_OUT_OF_MEMORY",
                "GLCOL_STATUS_INTERNAL",
            ]
        );
        for v in [11, 12, 1000, u32::MAX] {
            assert_eq!(GlcolStatus::from_raw(v), None);
        }
    }

    #[test]
    fn every_error_kind_has_its_status_and_back() {
        for &k in ErrorKind::ALL {
            let s = GlcolStatus::from(k);
            assert_eq!(s.kind(), Some(k), "{k:?} -> {s:?}");
            assert_eq!(format!("{k:?}"), format!("{s:?}"));
        }
        for &s in GlcolStatus::ALL {
            match s.kind() {
                Some(k) => assert_eq!(GlcolStatus::from(k), s),
                None => assert!(OWN_STATUSES.contains(&s), "{s:?}"),
            }
        }
        assert_eq!(
            GlcolStatus::ALL.len(),
            OWN_STATUSES.len() + ErrorKind::ALL.len()
        );
    }

    #[test]
    fn backend_values_are_dense_and_map_to_the_core() {
        assert_dense(GlcolBackend::ALL.iter().map(|&b| b as u32));
        assert_eq!(GlcolBackend::max_value(), 3);
        let mut by_value = GlcolBackend::ALL.to_vec();
        by_value.sort_by_key(|&b| b as u32);
        let names: Vec<&str> = by_value
            .iter()
            .map(|b| b.name().to_str().unwrap())
            .collect();
        assert_eq!(
            names,
            [
                "GLCOL_BACKEND_AUTO",
                "GLCOL_BACKEND_CPU",
                "GLCOL_BACKEND_GL_SELECT",
                "GLCOL_BACKEND_GL_COMPUTE",
            ]
        );
        assert_eq!(GlcolBackend::request(0), Some(Request::Auto));
        for &(b, r) in CORE_BACKENDS {
            let c = GlcolBackend::from(b);
            assert_eq!(GlcolBackend::request(c as u32), Some(r), "{b:?}");
            assert_eq!(format!("{b:?}"), format!("{c:?}"));
        }
        assert_eq!(CORE_BACKENDS.len() + 1, GlcolBackend::ALL.len());
        for v in [4, 7, 1000, u32::MAX] {
            assert_eq!(GlcolBackend::request(v), None);
        }
    }
}
