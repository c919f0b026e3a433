//! The street model: where walkers measured with eye trackers look. Each walker that comes
//! into view is fixated once with a set probability, after a latency, for about half a
//! second, and perhaps a second time; strangers within a few metres are looked at less
//! (civil inattention), and the rest of the time the eyes are on the path a few steps
//! ahead. Every constant comes from field measurements: docs/street.md lists them with
//! their sources and crowdgaze's measured figures beside them.

use crate::error::{check_at_least, check_range, Result};
use crate::math::random::Random;
use crate::scene::ids::NO_ENTITY;

/// How many walkers in view a character keeps track of (the nearest; farther ones wait
/// until one of these leaves the view).
pub const STREET_MEMORY: usize = 10;

/// Settings of the street model. Distances are metres, durations seconds, angles radians.
/// The defaults are the field figures: see docs/street.md.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StreetConfig {
    /// Half-angle of the part of the view in which walkers are noticed, about the walking
    /// direction. Default 60° (approaching walkers are in the central field).
    pub view_half_angle: f32,
    /// Probability that a first fixation is planned for a walker coming into view.
    /// Default 0.95: with the fixations missed while the eyes are busy
    /// (`miss_after`), walkers on real trajectories are fixated at least once 73–86 % of
    /// the time, as measured (Jovancevic et al. 2004: 73 %; Fotios, Uttley & Yang 2015:
    /// 86 %).
    pub first_fixation_probability: f32,
    /// Shortest latency from coming into view to the first fixation. Default 0.55 s
    /// (Jovancevic et al. 2004: 548 ms for a pedestrian on a collision course).
    pub latency_min: f32,
    /// Longest latency. Default 0.75 s (Jovancevic et al. 2004: 740 ms for others).
    pub latency_max: f32,
    /// Median duration of a fixation on a walker. Default 0.5 s (Fotios et al. 2018).
    pub fixation_median: f32,
    /// Spread of fixation durations: the standard deviation of their natural logarithm.
    /// Default 0.35 (most fixations between 0.3 and 0.9 s).
    pub fixation_log_spread: f32,
    /// A fixation that falls due while the eyes are on someone else and has waited this
    /// long is missed: attention is limited (Jovancevic et al. 2004: 41 % of pedestrians
    /// veering onto a collision course for about a second were not fixated). Default 0.5 s.
    pub miss_after: f32,
    /// Probability that a fixated walker is fixated a second time. Default 0.3
    /// (Jovancevic et al. 2004).
    pub refixation_probability: f32,
    /// Shortest wait between the end of a fixation and a second one. Default 0.5 s.
    pub refixation_gap_min: f32,
    /// Longest wait. Default 2 s.
    pub refixation_gap_max: f32,
    /// Strangers closer than this are looked at less, and the eyes go down the path while
    /// one is there (civil inattention: Goffman 1963; Hessels et al. 2022). Default 3 m.
    pub civil_distance: f32,
    /// Probability that a fixation due on a walker closer than `civil_distance` still
    /// happens. Default 0.25.
    pub civil_look_probability: f32,
    /// How far ahead on the ground the eyes rest when no walker is fixated: a few steps.
    /// Default 4 m.
    pub path_look_distance: f32,
    /// How far ahead on the ground the eyes go while a stranger is close. Default 2 m.
    pub civil_look_distance: f32,
}

impl Default for StreetConfig {
    fn default() -> Self {
        StreetConfig {
            view_half_angle: 60f32.to_radians(),
            first_fixation_probability: 0.95,
            latency_min: 0.55,
            latency_max: 0.75,
            fixation_median: 0.5,
            fixation_log_spread: 0.35,
            miss_after: 1.0,
            refixation_probability: 0.3,
            refixation_gap_min: 0.5,
            refixation_gap_max: 2.0,
            civil_distance: 3.0,
            civil_look_probability: 0.25,
            path_look_distance: 4.0,
            civil_look_distance: 2.0,
        }
    }
}

