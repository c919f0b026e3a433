//! `CrowdGaze` (a `Spatial`): owns the crowd, takes its settings from the inspector, and
//! once per frame reads every character and target, steps, and writes the gaze to the
//! skeletons. It emits `interest_changed(character, target)` when a character's eyes move
//! to another target (`null` for none; the active camera when it looks at the player).

use std::collections::HashSet;
use std::sync::Arc;
use std::time::Instant;

use crowdgaze_godot_adapter::crowdgaze::crowd::{ExplicitTarget, TargetPriority};
use crowdgaze_godot_adapter::crowdgaze::scene::ids::NO_ENTITY;
use crowdgaze_godot_adapter::lids::{find_blink_shapes, BlinkWriter};
use crowdgaze_godot_adapter::{
    check_crowd, claim_skeleton, message, Controls, CrowdSettings, EntityNode, PoseConvention,
    Reports, SceneCrowd, SkeletonClaim,
};
use gdnative::api::{ArrayMesh, MeshInstance, Skeleton};
use gdnative::nativescript::init::{Signal, SignalArgument};
use gdnative::nativescript::{ExportInfo, PropertyUsage};
use gdnative::prelude::*;

use crate::character::{resolve_crowd, CharacterInputs, Presence};
use crate::convert::{
    boundary, head_speed_hint, in_editor, node_path, number, on_main_thread_now, quat,
    seconds_hint, share_angle_hint, strength_hint, unit_hint, vec3, vector, xform, Data,
};
use crate::props::a_type;
use crate::skeleton::GodotSkeleton;
use crate::{checked_method, checked_property};

/// The addon's groups (shared with the other front end).
pub use crowdgaze_godot_adapter::membership::{CHARACTER_GROUP, CROWD_GROUP, TARGET_GROUP};

/// A registered node: its instance id, and its skeleton's for a character (0 for a target).
#[derive(Debug, Clone)]
pub struct Handle {
    node: i64,
    skeleton: i64,
    /// A character's node and skeleton as registered.
    kept: Option<Kept>,
    /// A character's hold on its skeleton (released when the handle goes).
    _claim: Option<Arc<SkeletonClaim>>,
    /// A character's eyelid mesh, if it has one with blink shapes.
    eyelids: Option<EyelidMesh>,
}

/// A `MeshInstance` whose blink blend shapes take a character's eyelid closure.
#[derive(Debug, Clone)]
pub struct EyelidMesh {
    /// The mesh instance's id.
    mesh: i64,
    /// Its blink shapes (indices into `properties`).
    writer: BlinkWriter,
    /// `blend_shapes/<name>` of each blend shape of the mesh, made once.
    properties: Vec<GodotString>,
}

impl EyelidMesh {
    /// Sets the blink shapes for character `slot` this frame (see
    /// [`SceneCrowd::blink_values`]).
    fn apply(&mut self, scene: &SceneCrowd<Handle>, slot: usize) {
        let values = scene.blink_values(slot, &mut self.writer);
        if values.iter().all(Option::is_none) {
            return;
        }
        // SAFETY: an id taken from a MeshInstance, used within this call.
        let Some(mesh) = (unsafe { live::<MeshInstance>(self.mesh) }) else {
            return;
        };
        for (shape, value) in values.into_iter().flatten() {
            if let Some(property) = self.properties.get(shape) {
                mesh.set(property.new_ref(), f64::from(value));
            }
        }
    }
}

/// The eyelid mesh `path` names from the character `node` with the shapes `shapes`
/// (`eyelid_shapes`): `Ok(None)` for an empty path; errors say what to fix.
fn eyelid_mesh(
    node: &Spatial,
    path: &NodePath,
    shapes: &str,
) -> Result<Option<EyelidMesh>, String> {
    if path.is_empty() {
        return Ok(None);
    }
    let text = path.to_string();
    let found = Some(node)
        .filter(|node| node.has_node(path.new_ref()))
        .and_then(|node| node.get_node(path.new_ref()))
        // SAFETY: a node of the tree, on the main thread, for this call.
        .and_then(|n| unsafe { n.assume_safe_if_sane() })
        .ok_or_else(|| format!("eyelid_mesh = '{text}' names no node: set it to a MeshInstance"))?;
    let instance = found.cast::<MeshInstance>().ok_or_else(|| {
        format!(
            "eyelid_mesh = '{text}' names a {}, not a MeshInstance",
            found.get_class()
        )
    })?;
    let names: Vec<String> = instance
        .mesh()
        // SAFETY: the mesh resource is held by the instance, used within this call.
        .and_then(|mesh| {
            unsafe { mesh.assume_safe() }
                .cast::<ArrayMesh>()
                .map(|m| m.claim())
        })
        .map(|mesh| {
            // SAFETY: as above.
            let mesh = unsafe { mesh.assume_safe() };
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
        mesh: instance.get_instance_id(),
        writer: BlinkWriter::new(shapes),
        properties: names
            .iter()
            .map(|name| GodotString::from(format!("blend_shapes/{name}")))
            .collect(),
    }))
}

/// A character's node and skeleton, kept at registration to be used each frame without an
/// object-database lookup while the node's stamp is still the one taken then (see
/// [`Presence`]).
#[derive(Debug, Clone)]
struct Kept {
    presence: Presence,
    stamp: u64,
    node: Ref<Spatial, Shared>,
    skeleton: Ref<Skeleton, Shared>,
}

