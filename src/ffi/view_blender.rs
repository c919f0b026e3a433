//! The C ABI of view-adaptive animation: the `cg_view_blender` handle, its config, key
//! clips and poses, cameras, and the weights and pose for a viewer. It checks, converts and
//! forwards to `crate::blend::ViewBlender`.

use super::blend::{check_all, pose_elements};
use super::error::Result;
use super::poison::Poison;
use super::status::cg_status;
use super::types::{cg_dualquat, cg_vec3};
use super::{
    borrow, ffi_boundary, handle_mut, handle_ref, into_c, read_versioned, slice, slice_mut,
    write_versioned, Handle, Out, Versioned,
};
use crate::blend::{BlendMethod, KeyClip, ViewBlender, ViewBlenderConfig, ViewDistance};
use crate::error::{ensure_finite, Error};
use crate::math::dualquat::DualQuat;

/// How `cg_view_blender` blends the key animations per joint (the `method` field of
/// `cg_view_blender_config`, a `uint32_t` holding one of these values).
#[repr(u32)]
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum cg_blend_method {
    /// Dual quaternion linear blending: closed form, the fastest. The default.
    Dlb = 0,
    /// Dual quaternion iterative blending: the exact mean, iterated to `precision`.
    Dib = 1,
}

/// How `cg_view_blender` measures the distance D between the viewer's direction and a key
/// camera on the unit sphere (the `distance` field of `cg_view_blender_config`, a `uint32_t`
/// holding one of these values).
#[repr(u32)]
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum cg_view_distance {
    /// The great-circle angle in radians (0 to π). The default.
    Geodesic = 0,
    /// The straight chord through the sphere, `|v_c - v_k|` (0 to 2): the paper's cheaper
    /// approximation.
    Chordal = 1,
}

/// View-adaptive animation of one character (opaque): key animations, key cameras around the
/// character, and the blend of the key animations by where the viewer stands (Chaudhuri,
/// Papagiannakis & Magnenat-Thalmann).
///
/// Created by `cg_view_blender_create`, destroyed by `cg_view_blender_destroy`. Set a clip or
/// pose for every key and add key cameras, then call `cg_view_blender_weights` /
/// `cg_view_blender_evaluate` each frame (they allocate nothing). Not safe for concurrent
/// mutation: the set/add calls must not overlap any other call on the same blender. Calls
/// taking a `const cg_view_blender*` may run concurrently with each other, so one blender can
/// serve many characters that share its key animations.
///
/// If a set/add call fails with `CG_STATUS_INTERNAL` (a bug, such as a caught panic), the
/// blender may be half-updated and is poisoned: every later call on it fails with
/// `CG_STATUS_POISONED`, whose message repeats the first failure's.
/// `cg_view_blender_destroy` still frees it.
pub struct cg_view_blender {
    _private: [u8; 0],
}

/// What a `cg_view_blender*` points to: the blender and its poison.
pub(crate) struct BlenderHandle {
    blender: ViewBlender,
    /// Set by the first set/add call that failed inside the library.
    poison: Poison,
    /// Test builds: whether the next set/add call panics once it has changed the blender.
    #[cfg(feature = "test-hooks")]
    panic_next: std::sync::atomic::AtomicBool,
}

// SAFETY: `cg_view_blender` is the opaque type of view blender handles only.
unsafe impl Handle for BlenderHandle {
    type Opaque = cg_view_blender;
    const NAME: &'static str = "blender";
    fn poison(&self) -> &Poison {
        &self.poison
    }
}

impl BlenderHandle {
    fn new(blender: ViewBlender) -> BlenderHandle {
        BlenderHandle {
            blender,
            poison: Poison::default(),
            #[cfg(feature = "test-hooks")]
            panic_next: std::sync::atomic::AtomicBool::new(false),
        }
    }

