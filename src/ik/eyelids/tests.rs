//! The blink model against its sources: rates, durations and shapes, gaze-evoked shares,
//! lids, determinism and the settings' ranges.

use super::*;

const FPS: f32 = 30.0;
const DT: f32 = 1.0 / FPS;
/// Ten simulated minutes at 30 frames per second.
const FRAMES: usize = 10 * 60 * 30;

/// The seeds of `count` characters.
fn seeds(count: u64) -> Vec<u64> {
    (0..count)
        .map(|i| crate::math::random::stream(7, Purpose::Scene, i).next_u64())
        .collect()
}

/// A blink seen frame by frame: its start frame, length in frames, and the frame its
/// closure peaked.
#[derive(Debug)]
struct Blink {
    start: usize,
    frames: usize,
    peak: usize,
    duration: f32,
}

/// Runs one character for `frames` frames, with a gaze shift of `amplitude` every
/// `shift_every` frames if given, and returns its blinks and the frames shifts started.
fn run(
    settings: &BlinkSettings,
    seed: u64,
    frames: usize,
    shifts: Option<(usize, f32)>,
) -> Vec<Blink> {
    let mut state = BlinkState::new(settings, seed);
    let mut blinks: Vec<Blink> = Vec::new();
    let mut peak_closure = 0.0;
    let mut was_blinking = false;
    for frame in 0..frames {
        let shift = shifts.and_then(|(every, amplitude)| (frame % every == 0).then_some(amplitude));
        let before = state.draws();
        state.advance(settings, seed, DT, shift);
        let closure = state.closure(seed);
        assert!((0.0..=1.0).contains(&closure), "closure {closure}");
        let blinking = state.is_blinking();
        let new_blink = blinking && (!was_blinking || state.draws() != before);
        if new_blink {
            blinks.push(Blink {
                start: frame,
                frames: 0,
                peak: frame,
                duration: state.blink_duration(seed).unwrap(),
            });
            peak_closure = 0.0;
        }
        if blinking {
            let blink = blinks.last_mut().unwrap();
            blink.frames += 1;
            if closure > peak_closure {
                peak_closure = closure;
                blink.peak = frame;
            }
        }
        was_blinking = blinking;
    }
    blinks
}

#[test]
fn rates_follow_each_characters_draw_and_the_crowd_mean() {
    let settings = BlinkSettings::default();
    let seeds = seeds(100);
    let mut rates = Vec::new();
    for &seed in &seeds {
        let rate = settings.rate_of(seed);
        assert!(
            (8.5..=25.5).contains(&rate),
            "rate {rate} outside 17 ± 50 %"
        );
        let blinks = run(&settings, seed, FRAMES, None).len() as f32;
        let measured = blinks / 10.0;
        assert!(
            (measured - rate).abs() <= 0.2 * rate,
            "seed {seed}: {measured} blinks a minute, drawn {rate}"
        );
        rates.push(measured);
    }
    let mean = rates.iter().sum::<f32>() / rates.len() as f32;
    assert!(
        (mean - 17.0).abs() < 1.0,
        "crowd mean {mean} blinks a minute"
    );
    // Not regular: the intervals of one character vary.
    let blinks = run(&settings, seeds[0], FRAMES, None);
    let gaps: Vec<f32> = blinks
        .windows(2)
        .map(|pair| (pair[1].start - pair[0].start) as f32 * DT)
        .collect();
    let gap_mean = gaps.iter().sum::<f32>() / gaps.len() as f32;
    let spread = (gaps.iter().map(|g| (g - gap_mean).powi(2)).sum::<f32>() / gaps.len() as f32)
        .sqrt()
        / gap_mean;
    assert!(
        (0.4..0.8).contains(&spread),
        "coefficient of variation {spread}"
    );
}