impl StreetConfig {
    /// Checks every setting; errors name the setting and its value.
    pub fn validate(&self) -> Result<()> {
        use std::f32::consts::PI;
        check_range(self.view_half_angle, 0.0, PI, "street_view_half_angle")?;
        check_range(
            self.first_fixation_probability,
            0.0,
            1.0,
            "street_first_fixation_probability",
        )?;
        check_at_least(self.latency_min, 0.0, "street_latency_min")?;
        check_range(self.latency_max, 0.0, 60.0, "street_latency_max")?;
        check_range(
            self.latency_min,
            0.0,
            self.latency_max,
            "street_latency_min",
        )?;
        let median = self.fixation_median;
        check_range(median, f32::MIN_POSITIVE, 60.0, "street_fixation_median")?;
        let spread = self.fixation_log_spread;
        check_range(spread, 0.0, 2.0, "street_fixation_log_spread")?;
        check_range(self.miss_after, 0.0, 60.0, "street_miss_after")?;
        let refixation = self.refixation_probability;
        check_range(refixation, 0.0, 1.0, "street_refixation_probability")?;
        let gap_max = self.refixation_gap_max;
        check_range(gap_max, 0.0, 600.0, "street_refixation_gap_max")?;
        let gap_min = self.refixation_gap_min;
        check_at_least(gap_min, 0.0, "street_refixation_gap_min")?;
        check_range(gap_min, 0.0, gap_max, "street_refixation_gap_min")?;
        check_range(self.civil_distance, 0.0, 1000.0, "street_civil_distance")?;
        let civil = self.civil_look_probability;
        check_range(civil, 0.0, 1.0, "street_civil_look_probability")?;
        let path = self.path_look_distance;
        check_range(path, 0.0, 1000.0, "street_path_look_distance")?;
        let civil_look = self.civil_look_distance;
        check_range(civil_look, 0.0, 1000.0, "street_civil_look_distance")
    }

    /// A fixation duration: log-normal about the median, kept within a factor of 4 of it.
    fn fixation_duration(&self, random: &mut Random) -> f32 {
        // Sum of four uniforms, centred and scaled: close to a standard normal, bounded.
        let normal =
            (random.next_f32() + random.next_f32() + random.next_f32() + random.next_f32() - 2.0)
                * 3f32.sqrt();
        let factor = (normal * self.fixation_log_spread).exp().clamp(0.25, 4.0);
        self.fixation_median * factor
    }
}

/// A walker the character noticed this update: in view and within the view distance.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Noticed {
    /// Its entity id.
    pub entity: u32,
    /// Its ground distance from the character (metres).
    pub distance: f32,
}

/// Seconds until a walker's next fixation; `NEVER` when none is planned.
const NEVER: f32 = f32::INFINITY;

/// One walker the character keeps track of.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Tracked {
    /// Its entity id, or `NO_ENTITY` for a free slot.
    entity: u32,
    /// Seconds until its next fixation is due (≤ 0: due), or `NEVER`.
    wait: f32,
    /// Its ground distance at the last update (metres).
    distance: f32,
    /// Fixations on it so far.
    fixations: u8,
    /// Seen in the current update.
    seen: bool,
    /// Seconds since it was last seen (it is forgotten after [`FORGET_TIME`]).
    unseen: f32,
}

impl Tracked {
    const FREE: Tracked = Tracked {
        entity: NO_ENTITY,
        wait: NEVER,
        distance: 0.0,
        fixations: 0,
        seen: false,
        unseen: 0.0,
    };
}

/// A walker out of view this long is forgotten: one coming back later is a new encounter,
/// one back sooner (a turn of the head, someone passing between) is the same.
const FORGET_TIME: f32 = 1.0;

/// A street character's state: the walkers in view it keeps track of, and its current
/// fixation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StreetState {
    tracked: [Tracked; STREET_MEMORY],
    /// The walker fixated now, or `NO_ENTITY`.
    fixated: u32,
    /// Seconds left of the current fixation.
    remaining: f32,
    /// True while a stranger is closer than the civil distance.
    civil: bool,
    /// Fixations started so far.
    fixations: u32,
}

impl Default for StreetState {
    fn default() -> Self {
        StreetState {
            tracked: [Tracked::FREE; STREET_MEMORY],
            fixated: NO_ENTITY,
            remaining: 0.0,
            civil: false,
            fixations: 0,
        }
    }
}

impl StreetState {
    /// The walker fixated now, or `NO_ENTITY` (the eyes are on the path).
    pub fn fixated(&self) -> u32 {
        self.fixated
    }

    /// True while a stranger is closer than the civil distance and not fixated: the eyes
    /// go down the path ([`StreetConfig::civil_look_distance`]).
    pub fn is_civil(&self) -> bool {
        self.civil && self.fixated == NO_ENTITY
    }

    /// Fixations started so far.
    pub fn fixation_count(&self) -> u32 {
        self.fixations
    }

