//! Poisoned handles. A call that changes a handle and fails inside the library (a caught
//! panic, or any other `CG_STATUS_INTERNAL`) may have left the object half-updated, which
//! breaks "a failed call changes nothing". Its handle is then poisoned: every later call on
//! it fails with `CG_STATUS_POISONED` and the first failure's message, and its `_destroy`
//! still frees it.
//!
//! A C call about to change a handle arms the handle's [`Poison`] for the rest of the call
//! (a thread-local slot, so concurrent ranged steps each arm their own); the panic boundary
//! ([`run_boundary`](super::run_boundary)) poisons what the call armed if it failed inside
//! the library, and disarms after every call.

use super::error::{FfiError, Result};
use std::cell::Cell;
use std::sync::OnceLock;

/// A handle's poison: the message of the failure that poisoned it, once one did.
#[derive(Debug, Default)]
pub(crate) struct Poison(OnceLock<String>);

impl Poison {
    /// Fails with [`FfiError::Poisoned`] if the handle is poisoned.
    pub(crate) fn check(&self) -> Result<()> {
        match self.0.get() {
            None => Ok(()),
            Some(message) => Err(FfiError::Poisoned(message.clone())),
        }
    }
}

thread_local! {
    /// The poison of the handle that the C call running on this thread changes, or NULL.
    static ARMED: Cell<*const Poison> = const { Cell::new(std::ptr::null()) };
}

/// Arms `poison` for the C call running on this thread: if the call fails inside the
/// library, the handle owning `poison` is poisoned.
pub(crate) fn arm(poison: &Poison) {
    let _ = ARMED.try_with(|armed| armed.set(poison));
}

/// Starts a C call: disarms, and returns what was armed (restored by [`leave`]).
pub(crate) fn enter() -> *const Poison {
    ARMED
        .try_with(|armed| armed.replace(std::ptr::null()))
        .unwrap_or(std::ptr::null())
}

/// Ends a C call that returned `result`: poisons the handle the call armed if it failed
/// inside the library ([`Error::Internal`](crate::error::Error::Internal)), and re-arms `outer`.
pub(crate) fn leave<T>(outer: *const Poison, result: &Result<T>) {
    let armed = ARMED
        .try_with(|armed| armed.replace(outer))
        .unwrap_or(std::ptr::null());
    let failed_inside = result.as_ref().err().filter(|error| error.is_internal());
    if let (Some(error), false) = (failed_inside, armed.is_null()) {
        // SAFETY: `arm` stored a pointer to the poison of a handle this call was using; the
        // C contract keeps a handle alive (no `_destroy`) while a call on it runs, and the
        // call has not returned yet.
        let poison = unsafe { &*armed };
        let _ = poison.0.set(error.to_string());
    }
}
