//! The Grillon–Thalmann scoring function: how interesting entity E is to character C now.
//!
//! From C's ground position, heading and velocity and E's, it computes the distance `d`, the
//! angle `α` of E in C's field of view, the angle `β` between their forward directions and
//! their relative speed `rs`; prunes E beyond `d_m` or outside the field of view; and
//! combines four subscores, each in [0, 1]:
//!
//! - proximity `S_p = exp(−(1 − d/2)² / 2)`: the paper's eq. 3 with the sign of its
//!   `(d_m/2 − 1)` term corrected, so that it peaks at 2 m as the text says;
//! - speed `S_s = min(1, ω_sw · rs)`;
//! - orientation `S_o = (π − α) β / π²`;
//! - periphery `S_pe = α (π − β) / ((fov/2) π)` if `β ≤ β_m`, else 0;
//!
//! into `S = I_E (ω_p S_p + ω_s S_s + ω_o S_o + ω_pe S_pe)` (eq. 7).
//!
//! `α` uses [`fast_acos`] and the proximity gaussian [`crate::math::fast::fast_exp`] (both
//! within 1e-4 of the exact functions); `β` is the difference of the two headings, taken the
//! short way round (no arc cosine).

use std::f32::consts::{PI, TAU};

use crate::math::fast::{acos_lanes, exp_lanes, fast_acos};
use crate::math::wide::Wide;

// What the scoring needs of an entity: defined with the scene, which fills it, and named here
// too, where it is read.
pub use crate::scene::GroundState;

/// Settings of the scoring function shared by every character.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ScoringConfig {
    /// `d_m`: entities farther than this (metres) are ignored. Default 10 m.
    pub max_distance: f32,
    /// Full horizontal field of view (radians); entities with `α > fov/2` are ignored.
    /// Default π (180°).
    pub field_of_view: f32,
    /// `ω_sw`: speed weighting (s/m), so `S_s = min(1, ω_sw · rs)`. Default 0.5.
    pub speed_weight: f32,
    /// `β_m`: largest angle between forward directions for the periphery subscore
    /// (radians). Default π/2.
    pub periphery_max_angle: f32,
    /// The score of an entity that talks (its pushed state says so) is multiplied by this,
    /// ≥ 0 (1: talking changes nothing). Default 1.5 (our choice: Kokkinara et al. §3.3.1
    /// note that people attend more to avatars that talk; the papers give no factor).
    pub talking_gain: f32,
}

impl Default for ScoringConfig {
    fn default() -> Self {
        ScoringConfig {
            max_distance: 10.0,
            field_of_view: PI,
            speed_weight: 0.5,
            periphery_max_angle: PI / 2.0,
            talking_gain: 1.5,
        }
    }
}

/// The four subscore weights `ω_p, ω_s, ω_o, ω_pe`; non-negative and summing to 1.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SubscoreWeights {
    /// `ω_p`, proximity.
    pub proximity: f32,
    /// `ω_s`, relative speed.
    pub speed: f32,
    /// `ω_o`, orientation.
    pub orientation: f32,
    /// `ω_pe`, periphery.
    pub periphery: f32,
}

impl SubscoreWeights {
    /// Equal weights of ¼.
    pub const EQUAL: SubscoreWeights = SubscoreWeights {
        proximity: 0.25,
        speed: 0.25,
        orientation: 0.25,
        periphery: 0.25,
    };

    /// The weights as an array `[ω_p, ω_s, ω_o, ω_pe]`.
    pub fn to_array(self) -> [f32; 4] {
        [self.proximity, self.speed, self.orientation, self.periphery]
    }

    /// Weights from `[ω_p, ω_s, ω_o, ω_pe]`, rescaled to sum to 1. `None` if any is
    /// negative or non-finite, or all are zero.
    pub fn normalised(values: [f32; 4]) -> Option<SubscoreWeights> {
        if values.iter().any(|v| !v.is_finite() || *v < 0.0) {
            return None;
        }
        let mut values = values;
        let mut sum: f32 = values.iter().sum();
        if sum == f32::INFINITY {
            // Finite weights whose sum overflows: a quarter of each sums below f32::MAX.
            values = values.map(|v| v * 0.25);
            sum = values.iter().sum();
        }
        if sum <= 0.0 {
            return None;
        }
        Some(SubscoreWeights {
            proximity: values[0] / sum,
            speed: values[1] / sum,
            orientation: values[2] / sum,
            periphery: values[3] / sum,
        })
    }
}

