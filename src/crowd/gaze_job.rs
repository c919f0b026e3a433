//! The gaze job: for every character, gaze IK towards what it attends to now — the spine,
//! neck, head and eyes turned with human timing (Paper 2), many characters at a time in
//! SIMD lanes.
//!
//! In: each character's look (its attention model's state, explicit target, the plan),
//! transform, chain and base pose. Out: each character's gaze motion (joint rotations, eye
//! origins and directions) and its random stream of timing draws; then, as its last stage,
//! what the readers will report for it (its gaze and final joint rotations), published in
//! the readers' order. Each chunk of characters blinks as soon as it has moved
//! (`blinks.rs`). A character's result
//! depends only on its own inputs, not on its batch or range, so ranges may run on several
//! threads.

use glam::Quat;

use super::look::LookContext;
use super::outputs::{gaze_info, joint_rotations};
use super::published::{Outputs, PublishTarget};
use super::states::{CharacterSlices, CharacterView, RawCharacterSlices};
use crate::error::{Error, Result};
use crate::ik::temporal::BATCH_LANES;
use crate::ik::{
    BlinkSettings, CharacterTransform, GazeChain, GazeConfig, GazeInput, GazeMotion, GazeRequest,
    MAX_CHAIN_JOINTS,
};
use crate::math::random::Random;

/// Characters the gaze IK sorts into moving and resting ones at a time.
const SORT_CHUNK: usize = 128;
// A position in a chunk is a byte.
const _: () = assert!(SORT_CHUNK <= 256);

/// How many characters ahead the gaze step prefetches a character's state.
const GAZE_PREFETCH_AHEAD: usize = 8;

/// How many characters ahead the publishing stage prefetches where a character's outputs
/// go (they are written in the readers' order, scattered when storage is in spatial order).
const PUBLISH_PREFETCH_AHEAD: usize = 8;

/// The gaze job of one step: its inputs, and the per-character arrays it writes.
#[derive(Debug, Clone, Copy)]
pub(super) struct GazeJob<'a> {
    /// Seconds since the previous step.
    pub dt: f32,
    /// The gaze IK's settings.
    pub config: &'a GazeConfig,
    /// The scene, the per-character tables, the chains and the plan.
    pub look: LookContext<'a>,
    /// The per-character arrays: writes `motions` and `gaze_randoms`, reads `models`.
    pub states: RawCharacterSlices,
    /// Where each moved character's outputs go, in the readers' order.
    pub publish: PublishTarget,
    /// The crowd's initial interest threshold (what the saliency and baseline models report).
    pub initial_threshold: f32,
    /// How the characters blink.
    pub blinks: &'a BlinkSettings,
    /// The crowd's seed (each character's blinks draw from it and the character's id).
    pub seed: u64,
}

