//! The mapping's own tests: a BVH-like skeleton, rotated rests, overrides, bad skeletons,
//! the checks that refuse silently wrong chains, and the per-frame conversions. The rigs
//! people ship are tested against their published hierarchies in `tests/rigs.rs`.

use super::*;

/// A BVH-like skeleton, Z up, facing −Y, identity rests (units of 10 cm).
fn biovision() -> Vec<RestBone<'static>> {
    let bone = |name, parent, x: f32, y: f32, z: f32| RestBone {
        name,
        parent,
        translation: Vec3::new(x, y, z),
        rotation: Quat::IDENTITY,
    };
    vec![
        bone("Hips", None, 0.0, 0.0, 9.5),
        bone("Spine", Some(0), 0.0, 0.0, 1.0),
        bone("Spine1", Some(1), 0.0, 0.0, 1.5),
        bone("Neck", Some(2), 0.0, 0.0, 2.5),
        bone("Head", Some(3), 0.0, 0.0, 1.0),
        bone("LeftArm", Some(2), 2.0, 0.0, 2.0),
        bone("RightArm", Some(2), -2.0, 0.0, 2.0),
    ]
}

fn metres_of_ten_cm() -> SkeletonOptions {
    SkeletonOptions {
        units_per_metre: 10.0,
        ..SkeletonOptions::default()
    }
}

#[test]
fn a_biovision_skeleton_maps_like_the_cli_did() {
    let bones = biovision();
    let mapped = map_skeleton(&bones, &BoneMap::default(), &metres_of_ten_cm()).unwrap();
    assert_eq!(mapped.bones, vec![1, 2, 3, 4]);
    assert_eq!(mapped.root, 0);
    assert_eq!(
        (mapped.up, mapped.forward),
        (Axis::PositiveZ, Axis::NegativeY)
    );
    let chain = &mapped.chain;
    assert_eq!((chain.spine_count(), chain.cervical_count()), (2, 1));
    assert!(!chain.has_eyes());
    assert_eq!(chain.joints()[2].offset, Vec3::new(0.0, 0.0, 0.25));
    assert!(chain
        .root_offset()
        .abs_diff_eq(Vec3::new(0.0, 0.0, 0.95), 1e-6));
    assert_eq!(chain.eye_forward(), Vec3::NEG_Y);
    assert_eq!(chain.joints()[0].limits.twist_axis(), Vec3::Z);
    // Spine 40° shared by two, neck 50°, head 20°.
    let yaw = |k: usize| chain.joints()[k].limits.max_twist().to_degrees();
    assert!((yaw(0) - 20.0).abs() < 1e-4 && (yaw(2) - 50.0).abs() < 1e-4);
    assert!((yaw(3) - 20.0).abs() < 1e-4);
}

