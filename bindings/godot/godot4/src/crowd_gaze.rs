//! `CrowdGaze` (a `Node3D`): owns the crowd, takes its settings from the inspector, and
//! once per frame reads every character and target and steps; each character's
//! `SkeletonModifier3D` then writes its gaze in its skeleton's modifier pass. It emits
//! `interest_changed(character, target)` when a character's eyes move to another target
//! (`null` for none; the active camera when it looks at the player).

use std::collections::HashSet;
use std::sync::Arc;
use std::time::Instant;

use crowdgaze_godot_adapter::crowdgaze::crowd::{ExplicitTarget, TargetPriority};
use crowdgaze_godot_adapter::crowdgaze::ik::MAX_CHAIN_JOINTS;
use crowdgaze_godot_adapter::{
    check_crowd, claim_skeleton, message, CharacterSettings, CrowdSettings, EntityNode,
    PoseConvention, Reports, SceneCrowd, SkeletonClaim,
};
use godot::classes::{Camera3D, INode3D, Node3D, Skeleton3D};
use godot::prelude::*;

use crate::character::resolve_crowd;
use crate::convert::{boundary, in_editor, quaternion, strings, vec3, vector, xform};
use crate::skeleton::GodotSkeleton;

/// The addon's groups (shared with the other front end).
pub use crowdgaze_godot_adapter::membership::{CHARACTER_GROUP, CROWD_GROUP, TARGET_GROUP};

/// A registered node: its instance id, and its skeleton's for a character (0 for a target).
#[derive(Debug, Clone)]
pub struct Handle {
    node: i64,
    skeleton: i64,
    /// A character's hold on its skeleton (released when the handle goes).
    _claim: Option<Arc<SkeletonClaim>>,
}

/// True if `node`, whose `crowd` path is `path`, joins the crowd `crowd`.
fn joins(crowd: InstanceId, node: &Gd<Node>, path: &NodePath) -> bool {
    matches!(resolve_crowd(node, path), Ok(Some(found)) if found.instance_id() == crowd)
}

/// A character node's parent `Skeleton3D`, if it is one.
pub fn skeleton_of(node: &Gd<Node3D>) -> Option<Gd<Skeleton3D>> {
    node.get_parent()
        .and_then(|parent| parent.try_cast::<Skeleton3D>().ok())
}

/// The live object of an instance id, if it is still there and of class `T`.
fn live<T: GodotClass + Inherits<Object>>(id: i64) -> Option<Gd<T>> {
    if id == 0 {
        return None;
    }
    Gd::<T>::try_from_instance_id(InstanceId::from_i64(id)).ok()
}

/// A node's path, for messages.
fn path_of<T: Inherits<Node>>(node: &Gd<T>) -> String {
    node.clone().upcast::<Node>().get_path().to_string()
}

/// The instance id of the object in a variant, if any.
fn instance_id(node: &Variant) -> Option<i64> {
    let object = node.try_to::<Gd<Object>>().ok()?;
    Some(object.instance_id().to_i64())
}

/// The node that owns a crowd. Its exported fields are the crowd's settings, read when the
/// crowd is created (when the node enters the tree); `camera_is_viewer` and
/// `viewer_impact` are read every frame.
#[derive(GodotClass)]
#[class(tool, base = Node3D)]
pub struct CrowdGaze {
    /// Seed of every random choice: the same scene and seed give the same gaze.
    #[export]
    seed: i64,
    /// Most characters the crowd holds.
    #[export]
    max_characters: i64,
    /// Most targets (`GazeTarget` nodes) the crowd holds.
    #[export]
    max_targets: i64,
    /// How far characters notice others (`d_m`, metres).
    #[export]
    max_distance: f64,
    /// The characters' field of view, degrees.
    #[export]
    field_of_view: f64,
    /// Smallest share of the time a character spends attending (0 to 1).
    #[export]
    attention_fraction_min: f64,
    /// Largest share of the time a character spends attending (0 to 1).
    #[export]
    attention_fraction_max: f64,
    /// Threads a step uses (1: the main thread only; 0: one per core).
    #[export]
    threads: i64,
    /// Level of detail: each character's attention is updated every `attention_period`
    /// frames (1 to 64, staggered; gaze IK runs every frame).
    #[export]
    attention_period: i64,
    /// Level of detail by distance: beyond `lod_distance` metres from the camera, attention
    /// is updated every `far_attention_period` frames (0: off).
    #[export]
    lod_distance: f64,
    /// See `lod_distance` (1 to 64).
    #[export]
    far_attention_period: i64,
    /// Make the active camera an entity the characters may look at.
    #[export]
    camera_is_viewer: bool,
    /// How interesting the camera is (`I_E`, ≥ 0).
    #[export]
    viewer_impact: f64,
    scene: Option<SceneCrowd<Handle>>,
    /// Nodes refused (reported once), by instance id.
    refused: HashSet<i64>,
    /// What was reported: each node's error once per cause.
    reports: Reports,
    /// True once creating the crowd failed (reported once).
    config_failed: bool,
    /// The last frame's cost, microseconds: reading the scene, stepping.
    frame_usec: [f64; 2],
    base: Base<Node3D>,
}

