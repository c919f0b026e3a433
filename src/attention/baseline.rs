//! The stock behaviour the saliency paper compares against (Kokkinara et al. §3.3.1, the
//! default Second Life avatar): the eyes look straight ahead or away at a random angle,
//! switching at preset intervals; the head looks straight ahead when idle and turns to
//! the nearest character that comes within a proximity radius. Objects are never looked
//! at. Provided so that users and tests can compare the models.

use crate::math::random::Random;
use crate::scene::ids::NO_ENTITY;

/// Settings of the baseline.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BaselineConfig {
    /// Shortest time (s) between two eye glances. Default 1.
    pub glance_interval_min: f32,
    /// Longest time (s) between two eye glances. Default 3.
    pub glance_interval_max: f32,
    /// Probability that a glance is away (at a random angle) rather than straight ahead.
    /// Default 0.5.
    pub glance_away_probability: f32,
    /// Largest yaw of a glance away (radians, either side). Default 25°.
    pub glance_max_yaw: f32,
    /// Largest pitch of a glance away (radians, up or down). Default 10°.
    pub glance_max_pitch: f32,
    /// A character closer than this (metres) makes the head turn to it. Default 2.5 m.
    pub proximity_radius: f32,
}

impl Default for BaselineConfig {
    fn default() -> Self {
        BaselineConfig {
            glance_interval_min: 1.0,
            glance_interval_max: 3.0,
            glance_away_probability: 0.5,
            glance_max_yaw: 25f32.to_radians(),
            glance_max_pitch: 10f32.to_radians(),
            proximity_radius: 2.5,
        }
    }
}

/// One character's baseline state.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BaselineState {
    /// Seconds until the next glance decision.
    next_glance: f32,
    /// Current eye glance (yaw, pitch) relative to the head, radians; (0, 0) is ahead.
    pub glance: (f32, f32),
    /// The character the head turns to, or `NO_ENTITY`.
    pub head_target: u32,
    /// Glances started so far.
    pub glances: u32,
}

impl Default for BaselineState {
    fn default() -> Self {
        BaselineState {
            next_glance: 0.0,
            glance: (0.0, 0.0),
            head_target: NO_ENTITY,
            glances: 0,
        }
    }
}

impl BaselineState {
    /// Advances by `dt`. `nearest_character` is the closest other character within the
    /// proximity radius (or `NO_ENTITY`), as the caller found it.
    pub fn update(
        &mut self,
        dt: f32,
        nearest_character: u32,
        config: &BaselineConfig,
        random: &mut Random,
    ) {
        self.head_target = nearest_character;
        self.next_glance -= dt;
        if self.next_glance <= 0.0 {
            self.next_glance = random.range(config.glance_interval_min, config.glance_interval_max);
            self.glance = if random.next_f32() < config.glance_away_probability {
                (
                    random.range(-config.glance_max_yaw, config.glance_max_yaw),
                    random.range(-config.glance_max_pitch, config.glance_max_pitch),
                )
            } else {
                (0.0, 0.0)
            };
            self.glances += 1;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn glances_follow_the_preset_intervals_and_the_head_follows_proximity() {
        let config = BaselineConfig::default();
        let mut state = BaselineState::default();
        let mut random = Random::new(9);
        let dt = 1.0 / 30.0;
        let mut away = 0;
        for frame in 0..3000 {
            let nearest = if frame % 600 < 300 { 7 } else { NO_ENTITY };
            state.update(dt, nearest, &config, &mut random);
            assert_eq!(state.head_target, nearest);
            assert!(state.glance.0.abs() <= config.glance_max_yaw);
            if state.glance != (0.0, 0.0) {
                away += 1;
            }
        }
        // 100 s with a glance every 1–3 s.
        assert!((33..=101).contains(&state.glances), "{}", state.glances);
        assert!(away > 300 && away < 2700, "{away}");
    }
}
