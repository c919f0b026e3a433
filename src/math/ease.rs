//! Progress curves of gaze motions: the ease of Grillon & Thalmann 2009,
//! `f_P(u) = ½ (1 + erf(s (u − ½)) / erf(s / 2))`, and the eye saccade and head movement
//! curves used by Kokkinara, Oyekoya & Steed 2011.
//!
//! It maps a motion's normalised progress `u ∈ [0, 1]` to the fraction of the rotation done:
//! exactly 0 at `u = 0` and 1 at `u = 1`, with a bell-shaped (gaussian) velocity. The
//! steepness `s` defaults to [`DEFAULT_STEEPNESS`].

/// Steepness `s` of the ease: 4 gives a velocity peak about 2.27× the mean, like a human
/// head movement.
pub const DEFAULT_STEEPNESS: f32 = 4.0;

/// A precomputed ease curve `f_P` with steepness `s`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Ease {
    steepness: f32,
    /// `1 / erf(s / 2)`, so that `f_P(1) = 1` exactly.
    inverse_norm: f32,
}

impl Ease {
    /// The curve with steepness `s > 0`.
    pub fn new(steepness: f32) -> Ease {
        let steepness = steepness.max(1e-3);
        Ease {
            steepness,
            inverse_norm: 1.0 / libm::erff(steepness * 0.5),
        }
    }

    /// `f_P(u)`: the fraction of the motion done at progress `u` (clamped to [0, 1]).
    /// Returns exactly 0 for `u ≤ 0` and exactly 1 for `u ≥ 1`.
    pub fn at(&self, progress: f32) -> f32 {
        if progress <= 0.0 {
            return 0.0;
        }
        if progress >= 1.0 {
            return 1.0;
        }
        let value = 0.5 * (1.0 + libm::erff(self.steepness * (progress - 0.5)) * self.inverse_norm);
        value.clamp(0.0, 1.0)
    }

    /// `d f_P / d u` at progress `u`: the velocity profile (a gaussian), 0 outside [0, 1].
    pub fn slope(&self, progress: f32) -> f32 {
        if !(0.0..=1.0).contains(&progress) {
            return 0.0;
        }
        let x = self.steepness * (progress - 0.5);
        // d/du erf(s(u − ½)) = 2s/√π · exp(−x²)
        0.5 * self.inverse_norm * self.steepness * std::f32::consts::FRAC_2_SQRT_PI * (-x * x).exp()
    }
}

impl Default for Ease {
    fn default() -> Self {
        Ease::new(DEFAULT_STEEPNESS)
    }
}

/// The eye saccade of Lee et al. as used by the paper (Kokkinara et al. 2011, eq. 7): the share of the eye's
/// rotation done in each of the six frames, `14 e^(−π/4 (x − 3)²)` for x = 1..6,
/// normalised to sum to 1.
pub fn saccade_profile() -> [f32; 6] {
    let mut weights = [0.0f32; 6];
    for (i, weight) in weights.iter_mut().enumerate() {
        let x = (i + 1) as f32 - 3.0;
        *weight = 14.0 * (-std::f32::consts::FRAC_PI_4 * x * x).exp();
    }
    let sum: f32 = weights.iter().sum();
    weights.map(|w| w / sum)
}

/// Fraction of the eye saccade done after `frames` frames (0 to 6) of 1/30 s.
pub fn saccade_progress(frames: f32) -> f32 {
    let profile = saccade_profile();
    let whole = frames.clamp(0.0, 6.0);
    let done = whole.floor() as usize;
    let mut sum: f32 = profile[..done].iter().sum();
    if done < 6 {
        sum += profile[done] * (whole - done as f32);
    }
    sum.min(1.0)
}

/// The head's saccadic transition (Kokkinara et al. 2011, eq. 8), `θ_h(u) = e^(0.027u)(sin(πu/2))^1.90` on
/// normalised time u ∈ [0, 1], divided by its end value so that it goes exactly from 0
/// to 1.
pub fn head_progress(u: f32) -> f32 {
    let u = u.clamp(0.0, 1.0);
    let curve = |u: f32| (0.027 * u).exp() * (std::f32::consts::FRAC_PI_2 * u).sin().powf(1.90);
    curve(u) / curve(1.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn exact_at_both_ends_and_symmetric() {
        let ease = Ease::default();
        assert_eq!(ease.at(0.0), 0.0);
        assert_eq!(ease.at(1.0), 1.0);
        assert_eq!(ease.at(-3.0), 0.0);
        assert_eq!(ease.at(7.0), 1.0);
        assert!((ease.at(0.5) - 0.5).abs() < 1e-6);
        for i in 1..10 {
            let u = i as f32 / 10.0;
            assert!((ease.at(u) + ease.at(1.0 - u) - 1.0).abs() < 1e-6);
        }
    }

    #[test]
    fn monotonic_with_bell_shaped_velocity() {
        let ease = Ease::default();
        let mut previous = 0.0;
        for i in 1..=100 {
            let value = ease.at(i as f32 / 100.0);
            assert!(value >= previous);
            previous = value;
        }
        assert!(ease.slope(0.5) > ease.slope(0.25));
        assert!(ease.slope(0.25) > ease.slope(0.05));
        // Peak velocity of s = 4: s / (√π erf(2)) ≈ 2.267 times the mean.
        assert!(
            (ease.slope(0.5) - 2.2674).abs() < 1e-3,
            "{}",
            ease.slope(0.5)
        );
    }

    #[test]
    fn slope_matches_finite_differences() {
        let ease = Ease::new(3.0);
        for i in 1..20 {
            let u = i as f32 / 20.0;
            let h = 1e-3;
            let numeric = (ease.at(u + h) - ease.at(u - h)) / (2.0 * h);
            assert!((numeric - ease.slope(u)).abs() < 1e-2, "at {u}");
        }
    }
}