#[godot_api]
impl INode3D for CrowdGaze {
    fn init(base: Base<Node3D>) -> Self {
        // The inspector's defaults, kept once in the adapter.
        let defaults = CrowdSettings::default();
        CrowdGaze {
            seed: defaults.seed,
            max_characters: defaults.max_characters,
            max_targets: defaults.max_targets,
            max_distance: defaults.max_distance,
            field_of_view: defaults.field_of_view,
            attention_fraction_min: defaults.attention_fraction_min,
            attention_fraction_max: defaults.attention_fraction_max,
            threads: defaults.threads,
            attention_period: defaults.attention_period,
            lod_distance: defaults.lod_distance,
            far_attention_period: defaults.far_attention_period,
            camera_is_viewer: true,
            viewer_impact: 3.0,
            scene: None,
            refused: HashSet::new(),
            reports: Reports::new(),
            config_failed: false,
            frame_usec: [0.0; 2],
            base,
        }
    }

    fn enter_tree(&mut self) {
        boundary("CrowdGaze._enter_tree", (), || {
            self.base_mut().add_to_group(CROWD_GROUP);
            if in_editor() {
                // Found by the characters' warnings; nothing runs in the editor.
                return;
            }
            // After the scripts that animate in _process (AnimationMixers run before any).
            if self.base().get_process_priority() == 0 {
                self.base_mut().set_process_priority(100);
            }
            self.scene();
            self.adopt();
        })
    }

    fn ready(&mut self) {
        boundary("CrowdGaze._ready", (), || {
            if in_editor() {
                self.base_mut().set_process(false);
            } else {
                self.adopt()
            }
        })
    }

    fn exit_tree(&mut self) {
        boundary("CrowdGaze._exit_tree", (), || {
            self.base_mut().remove_from_group(CROWD_GROUP);
            self.scene = None;
            self.refused.clear();
            self.reports.clear();
            self.config_failed = false;
        })
    }

    fn process(&mut self, delta: f64) {
        boundary("CrowdGaze._process", (), || {
            if !in_editor() {
                self.frame(delta)
            }
        })
    }

    fn get_configuration_warnings(&self) -> PackedStringArray {
        boundary(
            "CrowdGaze._get_configuration_warnings",
            PackedStringArray::new(),
            || strings(&check_crowd(&self.settings())),
        )
    }
}

impl CrowdGaze {
    /// The crowd's settings from the exported fields, as given.
    fn settings(&self) -> CrowdSettings {
        CrowdSettings {
            seed: self.seed,
            max_characters: self.max_characters,
            max_targets: self.max_targets,
            max_distance: self.max_distance,
            field_of_view: self.field_of_view,
            attention_fraction_min: self.attention_fraction_min,
            attention_fraction_max: self.attention_fraction_max,
            threads: self.threads,
            attention_period: self.attention_period,
            lod_distance: self.lod_distance,
            far_attention_period: self.far_attention_period,
        }
    }

    /// The crowd, created from the settings the first time.
    fn scene(&mut self) -> Option<&mut SceneCrowd<Handle>> {
        if self.scene.is_none() && !self.config_failed {
            let created = self
                .settings()
                .config()
                .and_then(|config| SceneCrowd::new(config, PoseConvention::PoseIsLocal));
            match created {
                Ok(scene) => self.scene = Some(scene),
                Err(error) => {
                    self.config_failed = true;
                    godot_error!(
                        "{}",
                        message(
                            &path_of(&self.to_gd()),
                            "CrowdGaze._enter_tree",
                            &error,
                            "no crowd is created"
                        )
                    );
                }
            }
        }
        self.scene.as_mut()
    }

    /// The active camera, when it is the viewer.
    fn camera(&self) -> Option<Gd<Camera3D>> {
        if !self.camera_is_viewer {
            return None;
        }
        self.base().get_viewport()?.get_camera_3d()
    }

