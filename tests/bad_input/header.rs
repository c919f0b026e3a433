//! The header: its functions, each with its doc comment, and the values of the statuses,
//! read from `include/crowdgaze.h` at test time.

use crowdgaze::ffi::status::cg_status;
use std::collections::{BTreeMap, BTreeSet};

pub(crate) struct Header {
    /// Function name → its doc comment, whitespace collapsed.
    pub(crate) functions: BTreeMap<String, String>,
    /// `CG_STATUS_*` name → value.
    statuses: BTreeMap<String, u32>,
}

impl Header {
    pub(crate) fn read() -> Header {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("include/crowdgaze.h");
        let text = std::fs::read_to_string(&path).expect("include/crowdgaze.h is readable");
        let mut functions = BTreeMap::new();
        let mut statuses = BTreeMap::new();
        let mut comment = Vec::new();
        for line in text.lines() {
            if let Some(doc) = line.strip_prefix("//") {
                comment.push(doc.trim().to_owned());
                continue;
            }
            if let Some((name, value)) = line.trim().trim_end_matches(',').split_once(" = ") {
                if name.starts_with("CG_STATUS_") {
                    statuses.insert(name.to_owned(), value.parse().expect("status value"));
                }
            }
            let declaration = line.starts_with(|c: char| c.is_ascii_alphabetic())
                && !line.starts_with("typedef")
                && !line.starts_with("enum ");
            if let (true, Some(open)) = (declaration, line.find('(')) {
                let name = line[..open]
                    .rsplit(|c: char| !(c.is_ascii_alphanumeric() || c == '_'))
                    .next()
                    .unwrap_or_default();
                if name.starts_with("cg_") {
                    functions.insert(name.to_owned(), comment.join(" "));
                }
            }
            comment.clear();
        }
        assert!(
            functions.len() > 40 && statuses.len() == cg_status::ALL.len(),
            "the header parser found {} functions and {} statuses: has the header's layout changed?",
            functions.len(),
            statuses.len()
        );
        Header {
            functions,
            statuses,
        }
    }

    /// The statuses the doc comment of `function` names, with those of the functions it
    /// refers to for its errors ("as `cg_…`", "those of `cg_…`").
    pub(crate) fn documented(&self, function: &str) -> BTreeSet<u32> {
        let mut found = BTreeSet::new();
        let mut pending = vec![function.to_owned()];
        let mut seen = BTreeSet::new();
        while let Some(name) = pending.pop() {
            if !seen.insert(name.clone()) {
                continue;
            }
            let Some(doc) = self.functions.get(&name) else {
                continue;
            };
            for (status, value) in &self.statuses {
                if doc.contains(status.as_str()) {
                    found.insert(*value);
                }
            }
            for marker in ["as `", "those of `", "as in `"] {
                for (at, _) in doc.match_indices(marker) {
                    let rest = &doc[at + marker.len()..];
                    let referenced = &rest[..rest.find('`').unwrap_or(0)];
                    if self.functions.contains_key(referenced) {
                        pending.push(referenced.to_owned());
                    }
                }
            }
        }
        found
    }

    pub(crate) fn status_name(&self, status: cg_status) -> &str {
        self.statuses
            .iter()
            .find(|(_, value)| **value == status as u32)
            .map_or("?", |(name, _)| name.as_str())
    }
}
