//! The saliency model of Kokkinara, Oyekoya & Steed 2011: separate targets for the eyes and
//! the head, chosen by a saliency score inside each one's field of view, held for a
//! limited fixation, with a random pick a quarter of the time.
//!
//! Score of a target O seen from the eye (or head) position E (paper §3.1):
//! - proximity `S_p = Σ aᵢ exp(−((x − bᵢ)/cᵢ)²) / a₁` of the distance x (the paper's
//!   Second Life units, which are metres), a = (19.11, 6.68), b = (1.83, 3.27),
//!   c = (0.87, 1.7);
//! - eccentricity `S_θ`, the same two-term fit of the angle θ in **degrees** between the
//!   head-centric vector and the direction to O, a = (40.13, 8.09), b = (14.39, −14.05),
//!   c = (4.18, 40.5);
//! - velocity `S_v = min(1, v / 6.096 m/s)` (the paper's 20 ft/s);
//! - rotation `S_Δq = min(1, Δq / 180°)` with Δq the target's turn in degrees per second;
//!
//! and `S_O = S_θ + S_p + S_v + S_Δq` (eq. 6). Both fits divided by a₁ peak a little above
//! 1 (≈ 1.17 at 2.0 m and ≈ 1.12 at 10.6°) because of their second term: kept as printed.
//! Parts of characters (head, eyes, chest, torso) are multiplied by a social weight.

use glam::Vec3;

use crate::math::random::Random;
use crate::scene::ids::NO_ENTITY;

/// `Σ aᵢ exp(−((x − bᵢ)/cᵢ)²) / a₁` for two terms (the paper's eq. 2 with n = 2).
#[inline]
pub fn two_term_gaussian(x: f32, a: [f32; 2], b: [f32; 2], c: [f32; 2]) -> f32 {
    let term = |i: usize| {
        let z = (x - b[i]) / c[i];
        a[i] * (-z * z).exp()
    };
    (term(0) + term(1)) / a[0]
}

/// `S_p` of a distance in metres.
pub fn proximity_saliency(distance: f32) -> f32 {
    two_term_gaussian(distance, [19.11, 6.68], [1.83, 3.27], [0.87, 1.7])
}

/// `S_θ` of an eccentricity in **degrees**.
pub fn eccentricity_saliency(degrees: f32) -> f32 {
    two_term_gaussian(degrees, [40.13, 8.09], [14.39, -14.05], [4.18, 40.5])
}

/// The paper's "reasonable maximum speed" of 20 ft/s, in m/s.
pub const MAX_SALIENT_SPEED: f32 = 6.096;

/// `S_v = min(1, v / 6.096 m/s)`.
pub fn velocity_saliency(speed: f32) -> f32 {
    (speed / MAX_SALIENT_SPEED).min(1.0)
}

/// `S_Δq = min(1, Δq / 180°)` of a turn rate in radians per second.
pub fn rotation_saliency(turn_rate: f32) -> f32 {
    (turn_rate.abs() / std::f32::consts::PI).min(1.0)
}

/// A rectangular field of view, as half-angles (radians) left/right and up/down of its
/// centre direction.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FieldOfView {
    /// Half of the horizontal field of view.
    pub half_horizontal: f32,
    /// Half of the vertical field of view.
    pub half_vertical: f32,
}

impl FieldOfView {
    /// A field of view from its full horizontal and vertical angles in degrees.
    pub fn from_degrees(horizontal: f32, vertical: f32) -> FieldOfView {
        FieldOfView {
            half_horizontal: (0.5 * horizontal).to_radians(),
            half_vertical: (0.5 * vertical).to_radians(),
        }
    }

    /// True if `direction` lies in the field of view centred on `forward` with `up` up:
    /// its yaw (about `up`) and pitch are within the half-angles. Directions behind are out.
    pub fn contains(&self, forward: Vec3, up: Vec3, direction: Vec3) -> bool {
        let side = up.cross(forward).normalize_or_zero();
        let ahead = direction.dot(forward);
        if ahead <= 0.0 {
            return false;
        }
        let yaw = direction.dot(side).atan2(ahead);
        let level = (ahead * ahead + direction.dot(side).powi(2)).sqrt();
        let pitch = direction.dot(up).atan2(level);
        yaw.abs() <= self.half_horizontal && pitch.abs() <= self.half_vertical
    }
}

