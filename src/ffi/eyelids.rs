//! The C API of the living eyes: reading each character's eyelids after a step (blink
//! closure, upper lids following the eyes). The model is `crate::ik::eyelids`; its
//! settings are fields of `cg_crowd_config`.

use super::crowd::cg_crowd;
use super::gaze::read_characters;
use super::{cg_status, ffi_boundary};

/// A character's eyelids after a step, as read by `cg_crowd_read_eyelids`. Not versioned:
/// an array element, like `cg_eye_info`.
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct cg_eyelids {
    /// The character's id.
    pub character: u32,
    /// How closed the left eye's lids are: 0 open, 1 closed (a blink).
    pub left_closure: f32,
    /// How closed the right eye's lids are (both eyes blink together).
    pub right_closure: f32,
    /// The left upper lid's pitch in the head's frame, radians, positive towards the head's
    /// up: `lid_gain` times the eye's pitch. The closure comes on top: blend from this
    /// pitch towards your closed lid by the closure.
    pub left_lid_pitch: f32,
    /// The right upper lid's pitch, radians.
    pub right_lid_pitch: f32,
}

/// Reads the eyelids of characters `first .. first + count` (in the order of
/// `cg_crowd_read_gaze`) after the last step, one `cg_eyelids` each in `out`
/// (`out_len >= count`): the blink's closure and each upper lid's pitch following its
/// eye. Blinks are drawn from the crowd's seed and each character's id: the same in every
/// run and at every thread count.
///
/// Errors: `CG_STATUS_NULL_ARGUMENT`, `CG_STATUS_INVALID_ARGUMENT` (range past the last
/// character, `out_len` too small, `out` misaligned). Safe to call concurrently with other
/// `const` calls.
#[no_mangle]
pub unsafe extern "C" fn cg_crowd_read_eyelids(
    crowd: *const cg_crowd,
    first: u32,
    count: u32,
    out: *mut cg_eyelids,
    out_len: usize,
) -> cg_status {
    ffi_boundary!({
        // SAFETY: the caller's contract, forwarded.
        unsafe {
            read_characters(crowd, first, count, out, out_len, |crowd, position| {
                let lids = crowd.eyelids_at(position);
                cg_eyelids {
                    character: lids.character,
                    left_closure: lids.left_closure,
                    right_closure: lids.right_closure,
                    left_lid_pitch: lids.left_lid_pitch,
                    right_lid_pitch: lids.right_lid_pitch,
                }
            })
        }
    })
}
