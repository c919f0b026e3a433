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
use crowdgaze_godot_adapter::crowdgaze::scene::ids::NO_ENTITY;
use crowdgaze_godot_adapter::lids::{find_blink_shapes, BlinkWriter};
use crowdgaze_godot_adapter::{
    check_crowd, claim_skeleton, message, Controls, CrowdSettings, EntityNode, PoseConvention,
    Reports, SceneCrowd, SkeletonClaim,
};
use godot::classes::{ArrayMesh, Camera3D, INode3D, MeshInstance3D, Node3D, Skeleton3D};
use godot::prelude::*;

use crate::character::{resolve_crowd, CharacterInputs};
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
    /// A character's eyelid mesh, if it has one with blink shapes.
    eyelids: Option<EyelidMesh>,
}

/// A `MeshInstance3D` whose blink blend shapes take a character's eyelid closure.
#[derive(Debug, Clone)]
pub struct EyelidMesh {
    /// The mesh instance's id.
    mesh: i64,
    /// Its blink shapes (blend shape indices).
    writer: BlinkWriter,
}

impl EyelidMesh {
    /// Sets the blink shapes for character `slot` this frame (see
    /// [`SceneCrowd::blink_values`]).
    fn apply(&mut self, scene: &SceneCrowd<Handle>, slot: usize) {
        let values = scene.blink_values(slot, &mut self.writer);
        if values.iter().all(Option::is_none) {
            return;
        }
        let Some(mut mesh) = live::<MeshInstance3D>(self.mesh) else {
            return;
        };
        let count = mesh.get_blend_shape_count().max(0) as usize;
        for (shape, value) in values.into_iter().flatten() {
            if shape < count {
                mesh.set_blend_shape_value(shape as i32, value);
            }
        }
    }
}

