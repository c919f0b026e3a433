//! Test hooks (cargo feature `test-hooks`, which only this crate's own tests enable): make
//! the next step or change of a handle panic inside the library, to test the panic boundary
//! and poisoned handles. Rust only: nothing here is in the C ABI or the header.
//!
//! cbindgen:ignore

use super::crowd::{cg_crowd, crowd_handle, Hook};
use super::rig::{cg_rig, rig_handle};
use super::view_blender::{blender_handle, cg_view_blender};
use super::{cg_status, ffi_boundary};

/// The crowd calls that [`panic_next`] can make panic. Each panics after it has changed the
/// crowd: `BeginStep` once the step is begun (the handle still in transition), `StepRange`
/// once its range is stepped (the range still counted as running), `EndStep` once the step
/// is ended (the handle still in transition), `Step` once the whole step is done.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PanicAt {
    /// `cg_crowd_begin_step`.
    BeginStep,
    /// `cg_crowd_step_range`.
    StepRange,
    /// `cg_crowd_end_step`.
    EndStep,
    /// `cg_crowd_step`.
    Step,
}

/// Makes the next call of kind `at` on `crowd` panic inside the library, once it has changed
/// the crowd. Fails (like a C call: a status, and `cg_last_error_message`) if `crowd` is NULL
/// or poisoned.
///
/// # Safety
/// `crowd`, if not NULL, must be a live handle from `cg_crowd_create`.
pub unsafe fn panic_next(crowd: *mut cg_crowd, at: PanicAt) -> cg_status {
    ffi_boundary!({
        // SAFETY: forwarded contract.
        let handle = unsafe { crowd_handle(crowd) }?;
        handle.panic_next(match at {
            PanicAt::BeginStep => Hook::BeginStep,
            PanicAt::StepRange => Hook::StepRange,
            PanicAt::EndStep => Hook::EndStep,
            PanicAt::Step => Hook::Step,
        });
        Ok(())
    })
}

/// Makes the next set/add call on `blender` (`cg_view_blender_set_key_clip`,
/// `cg_view_blender_set_key_pose`, `cg_view_blender_add_camera`) panic inside the library,
/// once it has changed the blender. Fails (a status) if `blender` is NULL or poisoned.
///
/// # Safety
/// `blender`, if not NULL, must be a live handle from `cg_view_blender_create`.
pub unsafe fn panic_next_change(blender: *mut cg_view_blender) -> cg_status {
    ffi_boundary!({
        // SAFETY: forwarded contract.
        unsafe { blender_handle(blender) }?.panic_next();
        Ok(())
    })
}

/// Makes the next call on `rig` (any `cg_rig_*` function taking it but `cg_rig_destroy`)
/// panic inside the library, after the rig is borrowed and before anything is written.
/// Fails (a status) if `rig` is NULL.
///
/// # Safety
/// `rig`, if not NULL, must be a live handle from `cg_rig_create`.
pub unsafe fn panic_next_rig_call(rig: *const cg_rig) -> cg_status {
    ffi_boundary!({
        // SAFETY: forwarded contract.
        unsafe { rig_handle(rig) }?.panic_next();
        Ok(())
    })
}