/// Settings of the saliency model.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SaliencyConfig {
    /// The eyes' field of view, centred on the head's forward. Default 70° × 50°.
    pub eye_field: FieldOfView,
    /// The head's field of view, centred on the body's forward. Default 120° × 90°.
    pub head_field: FieldOfView,
    /// Longest eye fixation (s). Default 0.3.
    pub eye_fixation: f32,
    /// Longest head fixation (s). Default 1.0.
    pub head_fixation: f32,
    /// Probability that a new target is drawn at random among the visible ones instead of
    /// by score. Default 0.25.
    pub random_pick_probability: f32,
    /// Multiplier of `S_O` for the parts of characters over objects (> 1 favours people, as
    /// the paper's database did). Default 1.5.
    pub social_weight: f32,
    /// Multiplier of `S_O` for each part of a character, indexed by
    /// [`TargetPart`](crate::attention::TargetPart) as `u8` (whole, head, left eye, right
    /// eye, chest, torso; objects are whole). Default 1.5 for the eyes, 1 for the others:
    /// Kokkinara et al. (§5) found people preferred longer eye contact between avatars and
    /// suggest a per-object weight, higher for the eyes, to get it; 1.5 is our choice.
    pub part_weights: [f32; 6],
}

impl Default for SaliencyConfig {
    fn default() -> Self {
        SaliencyConfig {
            eye_field: FieldOfView::from_degrees(70.0, 50.0),
            head_field: FieldOfView::from_degrees(120.0, 90.0),
            eye_fixation: 0.3,
            head_fixation: 1.0,
            random_pick_probability: 0.25,
            social_weight: 1.5,
            part_weights: [1.0, 1.0, 1.5, 1.5, 1.0, 1.0],
        }
    }
}

/// A point that can be looked at: an entity, a part of it, and where it is now.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SalientPoint {
    /// Entity id.
    pub entity: u32,
    /// Which part of the entity (a [`crate::attention::TargetPart`] as `u8`).
    pub part: u8,
    /// World position (metres).
    pub position: Vec3,
    /// Speed of the entity (m/s).
    pub speed: f32,
    /// Turn rate of the entity (rad/s).
    pub turn_rate: f32,
    /// True for parts of characters (they get the social weight).
    pub social: bool,
}

/// `S_O` of a point seen from `eye` with centre of gaze `centre` (unit), scaled by the
/// social weight for parts of characters.
pub fn saliency(point: &SalientPoint, eye: Vec3, centre: Vec3, config: &SaliencyConfig) -> f32 {
    let offset = point.position - eye;
    let distance = offset.length();
    let direction = if distance > 1e-6 {
        offset / distance
    } else {
        centre
    };
    let eccentricity = direction.dot(centre).clamp(-1.0, 1.0).acos().to_degrees();
    let score = eccentricity_saliency(eccentricity)
        + proximity_saliency(distance)
        + velocity_saliency(point.speed)
        + rotation_saliency(point.turn_rate);
    let part = config
        .part_weights
        .get(usize::from(point.part))
        .copied()
        .unwrap_or(1.0);
    if point.social {
        score * config.social_weight * part
    } else {
        score * part
    }
}

/// What a fixation is on: an entity and a part, or nothing.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Fixation {
    /// Entity id, or `NO_ENTITY`.
    pub entity: u32,
    /// Part of the entity.
    pub part: u8,
}

impl Fixation {
    /// No target.
    pub const NONE: Fixation = Fixation {
        entity: NO_ENTITY,
        part: 0,
    };
}

/// One fixation channel (eyes or head): its target and how long it has been held.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FixationChannel {
    /// The current target.
    pub target: Fixation,
    /// Seconds on it.
    pub held: f32,
    /// Fixations started so far.
    pub shifts: u32,
    /// Of which drawn at random.
    pub random_shifts: u32,
}

impl Default for FixationChannel {
    fn default() -> Self {
        FixationChannel {
            target: Fixation::NONE,
            held: 0.0,
            shifts: 0,
            random_shifts: 0,
        }
    }
}

impl FixationChannel {
    /// Advances by `dt`. The current target is kept while it is still `visible` and held
    /// less than `max_fixation`; otherwise a new one is chosen among `count` visible
    /// candidates: at random with probability `random_probability`, else the best by
    /// `score(i)`. `candidate(i)` names candidate `i`. Returns true on a new fixation.
    #[allow(clippy::too_many_arguments)]
    pub fn update(
        &mut self,
        dt: f32,
        max_fixation: f32,
        still_visible: bool,
        count: usize,
        candidate: impl Fn(usize) -> Fixation,
        score: impl Fn(usize) -> f32,
        random_probability: f32,
        random: &mut Random,
    ) -> bool {
        self.held += dt;
        if self.target != Fixation::NONE && still_visible && self.held < max_fixation {
            return false;
        }
        self.held = 0.0;
        if count == 0 {
            let changed = self.target != Fixation::NONE;
            self.target = Fixation::NONE;
            return changed;
        }
        let pick_random = random.next_f32() < random_probability;
        let chosen = if pick_random {
            random.below(count as u32) as usize
        } else {
            (0..count)
                .max_by(|&a, &b| score(a).total_cmp(&score(b)).then(b.cmp(&a)))
                .unwrap_or(0)
        };
        self.target = candidate(chosen);
        self.shifts += 1;
        if pick_random {
            self.random_shifts += 1;
        }
        true
    }
}

