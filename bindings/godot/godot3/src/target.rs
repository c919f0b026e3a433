//! `GazeTarget` (a `Spatial`): a scene object the characters may look at, at its origin
//! plus `look_at_height` along +Y, as interesting as its `impact`. It joins a `CrowdGaze`
//! node when it enters the tree and leaves it when it exits.

use gdnative::prelude::*;

use crowdgaze_godot_adapter::{check_target, message};

use crate::character::{crowd_found, leave, resolve_crowd, with_crowd};
use crate::convert::{boundary, in_editor, Data};
use crate::crowd_gaze::TARGET_GROUP;
use crate::{checked_method, checked_property};

/// A scene object for the characters to look at.
#[derive(NativeClass)]
#[inherit(Spatial)]
#[user_data(Data<GazeTarget>)]
#[register_with(Self::register)]
pub struct GazeTarget {
    /// The `CrowdGaze` node to join; empty: the nearest `CrowdGaze` ancestor, else the only
    /// `CrowdGaze` in the tree.
    crowd: NodePath,
    /// How high above the node's origin the characters look, metres.
    look_at_height: f64,
    /// How interesting it is (`I_E`, ≥ 0; characters have 1).
    impact: f64,
}

impl GazeTarget {
    fn new(_owner: &Spatial) -> Self {
        GazeTarget {
            crowd: NodePath::default(),
            look_at_height: 0.0,
            impact: 1.0,
        }
    }

    /// Registers the node's properties (each value's type checked, see
    /// [`props`](crate::props)) and methods (each call's argument count checked, see
    /// [`methods`](mod@crate::methods)).
    fn register(builder: &ClassBuilder<Self>) {
        // The exported properties, each with its value's type checked (see
        // [`props`](crate::props)).
        checked_property!(builder, GazeTarget, crowd: NodePath);
        checked_property!(builder, GazeTarget, look_at_height: f64 = 0.0, then Self::settings_changed);
        checked_property!(builder, GazeTarget, impact: f64 = 1.0, then Self::settings_changed);
        checked_method!(builder, GazeTarget, [], fn _enter_tree(&self, owner: TRef<Spatial>));
        checked_method!(builder, GazeTarget, [], fn _ready(&self, owner: TRef<Spatial>));
        checked_method!(builder, GazeTarget, [], fn _exit_tree(&self, owner: TRef<Spatial>));
        checked_method!(builder, GazeTarget, [], fn _get_configuration_warning(&self, owner: TRef<Spatial>) -> String);
    }

    /// The `crowd` path as set.
    pub fn crowd_path(&self) -> NodePath {
        self.crowd.new_ref()
    }

    /// The settings a `CrowdGaze` registers the target with: look-at height and impact.
    pub fn settings(&self) -> (f64, f64) {
        (self.look_at_height, self.impact)
    }
}

#[methods]
impl GazeTarget {
    fn _enter_tree(&self, owner: TRef<Spatial>) {
        boundary("GazeTarget._enter_tree", (), || {
            owner.add_to_group(TARGET_GROUP, false);
            if in_editor() {
                owner.update_configuration_warning();
                return;
            }
            self.join(owner, false);
        })
    }

    fn _ready(&self, owner: TRef<Spatial>) {
        boundary("GazeTarget._ready", (), || {
            if !in_editor() {
                self.join(owner, true)
            }
        })
    }

    fn _exit_tree(&self, owner: TRef<Spatial>) {
        boundary("GazeTarget._exit_tree", (), || {
            owner.remove_from_group(TARGET_GROUP);
            leave(&owner);
        })
    }

    /// The editor's configuration warnings, one per line (see [`check_target`]).
    fn _get_configuration_warning(&self, owner: TRef<Spatial>) -> String {
        boundary(
            "GazeTarget._get_configuration_warning",
            String::new(),
            || {
                if !owner.is_inside_tree() {
                    return String::new();
                }
                let crowd = crowd_found(&owner, &self.crowd);
                check_target(self.look_at_height, self.impact, &crowd).join("\n")
            },
        )
    }
}

impl GazeTarget {
    fn join(&self, owner: TRef<Spatial>, report: bool) {
        let path = owner.get_path().to_string();
        match resolve_crowd(&owner, &self.crowd) {
            Ok(Some(crowd)) => {
                let (height, impact) = self.settings();
                with_crowd(crowd, |crowd, crowd_owner| {
                    crowd.register_target(&crowd_owner, owner, height, impact)
                });
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
    fn settings_changed(&mut self, owner: TRef<Spatial>) {
        boundary("GazeTarget.settings_changed", (), || {
            if !owner.is_inside_tree() {
                return;
            }
            if in_editor() {
                owner.update_configuration_warning();
                return;
            }
            if let Ok(Some(crowd)) = resolve_crowd(&owner, &self.crowd) {
                let (height, impact) = self.settings();
                with_crowd(crowd, |crowd, crowd_owner| {
                    crowd.update_target(&crowd_owner, owner, height, impact)
                });
            }
        })
    }
}
