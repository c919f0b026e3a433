//! The library version, as header macros and as functions that report the linked library's.

use libc::c_char;

/// Major version of the header. Compare with `cg_version()` at run time to detect a header
/// and library mismatch.
pub const CG_VERSION_MAJOR: u32 = 0;
/// Minor version of the header.
pub const CG_VERSION_MINOR: u32 = 2;
/// Patch version of the header.
pub const CG_VERSION_PATCH: u32 = 0;

/// The linked library's version as `(major << 16) | (minor << 8) | patch`.
/// Thread-safe; never fails.
#[no_mangle]
pub extern "C" fn cg_version() -> u32 {
    (CG_VERSION_MAJOR << 16) | (CG_VERSION_MINOR << 8) | CG_VERSION_PATCH
}

/// The linked library's version as a static NUL-terminated string, "major.minor.patch".
/// The string must not be freed. Thread-safe; never fails.
#[no_mangle]
pub extern "C" fn cg_version_string() -> *const c_char {
    const VERSION: &str = concat!(env!("CARGO_PKG_VERSION"), "\0");
    VERSION.as_ptr().cast()
}
