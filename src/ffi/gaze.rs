//! C entry points of gaze IK on a crowd: base poses in, explicit targets, and the chain
//! joints and eyes out.

use glam::Quat;

use super::crowd::{cg_crowd, crowd_mut, crowd_ref};
use super::error::Result;
use super::types::{cg_quat, cg_vec3};
use super::{cg_status, ffi_boundary, read_versioned, write_versioned, Out, Versioned};
use crate::crowd::{ExplicitTarget, TargetPriority};
use crate::error::Error;

/// `cg_gaze_target.kind`: look at `point`.
pub const CG_GAZE_TARGET_POINT: u32 = 0;
/// `cg_gaze_target.kind`: look at entity `entity`, following it as it moves.
pub const CG_GAZE_TARGET_ENTITY: u32 = 1;

/// `cg_gaze_target.priority`: the target overrides automatic attention until cleared.
pub const CG_GAZE_PRIORITY_OVERRIDE: u32 = 0;
/// `cg_gaze_target.priority`: the target applies only while the character has no
/// automatic interest point.
pub const CG_GAZE_PRIORITY_WHEN_IDLE: u32 = 1;

/// A target set by game logic for one character (top-down attention). Set `struct_size`,
/// then fill it with `cg_gaze_target_init`.
#[repr(C)]
#[derive(Debug, Clone, Copy)]
pub struct cg_gaze_target {
    /// Size of this struct in bytes: set it to `sizeof(cg_gaze_target)` before every call
    /// taking the struct, `cg_gaze_target_init` included.
    pub struct_size: u32,
    /// `CG_GAZE_TARGET_POINT` (default) or `CG_GAZE_TARGET_ENTITY`.
    pub kind: u32,
    /// `CG_GAZE_PRIORITY_OVERRIDE` (default) or `CG_GAZE_PRIORITY_WHEN_IDLE`.
    pub priority: u32,
    /// The entity to look at, with `CG_GAZE_TARGET_ENTITY`.
    pub entity: u32,
    /// The point to look at (your units), with `CG_GAZE_TARGET_POINT`.
    pub point: cg_vec3,
}

impl Versioned for cg_gaze_target {
    const SIZES: &'static [usize] = &[std::mem::size_of::<cg_gaze_target>()];
    const NAME: &'static str = "cg_gaze_target";
    fn defaults() -> Self {
        cg_gaze_target {
            struct_size: std::mem::size_of::<Self>() as u32,
            kind: CG_GAZE_TARGET_POINT,
            priority: CG_GAZE_PRIORITY_OVERRIDE,
            entity: super::attention::CG_NO_TARGET,
            point: cg_vec3::default(),
        }
    }
}

/// Where a character's eyes are and where they look, as read by `cg_crowd_read_eyes`
/// (for debug drawing).
#[repr(C)]
#[derive(Debug, Clone, Copy, Default)]
pub struct cg_eye_info {
    /// The character's id.
    pub character: u32,
    /// Left eye position, your units (the head's position for a chain without eyes).
    pub left_origin: cg_vec3,
    /// Right eye position, your units.
    pub right_origin: cg_vec3,
    /// Left eye gaze direction, unit.
    pub left_direction: cg_vec3,
    /// Right eye gaze direction, unit.
    pub right_direction: cg_vec3,
}

/// Fills `target` with defaults (a point target at the origin, overriding). Set
/// `target->struct_size = sizeof(cg_gaze_target)` first: only that many bytes are written,
/// and `struct_size` keeps its value. The caller owns `target`.
///
/// Errors (nothing written): `CG_STATUS_NULL_ARGUMENT`, `CG_STATUS_BAD_STRUCT_SIZE`
/// (`struct_size` not a size the library knows, 0 or an unset field included).
/// Thread-safe.
#[no_mangle]
pub unsafe extern "C" fn cg_gaze_target_init(target: *mut cg_gaze_target) -> cg_status {
    ffi_boundary!({
        // SAFETY: the caller passes a cg_gaze_target of at least its struct_size bytes (or
        // NULL, rejected).
        unsafe { write_versioned(target, cg_gaze_target::defaults(), "target") }
    })
}

