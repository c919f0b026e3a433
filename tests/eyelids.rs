//! Living eyes through the crowd (issue #24): over 10 simulated minutes of the street, each
//! character blinks at its drawn rate, blinks last 100–500 ms and close faster than they
//! open, large gaze shifts start a blink as the chosen curve says, lids follow the eyes'
//! pitch; eye-only saccades on the main sequence last 2.2 ms/° · A + 21 ms; bad settings
//! are refused. (Identity across runs, thread counts and storage orders: the eyelids are
//! part of `support::output_bits`, which tests/threads.rs, storage_order.rs and
//! ranged_push.rs compare.)

mod support;

use crowdgaze::crowd::{ExplicitTarget, EyeMotion, TargetPriority};
use crowdgaze::ik::eyelids::character_seed;
use crowdgaze::ik::BlinkSettings;
use crowdgaze::scenario::Scenario;
use crowdgaze::{CharacterDesc, Crowd, CrowdConfig, Error};
use glam::Vec3;

const PEOPLE: usize = 40;
const DT: f32 = 1.0 / 60.0;
const MINUTES: f32 = 10.0;

/// One blink as seen frame by frame: its closure each frame it was above 0.
#[derive(Debug, Default)]
struct Blink {
    closures: Vec<f32>,
}

/// What 10 minutes of the street showed, per character (in the crowd's order).
struct Observed {
    /// The rate each character drew, blinks per minute.
    drawn: Vec<f32>,
    /// The blinks each character made, complete ones only.
    blinks: Vec<Vec<Blink>>,
    /// Gaze shifts: (amplitude, lids closing or closed at its start).
    shifts: Vec<(f32, bool)>,
}

/// Runs the street of `PEOPLE` for 10 minutes with `blinks`, recording every frame's
/// eyelids and every gaze shift's start.
fn observe(blinks: BlinkSettings) -> Observed {
    let config = CrowdConfig {
        blinks,
        ..CrowdConfig::default()
    };
    let seed = config.seed;
    let mut crowd = Crowd::new(config).unwrap();
    let mut scenario = Scenario::street(PEOPLE, 30, 5);
    scenario.populate(&mut crowd).unwrap();
    let ids = scenario.character_ids().to_vec();
    support::mix_attention_models(&mut crowd, &ids);
    let drawn = (0..crowd.character_count())
        .map(|i| blinks.rate_of(character_seed(seed, crowd.gaze_at(i).character)))
        .collect();
    let mut open: Vec<Option<Blink>> = (0..PEOPLE).map(|_| None).collect();
    let mut done: Vec<Vec<Blink>> = (0..PEOPLE).map(|_| Vec::new()).collect();
    let mut shifts = Vec::new();
    let frames = (MINUTES * 60.0 / DT) as usize;
    for frame in 0..frames {
        scenario.advance(DT);
        scenario
            .push(&mut crowd, (frame + 1) as f64 * f64::from(DT))
            .unwrap();
        crowd.step(DT).unwrap();
        for character in 0..PEOPLE {
            let lids = crowd.eyelids_at(character);
            assert_eq!(lids.left_closure, lids.right_closure);
            assert!((0.0..=1.0).contains(&lids.left_closure));
            let motion = crowd.gaze_motion(lids.character).unwrap();
            if let Some(amplitude) = motion.shift_start_amplitude() {
                shifts.push((amplitude, lids.left_closure > 0.0));
            }
            match (&mut open[character], lids.left_closure > 0.0) {
                (Some(blink), true) => blink.closures.push(lids.left_closure),
                (slot @ None, true) => {
                    // Blinks under way when the run starts are not complete: none is, the
                    // eyes start open.
                    *slot = Some(Blink {
                        closures: vec![lids.left_closure],
                    });
                }
                (slot @ Some(_), false) => done[character].push(slot.take().unwrap()),
                (None, false) => {}
            }
        }
    }
    Observed {
        drawn,
        blinks: done,
        shifts,
    }
}

