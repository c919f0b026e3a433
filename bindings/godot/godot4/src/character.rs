//! `CrowdGazeCharacter` (a `SkeletonModifier3D`): makes its parent `Skeleton3D` a character
//! of the crowd, and writes the character's gaze in the skeleton's modifier pass, after the
//! animation. Its transform relative to the skeleton is the character's frame (origin on the
//! ground, +Z the way the character faces): identity unless the model faces elsewhere. It
//! joins a `CrowdGaze` node when it enters the tree and leaves it when it exits (freed or
//! removed).

use godot::classes::{ISkeletonModifier3D, Node3D, SkeletonModifier3D};
use godot::prelude::*;

use crate::convert::boundary;
use crate::crowd_gaze::{CrowdGaze, CHARACTER_GROUP, CROWD_GROUP};

/// A character: its parent `Skeleton3D`'s bones are mapped to a gaze chain by name.
#[derive(GodotClass)]
#[class(base = SkeletonModifier3D)]
pub struct CrowdGazeCharacter {
    /// The `CrowdGaze` node to join; empty: the first one in the tree.
    #[export]
    crowd: NodePath,
    /// Bone map overrides, `Name=role` comma separated (roles: root, spine, neck, head,
    /// left_eye, right_eye, none), on top of the default map (Hips, Spine…, Neck, Head,
    /// LeftEye, RightEye and the usual variants).
    #[export]
    bone_map: GString,
    /// How interesting this character is to others (`I_E`, ≥ 0).
    #[export]
    impact: f64,
    /// The `CrowdGaze` node joined (its instance id), for the per-frame write.
    joined: Option<InstanceId>,
    base: Base<SkeletonModifier3D>,
}

/// The `CrowdGaze` node a character or target joins: the one at `path`, or the first one
/// in the tree.
pub fn find_crowd(node: &Gd<Node>, path: &NodePath) -> Option<Gd<CrowdGaze>> {
    if !node.is_inside_tree() {
        return None;
    }
    let found = if path.is_empty() {
        node.get_tree()
            .get_nodes_in_group(CROWD_GROUP)
            .iter_shared()
            .next()?
    } else {
        node.get_node_or_null(path)?
    };
    found.try_cast::<CrowdGaze>().ok()
}

#[godot_api]
impl ISkeletonModifier3D for CrowdGazeCharacter {
    fn init(base: Base<SkeletonModifier3D>) -> Self {
        CrowdGazeCharacter {
            crowd: NodePath::default(),
            bone_map: GString::new(),
            impact: 1.0,
            joined: None,
            base,
        }
    }

    fn enter_tree(&mut self) {
        boundary("CrowdGazeCharacter._enter_tree", (), || {
            self.base_mut().add_to_group(CHARACTER_GROUP);
            self.join(false);
        })
    }

    fn ready(&mut self) {
        boundary("CrowdGazeCharacter._ready", (), || self.join(true))
    }

    fn exit_tree(&mut self) {
        boundary("CrowdGazeCharacter._exit_tree", (), || {
            self.base_mut().remove_from_group(CHARACTER_GROUP);
            let node = self.to_gd().upcast::<Node>();
            let crowd = self
                .joined
                .take()
                .and_then(|id| Gd::try_from_instance_id(id).ok());
            if let Some(mut crowd) = crowd.or_else(|| find_crowd(&node, &self.crowd)) {
                let key = node.instance_id().to_i64();
                crowd.bind_mut().unregister(key);
            }
        })
    }

    fn process_modification(&mut self) {
        boundary("CrowdGazeCharacter._process_modification", (), || {
            let Some(skeleton) = self.base().get_skeleton() else {
                return;
            };
            let Some(id) = self.joined else {
                return;
            };
            // The crowd joined, found by id: no search of the tree each frame.
            if let Ok(mut crowd) = Gd::<CrowdGaze>::try_from_instance_id(id) {
                let key = self.to_gd().instance_id().to_i64();
                crowd.bind_mut().write_character(key, skeleton);
            }
        })
    }
}

#[godot_api]
impl CrowdGazeCharacter {
    /// The `CrowdGaze` node this character joins (null if there is none).
    #[func]
    fn get_crowd_node(&self) -> Variant {
        let node = self.to_gd().upcast::<Node>();
        find_crowd(&node, &self.crowd).map_or_else(Variant::nil, |crowd| crowd.to_variant())
    }
}

impl CrowdGazeCharacter {
    /// Records the `CrowdGaze` node that registered the character (it writes through it).
    pub fn set_joined(&mut self, crowd: InstanceId) {
        self.joined = Some(crowd);
    }

    /// The settings a `CrowdGaze` registers the character with: bone map and impact.
    pub fn settings(&self) -> (String, f64) {
        (self.bone_map.to_string(), self.impact)
    }

    fn join(&mut self, warn: bool) {
        let node = self.to_gd();
        match find_crowd(&node.clone().upcast::<Node>(), &self.crowd) {
            Some(mut crowd) => {
                let (bone_map, impact) = self.settings();
                self.joined = Some(crowd.instance_id());
                crowd
                    .bind_mut()
                    .register_character(node.upcast::<Node3D>(), &bone_map, impact);
            }
            None if warn => godot_warn!(
                "crowdgaze: {}: no CrowdGaze node in the tree yet; the character joins the \
                 first one that enters",
                node.upcast::<Node>().get_path()
            ),
            None => {}
        }
    }
}
