//! The per-function table of allowed statuses, read from the documentation in
//! `include/crowdgaze.h` (so the header is the specification being checked).
//!
//! A function may return `CG_STATUS_OK`, every status its doc comment names, and those of
//! the functions its "Errors" paragraph refers to (`Errors: as cg_crowd_read_joints`, `those
//! of cg_view_blender_weights`). `CG_STATUS_INTERNAL` is never allowed.

use std::collections::HashMap;
use std::sync::OnceLock;

const HEADER: &str = include_str!("../../../include/crowdgaze.h");

/// Documented statuses of every function of the header, as a bit set over status values.
pub struct Table {
    /// `CG_STATUS_NAME` (without the prefix) to its value.
    values: HashMap<String, u32>,
    /// Function name to the bit set of its allowed statuses.
    allowed: HashMap<String, u64>,
}

/// The table, parsed once.
pub fn table() -> &'static Table {
    static TABLE: OnceLock<Table> = OnceLock::new();
    TABLE.get_or_init(|| Table::parse(HEADER))
}

/// Words of `text` that start with `prefix` and go on with `[A-Za-z0-9_]`.
fn words<'a>(text: &'a str, prefix: &'a str) -> impl Iterator<Item = &'a str> + 'a {
    text.match_indices(prefix).filter_map(move |(start, _)| {
        let before = text[..start].chars().next_back();
        if before.is_some_and(|c| c.is_ascii_alphanumeric() || c == '_') {
            return None;
        }
        let rest = &text[start..];
        let end = rest
            .find(|c: char| !(c.is_ascii_alphanumeric() || c == '_'))
            .unwrap_or(rest.len());
        Some(&rest[..end])
    })
}

impl Table {
    fn parse(header: &str) -> Table {
        let mut values: HashMap<String, u32> = HashMap::new();
        for line in header.lines() {
            let line = line.trim();
            if let Some(rest) = line.strip_prefix("CG_STATUS_") {
                if let Some((name, value)) = rest.trim_end_matches(',').split_once(" = ") {
                    values.insert(name.to_owned(), value.parse().expect("status value"));
                }
            }
        }
        assert!(
            values.len() >= 10,
            "cg_status values in the header: {values:?}"
        );

        // Each function's doc comment: the `//` lines at column 0 right above it.
        let mut docs: HashMap<String, String> = HashMap::new();
        let mut comment = String::new();
        for line in header.lines() {
            if let Some(text) = line.strip_prefix("//") {
                comment.push_str(text);
                comment.push('\n');
                continue;
            }
            let declared = line
                .split_once('(')
                .and_then(|(head, _)| head.rsplit([' ', '*']).next())
                .filter(|name| name.starts_with("cg_") && !line.starts_with(' '));
            if let Some(name) = declared {
                docs.insert(name.to_owned(), std::mem::take(&mut comment));
            }
            comment.clear();
        }

        let named = |doc: &str| -> u64 {
            words(doc, "CG_STATUS_")
                .filter_map(|word| values.get(&word["CG_STATUS_".len()..]))
                .fold(0, |bits, value| bits | 1 << value)
        };
        let mut allowed = HashMap::new();
        for name in docs.keys() {
            // Follow the references of the Errors paragraphs, transitively.
            let mut bits = 1u64 << values["OK"];
            let mut pending = vec![name.as_str()];
            let mut seen: Vec<&str> = vec![];
            while let Some(function) = pending.pop() {
                if seen.contains(&function) {
                    continue;
                }
                seen.push(function);
                let Some(doc) = docs.get(function) else {
                    continue;
                };
                bits |= named(doc);
                if let Some(at) = doc.find("Errors") {
                    pending.extend(words(&doc[at..], "cg_").filter(|w| docs.contains_key(*w)));
                }
            }
            bits &= !(1u64 << values["INTERNAL"]);
            allowed.insert(name.clone(), bits);
        }
        Table { values, allowed }
    }

    /// Whether `function` may return `status`. Panics if the header does not declare
    /// `function` (a typo in the op table, or a function renamed).
    pub fn allows(&self, function: &str, status: u32) -> bool {
        let bits = self
            .allowed
            .get(function)
            .unwrap_or_else(|| panic!("{function} is not declared in include/crowdgaze.h"));
        status < 64 && bits & (1 << status) != 0
    }

    /// The names of the statuses `function` may return, for messages.
    pub fn describe(&self, function: &str) -> Vec<&str> {
        let bits = self.allowed.get(function).copied().unwrap_or(0);
        let mut names: Vec<(&u32, &str)> = self
            .values
            .iter()
            .filter(|(_, value)| bits & (1 << **value) != 0)
            .map(|(name, value)| (value, name.as_str()))
            .collect();
        names.sort();
        names.into_iter().map(|(_, name)| name).collect()
    }
}
