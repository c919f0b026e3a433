//! Gaze IK inside a crowd: interest points and explicit targets turn the chains, base poses
//! are composed, outputs are packed per chain, and removal and bad input are handled.

use crowdgaze::crowd::{ExplicitTarget, TargetPriority};
use crowdgaze::ik::{ChainJoint, GazeChain, JointLimits, JointRole};
use crowdgaze::scenario::Scenario;
use crowdgaze::scene::ids::NO_ENTITY;
use crowdgaze::scene::EntityUpdate;
use crowdgaze::{CharacterDesc, Crowd, CrowdConfig, Error};
use glam::{Quat, Vec3};

const DT: f32 = 1.0 / 30.0;

fn angle_to(origin: Vec3, direction: Vec3, target: Vec3) -> f32 {
    direction.angle_between(target - origin).to_degrees()
}

#[test]
fn an_explicit_target_is_reached_within_half_a_degree() {
    let mut crowd = Crowd::new(CrowdConfig::default()).unwrap();
    let id = crowd.add_character(&CharacterDesc::default()).unwrap();
    let target = Vec3::new(1.2, 1.4, 2.5);
    crowd
        .set_gaze_target(id, ExplicitTarget::Point(target), TargetPriority::Override)
        .unwrap();
    for _ in 0..150 {
        crowd.step(DT).unwrap();
    }
    let eyes = crowd.eyes_at(0);
    for eye in 0..2 {
        let error = angle_to(eyes.origins[eye], eyes.directions[eye], target);
        assert!(error < 0.5, "eye {eye} misses by {error}°");
    }
    // Cleared: back to the base (rest) pose.
    crowd.clear_gaze_target(id).unwrap();
    for _ in 0..90 {
        crowd.step(DT).unwrap();
    }
    let mut joints = [Quat::IDENTITY; 10];
    crowd.read_joints(0, 1, true, &mut joints).unwrap();
    assert!(joints
        .iter()
        .all(|q| q.angle_between(Quat::IDENTITY) < 1e-3));
}

#[test]
fn characters_look_at_their_interest_points() {
    let mut crowd = Crowd::new(CrowdConfig::default()).unwrap();
    let mut scenario = Scenario::street(60, 20, 4);
    scenario.populate(&mut crowd).unwrap();
    let mut checked = 0;
    for frame in 0..600 {
        scenario.advance(DT);
        scenario
            .push(&mut crowd, f64::from(frame as f32 * DT))
            .unwrap();
        crowd.step(DT).unwrap();
        if frame % 30 != 29 {
            continue;
        }
        for (character, &id) in scenario.character_ids().iter().enumerate() {
            let gaze = crowd.gaze(id).unwrap();
            let motion = crowd.gaze_motion(id).unwrap();
            // A target held for a while and reachable by the eyes: they are on it.
            if gaze.attending && motion.elapsed() > 1.0 {
                let eyes = crowd.eyes_at(character);
                let error = angle_to(eyes.origins[0], eyes.directions[0], gaze.target_position);
                if error < 5.0 {
                    checked += 1;
                }
            }
        }
    }
    assert!(checked > 50, "only {checked} settled gazes were on target");
}

#[test]
fn base_poses_compose_and_chains_pack() {
    let mut crowd = Crowd::new(CrowdConfig::default()).unwrap();
    let human = crowd.add_character(&CharacterDesc::default()).unwrap();
    // A BVH-like chain: 3 spine, 1 neck, head, no eyes.
    let limits = JointLimits::new(Vec3::Y, 0.3, -0.6, 0.6);
    let joint = |role, height| ChainJoint::new(role, Vec3::Y * height, Quat::IDENTITY, limits);
    let small = GazeChain::new(
        &[
            joint(JointRole::Spine, 0.0),
            joint(JointRole::Spine, 0.15),
            joint(JointRole::Spine, 0.15),
            joint(JointRole::Cervical, 0.2),
            joint(JointRole::Head, 0.1),
        ],
        Vec3::Z,
        Vec3::Y,
        Vec3::Y * 1.0,
    )
    .unwrap();
    let other = crowd
        .add_character(&CharacterDesc {
            position: Vec3::new(0.0, 0.0, 2.0),
            heading: std::f32::consts::PI,
            chain: Some(small),
            ..Default::default()
        })
        .unwrap();
    assert_eq!(crowd.joint_total(0, 2).unwrap(), 15);
    let tilt = Quat::from_rotation_x(0.2);
    crowd.set_base_pose(other, &[tilt; 5]).unwrap();
    assert!(matches!(
        crowd.set_base_pose(other, &[tilt; 4]),
        Err(Error::InvalidArgument(_))
    ));
    crowd
        .set_gaze_target(
            other,
            ExplicitTarget::Entity(human),
            TargetPriority::Override,
        )
        .unwrap();
    for _ in 0..60 {
        crowd.step(DT).unwrap();
    }
    let mut finals = [Quat::IDENTITY; 15];
    let mut deltas = [Quat::IDENTITY; 15];
    assert_eq!(crowd.read_joints(0, 2, false, &mut finals).unwrap(), 15);
    crowd.read_joints(0, 2, true, &mut deltas).unwrap();
    for joint in 10..15 {
        assert!((finals[joint] - tilt * deltas[joint]).length() < 1e-6);
    }
    assert!(deltas[10..15]
        .iter()
        .any(|q| q.angle_between(Quat::IDENTITY) > 0.01));
    assert!(crowd.read_joints(0, 2, false, &mut finals[..14]).is_err());
    assert!(crowd.read_joints(1, 2, false, &mut finals).is_err());
    // Removing the target entity clears the explicit target: the gaze lets go.
    crowd.remove_entity(human).unwrap();
    for _ in 0..90 {
        crowd.step(DT).unwrap();
    }
    crowd.read_joints(0, 1, true, &mut deltas[..5]).unwrap();
    assert!(deltas[..5]
        .iter()
        .all(|q| q.angle_between(Quat::IDENTITY) < 1e-3));
}

