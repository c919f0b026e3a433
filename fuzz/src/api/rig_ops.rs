//! Operations on a rig: created from a small fuzzed skeleton (a humanoid of up to 16 bones
//! whose names come from real rigs, weird ones included, with fuzzed parents, translations,
//! rotations, units, axes and bone maps), then its chain, report, lists and each frame's
//! conversions. A rig is immutable: failed calls must write nothing, successful ones finite
//! values.

use super::crowd_ops::init;
use super::input::Input;
use super::outputs::{bytes, sentinel, sized_sentinel};
use super::values::quat;
use super::{or_null, pointer_to, State};
use crowdgaze::ffi::chain::cg_chain_desc;
use crowdgaze::ffi::rig::*;
use crowdgaze::ffi::status::cg_status;
use crowdgaze::ffi::types::{cg_quat, cg_vec3};
use std::ffi::c_char;
use std::mem::size_of;
use std::ptr::{null, null_mut};

/// Bone names as rigs ship them: Mixamo, Unreal, Unity/VRM, Rigify, Daz, CMU BVH, facial
/// eyes, and weird ones (empty, spaces, a namespace alone, non-ASCII, a near-duplicate).
const NAMES: &[&str] = &[
    "mixamorig:Hips",
    "mixamorig:Spine",
    "mixamorig:Spine1",
    "mixamorig:Neck",
    "mixamorig:Head",
    "mixamorig:LeftEye",
    "mixamorig:RightEye",
    "pelvis",
    "spine_01",
    "spine_02",
    "neck_01",
    "head",
    "FACIAL_L_Eye",
    "FACIAL_R_Eye",
    "J_Bip_C_Chest",
    "J_Bip_C_Head",
    "ORG-spine.006",
    "DEF-eye.L",
    "lEye",
    "Bip01 R Eye",
    "LeftUpLeg",
    "RightUpLeg",
    "LeftToeBase",
    "RightToeBase",
    "LeftArm",
    "RightArm",
    "Jaw",
    "HeadTop_End",
    "",
    "   ",
    "mixamorig:",
    "Kopf",
    "頭",
    "MIXAMORIG:HEAD",
];

/// The humanoid every fuzzed skeleton starts from: (name index, parent, translation in
/// units of 10 cm).
const HUMANOID: &[(usize, i32, [f32; 3])] = &[
    (0, -1, [0.0, 10.0, 0.0]),
    (1, 0, [0.0, 1.0, 0.0]),
    (2, 1, [0.0, 1.2, 0.1]),
    (3, 2, [0.0, 2.0, 0.0]),
    (4, 3, [0.0, 1.0, 0.1]),
    (5, 4, [0.3, 0.5, 0.9]),
    (6, 4, [-0.3, 0.5, 0.9]),
    (24, 2, [1.5, 1.5, 0.0]),
    (25, 2, [-1.5, 1.5, 0.0]),
    (20, 0, [0.9, -0.5, 0.0]),
    (21, 0, [-0.9, -0.5, 0.0]),
    (22, 9, [0.0, -9.0, 1.2]),
    (23, 10, [0.0, -9.0, 1.2]),
    (27, 4, [0.0, 1.8, 0.0]),
    (26, 4, [0.0, 0.2, 0.8]),
    (11, 13, [0.0, 0.1, 0.0]),
];

/// Bone maps: ordinary overrides, ones that do not parse or name no bone.
const BONE_MAPS: &[&str] = &[
    "mixamorig:Spine1=root",
    "Spine=none",
    "LeftEye=none,RightEye=none",
    "Jaw=head",
    "HeadTop_End=head,mixamorig:Head=none",
    "Spine=elbow",
    "=head",
    "Spine",
    "mixamorig:Neck=spine",
    "nothing=none",
];

