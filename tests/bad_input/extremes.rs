//! Extreme finite values are not bad input: entities, weights, times and capacities at the
//! ends of their ranges.

use crate::{
    attention::params_of,
    fixture::{Harness, Setup, FPS, JOINTS},
    header::Header,
    joints::ALL_JOINTS,
    values::{bytes_of, init, last_error, ok, sized, transform, vec3, zeroed},
};
use crowdgaze::ffi::attention::*;
use crowdgaze::ffi::crowd::*;
use crowdgaze::ffi::frame::*;
use crowdgaze::ffi::gaze::*;
use crowdgaze::ffi::status::cg_status;
use crowdgaze::ffi::types::{cg_dualquat, cg_quat};
use crowdgaze::ffi::view_blender::*;
use std::ptr::null_mut;

/// Runs `work` on a thread and fails if it has not finished within a minute (a hang).
fn within_a_minute(what: &str, work: fn()) {
    let (done, finished) = std::sync::mpsc::channel();
    let thread = std::thread::spawn(move || {
        work();
        let _ = done.send(());
    });
    match finished.recv_timeout(std::time::Duration::from_secs(60)) {
        Ok(()) => thread.join().expect("no panic"),
        Err(std::sync::mpsc::RecvTimeoutError::Disconnected) => {
            std::panic::resume_unwind(thread.join().expect_err("it panicked"))
        }
        Err(std::sync::mpsc::RecvTimeoutError::Timeout) => panic!("{what} hangs"),
    }
}

/// Every gaze, joint and eye output of the crowd is finite.
fn assert_finite_outputs(h: &Harness, what: &str) {
    let mut gaze = [zeroed::<cg_gaze_info>(); 8];
    let mut count = 0;
    ok(unsafe { cg_crowd_read_gaze(h.crowd, gaze.as_mut_ptr(), 8, &mut count) });
    let mut joints = [zeroed::<cg_quat>(); ALL_JOINTS];
    ok(unsafe { cg_crowd_read_joints(h.crowd, 0, 4, joints.as_mut_ptr(), ALL_JOINTS) });
    let mut eyes = [zeroed::<cg_eye_info>(); 4];
    ok(unsafe { cg_crowd_read_eyes(h.crowd, 0, 4, eyes.as_mut_ptr(), 4) });
    let floats = |bytes: &[u8]| -> Vec<f32> {
        bytes
            .chunks_exact(4)
            .map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]))
            .collect()
    };
    let mut values = floats(bytes_of(&joints[..]));
    for info in &gaze[..count] {
        let t = info.target_position;
        values.extend([
            t.x,
            t.y,
            t.z,
            info.s_max,
            info.threshold,
            info.attentive_fraction,
        ]);
    }
    for eye in &eyes {
        values.extend(floats(&bytes_of(std::slice::from_ref(eye))[4..]));
    }
    assert!(values.iter().all(|v| v.is_finite()), "{what}: {values:?}");
}

/// Entities at the two ends of the float range, moving at ±FLT_MAX: stepping returns (the
/// neighbour grid once doubled its cells forever on a bounding box wider than a float) and
/// every output stays finite.
#[test]
fn entities_at_the_ends_of_the_float_range() {
    within_a_minute("stepping a crowd spanning ±FLT_MAX", || {
        let mut h = Harness::new(Setup::Online);
        let (t, mut states) = h.next_frame();
        for (state, sign) in states.iter_mut().zip([1.0f32, -1.0, 1.0, -1.0]) {
            state.position.x = sign * f32::MAX;
            state.velocity = vec3(sign * f32::MAX, 0.0, -sign * f32::MAX);
            state.flags = CG_STATE_HAS_VELOCITY;
        }
        ok(unsafe { cg_crowd_push_frame(h.crowd, t, states.as_ptr(), states.len()) });
        ok(unsafe {
            cg_crowd_set_viewer(h.crowd, &vec3(f32::MAX, 0.0, f32::MAX), 1.0, null_mut())
        });
        for _ in 0..10 {
            ok(unsafe { cg_crowd_step(h.crowd, (1.0 / FPS) as f32) });
        }
        assert_finite_outputs(&h, "after stepping at ±FLT_MAX");
        h.time = t;
        let (t, states) = h.next_frame();
        ok(unsafe { cg_crowd_push_frame(h.crowd, t, states.as_ptr(), states.len()) });
        ok(unsafe { cg_crowd_plan(h.crowd) });
        ok(unsafe { cg_crowd_step(h.crowd, (1.0 / FPS) as f32) });
        assert_finite_outputs(&h, "after planning");
    });
}