/// Gives `character` an explicit gaze target until `cg_crowd_clear_gaze_target`: a point,
/// or an entity followed as it moves, overriding the automatic interest point or only
/// filling in when there is none. The gaze moves there with the usual timing.
///
/// With conversations (`cg_crowd_set_conversation`): a `CG_GAZE_PRIORITY_OVERRIDE`
/// target wins over the character's conversation (it looks only at the target while the
/// other members go on, still looking at it); a `CG_GAZE_PRIORITY_WHEN_IDLE` target yields
/// to it, and shows only in the member's glances away from the group when its attention
/// model has nothing to look at.
///
/// Errors: `CG_STATUS_NULL_ARGUMENT`, `CG_STATUS_BAD_STRUCT_SIZE`, `CG_STATUS_NOT_FOUND`
/// (character or target entity), `CG_STATUS_NON_FINITE` (point),
/// `CG_STATUS_INVALID_ARGUMENT` (unknown kind or priority, an object as `character`, the
/// character itself as target). Not thread-safe.
#[no_mangle]
pub unsafe extern "C" fn cg_crowd_set_gaze_target(
    crowd: *mut cg_crowd,
    character: u32,
    target: *const cg_gaze_target,
) -> cg_status {
    ffi_boundary!({
        // SAFETY: handle contract of cg_crowd.
        let crowd = unsafe { crowd_mut(crowd) }?;
        // SAFETY: the caller passes a readable struct of at least its struct_size bytes.
        let target = unsafe { read_versioned(target) }?;
        let priority = match target.priority {
            CG_GAZE_PRIORITY_OVERRIDE => TargetPriority::Override,
            CG_GAZE_PRIORITY_WHEN_IDLE => TargetPriority::WhenIdle,
            other => {
                return Err(Error::InvalidArgument(format!(
                    "cg_gaze_target.priority is {other}, not a CG_GAZE_PRIORITY_*"
                ))
                .into())
            }
        };
        let explicit = match target.kind {
            CG_GAZE_TARGET_POINT => {
                let point = target.point.to_finite("cg_gaze_target.point")?;
                ExplicitTarget::Point(crowd.config().world.to_metres(point))
            }
            CG_GAZE_TARGET_ENTITY => ExplicitTarget::Entity(target.entity),
            other => {
                return Err(Error::InvalidArgument(format!(
                    "cg_gaze_target.kind is {other}, not a CG_GAZE_TARGET_*"
                ))
                .into())
            }
        };
        Ok(crowd.set_gaze_target(character, explicit, priority)?)
    })
}

/// Removes `character`'s explicit target; automatic attention takes over again.
///
/// Errors: `CG_STATUS_NULL_ARGUMENT`, `CG_STATUS_NOT_FOUND`, `CG_STATUS_INVALID_ARGUMENT`
/// (an object's id). Not thread-safe.
#[no_mangle]
pub unsafe extern "C" fn cg_crowd_clear_gaze_target(
    crowd: *mut cg_crowd,
    character: u32,
) -> cg_status {
    ffi_boundary!({
        // SAFETY: handle contract of cg_crowd.
        let crowd = unsafe { crowd_mut(crowd) }?;
        Ok(crowd.clear_gaze_target(character)?)
    })
}

fn to_quats(local: &[cg_quat], out: &mut [Quat]) -> Result<()> {
    for (index, (slot, rotation)) in out.iter_mut().zip(local).enumerate() {
        *slot = rotation.to_unit(&format!("local[{index}]"))?;
    }
    Ok(())
}

/// Sets a character's base pose: the local rotation of each of its chain joints, bottom to
/// top (`count` must equal the chain's joint count). Engines whose animation moves the
/// spine, neck, head or eyes push it every frame before `cg_crowd_step`; the gaze is added
/// on top (`final = base * delta`). Until set, the rest pose is the base. Quaternions are
/// normalised.
///
/// Errors: `CG_STATUS_NULL_ARGUMENT`, `CG_STATUS_NOT_FOUND`, `CG_STATUS_NON_FINITE`,
/// `CG_STATUS_INVALID_ARGUMENT` (count, a zero quaternion, an object's id). Not
/// thread-safe.
#[no_mangle]
pub unsafe extern "C" fn cg_crowd_set_base_pose(
    crowd: *mut cg_crowd,
    character: u32,
    local: *const cg_quat,
    count: usize,
) -> cg_status {
    ffi_boundary!({
        // SAFETY: handle contract of cg_crowd.
        let crowd = unsafe { crowd_mut(crowd) }?;
        // SAFETY: the caller passes `count` readable cg_quat (or (NULL, 0)).
        let local = unsafe { super::slice(local, count, "local") }?;
        if count > crate::ik::MAX_CHAIN_JOINTS {
            return Err(Error::InvalidArgument(format!(
                "count is {count}, a chain has at most {} joints",
                crate::ik::MAX_CHAIN_JOINTS
            ))
            .into());
        }
        let mut rotations = [Quat::IDENTITY; crate::ik::MAX_CHAIN_JOINTS];
        to_quats(local, &mut rotations)?;
        Ok(crowd.set_base_pose(character, &rotations[..count])?)
    })
}

