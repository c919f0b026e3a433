//! The gaze job's blink stage: each character's blinks go on, and a gaze shift that started
//! this step may start one (the model: [`crate::ik::eyelids`]). Runs on a chunk of
//! characters right after their gaze moved, while their motion state is in cache.

use super::gaze_job::GazeJob;
use crate::ik::eyelids::character_seed;
use crate::ik::{BlinkState, GazeMotion};

impl GazeJob<'_> {
    /// The blinks of characters `first ..` (one per entry of `motions`, already moved this
    /// step). Most characters' frames are quiet ([`BlinkState::advance_quietly`]) and need
    /// neither their id nor a draw; a crowd that never blinks skips the stage.
    pub(super) fn blink(&self, first: usize, motions: &[GazeMotion], blinks: &mut [BlinkState]) {
        if self.blinks.never_blink() {
            return;
        }
        for (local, (motion, blink)) in motions.iter().zip(blinks).enumerate() {
            let shift = motion.shift_start_amplitude();
            if !blink.advance_quietly(self.dt, shift) {
                let scene = self.look.scene;
                let entity = scene.character_entities()[first + local] as usize;
                let seed = character_seed(self.seed, scene.ids()[entity]);
                blink.advance(self.blinks, seed, self.dt, shift);
            }
        }
    }
}
