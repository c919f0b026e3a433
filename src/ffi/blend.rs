//! The C ABI of dual quaternion blending: dual quaternion conversions, DLB/DIB of transforms
//! and poses, the camera centre of a projection matrix. It checks, converts and forwards to
//! `crate::blend` and `crate::math::dualquat`.

use glam::{Mat4, Quat};

use super::error::Result;
use super::status::cg_status;
use super::types::{cg_dualquat, cg_quat, cg_vec3};
use super::{borrow, ffi_boundary, non_null, slice, slice_mut, Out};
use crate::blend::{self, AsDualQuat, DibSettings};
use crate::error::Error;
use crate::math::dualquat::DualQuat;

// ---------------------------------------------------------------------------------------------
// Conversions

impl cg_dualquat {
    /// The raw dual quaternion, as given.
    fn raw(self) -> DualQuat {
        DualQuat::from_parts(
            Quat::from_xyzw(self.real.x, self.real.y, self.real.z, self.real.w),
            Quat::from_xyzw(self.dual.x, self.dual.y, self.dual.z, self.dual.w),
        )
    }

    /// Converts to a unit dual quaternion after checking every component is finite and the
    /// real part is not zero.
    pub(crate) fn to_unit(self, what: &str) -> Result<DualQuat> {
        let raw = self.raw();
        if !raw.is_finite() {
            return Err(Error::NonFinite(format!("{what} is not finite: {self:?}")).into());
        }
        let unit = raw.try_normalize().ok_or_else(|| {
            Error::InvalidArgument(format!(
                "{what} has a zero real part, not a rigid transform"
            ))
        })?;
        check_translation(unit.translation(), what)?;
        Ok(unit)
    }
}

/// The longest translation accepted from C, in the caller's units: blends and conversions of
/// transforms up to this far (sums, differences and squared lengths) stay finite in `f32`.
const MAX_TRANSLATION: f32 = 1e18;

/// Fails with [`Error::InvalidArgument`] if `translation` is longer than [`MAX_TRANSLATION`].
pub(super) fn check_translation(
    translation: glam::Vec3,
    what: impl std::fmt::Display,
) -> Result<()> {
    // NaN (from an overflow computing it) fails too.
    if translation.length() <= MAX_TRANSLATION {
        Ok(())
    } else {
        Err(Error::InvalidArgument(format!(
            "{what} has a translation longer than {MAX_TRANSLATION:e}"
        ))
        .into())
    }
}

/// Read by the blenders in place. Only used on arrays checked by `check_all`, so the
/// normalisation cannot fail.
impl AsDualQuat for cg_dualquat {
    #[inline]
    fn as_dual_quat(self) -> DualQuat {
        let raw = self.raw();
        raw.try_normalize().unwrap_or(raw)
    }
}

impl From<DualQuat> for cg_dualquat {
    fn from(q: DualQuat) -> Self {
        cg_dualquat {
            real: q.real.into(),
            dual: q.dual.into(),
        }
    }
}

/// Checks every element of a C array of dual quaternions as [`cg_dualquat::to_unit`] does
/// (allocating only for the message of an error).
pub(super) fn check_all(values: &[cg_dualquat], what: &str) -> Result<()> {
    for (index, value) in values.iter().enumerate() {
        let raw = value.raw();
        if !raw.is_finite() {
            return Err(
                Error::NonFinite(format!("{what}[{index}] is not finite: {value:?}")).into(),
            );
        }
        let Some(unit) = raw.try_normalize() else {
            return Err(Error::InvalidArgument(format!(
                "{what}[{index}] has a zero real part, not a rigid transform"
            ))
            .into());
        };
        check_translation(unit.translation(), format_args!("{what}[{index}]"))?;
    }
    Ok(())
}

/// Fails with [`Error::InvalidArgument`] if the byte ranges of two C arrays overlap (an
/// output may not alias an input).
fn check_disjoint<A, B>(
    input: *const A,
    input_count: usize,
    output: *const B,
    output_count: usize,
    what: &str,
) -> Result<()> {
    let input_start = input as usize;
    let input_end = input_start + input_count * std::mem::size_of::<A>();
    let output_start = output as usize;
    let output_end = output_start + output_count * std::mem::size_of::<B>();
    if input_count > 0 && output_count > 0 && input_start < output_end && output_start < input_end {
        return Err(Error::InvalidArgument(format!("{what} overlaps its input")).into());
    }
    Ok(())
}

/// `key_count × joint_count`, or [`Error::InvalidArgument`] on overflow.
pub(super) fn pose_elements(key_count: usize, joint_count: usize) -> Result<usize> {
    key_count.checked_mul(joint_count).ok_or_else(|| {
        Error::InvalidArgument(format!("{key_count} × {joint_count} overflows")).into()
    })
}

