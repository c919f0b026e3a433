//! Operations on the crowd: one C API call each (after the `_init` calls that fill its
//! structs), with arguments read from the input.

use super::input::Input;
use super::outputs::{sentinel, sized_sentinel};
use super::values::{point, quat, vec3};
use super::{array_pointer, or_null, pointer_to, State};
use crowdgaze::ffi::attention::*;
use crowdgaze::ffi::chain::{cg_chain_desc, cg_chain_desc_init_human};
use crowdgaze::ffi::conversations::{
    cg_crowd_get_conversation, cg_crowd_remove_conversation, cg_crowd_set_conversation,
};
use crowdgaze::ffi::crowd::{
    cg_crowd, cg_crowd_config, cg_crowd_config_init, cg_crowd_config_init_street, cg_crowd_create,
    cg_crowd_destroy, cg_crowd_get_config, CG_EYE_MOTION_MAIN_SEQUENCE,
};
use crowdgaze::ffi::eyelids::{cg_crowd_read_eyelids, cg_eyelids};
use crowdgaze::ffi::following::cg_crowd_read_following;
use crowdgaze::ffi::frame::*;
use crowdgaze::ffi::gaze::*;
use crowdgaze::ffi::status::cg_status;
use crowdgaze::ffi::types::{cg_quat, cg_vec3};
use std::mem::{size_of, MaybeUninit};
use std::ptr::null_mut;

/// The chain joint count of the default (human) chain.
const HUMAN_JOINTS: usize = 10;

/// A struct filled by its `_init` function (whose status is checked), after setting its
/// `struct_size`.
pub fn init<T>(
    state: &State,
    function: &str,
    init: unsafe extern "C" fn(*mut T) -> cg_status,
) -> T {
    let mut value = MaybeUninit::<T>::uninit();
    // SAFETY: every versioned struct starts with its `uint32_t struct_size`.
    unsafe {
        value
            .as_mut_ptr()
            .cast::<u32>()
            .write(size_of::<T>() as u32)
    };
    assert_eq!(
        state.call(function, unsafe { init(value.as_mut_ptr()) }),
        cg_status::Ok
    );
    // SAFETY: the _init function succeeded, so it filled the whole struct.
    unsafe { value.assume_init() }
}

/// Creates the crowd every run starts with: 12 characters, 4 objects, recording on.
pub fn first_crowd(state: &mut State) {
    let mut config: cg_crowd_config = init(state, "cg_crowd_config_init", cg_crowd_config_init);
    config.max_characters = 12;
    config.max_objects = 4;
    config.max_recorded_states = 4000;
    let status = unsafe { cg_crowd_create(&config, &mut state.crowd) };
    assert_eq!(state.call("cg_crowd_create", status), cg_status::Ok);
    state.config = config;
}

