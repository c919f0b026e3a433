//! `CrowdGazeCharacter` (a `Spatial`): makes its parent `Skeleton` a character of the
//! crowd. Its global transform is the character's frame (its origin on the ground, its +Z
//! the way the character faces): keep it at the skeleton's origin unless the model faces
//! elsewhere. It joins a `CrowdGaze` node when it enters the tree and leaves it when it
//! exits (freed or removed).

use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Arc;

use gdnative::prelude::*;

use crate::convert::boundary;
use crate::crowd_gaze::{CrowdGaze, CHARACTER_GROUP, CROWD_GROUP};

/// A character: its parent `Skeleton`'s bones are mapped to a gaze chain by name.
#[derive(NativeClass)]
#[inherit(Spatial)]
pub struct CrowdGazeCharacter {
    /// The `CrowdGaze` node to join; empty: the first one in the tree.
    #[property]
    crowd: NodePath,
    /// Bone map overrides, `Name=role` comma separated (roles: root, spine, neck, head,
    /// left_eye, right_eye, none), on top of the default map (Hips, Spine…, Neck, Head,
    /// LeftEye, RightEye and the usual variants).
    #[property]
    bone_map: GodotString,
    /// How interesting this character is to others (`I_E`, ≥ 0).
    #[property(default = 1.0)]
    impact: f64,
    /// What the crowd knows of the node's life (see [`Presence`]).
    presence: Presence,
}

/// A `CrowdGazeCharacter` node's stamp: how many times it left the tree, or
/// [`Presence::GONE`] once the node is about to be freed or its script instance goes (the
/// script taken off it). While the stamp is the one taken at registration (in the tree), the
/// node has stayed alive and in the tree under the same parent (a node changes parent only
/// out of the tree), so the crowd uses the node and skeleton it kept then, without looking
/// their instance ids up in Godot's object database each frame (a hash lookup behind a lock
/// that costs more than reading the skeleton).
#[derive(Debug, Clone)]
pub struct Presence(Arc<AtomicU64>);

impl Presence {
    /// The stamp of a node that is gone, or whose script instance is.
    pub const GONE: u64 = u64::MAX;

    /// A node that has not left the tree yet.
    fn new() -> Self {
        Presence(Arc::new(AtomicU64::new(0)))
    }

    /// The current stamp.
    pub fn stamp(&self) -> u64 {
        self.0.load(Ordering::Acquire)
    }

    /// The node leaves the tree: a new stamp (unless it is gone).
    fn exited(&self) {
        let _ = self
            .0
            .fetch_update(Ordering::AcqRel, Ordering::Acquire, |stamp| {
                (stamp < Self::GONE - 1).then_some(stamp + 1)
            });
    }

    /// The node or its script instance goes, for good.
    fn gone(&self) {
        self.0.store(Self::GONE, Ordering::Release);
    }
}

impl CrowdGazeCharacter {
    fn new(_owner: &Spatial) -> Self {
        CrowdGazeCharacter {
            crowd: NodePath::default(),
            bone_map: GodotString::new(),
            impact: 1.0,
            presence: Presence::new(),
        }
    }

    /// The settings a `CrowdGaze` registers the character with: bone map and impact, and
    /// the node's presence.
    pub fn settings(&self) -> (String, f64, Presence) {
        (
            self.bone_map.to_string(),
            self.impact,
            self.presence.clone(),
        )
    }
}

impl Drop for CrowdGazeCharacter {
    /// The script instance goes: its node is freed, or keeps living without it (the crowd
    /// then finds it by id, as any node).
    fn drop(&mut self) {
        self.presence.gone();
    }
}

/// The `CrowdGaze` node a character or target joins: the one at `path`, or the first one
/// in the tree.
pub fn find_crowd<'a>(owner: &'a Spatial, path: &NodePath) -> Option<TRef<'a, Spatial, Shared>> {
    let node = if path.is_empty() {
        let tree = owner.get_tree()?;
        // SAFETY: the scene tree and its nodes live on the main thread for this call.
        let tree = unsafe { tree.assume_safe() };
        let nodes = tree.get_nodes_in_group(CROWD_GROUP);
        (0..nodes.len())
            .filter_map(|i| nodes.get(i).try_to_object::<Node>())
            .next()?
    } else {
        owner.get_node(path.new_ref())?
    };
    // SAFETY: as above.
    let node = unsafe { node.assume_safe_if_sane()? };
    node.cast::<Spatial>()
}

/// Calls `f` on the `CrowdGaze` behind `crowd`; false if it is not one or is busy.
pub fn with_crowd(
    crowd: TRef<Spatial, Shared>,
    f: impl FnOnce(&mut CrowdGaze, TRef<Spatial, Shared>),
) -> bool {
    crowd
        .cast_instance::<CrowdGaze>()
        .is_some_and(|instance| instance.map_mut(f).is_ok())
}

#[methods]
impl CrowdGazeCharacter {
    #[export]
    fn _enter_tree(&self, owner: TRef<Spatial>) {
        boundary("CrowdGazeCharacter._enter_tree", (), || {
            owner.add_to_group(CHARACTER_GROUP, false);
            self.join(owner, false);
        })
    }

    #[export]
    fn _ready(&self, owner: TRef<Spatial>) {
        boundary("CrowdGazeCharacter._ready", (), || self.join(owner, true))
    }

    #[export]
    fn _exit_tree(&self, owner: TRef<Spatial>) {
        boundary("CrowdGazeCharacter._exit_tree", (), || {
            owner.remove_from_group(CHARACTER_GROUP);
            self.presence.exited();
            if let Some(crowd) = find_crowd(&owner, &self.crowd) {
                let key = owner.get_instance_id();
                with_crowd(crowd, |crowd, _| crowd.unregister(key));
            }
        })
    }

    #[export]
    fn _notification(&self, _owner: TRef<Spatial>, what: i64) {
        if what == Object::NOTIFICATION_PREDELETE {
            self.presence.gone();
        }
    }

    /// The `CrowdGaze` node this character joins (null if there is none).
    #[export]
    fn get_crowd_node(&self, owner: TRef<Spatial>) -> Variant {
        find_crowd(&owner, &self.crowd).map_or_else(Variant::new, |crowd| crowd.to_variant())
    }
}

impl CrowdGazeCharacter {
    fn join(&self, owner: TRef<Spatial>, warn: bool) {
        match find_crowd(&owner, &self.crowd) {
            Some(crowd) => {
                let (bone_map, impact, presence) = self.settings();
                with_crowd(crowd, |crowd, crowd_owner| {
                    crowd.register_character(&crowd_owner, owner, &bone_map, impact, presence)
                });
            }
            None if warn => godot_warn!(
                "crowdgaze: {}: no CrowdGaze node in the tree yet; the character joins the \
                 first one that enters",
                owner.get_path().to_string()
            ),
            None => {}
        }
    }
}
