//! Influence, fades, eyelids, attention parameters, limits and conversations through the
//! adapter, read back from the skeletons.

use super::*;
use crate::fade::Controls;
use crate::lids::lid_angle;
use crate::settings::CrowdSettings;

/// The human with upper-lid bones under its head.
fn with_lids(convention: PoseConvention, global: Xform) -> FakeSkeleton {
    let mut skeleton = FakeSkeleton::human(convention, global, 1.0);
    let head = skeleton.bone("Head");
    for (name, x) in [("eyelid_upper_l", 0.032), ("eyelid_upper_r", -0.032)] {
        let rest =
            skeleton
                .rest_global(head)
                .inverse()
                .unwrap()
                .mul(&Xform::from_rotation_translation(
                    Quat::from_rotation_x(0.2),
                    Vec3::new(x, 1.65, 0.09),
                ));
        skeleton.names.push(name.into());
        skeleton.parents.push(Some(head));
        skeleton.rests.push(rest);
        skeleton.poses.push(match convention {
            PoseConvention::RestTimesPose => Xform::IDENTITY,
            PoseConvention::PoseIsLocal => rest,
        });
    }
    skeleton
}

/// A world of one character looking at a point to its left, and the skeleton as it was.
fn looking(convention: PoseConvention, settings: &CharacterSettings) -> (World, FakeSkeleton) {
    let mut world = World::new(CrowdConfig::default(), convention);
    let skeleton = with_lids(convention, placed(Vec3::new(1.0, 0.0, 2.0), 0.4));
    let rest = skeleton.clone();
    world.add_with(skeleton, settings).unwrap();
    look_to_the_left(&mut world);
    (world, rest)
}

/// Gives the world's first character (key 1000) new settings.
fn update(world: &mut World, settings: &CharacterSettings) {
    let (skeleton, node) = (world.skeletons[0].clone(), world.nodes[0]);
    world
        .crowd
        .update_character(1000, &skeleton, &node, settings)
        .unwrap();
}

/// Makes the world's first character look at a point to its left.
fn look_to_the_left(world: &mut World) {
    let id = world.crowd.entity_of(1000).unwrap();
    let point = world.skeletons[0]
        .global
        .transform_point(Vec3::new(2.0, 1.8, 1.0));
    world
        .crowd
        .crowd_mut()
        .set_gaze_target(id, ExplicitTarget::Point(point), TargetPriority::Override)
        .unwrap();
}

/// Each chain joint's angle from the animated pose (`rest`, never written) and from the
/// library's gaze, radians.
fn distances(world: &World, rest: &FakeSkeleton) -> Vec<(f32, f32, f32)> {
    let bones = world.crowd.chain_bones(0).unwrap().to_vec();
    let base = skeleton_locals(rest, &world.nodes[0], &bones);
    let now = skeleton_locals(&world.skeletons[0], &world.nodes[0], &bones);
    let mut gaze = [Quat::IDENTITY; 15];
    world.crowd.joint_rotations(0, &mut gaze).unwrap();
    (0..bones.len())
        .map(|k| {
            let half = base[k].slerp(gaze[k], 0.5);
            (
                angle(now[k], base[k]),
                angle(now[k], gaze[k]),
                angle(now[k], half),
            )
        })
        .collect()
}

