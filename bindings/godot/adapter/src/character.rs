//! A `CrowdGazeCharacter` node's settings as given (Godot's 64-bit values), checked: the
//! bone map and impact, the attention parameters, the chain's joint limits, the influence
//! controls and the talking flag. Errors name the property as the node spells it.

use crowdgaze::attention::AttentionModel;
use crowdgaze::ik::{ChainJoint, GazeChain, JointLimits, JointRole};
use crowdgaze::skeleton_map::BoneMap;
use crowdgaze::{Error, Result};

use crate::fade::Controls;

/// `max_head_turn`'s default, degrees: the yaw the neck and head of a chain mapped from a
/// skeleton may turn together (the library's limits: 50° for the neck, 20° for the head).
pub const DEFAULT_HEAD_TURN: f64 = 70.0;
/// `max_eye_angle`'s default, degrees: the cone each eye may turn in (the library's 35°).
pub const DEFAULT_EYE_ANGLE: f64 = 35.0;

/// A character node's values as Godot holds them, before any check.
#[derive(Debug, Clone, PartialEq)]
pub struct CharacterValues {
    /// `bone_map`: overrides, `Name=role,...`.
    pub bone_map: String,
    /// `impact`, `I_E`.
    pub impact: f64,
    /// `attention_fraction`: 0 to 1, or negative for the crowd's draw.
    pub attention_fraction: f64,
    /// `attention_model`: 0 the crowd model, 1 saliency, 2 the baseline, 3 the street model.
    pub attention_model: i64,
    /// `max_head_turn`, degrees.
    pub max_head_turn: f64,
    /// `max_eye_angle`, degrees.
    pub max_eye_angle: f64,
    /// `active`.
    pub active: bool,
    /// `influence`, 0 to 1.
    pub influence: f64,
    /// `influence_fade_time`, seconds.
    pub influence_fade_time: f64,
    /// `talking`.
    pub talking: bool,
}

impl Default for CharacterValues {
    /// The inspector's defaults.
    fn default() -> Self {
        let controls = Controls::default();
        CharacterValues {
            bone_map: String::new(),
            impact: 1.0,
            attention_fraction: -1.0,
            attention_model: 0,
            max_head_turn: DEFAULT_HEAD_TURN,
            max_eye_angle: DEFAULT_EYE_ANGLE,
            active: controls.active,
            influence: f64::from(controls.influence),
            influence_fade_time: f64::from(controls.fade_time),
            talking: false,
        }
    }
}

impl CharacterValues {
    /// The settings, checked.
    pub fn settings(&self) -> Result<CharacterSettings> {
        let mut settings = CharacterSettings::new(&self.bone_map, self.impact)?;
        let fraction = self.attention_fraction;
        settings.attention_fraction = if fraction.is_finite() && fraction < 0.0 {
            None
        } else if fraction.is_finite() && fraction <= 1.0 {
            Some(fraction as f32)
        } else {
            return Err(Error::InvalidArgument(format!(
                "attention_fraction = {fraction:?}: it must be from 0 to 1 (or -1 for the \
                 crowd's draw)"
            )));
        };
        settings.attention_model = match self.attention_model {
            0 => AttentionModel::Crowd,
            1 => AttentionModel::Saliency,
            2 => AttentionModel::Baseline,
            3 => AttentionModel::Street,
            other => {
                return Err(Error::InvalidArgument(format!(
                    "attention_model = {other}: it must be 0 (crowd), 1 (saliency), 2 \
                     (baseline) or 3 (street)"
                )))
            }
        };
        let angle = |value: f64, name: &str, high: f64| -> Result<f32> {
            if !(value.is_finite() && (0.0..=high).contains(&value)) {
                return Err(Error::InvalidArgument(format!(
                    "{name} = {value:?}: it must be from 0 to {high} degrees"
                )));
            }
            Ok(value as f32)
        };
        settings.max_head_turn = angle(self.max_head_turn, "max_head_turn", 180.0)?;
        settings.max_eye_angle = angle(self.max_eye_angle, "max_eye_angle", 90.0)?;
        settings.controls = Controls::new(self.active, self.influence, self.influence_fade_time)?;
        settings.talking = self.talking;
        Ok(settings)
    }
}

/// How a character is registered and driven.
#[derive(Debug, Clone, PartialEq)]
pub struct CharacterSettings {
    /// Bone names to roles: the library's default map with the node's overrides.
    pub bone_map: BoneMap,
    /// `I_E`, how interesting the character is to others (≥ 0).
    pub impact: f32,
    /// The share of the time it attends (0 to 1); `None`: the crowd's draw.
    pub attention_fraction: Option<f32>,
    /// The model that decides where it looks.
    pub attention_model: AttentionModel,
    /// Degrees the neck and head may turn together (yaw), [`DEFAULT_HEAD_TURN`] as mapped.
    pub max_head_turn: f32,
    /// Degrees each eye may turn (its cone's half-angle), [`DEFAULT_EYE_ANGLE`] as mapped.
    pub max_eye_angle: f32,
    /// Active, influence and fade time.
    pub controls: Controls,
    /// True while the character talks (pushed to the crowd each frame).
    pub talking: bool,
}

impl CharacterSettings {
    /// From the node's `bone_map` (overrides, `Name=role,...`) and `impact` as given; the
    /// rest at their defaults.
    pub fn new(bone_map: &str, impact: f64) -> Result<CharacterSettings> {
        let bone_map = BoneMap::with_overrides(bone_map)?;
        let impact = impact as f32;
        if !(impact.is_finite() && (0.0..=1e6).contains(&impact)) {
            return Err(Error::InvalidArgument(format!(
                "impact = {impact}: it must be from 0 to 1000000"
            )));
        }
        Ok(CharacterSettings {
            bone_map,
            impact,
            ..CharacterSettings::default()
        })
    }

