//! `cg_crowd_config` to and from the core's `CrowdConfig`: lengths between the caller's
//! units and metres, and errors naming the caller's field.

use super::crowd::{cg_crowd_config, CG_EYE_MOTION_MAIN_SEQUENCE, CG_EYE_MOTION_PAPER};
use super::types::cg_axis;
use crate::attention::baseline::BaselineConfig;
use crate::attention::conversation::ConversationSettings;
use crate::attention::following::FollowConfig;
use crate::attention::interest::InterestConfig;
use crate::attention::saliency::SaliencyConfig;
use crate::attention::score::ScoringConfig;
use crate::attention::street::StreetConfig;
use crate::attention::TargetPart;
use crate::crowd::{CrowdConfig, EyeMotion};
use crate::error::Error;
use crate::ik::{BlinkSettings, GazeConfig};
use crate::world::World;

impl cg_crowd_config {
    /// The C view of a core config (lengths in the caller's units).
    pub(super) fn from_core(core: &CrowdConfig) -> cg_crowd_config {
        let units = core.world.units_per_metre;
        cg_crowd_config {
            struct_size: std::mem::size_of::<cg_crowd_config>() as u32,
            max_characters: core.max_characters,
            seed: core.seed,
            max_objects: core.max_objects,
            up_axis: cg_axis::from_axis(core.world.up_axis),
            forward_axis: cg_axis::from_axis(core.world.forward_axis),
            units_per_metre: units,
            max_recorded_states: core.max_recorded_states,
            max_distance: core.scoring.max_distance * units,
            field_of_view: core.scoring.field_of_view,
            speed_weight: core.scoring.speed_weight,
            periphery_max_angle: core.scoring.periphery_max_angle,
            min_interest_time: core.interest.min_hold,
            max_interest_time: core.interest.max_hold,
            interest_cooldown: core.interest.cooldown,
            threshold_warmup: core.interest.warmup,
            initial_threshold: core.interest.initial_threshold,
            attention_fraction_min: core.attention_fraction_range.0,
            attention_fraction_max: core.attention_fraction_range.1,
            eyes_only_angle: core.gaze.spatial.bands.eyes_only,
            eyes_head_neck_angle: core.gaze.spatial.bands.eyes_head_and_neck,
            head_speed: core.gaze.timing.head_speed,
            max_activation_time: core.gaze.timing.max_activation_time,
            restart_distance: core.gaze.timing.restart_distance * units,
            min_deactivation_time: core.gaze.timing.min_deactivation_time,
            max_deactivation_time: core.gaze.timing.max_deactivation_time,
            eye_fixation_time: core.saliency.eye_fixation,
            head_fixation_time: core.saliency.head_fixation,
            random_pick_probability: core.saliency.random_pick_probability,
            social_weight: core.saliency.social_weight,
            proximity_radius: core.baseline.proximity_radius * units,
            attention_period: core.attention_period,
            lod_distance: core.lod_distance * units,
            far_attention_period: core.far_attention_period,
            threads: core.threads,
            reorder_period: core.reorder_period,
            blink_rate: core.blinks.mean_rate,
            blink_rate_spread: core.blinks.rate_spread,
            evoked_blink_min_amplitude: core.blinks.evoked_min_amplitude,
            evoked_blink_full_amplitude: core.blinks.evoked_full_amplitude,
            evoked_blink_probability: core.blinks.evoked_probability,
            lid_gain: core.blinks.lid_gain,
            eye_motion: match core.eye_motion {
                EyeMotion::Paper => CG_EYE_MOTION_PAPER,
                EyeMotion::MainSequence => CG_EYE_MOTION_MAIN_SEQUENCE,
            },
            max_conversations: core.max_conversations,
            talking_gain: core.scoring.talking_gain,
            eye_part_weight: core.saliency.part_weights[TargetPart::LeftEye as usize],
            listener_look_share: core.conversation.listener_share,
            listener_glance_time: core.conversation.listener_glance,
            speaker_look_share: core.conversation.speaker_share,
            speaker_glance_time: core.conversation.speaker_glance,
            idle_look_share: core.conversation.idle_share,
            idle_glance_time: core.conversation.idle_glance,
            turn_start_aversion_time: core.conversation.turn_start_aversion,
            street_view_half_angle: core.street.view_half_angle,
            street_first_fixation_probability: core.street.first_fixation_probability,
            street_latency_min: core.street.latency_min,
            street_latency_max: core.street.latency_max,
            street_fixation_median: core.street.fixation_median,
            street_fixation_log_spread: core.street.fixation_log_spread,
            street_refixation_probability: core.street.refixation_probability,
            street_refixation_gap_min: core.street.refixation_gap_min,
            street_refixation_gap_max: core.street.refixation_gap_max,
            street_civil_distance: core.street.civil_distance * units,
            street_civil_look_probability: core.street.civil_look_probability,
            street_path_look_distance: core.street.path_look_distance * units,
            street_civil_look_distance: core.street.civil_look_distance * units,
            follow_enabled: u32::from(core.following.enabled),
            follow_one_looker_probability: core.following.one_looker_probability,
            follow_max_probability: core.following.max_probability,
            follow_distance: core.following.distance * units,
            follow_view_half_angle: core.following.view_half_angle,
            follow_oncoming_weight: core.following.oncoming_weight,
            follow_glance_cue_weight: core.following.glance_cue_weight,
            follow_glance_min: core.following.glance_min,
            follow_glance_max: core.following.glance_max,
            follow_forget_time: core.following.forget_time,
            street_miss_after: core.street.miss_after,
            follow_reaction_min: core.following.reaction_min,
            follow_reaction_max: core.following.reaction_max,
        }
    }