/// A new rig from a fuzzed skeleton; it replaces the current one on success.
pub fn create(state: &mut State, input: &mut Input) {
    let mut desc: cg_rig_desc = init(state, "cg_rig_desc_init", cg_rig_desc_init);
    desc.struct_size = input.struct_size(size_of::<cg_rig_desc>());
    let count = match input.below(16) {
        15 => 1 + input.below(3) as usize,
        _ => HUMANOID.len() - input.below(8) as usize,
    };
    let mut names: Vec<Vec<u8>> = Vec::with_capacity(count);
    let mut parents = Vec::with_capacity(count);
    let mut translations = Vec::with_capacity(count);
    let mut rotations = Vec::with_capacity(count);
    for &(name, parent, t) in &HUMANOID[..count] {
        let name = match input.below(16) {
            13 => NAMES[input.below(NAMES.len() as u32) as usize]
                .as_bytes()
                .to_vec(),
            14 if input.rare() => vec![b'x'; 1025],
            14 => b"Left\xffEye".to_vec(),
            _ => NAMES[name].as_bytes().to_vec(),
        };
        names.push([name.as_slice(), b"\0"].concat());
        parents.push(match input.below(16) {
            14 => input.below(20) as i32 - 2,
            15 => input.u32() as i32,
            _ => parent,
        });
        let noise = |input: &mut Input| input.float() / 64.0;
        translations.push(cg_vec3 {
            x: t[0] + noise(input),
            y: t[1] + noise(input),
            z: t[2] + noise(input),
        });
        rotations.push(match input.below(4) {
            0 => quat(input),
            _ => cg_quat::IDENTITY,
        });
    }
    let mut name_pointers: Vec<*const c_char> = names.iter().map(|n| n.as_ptr().cast()).collect();
    if input.rare() {
        let at = input.below(count as u32) as usize;
        name_pointers[at] = null();
    }
    desc.bone_count = match input.below(32) {
        29 => 0,
        30 => 65_537,
        31 => u32::MAX,
        _ => count as u32,
    };
    desc.bone_names = array_or_null(&name_pointers, input);
    desc.parents = array_or_null(&parents, input);
    desc.rest_translations = array_or_null(&translations, input);
    desc.rest_rotations = match input.below(3) {
        0 => null(),
        _ => rotations.as_ptr(),
    };
    desc.units_per_metre = match input.below(16) {
        14 => 100.0,
        15 => input.float(),
        _ => 10.0,
    };
    let axis = |input: &mut Input| match input.below(16) {
        14 => input.below(6),
        15 => input.u32(),
        _ => CG_RIG_AXIS_DETECT,
    };
    desc.up = axis(input);
    desc.forward = axis(input);
    let map = match input.below(8) {
        7 => Some(
            [
                BONE_MAPS[input.below(BONE_MAPS.len() as u32) as usize].as_bytes(),
                b"\0",
            ]
            .concat(),
        ),
        _ => None,
    };
    desc.bone_map = map.as_ref().map_or(null(), |m| m.as_ptr().cast());
    if input.rare() {
        desc.crowd_up = input.choice(6);
        desc.crowd_forward = input.choice(6);
    }
    desc.crowd_units_per_metre = input.float_or(state.config.units_per_metre);
    let mut rig: *mut cg_rig = null_mut();
    let pointer = pointer_to(&desc, input);
    let out = or_null(&mut rig as *mut _, input);
    let status = state.call("cg_rig_create", unsafe { cg_rig_create(pointer, out) });
    if super::trace() {
        let message = crowdgaze::ffi::last_error::last_error_message();
        eprintln!("  cg_rig_create: {status:?} {message}");
    }
    if status == cg_status::Ok {
        unsafe { cg_rig_destroy(state.rig) };
        state.rig = rig;
        let mut counts = [0u32; 2];
        let status = unsafe { cg_rig_bone_count(rig, &mut counts[0]) };
        assert_eq!(state.call("cg_rig_bone_count", status), cg_status::Ok);
        let status = unsafe { cg_rig_joint_count(rig, &mut counts[1]) };
        assert_eq!(state.call("cg_rig_joint_count", status), cg_status::Ok);
        assert_eq!(counts[0], desc.bone_count, "cg_rig_bone_count");
        assert!(
            (1..=15).contains(&counts[1]),
            "cg_rig_joint_count {counts:?}"
        );
        state.rig_bones = counts[0] as usize;
        state.rig_joints = counts[1] as usize;
    } else {
        assert!(
            rig.is_null(),
            "cg_rig_create failed with {status:?} but wrote"
        );
    }
}

/// `values`, or rarely NULL.
fn array_or_null<T>(values: &[T], input: &mut Input) -> *const T {
    match input.rare() {
        true => null(),
        false => values.as_ptr(),
    }
}

/// The rig, rarely NULL (NULL too while no rig was created).
fn rig(state: &State, input: &mut Input) -> *const cg_rig {
    or_null(state.rig, input).cast_const()
}

/// `cg_rig_chain` into a versioned struct of a fuzzed `struct_size`.
pub fn chain(state: &mut State, input: &mut Input) {
    let rig = rig(state, input);
    let mut out = sized_sentinel::<cg_chain_desc>();
    let size = input.struct_size(size_of::<cg_chain_desc>());
    let pointer = or_null(out.as_mut_ptr(), input);
    if size != size_of::<cg_chain_desc>() as u32 {
        unsafe { out.as_mut_ptr().cast::<u32>().write(size) };
    }
    let status = state.call("cg_rig_chain", unsafe { cg_rig_chain(rig, pointer) });
    if size == size_of::<cg_chain_desc>() as u32 {
        state.versioned_output("cg_rig_chain", status, &out);
    } else {
        assert_ne!(
            status,
            cg_status::Ok,
            "cg_rig_chain took struct_size {size}"
        );
    }
}

