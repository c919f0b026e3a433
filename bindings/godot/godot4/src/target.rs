//! `GazeTarget` (a `Node3D`): a scene object the characters may look at, at its origin plus
//! `look_at_height` along +Y, as interesting as its `impact`. It joins a `CrowdGaze` node
//! when it enters the tree and leaves it when it exits.

use crowdgaze_godot_adapter::{check_target, message};
use godot::classes::{INode3D, Node3D};
use godot::prelude::*;

use crate::character::{crowd_found, leave, resolve_crowd};
use crate::convert::{boundary, in_editor, strings};
use crate::crowd_gaze::TARGET_GROUP;

/// A scene object for the characters to look at.
#[derive(GodotClass)]
#[class(tool, base = Node3D)]
pub struct GazeTarget {
    /// The `CrowdGaze` node to join; empty: the nearest `CrowdGaze` ancestor, else the only
    /// `CrowdGaze` in the tree.
    #[export]
    crowd: NodePath,
    /// How high above the node's origin the characters look, metres.
    #[export]
    #[var(set = set_look_at_height)]
    look_at_height: f64,
    /// How interesting it is (`I_E`, ≥ 0; characters have 1).
    #[export]
    #[var(set = set_impact)]
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
            if in_editor() {
                self.base_mut().update_configuration_warnings();
                return;
            }
            self.join(false);
        })
    }

    fn ready(&mut self) {
        boundary("GazeTarget._ready", (), || {
            if !in_editor() {
                self.join(true)
            }
        })
    }

    fn exit_tree(&mut self) {
        boundary("GazeTarget._exit_tree", (), || {
            self.base_mut().remove_from_group(TARGET_GROUP);
            let node = self.to_gd().upcast::<Node>();
            leave(&node);
        })
    }

    fn get_configuration_warnings(&self) -> PackedStringArray {
        boundary(
            "GazeTarget._get_configuration_warnings",
            PackedStringArray::new(),
            || {
                let node = self.to_gd().upcast::<Node>();
                if !node.is_inside_tree() {
                    return PackedStringArray::new();
                }
                let crowd = crowd_found(&node, &self.crowd);
                strings(&check_target(self.look_at_height, self.impact, &crowd))
            },
        )
    }
}

#[godot_api]
impl GazeTarget {
    /// Sets `look_at_height`; a target in a crowd takes it at once.
    #[func]
    fn set_look_at_height(&mut self, look_at_height: f64) {
        self.look_at_height = look_at_height;
        self.settings_changed();
    }

    /// Sets `impact`; a target in a crowd takes it at once.
    #[func]
    fn set_impact(&mut self, impact: f64) {
        self.impact = impact;
        self.settings_changed();
    }
}

impl GazeTarget {
    /// The settings a `CrowdGaze` registers the target with: look-at height and impact.
    pub fn settings(&self) -> (f64, f64) {
        (self.look_at_height, self.impact)
    }

    fn join(&self, report: bool) {
        let node = self.to_gd();
        let path = node.clone().upcast::<Node>().get_path().to_string();
        match resolve_crowd(&node.clone().upcast::<Node>(), &self.crowd) {
            Ok(Some(mut crowd)) => {
                let (height, impact) = self.settings();
                crowd
                    .bind_mut()
                    .register_target(node.upcast::<Node3D>(), height, impact);
            }
            Ok(None) if report => godot_warn!(
                "crowdgaze: {path}: no CrowdGaze node in the tree yet; the target joins the \
                 first one that enters"
            ),
            Ok(None) => {}
            Err(error) if report => godot_error!(
                "{}",
                message(
                    &path,
                    "GazeTarget._ready",
                    &error,
                    "the target joins no crowd"
                )
            ),
            Err(_) => {}
        }
    }

    /// `look_at_height` or `impact` was set: a target in a crowd takes the new values now.
    fn settings_changed(&mut self) {
        boundary("GazeTarget.settings_changed", (), || {
            let mut node = self.to_gd();
            if !node.is_inside_tree() {
                return;
            }
            if in_editor() {
                node.update_configuration_warnings();
                return;
            }
            if let Ok(Some(mut crowd)) = resolve_crowd(&node.clone().upcast::<Node>(), &self.crowd)
            {
                let (height, impact) = self.settings();
                crowd
                    .bind_mut()
                    .update_target(node.upcast::<Node3D>(), height, impact);
            }
        })
    }

    /// The `crowd` path as set.
    pub fn crowd_path(&self) -> NodePath {
        self.crowd.clone()
    }
}
