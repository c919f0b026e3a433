//! `GazeTarget` (a `Spatial`): a scene object the characters may look at, at its origin
//! plus `look_at_height` along +Y, as interesting as its `impact`. It joins a `CrowdGaze`
//! node when it enters the tree and leaves it when it exits.

use gdnative::prelude::*;

use crate::character::{find_crowd, with_crowd};
use crate::convert::boundary;
use crate::crowd_gaze::TARGET_GROUP;

/// A scene object for the characters to look at.
#[derive(NativeClass)]
#[inherit(Spatial)]
pub struct GazeTarget {
    /// The `CrowdGaze` node to join; empty: the first one in the tree.
    #[property]
    crowd: NodePath,
    /// How high above the node's origin the characters look, metres.
    #[property(default = 0.0)]
    look_at_height: f64,
    /// How interesting it is (`I_E`, ≥ 0; characters have 1).
    #[property(default = 1.0)]
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

    /// The settings a `CrowdGaze` registers the target with: look-at height and impact.
    pub fn settings(&self) -> (f64, f64) {
        (self.look_at_height, self.impact)
    }
}

#[methods]
impl GazeTarget {
    #[export]
    fn _enter_tree(&self, owner: TRef<Spatial>) {
        boundary("GazeTarget._enter_tree", (), || {
            owner.add_to_group(TARGET_GROUP, false);
            self.join(owner, false);
        })
    }

    #[export]
    fn _ready(&self, owner: TRef<Spatial>) {
        boundary("GazeTarget._ready", (), || self.join(owner, true))
    }

    #[export]
    fn _exit_tree(&self, owner: TRef<Spatial>) {
        boundary("GazeTarget._exit_tree", (), || {
            owner.remove_from_group(TARGET_GROUP);
            if let Some(crowd) = find_crowd(&owner, &self.crowd) {
                let key = owner.get_instance_id();
                with_crowd(crowd, |crowd, _| crowd.unregister(key));
            }
        })
    }
}

impl GazeTarget {
    fn join(&self, owner: TRef<Spatial>, warn: bool) {
        match find_crowd(&owner, &self.crowd) {
            Some(crowd) => {
                let (height, impact) = self.settings();
                with_crowd(crowd, |crowd, crowd_owner| {
                    crowd.register_target(&crowd_owner, owner, height, impact)
                });
            }
            None if warn => godot_warn!(
                "crowdgaze: {}: no CrowdGaze node in the tree yet; the target joins the first \
                 one that enters",
                owner.get_path().to_string()
            ),
            None => {}
        }
    }
}
