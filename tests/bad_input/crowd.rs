//! Rows: the crowd handle (create it, read its config, count its characters).

use crate::{
    corruption::{
        bad_output_sizes, change, invalid, non_finite, struct_sizes_from, Corruption,
        OLDER_CROWD_CONFIG,
    },
    table::Table,
    values::{floats, init, padded, Fields},
    BAD_SIZE, NULL_ARG,
};
use crowdgaze::ffi::attention::*;
use crowdgaze::ffi::crowd::*;
use crowdgaze::ffi::types::cg_axis;
use std::mem::offset_of;
use std::ptr::{null, null_mut};

fn crowd_config_floats() -> Fields {
    floats!(cg_crowd_config: units_per_metre, max_distance, field_of_view, speed_weight,
        periphery_max_angle, min_interest_time, max_interest_time, interest_cooldown,
        threshold_warmup, initial_threshold, attention_fraction_min, attention_fraction_max,
        eyes_only_angle, eyes_head_neck_angle, head_speed, max_activation_time,
        restart_distance, min_deactivation_time, max_deactivation_time, eye_fixation_time,
        head_fixation_time, random_pick_probability, social_weight, proximity_radius,
        lod_distance, blink_rate, blink_rate_spread, evoked_blink_min_amplitude,
        evoked_blink_full_amplitude, evoked_blink_probability, lid_gain, talking_gain,
        eye_part_weight, listener_look_share, listener_glance_time, speaker_look_share,
        speaker_glance_time, idle_look_share, idle_glance_time, turn_start_aversion_time,
        street_view_half_angle, street_first_fixation_probability, street_latency_min,
        street_latency_max, street_fixation_median, street_fixation_log_spread,
        street_refixation_probability, street_refixation_gap_min, street_refixation_gap_max,
        street_civil_distance, street_civil_look_probability, street_path_look_distance,
        street_civil_look_distance, follow_one_looker_probability, follow_max_probability,
        follow_distance, follow_view_half_angle, follow_oncoming_weight,
        follow_glance_cue_weight, follow_glance_min, follow_glance_max, follow_forget_time,
        street_miss_after, follow_reaction_min, follow_reaction_max)
}