/// Everything the scoring computed for one (character, entity) pair.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct ScoreBreakdown {
    /// `d`, ground distance (metres).
    pub distance: f32,
    /// `α`, angle of E in C's field of view (radians, 0 straight ahead, ≤ π).
    pub view_angle: f32,
    /// `β`, angle between C's and E's forward directions (radians, ≤ π).
    pub heading_angle: f32,
    /// `rs`, relative speed (m/s).
    pub relative_speed: f32,
    /// `S_p`.
    pub proximity: f32,
    /// `S_s`.
    pub speed: f32,
    /// `S_o`.
    pub orientation: f32,
    /// `S_pe`.
    pub periphery: f32,
    /// `S`, the weighted sum times the impact factor (0 when pruned).
    pub total: f32,
    /// True if E was pruned (beyond `d_m` or outside the field of view); subscores are 0.
    pub pruned: bool,
}

/// `S_p(d) = exp(−(1 − d/2)² / 2)`: 1 at 2 m, ≈ 0.61 at 0 m, ≈ 0.32 at 5 m.
#[inline]
pub fn proximity_score(distance: f32) -> f32 {
    proximity_lanes(distance)
}

/// `S_s = min(1, ω_sw · rs)`.
#[inline]
pub fn speed_score(relative_speed: f32, speed_weight: f32) -> f32 {
    speed_lanes(relative_speed, speed_weight)
}

/// `S_o = (π − α) β / π²`: high for entities ahead and coming towards C.
#[inline]
pub fn orientation_score(view_angle: f32, heading_angle: f32) -> f32 {
    orientation_lanes(view_angle, heading_angle)
}

/// `S_pe = α (π − β) / ((fov/2) π)` if `β ≤ β_m`, else 0: high for entities in the
/// periphery moving roughly C's way (about to overtake or be overtaken).
#[inline]
pub fn periphery_score(
    view_angle: f32,
    heading_angle: f32,
    half_field_of_view: f32,
    periphery_max_angle: f32,
) -> f32 {
    periphery_lanes(
        view_angle,
        heading_angle,
        inverse_periphery_scale(half_field_of_view),
        periphery_max_angle,
    )
}

/// `1 / ((fov/2) π)`: the periphery subscore multiplies by it (a division per entity
/// would cost more).
#[inline]
fn inverse_periphery_scale(half_field_of_view: f32) -> f32 {
    1.0 / (half_field_of_view * PI)
}

// The subscores for one entity per lane: the one definition of each formula (the scalar
// functions above are their one-lane form).

#[inline(always)]
fn proximity_lanes<W: Wide>(distance: W) -> W {
    let x = W::splat(1.0) - distance * 0.5;
    exp_lanes(x * -0.5 * x)
}

/// `β` from headings in [−π, π]: their difference, the short way round, in [0, π].
#[inline(always)]
fn heading_angle_lanes<W: Wide>(heading: W, observer_heading: W) -> W {
    let difference = (heading - observer_heading).abs();
    difference.min(W::splat(TAU) - difference)
}

#[inline(always)]
fn speed_lanes<W: Wide>(relative_speed: W, speed_weight: f32) -> W {
    (relative_speed * speed_weight).min(W::splat(1.0))
}

#[inline(always)]
fn orientation_lanes<W: Wide>(view_angle: W, heading_angle: W) -> W {
    (W::splat(PI) - view_angle) * heading_angle * (1.0 / (PI * PI))
}

#[inline(always)]
fn periphery_lanes<W: Wide>(
    view_angle: W,
    heading_angle: W,
    inverse_periphery_scale: f32,
    periphery_max_angle: f32,
) -> W {
    // Computed in every lane, then selected.
    let value = view_angle * (W::splat(PI) - heading_angle) * inverse_periphery_scale;
    W::select(
        heading_angle.cmpgt(W::splat(periphery_max_angle)),
        W::splat(0.0),
        value,
    )
}

