//! The C ABI of skeleton mapping: the `cg_rig` handle (a skeleton mapped to a gaze chain,
//! immutable once made), its description, and each frame's conversions between the
//! engine's bone rotations and the crowd's base pose and joints. It checks, converts and
//! forwards to `crate::skeleton_map`.

use std::ffi::CStr;

use glam::Quat;
use libc::c_char;

use super::chain::cg_chain_desc;
use super::error::Result;
use super::poison::Poison;
use super::status::cg_status;
use super::types::{cg_axis, cg_quat, cg_vec3};
use super::{
    ffi_boundary, handle_ref, into_c, read_versioned, slice, slice_mut, write_versioned, Handle,
    Out, Versioned,
};
use crate::alloc::{try_with_capacity, Field};
use crate::error::{ensure_finite, Error};
use crate::ik::MAX_CHAIN_JOINTS;
use crate::skeleton_map::{
    map_skeleton, BoneMap, BoneRole, BoneRotations, BoneRotationsMut, MappedChain, RestBone,
    SkeletonOptions, MAX_BONES, MAX_NAME_BYTES,
};
use crate::world::{Axis, World};

/// The most bones a rig may have (`cg_rig_desc.bone_count`).
pub const CG_MAX_RIG_BONES: usize = 65536;

const _: () = assert!(CG_MAX_RIG_BONES == MAX_BONES);

/// `cg_rig_desc.up` and `.forward`: detect the axis from the rest pose.
pub const CG_RIG_AXIS_DETECT: u32 = u32::MAX;

/// What a bone is for the gaze chain (`cg_rig_bone_roles` writes one per bone, as
/// `uint32_t`). The bone map's role names are given with each.
#[repr(u32)]
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum cg_bone_role {
    /// Not part of the chain (`none`).
    None = 0,
    /// The body root (`root`): not turned by gaze.
    Root = 1,
    /// A spine bone, lumbar or thoracic (`spine`).
    Spine = 2,
    /// A neck (cervical) bone (`neck`).
    Neck = 3,
    /// The head (`head`).
    Head = 4,
    /// The character's left eye, under the head (`left_eye`).
    LeftEye = 5,
    /// The character's right eye, under the head (`right_eye`).
    RightEye = 6,
}

impl cg_bone_role {
    /// The C value of a [`BoneRole`].
    fn from_role(role: BoneRole) -> u32 {
        (match role {
            BoneRole::None => cg_bone_role::None,
            BoneRole::Root => cg_bone_role::Root,
            BoneRole::Spine => cg_bone_role::Spine,
            BoneRole::Neck => cg_bone_role::Neck,
            BoneRole::Head => cg_bone_role::Head,
            BoneRole::LeftEye => cg_bone_role::LeftEye,
            BoneRole::RightEye => cg_bone_role::RightEye,
        }) as u32
    }
}

/// A skeleton mapped to a gaze chain (opaque): which bones are spine, neck, head and eyes,
/// the chain to give `cg_crowd_add_character`, and each frame's conversions between your
/// engine's bone local rotations and the crowd's base pose and joints.
///
/// Created by `cg_rig_create` from the skeleton's rest pose, destroyed by `cg_rig_destroy`.
/// Immutable once created: every other call takes a `const cg_rig*`, and may run
/// concurrently with any other on the same rig, so one rig serves every character that
/// shares its skeleton. A rig is never poisoned (no call changes it).
pub struct cg_rig {
    _private: [u8; 0],
}

/// What a `cg_rig*` points to: the mapping, and what the calls hand out.
pub(crate) struct RigHandle {
    mapped: MappedChain,
    /// The chain in the crowd's units, as `cg_rig_chain` writes it.
    chain: cg_chain_desc,
    /// The mapping report, as `cg_rig_report` copies it.
    report: String,
    /// Never set: no call changes a rig.
    poison: Poison,
    /// Test builds: whether the next call on the rig panics (after its checks, before it
    /// writes anything).
    #[cfg(feature = "test-hooks")]
    panic_next: std::sync::atomic::AtomicBool,
}

// SAFETY: `cg_rig` is the opaque type of rig handles only.
unsafe impl Handle for RigHandle {
    type Opaque = cg_rig;
    const NAME: &'static str = "rig";
    fn poison(&self) -> &Poison {
        &self.poison
    }
}

impl RigHandle {
    /// Test builds: makes the next call on the rig panic inside the library.
    #[cfg(feature = "test-hooks")]
    pub(crate) fn panic_next(&self) {
        self.panic_next
            .store(true, std::sync::atomic::Ordering::SeqCst);
    }