#[test]
fn influence_blends_from_the_animation_to_the_gaze() {
    for convention in [PoseConvention::RestTimesPose, PoseConvention::PoseIsLocal] {
        let (mut world, rest) = looking(convention, &CharacterSettings::default());
        for _ in 0..60 {
            world.frame(1.0 / 30.0);
        }
        let full = distances(&world, &rest);
        assert!(full.iter().all(|d| d.1 < 1e-5), "{convention:?} {full:?}");
        assert!(full.iter().any(|d| d.0 > 0.05), "the gaze turned nothing");
        // Half, at once.
        let half = CharacterSettings {
            controls: Controls::new(true, 0.5, 0.0).unwrap(),
            ..CharacterSettings::default()
        };
        update(&mut world, &half);
        world.frame(1.0 / 30.0);
        assert_eq!(world.crowd.influence(0).unwrap(), 0.5);
        let halfway = distances(&world, &rest);
        assert!(halfway.iter().all(|d| d.2 < 1e-5), "{halfway:?}");
        // The crowd's influence multiplies the character's.
        world
            .crowd
            .set_controls(&Controls::new(true, 0.5, 0.0).unwrap());
        world.frame(1.0 / 30.0);
        assert_eq!(world.crowd.influence(0).unwrap(), 0.25);
        world.crowd.set_controls(&Controls::default());
        // Inactive: the animated pose is written back once, then nothing is written.
        let off = CharacterSettings {
            controls: Controls::new(false, 0.5, 0.0).unwrap(),
            ..CharacterSettings::default()
        };
        update(&mut world, &off);
        world.frame(1.0 / 30.0);
        let none = distances(&world, &rest);
        assert!(none.iter().all(|d| d.0 < 1e-5), "{convention:?} {none:?}");
        let writes = world.skeletons[0].writes;
        let poses = world.skeletons[0].poses.clone();
        for _ in 0..30 {
            world.frame(1.0 / 30.0);
        }
        assert_eq!(
            world.skeletons[0].writes, writes,
            "bones written while inactive"
        );
        assert_eq!(world.skeletons[0].poses, poses);
        // Attention kept running: back on at once, the gaze is where the library has it.
        update(&mut world, &half);
        let full = CharacterSettings {
            controls: Controls::new(true, 1.0, 0.0).unwrap(),
            ..CharacterSettings::default()
        };
        update(&mut world, &full);
        world.frame(1.0 / 30.0);
        assert!(pose_error(&world, 0) < 1e-5);
    }
}

#[test]
fn a_fade_takes_its_time_and_ends_the_writes() {
    let convention = PoseConvention::RestTimesPose;
    let (mut world, rest) = looking(convention, &CharacterSettings::default());
    for _ in 0..30 {
        world.frame(1.0 / 30.0);
    }
    let fading = CharacterSettings {
        controls: Controls::new(false, 1.0, 1.0).unwrap(),
        ..CharacterSettings::default()
    };
    update(&mut world, &fading);
    for _ in 0..15 {
        world.frame(1.0 / 30.0);
    }
    assert!((world.crowd.influence(0).unwrap() - 0.5).abs() < 1e-4);
    for _ in 0..15 {
        world.frame(1.0 / 30.0);
    }
    assert!(world.crowd.influence(0).unwrap().abs() < 1e-4);
    world.frame(1.0 / 30.0);
    assert!(distances(&world, &rest).iter().all(|d| d.0 < 1e-5));
    let writes = world.skeletons[0].writes;
    world.frame(1.0 / 30.0);
    assert_eq!(world.skeletons[0].writes, writes);
}

#[test]
fn lid_bones_follow_the_library_s_eyelids() {
    for convention in [PoseConvention::RestTimesPose, PoseConvention::PoseIsLocal] {
        let (mut world, rest) = looking(convention, &CharacterSettings::default());
        let [Some(left), Some(right)] = world.crowd.lid_bones(0).unwrap() else {
            panic!("no lid bones found");
        };
        let mut blinked = false;
        for _ in 0..30 * 30 {
            world.frame(1.0 / 30.0);
            let lids = world.crowd.eyelids(0).unwrap();
            for (bone, pitch, closure) in [
                (left, lids.left_lid_pitch, lids.left_closure),
                (right, lids.right_lid_pitch, lids.right_closure),
            ] {
                // The lid's turn from its animated pose, about the head's lateral axis.
                let before = rotation_of(&rest.poses[bone].basis);
                let now = rotation_of(&world.skeletons[0].poses[bone].basis);
                let turn = before.conjugate() * now;
                let global = rotation_of(&rest.rest_global(bone).basis);
                // The character's left (its frame's +X) in the skeleton's frame.
                let (_, _, frame) = crate::skeleton::character_frame(&rest.global);
                let lateral =
                    rotation_of(&rest.global.basis).conjugate() * (frame.rotation() * Vec3::X);
                let axis = global.conjugate() * lateral;
                let expected = Quat::from_axis_angle(axis, lid_angle(pitch, closure, 1.0));
                assert!(
                    angle(turn, expected) < 1e-4,
                    "{convention:?}: lid off by {}",
                    angle(turn, expected)
                );
            }
            blinked |= lids.left_closure > 0.5;
        }
        assert!(blinked, "no blink in 30 s");
    }
}

