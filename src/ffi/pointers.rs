//! The caller's pointers, checked once: input arrays as slices, and outputs as [`Out`]. A
//! pointer must be aligned for its type; NULL and misaligned pointers fail with a message
//! naming the argument.

use std::marker::PhantomData;

use super::error::{FfiError, Result};
use crate::error::Error;

/// Fails with [`FfiError::NullArgument`] naming `what` if `pointer` is NULL.
pub(crate) fn non_null<T>(pointer: *const T, what: &str) -> Result<()> {
    if pointer.is_null() {
        Err(FfiError::NullArgument(format!("{what} is NULL")))
    } else {
        Ok(())
    }
}

/// Checks that `pointer` may be dereferenced as a `T`: not NULL and aligned for `T`.
pub(crate) fn check_pointer<T>(pointer: *const T, what: &str) -> Result<()> {
    non_null(pointer, what)?;
    if !(pointer as usize).is_multiple_of(std::mem::align_of::<T>()) {
        return Err(Error::InvalidArgument(format!(
            "{what} is not aligned to {} bytes",
            std::mem::align_of::<T>()
        ))
        .into());
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

/// Where a C call writes one result: a caller's pointer checked (not NULL, aligned) when
/// the `Out` is made, before the call does anything, so that writing it cannot fail.
///
/// Check every output first, then compute, then write: a failed call writes nothing.
pub(crate) struct Out<'a, T> {
    pointer: *mut T,
    _caller: PhantomData<&'a mut T>,
}

impl<'a, T> Out<'a, T> {
    /// Checks an output the caller must provide.
    ///
    /// # Safety
    /// If not NULL and aligned, `pointer` must be valid for a write of a `T` for `'a`, and
    /// not read or written by anything else meanwhile.
    pub(crate) unsafe fn new(pointer: *mut T, what: &str) -> Result<Out<'a, T>> {
        check_pointer(pointer, what)?;
        Ok(Out {
            pointer,
            _caller: PhantomData,
        })
    }

    /// Checks an output the caller may leave NULL (then nothing is written).
    ///
    /// # Safety
    /// As [`Out::new`].
    pub(crate) unsafe fn optional(pointer: *mut T, what: &str) -> Result<Option<Out<'a, T>>> {
        if pointer.is_null() {
            return Ok(None);
        }
        // SAFETY: forwarded contract.
        unsafe { Out::new(pointer, what) }.map(Some)
    }

    /// Writes the result. The caller's previous value is not read or dropped (C data).
    pub(crate) fn write(self, value: T) {
        // SAFETY: checked non-null and aligned in `new`; writable for 'a by its contract.
        unsafe { self.pointer.write(value) };
    }
}

/// Writes `value` to an optional output, if there is one.
pub(crate) fn write_optional<T>(out: Option<Out<'_, T>>, value: T) {
    if let Some(out) = out {
        out.write(value);
    }
}

/// Views a C array `(pointer, count)` as a slice. `(NULL, 0)` is an empty slice;
/// `(NULL, n > 0)` is [`FfiError::NullArgument`].
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

/// Checks a C array: not NULL, aligned, and `count` elements fit in the address space.
fn check_array<T>(pointer: *const T, count: usize, what: &str) -> Result<()> {
    if pointer.is_null() {
        return Err(FfiError::NullArgument(format!(
            "{what} is NULL but its count is {count}"
        )));
    }
    check_pointer(pointer, what)?;
    match count.checked_mul(std::mem::size_of::<T>().max(1)) {
        Some(bytes) if bytes <= isize::MAX as usize => Ok(()),
        _ => Err(Error::InvalidArgument(format!("{what} has an impossible count {count}")).into()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn arrays_follow_the_null_and_count_rules() {
        // SAFETY: (NULL, 0) and (NULL, n) are never dereferenced; the real array is valid.
        unsafe {
            assert!(slice::<f32>(std::ptr::null(), 0, "a").unwrap().is_empty());
            assert!(matches!(
                slice::<f32>(std::ptr::null(), 3, "a"),
                Err(FfiError::NullArgument(_))
            ));
            let data = [1.0f32, 2.0];
            assert_eq!(slice(data.as_ptr(), 2, "a").unwrap(), &data);
            let misaligned = (data.as_ptr() as *const u8).add(1).cast::<f32>();
            assert!(matches!(
                slice(misaligned, 1, "a"),
                Err(FfiError::Core(Error::InvalidArgument(_)))
            ));
            assert!(matches!(
                slice(data.as_ptr(), usize::MAX / 2, "a"),
                Err(FfiError::Core(Error::InvalidArgument(_)))
            ));
        }
    }

    #[test]
    fn outputs_are_checked_before_they_are_written() {
        let mut slot = 0u32;
        // SAFETY: `slot` is a live u32; NULL and a misaligned pointer are never written.
        unsafe {
            Out::new(&mut slot, "out").unwrap().write(7);
            assert!(matches!(
                Out::<u32>::new(std::ptr::null_mut(), "out"),
                Err(FfiError::NullArgument(_))
            ));
            assert!(Out::<u32>::optional(std::ptr::null_mut(), "out")
                .unwrap()
                .is_none());
            let misaligned = (&mut slot as *mut u32).cast::<u8>().add(1).cast::<u32>();
            let error = Out::new(misaligned, "out_id").err().unwrap();
            assert_eq!(
                error.to_string(),
                "invalid argument: out_id is not aligned to 4 bytes"
            );
            write_optional(Out::optional(&mut slot, "out").unwrap(), 9);
        }
        assert_eq!(slot, 9);
    }
}