    /// Test builds (feature `test-hooks`): panics if the next call was asked to panic
    /// (`testing::panic_next_rig_call`). Does nothing otherwise.
    fn test_hook(&self) {
        #[cfg(feature = "test-hooks")]
        if self
            .panic_next
            .swap(false, std::sync::atomic::Ordering::SeqCst)
        {
            panic!("test hook: a call on the rig panics");
        }
    }
}

/// A skeleton at rest, to map to a gaze chain with `cg_rig_create`. Set `struct_size`, fill
/// it with `cg_rig_desc_init`, then set `bone_count` and the bone arrays (they have no
/// usable default) and change what you need. The arrays are read during `cg_rig_create`
/// only, and stay yours.
///
/// Bones are listed parents before children; each bone's rest translation and rotation are
/// relative to its parent, in its parent's frame (a bone without a parent: relative to the
/// character, on the ground at heading 0). Roles are found by name (Mixamo, Unreal, Unity,
/// VRM, Daz, Character Creator, Rigify, CMU BVH and other conventions), with `bone_map`
/// overriding them; see docs/your-character.md.
#[repr(C)]
#[derive(Debug, Clone, Copy)]
pub struct cg_rig_desc {
    /// Size of this struct in bytes: set it to `sizeof(cg_rig_desc)` before every call
    /// taking the struct, `cg_rig_desc_init` included.
    pub struct_size: u32,
    /// Number of bones, 1 to `CG_MAX_RIG_BONES`. Default 0: must be set.
    pub bone_count: u32,
    /// `bone_count` bone names: NUL-terminated UTF-8, 1 to 1024 bytes, unique. Default NULL:
    /// must be set.
    pub bone_names: *const *const c_char,
    /// `bone_count` parent indices: -1 for a bone without a parent, else the index of a bone
    /// before this one. Default NULL: must be set.
    pub parents: *const i32,
    /// `bone_count` rest translations from the parent, in the parent's frame, in the
    /// skeleton's units (`units_per_metre`). Default NULL: must be set.
    pub rest_translations: *const cg_vec3,
    /// `bone_count` rest rotations relative to the parent (normalised on reading), or NULL
    /// for all identity. Default NULL.
    pub rest_rotations: *const cg_quat,
    /// How many of the skeleton's length units make a metre, in (0, 1e6]: 100 for
    /// centimetres. Default 1.
    pub units_per_metre: f32,
    /// The skeleton's up axis (a `cg_axis`), or `CG_RIG_AXIS_DETECT` to take the axis
    /// nearest to the rest pose's spine (chain root to head). Default `CG_RIG_AXIS_DETECT`.
    pub up: u32,
    /// The direction the skeleton faces at rest (a `cg_axis`, perpendicular to `up`), or
    /// `CG_RIG_AXIS_DETECT` to find it from left and right bone pairs, the eyes or the toes.
    /// Default `CG_RIG_AXIS_DETECT`.
    pub forward: u32,
    /// Role overrides, NUL-terminated UTF-8: `Name=role` entries separated by commas (roles
    /// `root`, `spine`, `neck`, `head`, `left_eye`, `right_eye`, `none`; names
    /// case-insensitive, with or without a `namespace:` prefix), e.g.
    /// `"mixamorig:Spine=none,Jaw=head"`; each must name a bone. NULL for none. Default NULL.
    pub bone_map: *const c_char,
    /// The crowd's up axis (its `cg_crowd_config.up_axis`): the chain and the poses are
    /// turned into the crowd's axes. Default `CG_AXIS_POSITIVE_Y`.
    pub crowd_up: u32,
    /// The crowd's forward axis (its `cg_crowd_config.forward_axis`), perpendicular to
    /// `crowd_up`. Default `CG_AXIS_POSITIVE_Z`.
    pub crowd_forward: u32,
    /// The crowd's `units_per_metre`: the lengths of the chain `cg_rig_chain` writes are in
    /// the crowd's units. Default 1.
    pub crowd_units_per_metre: f32,
}

impl Versioned for cg_rig_desc {
    const SIZES: &'static [usize] = &[std::mem::size_of::<cg_rig_desc>()];
    const NAME: &'static str = "cg_rig_desc";

    fn defaults() -> Self {
        cg_rig_desc {
            struct_size: std::mem::size_of::<cg_rig_desc>() as u32,
            bone_count: 0,
            bone_names: std::ptr::null(),
            parents: std::ptr::null(),
            rest_translations: std::ptr::null(),
            rest_rotations: std::ptr::null(),
            units_per_metre: 1.0,
            up: CG_RIG_AXIS_DETECT,
            forward: CG_RIG_AXIS_DETECT,
            bone_map: std::ptr::null(),
            crowd_up: cg_axis::PositiveY as u32,
            crowd_forward: cg_axis::PositiveZ as u32,
            crowd_units_per_metre: 1.0,
        }
    }
}

