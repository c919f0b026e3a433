//! DLB of one transform in scalar code: the weighted sum of the inputs flipped into the
//! pivot's hemisphere, and its normalisation (see [`super::linear`] for the rule). The lane
//! version falls back to it for lanes whose sum cancels.

use super::{inverse_total, unit_weight};
use crate::math::dualquat::DualQuat;

/// Below this fraction of `Σ w_k`, the aligned sum's real part is taken as cancelled and the
/// pivot moves to the largest weight (the lane version uses it too).
pub(crate) const CANCELLED_SUM: f32 = 1e-3;

/// DLB of the inputs `input(0) .. input(weights.len() − 1)`, weights already checked.
#[inline]
pub(crate) fn dlb_by(weights: &[f32], input: impl Fn(usize) -> DualQuat) -> DualQuat {
    let pivot = weights.iter().position(|&w| w > 0.0).unwrap_or(0);
    let inverse_total = inverse_total(weights);
    let (sum, total) = aligned_sum(weights, inverse_total, &input, input(pivot));
    if sum.real.length_squared() > (CANCELLED_SUM * total) * (CANCELLED_SUM * total) {
        return normalize(sum);
    }
    let heaviest = weights
        .iter()
        .enumerate()
        .fold(0, |best, (k, &w)| if w > weights[best] { k } else { best });
    normalize(aligned_sum(weights, inverse_total, &input, input(heaviest)).0)
}

/// `Σ w_k (±q̂_k)` with each sign chosen so that `q₀,k` lies in the pivot's hemisphere, and
/// `Σ w_k`, the weights divided by their sum first (`inverse_total`).
#[inline]
fn aligned_sum(
    weights: &[f32],
    inverse_total: f64,
    input: &impl Fn(usize) -> DualQuat,
    pivot: DualQuat,
) -> (DualQuat, f32) {
    let mut sum = DualQuat::ZERO;
    let mut total = 0.0;
    for (k, &weight) in weights.iter().enumerate() {
        let weight = unit_weight(weight, inverse_total);
        let q = input(k);
        let signed = if q.real.dot(pivot.real) < 0.0 {
            -weight
        } else {
            weight
        };
        sum = sum + q * signed;
        total += weight;
    }
    (sum, total)
}

/// `q̂ / ‖q̂‖` for a sum known to have a non-zero real part (NaN inputs stay NaN).
#[inline]
fn normalize(sum: DualQuat) -> DualQuat {
    let inverse = sum.real.length_recip();
    let real = sum.real * inverse;
    let dual = sum.dual * inverse;
    DualQuat::from_parts(real, dual - real * real.dot(dual))
}