impl GazeJob<'_> {
    /// Checks that the inputs and outputs describe the same characters.
    pub fn validate(&self) -> Result<()> {
        let characters = self.look.scene.character_count();
        let tables = &self.look.characters;
        if self.states.len() != characters
            || tables.chain_of.len() != characters
            || tables.posed.len() != characters
            || self.publish.characters() != characters
        {
            return Err(Error::Internal(format!(
                "the gaze job has {} states and {} chains for {characters} characters",
                self.states.len(),
                tables.chain_of.len()
            )));
        }
        Ok(())
    }

    /// Runs gaze IK for characters `first .. first + count` (storage order).
    ///
    /// # Safety
    /// The arrays behind `states` must be alive and unmoved, and no other code may touch
    /// these characters' entries meanwhile: concurrent calls take disjoint ranges.
    pub unsafe fn run(&self, first: usize, count: usize) {
        // SAFETY: the caller's contract.
        let mut slices = unsafe { self.states.range(first, count) };
        self.move_gaze(first, &mut slices);
        // SAFETY: the caller's contract covers these characters' published entries too.
        unsafe { self.publish(first, &slices) };
    }

    /// The last stage: for the characters of `slices` (the first is character `first`),
    /// what the readers report — gaze and final joint rotations — written in the readers'
    /// order, when this step publishes them ([`PublishTarget::outputs`]).
    ///
    /// # Safety
    /// As [`run`](Self::run): no other code touches these characters' published entries.
    unsafe fn publish(&self, first: usize, slices: &CharacterSlices<'_>) {
        if self.publish.outputs() == Outputs::default() {
            return;
        }
        for (local, (model, motion)) in slices.models.iter().zip(&*slices.motions).enumerate() {
            let character = first + local;
            self.publish.prefetch(character + PUBLISH_PREFETCH_AHEAD);
            let follow = &slices.follows[local];
            let view = CharacterView {
                model,
                motion,
                follow,
            };
            // SAFETY: the caller's contract.
            unsafe {
                self.publish.write(
                    character,
                    || gaze_info(&self.look, self.initial_threshold, character, view),
                    |out| joint_rotations(&self.look, character, view, false, out),
                )
            };
        }
    }

    /// Gaze IK for the characters of `slices` (the first is character `first`), up to
    /// [`BATCH_LANES`] per [`GazeMotion::update_batch`] call (which runs them as many at a
    /// time as the processor's SIMD lanes hold). Within each chunk of [`SORT_CHUNK`]
    /// characters, those at rest with nothing to look at ([`GazeMotion::is_resting`]) are
    /// batched apart from the others: a lane group costs the same whichever of its lanes
    /// move, and a group of resting characters only carries their eye rays along. (A
    /// character's result does not depend on its batch.)
    fn move_gaze(&self, first: usize, slices: &mut CharacterSlices<'_>) {
        let CharacterSlices {
            models,
            motions,
            gaze_randoms,
            blinks,
            follows,
            ..
        } = slices;
        let count = motions.len();
        let mut chunk = 0;
        while chunk < count {
            let len = (count - chunk).min(SORT_CHUNK);
            let ahead_motions = motions.as_ptr();
            let chunk_motions = &mut motions[chunk..chunk + len];
            let randoms = &mut gaze_randoms[chunk..chunk + len];
            let requests: [Option<GazeRequest>; SORT_CHUNK] = std::array::from_fn(|local| {
                if local >= len {
                    return None;
                }
                // The attention model state and the whole motion state (464 bytes) of a
                // character a few ahead.
                let ahead = chunk + local + GAZE_PREFETCH_AHEAD;
                if ahead < count {
                    crate::math::prefetch(models.as_ptr().wrapping_add(ahead));
                    let motion = ahead_motions.wrapping_add(ahead).cast::<[u8; 256]>();
                    crate::math::prefetch(motion);
                    crate::math::prefetch(motion.wrapping_add(1));
                }
                let view = CharacterView {
                    model: &models[chunk + local],
                    motion: &chunk_motions[local],
                    follow: &follows[chunk + local],
                };
                self.look.gaze_request(first + chunk + local, view)
            });
            let resting = |local: usize| chunk_motions[local].is_resting(requests[local].as_ref());
            // The moving characters first, then the resting ones (backwards). Each is
            // written at both ends and only one end moves on: no branch to mispredict.
            let mut order = [0u8; SORT_CHUNK];
            let (mut moving, mut back) = (0, len);
            for local in 0..len {
                let rests = resting(local);
                order[moving] = local as u8;
                order[back - 1] = local as u8;
                moving += usize::from(!rests);
                back -= usize::from(rests);
            }
            let mut motions: [Option<&mut GazeMotion>; SORT_CHUNK] = {
                let mut each = chunk_motions.iter_mut();
                std::array::from_fn(|_| each.next())
            };
            let mut randoms: [Option<&mut Random>; SORT_CHUNK] = {
                let mut each = randoms.iter_mut();
                std::array::from_fn(|_| each.next())
            };
            for (part_start, part_end) in [(0, moving), (moving, len)] {
                let mut start = part_start;
                while start < part_end {
                    let lanes = (part_end - start).min(BATCH_LANES);
                    let group = &order[start..start + lanes];
                    self.move_group(first + chunk, group, &requests, &mut motions, &mut randoms);
                    start += lanes;
                }
            }
            self.blink(
                first + chunk,
                chunk_motions,
                &mut blinks[chunk..chunk + len],
            );
            chunk += len;
        }
    }

    /// Gaze IK for one batch: the characters `first + group[i]`, whose requests are
    /// `requests[group[i]]` and whose motions and random streams are taken from
    /// `motions[group[i]]` and `randoms[group[i]]` (each `Some`, and `group` without
    /// repeats).
    fn move_group(
        &self,
        first: usize,
        group: &[u8],
        requests: &[Option<GazeRequest>; SORT_CHUNK],
        motions: &mut [Option<&mut GazeMotion>; SORT_CHUNK],
        randoms: &mut [Option<&mut Random>; SORT_CHUNK],
    ) {
        const LANES: usize = BATCH_LANES;
        let lanes = group.len();
        let local = |lane: usize| usize::from(group[lane.min(lanes - 1)]);
        let transforms: [CharacterTransform; LANES] =
            std::array::from_fn(|lane| self.look.character_transform(first + local(lane)));
        let chains: [&GazeChain; LANES] = std::array::from_fn(|lane| {
            self.look
                .characters
                .chain(self.look.chains, first + local(lane))
        });
        // Rest poses are read in place; a pose the engine set is unpacked here.
        let mut unpacked = [[Quat::IDENTITY; MAX_CHAIN_JOINTS]; LANES];
        for (lane, unpacked) in unpacked.iter_mut().enumerate().take(lanes) {
            let character = first + local(lane);
            if self.look.characters.posed[character] {
                *unpacked = self.look.characters.base_pose(self.look.chains, character);
            }
        }
        let bases: [&[Quat; MAX_CHAIN_JOINTS]; LANES] = std::array::from_fn(|lane| {
            let character = first + local(lane);
            if self.look.characters.posed[character] && lane < lanes {
                &unpacked[lane]
            } else {
                &self.look.chains.rests[self.look.characters.chain_of[character] as usize]
            }
        });
        let inputs: [GazeInput<'_>; LANES] = std::array::from_fn(|lane| GazeInput {
            character: transforms[lane],
            base: &bases[lane][..chains[lane].joint_count()],
            request: requests[local(lane)],
            dt: self.dt,
        });
        let mut motions = group.iter().map(|&local| {
            motions[usize::from(local)]
                .take()
                .expect("each character of a chunk once")
        });
        let mut randoms = group.iter().map(|&local| {
            randoms[usize::from(local)]
                .take()
                .expect("each character of a chunk once")
        });
        // One `update_batch` call for as many characters as `lanes` (a constant per arm).
        macro_rules! update_lanes {
            ($($count:literal)*) => {
                match lanes {
                    $($count => update_batch::<$count>(
                        std::array::from_fn(|_| motions.next().expect("a motion per lane")),
                        std::array::from_fn(|_| randoms.next().expect("a stream per lane")),
                        &chains,
                        self.config,
                        &inputs,
                    ),)*
                    _ => unreachable!("1 to BATCH_LANES characters per batch"),
                }
            };
        }
        update_lanes!(1 2 3 4 5 6 7 8 9 10 11 12 13 14 15 16);
    }
}

/// [`GazeMotion::update_batch`] for the first `N` characters of `chains` and `inputs`, whose
/// motions and random streams are `motions` and `randoms`, without its checks: every input
/// was checked when it came in.
fn update_batch<const N: usize>(
    motions: [&mut GazeMotion; N],
    randoms: [&mut Random; N],
    chains: &[&GazeChain; BATCH_LANES],
    config: &GazeConfig,
    inputs: &[GazeInput<'_>; BATCH_LANES],
) {
    GazeMotion::update_batch_prechecked(
        motions,
        std::array::from_fn(|lane| chains[lane]),
        config,
        std::array::from_fn(|lane| &inputs[lane]),
        randoms,
    );
}
