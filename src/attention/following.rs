//! Gaze following: a character notices people in its view looking at something (a point or
//! an object, not a person) and may glance there too, then goes back to its own attention.
//! The chance rises with how many look and saturates (Milgram, Bickman & Berkowitz 1969;
//! Gallup et al. 2012); people walking ahead in the same direction count more than
//! oncoming ones (Gallup, Chong & Couzin 2012); a passer-by's glance is a weaker cue than a
//! stare, so following does not cascade through the crowd (no tipping point: Gallup et al.
//! 2012). docs/street.md gives the figures and crowdgaze's measured ones beside them.

use glam::{Vec2, Vec3};

use crate::error::{check_range, Error, Result};
use crate::math::random::Random;

/// Settings of gaze following. Distances are metres, durations seconds, angles radians.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FollowConfig {
    /// Whether characters follow others' gaze. Default off: the crowd behaves exactly as
    /// without the layer.
    pub enabled: bool,
    /// Probability that a passer-by who sees one person staring looks too. Default 0.42
    /// (Milgram et al. 1969).
    pub one_looker_probability: f32,
    /// The probability with many lookers (the curve saturates there). Default 0.87
    /// (Milgram et al. 1969: 86 % with 15 lookers).
    pub max_probability: f32,
    /// Lookers are noticed up to this ground distance; at most the crowd's
    /// `max_distance`. Default 10 m.
    pub distance: f32,
    /// Half-angle of the view in which lookers are noticed, about the character's
    /// heading. Default 90°.
    pub view_half_angle: f32,
    /// Weight of a looker walking towards the character (a stationary one or one walking
    /// ahead the same way weighs 1). Default 0.5.
    pub oncoming_weight: f32,
    /// Weight of a character that is itself only glancing because it follows (a stare
    /// set by game logic weighs 1). Default 0.1: a glance is a weak cue, so following does
    /// not cascade.
    pub glance_cue_weight: f32,
    /// Shortest time from deciding to follow to the glance: noticing where others look
    /// and turning there. Default 0.3 s.
    pub reaction_min: f32,
    /// Longest. Default 1 s.
    pub reaction_max: f32,
    /// Shortest glance of a follower. Default 1 s.
    pub glance_min: f32,
    /// Longest glance. Default 2.5 s.
    pub glance_max: f32,
    /// Seconds with no looker in view after which an encounter is over: the next lookers
    /// are a new encounter, decided afresh. Default 10 s.
    pub forget_time: f32,
}

impl Default for FollowConfig {
    fn default() -> Self {
        FollowConfig::MILGRAM
    }
}

impl FollowConfig {
    /// The default strength: Milgram, Bickman & Berkowitz's street (1969), 42 % of
    /// passers-by looking up with one looker, 86 % with fifteen. Off until `enabled`.
    pub const MILGRAM: FollowConfig = FollowConfig {
        enabled: false,
        one_looker_probability: 0.42,
        max_probability: 0.87,
        distance: 10.0,
        view_half_angle: std::f32::consts::FRAC_PI_2,
        oncoming_weight: 0.5,
        glance_cue_weight: 0.1,
        reaction_min: 0.3,
        reaction_max: 1.0,
        glance_min: 1.0,
        glance_max: 2.5,
        forget_time: 10.0,
    };

    /// The weaker response Gallup et al. (2012) measured on an Oxford shopping street
    /// (about a quarter of passers-by, saturating by five lookers). Off until `enabled`.
    pub const GALLUP: FollowConfig = FollowConfig {
        one_looker_probability: 0.12,
        max_probability: 0.3,
        ..FollowConfig::MILGRAM
    };

    /// Probability that a passer-by follows lookers of total weight `lookers`:
    /// `P(k) = P_max (1 − (1 − p)^k)`, with `p = P(1) / P_max`: rising with `k`,
    /// saturating at `P_max`.
    pub fn probability(&self, lookers: f32) -> f32 {
        if lookers <= 0.0 || self.max_probability <= 0.0 {
            return 0.0;
        }
        let per_looker = (self.one_looker_probability / self.max_probability).min(1.0);
        self.max_probability * (1.0 - (1.0 - per_looker).powf(lookers))
    }

    /// Checks every setting; errors name the setting and its value.
    pub fn validate(&self, max_distance: f32) -> Result<()> {
        use std::f32::consts::PI;
        let ceiling = self.max_probability;
        check_range(ceiling, 0.0, 1.0, "follow_max_probability")?;
        let one = self.one_looker_probability;
        check_range(one, 0.0, ceiling, "follow_one_looker_probability")?;
        check_range(self.distance, 0.0, 1000.0, "follow_distance")?;
        check_range(self.view_half_angle, 0.0, PI, "follow_view_half_angle")?;
        check_range(self.oncoming_weight, 0.0, 1.0, "follow_oncoming_weight")?;
        check_range(self.glance_cue_weight, 0.0, 1.0, "follow_glance_cue_weight")?;
        check_range(self.reaction_max, 0.0, 60.0, "follow_reaction_max")?;
        let reaction = self.reaction_min;
        check_range(reaction, 0.0, self.reaction_max, "follow_reaction_min")?;
        check_range(self.glance_max, 0.0, 600.0, "follow_glance_max")?;
        check_range(self.glance_min, 0.0, self.glance_max, "follow_glance_min")?;
        check_range(self.forget_time, 0.0, 3600.0, "follow_forget_time")?;
        if self.enabled && self.distance > max_distance {
            return Err(Error::InvalidArgument(format!(
                "follow_distance ({} m) is beyond max_distance ({max_distance} m), the \
                 farthest anyone is seen: lower follow_distance or raise max_distance",
                self.distance
            )));
        }
        Ok(())
    }
}