// ---------------------------------------------------------------------------------------------
// Dual quaternions

/// Builds the unit dual quaternion of the rigid transform "rotate by `rotation`, then
/// translate by `translation`" (`x ↦ R x + t`) into `*out`.
///
/// `rotation` is normalised; `translation` is in your length unit. Writes `*out` only on
/// success. Thread-safe.
///
/// Errors: `CG_STATUS_NULL_ARGUMENT` (a NULL pointer), `CG_STATUS_NON_FINITE` (a NaN or
/// infinite component), `CG_STATUS_INVALID_ARGUMENT` (a zero-length rotation, a translation
/// longer than 1e18).
#[no_mangle]
pub unsafe extern "C" fn cg_dualquat_from_rt(
    rotation: *const cg_quat,
    translation: *const cg_vec3,
    out: *mut cg_dualquat,
) -> cg_status {
    ffi_boundary!({
        // SAFETY: the caller passes a writable cg_dualquat (or NULL, rejected).
        let out = unsafe { Out::new(out, "out") }?;
        // SAFETY: the caller passes readable rotation and translation (or NULL).
        let rotation = unsafe { borrow(rotation, "rotation") }?.to_unit("rotation")?;
        // SAFETY: as above.
        let translation =
            unsafe { borrow(translation, "translation") }?.to_finite("translation")?;
        check_translation(translation, "translation")?;
        let result = DualQuat::from_rotation_translation(rotation, translation);
        out.write(result.into());
        Ok(())
    })
}

/// Splits the rigid transform `*dual_quat` (normalised first) into its rotation
/// `*out_rotation` and translation `*out_translation` (your length unit).
///
/// Writes both outputs only on success. Thread-safe.
///
/// Errors: `CG_STATUS_NULL_ARGUMENT` (a NULL pointer), `CG_STATUS_NON_FINITE` (a NaN or
/// infinite component), `CG_STATUS_INVALID_ARGUMENT` (a zero real part, a translation longer
/// than 1e18).
#[no_mangle]
pub unsafe extern "C" fn cg_dualquat_to_rt(
    dual_quat: *const cg_dualquat,
    out_rotation: *mut cg_quat,
    out_translation: *mut cg_vec3,
) -> cg_status {
    ffi_boundary!({
        // SAFETY: the caller passes a writable cg_quat (or NULL, rejected).
        let out_rotation = unsafe { Out::new(out_rotation, "out_rotation") }?;
        // SAFETY: the caller passes a writable cg_vec3 (or NULL, rejected).
        let out_translation = unsafe { Out::new(out_translation, "out_translation") }?;
        // SAFETY: the caller passes a readable cg_dualquat (or NULL).
        let q = unsafe { borrow(dual_quat, "dual_quat") }?.to_unit("dual_quat")?;
        let (rotation, translation) = q.to_rotation_translation();
        out_rotation.write(rotation.into());
        out_translation.write(translation.into());
        Ok(())
    })
}

/// Converts a rigid 4×4 matrix to a unit dual quaternion into `*out`.
///
/// `matrix` points to 16 floats, **column-major** for column vectors (`p' = M p`, translation
/// in elements 12, 13, 14), as OpenGL, glam and Eigen store them. OpenSceneGraph's
/// `osg::Matrixf` (row vectors, translation in its 4th row) has exactly this memory layout:
/// pass `matrix.ptr()` as is. The matrix must be rigid: an orthonormal rotation block with
/// determinant +1 and a bottom row (0, 0, 0, 1), each within 1e-3. Writes `*out` only on
/// success. Thread-safe.
///
/// Errors: `CG_STATUS_NULL_ARGUMENT`, `CG_STATUS_NON_FINITE` (a NaN or infinite element),
/// `CG_STATUS_INVALID_ARGUMENT` (a scale, shear, reflection or projection, a translation
/// longer than 1e18).
#[no_mangle]
pub unsafe extern "C" fn cg_dualquat_from_matrix(
    matrix: *const f32,
    out: *mut cg_dualquat,
) -> cg_status {
    ffi_boundary!({
        // SAFETY: the caller passes a writable cg_dualquat (or NULL, rejected).
        let out = unsafe { Out::new(out, "out") }?;
        let mut elements = [0.0f32; 16];
        // SAFETY: the caller passes 16 readable floats (or NULL).
        elements.copy_from_slice(unsafe { slice(matrix, 16, "matrix") }?);
        let result = DualQuat::from_mat4(&Mat4::from_cols_array(&elements))?;
        check_translation(result.translation(), "matrix")?;
        out.write(result.into());
        Ok(())
    })
}

