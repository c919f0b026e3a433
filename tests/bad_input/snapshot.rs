//! Snapshots: every observable output of a crowd and of a view blender, as named byte strings.

use crate::{
    fixture::{JOINTS, KEYS},
    values::{bytes_of, init, sized, transform, vec3, zeroed, ZERO_QUAT},
};
use crowdgaze::ffi::attention::*;
use crowdgaze::ffi::chain::cg_chain_desc;
use crowdgaze::ffi::conversations::cg_crowd_get_conversation;
use crowdgaze::ffi::crowd::*;
use crowdgaze::ffi::following::cg_crowd_read_following;
use crowdgaze::ffi::gaze::*;
use crowdgaze::ffi::rig::*;
use crowdgaze::ffi::status::cg_status;
use crowdgaze::ffi::types::{cg_dualquat, cg_quat};
use crowdgaze::ffi::view_blender::*;

/// Observable outputs as named byte strings (floats by their bits, so NaN compares equal to
/// itself and −0 differs from +0).
#[derive(Default, PartialEq)]
pub(crate) struct Snapshot {
    pub(crate) sections: Vec<(String, Vec<u8>)>,
}

impl Snapshot {
    pub(crate) fn section(&mut self, name: impl Into<String>) -> &mut Vec<u8> {
        self.sections.push((name.into(), Vec::new()));
        &mut self.sections.last_mut().expect("just pushed").1
    }

    /// The names of the sections that differ from `other`'s.
    pub(crate) fn differences(&self, other: &Snapshot) -> Vec<String> {
        let mut out: Vec<String> = self
            .sections
            .iter()
            .zip(&other.sections)
            .filter(|(a, b)| a != b)
            .map(|((name, _), _)| name.clone())
            .collect();
        if self.sections.len() != other.sections.len() {
            out.push("the number of sections".into());
        }
        out
    }
}

pub(crate) fn status(bytes: &mut Vec<u8>, status: cg_status) {
    bytes.extend((status as u32).to_le_bytes());
}

fn count(bytes: &mut Vec<u8>, value: usize) {
    bytes.extend((value as u64).to_le_bytes());
}

/// Every reader of the crowd: count, config, gaze, joints (final and deltas), eyes, and
/// for every id its parameters, constraints, conversation and its score of every id.
pub(crate) fn crowd_snapshot(crowd: *const cg_crowd, ids: &[u32]) -> Snapshot {
    let mut s = Snapshot::default();
    let mut characters = 0usize;
    let b = s.section("cg_crowd_character_count");
    status(b, unsafe {
        cg_crowd_character_count(crowd, &mut characters)
    });
    count(b, characters);
    let mut config: cg_crowd_config = init(cg_crowd_config_init);
    let b = s.section("cg_crowd_get_config");
    status(b, unsafe { cg_crowd_get_config(crowd, &mut config) });
    b.extend(format!("{config:?}").bytes());
    let mut gaze = vec![zeroed::<cg_gaze_info>(); characters + 1];
    let mut written = usize::MAX;
    let b = s.section("cg_crowd_read_gaze");
    status(b, unsafe {
        cg_crowd_read_gaze(crowd, gaze.as_mut_ptr(), gaze.len(), &mut written)
    });
    count(b, written);
    b.extend(bytes_of(&gaze));
    let range = characters as u32;
    let mut total = 0usize;
    let b = s.section("cg_crowd_joint_total");
    status(b, unsafe {
        cg_crowd_joint_total(crowd, 0, range, &mut total)
    });
    count(b, total);
    type ReadJoints =
        unsafe extern "C" fn(*const cg_crowd, u32, u32, *mut cg_quat, usize) -> cg_status;
    for (name, read) in [
        ("cg_crowd_read_joints", cg_crowd_read_joints as ReadJoints),
        ("cg_crowd_read_joint_deltas", cg_crowd_read_joint_deltas),
    ] {
        let mut quats = vec![zeroed::<cg_quat>(); total];
        let b = s.section(name);
        status(b, unsafe {
            read(crowd, 0, range, quats.as_mut_ptr(), quats.len())
        });
        b.extend(bytes_of(&quats));
    }
    let mut eyes = vec![zeroed::<cg_eye_info>(); characters];
    let b = s.section("cg_crowd_read_eyes");
    status(b, unsafe {
        cg_crowd_read_eyes(crowd, 0, range, eyes.as_mut_ptr(), eyes.len())
    });
    b.extend(bytes_of(&eyes));
    for &id in ids {
        let mut params = [sized::<cg_character_params>()];
        let b = s.section(format!("cg_crowd_get_character_params({id})"));
        status(b, unsafe {
            cg_crowd_get_character_params(crowd, id, params.as_mut_ptr())
        });
        b.extend(bytes_of(&params));
        let mut constraints = [zeroed::<cg_constraint>(); 64];
        let mut total = usize::MAX;
        let b = s.section(format!("cg_crowd_read_constraints({id})"));
        status(b, unsafe {
            cg_crowd_read_constraints(
                crowd,
                id,
                constraints.as_mut_ptr(),
                constraints.len(),
                &mut total,
            )
        });
        count(b, total);
        b.extend(bytes_of(&constraints));
        let mut group = u32::MAX - 1;
        let b = s.section(format!("cg_crowd_get_conversation({id})"));
        status(b, unsafe {
            cg_crowd_get_conversation(crowd, id, &mut group)
        });
        b.extend(group.to_le_bytes());
        let (mut point, mut following, mut glances) = (vec3(9.0, 9.0, 9.0), 7u32, 7u32);
        let b = s.section(format!("cg_crowd_read_following({id})"));
        status(b, unsafe {
            cg_crowd_read_following(crowd, id, &mut point, &mut following, &mut glances)
        });
        b.extend(bytes_of(&[point]));
        b.extend(following.to_le_bytes());
        b.extend(glances.to_le_bytes());
        let b = s.section(format!("cg_crowd_score({id}, *)"));
        for &entity in ids {
            let mut score = [zeroed::<cg_score_breakdown>()];
            status(b, unsafe {
                cg_crowd_score(crowd, id, entity, score.as_mut_ptr())
            });
            b.extend(bytes_of(&score));
        }
    }
    s
}