    /// The street model's part of the core config (lengths to metres).
    fn street_config(&self, metres: f32) -> StreetConfig {
        StreetConfig {
            view_half_angle: self.street_view_half_angle,
            first_fixation_probability: self.street_first_fixation_probability,
            latency_min: self.street_latency_min,
            latency_max: self.street_latency_max,
            fixation_median: self.street_fixation_median,
            fixation_log_spread: self.street_fixation_log_spread,
            miss_after: self.street_miss_after,
            refixation_probability: self.street_refixation_probability,
            refixation_gap_min: self.street_refixation_gap_min,
            refixation_gap_max: self.street_refixation_gap_max,
            civil_distance: self.street_civil_distance * metres,
            civil_look_probability: self.street_civil_look_probability,
            path_look_distance: self.street_path_look_distance * metres,
            civil_look_distance: self.street_civil_look_distance * metres,
        }
    }

    /// The gaze following part of the core config (lengths to metres); `follow_enabled` is
    /// checked by [`Self::follow_enabled`].
    fn follow_config(&self, metres: f32) -> FollowConfig {
        FollowConfig {
            enabled: self.follow_enabled == 1,
            one_looker_probability: self.follow_one_looker_probability,
            max_probability: self.follow_max_probability,
            distance: self.follow_distance * metres,
            view_half_angle: self.follow_view_half_angle,
            oncoming_weight: self.follow_oncoming_weight,
            glance_cue_weight: self.follow_glance_cue_weight,
            reaction_min: self.follow_reaction_min,
            reaction_max: self.follow_reaction_max,
            glance_min: self.follow_glance_min,
            glance_max: self.follow_glance_max,
            forget_time: self.follow_forget_time,
        }
    }

    /// Checks `follow_enabled`, a 0/1 flag.
    fn follow_enabled(&self) -> crate::error::Result<()> {
        match self.follow_enabled {
            0 | 1 => Ok(()),
            other => Err(Error::InvalidArgument(format!(
                "cg_crowd_config.follow_enabled is {other}, must be 0 or 1"
            ))),
        }
    }

    /// The gaze IK part of the core config (other gaze settings keep their defaults).
    fn gaze_config(&self, metres: f32) -> GazeConfig {
        let mut gaze = GazeConfig::default();
        gaze.spatial.bands.eyes_only = self.eyes_only_angle;
        gaze.spatial.bands.eyes_head_and_neck = self.eyes_head_neck_angle;
        gaze.timing.head_speed = self.head_speed;
        gaze.timing.max_activation_time = self.max_activation_time;
        gaze.timing.restart_distance = self.restart_distance * metres;
        gaze.timing.min_deactivation_time = self.min_deactivation_time;
        gaze.timing.max_deactivation_time = self.max_deactivation_time;
        gaze
    }

