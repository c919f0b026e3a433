//! The `cg_crowd` handle: its config struct, creation and destruction.

use super::types::cg_axis;
use super::{ffi_boundary, read_versioned, Versioned};
use crate::crowd::{Crowd, CrowdConfig};
use crate::error::Result;
use crate::world::World;

/// A crowd of characters and the objects they may look at (opaque).
///
/// Created by `cg_crowd_create`, destroyed by `cg_crowd_destroy`. Not safe for concurrent
/// mutation: calls taking a `cg_crowd*` must not overlap with any other call on the same
/// crowd. Calls taking a `const cg_crowd*` may run concurrently with each other.
pub struct cg_crowd {
    _private: [u8; 0],
}

/// Settings of a crowd, fixed for its lifetime. Fill it with `cg_crowd_config_init`, then
/// change the fields you need.
#[repr(C)]
#[derive(Debug, Clone, Copy)]
pub struct cg_crowd_config {
    /// Size of this struct in bytes, set by `cg_crowd_config_init`; lets later versions of
    /// the library add fields without breaking callers compiled against this header.
    pub struct_size: u32,
    /// Most characters (entities that look) the crowd holds at once, 1 to 16 777 216.
    /// Default 1024.
    pub max_characters: u32,
    /// Seed of every random choice; same inputs and seed give bit-identical outputs.
    /// Default 0x6372_6f77_6467_617a.
    pub seed: u64,
    /// Most scene objects (entities that are only looked at), 0 to 16 777 216. Default 256.
    pub max_objects: u32,
    /// Which world axis points up, a `cg_axis`. Default `CG_AXIS_POSITIVE_Y`.
    pub up_axis: u32,
    /// Which world axis heading 0 faces, a `cg_axis` perpendicular to `up_axis`.
    /// Headings are counter-clockwise about `up_axis`. Default `CG_AXIS_POSITIVE_Z`.
    pub forward_axis: u32,
    /// How many of your length units make one metre: 1 for metres (default), 100 for
    /// Unreal's centimetres. Must be > 0 and finite.
    pub units_per_metre: f32,
}

impl Versioned for cg_crowd_config {
    const MIN_SIZE: usize = std::mem::size_of::<cg_crowd_config>();
    const NAME: &'static str = "cg_crowd_config";

    fn defaults() -> Self {
        let core = CrowdConfig::default();
        cg_crowd_config {
            struct_size: std::mem::size_of::<cg_crowd_config>() as u32,
            max_characters: core.max_characters,
            seed: core.seed,
            max_objects: core.max_objects,
            up_axis: cg_axis::PositiveY as u32,
            forward_axis: cg_axis::PositiveZ as u32,
            units_per_metre: core.world.units_per_metre,
        }
    }
}

impl cg_crowd_config {
    /// Checks and converts to the core's config.
    fn to_core(self) -> Result<CrowdConfig> {
        let world = World::new(
            cg_axis::parse(self.up_axis, "up_axis")?,
            cg_axis::parse(self.forward_axis, "forward_axis")?,
            self.units_per_metre,
        )?;
        let config = CrowdConfig {
            seed: self.seed,
            max_characters: self.max_characters,
            max_objects: self.max_objects,
            world,
        };
        config.validate()?;
        Ok(config)
    }
}

/// Fills `config` with the defaults documented on each field, including `struct_size`.
///
/// Errors: `CG_STATUS_NULL_ARGUMENT` if `config` is NULL. Thread-safe.
#[no_mangle]
pub extern "C" fn cg_crowd_config_init(config: *mut cg_crowd_config) -> super::cg_status {
    ffi_boundary!({
        // SAFETY: the caller passes a pointer to a cg_crowd_config it owns (or NULL).
        let config = unsafe { super::borrow_mut(config, "config") }?;
        *config = cg_crowd_config::defaults();
        Ok(())
    })
}