    /// Test builds: makes the next set/add call panic once it has changed the blender.
    #[cfg(feature = "test-hooks")]
    pub(crate) fn panic_next(&self) {
        self.panic_next
            .store(true, std::sync::atomic::Ordering::SeqCst);
    }
}

/// Settings of a view blender, fixed for its lifetime. Set `struct_size`, fill it with
/// `cg_view_blender_config_init`, then set `joint_count` and `key_count` (they have no usable
/// default) and change what you need.
#[repr(C)]
#[derive(Debug, Clone, Copy)]
pub struct cg_view_blender_config {
    /// Size of this struct in bytes: set it to `sizeof(cg_view_blender_config)` before every
    /// call taking the struct, `cg_view_blender_config_init` included. The library reads and
    /// writes no more than this, so later versions can add fields without breaking older
    /// callers.
    pub struct_size: u32,
    /// Joints per pose, 1 to 65536. Default 0: must be set.
    pub joint_count: u32,
    /// Key animations K, 1 to 32. Default 0: must be set.
    pub key_count: u32,
    /// Exponent α of the weights `w_k = D_k^-α / Σ D_j^-α`, in [2, 4]: lower spreads each key
    /// camera's influence wider, higher focuses it near the camera. Default 2.
    pub alpha: f32,
    /// A `cg_view_distance`: how D is measured. Default `CG_VIEW_DISTANCE_GEODESIC`.
    pub distance: u32,
    /// A `cg_blend_method`: DLB or DIB per joint. Default `CG_BLEND_METHOD_DLB`.
    pub method: u32,
    /// DIB's precision p (half-angles in radians and half-translations in your length unit,
    /// mixed), finite and > 0. Default 1e-6 (for metres; use 1e-4 with centimetres). Unused
    /// by DLB.
    pub precision: f32,
    /// DIB's most iterations per joint, 1 to 1000. Default 16. Unused by DLB.
    pub max_iterations: u32,
}

impl Versioned for cg_view_blender_config {
    const SIZES: &'static [usize] = &[std::mem::size_of::<cg_view_blender_config>()];
    const NAME: &'static str = "cg_view_blender_config";

    fn defaults() -> Self {
        let core = ViewBlenderConfig::new(0, 0);
        cg_view_blender_config {
            struct_size: std::mem::size_of::<cg_view_blender_config>() as u32,
            joint_count: 0,
            key_count: 0,
            alpha: core.alpha,
            distance: cg_view_distance::Geodesic as u32,
            method: cg_blend_method::Dlb as u32,
            precision: core.precision,
            max_iterations: core.max_iterations,
        }
    }
}

impl cg_view_blender_config {
    /// Checks and converts to the core's config.
    fn to_core(self) -> Result<ViewBlenderConfig> {
        ensure_finite(self.alpha, "alpha")?;
        ensure_finite(self.precision, "precision")?;
        let distance = match self.distance {
            0 => ViewDistance::Geodesic,
            1 => ViewDistance::Chordal,
            other => {
                return Err(Error::InvalidArgument(format!(
                    "distance is {other}, not a cg_view_distance"
                ))
                .into())
            }
        };
        let method = match self.method {
            0 => BlendMethod::Dlb,
            1 => BlendMethod::Dib,
            other => {
                return Err(Error::InvalidArgument(format!(
                    "method is {other}, not a cg_blend_method"
                ))
                .into())
            }
        };
        let config = ViewBlenderConfig {
            joint_count: self.joint_count as usize,
            key_count: self.key_count as usize,
            alpha: self.alpha,
            distance,
            method,
            precision: self.precision,
            max_iterations: self.max_iterations,
        };
        config.validate()?;
        Ok(config)
    }
}

