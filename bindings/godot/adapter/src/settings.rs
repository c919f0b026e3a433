//! A `CrowdGaze` node's inspector values as Godot holds them (64-bit integers and floats),
//! checked and turned into the library's [`CrowdConfig`]: a value out of range is reported
//! as it was given (`max_characters = -5`), never as what a conversion made of it.

use crowdgaze::attention::following::FollowConfig;
use crowdgaze::{CrowdConfig, Error, Result};

/// The `CrowdGaze` node's exported settings, as given.
#[derive(Debug, Clone, PartialEq)]
pub struct CrowdSettings {
    /// Seed of every random choice (any integer; its 64 bits are used).
    pub seed: i64,
    /// Most characters.
    pub max_characters: i64,
    /// Most targets.
    pub max_targets: i64,
    /// `d_m`, metres.
    pub max_distance: f64,
    /// Degrees.
    pub field_of_view: f64,
    /// Smallest attending share (0 to 1).
    pub attention_fraction_min: f64,
    /// Largest attending share (0 to 1).
    pub attention_fraction_max: f64,
    /// Threads a step uses (0: one per core).
    pub threads: i64,
    /// Frames between attention updates (1 to 64).
    pub attention_period: i64,
    /// Metres beyond which `far_attention_period` applies (0: off).
    pub lod_distance: f64,
    /// Frames between far attention updates (1 to 64).
    pub far_attention_period: i64,
    /// Degrees: gaze turns up to this the eyes make alone (the library's
    /// `eyes_only_angle`; per crowd, as in the library).
    pub eyes_only_angle: f64,
    /// Degrees: gaze turns up to this leave the spine still (eyes, head and neck; the
    /// library's `eyes_head_neck_angle`).
    pub eyes_head_neck_angle: f64,
    /// Degrees per second: the head speed `v_m` that times a gaze shift (the library's
    /// `head_speed`, which is in radians per second).
    pub head_speed: f64,
    /// Gaze following: characters may glance where others stare (a point or object set
    /// with an overriding gaze target). Off by default.
    pub gaze_following: bool,
    /// How strongly passers-by follow: 0 Milgram et al. 1969 (42 % with one looker, up to
    /// 87 %), 1 Gallup et al. 2012 (12 %, up to 30 %).
    pub following_strength: i64,
}

impl Default for CrowdSettings {
    /// The inspector's defaults.
    fn default() -> Self {
        CrowdSettings {
            seed: 1,
            max_characters: 1024,
            max_targets: 256,
            max_distance: 10.0,
            field_of_view: 180.0,
            attention_fraction_min: 0.2,
            attention_fraction_max: 0.6,
            threads: 1,
            attention_period: 1,
            lod_distance: 0.0,
            far_attention_period: 4,
            eyes_only_angle: 15.0,
            eyes_head_neck_angle: 30.0,
            head_speed: 360.0,
            gaze_following: false,
            following_strength: 0,
        }
    }
}