/// An axis of `cg_rig_desc` that may be left to detection.
fn detectable_axis(value: u32, what: &str) -> Result<Option<Axis>> {
    if value == CG_RIG_AXIS_DETECT {
        return Ok(None);
    }
    Ok(Some(cg_axis::parse(value, what)?))
}

/// Reads bone `index`'s name: not NULL, 1 to `MAX_NAME_BYTES` bytes of UTF-8 (at most
/// `MAX_NAME_BYTES + 1` bytes are read looking for its NUL).
///
/// # Safety
/// `name`, if not NULL, must point to a NUL-terminated string, or to at least
/// `MAX_NAME_BYTES + 1` readable bytes, valid for `'a`.
unsafe fn bone_name<'a>(name: *const c_char, index: usize) -> Result<&'a str> {
    if name.is_null() {
        return Err(Error::InvalidArgument(format!("bone_names[{index}] is NULL")).into());
    }
    // SAFETY: readable up to its NUL or MAX_NAME_BYTES + 1 bytes (contract); strnlen reads
    // no further.
    let length = unsafe { libc::strnlen(name, MAX_NAME_BYTES + 1) };
    if length == 0 || length > MAX_NAME_BYTES {
        return Err(Error::InvalidArgument(format!(
            "bone_names[{index}] is {}: names have 1 to {MAX_NAME_BYTES} bytes",
            if length == 0 { "empty" } else { "too long" }
        ))
        .into());
    }
    // SAFETY: `length` bytes are readable (strnlen found them before the NUL).
    let bytes = unsafe { std::slice::from_raw_parts(name.cast::<u8>(), length) };
    std::str::from_utf8(bytes).map_err(|error| {
        Error::InvalidArgument(format!(
            "bone_names[{index}] is not UTF-8 (byte {} is not valid)",
            error.valid_up_to()
        ))
        .into()
    })
}

/// Bone `index`'s parent from C: -1 for none, else a bone before it.
fn bone_parent(parent: i32, index: usize) -> Result<Option<usize>> {
    match parent {
        -1 => Ok(None),
        p if p >= 0 && (p as usize) < index => Ok(Some(p as usize)),
        p => Err(Error::InvalidArgument(format!(
            "parents[{index}] is {p}: a parent is -1 or the index of a bone before its child"
        ))
        .into()),
    }
}

/// Fails with `CG_STATUS_NON_FINITE` naming `array[index]` if `values` holds a NaN or an
/// infinity (the message is made only on failure).
fn ensure_element_finite(values: &[f32], array: &str, index: usize) -> Result<()> {
    match values.iter().find(|v| !v.is_finite()) {
        None => Ok(()),
        Some(bad) => Err(Error::NonFinite(format!("{array}[{index}] contains {bad}")).into()),
    }
}

/// A rotation from C as a unit quaternion: finite (else `CG_STATUS_NON_FINITE`) and not of
/// zero length (else `CG_STATUS_INVALID_ARGUMENT`), naming `array[index]`. Allocates only
/// on failure.
fn element_unit(q: cg_quat, array: &str, index: usize) -> Result<Quat> {
    ensure_element_finite(&[q.x, q.y, q.z, q.w], array, index)?;
    let q = Quat::from_xyzw(q.x, q.y, q.z, q.w);
    let length = q.length();
    if !(length > 1e-6 && length.is_finite()) {
        return Err(Error::InvalidArgument(format!(
            "{array}[{index}] has length {length}, not a rotation"
        ))
        .into());
    }
    Ok(q / length)
}