/// The smallest side of the cells lookers are sorted into (metres), for a follow distance
/// of 0.
pub const CUE_CELL_MIN: f32 = 0.5;

/// A character that shows others a gaze worth following this step: it stares or glances
/// at a point ([`FollowConfig`]). The crowd keeps them sorted by [`Cue::cell`], so that a
/// character finds the lookers near it without visiting every neighbour.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Cue {
    /// The ground cell it stands in ([`Cue::cell_of`]).
    pub cell: u64,
    /// Its entity id.
    pub id: u32,
    /// Its ground position (the crowd's ground coordinates, metres).
    pub ground: Vec2,
    /// Its ground velocity (m/s).
    pub velocity: Vec2,
    /// The point looked at (world, metres).
    pub point: Vec3,
    /// How much it counts as a looker: 1 for a stare, the glance weight for a follower.
    pub weight: f32,
}

impl Cue {
    /// The key of the ground cell of side `cell_size` holding `ground`: rows (the second
    /// coordinate) in the high half, columns in the low half, both offset to be positive,
    /// so that the three cells of a row side by side have consecutive keys.
    pub fn cell_of(ground: Vec2, cell_size: f32) -> u64 {
        let (column, row) = Self::coordinates(ground, cell_size);
        Self::key(column, row)
    }

    /// The key of cell (`column`, `row`).
    pub fn key(column: i64, row: i64) -> u64 {
        let offset = |value: i64| (value + (1 << 31)).clamp(0, (1 << 32) - 1) as u64;
        offset(row) << 32 | offset(column)
    }

    /// The cell (`column`, `row`) holding `ground` for cells of side `cell_size`.
    pub fn coordinates(ground: Vec2, cell_size: f32) -> (i64, i64) {
        let cell = |value: f32| (value / cell_size).floor().clamp(-1e9, 1e9) as i64;
        (cell(ground.x), cell(ground.y))
    }
}

/// The runs of the cell-sorted cues around one cell — its row and the rows beside it,
/// three cells wide each — kept for the next character: attention visits characters in
/// spatial order, so the next one is most often in the same cell.
#[derive(Debug, Clone, Default)]
pub struct CueRuns {
    /// The cell (column, row) the runs are for.
    cell: Option<(i64, i64)>,
    /// Cue index ranges, one per row.
    runs: [std::ops::Range<usize>; 3],
}

impl CueRuns {
    /// The runs of `cues` (sorted by cell) around `cell`.
    pub fn around(&mut self, cell: (i64, i64), cues: &[Cue]) -> [std::ops::Range<usize>; 3] {
        if self.cell != Some(cell) {
            let (column, row) = cell;
            self.runs = [row - 1, row, row + 1].map(|row| {
                let (first, last) = (Cue::key(column - 1, row), Cue::key(column + 1, row));
                let start = cues.partition_point(|cue| cue.cell < first);
                let end = start + cues[start..].partition_point(|cue| cue.cell <= last);
                start..end
            });
            self.cell = Some(cell);
        }
        self.runs.clone()
    }
}

/// A character's gaze following: the point it glances at now, if any, and what it has
/// decided in the current encounter.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct FollowState {
    /// The point followed now (world, metres), while `remaining > 0`.
    pub point: Vec3,
    /// Seconds until the decided glance starts (0: none waiting).
    pub delay: f32,
    /// Seconds left of the current glance (0: not following).
    pub remaining: f32,
    /// The lookers' weight already decided on in this encounter.
    pub decided: f32,
    /// Seconds since the last time a looker was in view.
    pub unseen: f32,
    /// Glances started so far.
    pub glances: u32,
}

impl FollowState {
    /// The point followed now, if the character follows someone's gaze.
    pub fn following(&self) -> Option<Vec3> {
        (self.remaining > 0.0 && self.delay <= 0.0).then_some(self.point)
    }