    /// Adds a `CrowdGazeCharacter` node (a child of its `Skeleton3D`) to the crowd, once; a
    /// skeleton that cannot be mapped is reported once and left out.
    pub fn register_character(&mut self, node: Gd<Node3D>, bone_map: &str, impact: f64) {
        let key = node.instance_id().to_i64();
        if self.refused.contains(&key) {
            return;
        }
        let Some(scene) = self.scene() else {
            return;
        };
        if scene.entity_of(key).is_some() {
            return;
        }
        let skeleton = skeleton_of(&node);
        let path = path_of(&node);
        let result = match skeleton {
            None => Err(
                "a CrowdGazeCharacter must be a child of a Skeleton3D: move it under one"
                    .to_string(),
            ),
            Some(skeleton) => {
                let skeleton_key = skeleton.instance_id().to_i64();
                claim_skeleton(skeleton_key, key, &path).and_then(|claim| {
                    CharacterSettings::new(bone_map, impact)
                        .and_then(|settings| {
                            let handle = Handle {
                                node: key,
                                skeleton: skeleton_key,
                                _claim: Some(Arc::new(claim)),
                            };
                            scene.add_character(
                                key,
                                handle,
                                &GodotSkeleton(skeleton),
                                &xform(&node.get_transform()),
                                &settings,
                            )
                        })
                        .map(|_| ())
                        .map_err(|error| error.to_string())
                })
            }
        };
        if let Err(error) = result {
            self.refused.insert(key);
            godot_error!(
                "{}",
                message(
                    &path,
                    "CrowdGazeCharacter._enter_tree",
                    &error,
                    "the character is left out of the crowd"
                )
            );
        }
    }

    /// A registered character's `bone_map` or `impact` changed: the crowd takes them (a
    /// character refused before tries to join again).
    pub fn update_character(&mut self, node: Gd<Node3D>, bone_map: &str, impact: f64) {
        let key = node.instance_id().to_i64();
        let registered = self.scene.as_ref().and_then(|s| s.entity_of(key)).is_some();
        if !registered {
            self.refused.remove(&key);
            self.register_character(node, bone_map, impact);
            return;
        }
        let (Some(scene), Some(skeleton)) = (self.scene.as_mut(), skeleton_of(&node)) else {
            return;
        };
        let result = CharacterSettings::new(bone_map, impact).and_then(|settings| {
            scene.update_character(
                key,
                &GodotSkeleton(skeleton),
                &xform(&node.get_transform()),
                &settings,
            )
        });
        if let Err(error) = result {
            if self.reports.first(key, "settings", &error) {
                godot_error!(
                    "{}",
                    message(
                        &path_of(&node),
                        "CrowdGazeCharacter.set_bone_map/set_impact",
                        &error,
                        "the character keeps its previous settings"
                    )
                );
            }
        }
    }

    /// A registered target's `look_at_height` or `impact` changed.
    pub fn update_target(&mut self, node: Gd<Node3D>, look_at_height: f64, impact: f64) {
        let key = node.instance_id().to_i64();
        let registered = self.scene.as_ref().and_then(|s| s.entity_of(key)).is_some();
        if !registered {
            self.refused.remove(&key);
            self.register_target(node, look_at_height, impact);
            return;
        }
        let Some(scene) = self.scene.as_mut() else {
            return;
        };
        if let Err(error) = scene.update_target(key, look_at_height as f32, impact as f32) {
            if self.reports.first(key, "settings", &error) {
                godot_error!(
                    "{}",
                    message(
                        &path_of(&node),
                        "GazeTarget.set_look_at_height/set_impact",
                        &error,
                        "the target keeps its previous settings"
                    )
                );
            }
        }
    }

    /// Adds a `GazeTarget` node to the crowd, once.
    pub fn register_target(&mut self, node: Gd<Node3D>, look_at_height: f64, impact: f64) {
        let key = node.instance_id().to_i64();
        if self.refused.contains(&key) {
            return;
        }
        let Some(scene) = self.scene() else {
            return;
        };
        if scene.entity_of(key).is_some() {
            return;
        }
        let handle = Handle {
            node: key,
            skeleton: 0,
            _claim: None,
        };
        let placed = xform(&node.get_global_transform());
        if let Err(error) =
            scene.add_target(key, handle, &placed, look_at_height as f32, impact as f32)
        {
            self.refused.insert(key);
            godot_error!(
                "{}",
                message(
                    &path_of(&node),
                    "GazeTarget._enter_tree",
                    &error,
                    "the target is left out of the crowd"
                )
            );
        }
    }

