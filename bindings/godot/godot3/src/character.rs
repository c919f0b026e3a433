//! `CrowdGazeCharacter` (a `Spatial`): makes its parent `Skeleton` a character of the
//! crowd. Its global transform is the character's frame (its origin on the ground, its +Z
//! the way the character faces): keep it at the skeleton's origin unless the model faces
//! elsewhere. It joins a `CrowdGaze` node when it enters the tree and leaves it when it
//! exits (freed or removed).

use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Arc;

use crowdgaze_godot_adapter::{
    check_character, choose_crowd, message, CharacterCheck, CharacterValues, CrowdFound, NamedNode,
};
use gdnative::nativescript::init::property::{StringHint, Usage};
use gdnative::prelude::*;

use crate::convert::{
    boundary, eye_angle_hint, first_report, fraction_hint, head_turn_hint, in_editor,
    is_main_thread, model_hint, node_path, seconds_hint, unit_hint, xform, Data,
};
use crate::crowd_gaze::{skeleton_of, CrowdGaze, CHARACTER_GROUP, CROWD_GROUP};
use crate::props::Given;
use crate::skeleton::GodotSkeleton;
use crate::{checked_method, checked_property};

/// A character: its parent `Skeleton`'s bones are mapped to a gaze chain by name.
#[derive(NativeClass)]
#[inherit(Spatial)]
#[user_data(Data<CrowdGazeCharacter>)]
#[register_with(Self::register)]
pub struct CrowdGazeCharacter {
    /// The `CrowdGaze` node to join; empty: the nearest `CrowdGaze` ancestor, else the only
    /// `CrowdGaze` in the tree.
    crowd: NodePath,
    /// Bone map overrides, `Name=role` comma separated (roles: root, spine, neck, head,
    /// left_eye, right_eye, none), on top of the default map (Hips, Spine…, Neck, Head,
    /// LeftEye, RightEye and the usual variants).
    bone_map: GodotString,
    /// How interesting this character is to others (`I_E`, ≥ 0).
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
            presence: Presence::new(),
        }
    }

    /// The `crowd` path as set.
    pub fn crowd_path(&self) -> NodePath {
        self.crowd.new_ref()
    }

    /// Registers the node's properties (each value's type checked), the read-only
    /// `mapping_report` (shown multiline in the inspector, not saved: how the parent
    /// skeleton's bones map to the gaze chain), and its methods (each call's argument count
    /// checked).
    fn register(builder: &ClassBuilder<Self>) {
        // The exported properties, each with its value's type checked (see
        // [`props`](crate::props)).
        checked_property!(builder, CrowdGazeCharacter, crowd: NodePath);
        checked_property!(builder, CrowdGazeCharacter, bone_map: GodotString, then Self::settings_changed);
        checked_property!(builder, CrowdGazeCharacter, impact: f64 = 1.0, then Self::settings_changed);
        let d = CharacterValues::default();
        checked_property!(builder, CrowdGazeCharacter, active: bool = d.active, then Self::settings_changed);
        checked_property!(builder, CrowdGazeCharacter, influence: f64 = d.influence, hint unit_hint(),
            expects "a float from 0 to 1", then Self::settings_changed);
        checked_property!(builder, CrowdGazeCharacter, influence_fade_time: f64 = d.influence_fade_time,
            hint seconds_hint(), expects "a float (seconds)", then Self::settings_changed);
        checked_property!(builder, CrowdGazeCharacter, talking: bool = d.talking, then Self::settings_changed);
        checked_property!(builder, CrowdGazeCharacter, attention_fraction: f64 = d.attention_fraction,
            hint fraction_hint(), expects "a float from 0 to 1, or -1", then Self::settings_changed);
        checked_property!(builder, CrowdGazeCharacter, attention_model: i64 = d.attention_model,
            hint model_hint(), expects "an int (0 to 3)", then Self::settings_changed);
        checked_property!(builder, CrowdGazeCharacter, max_head_turn: f64 = d.max_head_turn,
            hint head_turn_hint(), expects "a float (degrees)", then Self::settings_changed);
        checked_property!(builder, CrowdGazeCharacter, max_eye_angle: f64 = d.max_eye_angle,
            hint eye_angle_hint(), expects "a float (degrees)", then Self::settings_changed);
        checked_property!(builder, CrowdGazeCharacter, eyelid_mesh: NodePath, then Self::settings_changed);
        checked_property!(builder, CrowdGazeCharacter, eyelid_shapes: GodotString, then Self::settings_changed);
        builder
            .add_property::<Given<String>>("mapping_report")
            .with_getter(|this: &Self, owner: TRef<Spatial>| {
                Given(Ok(boundary(
                    "CrowdGazeCharacter.get_mapping_report",
                    String::new(),
                    || this.check(&owner).report,
                )))
            })
            .with_shr_setter(
                |_this: &Self, owner: TRef<Spatial>, _value: Given<String>| {
                    boundary("CrowdGazeCharacter.set_mapping_report", (), || {
                        let error =
                            "mapping_report is read-only: it shows how the skeleton's bones \
                                 are mapped; set bone_map to change the mapping";
                        // The editor's text box may send edits: it shows the report again.
                        if !in_editor()
                            && first_report(owner.get_instance_id(), "set_mapping_report", &error)
                        {
                            let path = node_path(&owner);
                            let method = "CrowdGazeCharacter.set_mapping_report";
                            godot_error!(
                                "{}",
                                message(&path, method, &error, "nothing is changed")
                            );
                        }
                    })
                },
            )
            .with_hint(StringHint::Multiline)
            .with_usage(Usage::EDITOR)
            .done();
        // The exported methods, each with its argument count checked (see
        // [`methods`](mod@crate::methods)).
        checked_method!(builder, CrowdGazeCharacter, [], fn _enter_tree(&self, owner: TRef<Spatial>));
        checked_method!(builder, CrowdGazeCharacter, [], fn _ready(&self, owner: TRef<Spatial>));
        checked_method!(builder, CrowdGazeCharacter, [], fn _exit_tree(&self, owner: TRef<Spatial>));
        checked_method!(builder, CrowdGazeCharacter, ["what"], fn _notification(&self, _owner: TRef<Spatial>, what: Variant));
        checked_method!(builder, CrowdGazeCharacter, [], fn _get_configuration_warning(&self, owner: TRef<Spatial>) -> String);
        checked_method!(builder, CrowdGazeCharacter, [], fn get_crowd_node(&self, owner: TRef<Spatial>) -> Variant);
        checked_method!(builder, CrowdGazeCharacter, [], fn _crowdgaze_join(&self, owner: TRef<Spatial>));
    }

    /// The mapping report and configuration warnings of the node as it is now (see
    /// [`check_character`]).
    fn check(&self, owner: &Spatial) -> CharacterCheck {
        if !owner.is_inside_tree() {
            return CharacterCheck {
                report: "no gaze chain yet: the node is not in the scene tree".into(),
                warnings: Vec::new(),
            };
        }
        let crowd = crowd_found(owner, &self.crowd);
        check_character(
            skeleton_of(owner).map(GodotSkeleton).as_ref(),
            &xform(&owner.transform()),
            &self.bone_map.to_string(),
            self.impact,
            &crowd,
        )
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
        match owner.get_node_or_null(path.new_ref()).and_then(sane) {
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

/// What [`resolve_crowd`] finds, for the editor's warnings.
pub fn crowd_found(owner: &Spatial, path: &NodePath) -> CrowdFound {
    match resolve_crowd(owner, path) {
        Ok(Some(_)) => CrowdFound::Found,
        Ok(None) => CrowdFound::NoneYet,
        Err(error) => CrowdFound::Wrong(error),
    }
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
    fn _enter_tree(&self, owner: TRef<Spatial>) {
        boundary("CrowdGazeCharacter._enter_tree", (), || {
            owner.add_to_group(CHARACTER_GROUP, false);
            if in_editor() {
                owner.update_configuration_warning();
                return;
            }
            self.join(owner, false);
        })
    }

    fn _ready(&self, owner: TRef<Spatial>) {
        boundary("CrowdGazeCharacter._ready", (), || {
            if !in_editor() {
                self.join(owner, true)
            }
        })
    }

    fn _exit_tree(&self, owner: TRef<Spatial>) {
        boundary("CrowdGazeCharacter._exit_tree", (), || {
            owner.remove_from_group(CHARACTER_GROUP);
            self.presence.exited();
            leave(&owner);
        })
    }

    fn _notification(&self, _owner: TRef<Spatial>, what: Variant) {
        // Godot passes an integer; anything else a script passes is no notification.
        if what.try_to_i64() == Some(Object::NOTIFICATION_PREDELETE) {
            self.presence.gone();
        }
    }

    /// The editor's configuration warnings, one per line (see [`check_character`]).
    fn _get_configuration_warning(&self, owner: TRef<Spatial>) -> String {
        boundary(
            "CrowdGazeCharacter._get_configuration_warning",
            String::new(),
            || self.check(&owner).warnings.join("\n"),
        )
    }

    /// The `CrowdGaze` node this character joins (null if there is none).
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
            if in_editor() {
                owner.update_configuration_warning();
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