/// A new crowd from a config with fuzzed fields; it replaces the current one on success.
pub fn create(state: &mut State, input: &mut Input) {
    let mut config: cg_crowd_config = init(state, "cg_crowd_config_init", cg_crowd_config_init);
    config.struct_size = input.struct_size(size_of::<cg_crowd_config>());
    config.seed = input.u64();
    config.max_characters = match input.below(16) {
        14 => 0,
        15 => 16_777_217,
        n => n + 1,
    };
    config.max_objects = match input.below(16) {
        15 => 16_777_217,
        n => n % 8,
    };
    config.max_recorded_states = [0, 64, 400, 2000][input.below(4) as usize];
    if input.rare() {
        config.up_axis = input.below(8);
        config.forward_axis = input.below(8);
    } else {
        // Perpendicular pairs: (up, forward) of the engines' conventions.
        let (up, forward) = [(2, 4), (4, 0), (4, 3), (2, 1)][input.below(4) as usize];
        config.up_axis = up;
        config.forward_axis = forward;
    }
    config.units_per_metre = match input.below(16) {
        13 => 100.0,
        14 => 0.01,
        15 => input.float(),
        _ => 1.0,
    };
    config.attention_period = match input.below(16) {
        15 => input.below(70),
        n => n % 4 + 1,
    };
    if input.below(4) == 3 {
        config.lod_distance = input.positive();
        config.far_attention_period = input.below(70);
    }
    // Rarely, any float for any float field.
    while input.rare() {
        let fields: [&mut f32; 25] = [
            &mut config.units_per_metre,
            &mut config.max_distance,
            &mut config.field_of_view,
            &mut config.speed_weight,
            &mut config.periphery_max_angle,
            &mut config.min_interest_time,
            &mut config.max_interest_time,
            &mut config.interest_cooldown,
            &mut config.threshold_warmup,
            &mut config.initial_threshold,
            &mut config.attention_fraction_min,
            &mut config.attention_fraction_max,
            &mut config.eyes_only_angle,
            &mut config.eyes_head_neck_angle,
            &mut config.head_speed,
            &mut config.max_activation_time,
            &mut config.restart_distance,
            &mut config.min_deactivation_time,
            &mut config.max_deactivation_time,
            &mut config.eye_fixation_time,
            &mut config.head_fixation_time,
            &mut config.random_pick_probability,
            &mut config.social_weight,
            &mut config.proximity_radius,
            &mut config.lod_distance,
        ];
        let index = input.below(25) as usize;
        *fields.into_iter().nth(index).expect("a field") = input.float();
    }
    let mut crowd: *mut cg_crowd = null_mut();
    let pointer = pointer_to(&config, input);
    let out = or_null(&mut crowd as *mut _, input);
    // Rarely, the recording at its documented maximum (read last, so that earlier inputs
    // decode as they did): 275 GB, which the create reserves untouched or refuses with
    // CG_STATUS_OUT_OF_MEMORY, never aborting.
    if input.rare() {
        config.max_recorded_states = u32::MAX;
    }
    // The living eyes' settings (read last too): any values, or blinking as fast as allowed
    // with every large shift blinking and the eyes on the main sequence.
    match input.below(8) {
        7 => {
            config.blink_rate = input.float();
            config.blink_rate_spread = input.float();
            config.evoked_blink_full_amplitude = input.float();
            config.lid_gain = input.float();
            config.eye_motion = input.below(4);
        }
        6 => {
            config.blink_rate = 120.0;
            config.evoked_blink_probability = 1.0;
            config.eye_motion = CG_EYE_MOTION_MAIN_SEQUENCE;
        }
        _ => {}
    }
    // The conversations' settings (read after the eyes'): any values and a small or bad
    // capacity, no room for a conversation, or glances as short and turns as abrupt as
    // allowed.
    match input.below(8) {
        7 => {
            config.max_conversations = [0, 1, 2, 3, 8_388_609, u32::MAX][input.below(6) as usize];
            let fields: [&mut f32; 9] = [
                &mut config.talking_gain,
                &mut config.eye_part_weight,
                &mut config.listener_look_share,
                &mut config.listener_glance_time,
                &mut config.speaker_look_share,
                &mut config.speaker_glance_time,
                &mut config.idle_look_share,
                &mut config.idle_glance_time,
                &mut config.turn_start_aversion_time,
            ];
            for field in fields {
                *field = input.float();
            }
        }
        6 => config.max_conversations = 0,
        5 => {
            config.max_conversations = 1;
            config.talking_gain = 100.0;
            config.listener_look_share = 0.999;
            config.listener_glance_time = 1e-3;
            config.speaker_glance_time = 1e-3;
            config.idle_glance_time = 1e-3;
            config.turn_start_aversion_time = 60.0;
        }
        _ => {}
    }
    street_settings(state, &mut config, input);
    let pointer: *const cg_crowd_config = if pointer.is_null() { pointer } else { &config };
    let status = state.change("cg_crowd_create", unsafe { cg_crowd_create(pointer, out) });
    if status == cg_status::Ok {
        unsafe { cg_crowd_destroy(state.crowd) };
        state.crowd = crowd;
        state.config = config;
        state.live.clear();
        state.removed.clear();
        state.conversations.clear();
        state.viewer = None;
        state.time = 0.0;
    } else {
        assert!(
            crowd.is_null(),
            "cg_crowd_create failed but wrote its handle"
        );
    }
}

/// A gaze chain for `cg_character_desc.chain`: the human one with some fields changed, in
/// fuzzed axes (a failed init leaves garbage bytes, a bad `struct_size`).
fn chain(state: &State, input: &mut Input) -> cg_chain_desc {
    let mut chain = sized_sentinel::<cg_chain_desc>()[0];
    let (up, forward) = if input.rare() {
        (input.below(8), input.below(8))
    } else {
        (2, 4)
    };
    let status = unsafe { cg_chain_desc_init_human(&mut chain, up, forward) };
    state.call("cg_chain_desc_init_human", status);
    for _ in 0..input.below(4) {
        let joint = input.below(16) as usize % chain.joints.len();
        let joint = &mut chain.joints[joint];
        match input.below(12) {
            0 => chain.joint_count = input.below(17),
            1 => joint.role = input.below(6),
            2 => joint.offset = vec3(input),
            3 => joint.rest = quat(input),
            4 => joint.twist_axis = vec3(input),
            5 => joint.max_swing = input.float(),
            6 => joint.min_twist = input.float(),
            7 => joint.max_twist = input.float(),
            8 => chain.eye_forward = vec3(input),
            9 => chain.eye_up = vec3(input),
            10 => chain.root_offset = vec3(input),
            _ => chain.struct_size = input.struct_size(size_of::<cg_chain_desc>()),
        }
    }
    chain
}

