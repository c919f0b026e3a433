//! The user documentation (`README.md`, `docs/*.md`) is built and run: every fenced code
//! block has a known language and passes its check here or elsewhere.
//!
//! - `c`, `cpp`: built and run by `tests/c_examples.rs`, statically and shared.
//! - `rust`: doc tests (`src/lib.rs` includes every page under `cfg(doctest)`; checked here).
//! - `python`: run here with the Python of the project's throw-away venv holding the installed
//!   wheel (`scripts/test` makes it: `target/wheel-venv`, or `$CG_PYTHON`), from an empty
//!   directory and without `CROWDGAZE_LIBRARY`, as a user who ran `pip install` would.
//! - `sh`: parsed by `bash -n`; every `scripts/…` it names exists and is executable, and every
//!   `cargo run -p crowdgaze-cli -- COMMAND` names a command the tool has.
//! - `cmake`: each line is a line of `c_examples/cmake_consumer/CMakeLists.txt` (built against
//!   an install by `tests/install.rs`).
//! - `text`: output or code that is not ours to run (said so beside it on the page).
//!
//! Also: every relative link of the pages points at a file that exists.

use std::path::{Path, PathBuf};
use std::process::Command;

#[path = "support/snippets.rs"]
mod snippets;

use snippets::{root, Snippet};

const LANGUAGES: &[&str] = &["c", "cpp", "rust", "python", "sh", "cmake", "text"];

#[test]
fn every_code_block_has_a_language_that_is_checked() {
    let all = snippets::all();
    assert!(all.len() >= 8, "too few code blocks: {}", all.len());
    let unknown: Vec<String> = all
        .iter()
        .filter(|s| !LANGUAGES.contains(&s.language.as_str()))
        .map(|s| format!("{} ```{}", s.place(), s.language))
        .collect();
    assert!(
        unknown.is_empty(),
        "code blocks in a language no test checks (use one of {LANGUAGES:?}): {unknown:?}"
    );
}

#[test]
fn every_page_runs_its_rust_blocks_as_doc_tests() {
    let lib = std::fs::read_to_string(root().join("src/lib.rs")).expect("src/lib.rs");
    for page in snippets::pages() {
        let relative = page.strip_prefix(root()).unwrap().to_string_lossy();
        let include = format!("include_str!(\"../{relative}\")");
        assert!(
            lib.contains(&include),
            "src/lib.rs's `documentation` module must include {relative} ({include})"
        );
    }
    assert!(
        snippets::in_language("rust")
            .iter()
            .any(|s| s.page == "README.md"),
        "the README shows no Rust program"
    );
}

/// The Python of the venv holding the installed wheel.
fn wheel_python() -> PathBuf {
    let python = match std::env::var_os("CG_PYTHON") {
        Some(path) => PathBuf::from(path),
        None => {
            let target = std::env::var_os("CARGO_TARGET_DIR")
                .map(PathBuf::from)
                .unwrap_or_else(|| root().join("target"));
            target.join("wheel-venv/bin/python")
        }
    };
    assert!(
        python.is_file(),
        "{} is missing: the Python with the crowdgaze wheel installed. scripts/test makes it \
         (pip install ./bindings/python in a fresh venv); or set CG_PYTHON",
        python.display()
    );
    python
}

fn run_python(python: &Path, script: &Path) -> std::process::Output {
    let directory = script.parent().unwrap();
    Command::new(python)
        .arg(script)
        .current_dir(directory)
        .env_remove("CROWDGAZE_LIBRARY")
        .env_remove("PYTHONPATH")
        .output()
        .unwrap_or_else(|e| panic!("run {}: {e}", python.display()))
}

fn python_work() -> PathBuf {
    let work = Path::new(env!("CARGO_TARGET_TMPDIR")).join("docs_python");
    std::fs::create_dir_all(&work).unwrap();
    work
}

#[test]
#[cfg_attr(miri, ignore)]
fn the_installed_wheel_carries_its_library_and_version() {
    let python = wheel_python();
    let script = python_work().join("wheel_check.py");
    std::fs::write(
        &script,
        "import importlib.metadata, crowdgaze\n\
         print(crowdgaze.__version__)\n\
         print(importlib.metadata.version('crowdgaze'))\n\
         print(crowdgaze.version_string())\n\
         print(crowdgaze.library_path)\n",
    )
    .unwrap();
    let output = run_python(&python, &script);
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    let lines: Vec<&str> = stdout.lines().collect();
    let version = env!("CARGO_PKG_VERSION");
    assert_eq!(&lines[..3], &[version, version, version], "{stdout}");
    assert!(
        lines[3].contains("site-packages/crowdgaze/_crowdgaze"),
        "the library must come from inside the wheel: {stdout}"
    );
}

