//! What a pushed state's flags make the library read: a heading that comes from the motion
//! (`CG_STATE_HEADING_FROM_MOTION`) is not read, so any value is accepted, NaN included, in
//! every way of pushing; without the flag a NaN heading is refused and changes nothing.

// The `unsafe { cg_... }` calls below pass pointers to live values of the sizes the header
// asks for: that is their safety comment, once for the file.
#![allow(clippy::undocumented_unsafe_blocks)]

mod support;

use crowdgaze::ffi::attention::*;
use crowdgaze::ffi::crowd::*;
use crowdgaze::ffi::frame::*;
use crowdgaze::ffi::status::cg_status;
use crowdgaze::scene::EntityUpdate;
use crowdgaze::{CharacterDesc, Crowd, CrowdConfig};
use glam::Vec3;
use support::{check, init, CrowdHandle};

/// Characters `ids` a metre apart, the second walking towards +X.
fn states(ids: &[u32], frame: usize, heading: f32, flags: u32) -> Vec<cg_entity_state> {
    ids.iter()
        .enumerate()
        .map(|(i, &id)| {
            let mut state: cg_entity_state = init(cg_entity_state_init);
            state.id = id;
            state.flags = flags;
            state.heading = heading;
            state.position.x = i as f32 + 0.05 * i as f32 * frame as f32;
            state
        })
        .collect()
}

#[test]
fn a_heading_from_motion_is_not_read_through_the_c_api() {
    let config: cg_crowd_config = init(cg_crowd_config_init);
    let crowd = CrowdHandle::new(&config);
    let ids: Vec<u32> = (0..2)
        .map(|i| crowd.add_character(Vec3::new(i as f32, 0.0, 0.0), 0.0))
        .collect();
    for frame in 1..=30u32 {
        let t = f64::from(frame) / 30.0;
        let pushed = states(&ids, frame as usize, f32::NAN, CG_STATE_HEADING_FROM_MOTION);
        check(
            unsafe { cg_crowd_push_frame(crowd.as_mut(), t, pushed.as_ptr(), 2) },
            "push_frame with a NaN heading from motion",
        );
        check(unsafe { cg_crowd_step(crowd.as_mut(), 1.0 / 30.0) }, "step");
    }
    // The ranged push reads states the same way.
    check(
        unsafe { cg_crowd_begin_push(crowd.as_mut(), 2.0) },
        "begin_push",
    );
    let pushed = states(&ids, 60, f32::NAN, CG_STATE_HEADING_FROM_MOTION);
    check(
        unsafe { cg_crowd_push_range(crowd.as_mut(), pushed.as_ptr(), 2) },
        "push_range with a NaN heading from motion",
    );
    check(unsafe { cg_crowd_end_push(crowd.as_mut()) }, "end_push");
    check(unsafe { cg_crowd_step(crowd.as_mut(), 1.0 / 30.0) }, "step");
    let mut gaze = [std::mem::MaybeUninit::<cg_gaze_info>::zeroed(); 2];
    let mut written = 0;
    check(
        unsafe { cg_crowd_read_gaze(crowd.as_const(), gaze.as_mut_ptr().cast(), 2, &mut written) },
        "read_gaze",
    );
    for info in &gaze[..written] {
        let info = unsafe { info.assume_init() };
        let p = info.target_position;
        assert!(p.x.is_finite() && p.y.is_finite() && p.z.is_finite());
    }
    // Without the flag the heading is read: NaN is refused and nothing is pushed.
    let pushed = states(&ids, 61, f32::NAN, 0);
    let status = unsafe { cg_crowd_push_frame(crowd.as_mut(), 3.0, pushed.as_ptr(), 2) };
    assert_eq!(status, cg_status::NonFinite);
    let pushed = states(&ids, 61, 0.5, 0);
    check(
        unsafe { cg_crowd_push_frame(crowd.as_mut(), 3.0, pushed.as_ptr(), 2) },
        "the same time after the refused push",
    );
}

#[test]
fn a_heading_from_motion_is_not_read_through_the_rust_api() {
    let mut crowd = Crowd::new(CrowdConfig::default()).unwrap();
    let id = crowd.add_character(&CharacterDesc::default()).unwrap();
    let update = |x: f32, heading: f32, heading_from_motion: bool| EntityUpdate {
        id,
        position: Vec3::new(x, 0.0, 0.0),
        heading,
        heading_from_motion,
        velocity: None,
        talking: false,
    };
    crowd
        .push_frame(0.1, &[update(0.1, f32::NAN, true)])
        .unwrap();
    crowd
        .push_frame(0.2, &[update(0.2, f32::INFINITY, true)])
        .unwrap();
    crowd.step(0.1).unwrap();
    assert!(crowd.scene().headings()[0].is_finite());
    assert!(crowd
        .push_frame(0.3, &[update(0.3, f32::NAN, false)])
        .is_err());
    assert!(crowd.time() < 0.25, "the refused push changed the time");
}
