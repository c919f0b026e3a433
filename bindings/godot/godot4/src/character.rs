//! `CrowdGazeCharacter` (a `SkeletonModifier3D`): makes its parent `Skeleton3D` a character
//! of the crowd, and writes the character's gaze in the skeleton's modifier pass, after the
//! animation. Its transform relative to the skeleton is the character's frame (origin on the
//! ground, +Z the way the character faces): identity unless the model faces elsewhere. It
//! joins a `CrowdGaze` node when it enters the tree and leaves it when it exits (freed or
//! removed).

use crowdgaze_godot_adapter::{
    check_character, choose_crowd, message, CharacterCheck, CharacterValues, CrowdFound, NamedNode,
};
use godot::classes::{ISkeletonModifier3D, Node3D, Os, SkeletonModifier3D};
use godot::prelude::*;

use crate::convert::{boundary, in_editor, strings, xform};
use crate::crowd_gaze::{skeleton_of, CrowdGaze, CHARACTER_GROUP, CROWD_GROUP};
use crate::skeleton::GodotSkeleton;

/// A character: its parent `Skeleton3D`'s bones are mapped to a gaze chain by name.
#[derive(GodotClass)]
#[class(tool, base = SkeletonModifier3D)]
pub struct CrowdGazeCharacter {
    /// The `CrowdGaze` node to join; empty: the nearest `CrowdGaze` ancestor, else the only
    /// `CrowdGaze` in the tree.
    #[export]
    crowd: NodePath,
    /// Bone map overrides, `Name=role` comma separated (roles: root, spine, neck, head,
    /// left_eye, right_eye, none), on top of the default map (Hips, Spine…, Neck, Head,
    /// LeftEye, RightEye and the usual variants).
    #[export]
    #[var(set = set_bone_map)]
    bone_map: GString,
    /// How interesting this character is to others (`I_E`, ≥ 0).
    #[export]
    #[var(set = set_impact)]
    impact: f64,
    /// How the parent skeleton's bones map to the gaze chain (read-only, not saved): the
    /// library's mapping report, or why there is no chain.
    #[var(get = get_mapping_report, no_set, hint = MULTILINE_TEXT, usage_flags = [EDITOR, READ_ONLY])]
    #[allow(
        dead_code,
        reason = "the property's field: its getter computes the report"
    )]
    mapping_report: GString,
    /// Whether the gaze is applied: false fades the influence to 0 over
    /// `influence_fade_time`, then leaves the bones to the animation (attention keeps
    /// running, so turning it back on is smooth).
    #[export]
    #[var(set = set_active)]
    active: bool,
    /// How much of the gaze the bones take, 0 (the animation alone) to 1 (the gaze); the
    /// `CrowdGaze` node's `influence` multiplies it.
    #[export(range = (0.0, 1.0, 0.01))]
    #[var(set = set_influence)]
    influence: f64,
    /// Seconds a change of `active` or `influence` takes to show fully (0: at once).
    #[export(range = (0.0, 10.0, 0.01, or_greater))]
    #[var(set = set_influence_fade_time)]
    influence_fade_time: f64,
    /// True while the character talks: others in its conversation look at it more.
    #[export]
    #[var(set = set_talking)]
    talking: bool,
    /// The share of the time the character attends to something, 0 to 1; -1: the crowd's
    /// draw (from `attention_fraction_min` to `attention_fraction_max`).
    #[export(range = (-1.0, 1.0, 0.01))]
    #[var(set = set_attention_fraction)]
    attention_fraction: f64,
    /// The model deciding where the character looks: 0 the crowd model (Grillon &
    /// Thalmann), 1 saliency (Kokkinara et al.), 2 the baseline, 3 the street model
    /// (walkers as measured with eye trackers).
    #[export(enum = (Crowd = 0, Saliency = 1, Baseline = 2, Street = 3))]
    #[var(set = set_attention_model)]
    attention_model: i64,
    /// Degrees the neck and head may turn together (yaw; the library's chain has 70). The
    /// skeleton is mapped again when it changes.
    #[export(range = (0.0, 180.0, 1.0))]
    #[var(set = set_max_head_turn)]
    max_head_turn: f64,
    /// Degrees each eye may turn from straight ahead (the library's chain has 35).
    #[export(range = (0.0, 90.0, 1.0))]
    #[var(set = set_max_eye_angle)]
    max_eye_angle: f64,
    /// A `MeshInstance3D` whose blink blend shapes take the eyelids' closure each frame
    /// (empty: none). Its shapes are found by name (ARKit `eyeBlinkLeft`/`eyeBlinkRight`,
    /// VRM `Blink_L`/`Blink_R`/`Blink`, `blink`) unless `eyelid_shapes` names them.
    #[export]
    #[var(set = set_eyelid_mesh)]
    eyelid_mesh: NodePath,
    /// The blink blend shapes of `eyelid_mesh`: empty (found by name), one name for both
    /// eyes, or `left,right`.
    #[export]
    #[var(set = set_eyelid_shapes)]
    eyelid_shapes: GString,
    /// The `CrowdGaze` node joined (its instance id), for the per-frame write.
    joined: Option<InstanceId>,
    base: Base<SkeletonModifier3D>,
}