/// The total score `S` of one entity per lane for one observer: what the candidate
/// searches use. The same operations in the same order at every width (so the same bits),
/// and the same subscore functions as [`Scorer::score`].
#[derive(Debug, Clone, Copy)]
pub(crate) struct LaneScorer<W> {
    forward_x: W,
    forward_y: W,
    heading: W,
    velocity_x: W,
    velocity_y: W,
    weights: SubscoreWeights,
    speed_weight: f32,
    inverse_periphery_scale: f32,
    periphery_max_angle: f32,
}

impl<W: Wide> LaneScorer<W> {
    /// The scorer for `observer` with its subscore `weights`.
    #[inline(always)]
    pub(crate) fn new(
        scorer: &Scorer,
        observer: &GroundState,
        weights: &SubscoreWeights,
    ) -> LaneScorer<W> {
        LaneScorer {
            forward_x: W::splat(observer.forward.x),
            forward_y: W::splat(observer.forward.y),
            heading: W::splat(observer.heading),
            velocity_x: W::splat(observer.velocity.x),
            velocity_y: W::splat(observer.velocity.y),
            weights: *weights,
            speed_weight: scorer.config.speed_weight,
            inverse_periphery_scale: inverse_periphery_scale(scorer.half_field_of_view),
            periphery_max_angle: scorer.config.periphery_max_angle,
        }
    }

    /// `S` for entities at `offset` from the observer (already pruned by distance and
    /// view), at `heading` (in [−π, π)), moving at `velocity`, with impact factor `impact`.
    #[inline(always)]
    pub(crate) fn score(
        &self,
        offset_x: W,
        offset_y: W,
        heading: W,
        velocity_x: W,
        velocity_y: W,
        impact: W,
    ) -> W {
        let distance = (offset_x * offset_x + offset_y * offset_y).sqrt();
        let along = self.forward_x * offset_x + self.forward_y * offset_y;
        // Divide in every lane, then select: an entity at C's position is straight ahead.
        let quotient = along / distance.max(W::splat(1e-6));
        let cos_view = W::select(distance.cmpgt(W::splat(1e-6)), quotient, W::splat(1.0));
        let view_angle = acos_lanes(cos_view);
        let heading_angle = heading_angle_lanes(heading, self.heading);
        let relative_x = velocity_x - self.velocity_x;
        let relative_y = velocity_y - self.velocity_y;
        let relative_speed = (relative_x * relative_x + relative_y * relative_y).sqrt();
        total_lanes(
            impact,
            [
                proximity_lanes(distance),
                speed_lanes(relative_speed, self.speed_weight),
                orientation_lanes(view_angle, heading_angle),
                periphery_lanes(
                    view_angle,
                    heading_angle,
                    self.inverse_periphery_scale,
                    self.periphery_max_angle,
                ),
            ],
            &self.weights,
        )
    }
}

/// `S = I_E (ω_p S_p + ω_s S_s + ω_o S_o + ω_pe S_pe)` (eq. 7) from the subscores
/// `[S_p, S_s, S_o, S_pe]`, one entity per lane.
#[inline(always)]
fn total_lanes<W: Wide>(impact: W, subscores: [W; 4], weights: &SubscoreWeights) -> W {
    let [proximity, speed, orientation, periphery] = subscores;
    impact
        * (proximity * weights.proximity
            + speed * weights.speed
            + orientation * weights.orientation
            + periphery * weights.periphery)
}

/// Precomputed per-call constants of the scoring function.
#[derive(Debug, Clone, Copy)]
pub struct Scorer {
    config: ScoringConfig,
    max_distance_squared: f32,
    half_field_of_view: f32,
    cos_half_field_of_view: f32,
}

impl Scorer {
    /// A scorer for `config`.
    pub fn new(config: ScoringConfig) -> Scorer {
        let half = 0.5 * config.field_of_view;
        Scorer {
            config,
            max_distance_squared: config.max_distance * config.max_distance,
            half_field_of_view: half,
            cos_half_field_of_view: half.cos(),
        }
    }