/// Sets the base poses of many characters at once: `local` holds, for each id of
/// `characters` in order, its chain joints' local rotations bottom to top, packed
/// (`local_count` must be the sum of their joint counts). All or nothing: on an error no
/// pose is changed.
///
/// Errors: as `cg_crowd_set_base_pose`, and `CG_STATUS_INVALID_ARGUMENT` if `local_count`
/// does not match. Not thread-safe.
#[no_mangle]
pub unsafe extern "C" fn cg_crowd_set_base_poses(
    crowd: *mut cg_crowd,
    characters: *const u32,
    character_count: usize,
    local: *const cg_quat,
    local_count: usize,
) -> cg_status {
    ffi_boundary!({
        // SAFETY: handle contract of cg_crowd.
        let crowd = unsafe { crowd_mut(crowd) }?;
        // SAFETY: the caller passes the two arrays with their counts.
        let characters = unsafe { super::slice(characters, character_count, "characters") }?;
        // SAFETY: as above.
        let local = unsafe { super::slice(local, local_count, "local") }?;
        // Check everything first, so that a failure changes nothing.
        let mut needed = 0usize;
        for &id in characters {
            needed += crowd.chain(id)?.joint_count();
        }
        if needed != local_count {
            return Err(Error::InvalidArgument(format!(
                "local_count is {local_count}, the characters' chains have {needed} joints"
            ))
            .into());
        }
        for (index, rotation) in local.iter().enumerate() {
            rotation.to_unit(&format!("local[{index}]"))?;
        }
        let mut offset = 0;
        for &id in characters {
            let joints = crowd.chain(id)?.joint_count();
            let mut rotations = [Quat::IDENTITY; crate::ik::MAX_CHAIN_JOINTS];
            to_quats(&local[offset..offset + joints], &mut rotations)?;
            crowd.set_base_pose(id, &rotations[..joints])?;
            offset += joints;
        }
        Ok(())
    })
}

/// Writes to `*out_total` how many joints the characters `first .. first + count` have
/// together (in the order of `cg_crowd_read_gaze`): the size `cg_crowd_read_joints` needs.
///
/// Errors: `CG_STATUS_NULL_ARGUMENT`, `CG_STATUS_INVALID_ARGUMENT` (range past the last
/// character). Safe to call concurrently with other `const` calls.
#[no_mangle]
pub unsafe extern "C" fn cg_crowd_joint_total(
    crowd: *const cg_crowd,
    first: u32,
    count: u32,
    out_total: *mut usize,
) -> cg_status {
    ffi_boundary!({
        // SAFETY: handle contract of cg_crowd.
        let crowd = unsafe { crowd_ref(crowd) }?;
        // SAFETY: the caller provides a writable size_t (or NULL, rejected).
        let out_total = unsafe { Out::new(out_total, "out_total") }?;
        out_total.write(crowd.joint_total(first as usize, count as usize)?);
        Ok(())
    })
}

fn read_joints(
    crowd: *const cg_crowd,
    first: u32,
    count: u32,
    out: *mut cg_quat,
    out_len: usize,
    deltas_only: bool,
) -> Result<()> {
    // SAFETY: handle contract of cg_crowd.
    let crowd = unsafe { crowd_ref(crowd) }?;
    // SAFETY: the caller provides `out_len` writable cg_quat (or (NULL, 0)).
    let out = unsafe { super::slice_mut(out, out_len, "out") }?;
    let total = crowd.joint_total(first as usize, count as usize)?;
    if out.len() < total {
        return Err(Error::InvalidArgument(format!(
            "out_len is {out_len}, the characters' chains have {total} joints"
        ))
        .into());
    }
    // Written in place through a cg_quat-sized view: cg_quat and Quat are both x, y, z, w.
    let mut written = 0;
    let mut buffer = [Quat::IDENTITY; crate::ik::MAX_CHAIN_JOINTS];
    for character in first as usize..(first + count) as usize {
        let joints = crowd.read_joints(character, 1, deltas_only, &mut buffer)?;
        for (slot, rotation) in out[written..written + joints].iter_mut().zip(&buffer) {
            *slot = (*rotation).into();
        }
        written += joints;
    }
    Ok(())
}

