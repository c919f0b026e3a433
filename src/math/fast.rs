//! Fast approximations for the scoring hot loop, within 1e-4 of the exact functions
//! (tests check the bounds over the whole domain used). Written as straight-line float
//! code so that loops over many candidates vectorise.

use std::f32::consts::PI;

use super::wide::{clamp, Wide};

/// Largest error of [`fast_acos`] against the exact arc cosine, in radians.
pub const FAST_ACOS_MAX_ERROR: f32 = 1e-4;

/// Largest relative error of [`fast_exp`] against the exact exponential on [−87, 0].
pub const FAST_EXP_MAX_RELATIVE_ERROR: f32 = 1e-5;

/// `acos(x)` in radians for `x` clamped to [−1, 1], by the polynomial of Abramowitz &
/// Stegun 4.4.45 (`√(1 − x)·(a₀ + a₁x + a₂x² + a₃x³)`, error ≤ 6.8e−5 rad).
#[inline(always)]
pub fn fast_acos(x: f32) -> f32 {
    acos_lanes(x)
}

/// [`fast_acos`] in every lane (the same operations, so the same bits in each lane).
#[inline(always)]
pub(crate) fn acos_lanes<W: Wide>(x: W) -> W {
    let x = clamp(x, -1.0, 1.0);
    let magnitude = x.abs();
    let polynomial = W::splat(1.570_728_8)
        + magnitude
            * (W::splat(-0.212_114_4)
                + magnitude * (W::splat(0.074_261) + magnitude * -0.018_729_3));
    let angle = (W::splat(1.0) - magnitude).sqrt() * polynomial;
    W::select(x.cmplt(W::splat(0.0)), W::splat(PI) - angle, angle)
}

/// `e^x` for `x` in [−87, 0] (clamped there: the scores only need non-positive
/// exponents), as `2^n · 2^f` with `2^f` by a degree-5 polynomial and `2^n` built from the
/// float's exponent bits. Relative error below 1e−5.
#[inline(always)]
pub fn fast_exp(x: f32) -> f32 {
    exp_lanes(x)
}

/// [`fast_exp`] in every lane (the same operations, so the same bits in each lane).
#[inline(always)]
pub(crate) fn exp_lanes<W: Wide>(x: W) -> W {
    // Round t to the nearest integer n with the 1.5·2²³ trick (no float→int cast, so a
    // loop of these vectorises).
    const MAGIC: f32 = 12_582_912.0;
    let t = clamp(x, -87.0, 0.0) * std::f32::consts::LOG2_E;
    let whole = (t + MAGIC) - MAGIC;
    let f = t - whole;
    // 2^f on [−½, ½]: its Taylor polynomial of degree 5 (error < 3e−6 there).
    let p = W::splat(1.0)
        + f * (W::splat(std::f32::consts::LN_2)
            + f * (W::splat(0.240_226_5)
                + f * (W::splat(0.055_504_1) + f * (W::splat(0.009_618_1) + f * 0.001_333_6))));
    // 2^n: n + 127 is in [1, 127] as t ≥ −125.6.
    p * whole.exp2_whole()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fast_acos_is_within_its_bound_everywhere() {
        let mut worst = 0.0f32;
        for i in 0..=200_000 {
            let x = -1.0 + 2.0 * i as f32 / 200_000.0;
            worst = worst.max((fast_acos(x) - (x as f64).acos() as f32).abs());
        }
        assert!(worst <= FAST_ACOS_MAX_ERROR, "worst error {worst}");
        assert_eq!(fast_acos(2.0), fast_acos(1.0));
        assert!(fast_acos(1.0).abs() < 1e-6);
        assert!((fast_acos(-1.0) - PI).abs() < 1e-4);
    }

    /// The lane forms give the scalar functions' bits in every lane.
    fn lanes_equal_scalar<W: Wide>() {
        let inputs: Vec<f32> = (0..=4000).map(|i| -2.0 + i as f32 / 1000.0).collect();
        for chunk in inputs.chunks_exact(W::LANES) {
            let (acos, exp) = (acos_lanes(W::load(chunk)), exp_lanes(W::load(chunk) * 30.0));
            for (i, &x) in chunk.iter().enumerate() {
                assert_eq!(acos.lane(i).to_bits(), fast_acos(x).to_bits(), "acos {x}");
                assert_eq!(
                    exp.lane(i).to_bits(),
                    fast_exp(x * 30.0).to_bits(),
                    "exp {x}"
                );
            }
        }
    }

    #[test]
    fn lane_forms_equal_the_scalar_functions_at_every_width() {
        crate::math::wide::for_every_width!(lanes_equal_scalar());
    }

    #[test]
    fn fast_exp_is_within_its_bound_on_the_scores_domain() {
        let mut worst = 0.0f64;
        for i in 0..=200_000 {
            let x = -87.0 * i as f64 / 200_000.0;
            let exact = x.exp();
            let relative = ((f64::from(fast_exp(x as f32)) - exact) / exact).abs();
            worst = worst.max(relative);
        }
        assert!(
            worst <= f64::from(FAST_EXP_MAX_RELATIVE_ERROR),
            "worst {worst}"
        );
        assert!((fast_exp(0.0) - 1.0).abs() < 1e-6);
        assert_eq!(fast_exp(5.0), fast_exp(0.0));
    }
}
