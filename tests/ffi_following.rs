//! Gaze following and the street preset seen from C's side: `cg_crowd_config_init_street`,
//! the `follow_*` and `street_*` lengths in the caller's units both ways, and
//! `cg_crowd_read_following` giving the followed point in the caller's units.

// The `unsafe { cg_... }` calls below pass pointers to live values of the sizes the header
// asks for: that is their safety comment, once for the file.
#![allow(clippy::undocumented_unsafe_blocks)]

mod support;

use crowdgaze::ffi::attention::*;
use crowdgaze::ffi::crowd::*;
use crowdgaze::ffi::following::cg_crowd_read_following;
use crowdgaze::ffi::frame::*;
use crowdgaze::ffi::gaze::*;
use crowdgaze::ffi::status::cg_status;
use crowdgaze::ffi::types::cg_vec3;
use std::ptr::null_mut;
use support::init;

const STARERS: usize = 5;
const FOLLOWERS: usize = 20;
const WINDOW: [f32; 3] = [0.0, 12.0, -6.0];
const FPS: f32 = 30.0;

fn vec3([x, y, z]: [f32; 3], units: f32) -> cg_vec3 {
    cg_vec3 {
        x: x * units,
        y: y * units,
        z: z * units,
    }
}

/// The street preset in `units` per metre, every length scaled.
fn street_config(units: f32) -> cg_crowd_config {
    let mut config: cg_crowd_config = init(cg_crowd_config_init_street);
    config.units_per_metre = units;
    for length in [
        &mut config.max_distance,
        &mut config.restart_distance,
        &mut config.proximity_radius,
        &mut config.street_civil_distance,
        &mut config.street_path_look_distance,
        &mut config.street_civil_look_distance,
        &mut config.follow_distance,
    ] {
        *length *= units;
    }
    config.max_characters = (STARERS + FOLLOWERS) as u32;
    config.seed = 1969;
    config
}

/// Five people staring at the window, twenty standing street-model characters facing
/// them 4 to 8 m away; every frame for 10 s, each follower's `cg_crowd_read_following`.
fn run(config: &cg_crowd_config) -> Vec<Vec<(Option<cg_vec3>, u32)>> {
    let units = config.units_per_metre;
    let mut crowd = null_mut();
    assert_eq!(
        unsafe { cg_crowd_create(config, &mut crowd) },
        cg_status::Ok
    );
    let mut ids = Vec::new();
    let mut states = Vec::new();
    for i in 0..STARERS + FOLLOWERS {
        let mut desc: cg_character_desc = init(cg_character_desc_init);
        desc.attention_model = cg_attention_model::Street as u32;
        let position = if i < STARERS {
            [-1.0 + 0.5 * i as f32, 0.0, 0.0]
        } else {
            let k = (i - STARERS) as f32;
            [-4.0 + (k % 5.0) * 2.0, 0.0, 4.0 + (k / 5.0).floor()]
        };
        desc.position = vec3(position, units);
        desc.heading = if i < STARERS {
            0.0
        } else {
            std::f32::consts::PI
        };
        let mut id = 0;
        assert_eq!(
            unsafe { cg_crowd_add_character(crowd, &desc, &mut id) },
            cg_status::Ok
        );
        let mut state: cg_entity_state = init(cg_entity_state_init);
        (state.id, state.position, state.heading) = (id, desc.position, desc.heading);
        ids.push(id);
        states.push(state);
    }
    for &starer in &ids[..STARERS] {
        let mut target: cg_gaze_target = init(cg_gaze_target_init);
        target.point = vec3(WINDOW, units);
        assert_eq!(
            unsafe { cg_crowd_set_gaze_target(crowd, starer, &target) },
            cg_status::Ok
        );
    }
    let mut frames = Vec::new();
    for frame in 1..=(10.0 * FPS) as usize {
        let t = frame as f64 / f64::from(FPS);
        let pushed = unsafe { cg_crowd_push_frame(crowd, t, states.as_ptr(), states.len()) };
        assert_eq!(pushed, cg_status::Ok);
        assert_eq!(unsafe { cg_crowd_step(crowd, 1.0 / FPS) }, cg_status::Ok);
        let read = ids[STARERS..].iter().map(|&id| {
            let (mut point, mut following, mut glances) = (vec3([9.0; 3], 1.0), 7, 7);
            let status = unsafe {
                cg_crowd_read_following(crowd, id, &mut point, &mut following, &mut glances)
            };
            assert_eq!(status, cg_status::Ok);
            assert!(following <= 1);
            if following == 0 {
                assert_eq!(point, cg_vec3::default(), "the origin when not following");
            }
            ((following == 1).then_some(point), glances)
        });
        frames.push(read.collect());
    }
    unsafe { cg_crowd_destroy(crowd) };
    frames
}