impl cg_rig_desc {
    /// Checks the description and maps its skeleton.
    ///
    /// # Safety
    /// Each array pointer, if not NULL and aligned, must point to `bone_count` readable
    /// elements; each name and `bone_map`, if not NULL, to a NUL-terminated string.
    unsafe fn map(&self) -> Result<MappedChain> {
        let count = self.bone_count as usize;
        if count == 0 || count > CG_MAX_RIG_BONES {
            return Err(Error::InvalidArgument(format!(
                "cg_rig_desc.bone_count is {count}, must be 1..={CG_MAX_RIG_BONES}"
            ))
            .into());
        }
        // SAFETY: `bone_count` readable elements each (contract), or NULL (rejected).
        let names = unsafe { slice(self.bone_names, count, "bone_names") }?;
        // SAFETY: as above.
        let parents = unsafe { slice(self.parents, count, "parents") }?;
        // SAFETY: as above.
        let translations = unsafe { slice(self.rest_translations, count, "rest_translations") }?;
        let rotations = match self.rest_rotations.is_null() {
            true => None,
            // SAFETY: as above.
            false => Some(unsafe { slice(self.rest_rotations, count, "rest_rotations") }?),
        };
        ensure_finite(self.units_per_metre, "units_per_metre")?;
        ensure_finite(self.crowd_units_per_metre, "crowd_units_per_metre")?;
        let up = detectable_axis(self.up, "up")?;
        let forward = detectable_axis(self.forward, "forward")?;
        let crowd = World::new(
            cg_axis::parse(self.crowd_up, "crowd_up")?,
            cg_axis::parse(self.crowd_forward, "crowd_forward")?,
            self.crowd_units_per_metre,
        )
        .map_err(|error| match error {
            Error::InvalidArgument(message) => Error::InvalidArgument(format!("crowd: {message}")),
            other => other,
        })?;
        let map = match self.bone_map.is_null() {
            true => BoneMap::default(),
            false => {
                // SAFETY: a NUL-terminated string (contract).
                let text = unsafe { CStr::from_ptr(self.bone_map) };
                let text = text.to_str().map_err(|error| {
                    Error::InvalidArgument(format!(
                        "bone_map is not UTF-8 (byte {} is not valid)",
                        error.valid_up_to()
                    ))
                })?;
                BoneMap::with_overrides(text)?
            }
        };
        let mut bones: Vec<RestBone<'_>> =
            try_with_capacity(count, &Field("cg_rig_desc.bone_count", count as u64))?;
        for index in 0..count {
            // SAFETY: a NUL-terminated string (contract).
            let name = unsafe { bone_name(names[index], index) }?;
            let parent = bone_parent(parents[index], index)?;
            let t = translations[index];
            ensure_element_finite(&[t.x, t.y, t.z], "rest_translations", index)?;
            let rotation = match rotations {
                None => Quat::IDENTITY,
                Some(rotations) => element_unit(rotations[index], "rest_rotations", index)?,
            };
            bones.push(RestBone {
                name,
                parent,
                translation: glam::Vec3::new(t.x, t.y, t.z),
                rotation,
            });
        }
        let options = SkeletonOptions {
            up,
            forward,
            units_per_metre: self.units_per_metre,
            root_offset: None,
            crowd_axes: Some((crowd.up_axis, crowd.forward_axis)),
        };
        Ok(map_skeleton(&bones, &map, &options)?)
    }
}

/// Fills `desc` with the defaults documented on each field. Set `desc->struct_size =
/// sizeof(cg_rig_desc)` first: only that many bytes are written, and `struct_size` keeps
/// its value. The caller owns `desc`.
///
/// Errors (nothing written): `CG_STATUS_NULL_ARGUMENT` if `desc` is NULL,
/// `CG_STATUS_BAD_STRUCT_SIZE` if `struct_size` is not a size of this struct the library
/// knows (0 or an unset field included). Thread-safe.
#[no_mangle]
pub unsafe extern "C" fn cg_rig_desc_init(desc: *mut cg_rig_desc) -> cg_status {
    ffi_boundary!({
        // SAFETY: the caller passes a cg_rig_desc it owns, of at least its struct_size
        // bytes (or NULL).
        unsafe { write_versioned(desc, cg_rig_desc::defaults(), "desc") }
    })
}

