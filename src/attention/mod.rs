//! Attention: which entity each character looks at, and when.
//!
//! The crowd model of Grillon & Thalmann 2009: [`score`](crate::attention::score) rates an entity for a
//! character, [`candidates`](crate::attention::candidates) finds each character's best entities fast, [`interest`](crate::attention::interest) turns the scores into interest points online, [`plan`](crate::attention::plan) does the
//! same offline over whole recorded trajectories with the exact percentile, and
//! [`quantile`](crate::attention::quantile) provides both percentiles. [`saliency`](crate::attention::saliency) is the eye-and-head model of
//! Kokkinara, Oyekoya & Steed 2011 and [`baseline`](crate::attention::baseline) the stock behaviour it is compared with.
//! [`street`](crate::attention::street) is a model calibrated on walkers measured with eye trackers, and
//! [`following`](crate::attention::following) the gaze-following layer every model may use.

pub mod baseline;
pub mod candidates;
pub mod conversation;
pub mod following;
pub mod interest;
pub mod plan;
pub mod quantile;
pub mod saliency;
pub mod score;
pub mod street;

use crate::math::random::Random;
use score::SubscoreWeights;

/// Which model decides where a character looks.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum AttentionModel {
    /// Grillon & Thalmann 2009: one interest point for the whole gaze chain.
    #[default]
    Crowd,
    /// Kokkinara, Oyekoya & Steed 2011: separate saliency-driven targets for eyes and head.
    Saliency,
    /// The stock virtual-world behaviour the saliency paper compares against.
    Baseline,
    /// Walkers as measured in the street with eye trackers ([`street`]): each walker coming
    /// into view fixated once with a set probability, after a latency, for about half a
    /// second; close strangers looked at less; the path ahead the rest of the time.
    Street,
}

/// Which part of an entity a character looks at.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[repr(u8)]
pub enum TargetPart {
    /// The entity's look-at point (an object's, or a character's eyes as a whole).
    Whole = 0,
    /// A character's head.
    Head = 1,
    /// A character's left eye.
    LeftEye = 2,
    /// A character's right eye.
    RightEye = 3,
    /// A character's chest.
    Chest = 4,
    /// A character's torso (belly).
    Torso = 5,
}

impl TargetPart {
    /// The five social targets a character offers (Kokkinara et al. §3.2).
    pub const SOCIAL: [TargetPart; 5] = [
        TargetPart::Head,
        TargetPart::LeftEye,
        TargetPart::RightEye,
        TargetPart::Chest,
        TargetPart::Torso,
    ];
}

/// A character's attention parameters.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CharacterParams {
    /// `ω_p, ω_s, ω_o, ω_pe`.
    pub weights: SubscoreWeights,
    /// `a`/100: the fraction of time the character attends to something, in [0, 1].
    pub attention_fraction: f32,
    /// The model deciding where the character looks.
    pub model: AttentionModel,
}

impl CharacterParams {
    /// Draws parameters: weights uniform on the simplex (they sum to 1) and the attention
    /// fraction uniform in `fraction_range`.
    pub fn random(random: &mut Random, fraction_range: (f32, f32)) -> CharacterParams {
        // −ln(u) draws are exponential; normalised, they are uniform on the simplex.
        let mut draw = || -(1.0 - random.next_f32()).ln();
        let raw = [draw(), draw(), draw(), draw()];
        let weights = SubscoreWeights::normalised(raw).unwrap_or(SubscoreWeights::EQUAL);
        CharacterParams {
            weights,
            attention_fraction: random.range(fraction_range.0, fraction_range.1),
            model: AttentionModel::Crowd,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn random_weights_sum_to_one_and_vary() {
        let mut random = Random::new(5);
        let a = CharacterParams::random(&mut random, (0.2, 0.6));
        let b = CharacterParams::random(&mut random, (0.2, 0.6));
        for params in [a, b] {
            let sum: f32 = params.weights.to_array().iter().sum();
            assert!((sum - 1.0).abs() < 1e-5);
            assert!((0.2..0.6).contains(&params.attention_fraction));
        }
        assert_ne!(a, b);
    }
}
