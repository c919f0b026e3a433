//! What the checks read from outputs: their floats (which must all be finite) and their
//! bytes (which must be untouched after a failed call).

use crowdgaze::ffi::attention::{
    cg_character_params, cg_constraint, cg_gaze_info, cg_score_breakdown,
};
use crowdgaze::ffi::chain::cg_chain_desc;
use crowdgaze::ffi::crowd::cg_crowd_config;
use crowdgaze::ffi::eyelids::cg_eyelids;
use crowdgaze::ffi::gaze::cg_eye_info;
use crowdgaze::ffi::types::{cg_dualquat, cg_quat, cg_vec3};

/// The byte every output buffer is filled with before a call.
const SENTINEL: u8 = 0xA5;

/// Plain C data that an API call writes: every bit pattern is a valid value.
///
/// # Safety
/// Implementors must be `repr(C)` types of integers and floats only.
pub unsafe trait Output: Copy {
    /// Appends the value's floats.
    fn floats(&self, out: &mut Vec<f64>);
}

/// `count` values filled with the sentinel byte.
pub fn sentinel<T: Output>(count: usize) -> Vec<T> {
    (0..count)
        .map(|_| {
            let mut value = std::mem::MaybeUninit::<T>::uninit();
            // SAFETY: `Output` types accept any bit pattern, so filling every byte makes a
            // valid value.
            unsafe {
                value.as_mut_ptr().write_bytes(SENTINEL, 1);
                value.assume_init()
            }
        })
        .collect()
}

/// The bytes of `values`.
pub fn bytes<T: Output>(values: &[T]) -> &[u8] {
    // SAFETY: `Output` types are plain data; the slice covers exactly `values`.
    unsafe { std::slice::from_raw_parts(values.as_ptr().cast(), std::mem::size_of_val(values)) }
}

/// Whether no byte of `values` was written since `sentinel`.
pub fn untouched<T: Output>(values: &[T]) -> bool {
    bytes(values).iter().all(|&b| b == SENTINEL)
}

/// One versioned struct filled with the sentinel byte but for its `struct_size`, set to
/// `size_of::<T>()` as a caller sets it before the call that fills the struct.
pub fn sized_sentinel<T: Output>() -> Vec<T> {
    let mut value = sentinel::<T>(1);
    // SAFETY: a versioned struct starts with its `uint32_t struct_size`.
    unsafe {
        value
            .as_mut_ptr()
            .cast::<u32>()
            .write(std::mem::size_of::<T>() as u32)
    };
    value
}

/// Whether no byte of a [`sized_sentinel`] was written since.
pub fn sized_untouched<T: Output>(values: &[T]) -> bool {
    let (size, rest) = bytes(values).split_at(4);
    size == (std::mem::size_of::<T>() as u32).to_ne_bytes() && rest.iter().all(|&b| b == SENTINEL)
}

/// The first value of `values` with a NaN or infinite float, as a message.
pub fn non_finite<T: Output + std::fmt::Debug>(values: &[T]) -> Option<String> {
    let mut floats = Vec::new();
    values.iter().enumerate().find_map(|(index, value)| {
        floats.clear();
        value.floats(&mut floats);
        (!floats.iter().all(|f| f.is_finite())).then(|| format!("[{index}] {value:?}"))
    })
}

macro_rules! output {
    ($type:ty, |$v:ident| [$($field:expr),* $(,)?]) => {
        // SAFETY: a repr(C) struct of integers and floats only.
        unsafe impl Output for $type {
            fn floats(&self, out: &mut Vec<f64>) {
                let $v = self;
                let floats: &[f64] = &[$(f64::from($field)),*];
                out.extend_from_slice(floats);
            }
        }
    };
}