/// Maps the skeleton `desc` describes to a gaze chain, in one call, and stores the rig's
/// handle in `*out_rig`.
///
/// Each bone gets a role (`cg_bone_role`) from its name or `bone_map`; the chain is the
/// head, the neck and spine bones below it (down to the first bone that is neither: the
/// chain root) and the two eyes under the head, if any; the skeleton's up and forward are
/// given or detected. `cg_rig_report` says what was found and why. The desc's arrays and
/// strings are read during the call only and stay the caller's; the caller owns the new
/// rig and releases it with `cg_rig_destroy`. `*out_rig` is written only on success.
/// Allocates (setup, not per frame). Thread-safe.
///
/// Errors: `CG_STATUS_NULL_ARGUMENT` (`desc`, `out_rig` or a bone array NULL),
/// `CG_STATUS_BAD_STRUCT_SIZE` (`desc->struct_size` not a size the library knows),
/// `CG_STATUS_NON_FINITE` (a NaN or infinite unit, translation or rotation),
/// `CG_STATUS_INVALID_ARGUMENT` (`bone_count` 0 or above `CG_MAX_RIG_BONES`; a name NULL,
/// empty, longer than 1024 bytes, not UTF-8 or given twice; a parent not -1 nor a bone
/// before its child; a zero rotation; an axis not a `cg_axis` or `CG_RIG_AXIS_DETECT`, or
/// not perpendicular; a unit out of range; a bone longer than 1 km; a `bone_map` that does
/// not parse or names no bone; a skeleton that does not map: no head, a chain that stops at
/// a bone it plainly should go through, one eye, a facing the rest pose does not show —
/// the message names the bone and the `bone_map` entry that fixes it),
/// `CG_STATUS_OUT_OF_MEMORY`.
#[no_mangle]
pub unsafe extern "C" fn cg_rig_create(
    desc: *const cg_rig_desc,
    out_rig: *mut *mut cg_rig,
) -> cg_status {
    ffi_boundary!({
        // SAFETY: the caller provides a writable cg_rig* (or NULL, rejected).
        let out_rig = unsafe { Out::new(out_rig, "out_rig") }?;
        // SAFETY: the caller passes a readable desc of at least its struct_size bytes.
        let desc = unsafe { read_versioned(desc) }?;
        // SAFETY: the desc's arrays and strings are the caller's, as documented.
        let mapped = unsafe { desc.map() }?;
        let chain = cg_chain_desc::from_core_in_units(&mapped.chain, desc.crowd_units_per_metre);
        let report = mapped.report();
        let rig = Box::new(RigHandle {
            mapped,
            chain,
            report,
            poison: Poison::default(),
            #[cfg(feature = "test-hooks")]
            panic_next: std::sync::atomic::AtomicBool::new(false),
        });
        out_rig.write(into_c(rig));
        Ok(())
    })
}

/// Destroys a rig created by `cg_rig_create` and frees everything it owns.
///
/// NULL is accepted and ignored. The handle must not be used afterwards, and no other call
/// on this rig may be running.
#[no_mangle]
pub unsafe extern "C" fn cg_rig_destroy(rig: *mut cg_rig) {
    // SAFETY: a rig handle from cg_rig_create (or NULL), destroyed once and not in use (the
    // caller's contract).
    unsafe { super::handle::destroy::<RigHandle>(rig) }
}

/// Reborrows a rig handle; runs the test hook.
///
/// # Safety
/// `rig`, if not NULL, must be a live handle from `cg_rig_create`.
unsafe fn rig_ref<'a>(rig: *const cg_rig) -> Result<&'a RigHandle> {
    // SAFETY: forwarded contract; a rig is never borrowed mutably.
    let handle = unsafe { handle_ref::<RigHandle>(rig) }?;
    handle.test_hook();
    Ok(handle)
}

/// Reborrows a rig handle for the test hooks.
///
/// # Safety
/// `rig`, if not NULL, must be a live handle from `cg_rig_create`.
#[cfg(feature = "test-hooks")]
pub(crate) unsafe fn rig_handle<'a>(rig: *const cg_rig) -> Result<&'a RigHandle> {
    // SAFETY: forwarded contract.
    unsafe { handle_ref::<RigHandle>(rig) }
}

/// Writes the rig's gaze chain to `*out_chain`: ready for `cg_character_desc.chain` of a
/// crowd whose axes and `units_per_metre` are the desc's `crowd_up`, `crowd_forward` and
/// `crowd_units_per_metre` (lengths are in those units; the crowd divides them back into
/// the mapped chain). Set `out_chain->struct_size = sizeof(cg_chain_desc)` first: at most
/// that many bytes are written, and `struct_size` keeps its value. The caller owns
/// `out_chain`.
///
/// Errors (nothing written): `CG_STATUS_NULL_ARGUMENT` (`rig` or `out_chain` NULL),
/// `CG_STATUS_BAD_STRUCT_SIZE` (`struct_size` not a size the library knows). Allocates
/// nothing; may run concurrently with other calls on this rig.
#[no_mangle]
pub unsafe extern "C" fn cg_rig_chain(
    rig: *const cg_rig,
    out_chain: *mut cg_chain_desc,
) -> cg_status {
    ffi_boundary!({
        // SAFETY: handle contract of cg_rig.
        let rig = unsafe { rig_ref(rig) }?;
        // SAFETY: the caller passes a cg_chain_desc it owns, of at least its struct_size
        // bytes (or NULL).
        unsafe { write_versioned(out_chain, rig.chain, "out_chain") }
    })
}

/// Writes the rig's number of bones (the `bone_count` it was created with) to `*out_count`.
///
/// Errors (nothing written): `CG_STATUS_NULL_ARGUMENT`. Allocates nothing; may run
/// concurrently with other calls on this rig.
#[no_mangle]
pub unsafe extern "C" fn cg_rig_bone_count(rig: *const cg_rig, out_count: *mut u32) -> cg_status {
    // SAFETY: forwarded contract.
    ffi_boundary!({ unsafe { write_count(rig, out_count, MappedChain::bone_count) } })
}