    /// Advances by `dt` seconds, with lookers of total weight `lookers` in view now, the
    /// nearest looking at `point`. More lookers than already decided on draw again, with
    /// the chance that makes the whole encounter's probability `P(lookers)`.
    pub fn update(
        &mut self,
        dt: f32,
        lookers: f32,
        point: Vec3,
        config: &FollowConfig,
        random: &mut Random,
    ) {
        if self.delay > 0.0 {
            // Turning towards the point: the glance starts when the delay runs out.
            self.delay = (self.delay - dt).max(0.0);
        } else if self.remaining > 0.0 {
            self.remaining = (self.remaining - dt).max(0.0);
        }
        if lookers <= 0.0 {
            self.unseen += dt;
            if self.unseen > config.forget_time {
                self.decided = 0.0;
                self.unseen = config.forget_time;
            }
            return;
        }
        self.unseen = 0.0;
        if self.remaining > 0.0 || lookers <= self.decided {
            return;
        }
        let before = config.probability(self.decided);
        let now = config.probability(lookers);
        self.decided = lookers;
        let chance = if before < 1.0 {
            (now - before) / (1.0 - before)
        } else {
            0.0
        };
        if random.next_f32() < chance {
            self.point = point;
            self.delay = random.range(config.reaction_min, config.reaction_max);
            self.remaining = random.range(config.glance_min, config.glance_max);
            self.glances += 1;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_milgram_curve_rises_and_saturates() {
        let config = FollowConfig::MILGRAM;
        let curve: Vec<f32> = [1.0, 2.0, 3.0, 5.0, 10.0, 15.0]
            .iter()
            .map(|&k| config.probability(k))
            .collect();
        assert!((curve[0] - 0.42).abs() < 1e-6);
        assert!((curve[5] - 0.86).abs() < 0.02, "{curve:?}");
        assert!(curve.windows(2).all(|pair| pair[1] >= pair[0]));
        // Saturating: each step adds less per looker.
        assert!(curve[5] - curve[4] < 0.01 && curve[1] - curve[0] > 0.15);
        let gallup = FollowConfig::GALLUP;
        assert!(gallup.probability(15.0) < 0.31 && gallup.probability(1.0) > 0.1);
        assert_eq!(config.probability(0.0), 0.0);
    }

    #[test]
    fn an_encounter_follows_with_the_probability_of_its_most_lookers() {
        let config = FollowConfig::MILGRAM;
        let mut random = Random::new(4);
        let trials = 20_000;
        let mut followed = 0;
        for _ in 0..trials {
            let mut state = FollowState::default();
            // Lookers come into view one by one: 1, 2, 3 — decided as if 3 at once.
            for lookers in [1.0, 1.0, 2.0, 3.0, 3.0, 2.0] {
                state.update(0.1, lookers, Vec3::Y, &config, &mut random);
            }
            followed += u32::from(state.glances > 0);
        }
        let share = followed as f32 / trials as f32;
        let expected = config.probability(3.0);
        // A glance under way when the third looker appears defers that draw; the glance
        // lasts 1–2.5 s, longer than this encounter, so the share is slightly below.
        assert!((share - expected).abs() < 0.04, "{share} vs {expected}");
    }

    #[test]
    fn glances_end_and_encounters_are_forgotten() {
        let config = FollowConfig {
            one_looker_probability: 1.0,
            max_probability: 1.0,
            ..FollowConfig::MILGRAM
        };
        let mut random = Random::new(1);
        let mut state = FollowState::default();
        state.update(0.1, 1.0, Vec3::new(0.0, 9.0, 0.0), &config, &mut random);
        assert_eq!(
            state.following(),
            None,
            "the glance starts after a reaction time"
        );
        for _ in 0..10 {
            state.update(0.1, 1.0, Vec3::ZERO, &config, &mut random);
        }
        assert_eq!(state.following(), Some(Vec3::new(0.0, 9.0, 0.0)));
        for _ in 0..30 {
            state.update(0.1, 1.0, Vec3::ZERO, &config, &mut random);
        }
        assert_eq!(state.following(), None, "the glance lasts at most 2.5 s");
        assert_eq!(state.glances, 1, "the same lookers draw once");
        for _ in 0..110 {
            state.update(0.1, 0.0, Vec3::ZERO, &config, &mut random);
        }
        state.update(0.1, 1.0, Vec3::ZERO, &config, &mut random);
        assert_eq!(state.glances, 2, "a new encounter after forget_time");
    }

    #[test]
    fn bad_settings_are_refused_by_name() {
        let too_far = FollowConfig {
            enabled: true,
            distance: 12.0,
            ..FollowConfig::MILGRAM
        };
        let message = too_far.validate(10.0).unwrap_err().to_string();
        assert!(message.contains("follow_distance"), "{message}");
        let inverted = FollowConfig {
            one_looker_probability: 0.9,
            ..FollowConfig::MILGRAM
        };
        assert!(inverted.validate(10.0).is_err());
        let nan = FollowConfig {
            glance_min: f32::NAN,
            ..FollowConfig::MILGRAM
        };
        let message = nan.validate(10.0).unwrap_err().to_string();
        assert!(message.contains("follow_glance_min"), "{message}");
        assert!(FollowConfig::MILGRAM.validate(10.0).is_ok());
        assert!(FollowConfig::GALLUP.validate(10.0).is_ok());
    }
}