/// The eyelid mesh `path` names from the character `node` with the shapes `shapes`
/// (`eyelid_shapes`): `Ok(None)` for an empty path; errors say what to fix.
fn eyelid_mesh(
    node: &Gd<Node3D>,
    path: &NodePath,
    shapes: &str,
) -> Result<Option<EyelidMesh>, String> {
    if path.is_empty() {
        return Ok(None);
    }
    let text = path.to_string();
    let found = node.get_node_or_null(path).ok_or_else(|| {
        format!("eyelid_mesh = '{text}' names no node: set it to a MeshInstance3D")
    })?;
    let instance = found.try_cast::<MeshInstance3D>().map_err(|other| {
        format!(
            "eyelid_mesh = '{text}' names a {}, not a MeshInstance3D",
            other.get_class()
        )
    })?;
    let names: Vec<String> = instance
        .get_mesh()
        .and_then(|mesh| mesh.try_cast::<ArrayMesh>().ok())
        .map(|mesh| {
            (0..mesh.get_blend_shape_count())
                .map(|k| mesh.get_blend_shape_name(k).to_string())
                .collect()
        })
        .unwrap_or_default();
    let shapes = find_blink_shapes(&names, shapes)?;
    if shapes.is_empty() {
        return Err(format!(
            "eyelid_mesh = '{text}' has no blink blend shape (eyeBlinkLeft/eyeBlinkRight, \
             Blink_L/Blink_R, Blink, blink): name its shapes in eyelid_shapes"
        ));
    }
    Ok(Some(EyelidMesh {
        mesh: instance.instance_id().to_i64(),
        writer: BlinkWriter::new(shapes),
    }))
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
    /// Degrees: gaze turns up to this the eyes make alone. Per crowd (as in the library),
    /// read when the crowd is made.
    #[export(range = (0.0, 180.0, 1.0))]
    eyes_only_angle: f64,
    /// Degrees: gaze turns up to this leave the spine still (eyes, head and neck). Per
    /// crowd, read when the crowd is made.
    #[export(range = (0.0, 180.0, 1.0))]
    eyes_head_neck_angle: f64,
    /// Degrees per second: the head speed that times gaze shifts (faster: shorter shifts).
    /// Per crowd, read when the crowd is made.
    #[export(range = (1.0, 1440.0, 1.0, or_greater))]
    head_speed: f64,
    /// Gaze following: characters may glance where others stare (a point or object set
    /// with `set_gaze_target`). Per crowd, read when the crowd is made.
    #[export]
    gaze_following: bool,
    /// How strongly passers-by follow: 0 Milgram (1969), 1 Gallup (2012). Per crowd.
    #[export(enum = (Milgram = 0, Gallup = 1))]
    following_strength: i64,
    /// Whether the crowd's gaze is applied: false fades every character's influence to 0
    /// over `influence_fade_time`, then leaves the bones to the animation.
    #[export]
    #[var(set = set_active)]
    active: bool,
    /// How much of the gaze every character's bones take (0 to 1), times the character's
    /// own `influence`.
    #[export(range = (0.0, 1.0, 0.01))]
    #[var(set = set_influence)]
    influence: f64,
    /// Seconds a change of `active` or `influence` takes to show fully (0: at once).
    #[export(range = (0.0, 10.0, 0.01, or_greater))]
    #[var(set = set_influence_fade_time)]
    influence_fade_time: f64,
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
        let controls = Controls::default();
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
            eyes_only_angle: defaults.eyes_only_angle,
            eyes_head_neck_angle: defaults.eyes_head_neck_angle,
            head_speed: defaults.head_speed,
            gaze_following: defaults.gaze_following,
            following_strength: defaults.following_strength,
            active: controls.active,
            influence: f64::from(controls.influence),
            influence_fade_time: f64::from(controls.fade_time),
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
            eyes_only_angle: self.eyes_only_angle,
            eyes_head_neck_angle: self.eyes_head_neck_angle,
            head_speed: self.head_speed,
            gaze_following: self.gaze_following,
            following_strength: self.following_strength,
        }
    }

    /// Gives the crowd the node's controls (a bad value is reported once and the crowd
    /// keeps its controls).
    fn apply_controls(&mut self) {
        // In the editor nothing runs: the crowd takes its controls when the game does.
        if in_editor() {
            return;
        }
        match Controls::new(self.active, self.influence, self.influence_fade_time) {
            Ok(controls) => {
                if let Some(scene) = self.scene.as_mut() {
                    scene.set_controls(&controls);
                }
            }
            // Out of the tree (a scene being loaded) it is reported when the crowd is made.
            Err(_) if !self.base().is_inside_tree() => {}
            Err(error) => {
                let me = self.to_gd();
                if self
                    .reports
                    .first(me.instance_id().to_i64(), "controls", &error)
                {
                    godot_error!(
                        "{}",
                        message(
                            &path_of(&me),
                            "CrowdGaze.set_active/set_influence/set_influence_fade_time",
                            &error,
                            "the crowd keeps its previous controls"
                        )
                    );
                }
            }
        }
    }

    /// The character's eyelid mesh; a path or shapes that do not fit are reported once.
    fn find_eyelids(
        reports: &mut Reports,
        node: &Gd<Node3D>,
        inputs: &CharacterInputs,
    ) -> Option<EyelidMesh> {
        match eyelid_mesh(node, &inputs.eyelid_mesh, &inputs.eyelid_shapes) {
            Ok(eyelids) => eyelids,
            Err(error) => {
                if reports.first(node.instance_id().to_i64(), "eyelids", &error) {
                    godot_error!(
                        "{}",
                        message(
                            &path_of(node),
                            "CrowdGazeCharacter.set_eyelid_mesh",
                            &error,
                            "no blend shape is set"
                        )
                    );
                }
                None
            }
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
                Ok(scene) => {
                    self.scene = Some(scene);
                    self.apply_controls();
                }
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
    pub fn register_character(&mut self, node: Gd<Node3D>, inputs: CharacterInputs) {
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
        let eyelids = Self::find_eyelids(&mut self.reports, &node, &inputs);
        let Some(scene) = self.scene.as_mut() else {
            return;
        };
        let result = match skeleton {
            None => Err(
                "a CrowdGazeCharacter must be a child of a Skeleton3D: move it under one"
                    .to_string(),
            ),
            Some(skeleton) => {
                let skeleton_key = skeleton.instance_id().to_i64();
                claim_skeleton(skeleton_key, key, &path).and_then(|claim| {
                    inputs
                        .values
                        .settings()
                        .and_then(|settings| {
                            let handle = Handle {
                                node: key,
                                skeleton: skeleton_key,
                                _claim: Some(Arc::new(claim)),
                                eyelids,
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

    /// A registered character's settings changed: the crowd takes them (a character
    /// refused before tries to join again).
    pub fn update_character(&mut self, node: Gd<Node3D>, inputs: CharacterInputs) {
        let key = node.instance_id().to_i64();
        let registered = self.scene.as_ref().and_then(|s| s.entity_of(key)).is_some();
        if !registered {
            self.refused.remove(&key);
            self.register_character(node, inputs);
            return;
        }
        let eyelids = Self::find_eyelids(&mut self.reports, &node, &inputs);
        let (Some(scene), Some(skeleton)) = (self.scene.as_mut(), skeleton_of(&node)) else {
            return;
        };
        if let Some(handle) = scene
            .character_slot(key)
            .and_then(|slot| scene.character_handle_mut(slot))
        {
            handle.eyelids = eyelids;
        }
        let result = inputs.values.settings().and_then(|settings| {
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
                        "CrowdGazeCharacter.set",
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
            eyelids: None,
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
            let eyelids = scene
                .character_handle_mut(slot)
                .and_then(|handle| handle.eyelids.take());
            if let Some(mut eyelids) = eyelids {
                eyelids.apply(scene, slot);
                if let Some(handle) = scene.character_handle_mut(slot) {
                    handle.eyelids = Some(eyelids);
                }
            }
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
                let inputs = character.bind().settings();
                let path = character.bind().crowd_path();
                let me = self.to_gd().instance_id();
                if joins(me, &character.clone().upcast::<Node>(), &path) {
                    character.bind_mut().set_joined(me);
                    self.register_character(character.upcast(), inputs);
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
        let node_variant = |id: u32| match scene.node_of(id) {
            EntityNode::Character(handle) | EntityNode::Target(handle) => {
                live::<Node>(handle.node).map(|node| node.to_variant())
            }
            EntityNode::Viewer => camera.as_ref().map(|camera| camera.to_variant()),
            EntityNode::None => None,
        };
        for change in scene.interest_changes() {
            let Some(character) = scene
                .character_handle(change.slot)
                .and_then(|h| live::<Node>(h.node))
            else {
                continue;
            };
            let character = character.to_variant();
            let (from, to) = (node_variant(change.from), node_variant(change.to));
            let mut emit = |signal: &str, target: Option<Variant>| {
                emits.push([
                    signal.to_variant(),
                    character.clone(),
                    target.unwrap_or_default(),
                ]);
            };
            if change.from != NO_ENTITY {
                emit("character_stopped_looking", from);
            }
            if change.to != NO_ENTITY {
                emit("character_started_looking", to.clone());
            }
            emit("interest_changed", to);
        }
        for start in scene.follow_starts() {
            if let Some(character) = scene
                .character_handle(start.slot)
                .and_then(|h| live::<Node>(h.node))
            {
                emits.push([
                    "character_followed_gaze".to_variant(),
                    character.to_variant(),
                    vector(start.point).to_variant(),
                ]);
            }
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

    /// A character's eyes arrived at a new target (a character or target node, or the
    /// camera); sent after `character_stopped_looking` for the one before.
    #[signal]
    fn character_started_looking(character: Gd<Node>, target: Variant);

    /// A character's eyes left a target (null if that node is gone).
    #[signal]
    fn character_stopped_looking(character: Gd<Node>, target: Variant);

    /// A character started to glance at `point` (world metres) because others stare there
    /// (gaze following).
    #[signal]
    fn character_followed_gaze(character: Gd<Node>, point: Vector3);

    /// Sets `active`; every character's influence fades to it.
    #[func]
    fn set_active(&mut self, active: bool) {
        self.active = active;
        boundary("CrowdGaze.set_active", (), || self.apply_controls())
    }

    /// Sets `influence`; every character's influence fades to it times its own.
    #[func]
    fn set_influence(&mut self, influence: f64) {
        self.influence = influence;
        boundary("CrowdGaze.set_influence", (), || self.apply_controls())
    }

    /// Sets `influence_fade_time`.
    #[func]
    fn set_influence_fade_time(&mut self, seconds: f64) {
        self.influence_fade_time = seconds;
        boundary("CrowdGaze.set_influence_fade_time", (), || {
            self.apply_controls()
        })
    }

    /// A character's eyelids after the last step: `Vector2(closure, lid_pitch)`, closure 0
    /// open to 1 closed (a blink), lid pitch in radians (positive up), both eyes' mean;
    /// `Vector2(0, 0)` for anything but a character of this crowd.
    #[func]
    fn get_eyelids(&self, character: Variant) -> Vector2 {
        boundary("CrowdGaze.get_eyelids", Vector2::ZERO, || {
            self.slot_of(&character)
                .and_then(|slot| self.scene.as_ref()?.eyelid_summary(slot).ok())
                .map_or(Vector2::ZERO, |(closure, pitch)| {
                    Vector2::new(closure, pitch)
                })
        })
    }

    /// A character's influence now (the crowd's times its own, fading), 0 to 1; 0 for
    /// anything but a character of this crowd.
    #[func]
    fn get_character_influence(&self, character: Variant) -> f64 {
        boundary("CrowdGaze.get_character_influence", 0.0, || {
            self.slot_of(&character)
                .and_then(|slot| self.scene.as_ref()?.influence(slot).ok())
                .map_or(0.0, f64::from)
        })
    }

    /// Makes `members` (an Array of 2 to 8 `CrowdGazeCharacter` nodes of this crowd, each
    /// in no other conversation) a group standing together and talking; they look at each
    /// other, more at whoever has `talking` set. Returns the conversation's id (≥ 0), or -1
    /// with an error.
    #[func]
    fn set_conversation(&mut self, members: Variant) -> i64 {
        boundary("CrowdGaze.set_conversation", -1, || {
            let result = match (self.scene.as_mut(), members.try_to::<VarArray>().ok()) {
                (None, _) => Err("the crowd was not created (see the first error)".to_string()),
                (_, None) => Err(format!(
                    "members must be an Array of CrowdGazeCharacter nodes, not a {:?}",
                    members.get_type()
                )),
                (Some(scene), Some(array)) => {
                    let keys: Vec<i64> = array
                        .iter_shared()
                        .map(|member| instance_id(&member).unwrap_or(0))
                        .collect();
                    scene
                        .set_conversation(&keys)
                        .map(i64::from)
                        .map_err(|e| e.to_string())
                }
            };
            result.unwrap_or_else(|error| {
                // Once per cause: a script retrying every frame does not flood the output.
                let key = self.to_gd().instance_id().to_i64();
                if self.reports.first(key, "set_conversation", &error) {
                    godot_error!(
                        "{}",
                        message(
                            &path_of(&self.to_gd()),
                            "CrowdGaze.set_conversation",
                            &error,
                            "no conversation is formed"
                        )
                    );
                }
                -1
            })
        })
    }

    /// Ends conversation `id` (from `set_conversation`): its members go back to their own
    /// attention. False (with an error) if there is no such conversation.
    #[func]
    fn remove_conversation(&mut self, id: Variant) -> bool {
        boundary("CrowdGaze.remove_conversation", false, || {
            let result = match (self.scene.as_mut(), id.try_to::<i64>().ok()) {
                (Some(scene), Some(id)) => scene.remove_conversation(id).map_err(|e| e.to_string()),
                (None, _) => Err("the crowd was not created (see the first error)".to_string()),
                (_, None) => Err(format!(
                    "id must be an int (from set_conversation), not a {:?}",
                    id.get_type()
                )),
            };
            result.map_or_else(
                |error| {
                    let key = self.to_gd().instance_id().to_i64();
                    if self.reports.first(key, "remove_conversation", &error) {
                        godot_error!(
                            "{}",
                            message(
                                &path_of(&self.to_gd()),
                                "CrowdGaze.remove_conversation",
                                &error,
                                ""
                            )
                        );
                    }
                    false
                },
                |()| true,
            )
        })
    }

    /// The conversation a character is in (its id), or -1 for none (and for anything but
    /// a character of this crowd).
    #[func]
    fn get_conversation(&self, character: Variant) -> i64 {
        boundary("CrowdGaze.get_conversation", -1, || {
            self.slot_of(&character)
                .and_then(|slot| self.scene.as_ref()?.conversation_of(slot).ok().flatten())
                .map_or(-1, i64::from)
        })
    }

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

    /// The point a character glances at because others stare there (gaze following), or
    /// null when it follows no one's gaze now (and for anything but a character of the
    /// crowd, or with `gaze_following` off).
    #[func]
    fn get_following(&self, character: Variant) -> Variant {
        boundary("CrowdGaze.get_following", Variant::nil(), || {
            self.slot_of(&character)
                .and_then(|slot| self.scene.as_ref()?.following(slot).ok().flatten())
                .map_or_else(Variant::nil, |point| vector(point).to_variant())
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
