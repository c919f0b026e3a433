//! The C ABI, and only that: check every argument coming from C, convert it to the Rust
//! core's types, forward the call, convert the result back. No algorithm lives here.
//!
//! Every `extern "C"` body runs inside `ffi_boundary!`, which catches panics (they never
//! cross into C), poisons the handle a failed call was changing (`poison`), records the
//! error message for `cg_last_error_message`, and maps the error to a [`cg_status`].
//!
//! Unsafe code: most of the crate's lives here, reading and writing through the caller's
//! pointers. The rest is in four places, each for speed or sharing: `math::wide` (SIMD
//! intrinsics, run only after the processor's check), `attention::candidates` (unchecked
//! loads within padding it asserts), `crowd::states` and `crowd::step` (disjoint character
//! ranges stepped from several threads) and `crowd::pool` (the worker threads' shared run).
//! Every unsafe block says why it is sound in a `// SAFETY:` comment, and every unsafe
//! operation sits in one (`unsafe_op_in_unsafe_fn` and `clippy::undocumented_unsafe_blocks`
//! are errors, Cargo.toml).
#![allow(non_camel_case_types)]
// C callers cannot see Rust's `unsafe`: every pointer is checked (NULL, alignment, size)
// before use, and the remaining validity contract is written in each function's doc.
#![allow(clippy::not_unsafe_ptr_arg_deref)]

pub mod attention;
pub mod blend;
pub mod chain;
pub mod crowd;
pub mod gaze;
pub mod last_error;
mod poison;
pub mod status;
#[cfg(feature = "test-hooks")]
pub mod testing;
pub mod types;
pub mod version;

pub use status::cg_status;

use crate::error::{Error, Result};

/// Runs a C entry point's body, which evaluates to `Result<()>`, inside the panic boundary
/// ([`run_boundary`]) and turns its outcome into a `cg_status`.
///
/// `ffi_boundary!(value_on_error; body)` is the form for functions that return a value
/// instead of a status: the body evaluates to `Result<T>` and `value_on_error` is returned
/// (after recording the message) on an error or a panic.
macro_rules! ffi_boundary {
    ($body:block) => {{
        match $crate::ffi::run_boundary(|| -> $crate::error::Result<()> { $body }) {
            Ok(()) => $crate::ffi::status::cg_status::Ok,
            Err(error) => $crate::ffi::last_error::record(&error),
        }
    }};
    ($on_error:expr; $body:block) => {{
        match $crate::ffi::run_boundary(|| $body) {
            Ok(value) => value,
            Err(error) => {
                $crate::ffi::last_error::record(&error);
                $on_error
            }
        }
    }};
}
pub(crate) use ffi_boundary;

/// Runs a C entry point's body: a panic is caught and becomes [`Error::Internal`], and if
/// the body armed a handle's poison ([`poison::arm`]) and failed inside the library, that
/// handle is poisoned.
pub(crate) fn run_boundary<T>(body: impl FnOnce() -> Result<T>) -> Result<T> {
    let outer = poison::enter();
    let result = match std::panic::catch_unwind(std::panic::AssertUnwindSafe(body)) {
        Ok(result) => result,
        Err(payload) => Err(panic_error(payload)),
    };
    poison::leave(outer, &result);
    result
}

/// Turns a caught panic's payload into an [`Error::Internal`] carrying its message.
pub(crate) fn panic_error(payload: Box<dyn std::any::Any + Send>) -> Error {
    let message = if let Some(text) = payload.downcast_ref::<&str>() {
        (*text).to_owned()
    } else if let Some(text) = payload.downcast_ref::<String>() {
        text.clone()
    } else {
        "panic with a non-text payload".to_owned()
    };
    Error::Internal(format!("caught panic: {message}"))
}