pub use crate::math::ease::{head_progress, saccade_profile, saccade_progress};

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn curves_at_hand_computed_points() {
        // At the first centroid the first term is a₁, the second a₂·exp(−((1.83−3.27)/1.7)²).
        let expected = (19.11 + 6.68 * (-((1.83f32 - 3.27) / 1.7).powi(2)).exp()) / 19.11;
        assert!((proximity_saliency(1.83) - expected).abs() < 1e-6);
        let peak = (0..1000)
            .map(|i| proximity_saliency(i as f32 * 0.01))
            .fold(0.0, f32::max);
        assert!((peak - 1.17).abs() < 0.01, "proximity peak {peak}");
        assert!(proximity_saliency(20.0) < 1e-6);
        let expected = (40.13 + 8.09 * (-((14.39f32 + 14.05) / 40.5).powi(2)).exp()) / 40.13;
        assert!((eccentricity_saliency(14.39) - expected).abs() < 1e-6);
        let peak = (0..900)
            .map(|i| eccentricity_saliency(i as f32 * 0.1))
            .fold(0.0, f32::max);
        assert!((peak - 1.12).abs() < 0.02, "eccentricity peak {peak}");
        assert!((velocity_saliency(3.048) - 0.5).abs() < 1e-6);
        assert_eq!(velocity_saliency(100.0), 1.0);
        assert!((rotation_saliency(std::f32::consts::FRAC_PI_2) - 0.5).abs() < 1e-6);
    }

    #[test]
    fn fields_of_view_prune_separately() {
        let (eye, head) = (
            SaliencyConfig::default().eye_field,
            SaliencyConfig::default().head_field,
        );
        let forward = Vec3::Z;
        let at = |yaw_degrees: f32, pitch_degrees: f32| {
            let (yaw, pitch) = (yaw_degrees.to_radians(), pitch_degrees.to_radians());
            Vec3::new(
                yaw.sin() * pitch.cos(),
                pitch.sin(),
                yaw.cos() * pitch.cos(),
            )
        };
        assert!(eye.contains(forward, Vec3::Y, at(30.0, 0.0)));
        assert!(!eye.contains(forward, Vec3::Y, at(40.0, 0.0)));
        assert!(head.contains(forward, Vec3::Y, at(40.0, 0.0)));
        assert!(!head.contains(forward, Vec3::Y, at(65.0, 0.0)));
        assert!(eye.contains(forward, Vec3::Y, at(0.0, 20.0)));
        assert!(!eye.contains(forward, Vec3::Y, at(0.0, 30.0)));
        assert!(head.contains(forward, Vec3::Y, at(0.0, 40.0)));
        assert!(!head.contains(forward, Vec3::Y, at(0.0, 50.0)));
        assert!(!head.contains(forward, Vec3::Y, -forward));
    }

    #[test]
    fn saccade_and_head_curves() {
        let profile = saccade_profile();
        assert!((profile.iter().sum::<f32>() - 1.0).abs() < 1e-6);
        assert!(profile[2] > profile[1] && profile[1] > profile[0]);
        assert_eq!(saccade_progress(0.0), 0.0);
        assert!((saccade_progress(6.0) - 1.0).abs() < 1e-6);
        assert!(saccade_progress(3.0) > 0.4 && saccade_progress(3.0) < 0.8);
        assert_eq!(head_progress(0.0), 0.0);
        assert!((head_progress(1.0) - 1.0).abs() < 1e-6);
        assert!(
            (head_progress(0.5) - 0.51).abs() < 0.01,
            "{}",
            head_progress(0.5)
        );
        assert!(
            head_progress(0.05) < 0.01,
            "slow start: {}",
            head_progress(0.05)
        );
        let mut previous = 0.0;
        for i in 1..=100 {
            let value = head_progress(i as f32 / 100.0);
            assert!(value >= previous);
            previous = value;
        }
    }

    #[test]
    fn fixations_are_held_then_renewed_with_random_picks() {
        let mut channel = FixationChannel::default();
        let mut random = Random::new(3);
        let candidate = |i: usize| Fixation {
            entity: i as u32,
            part: 0,
        };
        let score = |i: usize| i as f32; // the last is the most salient
        let dt = 1.0 / 30.0;
        let mut longest = 0.0f32;
        let mut held = 0.0f32;
        for _ in 0..30_000 {
            let changed = channel.update(dt, 0.3, true, 8, candidate, score, 0.25, &mut random);
            if changed {
                longest = longest.max(held);
                held = 0.0;
            }
            held += dt;
        }
        assert!(longest <= 0.3 + 1e-4, "longest fixation {longest}");
        let share = channel.random_shifts as f32 / channel.shifts as f32;
        assert!((share - 0.25).abs() <= 0.03, "random share {share}");
    }
}