/// The same skeleton in Godot's axes (Y up, +Z forward) with every bone's rest rotated
/// as importers do (each bone's Y along the bone) and two eyes: the chain must place
/// the joints, eyes and axes where the plain one does.
#[test]
fn rotated_rests_give_the_same_world_pose() {
    let plain = [
        ("Hips", None, Vec3::new(0.0, 0.95, 0.0)),
        ("Spine", Some(0), Vec3::new(0.0, 0.1, 0.0)),
        ("Chest", Some(1), Vec3::new(0.0, 0.3, 0.02)),
        ("Neck", Some(2), Vec3::new(0.0, 0.2, -0.02)),
        ("Head", Some(3), Vec3::new(0.0, 0.08, 0.0)),
        ("LeftEye", Some(4), Vec3::new(0.03, 0.06, 0.08)),
        ("RightEye", Some(4), Vec3::new(-0.03, 0.06, 0.08)),
    ];
    // Each bone's rest rotation: an arbitrary turn, compensated in its children.
    let turns: Vec<Quat> = (0..plain.len())
        .map(|i| {
            Quat::from_euler(
                glam::EulerRot::YXZ,
                0.3 * i as f32,
                -0.2,
                0.1 + 0.05 * i as f32,
            )
        })
        .collect();
    let mut globals = Vec::new();
    let mut bones = Vec::new();
    for (i, (name, parent, translation)) in plain.iter().enumerate() {
        let world = match parent {
            None => *translation,
            Some(p) => globals[*p] + *translation,
        };
        globals.push(world);
        let (parent_turn, parent_world) = match parent {
            None => (Quat::IDENTITY, Vec3::ZERO),
            Some(p) => (turns[*p], globals[*p]),
        };
        bones.push(RestBone {
            name,
            parent: *parent,
            translation: parent_turn.conjugate() * (world - parent_world),
            rotation: parent_turn.conjugate() * turns[i],
        });
    }
    let options = SkeletonOptions {
        up: Some(Axis::PositiveY),
        forward: Some(Axis::PositiveZ),
        ..SkeletonOptions::default()
    };
    let mapped = map_skeleton(&bones, &BoneMap::default(), &options).unwrap();
    assert_eq!(mapped.bones, vec![1, 2, 3, 4, 5, 6]);
    let chain = &mapped.chain;
    assert!(chain.has_eyes());
    // Forward kinematics of the chain at rest reach the same points.
    let mut position = chain.root_offset();
    let mut rotation = Quat::IDENTITY;
    for (k, joint) in chain.joints()[..chain.body_count()].iter().enumerate() {
        position += rotation * joint.offset;
        rotation *= joint.rest;
        assert!(position.abs_diff_eq(globals[k + 1], 1e-5), "joint {k}");
        // Every body joint twists about the world's up.
        assert!((rotation * joint.limits.twist_axis()).abs_diff_eq(Vec3::Y, 1e-5));
    }
    assert!((rotation * chain.eye_forward()).abs_diff_eq(Vec3::Z, 1e-5));
    assert!((rotation * chain.eye_up()).abs_diff_eq(Vec3::Y, 1e-5));
    for (k, eye) in [5, 6].into_iter().enumerate() {
        let joint = chain.joints()[chain.body_count() + k];
        assert!((position + rotation * joint.offset).abs_diff_eq(globals[eye], 1e-5));
        let eye_rotation = rotation * joint.rest;
        assert!((eye_rotation * joint.limits.twist_axis()).abs_diff_eq(Vec3::Z, 1e-5));
    }
    assert!((chain.look_at_height(Vec3::Y) - 1.69).abs() < 1e-4);
}

#[test]
fn overrides_and_namespaces() {
    let map = BoneMap::with_overrides(" Jaw=head , Head=none,mixamorig:Neck=spine").unwrap();
    assert_eq!(map.role_of("jaw"), BoneRole::Head);
    assert_eq!(map.role_of("Head"), BoneRole::None);
    assert_eq!(map.role_of("mixamorig:Neck"), BoneRole::Spine);
    assert_eq!(map.role_of("other:Neck"), BoneRole::Neck);
    assert_eq!(map.role_of("mixamorig:Spine2"), BoneRole::Spine);
    assert_eq!(map.role_of("Eye.L"), BoneRole::LeftEye);
    assert_eq!(map.role_of("Tail"), BoneRole::None);
    for role in BoneRole::ALL {
        assert_eq!(BoneRole::parse(role.name()), Some(role));
    }
    for bad in ["Head", "Head=brain", "=x"] {
        let error = BoneMap::with_overrides(bad).unwrap_err();
        assert!(matches!(error, Error::InvalidArgument(_)), "{bad}: {error}");
    }
    assert_eq!(parse_axis("-Z"), Some(Axis::NegativeZ));
    assert_eq!(parse_axis("w"), None);
}

#[test]
fn bad_skeletons_are_explained() {
    let options = metres_of_ten_cm();
    let message = |bones: &[RestBone<'_>]| {
        map_skeleton(bones, &BoneMap::default(), &options)
            .unwrap_err()
            .to_string()
    };
    let mut headless = biovision();
    headless[4].name = "Skull";
    let text = message(&headless);
    assert!(
        text.contains("no head bone") && text.contains("'Hips', 'Spine'"),
        "{text}"
    );
    assert!(message(&[]).contains("(none)"));
    let lone = [RestBone {
        name: "Head",
        parent: None,
        translation: Vec3::ZERO,
        rotation: Quat::IDENTITY,
    }];
    assert!(message(&lone).contains("no parent"));
    let mut upside = biovision();
    upside[2].name = "Neck1";
    upside[3].name = "Spine3";
    assert!(message(&upside).contains("spine bones then neck bones"));
    let mut one_eye = biovision();
    one_eye.push(RestBone {
        name: "LeftEye",
        parent: Some(4),
        translation: Vec3::ZERO,
        rotation: Quat::IDENTITY,
    });
    assert!(message(&one_eye).contains("no other eye"));
    one_eye.push(RestBone {
        name: "RightEye",
        parent: Some(3),
        translation: Vec3::ZERO,
        rotation: Quat::IDENTITY,
    });
    assert!(message(&one_eye).contains("not under the head"));
    let mut nan = biovision();
    nan[2].translation.y = f32::NAN;
    assert!(matches!(
        map_skeleton(&nan, &BoneMap::default(), &options),
        Err(Error::NonFinite(_))
    ));
    let mut loop_ = biovision();
    loop_[1].parent = Some(3);
    assert!(message(&loop_).contains("parents come before children"));
    let sideways = SkeletonOptions {
        up: Some(Axis::PositiveZ),
        forward: Some(Axis::NegativeZ),
        ..options
    };
    assert!(map_skeleton(&biovision(), &BoneMap::default(), &sideways).is_err());
    let zero = SkeletonOptions {
        units_per_metre: 0.0,
        ..options
    };
    assert!(map_skeleton(&biovision(), &BoneMap::default(), &zero).is_err());
}