impl CrowdSettings {
    /// The library's configuration. Errors name the setting and its value as given.
    pub fn config(&self) -> Result<CrowdConfig> {
        let count = |value: i64, name: &str| -> Result<u32> {
            u32::try_from(value).map_err(|_| {
                Error::InvalidArgument(format!(
                    "{name} = {value}: it must be a count from 0 to {}; set it in the inspector",
                    u32::MAX
                ))
            })
        };
        let real = |value: f64, name: &str| -> Result<f32> {
            let single = value as f32;
            if value.is_finite() && !single.is_finite() {
                return Err(Error::InvalidArgument(format!(
                    "{name} = {value:?}: too large; set it in the inspector"
                )));
            }
            Ok(single)
        };
        let mut config = CrowdConfig {
            seed: self.seed as u64,
            max_characters: count(self.max_characters, "max_characters")?,
            max_objects: count(self.max_targets, "max_targets")?,
            attention_fraction_range: (
                real(self.attention_fraction_min, "attention_fraction_min")?,
                real(self.attention_fraction_max, "attention_fraction_max")?,
            ),
            threads: count(self.threads, "threads")?,
            attention_period: count(self.attention_period, "attention_period")?,
            lod_distance: real(self.lod_distance, "lod_distance")?,
            far_attention_period: count(self.far_attention_period, "far_attention_period")?,
            ..CrowdConfig::default()
        };
        config.scoring.max_distance = real(self.max_distance, "max_distance")?;
        // The library checks radians; the node's value is in degrees.
        if !(self.field_of_view.is_finite() && (0.6..=360.0).contains(&self.field_of_view)) {
            return Err(Error::InvalidArgument(format!(
                "field_of_view = {:?}: it must be from 0.6 to 360 degrees; set it in the inspector",
                self.field_of_view
            )));
        }
        config.scoring.field_of_view = real(self.field_of_view, "field_of_view")?.to_radians();
        let degrees = |value: f64, name: &str, low: f64, high: f64, unit: &str| -> Result<f32> {
            if !(value.is_finite() && (low..=high).contains(&value)) {
                return Err(Error::InvalidArgument(format!(
                    "{name} = {value:?}: it must be from {low} to {high} {unit}; set it in the \
                     inspector"
                )));
            }
            Ok((value as f32).to_radians())
        };
        let eyes_only = degrees(
            self.eyes_only_angle,
            "eyes_only_angle",
            0.0,
            180.0,
            "degrees",
        )?;
        let eyes_head_neck = degrees(
            self.eyes_head_neck_angle,
            "eyes_head_neck_angle",
            0.0,
            180.0,
            "degrees",
        )?;
        if eyes_head_neck < eyes_only {
            return Err(Error::InvalidArgument(format!(
                "eyes_head_neck_angle = {} is below eyes_only_angle = {}: it must be at least \
                 that; set it in the inspector",
                self.eyes_head_neck_angle, self.eyes_only_angle
            )));
        }
        config.gaze.spatial.bands.eyes_only = eyes_only;
        config.gaze.spatial.bands.eyes_head_and_neck = eyes_head_neck;
        config.gaze.timing.head_speed = degrees(
            self.head_speed,
            "head_speed",
            1.0,
            100_000.0,
            "degrees per second",
        )?;
        config.following = match self.following_strength {
            0 => FollowConfig::MILGRAM,
            1 => FollowConfig::GALLUP,
            other => {
                return Err(Error::InvalidArgument(format!(
                    "following_strength = {other}: it must be 0 (Milgram) or 1 (Gallup); set \
                     it in the inspector"
                )))
            }
        };
        config.following.enabled = self.gaze_following;
        // Lookers are noticed up to 10 m, or as far as anyone is seen if that is nearer.
        config.following.distance = config.following.distance.min(config.scoring.max_distance);
        config.validate().map_err(|error| match error {
            // The library names max_objects; the node calls them targets.
            Error::InvalidArgument(text) => {
                Error::InvalidArgument(text.replace("max_objects", "max_targets"))
            }
            other => other,
        })?;
        Ok(config)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn values_are_reported_as_given() {
        assert!(CrowdSettings::default().config().is_ok());
        let negative = CrowdSettings {
            max_characters: -5,
            ..CrowdSettings::default()
        };
        let text = negative.config().unwrap_err().to_string();
        assert!(text.contains("max_characters = -5"), "{text}");
        let huge = CrowdSettings {
            max_targets: 1 << 40,
            ..CrowdSettings::default()
        };
        let text = huge.config().unwrap_err().to_string();
        assert!(text.contains("max_targets = 1099511627776"), "{text}");
        let zero = CrowdSettings {
            max_characters: 0,
            ..CrowdSettings::default()
        };
        let text = zero.config().unwrap_err().to_string();
        assert!(
            text.contains("max_characters") && text.contains('0'),
            "{text}"
        );
        let period = CrowdSettings {
            attention_period: 65,
            ..CrowdSettings::default()
        };
        assert!(period.config().unwrap_err().to_string().contains("65"));
        let far = CrowdSettings {
            max_distance: 1e300,
            ..CrowdSettings::default()
        };
        assert!(far
            .config()
            .unwrap_err()
            .to_string()
            .contains("max_distance = 1e300"));
        let fov = CrowdSettings {
            field_of_view: -90.0,
            ..CrowdSettings::default()
        };
        assert!(fov
            .config()
            .unwrap_err()
            .to_string()
            .contains("field_of_view = -90"));
        let seed = CrowdSettings {
            seed: -1,
            ..CrowdSettings::default()
        };
        assert_eq!(seed.config().unwrap().seed, u64::MAX);
    }

    #[test]
    fn gaze_following_is_off_by_default_and_its_strength_checked() {
        let config = CrowdSettings::default().config().unwrap();
        assert!(!config.following.enabled);
        let on = |strength: i64, max_distance: f64| CrowdSettings {
            gaze_following: true,
            following_strength: strength,
            max_distance,
            ..CrowdSettings::default()
        };
        let milgram = on(0, 17.0).config().unwrap().following;
        assert!(milgram.enabled);
        assert_eq!(
            milgram.one_looker_probability,
            FollowConfig::MILGRAM.one_looker_probability
        );
        assert_eq!(milgram.distance, FollowConfig::MILGRAM.distance);
        let gallup = on(1, 17.0).config().unwrap().following;
        assert_eq!(gallup.max_probability, FollowConfig::GALLUP.max_probability);
        // A crowd that sees less far notices lookers as far as it sees.
        assert_eq!(on(0, 4.0).config().unwrap().following.distance, 4.0);
        for strength in [-1, 2, i64::MAX] {
            let error = on(strength, 10.0).config().unwrap_err().to_string();
            assert!(
                error.contains(&format!("following_strength = {strength}: it must be 0")),
                "{error}"
            );
        }
    }

    #[test]
    fn head_share_and_speed_are_degrees_checked_by_name() {
        let config = CrowdSettings::default().config().unwrap();
        let library = CrowdConfig::default();
        let close = |a: f32, b: f32| (a - b).abs() < 1e-6;
        assert!(close(
            config.gaze.spatial.bands.eyes_only,
            library.gaze.spatial.bands.eyes_only
        ));
        assert!(close(
            config.gaze.spatial.bands.eyes_head_and_neck,
            library.gaze.spatial.bands.eyes_head_and_neck
        ));
        assert!(close(
            config.gaze.timing.head_speed,
            library.gaze.timing.head_speed
        ));
        let wide = CrowdSettings {
            eyes_only_angle: 25.0,
            eyes_head_neck_angle: 60.0,
            head_speed: 180.0,
            ..CrowdSettings::default()
        };
        let config = wide.config().unwrap();
        assert!(close(
            config.gaze.spatial.bands.eyes_only,
            25f32.to_radians()
        ));
        assert!(close(config.gaze.timing.head_speed, std::f32::consts::PI));
        for (settings, name) in [
            (
                CrowdSettings {
                    eyes_only_angle: f64::NAN,
                    ..CrowdSettings::default()
                },
                "eyes_only_angle = NaN",
            ),
            (
                CrowdSettings {
                    eyes_only_angle: 40.0,
                    ..CrowdSettings::default()
                },
                "eyes_head_neck_angle = 30 is below eyes_only_angle = 40",
            ),
            (
                CrowdSettings {
                    head_speed: -1.0,
                    ..CrowdSettings::default()
                },
                "head_speed = -1",
            ),
            (
                CrowdSettings {
                    eyes_head_neck_angle: 1e300,
                    ..CrowdSettings::default()
                },
                "eyes_head_neck_angle = 1e300",
            ),
        ] {
            let text = settings.config().unwrap_err().to_string();
            assert!(text.contains(name), "{text}");
        }
    }
}
