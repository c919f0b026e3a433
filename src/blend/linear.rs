//! Dual quaternion linear blending, DLB (Kavan et al.; Chaudhuri et al., equation 4):
//! `DLB(q̂_k, w_k) = Σ w_k q̂_k / ‖Σ w_k q̂_k‖`, for one transform or a whole pose.
//!
//! `q̂` and `−q̂` are the same transform, so before summing each input is flipped into the
//! hemisphere of the *pivot*: the first input with a non-zero weight (`q₀,k · q₀,pivot ≥ 0`).
//! Antipodal inputs thus blend the short way. Should the aligned sum still nearly cancel
//! (inputs spread over more than a half-turn with most of the weight away from the pivot),
//! the sum is redone with the largest weight's input as pivot, which cannot cancel; DLB
//! therefore never fails on valid weights. `‖·‖` is the dual quaternion norm: the result has
//! a unit real part and a dual part orthogonal to it, a rigid transform.

use super::aligned_sum::dlb_by;
use super::lanes::{dlb_lanes, PoseKeys};
use super::{check_pose_layout, check_weights, AsDualQuat};
use crate::error::Result;
use crate::math::dualquat::DualQuat;
use crate::math::wide::{run_widest, LaneJob, Wide};

/// DLB of `inputs` (unit dual quaternions) with weights `w_k`: one weight per input, finite,
/// `≥ 0`, not all zero (they need not sum to 1: DLB is scale invariant).
///
/// Errors: [`crate::Error::InvalidArgument`] or [`crate::Error::NonFinite`] for bad weights or
/// counts (see [`check_weights`]).
pub fn dlb<Q: AsDualQuat>(inputs: &[Q], weights: &[f32]) -> Result<DualQuat> {
    check_weights(inputs.len(), weights)?;
    Ok(dlb_by(weights, |k| inputs[k].as_dual_quat()))
}

/// DLB of a whole pose: `keys` holds `weights.len()` key poses of `joint_count` joints each,
/// key-major (joint `j` of key `k` at `keys[k · joint_count + j]`); joint `j` of `out` gets the
/// DLB of the keys' joint `j` with the shared weights. Allocates nothing.
///
/// Errors: bad weights (see [`check_weights`]), or [`crate::Error::InvalidArgument`] if
/// `keys.len() != weights.len() · joint_count` or `out.len() != joint_count`. Nothing is
/// written on error.
pub fn blend_pose_dlb<Q: AsDualQuat, O: From<DualQuat>>(
    keys: &[Q],
    weights: &[f32],
    joint_count: usize,
    out: &mut [O],
) -> Result<()> {
    check_pose_layout(keys.len(), weights.len(), joint_count, out.len())?;
    check_weights(weights.len(), weights)?;
    run_widest(PoseDlb {
        keys,
        weights,
        joint_count,
        out,
    });
    Ok(())
}

/// The arguments of [`blend_pose_dlb`], run at a lane width.
struct PoseDlb<'a, Q, O> {
    keys: &'a [Q],
    weights: &'a [f32],
    joint_count: usize,
    out: &'a mut [O],
}

