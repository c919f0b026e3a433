//! The errors of the C boundary: the core's [`Error`] plus the kinds only a C caller can
//! cause (a NULL pointer, a wrong `struct_size`, a handle poisoned by an earlier call).
//! Each maps to one `cg_status` ([`cg_status::from`]).

use std::fmt;

use super::status::cg_status;
use crate::error::Error;

/// Why a C call failed. Its `Display` is the message `cg_last_error_message` returns.
#[derive(Debug, Clone, PartialEq)]
pub(crate) enum FfiError {
    /// An error of the Rust core.
    Core(Error),
    /// A required pointer was NULL.
    NullArgument(String),
    /// A versioned struct's `struct_size` is not one this library knows.
    BadStructSize(String),
    /// An earlier call that changed this handle failed inside the library and may have left
    /// it half-updated; carries that call's message.
    Poisoned(String),
}

/// Results of the C boundary's helpers.
pub(crate) type Result<T> = std::result::Result<T, FfiError>;

impl From<Error> for FfiError {
    fn from(error: Error) -> FfiError {
        FfiError::Core(error)
    }
}

impl FfiError {
    /// Whether this is a bug inside the library ([`Error::Internal`]), which poisons the
    /// handle the failed call was changing.
    pub(crate) fn is_internal(&self) -> bool {
        matches!(self, FfiError::Core(Error::Internal(_)))
    }
}

impl fmt::Display for FfiError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            FfiError::Core(error) => error.fmt(f),
            FfiError::NullArgument(what) => write!(f, "null argument: {what}"),
            FfiError::BadStructSize(what) => write!(f, "bad struct_size: {what}"),
            FfiError::Poisoned(first) => write!(
                f,
                "poisoned: an earlier call failed inside the library: {first}"
            ),
        }
    }
}

impl From<&FfiError> for cg_status {
    fn from(error: &FfiError) -> Self {
        match error {
            FfiError::Core(core) => match core {
                Error::InvalidArgument(_) => cg_status::InvalidArgument,
                Error::NonFinite(_) => cg_status::NonFinite,
                Error::NotFound(_) => cg_status::NotFound,
                Error::Capacity(_) => cg_status::Capacity,
                Error::WrongState(_) => cg_status::WrongState,
                Error::NotConverged(_) => cg_status::NotConverged,
                Error::Internal(_) => cg_status::Internal,
                Error::OutOfMemory(_) => cg_status::OutOfMemory,
            },
            FfiError::NullArgument(_) => cg_status::NullArgument,
            FfiError::BadStructSize(_) => cg_status::BadStructSize,
            FfiError::Poisoned(_) => cg_status::Poisoned,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_kind_has_its_status_and_message() {
        let cases = [
            (
                FfiError::NullArgument("out is NULL".into()),
                cg_status::NullArgument,
                "null argument: out is NULL",
            ),
            (
                FfiError::BadStructSize("x".into()),
                cg_status::BadStructSize,
                "bad struct_size: x",
            ),
            (
                FfiError::Poisoned("internal error: boom".into()),
                cg_status::Poisoned,
                "poisoned: an earlier call failed inside the library: internal error: boom",
            ),
            (
                Error::NotFound("entity 7".into()).into(),
                cg_status::NotFound,
                "not found: entity 7",
            ),
        ];
        for (error, status, message) in cases {
            assert_eq!(cg_status::from(&error), status);
            assert_eq!(error.to_string(), message);
        }
        assert!(FfiError::from(Error::Internal("x".into())).is_internal());
        assert!(!FfiError::Poisoned("x".into()).is_internal());
    }
}