impl Handle {
    /// The character's node and skeleton if both are alive: the kept ones when they
    /// certainly are, else looked up by id (`None` if either is gone).
    ///
    /// # Safety
    ///
    /// The references must be used on the main thread within the current call only.
    unsafe fn character<'a>(
        &self,
    ) -> Option<(TRef<'a, Spatial, Shared>, TRef<'a, Skeleton, Shared>)> {
        if let Some(kept) = &self.kept {
            // The script was taken off the node (or the node is being freed): the node is
            // no character any more, and its skeleton is left alone.
            if kept.presence.stamp() == Presence::GONE {
                return None;
            }
            if kept.presence.stamp() == kept.stamp {
                // SAFETY: the node has stayed alive in the tree under its skeleton since it
                // was registered, so both live; used on the main thread within this call.
                return Some(unsafe { (kept.node.assume_safe(), kept.skeleton.assume_safe()) });
            }
        }
        // SAFETY: ids taken from a Spatial and a Skeleton, used within this call.
        let node = unsafe { live::<Spatial>(self.node) }?;
        let skeleton = unsafe { live::<Skeleton>(self.skeleton) }?;
        Some((node, skeleton))
    }
}

/// The node that owns a crowd. Its exported fields are the crowd's settings, read when the
/// crowd is created (when the node enters the tree); `camera_is_viewer` and
/// `viewer_impact` are read every frame.
#[derive(NativeClass)]
#[inherit(Spatial)]
#[user_data(Data<CrowdGaze>)]
#[register_with(Self::register)]
pub struct CrowdGaze {
    /// Seed of every random choice: the same scene and seed give the same gaze.
    seed: i64,
    /// Most characters the crowd holds.
    max_characters: i64,
    /// Most targets (`GazeTarget` nodes) the crowd holds.
    max_targets: i64,
    /// How far characters notice others (`d_m`, metres).
    max_distance: f64,
    /// The characters' field of view, degrees.
    field_of_view: f64,
    /// Smallest share of the time a character spends attending (0 to 1).
    attention_fraction_min: f64,
    /// Largest share of the time a character spends attending (0 to 1).
    attention_fraction_max: f64,
    /// Threads a step uses (1: the main thread only; 0: one per core).
    threads: i64,
    /// Level of detail: each character's attention is updated every `attention_period`
    /// frames (1 to 64, staggered; gaze IK runs every frame).
    attention_period: i64,
    /// Level of detail by distance: beyond `lod_distance` metres from the camera,
    /// attention is updated every `far_attention_period` frames (0: off).
    lod_distance: f64,
    /// See `lod_distance` (1 to 64).
    far_attention_period: i64,
    /// Degrees: gaze turns up to this the eyes make alone. Per crowd (as in the library),
    /// read when the crowd is made.
    eyes_only_angle: f64,
    /// Degrees: gaze turns up to this leave the spine still (eyes, head and neck). Per
    /// crowd, read when the crowd is made.
    eyes_head_neck_angle: f64,
    /// Degrees per second: the head speed that times gaze shifts (faster: shorter shifts).
    /// Per crowd, read when the crowd is made.
    head_speed: f64,
    /// Whether the crowd's gaze is applied: false fades every character's influence to 0
    /// over `influence_fade_time`, then leaves the bones to the animation.
    active: bool,
    /// How much of the gaze every character's bones take (0 to 1), times the character's
    /// own `influence`.
    influence: f64,
    /// Seconds a change of `active` or `influence` takes to show fully (0: at once).
    influence_fade_time: f64,
    /// Gaze following: characters may glance where others stare (a point or object set
    /// with `set_gaze_target`). Per crowd, read when the crowd is made.
    gaze_following: bool,
    /// How strongly passers-by follow: 0 Milgram (1969), 1 Gallup (2012). Per crowd.
    following_strength: i64,
    /// Make the active camera an entity the characters may look at.
    camera_is_viewer: bool,
    /// How interesting the camera is (`I_E`, ≥ 0).
    viewer_impact: f64,
    scene: Option<SceneCrowd<Handle>>,
    /// Nodes refused (reported once), by instance id.
    refused: HashSet<i64>,
    /// What was reported: each node's error once per cause.
    reports: Reports,
    /// True once creating the crowd failed (reported once).
    config_failed: bool,
    /// The last frame's cost, microseconds: reading the scene, stepping, writing bones.
    frame_usec: [f64; 3],
    /// This frame's skeleton of each character slot, found while reading and written after
    /// the step; empty between frames. Capacity for `max_characters`: no allocation per
    /// frame.
    skeletons: Vec<Ref<Skeleton, Shared>>,
}

/// The character or target node behind a variant, by instance id.
fn instance_id(node: &Variant) -> Option<i64> {
    let object = node.try_to_object::<Object>()?;
    // SAFETY: the object came from the engine on this (the main) thread, which owns it for
    // this call; only its id is read.
    let object = unsafe { object.assume_safe_if_sane()? };
    Some(object.get_instance_id())
}

/// The node of an instance id, if it is alive.
fn node_of(id: i64) -> Option<TRef<'static, Node, Shared>> {
    // SAFETY: every id the crowd keeps was taken from a `Node` (or a subclass).
    unsafe { live::<Node>(id) }
}

/// The object of an instance id while it lives (Godot 3 never reuses an id): one ObjectDB
/// lookup, without gdnative's class check by name (a string comparison through Godot,
/// several times the lookup's cost, that the per-frame loop cannot afford).
///
/// # Safety
///
/// `id` must have been taken from an object of class `T` (or a subclass), and the reference
/// used on the main thread within the current call only.
unsafe fn live<'a, T: GodotObject<RefKind = gdnative::ref_kind::ManuallyManaged>>(
    id: i64,
) -> Option<TRef<'a, T, Shared>> {
    let api = gdnative::private::get_api();
    // SAFETY: the GDNative API is initialised while any method of ours runs.
    let object = unsafe { (api.godot_instance_from_id)(id as gdnative::sys::godot_int) };
    let object = std::ptr::NonNull::new(object)?;
    // SAFETY: the object is alive (ObjectDB has it) and of class `T` (the caller's promise).
    Some(unsafe { Ref::<T, Shared>::from_sys(object).assume_safe() })
}

