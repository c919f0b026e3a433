//! The scene as a crowd: character, target and viewer nodes and their entity ids, the
//! frame's states pushed, the crowd stepped, the gaze written back, and the changes of
//! interest reported.
//!
//! A front end keeps one [`SceneCrowd`] per `CrowdGaze` node. Per frame: for each character
//! [`read_character`](SceneCrowd::read_character), for each target
//! [`read_target`](SceneCrowd::read_target), [`set_viewer`](SceneCrowd::set_viewer), then
//! [`step`](SceneCrowd::step), then for each character
//! [`write_character`](SceneCrowd::write_character), then
//! [`interest_changes`](SceneCrowd::interest_changes). After registration nothing allocates.

use std::collections::HashMap;

use crowdgaze::attention::CharacterParams;
use crowdgaze::crowd::EyelidState;
use crowdgaze::ik::{GazePhase, MAX_CHAIN_JOINTS};
use crowdgaze::scene::ids::NO_ENTITY;
use crowdgaze::scene::EntityUpdate;
use crowdgaze::{CharacterDesc, Crowd, CrowdConfig, Error, GazeInfo, ObjectDesc, Result};
use glam::{Quat, Vec3};

pub use crate::character::CharacterSettings;
use crate::fade::{Controls, Fade};
use crate::lids::BlinkWriter;
use crate::skeleton::{
    character_frame, prefetch_bytes, BoundSkeleton, PoseConvention, SkeletonAccess,
};

/// A character's skeleton hierarchy (chain bones' and the chain root's ancestors' parents)
/// is checked for changes every this many frames (staggered); its bone count every frame.
pub const HIERARCHY_PERIOD: u8 = 8;
use crate::xform::Xform;

/// A node's key: an id that names it for as long as it lives (Godot's instance id).
pub type NodeKey = i64;

/// A registered character (its small fields first, then the skeleton: see
/// [`prefetch`](Self::prefetch)).
#[derive(Debug)]
#[repr(C)]
struct Character<H> {
    key: NodeKey,
    id: u32,
    /// Its eyes' target after the last step, to report changes.
    target: u32,
    /// True while its transforms are not finite: it keeps its last state.
    stalled: bool,
    /// True if it was read this frame (and is pushed and written).
    fresh: bool,
    /// True while its skeleton cannot be mapped since its bones changed: it keeps its last
    /// state and its bones are left alone.
    unmapped: bool,
    /// Frames until its hierarchy is checked again.
    countdown: u8,
    /// The bone count of the last mapping that failed (not tried again until it changes).
    failed_count: Option<usize>,
    /// True if it glanced where others stare (gaze following) after the last step.
    following: bool,
    /// Its influence, fading to its controls' goal.
    fade: Fade,
    /// The influence its bones were last written with (0: not written, or the base pose
    /// written back): while both it and the influence are 0 its bones are left alone.
    written_weight: f32,
    /// The attention parameters the crowd drew for it (its own fraction and model go on
    /// top).
    drawn: CharacterParams,
    settings: CharacterSettings,
    handle: H,
    skeleton: BoundSkeleton,
}

impl<H> Character<H> {
    /// Prefetches what reading or writing the character touches (see
    /// [`BoundSkeleton::prefetch`]).
    fn prefetch(&self) {
        let start = self as *const Self as usize;
        prefetch_bytes(start, &self.skeleton as *const BoundSkeleton as usize);
        self.skeleton.prefetch();
    }
}

/// A character whose eyes moved to another target in the last step.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct InterestChange {
    /// The character's slot.
    pub slot: usize,
    /// The target it looked at before ([`NO_ENTITY`] for none; the id of a removed node
    /// names no node).
    pub from: u32,
    /// The target it looks at now ([`NO_ENTITY`] for none).
    pub to: u32,
}

/// A character that started to glance where others stare (gaze following) in the last
/// step.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FollowStart {
    /// The character's slot.
    pub slot: usize,
    /// The point it glances at, world metres.
    pub point: Vec3,
}

/// A registered scene object.
#[derive(Debug)]
struct Target<H> {
    key: NodeKey,
    handle: H,
    id: u32,
    look_at_height: f32,
    stalled: bool,
}

