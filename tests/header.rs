//! The checked-in header `include/crowdgaze.h` must be exactly what cbindgen generates from
//! `src/ffi`; and the versions in the header, Cargo.toml and the library must agree.
//! Run with `CG_BLESS=1` to rewrite the header.

use std::path::Path;

fn generate() -> String {
    let root = env!("CARGO_MANIFEST_DIR");
    let config = cbindgen::Config::from_file(Path::new(root).join("cbindgen.toml"))
        .expect("cbindgen.toml parses");
    let bindings = cbindgen::Builder::new()
        .with_crate(root)
        .with_config(config)
        .generate()
        .expect("cbindgen generates the header");
    let mut out = Vec::new();
    bindings.write(&mut out);
    String::from_utf8(out).expect("header is UTF-8")
}

#[test]
#[cfg_attr(miri, ignore)]
fn header_is_fresh() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("include/crowdgaze.h");
    let fresh = generate();
    if std::env::var_os("CG_BLESS").is_some() {
        std::fs::write(&path, &fresh).expect("write header");
        return;
    }
    let current = std::fs::read_to_string(&path).unwrap_or_default();
    assert!(
        current == fresh,
        "include/crowdgaze.h is stale: regenerate it with `CG_BLESS=1 cargo test --test header`"
    );
}

fn header_macro(header: &str, name: &str) -> u32 {
    let prefix = format!("#define {name} ");
    header
        .lines()
        .find_map(|line| line.strip_prefix(&prefix))
        .unwrap_or_else(|| panic!("{name} missing from the header"))
        .trim()
        .parse()
        .expect("version macro is a number")
}

#[test]
#[cfg_attr(miri, ignore)]
fn versions_agree() {
    let header =
        std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("include/crowdgaze.h"))
            .expect("header exists");
    let major = header_macro(&header, "CG_VERSION_MAJOR");
    let minor = header_macro(&header, "CG_VERSION_MINOR");
    let patch = header_macro(&header, "CG_VERSION_PATCH");
    let cargo: Vec<u32> = env!("CARGO_PKG_VERSION")
        .split('.')
        .map(|part| part.parse().expect("plain numeric version"))
        .collect();
    assert_eq!(vec![major, minor, patch], cargo, "header vs Cargo.toml");
    assert_eq!(
        crowdgaze::ffi::version::cg_version(),
        (major << 16) | (minor << 8) | patch,
        "header vs cg_version()"
    );
    // SAFETY: cg_version_string returns a static NUL-terminated string.
    let text = unsafe { std::ffi::CStr::from_ptr(crowdgaze::ffi::version::cg_version_string()) };
    assert_eq!(text.to_str().unwrap(), env!("CARGO_PKG_VERSION"));
}
