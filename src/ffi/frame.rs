//! C entry points of an engine's frame: pushing the entities' states (`cg_crowd_push_frame`,
//! or in parts from several threads: `cg_crowd_begin_push`, `cg_crowd_push_range`,
//! `cg_crowd_end_push`) and stepping the crowd (`cg_crowd_step`, or in ranges:
//! `cg_crowd_begin_step`, `cg_crowd_step_range`, `cg_crowd_end_step`).

use glam::Vec3;

use super::attention::{
    cg_entity_state, CG_STATE_HAS_VELOCITY, CG_STATE_HEADING_FROM_MOTION, CG_STATE_TALKING,
};
use super::crowd::{cg_crowd, crowd_handle, crowd_mut, test_hook, Hook};
use super::error::{FfiError, Result};
use super::types::cg_vec3;
use super::{borrow_current, cg_status, ffi_boundary, read_versioned};
use crate::error::{ensure_finite, Error};
use crate::scene::EntityUpdate;
use crate::world::World;

/// Converts the `index`-th element of a C state array with element size `stride`.
///
/// # Safety
/// `states` must point to `count` elements of `stride` bytes each, `index < count`.
#[inline(always)]
unsafe fn entity_update(
    world: &World,
    states: *const cg_entity_state,
    stride: usize,
    index: usize,
) -> Result<EntityUpdate> {
    // SAFETY: index < count and each element is `stride` bytes (caller contract).
    let element = unsafe { states.cast::<u8>().add(index * stride) }.cast::<cg_entity_state>();
    let older;
    // SAFETY: as above; both check struct_size against this library's layouts. A state of
    // this library's layout is read in place (the push's loops read every state).
    let state = match unsafe { borrow_current(element) } {
        Some(state) => state,
        None => {
            // SAFETY: as above; an older layout is copied over the defaults.
            older = unsafe { read_versioned(element) }?;
            &older
        }
    };
    let velocity = state.velocity;
    let has_velocity = state.flags & CG_STATE_HAS_VELOCITY != 0;
    let heading_from_motion = state.flags & CG_STATE_HEADING_FROM_MOTION != 0;
    // A heading the flags say to ignore is not read (NaN included).
    let heading = if heading_from_motion {
        0.0
    } else {
        state.heading
    };
    let values = [
        heading,
        state.position.x,
        state.position.y,
        state.position.z,
    ];
    if state.struct_size as usize != stride
        || state.flags & !KNOWN_STATE_FLAGS != 0
        || !values.iter().all(|value| value.is_finite())
        || has_velocity
            && ![velocity.x, velocity.y, velocity.z]
                .iter()
                .all(|v| v.is_finite())
    {
        return Err(state_error(state, stride, index));
    }
    let metres = |v: cg_vec3| world.to_metres(Vec3::new(v.x, v.y, v.z));
    Ok(EntityUpdate {
        id: state.id,
        position: metres(state.position),
        heading,
        heading_from_motion,
        velocity: has_velocity.then(|| metres(velocity)),
        talking: state.flags & CG_STATE_TALKING != 0,
    })
}

/// What is wrong with a state [`entity_update`] refused, checked in this order: its
/// `struct_size`, its heading (unless derived from motion), its flags, its velocity (when
/// flagged), its position.
#[cold]
#[inline(never)]
fn state_error(state: &cg_entity_state, stride: usize, index: usize) -> FfiError {
    if state.struct_size as usize != stride {
        return FfiError::BadStructSize(format!(
            "states[{index}].struct_size is {}, but states[0]'s is {stride}",
            state.struct_size
        ));
    }
    let checks = || -> Result<()> {
        if state.flags & CG_STATE_HEADING_FROM_MOTION == 0 {
            ensure_finite(state.heading, "heading")?;
        }
        if state.flags & !KNOWN_STATE_FLAGS != 0 {
            return Err(Error::InvalidArgument(format!(
                "states[{index}].flags has unknown bits 0x{:x}",
                state.flags
            ))
            .into());
        }
        if state.flags & CG_STATE_HAS_VELOCITY != 0 {
            state.velocity.to_finite("velocity")?;
        }
        state.position.to_finite("position")?;
        Ok(())
    };
    match checks() {
        Err(error) => error,
        Ok(()) => Error::Internal(format!("states[{index}] was refused, but is valid")).into(),
    }
}