/// Creates an empty crowd from `config` and stores its handle in `*out_crowd`.
///
/// All buffers are sized here from the capacities; later per-frame calls allocate nothing.
/// The caller owns the new crowd and must release it with `cg_crowd_destroy`.
/// `*out_crowd` is written only on success.
///
/// Errors: `CG_STATUS_NULL_ARGUMENT` (config or out_crowd NULL), `CG_STATUS_BAD_STRUCT_SIZE`
/// (config not filled by `cg_crowd_config_init`), `CG_STATUS_INVALID_ARGUMENT` (a field out of
/// range: capacities, axes not perpendicular or unknown, units_per_metre <= 0),
/// `CG_STATUS_NON_FINITE` (units_per_metre NaN or infinite). Thread-safe.
#[no_mangle]
pub extern "C" fn cg_crowd_create(
    config: *const cg_crowd_config,
    out_crowd: *mut *mut cg_crowd,
) -> super::cg_status {
    ffi_boundary!({
        super::non_null(out_crowd, "out_crowd")?;
        // SAFETY: the caller passes a readable config of at least its struct_size bytes.
        let config = unsafe { read_versioned(config) }?.to_core()?;
        let crowd = Box::new(Crowd::new(config)?);
        // SAFETY: out_crowd was checked non-null; the caller provides a writable slot.
        let out_crowd = unsafe { super::borrow_mut(out_crowd, "out_crowd") }?;
        *out_crowd = Box::into_raw(crowd).cast::<cg_crowd>();
        Ok(())
    })
}

/// Destroys a crowd created by `cg_crowd_create` and frees everything it owns.
///
/// NULL is accepted and ignored. The handle must not be used afterwards, and no other call
/// on this crowd may be running.
#[no_mangle]
pub extern "C" fn cg_crowd_destroy(crowd: *mut cg_crowd) {
    if crowd.is_null() {
        return;
    }
    let _ = ffi_boundary!({
        // SAFETY: a non-null crowd handle was produced by Box::into_raw in cg_crowd_create and
        // is destroyed once, by the caller's contract.
        drop(unsafe { Box::from_raw(crowd.cast::<Crowd>()) });
        Ok(())
    });
}

/// Reborrows a crowd handle as the core crowd.
///
/// # Safety
/// `crowd`, if not NULL, must be a live handle from `cg_crowd_create`, with no other
/// mutable access for `'a`.
pub(crate) unsafe fn crowd_ref<'a>(crowd: *const cg_crowd) -> Result<&'a Crowd> {
    // SAFETY: forwarded contract: a live handle is a Box<Crowd>.
    unsafe { super::borrow(crowd.cast::<Crowd>(), "crowd") }
}

/// Reborrows a crowd handle mutably as the core crowd.
///
/// # Safety
/// `crowd`, if not NULL, must be a live handle from `cg_crowd_create`, not accessed by
/// anything else for `'a`.
pub(crate) unsafe fn crowd_mut<'a>(crowd: *mut cg_crowd) -> Result<&'a mut Crowd> {
    // SAFETY: forwarded contract: a live handle is a Box<Crowd>.
    unsafe { super::borrow_mut(crowd.cast::<Crowd>(), "crowd") }
}

/// Copies the settings `crowd` was created with into `*out_config` (with the current
/// `struct_size`).
///
/// Errors: `CG_STATUS_NULL_ARGUMENT` if either pointer is NULL. Safe to call concurrently
/// with other `const` calls on the same crowd.
#[no_mangle]
pub extern "C" fn cg_crowd_get_config(
    crowd: *const cg_crowd,
    out_config: *mut cg_crowd_config,
) -> super::cg_status {
    ffi_boundary!({
        // SAFETY: handle contract of cg_crowd.
        let crowd = unsafe { crowd_ref(crowd) }?;
        // SAFETY: the caller provides a writable cg_crowd_config (or NULL).
        let out = unsafe { super::borrow_mut(out_config, "out_config") }?;
        let core = crowd.config();
        *out = cg_crowd_config {
            struct_size: std::mem::size_of::<cg_crowd_config>() as u32,
            max_characters: core.max_characters,
            seed: core.seed,
            max_objects: core.max_objects,
            up_axis: cg_axis::from_axis(core.world.up_axis),
            forward_axis: cg_axis::from_axis(core.world.forward_axis),
            units_per_metre: core.world.units_per_metre,
        };
        Ok(())
    })
}