/// The bone lists: chain bones and roles, into outputs of fuzzed lengths.
pub fn lists(state: &mut State, input: &mut Input) {
    let rig = rig(state, input);
    let length = input.count_or(state.rig_bones, 20);
    let mut out = sentinel::<u32>(length);
    let pointer = or_null(out.as_mut_ptr(), input);
    let (function, status) = match input.below(2) {
        0 => ("cg_rig_chain_bones", unsafe {
            cg_rig_chain_bones(rig, pointer, length)
        }),
        _ => ("cg_rig_bone_roles", unsafe {
            cg_rig_bone_roles(rig, pointer, length)
        }),
    };
    state.call(function, status);
    let written = match function {
        "cg_rig_chain_bones" => state.rig_joints,
        _ => state.rig_bones,
    };
    state.outputs(function, status, &out, written);
    if status == cg_status::Ok {
        let most = match function {
            "cg_rig_chain_bones" => state.rig_bones as u32 - 1,
            _ => cg_bone_role::RightEye as u32,
        };
        assert!(
            out[..written].iter().all(|&v| v <= most),
            "{function}: {:?}",
            &out[..written]
        );
    }
}

/// `cg_rig_report` into a buffer of any size (or NULL).
pub fn report(state: &mut State, input: &mut Input) {
    let rig = rig(state, input);
    let length = input.count(200);
    let mut buffer = vec![0x55u8 as c_char; length];
    let pointer = or_null(buffer.as_mut_ptr(), input);
    let full = unsafe { cg_rig_report(rig, pointer, length) };
    if rig.is_null() {
        assert_eq!(full, 0, "cg_rig_report(NULL)");
    } else {
        assert!(full > 0, "cg_rig_report: an empty report");
    }
    // A NULL rig writes nothing (the header's contract), as a NULL or empty buffer.
    if !rig.is_null() && !pointer.is_null() && length > 0 {
        let copied = full.min(length - 1);
        assert_eq!(buffer[copied], 0, "cg_rig_report: no NUL at {copied}");
        assert!(
            buffer[copied + 1..].iter().all(|&c| c == 0x55),
            "wrote past the NUL"
        );
    } else {
        assert!(buffer.iter().all(|&c| c == 0x55), "cg_rig_report wrote");
    }
}

/// Fuzzed bone rotations: mostly small turns, rarely zero, tiny or any floats.
fn bones(state: &State, input: &mut Input) -> Vec<cg_quat> {
    let count = input.count_or(state.rig_bones, 20);
    (0..count).map(|_| quat(input)).collect()
}

/// `cg_rig_base_pose` of fuzzed bone rotations.
pub fn base_pose(state: &mut State, input: &mut Input) {
    let rig = rig(state, input);
    let bones = bones(state, input);
    let pointer = or_null(bones.as_ptr().cast_mut(), input).cast_const();
    let length = input.count_or(state.rig_joints, 16);
    let mut out = sentinel::<cg_quat>(length);
    let out_pointer = or_null(out.as_mut_ptr(), input);
    let status = state.call("cg_rig_base_pose", unsafe {
        cg_rig_base_pose(rig, pointer, bones.len(), out_pointer, length)
    });
    state.outputs("cg_rig_base_pose", status, &out, state.rig_joints);
}

/// `cg_rig_write_joints` of fuzzed joints into fuzzed bone rotations, in place.
pub fn write_joints(state: &mut State, input: &mut Input) {
    let rig = rig(state, input);
    let count = input.count_or(state.rig_joints, 16);
    let joints: Vec<cg_quat> = (0..count).map(|_| quat(input)).collect();
    let joints_pointer = or_null(joints.as_ptr().cast_mut(), input).cast_const();
    let mut bones = bones(state, input);
    let before = bytes(&bones).to_vec();
    let pointer = or_null(bones.as_mut_ptr(), input);
    let status = state.call("cg_rig_write_joints", unsafe {
        cg_rig_write_joints(rig, joints_pointer, count, pointer, bones.len())
    });
    if status == cg_status::Ok {
        state.outputs("cg_rig_write_joints", status, &bones, bones.len());
    } else {
        assert!(
            bytes(&bones) == before.as_slice(),
            "cg_rig_write_joints failed with {status:?} but wrote the bones"
        );
    }
}
