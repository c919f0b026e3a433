//! Dual quaternion iterative blending, DIB (Kavan et al.; Chaudhuri et al., Algorithm 1), for
//! one transform or a whole pose:
//!
//! ```text
//! b̂ = DLB(q̂_k, w_k)
//! repeat  x̂ = Σ w_k log(b̂* q̂_k);  b̂ = b̂ exp(x̂)   until ‖x̂‖ < p
//! ```
//!
//! The result is the weighted mean of the transforms in the screw metric: it is rigid,
//! invariant to the coordinate system (`DIB(T q̂_k) = T DIB(q̂_k)`), and for two inputs equals
//! ScLERP ([`DualQuat::sclerp`]). Each `log` takes the shorter screw (`b̂* q̂_k` flipped to
//! `real.w ≥ 0`), so antipodal inputs blend the short way. With one or two inputs of non-zero
//! weight the fixed point is known in closed form (the input; ScLERP, where `x̂ = 0` exactly),
//! and it is returned without iterating.
//!
//! The loop is the paper's: each iteration computes `x̂` at the current `b̂`, applies it, and
//! stops once `‖x̂‖ < p`, so the result carries that last small correction. At most
//! `max_iterations` iterations run; if `‖x̂‖ < p` is not reached by then, the iterate with the
//! smallest measured `‖x̂‖` is returned and flagged as not converged.
//!
//! `‖x̂‖` is the Euclidean norm of the 8 components: half-angles in radians and
//! half-translations in the inputs' length unit. The iteration runs in f32, 4, 8 or 16 joints
//! at a time in SIMD lanes (see [`super::simd_lanes`]; the same bits at every width), to stay
//! within the frame budget, so `‖x̂‖` cannot go below f32 rounding: about 1e−7 plus 1e−7 ×
//! the translations' size. p = 1e−6 suits metres; with centimetres use 1e−4 (the same 1 µm).

use super::lanes::{dib_lanes, LaneKeys, PoseKeys};
pub use super::settings::{DibOutcome, DibSettings, PoseOutcome, MAX_ITERATIONS_LIMIT};
use super::{check_pose_layout, check_weights, AsDualQuat};
use crate::error::{Error, Result};
use crate::math::dualquat::DualQuat;
use crate::math::lanes::DualQuatLanes;
use crate::math::wide::{run_widest, LaneJob, Wide};

/// DIB of `inputs` (unit dual quaternions) with weights `w_k` (finite, `≥ 0`, not all zero;
/// divided by their sum). For one input it returns that input; for two it equals ScLERP.
///
/// Errors: bad weights or counts (see [`check_weights`]) or settings
/// ([`DibSettings::validate`]). Not converging is not an error here: see
/// [`DibOutcome::converged`] and [`DibOutcome::into_result`].
pub fn dib<Q: AsDualQuat>(
    inputs: &[Q],
    weights: &[f32],
    settings: &DibSettings,
) -> Result<DibOutcome> {
    settings.validate()?;
    let inverse_total = check_weights(inputs.len(), weights)?;
    let mut outcome = None;
    dib_joints(
        weights,
        inverse_total,
        settings,
        1,
        |k, _| inputs[k].as_dual_quat(),
        |_, joint_outcome| outcome = Some(*joint_outcome),
    );
    outcome.ok_or_else(|| Error::Internal("DIB produced no result".into()))
}

/// DIB of a whole pose, with the layout of [`super::blend_pose_dlb`] (key-major `keys`, joint
/// `j` of key `k` at `k · joint_count + j`). Every joint of `out` is written, converged or
/// not; the outcome says how many did not converge. Allocates nothing.
///
/// Errors: bad weights, layout or settings; nothing is written then.
pub fn blend_pose_dib<Q: AsDualQuat, O: From<DualQuat>>(
    keys: &[Q],
    weights: &[f32],
    joint_count: usize,
    settings: &DibSettings,
    out: &mut [O],
) -> Result<PoseOutcome> {
    settings.validate()?;
    check_pose_layout(keys.len(), weights.len(), joint_count, out.len())?;
    let inverse_total = check_weights(weights.len(), weights)?;
    let mut outcome = PoseOutcome::default();
    dib_joints(
        weights,
        inverse_total,
        settings,
        joint_count,
        |k, joint| keys[k * joint_count + joint].as_dual_quat(),
        |joint, joint_outcome| {
            outcome.add(joint_outcome);
            out[joint] = joint_outcome.blend.into();
        },
    );
    Ok(outcome)
}

/// Most keys whose joint groups are gathered once on the stack; beyond, they are
/// gathered again at each iteration.
const GATHERED_KEYS: usize = 8;