/// Calls `cg_crowd_add_character` or `cg_crowd_add_object` (`call`) with `desc`, each
/// pointer rarely NULL, checks the id written and records it.
fn add<D>(
    state: &mut State,
    input: &mut Input,
    function: &str,
    desc: &D,
    call: unsafe extern "C" fn(*mut cg_crowd, *const D, *mut u32) -> cg_status,
) {
    let crowd = state.crowd(input);
    let mut id = sentinel::<u32>(1);
    let out = or_null(id.as_mut_ptr(), input);
    let status = state.change(function, unsafe {
        call(crowd, pointer_to(desc, input), out)
    });
    state.outputs(function, status, &id, 1);
    added(state, status, out, id[0]);
}

/// Records an id the crowd returned.
fn added(state: &mut State, status: cg_status, out: *mut u32, id: u32) {
    if status == cg_status::Ok && !out.is_null() && !state.live.contains(&id) {
        state.live.push(id);
    }
}

pub fn add_character(state: &mut State, input: &mut Input) {
    let mut desc: cg_character_desc = init(state, "cg_character_desc_init", cg_character_desc_init);
    desc.struct_size = input.struct_size(size_of::<cg_character_desc>());
    desc.position = point(input, 0.0);
    desc.heading = input.float();
    desc.impact = input.float_or(1.0);
    desc.attention_model = input.choice(3);
    let chain = chain(state, input);
    if input.below(4) == 3 {
        desc.chain = &chain;
    }
    let function = "cg_crowd_add_character";
    add(state, input, function, &desc, cg_crowd_add_character);
}

pub fn add_object(state: &mut State, input: &mut Input) {
    let mut desc: cg_object_desc = init(state, "cg_object_desc_init", cg_object_desc_init);
    desc.struct_size = input.struct_size(size_of::<cg_object_desc>());
    desc.position = point(input, 0.0);
    desc.heading = input.float();
    desc.look_at_height = input.float_or(1.2);
    desc.impact = input.float_or(1.0);
    add(
        state,
        input,
        "cg_crowd_add_object",
        &desc,
        cg_crowd_add_object,
    );
}

pub fn remove_entity(state: &mut State, input: &mut Input) {
    let id = state.id(input);
    let crowd = state.crowd(input);
    let status = state.change("cg_crowd_remove_entity", unsafe {
        cg_crowd_remove_entity(crowd, id)
    });
    if status == cg_status::Ok {
        state.live.retain(|&live| live != id);
        state.removed.push(id);
        if state.viewer == Some(id) {
            state.viewer = None;
        }
    }
}

/// Up to six fuzzed entity states: ids, flags, struct sizes and values, any of them bad.
fn fuzzed_states(state: &mut State, input: &mut Input) -> Vec<cg_entity_state> {
    let count = input.count(6);
    let size = input.struct_size(size_of::<cg_entity_state>());
    (0..count)
        .map(|_| {
            let mut entity: cg_entity_state =
                init(state, "cg_entity_state_init", cg_entity_state_init);
            entity.struct_size = size;
            entity.id = state.id(input);
            entity.flags = input.choice(4);
            entity.heading = input.float();
            entity.position = point(input, 0.0);
            entity.velocity = vec3(input);
            entity
        })
        .collect()
}

/// A frame time: the next frame's mostly; the same, earlier, later or not finite.
fn fuzzed_time(state: &State, input: &mut Input) -> f64 {
    match input.below(16) {
        12 => state.time,
        13 => state.time - 1.0,
        14 => state.time + f64::from(input.float()),
        15 => [f64::NAN, f64::INFINITY, 1.0e300][input.below(3) as usize],
        _ => state.time + 1.0 / 30.0,
    }
}

/// Sets `CG_STATE_TALKING` on the states whose bit (index modulo 8) in one input byte is
/// set: read after an operation's other arguments, so that older inputs push what they did.
fn talking(states: &mut [cg_entity_state], input: &mut Input) {
    let talkers = input.byte();
    for (index, entity) in states.iter_mut().enumerate() {
        if talkers & (1 << (index % 8)) != 0 {
            entity.flags |= CG_STATE_TALKING;
        }
    }
}

