//! Rows: the view blender (create it, its key clips, poses and cameras, weights, evaluate).

use crate::{
    blend::{or_null, or_null_mut},
    corruption::{change, inside, invalid, non_finite, struct_sizes, Corruption},
    dual_quaternions::dualquat_corruptions,
    fixture::{Harness, Setup, JOINTS, KEYS},
    table::Table,
    values::{
        dualquat_fields, elements, floats, init, padded, transform, vec3, vec3_fields, Fields,
        Padded, ZERO_DUALQUAT, ZERO_QUAT,
    },
    INVALID, NON_FINITE, NULL_ARG, WRONG_STATE,
};
use crowdgaze::ffi::types::{cg_dualquat, cg_quat, cg_vec3};
use crowdgaze::ffi::view_blender::*;
use std::mem::offset_of;
use std::ptr::{null, null_mut};

fn blender_config(_: &Harness) -> Box<Padded<cg_view_blender_config>> {
    let mut config: cg_view_blender_config = init(cg_view_blender_config_init);
    config.joint_count = JOINTS as u32;
    config.key_count = KEYS as u32;
    padded(config)
}

/// The arguments of `cg_view_blender_set_key_clip` and `_set_key_pose`: two frames of
/// three joints (a pose uses the first).
#[repr(C)]
#[derive(Clone, Copy)]
struct ClipInput {
    frames: [cg_dualquat; 6],
    /// Frames of a clip, or joints of a pose.
    count: usize,
    frames_per_second: f32,
    key: u32,
    /// Pass `frames` as NULL.
    null: bool,
}

fn clip_input(_: &Harness) -> ClipInput {
    ClipInput {
        frames: std::array::from_fn(|i| {
            transform([1.0, 0.0, 0.0], 0.05 * i as f32, [0.0, 0.0, 0.1 * i as f32])
        }),
        count: 2,
        frames_per_second: 24.0,
        key: 1,
        null: false,
    }
}

fn pose_key_input(h: &Harness) -> ClipInput {
    ClipInput {
        count: JOINTS,
        ..clip_input(h)
    }
}

/// NaN and infinities in the first `elements` transforms, a zero real part, a key out of
/// range, `(NULL, count)`.
fn clip_corruptions(elements: usize) -> Vec<Corruption<ClipInput>> {
    type C = ClipInput;
    let mut out = non_finite::<C>(&elements_of_frames(elements));
    out.extend([
        change(
            "the last transform with a zero real part",
            INVALID,
            move |c: &mut C| c.frames[elements - 1] = ZERO_DUALQUAT,
        ),
        change("key 3 (key_count is 3)", INVALID, |c: &mut C| c.key = 3),
        change("key UINT32_MAX", INVALID, |c: &mut C| c.key = u32::MAX),
        change(
            "frames NULL with a non-zero count",
            NULL_ARG,
            |c: &mut C| c.null = true,
        ),
    ]);
    out
}

fn elements_of_frames(count: usize) -> Fields {
    elements::<cg_dualquat>(
        "frames",
        offset_of!(ClipInput, frames),
        count,
        &dualquat_fields(),
    )
}

/// The arguments of `cg_view_blender_weights` and `_evaluate`.
#[derive(Clone, Copy)]
struct ViewInput {
    character: cg_dualquat,
    viewer: cg_vec3,
    /// Weights or joints asked for.
    count: usize,
    t: f64,
    /// Which blender: 0 the complete one, 1 the one without camera, 2 the one with a key
    /// without clip; 3 NULL.
    blender: u8,
    /// Pass `character`, `viewer`, the output as NULL.
    nulls: [bool; 3],
}

fn view_input(_: &Harness) -> ViewInput {
    ViewInput {
        character: transform([0.0, 1.0, 0.0], 0.7, [1.0, 0.0, 2.0]),
        viewer: vec3(1.5, 1.7, 7.0),
        count: 3,
        t: 0.4,
        blender: 0,
        nulls: [false; 3],
    }
}