    /// The configuration.
    pub fn config(&self) -> &ScoringConfig {
        &self.config
    }

    /// Scores `entity` for `observer`, with the observer's subscore `weights` and the
    /// entity's impact factor. Pruned pairs come back with `pruned = true` and `total = 0`.
    #[inline]
    pub fn score(
        &self,
        observer: &GroundState,
        entity: &GroundState,
        weights: &SubscoreWeights,
        impact: f32,
    ) -> ScoreBreakdown {
        let offset = entity.position - observer.position;
        let distance_squared = offset.length_squared();
        if distance_squared > self.max_distance_squared {
            return ScoreBreakdown {
                distance: distance_squared.sqrt(),
                pruned: true,
                ..ScoreBreakdown::default()
            };
        }
        let distance = distance_squared.sqrt();
        // An entity exactly at C's position is straight ahead.
        let cos_view = if distance > 1e-6 {
            observer.forward.dot(offset) / distance
        } else {
            1.0
        };
        if cos_view < self.cos_half_field_of_view {
            return ScoreBreakdown {
                distance,
                view_angle: fast_acos(cos_view),
                pruned: true,
                ..ScoreBreakdown::default()
            };
        }
        let view_angle = fast_acos(cos_view);
        let heading_angle = heading_angle_lanes(entity.heading, observer.heading);
        let relative_speed = (entity.velocity - observer.velocity).length();
        let proximity = proximity_score(distance);
        let speed = speed_score(relative_speed, self.config.speed_weight);
        let orientation = orientation_score(view_angle, heading_angle);
        let periphery = periphery_score(
            view_angle,
            heading_angle,
            self.half_field_of_view,
            self.config.periphery_max_angle,
        );
        let total = total_lanes(impact, [proximity, speed, orientation, periphery], weights);
        ScoreBreakdown {
            distance,
            view_angle,
            heading_angle,
            relative_speed,
            proximity,
            speed,
            orientation,
            periphery,
            total,
            pruned: false,
        }
    }
}

impl Scorer {
    /// `d_m²`, for callers that prune by distance themselves.
    #[inline]
    pub fn max_distance_squared(&self) -> f32 {
        self.max_distance_squared
    }