/// Writes `value` through an optional output pointer: nothing if it is NULL.
///
/// # Safety
/// If not NULL, `pointer` must be valid for a write of a `T` (alignment not required).
pub(crate) unsafe fn write_optional<T>(pointer: *mut T, value: T) {
    if !pointer.is_null() {
        // SAFETY: non-null and writable by the caller's contract; unaligned is allowed.
        unsafe { pointer.write_unaligned(value) };
    }
}

/// Fails with [`Error::NullArgument`] naming `what` if `pointer` is NULL.
pub(crate) fn non_null<T>(pointer: *const T, what: &str) -> Result<()> {
    if pointer.is_null() {
        Err(Error::NullArgument(format!("{what} is NULL")))
    } else {
        Ok(())
    }
}

/// Checks that `pointer` may be dereferenced as a `T`: not NULL and aligned for `T`.
fn check_pointer<T>(pointer: *const T, what: &str) -> Result<()> {
    non_null(pointer, what)?;
    if !(pointer as usize).is_multiple_of(std::mem::align_of::<T>()) {
        return Err(Error::InvalidArgument(format!(
            "{what} is not aligned to {} bytes",
            std::mem::align_of::<T>()
        )));
    }
    Ok(())
}

/// Borrows a C object read-only, after checking the pointer.
///
/// # Safety
/// If not NULL and aligned, `pointer` must point to a valid `T` that stays valid and
/// unaliased by writers for `'a`.
pub(crate) unsafe fn borrow<'a, T>(pointer: *const T, what: &str) -> Result<&'a T> {
    check_pointer(pointer, what)?;
    // SAFETY: checked non-null and aligned; validity is the caller's contract.
    Ok(unsafe { &*pointer })
}

/// Borrows a C object mutably, after checking the pointer.
///
/// # Safety
/// If not NULL and aligned, `pointer` must point to a valid `T`, not aliased for `'a`.
pub(crate) unsafe fn borrow_mut<'a, T>(pointer: *mut T, what: &str) -> Result<&'a mut T> {
    check_pointer(pointer, what)?;
    // SAFETY: checked non-null and aligned; validity and exclusivity are the caller's contract.
    Ok(unsafe { &mut *pointer })
}

/// Views a C array `(pointer, count)` as a slice. `(NULL, 0)` is an empty slice;
/// `(NULL, n > 0)` is [`Error::NullArgument`].
///
/// # Safety
/// If `count > 0` and `pointer` is not NULL, it must point to `count` valid, initialised `T`s
/// that no one writes for `'a`.
pub(crate) unsafe fn slice<'a, T>(pointer: *const T, count: usize, what: &str) -> Result<&'a [T]> {
    if count == 0 {
        return Ok(&[]);
    }
    check_array::<T>(pointer, count, what)?;
    // SAFETY: checked non-null, aligned and size-bounded; validity is the caller's contract.
    Ok(unsafe { std::slice::from_raw_parts(pointer, count) })
}

/// Views a C output array `(pointer, count)` as a mutable slice, with the same rules as
/// [`slice()`].
///
/// # Safety
/// If `count > 0` and `pointer` is not NULL, it must point to `count` writable `T`s that no
/// one else accesses for `'a`.
pub(crate) unsafe fn slice_mut<'a, T>(
    pointer: *mut T,
    count: usize,
    what: &str,
) -> Result<&'a mut [T]> {
    if count == 0 {
        return Ok(&mut []);
    }
    check_array::<T>(pointer, count, what)?;
    // SAFETY: checked non-null, aligned and size-bounded; validity is the caller's contract.
    Ok(unsafe { std::slice::from_raw_parts_mut(pointer, count) })
}

fn check_array<T>(pointer: *const T, count: usize, what: &str) -> Result<()> {
    if pointer.is_null() {
        return Err(Error::NullArgument(format!(
            "{what} is NULL but its count is {count}"
        )));
    }
    check_pointer(pointer, what)?;
    match count.checked_mul(std::mem::size_of::<T>().max(1)) {
        Some(bytes) if bytes <= isize::MAX as usize => Ok(()),
        _ => Err(Error::InvalidArgument(format!(
            "{what} has an impossible count {count}"
        ))),
    }
}