    /// Checks and converts to the core's config (lengths to metres); an error names the
    /// field of this struct at fault.
    pub(super) fn to_core(self) -> crate::error::Result<CrowdConfig> {
        // The axes, unit and flag first: their errors name them already.
        self.world()?;
        self.follow_enabled()?;
        self.convert().map_err(|error| self.name_the_field(error))
    }

    /// The world conventions of this config.
    fn world(&self) -> crate::error::Result<World> {
        World::new(
            cg_axis::parse(self.up_axis, "up_axis")?,
            cg_axis::parse(self.forward_axis, "forward_axis")?,
            self.units_per_metre,
        )
    }

    /// [`Self::to_core`] with the core's words in errors.
    fn convert(self) -> crate::error::Result<CrowdConfig> {
        let world = self.world()?;
        let metres = 1.0 / self.units_per_metre;
        let config = CrowdConfig {
            seed: self.seed,
            max_characters: self.max_characters,
            max_objects: self.max_objects,
            world,
            scoring: ScoringConfig {
                max_distance: self.max_distance * metres,
                field_of_view: self.field_of_view,
                speed_weight: self.speed_weight,
                periphery_max_angle: self.periphery_max_angle,
                talking_gain: self.talking_gain,
            },
            interest: InterestConfig {
                min_hold: self.min_interest_time,
                max_hold: self.max_interest_time,
                cooldown: self.interest_cooldown,
                warmup: self.threshold_warmup,
                initial_threshold: self.initial_threshold,
            },
            attention_fraction_range: (self.attention_fraction_min, self.attention_fraction_max),
            max_recorded_states: self.max_recorded_states,
            gaze: self.gaze_config(metres),
            saliency: SaliencyConfig {
                eye_fixation: self.eye_fixation_time,
                head_fixation: self.head_fixation_time,
                random_pick_probability: self.random_pick_probability,
                social_weight: self.social_weight,
                part_weights: {
                    let mut weights = SaliencyConfig::default().part_weights;
                    weights[TargetPart::LeftEye as usize] = self.eye_part_weight;
                    weights[TargetPart::RightEye as usize] = self.eye_part_weight;
                    weights
                },
                ..SaliencyConfig::default()
            },
            baseline: BaselineConfig {
                proximity_radius: self.proximity_radius * metres,
                ..BaselineConfig::default()
            },
            attention_period: self.attention_period,
            lod_distance: self.lod_distance * metres,
            far_attention_period: self.far_attention_period,
            threads: self.threads,
            reorder_period: self.reorder_period,
            blinks: BlinkSettings {
                mean_rate: self.blink_rate,
                rate_spread: self.blink_rate_spread,
                evoked_min_amplitude: self.evoked_blink_min_amplitude,
                evoked_full_amplitude: self.evoked_blink_full_amplitude,
                evoked_probability: self.evoked_blink_probability,
                lid_gain: self.lid_gain,
            },
            eye_motion: match self.eye_motion {
                CG_EYE_MOTION_PAPER => EyeMotion::Paper,
                CG_EYE_MOTION_MAIN_SEQUENCE => EyeMotion::MainSequence,
                other => {
                    return Err(Error::InvalidArgument(format!(
                        "cg_crowd_config.eye_motion is {other}, not a CG_EYE_MOTION_*"
                    )))
                }
            },
            max_conversations: self.max_conversations,
            conversation: ConversationSettings {
                listener_share: self.listener_look_share,
                listener_glance: self.listener_glance_time,
                speaker_share: self.speaker_look_share,
                speaker_glance: self.speaker_glance_time,
                idle_share: self.idle_look_share,
                idle_glance: self.idle_glance_time,
                turn_start_aversion: self.turn_start_aversion_time,
            },
            street: self.street_config(metres),
            following: self.follow_config(metres),
        };
        config.validate()?;
        Ok(config)
    }

