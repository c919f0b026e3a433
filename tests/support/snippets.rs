//! The fenced code blocks of the user documentation (`README.md` and `docs/*.md`), for the
//! tests that build and run them: C and C++ in `tests/c_examples.rs`, Python, shell and
//! CMake in `tests/docs.rs`; Rust blocks run as doc tests (`src/lib.rs`, `documentation`).

use std::path::{Path, PathBuf};

/// One fenced code block.
#[derive(Clone, Debug)]
pub struct Snippet {
    /// The page, relative to the repository (`README.md`, `docs/attention.md`).
    pub page: String,
    /// The 1-based line of the opening fence.
    pub line: usize,
    /// The fence's language (`c`, `cpp`, `python`, `rust`, `sh`, `cmake`, `text`; empty if
    /// none was given).
    pub language: String,
    /// The block's text, with a final newline.
    pub code: String,
}

impl Snippet {
    /// A file name for the block: the page and line, e.g. `readme_l42`.
    pub fn stem(&self) -> String {
        let page = self
            .page
            .trim_end_matches(".md")
            .replace(['/', '-', '.'], "_")
            .to_lowercase();
        format!("{page}_l{}", self.line)
    }

    /// Where it is, for messages: `README.md:42`.
    pub fn place(&self) -> String {
        format!("{}:{}", self.page, self.line)
    }
}

/// The repository's root.
pub fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

/// The user documentation's pages: `README.md`, then `docs/*.md` by name.
pub fn pages() -> Vec<PathBuf> {
    let mut docs: Vec<PathBuf> = std::fs::read_dir(root().join("docs"))
        .expect("docs/ exists")
        .map(|entry| entry.expect("docs/ entry").path())
        .filter(|path| path.extension().is_some_and(|e| e == "md"))
        .collect();
    docs.sort();
    let mut pages = vec![root().join("README.md")];
    pages.extend(docs);
    pages
}

/// Every fenced block (```` ``` ```` fences) of `text`, a page named `page`.
pub fn parse(page: &str, text: &str) -> Vec<Snippet> {
    let mut snippets = Vec::new();
    let mut open: Option<Snippet> = None;
    for (index, line) in text.lines().enumerate() {
        let trimmed = line.trim_start();
        match open.as_mut() {
            None => {
                if let Some(info) = trimmed.strip_prefix("```") {
                    let language = info.split([' ', ',']).next().unwrap_or("").trim();
                    open = Some(Snippet {
                        page: page.to_owned(),
                        line: index + 1,
                        language: language.to_owned(),
                        code: String::new(),
                    });
                }
            }
            Some(snippet) => {
                if trimmed.starts_with("```") {
                    snippets.push(open.take().expect("open block"));
                } else {
                    snippet.code.push_str(line);
                    snippet.code.push('\n');
                }
            }
        }
    }
    assert!(open.is_none(), "{page}: a code block is not closed");
    snippets
}

/// Every fenced block of every page.
pub fn all() -> Vec<Snippet> {
    pages()
        .iter()
        .flat_map(|path| {
            let text = std::fs::read_to_string(path)
                .unwrap_or_else(|e| panic!("read {}: {e}", path.display()));
            let page = path
                .strip_prefix(root())
                .expect("a page of the repository")
                .to_string_lossy()
                .into_owned();
            parse(&page, &text)
        })
        .collect()
}

/// The blocks in `language`.
pub fn in_language(language: &str) -> Vec<Snippet> {
    all()
        .into_iter()
        .filter(|snippet| snippet.language == language)
        .collect()
}
