//! Many blends at once: DLB and DIB computed on several joints side by side, one joint per
//! SIMD lane, 4, 8 or 16 at a time (`math::wide::run_widest` picks the width), on
//! [`DualQuatLanes`]. Every lane computes the same operations whatever the width, so a
//! joint's blend does not depend on the width or on its neighbours.

use super::aligned_sum::{dlb_by, CANCELLED_SUM};
use super::settings::{DibOutcome, DibSettings};
use crate::math::dualquat::DualQuat;
use crate::math::lanes::{mask, DualQuatLanes, Floats, MAX_LANES};
use crate::math::wide::Wide;

/// The keys of a group of joints: key `k` with one joint per lane. Implementations are
/// `#[inline(always)]`, so that reading a key compiles inside the width-specific caller.
pub(crate) trait LaneKeys<W> {
    /// Key `k` of the group.
    fn key(&self, k: usize) -> DualQuatLanes<W>;
}

/// Keys gathered beforehand, key `k` at index `k`.
impl<W: Copy> LaneKeys<W> for [DualQuatLanes<W>] {
    #[inline(always)]
    fn key(&self, k: usize) -> DualQuatLanes<W> {
        self[k]
    }
}

/// The group of joints `start ..` of a pose whose joint `j` of key `k` is `input(k, j)`; lanes
/// past the last joint repeat it.
pub(crate) struct PoseKeys<'a, F> {
    /// Joint `j` of key `k`.
    pub(crate) input: &'a F,
    /// Joints per key.
    pub(crate) joint_count: usize,
    /// The group's first joint.
    pub(crate) start: usize,
}

impl<W: Wide, F: Fn(usize, usize) -> DualQuat> LaneKeys<W> for PoseKeys<'_, F> {
    #[inline(always)]
    fn key(&self, k: usize) -> DualQuatLanes<W> {
        let last = self.joint_count.saturating_sub(1);
        DualQuatLanes::gather(|lane| (self.input)(k, (self.start + lane).min(last)))
    }
}

/// DLB of `W::LANES` joints: `input(k)` gives key `k` of them, `weights` are checked and
/// shared. Signs align to the first input with a non-zero weight; a lane whose aligned sum
/// cancels is redone by the scalar DLB (which moves its pivot).
#[inline(always)]
pub(crate) fn dlb_lanes<W: Wide>(
    weights: &[f32],
    input: &(impl LaneKeys<W> + ?Sized),
) -> DualQuatLanes<W> {
    // The pivot is the first input with weight: the first one summed.
    let mut pivot = None;
    let mut sum = DualQuatLanes::zero();
    let mut total = 0.0;
    let inverse_total = super::inverse_total(weights);
    for (k, &weight) in weights.iter().enumerate() {
        if weight > 0.0 {
            let weight = super::unit_weight(weight, inverse_total);
            let q = input.key(k);
            let pivot = *pivot.get_or_insert(q);
            let w = Floats::splat(weight);
            let signed = Floats::select(q.real_dot(pivot).cmplt(Floats::zero()), -w, w);
            sum = sum.add_scaled(q, signed);
            total += weight;
        }
    }
    let limit = CANCELLED_SUM * total;
    let cancelled = sum.real_dot(sum).cmplt(Floats::splat(limit * limit));
    if cancelled.any() {
        return sum.normalize().replace_lanes(cancelled, |lane, _| {
            dlb_by(weights, |k| input.key(k).lane(lane))
        });
    }
    sum.normalize()
}

