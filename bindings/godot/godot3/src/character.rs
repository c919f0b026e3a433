//! `CrowdGazeCharacter` (a `Spatial`): makes its parent `Skeleton` a character of the
//! crowd. Its global transform is the character's frame (its origin on the ground, its +Z
//! the way the character faces): keep it at the skeleton's origin unless the model faces
//! elsewhere. It joins a `CrowdGaze` node when it enters the tree and leaves it when it
//! exits (freed or removed).

use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Arc;

use crowdgaze_godot_adapter::{choose_crowd, message, CharacterValues, NamedNode, Reports};
use gdnative::nativescript::init::property::hint::FloatHint;
use gdnative::prelude::*;

use crate::convert::{
    add_checked, boundary, eye_angle_hint, fraction_hint, head_turn_hint, is_main_thread,
    model_hint, refuse_once, seconds_hint, unit_hint, Checked, Data,
};
use crate::crowd_gaze::{CrowdGaze, CHARACTER_GROUP, CROWD_GROUP};

/// A character: its parent `Skeleton`'s bones are mapped to a gaze chain by name.
#[derive(NativeClass)]
#[inherit(Spatial)]
#[user_data(Data<CrowdGazeCharacter>)]
#[register_with(Self::register)]
pub struct CrowdGazeCharacter {
    /// The `CrowdGaze` node to join; empty: the nearest `CrowdGaze` ancestor, else the only
    /// `CrowdGaze` in the tree.
    #[property]
    crowd: NodePath,
    /// Bone map overrides, `Name=role` comma separated (roles: root, spine, neck, head,
    /// left_eye, right_eye, none), on top of the default map (Hips, Spine…, Neck, Head,
    /// LeftEye, RightEye and the usual variants).
    #[property(after_set = "Self::settings_changed")]
    bone_map: GodotString,
    /// How interesting this character is to others (`I_E`, ≥ 0).
    #[property(default = 1.0, after_set = "Self::settings_changed")]
    impact: f64,
    /// Whether the gaze is applied: false fades the influence to 0 over
    /// `influence_fade_time`, then leaves the bones to the animation (attention keeps
    /// running, so turning it back on is smooth).
    active: bool,
    /// How much of the gaze the bones take, 0 (the animation alone) to 1 (the gaze); the
    /// `CrowdGaze` node's `influence` multiplies it.
    influence: f64,
    /// Seconds a change of `active` or `influence` takes to show fully (0: at once).
    influence_fade_time: f64,
    /// True while the character talks: others in its conversation look at it more.
    talking: bool,
    /// The share of the time the character attends to something, 0 to 1; -1: the crowd's
    /// draw (from `attention_fraction_min` to `attention_fraction_max`).
    attention_fraction: f64,
    /// The model deciding where the character looks: 0 the crowd model (Grillon &
    /// Thalmann), 1 saliency (Kokkinara et al.), 2 the baseline.
    attention_model: i64,
    /// Degrees the neck and head may turn together (yaw; the library's chain has 70). The
    /// skeleton is mapped again when it changes.
    max_head_turn: f64,
    /// Degrees each eye may turn from straight ahead (the library's chain has 35).
    max_eye_angle: f64,
    /// A `MeshInstance` whose blink blend shapes take the eyelids' closure each frame
    /// (empty: none). Its shapes are found by name (ARKit `eyeBlinkLeft`/`eyeBlinkRight`,
    /// VRM `Blink_L`/`Blink_R`/`Blink`, `blink`) unless `eyelid_shapes` names them.
    eyelid_mesh: NodePath,
    /// The blink blend shapes of `eyelid_mesh`: empty (found by name), one name for both
    /// eyes, or `left,right`.
    eyelid_shapes: GodotString,
    /// What was reported of values of the wrong type (once per property and type).
    reports: Reports,
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
        let defaults = CharacterValues::default();
        CrowdGazeCharacter {
            crowd: NodePath::default(),
            bone_map: GodotString::new(),
            impact: defaults.impact,
            active: defaults.active,
            influence: defaults.influence,
            influence_fade_time: defaults.influence_fade_time,
            talking: defaults.talking,
            attention_fraction: defaults.attention_fraction,
            attention_model: defaults.attention_model,
            max_head_turn: defaults.max_head_turn,
            max_eye_angle: defaults.max_eye_angle,
            eyelid_mesh: NodePath::default(),
            eyelid_shapes: GodotString::new(),
            reports: Reports::new(),
            presence: Presence::new(),
        }
    }

    /// Registers the properties that check their values' types (see [`add_checked`]).
    fn register(builder: &ClassBuilder<Self>) {
        let d = CharacterValues::default();
        let refuse = Self::refuse;
        type Get<T> = fn(&CrowdGazeCharacter) -> T;
        type Set<T> = fn(&mut CrowdGazeCharacter, TRef<Spatial>, T);
        /// Name, type as a message says it, default, hint, getter, setter.
        type Float = (
            &'static str,
            &'static str,
            f64,
            FloatHint<f64>,
            Get<f64>,
            Set<f64>,
        );
        let floats: [Float; 5] = [
            (
                "influence",
                "a float from 0 to 1",
                d.influence,
                unit_hint(),
                |c| c.influence,
                |c, owner, v| c.set(owner, |c| c.influence = v),
            ),
            (
                "influence_fade_time",
                "a float (seconds)",
                d.influence_fade_time,
                seconds_hint(),
                |c| c.influence_fade_time,
                |c, owner, v| c.set(owner, |c| c.influence_fade_time = v),
            ),
            (
                "attention_fraction",
                "a float from 0 to 1, or -1",
                d.attention_fraction,
                fraction_hint(),
                |c| c.attention_fraction,
                |c, owner, v| c.set(owner, |c| c.attention_fraction = v),
            ),
            (
                "max_head_turn",
                "a float (degrees)",
                d.max_head_turn,
                head_turn_hint(),
                |c| c.max_head_turn,
                |c, owner, v| c.set(owner, |c| c.max_head_turn = v),
            ),
            (
                "max_eye_angle",
                "a float (degrees)",
                d.max_eye_angle,
                eye_angle_hint(),
                |c| c.max_eye_angle,
                |c, owner, v| c.set(owner, |c| c.max_eye_angle = v),
            ),
        ];
        for (name, expected, default, hint, get, set) in floats {
            let hint = Some(hint);
            add_checked(
                builder,
                Checked {
                    name,
                    expected,
                    default,
                    hint,
                    get,
                    set,
                    refuse,
                },
            );
        }
        let bools: [(&str, bool, Get<bool>, Set<bool>); 2] = [
            (
                "active",
                d.active,
                |c| c.active,
                |c, owner, v| c.set(owner, |c| c.active = v),
            ),
            (
                "talking",
                d.talking,
                |c| c.talking,
                |c, owner, v| c.set(owner, |c| c.talking = v),
            ),
        ];
        for (name, default, get, set) in bools {
            let (expected, hint) = ("a bool", None);
            add_checked(
                builder,
                Checked {
                    name,
                    expected,
                    default,
                    hint,
                    get,
                    set,
                    refuse,
                },
            );
        }
        add_checked(
            builder,
            Checked {
                name: "attention_model",
                expected: "an int (0, 1 or 2)",
                default: d.attention_model,
                hint: Some(model_hint()),
                get: |c| c.attention_model,
                set: |c, owner, v| c.set(owner, |c| c.attention_model = v),
                refuse,
            },
        );
        add_checked(
            builder,
            Checked {
                name: "eyelid_mesh",
                expected: "a NodePath",
                default: NodePath::default(),
                hint: None,
                get: |c| c.eyelid_mesh.new_ref(),
                set: |c, owner, v| c.set(owner, |c| c.eyelid_mesh = v),
                refuse,
            },
        );
        add_checked(
            builder,
            Checked {
                name: "eyelid_shapes",
                expected: "a String",
                default: GodotString::new(),
                hint: None,
                get: |c| c.eyelid_shapes.clone(),
                set: |c, owner, v| c.set(owner, |c| c.eyelid_shapes = v),
                refuse,
            },
        );
    }

    /// Sets a property with `change`; a character in a crowd takes it at once.
    fn set(&mut self, owner: TRef<Spatial>, change: impl FnOnce(&mut Self)) {
        change(self);
        self.settings_changed(owner);
    }

    /// A property was given a value of the wrong type: reported once per property and type;
    /// the property keeps its value.
    fn refuse(&mut self, owner: TRef<Spatial>, error: &str) {
        refuse_once(&mut self.reports, &owner, "CrowdGazeCharacter.set", error);
    }

    /// The `crowd` path as set.
    pub fn crowd_path(&self) -> NodePath {
        self.crowd.new_ref()
    }

    /// The settings a `CrowdGaze` registers the character with, as given.
    pub fn settings(&self) -> CharacterInputs {
        CharacterInputs {
            values: CharacterValues {
                bone_map: self.bone_map.to_string(),
                impact: self.impact,
                attention_fraction: self.attention_fraction,
                attention_model: self.attention_model,
                max_head_turn: self.max_head_turn,
                max_eye_angle: self.max_eye_angle,
                active: self.active,
                influence: self.influence,
                influence_fade_time: self.influence_fade_time,
                talking: self.talking,
            },
            eyelid_mesh: self.eyelid_mesh.new_ref(),
            eyelid_shapes: self.eyelid_shapes.to_string(),
            presence: self.presence.clone(),
        }
    }
}