/// A node's path, for messages (see [`node_path`]).
fn path_of(node: &Node) -> String {
    node_path(node)
}

/// A character node's parent `Skeleton`, if it is one.
pub fn skeleton_of<'a>(node: &Spatial) -> Option<TRef<'a, Skeleton, Shared>> {
    node.get_parent()
        // SAFETY: the parent is in the tree, owned by the main thread, for this call.
        .and_then(|parent| unsafe { parent.assume_safe_if_sane() })
        .and_then(|parent| parent.cast::<Skeleton>())
}

/// True if `node`, whose `crowd` path is `path`, joins the crowd `owner`.
fn joins(owner: &Spatial, node: &Spatial, path: &NodePath) -> bool {
    matches!(resolve_crowd(node, path), Ok(Some(crowd)) if crowd.get_instance_id() == owner.get_instance_id())
}

impl CrowdGaze {
    fn new(_owner: &Spatial) -> Self {
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
            frame_usec: [0.0; 3],
            skeletons: Vec::new(),
        }
    }

    fn register(builder: &ClassBuilder<Self>) {
        let node = || SignalArgument {
            name: "node",
            default: Variant::new(),
            export_info: ExportInfo::new(VariantType::Object),
            usage: PropertyUsage::DEFAULT,
        };
        for name in [
            "interest_changed",
            "character_started_looking",
            "character_stopped_looking",
        ] {
            builder.add_signal(Signal {
                name,
                args: &[
                    SignalArgument {
                        name: "character",
                        ..node()
                    },
                    SignalArgument {
                        name: "target",
                        ..node()
                    },
                ],
            });
        }
        builder.add_signal(Signal {
            name: "character_followed_gaze",
            args: &[
                SignalArgument {
                    name: "character",
                    ..node()
                },
                SignalArgument {
                    name: "point",
                    default: Variant::new(),
                    export_info: ExportInfo::new(VariantType::Vector3),
                    usage: PropertyUsage::DEFAULT,
                },
            ],
        });
        Self::register_properties(builder);
        Self::register_methods(builder);
    }

    /// The exported properties, each with its value's type checked (see
    /// [`props`](crate::props)); the defaults are the adapter's.
    fn register_properties(builder: &ClassBuilder<Self>) {
        let d = CrowdSettings::default();
        checked_property!(builder, CrowdGaze, seed: i64 = d.seed);
        checked_property!(builder, CrowdGaze, max_characters: i64 = d.max_characters);
        checked_property!(builder, CrowdGaze, max_targets: i64 = d.max_targets);
        checked_property!(builder, CrowdGaze, max_distance: f64 = d.max_distance);
        checked_property!(builder, CrowdGaze, field_of_view: f64 = d.field_of_view);
        checked_property!(builder, CrowdGaze, attention_fraction_min: f64 = d.attention_fraction_min);
        checked_property!(builder, CrowdGaze, attention_fraction_max: f64 = d.attention_fraction_max);
        checked_property!(builder, CrowdGaze, threads: i64 = d.threads);
        checked_property!(builder, CrowdGaze, attention_period: i64 = d.attention_period);
        checked_property!(builder, CrowdGaze, lod_distance: f64 = d.lod_distance);
        checked_property!(builder, CrowdGaze, far_attention_period: i64 = d.far_attention_period);
        checked_property!(builder, CrowdGaze, camera_is_viewer: bool = true);
        checked_property!(builder, CrowdGaze, viewer_impact: f64 = 3.0);
        checked_property!(builder, CrowdGaze, eyes_only_angle: f64 = d.eyes_only_angle,
            hint share_angle_hint(), expects "a float (degrees)");
        checked_property!(builder, CrowdGaze, eyes_head_neck_angle: f64 = d.eyes_head_neck_angle,
            hint share_angle_hint(), expects "a float (degrees)");
        checked_property!(builder, CrowdGaze, head_speed: f64 = d.head_speed,
            hint head_speed_hint(), expects "a float (degrees per second)");
        checked_property!(builder, CrowdGaze, gaze_following: bool = d.gaze_following);
        checked_property!(builder, CrowdGaze, following_strength: i64 = d.following_strength,
            hint strength_hint(), expects "an int (0 Milgram, 1 Gallup)");
        let c = Controls::default();
        checked_property!(builder, CrowdGaze, active: bool = c.active, then Self::controls_changed);
        checked_property!(builder, CrowdGaze, influence: f64 = f64::from(c.influence),
            hint unit_hint(), expects "a float from 0 to 1", then Self::controls_changed);
        checked_property!(builder, CrowdGaze, influence_fade_time: f64 = f64::from(c.fade_time),
            hint seconds_hint(), expects "a float (seconds)", then Self::controls_changed);
    }

    /// The exported methods, each with its argument count checked (see
    /// [`methods`](mod@crate::methods)).
    fn register_methods(builder: &ClassBuilder<Self>) {
        checked_method!(builder, CrowdGaze, [], fn _enter_tree(&mut self, owner: &Spatial));
        checked_method!(builder, CrowdGaze, [], fn _ready(&mut self, owner: &Spatial));
        checked_method!(builder, CrowdGaze, [], fn _exit_tree(&mut self, owner: &Spatial));
        checked_method!(builder, CrowdGaze, ["delta"], fn _process(&mut self, owner: &Spatial, delta: Variant));
        checked_method!(builder, CrowdGaze, [], fn _get_configuration_warning(&self, _owner: &Spatial) -> String);
        checked_method!(builder, CrowdGaze, [], fn get_character_count(&self, _owner: &Spatial) -> i64);
        checked_method!(builder, CrowdGaze, [], fn get_target_count(&self, _owner: &Spatial) -> i64);
        checked_method!(builder, CrowdGaze, ["character"], fn get_gaze_target(&self, owner: &Spatial, character: Variant) -> Variant);
        checked_method!(builder, CrowdGaze, ["character"], fn get_gaze_point(&self, _owner: &Spatial, character: Variant) -> Vector3);
        checked_method!(builder, CrowdGaze, ["character"], fn is_attending(&self, _owner: &Spatial, character: Variant) -> bool);
        checked_method!(builder, CrowdGaze, ["character"], fn is_holding(&self, _owner: &Spatial, character: Variant) -> bool);
        checked_method!(builder, CrowdGaze, ["character"], fn get_chain_bones(&self, _owner: &Spatial, character: Variant) -> VariantArray);
        checked_method!(builder, CrowdGaze, ["character"], fn get_joint_rotations(&self, _owner: &Spatial, character: Variant) -> VariantArray);
        checked_method!(builder, CrowdGaze, ["character"], fn get_look_at_height(&self, _owner: &Spatial, character: Variant) -> f64);
        checked_method!(builder, CrowdGaze, ["character", "target"], fn set_gaze_target(&mut self, owner: &Spatial, character: Variant, target: Variant) -> bool);
        checked_method!(builder, CrowdGaze, ["character"], fn clear_gaze_target(&mut self, _owner: &Spatial, character: Variant) -> bool);
        checked_method!(builder, CrowdGaze, ["character"], fn get_following(&self, _owner: &Spatial, character: Variant) -> Variant);
        checked_method!(builder, CrowdGaze, ["character"], fn get_eyelids(&self, _owner: &Spatial, character: Variant) -> Vector2);
        checked_method!(builder, CrowdGaze, ["character"], fn get_character_influence(&self, _owner: &Spatial, character: Variant) -> f64);
        checked_method!(builder, CrowdGaze, ["members"], fn set_conversation(&mut self, owner: &Spatial, members: Variant) -> i64);
        checked_method!(builder, CrowdGaze, ["id"], fn remove_conversation(&mut self, owner: &Spatial, id: Variant) -> bool);
        checked_method!(builder, CrowdGaze, ["character"], fn get_conversation(&self, _owner: &Spatial, character: Variant) -> i64);
        checked_method!(builder, CrowdGaze, [], fn get_frame_usec(&self, _owner: &Spatial) -> f64);
        checked_method!(builder, CrowdGaze, [], fn get_frame_parts_usec(&self, _owner: &Spatial) -> Vector3);
    }

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

    /// `active`, `influence` or `influence_fade_time` was set: the crowd takes them (in
    /// the editor, only the warnings are shown again).
    fn controls_changed(&mut self, owner: TRef<Spatial>) {
        boundary("CrowdGaze.controls_changed", (), || {
            if in_editor() {
                if owner.is_inside_tree() {
                    owner.update_configuration_warning();
                }
                return;
            }
            self.apply_controls(&owner);
        })
    }

    /// Gives the crowd the node's controls.
    fn apply_controls(&mut self, owner: &Spatial) {
        match Controls::new(self.active, self.influence, self.influence_fade_time) {
            Ok(controls) => {
                if let Some(scene) = self.scene.as_mut() {
                    scene.set_controls(&controls);
                }
            }
            // Out of the tree (a scene being loaded) it is reported when the crowd is made.
            Err(_) if !owner.is_inside_tree() => {}
            Err(error) => {
                if self
                    .reports
                    .first(owner.get_instance_id(), "controls", &error)
                {
                    godot_error!(
                        "{}",
                        message(
                            &path_of(owner),
                            "CrowdGaze.set_active/set_influence/set_influence_fade_time",
                            &error,
                            "the crowd keeps its previous controls"
                        )
                    );
                }
            }
        }
    }

    /// The crowd, created from the settings the first time.
    fn scene(&mut self, owner: &Spatial) -> Option<&mut SceneCrowd<Handle>> {
        if self.scene.is_none() && !self.config_failed {
            let created = self.settings().config().and_then(|config| {
                let capacity = config.max_characters as usize;
                SceneCrowd::new(config, PoseConvention::RestTimesPose).map(|s| (s, capacity))
            });
            match created {
                Ok((scene, capacity)) => {
                    self.skeletons = Vec::with_capacity(capacity);
                    self.scene = Some(scene);
                    self.apply_controls(owner);
                }
                Err(error) => {
                    self.config_failed = true;
                    godot_error!(
                        "{}",
                        message(
                            &path_of(owner),
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

    /// Adds a `CrowdGazeCharacter` node (a child of its `Skeleton`) to the crowd, once; a
    /// skeleton that cannot be mapped is reported once and left out. `presence` is the
    /// node's (see [`Presence`]); it must be in the tree.
    pub fn register_character(
        &mut self,
        owner: &Spatial,
        node: TRef<Spatial>,
        inputs: CharacterInputs,
    ) {
        let key = node.get_instance_id();
        if self.refused.contains(&key) {
            return;
        }
        let Some(scene) = self.scene(owner) else {
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
                "a CrowdGazeCharacter must be a child of a Skeleton: move it under one".to_string(),
            ),
            Some(skeleton) => {
                claim_skeleton(skeleton.get_instance_id(), key, &path).and_then(|claim| {
                    let presence = inputs.presence;
                    inputs
                        .values
                        .settings()
                        .and_then(|settings| {
                            let handle = Handle {
                                node: key,
                                skeleton: skeleton.get_instance_id(),
                                kept: Some(Kept {
                                    stamp: presence.stamp(),
                                    presence,
                                    node: node.claim(),
                                    skeleton: skeleton.claim(),
                                }),
                                _claim: Some(Arc::new(claim)),
                                eyelids,
                            };
                            scene.add_character(
                                key,
                                handle,
                                &GodotSkeleton(skeleton),
                                &xform(&node.transform()),
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
    pub fn update_character(
        &mut self,
        owner: &Spatial,
        node: TRef<Spatial>,
        inputs: CharacterInputs,
    ) {
        let key = node.get_instance_id();
        let registered = self.scene.as_ref().and_then(|s| s.entity_of(key)).is_some();
        if !registered {
            self.refused.remove(&key);
            self.register_character(owner, node, inputs);
            return;
        }
        let Some(scene) = self.scene.as_mut() else {
            return;
        };
        let skeleton = skeleton_of(&node);
        let Some(skeleton) = skeleton else {
            return;
        };
        let result = inputs.values.settings().and_then(|settings| {
            scene.update_character(
                key,
                &GodotSkeleton(skeleton),
                &xform(&node.transform()),
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
        let eyelids = Self::find_eyelids(&mut self.reports, &node, &inputs);
        if let Some(handle) = self.scene.as_mut().and_then(|scene| {
            scene
                .character_slot(key)
                .and_then(|s| scene.character_handle_mut(s))
        }) {
            handle.eyelids = eyelids;
        }
    }

    /// The character's eyelid mesh; a path or shapes that do not fit are reported once.
    fn find_eyelids(
        reports: &mut Reports,
        node: &Spatial,
        inputs: &CharacterInputs,
    ) -> Option<EyelidMesh> {
        match eyelid_mesh(node, &inputs.eyelid_mesh, &inputs.eyelid_shapes) {
            Ok(eyelids) => eyelids,
            Err(error) => {
                if reports.first(node.get_instance_id(), "eyelids", &error) {
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

    /// A registered target's `look_at_height` or `impact` changed.
    pub fn update_target(
        &mut self,
        owner: &Spatial,
        node: TRef<Spatial>,
        look_at_height: f64,
        impact: f64,
    ) {
        let key = node.get_instance_id();
        let registered = self.scene.as_ref().and_then(|s| s.entity_of(key)).is_some();
        if !registered {
            self.refused.remove(&key);
            self.register_target(owner, node, look_at_height, impact);
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
    pub fn register_target(
        &mut self,
        owner: &Spatial,
        node: TRef<Spatial>,
        look_at_height: f64,
        impact: f64,
    ) {
        let key = node.get_instance_id();
        if self.refused.contains(&key) {
            return;
        }
        let Some(scene) = self.scene(owner) else {
            return;
        };
        if scene.entity_of(key).is_some() {
            return;
        }
        let handle = Handle {
            node: key,
            skeleton: 0,
            kept: None,
            _claim: None,
            eyelids: None,
        };
        let placed = xform(&node.global_transform());
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

    /// Registers the characters and targets already in the tree.
    fn adopt(&mut self, owner: &Spatial) {
        let Some(tree) = owner.get_tree() else {
            return;
        };
        // SAFETY: the scene tree outlives this call, on the main thread.
        let tree = unsafe { tree.assume_safe() };
        for variant in tree.get_nodes_in_group(CHARACTER_GROUP).iter() {
            let Some(node) = variant.try_to_object::<Spatial>() else {
                continue;
            };
            // SAFETY: as above, for a node in the tree.
            let Some(node) = (unsafe { node.assume_safe_if_sane() }) else {
                continue;
            };
            let settings = node
                .cast_instance::<crate::character::CrowdGazeCharacter>()
                .and_then(|instance| instance.map(|c, _| (c.settings(), c.crowd_path())).ok());
            if let Some((inputs, path)) = settings {
                if joins(owner, &node, &path) {
                    self.register_character(owner, node, inputs);
                }
            }
        }
        for variant in tree.get_nodes_in_group(TARGET_GROUP).iter() {
            let Some(node) = variant.try_to_object::<Spatial>() else {
                continue;
            };
            // SAFETY: as above.
            let Some(node) = (unsafe { node.assume_safe_if_sane() }) else {
                continue;
            };
            let settings = node
                .cast_instance::<crate::target::GazeTarget>()
                .and_then(|instance| instance.map(|t, _| (t.settings(), t.crowd_path())).ok());
            if let Some(((height, impact), path)) = settings {
                if joins(owner, &node, &path) {
                    self.register_target(owner, node, height, impact);
                }
            }
        }
    }

    /// One frame: read, step, write, report.
    fn frame(&mut self, owner: &Spatial, delta: f64) {
        let start = Instant::now();
        let camera = if self.camera_is_viewer {
            owner
                .get_viewport()
                // SAFETY: the viewport and its camera live on the main thread for this call.
                .and_then(|viewport| unsafe { viewport.assume_safe_if_sane() })
                .and_then(|viewport| viewport.get_camera())
                .and_then(|camera| unsafe { camera.assume_safe_if_sane() })
        } else {
            None
        };
        let viewer_impact = self.viewer_impact as f32;
        let Some(scene) = self.scene.as_mut() else {
            return;
        };
        // Read every character; drop those whose node or skeleton is gone.
        let skeletons = &mut self.skeletons;
        let reports = &mut self.reports;
        skeletons.clear();
        let mut slot = 0;
        while slot < scene.character_count() {
            let Some(handle) = scene.character_handle(slot) else {
                break;
            };
            // SAFETY: used within this call, on the main thread.
            match unsafe { handle.character() } {
                Some((node, skeleton)) => {
                    let placed = xform(&node.transform());
                    if let Err(error) =
                        scene.read_character(slot, &GodotSkeleton(skeleton), &placed)
                    {
                        if reports.first(node.get_instance_id(), "read", &error) {
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
                    skeletons.push(skeleton.claim());
                    slot += 1;
                }
                None => {
                    let key = handle.node;
                    scene.remove(key);
                    reports.forget(key);
                }
            }
        }
        let mut slot = 0;
        while slot < scene.target_count() {
            let Some(handle) = scene.target_handle(slot).cloned() else {
                break;
            };
            // SAFETY: an id taken from a Spatial, used within this call.
            match unsafe { live::<Spatial>(handle.node) } {
                Some(node) => {
                    if let Err(error) = scene.read_target(slot, &xform(&node.global_transform())) {
                        if reports.first(node.get_instance_id(), "read", &error) {
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
                _ => {
                    scene.remove(handle.node);
                }
            }
        }
        let viewer = camera.map(|camera| vec3(camera.global_transform().origin));
        let crowd_key = owner.get_instance_id();
        if let Err(error) = scene.set_viewer(viewer, viewer_impact) {
            if reports.first(crowd_key, "viewer", &error) {
                let error = format!("the camera as the viewer: {error}");
                godot_error!(
                    "{}",
                    message(&path_of(owner), "CrowdGaze._process", &error, "")
                );
            }
        }
        let read = start.elapsed();
        if let Err(error) = scene.step(delta as f32) {
            skeletons.clear();
            if reports.first(crowd_key, "step", &error) {
                godot_error!(
                    "{}",
                    message(
                        &path_of(owner),
                        "CrowdGaze._process",
                        &error,
                        "the frame is skipped"
                    )
                );
            }
            return;
        }
        let stepped = start.elapsed();
        // The skeletons read above (one per slot): nothing that could free them ran since.
        for (slot, skeleton) in skeletons.drain(..).enumerate() {
            // SAFETY: alive (above), used on the main thread within this call.
            let skeleton = unsafe { skeleton.assume_safe() };
            if let Err(error) = scene.write_character(slot, &mut GodotSkeleton(skeleton)) {
                let key = scene.character_key(slot).unwrap_or_default();
                if reports.first(key, "write", &error) {
                    godot_error!(
                        "{}",
                        message(&path_of(&skeleton), "CrowdGaze._process", &error, "")
                    );
                }
            }
            let eyelids = scene
                .character_handle_mut(slot)
                .and_then(|handle| handle.eyelids.take());
            if let Some(mut eyelids) = eyelids {
                eyelids.apply(scene, slot);
                if let Some(handle) = scene.character_handle_mut(slot) {
                    handle.eyelids = Some(eyelids);
                }
            }
        }
        let written = start.elapsed();
        self.frame_usec = [
            read.as_secs_f64() * 1e6,
            (stepped - read).as_secs_f64() * 1e6,
            (written - stepped).as_secs_f64() * 1e6,
        ];
        // Signals go out at the end of the frame, when no method of this node is running.
        let node_variant = |id: u32| match scene.node_of(id) {
            EntityNode::Character(handle) | EntityNode::Target(handle) => {
                node_of(handle.node).map(|node| node.to_variant())
            }
            EntityNode::Viewer => camera.map(|camera| camera.to_variant()),
            EntityNode::None => None,
        };
        for change in scene.interest_changes() {
            let Some(character) = scene
                .character_handle(change.slot)
                .and_then(|h| node_of(h.node))
            else {
                continue;
            };
            let character = character.to_variant();
            let (from, to) = (node_variant(change.from), node_variant(change.to));
            let emit = |signal: &str, target: Option<Variant>| {
                let arguments = [
                    signal.to_variant(),
                    character.clone(),
                    target.unwrap_or_default(),
                ];
                // SAFETY: a deferred call of a built-in method on the node itself.
                unsafe { owner.call_deferred("emit_signal", &arguments) };
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
            let Some(character) = scene
                .character_handle(start.slot)
                .and_then(|h| node_of(h.node))
            else {
                continue;
            };
            let arguments = [
                "character_followed_gaze".to_variant(),
                character.to_variant(),
                vector(start.point).to_variant(),
            ];
            // SAFETY: a deferred call of a built-in method on the node itself.
            unsafe { owner.call_deferred("emit_signal", &arguments) };
        }
    }

    /// The character slot of a node variant.
    fn slot_of(&self, character: &Variant) -> Option<usize> {
        self.scene.as_ref()?.character_slot(instance_id(character)?)
    }
}

#[methods]
impl CrowdGaze {
    fn _enter_tree(&mut self, owner: &Spatial) {
        boundary("CrowdGaze._enter_tree", (), || {
            owner.add_to_group(CROWD_GROUP, false);
            if in_editor() {
                // Found by the characters' warnings; nothing runs in the editor.
                owner.set_process(false);
                return;
            }
            on_main_thread_now();
            // After the scripts that animate in _process (AnimationPlayers run before any).
            if owner.process_priority() == 0 {
                owner.set_process_priority(100);
            }
            self.scene(owner);
            self.adopt(owner);
        })
    }

    fn _ready(&mut self, owner: &Spatial) {
        boundary("CrowdGaze._ready", (), || {
            if in_editor() {
                // Godot turns processing on after _enter_tree for a script with _process.
                owner.set_process(false);
            } else {
                self.adopt(owner)
            }
        })
    }

    fn _exit_tree(&mut self, owner: &Spatial) {
        boundary("CrowdGaze._exit_tree", (), || {
            owner.remove_from_group(CROWD_GROUP);
            self.scene = None;
            self.refused.clear();
            self.reports.clear();
            self.config_failed = false;
        })
    }

    fn _process(&mut self, owner: &Spatial, delta: Variant) {
        boundary("CrowdGaze._process", (), || {
            if in_editor() {
                return;
            }
            // Godot passes a float; a script calling it may pass anything.
            match number(&delta) {
                Some(delta) => self.frame(owner, delta),
                None => {
                    let error = "the delta must be a number of seconds";
                    if self
                        .reports
                        .first(owner.get_instance_id(), "_process", &error)
                    {
                        let path = path_of(owner);
                        let method = "CrowdGaze._process";
                        godot_error!("{}", message(&path, method, &error, "the frame is skipped"));
                    }
                }
            }
        })
    }

    /// The editor's configuration warnings: the settings, checked as when the node enters
    /// the tree.
    fn _get_configuration_warning(&self, _owner: &Spatial) -> String {
        boundary(
            "CrowdGaze._get_configuration_warning",
            String::new(),
            || check_crowd(&self.settings()).join("\n"),
        )
    }

    /// Number of characters in the crowd.
    fn get_character_count(&self, _owner: &Spatial) -> i64 {
        boundary("CrowdGaze.get_character_count", 0, || {
            self.scene
                .as_ref()
                .map_or(0, |s| s.character_count() as i64)
        })
    }

    /// Number of targets in the crowd.
    fn get_target_count(&self, _owner: &Spatial) -> i64 {
        boundary("CrowdGaze.get_target_count", 0, || {
            self.scene.as_ref().map_or(0, |s| s.target_count() as i64)
        })
    }

    /// What a character's eyes look at: a character or target node, the camera, or null.
    fn get_gaze_target(&self, owner: &Spatial, character: Variant) -> Variant {
        boundary("CrowdGaze.get_gaze_target", Variant::new(), || {
            let (Some(scene), Some(slot)) = (self.scene.as_ref(), self.slot_of(&character)) else {
                return Variant::new();
            };
            let Ok(gaze) = scene.gaze(slot) else {
                return Variant::new();
            };
            match scene.node_of(gaze.target) {
                EntityNode::Character(handle) | EntityNode::Target(handle) => {
                    node_of(handle.node).map_or_else(Variant::new, |node| node.to_variant())
                }
                EntityNode::Viewer => owner
                    .get_viewport()
                    .and_then(|viewport| unsafe { viewport.assume_safe_if_sane() })
                    .and_then(|viewport| viewport.get_camera())
                    .map_or_else(Variant::new, |camera| camera.to_variant()),
                EntityNode::None => Variant::new(),
            }
        })
    }

    /// The point a character's eyes are sent to (metres, world).
    fn get_gaze_point(&self, _owner: &Spatial, character: Variant) -> Vector3 {
        boundary("CrowdGaze.get_gaze_point", Vector3::zero(), || {
            self.slot_of(&character)
                .and_then(|slot| self.scene.as_ref()?.gaze(slot).ok())
                .map_or(Vector3::zero(), |gaze| vector(gaze.target_position))
        })
    }

    /// The point a character glances at because others stare there (gaze following), or
    /// null when it follows no one's gaze now (and for anything but a character of the
    /// crowd, or with `gaze_following` off).
    fn get_following(&self, _owner: &Spatial, character: Variant) -> Variant {
        boundary("CrowdGaze.get_following", Variant::new(), || {
            self.slot_of(&character)
                .and_then(|slot| self.scene.as_ref()?.following(slot).ok().flatten())
                .map_or_else(Variant::new, |point| vector(point).to_variant())
        })
    }

    /// True if a character attends to something.
    fn is_attending(&self, _owner: &Spatial, character: Variant) -> bool {
        boundary("CrowdGaze.is_attending", false, || {
            self.slot_of(&character)
                .and_then(|slot| self.scene.as_ref()?.gaze(slot).ok())
                .is_some_and(|gaze| gaze.attending)
        })
    }

    /// True once a character's gaze has arrived on its target and follows it.
    fn is_holding(&self, _owner: &Spatial, character: Variant) -> bool {
        boundary("CrowdGaze.is_holding", false, || {
            self.slot_of(&character)
                .and_then(|slot| self.scene.as_ref()?.is_holding(slot).ok())
                .unwrap_or(false)
        })
    }

    /// The bones of a character's gaze chain, bottom to top (spine, neck, head, eyes).
    fn get_chain_bones(&self, _owner: &Spatial, character: Variant) -> VariantArray {
        boundary(
            "CrowdGaze.get_chain_bones",
            VariantArray::new().into_shared(),
            || {
                let array = VariantArray::new();
                if let Some(bones) = self
                    .slot_of(&character)
                    .and_then(|slot| self.scene.as_ref()?.chain_bones(slot).ok())
                {
                    for &bone in bones {
                        array.push(bone as i64);
                    }
                }
                array.into_shared()
            },
        )
    }

    /// The library's final rotation of each chain joint (`base * delta`): local to its
    /// parent bone, the first one relative to the character node's frame.
    fn get_joint_rotations(&self, _owner: &Spatial, character: Variant) -> VariantArray {
        boundary(
            "CrowdGaze.get_joint_rotations",
            VariantArray::new().into_shared(),
            || {
                let array = VariantArray::new();
                let mut joints = [glam::Quat::IDENTITY;
                    crowdgaze_godot_adapter::crowdgaze::ik::MAX_CHAIN_JOINTS];
                if let Some(count) = self
                    .slot_of(&character)
                    .and_then(|slot| self.scene.as_ref()?.joint_rotations(slot, &mut joints).ok())
                {
                    for joint in &joints[..count] {
                        array.push(quat(*joint));
                    }
                }
                array.into_shared()
            },
        )
    }

    /// How high above a character's node its eyes are at rest (where others look), metres.
    fn get_look_at_height(&self, _owner: &Spatial, character: Variant) -> f64 {
        boundary("CrowdGaze.get_look_at_height", 0.0, || {
            self.slot_of(&character)
                .and_then(|slot| self.scene.as_ref()?.look_at_height(slot).ok())
                .map_or(0.0, f64::from)
        })
    }

    /// Makes a character look at `target` (a registered character or target node, the
    /// camera, or a `Vector3` point) whatever its attention says, until
    /// `clear_gaze_target`. Returns false (with an error) if either is unknown.
    fn set_gaze_target(&mut self, owner: &Spatial, character: Variant, target: Variant) -> bool {
        boundary("CrowdGaze.set_gaze_target", false, || {
            let slot = self.slot_of(&character);
            let Some(scene) = self.scene.as_mut() else {
                return false;
            };
            let explicit = if target.get_type() == VariantType::Vector3 {
                Some(ExplicitTarget::Point(vec3(target.to_vector3())))
            } else {
                instance_id(&target)
                    .and_then(|key| {
                        scene.entity_of(key).or_else(|| {
                            // The camera is the viewer.
                            let camera = owner
                                .get_viewport()
                                .and_then(|v| unsafe { v.assume_safe_if_sane() })
                                .and_then(|v| v.get_camera())
                                .and_then(|c| unsafe { c.assume_safe_if_sane() })?;
                            (camera.get_instance_id() == key)
                                .then(|| scene.viewer())
                                .flatten()
                        })
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
                    let key = owner.get_instance_id();
                    if self.reports.first(key, "set_gaze_target", &error) {
                        let method = "CrowdGaze.set_gaze_target";
                        godot_error!("{}", message(&path_of(owner), method, &error, ""));
                    }
                    false
                }
            }
        })
    }

    /// Gives a character back to its attention.
    fn clear_gaze_target(&mut self, _owner: &Spatial, character: Variant) -> bool {
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

    /// A character's eyelids after the last step: `Vector2(closure, lid_pitch)`, closure 0
    /// open to 1 closed (a blink), lid pitch in radians (positive up), both eyes' mean;
    /// `Vector2(0, 0)` for anything but a character of this crowd.
    fn get_eyelids(&self, _owner: &Spatial, character: Variant) -> Vector2 {
        boundary("CrowdGaze.get_eyelids", Vector2::zero(), || {
            self.slot_of(&character)
                .and_then(|slot| self.scene.as_ref()?.eyelid_summary(slot).ok())
                .map_or(Vector2::zero(), |(closure, pitch)| {
                    Vector2::new(closure, pitch)
                })
        })
    }

    /// A character's influence now (the crowd's times its own, fading), 0 to 1; 0 for
    /// anything but a character of this crowd.
    fn get_character_influence(&self, _owner: &Spatial, character: Variant) -> f64 {
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
    fn set_conversation(&mut self, owner: &Spatial, members: Variant) -> i64 {
        boundary("CrowdGaze.set_conversation", -1, || {
            let result = match (self.scene.as_mut(), members.try_to_array()) {
                (None, _) => Err("the crowd was not created (see the first error)".to_string()),
                (_, None) => Err(format!(
                    "members must be an Array of CrowdGazeCharacter nodes, not {}",
                    a_type(&members)
                )),
                (Some(scene), Some(array)) => {
                    let keys: Vec<i64> = array
                        .iter()
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
                if self
                    .reports
                    .first(owner.get_instance_id(), "set_conversation", &error)
                {
                    godot_error!(
                        "{}",
                        message(
                            &path_of(owner),
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
    fn remove_conversation(&mut self, owner: &Spatial, id: Variant) -> bool {
        boundary("CrowdGaze.remove_conversation", false, || {
            let result = match (self.scene.as_mut(), id.try_to_i64()) {
                (Some(scene), Some(id)) => scene.remove_conversation(id).map_err(|e| e.to_string()),
                (None, _) => Err("the crowd was not created (see the first error)".to_string()),
                (_, None) => Err(format!(
                    "id must be an int (from set_conversation), not {}",
                    a_type(&id)
                )),
            };
            result.map_or_else(
                |error| {
                    if self
                        .reports
                        .first(owner.get_instance_id(), "remove_conversation", &error)
                    {
                        godot_error!(
                            "{}",
                            message(&path_of(owner), "CrowdGaze.remove_conversation", &error, "")
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
    fn get_conversation(&self, _owner: &Spatial, character: Variant) -> i64 {
        boundary("CrowdGaze.get_conversation", -1, || {
            self.slot_of(&character)
                .and_then(|slot| self.scene.as_ref()?.conversation_of(slot).ok().flatten())
                .map_or(-1, i64::from)
        })
    }

    /// The last frame's cost in this node (reading the scene, stepping the crowd and
    /// writing the bones), microseconds.
    fn get_frame_usec(&self, _owner: &Spatial) -> f64 {
        self.frame_usec.iter().sum()
    }

    /// The last frame's cost in this node by part, microseconds: `[read, step, write]`.
    fn get_frame_parts_usec(&self, _owner: &Spatial) -> Vector3 {
        Vector3::new(
            self.frame_usec[0] as f32,
            self.frame_usec[1] as f32,
            self.frame_usec[2] as f32,
        )
    }
}