pub fn push_frame(state: &mut State, input: &mut Input) {
    let mut states = fuzzed_states(state, input);
    let count = states.len();
    let t = fuzzed_time(state, input);
    let crowd = state.crowd(input);
    let pointer = array_pointer(&states, input);
    talking(&mut states, input);
    let pointer = if pointer.is_null() {
        pointer
    } else {
        states.as_ptr()
    };
    let status = state.change("cg_crowd_push_frame", unsafe {
        cg_crowd_push_frame(crowd, t, pointer, count)
    });
    if status == cg_status::Ok {
        state.time = t;
    }
}

/// A push in parts: `cg_crowd_begin_push`, up to four `cg_crowd_push_range` calls with
/// fuzzed states (entities pushed twice, bad values, before a begin that failed), then
/// `cg_crowd_end_push` (on a fuzzed handle, then on the real one, so that the push is
/// closed whatever happened). Nothing else runs while the push is open.
pub fn ranged_push(state: &mut State, input: &mut Input) {
    let t = fuzzed_time(state, input);
    let crowd = state.crowd(input);
    let begun = state.change("cg_crowd_begin_push", unsafe {
        cg_crowd_begin_push(crowd, t)
    });
    for _ in 0..input.below(5) {
        let states = fuzzed_states(state, input);
        let count = states.len();
        let crowd = state.crowd(input);
        let pointer = array_pointer(&states, input);
        state.change("cg_crowd_push_range", unsafe {
            cg_crowd_push_range(crowd, pointer, count)
        });
    }
    let crowd = state.crowd(input);
    state.change("cg_crowd_end_push", unsafe { cg_crowd_end_push(crowd) });
    state.change("cg_crowd_end_push", unsafe {
        cg_crowd_end_push(state.crowd)
    });
    if begun == cg_status::Ok {
        state.time = t;
    }
}

pub fn step(state: &mut State, input: &mut Input) {
    let dt = input.float_or(1.0 / 30.0);
    let crowd = state.crowd(input);
    state.change("cg_crowd_step", unsafe { cg_crowd_step(crowd, dt) });
}

/// A step split into ranges: `cg_crowd_begin_step`, up to four `cg_crowd_step_range`
/// calls on fuzzed ranges (overlapping, empty, past the end, before a begin that failed),
/// then `cg_crowd_end_step` (on a fuzzed handle, then on the real one, so that the step is
/// closed whatever happened). Nothing else runs while the step is open.
pub fn ranged_step(state: &mut State, input: &mut Input) {
    let dt = input.float_or(1.0 / 30.0);
    let crowd = state.crowd(input);
    state.change("cg_crowd_begin_step", unsafe {
        cg_crowd_begin_step(crowd, dt)
    });
    for _ in 0..input.below(5) {
        let first = if input.rare() {
            input.u32()
        } else {
            input.below(64)
        };
        let count = if input.rare() {
            input.u32()
        } else {
            input.below(64)
        };
        let crowd = state.crowd(input);
        state.change("cg_crowd_step_range", unsafe {
            cg_crowd_step_range(crowd, first, count)
        });
    }
    let crowd = state.crowd(input);
    state.change("cg_crowd_end_step", unsafe { cg_crowd_end_step(crowd) });
    state.change("cg_crowd_end_step", unsafe {
        cg_crowd_end_step(state.crowd)
    });
}

/// A frame of a walking crowd: every live entity moves along x in its own lane, some of
/// them talking, then a step of 1/30 s. Drives the simulation forward with valid calls.
pub fn walk(state: &mut State, input: &mut Input) {
    let t = state.time + 1.0 / 30.0;
    let mut states: Vec<cg_entity_state> = state
        .live
        .iter()
        .enumerate()
        .map(|(lane, &id)| {
            let mut entity: cg_entity_state =
                init(state, "cg_entity_state_init", cg_entity_state_init);
            entity.id = id;
            entity.flags = CG_STATE_HEADING_FROM_MOTION;
            entity.position.x = (lane as f32 * 1.3 + t as f32 * 1.2) % 20.0 - 10.0;
            entity.position.z = lane as f32 * 0.7 - 4.0 + input.float() / 16.0;
            entity
        })
        .collect();
    talking(&mut states, input);
    let status = state.change("cg_crowd_push_frame", unsafe {
        cg_crowd_push_frame(state.crowd, t, states.as_ptr(), states.len())
    });
    if status == cg_status::Ok {
        state.time = t;
    }
    state.change("cg_crowd_step", unsafe {
        cg_crowd_step(state.crowd, 1.0 / 30.0)
    });
}