#[test]
fn attention_parameters_limits_and_talking_are_the_character_s() {
    let mut world = World::new(CrowdConfig::default(), PoseConvention::RestTimesPose);
    let settings = CharacterSettings {
        attention_fraction: Some(0.3),
        max_head_turn: 20.0,
        max_eye_angle: 10.0,
        ..CharacterSettings::default()
    };
    let place = placed(Vec3::ZERO, 0.0);
    let id = world
        .add_with(
            FakeSkeleton::human(PoseConvention::RestTimesPose, place, 1.0),
            &settings,
        )
        .unwrap();
    let params = world.crowd.crowd().character_params(id).unwrap();
    assert_eq!(params.attention_fraction, 0.3);
    let chain = *world.crowd.crowd().chain(id).unwrap();
    let eye = chain.joints()[chain.eye_indices().unwrap()[0]];
    assert!((eye.limits.max_swing() - 10f32.to_radians()).abs() < 1e-6);
    // A target far to the side: the head turns no more than its limits allow.
    let point = Vec3::new(5.0, 1.6, 0.5);
    world
        .crowd
        .crowd_mut()
        .set_gaze_target(id, ExplicitTarget::Point(point), TargetPriority::Override)
        .unwrap();
    for _ in 0..90 {
        world.frame(1.0 / 30.0);
    }
    let deltas = world.crowd.crowd().gaze_motion(id).unwrap().deltas();
    let yaw: f32 = chain.joints()[..chain.body_count()]
        .iter()
        .zip(deltas)
        .filter(|(joint, _)| joint.role != crowdgaze::ik::JointRole::Spine)
        .map(|(joint, delta)| joint.limits.swing_twist_angles(*delta).1.abs())
        .sum();
    assert!(
        yaw.to_degrees() <= 20.0 + 0.01,
        "head and neck turned {yaw}"
    );
    // Back to the crowd's draw, and talking.
    let drawn = CharacterSettings {
        talking: true,
        ..CharacterSettings::default()
    };
    update(&mut world, &drawn);
    let id = world.crowd.entity_of(1000).unwrap();
    let params = world.crowd.crowd().character_params(id).unwrap();
    assert!((0.2..0.6).contains(&params.attention_fraction));
}

#[test]
fn conversations_by_node() {
    let mut world = World::new(CrowdConfig::default(), PoseConvention::RestTimesPose);
    for x in [0.0, 1.0, 2.0] {
        world
            .add(FakeSkeleton::human(
                PoseConvention::RestTimesPose,
                placed(Vec3::new(x, 0.0, 0.0), 0.0),
                1.0,
            ))
            .unwrap();
    }
    let id = world.crowd.set_conversation(&[1000, 1001]).unwrap();
    assert_eq!(world.crowd.conversation_of(0).unwrap(), Some(id));
    assert_eq!(world.crowd.conversation_of(2).unwrap(), None);
    let text = world
        .crowd
        .set_conversation(&[1002, 77])
        .unwrap_err()
        .to_string();
    assert!(text.contains("member 1"), "{text}");
    assert!(world.crowd.set_conversation(&[1002]).is_err());
    assert!(world.crowd.set_conversation(&[1001, 1002]).is_err());
    world.frame(1.0 / 30.0);
    world.crowd.remove_conversation(i64::from(id)).unwrap();
    assert!(world.crowd.remove_conversation(i64::from(id)).is_err());
    assert!(world.crowd.remove_conversation(-5).is_err());
    assert!(world.crowd.remove_conversation(i64::MAX).is_err());
    assert_eq!(world.crowd.conversation_of(1).unwrap(), None);
}

