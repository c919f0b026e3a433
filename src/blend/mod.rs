//! Blending rigid transforms with dual quaternions, and view-adaptive animation (Chaudhuri,
//! Papagiannakis & Magnenat-Thalmann): DLB, DIB, key clips, key cameras and the view blender.
//!
//! - [`linear`](crate::blend::linear): dual quaternion linear blending, DLB (equation 4), one transform or a pose.
//! - [`iterative`](crate::blend::iterative): dual quaternion iterative blending, DIB (Algorithm 1), one or a pose.
//! - [`clip`](crate::blend::clip): key animations (clips of poses) and their sampling at a time.
//! - [`view`](crate::blend::view): the [`ViewBlender`](crate::blend::ViewBlender): key cameras, view weights (equation 2), the blended pose
//!   (equation 3).
//! - [`projection`](crate::blend::projection): the viewer's position from a 3×4 camera matrix `P = K[R|t]`.
//!
//! Inputs are unit dual quaternions ([`DualQuat`](crate::math::dualquat::DualQuat), or anything [`AsDualQuat`](crate::blend::AsDualQuat)); weights are
//! non-negative, not all zero, and are divided by their sum. Nothing here allocates except
//! building a [`view::ViewBlender`](crate::blend::view::ViewBlender) and giving it clips and cameras.

mod aligned_sum;
pub mod clip;
pub mod iterative;
mod lanes;
pub mod linear;
pub mod projection;
mod settings;
pub mod view;

pub use clip::KeyClip;
pub use iterative::{blend_pose_dib, dib, DibOutcome, DibSettings, PoseOutcome};
pub use linear::{blend_pose_dlb, dlb};
pub use projection::camera_centre_from_projection;
pub use view::{BlendMethod, KeyCamera, ViewBlender, ViewBlenderConfig, ViewDistance};

use crate::error::{Error, Result};
use crate::math::dualquat::DualQuat;

/// How many joints the pose blends (DLB, DIB, ScLERP of two keys) compute side by side on
/// this processor, one per SIMD lane: 16 where it has AVX-512F, 8 with AVX, else 4 (SSE2 on
/// x86-64, NEON or plain floats elsewhere). Chosen at run time; every width gives the same
/// bits, so results do not depend on it.
pub fn simd_lanes() -> usize {
    crate::math::wide::widest_lanes()
}

/// An element the blenders read as a unit dual quaternion. Implemented by [`DualQuat`]
/// (taken as is: it must already be unit) and by the C ABI's `cg_dualquat` (normalised on
/// reading), so C arrays are blended in place without a copy.
pub trait AsDualQuat: Copy {
    /// The unit dual quaternion this element holds.
    fn as_dual_quat(self) -> DualQuat;
}

impl AsDualQuat for DualQuat {
    #[inline]
    fn as_dual_quat(self) -> DualQuat {
        self
    }
}

/// Checks blend weights `w_k` against `input_count` inputs: one weight per input, at least
/// one input, every weight finite and `≥ 0`, and a positive sum. Returns `1 / Σ w_k`, the
/// factor that makes them convex.
///
/// Errors: [`Error::InvalidArgument`] (counts, a negative weight, a zero sum),
/// [`Error::NonFinite`] (a NaN or infinite weight).
pub fn check_weights(input_count: usize, weights: &[f32]) -> Result<f64> {
    if input_count == 0 {
        return Err(Error::InvalidArgument(
            "nothing to blend: the input count is 0".into(),
        ));
    }
    if weights.len() != input_count {
        return Err(Error::InvalidArgument(format!(
            "{} weights for {input_count} inputs",
            weights.len()
        )));
    }
    let mut total = 0.0f64;
    for (index, &weight) in weights.iter().enumerate() {
        if !weight.is_finite() {
            return Err(Error::NonFinite(format!("weight {index} is {weight}")));
        }
        if weight < 0.0 {
            return Err(Error::InvalidArgument(format!(
                "weight {index} is {weight}, weights must be >= 0"
            )));
        }
        total += f64::from(weight);
    }
    if total <= 0.0 {
        return Err(Error::InvalidArgument("the weights sum to 0".into()));
    }
    Ok(1.0 / total)
}

/// `1 / Σ w_k`, summed in `f64` so that weights near `f32::MAX` do not overflow.
#[inline]
pub(crate) fn inverse_total(weights: &[f32]) -> f64 {
    1.0 / weights.iter().map(|&w| f64::from(w)).sum::<f64>()
}

/// The weight `w_k / Σ w_k` in `[0, 1]`: the blenders sum weighted inputs with these, so
/// that huge weights cannot overflow and tiny ones cannot vanish.
#[inline]
pub(crate) fn unit_weight(weight: f32, inverse_total: f64) -> f32 {
    (f64::from(weight) * inverse_total) as f32
}

/// Checks the layout of a pose blend: `keys` holds `key_count × joint_count` dual quaternions,
/// key-major (joint `j` of key `k` at `k · joint_count + j`), and the output holds
/// `joint_count`.
pub(crate) fn check_pose_layout(
    keys_len: usize,
    key_count: usize,
    joint_count: usize,
    out_len: usize,
) -> Result<()> {
    let expected = key_count.checked_mul(joint_count).ok_or_else(|| {
        Error::InvalidArgument(format!("{key_count} keys × {joint_count} joints overflows"))
    })?;
    if keys_len != expected {
        return Err(Error::InvalidArgument(format!(
            "{keys_len} key transforms, expected {key_count} keys × {joint_count} joints = {expected}"
        )));
    }
    if out_len != joint_count {
        return Err(Error::InvalidArgument(format!(
            "output holds {out_len} joints, expected {joint_count}"
        )));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn weights_are_checked() {
        assert_eq!(check_weights(2, &[1.0, 3.0]).unwrap(), 0.25);
        assert!(matches!(
            check_weights(0, &[]),
            Err(Error::InvalidArgument(_))
        ));
        assert!(matches!(
            check_weights(2, &[1.0]),
            Err(Error::InvalidArgument(_))
        ));
        assert!(matches!(
            check_weights(2, &[1.0, -0.5]),
            Err(Error::InvalidArgument(_))
        ));
        assert!(matches!(
            check_weights(2, &[0.0, 0.0]),
            Err(Error::InvalidArgument(_))
        ));
        assert!(matches!(
            check_weights(2, &[f32::NAN, 1.0]),
            Err(Error::NonFinite(_))
        ));
        // Huge weights do not overflow the sum.
        assert!(check_weights(2, &[f32::MAX, f32::MAX]).is_ok());
    }

    #[test]
    fn pose_layout_is_checked() {
        assert!(check_pose_layout(6, 2, 3, 3).is_ok());
        assert!(check_pose_layout(5, 2, 3, 3).is_err());
        assert!(check_pose_layout(6, 2, 3, 2).is_err());
        assert!(check_pose_layout(0, usize::MAX, 2, 2).is_err());
        assert!(check_pose_layout(0, 3, 0, 0).is_ok());
    }
}