#[test]
fn the_street_preset_is_the_default_but_for_its_view_distance_and_following() {
    let defaults: cg_crowd_config = init(cg_crowd_config_init);
    let street: cg_crowd_config = init(cg_crowd_config_init_street);
    assert_eq!((defaults.max_distance, defaults.follow_enabled), (10.0, 0));
    assert_eq!((street.max_distance, street.follow_enabled), (17.0, 1));
    let mut same = street;
    (same.max_distance, same.follow_enabled) = (10.0, 0);
    assert_eq!(format!("{same:?}"), format!("{defaults:?}"));
    assert_eq!(street.street_first_fixation_probability, 0.95);
    assert_eq!(street.follow_one_looker_probability, 0.42);
}

#[test]
fn the_followed_point_is_in_the_callers_units() {
    let metres = run(&street_config(1.0));
    let centimetres = run(&street_config(100.0));
    let mut compared = 0;
    for (m, cm) in metres.iter().zip(&centimetres) {
        for (&(in_m, glances_m), &(in_cm, glances_cm)) in m.iter().zip(cm) {
            assert_eq!(glances_m, glances_cm, "the same decisions in both units");
            match (in_m, in_cm) {
                (None, None) => {}
                (Some(p), Some(q)) => {
                    for (a, b) in [(p.x, q.x), (p.y, q.y), (p.z, q.z)] {
                        assert!((a * 100.0 - b).abs() <= 1e-3, "{p:?} {q:?}");
                    }
                    assert!((p.y - WINDOW[1]).abs() < 1e-5 && (p.z - WINDOW[2]).abs() < 1e-5);
                    compared += 1;
                }
                other => panic!("one follows and the other not: {other:?}"),
            }
        }
    }
    let last = metres.last().unwrap();
    let followers = last.iter().filter(|(_, glances)| *glances > 0).count();
    assert!(
        compared > 0 && followers >= FOLLOWERS / 3,
        "{followers} followers"
    );
}

#[test]
fn following_lengths_come_back_in_the_callers_units() {
    let config = street_config(100.0);
    let mut crowd = null_mut();
    assert_eq!(
        unsafe { cg_crowd_create(&config, &mut crowd) },
        cg_status::Ok
    );
    let mut back: cg_crowd_config = init(cg_crowd_config_init);
    assert_eq!(
        unsafe { cg_crowd_get_config(crowd, &mut back) },
        cg_status::Ok
    );
    assert_eq!(back.follow_enabled, 1);
    assert!((back.follow_distance - 1000.0).abs() < 1e-3);
    assert!((back.max_distance - 1700.0).abs() < 1e-3);
    assert!((back.street_civil_distance - 300.0).abs() < 1e-3);
    assert!((back.street_path_look_distance - 400.0).abs() < 1e-3);
    assert!((back.street_civil_look_distance - 200.0).abs() < 1e-3);
    assert_eq!(back.street_latency_max, config.street_latency_max);
    unsafe { cg_crowd_destroy(crowd) };
}