    /// Names the field of this struct that a core error comes from: the core's names
    /// (`min_hold`) and units (metres) are not the caller's (`min_interest_time`, their
    /// units), and a NaN among grouped settings ("blink settings contains NaN") names none.
    /// Finds the first real-valued field that alone, over the defaults in the caller's
    /// units and axes, fails the same way; an error only a combination of fields makes (or
    /// one of the integer fields, whose names are the same) keeps the core's words, after
    /// the struct's name. Runs only on a failed create.
    fn name_the_field(mut self, error: Error) -> Error {
        // The same kind of error with other words.
        let (detail, remake): (&String, fn(String) -> Error) = match &error {
            Error::InvalidArgument(detail) => (detail, Error::InvalidArgument),
            Error::NonFinite(detail) => (detail, Error::NonFinite),
            _ => return error,
        };
        let world = World {
            units_per_metre: self.units_per_metre,
            ..World::default()
        };
        let mut defaults = cg_crowd_config::from_core(&CrowdConfig {
            world,
            ..CrowdConfig::default()
        });
        defaults.up_axis = self.up_axis;
        defaults.forward_axis = self.forward_axis;
        let count = self.real_fields().len();
        for index in 0..count {
            let (name, value) = {
                let (name, value) = &self.real_fields()[index];
                (*name, **value)
            };
            let mut alone = defaults;
            *alone.real_fields()[index].1 = value;
            let same = match (alone.convert(), &error) {
                (Err(Error::InvalidArgument(again)), Error::InvalidArgument(_))
                | (Err(Error::NonFinite(again)), Error::NonFinite(_)) => again == *detail,
                _ => false,
            };
            if same {
                if matches!(error, Error::NonFinite(_)) && detail.starts_with(name) {
                    return error; // the core's words name it already
                }
                let length = LENGTH_FIELDS.contains(&name);
                // The street and following settings' own words name the field already and,
                // but for lengths (metres there), give the caller's value.
                let own_words = name.starts_with("street_") || name.starts_with("follow_");
                if own_words && !length && detail.starts_with(&format!("{name} is ")) {
                    return remake(format!("cg_crowd_config.{detail}"));
                }
                let units = if length {
                    format!(" (your units; units_per_metre is {})", self.units_per_metre)
                } else {
                    String::new()
                };
                return remake(format!(
                    "cg_crowd_config.{name} is {value}{units}: {detail}"
                ));
            }
        }
        match error {
            Error::InvalidArgument(_) => remake(format!("cg_crowd_config: {detail}")),
            _ => error,
        }
    }

    /// The real-valued fields but `units_per_metre`, by name.
    fn real_fields(&mut self) -> [(&'static str, &mut f32); 61] {
        macro_rules! named {
            ($($field:ident),* $(,)?) => {
                [$((stringify!($field), &mut self.$field)),*]
            };
        }
        named!(
            max_distance,
            field_of_view,
            speed_weight,
            periphery_max_angle,
            min_interest_time,
            max_interest_time,
            interest_cooldown,
            threshold_warmup,
            initial_threshold,
            attention_fraction_min,
            attention_fraction_max,
            eyes_only_angle,
            eyes_head_neck_angle,
            head_speed,
            max_activation_time,
            restart_distance,
            min_deactivation_time,
            max_deactivation_time,
            eye_fixation_time,
            head_fixation_time,
            random_pick_probability,
            social_weight,
            proximity_radius,
            lod_distance,
            blink_rate,
            blink_rate_spread,
            evoked_blink_min_amplitude,
            evoked_blink_full_amplitude,
            evoked_blink_probability,
            lid_gain,
            talking_gain,
            eye_part_weight,
            listener_look_share,
            listener_glance_time,
            speaker_look_share,
            speaker_glance_time,
            idle_look_share,
            idle_glance_time,
            turn_start_aversion_time,
            street_view_half_angle,
            street_first_fixation_probability,
            street_latency_min,
            street_latency_max,
            street_fixation_median,
            street_fixation_log_spread,
            street_refixation_probability,
            street_refixation_gap_min,
            street_refixation_gap_max,
            street_civil_distance,
            street_civil_look_probability,
            street_path_look_distance,
            street_civil_look_distance,
            follow_one_looker_probability,
            follow_max_probability,
            follow_distance,
            follow_view_half_angle,
            follow_oncoming_weight,
            follow_glance_cue_weight,
            follow_glance_min,
            follow_glance_max,
            follow_forget_time,
        )
    }
}

/// The fields of `cg_crowd_config` in the caller's length units.
const LENGTH_FIELDS: &[&str] = &[
    "max_distance",
    "restart_distance",
    "proximity_radius",
    "lod_distance",
    "street_civil_distance",
    "street_path_look_distance",
    "street_civil_look_distance",
    "follow_distance",
];

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ffi::Versioned;

