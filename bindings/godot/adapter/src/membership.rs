//! Which crowd a node joins, and which character drives a skeleton: the rules both front
//! ends follow, so that a character is never in two crowds and a skeleton never driven by
//! two characters.
//!
//! - [`choose_crowd`]: a character or target joins the `CrowdGaze` its `crowd` path names,
//!   else its nearest `CrowdGaze` ancestor, else the only `CrowdGaze` in the tree; a path
//!   naming nothing or something else, or several crowds and none an ancestor, is an
//!   error that says what to set.
//! - [`claim_skeleton`]: one character per skeleton across every crowd of the process; the
//!   claim is released when the returned [`SkeletonClaim`] is dropped.

use std::collections::BTreeMap;
use std::sync::Mutex;

use crate::crowd::NodeKey;

/// The group every `CrowdGaze` node is in while in the tree. The addon's groups start with
/// an underscore so that they cannot clash with a game's own; read them, do not add nodes
/// to them.
pub const CROWD_GROUP: &str = "_crowdgaze_crowds";
/// The group every `CrowdGazeCharacter` node is in while in the tree.
pub const CHARACTER_GROUP: &str = "_crowdgaze_characters";
/// The group every `GazeTarget` node is in while in the tree.
pub const TARGET_GROUP: &str = "_crowdgaze_targets";

/// What a node's `crowd` path names, as the front end found it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum NamedNode<K> {
    /// The path is empty.
    Unset,
    /// No node is at the path.
    Missing,
    /// A node that is not a `CrowdGaze`: its class (and script) for the message.
    NotACrowd(String),
    /// A `CrowdGaze` node.
    Crowd(K),
}

/// The crowd a node joins (`None`: no crowd yet; it joins the one that enters), from its
/// `crowd` path as written (`path`), what the path names (`named`), its nearest
/// `CrowdGaze` ancestor, and every `CrowdGaze` in the tree.
///
/// Errors (the node joins no crowd): the path names no node or a node that is not a
/// `CrowdGaze`; the path is empty, no ancestor is a `CrowdGaze`, and several are in the
/// tree.
pub fn choose_crowd<K: Copy>(
    path: &str,
    named: NamedNode<K>,
    ancestor: Option<K>,
    in_tree: &[K],
) -> Result<Option<K>, String> {
    match named {
        NamedNode::Crowd(crowd) => Ok(Some(crowd)),
        NamedNode::Missing => Err(format!(
            "crowd = '{path}' names no node: point it at a CrowdGaze node, or clear it to \
             join the nearest CrowdGaze ancestor"
        )),
        NamedNode::NotACrowd(class) => Err(format!(
            "crowd = '{path}' names a {class}, not a CrowdGaze: point it at a CrowdGaze node, \
             or clear it to join the nearest CrowdGaze ancestor"
        )),
        NamedNode::Unset => match (ancestor, in_tree) {
            (Some(crowd), _) => Ok(Some(crowd)),
            (None, []) => Ok(None),
            (None, [only]) => Ok(Some(*only)),
            (None, several) => Err(format!(
                "{} CrowdGaze nodes are in the tree and none is an ancestor of this node: set \
                 its crowd path to the one to join",
                several.len()
            )),
        },
    }
}

/// The characters driving skeletons: skeleton key → (character key, character path).
static CLAIMS: Mutex<BTreeMap<NodeKey, (NodeKey, String)>> = Mutex::new(BTreeMap::new());

/// A character's hold on its skeleton, released when dropped.
#[derive(Debug)]
pub struct SkeletonClaim {
    skeleton: NodeKey,
    character: NodeKey,
}

impl Drop for SkeletonClaim {
    fn drop(&mut self) {
        let mut claims = CLAIMS.lock().unwrap_or_else(|e| e.into_inner());
        if claims.get(&self.skeleton).map(|held| held.0) == Some(self.character) {
            claims.remove(&self.skeleton);
        }
    }
}

/// Makes `character` (whose node path is `path`) the one character driving `skeleton`.
/// Errors if another character holds it: the message names that one.
pub fn claim_skeleton(
    skeleton: NodeKey,
    character: NodeKey,
    path: &str,
) -> Result<SkeletonClaim, String> {
    let mut claims = CLAIMS.lock().unwrap_or_else(|e| e.into_inner());
    match claims.get(&skeleton) {
        Some((holder, holder_path)) if *holder != character => Err(format!(
            "its skeleton is driven already by the CrowdGazeCharacter {holder_path}: one \
             CrowdGazeCharacter per skeleton; remove one of the two"
        )),
        _ => {
            claims.insert(skeleton, (character, path.to_string()));
            Ok(SkeletonClaim {
                skeleton,
                character,
            })
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_path_then_the_ancestor_then_the_only_crowd() {
        let crowds = [10, 20];
        assert_eq!(
            choose_crowd("../B", NamedNode::Crowd(20), Some(10), &crowds),
            Ok(Some(20))
        );
        assert_eq!(
            choose_crowd("", NamedNode::Unset, Some(10), &crowds),
            Ok(Some(10))
        );
        assert_eq!(
            choose_crowd("", NamedNode::Unset, None, &[20]),
            Ok(Some(20))
        );
        assert_eq!(
            choose_crowd::<i64>("", NamedNode::Unset, None, &[]),
            Ok(None)
        );
        let several = choose_crowd("", NamedNode::Unset, None, &crowds).unwrap_err();
        assert!(several.contains("2 CrowdGaze nodes") && several.contains("set its crowd path"));
        let missing = choose_crowd("../Nope", NamedNode::Missing, Some(10), &crowds);
        assert!(missing
            .unwrap_err()
            .contains("crowd = '../Nope' names no node"));
        let other = choose_crowd(
            "../Lamp",
            NamedNode::NotACrowd("Spatial".into()),
            None,
            &[10],
        );
        assert!(other
            .unwrap_err()
            .contains("names a Spatial, not a CrowdGaze"));
    }

    #[test]
    fn one_character_per_skeleton() {
        let first = claim_skeleton(-7001, -1, "/root/A/Skeleton/Gaze").unwrap();
        // The holder may claim again (re-registration).
        let again = claim_skeleton(-7001, -1, "/root/A/Skeleton/Gaze").unwrap();
        let error = claim_skeleton(-7001, -2, "/root/A/Skeleton/Gaze2").unwrap_err();
        assert!(error.contains("/root/A/Skeleton/Gaze:"), "{error}");
        drop(again);
        drop(first);
        let second = claim_skeleton(-7001, -2, "/root/A/Skeleton/Gaze2").unwrap();
        // A stale claim of the first does not release the second's.
        drop(SkeletonClaim {
            skeleton: -7001,
            character: -1,
        });
        assert!(claim_skeleton(-7001, -3, "x").is_err());
        drop(second);
        assert!(claim_skeleton(-7001, -3, "x").is_ok());
    }
}