#[test]
fn each_character_blinks_at_its_drawn_rate_and_the_crowd_at_the_mean() {
    // Spontaneous blinks alone: gaze-evoked ones come on top of the drawn rate.
    let settings = BlinkSettings {
        evoked_probability: 0.0,
        ..BlinkSettings::default()
    };
    let observed = observe(settings);
    let mut measured_sum = 0.0;
    for (character, (blinks, drawn)) in observed.blinks.iter().zip(&observed.drawn).enumerate() {
        let rate = blinks.len() as f32 / MINUTES;
        assert!(
            (rate - drawn).abs() <= 0.2 * drawn,
            "character {character}: {rate} blinks a minute, drew {drawn}"
        );
        measured_sum += rate;
    }
    let measured_mean = measured_sum / PEOPLE as f32;
    let drawn_mean = observed.drawn.iter().sum::<f32>() / PEOPLE as f32;
    println!(
        "{PEOPLE} characters: drew {drawn_mean} blinks a minute on average, made {measured_mean}"
    );
    // The drawn rates spread ±50 % around 17; their mean over 40 characters within 10 %.
    assert!((drawn_mean - 17.0).abs() <= 1.7, "drawn mean {drawn_mean}");
    assert!(
        (measured_mean - 17.0).abs() <= 1.7,
        "the crowd blinks {measured_mean} times a minute"
    );
}

#[test]
fn blinks_are_100_to_500_ms_close_faster_than_they_open_and_large_shifts_start_one() {
    let settings = BlinkSettings::default();
    let observed = observe(settings);
    let mut count = 0;
    for blink in observed.blinks.iter().flatten() {
        let duration = blink.closures.len() as f32 * DT;
        assert!(
            (0.1..=0.5).contains(&duration),
            "a blink of {duration} s: {:?}",
            blink.closures
        );
        // The closest frame comes in the first half: closing is the faster phase.
        let peak = blink
            .closures
            .iter()
            .enumerate()
            .max_by(|a, b| a.1.total_cmp(b.1))
            .unwrap()
            .0;
        assert!(
            peak + 1 < blink.closures.len() - peak,
            "closing {} frames, opening {}: {:?}",
            peak + 1,
            blink.closures.len() - peak,
            blink.closures
        );
        count += 1;
    }
    assert!(count > PEOPLE * 100, "only {count} blinks");

    // Gaze-evoked blinks: shifts above 40° start a blink with the curve's probability (0.97
    // there) — or find one under way.
    let large: Vec<bool> = observed
        .shifts
        .iter()
        .filter(|(amplitude, _)| *amplitude > 40f32.to_radians())
        .map(|(_, blink)| *blink)
        .collect();
    assert!(large.len() >= 100, "only {} shifts above 40°", large.len());
    let share = large.iter().filter(|&&blink| blink).count() as f32 / large.len() as f32;
    let expected = settings.evoked_probability_at(40f32.to_radians());
    println!(
        "{count} blinks; {share} of {} shifts above 40° start with a blink (curve {expected})",
        large.len()
    );
    assert!(
        (share - expected).abs() <= 0.10,
        "{share} of {} shifts above 40° start with a blink, the curve says {expected}",
        large.len()
    );
    // Small shifts (under the curve's 10° floor) find only spontaneous blinks under way.
    let small: Vec<bool> = observed
        .shifts
        .iter()
        .filter(|(amplitude, _)| *amplitude < 8f32.to_radians())
        .map(|(_, blink)| *blink)
        .collect();
    let small_share = small.iter().filter(|&&blink| blink).count() as f32 / small.len() as f32;
    println!("{small_share} of {} shifts under 8°", small.len());
    assert!(
        small_share < 0.15,
        "{small_share} of {} small shifts",
        small.len()
    );
}

/// A crowd of one character at the origin facing +z, with `config`.
fn lone_character(config: CrowdConfig) -> (Crowd, u32) {
    let mut crowd = Crowd::new(config).unwrap();
    let id = crowd
        .add_character(&CharacterDesc {
            position: Vec3::ZERO,
            heading: 0.0,
            ..CharacterDesc::default()
        })
        .unwrap();
    (crowd, id)
}