#[test]
fn blinks_last_100_to_500_ms_and_close_faster_than_they_open() {
    let settings = BlinkSettings::default();
    let mut count = 0;
    for seed in seeds(20) {
        let blinks = run(&settings, seed, FRAMES / 4, None);
        // (Leaving out one cut short by the end of the run.)
        for blink in blinks.iter().filter(|b| b.start + 15 < FRAMES / 4) {
            assert!((0.1..=0.5).contains(&blink.duration), "{blink:?}");
            // Seen in frames: the blink spans its duration, give or take a frame.
            let seen = blink.frames as f32 * DT;
            assert!((seen - blink.duration).abs() <= DT + 1e-4, "{blink:?}");
            // The peak comes in the first half: closing is faster than opening.
            let to_peak = (blink.peak - blink.start) as f32 * DT;
            assert!(to_peak < 0.5 * blink.duration, "{blink:?}");
            count += 1;
        }
    }
    assert!(count > 200, "{count} blinks");
    // The shape itself: closed at a third, half open again halfway through the opening.
    let seed = 3;
    let mut state = BlinkState::new(&settings, seed);
    while !state.is_blinking() {
        state.advance(&settings, seed, 1e-3, None);
    }
    let duration = state.blink_duration(seed).unwrap();
    let start = -state.clock;
    state.advance(&settings, seed, CLOSING_SHARE * duration - start, None);
    assert!((state.closure(seed) - 1.0).abs() < 1e-3);
    state.advance(
        &settings,
        seed,
        (1.0 - CLOSING_SHARE) * duration / 2.0,
        None,
    );
    assert!((state.closure(seed) - 0.5).abs() < 1e-3);
}

#[test]
fn large_gaze_shifts_start_a_blink_as_the_curve_says() {
    let settings = BlinkSettings::default();
    // A shift every 2 s for ten minutes, per amplitude: the share of shifts whose frame
    // starts a blink.
    for (degrees, expected) in [(45.0f32, 0.97), (21.5, 0.485), (5.0, 0.0)] {
        let mut shifts = 0;
        let mut evoked = 0;
        for seed in seeds(10) {
            let blinks = run(&settings, seed, FRAMES, Some((60, degrees.to_radians())));
            shifts += FRAMES.div_ceil(60);
            evoked += blinks.iter().filter(|b| b.start % 60 == 0).count();
        }
        let share = evoked as f32 / shifts as f32;
        // Spontaneous blinks start in a shift's frame about once in a hundred.
        assert!(
            (share - expected).abs() <= 0.1,
            "{degrees}°: {share} of shifts with a blink, curve {expected}"
        );
    }
    assert_eq!(settings.evoked_probability_at(40f32.to_radians()), 0.97);
    assert_eq!(settings.evoked_probability_at(0.0), 0.0);
}

#[test]
fn a_characters_blinking_takes_8_bytes() {
    assert_eq!(std::mem::size_of::<BlinkState>(), 8);
}

#[test]
fn lids_follow_the_eyes_pitch() {
    let settings = BlinkSettings::default();
    for pitch in [-0.4f32, -0.1, 0.0, 0.2] {
        assert_eq!(settings.lid_pitch(pitch), pitch);
    }
    let half = BlinkSettings {
        lid_gain: 0.5,
        ..settings
    };
    assert_eq!(half.lid_pitch(-0.4), -0.2);
}

#[test]
fn the_same_seed_blinks_the_same_and_others_differ() {
    let settings = BlinkSettings::default();
    let starts = |seed| -> Vec<usize> {
        run(&settings, seed, FRAMES / 10, Some((45, 0.7)))
            .iter()
            .map(|b| b.start)
            .collect()
    };
    assert_eq!(starts(11), starts(11));
    assert_ne!(starts(11), starts(12));
    // No spontaneous blinks at rate 0, and none evoked at probability 0.
    let still = BlinkSettings {
        mean_rate: 0.0,
        evoked_probability: 0.0,
        ..settings
    };
    assert!(run(&still, 5, FRAMES / 10, Some((30, 1.0))).is_empty());
}

