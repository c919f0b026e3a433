//! The Godot addon's documentation quotes real files: a `text` block whose introducing line
//! (the last non-blank line above its fence) names a file under `bindings/godot/` and says
//! "quoted" must match that file, line for line in order (a `...` line skips lines). The
//! quoted files are the Godot 3.2 demo's, which `scripts/godot-check` runs, so the code a
//! reader copies is code that runs.

use std::path::Path;

// The shared page parser; this test uses part of it.
#[allow(dead_code)]
#[path = "support/snippets.rs"]
mod snippets;

use snippets::root;

/// The file an introducing line names, if it quotes one: the first `` `bindings/godot/…` ``
/// path on a line that contains "quoted".
fn quoted_file(line: &str) -> Option<String> {
    if !line.to_lowercase().contains("quoted") {
        return None;
    }
    let start = line.find("`bindings/godot/")? + 1;
    let end = start + line[start..].find('`')?;
    Some(line[start..end].to_owned())
}

/// A line as compared: tabs (GDScript's indentation) as four spaces, no trailing blanks.
fn normal(line: &str) -> String {
    line.replace('\t', "    ").trim_end().to_owned()
}

/// Checks that `block`'s lines appear in `file`'s, in order: each run of lines between
/// `...` lines is a run of consecutive lines of the file, after the previous run.
fn check_quote(place: &str, path: &str, block: &str) {
    let text = std::fs::read_to_string(root().join(path))
        .unwrap_or_else(|e| panic!("{place}: quotes {path}, which cannot be read: {e}"));
    let lines: Vec<String> = text.lines().map(normal).collect();
    let mut runs: Vec<Vec<String>> = vec![Vec::new()];
    for line in block.lines() {
        if line.trim() == "..." {
            runs.push(Vec::new());
        } else {
            runs.last_mut().expect("a run").push(normal(line));
        }
    }
    let mut at = 0;
    for run in runs.iter().filter(|run| !run.is_empty()) {
        let found = (at..=lines.len().saturating_sub(run.len()))
            .find(|&start| lines[start..start + run.len()] == run[..]);
        match found {
            Some(start) => at = start + run.len(),
            None => panic!(
                "{place}: these lines are not in {path} as quoted (after its line {at}): \
                 {run:#?}; quote the file as it is"
            ),
        }
    }
}

#[test]
fn quoted_godot_code_is_the_demos_code() {
    let mut quotes = Vec::new();
    for page in snippets::pages() {
        let relative = page
            .strip_prefix(root())
            .unwrap()
            .to_string_lossy()
            .into_owned();
        let text = std::fs::read_to_string(&page).unwrap();
        let lines: Vec<&str> = text.lines().collect();
        for snippet in snippets::parse(&relative, &text) {
            if snippet.language != "text" {
                continue;
            }
            let introduction = lines[..snippet.line - 1]
                .iter()
                .rev()
                .find(|l| !l.trim().is_empty())
                .copied()
                .unwrap_or("");
            if let Some(path) = quoted_file(introduction) {
                check_quote(&snippet.place(), &path, &snippet.code);
                quotes.push((snippet.place(), path));
            }
        }
    }
    // The pages quote the demo: a check that found nothing to check would prove nothing.
    assert!(
        quotes
            .iter()
            .any(|(place, _)| place.starts_with("docs/engines.md")),
        "docs/engines.md quotes no Godot demo file: {quotes:?}"
    );
    assert!(
        quotes
            .iter()
            .any(|(place, _)| place.starts_with("README.md")),
        "the README quotes no Godot demo file: {quotes:?}"
    );
    for (_, path) in &quotes {
        assert!(
            path.starts_with("bindings/godot/godot3/") && Path::new(path).extension().is_some(),
            "{path}: quote the Godot 3.2 demo or addon, which scripts/godot-check runs"
        );
    }
}

#[test]
fn a_quote_that_differs_is_caught() {
    let path = "bindings/godot/godot3/demo/lib/walk.gd";
    let file = std::fs::read_to_string(root().join(path)).unwrap();
    let line = file.lines().find(|l| l.contains("STRIDE")).unwrap();
    check_quote("test", path, &format!("{line}\n"));
    let result = std::panic::catch_unwind(|| {
        check_quote("test", path, &format!("{line} # changed\n"));
    });
    assert!(result.is_err(), "a changed line passed");
    assert_eq!(
        quoted_file("Quoted from `bindings/godot/godot3/demo/demo.gd` (run by the check):"),
        Some("bindings/godot/godot3/demo/demo.gd".into())
    );
    assert_eq!(
        quoted_file("See `bindings/godot/godot3/demo/demo.gd`."),
        None
    );
}
