//! The native part of the crowdgaze Python package: the crowdgaze library built as the
//! extension module `crowdgaze._crowdgaze`, so that the wheel carries it.
//!
//! Linking the `crowdgaze` crate into this cdylib exports every `cg_` function of
//! `include/crowdgaze.h` from it; the package's ctypes layer (`crowdgaze/_native.py`) loads
//! this file as its C library. The module itself only says which version it was built from.
//!
//! The module needs the `python` feature, which maturin turns on; without it this is the C ABI
//! alone, which `cargo test --workspace` builds with no Python to link against.

// Keeps the crate, and with it its exported C functions, in this library.
pub use crowdgaze;

/// `crowdgaze._crowdgaze`: `__version__` is the crowdgaze version this library was built from.
#[cfg(feature = "python")]
#[pyo3::pymodule]
fn _crowdgaze(module: &pyo3::Bound<'_, pyo3::types::PyModule>) -> pyo3::PyResult<()> {
    use pyo3::types::PyModuleMethods;
    module.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