/// Fills `config` with the defaults documented on each field. Set `config->struct_size =
/// sizeof(cg_view_blender_config)` first: only that many bytes are written, and
/// `struct_size` keeps its value. The caller owns `config`.
///
/// Errors (nothing written): `CG_STATUS_NULL_ARGUMENT` if `config` is NULL,
/// `CG_STATUS_BAD_STRUCT_SIZE` if `struct_size` is not a size of this struct the library
/// knows (0 or an unset field included). Thread-safe.
#[no_mangle]
pub unsafe extern "C" fn cg_view_blender_config_init(
    config: *mut cg_view_blender_config,
) -> cg_status {
    ffi_boundary!({
        // SAFETY: the caller passes a cg_view_blender_config it owns, of at least its
        // struct_size bytes (or NULL).
        unsafe { write_versioned(config, cg_view_blender_config::defaults(), "config") }
    })
}

/// Creates a view blender from `config`, with no key animation and no key camera yet, and
/// stores its handle in `*out_blender`.
///
/// The caller owns the new blender and releases it with `cg_view_blender_destroy`.
/// `*out_blender` is written only on success. Thread-safe.
///
/// Errors: `CG_STATUS_NULL_ARGUMENT`, `CG_STATUS_BAD_STRUCT_SIZE` (`config->struct_size`
/// not a size the library knows), `CG_STATUS_INVALID_ARGUMENT` (a field out of its range,
/// an unknown enum value), `CG_STATUS_NON_FINITE` (alpha or precision NaN or infinite),
/// `CG_STATUS_OUT_OF_MEMORY`.
#[no_mangle]
pub unsafe extern "C" fn cg_view_blender_create(
    config: *const cg_view_blender_config,
    out_blender: *mut *mut cg_view_blender,
) -> cg_status {
    ffi_boundary!({
        // SAFETY: the caller provides a writable cg_view_blender* (or NULL, rejected).
        let out_blender = unsafe { Out::new(out_blender, "out_blender") }?;
        // SAFETY: the caller passes a readable config of at least its struct_size bytes.
        let config = unsafe { read_versioned(config) }?.to_core()?;
        let blender = Box::new(BlenderHandle::new(ViewBlender::new(config)?));
        out_blender.write(into_c(blender));
        Ok(())
    })
}

/// Destroys a view blender created by `cg_view_blender_create` and frees everything it owns
/// (its clips and cameras), also when the blender is poisoned.
///
/// NULL is accepted and ignored. The handle must not be used afterwards, and no other call
/// on this blender may be running.
#[no_mangle]
pub unsafe extern "C" fn cg_view_blender_destroy(blender: *mut cg_view_blender) {
    // SAFETY: a blender handle from cg_view_blender_create (or NULL), destroyed once and not
    // in use (the caller's contract).
    unsafe { super::handle::destroy::<BlenderHandle>(blender) }
}

/// Reborrows a blender handle as its handle state; fails if the blender is poisoned.
///
/// # Safety
/// `blender`, if not NULL, must be a live handle from `cg_view_blender_create`, with no
/// mutable access for `'a`.
pub(crate) unsafe fn blender_handle<'a>(
    blender: *const cg_view_blender,
) -> Result<&'a BlenderHandle> {
    // SAFETY: forwarded contract.
    unsafe { handle_ref::<BlenderHandle>(blender) }
}

/// Reborrows a blender handle as the core blender; fails if the blender is poisoned.
///
/// # Safety
/// `blender`, if not NULL, must be a live handle from `cg_view_blender_create`, with no
/// mutable access for `'a`.
unsafe fn blender_ref<'a>(blender: *const cg_view_blender) -> Result<&'a ViewBlender> {
    // SAFETY: forwarded contract.
    Ok(&unsafe { blender_handle(blender) }?.blender)
}

/// Reborrows a blender handle mutably as the core blender, for a call that changes it (its
/// poison is armed for the call); fails if the blender is poisoned.
///
/// # Safety
/// `blender`, if not NULL, must be a live handle from `cg_view_blender_create`, not accessed
/// by anything else for `'a`.
unsafe fn blender_mut<'a>(blender: *mut cg_view_blender) -> Result<&'a mut ViewBlender> {
    // SAFETY: forwarded contract.
    Ok(&mut unsafe { handle_mut::<BlenderHandle>(blender) }?.blender)
}