/// DIB (Algorithm 1) of `W::LANES` joints at once, each lane stopping when its own
/// `‖x̂‖ < p`: the per-lane results are exactly what [`super::iterative`] documents.
/// `inverse_total` is `1 / Σ w_k`; lanes `lanes_used..` are padding and ignored; `write(i, …)`
/// receives the outcome of each lane `i < lanes_used`.
#[inline(always)]
pub(crate) fn dib_lanes<W: Wide>(
    weights: &[f32],
    inverse_total: f64,
    settings: &DibSettings,
    lanes_used: usize,
    input: &(impl LaneKeys<W> + ?Sized),
    mut write: impl FnMut(usize, &DibOutcome),
) {
    let precision = Floats::splat(settings.precision);
    let mut blend = dlb_lanes(weights, input);
    let mut best = blend;
    let mut best_residual = Floats::splat(f32::INFINITY);
    let mut result = blend;
    let mut result_residual = Floats::zero();
    let mut result_iterations = [0u32; MAX_LANES];
    let mut done = mask::<W>(|lane| lane >= lanes_used);
    let mut converged = mask::<W>(|_| false);
    for iteration in 1..=settings.max_iterations {
        let inverse = blend.conjugate();
        let mut step = DualQuatLanes::zero();
        for (k, &weight) in weights.iter().enumerate() {
            if weight > 0.0 {
                let w = Floats::splat(super::unit_weight(weight, inverse_total));
                step = step.add_pure_scaled(inverse.mul(input.key(k)).log(), w);
            }
        }
        let residual = step.length();
        let improved = residual.cmplt(best_residual);
        best = DualQuatLanes::select(improved, blend, best);
        best_residual = Floats::select(improved, residual, best_residual);
        let next = blend.mul(step.exp()).normalize();
        let newly = residual.cmplt(precision) & !done;
        result = DualQuatLanes::select(newly, next, result);
        result_residual = Floats::select(newly, residual, result_residual);
        if newly.any() {
            for (lane, iterations) in result_iterations.iter_mut().enumerate().take(W::LANES) {
                if newly.test(lane) {
                    *iterations = iteration;
                }
            }
        }
        converged |= newly;
        done |= newly;
        if done.all() {
            break;
        }
        blend = next;
    }
    let residuals = Floats::select(converged, result_residual, best_residual);
    DualQuatLanes::select(converged, result, best).scatter(|lane, blend| {
        if lane < lanes_used {
            let converged = converged.test(lane);
            write(
                lane,
                &DibOutcome {
                    blend,
                    residual: residuals.lane(lane),
                    iterations: if converged {
                        result_iterations[lane]
                    } else {
                        settings.max_iterations
                    },
                    converged,
                },
            );
        }
    });
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::lanes::tests::random_transform;
    use crate::math::random::Random;
    use crate::math::wide::for_every_width;
    use glam::Vec4;

    /// A joint's DIB does not depend on the width it was computed at: the same bits in a
    /// lane of 4, 8 or 16.
    #[test]
    fn dib_gives_the_same_bits_at_every_width() {
        let mut random = Random::new(14);
        let weights = [0.2, 0.5, 0.3];
        let keys: Vec<Vec<DualQuat>> = (0..3)
            .map(|_| {
                (0..16)
                    .map(|_| random_transform(&mut random, 1.5))
                    .collect()
            })
            .collect();
        let settings = DibSettings::default();
        fn run<W: Wide>(
            keys: &[Vec<DualQuat>],
            weights: &[f32],
            settings: &DibSettings,
        ) -> Vec<DibOutcome> {
            let mut out = Vec::new();
            for start in (0..16).step_by(W::LANES) {
                let gathered: Vec<DualQuatLanes<W>> = keys
                    .iter()
                    .map(|key| DualQuatLanes::gather(|i| key[start + i]))
                    .collect();
                dib_lanes(weights, 1.0, settings, W::LANES, &gathered[..], |_, o| {
                    out.push(*o)
                });
            }
            out
        }
        let four = run::<Vec4>(&keys, &weights, &settings);
        assert_eq!(four.len(), 16);
        assert!(four.iter().all(|o| o.converged && o.iterations >= 1));
        fn same_as_four<W: Wide>(
            four: &[DibOutcome],
            keys: &[Vec<DualQuat>],
            weights: &[f32],
            settings: &DibSettings,
        ) {
            assert_eq!(run::<W>(keys, weights, settings), four);
        }
        for_every_width!(same_as_four(&four, &keys, &weights, &settings));
    }
}
