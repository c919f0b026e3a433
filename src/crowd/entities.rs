//! Adding, changing and removing the crowd's entities between steps: characters (with
//! their chains and attention parameters), objects, the viewer, base poses, explicit
//! targets and attention periods.

use glam::{Quat, Vec3};

use super::config::{check_count, check_range};
use super::model_state::ModelState;
use super::states::AttentionLod;
use super::tables::StoredTarget;
use super::values::{CharacterDesc, ExplicitTarget, ObjectDesc, TargetPriority};
use super::Crowd;
use crate::attention::CharacterParams;
use crate::error::{ensure_all_finite, ensure_finite, Error, Result};
use crate::ik::eyelids::character_seed;
use crate::ik::{BlinkState, GazeChain, GazeMotion, MAX_CHAIN_JOINTS};
use crate::math::packed::PackedQuat;
use crate::math::random::{stream, Purpose};
use crate::scene::ids::EntityKind;

impl Crowd {
    fn check_impact(impact: f32) -> Result<()> {
        check_range(impact, 0.0, 1e6, "impact")
    }

    fn check_params(params: &CharacterParams) -> Result<()> {
        crate::error::ensure_all_finite(&params.weights.to_array(), "weights")?;
        let sum: f32 = params.weights.to_array().iter().sum();
        if params.weights.to_array().iter().any(|w| *w < 0.0) || (sum - 1.0).abs() > 1e-3 {
            return Err(Error::InvalidArgument(
                "weights must be non-negative and sum to 1".into(),
            ));
        }
        check_range(params.attention_fraction, 0.0, 1.0, "attention_fraction")
    }

    /// Adds a character; returns its id.
    pub fn add_character(&mut self, desc: &CharacterDesc) -> Result<u32> {
        crate::error::ensure_all_finite(&desc.position.to_array(), "position")?;
        ensure_finite(desc.heading, "heading")?;
        Self::check_impact(desc.impact)?;
        if let Some(params) = &desc.params {
            Self::check_params(params)?;
        }
        self.ensure_online("add a character")?;
        let params = desc.params.unwrap_or_else(|| {
            let mut random = stream(
                self.shared.config.seed,
                Purpose::CharacterParams,
                self.shared.characters_created,
            );
            let mut params =
                CharacterParams::random(&mut random, self.shared.config.attention_fraction_range);
            params.model = desc.model;
            params
        });
        let world = self.shared.config.world;
        let chain = match desc.chain {
            Some(chain) => {
                chain.validate()?;
                chain
            }
            None => GazeChain::human(world.up, world.forward),
        };
        let known_chain = self.shared.chains.find(&chain);
        if known_chain.is_none()
            && self.character_count() < self.shared.config.max_characters as usize
        {
            // Room for a new distinct chain, before anything changes.
            self.shared.chains.reserve_one()?;
        }
        self.published.reserve_chain(chain.joint_count())?;
        let id = self.shared.scene.add(
            EntityKind::Character,
            desc.position,
            desc.heading,
            chain.look_at_height(world.up),
            desc.impact,
        )?;
        let chain_index = match known_chain {
            Some(index) => index,
            None => self.shared.chains.push(chain, world.up),
        };
        let created = self.shared.characters_created;
        let seed = self.shared.config.seed;
        self.shared.characters.push(params, chain_index as u32);
        self.shared.characters_created += 1;
        self.states.push(
            AttentionLod {
                stagger: (created % 64) as u8,
                period: 0,
                pending: 0.0,
            },
            ModelState::new(params.model, &self.shared.config.interest),
            GazeMotion::new(&chain),
            stream(seed, Purpose::Saliency, created),
            stream(seed, Purpose::GazeTiming, created),
            BlinkState::new(&self.shared.config.blinks, character_seed(seed, id)),
        );
        // The new character is the last both in dense order and in readers' order.
        self.read_order.push(self.read_order.len() as u32);
        self.published.add_chain(chain.joint_count());
        Ok(id)
    }