/// Writes the number of joints of the rig's gaze chain (its `cg_chain_desc.joint_count`,
/// 1 to `CG_MAX_CHAIN_JOINTS`) to `*out_count`.
///
/// Errors (nothing written): `CG_STATUS_NULL_ARGUMENT`. Allocates nothing; may run
/// concurrently with other calls on this rig.
#[no_mangle]
pub unsafe extern "C" fn cg_rig_joint_count(rig: *const cg_rig, out_count: *mut u32) -> cg_status {
    // SAFETY: forwarded contract.
    ffi_boundary!({ unsafe { write_count(rig, out_count, MappedChain::joint_count) } })
}

/// Writes one of the rig's counts to `*out_count`.
///
/// # Safety
/// `rig`, if not NULL, must be a live rig; `out_count`, if not NULL and aligned, writable.
unsafe fn write_count(
    rig: *const cg_rig,
    out_count: *mut u32,
    count: fn(&MappedChain) -> usize,
) -> Result<()> {
    // SAFETY: handle contract of cg_rig.
    let rig = unsafe { rig_ref(rig) }?;
    // SAFETY: the caller provides a writable uint32_t (or NULL, rejected).
    let out_count = unsafe { Out::new(out_count, "out_count") }?;
    out_count.write(count(&rig.mapped) as u32);
    Ok(())
}

/// Writes one value per element of a list of the rig's (`list` picks it, `value` converts
/// each element) into `out[0 .. its length]`; `of` names the elements in errors.
///
/// # Safety
/// `rig`, if not NULL, must be a live rig; `out`, if not NULL and aligned, must hold
/// `out_len` writable uint32_t.
unsafe fn write_list<T: Copy>(
    rig: *const cg_rig,
    out: *mut u32,
    out_len: usize,
    (what, of): (&str, &str),
    list: fn(&MappedChain) -> &[T],
    value: fn(T) -> u32,
) -> Result<()> {
    // SAFETY: handle contract of cg_rig.
    let rig = unsafe { rig_ref(rig) }?;
    // SAFETY: the caller provides `out_len` writable uint32_t (or (NULL, 0)).
    let out = unsafe { slice_mut(out, out_len, what) }?;
    let list = list(&rig.mapped);
    ensure_room(out.len(), list.len(), "out_len", of)?;
    for (slot, &element) in out.iter_mut().zip(list) {
        *slot = value(element);
    }
    Ok(())
}

/// Checks that an output array of `length` elements holds `needed`, naming it `what`.
fn ensure_room(length: usize, needed: usize, what: &str, of: &str) -> Result<()> {
    if length < needed {
        return Err(Error::InvalidArgument(format!(
            "{what} is {length}, the rig has {needed} {of}"
        ))
        .into());
    }
    Ok(())
}

/// Writes the bone index of each chain joint, bottom to top (spine, neck, head, then the
/// left and right eye if the chain has eyes), into `out_bones[0 .. joint count]`
/// (`out_len` at least `cg_rig_joint_count`'s; entries past it are left alone). The caller
/// owns `out_bones`.
///
/// Errors (nothing written): `CG_STATUS_NULL_ARGUMENT`, `CG_STATUS_INVALID_ARGUMENT`
/// (`out_len` below the joint count). Allocates nothing; may run concurrently with other
/// calls on this rig.
#[no_mangle]
pub unsafe extern "C" fn cg_rig_chain_bones(
    rig: *const cg_rig,
    out_bones: *mut u32,
    out_len: usize,
) -> cg_status {
    ffi_boundary!({
        let what = ("out_bones", "chain joints");
        // SAFETY: forwarded contract.
        unsafe { write_list(rig, out_bones, out_len, what, |m| &m.bones, |b| b as u32) }
    })
}

/// Writes the role (a `cg_bone_role`) of every bone, in the skeleton's order, into
/// `out_roles[0 .. bone count]` (`out_len` at least `cg_rig_bone_count`'s; entries past it
/// are left alone). A bone may have a role without being in the chain (the root, a spine
/// bone below the chain root): `cg_rig_chain_bones` lists the chain's. The caller owns
/// `out_roles`.
///
/// Errors (nothing written): `CG_STATUS_NULL_ARGUMENT`, `CG_STATUS_INVALID_ARGUMENT`
/// (`out_len` below the bone count). Allocates nothing; may run concurrently with other
/// calls on this rig.
#[no_mangle]
pub unsafe extern "C" fn cg_rig_bone_roles(
    rig: *const cg_rig,
    out_roles: *mut u32,
    out_len: usize,
) -> cg_status {
    ffi_boundary!({
        let what = ("out_roles", "bones");
        let role = cg_bone_role::from_role;
        // SAFETY: forwarded contract.
        unsafe { write_list(rig, out_roles, out_len, what, |m| &m.roles, role) }
    })
}