/// Algorithm 1 for `joint_count` joints sharing `weights` (already checked;
/// `inverse_total = 1 / Σ w_k`), where `input(k, j)` is joint `j` of key `k`; `write(j, …)`
/// receives each joint's outcome. Joints run side by side in SIMD lanes, as many as the
/// processor's widest vectors hold (see [`run_widest`]).
pub(crate) fn dib_joints(
    weights: &[f32],
    inverse_total: f64,
    settings: &DibSettings,
    joint_count: usize,
    input: impl Fn(usize, usize) -> DualQuat,
    write: impl FnMut(usize, &DibOutcome),
) {
    run_widest(DibJoints {
        weights,
        inverse_total,
        settings,
        joint_count,
        input,
        write,
    })
}

/// The arguments of [`dib_joints`], run at a lane width.
struct DibJoints<'a, I, O> {
    weights: &'a [f32],
    inverse_total: f64,
    settings: &'a DibSettings,
    joint_count: usize,
    input: I,
    write: O,
}

impl<I, O> LaneJob for DibJoints<'_, I, O>
where
    I: Fn(usize, usize) -> DualQuat,
    O: FnMut(usize, &DibOutcome),
{
    type Output = ();

    #[inline(always)]
    fn run<W: Wide>(self) {
        let DibJoints {
            weights,
            inverse_total,
            settings,
            joint_count,
            input,
            mut write,
        } = self;
        let group = |start: usize| PoseKeys {
            input: &input,
            joint_count,
            start,
        };
        // One or two inputs with weight: the fixed point is known in closed form (the input,
        // or ScLERP, where `x̂ = 0` exactly), so no iteration is needed.
        let mut active = weights.iter().enumerate().filter(|(_, &w)| w > 0.0);
        match (active.next(), active.next(), active.next()) {
            (Some((only, _)), None, _) => {
                for joint in 0..joint_count {
                    let q = input(only, joint);
                    write(
                        joint,
                        &DibOutcome::closed_form(q.try_normalize().unwrap_or(q)),
                    );
                }
                return;
            }
            (Some((first, &w_first)), Some((second, &w_second)), None) => {
                let t = (f64::from(w_second) / (f64::from(w_first) + f64::from(w_second))) as f32;
                for start in (0..joint_count).step_by(W::LANES) {
                    let used = joint_count - start;
                    let keys = group(start);
                    LaneKeys::<W>::key(&keys, first)
                        .sclerp(keys.key(second), t)
                        .scatter(|lane, blend| {
                            if lane < used {
                                write(start + lane, &DibOutcome::closed_form(blend));
                            }
                        });
                }
                return;
            }
            _ => {}
        }
        let mut gathered = [DualQuatLanes::<W>::zero(); GATHERED_KEYS];
        for start in (0..joint_count).step_by(W::LANES) {
            let lanes_used = (joint_count - start).min(W::LANES);
            let write_joint = |lane: usize, outcome: &DibOutcome| write(start + lane, outcome);
            if weights.len() <= GATHERED_KEYS {
                for (k, slot) in gathered.iter_mut().enumerate().take(weights.len()) {
                    if weights[k] > 0.0 {
                        *slot = group(start).key(k);
                    }
                }
                dib_lanes::<W>(
                    weights,
                    inverse_total,
                    settings,
                    lanes_used,
                    &gathered[..],
                    write_joint,
                );
            } else {
                dib_lanes::<W>(
                    weights,
                    inverse_total,
                    settings,
                    lanes_used,
                    &group(start),
                    write_joint,
                );
            }
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

    fn same(a: DualQuat, b: DualQuat, tolerance: f32) -> bool {
        (a - b).length() <= tolerance || (a + b).length() <= tolerance
    }

    #[test]
    fn huge_and_tiny_weights_blend_like_unit_ones() {
        // Found by the fuzz target: weights near f32::MAX overflowed into NaN.
        let a = transform(Vec3::Y, 0.4, Vec3::new(1.0, 0.0, 2.0));
        let b = transform(Vec3::X, -0.3, Vec3::new(-3.0, 1.0, 0.0));
        let c = transform(Vec3::Z, 0.9, Vec3::new(0.0, 2.0, 1.0));
        let settings = DibSettings::default();
        for inputs in [&[a, b][..], &[a, b, c]] {
            let unit = dib(inputs, &[1.0, 3.0, 2.0][..inputs.len()], &settings).unwrap();
            for scale in [f32::MAX / 3.0, 1.0e-40] {
                let weights: Vec<f32> = [1.0, 3.0, 2.0][..inputs.len()]
                    .iter()
                    .map(|w| w * scale)
                    .collect();
                let blended = dib(inputs, &weights, &settings).unwrap();
                assert!(
                    same(blended.blend, unit.blend, 1e-5),
                    "{weights:?}: {blended:?}"
                );
            }
        }
    }

    #[test]
    fn one_input_is_returned_at_once() {
        let q = transform(Vec3::X, 2.0, Vec3::new(4.0, 5.0, 6.0));
        let outcome = dib(&[q], &[1.0], &DibSettings::default()).unwrap();
        assert!(outcome.converged);
        assert_eq!(outcome.iterations, 0);
        assert!(same(outcome.blend, q, 1e-6));
    }

    #[test]
    fn two_inputs_give_sclerp() {
        let a = transform(Vec3::new(1.0, 2.0, 0.5), 0.4, Vec3::new(0.2, 0.0, 1.0));
        let b = transform(Vec3::new(-1.0, 0.5, 0.0), 1.9, Vec3::new(1.5, -0.7, 0.3));
        for t in [0.0f32, 0.1, 0.5, 0.8, 1.0] {
            // The closed form, and the iteration itself (b split into two equal inputs, so
            // that three inputs have weight).
            let closed = dib(&[a, b], &[1.0 - t, t], &DibSettings::default()).unwrap();
            assert!(closed.converged);
            assert!(same(closed.blend, a.sclerp(b, t), 1e-6), "t = {t}");
            if t > 0.0 && t < 1.0 {
                let weights = [1.0 - t, t / 2.0, t / 2.0];
                let iterated = dib(&[a, b, b], &weights, &DibSettings::default()).unwrap();
                assert!(iterated.converged && iterated.iterations > 0);
                assert!(same(iterated.blend, a.sclerp(b, t), 1e-5), "t = {t}");
            }
        }
    }

    #[test]
    fn the_residual_is_below_the_precision_in_any_unit() {
        // Metres with p = 1e−6, and the same poses in centimetres with p = 1e−4.
        for (scale, precision) in [(1.0f32, 1e-6f32), (100.0, 1e-4)] {
            let inputs = [
                transform(Vec3::Y, 0.5, Vec3::new(1.0, 0.0, 0.0) * scale),
                transform(Vec3::Z, -0.9, Vec3::new(0.0, 2.5, 0.0) * scale),
                transform(Vec3::X, 1.2, Vec3::new(0.0, 0.0, -0.8) * scale),
            ];
            let settings = DibSettings {
                precision,
                max_iterations: 50,
            };
            let outcome = dib(&inputs, &[0.2, 0.3, 0.5], &settings).unwrap();
            assert!(outcome.converged, "{outcome:?}");
            assert!(outcome.residual < precision);
            assert!(outcome.blend.is_unit(1e-6));
        }
    }

    #[test]
    fn running_out_of_iterations_is_reported_with_the_best_iterate() {
        let inputs = [
            transform(Vec3::Y, 0.0, Vec3::ZERO),
            transform(Vec3::Y, 2.5, Vec3::new(3.0, 0.0, 0.0)),
            transform(Vec3::X, 2.0, Vec3::new(0.0, 3.0, 0.0)),
        ];
        let weights = [0.3, 0.4, 0.3];
        let settings = DibSettings {
            precision: 1e-6,
            max_iterations: 1,
        };
        let outcome = dib(&inputs, &weights, &settings).unwrap();
        assert!(!outcome.converged);
        assert!(outcome.residual >= 1e-6);
        assert_eq!(outcome.iterations, 1);
        // With one iteration, the only measured iterate is DLB.
        let dlb = super::super::dlb(&inputs, &weights).unwrap();
        assert!(same(outcome.blend, dlb, 1e-6));
        assert!(matches!(
            outcome.into_result(&settings),
            Err(Error::NotConverged(_))
        ));
    }

    #[test]
    fn settings_are_checked() {
        let q = [DualQuat::IDENTITY];
        for (precision, max_iterations) in [
            (0.0, 4),
            (-1.0, 4),
            (1e-6, 0),
            (1e-6, MAX_ITERATIONS_LIMIT + 1),
        ] {
            let settings = DibSettings {
                precision,
                max_iterations,
            };
            assert!(matches!(
                dib(&q, &[1.0], &settings),
                Err(Error::InvalidArgument(_))
            ));
        }
        let nan = DibSettings {
            precision: f32::NAN,
            max_iterations: 4,
        };
        assert!(matches!(dib(&q, &[1.0], &nan), Err(Error::NonFinite(_))));
    }
}