/// What a `CrowdGaze` registers a character with: its values as given, its eyelid mesh
/// and shapes, and its presence.
pub struct CharacterInputs {
    /// The adapter's values.
    pub values: CharacterValues,
    /// `eyelid_mesh`, relative to the character node.
    pub eyelid_mesh: NodePath,
    /// `eyelid_shapes`.
    pub eyelid_shapes: String,
    /// The node's presence (see [`Presence`]).
    pub presence: Presence,
}

impl Drop for CrowdGazeCharacter {
    /// The script instance goes: its node is freed, or keeps living without it (the crowd
    /// then finds it by id, as any node).
    fn drop(&mut self) {
        self.presence.gone();
    }
}

/// The `CrowdGaze` node a character or target joins (see
/// [`choose_crowd`]): the one its `crowd` path names, else its nearest `CrowdGaze`
/// ancestor, else the only one in the tree; `Ok(None)` if there is none yet. Errors say
/// what to set.
pub fn resolve_crowd<'a>(
    owner: &'a Spatial,
    path: &NodePath,
) -> Result<Option<TRef<'a, Spatial, Shared>>, String> {
    // SAFETY: the nodes of the tree live on the main thread for this call.
    let sane = |node: Ref<Node, Shared>| unsafe { node.assume_safe_if_sane() };
    let is_crowd = |node: TRef<'a, Node, Shared>| {
        node.cast::<Spatial>()
            .filter(|spatial| spatial.cast_instance::<CrowdGaze>().is_some())
    };
    let mut candidates: Vec<TRef<'a, Spatial, Shared>> = Vec::new();
    let named = if path.is_empty() {
        NamedNode::Unset
    } else {
        match owner.get_node(path.new_ref()).and_then(sane) {
            None => NamedNode::Missing,
            Some(node) => match is_crowd(node) {
                Some(crowd) => {
                    candidates.push(crowd);
                    NamedNode::Crowd(0)
                }
                None => NamedNode::NotACrowd(format!(
                    "{} ({})",
                    node.get_class(),
                    node.get_path().to_string()
                )),
            },
        }
    };
    let mut ancestor = None;
    let mut parent = owner.get_parent().and_then(sane);
    while let Some(node) = parent {
        if let Some(crowd) = is_crowd(node) {
            ancestor = Some(candidates.len());
            candidates.push(crowd);
            break;
        }
        parent = node.get_parent().and_then(sane);
    }
    let mut in_tree = Vec::new();
    if let Some(tree) = owner.get_tree() {
        // SAFETY: the scene tree lives on the main thread for this call.
        let tree = unsafe { tree.assume_safe() };
        for node in tree.get_nodes_in_group(CROWD_GROUP).iter() {
            if let Some(crowd) = node
                .try_to_object::<Node>()
                .and_then(sane)
                .and_then(is_crowd)
            {
                in_tree.push(candidates.len());
                candidates.push(crowd);
            }
        }
    }
    let text = path.to_string();
    Ok(choose_crowd(&text, named, ancestor, &in_tree)?.map(|k| candidates[k]))
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
            leave(&owner);
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
        boundary("CrowdGazeCharacter.get_crowd_node", Variant::new(), || {
            resolve_crowd(&owner, &self.crowd)
                .ok()
                .flatten()
                .map_or_else(Variant::new, |crowd| crowd.to_variant())
        })
    }

    /// Joins the crowd on the main thread (called deferred when the node entered the tree
    /// on another thread).
    #[export]
    fn _crowdgaze_join(&self, owner: TRef<Spatial>) {
        boundary("CrowdGazeCharacter._crowdgaze_join", (), || {
            if owner.is_inside_tree() {
                self.join(owner, true);
            }
        })
    }
}

