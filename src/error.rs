//! The one error type of the Rust core; `src/ffi` adds the kinds only a C caller can cause
//! and maps each kind to a `cg_status`.

use thiserror::Error;

/// Why a crowdgaze operation failed.
///
/// Every variant carries a one-line explanation that the C API hands back through
/// `cg_last_error_message`. The *kind* of a variant (its name) is what callers branch on.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum Error {
    /// A value is out of its documented range or inconsistent with another one.
    #[error("invalid argument: {0}")]
    InvalidArgument(String),
    /// A floating-point input was NaN or infinite.
    #[error("non-finite value: {0}")]
    NonFinite(String),
    /// An id names nothing that exists (never created, or removed).
    #[error("not found: {0}")]
    NotFound(String),
    /// A fixed capacity chosen at creation would be exceeded.
    #[error("capacity exceeded: {0}")]
    Capacity(String),
    /// The call is not allowed in the object's current state.
    #[error("wrong state: {0}")]
    WrongState(String),
    /// An iterative method stopped at its iteration limit before reaching its precision.
    #[error("not converged: {0}")]
    NotConverged(String),
    /// A bug inside crowdgaze (for example a caught panic).
    #[error("internal error: {0}")]
    Internal(String),
    /// Memory for a buffer sized from the caller's numbers could not be allocated (the
    /// message names the number and the bytes asked); nothing was created or changed.
    #[error("out of memory: {0}")]
    OutOfMemory(String),
}

/// Shorthand for results of the Rust core.
pub type Result<T> = std::result::Result<T, Error>;

/// Fails with [`Error::NonFinite`] naming `what` if `value` is NaN or infinite.
pub fn ensure_finite(value: f32, what: &str) -> Result<()> {
    if value.is_finite() {
        Ok(())
    } else {
        Err(Error::NonFinite(format!("{what} is {value}")))
    }
}

/// Fails naming `what` unless `value` is finite ([`Error::NonFinite`]) and at least
/// `low` ([`Error::InvalidArgument`]).
pub(crate) fn check_at_least(value: f32, low: f32, what: &str) -> Result<()> {
    ensure_finite(value, what)?;
    if value < low {
        return Err(Error::InvalidArgument(format!(
            "{what} is {value}, must be >= {low}"
        )));
    }
    Ok(())
}

/// Fails naming `what` unless `value` is finite ([`Error::NonFinite`]) and in
/// `[low, high]` ([`Error::InvalidArgument`]).
pub(crate) fn check_range(value: f32, low: f32, high: f32, what: &str) -> Result<()> {
    ensure_finite(value, what)?;
    if value < low || value > high {
        return Err(Error::InvalidArgument(format!(
            "{what} is {value}, must be in [{low}, {high}]"
        )));
    }
    Ok(())
}

/// Fails with [`Error::NonFinite`] naming `what` if any component of `values` is NaN or infinite.
pub fn ensure_all_finite(values: &[f32], what: &str) -> Result<()> {
    match values.iter().find(|v| !v.is_finite()) {
        None => Ok(()),
        Some(bad) => Err(Error::NonFinite(format!("{what} contains {bad}"))),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finite_checks_name_the_value() {
        assert!(ensure_finite(1.0, "x").is_ok());
        let err = ensure_finite(f32::NAN, "speed").unwrap_err();
        assert_eq!(err.to_string(), "non-finite value: speed is NaN");
        let err = ensure_all_finite(&[0.0, f32::INFINITY], "position").unwrap_err();
        assert_eq!(err.to_string(), "non-finite value: position contains inf");
    }
}