/// Test builds (feature `test-hooks`): panics if the next set/add call on `blender` was
/// asked to panic (`testing::panic_next_change`). Does nothing otherwise.
///
/// # Safety
/// `blender`, if not NULL, must be a live handle from `cg_view_blender_create`, with no
/// mutable access meanwhile.
unsafe fn test_hook(blender: *const cg_view_blender) {
    #[cfg(feature = "test-hooks")]
    {
        // SAFETY: forwarded contract.
        let handle = unsafe { blender_handle(blender) };
        let armed = handle.is_ok_and(|handle| {
            handle
                .panic_next
                .swap(false, std::sync::atomic::Ordering::SeqCst)
        });
        if armed {
            panic!("test hook: a change of the view blender panics");
        }
    }
    #[cfg(not(feature = "test-hooks"))]
    let _ = blender;
}

/// Sets (or replaces) key animation `key` (0 to `key_count - 1`) to a clip of `frame_count`
/// poses played at `frames_per_second`.
///
/// `frames` holds `frame_count * joint_count` rigid transforms (the joints' local transforms,
/// as your skeleton defines them), **frame-major**: joint `j` of frame `f` at
/// `frames[f * joint_count + j]`. They are copied (and normalised): the caller keeps ownership.
/// Frame `f` plays at time `f / frames_per_second`. A clamped clip (`looping` false) holds its
/// first and last frames outside its range; a looping one repeats with period
/// `frame_count / frames_per_second` and interpolates from the last frame back to the first
/// (do not repeat the first frame at the end). Between frames each joint is interpolated by
/// DLB of the two neighbouring frames. `frames_per_second` must be finite, and > 0 unless
/// `frame_count` is 1.
///
/// Allocates (setup, not per frame). Not safe concurrently with any other call on this
/// blender. Nothing changes on error.
///
/// Errors: `CG_STATUS_NULL_ARGUMENT`, `CG_STATUS_NON_FINITE` (a NaN or infinite component or
/// frame rate), `CG_STATUS_INVALID_ARGUMENT` (key out of range, `frame_count` 0, frame rate
/// <= 0, a transform with a zero real part or a translation longer than 1e18, a count
/// overflowing), `CG_STATUS_OUT_OF_MEMORY` (no memory for the copy of `frames`).
#[no_mangle]
pub unsafe extern "C" fn cg_view_blender_set_key_clip(
    blender: *mut cg_view_blender,
    key: u32,
    frames: *const cg_dualquat,
    frame_count: usize,
    frames_per_second: f32,
    looping: bool,
) -> cg_status {
    ffi_boundary!({
        let handle = blender;
        // SAFETY: handle contract of cg_view_blender.
        let blender = unsafe { blender_mut(handle) }?;
        let joint_count = blender.config().joint_count;
        let elements = pose_elements(frame_count, joint_count)?;
        // SAFETY: the caller passes `frame_count * joint_count` readable transforms (or NULL, 0).
        let frames = unsafe { slice(frames, elements, "frames") }?;
        ensure_finite(frames_per_second, "frames_per_second")?;
        check_all(frames, "frames")?;
        let clip = KeyClip::new(frames, joint_count, frames_per_second, looping)?;
        blender.set_key_clip(key as usize, clip)?;
        // SAFETY: as above; the blender's mutable borrow has ended.
        unsafe { test_hook(handle) };
        Ok(())
    })
}

