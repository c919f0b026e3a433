//! The addon's error messages: one shape for both front ends (`crowdgaze: <node path>:
//! <Class.method>: <what>; <what happens now>`), capped in length, and printed once per
//! node, method and cause ([`Reports`]), however many frames the cause lasts.

use std::collections::HashSet;
use std::fmt::Display;
use std::hash::{DefaultHasher, Hash, Hasher};

use crate::crowd::NodeKey;

/// Longest message the addon prints, in characters (a longer one is cut, marked `...`).
pub const MAX_MESSAGE_CHARS: usize = 1500;

/// `crowdgaze: <node>: <method>: <error>` and `; <consequence>` if there is one, cut to
/// [`MAX_MESSAGE_CHARS`].
pub fn message(node: &str, method: &str, error: &dyn Display, consequence: &str) -> String {
    let mut text = format!("crowdgaze: {node}: {method}: {error}");
    if !consequence.is_empty() {
        text.push_str("; ");
        text.push_str(consequence);
    }
    if text.chars().count() > MAX_MESSAGE_CHARS {
        text = text.chars().take(MAX_MESSAGE_CHARS - 3).collect::<String>() + "...";
    }
    text
}

/// What was reported, so that each (node, method, cause) is reported once. The cause is
/// the error's text with its digits left out: "bone Spine1's pose is not finite" each
/// frame is one cause, a bone count that changes again is the same cause. Not safe for
/// concurrent mutation.
#[derive(Debug, Default)]
pub struct Reports {
    seen: HashSet<(NodeKey, u64)>,
}

impl Reports {
    /// No report yet.
    pub fn new() -> Self {
        Reports::default()
    }

    /// True the first time `node`'s `method` reports `error` (then print it), false after.
    pub fn first(&mut self, node: NodeKey, method: &str, error: &dyn Display) -> bool {
        let mut hasher = DefaultHasher::new();
        method.hash(&mut hasher);
        for c in error.to_string().chars().filter(|c| !c.is_ascii_digit()) {
            c.hash(&mut hasher);
        }
        self.seen.insert((node, hasher.finish()))
    }

    /// Forgets `node`'s reports (it left: if it comes back, its errors are new).
    pub fn forget(&mut self, node: NodeKey) {
        self.seen.retain(|(key, _)| *key != node);
    }

    /// Forgets every report.
    pub fn clear(&mut self) {
        self.seen.clear();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn messages_name_node_and_method_and_are_capped() {
        let text = message(
            "/root/A",
            "CrowdGaze._process",
            &"the delta is NaN",
            "skipped",
        );
        assert_eq!(
            text,
            "crowdgaze: /root/A: CrowdGaze._process: the delta is NaN; skipped"
        );
        let long = "x".repeat(600_000);
        let text = message("/root/A", "m", &long, "");
        assert_eq!(text.chars().count(), MAX_MESSAGE_CHARS);
        assert!(text.ends_with("..."));
    }

    #[test]
    fn each_node_method_and_cause_is_reported_once() {
        let mut reports = Reports::new();
        assert!(reports.first(1, "read", &"the skeleton has 61 bones"));
        assert!(!reports.first(1, "read", &"the skeleton has 62 bones"));
        assert!(reports.first(1, "read", &"bone Head's pose is not finite"));
        assert!(reports.first(1, "write", &"the skeleton has 61 bones"));
        assert!(reports.first(2, "read", &"the skeleton has 61 bones"));
        reports.forget(1);
        assert!(reports.first(1, "read", &"the skeleton has 61 bones"));
        assert!(!reports.first(2, "read", &"the skeleton has 61 bones"));
        reports.clear();
        assert!(reports.first(2, "read", &"the skeleton has 61 bones"));
    }
}