fn view_corruptions() -> Vec<Corruption<ViewInput>> {
    type V = ViewInput;
    let mut out = inside(dualquat_corruptions("character"), "", |v: &mut V| {
        &mut v.character
    });
    out.extend(inside(
        non_finite(&vec3_fields()),
        "viewer.",
        |v: &mut V| &mut v.viewer,
    ));
    out.extend([
        change("blender NULL", NULL_ARG, |v: &mut V| v.blender = 3),
        change("character NULL", NULL_ARG, |v: &mut V| v.nulls[0] = true),
        change("viewer NULL", NULL_ARG, |v: &mut V| v.nulls[1] = true),
        change("output NULL with a count of 3", NULL_ARG, |v: &mut V| {
            v.nulls[2] = true
        }),
        change("count 2 (3 keys and joints)", INVALID, |v: &mut V| {
            v.count = 2
        }),
        change("count 4 (3 keys and joints)", INVALID, |v: &mut V| {
            v.count = 4
        }),
        change("count 0", INVALID, |v: &mut V| v.count = 0),
        change("count SIZE_MAX", INVALID, |v: &mut V| v.count = usize::MAX),
        change("viewer at the character's centre", INVALID, |v: &mut V| {
            v.viewer = vec3(1.0, 0.0, 2.0)
        }),
        change("no key camera yet", WRONG_STATE, |v: &mut V| v.blender = 1),
    ]);
    out
}

impl ViewInput {
    fn blender(&self, h: &Harness) -> *const cg_view_blender {
        match self.blender {
            0 => h.blender,
            1 => h.blender_no_camera,
            2 => h.blender_no_clip,
            _ => null(),
        }
    }

    fn character(&self) -> *const cg_dualquat {
        or_null(&self.character, self.nulls[0])
    }

    fn viewer(&self) -> *const cg_vec3 {
        or_null(&self.viewer, self.nulls[1])
    }
}

