//! The operation table: what each op byte calls. Append new operations at the end (at most
//! 64): the committed seeds keep their meaning.

use super::input::Input;
use super::{blend_ops, crowd_ops, rig_ops, State};
use crowdgaze::ffi::last_error::cg_last_error_message;
use crowdgaze::ffi::status::cg_status_str;
use crowdgaze::ffi::version::{cg_version, cg_version_string};

/// One operation: a name for messages and the function running it.
pub type Op = (&'static str, fn(&mut State, &mut Input));

pub const OPS: &[Op] = &[
    ("crowd_create", crowd_ops::create),
    ("add_character", crowd_ops::add_character),
    ("add_object", crowd_ops::add_object),
    ("remove_entity", crowd_ops::remove_entity),
    ("push_frame", crowd_ops::push_frame),
    ("step", crowd_ops::step),
    ("walk", crowd_ops::walk),
    ("read_gaze", crowd_ops::read_gaze),
    ("score", crowd_ops::score),
    ("get_character_params", crowd_ops::get_character_params),
    ("set_character_params", crowd_ops::set_character_params),
    ("set_impact", crowd_ops::set_impact),
    ("plan", crowd_ops::plan),
    ("clear_plan", crowd_ops::clear_plan),
    ("read_constraints", crowd_ops::read_constraints),
    ("set_viewer", crowd_ops::set_viewer),
    ("set_attention_period", crowd_ops::set_attention_period),
    ("set_gaze_target", crowd_ops::set_gaze_target),
    ("clear_gaze_target", crowd_ops::clear_gaze_target),
    ("set_base_pose", crowd_ops::set_base_pose),
    ("set_base_poses", crowd_ops::set_base_poses),
    ("joint_total", crowd_ops::joint_total),
    ("read_joints", crowd_ops::read_joint_rotations),
    ("read_joint_deltas", crowd_ops::read_joint_deltas),
    ("read_eyes", crowd_ops::read_eyes),
    ("character_count", crowd_ops::character_count),
    ("get_config", crowd_ops::get_config),
    ("chain_init", crowd_ops::chain_init),
    ("blender_create", blend_ops::create),
    ("set_key_clip", blend_ops::set_key_clip),
    ("set_key_pose", blend_ops::set_key_pose),
    ("add_camera", blend_ops::add_camera),
    ("weights", blend_ops::weights),
    ("evaluate", blend_ops::evaluate),
    ("from_rt", blend_ops::from_rt),
    ("to_rt", blend_ops::to_rt),
    ("from_matrix", blend_ops::from_matrix),
    ("to_matrix", blend_ops::to_matrix),
    ("blend_dlb", blend_ops::blend_dlb),
    ("blend_dib", blend_ops::blend_dib),
    ("blend_pose_dlb", blend_ops::blend_pose_dlb),
    ("blend_pose_dib", blend_ops::blend_pose_dib),
    ("camera_center", blend_ops::camera_center),
    ("messages", messages),
    ("ranged_step", crowd_ops::ranged_step),
    ("ranged_push", crowd_ops::ranged_push),
    ("read_eyelids", crowd_ops::read_eyelids),
    ("set_conversation", crowd_ops::set_conversation),
    ("remove_conversation", crowd_ops::remove_conversation),
    ("get_conversation", crowd_ops::get_conversation),
    ("rig_create", rig_ops::create),
    ("rig_chain", rig_ops::chain),
    ("rig_lists", rig_ops::lists),
    ("rig_report", rig_ops::report),
    ("rig_base_pose", rig_ops::base_pose),
    ("rig_write_joints", rig_ops::write_joints),
    ("read_following", crowd_ops::read_following),
];

/// The functions that return no status: the last error message into a buffer of any
/// size (or NULL), a status's string, the version.
fn messages(_state: &mut State, input: &mut Input) {
    let length = input.count(40);
    let mut buffer = vec![0x55u8 as std::ffi::c_char; length];
    let pointer = if input.rare() {
        std::ptr::null_mut()
    } else {
        buffer.as_mut_ptr()
    };
    let full = unsafe { cg_last_error_message(pointer, length) };
    if !pointer.is_null() && length > 0 {
        let copied = full.min(length - 1);
        assert_eq!(
            buffer[copied], 0,
            "cg_last_error_message: no NUL at {copied}"
        );
        assert!(
            buffer[..copied].iter().all(|&c| c != 0),
            "NUL inside the message"
        );
    }
    let status = if input.rare() {
        input.u32()
    } else {
        input.below(11)
    };
    assert!(
        !cg_status_str(status).is_null(),
        "cg_status_str({status}) is NULL"
    );
    assert!(
        !cg_version_string().is_null(),
        "cg_version_string() is NULL"
    );
    assert_eq!(
        cg_version() >> 16,
        crowdgaze::ffi::version::CG_VERSION_MAJOR
    );
}