pub fn read_gaze(state: &mut State, input: &mut Input) {
    let mut out = sentinel::<cg_gaze_info>(input.count(20));
    let mut written = sentinel::<usize>(1);
    let crowd = state.crowd(input);
    let pointer = or_null(out.as_mut_ptr(), input);
    let written_pointer = if input.below(4) == 3 {
        null_mut()
    } else {
        written.as_mut_ptr()
    };
    let status = state.call("cg_crowd_read_gaze", unsafe {
        cg_crowd_read_gaze(crowd, pointer, out.len(), written_pointer)
    });
    let filled = if written_pointer.is_null() {
        0
    } else {
        written[0]
    };
    if status == cg_status::Ok {
        assert!(
            filled <= out.len(),
            "cg_crowd_read_gaze wrote {filled} > count"
        );
    }
    state.outputs("cg_crowd_read_gaze", status, &out, filled);
}

pub fn score(state: &mut State, input: &mut Input) {
    let (character, entity) = (state.id(input), state.id(input));
    let mut out = sentinel::<cg_score_breakdown>(1);
    let crowd = state.crowd(input);
    let pointer = or_null(out.as_mut_ptr(), input);
    let status = state.call("cg_crowd_score", unsafe {
        cg_crowd_score(crowd, character, entity, pointer)
    });
    state.outputs("cg_crowd_score", status, &out, 1);
}

pub fn get_character_params(state: &mut State, input: &mut Input) {
    let id = state.id(input);
    let mut out = sized_sentinel::<cg_character_params>();
    let crowd = state.crowd(input);
    let pointer = or_null(out.as_mut_ptr(), input);
    let status = state.call("cg_crowd_get_character_params", unsafe {
        cg_crowd_get_character_params(crowd, id, pointer)
    });
    state.versioned_output("cg_crowd_get_character_params", status, &out);
}

pub fn set_character_params(state: &mut State, input: &mut Input) {
    let id = state.id(input);
    let mut params = cg_character_params {
        struct_size: size_of::<cg_character_params>() as u32,
        weight_proximity: 0.25,
        weight_speed: 0.25,
        weight_orientation: 0.25,
        weight_periphery: 0.25,
        attention_fraction: 0.4,
        attention_model: 0,
    };
    let status = unsafe { cg_crowd_get_character_params(state.crowd, id, &mut params) };
    state.call("cg_crowd_get_character_params", status);
    for _ in 0..input.below(3) {
        match input.below(7) {
            0 => params.weight_proximity = input.float(),
            1 => params.weight_speed = input.float(),
            2 => params.weight_orientation = input.float(),
            3 => params.weight_periphery = input.float(),
            4 => params.attention_fraction = input.float(),
            5 => params.attention_model = input.below(4),
            _ => params.struct_size = input.struct_size(size_of::<cg_character_params>()),
        }
    }
    let crowd = state.crowd(input);
    let pointer = pointer_to(&params, input);
    state.change("cg_crowd_set_character_params", unsafe {
        cg_crowd_set_character_params(crowd, id, pointer)
    });
}

pub fn set_impact(state: &mut State, input: &mut Input) {
    let id = state.id(input);
    let impact = input.positive();
    let crowd = state.crowd(input);
    state.change("cg_crowd_set_impact", unsafe {
        cg_crowd_set_impact(crowd, id, impact)
    });
}

pub fn plan(state: &mut State, input: &mut Input) {
    let crowd = state.crowd(input);
    state.change("cg_crowd_plan", unsafe { cg_crowd_plan(crowd) });
}

pub fn clear_plan(state: &mut State, input: &mut Input) {
    let crowd = state.crowd(input);
    state.change("cg_crowd_clear_plan", unsafe { cg_crowd_clear_plan(crowd) });
}

pub fn read_constraints(state: &mut State, input: &mut Input) {
    let id = state.id(input);
    let mut out = sentinel::<cg_constraint>(input.count(8));
    let mut total = sentinel::<usize>(1);
    let crowd = state.crowd(input);
    let pointer = or_null(out.as_mut_ptr(), input);
    let total_pointer = or_null(total.as_mut_ptr(), input);
    let status = state.call("cg_crowd_read_constraints", unsafe {
        cg_crowd_read_constraints(crowd, id, pointer, out.len(), total_pointer)
    });
    let filled = if total_pointer.is_null() { 0 } else { total[0] };
    state.outputs("cg_crowd_read_constraints", status, &out, filled);
}