/// The weights and the evaluated poses of a blender for viewers on each key camera (where
/// one key alone is seen) and off them, at several times.
pub(crate) fn blender_snapshot(s: &mut Snapshot, name: &str, blender: *const cg_view_blender) {
    let b = s.section(name);
    let placed = transform([0.0, 1.0, 0.0], 0.7, [1.0, 0.0, 2.0]);
    for (character, origin) in [(IDENTITY_DQ, [0.0; 3]), (placed, [1.0, 0.0, 2.0])] {
        for direction in [
            [0.0, 0.0, 5.0],
            [5.0, 0.0, 0.0],
            [0.0, 0.0, -5.0],
            [-5.0, 0.0, 0.0],
            [0.0, 5.0, 0.0],
            [1.0, 2.0, 3.0],
        ] {
            let viewer = vec3(
                origin[0] + direction[0],
                origin[1] + direction[1],
                origin[2] + direction[2],
            );
            let mut weights = [0.0f32; KEYS];
            status(b, unsafe {
                cg_view_blender_weights(blender, &character, &viewer, weights.as_mut_ptr(), KEYS)
            });
            b.extend(bytes_of(&weights));
            for t in [0.0, 0.13, 0.55, 2.4] {
                let mut pose = [zeroed::<cg_dualquat>(); JOINTS];
                status(b, unsafe {
                    cg_view_blender_evaluate(
                        blender,
                        &character,
                        &viewer,
                        t,
                        pose.as_mut_ptr(),
                        JOINTS,
                    )
                });
                b.extend(bytes_of(&pose));
            }
        }
    }
}

pub(crate) const IDENTITY_DQ: cg_dualquat = cg_dualquat {
    real: cg_quat::IDENTITY,
    dual: ZERO_QUAT,
};

/// Everything a rig tells: its counts, chain, chain bones, roles, report, and the base
/// pose and joints written back of a posed skeleton.
pub(crate) fn rig_snapshot(s: &mut Snapshot, rig: *const cg_rig) {
    let b = s.section("rig");
    let (mut bones, mut joints) = (0u32, 0u32);
    status(b, unsafe { cg_rig_bone_count(rig, &mut bones) });
    status(b, unsafe { cg_rig_joint_count(rig, &mut joints) });
    b.extend(bones.to_le_bytes());
    b.extend(joints.to_le_bytes());
    let mut chain: cg_chain_desc = unsafe { std::mem::zeroed() };
    chain.struct_size = size_of::<cg_chain_desc>() as u32;
    status(b, unsafe { cg_rig_chain(rig, &mut chain) });
    b.extend(format!("{chain:?}").bytes());
    let mut list = [0u32; 80];
    status(b, unsafe { cg_rig_chain_bones(rig, list.as_mut_ptr(), 80) });
    status(b, unsafe {
        cg_rig_bone_roles(rig, list[15..].as_mut_ptr(), 65)
    });
    list.iter().for_each(|v| b.extend(v.to_le_bytes()));
    let mut report = vec![0u8; 2048];
    let length = unsafe { cg_rig_report(rig, report.as_mut_ptr().cast(), report.len()) };
    count(b, length);
    b.extend(&report);
    let skeleton = crate::skeleton::Skeleton::mixamo();
    let mut posed = skeleton.animated(0.8);
    let mut base = [ZERO_QUAT; 15];
    status(b, unsafe {
        cg_rig_base_pose(rig, posed.as_ptr(), posed.len(), base.as_mut_ptr(), 15)
    });
    b.extend(bytes_of(&base));
    status(b, unsafe {
        cg_rig_write_joints(rig, base.as_ptr(), joints as usize, posed.as_mut_ptr(), 65)
    });
    b.extend(bytes_of(&posed));
}
