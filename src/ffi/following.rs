//! The C API of gaze following: which characters glance where others stare, and at what.
//! The model is `crate::attention::following`; its settings are the `follow_*` fields of
//! `cg_crowd_config`.

use super::crowd::{cg_crowd, crowd_ref};
use super::types::cg_vec3;
use super::{cg_status, ffi_boundary, Out};

/// Reads whether `character` glances now at a point because others look there (gaze
/// following, the `follow_*` fields of `cg_crowd_config`): `*out_following` is 1 while it
/// does, with the point in `*out_point` (world, your units and axes), and 0 otherwise, with
/// `*out_point` the origin. `*out_glances` is how many such glances it has started since it
/// was added. A character with a `CG_GAZE_PRIORITY_OVERRIDE` target follows no one (its
/// target wins), and with `follow_enabled` 0 no one ever follows. The caller owns the
/// outputs, written only on success.
///
/// Errors (nothing written): `CG_STATUS_NULL_ARGUMENT` (a NULL pointer),
/// `CG_STATUS_NOT_FOUND` (no such entity), `CG_STATUS_INVALID_ARGUMENT` (an object's or the
/// viewer's id, a misaligned output). Safe to call concurrently with other `const` calls.
#[no_mangle]
pub unsafe extern "C" fn cg_crowd_read_following(
    crowd: *const cg_crowd,
    character: u32,
    out_point: *mut cg_vec3,
    out_following: *mut u32,
    out_glances: *mut u32,
) -> cg_status {
    ffi_boundary!({
        // SAFETY: handle contract of cg_crowd.
        let crowd = unsafe { crowd_ref(crowd) }?;
        // SAFETY: the caller provides writable outputs (or NULL, rejected).
        let out_point = unsafe { Out::new(out_point, "out_point") }?;
        // SAFETY: as above.
        let out_following = unsafe { Out::new(out_following, "out_following") }?;
        // SAFETY: as above.
        let out_glances = unsafe { Out::new(out_glances, "out_glances") }?;
        let (point, glances) = crowd.following(character)?;
        let world = crowd.config().world;
        out_point.write(point.map_or(cg_vec3::default(), |p| world.from_metres(p).into()));
        out_following.write(u32::from(point.is_some()));
        out_glances.write(glances);
        Ok(())
    })
}
