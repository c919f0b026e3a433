//! Tools and test oracles: the candidate search by id or by the all-pairs loop, one
//! character-entity score with every intermediate, and the state a character costs.

use super::states;
use super::tables::Characters;
use super::values::GazeInfo;
use super::Crowd;
use crate::attention::candidates::{
    all_pairs_candidates, nearby_candidates, CandidateBatch, NeighbourIndex,
};
use crate::attention::interest::Candidate;
use crate::attention::score::ScoreBreakdown;
use crate::error::Result;
use crate::scene::Scene;

impl Crowd {
    /// The best and second-best entities for a character (by dense index) among those near
    /// it, skipping itself and entities on cool-down, on the index of the last step.
    fn best_nearby(&self, character: usize) -> (Candidate, Candidate) {
        let tracker = self.states.models[character].tracker();
        nearby_candidates(
            &self.shared.scene,
            &self.shared.neighbours,
            &self.shared.scorer,
            character,
            &self.shared.characters.params[character].weights,
            &mut CandidateBatch::default(),
            |id| tracker.is_some_and(|tracker| tracker.is_cooling(id)),
        )
    }

    /// The same as the grid search, by scoring every entity (the all-pairs loop): a test
    /// oracle and the baseline of the benchmarks.
    pub fn best_all_pairs(&self, character_id: u32) -> Result<(Candidate, Candidate)> {
        let character = self.shared.scene.character_index(character_id)?;
        Ok(self.all_pairs_of(character))
    }

    /// [`best_all_pairs`](Self::best_all_pairs) by position in the character order (see
    /// [`gaze_at`](Self::gaze_at)). Panics if `position` is out of range.
    pub fn best_all_pairs_at(&self, position: usize) -> (Candidate, Candidate) {
        self.all_pairs_of(self.dense_index(position))
    }

    fn all_pairs_of(&self, character: usize) -> (Candidate, Candidate) {
        let tracker = self.states.models[character].tracker();
        all_pairs_candidates(
            &self.shared.scene,
            &self.shared.scorer,
            character,
            &self.shared.characters.params[character].weights,
            |id| tracker.is_some_and(|tracker| tracker.is_cooling(id)),
        )
    }

    /// The grid search for one character by id, on the grid of the last step.
    pub fn best_nearby_by_id(&self, character_id: u32) -> Result<(Candidate, Candidate)> {
        let character = self.shared.scene.character_index(character_id)?;
        Ok(self.best_nearby(character))
    }

    /// Rebuilds the spatial grid from the current positions (done by every step).
    pub fn rebuild_grid(&mut self) {
        let shared = &mut *self.shared;
        shared
            .neighbours
            .rebuild(&shared.scene, shared.config.scoring.talking_gain);
    }

    /// Scores one (character, entity) pair on the current state, with every intermediate.
    pub fn score(&self, character_id: u32, entity_id: u32) -> Result<ScoreBreakdown> {
        let character = self.shared.scene.character_index(character_id)?;
        let (_, entity) = self.shared.scene.find(entity_id)?;
        let observer = self
            .shared
            .scene
            .ground_state(self.shared.scene.character_entities()[character] as usize);
        Ok(self.shared.scorer.score(
            &observer,
            &self.shared.scene.ground_state(entity),
            &self.shared.characters.params[character].weights,
            self.shared
                .scene
                .attention_impact(entity, self.shared.config.scoring.talking_gain),
        ))
    }

    /// Bytes of state the crowd keeps per character: its per-character arrays, its entity's
    /// share of the scene and the neighbour index, and the step's per-character scratch
    /// (visiting order, and two bit sets counted as one byte). All are buffers sized at
    /// creation.
    pub fn state_bytes_per_character() -> usize {
        use std::mem::size_of;
        let per_character = Characters::bytes_per_character()
            + size_of::<u32>() // place in the readers' order
            + size_of::<u32>() // attention's visiting order (scratch)
            + 1 // claim bits of the ranged step and push, a reordering bit (scratch)
            + states::bytes_per_character();
        per_character + Scene::bytes_per_entity() + NeighbourIndex::bytes_per_entity()
    }

    /// Bytes the crowd keeps per character for the readers beside its state: the last
    /// step's outputs laid out in the readers' order (its [`GazeInfo`], where its joints
    /// start, its reader position), sized at creation; plus 16 bytes per chain joint (the
    /// final rotations), reserved as characters are added.
    pub fn output_bytes_per_character() -> usize {
        use std::mem::size_of;
        size_of::<GazeInfo>() + 2 * size_of::<u32>()
    }
}