/// Values of `cg_crowd_config` outside their documented ranges.
fn crowd_config_out_of_range() -> Vec<Corruption<cg_crowd_config>> {
    type C = cg_crowd_config;
    invalid::<C>(&[
        ("max_characters 0", |c| c.max_characters = 0),
        ("max_characters 2^24 + 1", |c| {
            c.max_characters = (1 << 24) + 1
        }),
        ("max_characters UINT32_MAX", |c| c.max_characters = u32::MAX),
        ("max_objects 2^24 + 1", |c| c.max_objects = (1 << 24) + 1),
        ("up_axis 6", |c| c.up_axis = 6),
        ("forward_axis UINT32_MAX", |c| c.forward_axis = u32::MAX),
        ("forward_axis = up_axis", |c| c.forward_axis = c.up_axis),
        ("forward_axis = -up_axis", |c| {
            c.forward_axis = cg_axis::NegativeY as u32
        }),
        ("units_per_metre 0", |c| c.units_per_metre = 0.0),
        ("units_per_metre -100", |c| c.units_per_metre = -100.0),
        ("max_distance -1", |c| c.max_distance = -1.0),
        ("field_of_view 0", |c| c.field_of_view = 0.0),
        ("field_of_view 7 (> 2π)", |c| c.field_of_view = 7.0),
        ("speed_weight -1", |c| c.speed_weight = -1.0),
        ("periphery_max_angle 4 (> π)", |c| {
            c.periphery_max_angle = 4.0
        }),
        ("min_interest_time -1", |c| c.min_interest_time = -1.0),
        ("max_interest_time < min_interest_time", |c| {
            c.max_interest_time = c.min_interest_time / 2.0
        }),
        ("interest_cooldown -1", |c| c.interest_cooldown = -1.0),
        ("threshold_warmup -1", |c| c.threshold_warmup = -1.0),
        ("initial_threshold -1", |c| c.initial_threshold = -1.0),
        ("attention_fraction_min -0.1", |c| {
            c.attention_fraction_min = -0.1
        }),
        ("attention_fraction_max 1.5", |c| {
            c.attention_fraction_max = 1.5
        }),
        ("attention_fraction_min > attention_fraction_max", |c| {
            c.attention_fraction_min = c.attention_fraction_max + 0.1
        }),
        ("eyes_only_angle -0.1", |c| c.eyes_only_angle = -0.1),
        ("eyes_head_neck_angle < eyes_only_angle", |c| {
            c.eyes_head_neck_angle = c.eyes_only_angle / 2.0
        }),
        ("head_speed 0", |c| c.head_speed = 0.0),
        ("max_activation_time -1", |c| c.max_activation_time = -1.0),
        ("restart_distance -1", |c| c.restart_distance = -1.0),
        ("min_deactivation_time -1", |c| {
            c.min_deactivation_time = -1.0
        }),
        ("max_deactivation_time < min_deactivation_time", |c| {
            c.max_deactivation_time = c.min_deactivation_time / 2.0
        }),
        ("eye_fixation_time 0", |c| c.eye_fixation_time = 0.0),
        ("head_fixation_time -1", |c| c.head_fixation_time = -1.0),
        ("random_pick_probability 1.5", |c| {
            c.random_pick_probability = 1.5
        }),
        ("social_weight -1", |c| c.social_weight = -1.0),
        ("proximity_radius -1", |c| c.proximity_radius = -1.0),
        ("attention_period 0", |c| c.attention_period = 0),
        ("attention_period 65", |c| c.attention_period = 65),
        ("lod_distance -1", |c| c.lod_distance = -1.0),
        ("far_attention_period 0", |c| c.far_attention_period = 0),
        ("far_attention_period 65", |c| c.far_attention_period = 65),
        ("threads 65", |c| c.threads = 65),
        ("threads UINT32_MAX", |c| c.threads = u32::MAX),
        ("blink_rate -1", |c| c.blink_rate = -1.0),
        ("blink_rate 121", |c| c.blink_rate = 121.0),
        ("blink_rate_spread 1", |c| c.blink_rate_spread = 1.0),
        ("blink_rate_spread -0.1", |c| c.blink_rate_spread = -0.1),
        ("evoked_blink_min_amplitude -0.1", |c| {
            c.evoked_blink_min_amplitude = -0.1
        }),
        (
            "evoked_blink_full_amplitude = evoked_blink_min_amplitude",
            |c| c.evoked_blink_full_amplitude = c.evoked_blink_min_amplitude,
        ),
        ("evoked_blink_full_amplitude 4 (> π)", |c| {
            c.evoked_blink_full_amplitude = 4.0
        }),
        ("evoked_blink_probability 1.5", |c| {
            c.evoked_blink_probability = 1.5
        }),
        ("lid_gain -1", |c| c.lid_gain = -1.0),
        ("lid_gain 3", |c| c.lid_gain = 3.0),
        ("eye_motion 2", |c| c.eye_motion = 2),
        ("eye_motion UINT32_MAX", |c| c.eye_motion = u32::MAX),
        ("max_conversations 2^23 + 1", |c| {
            c.max_conversations = (1 << 23) + 1
        }),
        ("max_conversations UINT32_MAX", |c| {
            c.max_conversations = u32::MAX
        }),
        ("talking_gain -1", |c| c.talking_gain = -1.0),
        ("talking_gain 101", |c| c.talking_gain = 101.0),
        ("eye_part_weight -0.1", |c| c.eye_part_weight = -0.1),
        ("eye_part_weight 101", |c| c.eye_part_weight = 101.0),
        ("listener_look_share 0", |c| c.listener_look_share = 0.0),
        ("listener_look_share 1", |c| c.listener_look_share = 1.0),
        ("listener_glance_time 0", |c| c.listener_glance_time = 0.0),
        ("listener_glance_time 601", |c| {
            c.listener_glance_time = 601.0
        }),
        ("speaker_look_share -0.5", |c| c.speaker_look_share = -0.5),
        ("speaker_look_share 1", |c| c.speaker_look_share = 1.0),
        ("speaker_glance_time -1", |c| c.speaker_glance_time = -1.0),
        ("speaker_glance_time 601", |c| c.speaker_glance_time = 601.0),
        ("idle_look_share 0", |c| c.idle_look_share = 0.0),
        ("idle_look_share 1.5", |c| c.idle_look_share = 1.5),
        ("idle_glance_time 0", |c| c.idle_glance_time = 0.0),
        ("idle_glance_time 601", |c| c.idle_glance_time = 601.0),
        ("turn_start_aversion_time -0.1", |c| {
            c.turn_start_aversion_time = -0.1
        }),
        ("turn_start_aversion_time 61", |c| {
            c.turn_start_aversion_time = 61.0
        }),
        ("street_view_half_angle -0.1", |c| {
            c.street_view_half_angle = -0.1
        }),
        ("street_view_half_angle 4 (> π)", |c| {
            c.street_view_half_angle = 4.0
        }),
        ("street_first_fixation_probability -0.1", |c| {
            c.street_first_fixation_probability = -0.1
        }),
        ("street_first_fixation_probability 1.5", |c| {
            c.street_first_fixation_probability = 1.5
        }),
        ("street_latency_min -1", |c| c.street_latency_min = -1.0),
        ("street_latency_min > street_latency_max", |c| {
            c.street_latency_min = c.street_latency_max + 0.1
        }),
        ("street_latency_max 61", |c| {
            c.street_latency_min = 0.0;
            c.street_latency_max = 61.0
        }),
        ("street_fixation_median 0", |c| {
            c.street_fixation_median = 0.0
        }),
        ("street_fixation_median 61", |c| {
            c.street_fixation_median = 61.0
        }),
        ("street_fixation_log_spread -0.1", |c| {
            c.street_fixation_log_spread = -0.1
        }),
        ("street_fixation_log_spread 3", |c| {
            c.street_fixation_log_spread = 3.0
        }),
        ("street_refixation_probability -0.1", |c| {
            c.street_refixation_probability = -0.1
        }),
        ("street_refixation_probability 1.5", |c| {
            c.street_refixation_probability = 1.5
        }),
        ("street_refixation_gap_min -1", |c| {
            c.street_refixation_gap_min = -1.0
        }),
        (
            "street_refixation_gap_min > street_refixation_gap_max",
            |c| c.street_refixation_gap_min = c.street_refixation_gap_max + 1.0,
        ),
        ("street_refixation_gap_max 601", |c| {
            c.street_refixation_gap_max = 601.0
        }),
        ("street_civil_distance -1", |c| {
            c.street_civil_distance = -1.0
        }),
        ("street_civil_distance 1001 m", |c| {
            c.street_civil_distance = 1001.0
        }),
        ("street_civil_look_probability -0.1", |c| {
            c.street_civil_look_probability = -0.1
        }),
        ("street_civil_look_probability 1.5", |c| {
            c.street_civil_look_probability = 1.5
        }),
        ("street_path_look_distance -1", |c| {
            c.street_path_look_distance = -1.0
        }),
        ("street_path_look_distance 1001 m", |c| {
            c.street_path_look_distance = 1001.0
        }),
        ("street_civil_look_distance -1", |c| {
            c.street_civil_look_distance = -1.0
        }),
        ("street_civil_look_distance 1001 m", |c| {
            c.street_civil_look_distance = 1001.0
        }),
        ("follow_enabled 2", |c| c.follow_enabled = 2),
        ("follow_enabled UINT32_MAX", |c| c.follow_enabled = u32::MAX),
        ("follow_one_looker_probability -0.1", |c| {
            c.follow_one_looker_probability = -0.1
        }),
        (
            "follow_one_looker_probability > follow_max_probability",
            |c| c.follow_one_looker_probability = c.follow_max_probability + 0.05,
        ),
        ("follow_max_probability 1.5", |c| {
            c.follow_max_probability = 1.5
        }),
        ("follow_distance -1", |c| c.follow_distance = -1.0),
        ("follow_distance 1001 m", |c| c.follow_distance = 1001.0),
        ("follow_distance > max_distance, following on", |c| {
            c.follow_enabled = 1;
            c.follow_distance = c.max_distance + 1.0
        }),
        ("follow_view_half_angle -0.1", |c| {
            c.follow_view_half_angle = -0.1
        }),
        ("follow_view_half_angle 4 (> π)", |c| {
            c.follow_view_half_angle = 4.0
        }),
        ("follow_oncoming_weight -0.1", |c| {
            c.follow_oncoming_weight = -0.1
        }),
        ("follow_oncoming_weight 1.5", |c| {
            c.follow_oncoming_weight = 1.5
        }),
        ("follow_glance_cue_weight -0.1", |c| {
            c.follow_glance_cue_weight = -0.1
        }),
        ("follow_glance_cue_weight 1.5", |c| {
            c.follow_glance_cue_weight = 1.5
        }),
        ("follow_glance_min -1", |c| c.follow_glance_min = -1.0),
        ("follow_glance_min > follow_glance_max", |c| {
            c.follow_glance_min = c.follow_glance_max + 1.0
        }),
        ("follow_glance_max 601", |c| c.follow_glance_max = 601.0),
        ("follow_forget_time -1", |c| c.follow_forget_time = -1.0),
        ("follow_forget_time 3601", |c| c.follow_forget_time = 3601.0),
        ("street_miss_after -1", |c| c.street_miss_after = -1.0),
        ("street_miss_after 61", |c| c.street_miss_after = 61.0),
        ("follow_reaction_min > follow_reaction_max", |c| {
            c.follow_reaction_min = c.follow_reaction_max + 1.0
        }),
        ("follow_reaction_max 61", |c| c.follow_reaction_max = 61.0),
    ])
}

