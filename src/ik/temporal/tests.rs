//! Tests of the temporal resolution: the same bits at every lane width and from the resting
//! characters' short update, the state's size, the activation time and the timing checks.

use glam::{Quat, Vec3, Vec4};

use super::update::UpdateGroups;
use super::{GazeConfig, GazeInput, GazeMotion, GazePhase, GazeRequest, GazeTiming};
use crate::error::Error;
use crate::ik::chain::{ChainJoint, GazeChain, JointLimits, JointRole};
use crate::ik::spatial::{Prepared, TurnSide};
use crate::ik::CharacterTransform;
use crate::math::random::{stream, Purpose, Random};
use crate::math::wide::{for_every_width, LaneJob, Wide};

/// One character's state after a frame, floats as their bits.
type State = (
    Vec<[u32; 4]>,
    [[u32; 3]; 2],
    [[u32; 3]; 2],
    GazePhase,
    TurnSide,
);

/// A vector's bits.
fn bits(v: Vec3) -> [u32; 3] {
    v.to_array().map(f32::to_bits)
}

/// A short chain without eyes (spine, neck, head), so that lane groups mix chains.
fn eyeless_chain() -> GazeChain {
    let limits = |yaw: f32, swing: f32| {
        JointLimits::new(
            Vec3::Y,
            swing.to_radians(),
            -yaw.to_radians(),
            yaw.to_radians(),
        )
    };
    let joints = [
        (
            JointRole::Spine,
            Vec3::new(0.0, 0.1, 0.0),
            limits(10.0, 8.0),
        ),
        (
            JointRole::Spine,
            Vec3::new(0.0, 0.2, 0.0),
            limits(10.0, 8.0),
        ),
        (
            JointRole::Cervical,
            Vec3::new(0.0, 0.25, 0.02),
            limits(35.0, 30.0),
        ),
        (
            JointRole::Head,
            Vec3::new(0.0, 0.1, 0.0),
            limits(40.0, 30.0),
        ),
    ]
    .map(|(role, offset, limits)| ChainJoint::new(role, offset, Quat::IDENTITY, limits));
    GazeChain::new(&joints, Vec3::Z, Vec3::Y, Vec3::new(0.0, 1.0, 0.0)).expect("valid chain")
}

/// 16 characters (three kinds of chain and base pose, each placed and turned its own way,
/// with targets that jump, go behind and drop out) run for `frames` frames in batches of
/// `batch` characters, in lane groups of `W`: every character's state after every frame.
fn run_at<W: Wide>(frames: usize, batch: usize) -> Vec<Vec<State>> {
    let human = GazeChain::human(Vec3::Y, Vec3::Z);
    let eyeless = eyeless_chain();
    let rest: Vec<Quat> = human.joints().iter().map(|joint| joint.rest).collect();
    let animated: Vec<Quat> = (0..10)
        .map(|i| Quat::from_rotation_x(0.02 * i as f32) * Quat::from_rotation_y(-0.03 * i as f32))
        .collect();
    let eyeless_rest = vec![Quat::IDENTITY; eyeless.joint_count()];
    let config = GazeConfig::default();
    let count = 16;
    let chains: Vec<&GazeChain> = (0..count)
        .map(|i| if i % 5 == 3 { &eyeless } else { &human })
        .collect();
    let mut motions: Vec<GazeMotion> = chains.iter().map(|c| GazeMotion::new(c)).collect();
    let mut randoms: Vec<Random> = (0..count)
        .map(|i| stream(5, Purpose::GazeTiming, i as u64))
        .collect();
    let prepared = Prepared::new(&config.spatial);
    let mut history = Vec::new();
    for frame in 0..frames {
        let inputs: Vec<GazeInput<'_>> = (0..count)
            .map(|i| {
                let base = match (i % 5, i % 2) {
                    (3, _) => &eyeless_rest,
                    (_, 0) => &rest,
                    _ => &animated,
                };
                let phase = (frame + 23 * i) % 90;
                let yaw = ((i * 47 + frame / 30 * 61) % 340) as f32 - 170.0;
                let position = Vec3::new(i as f32, 0.0, (i % 3) as f32);
                let target = position
                    + Vec3::new(yaw.to_radians().sin(), 1.6, yaw.to_radians().cos()) * 2.0
                    + Vec3::X * (frame as f32 * 0.02);
                GazeInput {
                    character: CharacterTransform::from_heading(position, Vec3::Y, i as f32 * 0.7),
                    base,
                    request: (phase < 70).then(|| GazeRequest::at((frame / 30 + i) as u64, target)),
                    dt: 1.0 / 30.0,
                }
            })
            .collect();
        let input_refs: Vec<&GazeInput<'_>> = inputs.iter().collect();
        let mut motion_refs: Vec<&mut GazeMotion> = motions.iter_mut().collect();
        let mut random_refs: Vec<&mut Random> = randoms.iter_mut().collect();
        for first in (0..count).step_by(batch) {
            let end = count.min(first + batch);
            UpdateGroups {
                motions: &mut motion_refs[first..end],
                chains: &chains[first..end],
                config: &config,
                inputs: &input_refs[first..end],
                randoms: &mut random_refs[first..end],
                ok: &[true; 16][first..end],
                prepared: &prepared,
            }
            .run::<W>();
        }
        history.push(
            motions
                .iter()
                .map(|m| {
                    (
                        m.deltas()
                            .iter()
                            .map(|q| q.to_array().map(f32::to_bits))
                            .collect(),
                        m.eye_origins().map(bits),
                        m.eye_directions().map(bits),
                        m.phase(),
                        m.turn_side(),
                    )
                })
                .collect(),
        );
    }
    history
}

