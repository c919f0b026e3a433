//! The crowd-attention C entry points seen from C's side: statuses for NULL and bad input,
//! unit conversion at the edge, and "a failed call changes nothing".

// The `unsafe { cg_... }` calls below pass pointers to live values of the sizes the header
// asks for, or deliberately bad ones (NULL, misaligned, wrong struct_size) that the library
// must refuse: that is their safety comment, once for the file.
#![allow(clippy::undocumented_unsafe_blocks)]

use crowdgaze::ffi::attention::*;

use crowdgaze::ffi::crowd::*;
use crowdgaze::ffi::frame::*;
use crowdgaze::ffi::last_error::last_error_message;
use crowdgaze::ffi::status::cg_status;
use crowdgaze::ffi::types::cg_vec3;
use std::mem::MaybeUninit;
use std::ptr::{null, null_mut};

fn crowd(units_per_metre: f32, recorded: u32) -> *mut cg_crowd {
    let mut config = MaybeUninit::<cg_crowd_config>::uninit();
    // SAFETY: a versioned struct starts with its `uint32_t struct_size`, set before the call.
    unsafe {
        config
            .as_mut_ptr()
            .cast::<u32>()
            .write(std::mem::size_of::<cg_crowd_config>() as u32)
    };
    assert_eq!(
        unsafe { cg_crowd_config_init(config.as_mut_ptr()) },
        cg_status::Ok
    );
    // SAFETY: initialised above.
    let mut config = unsafe { config.assume_init() };
    config.units_per_metre = units_per_metre;
    config.max_distance = 10.0 * units_per_metre;
    config.restart_distance = 0.5 * units_per_metre;
    config.max_characters = 4;
    config.max_objects = 1;
    config.max_recorded_states = recorded;
    let mut handle = null_mut();
    assert_eq!(
        unsafe { cg_crowd_create(&config, &mut handle) },
        cg_status::Ok
    );
    handle
}

fn character(handle: *mut cg_crowd, x: f32, z: f32, heading: f32) -> u32 {
    let mut desc = MaybeUninit::<cg_character_desc>::uninit();
    // SAFETY: a versioned struct starts with its `uint32_t struct_size`, set before the call.
    unsafe {
        desc.as_mut_ptr()
            .cast::<u32>()
            .write(std::mem::size_of::<cg_character_desc>() as u32)
    };
    assert_eq!(
        unsafe { cg_character_desc_init(desc.as_mut_ptr()) },
        cg_status::Ok
    );
    // SAFETY: initialised above.
    let mut desc = unsafe { desc.assume_init() };
    desc.position = cg_vec3 { x, y: 0.0, z };
    desc.heading = heading;
    let mut id = 0;
    assert_eq!(
        unsafe { cg_crowd_add_character(handle, &desc, &mut id) },
        cg_status::Ok
    );
    id
}

fn state(id: u32, x: f32, z: f32) -> cg_entity_state {
    let mut state = MaybeUninit::<cg_entity_state>::uninit();
    // SAFETY: a versioned struct starts with its `uint32_t struct_size`, set before the call.
    unsafe {
        state
            .as_mut_ptr()
            .cast::<u32>()
            .write(std::mem::size_of::<cg_entity_state>() as u32)
    };
    assert_eq!(
        unsafe { cg_entity_state_init(state.as_mut_ptr()) },
        cg_status::Ok
    );
    // SAFETY: initialised above.
    let mut state = unsafe { state.assume_init() };
    state.id = id;
    state.position = cg_vec3 { x, y: 0.0, z };
    state
}

fn gaze(handle: *const cg_crowd) -> Vec<cg_gaze_info> {
    let mut out = vec![cg_gaze_info::default(); 4];
    let mut written = 0;
    assert_eq!(
        unsafe { cg_crowd_read_gaze(handle, out.as_mut_ptr(), out.len(), &mut written) },
        cg_status::Ok
    );
    out.truncate(written);
    out
}

