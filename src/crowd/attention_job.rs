//! The attention job: for every character, its attention model's update this frame — the
//! crowd model's best entities, threshold and interest point (Paper 1; a plan replaces them
//! offline), or the saliency and baseline models' eye and head targets — every `period`
//! steps by its level of detail.
//!
//! In: the scene and its neighbour index, the scorer, each character's parameters (and, for
//! the saliency model, its eyes and head from the last gaze update). Out: each character's
//! level-of-detail clock, model state and model random stream. A character's update reads
//! only shared data and writes only its own entries, so ranges may run on several threads.

use glam::Vec2;

use super::config::CrowdConfig;
use super::look::LookContext;
use super::model_state::ModelState;
use super::states::{CharacterMut, RawCharacterSlices};
use crate::attention::candidates::{nearby_candidates, CandidateBatch, NeighbourIndex};
use crate::attention::following::CueRuns;
use crate::attention::score::Scorer;
use crate::attention::AttentionModel;
use crate::error::{Error, Result};

/// How many characters ahead attention in grid order prefetches a character's state.
const PREFETCH_AHEAD: usize = 12;

/// What every character's step this frame shares, fixed by `Crowd::begin_step`.
#[derive(Debug, Clone, Copy)]
pub(super) struct Frame {
    /// Seconds since the previous step.
    pub dt: f32,
    /// Steps taken before this one (staggers the level-of-detail updates).
    pub step_index: u64,
    /// The viewer's ground position, if there is a viewer.
    pub viewer: Option<Vec2>,
    /// `S_MAX`, the largest impact in the scene.
    pub max_score: f32,
}

/// The attention job of one step: its inputs, and the per-character arrays it writes.
#[derive(Debug, Clone, Copy)]
pub(super) struct AttentionJob<'a> {
    /// This frame's shared values.
    pub frame: Frame,
    /// The crowd's settings (level of detail, interest, saliency, baseline).
    pub config: &'a CrowdConfig,
    /// The scoring function `S(C, E)`.
    pub scorer: &'a Scorer,
    /// The neighbour index of this frame's positions.
    pub neighbours: &'a NeighbourIndex,
    /// The scene, the per-character tables, the chains and the plan.
    pub look: LookContext<'a>,
    /// The per-character arrays: writes `lod`, `models` and `model_randoms`, reads `motions`.
    pub states: RawCharacterSlices,
}

impl AttentionJob<'_> {
    /// Checks that the inputs and outputs describe the same characters.
    pub fn validate(&self) -> Result<()> {
        let characters = self.look.scene.character_count();
        if self.states.len() != characters || self.look.characters.params.len() != characters {
            return Err(Error::Internal(format!(
                "the attention job has {} states and {} parameters for {characters} characters",
                self.states.len(),
                self.look.characters.params.len()
            )));
        }
        Ok(())
    }

    /// Runs attention for characters `first .. first + count` (storage order).
    ///
    /// # Safety
    /// The arrays behind `states` must be alive and unmoved, and no other code may touch
    /// these characters' entries meanwhile: concurrent calls take disjoint ranges.
    pub unsafe fn run(&self, first: usize, count: usize) {
        let mut batch = CandidateBatch::default();
        let mut runs = CueRuns::default();
        // SAFETY: the caller's contract.
        let mut slices = unsafe { self.states.range(first, count) };
        for local in 0..count {
            self.attend_one(
                first + local,
                slices.character(local),
                &mut batch,
                &mut runs,
            );
        }
    }

    /// Runs attention for the characters `order` lists (a part of the spatial grid's order:
    /// neighbours in space are neighbours in this loop, so their data is in cache).
    ///
    /// # Safety
    /// As [`run`](Self::run), for the characters listed; `order` holds no repeats, and
    /// concurrent calls take disjoint parts of one permutation.
    pub unsafe fn run_in_order(&self, order: &[u32]) {
        let mut batch = CandidateBatch::default();
        let mut runs = CueRuns::default();
        for (position, &character) in order.iter().enumerate() {
            // Characters come in grid order, not memory order: start loading the state of
            // the one a few steps ahead (its neighbours are in cache already).
            if let Some(&ahead) = order.get(position + PREFETCH_AHEAD) {
                self.states.prefetch_attention(ahead as usize);
                self.prefetch(ahead as usize);
            }
            let character = character as usize;
            // SAFETY: the caller's contract: no one else touches this character.
            let mut slices = unsafe { self.states.range(character, 1) };
            self.attend_one(character, slices.character(0), &mut batch, &mut runs);
        }
    }

    /// Hints the processor to load what attention reads of character `character` that
    /// lives in the shared state: its parameters, its entity's ground state and grid slot.
    #[inline]
    fn prefetch(&self, character: usize) {
        crate::math::prefetch(self.look.characters.params.as_ptr().wrapping_add(character));
        if let Some(&entity) = self.look.scene.character_entities().get(character) {
            let entity = entity as usize;
            crate::math::prefetch(
                self.look
                    .scene
                    .ground_positions()
                    .as_ptr()
                    .wrapping_add(entity),
            );
            crate::math::prefetch(self.look.scene.forwards().as_ptr().wrapping_add(entity));
            crate::math::prefetch(self.look.scene.headings().as_ptr().wrapping_add(entity));
            crate::math::prefetch(self.look.scene.velocities().as_ptr().wrapping_add(entity));
            self.neighbours.prefetch_entity(entity);
        }
    }

    /// Attention for one character by its model, every `period` steps (level of detail):
    /// the crowd model's best entities, threshold and interest point (online; a plan
    /// replaces them), or the saliency and baseline models' eye and head targets.
    fn attend_one(
        &self,
        character: usize,
        state: CharacterMut<'_>,
        batch: &mut CandidateBatch,
        runs: &mut CueRuns,
    ) {
        let config = self.config;
        let period = match u32::from(state.lod.period) {
            0 => {
                let entity = self.look.scene.character_entities()[character] as usize;
                let far = config.lod_distance > 0.0
                    && self.frame.viewer.is_some_and(|viewer| {
                        viewer.distance(self.look.scene.ground_positions()[entity])
                            > config.lod_distance
                    });
                if far {
                    config.far_attention_period
                } else {
                    config.attention_period
                }
            }
            period => period,
        };
        state.lod.pending += self.frame.dt;
        if !(self.frame.step_index + u64::from(state.lod.stagger)).is_multiple_of(u64::from(period))
        {
            return;
        }
        let dt = std::mem::take(&mut state.lod.pending);
        if config.following.enabled {
            self.follow(character, dt, state.follow, state.model_random, runs);
        }
        match self.look.characters.params[character].model {
            AttentionModel::Crowd if self.look.plan.is_some() => {}
            AttentionModel::Crowd => {
                let ModelState::Crowd(tracker) = state.model else {
                    return;
                };
                let (best, second) = nearby_candidates(
                    self.look.scene,
                    self.neighbours,
                    self.scorer,
                    character,
                    &self.look.characters.params[character].weights,
                    batch,
                    |id| tracker.is_cooling(id),
                );
                let fraction = self.look.characters.params[character].attention_fraction;
                tracker.update(
                    best,
                    second,
                    self.frame.max_score,
                    fraction,
                    dt,
                    &config.interest,
                );
            }
            AttentionModel::Saliency => self.attend_saliency(character, dt, state),
            AttentionModel::Baseline => self.attend_baseline(character, dt, state),
            AttentionModel::Street => self.attend_street(character, dt, state),
        }
    }
}
