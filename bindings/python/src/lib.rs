//! The native part of the crowdgaze Python package: the crowdgaze library built as the
//! extension module `crowdgaze._crowdgaze`, so that the wheel carries it.
//!
//! Linking the `crowdgaze` crate into this cdylib exports every `cg_` function of
//! `include/crowdgaze.h` from it; the package's ctypes layer (`crowdgaze/_native.py`) loads
//! this file as its C library. The module itself only says which version it was built from.

use pyo3::prelude::*;

// Keeps the crate, and with it its exported C functions, in this library.
pub use crowdgaze;

/// `crowdgaze._crowdgaze`: `__version__` is the crowdgaze version this library was built from.
#[pymodule]
fn _crowdgaze(module: &Bound<'_, PyModule>) -> PyResult<()> {
    module.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
