//! Fallible allocation: every buffer whose size comes from a caller's numbers (capacities,
//! clip lengths, recordings) is allocated through here, so that running out of memory is an
//! [`Error::OutOfMemory`] naming the number and the bytes asked, never an abort.
//!
//! Rust's infallible allocations (`Vec::with_capacity`, `vec![x; n]`, a `push` past the
//! capacity) abort the whole process when the allocator fails, and no `catch_unwind` sees
//! it: a capacity inside its documented range could kill an engine that asked for too much
//! (a 100 GB recording, a 16-million-character crowd under a 2 GiB address-space limit).
//! These helpers use `try_reserve_exact` instead, and count elements with checked
//! arithmetic ([`checked`](crate::alloc::checked)): a count that overflows `usize` fails the same way.
//!
//! A buffer is allocated exactly to the length asked (as `Vec::with_capacity` does), so a
//! fallible create sizes everything as the infallible one did.

use std::collections::HashMap;
use std::fmt::{self, Display};
use std::hash::Hash;
use std::mem::size_of;

use crate::error::{Error, Result};

/// A caller's number that buffers are sized from, as out-of-memory messages show it:
/// `Field("max_characters", 16777216)` reads `max_characters = 16777216`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Field(pub &'static str, pub u64);

impl Display for Field {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{} = {}", self.0, self.1)
    }
}

/// The error of a buffer of `count` `T`s for `what` that could not be allocated.
fn out_of_memory<T>(what: &dyn Display, count: usize) -> Error {
    // In u128, where no element count times an element size overflows.
    let bytes = count as u128 * size_of::<T>() as u128;
    Error::OutOfMemory(format!("{what} needs {bytes} bytes"))
}

/// `count`, or [`Error::OutOfMemory`] for `what` if computing it overflowed `usize` (pass
/// `a.checked_mul(b)`, `a.checked_add(b)`).
pub fn checked(count: Option<usize>, what: &dyn Display) -> Result<usize> {
    count.ok_or_else(|| {
        Error::OutOfMemory(format!(
            "{what} needs more than {} elements in one buffer",
            usize::MAX
        ))
    })
}

/// Grows `vec`'s capacity to hold exactly `additional` more elements, or fails with
/// [`Error::OutOfMemory`] for `what`, leaving `vec` as it was.
pub fn try_reserve_exact<T>(vec: &mut Vec<T>, additional: usize, what: &dyn Display) -> Result<()> {
    fault::check::<T>(what, additional)?;
    vec.try_reserve_exact(additional)
        .map_err(|_| out_of_memory::<T>(what, vec.len().saturating_add(additional)))
}

/// Makes room for `additional` more elements in `vec` (amortised growth, as `push` does),
/// or fails with [`Error::OutOfMemory`] for `what`, leaving `vec` as it was. For lists
/// that grow on explicit calls (distinct gaze chains, key cameras, planned constraints).
pub fn try_reserve<T>(vec: &mut Vec<T>, additional: usize, what: &dyn Display) -> Result<()> {
    fault::check::<T>(what, additional)?;
    vec.try_reserve(additional)
        .map_err(|_| out_of_memory::<T>(what, vec.len().saturating_add(additional)))
}

/// An empty vector with room for exactly `capacity` elements.
pub fn try_with_capacity<T>(capacity: usize, what: &dyn Display) -> Result<Vec<T>> {
    let mut vec = Vec::new();
    try_reserve_exact(&mut vec, capacity, what)?;
    Ok(vec)
}

/// `len` copies of `value` (`vec![value; len]`, fallible).
pub fn try_vec<T: Clone>(len: usize, value: T, what: &dyn Display) -> Result<Vec<T>> {
    let mut vec = try_with_capacity(len, what)?;
    vec.resize(len, value);
    Ok(vec)
}

/// A copy of `values` with the capacity of `values` (a clone that keeps its room to grow
/// without allocating).
pub fn try_clone<T: Clone>(values: &Vec<T>, what: &dyn Display) -> Result<Vec<T>> {
    let mut vec = try_with_capacity(values.capacity(), what)?;
    vec.extend_from_slice(values);
    Ok(vec)
}