    /// True if the chain these settings build differs from `other`'s (the skeleton is
    /// mapped again).
    pub fn chain_differs(&self, other: &CharacterSettings) -> bool {
        self.bone_map != other.bone_map
            || self.max_head_turn != other.max_head_turn
            || self.max_eye_angle != other.max_eye_angle
    }

    /// `chain` (as the skeleton map built it, with the library's limits) with these
    /// settings' joint limits: the neck's and head's yaw limits scaled so that together
    /// they reach `max_head_turn`, each eye's cone `max_eye_angle`. The chain itself at the
    /// defaults.
    pub fn limit_chain(&self, chain: &GazeChain) -> Result<GazeChain> {
        let head = f64::from(self.max_head_turn);
        let eye = f64::from(self.max_eye_angle);
        if head == DEFAULT_HEAD_TURN && eye == DEFAULT_EYE_ANGLE {
            return Ok(*chain);
        }
        let scale = (head / DEFAULT_HEAD_TURN) as f32;
        let pi = std::f32::consts::PI;
        let joints: Vec<ChainJoint> = chain
            .joints()
            .iter()
            .map(|joint| {
                let limits = joint.limits;
                let limits = match joint.role {
                    JointRole::Cervical | JointRole::Head => JointLimits::new(
                        limits.twist_axis(),
                        limits.max_swing(),
                        (limits.min_twist() * scale).max(-pi),
                        (limits.max_twist() * scale).min(pi),
                    ),
                    JointRole::LeftEye | JointRole::RightEye => JointLimits::new(
                        limits.twist_axis(),
                        (eye as f32).to_radians(),
                        limits.min_twist(),
                        limits.max_twist(),
                    ),
                    JointRole::Spine => limits,
                };
                ChainJoint { limits, ..*joint }
            })
            .collect();
        GazeChain::new(
            &joints,
            chain.eye_forward(),
            chain.eye_up(),
            chain.root_offset(),
        )
    }
}

impl Default for CharacterSettings {
    fn default() -> Self {
        CharacterSettings {
            bone_map: BoneMap::default(),
            impact: 1.0,
            attention_fraction: None,
            attention_model: AttentionModel::Crowd,
            max_head_turn: DEFAULT_HEAD_TURN as f32,
            max_eye_angle: DEFAULT_EYE_ANGLE as f32,
            controls: Controls::default(),
            talking: false,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    #[test]
    fn values_are_checked_and_named() {
        let settings = CharacterValues::default().settings().unwrap();
        assert_eq!(settings, CharacterSettings::default());
        let bad = |values: CharacterValues, name: &str| {
            let text = values.settings().unwrap_err().to_string();
            assert!(text.contains(name), "{text}");
        };
        let v = CharacterValues::default;
        bad(
            CharacterValues {
                attention_fraction: 1.5,
                ..v()
            },
            "attention_fraction = 1.5",
        );
        bad(
            CharacterValues {
                attention_fraction: f64::NEG_INFINITY,
                ..v()
            },
            "attention_fraction = -inf",
        );
        bad(
            CharacterValues {
                attention_model: 7,
                ..v()
            },
            "attention_model = 7",
        );
        bad(
            CharacterValues {
                max_head_turn: -1.0,
                ..v()
            },
            "max_head_turn = -1",
        );
        bad(
            CharacterValues {
                max_eye_angle: f64::NAN,
                ..v()
            },
            "max_eye_angle = NaN",
        );
        bad(
            CharacterValues {
                influence: 2.0,
                ..v()
            },
            "influence = 2",
        );
        let chosen = CharacterValues {
            attention_fraction: 0.25,
            attention_model: 1,
            talking: true,
            ..v()
        }
        .settings()
        .unwrap();
        assert_eq!(chosen.attention_fraction, Some(0.25));
        assert_eq!(chosen.attention_model, AttentionModel::Saliency);
        assert!(chosen.talking);
    }

    #[test]
    fn limits_scale_the_neck_and_head_and_set_the_eyes() {
        let chain = GazeChain::human(Vec3::Y, Vec3::Z);
        let defaults = CharacterSettings::default();
        assert_eq!(defaults.limit_chain(&chain).unwrap(), chain);
        let narrow = CharacterSettings {
            max_head_turn: 35.0,
            max_eye_angle: 10.0,
            ..CharacterSettings::default()
        };
        assert!(narrow.chain_differs(&defaults));
        let limited = narrow.limit_chain(&chain).unwrap();
        for (before, after) in chain.joints().iter().zip(limited.joints()) {
            let (b, a) = (before.limits, after.limits);
            match before.role {
                JointRole::Cervical | JointRole::Head => {
                    assert!((a.max_twist() - b.max_twist() / 2.0).abs() < 1e-6);
                    assert_eq!(a.max_swing(), b.max_swing());
                }
                JointRole::LeftEye | JointRole::RightEye => {
                    assert!((a.max_swing() - 10f32.to_radians()).abs() < 1e-6)
                }
                JointRole::Spine => assert_eq!(a, b),
            }
        }
        let wide = CharacterSettings {
            max_head_turn: 180.0,
            ..CharacterSettings::default()
        };
        assert!(wide.limit_chain(&chain).is_ok());
    }
}