#[test]
fn null_arguments_are_rejected() {
    let handle = crowd(1.0, 0);
    let a = character(handle, 0.0, 0.0, 0.0);
    let mut id = 0;
    let mut desc = MaybeUninit::<cg_character_desc>::uninit();
    // SAFETY: a versioned struct starts with its `uint32_t struct_size`, set before the call.
    unsafe {
        desc.as_mut_ptr()
            .cast::<u32>()
            .write(std::mem::size_of::<cg_character_desc>() as u32)
    };
    assert_eq!(
        unsafe { cg_character_desc_init(null_mut()) },
        cg_status::NullArgument
    );
    assert_eq!(
        unsafe { cg_object_desc_init(null_mut()) },
        cg_status::NullArgument
    );
    assert_eq!(
        unsafe { cg_entity_state_init(null_mut()) },
        cg_status::NullArgument
    );
    assert_eq!(
        unsafe { cg_character_desc_init(desc.as_mut_ptr()) },
        cg_status::Ok
    );
    assert_eq!(
        unsafe { cg_crowd_add_character(null_mut(), desc.as_ptr(), &mut id) },
        cg_status::NullArgument
    );
    assert_eq!(
        unsafe { cg_crowd_add_character(handle, null(), &mut id) },
        cg_status::NullArgument
    );
    assert_eq!(
        unsafe { cg_crowd_add_character(handle, desc.as_ptr(), null_mut()) },
        cg_status::NullArgument
    );
    assert_eq!(
        unsafe { cg_crowd_add_object(handle, null(), &mut id) },
        cg_status::NullArgument
    );
    assert_eq!(
        unsafe { cg_crowd_remove_entity(null_mut(), a) },
        cg_status::NullArgument
    );
    assert_eq!(
        unsafe { cg_crowd_character_count(handle, null_mut()) },
        cg_status::NullArgument
    );
    assert_eq!(
        unsafe { cg_crowd_push_frame(handle, 0.0, null(), 3) },
        cg_status::NullArgument
    );
    assert_eq!(
        unsafe { cg_crowd_push_frame(handle, 0.0, null(), 0) },
        cg_status::Ok
    );
    assert_eq!(
        unsafe { cg_crowd_step(null_mut(), 0.1) },
        cg_status::NullArgument
    );
    assert_eq!(
        unsafe { cg_crowd_read_gaze(handle, null_mut(), 2, null_mut()) },
        cg_status::NullArgument
    );
    assert_eq!(
        unsafe { cg_crowd_read_gaze(handle, null_mut(), 0, null_mut()) },
        cg_status::Ok
    );
    assert_eq!(
        unsafe { cg_crowd_score(handle, a, a, null_mut()) },
        cg_status::NullArgument
    );
    assert_eq!(
        unsafe { cg_crowd_get_character_params(handle, a, null_mut()) },
        cg_status::NullArgument
    );
    assert_eq!(
        unsafe { cg_crowd_set_character_params(handle, a, null()) },
        cg_status::NullArgument
    );
    assert_eq!(
        unsafe { cg_crowd_plan(null_mut()) },
        cg_status::NullArgument
    );
    assert_eq!(
        unsafe { cg_crowd_clear_plan(null_mut()) },
        cg_status::NullArgument
    );
    assert_eq!(
        unsafe { cg_crowd_read_constraints(null(), a, null_mut(), 0, null_mut()) },
        cg_status::NullArgument
    );
    assert!(last_error_message().contains("NULL"));
    unsafe { cg_crowd_destroy(handle) };
}

