//! The C API of conversations: groups of characters standing together and talking, whose
//! members look at each other as people in conversation do. Who talks comes with each
//! frame (`CG_STATE_TALKING`); the model is `crate::attention::conversation`, its settings
//! fields of `cg_crowd_config`.

use super::crowd::{cg_crowd, crowd_mut, crowd_ref};
use super::{cg_status, ffi_boundary, slice, Out};

/// Most members of one conversation.
pub const CG_MAX_CONVERSATION_MEMBERS: u32 = 8;

/// Makes the characters `members[0 .. count]` (2 to `CG_MAX_CONVERSATION_MEMBERS` ids, each
/// in no other conversation) a group standing together and talking, and writes its id to
/// `*out_group`. From the next step its members look at each other: listeners mostly at the
/// member whose pushed state has `CG_STATE_TALKING`, the speaker at its listeners now and
/// then, and away between glances. A removed character leaves its group; a group left with
/// one member ends. The caller keeps `members`.
///
/// Ids are given in turn, never `CG_NO_TARGET` nor a live group's: the id of a removed
/// group names no group (`CG_STATUS_NOT_FOUND` from `cg_crowd_remove_conversation`) until
/// at least 2^32 - 1 - `max_conversations` more groups have been formed (4 286 578 687 at
/// the largest `max_conversations`, 8 388 608), however long other groups last.
///
/// Errors (nothing changed): `CG_STATUS_NULL_ARGUMENT`, `CG_STATUS_INVALID_ARGUMENT` (fewer
/// than 2 or more than 8 members, an id listed twice, an object, a character already in a
/// conversation), `CG_STATUS_NOT_FOUND` (an unknown id),
/// `CG_STATUS_CAPACITY` (`max_conversations` groups exist already). Not thread-safe.
#[no_mangle]
pub unsafe extern "C" fn cg_crowd_set_conversation(
    crowd: *mut cg_crowd,
    members: *const u32,
    count: usize,
    out_group: *mut u32,
) -> cg_status {
    ffi_boundary!({
        // SAFETY: handle contract of cg_crowd.
        let crowd = unsafe { crowd_mut(crowd) }?;
        // SAFETY: the caller provides `count` readable ids (or (NULL, 0)).
        let members = unsafe { slice(members, count, "members") }?;
        // SAFETY: the caller provides a writable uint32_t (or NULL, rejected).
        let out_group = unsafe { Out::new(out_group, "out_group") }?;
        let group = crowd.set_conversation(members)?;
        out_group.write(group);
        Ok(())
    })
}

/// Ends conversation `group`: its members go back to their own attention.
///
/// Errors: `CG_STATUS_NULL_ARGUMENT`, `CG_STATUS_NOT_FOUND` (no such group, or one that
/// already ended). Not thread-safe.
#[no_mangle]
pub unsafe extern "C" fn cg_crowd_remove_conversation(
    crowd: *mut cg_crowd,
    group: u32,
) -> cg_status {
    ffi_boundary!({
        // SAFETY: handle contract of cg_crowd.
        let crowd = unsafe { crowd_mut(crowd) }?;
        Ok(crowd.remove_conversation(group)?)
    })
}

/// Writes the conversation `character` is in to `*out_group`, or `CG_NO_TARGET` if it is in
/// none.
///
/// Errors: `CG_STATUS_NULL_ARGUMENT`, `CG_STATUS_NOT_FOUND` (no such entity),
/// `CG_STATUS_INVALID_ARGUMENT` (an object's or the viewer's id). Safe to call concurrently
/// with other `const` calls.
#[no_mangle]
pub unsafe extern "C" fn cg_crowd_get_conversation(
    crowd: *const cg_crowd,
    character: u32,
    out_group: *mut u32,
) -> cg_status {
    ffi_boundary!({
        // SAFETY: handle contract of cg_crowd.
        let crowd = unsafe { crowd_ref(crowd) }?;
        // SAFETY: the caller provides a writable uint32_t (or NULL, rejected).
        let out_group = unsafe { Out::new(out_group, "out_group") }?;
        let group = crowd.conversation_of(character)?;
        out_group.write(group.unwrap_or(super::attention::CG_NO_TARGET));
        Ok(())
    })
}
