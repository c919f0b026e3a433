//! Compiles every C program in `c_examples/` (C99) and every C++ one (C++17, with the C++
//! wrapper's `bindings/cpp/` on the include path) against `include/crowdgaze.h` and the
//! library built by this `cargo test`, once linked statically and once against the shared
//! library, runs each, and checks its exit status and output.
//!
//! Each example prints what it checked and ends with the line `ok`. Extra expectations for
//! particular examples are in [`expected_output`]. Examples that read the development
//! workspace's data (`../shared/data` beside the repository) get its path in `CG_DATA_DIR`.
//!
//! The C and C++ code blocks of the user documentation (`README.md`, `docs/*.md`) are built
//! and run the same way (C11 for C): each is a whole program that must exit with 0.
//!
//! Memory checks (`scripts/memcheck`) reuse this harness through two variables:
//! `CG_EXAMPLE_RUNNER` is a command that runs each example (valgrind with its options), and
//! `CG_EXAMPLE_CFLAGS` extra flags compiling and linking each one (the sanitizers). When
//! either is set, the CMake consumer's `c_examples/cmake_consumer/main.c` is checked too
//! (it is otherwise built only against an install, by `tests/install.rs`).

use std::path::{Path, PathBuf};
use std::process::Command;

#[path = "support/snippets.rs"]
mod snippets;

/// The directory holding `libcrowdgaze.a` and `libcrowdgaze.so` built for this test run.
fn library_dir() -> PathBuf {
    let exe = std::env::current_exe().expect("test executable path");
    let deps = exe.parent().expect("deps dir").to_path_buf();
    for dir in [
        deps.clone(),
        deps.parent().expect("profile dir").to_path_buf(),
    ] {
        if dir.join("libcrowdgaze.a").exists() && dir.join("libcrowdgaze.so").exists() {
            return dir;
        }
    }
    panic!("libcrowdgaze.a / .so not found next to {}", exe.display());
}

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

/// The shared library's SONAME: `libcrowdgaze.so.0.MINOR` below 1.0 (a minor release may
/// break the ABI), `libcrowdgaze.so.MAJOR` from 1.0, as `build.rs` sets it.
fn soname() -> String {
    match env!("CARGO_PKG_VERSION_MAJOR") {
        "0" => format!("libcrowdgaze.so.0.{}", env!("CARGO_PKG_VERSION_MINOR")),
        major => format!("libcrowdgaze.so.{major}"),
    }
}

/// Work directory for compiled examples, with the shared library installed under its SONAME.
fn work_dir() -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("c_examples");
    std::fs::create_dir_all(&dir).expect("create work dir");
    let so = dir.join(soname());
    std::fs::copy(library_dir().join("libcrowdgaze.so"), &so).expect("copy shared library");
    let link = dir.join("libcrowdgaze.so");
    let _ = std::fs::remove_file(&link);
    std::os::unix::fs::symlink(soname(), &link).expect("symlink libcrowdgaze.so");
    dir
}

/// Native libraries the Rust standard library needs when linked statically on Linux
/// (what `rustc --print native-static-libs` reports).
const NATIVE_STATIC_LIBS: &[&str] = &[
    "-lgcc_s",
    "-lutil",
    "-lrt",
    "-lpthread",
    "-lm",
    "-ldl",
    "-lc",
];

#[derive(Clone, Copy, Debug)]
enum Linkage {
    Static,
    Shared,
}

/// A program of `c_examples/`, or a code block of the documentation written to a file.
#[derive(Clone, Debug)]
struct Source {
    path: PathBuf,
    /// From the documentation (`README.md:42`): C11, and no final `ok` asked for.
    snippet: Option<String>,
}

