//! The panic boundary every C entry point runs inside: a panic never crosses into C, the
//! error becomes the thread's last message and a `cg_status`, and an internal failure
//! poisons the handle the call was changing.

use super::error::{FfiError, Result};
use super::poison;
use crate::error::Error;

/// Runs a C entry point's body, which evaluates to `Result<()>` (the boundary's
/// [`Result`](super::error::Result)), inside the panic boundary ([`run_boundary`]) and
/// turns its outcome into a `cg_status`.
///
/// `ffi_boundary!(value_on_error; body)` is the form for functions that return a value
/// instead of a status: the body evaluates to `Result<T>` and `value_on_error` is returned
/// (after recording the message) on an error or a panic.
macro_rules! ffi_boundary {
    ($body:block) => {{
        match $crate::ffi::boundary::run_boundary(|| -> $crate::ffi::error::Result<()> { $body }) {
            Ok(()) => $crate::ffi::status::cg_status::Ok,
            Err(error) => $crate::ffi::last_error::record(&error),
        }
    }};
    ($on_error:expr; $body:block) => {{
        match $crate::ffi::boundary::run_boundary(|| $body) {
            Ok(value) => value,
            Err(error) => {
                $crate::ffi::last_error::record(&error);
                $on_error
            }
        }
    }};
}
pub(crate) use ffi_boundary;

/// Runs a C entry point's body: a panic is caught and becomes [`Error::Internal`], and if
/// the body armed a handle's poison ([`poison::arm`]) and failed inside the library, that
/// handle is poisoned.
pub(crate) fn run_boundary<T>(body: impl FnOnce() -> Result<T>) -> Result<T> {
    let outer = poison::enter();
    let result = match std::panic::catch_unwind(std::panic::AssertUnwindSafe(body)) {
        Ok(result) => result,
        Err(payload) => Err(panic_error(payload)),
    };
    poison::leave(outer, &result);
    result
}

/// Turns a caught panic's payload into an [`Error::Internal`] carrying its message.
fn panic_error(payload: Box<dyn std::any::Any + Send>) -> FfiError {
    let message = if let Some(text) = payload.downcast_ref::<&str>() {
        (*text).to_owned()
    } else if let Some(text) = payload.downcast_ref::<String>() {
        text.clone()
    } else {
        "panic with a non-text payload".to_owned()
    };
    Error::Internal(format!("caught panic: {message}")).into()
}

#[cfg(test)]
mod tests {
    use super::super::{cg_status, last_error, poison};
    use super::*;

    fn failing(kind: u8) -> cg_status {
        ffi_boundary!({
            match kind {
                0 => Ok(()),
                1 => Err(Error::NotFound("entity 7".into()).into()),
                _ => panic!("boom {kind}"),
            }
        })
    }

    #[test]
    fn boundary_maps_errors_and_catches_panics() {
        assert_eq!(failing(0), cg_status::Ok);
        assert_eq!(failing(1), cg_status::NotFound);
        assert_eq!(last_error::last_error_message(), "not found: entity 7");
        let hook = std::panic::take_hook();
        std::panic::set_hook(Box::new(|_| {}));
        let status = failing(2);
        std::panic::set_hook(hook);
        assert_eq!(status, cg_status::Internal);
        assert_eq!(
            last_error::last_error_message(),
            "internal error: caught panic: boom 2"
        );
    }

    /// A call that arms `poison` and then fails with `kind` (0 ok, 1 not found, 2 panic,
    /// 3 internal error).
    fn changing(poison: &poison::Poison, kind: u8) -> cg_status {
        ffi_boundary!({
            poison.check()?;
            poison::arm(poison);
            match kind {
                0 => Ok(()),
                1 => Err(Error::NotFound("entity 7".into()).into()),
                2 => panic!("boom {kind}"),
                _ => Err(Error::Internal("half done".into()).into()),
            }
        })
    }

    #[test]
    fn an_internal_failure_poisons_the_armed_handle() {
        let hook = std::panic::take_hook();
        std::panic::set_hook(Box::new(|_| {}));
        for (kind, first) in [
            (2, "internal error: caught panic: boom 2"),
            (3, "internal error: half done"),
        ] {
            let poison = poison::Poison::default();
            assert_eq!(changing(&poison, 0), cg_status::Ok);
            assert_eq!(changing(&poison, 1), cg_status::NotFound, "not internal");
            assert_eq!(changing(&poison, kind), cg_status::Internal);
            assert_eq!(last_error::last_error_message(), first);
            for _ in 0..2 {
                assert_eq!(changing(&poison, 0), cg_status::Poisoned);
                assert_eq!(
                    last_error::last_error_message(),
                    format!("poisoned: an earlier call failed inside the library: {first}")
                );
            }
            // A call that armed nothing poisons nothing.
            assert_eq!(failing(2), cg_status::Internal);
        }
        std::panic::set_hook(hook);
    }
}