/// Converts the rigid transform `*dual_quat` (normalised first) to a 4×4 matrix, written as
/// 16 floats to `out`, column-major for column vectors (the layout `cg_dualquat_from_matrix`
/// reads, and `osg::Matrixf::set(const float*)` takes).
///
/// Writes `out` only on success. Thread-safe.
///
/// Errors: `CG_STATUS_NULL_ARGUMENT`, `CG_STATUS_NON_FINITE`, `CG_STATUS_INVALID_ARGUMENT` (a
/// zero real part, a translation longer than 1e18).
#[no_mangle]
pub unsafe extern "C" fn cg_dualquat_to_matrix(
    dual_quat: *const cg_dualquat,
    out: *mut f32,
) -> cg_status {
    ffi_boundary!({
        non_null(out, "out")?;
        // SAFETY: the caller passes a readable cg_dualquat (or NULL).
        let q = unsafe { borrow(dual_quat, "dual_quat") }?.to_unit("dual_quat")?;
        let elements = q.to_mat4().to_cols_array();
        // SAFETY: the caller passes 16 writable floats.
        unsafe { slice_mut(out, 16, "out") }?.copy_from_slice(&elements);
        Ok(())
    })
}

// ---------------------------------------------------------------------------------------------
// Blending

/// Dual quaternion linear blending (DLB, equation 4 of Chaudhuri et al.) of `count` rigid
/// transforms `inputs` with weights `weights` into `*out`: `Σ w_k q̂_k / ‖Σ w_k q̂_k‖`.
///
/// Inputs are normalised; antipodal ones (`q̂` and `−q̂`, the same transform) are flipped to the
/// hemisphere of the first input with a non-zero weight, so blends go the short way. Weights
/// must be finite, `>= 0` and not all zero; they need not sum to 1. `out` may alias an input.
/// Writes `*out` only on success. Thread-safe; allocates nothing.
///
/// Errors: `CG_STATUS_NULL_ARGUMENT` (a NULL pointer with `count > 0`, or `out` NULL),
/// `CG_STATUS_NON_FINITE` (a NaN or infinite input or weight), `CG_STATUS_INVALID_ARGUMENT`
/// (`count` 0, a negative weight, weights summing to 0, an input with a zero real part or a
/// translation longer than 1e18).
#[no_mangle]
pub unsafe extern "C" fn cg_blend_dlb(
    inputs: *const cg_dualquat,
    weights: *const f32,
    count: usize,
    out: *mut cg_dualquat,
) -> cg_status {
    ffi_boundary!({
        // SAFETY: the caller passes `count` readable transforms and weights (or NULL, 0).
        let inputs = unsafe { slice(inputs, count, "inputs") }?;
        // SAFETY: as above.
        let weights = unsafe { slice(weights, count, "weights") }?;
        // SAFETY: the caller passes a writable cg_dualquat (or NULL, rejected).
        let out = unsafe { Out::new(out, "out") }?;
        check_all(inputs, "inputs")?;
        let result = blend::dlb(inputs, weights)?;
        out.write(result.into());
        Ok(())
    })
}

/// Dual quaternion iterative blending (DIB, Algorithm 1 of Chaudhuri et al.) of `count` rigid
/// transforms with weights `weights` into `*out`: starting from DLB, repeats
/// `x = Σ w_k log(b* q̂_k)`, `b = b exp(x)` until `‖x‖ < precision`, at most `max_iterations`
/// times. The exact weighted mean in the screw metric: rigid, coordinate invariant, ScLERP for
/// two inputs, the input itself for one.
///
/// `precision` is in mixed units (half-angles in radians, half-translations in your length
/// unit), finite and `> 0`: 1e-6 suits metres, 1e-4 centimetres (the iteration runs in float,
/// whose rounding is about 1e-7 of the translations). `max_iterations` is 1 to 1000; 16 is
/// plenty (typical poses need 2 to 4). Inputs and weights as in `cg_blend_dlb`; `out` may
/// alias an input. Thread-safe; allocates nothing.
///
/// Returns `CG_STATUS_OK` with `*out` written; or `CG_STATUS_NOT_CONVERGED` with `*out` holding
/// the best iterate when the precision was not reached in `max_iterations`.
///
/// Errors (nothing written): those of `cg_blend_dlb`, plus `CG_STATUS_NON_FINITE` (precision
/// NaN or infinite) and `CG_STATUS_INVALID_ARGUMENT` (precision `<= 0`, max_iterations 0 or
/// above 1000).
#[no_mangle]
pub unsafe extern "C" fn cg_blend_dib(
    inputs: *const cg_dualquat,
    weights: *const f32,
    count: usize,
    precision: f32,
    max_iterations: u32,
    out: *mut cg_dualquat,
) -> cg_status {
    ffi_boundary!({
        // SAFETY: the caller passes `count` readable transforms and weights (or NULL, 0).
        let inputs = unsafe { slice(inputs, count, "inputs") }?;
        // SAFETY: as above.
        let weights = unsafe { slice(weights, count, "weights") }?;
        // SAFETY: the caller passes a writable cg_dualquat (or NULL, rejected).
        let out = unsafe { Out::new(out, "out") }?;
        check_all(inputs, "inputs")?;
        let settings = DibSettings {
            precision,
            max_iterations,
        };
        let outcome = blend::dib(inputs, weights, &settings)?;
        out.write(outcome.blend.into());
        outcome.into_result(&settings)?;
        Ok(())
    })
}

