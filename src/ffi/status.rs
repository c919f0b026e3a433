//! `cg_status`: the result code of every fallible C call, and its static description.

use libc::c_char;

/// Result code of every fallible crowdgaze C function. `CG_STATUS_OK` (0) is success; any
/// other value means the call changed nothing and `cg_last_error_message` says why.
///
/// Values are stable: a retired value is never reused. Statuses coming back in from C (as in
/// `cg_status_str`) are taken as `uint32_t`, so an unknown value is never undefined behaviour.
#[repr(u32)]
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum cg_status {
    /// Success.
    Ok = 0,
    /// A required pointer was NULL, or an array pointer was NULL with a non-zero count.
    NullArgument = 1,
    /// A value is out of its documented range or inconsistent with another argument.
    InvalidArgument = 2,
    /// A floating-point input was NaN or infinite.
    NonFinite = 3,
    /// An id names no entity (never created, or removed).
    NotFound = 4,
    /// A capacity fixed at creation would be exceeded.
    Capacity = 5,
    /// A versioned struct's `struct_size` is not one this library knows (fill it with the
    /// matching `_init` function).
    BadStructSize = 6,
    /// The call is not allowed in the object's current state.
    WrongState = 7,
    /// An iterative method reached its iteration limit first; outputs hold the best result.
    NotConverged = 8,
    /// A bug inside crowdgaze (for example a caught panic). Please report it.
    Internal = 9,
    /// Memory ran out: a buffer sized from the arguments (a capacity of a create, a clip,
    /// a recording to plan) could not be allocated. The message names the field or count
    /// and the bytes asked. Nothing was created and nothing changed (a create writes no
    /// handle); smaller capacities may succeed.
    OutOfMemory = 10,
    /// An earlier call that changed this handle failed with `CG_STATUS_INTERNAL` and may
    /// have left it half-updated, so the handle is poisoned: every later call on it fails
    /// with this status (the message repeats the first failure's), and only its `_destroy`
    /// works, freeing it.
    Poisoned = 11,
}

impl cg_status {
    /// Every status, in value order (for tests and tools).
    /// cbindgen:ignore
    pub const ALL: [cg_status; 12] = [
        cg_status::Ok,
        cg_status::NullArgument,
        cg_status::InvalidArgument,
        cg_status::NonFinite,
        cg_status::NotFound,
        cg_status::Capacity,
        cg_status::BadStructSize,
        cg_status::WrongState,
        cg_status::NotConverged,
        cg_status::Internal,
        cg_status::OutOfMemory,
        cg_status::Poisoned,
    ];

    /// The static, NUL-terminated description of this status.
    pub fn description(self) -> &'static core::ffi::CStr {
        match self {
            cg_status::Ok => c"ok",
            cg_status::NullArgument => c"null argument",
            cg_status::InvalidArgument => c"invalid argument",
            cg_status::NonFinite => c"non-finite value (NaN or infinity)",
            cg_status::NotFound => c"not found",
            cg_status::Capacity => c"capacity exceeded",
            cg_status::BadStructSize => c"bad struct_size",
            cg_status::WrongState => c"wrong state",
            cg_status::NotConverged => c"not converged",
            cg_status::Internal => c"internal error",
            cg_status::OutOfMemory => c"out of memory",
            cg_status::Poisoned => c"poisoned",
        }
    }
}

impl TryFrom<u32> for cg_status {
    type Error = u32;

    fn try_from(value: u32) -> Result<Self, u32> {
        cg_status::ALL.get(value as usize).copied().ok_or(value)
    }
}

/// Returns a static, NUL-terminated English description of `status`. Never NULL: a value
/// that is not a `cg_status` gives "unknown status". The string must not be freed.
/// Thread-safe.
#[no_mangle]
pub extern "C" fn cg_status_str(status: u32) -> *const c_char {
    match cg_status::try_from(status) {
        Ok(known) => known.description().as_ptr(),
        Err(_) => c"unknown status".as_ptr(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn values_round_trip_through_u32() {
        for (index, status) in cg_status::ALL.iter().enumerate() {
            assert_eq!(*status as u32, index as u32);
            assert_eq!(cg_status::try_from(index as u32), Ok(*status));
        }
        assert_eq!(cg_status::try_from(12), Err(12));
    }

    #[test]
    fn descriptions_are_distinct() {
        let mut seen = std::collections::HashSet::new();
        for status in cg_status::ALL {
            assert!(seen.insert(status.description()));
        }
    }
}