/// Inserts `key → value` into `map`, first making room for a new key, or fails with
/// [`Error::OutOfMemory`] for `what`, leaving `map` as it was.
pub fn try_insert<K: Eq + Hash, V>(
    map: &mut HashMap<K, V>,
    key: K,
    value: V,
    what: &dyn Display,
) -> Result<()> {
    if !map.contains_key(&key) {
        fault::check::<(K, V)>(what, 1)?;
        map.try_reserve(1)
            .map_err(|_| out_of_memory::<(K, V)>(what, map.len().saturating_add(1)))?;
    }
    map.insert(key, value);
    Ok(())
}

/// Failure injection for the crate's unit tests: [`fail_after`](fault::fail_after)`(n)`
/// makes the calling thread's `n`-th fallible allocation from then on fail, so that a test
/// can fail each allocation of an operation in turn. Nothing in other builds.
pub(crate) mod fault {
    use super::*;

    #[cfg(test)]
    thread_local! {
        /// Allocations left before the injected failure (`None`: no failure planned).
        static LEFT: std::cell::Cell<Option<usize>> = const { std::cell::Cell::new(None) };
    }

    /// Makes the `n`-th fallible allocation of this thread from now on fail (0: the next);
    /// `None` stops injecting.
    #[cfg(test)]
    pub fn fail_after(n: Option<usize>) {
        LEFT.with(|left| left.set(n));
    }

    /// Fails if this allocation is the one to fail.
    #[cfg(test)]
    pub(super) fn check<T>(what: &dyn Display, count: usize) -> Result<()> {
        LEFT.with(|left| match left.get() {
            Some(0) => {
                left.set(None);
                Err(out_of_memory::<T>(what, count))
            }
            Some(n) => {
                left.set(Some(n - 1));
                Ok(())
            }
            None => Ok(()),
        })
    }

    #[cfg(not(test))]
    #[inline(always)]
    #[allow(clippy::extra_unused_type_parameters)] // the same signature as in tests
    pub(super) fn check<T>(_: &dyn Display, _: usize) -> Result<()> {
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn buffers_have_exactly_their_length() {
        let v: Vec<u32> = try_with_capacity(10, &Field("n", 10)).unwrap();
        assert_eq!((v.len(), v.capacity()), (0, 10));
        let v = try_vec(7, 3u8, &Field("n", 7)).unwrap();
        assert_eq!(v, [3; 7]);
        assert_eq!(v.capacity(), 7);
        let mut roomy = Vec::with_capacity(9);
        roomy.push(1u64);
        let copy = try_clone(&roomy, &Field("n", 9)).unwrap();
        assert_eq!((copy.as_slice(), copy.capacity()), (&[1u64][..], 9));
    }

    #[test]
    fn impossible_sizes_fail_with_the_field_and_bytes() {
        let what = Field("max_recorded_states", u64::from(u32::MAX));
        // More than isize::MAX bytes: refused before asking the allocator.
        let err = try_with_capacity::<[u8; 24]>(usize::MAX / 8, &what).unwrap_err();
        assert_eq!(
            err.to_string(),
            format!(
                "out of memory: max_recorded_states = 4294967295 needs {} bytes",
                (usize::MAX / 8) as u128 * 24
            )
        );
        let err = checked(usize::MAX.checked_add(1), &what).unwrap_err();
        assert!(matches!(err, Error::OutOfMemory(_)), "{err}");
        assert!(err
            .to_string()
            .starts_with("out of memory: max_recorded_states"));
    }

    #[test]
    fn injected_failures_hit_the_chosen_allocation() {
        fault::fail_after(Some(1));
        assert!(try_vec(1, 0u8, &Field("a", 1)).is_ok());
        let err = try_vec(2, 0u16, &Field("b", 2)).unwrap_err();
        assert_eq!(err.to_string(), "out of memory: b = 2 needs 4 bytes");
        assert!(try_vec(3, 0u8, &Field("c", 3)).is_ok(), "only one failure");
        let mut map = HashMap::new();
        fault::fail_after(Some(0));
        assert!(try_insert(&mut map, 1, 2, &Field("d", 1)).is_err());
        assert!(map.is_empty());
        assert!(try_insert(&mut map, 1, 2, &Field("d", 1)).is_ok());
    }
}