    /// Advances by `dt` seconds. `noticed` lists the walkers in view within the view
    /// distance, nearest first (ties by id); at most [`STREET_MEMORY`] of them are read.
    pub fn update(
        &mut self,
        dt: f32,
        noticed: &[Noticed],
        config: &StreetConfig,
        random: &mut Random,
    ) {
        for tracked in &mut self.tracked {
            tracked.seen = false;
        }
        let noticed = &noticed[..noticed.len().min(STREET_MEMORY)];
        let mut civil = false;
        for walker in noticed {
            civil |= walker.distance < config.civil_distance;
            if let Some(tracked) = self.tracked.iter_mut().find(|t| t.entity == walker.entity) {
                tracked.seen = true;
                tracked.unseen = 0.0;
                tracked.distance = walker.distance;
            }
        }
        // Walkers out of view long enough are forgotten (one coming back is a new
        // encounter).
        for tracked in &mut self.tracked {
            if tracked.entity != NO_ENTITY && !tracked.seen {
                tracked.unseen += dt;
                if tracked.unseen > FORGET_TIME {
                    *tracked = Tracked::FREE;
                }
            }
        }
        // Walkers coming into view, each in a free slot, else in place of the one unseen
        // longest (at most STREET_MEMORY are seen at once).
        for walker in noticed {
            if self.tracked.iter().any(|t| t.entity == walker.entity) {
                continue;
            }
            let free = self.tracked.iter().position(|t| t.entity == NO_ENTITY);
            let slot = free.or_else(|| {
                self.tracked
                    .iter()
                    .enumerate()
                    .filter(|(_, t)| !t.seen)
                    .max_by(|(_, a), (_, b)| {
                        a.unseen.total_cmp(&b.unseen).then(b.entity.cmp(&a.entity))
                    })
                    .map(|(slot, _)| slot)
            });
            let Some(slot) = slot else {
                break;
            };
            let wait = if random.next_f32() < config.first_fixation_probability {
                random.range(config.latency_min, config.latency_max)
            } else {
                NEVER
            };
            self.tracked[slot] = Tracked {
                entity: walker.entity,
                wait,
                distance: walker.distance,
                fixations: 0,
                seen: true,
                unseen: 0.0,
            };
        }
        self.civil = civil;

        if self.fixated != NO_ENTITY {
            self.remaining -= dt;
            let still_seen = self
                .tracked
                .iter()
                .any(|t| t.entity == self.fixated && t.seen);
            if self.remaining <= 0.0 || !still_seen {
                self.end_fixation(config, random);
            }
        }
        for tracked in &mut self.tracked {
            if tracked.entity != NO_ENTITY && tracked.wait != NEVER {
                tracked.wait -= dt;
            }
        }
        if self.fixated == NO_ENTITY {
            self.start_due_fixation(config, random);
        }
    }

    /// Ends the current fixation; the walker may be planned for a second one.
    fn end_fixation(&mut self, config: &StreetConfig, random: &mut Random) {
        let fixated = std::mem::replace(&mut self.fixated, NO_ENTITY);
        self.remaining = 0.0;
        if let Some(tracked) = self.tracked.iter_mut().find(|t| t.entity == fixated) {
            tracked.wait =
                if tracked.fixations == 1 && random.next_f32() < config.refixation_probability {
                    random.range(config.refixation_gap_min, config.refixation_gap_max)
                } else {
                    NEVER
                };
        }
    }

    /// Starts the fixation due longest (ties: the nearest, then the lowest id); one due on
    /// a walker within the civil distance happens only with the civil probability.
    fn start_due_fixation(&mut self, config: &StreetConfig, random: &mut Random) {
        loop {
            let due = self
                .tracked
                .iter()
                .enumerate()
                .filter(|(_, t)| t.seen && t.wait <= 0.0)
                .min_by(|(_, a), (_, b)| {
                    a.wait
                        .total_cmp(&b.wait)
                        .then(a.distance.total_cmp(&b.distance))
                        .then(a.entity.cmp(&b.entity))
                })
                .map(|(slot, _)| slot);
            let Some(slot) = due else {
                return;
            };
            let tracked = &mut self.tracked[slot];
            if -tracked.wait > config.miss_after {
                // Due too long ago, while the eyes were busy: missed.
                tracked.wait = NEVER;
                continue;
            }
            if tracked.distance < config.civil_distance
                && random.next_f32() >= config.civil_look_probability
            {
                // Looked away from, as strangers do when they are close.
                tracked.wait = NEVER;
                continue;
            }
            tracked.fixations = tracked.fixations.saturating_add(1);
            tracked.wait = NEVER;
            self.fixated = tracked.entity;
            self.remaining = config.fixation_duration(random);
            self.fixations += 1;
            return;
        }
    }