/// The batched gaze IK does not depend on the width it runs at: the same bits for every
/// character at 4, 8 and 16 lanes.
#[test]
fn update_batch_gives_the_same_bits_at_every_width() {
    let frames = 200;
    let four = run_at::<Vec4>(frames, 16);
    let phases: std::collections::HashSet<String> = four
        .iter()
        .flat_map(|frame| frame.iter().map(|state| format!("{:?}", state.3)))
        .collect();
    assert_eq!(phases.len(), 4, "every phase is exercised: {phases:?}");
    fn same_as_four<W: Wide>(four: &[Vec<State>], frames: usize) {
        let wide = run_at::<W>(frames, 16);
        for (frame, (wide, four)) in wide.iter().zip(four).enumerate() {
            assert_eq!(wide, four, "frame {frame} at {} lanes", W::LANES);
        }
    }
    for_every_width!(same_as_four(&four, frames));
}

/// A character at rest with nothing to look at gets the same bits from the resting
/// characters' short update (its lane group rests wholly: here, a batch of one) as from
/// the full update (its group has moving characters), frame after frame.
#[test]
fn resting_characters_get_the_same_bits_from_the_short_update() {
    let frames = 600;
    let together = run_at::<Vec4>(frames, 16);
    let alone = run_at::<Vec4>(frames, 1);
    // Updates of a resting character (idle before and after) in a group where another
    // character moves: the short update ran for it alone, the full one in the group.
    let idle = |state: &State| state.3 == GazePhase::Idle;
    let compared: usize = together
        .windows(2)
        .filter(|frames| !frames[1].iter().all(idle))
        .map(|frames| {
            let (before, after) = (&frames[0], &frames[1]);
            (0..after.len())
                .filter(|&character| idle(&before[character]) && idle(&after[character]))
                .count()
        })
        .sum();
    assert!(compared >= 40, "only {compared} resting updates compared");
    for (frame, (alone, together)) in alone.iter().zip(&together).enumerate() {
        assert_eq!(alone, together, "frame {frame}");
    }
}

#[test]
fn motion_state_is_small() {
    assert_eq!(std::mem::size_of::<GazeMotion>(), 464);
    assert!(std::mem::size_of::<GazeMotion>() < 1024);
}

#[test]
fn activation_time_formula_and_bounds() {
    let timing = GazeTiming::default();
    // θ_head = π/2 at full interest: (π/2) / 2π = 0.25 s.
    assert!((timing.activation_time(std::f32::consts::FRAC_PI_2, 1.0) - 0.25).abs() < 1e-6);
    // Half the interest, twice the time.
    assert!((timing.activation_time(std::f32::consts::FRAC_PI_2, 0.5) - 0.5).abs() < 1e-6);
    // Capped at 2 s, at least 0.2 s.
    assert_eq!(timing.activation_time(3.0, 0.01), 2.0);
    assert_eq!(timing.activation_time(0.0, 1.0), 0.2);
    assert_eq!(
        timing.activation_time(1.0, 5.0),
        timing.activation_time(1.0, 1.0)
    );
}

#[test]
fn timing_is_validated() {
    assert!(GazeTiming::default().validate().is_ok());
    let bad = GazeTiming {
        min_activation_time: 0.0,
        ..GazeTiming::default()
    };
    assert!(matches!(bad.validate(), Err(Error::InvalidArgument(_))));
    let bad = GazeTiming {
        head_speed: f32::NAN,
        ..GazeTiming::default()
    };
    assert!(matches!(bad.validate(), Err(Error::NonFinite(_))));
    let bad = GazeTiming {
        max_deactivation_time: 0.1,
        ..GazeTiming::default()
    };
    assert!(matches!(bad.validate(), Err(Error::InvalidArgument(_))));
}
