//! Tests of the spatial resolution: shares, recruitment bands, vergence, the behind rule's
//! hysteresis, degenerate targets and input checks.

use std::f32::consts::PI;

use glam::{Quat, Vec3};

use super::{eye_rays, solve, SpatialConfig, SpatialSolution, TurnSide};
use crate::error::Error;
use crate::ik::chain::GazeChain;
use crate::ik::CharacterTransform;

fn human() -> GazeChain {
    GazeChain::human(Vec3::Y, Vec3::Z)
}

fn rest(chain: &GazeChain) -> Vec<Quat> {
    chain.joints().iter().map(|j| j.rest).collect()
}

fn solve_at(chain: &GazeChain, target: Vec3, side: &mut TurnSide) -> (Vec<Quat>, SpatialSolution) {
    let mut deltas = vec![Quat::NAN; chain.joint_count()];
    let solution = solve(
        chain,
        &SpatialConfig::default(),
        &CharacterTransform::IDENTITY,
        &rest(chain),
        target,
        target,
        side,
        &mut deltas,
    )
    .unwrap();
    (deltas, solution)
}

/// A target at `yaw` degrees to the left, at eye height, `distance` metres away.
fn around(yaw: f32, distance: f32) -> Vec3 {
    let yaw = yaw.to_radians();
    Vec3::new(yaw.sin() * distance, 1.62, yaw.cos() * distance)
}

#[test]
fn shares_follow_the_linear_formula() {
    // Unlimited joints and a far target: the spine shares are c_i = 2(n+1−i)/(n(n+1)).
    let mut joints = human().joints().to_vec();
    for joint in &mut joints {
        joint.limits = JointLimits::free(joint.limits.twist_axis());
    }
    use super::super::chain::JointLimits;
    let chain = GazeChain::new(&joints, Vec3::Z, Vec3::Y, Vec3::Y * 0.95).unwrap();
    let (deltas, solution) = solve_at(&chain, around(100.0, 1000.0), &mut TurnSide::default());
    assert!((solution.gaze_angle - 100f32.to_radians()).abs() < 1e-3);
    let spine: Vec<f32> = deltas[..5]
        .iter()
        .map(|q| q.angle_between(Quat::IDENTITY))
        .collect();
    let budget = 70f32.to_radians();
    for (i, angle) in spine.iter().enumerate() {
        let expected = budget * 2.0 * (5 - i) as f32 / 30.0;
        assert!(
            (angle - expected).abs() < 2e-3,
            "spine {i}: {angle} vs {expected}"
        );
    }
    let neck: Vec<f32> = deltas[5..8]
        .iter()
        .map(|q| q.angle_between(Quat::IDENTITY))
        .collect();
    let budget = 15f32.to_radians();
    for (i, angle) in neck.iter().enumerate() {
        let expected = budget * 2.0 * (3 - i) as f32 / 12.0;
        assert!(
            (angle - expected).abs() < 2e-3,
            "neck {i}: {angle} vs {expected}"
        );
    }
}

#[test]
fn bands_recruit_groups() {
    let chain = human();
    let (deltas, solution) = solve_at(&chain, around(10.0, 3.0), &mut TurnSide::default());
    assert!(solution.gaze_angle < 15f32.to_radians());
    assert!(deltas[..8].iter().all(|q| *q == Quat::IDENTITY));
    assert!(deltas[8] != Quat::IDENTITY);
    let (deltas, _) = solve_at(&chain, around(25.0, 3.0), &mut TurnSide::default());
    assert!(deltas[..5].iter().all(|q| *q == Quat::IDENTITY));
    assert!(deltas[5..8].iter().all(|q| *q != Quat::IDENTITY));
    let (deltas, _) = solve_at(&chain, around(60.0, 3.0), &mut TurnSide::default());
    assert!(deltas.iter().all(|q| *q != Quat::IDENTITY));
}