#[test]
#[cfg_attr(miri, ignore)]
fn python_blocks_run_with_the_installed_wheel() {
    let blocks = snippets::in_language("python");
    assert!(
        blocks.iter().any(|s| s.page == "README.md"),
        "the README shows no Python program"
    );
    let python = wheel_python();
    let work = python_work();
    for snippet in &blocks {
        let script = work.join(format!("{}.py", snippet.stem()));
        std::fs::write(&script, &snippet.code).unwrap();
        let output = run_python(&python, &script);
        assert!(
            output.status.success(),
            "the Python block at {} failed ({:?}):\nstdout:\n{}\nstderr:\n{}",
            snippet.place(),
            output.status,
            String::from_utf8_lossy(&output.stdout),
            String::from_utf8_lossy(&output.stderr)
        );
        println!("{} ran", snippet.place());
    }
}

/// The commands of the command-line tool (`crowdgaze --help`).
fn cli_commands() -> Vec<String> {
    let output = Command::new(env!("CARGO"))
        .args(["run", "--quiet", "-p", "crowdgaze-cli", "--", "--help"])
        .current_dir(root())
        .output()
        .expect("run cargo");
    assert!(
        output.status.success(),
        "crowdgaze --help: {}",
        String::from_utf8_lossy(&output.stderr)
    );
    let help = String::from_utf8_lossy(&output.stdout).into_owned();
    help.lines()
        .skip_while(|line| !line.starts_with("Commands:"))
        .skip(1)
        .take_while(|line| line.starts_with("  "))
        .filter_map(|line| line.split_whitespace().next().map(String::from))
        .collect()
}

fn check_shell(snippet: &Snippet, commands: &[String]) {
    let syntax = Command::new("bash")
        .arg("-n")
        .arg("-c")
        .arg(&snippet.code)
        .output()
        .expect("run bash");
    assert!(
        syntax.status.success(),
        "{}: not valid shell: {}",
        snippet.place(),
        String::from_utf8_lossy(&syntax.stderr)
    );
    for line in snippet.code.lines() {
        let line = line.split('#').next().unwrap_or("");
        let words: Vec<&str> = line.split_whitespace().collect();
        for word in &words {
            if let Some(script) = word.strip_prefix("scripts/") {
                let path = root().join("scripts").join(script);
                let executable = std::fs::metadata(&path)
                    .map(|m| std::os::unix::fs::PermissionsExt::mode(&m.permissions()) & 0o111 != 0)
                    .unwrap_or(false);
                assert!(
                    executable,
                    "{}: scripts/{script} is not an executable script",
                    snippet.place()
                );
            }
        }
        if words.starts_with(&["cargo", "run"]) && words.contains(&"crowdgaze-cli") {
            let command = words
                .iter()
                .position(|w| *w == "--")
                .and_then(|at| words.get(at + 1))
                .unwrap_or_else(|| panic!("{}: which command? {line}", snippet.place()));
            assert!(
                commands.iter().any(|c| c == command),
                "{}: the tool has no command {command} (it has {commands:?})",
                snippet.place()
            );
        }
    }
}

#[test]
#[cfg_attr(miri, ignore)]
fn shell_blocks_name_real_scripts_and_commands() {
    let commands = cli_commands();
    assert!(commands.iter().any(|c| c == "demo"), "{commands:?}");
    let blocks = snippets::in_language("sh");
    assert!(
        blocks
            .iter()
            .any(|s| s.page == "README.md" && s.code.contains("scripts/test")),
        "the README's Quick start must show scripts/test"
    );
    for snippet in &blocks {
        check_shell(snippet, &commands);
    }
}

#[test]
fn cmake_blocks_are_the_tested_consumer() {
    let consumer =
        std::fs::read_to_string(root().join("c_examples/cmake_consumer/CMakeLists.txt")).unwrap();
    let lines: Vec<&str> = consumer.lines().map(str::trim).collect();
    for snippet in snippets::in_language("cmake") {
        for line in snippet
            .code
            .lines()
            .map(str::trim)
            .filter(|l| !l.is_empty())
        {
            assert!(
                lines.contains(&line),
                "{}: {line:?} is not in c_examples/cmake_consumer/CMakeLists.txt",
                snippet.place()
            );
        }
    }
}

#[test]
fn relative_links_point_at_files() {
    for page in snippets::pages() {
        let text = std::fs::read_to_string(&page).unwrap();
        let base = page.parent().unwrap();
        let mut rest = text.as_str();
        while let Some(at) = rest.find("](") {
            rest = &rest[at + 2..];
            let end = rest.find(')').unwrap_or(rest.len());
            let target = rest[..end].split('#').next().unwrap_or("").trim();
            if target.is_empty() || target.contains("://") || target.starts_with("mailto:") {
                continue;
            }
            assert!(
                base.join(target).exists(),
                "{}: the link {target} points at nothing",
                page.display()
            );
        }
    }
}
