//! Online interest points: which entity a character attends to, frame by frame.
//!
//! The rules (Grillon & Thalmann 2009, "Automatic Interest Point Detection"):
//! - the threshold `A` is the `(100 − a)`th percentile of the character's `S_max(t)`,
//!   read from a streaming [`ScoreHistogram`] of `S_max / S_MAX`; during a warm-up (default
//!   1 s of history) a configured initial threshold is used instead;
//! - online, the confirmation delay below and the `d_l` cool-downs cut into the time spent
//!   above `A`, so a character would attend less than `a`% of the time. The tracker
//!   measures the ratio `ρ` = (time attending) / (time with `S_max ≥ A`) and reads the
//!   percentile at level `a / ρ` instead of `a`, so that it attends `a`% of the time as the
//!   paper intends. (Offline planning needs no such correction.)
//! - an entity becomes the interest point (IP) once it has held `S_max ≥ A` for at least
//!   `min_hold` (1/3 s) — online this is necessarily a reaction delay of `min_hold`;
//! - the IP ends when it stops holding `S_max ≥ A`; if another entity has taken over, the
//!   IP stays until that entity qualifies and then hands over directly (IP → IP, no rest);
//! - an IP held longer than `d_l` (`max_hold`, 4 s) is dropped, put on a cool-down during
//!   which it is not scored, and the next-best entity takes over at once if it is above `A`.

use super::quantile::ScoreHistogram;
use crate::scene::ids::NO_ENTITY;

/// Timing and threshold settings of interest-point selection.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct InterestConfig {
    /// Least time (s) an entity must hold `S_max ≥ A` to become the IP. Default 1/3 s.
    pub min_hold: f32,
    /// `d_l`: longest time (s) an IP is kept before the next-best takes over. Default 4 s.
    pub max_hold: f32,
    /// How long (s) an IP dropped after `d_l` is not picked again. Default 2 s.
    pub cooldown: f32,
    /// Seconds of `S_max` history before the streaming percentile is trusted. Default 1 s.
    pub warmup: f32,
    /// The threshold used during the warm-up. Default 0.35.
    pub initial_threshold: f32,
}

impl Default for InterestConfig {
    fn default() -> Self {
        InterestConfig {
            min_hold: 1.0 / 3.0,
            max_hold: 4.0,
            cooldown: 2.0,
            warmup: 1.0,
            initial_threshold: 0.35,
        }
    }
}

/// An entity and its score this frame (`NO_ENTITY` and 0 for none).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Candidate {
    /// Entity id.
    pub id: u32,
    /// Its score `S`.
    pub score: f32,
}

impl Candidate {
    /// No entity.
    pub const NONE: Candidate = Candidate {
        id: NO_ENTITY,
        score: 0.0,
    };
}

/// Most entities on cool-down at once per character; a new one replaces the oldest.
pub const MAX_COOLDOWNS: usize = 4;

/// A character's interest-point state: plain data, fixed size (212 bytes, checked by a
/// test).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct InterestTracker {
    histogram: ScoreHistogram,
    /// Seconds with `S_max ≥ A` after the warm-up (for the correction `ρ`).
    above_time: f32,
    /// Seconds attending after the warm-up (for the correction `ρ`).
    attending_time: f32,
    candidate: u32,
    candidate_time: f32,
    interest: u32,
    interest_time: f32,
    cooldown_ids: [u32; MAX_COOLDOWNS],
    cooldown_left: [f32; MAX_COOLDOWNS],
    threshold: f32,
    s_max: f32,
    attentive_time: f32,
    /// Seconds observed (updates since creation): also the length of the `S_max` history,
    /// for the warm-up.
    observed_time: f32,
    interest_count: u32,
}

impl InterestTracker {
    /// A tracker for a character (whose attention fraction `a`/100 each
    /// [`update`](Self::update) takes).
    pub fn new(config: &InterestConfig) -> InterestTracker {
        InterestTracker {
            histogram: ScoreHistogram::default(),
            above_time: 0.0,
            attending_time: 0.0,
            candidate: NO_ENTITY,
            candidate_time: 0.0,
            interest: NO_ENTITY,
            interest_time: 0.0,
            cooldown_ids: [NO_ENTITY; MAX_COOLDOWNS],
            cooldown_left: [0.0; MAX_COOLDOWNS],
            threshold: config.initial_threshold,
            s_max: 0.0,
            attentive_time: 0.0,
            observed_time: 0.0,
            interest_count: 0,
        }
    }

    /// For a changed attention fraction: restarts the delay correction (the score history
    /// is kept: it does not depend on the fraction).
    pub fn restart_delay_correction(&mut self) {
        self.above_time = 0.0;
        self.attending_time = 0.0;
    }

    /// The current IP's id, or `NO_ENTITY`.
    pub fn interest(&self) -> u32 {
        self.interest
    }

    /// How long (s) the current IP has been held.
    pub fn interest_time(&self) -> f32 {
        self.interest_time
    }

    /// The threshold `A` used in the last update.
    pub fn threshold(&self) -> f32 {
        self.threshold
    }