/// Checks and views the arguments of the pose blends: `key_count × joint_count` finite
/// key transforms (key-major), `key_count` weights, and `joint_count` outputs not
/// overlapping the keys.
///
/// # Safety
/// The pointers must be valid for those counts, as the pose blends document.
unsafe fn pose_arguments<'a>(
    keys: *const cg_dualquat,
    weights: *const f32,
    key_count: usize,
    joint_count: usize,
    out_pose: *mut cg_dualquat,
) -> Result<(&'a [cg_dualquat], &'a [f32], &'a mut [cg_dualquat])> {
    let elements = pose_elements(key_count, joint_count)?;
    // SAFETY: the caller passes `key_count * joint_count` readable transforms (or NULL, 0).
    let keys_slice = unsafe { slice(keys, elements, "keys") }?;
    // SAFETY: the caller passes `key_count` readable weights (or NULL, 0).
    let weights = unsafe { slice(weights, key_count, "weights") }?;
    check_all(keys_slice, "keys")?;
    non_null_array(out_pose, joint_count, "out_pose")?;
    check_disjoint(keys, elements, out_pose, joint_count, "out_pose")?;
    // SAFETY: `joint_count` writable transforms, checked not to overlap `keys`.
    let out = unsafe { slice_mut(out_pose, joint_count, "out_pose") }?;
    Ok((keys_slice, weights, out))
}

/// DLB of whole poses: `keys` holds `key_count` poses of `joint_count` joints each,
/// **key-major** (joint `j` of key `k` at `keys[k * joint_count + j]`); joint `j` of `out_pose`
/// (`joint_count` long) gets the DLB of the keys' joint `j` with the shared `weights`
/// (`key_count` long). Rules of `cg_blend_dlb` per joint.
///
/// `out_pose` must not overlap `keys`. `joint_count` 0 is a valid empty pose. Writes
/// `out_pose` only on success. Thread-safe; allocates nothing.
///
/// Errors: `CG_STATUS_NULL_ARGUMENT`, `CG_STATUS_NON_FINITE`, `CG_STATUS_INVALID_ARGUMENT` (as
/// `cg_blend_dlb`, plus `key_count * joint_count` overflowing or `out_pose` overlapping `keys`).
#[no_mangle]
pub unsafe extern "C" fn cg_blend_pose_dlb(
    keys: *const cg_dualquat,
    weights: *const f32,
    key_count: usize,
    joint_count: usize,
    out_pose: *mut cg_dualquat,
) -> cg_status {
    ffi_boundary!({
        // SAFETY: forwarded caller contract of cg_blend_pose_dlb.
        let (keys_slice, weights, out) =
            unsafe { pose_arguments(keys, weights, key_count, joint_count, out_pose) }?;
        Ok(blend::blend_pose_dlb(
            keys_slice,
            weights,
            joint_count,
            out,
        )?)
    })
}

/// DIB of whole poses, with the layout of `cg_blend_pose_dlb` and the precision and
/// iteration rules of `cg_blend_dib`, per joint.
///
/// Returns `CG_STATUS_OK` with every joint written; or `CG_STATUS_NOT_CONVERGED` with every
/// joint written (the best iterate where the precision was not reached) — the message says
/// how many joints did not converge. Thread-safe; allocates nothing.
///
/// Errors (nothing written): those of `cg_blend_pose_dlb` and of the DIB settings.
#[no_mangle]
pub unsafe extern "C" fn cg_blend_pose_dib(
    keys: *const cg_dualquat,
    weights: *const f32,
    key_count: usize,
    joint_count: usize,
    precision: f32,
    max_iterations: u32,
    out_pose: *mut cg_dualquat,
) -> cg_status {
    ffi_boundary!({
        // SAFETY: forwarded caller contract of cg_blend_pose_dib.
        let (keys_slice, weights, out) =
            unsafe { pose_arguments(keys, weights, key_count, joint_count, out_pose) }?;
        let settings = DibSettings {
            precision,
            max_iterations,
        };
        Ok(
            blend::blend_pose_dib(keys_slice, weights, joint_count, &settings, out)?
                .into_result(&settings)?,
        )
    })
}

