//! SIMD widths: the mixed street (every chain shape of `support::varied_chains` side by side,
//! base poses, three attention models, a level of detail) gives the same outputs bit for
//! bit with 1 lane (plain floats), 4 (SSE2), 8 (AVX) and 16 (AVX-512F) — each where the
//! processor has it — stepped whole, and with every character in a range of its own (so
//! that each sits alone in its batch, and every batch boundary falls between two).
//!
//! Its own test binary: the width limit (`crowdgaze::math::set_max_simd_lanes`) is
//! process-wide, and the tests here take turns with it ([`WIDTH`]).

mod support;

use crowdgaze::math::set_max_simd_lanes;
use crowdgaze::{Crowd, CrowdConfig};
use glam::Vec3;

/// Held while a test sets the width and runs at it.
static WIDTH: std::sync::Mutex<()> = std::sync::Mutex::new(());

const PEOPLE: usize = 70;
const FRAMES: usize = 60;
const DT: f32 = 1.0 / 30.0;

/// The widths to compare: 1 and 4 everywhere, 8 and 16 where the processor has them.
fn widths() -> Vec<usize> {
    let mut widths = vec![1, 4];
    #[cfg(target_arch = "x86_64")]
    {
        if std::is_x86_feature_detected!("avx") {
            widths.push(8);
        }
        if std::is_x86_feature_detected!("avx512f") {
            widths.push(16);
        }
    }
    widths
}

/// Runs the mixed street for `FRAMES` frames at `lanes`, stepping each frame with `step`.
fn run(lanes: usize, step: fn(&mut Crowd, usize)) -> Vec<Vec<u32>> {
    let _turn = WIDTH
        .lock()
        .unwrap_or_else(|poisoned| poisoned.into_inner());
    set_max_simd_lanes(lanes);
    let config = CrowdConfig {
        threads: 1,
        ..support::mixed_street_config()
    };
    let (mut crowd, mut scenario) = support::mixed_street(config, PEOPLE, 20, 4);
    let outputs = (0..FRAMES)
        .map(|frame| {
            scenario.advance(DT);
            scenario
                .push(&mut crowd, (frame + 1) as f64 * f64::from(DT))
                .unwrap();
            let viewer = Vec3::new(1.0 + frame as f32 * 0.1, 1.7, 2.0);
            crowd.set_viewer(viewer, 2.0).unwrap();
            step(&mut crowd, frame);
            support::output_bits(&crowd)
        })
        .collect();
    set_max_simd_lanes(usize::MAX);
    outputs
}

fn whole(crowd: &mut Crowd, _: usize) {
    crowd.step(DT).unwrap();
}

/// Every character in a range of its own, in reverse order; or, every other frame, ranges
/// of 1 to 17 characters, so that the ranges' ends fall at every offset of a batch.
fn split(crowd: &mut Crowd, frame: usize) {
    crowd.begin_step(DT).unwrap();
    let count = crowd.character_count();
    if frame.is_multiple_of(2) {
        for first in (0..count).rev() {
            crowd.step_range(first, 1).unwrap();
        }
    } else {
        let mut first = 0;
        let mut size = 1 + frame % 17;
        while first < count {
            let take = size.min(count - first);
            crowd.step_range(first, take).unwrap();
            first += take;
            size = 1 + (size * 5 + 3) % 17;
        }
    }
    crowd.end_step().unwrap();
}

#[test]
fn every_width_and_split_gives_the_same_bits() {
    let expected = run(usize::MAX, whole);
    assert!(expected.first() != expected.last(), "the street moved");
    for lanes in widths() {
        support::assert_same(&expected, &run(lanes, whole), &format!("{lanes} lanes"));
        support::assert_same(
            &expected,
            &run(lanes, split),
            &format!("{lanes} lanes, split"),
        );
    }
}

