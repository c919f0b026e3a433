//! Reading a step's results back, in the order the engine created its characters: where
//! each looks ([`GazeInfo`]), its chain's joint rotations, its eyes.

use glam::Quat;

use super::outputs::{gaze_info, joint_rotations};
use super::published::Published;
use super::values::{EyeState, EyelidState, GazeInfo};
use super::Crowd;
use crate::error::{Error, Result};
use crate::ik::eyelids::{character_seed, eye_pitches};
use crate::ik::{GazeChain, GazeMotion};

impl Crowd {
    /// The dense index (where its state is stored) of the character at `position` in the
    /// character order readers see. Panics if `position` is out of range.
    pub(super) fn dense_index(&self, position: usize) -> usize {
        self.read_order[position] as usize
    }

    /// Where the character at `position` in the crowd's character order looks now. That
    /// order is creation order, except that removing a character moves the last one into
    /// its place; the crowd's own storage order (spatial, see [`Crowd`]) never shows
    /// through. Panics if `position` is out of range.
    pub fn gaze_at(&self, position: usize) -> GazeInfo {
        Published::want(&self.published.gaze_wanted);
        if self.published.outputs.gaze && self.unchanged_since_step() {
            return self.published.gaze[position];
        }
        self.gaze_of(self.dense_index(position))
    }

    /// True while nothing has changed since the last step: what it published (see
    /// [`Published`]) is what the readers would compute.
    pub(super) fn unchanged_since_step(&self) -> bool {
        !self.shared.changed && !self.states.changed
    }

    /// Where a character (by dense index) looks now.
    pub(super) fn gaze_of(&self, character: usize) -> GazeInfo {
        let initial_threshold = self.shared.config.interest.initial_threshold;
        gaze_info(
            &self.shared.look(),
            initial_threshold,
            character,
            self.states.view(character),
        )
    }

    /// Where a character looks now, by id.
    pub fn gaze(&self, character_id: u32) -> Result<GazeInfo> {
        Ok(self.gaze_of(self.shared.scene.character_index(character_id)?))
    }

    /// The point a character glances at because others look there (gaze following,
    /// [`FollowConfig`](crate::attention::following::FollowConfig)), world metres; `None`
    /// when it does not follow anyone's gaze now (or following is off). Glances started so
    /// far are the second value.
    pub fn following(&self, character_id: u32) -> Result<(Option<glam::Vec3>, u32)> {
        let character = self.shared.scene.character_index(character_id)?;
        let view = self.states.view(character);
        Ok((
            self.shared.look().followed_point(character, view),
            view.follow.glances,
        ))
    }

    /// A character's gaze chain.
    pub fn chain(&self, character_id: u32) -> Result<&GazeChain> {
        Ok(self.chain_of(self.shared.scene.character_index(character_id)?))
    }

    /// Number of chain joints of the characters `first .. first + count` (in the character
    /// order, see [`gaze_at`](Self::gaze_at)) together: the length of their packed
    /// joint outputs.
    pub fn joint_total(&self, first: usize, count: usize) -> Result<usize> {
        let range = self.character_range(first, count)?;
        if self.unchanged_since_step() {
            let starts = &self.published.joint_start;
            return Ok((starts[range.end] - starts[range.start]) as usize);
        }
        Ok(self.read_order[range]
            .iter()
            .map(|&character| self.chain_of(character as usize).joint_count())
            .sum())
    }

    /// The chain of the character at storage index `character`.
    pub(super) fn chain_of(&self, character: usize) -> &GazeChain {
        self.shared.characters.chain(&self.shared.chains, character)
    }

    fn character_range(&self, first: usize, count: usize) -> Result<std::ops::Range<usize>> {
        let characters = self.character_count();
        match first.checked_add(count) {
            Some(end) if end <= characters => Ok(first..end),
            _ => Err(Error::InvalidArgument(format!(
                "characters {first} .. {first} + {count} are out of range: there are {characters}"
            ))),
        }
    }