/// The eyes' mean direction (unit) of the crowd's first character.
fn gaze_direction(crowd: &Crowd) -> Vec3 {
    let eyes = crowd.eyes_at(0);
    (eyes.directions[0] + eyes.directions[1]).normalize()
}

#[test]
fn eye_only_saccades_on_the_main_sequence_last_2_2_ms_per_degree_plus_21_ms() {
    let mut config = CrowdConfig {
        eye_motion: EyeMotion::MainSequence,
        ..CrowdConfig::default()
    };
    // Shifts up to 32° move the eyes alone.
    config.gaze.spatial.bands.eyes_only = 32f32.to_radians();
    config.gaze.spatial.bands.eyes_head_and_neck = 50f32.to_radians();
    // Each new point starts a shift (a point target moving farther restarts it).
    config.gaze.timing.restart_distance = 0.1;
    let (mut crowd, id) = lone_character(config);
    let dt = 0.0005;
    // Settle looking straight ahead at a point 5 m away at eye height.
    crowd.step(dt).unwrap();
    let eye = crowd.eyes_at(0).origins[0];
    let ahead = Vec3::new(0.0, eye.y, 5.0);
    let look = |crowd: &mut Crowd, point: Vec3| {
        crowd
            .set_gaze_target(id, ExplicitTarget::Point(point), TargetPriority::Override)
            .unwrap();
    };
    look(&mut crowd, ahead);
    for _ in 0..2000 {
        crowd.step(dt).unwrap();
    }
    for amplitude_degrees in [5.0f32, 10.0, 20.0, 30.0] {
        let from = gaze_direction(&crowd);
        let (sin, cos) = amplitude_degrees.to_radians().sin_cos();
        let target = Vec3::new(5.0 * sin, eye.y, 5.0 * cos);
        look(&mut crowd, target);
        let mut last = from;
        let mut moving_until = 0.0;
        for step in 1..=1000 {
            crowd.step(dt).unwrap();
            let now = gaze_direction(&crowd);
            if now.cross(last).length() > 1e-6 {
                moving_until = step as f32 * dt;
            }
            last = now;
        }
        let amplitude = from.angle_between(last).to_degrees();
        let expected = 0.0022 * amplitude + 0.021;
        println!("{amplitude:.2}°: {moving_until} s, main sequence {expected} s");
        assert!(
            (moving_until - expected).abs() <= 0.1 * expected,
            "a {amplitude}° saccade took {moving_until} s, the main sequence says {expected} s"
        );
        // The head stayed: the eyes did the shift.
        assert!((amplitude - amplitude_degrees).abs() < 1.0, "{amplitude}°");
        // Back to straight ahead for the next one.
        look(&mut crowd, ahead);
        for _ in 0..1000 {
            crowd.step(dt).unwrap();
        }
    }
}

#[test]
fn lids_follow_the_eyes_pitch() {
    let (mut crowd, id) = lone_character(CrowdConfig {
        blinks: BlinkSettings {
            mean_rate: 0.0,
            ..BlinkSettings::default()
        },
        ..CrowdConfig::default()
    });
    crowd.step(1.0 / 60.0).unwrap();
    let eye = crowd.eyes_at(0).origins[0];
    for height in [-1.0f32, -0.3, 0.0, 0.4] {
        let target = Vec3::new(0.0, eye.y + height, 5.0);
        crowd
            .set_gaze_target(id, ExplicitTarget::Point(target), TargetPriority::Override)
            .unwrap();
        for _ in 0..120 {
            crowd.step(1.0 / 60.0).unwrap();
        }
        let lids = crowd.eyelids_at(0);
        let eyes = crowd.eyes_at(0);
        // Targets within 15° of straight ahead move the eyes alone: the head stays upright,
        // so the eye's pitch in the head's frame is its pitch in the world's.
        for (lid, direction) in [
            (lids.left_lid_pitch, eyes.directions[0]),
            (lids.right_lid_pitch, eyes.directions[1]),
        ] {
            let eye_pitch = direction.y.clamp(-1.0, 1.0).asin();
            assert!(
                (lid - eye_pitch).abs() < 2e-3,
                "looking {height} m up: lid {lid}, eye {eye_pitch}"
            );
        }
        if height < 0.0 {
            assert!(lids.left_lid_pitch < -0.05, "looking down lowers the lids");
        }
        assert_eq!(lids.left_closure, 0.0);
    }
}