pub(crate) fn rows_crowd(t: &mut Table) {
    let f = "cg_crowd_create";
    t.case(f, "config NULL", NULL_ARG, |h| unsafe {
        cg_crowd_create(null(), &mut h.out.crowd)
    });
    t.case(f, "out_crowd NULL", NULL_ARG, |_| unsafe {
        cg_crowd_create(&init(cg_crowd_config_init), null_mut())
    });
    // Callers built against older headers pass the sizes of the older layouts (144 bytes,
    // before `reorder_period`; 152, before the blink fields; 176, before the conversation
    // fields; 216, before the street and following fields), which are accepted.
    let mut corruptions = struct_sizes_from::<cg_crowd_config>(OLDER_CROWD_CONFIG);
    // Between two layouts' sizes: no layout's.
    for size in [148u32, 156, 180, 212, 220, 264] {
        corruptions.push(change(
            format!("struct_size {size} (between two layouts)"),
            BAD_SIZE,
            move |c: &mut cg_crowd_config| c.struct_size = size,
        ));
    }
    corruptions.extend(non_finite(&crowd_config_floats()));
    corruptions.extend(crowd_config_out_of_range());
    t.corrupt_struct(
        f,
        "config",
        corruptions,
        |_| padded(init(cg_crowd_config_init)),
        |h, config| unsafe { cg_crowd_create(config, &mut h.out.crowd) },
    );

    let f = "cg_crowd_get_config";
    t.case(f, "crowd NULL", NULL_ARG, |h| unsafe {
        cg_crowd_get_config(null(), &mut h.out.crowd_config)
    });
    t.case(f, "out_config NULL", NULL_ARG, |h| unsafe {
        cg_crowd_get_config(h.crowd, null_mut())
    });
    bad_output_sizes(t, f, OLDER_CROWD_CONFIG, |h, out| unsafe {
        cg_crowd_get_config(h.crowd, out)
    });

    let f = "cg_crowd_character_count";
    t.case(f, "crowd NULL", NULL_ARG, |h| unsafe {
        cg_crowd_character_count(null(), &mut h.out.count)
    });
    t.case(f, "out_count NULL", NULL_ARG, |h| unsafe {
        cg_crowd_character_count(h.crowd, null_mut())
    });
}