/// Weights of FLT_MAX are >= 0 and not all zero: accepted and rescaled to ¼ each (their sum
/// once overflowed and the call failed).
#[test]
fn the_largest_weights_are_rescaled() {
    let h = Harness::new(Setup::Online);
    let mut params = params_of(&h);
    let p = &mut params.value;
    (p.weight_proximity, p.weight_speed) = (f32::MAX, f32::MAX);
    (p.weight_orientation, p.weight_periphery) = (f32::MAX, f32::MAX);
    ok(unsafe { cg_crowd_set_character_params(h.crowd, h.character(0), p) });
    let mut back = [sized::<cg_character_params>()];
    ok(unsafe { cg_crowd_get_character_params(h.crowd, h.character(0), back.as_mut_ptr()) });
    let b = back[0];
    let weights = [
        b.weight_proximity,
        b.weight_speed,
        b.weight_orientation,
        b.weight_periphery,
    ];
    assert_eq!(weights, [0.25; 4]);
}

/// A pose at any finite time is finite: `time × frames_per_second` overflowing a double
/// once made a looping clip's phase NaN.
#[test]
fn poses_at_the_ends_of_time_are_finite() {
    let h = Harness::new(Setup::Online);
    let character = transform([0.0, 1.0, 0.0], 0.7, [1.0, 0.0, 2.0]);
    let viewer = vec3(2.0, 2.0, 5.0);
    for t in [1e300, -1e300, f64::MAX, f64::MIN, 1e-300] {
        let mut pose = [zeroed::<cg_dualquat>(); JOINTS];
        ok(unsafe {
            cg_view_blender_evaluate(h.blender, &character, &viewer, t, pose.as_mut_ptr(), JOINTS)
        });
        let bytes = bytes_of(&pose[..]);
        assert!(
            bytes
                .chunks_exact(4)
                .all(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]).is_finite()),
            "t = {t}: {pose:?}"
        );
    }
}

/// Capacities at their documented maxima return `CG_STATUS_OK` or `CG_STATUS_OUT_OF_MEMORY`
/// (documented for the create), never abort the process; a failed create writes no handle
/// and names the field and the bytes asked.
///
/// Only the maxima that are safe to try in a process without an address-space cap are here:
/// a 275 GB recording is refused by the allocator (or, where memory is overcommitted,
/// reserved and never touched), and the largest view blender is small. The maxima that need
/// gigabytes (16 777 216 characters or objects, a clip or a plan larger than memory) run in
/// children capped at 2 GiB in `c_examples/out_of_memory.c`.
#[test]
fn capacities_at_their_maxima_return_ok_or_out_of_memory() {
    let header = Header::read();
    let allowed = [cg_status::Ok, cg_status::OutOfMemory];
    for function in ["cg_crowd_create", "cg_view_blender_create"] {
        assert!(
            header
                .documented(function)
                .contains(&(cg_status::OutOfMemory as u32)),
            "{function} does not document CG_STATUS_OUT_OF_MEMORY"
        );
    }

    let mut config: cg_crowd_config = init(cg_crowd_config_init);
    config.max_recorded_states = u32::MAX;
    let mut crowd: *mut cg_crowd = null_mut();
    let status = unsafe { cg_crowd_create(&config, &mut crowd) };
    assert!(allowed.contains(&status), "{status:?}: {}", last_error());
    if status == cg_status::Ok {
        let mut back: cg_crowd_config = init(cg_crowd_config_init);
        ok(unsafe { cg_crowd_get_config(crowd, &mut back) });
        assert_eq!(back.max_recorded_states, u32::MAX);
        unsafe { cg_crowd_destroy(crowd) };
    } else {
        assert!(crowd.is_null(), "a failed create wrote a handle");
        let message = last_error();
        assert!(
            message.starts_with("out of memory: max_recorded_states = 4294967295 needs ")
                && message.ends_with(" bytes")
                && !message.contains('\n'),
            "{message}"
        );
    }

    let mut config: cg_view_blender_config = init(cg_view_blender_config_init);
    config.joint_count = 65536;
    config.key_count = 32;
    let mut blender: *mut cg_view_blender = null_mut();
    ok(unsafe { cg_view_blender_create(&config, &mut blender) });
    unsafe { cg_view_blender_destroy(blender) };
}