    /// `cos(fov/2)`, for callers that prune by view themselves.
    #[inline]
    pub fn cos_half_field_of_view(&self) -> f32 {
        self.cos_half_field_of_view
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec2;

    fn close(a: f32, b: f32) -> bool {
        (a - b).abs() < 1e-5
    }

    #[test]
    fn proximity_peaks_at_two_metres() {
        assert!(close(proximity_score(2.0), 1.0));
        assert!(close(proximity_score(0.0), (-0.5f32).exp()));
        assert!(close(proximity_score(4.0), (-0.5f32).exp()));
        assert!(close(proximity_score(10.0), (-8.0f32).exp()));
        assert!(proximity_score(2.5) > proximity_score(3.0));
        assert!(proximity_score(2.0) > proximity_score(1.5));
    }

    #[test]
    fn subscores_at_hand_computed_points() {
        assert!(close(speed_score(1.0, 0.5), 0.5));
        assert!(close(speed_score(5.0, 0.5), 1.0));
        // Straight ahead (α = 0) and coming head-on (β = π): S_o = π·π/π² = 1.
        assert!(close(orientation_score(0.0, PI), 1.0));
        // At the side (α = π/2), crossing (β = π/2): (π/2)(π/2)/π² = 1/4.
        assert!(close(orientation_score(PI / 2.0, PI / 2.0), 0.25));
        // At the edge of a 180° view (α = π/2), same direction (β = 0): (π/2)π/((π/2)π) = 1.
        assert!(close(
            periphery_score(PI / 2.0, 0.0, PI / 2.0, PI / 2.0),
            1.0
        ));
        assert!(close(
            periphery_score(PI / 4.0, PI / 4.0, PI / 2.0, PI / 2.0),
            0.375
        ));
        assert_eq!(periphery_score(PI / 2.0, 2.0, PI / 2.0, PI / 2.0), 0.0);
    }

    fn walker(x: f32, y: f32, forward: Vec2, speed: f32) -> GroundState {
        GroundState {
            position: Vec2::new(x, y),
            forward,
            heading: crate::math::wrap_angle(forward.to_angle()),
            velocity: forward * speed,
        }
    }

    #[test]
    fn full_score_of_a_head_on_walker() {
        let scorer = Scorer::new(ScoringConfig::default());
        let me = walker(0.0, 0.0, Vec2::X, 1.0);
        let other = walker(2.0, 0.0, Vec2::NEG_X, 1.0);
        let s = scorer.score(&me, &other, &SubscoreWeights::EQUAL, 2.0);
        assert!(!s.pruned);
        assert!(close(s.distance, 2.0));
        assert!(close(s.view_angle, 0.0));
        assert!(close(s.heading_angle, PI));
        assert!(close(s.relative_speed, 2.0));
        assert!(close(s.proximity, 1.0));
        assert!(close(s.speed, 1.0));
        assert!(close(s.orientation, 1.0));
        assert_eq!(s.periphery, 0.0);
        assert!(close(s.total, 2.0 * 0.25 * 3.0));
    }

    #[test]
    fn pruned_beyond_max_distance_and_outside_the_view() {
        let scorer = Scorer::new(ScoringConfig::default());
        let me = walker(0.0, 0.0, Vec2::X, 1.0);
        let far = walker(10.5, 0.0, Vec2::X, 1.0);
        let s = scorer.score(&me, &far, &SubscoreWeights::EQUAL, 1.0);
        assert!(s.pruned && s.total == 0.0 && s.proximity == 0.0);
        let behind = walker(-3.0, 0.5, Vec2::X, 1.0);
        let s = scorer.score(&me, &behind, &SubscoreWeights::EQUAL, 1.0);
        assert!(s.pruned && s.total == 0.0);
        // Just inside d_m and just inside the 180° field of view.
        let edge = walker(0.01, 9.99, Vec2::X, 1.0);
        assert!(
            !scorer
                .score(&me, &edge, &SubscoreWeights::EQUAL, 1.0)
                .pruned
        );
        let narrow = Scorer::new(ScoringConfig {
            field_of_view: PI / 2.0,
            ..ScoringConfig::default()
        });
        assert!(
            narrow
                .score(&me, &edge, &SubscoreWeights::EQUAL, 1.0)
                .pruned
        );
    }

    #[test]
    fn heading_angle_is_the_angle_between_the_forward_directions() {
        let mut random = crate::math::random::Random::new(17);
        let mut worst = 0.0f64;
        for i in 0..20_000 {
            // Headings of any size (the scene wraps them), and some exactly ±π apart.
            let observer = random.range(-40.0, 40.0);
            let entity = if i % 100 == 0 {
                observer + PI
            } else {
                random.range(-40.0, 40.0)
            };
            let turn = (entity as f64 - observer as f64).rem_euclid(std::f64::consts::TAU);
            let exact = turn.min(std::f64::consts::TAU - turn);
            let beta = heading_angle_lanes(
                crate::math::wrap_angle(entity),
                crate::math::wrap_angle(observer),
            );
            assert!((0.0..=PI).contains(&beta), "{beta}");
            worst = worst.max((beta as f64 - exact).abs());
        }
        // The wrapped headings' rounding (a few 1e−7).
        assert!(worst < 1e-6, "worst {worst}");
    }

    #[test]
    fn weights_are_normalised_or_rejected() {
        let w = SubscoreWeights::normalised([1.0, 1.0, 2.0, 0.0]).unwrap();
        assert_eq!(w.to_array(), [0.25, 0.25, 0.5, 0.0]);
        assert!(SubscoreWeights::normalised([0.0; 4]).is_none());
        assert!(SubscoreWeights::normalised([-1.0, 1.0, 1.0, 1.0]).is_none());
        assert!(SubscoreWeights::normalised([f32::NAN, 1.0, 1.0, 1.0]).is_none());
    }
}