/// Copies the rig's mapping report into `buffer` and returns its full length in bytes (not
/// counting the terminating NUL), as `cg_last_error_message` does.
///
/// The report is a few lines of English (each ending with `\n`): the chain (`gaze chain of
/// 10 joints: 5 spine, 2 neck, head, 2 eyes; hangs from 'Hips'`), the skeleton's up and
/// forward and how they were found, the role of each chain bone and whether it came from
/// its name or an override, and notes (a chain without neck, an eye under facial bones).
///
/// `buffer` may be NULL or `buffer_len` 0: nothing is written and the length is still
/// returned, so a caller can size a buffer. Otherwise at most `buffer_len - 1` bytes are
/// copied, always followed by a NUL; a return value `>= buffer_len` means the report was
/// truncated. The caller owns `buffer`. Returns 0 (and writes nothing) if `rig` is NULL.
/// Allocates nothing; may run concurrently with other calls on this rig.
#[no_mangle]
pub unsafe extern "C" fn cg_rig_report(
    rig: *const cg_rig,
    buffer: *mut c_char,
    buffer_len: usize,
) -> usize {
    ffi_boundary!(0; {
        // SAFETY: handle contract of cg_rig.
        let rig = unsafe { rig_ref(rig) }?;
        // SAFETY: the caller's buffer of `buffer_len` writable bytes (or NULL).
        Ok(unsafe { super::last_error::copy_text(&rig.report, buffer, buffer_len) })
    })
}

/// A caller's bone rotations, read in place.
struct CallerBones<'a>(&'a [cg_quat]);

impl BoneRotations for CallerBones<'_> {
    fn bone_count(&self) -> usize {
        self.0.len()
    }
    /// Normalised (each was checked finite and not zero): a product along a long path of
    /// tiny or huge quaternions cannot underflow or overflow.
    fn rotation(&self, bone: usize) -> Quat {
        let q = self.0[bone];
        let q = Quat::from_xyzw(q.x, q.y, q.z, q.w);
        q / q.length()
    }
}

/// A caller's bone rotations, read and written in place.
struct CallerBonesMut<'a>(&'a mut [cg_quat]);

impl BoneRotations for CallerBonesMut<'_> {
    fn bone_count(&self) -> usize {
        self.0.len()
    }
    fn rotation(&self, bone: usize) -> Quat {
        CallerBones(self.0).rotation(bone)
    }
}

impl BoneRotationsMut for CallerBonesMut<'_> {
    fn set_rotation(&mut self, bone: usize, rotation: Quat) {
        self.0[bone] = rotation.into();
    }
}

/// Checks the caller's bone rotations: as many as the rig's bones, each that the
/// conversions read finite and not zero. Allocates only on failure.
fn check_bones(rig: &RigHandle, bones: &[cg_quat], what: &str) -> Result<()> {
    let expected = rig.mapped.bone_count();
    if bones.len() != expected {
        return Err(Error::InvalidArgument(format!(
            "bone_count is {}, the rig has {expected} bones",
            bones.len()
        ))
        .into());
    }
    // Only the bones the conversions read: a skeleton's fingers and faces are most of its
    // bones, and checking them all would cost more than the conversion.
    for &index in rig.mapped.bones_read() {
        element_unit(bones[index as usize], what, index as usize)?;
    }
    Ok(())
}