    /// Adds a scene object; returns its id.
    pub fn add_object(&mut self, desc: &ObjectDesc) -> Result<u32> {
        crate::error::ensure_all_finite(&desc.position.to_array(), "position")?;
        ensure_finite(desc.heading, "heading")?;
        check_range(desc.look_at_height, -1e6, 1e6, "look_at_height")?;
        Self::check_impact(desc.impact)?;
        self.ensure_online("add an object")?;
        let objects = self.shared.scene.len()
            - self.character_count()
            - usize::from(self.shared.viewer.is_some());
        if objects >= self.shared.config.max_objects as usize {
            return Err(Error::Capacity(format!(
                "the crowd already holds max_objects = {} objects",
                self.shared.config.max_objects
            )));
        }
        self.shared.scene.add(
            EntityKind::Object,
            desc.position,
            desc.heading,
            desc.look_at_height,
            desc.impact,
        )
    }

    /// Removes a character or object. Characters looking at it look elsewhere.
    pub fn remove_entity(&mut self, id: u32) -> Result<()> {
        self.shared.scene.find(id)?;
        self.ensure_online("remove an entity")?;
        if let Ok(character) = self.shared.scene.character_index(id) {
            self.leave_conversation(character);
        }
        if let Some(slot) = self.shared.scene.remove(id)? {
            let slot = slot as usize;
            let joints = self.chain_of(slot).joint_count();
            self.published.release_chain(joints);
            self.shared.characters.swap_remove(slot);
            self.states.swap_remove(slot);
            // Readers' order: the last character read takes the removed one's place, and the
            // last dense character (moved to `slot` above) is found at its new index.
            let last = self.read_order.len() - 1;
            if let Some(position) = self.read_order.iter().position(|&c| c as usize == slot) {
                self.read_order.swap_remove(position);
            }
            if let Some(moved) = self.read_order.iter_mut().find(|c| **c as usize == last) {
                *moved = slot as u32;
            }
        }
        if self.shared.viewer == Some(id) {
            self.shared.viewer = None;
        }
        for model in &mut self.states.models {
            model.forget(id);
        }
        for explicit in &mut self.shared.characters.explicit {
            if matches!(explicit, StoredTarget::Entity(_, target) if *target == id) {
                *explicit = StoredTarget::None;
            }
        }
        Ok(())
    }

    /// Makes the viewer (the user, or the camera) an entity that characters may look at,
    /// or moves it: `position` in metres (the point looked at), `impact` its `I_E`. Its
    /// velocity comes from successive calls at successive frame times; its heading from its
    /// motion. Returns its id; remove it with [`remove_entity`](Self::remove_entity).
    pub fn set_viewer(&mut self, position: Vec3, impact: f32) -> Result<u32> {
        ensure_all_finite(&position.to_array(), "viewer position")?;
        Self::check_impact(impact)?;
        self.ensure_online("set the viewer")?;
        let id = match self.shared.viewer {
            Some(id) => {
                let index = self
                    .shared
                    .scene
                    .index_of(id)
                    .ok_or_else(|| Error::Internal("the viewer entity is missing".into()))?;
                self.shared.scene.set_impact(index, impact);
                id
            }
            None => {
                let id = self
                    .shared
                    .scene
                    .add(EntityKind::Object, position, 0.0, 0.0, impact)?;
                self.shared.viewer = Some(id);
                id
            }
        };
        let time = if self.shared.time.is_finite() {
            self.shared.time
        } else {
            0.0
        };
        self.shared.scene.apply_one(
            time,
            &crate::scene::EntityUpdate {
                id,
                position,
                heading: 0.0,
                heading_from_motion: true,
                velocity: None,
                talking: false,
            },
        );
        Ok(id)
    }

    /// The viewer's entity id, if set.
    pub fn viewer(&self) -> Option<u32> {
        self.shared.viewer
    }

    pub(super) fn ensure_online(&self, what: &str) -> Result<()> {
        if self.open_step.is_some() {
            return Err(Error::WrongState(format!(
                "cannot {what} while a step is open (end it first)"
            )));
        }
        if self.open_push.is_some() {
            return Err(Error::WrongState(format!(
                "cannot {what} while a push is open (end it first)"
            )));
        }
        if self.shared.plan.is_some() {
            return Err(Error::WrongState(format!(
                "cannot {what} while a plan is active (clear it first)"
            )));
        }
        Ok(())
    }

    /// A character's attention parameters.
    pub fn character_params(&self, id: u32) -> Result<CharacterParams> {
        Ok(self.shared.characters.params[self.shared.scene.character_index(id)?])
    }