/// A rig with its eyes under a facial root, a twist bone between the neck and the head's
/// parent path, and rotated rests (Z up, facing +Y, centimetres, like Unreal's).
fn unreal_like() -> Vec<RestBone<'static>> {
    let turn = Quat::from_rotation_z(0.3) * Quat::from_rotation_x(-0.2);
    let bone = |name, parent, x: f32, y: f32, z: f32| RestBone {
        name,
        parent,
        translation: Vec3::new(x, y, z),
        rotation: Quat::IDENTITY,
    };
    let mut bones = vec![
        bone("root", None, 0.0, 0.0, 0.0),
        bone("pelvis", Some(0), 0.0, 0.0, 95.0),
        bone("spine_01", Some(1), 0.0, 0.0, 10.0),
        bone("spine_02", Some(2), 0.0, 0.0, 15.0),
        bone("neck_01", Some(3), 0.0, 0.0, 30.0),
        bone("head", Some(4), 0.0, 0.0, 8.0),
        bone("FACIAL_C_FacialRoot", Some(5), 0.0, 2.0, 3.0),
        bone("FACIAL_L_Eye", Some(6), -3.2, 7.0, 4.0),
        bone("FACIAL_R_Eye", Some(6), 3.2, 7.0, 4.0),
        bone("thigh_l", Some(1), -10.0, 0.0, -5.0),
        bone("thigh_r", Some(1), 10.0, 0.0, -5.0),
    ];
    // The facial root turned, its eyes turned back: the rest pose is the same.
    bones[6].rotation = turn;
    for eye in [7, 8] {
        bones[eye].translation = turn.conjugate() * bones[eye].translation;
        bones[eye].rotation = turn.conjugate();
    }
    bones
}

fn centimetres() -> SkeletonOptions {
    SkeletonOptions {
        units_per_metre: 100.0,
        ..SkeletonOptions::default()
    }
}

#[test]
fn eyes_under_a_facial_root_map_and_the_pose_goes_round() {
    let bones = unreal_like();
    let mapped = map_skeleton(&bones, &BoneMap::default(), &centimetres()).unwrap();
    assert_eq!(mapped.bones, vec![2, 3, 4, 5, 7, 8]);
    assert_eq!(mapped.root, 1);
    assert_eq!(
        (mapped.up, mapped.forward),
        (Axis::PositiveZ, Axis::PositiveY)
    );
    assert_eq!(mapped.facing_from, FacingFrom::Eyes);
    assert!(
        mapped.report().contains("FACIAL_C_FacialRoot"),
        "{}",
        mapped.report()
    );
    let chain = &mapped.chain;
    assert!(chain.has_eyes());
    // The eyes sit where the rest pose puts them, relative to the head.
    let left = chain.joints()[4];
    assert!(
        left.offset.abs_diff_eq(Vec3::new(-0.032, 0.09, 0.07), 1e-5),
        "{}",
        left.offset
    );
    assert!(left.rest.abs_diff_eq(Quat::IDENTITY, 1e-5));
    // Rest locals give the rest chain; joints written back come out of base_pose again.
    let locals: Vec<Quat> = bones.iter().map(|b| b.rotation).collect();
    let mut base = vec![Quat::IDENTITY; mapped.joint_count()];
    mapped.base_pose(&locals, &mut base).unwrap();
    for (k, joint) in chain.joints().iter().enumerate() {
        assert!(base[k].abs_diff_eq(joint.rest, 1e-5), "joint {k}");
    }
    let mut animated = locals.clone();
    animated[0] = Quat::from_rotation_z(0.4);
    animated[1] = Quat::from_rotation_y(0.1);
    animated[6] = Quat::from_rotation_x(0.2) * animated[6];
    let joints: Vec<Quat> = (0..mapped.joint_count())
        .map(|k| Quat::from_rotation_z(0.05 * k as f32) * Quat::from_rotation_x(0.1))
        .collect();
    let mut written = animated.clone();
    mapped.write_joints(&joints, &mut written).unwrap();
    mapped.base_pose(&written, &mut base).unwrap();
    for (k, (got, want)) in base.iter().zip(&joints).enumerate() {
        assert!(got.abs_diff_eq(*want, 1e-5), "joint {k}: {got} vs {want}");
    }
    // Bones outside the chain are left alone.
    for bone in [0, 1, 6, 9, 10] {
        assert_eq!(written[bone], animated[bone]);
    }
    // Bad arrays: errors, nothing written.
    let before = written.clone();
    assert!(mapped.write_joints(&joints[1..], &mut written).is_err());
    let mut nan = joints.clone();
    nan[2].x = f32::NAN;
    assert!(matches!(
        mapped.write_joints(&nan, &mut written),
        Err(Error::NonFinite(_))
    ));
    assert_eq!(written, before);
    assert!(mapped.base_pose(&locals[1..], &mut base).is_err());
}