/// Turns your engine's bone local rotations into the crowd's base pose for one character:
/// `bone_rotations` holds one rotation per bone (`bone_count` = the rig's, the skeleton's
/// order, each relative to its parent, as your animation poses them this frame), and
/// `out_base[0 .. joint count]` receives each chain joint's base rotation, bottom to top,
/// ready for `cg_crowd_set_base_pose` (`out_len` at least `cg_rig_joint_count`'s; entries
/// past it are left alone). Rotations of the chain root's ancestors and of bones between
/// chain joints are folded in; the first joint's is turned into the crowd's axes. Inputs
/// are normalised; both arrays stay the caller's.
///
/// Only the rotations of the chain's bones, the bones between them and the chain root's
/// ancestors are read: the others (fingers, faces) may hold anything.
///
/// Errors (nothing written): `CG_STATUS_NULL_ARGUMENT`, `CG_STATUS_NON_FINITE` (a NaN or
/// infinite rotation of a bone read), `CG_STATUS_INVALID_ARGUMENT` (`bone_count` not the
/// rig's, `out_len` below the joint count, a zero rotation of a bone read). Allocates nothing; may run
/// concurrently with other calls on this rig.
#[no_mangle]
pub unsafe extern "C" fn cg_rig_base_pose(
    rig: *const cg_rig,
    bone_rotations: *const cg_quat,
    bone_count: usize,
    out_base: *mut cg_quat,
    out_len: usize,
) -> cg_status {
    ffi_boundary!({
        // SAFETY: handle contract of cg_rig.
        let rig = unsafe { rig_ref(rig) }?;
        // SAFETY: the caller passes `bone_count` readable cg_quat (or (NULL, 0)).
        let bones = unsafe { slice(bone_rotations, bone_count, "bone_rotations") }?;
        // SAFETY: the caller provides `out_len` writable cg_quat (or (NULL, 0)), not
        // overlapping `bone_rotations`.
        let out = unsafe { slice_mut(out_base, out_len, "out_base") }?;
        check_bones(rig, bones, "bone_rotations")?;
        let joints = rig.mapped.joint_count();
        ensure_room(out.len(), joints, "out_len", "chain joints")?;
        let mut base = [Quat::IDENTITY; MAX_CHAIN_JOINTS];
        rig.mapped
            .base_pose_of(&CallerBones(bones), &mut base[..joints])?;
        for (slot, rotation) in out.iter_mut().zip(&base[..joints]) {
            *slot = (*rotation).into();
        }
        Ok(())
    })
}

/// Writes the crowd's gaze result for one character back into your engine's bone local
/// rotations, in place: `joints` holds the character's chain joints' final local rotations
/// (`joint_count` = the rig's, bottom to top, as `cg_crowd_read_joints` gives them for
/// this character), and `bone_rotations` the skeleton's bone local rotations
/// (`bone_count` = the rig's), posed as for `cg_rig_base_pose` this frame. Each chain
/// joint's bone gets the local rotation that, with the other bones as they are, makes the
/// joint's; every other bone is left as it was. Inputs are normalised; both arrays stay
/// the caller's.
///
/// Bones that are not read for `cg_rig_base_pose` are neither read nor written here.
///
/// Errors (nothing written): `CG_STATUS_NULL_ARGUMENT`, `CG_STATUS_NON_FINITE` (a NaN or
/// infinite rotation: of a joint, or of a bone read), `CG_STATUS_INVALID_ARGUMENT`
/// (`joint_count` or `bone_count` not the rig's, a zero rotation). Allocates nothing; may run concurrently with other calls on
/// this rig.
#[no_mangle]
pub unsafe extern "C" fn cg_rig_write_joints(
    rig: *const cg_rig,
    joints: *const cg_quat,
    joint_count: usize,
    bone_rotations: *mut cg_quat,
    bone_count: usize,
) -> cg_status {
    ffi_boundary!({
        // SAFETY: handle contract of cg_rig.
        let rig = unsafe { rig_ref(rig) }?;
        // SAFETY: the caller passes `joint_count` readable cg_quat (or (NULL, 0)).
        let given = unsafe { slice(joints, joint_count, "joints") }?;
        // SAFETY: the caller provides `bone_count` readable and writable cg_quat (or
        // (NULL, 0)), not overlapping `joints`.
        let bones = unsafe { slice_mut(bone_rotations, bone_count, "bone_rotations") }?;
        check_bones(rig, bones, "bone_rotations")?;
        let expected = rig.mapped.joint_count();
        if given.len() != expected {
            return Err(Error::InvalidArgument(format!(
                "joint_count is {}, the rig's chain has {expected} joints",
                given.len()
            ))
            .into());
        }
        let mut rotations = [Quat::IDENTITY; MAX_CHAIN_JOINTS];
        for (index, (slot, &q)) in rotations.iter_mut().zip(given).enumerate() {
            *slot = element_unit(q, "joints", index)?;
        }
        let mut bones = CallerBonesMut(bones);
        Ok(rig
            .mapped
            .write_joints_into(&rotations[..expected], &mut bones)?)
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn roles_match_their_c_values() {
        for (role, value) in [
            (BoneRole::None, 0),
            (BoneRole::Root, 1),
            (BoneRole::Spine, 2),
            (BoneRole::Neck, 3),
            (BoneRole::Head, 4),
            (BoneRole::LeftEye, 5),
            (BoneRole::RightEye, 6),
        ] {
            assert_eq!(cg_bone_role::from_role(role), value);
        }
        let defaults = cg_rig_desc::defaults();
        assert_eq!(
            defaults.struct_size as usize,
            std::mem::size_of::<cg_rig_desc>()
        );
        assert_eq!(defaults.up, CG_RIG_AXIS_DETECT);
    }
}