pub fn set_viewer(state: &mut State, input: &mut Input) {
    let position = point(input, 1.6);
    let impact = input.float_or(1.0);
    let crowd = state.crowd(input);
    let pointer = pointer_to(&position, input);
    let mut id = sentinel::<u32>(1);
    let out = if input.below(4) == 3 {
        null_mut()
    } else {
        id.as_mut_ptr()
    };
    let status = state.change("cg_crowd_set_viewer", unsafe {
        cg_crowd_set_viewer(crowd, pointer, impact, out)
    });
    state.outputs(
        "cg_crowd_set_viewer",
        status,
        &id,
        if out.is_null() { 0 } else { 1 },
    );
    if status == cg_status::Ok && !out.is_null() {
        state.viewer = Some(id[0]);
        added(state, status, out, id[0]);
    }
}

pub fn set_attention_period(state: &mut State, input: &mut Input) {
    let id = state.id(input);
    let period = input.choice(70);
    let crowd = state.crowd(input);
    state.change("cg_crowd_set_attention_period", unsafe {
        cg_crowd_set_attention_period(crowd, id, period)
    });
}

pub fn set_gaze_target(state: &mut State, input: &mut Input) {
    let character = state.id(input);
    let mut target: cg_gaze_target = init(state, "cg_gaze_target_init", cg_gaze_target_init);
    target.struct_size = input.struct_size(size_of::<cg_gaze_target>());
    target.kind = input.choice(2);
    target.priority = input.choice(2);
    target.entity = state.id(input);
    target.point = point(input, 1.6);
    let crowd = state.crowd(input);
    let pointer = pointer_to(&target, input);
    state.change("cg_crowd_set_gaze_target", unsafe {
        cg_crowd_set_gaze_target(crowd, character, pointer)
    });
}

pub fn clear_gaze_target(state: &mut State, input: &mut Input) {
    let id = state.id(input);
    let crowd = state.crowd(input);
    state.change("cg_crowd_clear_gaze_target", unsafe {
        cg_crowd_clear_gaze_target(crowd, id)
    });
}

/// `count` joint rotations, mostly `HUMAN_JOINTS`.
fn pose(input: &mut Input, count: usize) -> Vec<cg_quat> {
    (0..count).map(|_| quat(input)).collect()
}

pub fn set_base_pose(state: &mut State, input: &mut Input) {
    let id = state.id(input);
    let count = input.count_or(HUMAN_JOINTS, 16);
    let local = pose(input, count);
    let crowd = state.crowd(input);
    let pointer = array_pointer(&local, input);
    state.change("cg_crowd_set_base_pose", unsafe {
        cg_crowd_set_base_pose(crowd, id, pointer, count)
    });
}

pub fn set_base_poses(state: &mut State, input: &mut Input) {
    let characters: Vec<u32> = (0..input.count(4)).map(|_| state.id(input)).collect();
    let count = input.count_or(characters.len() * HUMAN_JOINTS, 50);
    let local = pose(input, count);
    let crowd = state.crowd(input);
    let ids = array_pointer(&characters, input);
    let pointer = array_pointer(&local, input);
    state.change("cg_crowd_set_base_poses", unsafe {
        cg_crowd_set_base_poses(crowd, ids, characters.len(), pointer, count)
    });
}

/// A character range: mostly small, rarely any values (overflowing `first + count`).
fn range(input: &mut Input) -> (u32, u32) {
    if input.rare() {
        (input.u32(), input.u32())
    } else {
        (input.below(14), input.below(14))
    }
}

pub fn joint_total(state: &mut State, input: &mut Input) {
    let (first, count) = range(input);
    let mut total = sentinel::<usize>(1);
    let crowd = state.crowd(input);
    let pointer = or_null(total.as_mut_ptr(), input);
    let status = state.call("cg_crowd_joint_total", unsafe {
        cg_crowd_joint_total(crowd, first, count, pointer)
    });
    state.outputs("cg_crowd_joint_total", status, &total, 1);
}

/// `cg_crowd_read_joints` or `cg_crowd_read_joint_deltas`.
fn read_joints(
    state: &mut State,
    input: &mut Input,
    function: &str,
    read: unsafe extern "C" fn(*const cg_crowd, u32, u32, *mut cg_quat, usize) -> cg_status,
) {
    let (first, count) = range(input);
    let length = input.count_or((count as usize).min(16) * HUMAN_JOINTS, 255);
    let mut out = sentinel::<cg_quat>(length);
    let crowd = state.crowd(input);
    let pointer = or_null(out.as_mut_ptr(), input);
    let status = state.call(function, unsafe {
        read(crowd, first, count, pointer, length)
    });
    let mut total = 0;
    if status == cg_status::Ok {
        let total_status = unsafe { cg_crowd_joint_total(crowd, first, count, &mut total) };
        assert_eq!(
            total_status,
            cg_status::Ok,
            "{function} succeeded on that range"
        );
    }
    state.outputs(function, status, &out, total);
}

