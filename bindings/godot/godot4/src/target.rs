//! `GazeTarget` (a `Node3D`): a scene object the characters may look at, at its origin plus
//! `look_at_height` along +Y, as interesting as its `impact`. It joins a `CrowdGaze` node
//! when it enters the tree and leaves it when it exits.

use godot::classes::{INode3D, Node3D};
use godot::prelude::*;

use crate::character::find_crowd;
use crate::convert::boundary;
use crate::crowd_gaze::TARGET_GROUP;

/// A scene object for the characters to look at.
#[derive(GodotClass)]
#[class(base = Node3D)]
pub struct GazeTarget {
    /// The `CrowdGaze` node to join; empty: the first one in the tree.
    #[export]
    crowd: NodePath,
    /// How high above the node's origin the characters look, metres.
    #[export]
    look_at_height: f64,
    /// How interesting it is (`I_E`, ≥ 0; characters have 1).
    #[export]
    impact: f64,
    base: Base<Node3D>,
}

#[godot_api]
impl INode3D for GazeTarget {
    fn init(base: Base<Node3D>) -> Self {
        GazeTarget {
            crowd: NodePath::default(),
            look_at_height: 0.0,
            impact: 1.0,
            base,
        }
    }

    fn enter_tree(&mut self) {
        boundary("GazeTarget._enter_tree", (), || {
            self.base_mut().add_to_group(TARGET_GROUP);
            self.join(false);
        })
    }

    fn ready(&mut self) {
        boundary("GazeTarget._ready", (), || self.join(true))
    }

    fn exit_tree(&mut self) {
        boundary("GazeTarget._exit_tree", (), || {
            self.base_mut().remove_from_group(TARGET_GROUP);
            let node = self.to_gd().upcast::<Node>();
            if let Some(mut crowd) = find_crowd(&node, &self.crowd) {
                crowd.bind_mut().unregister(node.instance_id().to_i64());
            }
        })
    }
}

impl GazeTarget {
    /// The settings a `CrowdGaze` registers the target with: look-at height and impact.
    pub fn settings(&self) -> (f64, f64) {
        (self.look_at_height, self.impact)
    }

    fn join(&self, warn: bool) {
        let node = self.to_gd();
        match find_crowd(&node.clone().upcast::<Node>(), &self.crowd) {
            Some(mut crowd) => {
                let (height, impact) = self.settings();
                crowd
                    .bind_mut()
                    .register_target(node.upcast::<Node3D>(), height, impact);
            }
            None if warn => godot_warn!(
                "crowdgaze: {}: no CrowdGaze node in the tree yet; the target joins the first \
                 one that enters",
                node.upcast::<Node>().get_path()
            ),
            None => {}
        }
    }
}