#[test]
fn the_chain_turns_into_the_crowds_axes() {
    let bones = unreal_like();
    let options = SkeletonOptions {
        crowd_axes: Some((Axis::PositiveY, Axis::PositiveZ)),
        ..centimetres()
    };
    let mapped = map_skeleton(&bones, &BoneMap::default(), &options).unwrap();
    let chain = &mapped.chain;
    assert!(chain
        .root_offset()
        .abs_diff_eq(Vec3::new(0.0, 0.95, 0.0), 1e-5));
    // At rest, the head's forward is the crowd's +Z.
    let locals: Vec<Quat> = bones.iter().map(|b| b.rotation).collect();
    let mut base = vec![Quat::IDENTITY; mapped.joint_count()];
    mapped.base_pose(&locals, &mut base).unwrap();
    let head = base[..chain.body_count()]
        .iter()
        .fold(Quat::IDENTITY, |r, q| r * *q);
    assert!((head * chain.eye_forward()).abs_diff_eq(Vec3::Z, 1e-5));
    assert!((head * chain.eye_up()).abs_diff_eq(Vec3::Y, 1e-5));
}

#[test]
fn a_walk_that_stops_short_is_refused_with_the_fix() {
    let options = centimetres();
    let message = |bones: &[RestBone<'_>], map: &BoneMap| {
        map_skeleton(bones, map, &options).unwrap_err().to_string()
    };
    // An unrecognised bone between the spine and the neck.
    let mut bones = unreal_like();
    bones[3].name = "ribcage";
    let text = message(&bones, &BoneMap::default());
    assert!(
        text.contains("'ribcage'") && text.contains("ribcage=spine"),
        "{text}"
    );
    let fixed = BoneMap::with_overrides("ribcage=spine").unwrap();
    assert_eq!(
        map_skeleton(&bones, &fixed, &options).unwrap().bones.len(),
        6
    );
    // A head straight on the root: refused, unless the override says it is meant.
    let mut bones = unreal_like();
    bones[5].parent = Some(1);
    bones[5].translation = Vec3::new(0.0, 0.0, 63.0);
    let text = message(&bones, &BoneMap::default());
    assert!(
        text.contains("head alone") && text.contains("pelvis=root"),
        "{text}"
    );
    let meant = BoneMap::with_overrides("pelvis=root").unwrap();
    let mapped = map_skeleton(&bones, &meant, &options).unwrap();
    assert_eq!(mapped.chain.body_count(), 1);
    assert!(mapped.report().contains("head-only"), "{}", mapped.report());
    // Eyes that no rule reads.
    let mut bones = unreal_like();
    bones[7].name = "EyeBallA";
    bones[8].name = "EyeBallB";
    let text = message(&bones, &BoneMap::default());
    assert!(
        text.contains("look like eyes") && text.contains("EyeBallA"),
        "{text}"
    );
    let none = BoneMap::with_overrides("EyeBallA=none,EyeBallB=none").unwrap();
    assert!(!map_skeleton(&bones, &none, &options)
        .unwrap()
        .chain
        .has_eyes());
    let eyes = BoneMap::with_overrides("EyeBallA=left_eye,EyeBallB=right_eye").unwrap();
    assert!(map_skeleton(&bones, &eyes, &options)
        .unwrap()
        .chain
        .has_eyes());
}