/// Fails with [`FfiError::NullArgument`](super::error::FfiError::NullArgument) for an output array `(NULL, n > 0)`.
fn non_null_array<T>(pointer: *const T, count: usize, what: &str) -> Result<()> {
    if count > 0 {
        non_null(pointer, what)?;
    }
    Ok(())
}

/// The centre of a projective camera `P = K[R|t]` (3×4) into `*out`: the right null space of
/// `P` (`P (C, 1) = 0`), i.e. `C = −Rᵀ t`. Use it as the viewer position of
/// `cg_view_blender_weights` and `cg_view_blender_evaluate` when the viewer comes from camera
/// tracking.
///
/// `projection` points to 12 floats, **row-major** (`projection[4 * r + c]` is row `r`,
/// column `c`, as OpenCV and Hartley & Zisserman write P); any non-zero scale of P works.
/// `*out` is in the units and frame of the world P maps from. Writes `*out` only on success.
/// Thread-safe.
///
/// Errors: `CG_STATUS_NULL_ARGUMENT`, `CG_STATUS_NON_FINITE` (a NaN or infinite element),
/// `CG_STATUS_INVALID_ARGUMENT` (a degenerate P: singular left 3×3 block, as for an affine
/// camera, rank below 3, or a centre too far away for a float).
#[no_mangle]
pub unsafe extern "C" fn cg_camera_center_from_projection(
    projection: *const f32,
    out: *mut cg_vec3,
) -> cg_status {
    ffi_boundary!({
        // SAFETY: the caller passes a writable cg_vec3 (or NULL, rejected).
        let out = unsafe { Out::new(out, "out") }?;
        let mut elements = [0.0f32; 12];
        // SAFETY: the caller passes 12 readable floats (or NULL).
        elements.copy_from_slice(unsafe { slice(projection, 12, "projection") }?);
        let centre = blend::camera_centre_from_projection(&elements)?;
        out.write(centre.into());
        Ok(())
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ffi::error::FfiError;

    fn dq(q: DualQuat) -> cg_dualquat {
        q.into()
    }

    #[test]
    fn conversions_check_their_input() {
        let zero = cg_dualquat {
            real: cg_quat {
                x: 0.0,
                y: 0.0,
                z: 0.0,
                w: 0.0,
            },
            dual: cg_quat::IDENTITY,
        };
        assert!(matches!(
            zero.to_unit("q"),
            Err(FfiError::Core(Error::InvalidArgument(_)))
        ));
        let mut nan = dq(DualQuat::IDENTITY);
        nan.dual.y = f32::NAN;
        assert!(matches!(
            nan.to_unit("q"),
            Err(FfiError::Core(Error::NonFinite(_)))
        ));
        let mut scaled = dq(DualQuat::IDENTITY);
        scaled.real.w = 3.0;
        assert_eq!(scaled.to_unit("q").unwrap(), DualQuat::IDENTITY);
        // Translations up to 1e18 (found by the fuzz target: longer ones overflowed blends).
        let far = |t: f32| {
            dq(DualQuat::from_rotation_translation(
                Quat::IDENTITY,
                glam::Vec3::new(t, 0.0, -t),
            ))
        };
        assert!(far(7.0e17).to_unit("q").is_ok());
        assert!(matches!(
            far(1.0e18).to_unit("q"),
            Err(FfiError::Core(Error::InvalidArgument(_)))
        ));
        assert!(matches!(
            far(f32::MAX).to_unit("q"),
            Err(FfiError::Core(Error::InvalidArgument(_)))
        ));
        assert!(matches!(
            check_all(&[dq(DualQuat::IDENTITY), far(1.0e30)], "keys"),
            Err(FfiError::Core(Error::InvalidArgument(_)))
        ));
    }

    #[test]
    fn overlapping_arrays_are_detected() {
        let data = [0u8; 64];
        let p = data.as_ptr();
        assert!(check_disjoint(p, 32, p.wrapping_add(16), 32, "out").is_err());
        assert!(check_disjoint(p, 32, p.wrapping_add(32), 32, "out").is_ok());
        assert!(check_disjoint(p, 0, p, 32, "out").is_ok());
    }
}