#[test]
fn bad_blink_settings_are_refused_and_change_nothing() {
    let bad = [
        (
            BlinkSettings {
                mean_rate: -1.0,
                ..BlinkSettings::default()
            },
            "invalid",
        ),
        (
            BlinkSettings {
                mean_rate: f32::NAN,
                ..BlinkSettings::default()
            },
            "non-finite",
        ),
        (
            BlinkSettings {
                rate_spread: 1.5,
                ..BlinkSettings::default()
            },
            "invalid",
        ),
        (
            BlinkSettings {
                evoked_probability: f32::INFINITY,
                ..BlinkSettings::default()
            },
            "non-finite",
        ),
    ];
    for (blinks, kind) in bad {
        let error = Crowd::new(CrowdConfig {
            blinks,
            ..CrowdConfig::default()
        })
        .unwrap_err();
        match (kind, &error) {
            ("invalid", Error::InvalidArgument(_)) | ("non-finite", Error::NonFinite(_)) => {}
            _ => panic!("{blinks:?}: {error:?}"),
        }
    }
}

#[test]
fn the_c_config_names_a_bad_blink_field() {
    use crowdgaze::ffi::crowd::{cg_crowd, cg_crowd_config_init, cg_crowd_create};
    use crowdgaze::ffi::last_error::last_error_message;
    use crowdgaze::ffi::status::cg_status;
    type Spoil = fn(&mut crowdgaze::ffi::crowd::cg_crowd_config);
    let cases: [(Spoil, cg_status, &str); 4] = [
        (
            |c| c.blink_rate = f32::NAN,
            cg_status::NonFinite,
            "blink_rate",
        ),
        (
            |c| c.lid_gain = f32::INFINITY,
            cg_status::NonFinite,
            "lid_gain",
        ),
        (
            |c| c.blink_rate_spread = 1.0,
            cg_status::InvalidArgument,
            "blink_rate_spread",
        ),
        (
            |c| c.eye_motion = 9,
            cg_status::InvalidArgument,
            "eye_motion",
        ),
    ];
    for (spoil, status, field) in cases {
        let mut config = support::init(cg_crowd_config_init);
        spoil(&mut config);
        let mut crowd: *mut cg_crowd = std::ptr::null_mut();
        // SAFETY: a config of its own size and a writable handle.
        assert_eq!(unsafe { cg_crowd_create(&config, &mut crowd) }, status);
        assert!(crowd.is_null());
        let message = last_error_message();
        assert!(
            message.contains(&format!("cg_crowd_config.{field}")),
            "{field}: {message}"
        );
    }
}

#[test]
fn a_longer_output_than_asked_for_is_written_only_as_far_as_count() {
    use crowdgaze::ffi::eyelids::{cg_crowd_read_eyelids, cg_eyelids};
    use crowdgaze::ffi::status::cg_status;
    let handle =
        support::CrowdHandle::new(&support::init(crowdgaze::ffi::crowd::cg_crowd_config_init));
    for x in 0..3 {
        handle.add_character(Vec3::new(x as f32, 0.0, 0.0), 0.0);
    }
    let untouched = cg_eyelids {
        character: 77,
        left_closure: 7.0,
        ..cg_eyelids::default()
    };
    let mut out = [untouched; 8];
    // SAFETY: a live crowd and 8 writable entries.
    let status =
        unsafe { cg_crowd_read_eyelids(handle.as_const(), 1, 2, out.as_mut_ptr(), out.len()) };
    assert_eq!(status, cg_status::Ok);
    assert!(out[..2].iter().all(|lids| lids.character != 77));
    assert!(out[2..].iter().all(|lids| *lids == untouched));
}