/// Every `CG_STATE_*` bit.
const KNOWN_STATE_FLAGS: u32 =
    CG_STATE_HEADING_FROM_MOTION | CG_STATE_HAS_VELOCITY | CG_STATE_TALKING;

/// Checks a C array of `count` entity states (non-null unless empty, one `struct_size`
/// for all) and returns its stride in bytes.
///
/// # Safety
/// If not NULL, `states` must point to `count` readable elements, each starting with its
/// `struct_size`.
unsafe fn state_stride(states: *const cg_entity_state, count: usize) -> Result<usize> {
    let stride = if count == 0 {
        std::mem::size_of::<cg_entity_state>()
    } else {
        // SAFETY: a non-empty array's first element starts with its struct_size.
        unsafe { read_versioned(states) }?.struct_size as usize
    };
    // SAFETY: checks the (pointer, count) pair; elements are `stride` bytes apart.
    unsafe { super::slice(states.cast::<u8>(), count.saturating_mul(stride), "states") }?;
    Ok(stride)
}

/// Pushes one frame of entity states at time `t` (seconds). Entities not listed keep
/// their last state; velocities come from the previous pushed position unless given.
/// An entity listed twice takes both states in turn. With recording on
/// (`max_recorded_states > 0`) the frame is also recorded for `cg_crowd_plan`. `states`
/// stays yours; nothing is allocated. To push from several threads, see
/// `cg_crowd_begin_push`.
///
/// Errors (and nothing is changed): `CG_STATUS_NULL_ARGUMENT` (crowd, or states NULL with
/// count > 0), `CG_STATUS_BAD_STRUCT_SIZE`, `CG_STATUS_NON_FINITE` (t or any value),
/// `CG_STATUS_NOT_FOUND` (an unknown id), `CG_STATUS_INVALID_ARGUMENT` (t earlier than the
/// previous frame's, unknown flag bits), `CG_STATUS_CAPACITY` (recording full),
/// `CG_STATUS_WRONG_STATE` (a plan is active, or a ranged step or push is open). Not
/// thread-safe.
#[no_mangle]
pub unsafe extern "C" fn cg_crowd_push_frame(
    crowd: *mut cg_crowd,
    t: f64,
    states: *const cg_entity_state,
    count: usize,
) -> cg_status {
    ffi_boundary!({
        // SAFETY: handle contract of cg_crowd.
        let crowd = unsafe { crowd_mut(crowd) }?;
        // SAFETY: the caller's array (contract of this function).
        let stride = unsafe { state_stride(states, count) }?;
        let world = crowd.config().world;
        crowd.push_frame_with(
            t,
            count,
            #[inline(always)]
            |index| {
                // SAFETY: index < count, stride-sized elements checked above.
                unsafe { entity_update(&world, states, stride, index) }
            },
        )
    })
}

/// Begins a frame pushed in parts from several threads, at time `t` (seconds, not
/// earlier than the previous frame): then call `cg_crowd_push_range` with parts of the
/// frame's states (from as many threads as you like, e.g. one part per worker of your job
/// system), and `cg_crowd_end_push` once they have all returned. The result is the same as
/// one `cg_crowd_push_frame` of all the parts, bit for bit, however the frame is split.
/// Until `cg_crowd_end_push`, every other call on this crowd fails with
/// `CG_STATUS_WRONG_STATE`. Allocates nothing.
///
/// Errors (and nothing is changed): `CG_STATUS_NULL_ARGUMENT`, `CG_STATUS_NON_FINITE` (t),
/// `CG_STATUS_INVALID_ARGUMENT` (t earlier than the previous frame's),
/// `CG_STATUS_WRONG_STATE` (a ranged step or push is open, a plan is active, or recording
/// is on: record with `cg_crowd_push_frame`). Not thread-safe: no other call on this crowd
/// may run at the same time.
#[no_mangle]
pub unsafe extern "C" fn cg_crowd_begin_push(crowd: *mut cg_crowd, t: f64) -> cg_status {
    ffi_boundary!({
        // SAFETY: handle contract of cg_crowd.
        let handle = unsafe { crowd_handle(crowd) }?;
        // SAFETY: by the C contract no other call runs on this crowd now.
        unsafe { handle.begin_push(t) }
    })
}

