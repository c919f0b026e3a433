//! `cg_rig` through the C ABI: a Mixamo skeleton (centimetres, rotated rest frames) maps in
//! one call to the chain the core maps; the chain drives a crowd in other units and axes;
//! each frame's conversions agree with the core's and round-trip; the report and the role
//! and bone lists read back what the mapping found.

// The `unsafe { cg_... }` calls below pass pointers to live values of the sizes the header
// asks for: that is their safety comment, once for the file.
#![allow(clippy::undocumented_unsafe_blocks)]

mod support;

use crowdgaze::ffi::attention::*;
use crowdgaze::ffi::chain::*;
use crowdgaze::ffi::crowd::*;
use crowdgaze::ffi::rig::*;
use crowdgaze::ffi::status::cg_status;
use crowdgaze::ffi::types::cg_quat;
use crowdgaze::skeleton_map::{map_skeleton, BoneMap, RestBone, SkeletonOptions};
use crowdgaze::world::Axis;
use glam::{Quat, Vec3};
use std::ptr::null_mut;
use support::rig::{bone, glam_quat, Skeleton};
use support::{check, init, CrowdHandle};

/// The core's mapping of `skeleton` (centimetres), for a crowd of these axes.
fn core_mapping(
    skeleton: &Skeleton,
    crowd_axes: (Axis, Axis),
) -> crowdgaze::skeleton_map::MappedChain {
    let bones: Vec<RestBone<'_>> = (0..skeleton.names.len())
        .map(|i| RestBone {
            name: skeleton.names[i].to_str().unwrap(),
            parent: usize::try_from(skeleton.parents[i]).ok(),
            translation: Vec3::new(
                skeleton.translations[i].x,
                skeleton.translations[i].y,
                skeleton.translations[i].z,
            ),
            rotation: glam_quat(skeleton.rotations[i]).normalize(),
        })
        .collect();
    let options = SkeletonOptions {
        units_per_metre: 100.0,
        crowd_axes: Some(crowd_axes),
        ..SkeletonOptions::default()
    };
    map_skeleton(&bones, &BoneMap::default(), &options).unwrap()
}

fn report(rig: *const cg_rig) -> String {
    let length = unsafe { cg_rig_report(rig, null_mut(), 0) };
    let mut buffer = vec![0 as std::os::raw::c_char; length + 1];
    assert_eq!(
        unsafe { cg_rig_report(rig, buffer.as_mut_ptr(), buffer.len()) },
        length
    );
    let bytes: Vec<u8> = buffer[..length].iter().map(|&c| c as u8).collect();
    String::from_utf8(bytes).unwrap()
}

#[test]
fn a_mixamo_skeleton_maps_in_one_call() {
    let skeleton = Skeleton::mixamo();
    let rig = skeleton.rig(1.0);
    let (mut bones, mut joints) = (0u32, 0u32);
    check(
        unsafe { cg_rig_bone_count(rig.0, &mut bones) },
        "bone_count",
    );
    check(
        unsafe { cg_rig_joint_count(rig.0, &mut joints) },
        "joint_count",
    );
    assert_eq!((bones, joints), (65, 7));
    let mut chain_bones = [u32::MAX; 9];
    check(
        unsafe { cg_rig_chain_bones(rig.0, chain_bones.as_mut_ptr(), 9) },
        "chain_bones",
    );
    let expected: Vec<u32> = [
        "Spine", "Spine1", "Spine2", "Neck", "Head", "LeftEye", "RightEye",
    ]
    .iter()
    .map(|name| bone(&skeleton, name) as u32)
    .collect();
    assert_eq!(&chain_bones[..7], expected.as_slice());
    assert_eq!(
        chain_bones[7..],
        [u32::MAX; 2],
        "past the joints: untouched"
    );
    let mut roles = vec![u32::MAX; 65];
    check(
        unsafe { cg_rig_bone_roles(rig.0, roles.as_mut_ptr(), 65) },
        "bone_roles",
    );
    for (name, role) in [
        ("Hips", cg_bone_role::Root),
        ("Spine1", cg_bone_role::Spine),
        ("Neck", cg_bone_role::Neck),
        ("Head", cg_bone_role::Head),
        ("LeftEye", cg_bone_role::LeftEye),
        ("RightEye", cg_bone_role::RightEye),
        ("LeftHandThumb2", cg_bone_role::None),
    ] {
        assert_eq!(roles[bone(&skeleton, name)], role as u32, "{name}");
    }
    let text = report(rig.0);
    assert!(
        text.starts_with(
            "gaze chain of 7 joints: 3 spine, 1 neck, head, 2 eyes; hangs from \
             'mixamorig:Hips'\nup +Y, forward +Z (from the eyes in front of the head)\n"
        ),
        "{text}"
    );
    // Truncated like cg_last_error_message: NUL-terminated, the full length returned.
    let mut small = [7 as std::os::raw::c_char; 6];
    assert_eq!(
        unsafe { cg_rig_report(rig.0, small.as_mut_ptr(), 6) },
        text.len()
    );
    assert_eq!(small.map(|c| c as u8), *b"gaze \0");
    assert_eq!(unsafe { cg_rig_report(std::ptr::null(), null_mut(), 0) }, 0);
}