/// What an entity id is in the scene.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum EntityNode<'a, H> {
    /// A character node.
    Character(&'a H),
    /// A target node.
    Target(&'a H),
    /// The viewer (the camera).
    Viewer,
    /// Nothing (no target, or an id no longer in the scene).
    None,
}

/// Where an entity id lives.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Slot {
    Character(usize),
    Target(usize),
}

/// One `CrowdGaze` node's crowd and the nodes in it. Not safe for concurrent mutation.
#[derive(Debug)]
pub struct SceneCrowd<H> {
    crowd: Crowd,
    convention: PoseConvention,
    characters: Vec<Character<H>>,
    targets: Vec<Target<H>>,
    by_key: HashMap<NodeKey, u32>,
    slots: HashMap<u32, Slot>,
    viewer: Option<u32>,
    viewer_position: Option<Vec3>,
    /// This frame's entity states (capacity for every entity: no allocation per frame).
    updates: Vec<EntityUpdate>,
    /// Characters whose eyes' target changed in the last step.
    changes: Vec<InterestChange>,
    /// True if the crowd's characters follow others' gaze.
    following: bool,
    /// Characters that started to follow someone's gaze in the last step.
    follows: Vec<FollowStart>,
    /// The crowd-wide influence (`CrowdGaze`'s controls), times each character's.
    fade: Fade,
    /// Scratch for one character's joints.
    joints: [Quat; MAX_CHAIN_JOINTS],
    time: f64,
    /// `max_characters` as configured (the library's crowd holds one more, so that a
    /// character can be re-mapped in a full crowd: new chain added before the old removed).
    max_characters: usize,
}

/// A character's attention parameters: those the crowd drew, with the settings' own
/// fraction and model.
fn params_for(drawn: &CharacterParams, settings: &CharacterSettings) -> CharacterParams {
    CharacterParams {
        attention_fraction: settings
            .attention_fraction
            .unwrap_or(drawn.attention_fraction),
        model: settings.attention_model,
        ..*drawn
    }
}

impl<H> SceneCrowd<H> {
    /// A crowd with `config` (its world must be Godot's: Y up, +Z forward, metres, the
    /// library's default) for skeletons whose poses follow `convention`.
    pub fn new(config: CrowdConfig, convention: PoseConvention) -> Result<SceneCrowd<H>> {
        let world = crowdgaze::World::y_up();
        if config.world != world {
            return Err(Error::InvalidArgument(
                "a Godot crowd's world is Y up, +Z forward, in metres".into(),
            ));
        }
        config.validate()?;
        let entities = (config.max_characters + config.max_objects) as usize + 2;
        let characters = config.max_characters as usize;
        let spare = CrowdConfig {
            max_characters: config.max_characters.saturating_add(1),
            ..config
        };
        Ok(SceneCrowd {
            crowd: Crowd::new(spare)?,
            max_characters: characters,
            convention,
            characters: Vec::with_capacity(characters),
            targets: Vec::new(),
            by_key: HashMap::with_capacity(entities),
            slots: HashMap::with_capacity(entities),
            viewer: None,
            viewer_position: None,
            updates: Vec::with_capacity(entities),
            changes: Vec::with_capacity(characters),
            following: config.following.enabled,
            follows: Vec::with_capacity(if config.following.enabled {
                characters
            } else {
                0
            }),
            fade: Fade::FULL,
            joints: [Quat::IDENTITY; MAX_CHAIN_JOINTS],
            time: 0.0,
        })
    }

    /// The crowd (for reading gaze, chains and joints).
    pub fn crowd(&self) -> &Crowd {
        &self.crowd
    }

    /// The crowd, for game logic (explicit targets, parameters). Removing entities through
    /// it leaves their nodes registered here: use [`remove`](Self::remove).
    pub fn crowd_mut(&mut self) -> &mut Crowd {
        &mut self.crowd
    }

    /// Number of registered characters.
    pub fn character_count(&self) -> usize {
        self.characters.len()
    }

    /// Number of registered targets.
    pub fn target_count(&self) -> usize {
        self.targets.len()
    }