pub(crate) fn rows_view_blender(t: &mut Table) {
    let f = "cg_view_blender_create";
    t.case(f, "config NULL", NULL_ARG, |h| unsafe {
        cg_view_blender_create(null(), &mut h.out.blender)
    });
    t.case(f, "out_blender NULL", NULL_ARG, |h| unsafe {
        cg_view_blender_create(&blender_config(h).value, null_mut())
    });
    type C = cg_view_blender_config;
    let mut config = struct_sizes::<C>();
    config.extend(non_finite(&floats!(C: alpha, precision)));
    config.extend(invalid::<C>(&[
        ("joint_count 0", |c| c.joint_count = 0),
        ("joint_count 65537", |c| c.joint_count = 65537),
        ("joint_count UINT32_MAX", |c| c.joint_count = u32::MAX),
        ("key_count 0", |c| c.key_count = 0),
        ("key_count 33", |c| c.key_count = 33),
        ("alpha 1.9", |c| c.alpha = 1.9),
        ("alpha 4.1", |c| c.alpha = 4.1),
        ("distance 2", |c| c.distance = 2),
        ("method 2", |c| c.method = 2),
        ("method UINT32_MAX", |c| c.method = u32::MAX),
        ("precision 0", |c| c.precision = 0.0),
        ("precision -1", |c| c.precision = -1.0),
        ("max_iterations 0", |c| c.max_iterations = 0),
        ("max_iterations 1001", |c| c.max_iterations = 1001),
    ]));
    t.corrupt_struct(f, "config", config, blender_config, |h, config| unsafe {
        cg_view_blender_create(config, &mut h.out.blender)
    });

    let f = "cg_view_blender_set_key_clip";
    let set_clip = |h: &mut Harness, c: &mut ClipInput| {
        let frames = or_null(c.frames.as_ptr(), c.null);
        unsafe {
            cg_view_blender_set_key_clip(
                h.blender,
                c.key,
                frames,
                c.count,
                c.frames_per_second,
                true,
            )
        }
    };
    t.case(f, "blender NULL", NULL_ARG, |h| {
        let c = clip_input(h);
        unsafe { cg_view_blender_set_key_clip(null_mut(), 1, c.frames.as_ptr(), 2, 24.0, false) }
    });
    let mut clip = clip_corruptions(6);
    clip.extend(non_finite(&floats!(ClipInput: frames_per_second)));
    clip.extend(invalid::<ClipInput>(&[
        ("frame_count 0", |c| c.count = 0),
        ("frame_count × joint_count overflowing", |c| {
            c.count = usize::MAX
        }),
        ("frame_count × joint_count too big for memory", |c| {
            c.count = usize::MAX / 4
        }),
        ("frames_per_second 0", |c| c.frames_per_second = 0.0),
        ("frames_per_second -24", |c| c.frames_per_second = -24.0),
    ]));
    t.corrupt(Setup::Online, f, clip, clip_input, set_clip);

    let f = "cg_view_blender_set_key_pose";
    t.case(f, "blender NULL", NULL_ARG, |h| {
        let c = pose_key_input(h);
        unsafe { cg_view_blender_set_key_pose(null_mut(), 1, c.frames.as_ptr(), JOINTS) }
    });
    let mut pose = clip_corruptions(JOINTS);
    pose.extend(invalid::<ClipInput>(&[
        ("joint_count 2 (the blender has 3)", |c| c.count = 2),
        ("joint_count 4 (the blender has 3)", |c| c.count = 4),
        ("(pose NULL, joint_count 0)", |c| {
            c.count = 0;
            c.null = true;
        }),
        ("joint_count SIZE_MAX", |c| c.count = usize::MAX),
    ]));
    t.corrupt(Setup::Online, f, pose, pose_key_input, |h, c| {
        let pose = or_null(c.frames.as_ptr(), c.null);
        unsafe { cg_view_blender_set_key_pose(h.blender, c.key, pose, c.count) }
    });

    let f = "cg_view_blender_add_camera";
    t.case(f, "blender NULL", NULL_ARG, |_| unsafe {
        cg_view_blender_add_camera(null_mut(), vec3(0.0, 1.0, 0.0), 0)
    });
    let mut camera = inside(
        non_finite(&vec3_fields()),
        "direction.",
        |c: &mut ClipInput| &mut c.frames[0].real,
    );
    camera.extend(invalid::<ClipInput>(&[
        ("direction zero", |c| c.frames[0].real = ZERO_QUAT),
        ("key 3 (key_count is 3)", |c| c.key = 3),
        ("key UINT32_MAX", |c| c.key = u32::MAX),
    ]));
    t.corrupt(Setup::Online, f, camera, camera_input, |h, c| {
        let q = c.frames[0].real;
        unsafe { cg_view_blender_add_camera(h.blender, vec3(q.x, q.y, q.z), c.key) }
    });

    let f = "cg_view_blender_weights";
    t.corrupt(Setup::Online, f, view_corruptions(), view_input, |h, v| {
        let out = or_null_mut(h.out.weights.as_mut_ptr(), v.nulls[2]);
        unsafe { cg_view_blender_weights(v.blender(h), v.character(), v.viewer(), out, v.count) }
    });

    let f = "cg_view_blender_evaluate";
    let mut evaluate = view_corruptions();
    for (label, value) in [
        ("NaN", f64::NAN),
        ("+Inf", f64::INFINITY),
        ("-Inf", f64::NEG_INFINITY),
    ] {
        evaluate.push(change(
            format!("t = {label}"),
            NON_FINITE,
            move |v: &mut ViewInput| v.t = value,
        ));
    }
    evaluate.push(change(
        "key 1 has no clip or pose",
        WRONG_STATE,
        |v: &mut ViewInput| v.blender = 2,
    ));
    t.corrupt(Setup::Online, f, evaluate, view_input, |h, v| {
        let out = or_null_mut(h.out.pose.as_mut_ptr(), v.nulls[2]);
        unsafe {
            cg_view_blender_evaluate(v.blender(h), v.character(), v.viewer(), v.t, out, v.count)
        }
    });
}

/// A camera direction (in `frames[0].real`'s x, y, z) and its key.
fn camera_input(h: &Harness) -> ClipInput {
    let mut input = clip_input(h);
    input.frames[0].real = cg_quat {
        x: 0.0,
        y: 1.0,
        z: 0.0,
        w: 0.0,
    };
    input
}