    /// Removes a node from the crowd (it left the tree).
    pub fn unregister(&mut self, key: i64) {
        self.refused.remove(&key);
        self.reports.forget(key);
        if let Some(scene) = self.scene.as_mut() {
            scene.remove(key);
        }
    }

    /// Writes a character's gaze to its skeleton (its modifier pass, after the animation).
    pub fn write_character(&mut self, key: i64, skeleton: Gd<Skeleton3D>) {
        let Some(scene) = self.scene.as_mut() else {
            return;
        };
        if let Some(slot) = scene.character_slot(key) {
            if let Err(error) = scene.write_character(slot, &mut GodotSkeleton(skeleton)) {
                if self.reports.first(key, "write", &error) {
                    let path = path_of(&self.to_gd());
                    godot_error!(
                        "{}",
                        message(
                            &path,
                            "CrowdGazeCharacter._process_modification",
                            &error,
                            ""
                        )
                    );
                }
            }
        }
    }

    /// Registers the characters and targets already in the tree.
    fn adopt(&mut self) {
        if !self.base().is_inside_tree() {
            return;
        }
        let tree = self.base().get_tree();
        for node in tree.get_nodes_in_group(CHARACTER_GROUP).iter_shared() {
            if let Ok(mut character) = node.try_cast::<crate::character::CrowdGazeCharacter>() {
                let (bone_map, impact) = character.bind().settings();
                let path = character.bind().crowd_path();
                let me = self.to_gd().instance_id();
                if joins(me, &character.clone().upcast::<Node>(), &path) {
                    character.bind_mut().set_joined(me);
                    self.register_character(character.upcast(), &bone_map, impact);
                }
            }
        }
        for node in tree.get_nodes_in_group(TARGET_GROUP).iter_shared() {
            if let Ok(target) = node.try_cast::<crate::target::GazeTarget>() {
                let (height, impact) = target.bind().settings();
                let path = target.bind().crowd_path();
                if joins(
                    self.to_gd().instance_id(),
                    &target.clone().upcast::<Node>(),
                    &path,
                ) {
                    self.register_target(target.upcast(), height, impact);
                }
            }
        }
    }

    /// One frame: read, step, report. The characters' modifiers write afterwards.
    fn frame(&mut self, delta: f64) {
        let start = Instant::now();
        let camera = self.camera();
        let viewer_impact = self.viewer_impact as f32;
        let me = self.to_gd();
        let crowd_key = me.instance_id().to_i64();
        let reports = &mut self.reports;
        let Some(scene) = self.scene.as_mut() else {
            return;
        };
        let mut slot = 0;
        while slot < scene.character_count() {
            let Some(handle) = scene.character_handle(slot).cloned() else {
                break;
            };
            match (
                live::<Node3D>(handle.node),
                live::<Skeleton3D>(handle.skeleton),
            ) {
                (Some(node), Some(skeleton)) => {
                    let placed = xform(&node.get_transform());
                    if let Err(error) =
                        scene.read_character(slot, &GodotSkeleton(skeleton), &placed)
                    {
                        if reports.first(handle.node, "read", &error) {
                            godot_error!(
                                "{}",
                                message(
                                    &path_of(&node),
                                    "CrowdGaze._process",
                                    &error,
                                    "the character keeps its last state and its bones are \
                                     left alone until this is fixed"
                                )
                            );
                        }
                    }
                    slot += 1;
                }
                _ => {
                    scene.remove(handle.node);
                    reports.forget(handle.node);
                }
            }
        }
        let mut slot = 0;
        while slot < scene.target_count() {
            let Some(handle) = scene.target_handle(slot).cloned() else {
                break;
            };
            match live::<Node3D>(handle.node) {
                Some(node) => {
                    if let Err(error) =
                        scene.read_target(slot, &xform(&node.get_global_transform()))
                    {
                        if reports.first(handle.node, "read", &error) {
                            godot_error!(
                                "{}",
                                message(
                                    &path_of(&node),
                                    "CrowdGaze._process",
                                    &error,
                                    "the target stays where it was"
                                )
                            );
                        }
                    }
                    slot += 1;
                }
                None => {
                    scene.remove(handle.node);
                }
            }
        }
        let viewer = camera
            .as_ref()
            .map(|camera| vec3(camera.get_global_transform().origin));
        if let Err(error) = scene.set_viewer(viewer, viewer_impact) {
            if reports.first(crowd_key, "viewer", &error) {
                let error = format!("the camera as the viewer: {error}");
                godot_error!(
                    "{}",
                    message(&path_of(&me), "CrowdGaze._process", &error, "")
                );
            }
        }
        let read = start.elapsed();
        if let Err(error) = scene.step(delta as f32) {
            if reports.first(crowd_key, "step", &error) {
                godot_error!(
                    "{}",
                    message(
                        &path_of(&me),
                        "CrowdGaze._process",
                        &error,
                        "the frame is skipped"
                    )
                );
            }
            return;
        }
        self.frame_usec = [
            read.as_secs_f64() * 1e6,
            (start.elapsed() - read).as_secs_f64() * 1e6,
        ];
        // Signals go out at the end of the frame, when no method of this node is running.
        let mut emits = Vec::new();
        for &(slot, target) in scene.interest_changes() {
            let Some(character) = scene
                .character_handle(slot)
                .and_then(|h| live::<Node>(h.node))
            else {
                continue;
            };
            let target = match scene.node_of(target) {
                EntityNode::Character(handle) | EntityNode::Target(handle) => {
                    live::<Node>(handle.node).map(|node| node.to_variant())
                }
                EntityNode::Viewer => camera.as_ref().map(|camera| camera.to_variant()),
                EntityNode::None => None,
            };
            emits.push([
                "interest_changed".to_variant(),
                character.to_variant(),
                target.unwrap_or_default(),
            ]);
        }
        for arguments in emits {
            self.base_mut().call_deferred("emit_signal", &arguments);
        }
    }