/// A C struct that starts with `uint32_t struct_size`, so that fields can be appended in
/// later versions without breaking callers compiled against older headers.
///
/// The caller states its struct's size in `struct_size` before every call that reads or
/// writes the struct (its `_init` function included), and the library never reads or
/// writes past it: an older caller's struct is shorter than this library's.
pub(crate) trait Versioned: Copy {
    /// Every `struct_size` this library accepts: the sizes (C's `sizeof`) of the layouts
    /// that headers declared, oldest first, ending with `size_of::<Self>()`. Fields past a
    /// caller's `struct_size` take their defaults.
    const SIZES: &'static [usize];
    /// The struct filled with its documented defaults and the current `struct_size`.
    fn defaults() -> Self;
    /// Name used in error messages.
    const NAME: &'static str;
}

/// C's `sizeof` of an older layout of `T` whose last field ends at byte `end`: the
/// compiler pads a struct to a multiple of its alignment.
pub(crate) const fn layout_size<T>(end: usize) -> usize {
    end.next_multiple_of(std::mem::align_of::<T>())
}

/// Reads and checks the `struct_size` that a versioned struct from C starts with, and
/// returns it in bytes.
///
/// # Safety
/// `pointer` must be non-null and aligned for `T`, and its first 4 bytes readable and
/// initialised by the caller.
unsafe fn stated_size<T: Versioned>(pointer: *const T) -> Result<usize> {
    // SAFETY: every versioned struct starts with a u32 `struct_size`; the pointer is non-null
    // and aligned for T, hence for u32, and those 4 bytes are the caller's (contract).
    let declared = unsafe { pointer.cast::<u32>().read() } as usize;
    if T::SIZES.contains(&declared) {
        return Ok(declared);
    }
    let known: Vec<String> = T::SIZES.iter().rev().map(usize::to_string).collect();
    Err(Error::BadStructSize(format!(
        "{0}.struct_size is {declared}, not a size this library knows ({1}): set it to \
         sizeof({0}) before the call",
        T::NAME,
        known.join(" or "),
    )))
}

/// Reads a versioned struct from C: checks the pointer and `struct_size`, then copies the
/// caller's prefix over the defaults.
///
/// # Safety
/// If not NULL and aligned, `pointer` must point to at least `struct_size` readable bytes,
/// where `struct_size` is the struct's first field.
pub(crate) unsafe fn read_versioned<T: Versioned>(pointer: *const T) -> Result<T> {
    check_pointer(pointer, T::NAME)?;
    // SAFETY: checked non-null and aligned; the struct starts with its size (contract).
    let declared = unsafe { stated_size(pointer) }?;
    let mut value = T::defaults();
    // SAFETY: `declared <= size_of::<T>()` bytes are readable at `pointer` (caller contract)
    // and writable in `value`; the regions do not overlap. Every field is plain old data.
    unsafe {
        std::ptr::copy_nonoverlapping(
            pointer.cast::<u8>(),
            (&mut value as *mut T).cast::<u8>(),
            declared,
        );
    }
    Ok(value)
}