#[test]
fn new_limits_hold_in_the_poses_of_a_skeleton_nothing_animates() {
    // Mapped again with new limits, the skeleton's bones still hold the old gaze: the new
    // binding must not read it as the animated pose.
    let (mut world, _) = looking(PoseConvention::RestTimesPose, &CharacterSettings::default());
    for _ in 0..60 {
        world.frame(1.0 / 30.0);
    }
    let eye_turn = |world: &World| {
        let skeleton = &world.skeletons[0];
        ["LeftEye", "RightEye"]
            .iter()
            .map(|name| {
                let pose = rotation_of(&skeleton.poses[skeleton.bone(name)].basis);
                angle(pose, Quat::IDENTITY).to_degrees()
            })
            .fold(0.0, f32::max)
    };
    assert!(
        eye_turn(&world) > 8.0,
        "the eyes turned {}",
        eye_turn(&world)
    );
    let narrow = CharacterSettings {
        max_eye_angle: 4.0,
        ..CharacterSettings::default()
    };
    update(&mut world, &narrow);
    look_to_the_left(&mut world);
    for _ in 0..60 {
        world.frame(1.0 / 30.0);
    }
    assert!(
        eye_turn(&world) <= 4.0 + 1e-3,
        "the eyes turned {}",
        eye_turn(&world)
    );
    assert!(pose_error(&world, 0) < 1e-5);
}

/// Three people stare at a point up a facade; eight stand behind them facing the same
/// way. Returns each step's follow starts (slot, distance of the point from the stared
/// point) and whether `following` answered a point for every slot that started.
fn staring_group(following: bool) -> (Vec<(usize, f32)>, bool) {
    let settings = CrowdSettings {
        gaze_following: following,
        max_distance: 17.0,
        ..CrowdSettings::default()
    };
    let mut world = World::new(settings.config().unwrap(), PoseConvention::RestTimesPose);
    let stared = Vec3::new(0.0, 6.0, 9.0);
    for k in 0..3 {
        let at = placed(Vec3::new(k as f32 - 1.0, 0.0, 5.0), 0.0);
        let id = world
            .add(FakeSkeleton::human(PoseConvention::RestTimesPose, at, 1.0))
            .unwrap();
        world
            .crowd
            .crowd_mut()
            .set_gaze_target(id, ExplicitTarget::Point(stared), TargetPriority::Override)
            .unwrap();
    }
    for k in 0..8 {
        let at = placed(Vec3::new(k as f32 * 0.8 - 3.0, 0.0, 1.0), 0.0);
        world
            .add(FakeSkeleton::human(PoseConvention::RestTimesPose, at, 1.0))
            .unwrap();
    }
    let (mut starts, mut answered) = (Vec::new(), true);
    for _ in 0..300 {
        world.frame(1.0 / 30.0);
        for start in world.crowd.follow_starts() {
            starts.push((start.slot, start.point.distance(stared)));
            answered &= world.crowd.following(start.slot).unwrap().is_some();
        }
    }
    (starts, answered)
}

#[test]
fn passers_by_follow_a_stare_only_with_following_on() {
    let (starts, answered) = staring_group(true);
    let followers: std::collections::HashSet<usize> = starts.iter().map(|s| s.0).collect();
    assert!(
        followers.iter().any(|&slot| slot >= 3),
        "no passer-by followed: {starts:?}"
    );
    assert!(starts.iter().all(|s| s.1 < 0.5), "{starts:?}");
    assert!(answered, "following() gave no point for a follower");
    let (starts, _) = staring_group(false);
    assert!(starts.is_empty(), "following off, yet {starts:?}");
}