output!(u32, |_v| []);
output!(usize, |_v| []);
output!(f32, |v| [*v]);
output!(cg_vec3, |v| [v.x, v.y, v.z]);
output!(cg_quat, |v| [v.x, v.y, v.z, v.w]);
output!(cg_dualquat, |v| [
    v.real.x, v.real.y, v.real.z, v.real.w, v.dual.x, v.dual.y, v.dual.z, v.dual.w
]);
output!(cg_gaze_info, |v| [
    v.target_position.x,
    v.target_position.y,
    v.target_position.z,
    v.s_max,
    v.threshold,
    v.attentive_fraction,
]);
output!(cg_eye_info, |v| [
    v.left_origin.x,
    v.left_origin.y,
    v.left_origin.z,
    v.right_origin.x,
    v.right_origin.y,
    v.right_origin.z,
    v.left_direction.x,
    v.left_direction.y,
    v.left_direction.z,
    v.right_direction.x,
    v.right_direction.y,
    v.right_direction.z,
]);
output!(cg_eyelids, |v| [
    v.left_closure,
    v.right_closure,
    v.left_lid_pitch,
    v.right_lid_pitch,
]);
output!(cg_score_breakdown, |v| [
    v.distance,
    v.view_angle,
    v.heading_angle,
    v.relative_speed,
    v.proximity,
    v.speed,
    v.orientation,
    v.periphery,
    v.total,
]);
output!(cg_character_params, |v| [
    v.weight_proximity,
    v.weight_speed,
    v.weight_orientation,
    v.weight_periphery,
    v.attention_fraction,
]);
output!(cg_constraint, |v| [v.s_max, v.begin, v.end]);
output!(cg_crowd_config, |v| [
    v.units_per_metre,
    v.max_distance,
    v.field_of_view,
    v.speed_weight,
    v.periphery_max_angle,
    v.min_interest_time,
    v.max_interest_time,
    v.interest_cooldown,
    v.threshold_warmup,
    v.initial_threshold,
    v.attention_fraction_min,
    v.attention_fraction_max,
    v.eyes_only_angle,
    v.eyes_head_neck_angle,
    v.head_speed,
    v.max_activation_time,
    v.restart_distance,
    v.min_deactivation_time,
    v.max_deactivation_time,
    v.eye_fixation_time,
    v.head_fixation_time,
    v.random_pick_probability,
    v.social_weight,
    v.proximity_radius,
    v.lod_distance,
    v.blink_rate,
    v.blink_rate_spread,
    v.evoked_blink_min_amplitude,
    v.evoked_blink_full_amplitude,
    v.evoked_blink_probability,
    v.lid_gain,
    v.talking_gain,
    v.eye_part_weight,
    v.listener_look_share,
    v.listener_glance_time,
    v.speaker_look_share,
    v.speaker_glance_time,
    v.idle_look_share,
    v.idle_glance_time,
    v.turn_start_aversion_time,
    v.street_view_half_angle,
    v.street_first_fixation_probability,
    v.street_latency_min,
    v.street_latency_max,
    v.street_fixation_median,
    v.street_fixation_log_spread,
    v.street_refixation_probability,
    v.street_refixation_gap_min,
    v.street_refixation_gap_max,
    v.street_civil_distance,
    v.street_civil_look_probability,
    v.street_path_look_distance,
    v.street_civil_look_distance,
    v.follow_one_looker_probability,
    v.follow_max_probability,
    v.follow_distance,
    v.follow_view_half_angle,
    v.follow_oncoming_weight,
    v.follow_glance_cue_weight,
    v.follow_glance_min,
    v.follow_glance_max,
    v.follow_forget_time,
    v.street_miss_after,
    v.follow_reaction_min,
    v.follow_reaction_max,
]);

// SAFETY: a repr(C) struct of integers and floats only.
unsafe impl Output for cg_chain_desc {
    fn floats(&self, out: &mut Vec<f64>) {
        for joint in &self.joints[..(self.joint_count as usize).min(self.joints.len())] {
            joint.offset.floats(out);
            joint.rest.floats(out);
            joint.twist_axis.floats(out);
            out.extend([joint.max_swing, joint.min_twist, joint.max_twist].map(f64::from));
        }
        for v in [self.eye_forward, self.eye_up, self.root_offset] {
            v.floats(out);
        }
    }
}
