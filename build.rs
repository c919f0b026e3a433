//! Build script: gives the shared library its SONAME on Linux, the part of the version that
//! breaks the ABI — `libcrowdgaze.so.0.<minor>` below 1.0, `libcrowdgaze.so.<major>` from 1.0
//! (as cargo-c names them) — so that a program records the ABI-compatible name it was linked
//! against and the loader refuses an incompatible library instead of running with it.

fn main() {
    let major = std::env::var("CARGO_PKG_VERSION_MAJOR").expect("cargo sets the version");
    let minor = std::env::var("CARGO_PKG_VERSION_MINOR").expect("cargo sets the version");
    let abi = if major == "0" {
        format!("0.{minor}")
    } else {
        major
    };
    let target_os = std::env::var("CARGO_CFG_TARGET_OS").unwrap_or_default();
    if target_os == "linux" {
        println!("cargo:rustc-cdylib-link-arg=-Wl,-soname,libcrowdgaze.so.{abi}");
    }
    println!("cargo:rerun-if-changed=build.rs");
}