#[test]
fn bad_values_fail_and_change_nothing() {
    let handle = crowd(1.0, 0);
    let a = character(handle, 0.0, 0.0, 0.0);
    let b = character(handle, 0.0, 3.0, std::f32::consts::PI);
    let good = [state(a, 0.0, 0.0), state(b, 0.0, 3.0)];
    assert_eq!(
        unsafe { cg_crowd_push_frame(handle, 1.0, good.as_ptr(), 2) },
        cg_status::Ok
    );
    assert_eq!(unsafe { cg_crowd_step(handle, 0.1) }, cg_status::Ok);
    let before = gaze(handle);

    let mut bad = good;
    bad[1].position.x = f32::NAN;
    assert_eq!(
        unsafe { cg_crowd_push_frame(handle, 2.0, bad.as_ptr(), 2) },
        cg_status::NonFinite
    );
    let mut unknown = good;
    unknown[1].id = 12345;
    assert_eq!(
        unsafe { cg_crowd_push_frame(handle, 2.0, unknown.as_ptr(), 2) },
        cg_status::NotFound
    );
    assert_eq!(
        unsafe { cg_crowd_push_frame(handle, 0.5, good.as_ptr(), 2) },
        cg_status::InvalidArgument
    );
    assert_eq!(
        unsafe { cg_crowd_push_frame(handle, f64::NAN, good.as_ptr(), 2) },
        cg_status::NonFinite
    );
    let mut wrong_size = good;
    wrong_size[0].struct_size = 8;
    assert_eq!(
        unsafe { cg_crowd_push_frame(handle, 2.0, wrong_size.as_ptr(), 2) },
        cg_status::BadStructSize
    );
    let mut flags = good;
    flags[0].flags = 0x80;
    assert_eq!(
        unsafe { cg_crowd_push_frame(handle, 2.0, flags.as_ptr(), 2) },
        cg_status::InvalidArgument
    );
    assert_eq!(
        unsafe { cg_crowd_step(handle, f32::INFINITY) },
        cg_status::NonFinite
    );
    assert_eq!(
        unsafe { cg_crowd_step(handle, -1.0) },
        cg_status::InvalidArgument
    );
    assert_eq!(
        unsafe { cg_crowd_set_impact(handle, a, -1.0) },
        cg_status::InvalidArgument
    );
    assert_eq!(
        unsafe { cg_crowd_set_impact(handle, 999, 1.0) },
        cg_status::NotFound
    );

    let mut params = MaybeUninit::<cg_character_params>::uninit();
    // SAFETY: a versioned struct starts with its `uint32_t struct_size`, set before the call.
    unsafe {
        params
            .as_mut_ptr()
            .cast::<u32>()
            .write(std::mem::size_of::<cg_character_params>() as u32)
    };
    assert_eq!(
        unsafe { cg_crowd_get_character_params(handle, a, params.as_mut_ptr()) },
        cg_status::Ok
    );
    // SAFETY: written above.
    let params = unsafe { params.assume_init() };
    let negative = cg_character_params {
        weight_speed: -1.0,
        ..params
    };
    assert_eq!(
        unsafe { cg_crowd_set_character_params(handle, a, &negative) },
        cg_status::InvalidArgument
    );
    let fraction = cg_character_params {
        attention_fraction: 2.0,
        ..params
    };
    assert_eq!(
        unsafe { cg_crowd_set_character_params(handle, a, &fraction) },
        cg_status::InvalidArgument
    );
    let nan = cg_character_params {
        weight_orientation: f32::NAN,
        ..params
    };
    assert_eq!(
        unsafe { cg_crowd_set_character_params(handle, a, &nan) },
        cg_status::NonFinite
    );
    let mut again = MaybeUninit::<cg_character_params>::uninit();
    // SAFETY: a versioned struct starts with its `uint32_t struct_size`, set before the call.
    unsafe {
        again
            .as_mut_ptr()
            .cast::<u32>()
            .write(std::mem::size_of::<cg_character_params>() as u32)
    };
    assert_eq!(
        unsafe { cg_crowd_get_character_params(handle, a, again.as_mut_ptr()) },
        cg_status::Ok
    );
    // SAFETY: written above.
    let again = unsafe { again.assume_init() };
    assert_eq!(again.weight_speed, params.weight_speed);
    assert_eq!(again.attention_fraction, params.attention_fraction);

    assert_eq!(unsafe { cg_crowd_plan(handle) }, cg_status::WrongState);
    assert_eq!(
        unsafe { cg_crowd_read_constraints(handle, a, null_mut(), 0, null_mut()) },
        cg_status::WrongState
    );
    let mut out = cg_score_breakdown::default();
    assert_eq!(
        unsafe { cg_crowd_score(handle, a, 4242, &mut out) },
        cg_status::NotFound
    );

    // Nothing above changed the crowd.
    let after = gaze(handle);
    assert_eq!(before.len(), after.len());
    for (x, y) in before.iter().zip(&after) {
        assert_eq!(x.target, y.target);
        assert_eq!(x.target_position.x, y.target_position.x);
        assert_eq!(x.s_max, y.s_max);
    }
    // Capacity.
    let _c = character(handle, 5.0, 0.0, 0.0);
    let _d = character(handle, 6.0, 0.0, 0.0);
    let mut desc = MaybeUninit::<cg_character_desc>::uninit();
    // SAFETY: a versioned struct starts with its `uint32_t struct_size`, set before the call.
    unsafe {
        desc.as_mut_ptr()
            .cast::<u32>()
            .write(std::mem::size_of::<cg_character_desc>() as u32)
    };
    assert_eq!(
        unsafe { cg_character_desc_init(desc.as_mut_ptr()) },
        cg_status::Ok
    );
    let mut id = 0;
    assert_eq!(
        unsafe { cg_crowd_add_character(handle, desc.as_ptr(), &mut id) },
        cg_status::Capacity
    );
    assert_eq!(unsafe { cg_crowd_remove_entity(handle, a) }, cg_status::Ok);
    assert_eq!(
        unsafe { cg_crowd_remove_entity(handle, a) },
        cg_status::NotFound
    );
    unsafe { cg_crowd_destroy(handle) };
}

