//! The boundary: every entry point's body runs in [`guard`], which turns errors into a
//! status plus a thread-local message and catches panics.

use std::cell::{Cell, RefCell};
use std::ffi::{c_char, CString};
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::sync::Once;

use super::types::GlcolStatus;
use crate::Error;

thread_local! {
    static LAST_ERROR: RefCell<CString> = RefCell::new(CString::default());
    /// True while this thread runs a guarded body: its panics are reported as a status and
    /// a message, never printed.
    static IN_GUARD: Cell<bool> = const { Cell::new(false) };
    /// Where the last guarded panic happened (file:line), for the message.
    static PANIC_AT: RefCell<String> = const { RefCell::new(String::new()) };
}

static QUIET_HOOK: Once = Once::new();

/// Installs (once) a panic hook that stays silent for panics inside [`guard`] (the library
/// never writes to stderr) and hands every other panic to the hook that was there before.
fn install_quiet_hook() {
    QUIET_HOOK.call_once(|| {
        let previous = std::panic::take_hook();
        std::panic::set_hook(Box::new(move |info| {
            if IN_GUARD.try_with(Cell::get).unwrap_or(false) {
                if let Some(l) = info.location() {
                    let _ = PANIC_AT.try_with(|p| {
                        if let Ok(mut p) = p.try_borrow_mut() {
                            *p = format!("{}:{}", l.file(), l.line());
                        }
                    });
                }
            } else {
                previous(info);
            }
        }));
    });
}

/// Runs `f` with this thread marked as inside the boundary, catching panics.
fn guarded<T>(f: impl FnOnce() -> T) -> std::thread::Result<T> {
    install_quiet_hook();
    let outer = IN_GUARD.try_with(|g| g.replace(true)).unwrap_or(false);
    let r = catch_unwind(AssertUnwindSafe(f));
    let _ = IN_GUARD.try_with(|g| g.set(outer));
    r
}

/// A failure at the boundary: the status to return and the message to keep.
#[derive(Debug)]
pub struct Fail(pub GlcolStatus, pub String);

/// A core error fails with its kind's status (the mapping is generated in `tables.rs`).
impl From<Error> for Fail {
    fn from(e: Error) -> Fail {
        Fail(GlcolStatus::from(e.kind), e.message)
    }
}

/// What a guarded body returns.
pub type FfiResult = Result<(), Fail>;

/// `Err(NULL_POINTER)` naming `what` when `p` is NULL.
pub fn non_null<T>(p: *const T, what: &str) -> FfiResult {
    if p.is_null() {
        Err(Fail(GlcolStatus::NullPointer, format!("{what} is NULL")))
    } else {
        Ok(())
    }
}

/// `INVALID_ARGUMENT` with `msg`.
pub fn invalid(msg: impl Into<String>) -> Fail {
    Fail(GlcolStatus::InvalidArgument, msg.into())
}

/// Runs `f`, catching panics. Failures set the thread's last error message.
pub fn guard(f: impl FnOnce() -> FfiResult) -> GlcolStatus {
    match guarded(f) {
        Ok(Ok(())) => GlcolStatus::Ok,
        Ok(Err(Fail(status, msg))) => {
            set_last_error(&msg);
            status
        }
        Err(payload) => {
            let what = payload
                .downcast_ref::<&str>()
                .map(|s| s.to_string())
                .or_else(|| payload.downcast_ref::<String>().cloned())
                .unwrap_or_else(|| "unknown panic".into());
            let at = PANIC_AT
                .try_with(|p| p.try_borrow().map(|s| s.clone()).unwrap_or_default())
                .unwrap_or_default();
            set_last_error(&format!("internal error (please report): {what} at {at}"));
            GlcolStatus::Internal
        }
    }
}

/// Runs `f` (which cannot fail) with panics caught; returns `default` after a panic.
pub fn guard_or<T>(default: T, f: impl FnOnce() -> T) -> T {
    guarded(f).unwrap_or(default)
}

/// Keeps `msg` as this thread's last error message (a NUL in it becomes a space).
pub fn set_last_error(msg: &str) {
    let c = CString::new(msg.replace('\0', " ")).unwrap_or_default();
    // try_with / try_borrow_mut: this path must never panic (thread teardown, reentrancy).
    let _ = LAST_ERROR.try_with(|cell| {
        if let Ok(mut slot) = cell.try_borrow_mut() {
            *slot = c;
        }
    });
}

/// Pointer to the thread's last error message, valid until the next failing call on it.
pub fn last_error_ptr() -> *const c_char {
    static EMPTY: &[u8] = b"\0";
    LAST_ERROR
        .try_with(|cell| {
            cell.try_borrow()
                .map(|s| s.as_ptr())
                .unwrap_or(EMPTY.as_ptr().cast())
        })
        .unwrap_or(EMPTY.as_ptr().cast())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ffi::desc::try_reserve;
    use crate::ErrorKind;
    use std::ffi::CStr;

    fn last_error() -> String {
        // SAFETY: last_error_ptr is never NULL and points to this thread's NUL-terminated
        // message, unchanged while it is read here.
        unsafe { CStr::from_ptr(last_error_ptr()) }
            .to_str()
            .unwrap()
            .to_owned()
    }

    #[test]
    fn panics_become_internal_with_message() {
        let s = guard(|| panic!("boom {}", 42));
        assert_eq!(s, GlcolStatus::Internal);
        let msg = last_error();
        assert!(
            msg.contains("boom 42") && msg.contains("guard.rs:"),
            "{msg}"
        );
        assert_eq!(guard_or(7, || panic!("x")), 7);
    }

    #[test]
    fn errors_keep_their_status_and_message() {
        let s = guard(|| Err(Error::new(ErrorKind::NonFinite, "vertex 3 is NaN").into()));
        assert_eq!(s, GlcolStatus::NonFinite);
        let msg = last_error();
        assert_eq!(msg, "vertex 3 is NaN");
        assert_eq!(guard(|| Ok(())), GlcolStatus::Ok);
    }

    /// Out-of-memory is recognised by the error's type where the allocation fails (a
    /// failed `try_reserve`), and the boundary answers OUT_OF_MEMORY for its kind; a message
    /// that merely mentions memory does not make an error out-of-memory.
    #[test]
    fn a_failed_allocation_is_out_of_memory_by_kind_not_by_text() {
        let s = guard(|| {
            let mut v: Vec<u64> = Vec::new();
            try_reserve(&mut v, usize::MAX / 4, "the query's contacts")?;
            Ok(())
        });
        assert_eq!(s, GlcolStatus::OutOfMemory);
        assert!(
            last_error().starts_with("the query's contacts: "),
            "{}",
            last_error()
        );
        let s =
            guard(|| Err(Error::new(ErrorKind::GlError, "GL_OUT_OF_MEMORY during a draw").into()));
        assert_eq!(s, GlcolStatus::GlError);
    }
}