#[test]
fn the_chain_is_the_core_mapping_in_the_crowds_units_and_axes() {
    let skeleton = Skeleton::mixamo();
    for (units, up, forward, axes) in [
        (1.0, 2, 4, (Axis::PositiveY, Axis::PositiveZ)),
        (100.0, 2, 4, (Axis::PositiveY, Axis::PositiveZ)),
        (39.37, 4, 3, (Axis::PositiveZ, Axis::NegativeY)),
    ] {
        let mut desc = skeleton.desc(units);
        desc.crowd_up = up;
        desc.crowd_forward = forward;
        let mut rig = null_mut();
        check(unsafe { cg_rig_create(&desc, &mut rig) }, "cg_rig_create");
        let mut chain: cg_chain_desc = unsafe { std::mem::zeroed() };
        chain.struct_size = std::mem::size_of::<cg_chain_desc>() as u32;
        check(unsafe { cg_rig_chain(rig, &mut chain) }, "cg_rig_chain");
        let core = core_mapping(&skeleton, axes);
        assert_eq!(chain.joint_count as usize, core.chain.joint_count());
        let close = |a: [f32; 3], b: Vec3, what: &str| {
            let a = Vec3::from(a) / units;
            assert!(
                a.abs_diff_eq(b, 1e-6 * b.length().max(1.0)),
                "{what}: {a} {b}"
            );
        };
        for (k, joint) in core.chain.joints().iter().enumerate() {
            let c = chain.joints[k];
            close([c.offset.x, c.offset.y, c.offset.z], joint.offset, "offset");
            assert_eq!(glam_quat(c.rest), joint.rest, "rest {k}");
            assert_eq!(c.max_swing, joint.limits.max_swing());
        }
        let r = chain.root_offset;
        close([r.x, r.y, r.z], core.chain.root_offset(), "root_offset");
        // The crowd of those units and axes takes it, and places the eyes at the height the
        // skeleton has them (165 cm).
        let mut config: cg_crowd_config = init(cg_crowd_config_init);
        config.units_per_metre = units;
        config.up_axis = up;
        config.forward_axis = forward;
        let crowd = CrowdHandle::new(&config);
        let mut character: cg_character_desc = init(cg_character_desc_init);
        character.chain = &chain;
        let mut id = 0;
        check(
            unsafe { cg_crowd_add_character(crowd.as_mut(), &character, &mut id) },
            "cg_crowd_add_character",
        );
        assert!((core.chain.look_at_height(axes.0.vector()) - 1.65).abs() < 0.01);
        unsafe { cg_rig_destroy(rig) };
    }
}