    /// The character slot of a node variant.
    fn slot_of(&self, character: &Variant) -> Option<usize> {
        self.scene.as_ref()?.character_slot(instance_id(character)?)
    }
}

#[godot_api]
impl CrowdGaze {
    /// A character's eyes moved to another target: a character or target node, the camera,
    /// or null.
    #[signal]
    fn interest_changed(character: Gd<Node>, target: Variant);

    /// Number of characters in the crowd.
    #[func]
    fn get_character_count(&self) -> i64 {
        boundary("CrowdGaze.get_character_count", 0, || {
            self.scene
                .as_ref()
                .map_or(0, |s| s.character_count() as i64)
        })
    }

    /// Number of targets in the crowd.
    #[func]
    fn get_target_count(&self) -> i64 {
        boundary("CrowdGaze.get_target_count", 0, || {
            self.scene.as_ref().map_or(0, |s| s.target_count() as i64)
        })
    }

    /// What a character's eyes look at: a character or target node, the camera, or null.
    #[func]
    fn get_gaze_target(&self, character: Variant) -> Variant {
        boundary("CrowdGaze.get_gaze_target", Variant::nil(), || {
            let (Some(scene), Some(slot)) = (self.scene.as_ref(), self.slot_of(&character)) else {
                return Variant::nil();
            };
            let Ok(gaze) = scene.gaze(slot) else {
                return Variant::nil();
            };
            match scene.node_of(gaze.target) {
                EntityNode::Character(handle) | EntityNode::Target(handle) => {
                    live::<Node>(handle.node).map_or_else(Variant::nil, |node| node.to_variant())
                }
                EntityNode::Viewer => self
                    .camera()
                    .map_or_else(Variant::nil, |camera| camera.to_variant()),
                EntityNode::None => Variant::nil(),
            }
        })
    }

    /// The point a character's eyes are sent to (metres, world).
    #[func]
    fn get_gaze_point(&self, character: Variant) -> Vector3 {
        boundary("CrowdGaze.get_gaze_point", Vector3::ZERO, || {
            self.slot_of(&character)
                .and_then(|slot| self.scene.as_ref()?.gaze(slot).ok())
                .map_or(Vector3::ZERO, |gaze| vector(gaze.target_position))
        })
    }

    /// True if a character attends to something.
    #[func]
    fn is_attending(&self, character: Variant) -> bool {
        boundary("CrowdGaze.is_attending", false, || {
            self.slot_of(&character)
                .and_then(|slot| self.scene.as_ref()?.gaze(slot).ok())
                .is_some_and(|gaze| gaze.attending)
        })
    }

    /// True once a character's gaze has arrived on its target and follows it.
    #[func]
    fn is_holding(&self, character: Variant) -> bool {
        boundary("CrowdGaze.is_holding", false, || {
            self.slot_of(&character)
                .and_then(|slot| self.scene.as_ref()?.is_holding(slot).ok())
                .unwrap_or(false)
        })
    }