#[test]
fn the_facing_comes_from_sides_eyes_or_toes_or_is_asked_for() {
    let options = centimetres();
    // The eyes in front of the head say +Y.
    let mut bones = unreal_like();
    let mapped = map_skeleton(&bones, &BoneMap::default(), &options).unwrap();
    assert_eq!(
        (mapped.forward, mapped.facing_from),
        (Axis::PositiveY, FacingFrom::Eyes)
    );
    // Mirrored (Unreal's left-handed numbers): still +Y, and a note says so.
    for bone in &mut bones {
        bone.translation.x = -bone.translation.x;
        bone.rotation = Quat::from_xyzw(
            bone.rotation.x,
            -bone.rotation.y,
            -bone.rotation.z,
            bone.rotation.w,
        );
    }
    let mapped = map_skeleton(&bones, &BoneMap::default(), &options).unwrap();
    assert_eq!(
        (mapped.forward, mapped.facing_from),
        (Axis::PositiveY, FacingFrom::Eyes)
    );
    assert!(mapped.report().contains("mirrored"), "{}", mapped.report());
    // No eyes, no toes: the left and right thighs.
    let mut bones = unreal_like();
    bones.drain(6..9);
    for thigh in &mut bones[6..] {
        thigh.parent = Some(1);
    }
    let mapped = map_skeleton(&bones, &BoneMap::default(), &options).unwrap();
    assert_eq!(
        (mapped.forward, mapped.facing_from),
        (Axis::PositiveY, FacingFrom::SidePairs)
    );
    // Without eyes either: the toes.
    let mut bones = unreal_like();
    bones.truncate(6);
    let bone = |name, parent, y: f32, z: f32| RestBone {
        name,
        parent: Some(parent),
        translation: Vec3::new(0.0, y, z),
        rotation: Quat::IDENTITY,
    };
    bones.push(bone("foot", 1, 0.0, -90.0));
    bones.push(bone("toes", 6, 12.0, -5.0));
    let mapped = map_skeleton(&bones, &BoneMap::default(), &options).unwrap();
    assert_eq!(
        (mapped.forward, mapped.facing_from),
        (Axis::PositiveY, FacingFrom::Toes)
    );
    // Nothing shows it: refused, asking for the axis.
    bones.truncate(6);
    let text = map_skeleton(&bones, &BoneMap::default(), &options)
        .unwrap_err()
        .to_string();
    assert!(text.contains("give the forward axis"), "{text}");
    let given = SkeletonOptions {
        forward: Some(Axis::NegativeX),
        ..options
    };
    let mapped = map_skeleton(&bones, &BoneMap::default(), &given).unwrap();
    assert_eq!(mapped.facing_from, FacingFrom::Given);
}

#[test]
fn bad_bones_and_overrides_are_refused() {
    let options = centimetres();
    let message = |bones: &[RestBone<'_>], map: &BoneMap| {
        map_skeleton(bones, map, &options).unwrap_err().to_string()
    };
    let mut twice = unreal_like();
    twice[4].name = "spine_02";
    assert!(message(&twice, &BoneMap::default()).contains("both called 'spine_02'"));
    let mut empty = unreal_like();
    empty[9].name = " ";
    assert!(message(&empty, &BoneMap::default()).contains("empty name"));
    let mut long = unreal_like();
    let name = "x".repeat(MAX_NAME_BYTES + 1);
    long[9].name = &name;
    assert!(message(&long, &BoneMap::default()).contains("too long"));
    let mut stretched = unreal_like();
    stretched[2].rotation = Quat::from_xyzw(0.0, 0.0, 0.0, 1.01);
    assert!(message(&stretched, &BoneMap::default()).contains("length"));
    let mut far = unreal_like();
    far[9].translation.x = 1e9;
    assert!(message(&far, &BoneMap::default()).contains("units_per_metre"));
    let stray = BoneMap::with_overrides("Spine9=spine").unwrap();
    assert!(message(&unreal_like(), &stray).contains("no bone of that name"));
    assert!(BoneMap::with_overrides("head=head,HEAD=none").is_err());
    // A skeleton of thousands of bones without a head: a short message.
    let names: Vec<String> = (0..3000).map(|i| format!("bone_{i}")).collect();
    let many: Vec<RestBone<'_>> = names
        .iter()
        .enumerate()
        .map(|(i, name)| RestBone {
            name,
            parent: i.checked_sub(1),
            translation: Vec3::Y,
            rotation: Quat::IDENTITY,
        })
        .collect();
    let text = message(&many, &BoneMap::default());
    assert!(
        text.len() < 600 && text.contains("and 2988 more"),
        "{}",
        text.len()
    );
}