    fn create_error(change: impl FnOnce(&mut cg_crowd_config)) -> String {
        let mut config = cg_crowd_config::defaults();
        change(&mut config);
        match config.to_core() {
            Err(Error::InvalidArgument(message)) => message,
            other => panic!("expected an invalid argument, got {other:?}"),
        }
    }

    /// Asserts that the config `change` makes is refused with a message starting `prefix`.
    fn refused_as(prefix: &str, change: impl FnOnce(&mut cg_crowd_config)) {
        let message = create_error(change);
        assert!(message.starts_with(prefix), "{message}");
    }

    #[test]
    fn config_errors_name_the_callers_field_in_the_callers_units() {
        refused_as("cg_crowd_config.min_interest_time is -1: ", |c| {
            c.min_interest_time = -1.0
        });
        refused_as(
            "cg_crowd_config.max_distance is 0.5 (your units; units_per_metre is 100): ",
            |c| {
                c.units_per_metre = 100.0;
                c.max_distance = 0.5;
            },
        );
        refused_as("units_per_metre is ", |c| c.units_per_metre = 1e30);
        // Only a combination is wrong: the core's words, after the struct's name.
        let message = create_error(|c| {
            c.attention_fraction_min = 0.9;
            c.attention_fraction_max = 0.5;
        });
        assert!(message.starts_with("cg_crowd_config: "), "{message}");
        assert!(message.contains("attention_fraction_max"), "{message}");
    }

    #[test]
    fn street_and_following_fields_name_themselves_in_the_callers_units() {
        refused_as(
            "cg_crowd_config.street_latency_min is -1, must be >= 0",
            |c| c.street_latency_min = -1.0,
        );
        refused_as(
            "cg_crowd_config.street_civil_distance is 200000 (your units; units_per_metre is 100): ",
            |c| {
                c.units_per_metre = 100.0;
                c.street_civil_distance = 200_000.0;
            },
        );
        refused_as(
            "cg_crowd_config.follow_max_probability is 1.5, must be in [0, 1]",
            |c| c.follow_max_probability = 1.5,
        );
        let message = create_error(|c| c.follow_enabled = 2);
        assert_eq!(
            message,
            "cg_crowd_config.follow_enabled is 2, must be 0 or 1"
        );
        // Only with following on is a follow_distance beyond max_distance wrong.
        let message = create_error(|c| {
            c.follow_enabled = 1;
            c.max_distance = 5.0;
        });
        assert!(
            message.starts_with("cg_crowd_config: follow_distance"),
            "{message}"
        );
        let mut off = cg_crowd_config::defaults();
        off.max_distance = 5.0;
        assert!(off.to_core().is_ok());
    }

    #[test]
    fn street_and_following_lengths_convert_both_ways() {
        let mut config = cg_crowd_config::from_core(&CrowdConfig::street());
        assert_eq!(config.follow_enabled, 1);
        assert_eq!(config.max_distance, 17.0);
        config.units_per_metre = 100.0;
        config.max_distance *= 100.0;
        config.street_civil_distance = 250.0;
        config.street_path_look_distance = 500.0;
        config.street_civil_look_distance = 150.0;
        config.follow_distance = 800.0;
        let core = config.to_core().unwrap();
        assert_eq!(core.street.civil_distance, 2.5);
        assert_eq!(core.street.path_look_distance, 5.0);
        assert_eq!(core.street.civil_look_distance, 1.5);
        assert_eq!(core.following.distance, 8.0);
        assert!(core.following.enabled);
        let back = cg_crowd_config::from_core(&core);
        assert_eq!(back.street_civil_distance, 250.0);
        assert_eq!(back.follow_distance, 800.0);
        assert_eq!(back.street_view_half_angle, config.street_view_half_angle);
    }
}