pub fn read_joint_rotations(state: &mut State, input: &mut Input) {
    read_joints(state, input, "cg_crowd_read_joints", cg_crowd_read_joints);
}

pub fn read_joint_deltas(state: &mut State, input: &mut Input) {
    read_joints(
        state,
        input,
        "cg_crowd_read_joint_deltas",
        cg_crowd_read_joint_deltas,
    );
}

pub fn read_eyes(state: &mut State, input: &mut Input) {
    let (first, count) = range(input);
    let length = input.count_or((count as usize).min(16), 20);
    let mut out = sentinel::<cg_eye_info>(length);
    let crowd = state.crowd(input);
    let pointer = or_null(out.as_mut_ptr(), input);
    let status = state.call("cg_crowd_read_eyes", unsafe {
        cg_crowd_read_eyes(crowd, first, count, pointer, length)
    });
    state.outputs("cg_crowd_read_eyes", status, &out, count as usize);
}

pub fn read_eyelids(state: &mut State, input: &mut Input) {
    let (first, count) = range(input);
    let length = input.count_or((count as usize).min(16), 20);
    let mut out = sentinel::<cg_eyelids>(length);
    let crowd = state.crowd(input);
    let pointer = or_null(out.as_mut_ptr(), input);
    let status = state.call("cg_crowd_read_eyelids", unsafe {
        cg_crowd_read_eyelids(crowd, first, count, pointer, length)
    });
    state.outputs("cg_crowd_read_eyelids", status, &out, count as usize);
}

pub fn character_count(state: &mut State, input: &mut Input) {
    let mut count = sentinel::<usize>(1);
    let crowd = state.crowd(input);
    let pointer = or_null(count.as_mut_ptr(), input);
    let status = state.call("cg_crowd_character_count", unsafe {
        cg_crowd_character_count(crowd, pointer)
    });
    state.outputs("cg_crowd_character_count", status, &count, 1);
}

pub fn get_config(state: &mut State, input: &mut Input) {
    let mut config = sized_sentinel::<cg_crowd_config>();
    let crowd = state.crowd(input);
    let pointer = or_null(config.as_mut_ptr(), input);
    let status = state.call("cg_crowd_get_config", unsafe {
        cg_crowd_get_config(crowd, pointer)
    });
    state.versioned_output("cg_crowd_get_config", status, &config);
}

pub fn chain_init(state: &mut State, input: &mut Input) {
    let (up, forward) = (input.below(8), input.below(8));
    let mut chain = sized_sentinel::<cg_chain_desc>();
    let pointer = or_null(chain.as_mut_ptr(), input);
    let status = state.call("cg_chain_desc_init_human", unsafe {
        cg_chain_desc_init_human(pointer, up, forward)
    });
    state.versioned_output("cg_chain_desc_init_human", status, &chain);
}

/// `cg_crowd_set_conversation`: 2 to 8 members mostly, rarely too few or too many or an
/// impossible count; the ids from [`State::id`] (live entities mostly, objects among them,
/// sometimes the viewer, removed or unknown ids; repeats by chance). Records the group on
/// success.
pub fn set_conversation(state: &mut State, input: &mut Input) {
    let count = match input.below(16) {
        15 => usize::MAX,
        14 => input.below(11) as usize,
        n => 2 + n as usize % 7,
    };
    // SIZE_MAX is refused before any member is read: 10 ids stand for it.
    let members: Vec<u32> = (0..count.min(10)).map(|_| state.id(input)).collect();
    let crowd = state.crowd(input);
    let pointer = array_pointer(&members, input);
    let mut group = sentinel::<u32>(1);
    let out = or_null(group.as_mut_ptr(), input);
    let function = "cg_crowd_set_conversation";
    let status = state.change(function, unsafe {
        cg_crowd_set_conversation(crowd, pointer, count, out)
    });
    state.outputs(function, status, &group, 1);
    if status == cg_status::Ok {
        assert!(
            !state.conversations.contains(&group[0]),
            "{function} returned the id {} of an earlier group",
            group[0]
        );
        state.conversations.push(group[0]);
    }
}

/// `cg_crowd_remove_conversation` of a group the crowd returned (live or ended) mostly.
pub fn remove_conversation(state: &mut State, input: &mut Input) {
    let group = state.conversation(input);
    let crowd = state.crowd(input);
    state.change("cg_crowd_remove_conversation", unsafe {
        cg_crowd_remove_conversation(crowd, group)
    });
}