    /// Drops every reference to a removed entity.
    pub fn forget(&mut self, id: u32) {
        if self.fixated == id {
            self.fixated = NO_ENTITY;
            self.remaining = 0.0;
        }
        for tracked in &mut self.tracked {
            if tracked.entity == id {
                *tracked = Tracked::FREE;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const DT: f32 = 1.0 / 30.0;

    /// Runs `walkers` encounters of one walker each: it comes into view at 17 m and
    /// approaches at 2.6 m/s until it passes. Returns (fixated at least once, fixated
    /// twice, first-fixation latencies, durations, distances at fixation start).
    fn encounters(walkers: u32, config: &StreetConfig) -> (u32, u32, Vec<f32>, Vec<f32>, Vec<f32>) {
        let mut random = Random::new(3);
        let (mut once, mut twice) = (0, 0);
        let (mut latencies, mut durations, mut distances) = (vec![], vec![], vec![]);
        for walker in 0..walkers {
            let mut state = StreetState::default();
            let mut distance = 17.0f32;
            let mut time = 0.0;
            let mut fixations = 0;
            let mut fixation_start = None;
            while distance > 0.5 {
                state.update(
                    DT,
                    &[Noticed {
                        entity: walker,
                        distance,
                    }],
                    config,
                    &mut random,
                );
                time += DT;
                match (state.fixated() == walker, fixation_start) {
                    (true, None) => {
                        fixations += 1;
                        if fixations == 1 {
                            latencies.push(time);
                        }
                        distances.push(distance);
                        fixation_start = Some(time);
                    }
                    (false, Some(start)) => {
                        durations.push(time - start);
                        fixation_start = None;
                    }
                    _ => {}
                }
                distance -= 2.6 * DT;
            }
            once += u32::from(fixations >= 1);
            twice += u32::from(fixations >= 2);
        }
        (once, twice, latencies, durations, distances)
    }

    fn median(values: &mut [f32]) -> f32 {
        values.sort_by(f32::total_cmp);
        values[values.len() / 2]
    }

    #[test]
    fn an_approaching_walker_is_fixated_as_in_the_field() {
        let config = StreetConfig::default();
        let (once, twice, mut latencies, mut durations, mut distances) = encounters(2000, &config);
        // Alone in view, every planned first fixation happens (with others, some are
        // missed: tests/street.rs measures that on real trajectories).
        let share = once as f32 / 2000.0;
        assert!((0.93..0.97).contains(&share), "{share}");
        let second = twice as f32 / once as f32;
        assert!((0.22..0.34).contains(&second), "{second}");
        let latency = median(&mut latencies);
        assert!((0.6..0.7).contains(&latency), "{latency}");
        let duration = median(&mut durations);
        assert!((0.45..0.56).contains(&duration), "{duration}");
        assert!(durations.iter().all(|&d| (0.1..=2.1).contains(&d)));
        let distance = median(&mut distances);
        assert!((14.0..16.5).contains(&distance), "{distance}");
    }

    #[test]
    fn close_strangers_are_looked_at_less_and_the_eyes_go_down() {
        let config = StreetConfig::default();
        let mut random = Random::new(8);
        let (mut far, mut near) = (0, 0);
        for walker in 0..2000 {
            // Comes into view already close (from a doorway), or farther.
            let distance = if walker % 2 == 0 { 2.0 } else { 8.0 };
            let mut state = StreetState::default();
            for _ in 0..60 {
                state.update(
                    DT,
                    &[Noticed {
                        entity: walker,
                        distance,
                    }],
                    &config,
                    &mut random,
                );
                if state.fixated() == walker {
                    break;
                }
            }
            if state.fixated() == walker {
                if walker % 2 == 0 {
                    near += 1;
                } else {
                    far += 1;
                }
            } else if walker % 2 == 0 {
                assert!(state.is_civil());
            }
        }
        assert!(near * 2 < far, "near {near}, far {far}");
    }

    #[test]
    fn walkers_leaving_the_view_are_forgotten_and_memory_is_bounded() {
        let config = StreetConfig::default();
        let mut random = Random::new(1);
        let mut state = StreetState::default();
        let crowd: Vec<Noticed> = (0..40)
            .map(|entity| Noticed {
                entity,
                distance: 5.0 + entity as f32 * 0.1,
            })
            .collect();
        for _ in 0..300 {
            state.update(DT, &crowd, &config, &mut random);
            assert!(state.fixated() == NO_ENTITY || state.fixated() < STREET_MEMORY as u32);
        }
        // Ten walkers due at once: a few are fixated, the rest missed while the eyes are
        // busy (each waits at most `miss_after`).
        assert!(
            (2..10).contains(&state.fixation_count()),
            "{}",
            state.fixation_count()
        );
        state.update(DT, &[], &config, &mut random);
        assert_eq!(state.fixated(), NO_ENTITY);
        for _ in 0..31 {
            state.update(DT, &[], &config, &mut random);
        }
        assert!(state.tracked.iter().all(|t| t.entity == NO_ENTITY));
    }

    #[test]
    fn bad_settings_are_refused_by_name() {
        let mut config = StreetConfig {
            latency_min: 2.0,
            ..StreetConfig::default()
        };
        let message = config.validate().unwrap_err().to_string();
        assert!(message.contains("street_latency_min"), "{message}");
        config = StreetConfig {
            first_fixation_probability: f32::NAN,
            ..StreetConfig::default()
        };
        let message = config.validate().unwrap_err().to_string();
        assert!(
            message.contains("street_first_fixation_probability"),
            "{message}"
        );
        assert!(StreetConfig::default().validate().is_ok());
    }
}