/// Pushes `count` entity states into the push opened by `cg_crowd_begin_push`, as
/// `cg_crowd_push_frame` would. Each entity may be pushed once per push: a state for an
/// entity that this or another call already pushed in this push is an error. Entities no
/// call pushes keep their last state. `states` stays yours and must not change during the
/// call. Thread-safe: several threads may call it at once on the same crowd, each with its
/// own entities. `count` 0 does nothing. Allocates nothing.
///
/// Each call first checks its states and claims their entities, then writes them. Two
/// calls that race over the same entity: at least one fails with `CG_STATUS_WRONG_STATE`,
/// and both may (each can meet a claim the other holds until it gives it back on failing);
/// a call that fails keeps its claims until it returns, and meanwhile refuses other calls'
/// states for those entities. Give each entity to one call. A call racing with
/// `cg_crowd_end_push` either runs first (and `cg_crowd_end_push` fails) or fails with
/// `CG_STATUS_WRONG_STATE`, pushing nothing.
///
/// Errors (and nothing in this call's states is pushed): `CG_STATUS_NULL_ARGUMENT`
/// (crowd, or states NULL with count > 0), `CG_STATUS_BAD_STRUCT_SIZE`,
/// `CG_STATUS_NON_FINITE` (any value), `CG_STATUS_NOT_FOUND` (an unknown id),
/// `CG_STATUS_INVALID_ARGUMENT` (unknown flag bits; or `states` changed while the call read
/// them: then each state that still names the entity it first named, with valid values,
/// is pushed as read the second time, the others skipped), `CG_STATUS_WRONG_STATE` (no ranged push is open, it is being ended, or an
/// entity was pushed already in this push, by this call or another).
#[no_mangle]
pub unsafe extern "C" fn cg_crowd_push_range(
    crowd: *mut cg_crowd,
    states: *const cg_entity_state,
    count: usize,
) -> cg_status {
    ffi_boundary!({
        // SAFETY: handle contract of cg_crowd; this call only needs shared access.
        let handle = unsafe { crowd_handle(crowd) }?;
        // SAFETY: the caller's array (contract of this function).
        let stride = unsafe { state_stride(states, count) }?;
        handle.push_range(|ranges| {
            let world = ranges.world();
            ranges.push_with(count, |index| {
                // SAFETY: index < count, stride-sized elements checked above.
                unsafe { entity_update(&world, states, stride, index) }
            })
        })
    })
}

/// Ends the push opened by `cg_crowd_begin_push`: the frame's time becomes the crowd's.
/// Entities that no `cg_crowd_push_range` call pushed keep their last state.
///
/// Errors: `CG_STATUS_NULL_ARGUMENT`, `CG_STATUS_WRONG_STATE` (no ranged push is open, or
/// `cg_crowd_push_range` calls are still running: then the push stays open and nothing
/// changes; call it again once they have returned). Not thread-safe: call it after every
/// `cg_crowd_push_range` call has returned; a call that starts while this one runs fails
/// with `CG_STATUS_WRONG_STATE`.
#[no_mangle]
pub unsafe extern "C" fn cg_crowd_end_push(crowd: *mut cg_crowd) -> cg_status {
    ffi_boundary!({
        // SAFETY: handle contract of cg_crowd.
        let handle = unsafe { crowd_handle(crowd) }?;
        // SAFETY: by the C contract no other call but ranges runs on this crowd now.
        unsafe { handle.end_push() }
    })
}

/// Steps every character `dt` seconds (>= 0) after the previous step: attention (scores
/// the entities near each character, updates its threshold and interest point; after
/// `cg_crowd_plan`, follows the plan instead), then gaze IK. With `threads > 1` in the
/// config, the crowd's worker threads share the work; results are the same. Allocates
/// nothing. The same as `cg_crowd_begin_step`, one range over all characters, and
/// `cg_crowd_end_step`.
///
/// Any finite `dt` returns in a time bounded by the crowd's size. A step longer than one
/// hour (a pause, or a time stamp passed as `dt` by mistake) moves attention, gaze, blinks
/// and conversations on by one hour, long after all of them have settled: the characters
/// start afresh, and the next frames go on normally. A plan's replay clock moves by the
/// whole `dt`.
///
/// In a child process made by `fork()` after the crowd's worker threads started, the first
/// step starts new workers in the child (or steps on the calling thread alone if that
/// fails); results are the same. The parent is not affected.
///
/// Errors: `CG_STATUS_NULL_ARGUMENT`, `CG_STATUS_NON_FINITE` (dt), `CG_STATUS_INVALID_ARGUMENT`
/// (dt < 0), `CG_STATUS_WRONG_STATE` (a ranged step is open). Not thread-safe: no other
/// call on this crowd may run at the same time.
#[no_mangle]
pub unsafe extern "C" fn cg_crowd_step(crowd: *mut cg_crowd, dt: f32) -> cg_status {
    ffi_boundary!({
        // SAFETY: handle contract of cg_crowd.
        unsafe { crowd_mut(crowd) }?.step(dt)?;
        // SAFETY: as above; the crowd's mutable borrow has ended.
        unsafe { test_hook(crowd, Hook::Step) };
        Ok(())
    })
}