#[test]
fn settings_out_of_range_are_refused() {
    assert!(BlinkSettings::default().validate().is_ok());
    let bad = [
        BlinkSettings {
            mean_rate: -1.0,
            ..Default::default()
        },
        BlinkSettings {
            mean_rate: 121.0,
            ..Default::default()
        },
        BlinkSettings {
            rate_spread: 1.0,
            ..Default::default()
        },
        BlinkSettings {
            rate_spread: -0.1,
            ..Default::default()
        },
        BlinkSettings {
            evoked_min_amplitude: 0.7,
            evoked_full_amplitude: 0.5,
            ..Default::default()
        },
        BlinkSettings {
            evoked_probability: 1.5,
            ..Default::default()
        },
        BlinkSettings {
            lid_gain: 3.0,
            ..Default::default()
        },
    ];
    for settings in bad {
        assert!(
            matches!(settings.validate(), Err(Error::InvalidArgument(_))),
            "{settings:?}"
        );
    }
    let nan = BlinkSettings {
        mean_rate: f32::NAN,
        ..Default::default()
    };
    assert!(matches!(nan.validate(), Err(Error::NonFinite(_))));
}

#[test]
fn eye_pitches_measure_each_eye_against_the_heads_up() {
    use crate::ik::{GazeChain, MAX_CHAIN_JOINTS};
    use glam::{Quat, Vec3};
    let chain = GazeChain::human(Vec3::Y, Vec3::Z);
    let rest = |joint: usize| chain.joints()[joint].rest;
    let [left, right] = chain.eye_indices().unwrap();
    let mut deltas = [Quat::IDENTITY; MAX_CHAIN_JOINTS];
    let deltas = &mut deltas[..chain.joint_count()];
    assert_eq!(eye_pitches(&chain, rest, deltas), [0.0, 0.0]);
    // Turning an eye about the head's side axis (+x: forward +z goes down) pitches it down;
    // turning it about the head's up leaves its pitch alone.
    deltas[left] = Quat::from_rotation_x(0.3);
    deltas[right] = Quat::from_rotation_y(0.5);
    let [left_pitch, right_pitch] = eye_pitches(&chain, rest, deltas);
    assert!((left_pitch + 0.3).abs() < 1e-5, "{left_pitch}");
    assert!(right_pitch.abs() < 1e-5, "{right_pitch}");
    // A chain without eyes: no pitch.
    let eyeless = GazeChain::new(
        &chain.joints()[..chain.body_count()],
        chain.eye_forward(),
        chain.eye_up(),
        chain.root_offset(),
    )
    .unwrap();
    assert_eq!(eye_pitches(&eyeless, rest, deltas), [0.0, 0.0]);
}

#[test]
fn a_step_of_any_length_returns_with_open_eyes_and_blinking_goes_on() {
    let settings = BlinkSettings {
        mean_rate: 120.0, // the most draws a step can need
        ..BlinkSettings::default()
    };
    for seed in seeds(20) {
        for dt in [30.0, 61.0, 1.0e4, 1.0e7, 3.0e8, 1.0e20, f32::MAX] {
            let mut state = BlinkState::new(&settings, seed);
            state.advance(&settings, seed, 1.0, Some(1.0)); // mid-blink, evoked
            let before = state.draws();
            state.advance(&settings, seed, dt, None);
            // Replayed blink by blink up to the horizon, started afresh beyond it: a
            // bounded number of draws either way.
            let used = state.draws() - before;
            assert!(
                used as f32 <= CATCH_UP_HORIZON / MIN_OPEN + 1.0,
                "dt {dt}: {used} draws"
            );
            assert!(state.clock.is_finite(), "dt {dt}: clock {}", state.clock);
            if dt > CATCH_UP_HORIZON {
                assert!(
                    !state.is_blinking(),
                    "dt {dt}: blinking after a fresh start"
                );
                assert_eq!(used, 1, "dt {dt}: a fresh start draws once");
            }
            // Normal frames afterwards: the character blinks again within a minute.
            let blinks_before = state.draws();
            for _ in 0..(60.0 * FPS) as usize {
                state.advance(&settings, seed, DT, None);
                assert!((0.0..=1.0).contains(&state.closure(seed)));
            }
            assert!(
                state.draws() > blinks_before + 10,
                "dt {dt}: no blinks after"
            );
        }
    }
}