#[test]
fn lengths_are_converted_at_the_edge() {
    // The same scene in metres and in centimetres gives the same scores and angles.
    let mut results = Vec::new();
    for units in [1.0f32, 100.0] {
        let handle = crowd(units, 0);
        let a = character(handle, 0.0, 0.0, 0.0);
        let b = character(handle, 0.5 * units, 2.0 * units, std::f32::consts::PI);
        let states = [state(a, 0.0, 0.0), state(b, 0.5 * units, 2.0 * units)];
        assert_eq!(
            unsafe { cg_crowd_push_frame(handle, 0.0, states.as_ptr(), 2) },
            cg_status::Ok
        );
        let moved = [
            state(a, 0.0, 0.1 * units),
            state(b, 0.5 * units, 1.9 * units),
        ];
        assert_eq!(
            unsafe { cg_crowd_push_frame(handle, 0.1, moved.as_ptr(), 2) },
            cg_status::Ok
        );
        let mut score = cg_score_breakdown::default();
        assert_eq!(
            unsafe { cg_crowd_score(handle, a, b, &mut score) },
            cg_status::Ok
        );
        assert!((score.distance / units - (0.25f32 + 1.8 * 1.8).sqrt()).abs() < 1e-4);
        assert!((score.relative_speed / units - 2.0).abs() < 1e-3);
        assert_eq!(score.pruned, 0);
        results.push((score.total, score.view_angle, score.proximity));
        assert_eq!(unsafe { cg_crowd_step(handle, 0.1) }, cg_status::Ok);
        let g = gaze(handle);
        assert!(
            g[0].target_position.y > 1.0 * units,
            "eye height in caller units"
        );
        unsafe { cg_crowd_destroy(handle) };
    }
    assert!((results[0].0 - results[1].0).abs() < 1e-5);
    assert!((results[0].1 - results[1].1).abs() < 1e-5);
}

#[test]
fn offline_planning_through_the_c_api() {
    let handle = crowd(1.0, 2000);
    let a = character(handle, 0.0, 0.0, 0.0);
    let b = character(handle, 0.0, 6.0, std::f32::consts::PI);
    for frame in 0..200 {
        let t = f64::from(frame) / 30.0;
        let offset = t as f32;
        let mut states = [state(a, 0.0, offset), state(b, 0.0, 6.0 - offset)];
        for s in &mut states {
            s.flags = CG_STATE_HEADING_FROM_MOTION;
        }
        assert_eq!(
            unsafe { cg_crowd_push_frame(handle, t, states.as_ptr(), 2) },
            cg_status::Ok
        );
    }
    assert_eq!(unsafe { cg_crowd_plan(handle) }, cg_status::Ok);
    assert_eq!(unsafe { cg_crowd_plan(handle) }, cg_status::WrongState);
    let mut total = 0;
    assert_eq!(
        unsafe { cg_crowd_read_constraints(handle, a, null_mut(), 0, &mut total) },
        cg_status::Ok
    );
    let mut constraints = vec![cg_constraint::default(); total];
    assert_eq!(
        unsafe {
            cg_crowd_read_constraints(handle, a, constraints.as_mut_ptr(), total, &mut total)
        },
        cg_status::Ok
    );
    assert!(constraints.iter().all(|k| k.entity == b && k.end > k.begin));
    let states = [state(a, 0.0, 0.0)];
    assert_eq!(
        unsafe { cg_crowd_push_frame(handle, 99.0, states.as_ptr(), 1) },
        cg_status::WrongState
    );
    assert_eq!(unsafe { cg_crowd_clear_plan(handle) }, cg_status::Ok);
    assert_eq!(
        unsafe { cg_crowd_push_frame(handle, 99.0, states.as_ptr(), 1) },
        cg_status::Ok
    );
    unsafe { cg_crowd_destroy(handle) };
}