#[test]
fn eyes_converge_on_the_target() {
    let chain = human();
    for yaw in [0.0, 5.0, 20.0, -40.0, 80.0, -100.0] {
        let target = around(yaw, 2.0) + Vec3::Y * 0.3;
        let (deltas, _) = solve_at(&chain, target, &mut TurnSide::default());
        let rays = eye_rays(
            &chain,
            &CharacterTransform::IDENTITY,
            &rest(&chain),
            &deltas,
        )
        .unwrap();
        for eye in 0..2 {
            let wanted = (target - rays.origins[eye]).normalize();
            let error = rays.directions[eye].angle_between(wanted);
            assert!(error < 0.5f32.to_radians(), "yaw {yaw} eye {eye}: {error}");
        }
    }
}

#[test]
fn behind_keeps_its_side_with_hysteresis() {
    let chain = human();
    let mut side = TurnSide::UNDECIDED;
    let head_yaw = |deltas: &[Quat]| {
        let (_, twist) = chain.joints()[7].limits.swing_twist_angles(deltas[7]);
        twist
    };
    // Exactly behind, undecided: left.
    let (deltas, _) = solve_at(&chain, Vec3::new(0.0, 1.62, -3.0), &mut side);
    assert_eq!(side, TurnSide::LEFT);
    assert!(head_yaw(&deltas) > 0.0);
    // Sweep from 150° left through behind to 160° right (−160°): still turning left.
    for yaw in [150.0, 170.0, 179.0, 181.0, 190.0, 200.0, 205.0] {
        let (deltas, solution) = solve_at(&chain, around(yaw, 3.0), &mut side);
        assert_eq!(side, TurnSide::LEFT, "at {yaw}");
        assert!(!solution.side_switched);
        assert!(head_yaw(&deltas) > 0.0, "at {yaw}");
    }
    // Clearly on the right: switch, reported once.
    let (deltas, solution) = solve_at(&chain, around(215.0, 3.0), &mut side);
    assert_eq!(side, TurnSide::RIGHT);
    assert!(solution.side_switched);
    assert!(head_yaw(&deltas) < 0.0);
    let (_, solution) = solve_at(&chain, around(200.0, 3.0), &mut side);
    assert!(!solution.side_switched);
    assert_eq!(side, TurnSide::RIGHT);
}

#[test]
fn degenerate_targets_give_finite_deltas() {
    let chain = human();
    let eye = chain.rest_eye_position();
    for target in [
        eye,
        eye + Vec3::Y * 5.0,
        eye - Vec3::Z * 2.0,
        eye + Vec3::Z * 1e-7,
        eye - Vec3::Y * 3.0,
    ] {
        let (deltas, _) = solve_at(&chain, target, &mut TurnSide::default());
        assert!(
            deltas
                .iter()
                .all(|q| q.is_finite() && (q.length() - 1.0).abs() < 1e-4),
            "{target}"
        );
    }
    let (deltas, solution) = solve_at(&chain, eye, &mut TurnSide::default());
    assert_eq!(solution.gaze_angle, 0.0);
    assert!(deltas[..8].iter().all(|q| *q == Quat::IDENTITY));
    let _ = PI;
}

#[test]
fn bad_inputs_are_errors() {
    let chain = human();
    let mut deltas = vec![Quat::IDENTITY; 10];
    let base = rest(&chain);
    let call = |base: &[Quat], target: Vec3, deltas: &mut [Quat]| {
        solve(
            &chain,
            &SpatialConfig::default(),
            &CharacterTransform::IDENTITY,
            base,
            target,
            target,
            &mut TurnSide::default(),
            deltas,
        )
    };
    assert!(matches!(
        call(&base[..9], Vec3::Z, &mut deltas),
        Err(Error::InvalidArgument(_))
    ));
    assert!(matches!(
        call(&base, Vec3::NAN, &mut deltas),
        Err(Error::NonFinite(_))
    ));
    assert!(matches!(
        call(&base, Vec3::Z, &mut deltas[..3]),
        Err(Error::InvalidArgument(_))
    ));
}