#[test]
fn frame_conversions_agree_with_the_core_and_round_trip() {
    let skeleton = Skeleton::mixamo();
    let rig = skeleton.rig(100.0);
    let core = core_mapping(&skeleton, (Axis::PositiveY, Axis::PositiveZ));
    for phase in [0.0f32, 0.7, 2.9] {
        let bones = skeleton.animated(phase);
        let mut base = [cg_quat::IDENTITY; 8];
        check(
            unsafe { cg_rig_base_pose(rig.0, bones.as_ptr(), 65, base.as_mut_ptr(), 8) },
            "cg_rig_base_pose",
        );
        assert_eq!(base[7], cg_quat::IDENTITY, "past the joints: untouched");
        let locals: Vec<Quat> = bones.iter().map(|&q| glam_quat(q)).collect();
        let mut expected = [Quat::IDENTITY; 7];
        core.base_pose(&locals, &mut expected).unwrap();
        for k in 0..7 {
            assert_eq!(glam_quat(base[k]), expected[k], "joint {k}");
        }
        // Writing the base pose back leaves the bones as they were.
        let mut written = bones.clone();
        check(
            unsafe { cg_rig_write_joints(rig.0, base.as_ptr(), 7, written.as_mut_ptr(), 65) },
            "cg_rig_write_joints",
        );
        for (i, (a, b)) in written.iter().zip(&bones).enumerate() {
            let (a, b) = (glam_quat(*a), glam_quat(*b).normalize());
            assert!(a.dot(b).abs() > 1.0 - 1e-5, "bone {i}: {a} {b}");
        }
        // A gaze turn written agrees with the core's.
        let turned: Vec<cg_quat> = base[..7]
            .iter()
            .map(|&q| (glam_quat(q) * Quat::from_rotation_y(0.3)).into())
            .collect();
        let mut written = bones.clone();
        check(
            unsafe { cg_rig_write_joints(rig.0, turned.as_ptr(), 7, written.as_mut_ptr(), 65) },
            "cg_rig_write_joints",
        );
        let mut core_written = locals.clone();
        let turned_core: Vec<Quat> = turned.iter().map(|&q| glam_quat(q)).collect();
        core.write_joints(&turned_core, &mut core_written).unwrap();
        // (The C call normalises the joints it is given: equal to float rounding.)
        for (i, (a, b)) in written.iter().zip(&core_written).enumerate() {
            assert!(glam_quat(*a).abs_diff_eq(*b, 1e-6), "bone {i}");
        }
    }
}

#[test]
fn bones_the_chain_does_not_read_may_hold_anything() {
    let skeleton = Skeleton::mixamo();
    let rig = skeleton.rig(100.0);
    let mut bones = skeleton.animated(0.4);
    let mut base = [cg_quat::IDENTITY; 7];
    check(
        unsafe { cg_rig_base_pose(rig.0, bones.as_ptr(), 65, base.as_mut_ptr(), 7) },
        "cg_rig_base_pose",
    );
    // A finger (read by no joint) NaN, another zero: the same base pose, and they stay.
    let finger = bone(&skeleton, "LeftHandThumb2");
    bones[finger] = cg_quat {
        x: f32::NAN,
        ..cg_quat::IDENTITY
    };
    bones[finger + 1] = cg_quat {
        x: 0.0,
        y: 0.0,
        z: 0.0,
        w: 0.0,
    };
    let mut again = [cg_quat::IDENTITY; 7];
    check(
        unsafe { cg_rig_base_pose(rig.0, bones.as_ptr(), 65, again.as_mut_ptr(), 7) },
        "cg_rig_base_pose with a NaN finger",
    );
    assert_eq!(base, again);
    check(
        unsafe { cg_rig_write_joints(rig.0, base.as_ptr(), 7, bones.as_mut_ptr(), 65) },
        "cg_rig_write_joints with a NaN finger",
    );
    assert!(bones[finger].x.is_nan() && bones[finger + 1].w == 0.0);
}

#[test]
fn overrides_and_failures_name_the_bone() {
    let skeleton = Skeleton::mixamo();
    let mut desc = skeleton.desc(1.0);
    let mut rig = null_mut();
    for (map, named) in [
        (c"mixamorig:Spine1=none", "'mixamorig:Spine1'"),
        (c"Jaw=head", "'Jaw'"),
        (c"Spine=elbow", "'elbow' is not a role"),
    ] {
        desc.bone_map = map.as_ptr();
        assert_eq!(
            unsafe { cg_rig_create(&desc, &mut rig) },
            cg_status::InvalidArgument
        );
        assert!(rig.is_null());
        let message = crowdgaze::ffi::last_error::last_error_message();
        assert!(message.contains(named), "{message}");
    }
    // Spine1 as the root: a shorter chain, said in the report.
    let map = c"Spine=none,Spine1=root";
    desc.bone_map = map.as_ptr();
    check(unsafe { cg_rig_create(&desc, &mut rig) }, "cg_rig_create");
    let mut joints = 0;
    check(
        unsafe { cg_rig_joint_count(rig, &mut joints) },
        "joint_count",
    );
    assert_eq!(joints, 5, "Spine2, Neck, Head and the eyes");
    let text = report(rig);
    assert!(text.contains("hangs from 'mixamorig:Spine1'"), "{text}");
    let mut roles = [0u32; 65];
    check(
        unsafe { cg_rig_bone_roles(rig, roles.as_mut_ptr(), 65) },
        "roles",
    );
    assert_eq!(roles[bone(&skeleton, "Spine")], cg_bone_role::None as u32);
    assert_eq!(roles[bone(&skeleton, "Spine1")], cg_bone_role::Root as u32);
    unsafe { cg_rig_destroy(rig) };
}
