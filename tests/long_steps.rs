//! Long time steps: every finite `dt` the API accepts returns at once, whatever the stage
//! (blinks, conversation turns, interest-point clocks, glances, level-of-detail clocks,
//! plans), leaves every output finite, and the crowd goes on living afterwards — it blinks,
//! looks and talks again at normal frame rates.
//!
//! A step that does not return within [`DEADLINE`] fails the test (a hang is a crash); the
//! deadline is a guard, not a measurement: a long step costs what a normal one does.

mod support;

use crowdgaze::scenario::Scenario;
use crowdgaze::{Crowd, CrowdConfig};
use std::sync::mpsc;
use std::time::Duration;

/// How long a test may run before it counts as a hang.
const DEADLINE: Duration = Duration::from_secs(120);

/// Steps of a normal frame.
const DT: f32 = 1.0 / 30.0;

/// The long steps tried, seconds: a time stamp passed as a step (`time.time()`), where f32
/// steps of blink intervals stop making progress, and the largest finite f32.
const LONG_STEPS: [f32; 6] = [1.0e4, 1.0e7, 3.0e8, 1.7e9, 1.0e20, f32::MAX];

/// Runs `test` on its own thread and fails if it does not end within [`DEADLINE`].
fn within_deadline(test: impl FnOnce() + Send + 'static) {
    let (done, finished) = mpsc::channel();
    let worker = std::thread::spawn(move || {
        test();
        let _ = done.send(());
    });
    match finished.recv_timeout(DEADLINE) {
        Ok(()) => worker.join().unwrap(),
        Err(mpsc::RecvTimeoutError::Disconnected) => {
            // The test panicked: report its panic.
            if let Err(panic) = worker.join() {
                std::panic::resume_unwind(panic);
            }
        }
        Err(mpsc::RecvTimeoutError::Timeout) => {
            panic!("a long step did not return within {DEADLINE:?}: it hangs")
        }
    }
}

/// The mixed street (three attention models, a level of detail, attention every second
/// step, explicit targets) with talking groups, on `threads` threads.
fn street(threads: u32, max_recorded_states: u32) -> (Crowd, Scenario) {
    let config = CrowdConfig {
        threads,
        max_recorded_states,
        ..support::mixed_street_config()
    };
    let mut crowd = Crowd::new(config).unwrap();
    let mut scenario = Scenario::street(60, 12, 5).with_conversations(0.3, 7);
    scenario.populate(&mut crowd).unwrap();
    let ids = scenario.character_ids().to_vec();
    support::mix_attention_models(&mut crowd, &ids);
    crowd
        .set_viewer(glam::Vec3::new(3.0, 1.7, 2.0), 2.0)
        .unwrap();
    (crowd, scenario)
}

/// Plays `frames` normal frames.
fn play(crowd: &mut Crowd, scenario: &mut Scenario, frames: usize) {
    scenario.play(crowd, frames, DT, |_| ()).unwrap();
}

/// Every output is finite (the ids among them are integers, skipped).
fn assert_finite(crowd: &Crowd, what: &str) {
    for character in 0..crowd.character_count() {
        let gaze = crowd.gaze_at(character);
        let lids = crowd.eyelids_at(character);
        let eyes = crowd.eyes_at(character);
        let numbers = gaze
            .target_position
            .to_array()
            .into_iter()
            .chain([gaze.s_max, gaze.threshold, gaze.attentive_fraction])
            .chain([lids.left_closure, lids.right_closure])
            .chain([lids.left_lid_pitch, lids.right_lid_pitch])
            .chain(eyes.origins.iter().flat_map(|v| v.to_array()))
            .chain(eyes.directions.iter().flat_map(|v| v.to_array()));
        for number in numbers {
            // s_max and the threshold may be infinite by design (a character that never
            // attends has an infinite threshold); NaN never.
            assert!(!number.is_nan(), "{what}: character {character} has NaN");
        }
    }
    let count = crowd.character_count();
    let mut joints = vec![glam::Quat::IDENTITY; crowd.joint_total(0, count).unwrap()];
    crowd.read_joints(0, count, false, &mut joints).unwrap();
    for joint in &joints {
        assert!(joint.is_finite(), "{what}: a joint is {joint:?}");
        assert!((joint.length() - 1.0).abs() < 1e-3, "{what}: {joint:?}");
    }
}

