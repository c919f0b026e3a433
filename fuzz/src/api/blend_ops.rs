//! Operations on dual quaternions, the blend functions and the view blender.

use super::crowd_ops::init;
use super::input::Input;
use super::outputs::sentinel;
use super::outputs::Output;
use super::values::{dualquat, dualquats, point, quat, vec3, weight};
use super::{array_pointer, or_null, pointer_to, rigid, State};
use crowdgaze::ffi::blend::*;
use crowdgaze::ffi::status::cg_status;
use crowdgaze::ffi::types::{cg_dualquat, cg_quat, cg_vec3};
use crowdgaze::ffi::view_blender::*;
use std::mem::size_of;
use std::ptr::null_mut;

/// Creates the blender every run starts with: 2 joints, 3 keys, DLB.
pub fn first_blender(state: &mut State) {
    let mut config: cg_view_blender_config = init(
        state,
        "cg_view_blender_config_init",
        cg_view_blender_config_init,
    );
    config.joint_count = 2;
    config.key_count = 3;
    let status = unsafe { cg_view_blender_create(&config, &mut state.blender) };
    assert_eq!(state.call("cg_view_blender_create", status), cg_status::Ok);
    state.blend_joints = 2;
    state.blend_keys = 3;
}

/// A new blender from a fuzzed config; it replaces the current one on success.
pub fn create(state: &mut State, input: &mut Input) {
    let mut config: cg_view_blender_config = init(
        state,
        "cg_view_blender_config_init",
        cg_view_blender_config_init,
    );
    config.struct_size = input.struct_size(size_of::<cg_view_blender_config>());
    config.joint_count = match input.below(16) {
        13 => 0,
        14 => 65_537,
        15 => u32::MAX,
        n => n % 4 + 1,
    };
    config.key_count = match input.below(16) {
        13 => 0,
        14 => 33,
        15 => u32::MAX,
        n => n % 4 + 1,
    };
    let alpha = 2.0 + input.below(3) as f32;
    config.alpha = input.float_or(alpha);
    config.distance = input.choice(2);
    config.method = input.choice(2);
    config.precision = match input.below(16) {
        14 => 1.0e-3,
        15 => input.float(),
        _ => 1.0e-6,
    };
    config.max_iterations = match input.below(16) {
        12 => 0,
        13 => 1,
        14 => 1000,
        15 => 1001,
        _ => 16,
    };
    let mut blender: *mut cg_view_blender = null_mut();
    let pointer = pointer_to(&config, input);
    let out = or_null(&mut blender as *mut _, input);
    let status = state.change("cg_view_blender_create", unsafe {
        cg_view_blender_create(pointer, out)
    });
    if status == cg_status::Ok {
        unsafe { cg_view_blender_destroy(state.blender) };
        state.blender = blender;
        state.blend_joints = config.joint_count as usize;
        state.blend_keys = config.key_count as usize;
    } else {
        assert!(
            blender.is_null(),
            "cg_view_blender_create failed but wrote its handle"
        );
    }
}

/// A key index: mostly a valid one, rarely one past the end or any value.
fn key(state: &State, input: &mut Input) -> u32 {
    match input.below(16) {
        14 => state.blend_keys as u32,
        15 => input.u32(),
        n => n % state.blend_keys.max(1) as u32,
    }
}

pub fn set_key_clip(state: &mut State, input: &mut Input) {
    let key = key(state, input);
    let frame_count = input.count(4);
    let frames = dualquats(input, frame_count * state.blend_joints);
    let frames_per_second = input.float_or(30.0);
    let looping = input.byte() % 2 == 1;
    let blender = state.blender(input);
    let pointer = array_pointer(&frames, input);
    state.change("cg_view_blender_set_key_clip", unsafe {
        cg_view_blender_set_key_clip(
            blender,
            key,
            pointer,
            frame_count,
            frames_per_second,
            looping,
        )
    });
}

pub fn set_key_pose(state: &mut State, input: &mut Input) {
    let key = key(state, input);
    let count = input.count_or(state.blend_joints, 6);
    let pose = dualquats(input, count);
    let blender = state.blender(input);
    let pointer = array_pointer(&pose, input);
    state.change("cg_view_blender_set_key_pose", unsafe {
        cg_view_blender_set_key_pose(blender, key, pointer, count)
    });
}

pub fn add_camera(state: &mut State, input: &mut Input) {
    let direction = if input.rare() {
        vec3(input)
    } else {
        let (sin, cos) = (input.float() / 2.0).sin_cos();
        cg_vec3 {
            x: sin,
            y: input.float() / 16.0,
            z: cos,
        }
    };
    let key = key(state, input);
    let blender = state.blender(input);
    state.change("cg_view_blender_add_camera", unsafe {
        cg_view_blender_add_camera(blender, direction, key)
    });
}

