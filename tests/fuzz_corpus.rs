//! Replays the fuzz target's committed corpus (`fuzz/corpus/api_calls/`: seeds and the
//! inputs that once crashed) through its interpreter, on stable Rust: every input must run
//! without a panic (an undocumented status, a NaN or infinity in an output, an output written
//! by a failed call, or a failed call that changed the crowd). See `scripts/fuzz`.
//!
//! `CG_FUZZ_INPUT=path` replays one file (an artifact of a fuzz run) instead.

#[path = "../fuzz/src/api/mod.rs"]
mod api;

use std::path::{Path, PathBuf};

fn inputs() -> Vec<PathBuf> {
    if let Some(one) = std::env::var_os("CG_FUZZ_INPUT") {
        return vec![PathBuf::from(one)];
    }
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("fuzz/corpus/api_calls");
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .map(|entry| entry.expect("dir entry").path())
        .filter(|path| path.is_file())
        .collect();
    files.sort();
    files
}

#[test]
fn fuzz_corpus_replays_clean() {
    let files = inputs();
    assert!(!files.is_empty(), "no corpus files");
    for file in &files {
        let data = std::fs::read(file).expect("read corpus file");
        let outcome = std::panic::catch_unwind(|| api::run(&data));
        assert!(
            outcome.is_ok(),
            "{} fails (see the panic above)",
            file.display()
        );
    }
    println!("{} corpus inputs replayed", files.len());
}