fn compile(source: &Source, linkage: Linkage, work: &Path) -> PathBuf {
    let is_snippet = source.snippet.is_some();
    let source = source.path.as_path();
    let is_cpp = source.extension().is_some_and(|e| e == "cpp");
    let stem = name(source);
    let output = work.join(format!("{stem}_{linkage:?}").to_lowercase());
    let compiler = if is_cpp {
        std::env::var("CXX").unwrap_or_else(|_| "c++".into())
    } else {
        std::env::var("CC").unwrap_or_else(|_| "cc".into())
    };
    let mut command = Command::new(&compiler);
    command
        .arg(match (is_cpp, is_snippet) {
            (true, _) => "-std=c++17",
            (false, false) => "-std=c99",
            (false, true) => "-std=c11",
        })
        .args(["-Wall", "-Wextra", "-Wpedantic", "-Werror", "-O1", "-g"])
        .arg("-I")
        .arg(root().join("include"));
    if is_cpp {
        // The header-only C++ wrapper, bindings/cpp/crowdgaze.hpp.
        command.arg("-I").arg(root().join("bindings/cpp"));
    }
    command.args(extra_flags(&stem));
    command.args(words("CG_EXAMPLE_CFLAGS"));
    command.arg(source).arg("-o").arg(&output);
    match linkage {
        Linkage::Static => {
            command.arg(library_dir().join("libcrowdgaze.a"));
            command.args(NATIVE_STATIC_LIBS);
        }
        Linkage::Shared => {
            command
                .arg("-L")
                .arg(work)
                .arg("-lcrowdgaze")
                .arg(format!("-Wl,-rpath,{}", work.display()));
        }
    }
    if !is_cpp {
        command.arg("-lm");
    }
    let result = command
        .output()
        .unwrap_or_else(|e| panic!("run {compiler}: {e}"));
    assert!(
        result.status.success(),
        "compiling {} ({linkage:?}) failed:\n{}",
        source.display(),
        String::from_utf8_lossy(&result.stderr)
    );
    output
}

/// The whitespace-separated words of environment variable `variable` (none if unset).
fn words(variable: &str) -> Vec<String> {
    std::env::var(variable)
        .unwrap_or_default()
        .split_whitespace()
        .map(String::from)
        .collect()
}

/// An example's name: its file stem, or its directory's name for a `main.c`.
fn name(source: &Path) -> String {
    let stem = source.file_stem().unwrap().to_string_lossy();
    if stem == "main" {
        let parent = source.parent().and_then(Path::file_name).unwrap();
        parent.to_string_lossy().into_owned()
    } else {
        stem.into_owned()
    }
}

/// Compiler flags particular examples need besides the common ones.
fn extra_flags(stem: &str) -> &'static [&'static str] {
    match stem {
        // The C++ wrapper as engine modules build it (Unreal's have no exceptions).
        "cpp_no_exceptions" => &["-fno-exceptions"],
        _ => &[],
    }
}

/// Substrings that particular examples must print, besides the final `ok`.
fn expected_output(stem: &str) -> Vec<String> {
    match stem {
        "version" => vec![format!("library {}", env!("CARGO_PKG_VERSION"))],
        "errors" => vec![
            "CG_STATUS_NULL_ARGUMENT: null argument".into(),
            "bad struct_size: cg_crowd_config.struct_size is 3".into(),
        ],
        "chain" => vec![
            "joints 10, eye height 1.62 m".into(),
            "pelvis at 95 cm".into(),
        ],
        "view_blend" => vec![
            "on key camera 1: weights 0.000 1.000 0.000".into(),
            "camera centre from P: (4.000, 1.600, 1.000)".into(),
        ],
        "cpp_wrapper" => vec![
            "left eye off the target by 0.00 deg".into(),
            "step(-1) threw: invalid argument: dt is -1, must be >= 0".into(),
            "half-way viewer: weights 0.500 0.500, head yaw 30.00 deg".into(),
        ],
        "rig" => vec![
            "Mixamo: gaze chain of 7 joints: 3 spine, 1 neck, head, 2 eyes; hangs from \
             'mixamorig:Hips'"
                .into(),
            "BVH wave_hello.bvh, 27 joints".into(),
            "BVH: gaze chain of 6 joints: 4 spine, 1 neck, head; hangs from 'Hips'".into(),
            "BVH character driven:".into(),
        ],
        "street_following" => vec![
            "passers-by glanced at the window".into(),
            "follow_enabled 0 and a 216-byte config: bit-identical over 1200 frames".into(),
        ],
        "cpp_no_exceptions" => vec![
            "joints 20, eye directions x +1.00 and -1.00".into(),
            "try_step(-1): invalid argument (invalid argument: dt is -1, must be >= 0)".into(),
        ],
        _ => vec![],
    }
}

fn examples(work: &Path) -> Vec<Source> {
    let mut paths: Vec<PathBuf> = std::fs::read_dir(root().join("c_examples"))
        .expect("c_examples/ exists")
        .map(|entry| entry.expect("dir entry").path())
        .filter(|path| path.extension().is_some_and(|e| e == "c" || e == "cpp"))
        .collect();
    paths.sort();
    if !words("CG_EXAMPLE_RUNNER").is_empty() || !words("CG_EXAMPLE_CFLAGS").is_empty() {
        paths.push(root().join("c_examples/cmake_consumer/main.c"));
    }
    let mut sources: Vec<Source> = paths
        .into_iter()
        .map(|path| Source {
            path,
            snippet: None,
        })
        .collect();
    sources.extend(documentation_programs(work));
    sources
}