/// The street model's and gaze following's settings of a new crowd's config (read after
/// the conversations', so that earlier inputs decode as they did): the street preset in the
/// config's units, any values (and any `follow_enabled`), or following as strong and as
/// short-lived as allowed, every glance a cue as strong as a stare.
fn street_settings(state: &State, config: &mut cg_crowd_config, input: &mut Input) {
    match input.below(8) {
        7 => {
            config.follow_enabled = input.below(3);
            let fields: [&mut f32; 25] = [
                &mut config.street_view_half_angle,
                &mut config.street_first_fixation_probability,
                &mut config.street_latency_min,
                &mut config.street_latency_max,
                &mut config.street_fixation_median,
                &mut config.street_fixation_log_spread,
                &mut config.street_refixation_probability,
                &mut config.street_refixation_gap_min,
                &mut config.street_refixation_gap_max,
                &mut config.street_civil_distance,
                &mut config.street_civil_look_probability,
                &mut config.street_path_look_distance,
                &mut config.street_civil_look_distance,
                &mut config.follow_one_looker_probability,
                &mut config.follow_max_probability,
                &mut config.follow_distance,
                &mut config.follow_view_half_angle,
                &mut config.follow_oncoming_weight,
                &mut config.follow_glance_cue_weight,
                &mut config.follow_glance_min,
                &mut config.follow_glance_max,
                &mut config.follow_forget_time,
                &mut config.street_miss_after,
                &mut config.follow_reaction_min,
                &mut config.follow_reaction_max,
            ];
            for field in fields {
                *field = input.float();
            }
        }
        6 => {
            let street = init(
                state,
                "cg_crowd_config_init_street",
                cg_crowd_config_init_street,
            );
            let units = config.units_per_metre;
            config.follow_enabled = street.follow_enabled;
            config.max_distance = street.max_distance * units;
            config.follow_distance = street.follow_distance * units;
            config.street_civil_distance = street.street_civil_distance * units;
            config.street_path_look_distance = street.street_path_look_distance * units;
            config.street_civil_look_distance = street.street_civil_look_distance * units;
        }
        5 => {
            config.follow_enabled = 1;
            config.follow_one_looker_probability = 1.0;
            config.follow_max_probability = 1.0;
            config.follow_view_half_angle = std::f32::consts::PI;
            config.follow_oncoming_weight = 1.0;
            config.follow_glance_cue_weight = 1.0;
            config.follow_glance_min = 0.0;
            config.follow_glance_max = 1e-3;
            config.follow_forget_time = 0.0;
            config.follow_reaction_min = 0.0;
            config.follow_reaction_max = 0.0;
            config.street_miss_after = 0.0;
            config.street_first_fixation_probability = 1.0;
            config.street_refixation_probability = 1.0;
            config.street_latency_min = 0.0;
            config.street_latency_max = 0.0;
        }
        _ => {}
    }
}

/// `cg_crowd_read_following`: `*out_following` must be 0 or 1, the point the origin when
/// not following, and a glance count no larger than the steps taken allow.
pub fn read_following(state: &mut State, input: &mut Input) {
    let id = state.id(input);
    let mut point = sentinel::<cg_vec3>(1);
    let mut flags = sentinel::<u32>(2);
    let crowd = state.crowd(input);
    let point_out = or_null(point.as_mut_ptr(), input);
    let following_out = or_null(flags.as_mut_ptr(), input);
    let glances_out = or_null(flags[1..].as_mut_ptr(), input);
    let function = "cg_crowd_read_following";
    let status = state.call(function, unsafe {
        cg_crowd_read_following(crowd, id, point_out, following_out, glances_out)
    });
    state.outputs(function, status, &point, 1);
    state.outputs(function, status, &flags, 2);
    if status == cg_status::Ok {
        assert!(
            flags[0] <= 1,
            "{function}({id}) gave following {}",
            flags[0]
        );
        if flags[0] == 0 {
            assert_eq!(
                (point[0].x, point[0].y, point[0].z),
                (0.0, 0.0, 0.0),
                "{function}({id}): a point while not following"
            );
        }
    }
}

/// `cg_crowd_get_conversation`, whose group must be `CG_NO_TARGET` or one the crowd
/// returned.
pub fn get_conversation(state: &mut State, input: &mut Input) {
    let id = state.id(input);
    let mut group = sentinel::<u32>(1);
    let crowd = state.crowd(input);
    let out = or_null(group.as_mut_ptr(), input);
    let function = "cg_crowd_get_conversation";
    let status = state.call(function, unsafe {
        cg_crowd_get_conversation(crowd, id, out)
    });
    state.outputs(function, status, &group, 1);
    if status == cg_status::Ok {
        assert!(
            group[0] == CG_NO_TARGET || state.conversations.contains(&group[0]),
            "{function}({id}) gave {}, a group the crowd never returned",
            group[0]
        );
    }
}