    /// `S_max` of the last update.
    pub fn s_max(&self) -> f32 {
        self.s_max
    }

    /// Seconds spent with an IP, and seconds observed, since creation.
    pub fn attentive_seconds(&self) -> (f32, f32) {
        (self.attentive_time, self.observed_time)
    }

    /// Number of IPs started since creation.
    pub fn interest_count(&self) -> u32 {
        self.interest_count
    }

    /// True if `id` is on cool-down and must not be scored.
    #[inline]
    pub fn is_cooling(&self, id: u32) -> bool {
        self.cooldown_ids.contains(&id)
    }

    /// Forgets `id` wherever it appears (the entity was removed).
    pub fn forget(&mut self, id: u32) {
        if self.interest == id {
            self.interest = NO_ENTITY;
            self.interest_time = 0.0;
        }
        if self.candidate == id {
            self.candidate = NO_ENTITY;
            self.candidate_time = 0.0;
        }
        for slot in 0..MAX_COOLDOWNS {
            if self.cooldown_ids[slot] == id {
                self.cooldown_ids[slot] = NO_ENTITY;
            }
        }
    }

    fn start_cooldown(&mut self, id: u32, duration: f32) {
        let slot = (0..MAX_COOLDOWNS)
            .min_by(|&a, &b| self.cooldown_left[a].total_cmp(&self.cooldown_left[b]))
            .unwrap_or(0);
        self.cooldown_ids[slot] = id;
        self.cooldown_left[slot] = duration;
    }

    fn tick_cooldowns(&mut self, dt: f32) {
        for slot in 0..MAX_COOLDOWNS {
            if self.cooldown_ids[slot] != NO_ENTITY {
                self.cooldown_left[slot] -= dt;
                if self.cooldown_left[slot] <= 0.0 {
                    self.cooldown_ids[slot] = NO_ENTITY;
                }
            }
        }
    }

    /// `ρ`: the share of the time above the threshold actually spent attending (1 until
    /// measured; a prior of one second on both sides keeps it stable early on).
    pub fn attending_ratio(&self) -> f32 {
        ((self.attending_time + 1.0) / (self.above_time + 1.0)).clamp(0.25, 1.0)
    }

    /// The threshold for the next decision: the `(1 − a/ρ)` quantile once warm, else the
    /// initial one. `max_score` is `S_MAX`, the largest possible score; `attention_fraction`
    /// is `a`/100.
    fn current_threshold(
        &mut self,
        config: &InterestConfig,
        max_score: f32,
        attention_fraction: f32,
    ) -> f32 {
        if attention_fraction <= 0.0 {
            return f32::INFINITY;
        }
        if attention_fraction >= 1.0 {
            return 0.0;
        }
        if self.observed_time < config.warmup {
            return config.initial_threshold;
        }
        let level = (attention_fraction / self.attending_ratio()).min(0.98);
        self.histogram
            .quantile_near(1.0 - level)
            .map_or(config.initial_threshold, |q| q * max_score)
    }