/// Writes a versioned struct to C: checks the pointer (`what` names it in errors) and the
/// `struct_size` the caller set, then copies that many bytes of `value`, whose own
/// `struct_size` becomes the caller's. Nothing is written on an error.
///
/// # Safety
/// If not NULL and aligned, `pointer` must point to a `uint32_t struct_size` the caller
/// set, followed by writable bytes up to `struct_size` in all.
pub(crate) unsafe fn write_versioned<T: Versioned>(
    pointer: *mut T,
    value: T,
    what: &str,
) -> Result<()> {
    check_pointer(pointer, what)?;
    // SAFETY: checked non-null and aligned; the struct starts with its size (contract).
    let declared = unsafe { stated_size(pointer.cast_const()) }?;
    let mut value = value;
    // SAFETY: `value` is a T, which starts with its u32 `struct_size`.
    unsafe { (&mut value as *mut T).cast::<u32>().write(declared as u32) };
    // SAFETY: `declared <= size_of::<T>()` bytes are readable in `value` and writable at
    // `pointer` (caller contract); the regions do not overlap. No `&mut T` to the caller's
    // memory is made: it may be shorter than a T.
    unsafe {
        std::ptr::copy_nonoverlapping(
            (&value as *const T).cast::<u8>(),
            pointer.cast::<u8>(),
            declared,
        );
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn failing(kind: u8) -> cg_status {
        ffi_boundary!({
            match kind {
                0 => Ok(()),
                1 => Err(Error::NotFound("entity 7".into())),
                _ => panic!("boom {kind}"),
            }
        })
    }

    #[test]
    fn boundary_maps_errors_and_catches_panics() {
        assert_eq!(failing(0), cg_status::Ok);
        assert_eq!(failing(1), cg_status::NotFound);
        assert_eq!(last_error::last_error_message(), "not found: entity 7");
        let hook = std::panic::take_hook();
        std::panic::set_hook(Box::new(|_| {}));
        let status = failing(2);
        std::panic::set_hook(hook);
        assert_eq!(status, cg_status::Internal);
        assert_eq!(
            last_error::last_error_message(),
            "internal error: caught panic: boom 2"
        );
    }

    /// A call that arms `poison` and then fails with `kind` (0 ok, 1 not found, 2 panic,
    /// 3 internal error).
    fn changing(poison: &poison::Poison, kind: u8) -> cg_status {
        ffi_boundary!({
            poison.check()?;
            poison::arm(poison);
            match kind {
                0 => Ok(()),
                1 => Err(Error::NotFound("entity 7".into())),
                2 => panic!("boom {kind}"),
                _ => Err(Error::Internal("half done".into())),
            }
        })
    }

    #[test]
    fn an_internal_failure_poisons_the_armed_handle() {
        let hook = std::panic::take_hook();
        std::panic::set_hook(Box::new(|_| {}));
        for (kind, first) in [
            (2, "internal error: caught panic: boom 2"),
            (3, "internal error: half done"),
        ] {
            let poison = poison::Poison::default();
            assert_eq!(changing(&poison, 0), cg_status::Ok);
            assert_eq!(changing(&poison, 1), cg_status::NotFound, "not internal");
            assert_eq!(changing(&poison, kind), cg_status::Internal);
            assert_eq!(last_error::last_error_message(), first);
            for _ in 0..2 {
                assert_eq!(changing(&poison, 0), cg_status::Poisoned);
                assert_eq!(
                    last_error::last_error_message(),
                    format!("poisoned: an earlier call failed inside the library: {first}")
                );
            }
            // A call that armed nothing poisons nothing.
            assert_eq!(failing(2), cg_status::Internal);
        }
        std::panic::set_hook(hook);
    }

    #[test]
    fn arrays_follow_the_null_and_count_rules() {
        // SAFETY: (NULL, 0) and (NULL, n) are never dereferenced; the real array is valid.
        unsafe {
            assert!(slice::<f32>(std::ptr::null(), 0, "a").unwrap().is_empty());
            assert!(matches!(
                slice::<f32>(std::ptr::null(), 3, "a"),
                Err(Error::NullArgument(_))
            ));
            let data = [1.0f32, 2.0];
            assert_eq!(slice(data.as_ptr(), 2, "a").unwrap(), &data);
            let misaligned = (data.as_ptr() as *const u8).add(1).cast::<f32>();
            assert!(matches!(
                slice(misaligned, 1, "a"),
                Err(Error::InvalidArgument(_))
            ));
            assert!(matches!(
                slice(data.as_ptr(), usize::MAX / 2, "a"),
                Err(Error::InvalidArgument(_))
            ));
        }
    }
}