#[test]
fn head_and_eyes_alone_look_from_the_head_in_any_batch() {
    // A chain of head and eyes only (no spine, no neck) next to longer chains: its eyes
    // hang from its head at 1.56 + 0.06 m, whether it is stepped with the others or alone.
    let world = crowdgaze::World::default();
    let chains = support::varied_chains(&world);
    let eyes_only = chains[1];
    let mut crowd = Crowd::new(CrowdConfig::default()).unwrap();
    let mut ids = Vec::new();
    for i in 0..20 {
        let chain = if i == 5 { eyes_only } else { chains[0] };
        let desc = crowdgaze::CharacterDesc {
            position: Vec3::new(i as f32, 0.0, 0.0),
            chain: Some(chain),
            ..Default::default()
        };
        ids.push(crowd.add_character(&desc).unwrap());
    }
    crowd.step(DT).unwrap();
    let character = (0..crowd.character_count())
        .find(|&c| crowd.gaze_at(c).character == ids[5])
        .unwrap();
    let eyes = crowd.eyes_at(character);
    for origin in eyes.origins {
        assert!((origin.y - 1.62).abs() < 0.02, "eye origin {origin}");
    }
    // Alone in its range: the same bits.
    crowd.begin_step(DT).unwrap();
    crowd.step_range(character, 1).unwrap();
    crowd.end_step().unwrap();
    let alone = crowd.eyes_at(character);
    let mut twin = Crowd::new(CrowdConfig::default()).unwrap();
    for (i, _) in ids.iter().enumerate() {
        let chain = if i == 5 { eyes_only } else { chains[0] };
        let desc = crowdgaze::CharacterDesc {
            position: Vec3::new(i as f32, 0.0, 0.0),
            chain: Some(chain),
            ..Default::default()
        };
        twin.add_character(&desc).unwrap();
    }
    twin.step(DT).unwrap();
    twin.step(DT).unwrap();
    let together = twin.eyes_at(character);
    assert_eq!(alone.origins, together.origins);
    assert_eq!(alone.directions, together.directions);
}

/// Three characters of one chain, each with its own base pose, looking at points that
/// sweep around them (so that some recruit the spine and some not in the same batch).
fn three_with_base_poses(lanes: usize, alone: bool, explicit: bool) -> Vec<Vec<u32>> {
    use crowdgaze::crowd::{ExplicitTarget, TargetPriority};
    let _turn = WIDTH
        .lock()
        .unwrap_or_else(|poisoned| poisoned.into_inner());
    set_max_simd_lanes(lanes);
    let mut crowd = Crowd::new(CrowdConfig::default()).unwrap();
    let ids: Vec<u32> = (0..3)
        .map(|i| {
            let desc = crowdgaze::CharacterDesc {
                position: Vec3::new(2.0 * i as f32, 0.0, 0.0),
                heading: 0.4 * i as f32,
                ..Default::default()
            };
            crowd.add_character(&desc).unwrap()
        })
        .collect();
    support::set_base_poses(&mut crowd, &ids);
    let side = crowd.config().world.side;
    let pose: Vec<glam::Quat> = (0..10)
        .map(|joint| glam::Quat::from_axis_angle(side, -0.03 * joint as f32))
        .collect();
    crowd.set_base_pose(ids[2], &pose).unwrap();
    let outputs = (0..300)
        .map(|frame| {
            for (i, &id) in ids.iter().enumerate().filter(|_| explicit) {
                let angle = frame as f32 * 0.05 * (1.0 + i as f32) + i as f32;
                let point = Vec3::new(3.0 * angle.sin(), 1.0 + angle.cos(), 3.0 * angle.cos());
                crowd
                    .set_gaze_target(id, ExplicitTarget::Point(point), TargetPriority::Override)
                    .unwrap();
            }
            if alone {
                crowd.begin_step(DT).unwrap();
                for first in 0..3 {
                    crowd.step_range(first, 1).unwrap();
                }
                crowd.end_step().unwrap();
            } else {
                crowd.step(DT).unwrap();
            }
            support::output_bits(&crowd)
        })
        .collect();
    set_max_simd_lanes(usize::MAX);
    outputs
}

#[test]
fn base_poses_give_the_same_bits_stepped_together_or_alone() {
    for explicit in [true, false] {
        let expected = three_with_base_poses(usize::MAX, false, explicit);
        for lanes in widths() {
            for alone in [false, true] {
                support::assert_same(
                    &expected,
                    &three_with_base_poses(lanes, alone, explicit),
                    &format!("{lanes} lanes, alone {alone}, explicit targets {explicit}"),
                );
            }
        }
    }
}