    /// Advances by `dt` seconds given this frame's best and second-best entities (both
    /// excluding entities on cool-down), `S_MAX` (`max_score`, the largest possible
    /// score: the largest impact factor) and the character's attention fraction `a`/100.
    /// Returns true if the IP changed.
    pub fn update(
        &mut self,
        best: Candidate,
        second: Candidate,
        max_score: f32,
        attention_fraction: f32,
        dt: f32,
        config: &InterestConfig,
    ) -> bool {
        let before = self.interest;
        self.tick_cooldowns(dt);
        if max_score > 0.0 {
            self.histogram.push(best.score / max_score);
        }
        let warm = self.observed_time >= config.warmup;
        self.observed_time += dt;
        self.threshold = self.current_threshold(config, max_score, attention_fraction);
        self.s_max = best.score;
        let qualifies = |c: Candidate, threshold: f32| {
            c.id != NO_ENTITY && c.score > 0.0 && c.score >= threshold
        };

        // The run of the entity holding S_max above the threshold.
        if qualifies(best, self.threshold) {
            if best.id == self.candidate {
                self.candidate_time += dt;
            } else {
                self.candidate = best.id;
                self.candidate_time = dt;
            }
        } else {
            self.candidate = NO_ENTITY;
            self.candidate_time = 0.0;
        }

        if self.interest != NO_ENTITY {
            self.interest_time += dt;
            if self.interest_time > config.max_hold {
                // d_l reached: drop, cool down, hand over to the next-best at once.
                let dropped = self.interest;
                self.start_cooldown(dropped, config.cooldown);
                let next = if best.id == dropped { second } else { best };
                self.interest = NO_ENTITY;
                self.interest_time = 0.0;
                if qualifies(next, self.threshold) {
                    self.interest = next.id;
                    self.candidate = next.id;
                    self.candidate_time = self.candidate_time.max(config.min_hold);
                } else {
                    self.candidate = NO_ENTITY;
                    self.candidate_time = 0.0;
                }
            } else if self.candidate == NO_ENTITY {
                // Nobody holds S_max above A: the IP ends.
                self.interest = NO_ENTITY;
                self.interest_time = 0.0;
            }
        }
        if self.candidate != NO_ENTITY
            && self.candidate != self.interest
            && self.candidate_time >= config.min_hold - 1e-6
        {
            self.interest = self.candidate;
            self.interest_time = 0.0;
        }

        if self.interest != NO_ENTITY {
            self.attentive_time += dt;
        }
        if warm {
            if qualifies(best, self.threshold) {
                self.above_time += dt;
            }
            if self.interest != NO_ENTITY {
                self.attending_time += dt;
            }
        }
        let changed = self.interest != before;
        if changed && self.interest != NO_ENTITY {
            self.interest_count += 1;
        }
        changed
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const DT: f32 = 1.0 / 30.0;

    /// The attention fraction of the trackers below but one.
    const HALF: f32 = 0.5;

    fn tracker(config: &InterestConfig) -> InterestTracker {
        InterestTracker::new(config)
    }

    fn c(id: u32, score: f32) -> Candidate {
        Candidate { id, score }
    }

    #[test]
    fn tracker_state_is_small() {
        // Part of a character's state (Crowd::state_bytes_per_character): the 140-byte
        // histogram (128 of counts, its total and its quantile cursor) and 19 four-byte
        // fields.
        assert_eq!(std::mem::size_of::<ScoreHistogram>(), 140);
        assert_eq!(std::mem::size_of::<InterestTracker>(), 216);
    }

    #[test]
    fn an_entity_must_hold_the_best_score_for_a_third_of_a_second() {
        let config = InterestConfig {
            warmup: 1e9,
            initial_threshold: 0.3,
            ..InterestConfig::default()
        };
        let mut t = tracker(&config);
        for frame in 0..9 {
            t.update(c(7, 0.5), Candidate::NONE, 1.0, HALF, DT, &config);
            assert_eq!(t.interest(), NO_ENTITY, "frame {frame}");
        }
        t.update(c(7, 0.5), Candidate::NONE, 1.0, HALF, DT, &config);
        assert_eq!(t.interest(), 7);
        // Below the threshold: the IP ends at once.
        t.update(c(7, 0.2), Candidate::NONE, 1.0, HALF, DT, &config);
        assert_eq!(t.interest(), NO_ENTITY);
    }

    #[test]
    fn a_new_best_takes_over_after_it_qualifies_without_a_gap() {
        let config = InterestConfig {
            warmup: 1e9,
            initial_threshold: 0.3,
            ..InterestConfig::default()
        };
        let mut t = tracker(&config);
        for _ in 0..12 {
            t.update(c(1, 0.5), Candidate::NONE, 1.0, HALF, DT, &config);
        }
        assert_eq!(t.interest(), 1);
        for _ in 0..9 {
            t.update(c(2, 0.6), c(1, 0.5), 1.0, HALF, DT, &config);
            assert_eq!(t.interest(), 1);
        }
        t.update(c(2, 0.6), c(1, 0.5), 1.0, HALF, DT, &config);
        assert_eq!(t.interest(), 2);
        assert_eq!(t.interest_count(), 2);
    }

    #[test]
    fn max_hold_drops_cools_down_and_hands_over() {
        let config = InterestConfig {
            warmup: 1e9,
            initial_threshold: 0.3,
            ..InterestConfig::default()
        };
        let mut t = tracker(&config);
        let mut held = 0.0;
        while t.interest() != 2 {
            t.update(c(1, 0.9), c(2, 0.5), 1.0, HALF, DT, &config);
            if t.interest() == 1 {
                held += DT;
            }
            assert!(held <= config.max_hold + DT);
        }
        assert!(t.is_cooling(1));
        // While entity 1 cools down the caller does not score it: 2 is the best.
        for _ in 0..30 {
            t.update(c(2, 0.5), Candidate::NONE, 1.0, HALF, DT, &config);
            assert_eq!(t.interest(), 2);
        }
        for _ in 0..40 {
            t.update(c(2, 0.5), Candidate::NONE, 1.0, HALF, DT, &config);
        }
        assert!(!t.is_cooling(1));
    }

    #[test]
    fn threshold_follows_the_percentile_after_warmup() {
        let config = InterestConfig::default();
        let mut t = InterestTracker::new(&config);
        for i in 0..600 {
            let score = (i % 100) as f32 / 100.0;
            t.update(c(3, score), Candidate::NONE, 1.0, 0.25, DT, &config);
        }
        // Close to the 75th percentile of a uniform ramp over [0, 0.99] (the level is
        // corrected by ρ, which stays near 1 here as the runs are long).
        assert!(t.attending_ratio() > 0.8, "{}", t.attending_ratio());
        assert!((0.6..0.8).contains(&t.threshold()), "{}", t.threshold());
        let mut never = InterestTracker::new(&config);
        assert_eq!(never.current_threshold(&config, 1.0, 0.0), f32::INFINITY);
    }
}