#[test]
fn when_idle_targets_yield_to_interest_points() {
    let mut crowd = Crowd::new(CrowdConfig::default()).unwrap();
    let a = crowd.add_character(&CharacterDesc::default()).unwrap();
    crowd
        .set_gaze_target(
            a,
            ExplicitTarget::Point(Vec3::new(-3.0, 1.6, 3.0)),
            TargetPriority::WhenIdle,
        )
        .unwrap();
    for _ in 0..60 {
        crowd.step(DT).unwrap();
    }
    assert_eq!(crowd.gaze(a).unwrap().target, NO_ENTITY);
    let eyes = crowd.eyes_at(0);
    assert!(
        angle_to(
            eyes.origins[0],
            eyes.directions[0],
            Vec3::new(-3.0, 1.6, 3.0)
        ) < 1.0
    );
    assert!(crowd
        .set_gaze_target(a, ExplicitTarget::Entity(a), TargetPriority::Override)
        .is_err());
    assert!(crowd
        .set_gaze_target(
            a,
            ExplicitTarget::Point(Vec3::NAN),
            TargetPriority::Override
        )
        .is_err());
    let moved = EntityUpdate {
        id: a,
        position: Vec3::new(0.0, 0.0, 0.1),
        heading: 0.0,
        heading_from_motion: false,
        velocity: None,
        talking: false,
    };
    crowd.push_frame(1.0, &[moved]).unwrap();
    crowd.step(DT).unwrap();
}

#[test]
fn a_view_blended_pose_is_the_base_of_the_gaze_chain() {
    use crowdgaze::blend::{ViewBlender, ViewBlenderConfig};
    use crowdgaze::math::dualquat::DualQuat;

    // Two static key poses of the 10 chain joints: spine bent left, spine bent right; one
    // key camera each (left and right of the character).
    let mut blender = ViewBlender::new(ViewBlenderConfig::new(10, 2)).unwrap();
    let pose = |angle: f32| {
        [DualQuat::from_rotation_translation(Quat::from_rotation_z(angle), Vec3::ZERO); 10]
    };
    blender.set_key_pose(0, &pose(0.1)).unwrap();
    blender.set_key_pose(1, &pose(-0.1)).unwrap();
    blender.add_camera(Vec3::X, 0).unwrap();
    blender.add_camera(Vec3::NEG_X, 1).unwrap();

    let mut crowd = Crowd::new(CrowdConfig::default()).unwrap();
    let id = crowd.add_character(&CharacterDesc::default()).unwrap();
    let character = DualQuat::IDENTITY;
    let mut blended = [DualQuat::IDENTITY; 10];
    // The viewer stands on the left key camera: the left pose alone.
    blender
        .evaluate(character, Vec3::new(3.0, 0.0, 0.0), 0.0, &mut blended)
        .unwrap();
    let base: Vec<Quat> = blended.iter().map(|q| q.rotation()).collect();
    assert!(base[0].angle_between(Quat::from_rotation_z(0.1)) < 1e-5);
    crowd.set_base_pose(id, &base).unwrap();
    crowd
        .set_gaze_target(
            id,
            ExplicitTarget::Point(Vec3::new(0.5, 1.6, 3.0)),
            TargetPriority::Override,
        )
        .unwrap();
    for _ in 0..30 {
        crowd.step(DT).unwrap();
    }
    let (mut finals, mut deltas) = ([Quat::IDENTITY; 10], [Quat::IDENTITY; 10]);
    crowd.read_joints(0, 1, false, &mut finals).unwrap();
    crowd.read_joints(0, 1, true, &mut deltas).unwrap();
    for joint in 0..10 {
        assert!((finals[joint] - base[joint] * deltas[joint]).length() < 1e-5);
    }
}

#[test]
fn state_per_character_is_reported() {
    let bytes = Crowd::state_bytes_per_character();
    println!("state per character: {bytes} bytes");
    assert!(bytes > 500 && bytes < 2048, "{bytes}");
}