/// What a `CrowdGaze` registers a character with: its values as given, and its eyelid
/// mesh and shapes.
pub struct CharacterInputs {
    /// The adapter's values.
    pub values: CharacterValues,
    /// `eyelid_mesh`, relative to the character node.
    pub eyelid_mesh: NodePath,
    /// `eyelid_shapes`.
    pub eyelid_shapes: String,
}

/// The `CrowdGaze` node a character or target joins (see [`choose_crowd`]): the one its
/// `crowd` path names, else its nearest `CrowdGaze` ancestor, else the only one in the
/// tree; `Ok(None)` if there is none yet. Errors say what to set.
pub fn resolve_crowd(node: &Gd<Node>, path: &NodePath) -> Result<Option<Gd<CrowdGaze>>, String> {
    if !node.is_inside_tree() {
        return Ok(None);
    }
    let mut candidates: Vec<Gd<CrowdGaze>> = Vec::new();
    let named = if path.is_empty() {
        NamedNode::Unset
    } else {
        match node.get_node_or_null(path) {
            None => NamedNode::Missing,
            Some(found) => match found.clone().try_cast::<CrowdGaze>() {
                Ok(crowd) => {
                    candidates.push(crowd);
                    NamedNode::Crowd(0)
                }
                Err(other) => {
                    NamedNode::NotACrowd(format!("{} ({})", other.get_class(), other.get_path()))
                }
            },
        }
    };
    let mut ancestor = None;
    let mut parent = node.get_parent();
    while let Some(current) = parent {
        match current.clone().try_cast::<CrowdGaze>() {
            Ok(crowd) => {
                ancestor = Some(candidates.len());
                candidates.push(crowd);
                break;
            }
            Err(current) => parent = current.get_parent(),
        }
    }
    let mut in_tree = Vec::new();
    if let Some(tree) = node.get_tree_or_null() {
        for found in tree.get_nodes_in_group(CROWD_GROUP).iter_shared() {
            if let Ok(crowd) = found.try_cast::<CrowdGaze>() {
                in_tree.push(candidates.len());
                candidates.push(crowd);
            }
        }
    }
    let text = path.to_string();
    Ok(choose_crowd(&text, named, ancestor, &in_tree)?.map(|k| candidates[k].clone()))
}

/// What [`resolve_crowd`] finds, for the editor's warnings.
pub fn crowd_found(node: &Gd<Node>, path: &NodePath) -> CrowdFound {
    match resolve_crowd(node, path) {
        Ok(Some(_)) => CrowdFound::Found,
        Ok(None) => CrowdFound::NoneYet,
        Err(error) => CrowdFound::Wrong(error),
    }
}

