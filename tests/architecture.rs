//! The house rules of the source tree (docs/architecture.md): no import cycle among the
//! library's files or layers, a checker that finds them, and no file of the library over
//! 1 000 lines.

use std::path::{Path, PathBuf};
use std::process::Command;

/// The most lines a file of `src/` may have.
const MAX_LINES: usize = 1000;

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

/// Runs `scripts/check-cycles` on `src`: its exit status and output.
fn check_cycles(src: &Path) -> (bool, String) {
    let output = Command::new("python3")
        .arg(root().join("scripts/check-cycles"))
        .arg(src)
        .output()
        .expect("python3 runs (scripts/setup installs it)");
    let text = String::from_utf8_lossy(&output.stdout).into_owned()
        + &String::from_utf8_lossy(&output.stderr);
    (output.status.success(), text)
}

/// A throw-away crate made of `files` (path, text) under a fresh directory.
fn fixture(name: &str, files: &[(&str, &str)]) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("cycles-{name}"));
    let _ = std::fs::remove_dir_all(&dir);
    for (path, text) in files {
        let path = dir.join(path);
        std::fs::create_dir_all(path.parent().unwrap()).unwrap();
        std::fs::write(path, text).unwrap();
    }
    dir
}

#[test]
fn the_library_has_no_import_cycle() {
    let (ok, output) = check_cycles(&root().join("src"));
    assert!(ok, "scripts/check-cycles src:\n{output}");
}

#[test]
fn the_checker_finds_cycles_among_files_and_layers() {
    let files = fixture(
        "files",
        &[
            ("lib.rs", "mod a;\nmod b;\n"),
            ("a.rs", "use crate::b::B;\npub struct A(B);\n"),
            (
                "b.rs",
                "pub struct B;\npub fn make() -> crate::a::A { todo!() }\n",
            ),
        ],
    );
    let (ok, output) = check_cycles(&files);
    assert!(!ok, "a <-> b not found:\n{output}");
    assert!(
        output.contains("a.rs") && output.contains("b.rs"),
        "{output}"
    );

    // Two layers whose files do not loop, but the layers do: low/x uses high, high/y uses low.
    let layers = fixture(
        "layers",
        &[
            ("lib.rs", "mod high;\nmod low;\n"),
            ("high/mod.rs", "mod y;\npub use y::Y;\n"),
            ("high/y.rs", "pub struct Y(crate::low::Z);\n"),
            ("low/mod.rs", "mod x;\nmod z;\npub use z::Z;\n"),
            ("low/x.rs", "pub fn f(_: crate::high::Y) {}\n"),
            ("low/z.rs", "pub struct Z;\n"),
        ],
    );
    let (ok, output) = check_cycles(&layers);
    assert!(!ok, "the layer cycle high <-> low not found:\n{output}");
    assert!(output.contains("among layers: high, low"), "{output}");
}

#[test]
fn a_parent_that_only_re_exports_is_no_cycle() {
    // The pattern of every directory here: mod.rs declares and re-exports, a child uses a
    // sibling through the parent's path.
    let tree = fixture(
        "facade",
        &[
            ("lib.rs", "mod m;\n"),
            ("m/mod.rs", "mod p;\nmod q;\npub use p::P;\npub use q::Q;\n"),
            ("m/p.rs", "pub struct P;\n"),
            ("m/q.rs", "use super::P;\npub struct Q(P);\n"),
        ],
    );
    let (ok, output) = check_cycles(&tree);
    assert!(ok, "{output}");
}

#[test]
fn no_file_of_the_library_is_over_a_thousand_lines() {
    let mut long = Vec::new();
    let mut pending = vec![root().join("src")];
    while let Some(dir) = pending.pop() {
        for entry in std::fs::read_dir(&dir).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                pending.push(path);
            } else if path.extension().is_some_and(|e| e == "rs") {
                let lines = std::fs::read_to_string(&path).unwrap().lines().count();
                if lines > MAX_LINES {
                    long.push(format!("{} ({lines} lines)", path.display()));
                }
            }
        }
    }
    assert!(
        long.is_empty(),
        "split by job (docs/architecture.md): {long:?}"
    );
}