/// Takes a node out of every crowd (it left the tree, or its script goes).
pub fn leave(owner: &Spatial) {
    let key = owner.get_instance_id();
    if let Some(tree) = owner.get_tree() {
        // SAFETY: the scene tree and its nodes live on the main thread for this call.
        let tree = unsafe { tree.assume_safe() };
        for node in tree.get_nodes_in_group(CROWD_GROUP).iter() {
            let crowd = node
                .try_to_object::<Spatial>()
                .and_then(|node| unsafe { node.assume_safe_if_sane() });
            if let Some(crowd) = crowd {
                with_crowd(crowd, |crowd, _| crowd.unregister(key));
            }
        }
    }
}

impl CrowdGazeCharacter {
    /// Joins its crowd; on another thread than the main one, deferred to it. With `report`
    /// (in `_ready`), a crowd path or tree that names no crowd is reported.
    fn join(&self, owner: TRef<Spatial>, report: bool) {
        if !is_main_thread() {
            // SAFETY: a deferred call of our own method, run on the main thread.
            unsafe { owner.call_deferred("_crowdgaze_join", &[]) };
            return;
        }
        let path = owner.get_path().to_string();
        match resolve_crowd(&owner, &self.crowd) {
            Ok(Some(crowd)) => {
                let inputs = self.settings();
                with_crowd(crowd, |crowd, crowd_owner| {
                    crowd.register_character(&crowd_owner, owner, inputs)
                });
            }
            Ok(None) if report => godot_warn!(
                "crowdgaze: {path}: no CrowdGaze node in the tree yet; the character joins the \
                 first one that enters"
            ),
            Ok(None) => {}
            Err(error) if report => godot_error!(
                "{}",
                message(
                    &path,
                    "CrowdGazeCharacter._ready",
                    &error,
                    "the character joins no crowd"
                )
            ),
            Err(_) => {}
        }
    }

    /// A setting was set: a character in a crowd takes the new values now.
    fn settings_changed(&mut self, owner: TRef<Spatial>) {
        boundary("CrowdGazeCharacter.settings_changed", (), || {
            if !owner.is_inside_tree() {
                return;
            }
            if let Ok(Some(crowd)) = resolve_crowd(&owner, &self.crowd) {
                let inputs = self.settings();
                with_crowd(crowd, |crowd, crowd_owner| {
                    crowd.update_character(&crowd_owner, owner, inputs)
                });
            }
        })
    }
}