/// True on Godot's main thread.
pub fn is_main_thread() -> bool {
    let os = Os::singleton();
    os.get_thread_caller_id() == os.get_main_thread_id()
}

/// Takes a node out of every crowd (it left the tree).
pub fn leave(node: &Gd<Node>) {
    let key = node.instance_id().to_i64();
    if let Some(tree) = node.get_tree_or_null() {
        for found in tree.get_nodes_in_group(CROWD_GROUP).iter_shared() {
            if let Ok(mut crowd) = found.try_cast::<CrowdGaze>() {
                crowd.bind_mut().unregister(key);
            }
        }
    }
}

#[godot_api]
impl ISkeletonModifier3D for CrowdGazeCharacter {
    fn init(base: Base<SkeletonModifier3D>) -> Self {
        let defaults = CharacterValues::default();
        CrowdGazeCharacter {
            crowd: NodePath::default(),
            bone_map: GString::new(),
            impact: defaults.impact,
            mapping_report: GString::new(),
            active: defaults.active,
            influence: defaults.influence,
            influence_fade_time: defaults.influence_fade_time,
            talking: defaults.talking,
            attention_fraction: defaults.attention_fraction,
            attention_model: defaults.attention_model,
            max_head_turn: defaults.max_head_turn,
            max_eye_angle: defaults.max_eye_angle,
            eyelid_mesh: NodePath::default(),
            eyelid_shapes: GString::new(),
            joined: None,
            base,
        }
    }

    fn enter_tree(&mut self) {
        boundary("CrowdGazeCharacter._enter_tree", (), || {
            self.base_mut().add_to_group(CHARACTER_GROUP);
            if in_editor() {
                self.base_mut().update_configuration_warnings();
                return;
            }
            self.join(false);
        })
    }

    fn ready(&mut self) {
        boundary("CrowdGazeCharacter._ready", (), || {
            if !in_editor() {
                self.join(true)
            }
        })
    }

    fn exit_tree(&mut self) {
        boundary("CrowdGazeCharacter._exit_tree", (), || {
            self.base_mut().remove_from_group(CHARACTER_GROUP);
            let node = self.to_gd().upcast::<Node>();
            self.joined = None;
            leave(&node);
        })
    }

    fn get_configuration_warnings(&self) -> PackedStringArray {
        boundary(
            "CrowdGazeCharacter._get_configuration_warnings",
            PackedStringArray::new(),
            || strings(&self.check().warnings),
        )
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
        resolve_crowd(&node, &self.crowd)
            .ok()
            .flatten()
            .map_or_else(Variant::nil, |crowd| crowd.to_variant())
    }

    /// The mapping report (see [`check_character`]).
    #[func]
    fn get_mapping_report(&self) -> GString {
        boundary(
            "CrowdGazeCharacter.get_mapping_report",
            GString::new(),
            || GString::from(self.check().report.as_str()),
        )
    }

    /// Sets `bone_map`; a character in a crowd is mapped again at once.
    #[func]
    fn set_bone_map(&mut self, bone_map: GString) {
        self.bone_map = bone_map;
        self.settings_changed();
    }

    /// Sets `impact`; a character in a crowd takes it at once.
    #[func]
    fn set_impact(&mut self, impact: f64) {
        self.impact = impact;
        self.settings_changed();
    }

    /// Sets `active`; the influence fades to it.
    #[func]
    fn set_active(&mut self, active: bool) {
        self.active = active;
        self.settings_changed();
    }

    /// Sets `influence`; the influence fades to it.
    #[func]
    fn set_influence(&mut self, influence: f64) {
        self.influence = influence;
        self.settings_changed();
    }

    /// Sets `influence_fade_time`.
    #[func]
    fn set_influence_fade_time(&mut self, seconds: f64) {
        self.influence_fade_time = seconds;
        self.settings_changed();
    }