impl<Q: AsDualQuat, O: From<DualQuat>> LaneJob for PoseDlb<'_, Q, O> {
    type Output = ();

    #[inline(always)]
    fn run<W: Wide>(self) {
        let PoseDlb {
            keys,
            weights,
            joint_count,
            out,
        } = self;
        for (chunk, slots) in out.chunks_mut(W::LANES).enumerate() {
            let start = chunk * W::LANES;
            let input = PoseKeys {
                input: &|k: usize, joint: usize| keys[k * joint_count + joint].as_dual_quat(),
                joint_count,
                start,
            };
            dlb_lanes::<W>(weights, &input).scatter(|lane, q| {
                if let Some(slot) = slots.get_mut(lane) {
                    *slot = q.into();
                }
            });
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::{Quat, Vec3};

    fn transform(axis: Vec3, angle: f32, translation: Vec3) -> DualQuat {
        DualQuat::from_rotation_translation(
            Quat::from_axis_angle(axis.normalize(), angle),
            translation,
        )
    }

    #[test]
    fn huge_and_tiny_weights_blend_like_unit_ones() {
        // Found by the fuzz target: weights near f32::MAX overflowed the sum into NaN.
        let a = transform(Vec3::Y, 0.4, Vec3::new(1.0, 0.0, 2.0));
        let b = transform(Vec3::X, -0.3, Vec3::new(-3.0, 1.0, 0.0));
        let unit = dlb(&[a, b], &[1.0, 3.0]).unwrap();
        for weights in [[f32::MAX / 3.0, f32::MAX], [1.0e-40, 3.0e-40]] {
            let blended = dlb(&[a, b], &weights).unwrap();
            assert!((blended - unit).length() < 1e-5, "{weights:?}: {blended:?}");
            let mut pose = [DualQuat::IDENTITY];
            blend_pose_dlb(&[a, b], &weights, 1, &mut pose).unwrap();
            assert!((pose[0] - unit).length() < 1e-5, "{weights:?}: {pose:?}");
        }
    }

    #[test]
    fn one_input_is_returned() {
        let q = transform(Vec3::Y, 0.7, Vec3::new(1.0, 2.0, 3.0));
        let blended = dlb(&[q], &[0.3]).unwrap();
        assert!((blended - q).length() < 1e-6);
    }

    #[test]
    fn equals_the_closed_formula() {
        let inputs = [
            transform(Vec3::Y, 0.3, Vec3::new(0.0, 1.0, 0.0)),
            transform(Vec3::X, -0.5, Vec3::new(0.5, 0.0, 0.2)),
            transform(Vec3::new(1.0, 1.0, 0.0), 1.0, Vec3::new(-1.0, 0.0, 2.0)),
        ];
        let weights = [0.2f32, 0.5, 0.3];
        let mut sum = DualQuat::ZERO;
        for (q, w) in inputs.iter().zip(weights) {
            sum = sum + *q * w;
        }
        let length = sum.real.length();
        let real = sum.real / length;
        let dual = sum.dual / length - real * (real.dot(sum.dual) / length);
        let blended = dlb(&inputs, &weights).unwrap();
        assert!((blended.real - real).length() < 1e-6);
        assert!((blended.dual - dual).length() < 1e-6);
        assert!(blended.is_unit(1e-6));
    }

    #[test]
    fn antipodal_inputs_blend_the_short_way() {
        let a = transform(Vec3::Z, 0.2, Vec3::X);
        let b = transform(Vec3::Z, 0.6, Vec3::X);
        let expected = dlb(&[a, b], &[0.5, 0.5]).unwrap();
        let flipped = dlb(&[a, -b], &[0.5, 0.5]).unwrap();
        assert!((expected - flipped).length() < 1e-6);
        let (rotation, _) = flipped.to_rotation_translation();
        let (axis, angle) = rotation.to_axis_angle();
        assert!((angle - 0.4).abs() < 1e-5 && axis.dot(Vec3::Z) > 0.999);
    }

    #[test]
    fn a_cancelling_sum_moves_the_pivot() {
        // Pivot (weight 0.01) at the identity; the heavy inputs are half-turns about x
        // and −x... which are the same rotation, signs opposite: aligned to the identity
        // (dot 0) they could cancel.
        let pivot = DualQuat::IDENTITY;
        let a = DualQuat::from_rotation(Quat::from_xyzw(1.0, 0.0, 0.0, 0.0));
        let b = DualQuat::from_rotation(Quat::from_xyzw(-1.0, 0.0, 0.0, 0.0));
        let blended = dlb(&[pivot, a, b], &[1e-6, 0.5, 0.5]).unwrap();
        assert!(blended.is_finite());
        assert!(blended.is_unit(1e-5));
        assert!(blended.real.x.abs() > 0.99, "{blended:?}");
    }

    #[test]
    fn pose_blend_is_per_joint() {
        let joints = 3;
        let key_a: Vec<DualQuat> = (0..joints)
            .map(|j| transform(Vec3::Y, 0.1 * j as f32, Vec3::X * j as f32))
            .collect();
        let key_b: Vec<DualQuat> = (0..joints)
            .map(|j| transform(Vec3::Z, -0.2 * j as f32, Vec3::Y))
            .collect();
        let keys: Vec<DualQuat> = key_a.iter().chain(key_b.iter()).copied().collect();
        let weights = [0.25, 0.75];
        let mut out = vec![DualQuat::ZERO; joints];
        blend_pose_dlb(&keys, &weights, joints, &mut out).unwrap();
        for j in 0..joints {
            let expected = dlb(&[key_a[j], key_b[j]], &weights).unwrap();
            assert!((out[j] - expected).length() < 1e-7);
        }
        let mut short = vec![DualQuat::ZERO; joints - 1];
        assert!(blend_pose_dlb(&keys, &weights, joints, &mut short).is_err());
        assert!(short.iter().all(|q| *q == DualQuat::ZERO));
    }
}