/// Blinks, interest points and glances seen over `frames` normal frames: the crowd still
/// lives.
fn assert_alive(crowd: &mut Crowd, scenario: &mut Scenario, what: &str) {
    let mut blinking = 0;
    let mut closed_frames = 0;
    let mut targets = std::collections::BTreeSet::new();
    let start = crowd.time().max(0.0);
    for frame in 0..150 {
        scenario.advance(DT);
        scenario
            .push(crowd, start + (frame + 1) as f64 * f64::from(DT))
            .unwrap();
        crowd.step(DT).unwrap();
        let mut closed = 0;
        for character in 0..crowd.character_count() {
            closed += usize::from(crowd.eyelids_at(character).left_closure > 0.0);
            targets.insert((character, crowd.gaze_at(character).target));
        }
        blinking = blinking.max(closed);
        closed_frames += usize::from(closed > 0);
    }
    assert_finite(crowd, what);
    // 60 characters at about 17 blinks a minute blink about 85 times in 5 s.
    assert!(
        closed_frames > 30,
        "{what}: lids closed in {closed_frames} frames of 150"
    );
    assert!(blinking < 20, "{what}: {blinking} characters blink at once");
    // Each character looks at several things in 5 s.
    assert!(
        targets.len() > 90,
        "{what}: {} (character, target) pairs",
        targets.len()
    );
}

#[test]
fn long_steps_return_and_leave_the_crowd_alive() {
    within_deadline(|| {
        for threads in [1, 2] {
            for dt in LONG_STEPS {
                let what = format!("dt {dt:e} on {threads} threads");
                let (mut crowd, mut scenario) = street(threads, 0);
                play(&mut crowd, &mut scenario, 20);
                // The people stand still during the long step: the clocks move, not them.
                let time = crowd.time() + f64::from(dt);
                scenario.push(&mut crowd, time).unwrap();
                crowd.step(dt).unwrap();
                assert_finite(&crowd, &what);
                // Several long steps in a row, then back to normal frames.
                for _ in 0..3 {
                    crowd.step(dt).unwrap();
                }
                assert_finite(&crowd, &what);
                assert_alive(&mut crowd, &mut scenario, &what);
            }
        }
    });
}

#[test]
fn long_steps_in_ranges_and_halves_return() {
    within_deadline(|| {
        for dt in LONG_STEPS {
            let what = format!("dt {dt:e}, ranged");
            let (mut crowd, mut scenario) = street(1, 0);
            play(&mut crowd, &mut scenario, 10);
            crowd.begin_step(dt).unwrap();
            {
                let ranges = crowd.step_ranges().unwrap();
                let count = ranges.character_count();
                std::thread::scope(|scope| {
                    scope.spawn(|| ranges.run_range(0, count / 2).unwrap());
                    scope.spawn(|| ranges.run_range(count / 2, count - count / 2).unwrap());
                });
            }
            crowd.end_step().unwrap();
            crowd.step_attention(dt).unwrap();
            crowd.step_gaze(dt).unwrap();
            assert_finite(&crowd, &what);
            assert_alive(&mut crowd, &mut scenario, &what);
        }
    });
}

#[test]
fn long_steps_follow_a_plan() {
    within_deadline(|| {
        for dt in [1.0e7, 3.0e8, f32::MAX] {
            let what = format!("dt {dt:e}, planned");
            let (mut crowd, mut scenario) = street(1, 60 * 80);
            play(&mut crowd, &mut scenario, 60);
            crowd.plan().unwrap();
            crowd.step(dt).unwrap();
            crowd.step(dt).unwrap();
            assert_finite(&crowd, &what);
        }
    });
}