/// Begins a step split into ranges, `dt` seconds (>= 0) after the previous one: advances
/// the plan's clock, rebuilds the spatial grid and fixes what all characters share this
/// frame. Then call `cg_crowd_step_range` on ranges of characters (from as many threads as
/// you like, e.g. your job system's workers), and `cg_crowd_end_step` once they have all
/// returned. The outputs are identical to `cg_crowd_step`'s, however the crowd is split.
/// Until `cg_crowd_end_step`, every other call on this crowd fails with
/// `CG_STATUS_WRONG_STATE`. Allocates nothing.
///
/// Errors: `CG_STATUS_NULL_ARGUMENT`, `CG_STATUS_NON_FINITE` (dt), `CG_STATUS_INVALID_ARGUMENT`
/// (dt < 0), `CG_STATUS_WRONG_STATE` (a ranged step is already open). Not thread-safe: no
/// other call on this crowd may run at the same time.
#[no_mangle]
pub unsafe extern "C" fn cg_crowd_begin_step(crowd: *mut cg_crowd, dt: f32) -> cg_status {
    ffi_boundary!({
        // SAFETY: handle contract of cg_crowd.
        let handle = unsafe { crowd_handle(crowd) }?;
        // SAFETY: by the C contract no other call runs on this crowd now.
        unsafe { handle.begin_step(dt) }
    })
}

/// Steps characters `first .. first + count` of the step opened by `cg_crowd_begin_step`:
/// attention, then gaze IK. The range indexes the crowd's storage order, which keeps
/// neighbours in space together (see `reorder_period` in `cg_crowd_config`) and is not the
/// order of `cg_crowd_read_gaze`: split `0 .. character count` into disjoint ranges any way
/// you like; every character is stepped once, and the outputs do not depend on the split.
/// Thread-safe for disjoint ranges: several threads may call it at once on the same crowd.
/// `count` 0 does nothing. Allocates nothing.
///
/// Errors: `CG_STATUS_NULL_ARGUMENT`, `CG_STATUS_INVALID_ARGUMENT` (the range goes past the
/// last character), `CG_STATUS_WRONG_STATE` (no ranged step is open, or the range overlaps
/// one already stepped in this step; then nothing in it is stepped).
#[no_mangle]
pub unsafe extern "C" fn cg_crowd_step_range(
    crowd: *mut cg_crowd,
    first: u32,
    count: u32,
) -> cg_status {
    ffi_boundary!({
        // SAFETY: handle contract of cg_crowd; this call only needs shared access.
        let handle = unsafe { crowd_handle(crowd) }?;
        handle.step_range(first as usize, count as usize)
    })
}

/// Ends the step opened by `cg_crowd_begin_step`. Characters that no range covered are
/// stepped now, so a step always moves the whole crowd. Call it after every
/// `cg_crowd_step_range` call of this step has returned. Allocates nothing.
///
/// Errors: `CG_STATUS_NULL_ARGUMENT`, `CG_STATUS_WRONG_STATE` (no ranged step is open, or
/// `cg_crowd_step_range` calls are still running: the step stays open). Not thread-safe
/// with anything but `cg_crowd_step_range`.
#[no_mangle]
pub unsafe extern "C" fn cg_crowd_end_step(crowd: *mut cg_crowd) -> cg_status {
    ffi_boundary!({
        // SAFETY: handle contract of cg_crowd.
        let handle = unsafe { crowd_handle(crowd) }?;
        // SAFETY: by the C contract only ranges may run on this crowd now.
        unsafe { handle.end_step() }
    })
}