/// Calls `cg_view_blender_weights` or `cg_view_blender_evaluate` (`call`) with a character
/// transform and a viewer position read from the input and `count` outputs (mostly
/// `usual`), each pointer rarely NULL, and checks the outputs.
fn view_call<T: Output + std::fmt::Debug>(
    state: &mut State,
    input: &mut Input,
    function: &str,
    usual: usize,
    call: impl FnOnce(
        *const cg_view_blender,
        *const cg_dualquat,
        *const cg_vec3,
        *mut T,
        usize,
    ) -> cg_status,
) {
    let character = dualquat(input);
    let mut viewer = point(input, 1.5);
    viewer.z += 4.0;
    let count = input.count_or(usual, 6);
    let mut out = sentinel::<T>(count);
    let blender = state.blender(input);
    let status = call(
        blender,
        pointer_to(&character, input),
        pointer_to(&viewer, input),
        or_null(out.as_mut_ptr(), input),
        count,
    );
    let status = state.call(function, status);
    state.outputs(function, status, &out, count);
}

pub fn weights(state: &mut State, input: &mut Input) {
    let usual = state.blend_keys;
    let call = |blender, character, viewer, out: *mut f32, count| unsafe {
        cg_view_blender_weights(blender, character, viewer, out, count)
    };
    view_call(state, input, "cg_view_blender_weights", usual, call);
}

pub fn evaluate(state: &mut State, input: &mut Input) {
    let t = match input.below(16) {
        14 => f64::from(input.float()),
        15 => [f64::NAN, f64::INFINITY, -1.0e300, 1.0e300][input.below(4) as usize],
        _ => f64::from(input.byte()) / 16.0,
    };
    let usual = state.blend_joints;
    let call = |blender, character, viewer, out: *mut cg_dualquat, count| unsafe {
        cg_view_blender_evaluate(blender, character, viewer, t, out, count)
    };
    view_call(state, input, "cg_view_blender_evaluate", usual, call);
}

pub fn from_rt(state: &mut State, input: &mut Input) {
    let rotation = quat(input);
    let translation = vec3(input);
    let mut out = sentinel::<cg_dualquat>(1);
    let status = unsafe {
        cg_dualquat_from_rt(
            pointer_to(&rotation, input),
            pointer_to(&translation, input),
            or_null(out.as_mut_ptr(), input),
        )
    };
    let status = state.call("cg_dualquat_from_rt", status);
    state.outputs("cg_dualquat_from_rt", status, &out, 1);
}

pub fn to_rt(state: &mut State, input: &mut Input) {
    let transform = dualquat(input);
    let mut rotation = sentinel::<cg_quat>(1);
    let mut translation = sentinel::<cg_vec3>(1);
    let status = unsafe {
        cg_dualquat_to_rt(
            pointer_to(&transform, input),
            or_null(rotation.as_mut_ptr(), input),
            or_null(translation.as_mut_ptr(), input),
        )
    };
    let status = state.call("cg_dualquat_to_rt", status);
    state.outputs("cg_dualquat_to_rt", status, &rotation, 1);
    state.outputs("cg_dualquat_to_rt", status, &translation, 1);
}

/// A 4×4 column-major matrix: mostly rigid (made by `cg_dualquat_to_matrix`), with rarely
/// an element replaced by any float.
fn matrix(state: &State, input: &mut Input) -> [f32; 16] {
    let mut matrix = [0.0f32; 16];
    let transform = rigid(input.float(), vec3(input));
    let status = unsafe { cg_dualquat_to_matrix(&transform, matrix.as_mut_ptr()) };
    state.call("cg_dualquat_to_matrix", status);
    while input.rare() {
        matrix[input.below(16) as usize] = input.float();
    }
    matrix
}

pub fn from_matrix(state: &mut State, input: &mut Input) {
    let matrix = matrix(state, input);
    let mut out = sentinel::<cg_dualquat>(1);
    let pointer = array_pointer(&matrix, input);
    let status = unsafe { cg_dualquat_from_matrix(pointer, or_null(out.as_mut_ptr(), input)) };
    let status = state.call("cg_dualquat_from_matrix", status);
    state.outputs("cg_dualquat_from_matrix", status, &out, 1);
}

pub fn to_matrix(state: &mut State, input: &mut Input) {
    let transform = dualquat(input);
    let mut out = sentinel::<f32>(16);
    let status = unsafe {
        cg_dualquat_to_matrix(
            pointer_to(&transform, input),
            or_null(out.as_mut_ptr(), input),
        )
    };
    let status = state.call("cg_dualquat_to_matrix", status);
    state.outputs("cg_dualquat_to_matrix", status, &out, 16);
}

/// DIB's settings: mostly usable ones, rarely any.
fn dib_settings(input: &mut Input) -> (f32, u32) {
    let precision = match input.below(16) {
        14 => 1.0e-3,
        15 => input.float(),
        _ => 1.0e-6,
    };
    let iterations = if input.rare() {
        [0, 1, 1000, 1001, u32::MAX][input.below(5) as usize]
    } else {
        16
    };
    (precision, iterations)
}