/// Sets (or replaces) key `key` (0 to `key_count - 1`) to a static pose: `pose` holds
/// `joint_count` rigid transforms (copied and normalised; the caller keeps ownership).
/// `joint_count` must equal the blender's.
///
/// Allocates (setup, not per frame). Not safe concurrently with any other call on this
/// blender. Nothing changes on error.
///
/// Errors: `CG_STATUS_NULL_ARGUMENT`, `CG_STATUS_NON_FINITE`, `CG_STATUS_INVALID_ARGUMENT` (key
/// out of range, wrong `joint_count`, a transform with a zero real part or a translation longer
/// than 1e18), `CG_STATUS_OUT_OF_MEMORY`.
#[no_mangle]
pub unsafe extern "C" fn cg_view_blender_set_key_pose(
    blender: *mut cg_view_blender,
    key: u32,
    pose: *const cg_dualquat,
    joint_count: usize,
) -> cg_status {
    ffi_boundary!({
        let handle = blender;
        // SAFETY: handle contract of cg_view_blender.
        let blender = unsafe { blender_mut(handle) }?;
        // SAFETY: the caller passes `joint_count` readable transforms (or NULL, 0).
        let pose = unsafe { slice(pose, joint_count, "pose") }?;
        check_all(pose, "pose")?;
        blender.set_key_pose(key as usize, pose)?;
        // SAFETY: as above; the blender's mutable borrow has ended.
        unsafe { test_hook(handle) };
        Ok(())
    })
}

/// Adds a key camera: the direction `direction` from the character's centre, in the
/// character's own frame (any non-zero length; it is normalised onto the unit sphere), mapped
/// to key animation `key`. Several cameras may map to one key; a key with no camera never
/// contributes. The camera moves with the character.
///
/// Allocates (setup, not per frame). Not safe concurrently with any other call on this
/// blender. Nothing changes on error.
///
/// Errors: `CG_STATUS_NULL_ARGUMENT` (blender NULL), `CG_STATUS_NON_FINITE`,
/// `CG_STATUS_INVALID_ARGUMENT` (key out of range, a zero direction),
/// `CG_STATUS_OUT_OF_MEMORY`.
#[no_mangle]
pub unsafe extern "C" fn cg_view_blender_add_camera(
    blender: *mut cg_view_blender,
    direction: cg_vec3,
    key: u32,
) -> cg_status {
    ffi_boundary!({
        let handle = blender;
        // SAFETY: handle contract of cg_view_blender.
        let blender = unsafe { blender_mut(handle) }?;
        let direction = direction.to_finite("direction")?;
        blender.add_camera(direction, key as usize)?;
        // SAFETY: as above; the blender's mutable borrow has ended.
        unsafe { test_hook(handle) };
        Ok(())
    })
}

/// Reads the character transform and viewer position from C.
///
/// # Safety
/// Each pointer, if not NULL and aligned, must point to a readable value.
unsafe fn read_view(
    character: *const cg_dualquat,
    viewer: *const cg_vec3,
) -> Result<(DualQuat, glam::Vec3)> {
    // SAFETY: forwarded contract.
    let character = unsafe { borrow(character, "character") }?.to_unit("character")?;
    // SAFETY: forwarded contract.
    let viewer = unsafe { borrow(viewer, "viewer") }?.to_finite("viewer")?;
    Ok((character, viewer))
}

