//! Handles: a Rust object handed to C as an opaque pointer. Made from a `Box` on create,
//! borrowed back (checked, and refused once poisoned) on every call, and turned back into
//! the `Box` on destroy. The one place handle pointers are cast.

use super::error::Result;
use super::pointers::check_pointer;
use super::poison::Poison;

/// A Rust type that C holds as `*mut Self::Opaque`, which is a `Box<Self>` cast.
///
/// # Safety
/// `Opaque` must be a type of its own (a zero-sized `cg_*` struct) that no other `Handle`
/// uses, so that an opaque pointer can only have come from a `Box<Self>`.
pub(crate) unsafe trait Handle: Sized {
    /// The C type, opaque to C: `cg_crowd`, `cg_view_blender`.
    type Opaque;
    /// The argument's name in error messages.
    const NAME: &'static str;
    /// The poison an internal failure of a call changing this handle sets.
    fn poison(&self) -> &Poison;
}

/// Hands `value` to C: the caller owns the pointer until it passes it to [`destroy`].
pub(crate) fn into_c<H: Handle>(value: Box<H>) -> *mut H::Opaque {
    Box::into_raw(value).cast::<H::Opaque>()
}

/// Borrows a handle from C read-only: fails on NULL, a misaligned pointer, or a poisoned
/// handle.
///
/// # Safety
/// `pointer`, if not NULL, must have come from [`into_c`] and not been destroyed, and no
/// `&mut` to it may exist for `'a`.
pub(crate) unsafe fn handle_ref<'a, H: Handle>(pointer: *const H::Opaque) -> Result<&'a H> {
    let pointer = pointer.cast::<H>();
    check_pointer(pointer, H::NAME)?;
    // SAFETY: a live handle is a Box<H> (contract); shared access only.
    let handle = unsafe { &*pointer };
    handle.poison().check()?;
    Ok(handle)
}

/// Borrows a handle from C mutably, and arms its poison for the running call (which is
/// about to change it): fails on NULL, a misaligned pointer, or a poisoned handle.
///
/// # Safety
/// `pointer`, if not NULL, must have come from [`into_c`] and not been destroyed, and
/// nothing else may access it for `'a`.
pub(crate) unsafe fn handle_mut<'a, H: Handle>(pointer: *mut H::Opaque) -> Result<&'a mut H> {
    let pointer = pointer.cast::<H>();
    check_pointer(pointer, H::NAME)?;
    // SAFETY: a live handle is a Box<H> (contract), and access is exclusive for 'a.
    let handle = unsafe { &mut *pointer };
    handle.poison().check()?;
    super::poison::arm(handle.poison());
    Ok(handle)
}

/// Frees a handle C is done with, also a poisoned one. NULL is ignored.
///
/// # Safety
/// `pointer`, if not NULL, must have come from [`into_c`] and not been destroyed, and no
/// call may be using it.
pub(crate) unsafe fn destroy<H: Handle>(pointer: *mut H::Opaque) {
    if pointer.is_null() {
        return;
    }
    let _ = super::boundary::run_boundary(|| -> Result<()> {
        // SAFETY: a live handle is a Box<H>, destroyed once (contract).
        drop(unsafe { Box::from_raw(pointer.cast::<H>()) });
        Ok(())
    });
}