    /// Sets `talking`; pushed to the crowd from the next frame.
    #[func]
    fn set_talking(&mut self, talking: bool) {
        self.talking = talking;
        self.settings_changed();
    }

    /// Sets `attention_fraction`.
    #[func]
    fn set_attention_fraction(&mut self, fraction: f64) {
        self.attention_fraction = fraction;
        self.settings_changed();
    }

    /// Sets `attention_model`.
    #[func]
    fn set_attention_model(&mut self, model: i64) {
        self.attention_model = model;
        self.settings_changed();
    }

    /// Sets `max_head_turn`; the skeleton is mapped again.
    #[func]
    fn set_max_head_turn(&mut self, degrees: f64) {
        self.max_head_turn = degrees;
        self.settings_changed();
    }

    /// Sets `max_eye_angle`; the skeleton is mapped again.
    #[func]
    fn set_max_eye_angle(&mut self, degrees: f64) {
        self.max_eye_angle = degrees;
        self.settings_changed();
    }

    /// Sets `eyelid_mesh`; its blink shapes are found again.
    #[func]
    fn set_eyelid_mesh(&mut self, path: NodePath) {
        self.eyelid_mesh = path;
        self.settings_changed();
    }

    /// Sets `eyelid_shapes`; the mesh's blink shapes are found again.
    #[func]
    fn set_eyelid_shapes(&mut self, shapes: GString) {
        self.eyelid_shapes = shapes;
        self.settings_changed();
    }

    /// Joins the crowd on the main thread (called deferred when the node entered the tree
    /// on another thread).
    #[func]
    fn _crowdgaze_join(&mut self) {
        boundary("CrowdGazeCharacter._crowdgaze_join", (), || {
            if self.base().is_inside_tree() {
                self.join(true);
            }
        })
    }
}

impl CrowdGazeCharacter {
    /// The mapping report and configuration warnings of the node as it is now (see
    /// [`check_character`]).
    fn check(&self) -> CharacterCheck {
        let node = self.to_gd().upcast::<Node3D>();
        if !node.is_inside_tree() {
            return CharacterCheck {
                report: "no gaze chain yet: the node is not in the scene tree".into(),
                warnings: Vec::new(),
            };
        }
        let crowd = crowd_found(&node.clone().upcast::<Node>(), &self.crowd);
        check_character(
            skeleton_of(&node).map(GodotSkeleton).as_ref(),
            &xform(&node.get_transform()),
            &self.bone_map.to_string(),
            self.impact,
            &crowd,
        )
    }

    /// Records the `CrowdGaze` node that registered the character (it writes through it).
    pub fn set_joined(&mut self, crowd: InstanceId) {
        self.joined = Some(crowd);
    }

    /// The `crowd` path as set.
    pub fn crowd_path(&self) -> NodePath {
        self.crowd.clone()
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
            eyelid_mesh: self.eyelid_mesh.clone(),
            eyelid_shapes: self.eyelid_shapes.to_string(),
        }
    }

    /// Joins its crowd; on another thread than the main one, deferred to it. With `report`
    /// (in `_ready`), a crowd path or tree that names no crowd is reported.
    fn join(&mut self, report: bool) {
        if !is_main_thread() {
            self.base_mut().call_deferred("_crowdgaze_join", &[]);
            return;
        }
        let node = self.to_gd();
        let path = node.clone().upcast::<Node>().get_path().to_string();
        match resolve_crowd(&node.clone().upcast::<Node>(), &self.crowd) {
            Ok(Some(mut crowd)) => {
                let inputs = self.settings();
                self.joined = Some(crowd.instance_id());
                crowd
                    .bind_mut()
                    .register_character(node.upcast::<Node3D>(), inputs);
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
    fn settings_changed(&mut self) {
        boundary("CrowdGazeCharacter.settings_changed", (), || {
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
                let inputs = self.settings();
                crowd
                    .bind_mut()
                    .update_character(node.upcast::<Node3D>(), inputs);
            }
        })
    }
}