/// The documentation's C and C++ code blocks, each written to a file of `work/snippets`.
fn documentation_programs(work: &Path) -> Vec<Source> {
    let directory = work.join("snippets");
    std::fs::create_dir_all(&directory).expect("create snippets dir");
    let mut sources = Vec::new();
    for (language, extension) in [("c", "c"), ("cpp", "cpp")] {
        for snippet in snippets::in_language(language) {
            let path = directory.join(format!("{}.{extension}", snippet.stem()));
            std::fs::write(&path, &snippet.code).expect("write snippet");
            sources.push(Source {
                path,
                snippet: Some(snippet.place()),
            });
        }
    }
    sources
}

#[test]
#[cfg_attr(miri, ignore)]
fn the_documentation_has_c_and_cpp_programs() {
    let work = work_dir();
    let programs = documentation_programs(&work);
    for language in ["c", "cpp"] {
        assert!(
            snippets::in_language(language)
                .iter()
                .any(|s| s.page == "README.md"),
            "the README shows no {language} program"
        );
    }
    assert!(programs.len() >= 2, "{programs:?}");
}

#[test]
#[cfg_attr(miri, ignore)]
fn c_examples_build_and_pass_static_and_shared() {
    let work = work_dir();
    let sources = examples(&work);
    assert!(
        sources.len() >= 3,
        "expected the C and C++ examples, found {sources:?}"
    );
    let runner = words("CG_EXAMPLE_RUNNER");
    for source in &sources {
        let stem = match &source.snippet {
            Some(place) => place.clone(),
            None => name(&source.path),
        };
        for linkage in [Linkage::Static, Linkage::Shared] {
            let program = compile(source, linkage, &work);
            let mut command = match runner.split_first() {
                Some((tool, options)) => {
                    let mut command = Command::new(tool);
                    command.args(options).arg(&program);
                    command
                }
                None => Command::new(&program),
            };
            // Examples that read the shared data (rig.c's BVH file) find it here.
            command.env("CG_DATA_DIR", root().join("../shared/data"));
            let run = command.current_dir(root()).output().expect("run example");
            let stdout = String::from_utf8_lossy(&run.stdout);
            assert!(
                run.status.success(),
                "{stem} ({linkage:?}) exited with {:?}\nstdout:\n{stdout}\nstderr:\n{}",
                run.status,
                String::from_utf8_lossy(&run.stderr)
            );
            if source.snippet.is_none() {
                assert_eq!(
                    stdout.lines().last(),
                    Some("ok"),
                    "{stem} ({linkage:?}) must end with `ok`:\n{stdout}"
                );
            }
            for needle in expected_output(&stem) {
                assert!(
                    stdout.contains(&needle),
                    "{stem} ({linkage:?}) should print {needle:?}:\n{stdout}"
                );
            }
            println!("example {stem} ({linkage:?}) ran clean");
        }
    }
}

#[test]
#[cfg_attr(miri, ignore)]
fn shared_library_exports_only_cg_symbols() {
    let so = library_dir().join("libcrowdgaze.so");
    let nm = Command::new("nm")
        .args(["-D", "--defined-only"])
        .arg(&so)
        .output()
        .expect("run nm");
    assert!(nm.status.success());
    let listing = String::from_utf8_lossy(&nm.stdout);
    let names: Vec<&str> = listing
        .lines()
        .filter_map(|line| line.split_whitespace().nth(2))
        .collect();
    assert!(names.contains(&"cg_crowd_create"), "{listing}");
    let foreign: Vec<&&str> = names.iter().filter(|n| !n.starts_with("cg_")).collect();
    assert!(foreign.is_empty(), "non-cg_ exports: {foreign:?}");

    // Every exported function is declared in the header, and every declared one is exported.
    let header = std::fs::read_to_string(root().join("include/crowdgaze.h")).expect("header");
    let mut declared: Vec<String> = header
        .lines()
        .filter(|line| !line.starts_with("//") && !line.starts_with(' '))
        .filter_map(|line| {
            let open = line.find('(')?;
            let name = line[..open].rsplit([' ', '*']).next()?;
            name.starts_with("cg_").then(|| name.to_owned())
        })
        .collect();
    declared.sort();
    let mut exported: Vec<String> = names.iter().map(|n| n.to_string()).collect();
    exported.sort();
    assert_eq!(
        declared, exported,
        "header declarations vs exported symbols"
    );

    let readelf = Command::new("readelf")
        .arg("-d")
        .arg(&so)
        .output()
        .expect("readelf");
    let dynamic = String::from_utf8_lossy(&readelf.stdout);
    let soname = format!("Library soname: [{}]", soname());
    assert!(dynamic.contains(&soname), "SONAME missing:\n{dynamic}");
}