    /// Replaces a character's attention parameters (weights must sum to 1). Changing the
    /// attention fraction restarts its percentile estimate; switching to or from the crowd
    /// model starts the new model's state afresh (see [`ModelState`]).
    pub fn set_character_params(&mut self, id: u32, params: &CharacterParams) -> Result<()> {
        let index = self.shared.scene.character_index(id)?;
        Self::check_params(params)?;
        let model = &mut self.states.models[index];
        if !model.serves(params.model) {
            *model = ModelState::new(params.model, &self.shared.config.interest);
        } else if params.attention_fraction
            != self.shared.characters.params[index].attention_fraction
        {
            if let ModelState::Crowd(tracker) = model {
                tracker.restart_delay_correction();
            }
        }
        self.shared.characters.params[index] = *params;
        Ok(())
    }

    /// Sets an entity's impact factor `I_E` (≥ 0).
    pub fn set_impact(&mut self, id: u32, impact: f32) -> Result<()> {
        let (_, index) = self.shared.scene.find(id)?;
        Self::check_impact(impact)?;
        self.shared.scene.set_impact(index, impact);
        Ok(())
    }

    /// Sets a scene object's look-at height (metres above its position, where characters
    /// look). Errors for a character (its chain gives its height) or an unknown id.
    pub fn set_look_at_height(&mut self, id: u32, height: f32) -> Result<()> {
        let (kind, index) = self.shared.scene.find(id)?;
        if kind != EntityKind::Object {
            return Err(Error::InvalidArgument(format!(
                "entity {id} is not a scene object: only objects have a settable look-at height"
            )));
        }
        check_range(height, -1e6, 1e6, "look_at_height")?;
        self.shared.scene.set_look_at_height(index, height);
        Ok(())
    }

    /// Sets a character's base pose: the local rotation of each chain joint, bottom to top
    /// (the engine's animated pose; the rest pose until set). Rotations are normalised.
    pub fn set_base_pose(&mut self, character_id: u32, local: &[Quat]) -> Result<()> {
        let character = self.shared.scene.character_index(character_id)?;
        let joints = self
            .shared
            .characters
            .chain(&self.shared.chains, character)
            .joint_count();
        if local.len() != joints {
            return Err(Error::InvalidArgument(format!(
                "the base pose has {} rotations, the chain {joints} joints",
                local.len()
            )));
        }
        let mut base = [PackedQuat::IDENTITY; MAX_CHAIN_JOINTS];
        for (slot, rotation) in base.iter_mut().zip(local) {
            crate::error::ensure_all_finite(&rotation.to_array(), "base pose")?;
            let length = rotation.length();
            if length <= 1e-6 {
                return Err(Error::InvalidArgument(
                    "a base rotation has length 0".into(),
                ));
            }
            *slot = PackedQuat::pack(*rotation / length);
        }
        self.shared.characters.bases[character] = base;
        self.shared.characters.posed[character] = true;
        Ok(())
    }

    /// Gives a character an explicit target until [`clear_gaze_target`](Self::clear_gaze_target).
    pub fn set_gaze_target(
        &mut self,
        character_id: u32,
        target: ExplicitTarget,
        priority: TargetPriority,
    ) -> Result<()> {
        let character = self.shared.scene.character_index(character_id)?;
        match target {
            ExplicitTarget::Point(point) => {
                crate::error::ensure_all_finite(&point.to_array(), "target point")?
            }
            ExplicitTarget::Entity(id) => {
                self.shared.scene.find(id)?;
                if id == character_id {
                    return Err(Error::InvalidArgument(
                        "a character cannot look at itself".into(),
                    ));
                }
            }
        }
        self.shared.characters.explicit[character] = StoredTarget::new(Some((target, priority)));
        Ok(())
    }

    /// Removes a character's explicit target; its automatic attention takes over again.
    pub fn clear_gaze_target(&mut self, character_id: u32) -> Result<()> {
        let character = self.shared.scene.character_index(character_id)?;
        self.shared.characters.explicit[character] = StoredTarget::None;
        Ok(())
    }

    /// Sets how often a character's attention is updated: every `period` steps (1 to 64),
    /// or 0 for the crowd's level of detail (`attention_period`, or `far_attention_period`
    /// beyond `lod_distance` from the viewer). Gaze IK still runs every step.
    pub fn set_attention_period(&mut self, character_id: u32, period: u32) -> Result<()> {
        let character = self.shared.scene.character_index(character_id)?;
        check_count(period, 0, 64, "period")?;
        self.states.lod[character].period = period as u8; // at most 64: checked
        Ok(())
    }
}