/// Reads the gaze result of characters `first .. first + count` (in the order of
/// `cg_crowd_read_gaze`): each chain joint's final local rotation `base * delta`, bottom to
/// top, chain after chain, packed into `out` (`out_len` at least their joint total, see
/// `cg_crowd_joint_total`; the human chain has 10). Write them to your skeleton's spine,
/// neck, head and eye bones. `out` stays yours; nothing is allocated.
///
/// Errors: `CG_STATUS_NULL_ARGUMENT`, `CG_STATUS_INVALID_ARGUMENT` (range past the last
/// character, `out_len` too small). Safe to call concurrently with other `const` calls.
#[no_mangle]
pub unsafe extern "C" fn cg_crowd_read_joints(
    crowd: *const cg_crowd,
    first: u32,
    count: u32,
    out: *mut cg_quat,
    out_len: usize,
) -> cg_status {
    ffi_boundary!({ read_joints(crowd, first, count, out, out_len, false) })
}

/// Like `cg_crowd_read_joints`, but the displacement (delta) rotations alone, for engines
/// that layer gaze additively on their own pose: `final = base * delta`.
///
/// Errors: as `cg_crowd_read_joints`. Safe to call concurrently with other `const` calls.
#[no_mangle]
pub unsafe extern "C" fn cg_crowd_read_joint_deltas(
    crowd: *const cg_crowd,
    first: u32,
    count: u32,
    out: *mut cg_quat,
    out_len: usize,
) -> cg_status {
    ffi_boundary!({ read_joints(crowd, first, count, out, out_len, true) })
}

/// Reads where the eyes of characters `first .. first + count` (in the order of
/// `cg_crowd_read_gaze`) are and look (world, your units), one `cg_eye_info` each in `out`
/// (`out_len >= count`), for debug drawing.
///
/// Errors: `CG_STATUS_NULL_ARGUMENT`, `CG_STATUS_INVALID_ARGUMENT` (range, `out_len`). Safe
/// to call concurrently with other `const` calls.
#[no_mangle]
pub unsafe extern "C" fn cg_crowd_read_eyes(
    crowd: *const cg_crowd,
    first: u32,
    count: u32,
    out: *mut cg_eye_info,
    out_len: usize,
) -> cg_status {
    ffi_boundary!({
        // SAFETY: the caller's contract, forwarded.
        unsafe {
            read_characters(crowd, first, count, out, out_len, |crowd, character| {
                let world = crowd.config().world;
                let eyes = crowd.eyes_at(character);
                cg_eye_info {
                    character: eyes.character,
                    left_origin: world.from_metres(eyes.origins[0]).into(),
                    right_origin: world.from_metres(eyes.origins[1]).into(),
                    left_direction: eyes.directions[0].into(),
                    right_direction: eyes.directions[1].into(),
                }
            })
        }
    })
}

/// A per-character reader's body: checks `crowd`, `out` (`out_len` writable `T`, or (NULL,
/// 0)) and the range `first .. first + count` of the characters in the order of
/// `cg_crowd_read_gaze`, then writes `each(crowd, position)` for each into `out[..count]`.
///
/// # Safety
/// `crowd` must be NULL or a live handle, and `out` NULL or valid for `out_len` writes of
/// `T` (the contract of the readers).
pub(super) unsafe fn read_characters<T>(
    crowd: *const cg_crowd,
    first: u32,
    count: u32,
    out: *mut T,
    out_len: usize,
    each: impl Fn(&crate::crowd::Crowd, usize) -> T,
) -> Result<()> {
    // SAFETY: handle contract of cg_crowd.
    let crowd = unsafe { crowd_ref(crowd) }?;
    // SAFETY: the caller provides `out_len` writable values (or (NULL, 0)).
    let out = unsafe { super::slice_mut(out, out_len, "out") }?;
    crowd.joint_total(first as usize, count as usize)?;
    if out.len() < count as usize {
        return Err(Error::InvalidArgument(format!(
            "out_len is {out_len}, {count} characters were asked for"
        ))
        .into());
    }
    let positions = first as usize..first as usize + count as usize;
    for (slot, position) in out.iter_mut().zip(positions) {
        *slot = each(crowd, position);
    }
    Ok(())
}