    /// The bones of a character's gaze chain, bottom to top (spine, neck, head, eyes).
    #[func]
    fn get_chain_bones(&self, character: Variant) -> PackedInt32Array {
        boundary("CrowdGaze.get_chain_bones", PackedInt32Array::new(), || {
            let mut array = PackedInt32Array::new();
            if let Some(bones) = self
                .slot_of(&character)
                .and_then(|slot| self.scene.as_ref()?.chain_bones(slot).ok())
            {
                for &bone in bones {
                    array.push(bone as i32);
                }
            }
            array
        })
    }

    /// The library's final rotation of each chain joint (`base * delta`): local to its
    /// parent bone, the first one relative to the character node's frame.
    #[func]
    fn get_joint_rotations(&self, character: Variant) -> Array<Quaternion> {
        boundary("CrowdGaze.get_joint_rotations", Array::new(), || {
            let mut array = Array::new();
            let mut joints = [glam::Quat::IDENTITY; MAX_CHAIN_JOINTS];
            if let Some(count) = self
                .slot_of(&character)
                .and_then(|slot| self.scene.as_ref()?.joint_rotations(slot, &mut joints).ok())
            {
                for joint in &joints[..count] {
                    array.push(quaternion(*joint));
                }
            }
            array
        })
    }

    /// How high above a character's node its eyes are at rest (where others look), metres.
    #[func]
    fn get_look_at_height(&self, character: Variant) -> f64 {
        boundary("CrowdGaze.get_look_at_height", 0.0, || {
            self.slot_of(&character)
                .and_then(|slot| self.scene.as_ref()?.look_at_height(slot).ok())
                .map_or(0.0, f64::from)
        })
    }

    /// Makes a character look at `target` (a registered character or target node, the
    /// camera, or a `Vector3` point) whatever its attention says, until
    /// `clear_gaze_target`. Returns false (with an error) if either is unknown.
    #[func]
    fn set_gaze_target(&mut self, character: Variant, target: Variant) -> bool {
        boundary("CrowdGaze.set_gaze_target", false, || {
            let slot = self.slot_of(&character);
            let camera = self.camera().map(|c| c.instance_id().to_i64());
            let me = path_of(&self.to_gd());
            let Some(scene) = self.scene.as_mut() else {
                return false;
            };
            let explicit = if let Ok(point) = target.try_to::<Vector3>() {
                Some(ExplicitTarget::Point(vec3(point)))
            } else {
                instance_id(&target)
                    .and_then(|key| {
                        scene
                            .entity_of(key)
                            .or_else(|| (camera == Some(key)).then(|| scene.viewer()).flatten())
                    })
                    .map(ExplicitTarget::Entity)
            };
            let result = match (slot, explicit) {
                (Some(slot), Some(explicit)) => scene
                    .gaze(slot)
                    .map(|gaze| gaze.character)
                    .and_then(|id| {
                        scene
                            .crowd_mut()
                            .set_gaze_target(id, explicit, TargetPriority::Override)
                    })
                    .map_err(|e| e.to_string()),
                (None, _) => Err("the character is not in the crowd".into()),
                (_, None) => Err("the target is neither a point nor in the crowd".into()),
            };
            match result {
                Ok(()) => true,
                Err(error) => {
                    godot_error!("{}", message(&me, "CrowdGaze.set_gaze_target", &error, ""));
                    false
                }
            }
        })
    }

    /// Gives a character back to its attention.
    #[func]
    fn clear_gaze_target(&mut self, character: Variant) -> bool {
        boundary("CrowdGaze.clear_gaze_target", false, || {
            let slot = self.slot_of(&character);
            let Some((scene, slot)) = self.scene.as_mut().zip(slot) else {
                return false;
            };
            scene
                .gaze(slot)
                .and_then(|gaze| scene.crowd_mut().clear_gaze_target(gaze.character))
                .is_ok()
        })
    }

    /// The last frame's cost in this node (reading the scene and stepping the crowd; the
    /// modifiers' writes come after), microseconds.
    #[func]
    fn get_frame_usec(&self) -> f64 {
        self.frame_usec.iter().sum()
    }

    /// The last frame's cost in this node by part, microseconds: `(read, step, 0)` (the
    /// writes are the modifiers').
    #[func]
    fn get_frame_parts_usec(&self) -> Vector3 {
        Vector3::new(self.frame_usec[0] as f32, self.frame_usec[1] as f32, 0.0)
    }
}
