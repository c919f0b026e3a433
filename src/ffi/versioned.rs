//! Versioned structs: C structs that start with `uint32_t struct_size`, read and written
//! only up to the size the caller states, so that older callers keep working.

use super::error::{FfiError, Result};
use super::pointers::check_pointer;

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
    Err(FfiError::BadStructSize(format!(
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
#[inline]
pub(crate) unsafe fn read_versioned<T: Versioned>(pointer: *const T) -> Result<T> {
    // The common case inline (arrays of states are read element by element): a struct of
    // this library's own layout.
    if !pointer.is_null() && pointer.is_aligned() {
        // SAFETY: non-null and aligned; the struct starts with its u32 size (contract).
        let declared = unsafe { pointer.cast::<u32>().read() } as usize;
        if declared == std::mem::size_of::<T>() {
            // SAFETY: the caller's struct is this library's layout, all of it readable
            // (contract); every field is plain old data.
            return Ok(unsafe { pointer.read() });
        }
    }
    // SAFETY: forwarded contract.
    unsafe { read_older_versioned(pointer) }
}

/// Borrows a versioned struct from C in place if it has this library's own layout
/// (non-null, aligned, `struct_size` this library's); `None` otherwise (then read it with
/// [`read_versioned`], which reports what is wrong). For hot loops over arrays: no copy.
///
/// # Safety
/// If not NULL and aligned, `pointer` must point to at least `struct_size` readable bytes,
/// where `struct_size` is the struct's first field, valid and unchanged for `'a`.
#[inline]
pub(crate) unsafe fn borrow_current<'a, T: Versioned>(pointer: *const T) -> Option<&'a T> {
    if pointer.is_null() || !pointer.is_aligned() {
        return None;
    }
    // SAFETY: non-null and aligned; the struct starts with its u32 size (contract).
    let declared = unsafe { pointer.cast::<u32>().read() } as usize;
    // SAFETY: of this library's layout, all of it readable and valid for 'a (contract);
    // every field is plain old data.
    (declared == std::mem::size_of::<T>()).then(|| unsafe { &*pointer })
}

/// [`read_versioned`] for every other case: an older layout, or a bad pointer or size.
///
/// # Safety
/// As [`read_versioned`].
#[cold]
#[inline(never)]
unsafe fn read_older_versioned<T: Versioned>(pointer: *const T) -> Result<T> {
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