    /// Writes the chain joints of characters `first .. first + count` (in the character
    /// order, see [`gaze_at`](Self::gaze_at)) into `out`, packed one chain after
    /// another, bottom to top: the final local rotations `base * delta`, or the deltas
    /// alone with `deltas_only`. `out` must hold [`joint_total`](Self::joint_total)
    /// rotations; returns how many were written.
    pub fn read_joints(
        &self,
        first: usize,
        count: usize,
        deltas_only: bool,
        out: &mut [Quat],
    ) -> Result<usize> {
        let total = self.joint_total(first, count)?;
        if out.len() < total {
            return Err(Error::InvalidArgument(format!(
                "the output holds {} rotations, {total} are needed",
                out.len()
            )));
        }
        if !deltas_only {
            Published::want(&self.published.joints_wanted);
        }
        if !deltas_only && self.published.outputs.joints && self.unchanged_since_step() {
            let start = self.published.joint_start[first] as usize;
            out[..total].copy_from_slice(&self.published.joints[start..start + total]);
            return Ok(total);
        }
        let mut written = 0;
        for &character in &self.read_order[first..first + count] {
            written += self.write_joints(character as usize, deltas_only, &mut out[written..]);
        }
        Ok(written)
    }

    /// [`read_joints`](Self::read_joints) for one character, by id: `out` must hold its
    /// chain's joint count of rotations; returns how many were written.
    pub fn read_joints_of(
        &self,
        character_id: u32,
        deltas_only: bool,
        out: &mut [Quat],
    ) -> Result<usize> {
        let character = self.shared.scene.character_index(character_id)?;
        let joints = self.chain_of(character).joint_count();
        if out.len() < joints {
            return Err(Error::InvalidArgument(format!(
                "the output holds {} rotations, {joints} are needed",
                out.len()
            )));
        }
        Ok(self.write_joints(character, deltas_only, out))
    }

    /// Writes the chain joints of the character at dense index `character` to the start of
    /// `out` (which holds them all); returns how many.
    pub(super) fn write_joints(
        &self,
        character: usize,
        deltas_only: bool,
        out: &mut [Quat],
    ) -> usize {
        let view = self.states.view(character);
        joint_rotations(&self.shared.look(), character, view, deltas_only, out)
    }

    /// Where the eyes of the character at `position` in the character order (see
    /// [`gaze_at`](Self::gaze_at)) are and look after the last step. Panics if
    /// `position` is out of range.
    pub fn eyes_at(&self, position: usize) -> EyeState {
        let character = self.dense_index(position);
        let motion = &self.states.motions[character];
        let entity = self.shared.scene.character_entities()[character] as usize;
        EyeState {
            character: self.shared.scene.ids()[entity],
            origins: motion.eye_origins(),
            directions: motion.eye_directions(),
        }
    }

    /// A character's gaze motion (phase, timing), by id.
    pub fn gaze_motion(&self, character_id: u32) -> Result<&GazeMotion> {
        Ok(&self.states.motions[self.shared.scene.character_index(character_id)?])
    }

    /// The eyelids of the character at `position` in the character order (see
    /// [`gaze_at`](Self::gaze_at)) after the last step: how closed they are (the blink)
    /// and each upper lid's pitch following its eye ([`crate::ik::eyelids`]). Panics if
    /// `position` is out of range.
    pub fn eyelids_at(&self, position: usize) -> EyelidState {
        self.eyelids_of(self.dense_index(position))
    }

    /// A character's eyelids after the last step, by id.
    pub fn eyelids(&self, character_id: u32) -> Result<EyelidState> {
        Ok(self.eyelids_of(self.shared.scene.character_index(character_id)?))
    }

    /// The eyelids of the character at dense index `character`.
    fn eyelids_of(&self, character: usize) -> EyelidState {
        let scene = &self.shared.scene;
        let id = scene.ids()[scene.character_entities()[character] as usize];
        let settings = &self.shared.config.blinks;
        // Open eyes need no draw (nor the character's seed).
        let blink = &self.states.blinks[character];
        let closure = if blink.is_blinking() {
            blink.closure(character_seed(self.shared.config.seed, id))
        } else {
            0.0
        };
        let chain = self.chain_of(character);
        let tables = &self.shared.characters;
        let base = |joint| tables.base_rotation(&self.shared.chains, character, joint);
        let deltas = self.states.motions[character].deltas();
        let [left, right] = eye_pitches(chain, base, deltas);
        EyelidState {
            character: id,
            left_closure: closure,
            right_closure: closure,
            left_lid_pitch: settings.lid_pitch(left),
            right_lid_pitch: settings.lid_pitch(right),
        }
    }
}