/// `cg_blend_dlb` or `cg_blend_dib` (`dib` holds its settings).
fn blend(state: &mut State, input: &mut Input, dib: Option<(f32, u32)>) {
    let count = input.count(5);
    let mut inputs = dualquats(input, count);
    let weights: Vec<f32> = (0..count).map(|_| weight(input)).collect();
    let mut out = sentinel::<cg_dualquat>(1);
    // `out` may alias an input.
    let aliased = count > 0 && input.below(8) == 7;
    let out_pointer = if aliased {
        inputs.as_mut_ptr()
    } else {
        or_null(out.as_mut_ptr(), input)
    };
    let inputs_pointer = array_pointer(&inputs, input);
    let weights_pointer = array_pointer(&weights, input);
    let (function, status) = match dib {
        None => ("cg_blend_dlb", unsafe {
            cg_blend_dlb(inputs_pointer, weights_pointer, count, out_pointer)
        }),
        Some((precision, iterations)) => ("cg_blend_dib", unsafe {
            cg_blend_dib(
                inputs_pointer,
                weights_pointer,
                count,
                precision,
                iterations,
                out_pointer,
            )
        }),
    };
    let status = state.call(function, status);
    if aliased {
        if status == cg_status::Ok || status == cg_status::NotConverged {
            state.outputs(function, status, &inputs[..1], 1);
        }
    } else {
        state.outputs(function, status, &out, 1);
    }
}

pub fn blend_dlb(state: &mut State, input: &mut Input) {
    blend(state, input, None);
}

pub fn blend_dib(state: &mut State, input: &mut Input) {
    let settings = dib_settings(input);
    blend(state, input, Some(settings));
}

/// `cg_blend_pose_dlb` or `cg_blend_pose_dib` (`dib` holds its settings).
fn blend_pose(state: &mut State, input: &mut Input, dib: Option<(f32, u32)>) {
    let (key_count, joint_count) = (input.count(4), input.count(4));
    let mut keys = dualquats(input, key_count * joint_count);
    let weights: Vec<f32> = (0..key_count).map(|_| weight(input)).collect();
    let mut out = sentinel::<cg_dualquat>(joint_count);
    // Rarely `out_pose` overlapping `keys` (documented as an invalid argument).
    let overlapping = key_count > 0 && joint_count > 0 && input.below(8) == 7;
    let out_pointer = if overlapping {
        keys.as_mut_ptr()
    } else {
        or_null(out.as_mut_ptr(), input)
    };
    let keys_pointer = array_pointer(&keys, input);
    let weights_pointer = array_pointer(&weights, input);
    let (function, status) = match dib {
        None => ("cg_blend_pose_dlb", unsafe {
            cg_blend_pose_dlb(
                keys_pointer,
                weights_pointer,
                key_count,
                joint_count,
                out_pointer,
            )
        }),
        Some((precision, iterations)) => ("cg_blend_pose_dib", unsafe {
            cg_blend_pose_dib(
                keys_pointer,
                weights_pointer,
                key_count,
                joint_count,
                precision,
                iterations,
                out_pointer,
            )
        }),
    };
    let status = state.call(function, status);
    assert!(
        !(overlapping && status == cg_status::Ok),
        "{function} accepted an output overlapping its keys"
    );
    state.outputs(function, status, &out, joint_count);
}

pub fn blend_pose_dlb(state: &mut State, input: &mut Input) {
    blend_pose(state, input, None);
}

pub fn blend_pose_dib(state: &mut State, input: &mut Input) {
    let settings = dib_settings(input);
    blend_pose(state, input, Some(settings));
}

/// A 3×4 projection `K [R | t]`, row-major: focal length, yaw and centre from the input,
/// rarely an element replaced by any float.
pub fn camera_center(state: &mut State, input: &mut Input) {
    let focal = 1.0 + f32::from(input.byte());
    let (sin, cos) = input.float().sin_cos();
    let centre = vec3(input);
    // R = yaw rotation, t = -R C.
    let rotation = [[cos, 0.0, sin], [0.0, 1.0, 0.0], [-sin, 0.0, cos]];
    let mut projection = [0.0f32; 12];
    for (row, r) in rotation.iter().enumerate() {
        let t = -(r[0] * centre.x + r[1] * centre.y + r[2] * centre.z);
        let scale = if row < 2 { focal } else { 1.0 };
        projection[4 * row..4 * row + 4].copy_from_slice(&[
            r[0] * scale,
            r[1] * scale,
            r[2] * scale,
            t * scale,
        ]);
    }
    while input.rare() {
        projection[input.below(12) as usize] = input.float();
    }
    let mut out = sentinel::<cg_vec3>(1);
    let pointer = array_pointer(&projection, input);
    let status =
        unsafe { cg_camera_center_from_projection(pointer, or_null(out.as_mut_ptr(), input)) };
    let status = state.call("cg_camera_center_from_projection", status);
    state.outputs("cg_camera_center_from_projection", status, &out, 1);
}