/// The view weights of the key animations for a viewer at `*viewer` looking at the character
/// placed by `*character`, into `out_weights` (`count` = `key_count` floats).
///
/// `*character` is the character's rigid transform in the world (rotation and position; see
/// `cg_dualquat_from_rt`), `*viewer` the viewer's world position, in the same length unit
/// (only directions matter). The viewer's direction in the character's frame is projected on
/// the unit sphere, and key k gets `w_k = Σ_{cameras c of k} D_c^-α / Σ_{all cameras} D_c^-α`:
/// convex weights summing to 1. A viewer on a key camera (D < 1e-6) gets that camera's key
/// alone. Writes `out_weights` only on success. Allocates nothing; may run concurrently with
/// other const calls on this blender.
///
/// Errors: `CG_STATUS_NULL_ARGUMENT`, `CG_STATUS_NON_FINITE` (a NaN or infinite input),
/// `CG_STATUS_INVALID_ARGUMENT` (`count` is not `key_count`, the character transform has a zero
/// real part or a translation longer than 1e18, or the viewer is at the character's centre,
/// within 1e-6 of its position scaled by max(1, |positions|)), `CG_STATUS_WRONG_STATE` (no key
/// camera yet).
#[no_mangle]
pub unsafe extern "C" fn cg_view_blender_weights(
    blender: *const cg_view_blender,
    character: *const cg_dualquat,
    viewer: *const cg_vec3,
    out_weights: *mut f32,
    count: usize,
) -> cg_status {
    ffi_boundary!({
        // SAFETY: handle contract of cg_view_blender.
        let blender = unsafe { blender_ref(blender) }?;
        // SAFETY: the caller passes readable character and viewer (or NULL).
        let (character, viewer) = unsafe { read_view(character, viewer) }?;
        // SAFETY: the caller passes `count` writable floats (or NULL, 0).
        let out = unsafe { slice_mut(out_weights, count, "out_weights") }?;
        Ok(blender.weights(character, viewer, out)?)
    })
}

/// The blended pose at time `t` (seconds) for a viewer at `*viewer` looking at the character
/// placed by `*character`, into `out_pose` (`joints` = `joint_count` transforms, the joints'
/// local transforms in your skeleton's order).
///
/// Computes the weights as `cg_view_blender_weights`, samples every key animation with a
/// non-zero weight at `t`, and blends each joint with DLB or DIB (the config's `method`).
/// Every key must have a clip or pose. Allocates nothing; may run concurrently with other
/// const calls on this blender.
///
/// Returns `CG_STATUS_OK` with the pose written; or, with DIB, `CG_STATUS_NOT_CONVERGED` with
/// the whole pose written (the best iterate for the joints that missed the precision).
///
/// Errors (nothing written): those of `cg_view_blender_weights`, plus
/// `CG_STATUS_INVALID_ARGUMENT` (`joints` is not `joint_count`), `CG_STATUS_NON_FINITE` (`t`
/// NaN or infinite), `CG_STATUS_WRONG_STATE` (a key without clip or pose).
#[no_mangle]
pub unsafe extern "C" fn cg_view_blender_evaluate(
    blender: *const cg_view_blender,
    character: *const cg_dualquat,
    viewer: *const cg_vec3,
    t: f64,
    out_pose: *mut cg_dualquat,
    joints: usize,
) -> cg_status {
    ffi_boundary!({
        // SAFETY: handle contract of cg_view_blender.
        let blender = unsafe { blender_ref(blender) }?;
        // SAFETY: the caller passes readable character and viewer (or NULL).
        let (character, viewer) = unsafe { read_view(character, viewer) }?;
        // SAFETY: the caller passes `joints` writable transforms (or NULL, 0); the character
        // and viewer were copied out above.
        let out = unsafe { slice_mut(out_pose, joints, "out_pose") }?;
        Ok(blender
            .evaluate(character, viewer, t, out)?
            .into_result(&blender.config().dib_settings())?)
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn enums_match_their_c_values() {
        assert_eq!(cg_blend_method::Dlb as u32, 0);
        assert_eq!(cg_blend_method::Dib as u32, 1);
        assert_eq!(cg_view_distance::Geodesic as u32, 0);
        assert_eq!(cg_view_distance::Chordal as u32, 1);
        let defaults = cg_view_blender_config::defaults();
        assert_eq!(
            defaults.struct_size as usize,
            std::mem::size_of::<cg_view_blender_config>()
        );
        assert!(defaults.to_core().is_err(), "counts must be set");
        let filled = cg_view_blender_config {
            joint_count: 3,
            key_count: 2,
            ..defaults
        };
        let core = filled.to_core().unwrap();
        assert_eq!(core, ViewBlenderConfig::new(3, 2));
    }
}