    /// The handle of character `slot` (`0 .. character_count()`).
    pub fn character_handle(&self, slot: usize) -> Option<&H> {
        self.characters.get(slot).map(|c| &c.handle)
    }

    /// The handle of character `slot`, to change what the front end keeps in it.
    pub fn character_handle_mut(&mut self, slot: usize) -> Option<&mut H> {
        self.characters.get_mut(slot).map(|c| &mut c.handle)
    }

    /// The handle of target `slot` (`0 .. target_count()`).
    pub fn target_handle(&self, slot: usize) -> Option<&H> {
        self.targets.get(slot).map(|t| &t.handle)
    }

    /// The entity id of a registered node.
    pub fn entity_of(&self, key: NodeKey) -> Option<u32> {
        self.by_key.get(&key).copied()
    }

    /// The character slot of a registered character node.
    pub fn character_slot(&self, key: NodeKey) -> Option<usize> {
        match self.slots.get(&self.entity_of(key)?) {
            Some(Slot::Character(slot)) => Some(*slot),
            _ => None,
        }
    }

    /// The node behind an entity id.
    pub fn node_of(&self, id: u32) -> EntityNode<'_, H> {
        if Some(id) == self.viewer && id != NO_ENTITY {
            return EntityNode::Viewer;
        }
        match self.slots.get(&id) {
            Some(Slot::Character(slot)) => EntityNode::Character(&self.characters[*slot].handle),
            Some(Slot::Target(slot)) => EntityNode::Target(&self.targets[*slot].handle),
            None => EntityNode::None,
        }
    }

    /// Registers a character node: maps its skeleton's bones to a gaze chain and adds it to
    /// the crowd at its node's place. `node` is the character node's transform relative to
    /// its skeleton (the node is the skeleton's child: identity unless the model faces
    /// elsewhere than the character).
    ///
    /// Errors (nothing is added): the node is registered already, the skeleton has no
    /// recognisable head (the message lists its bones) or another mapping error, a
    /// transform is not finite, the crowd is full.
    pub fn add_character(
        &mut self,
        key: NodeKey,
        handle: H,
        skeleton: &impl SkeletonAccess,
        node: &Xform,
        settings: &CharacterSettings,
    ) -> Result<u32> {
        if self.by_key.contains_key(&key) {
            return Err(Error::InvalidArgument(
                "the node is registered already".into(),
            ));
        }
        if self.characters.len() >= self.max_characters {
            return Err(Error::Capacity(format!(
                "the crowd already holds max_characters = {} characters",
                self.max_characters
            )));
        }
        let (bound, id, drawn) = self.add_entity(skeleton, node, settings)?;
        self.by_key.insert(key, id);
        self.slots
            .insert(id, Slot::Character(self.characters.len()));
        self.characters.push(Character {
            key,
            handle,
            id,
            skeleton: bound,
            stalled: false,
            fresh: false,
            unmapped: false,
            countdown: (self.characters.len() % usize::from(HIERARCHY_PERIOD)) as u8,
            failed_count: None,
            fade: Fade::at(settings.controls.goal()),
            following: false,
            written_weight: 0.0,
            drawn,
            settings: settings.clone(),
            target: NO_ENTITY,
        });
        Ok(id)
    }

    /// Registers a scene object: a target at the node's origin whose look-at point is
    /// `look_at_height` metres above it, of interest `impact`.
    pub fn add_target(
        &mut self,
        key: NodeKey,
        handle: H,
        node: &Xform,
        look_at_height: f32,
        impact: f32,
    ) -> Result<u32> {
        if self.by_key.contains_key(&key) {
            return Err(Error::InvalidArgument(
                "the node is registered already".into(),
            ));
        }
        if !node.is_finite() {
            return Err(Error::NonFinite(
                "the target's global transform is not finite".into(),
            ));
        }
        let (position, heading, _) = character_frame(node);
        let id = self.crowd.add_object(&ObjectDesc {
            position,
            heading,
            look_at_height,
            impact,
        })?;
        self.by_key.insert(key, id);
        self.slots.insert(id, Slot::Target(self.targets.len()));
        self.targets.push(Target {
            key,
            handle,
            id,
            look_at_height,
            stalled: false,
        });
        Ok(id)
    }

    /// Removes a character or target node from the crowd (at once: characters looking at
    /// it look elsewhere from the next step). Returns its handle, `None` if it was not
    /// registered.
    pub fn remove(&mut self, key: NodeKey) -> Option<H> {
        let id = self.by_key.remove(&key)?;
        let slot = self.slots.remove(&id)?;
        // The crowd knows the id: the adapter added it and nothing else removes it.
        let _ = self.crowd.remove_entity(id);
        let handle = match slot {
            Slot::Character(slot) => {
                let removed = self.characters.swap_remove(slot);
                if let Some(moved) = self.characters.get(slot) {
                    self.slots.insert(moved.id, Slot::Character(slot));
                }
                // Pending changes follow the character moved into the slot.
                let moved_from = self.characters.len();
                self.changes.retain(|change| change.slot != slot);
                for change in &mut self.changes {
                    if change.slot == moved_from {
                        change.slot = slot;
                    }
                }
                removed.handle
            }
            Slot::Target(slot) => {
                let removed = self.targets.swap_remove(slot);
                if let Some(moved) = self.targets.get(slot) {
                    self.slots.insert(moved.id, Slot::Target(slot));
                }
                removed.handle
            }
        };
        // Characters that looked at it keep its (never reused) id as their last target, so
        // the next step reports their change.
        Some(handle)
    }

    /// Maps a skeleton to a chain (with the settings' limits) and adds it to the crowd as a
    /// character with the settings' attention parameters: the binding, the entity id and
    /// the parameters the crowd drew.
    fn add_entity(
        &mut self,
        skeleton: &impl SkeletonAccess,
        node: &Xform,
        settings: &CharacterSettings,
    ) -> Result<(BoundSkeleton, u32, CharacterParams)> {
        let (bound, chain) =
            BoundSkeleton::bind(skeleton, node, &settings.bone_map, self.convention)?;
        let chain = settings.limit_chain(&chain)?;
        let (position, heading, _) = character_frame(&skeleton.global_transform().mul(node));
        let id = self.crowd.add_character(&CharacterDesc {
            position,
            heading,
            impact: settings.impact,
            chain: Some(chain),
            ..CharacterDesc::default()
        })?;
        let drawn = self.crowd.character_params(id)?;
        if let Err(error) = self
            .crowd
            .set_character_params(id, &params_for(&drawn, settings))
        {
            let _ = self.crowd.remove_entity(id);
            return Err(error);
        }
        Ok((bound, id, drawn))
    }

    /// Maps character `slot`'s skeleton again (its bones or its settings changed): a new
    /// chain, a new entity id (others looking at it look elsewhere). With `settings`, they
    /// become the character's. On an error nothing changes.
    fn remap(
        &mut self,
        slot: usize,
        skeleton: &impl SkeletonAccess,
        node: &Xform,
        settings: Option<&CharacterSettings>,
    ) -> Result<()> {
        let character = self
            .characters
            .get(slot)
            .ok_or_else(|| Error::InvalidArgument(format!("there is no character {slot}")))?;
        let settings = settings.unwrap_or(&character.settings).clone();
        // The crowd has room for one more: the new entity first, so that a failure leaves
        // the old one.
        let (bound, id, drawn) = self.add_entity(skeleton, node, &settings)?;
        let character = &mut self.characters[slot];
        character.drawn = drawn;
        let old = character.id;
        let _ = self.crowd.remove_entity(old);
        self.slots.remove(&old);
        self.slots.insert(id, Slot::Character(slot));
        self.by_key.insert(character.key, id);
        character.id = id;
        let mut bound = bound;
        bound.carry_over(&character.skeleton);
        character.skeleton = bound;
        settings.controls.apply(&mut character.fade);
        character.written_weight = 0.0;
        character.settings = settings;
        character.unmapped = false;
        character.failed_count = None;
        character.stalled = false;
        Ok(())
    }

    /// A registered character's settings changed: a new bone map or new limits map the
    /// skeleton again, the rest is set (impact, attention parameters, controls, talking).
    /// On an error (a bone map that does not parse or map, a value out of range) the
    /// character keeps its previous settings. Errors if the node is not a registered
    /// character.
    pub fn update_character(
        &mut self,
        key: NodeKey,
        skeleton: &impl SkeletonAccess,
        node: &Xform,
        settings: &CharacterSettings,
    ) -> Result<()> {
        let slot = self
            .character_slot(key)
            .ok_or_else(|| Error::NotFound("the node is not a character of the crowd".into()))?;
        let character = &self.characters[slot];
        if settings.chain_differs(&character.settings) || character.unmapped {
            return self.remap(slot, skeleton, node, Some(settings));
        }
        if settings.impact != character.settings.impact {
            self.crowd.set_impact(character.id, settings.impact)?;
            self.characters[slot].settings.impact = settings.impact;
        }
        let character = &self.characters[slot];
        if settings.attention_fraction != character.settings.attention_fraction
            || settings.attention_model != character.settings.attention_model
        {
            let params = params_for(&character.drawn, settings);
            self.crowd.set_character_params(character.id, &params)?;
        }
        let character = &mut self.characters[slot];
        settings.controls.apply(&mut character.fade);
        character.settings = settings.clone();
        Ok(())
    }

    /// A registered target's settings changed: its look-at height (metres) and impact.
    /// On an error nothing changes.
    pub fn update_target(&mut self, key: NodeKey, look_at_height: f32, impact: f32) -> Result<()> {
        let slot = match self.entity_of(key).and_then(|id| self.slots.get(&id)) {
            Some(Slot::Target(slot)) => *slot,
            _ => {
                return Err(Error::NotFound(
                    "the node is not a target of the crowd".into(),
                ))
            }
        };
        let target = &mut self.targets[slot];
        if !(impact.is_finite() && (0.0..=1e6).contains(&impact)) {
            return Err(Error::InvalidArgument(format!(
                "impact = {impact}: it must be from 0 to 1000000"
            )));
        }
        self.crowd.set_look_at_height(target.id, look_at_height)?;
        self.crowd.set_impact(target.id, impact)?;
        target.look_at_height = look_at_height;
        Ok(())
    }

    /// Makes the viewer (the active camera) an entity at `position`, or removes it with
    /// `None`. Its interest is `impact`. Call once per frame before [`step`](Self::step);
    /// its velocity comes from the frames.
    pub fn set_viewer(&mut self, position: Option<Vec3>, impact: f32) -> Result<()> {
        match position {
            Some(position) => {
                if !position.is_finite() {
                    return Err(Error::NonFinite(
                        "the camera's position is not finite".into(),
                    ));
                }
                match self.viewer {
                    None => self.viewer = Some(self.crowd.set_viewer(position, impact)?),
                    Some(id) => self.crowd.set_impact(id, impact)?,
                }
                self.viewer_position = Some(position);
            }
            None => {
                if let Some(id) = self.viewer.take() {
                    self.crowd.remove_entity(id)?;
                }
                self.viewer_position = None;
            }
        }
        Ok(())
    }

    /// The viewer's entity id, if there is one.
    pub fn viewer(&self) -> Option<u32> {
        self.viewer
    }

    /// Reads character `slot`: its node's transform relative to its skeleton, `node`, and
    /// the skeleton's place and animated pose. On a NaN or infinite transform the character keeps its last state
    /// (position, base pose, bones) until its transforms are finite again; the error is
    /// returned once, when that starts.
    pub fn read_character(
        &mut self,
        slot: usize,
        skeleton: &impl SkeletonAccess,
        node: &Xform,
    ) -> Result<()> {
        let character = self
            .characters
            .get_mut(slot)
            .ok_or_else(|| Error::InvalidArgument(format!("there is no character {slot}")))?;
        character.fresh = false;
        // The skeleton's bones: their count each frame, the chain's parents every
        // HIERARCHY_PERIOD frames. A change maps the skeleton again.
        let count = skeleton.bone_count();
        let due = character.countdown == 0;
        character.countdown = match character.countdown {
            0 => HIERARCHY_PERIOD - 1,
            n => n - 1,
        };
        let changed = if character.unmapped {
            character.failed_count != Some(count)
        } else {
            count != character.skeleton.bone_count
                || (due && character.skeleton.hierarchy_changed(skeleton))
        };
        if changed {
            if let Err(error) = self.remap(slot, skeleton, node, None) {
                let character = &mut self.characters[slot];
                character.unmapped = true;
                character.failed_count = Some(count);
                return Err(error);
            }
        }
        if self.characters[slot].unmapped {
            return Ok(());
        }
        if let Some(next) = self.characters.get(slot + 1) {
            next.prefetch();
        }
        let character = &mut self.characters[slot];
        match character.skeleton.read(skeleton, node) {
            Ok(read) => {
                let joints = character.skeleton.joint_count;
                self.crowd
                    .set_base_pose(character.id, &read.base[..joints])?;
                character.stalled = false;
                character.fresh = true;
                self.updates.push(EntityUpdate {
                    id: character.id,
                    position: read.position,
                    heading: read.heading,
                    heading_from_motion: false,
                    velocity: None,
                    talking: character.settings.talking,
                });
                Ok(())
            }
            Err(error) => {
                let first = !character.stalled;
                character.stalled = true;
                if first {
                    Err(error)
                } else {
                    Ok(())
                }
            }
        }
    }

    /// Reads target `slot` at its node's global transform `node`. A NaN or infinite
    /// transform keeps it where it was; the error is returned once, when that starts.
    pub fn read_target(&mut self, slot: usize, node: &Xform) -> Result<()> {
        let target = self
            .targets
            .get_mut(slot)
            .ok_or_else(|| Error::InvalidArgument(format!("there is no target {slot}")))?;
        if !node.is_finite() {
            let first = !target.stalled;
            target.stalled = true;
            return if first {
                Err(Error::NonFinite(
                    "the target's global transform is not finite".into(),
                ))
            } else {
                Ok(())
            };
        }
        target.stalled = false;
        let (position, heading, _) = character_frame(node);
        self.updates.push(EntityUpdate {
            id: target.id,
            position,
            heading,
            heading_from_motion: false,
            velocity: None,
            talking: false,
        });
        Ok(())
    }

    /// Pushes the frame read since the last step (`dt` seconds after it) and steps the
    /// crowd. Characters and targets not read this frame keep their last state.
    pub fn step(&mut self, dt: f32) -> Result<()> {
        if !dt.is_finite() {
            self.updates.clear();
            return Err(Error::NonFinite(format!(
                "the frame's delta is {dt}: it must be finite"
            )));
        }
        // Godot 3 sometimes hands a negative delta (godotengine/godot#26887): no time passed.
        let dt = dt.max(0.0);
        if let (Some(id), Some(position)) = (self.viewer, self.viewer_position) {
            self.updates.push(EntityUpdate {
                id,
                position,
                heading: 0.0,
                heading_from_motion: true,
                velocity: None,
                talking: false,
            });
        }
        self.time += f64::from(dt);
        self.fade.advance(dt);
        let pushed = self.crowd.push_frame(self.time, &self.updates);
        self.updates.clear();
        pushed?;
        self.crowd.step(dt)?;
        self.changes.clear();
        self.follows.clear();
        // One pass over the characters: their fades, their targets' changes, and (with gaze
        // following on) the glances they start.
        for (slot, character) in self.characters.iter_mut().enumerate() {
            character.fade.advance(dt);
            let target = self
                .crowd
                .gaze(character.id)
                .map_or(NO_ENTITY, |g| g.target);
            if target != character.target {
                self.changes.push(InterestChange {
                    slot,
                    from: character.target,
                    to: target,
                });
                character.target = target;
            }
            if self.following {
                let point = self.crowd.following(character.id).ok().and_then(|f| f.0);
                if let (Some(point), false) = (point, character.following) {
                    self.follows.push(FollowStart { slot, point });
                }
                character.following = point.is_some();
            }
        }
        Ok(())
    }

    /// Writes character `slot`'s gaze to its skeleton's chain bones (if it was read this
    /// frame; a stalled character's bones are left alone), blended from the animated pose
    /// by its influence (the crowd's times its own), and its upper lids if the skeleton has
    /// lid bones. At influence 0 the animated pose is written back once, then the bones are
    /// left alone until the influence rises again.
    pub fn write_character(
        &mut self,
        slot: usize,
        skeleton: &mut impl SkeletonAccess,
    ) -> Result<()> {
        let character = self
            .characters
            .get_mut(slot)
            .ok_or_else(|| Error::InvalidArgument(format!("there is no character {slot}")))?;
        if !character.fresh {
            return Ok(());
        }
        if let Some(next) = self.characters.get(slot + 1) {
            next.prefetch();
        }
        let character = &mut self.characters[slot];
        let weight = self.fade.value() * character.fade.value();
        if weight <= 0.0 && character.written_weight <= 0.0 {
            return Ok(());
        }
        let joints = character.skeleton.joint_count;
        self.crowd
            .read_joints_of(character.id, false, &mut self.joints[..joints])?;
        character
            .skeleton
            .write(skeleton, &self.joints[..joints], weight);
        if character.skeleton.has_lids() {
            let lids = self.crowd.eyelids(character.id)?;
            character.skeleton.write_lids(skeleton, &lids, weight);
        }
        character.written_weight = weight;
        Ok(())
    }

    /// The characters whose eyes' target changed in the last step (target ids,
    /// [`NO_ENTITY`] for none). Map ids to nodes with [`node_of`](Self::node_of).
    pub fn interest_changes(&self) -> &[InterestChange] {
        &self.changes
    }

    /// The characters that started to glance where others stare in the last step (gaze
    /// following; empty when it is off).
    pub fn follow_starts(&self) -> &[FollowStart] {
        &self.follows
    }

    /// The point character `slot` glances at because others stare there (gaze following),
    /// world metres; `None` when it follows no one's gaze now, or following is off.
    pub fn following(&self, slot: usize) -> Result<Option<Vec3>> {
        Ok(self.crowd.following(self.character(slot)?.id)?.0)
    }

    /// Sets the crowd-wide controls (the `CrowdGaze` node's `active`, `influence` and
    /// `influence_fade_time`): every character's influence is multiplied by the crowd's.
    pub fn set_controls(&mut self, controls: &Controls) {
        controls.apply(&mut self.fade);
    }

    /// The crowd-wide influence now, 0 to 1.
    pub fn crowd_influence(&self) -> f32 {
        self.fade.value()
    }

    /// Character `slot`'s influence now (the crowd's times its own), 0 to 1.
    pub fn influence(&self, slot: usize) -> Result<f32> {
        Ok(self.fade.value() * self.character(slot)?.fade.value())
    }

    /// Character `slot`'s eyelids after the last step (closure and lid pitch, as the
    /// library computes them, whatever the influence).
    pub fn eyelids(&self, slot: usize) -> Result<EyelidState> {
        self.crowd.eyelids(self.character(slot)?.id)
    }

    /// Character `slot`'s eyelids for a script: the mean closure of both eyes (0 open, 1
    /// closed) and their lids' mean pitch (radians, positive up).
    pub fn eyelid_summary(&self, slot: usize) -> Result<(f32, f32)> {
        let lids = self.eyelids(slot)?;
        Ok((
            0.5 * (lids.left_closure + lids.right_closure),
            0.5 * (lids.left_lid_pitch + lids.right_lid_pitch),
        ))
    }

    /// The blink shape values to set for character `slot` this frame (see
    /// [`BlinkWriter::frame`]); none if the slot is not a character's.
    pub fn blink_values(&self, slot: usize, writer: &mut BlinkWriter) -> [Option<(usize, f32)>; 2] {
        match (self.eyelids(slot), self.influence(slot)) {
            (Ok(lids), Ok(weight)) => writer.frame(lids.left_closure, lids.right_closure, weight),
            _ => [None, None],
        }
    }

    /// The upper-lid bones found in character `slot`'s skeleton (left, right).
    pub fn lid_bones(&self, slot: usize) -> Result<[Option<usize>; 2]> {
        Ok(self.character(slot)?.skeleton.lid_bones())
    }

    /// Makes the characters of nodes `members` (2 to 8, each in no other conversation) a
    /// group standing together and talking; returns the group's id. Errors name the
    /// member that is not a character of the crowd (by its position in `members`).
    pub fn set_conversation(&mut self, members: &[NodeKey]) -> Result<u32> {
        let mut ids = [NO_ENTITY; crowdgaze::attention::conversation::MAX_MEMBERS];
        if members.len() > ids.len() || members.len() < 2 {
            return Err(Error::InvalidArgument(format!(
                "a conversation has 2 to {} members, not {}",
                ids.len(),
                members.len()
            )));
        }
        for (k, &key) in members.iter().enumerate() {
            ids[k] = self
                .character_slot(key)
                .map(|slot| self.characters[slot].id)
                .ok_or_else(|| {
                    Error::NotFound(format!(
                        "member {k} is not a character of this crowd (give CrowdGazeCharacter \
                         nodes that joined it)"
                    ))
                })?;
        }
        self.crowd.set_conversation(&ids[..members.len()])
    }

    /// Ends conversation `id` (as a script holds it: any integer): its members go back to
    /// their own attention.
    pub fn remove_conversation(&mut self, id: i64) -> Result<()> {
        let id = u32::try_from(id)
            .map_err(|_| Error::NotFound(format!("there is no conversation {id}")))?;
        self.crowd.remove_conversation(id)
    }

    /// The conversation character `slot` is in, if any.
    pub fn conversation_of(&self, slot: usize) -> Result<Option<u32>> {
        self.crowd.conversation_of(self.character(slot)?.id)
    }

    /// Where character `slot` looks after the last step.
    pub fn gaze(&self, slot: usize) -> Result<GazeInfo> {
        self.crowd.gaze(self.character(slot)?.id)
    }

    /// True once character `slot`'s gaze has arrived on its target and follows it.
    pub fn is_holding(&self, slot: usize) -> Result<bool> {
        Ok(self.crowd.gaze_motion(self.character(slot)?.id)?.phase() == GazePhase::Holding)
    }

    /// The final local rotations of character `slot`'s chain joints (`base * delta`, the
    /// first in the character frame), as the library returned them; `out` must hold one per
    /// joint. Returns how many.
    pub fn joint_rotations(&self, slot: usize, out: &mut [Quat]) -> Result<usize> {
        self.crowd
            .read_joints_of(self.character(slot)?.id, false, out)
    }

    /// The chain bones of character `slot`, bottom to top (spine, neck, head, eyes).
    pub fn chain_bones(&self, slot: usize) -> Result<&[usize]> {
        Ok(self.character(slot)?.skeleton.chain_bones())
    }

    /// The mapping report of character `slot`'s skeleton: its chain, the role of each chain
    /// bone and the mapping's notes (see
    /// [`MappedChain::report`](crowdgaze::skeleton_map::MappedChain::report)).
    pub fn mapping_report(&self, slot: usize) -> Result<&str> {
        Ok(&self.character(slot)?.skeleton.report)
    }

    /// How high above its node's origin character `slot` is looked at (its rest eye
    /// height), metres.
    pub fn look_at_height(&self, slot: usize) -> Result<f32> {
        let id = self.character(slot)?.id;
        Ok(self.crowd.chain(id)?.look_at_height(Vec3::Y))
    }

    /// The look-at height of target `slot`, metres.
    pub fn target_look_at_height(&self, slot: usize) -> Result<f32> {
        self.targets
            .get(slot)
            .map(|t| t.look_at_height)
            .ok_or_else(|| Error::InvalidArgument(format!("there is no target {slot}")))
    }

    /// The key of character `slot`.
    pub fn character_key(&self, slot: usize) -> Option<NodeKey> {
        self.characters.get(slot).map(|c| c.key)
    }

    /// The key of target `slot`.
    pub fn target_key(&self, slot: usize) -> Option<NodeKey> {
        self.targets.get(slot).map(|t| t.key)
    }

    fn character(&self, slot: usize) -> Result<&Character<H>> {
        self.characters
            .get(slot)
            .ok_or_else(|| Error::InvalidArgument(format!("there is no character {slot}")))
    }
}
