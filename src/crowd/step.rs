//! Stepping: one frame of attention and gaze IK for every character, whole or in ranges.
//!
//! A step is begun once ([`Crowd::begin_step`]: the plan's clock, the spatial grid, the
//! frame's shared values), run over ranges of characters ([`StepRanges::run_range`], safe
//! to call from several threads on disjoint ranges), and ended ([`Crowd::end_step`], which
//! steps any character no range covered). Each character's step reads only the shared
//! state and writes only its own entries of the per-character arrays, so the result does
//! not depend on how the crowd is split or how many threads run it.

use std::sync::atomic::{AtomicU64, Ordering};

use glam::{Quat, Vec2};

use super::models::ModelState;
use super::states::{CharacterMut, CharacterSlices, CharacterView, RawCharacterSlices};
use super::{Crowd, ExplicitTarget, Shared, TargetPriority, EXPLICIT_POINT_KEY};
use crate::attention::candidates::{nearby_candidates, CandidateBatch};
use crate::attention::AttentionModel;
use crate::error::{ensure_finite, Error, Result};
use crate::ik::temporal::BATCH_LANES;
use crate::ik::{
    CharacterTransform, GazeChain, GazeConfig, GazeInput, GazeMotion, GazeRequest, MotionStyle,
    MAX_CHAIN_JOINTS,
};
use crate::math::random::Random;
use crate::scene::ids::NO_ENTITY;

/// Characters per task when [`Crowd::step`] shares a step among its worker threads.
const CHARACTERS_PER_TASK: usize = 128;

/// Characters the gaze IK sorts into moving and resting ones at a time.
const SORT_CHUNK: usize = 128;
// A position in a chunk is a byte.
const _: () = assert!(SORT_CHUNK <= 256);

/// How many characters ahead the gaze step prefetches a character's state.
const GAZE_PREFETCH_AHEAD: usize = 8;

/// From this many characters on, attention visits characters in spatial-grid order: the
/// neighbours' data (about 40 bytes an entity) then outgrows the caches, and visiting
/// neighbours one after another keeps it in them (each character's own state, read out of
/// order then, is prefetched a few characters ahead). Below, the dense order is as fast:
/// the neighbour data fits the caches anyway, and the per-character state is read in
/// sequence. (Measured on the plaza with the prefetch: grid order as fast at 10 000, 30%
/// faster at 100 000 than grid order without it.)
const GRID_ORDER_FROM: usize = 30_000;

/// How many characters ahead attention in grid order prefetches a character's state.
const PREFETCH_AHEAD: usize = 12;

/// What every character's step this frame shares, fixed by [`Crowd::begin_step`].
#[derive(Debug, Clone, Copy)]
pub(super) struct Frame {
    /// Seconds since the previous step.
    dt: f32,
    /// Steps taken before this one (staggers the level-of-detail updates).
    step_index: u64,
    /// The viewer's ground position, if there is a viewer.
    viewer: Option<Vec2>,
    /// `S_MAX`, the largest impact in the scene.
    max_score: f32,
    /// True when attention follows a plan.
    planned: bool,
    /// Which parts of a character's step run.
    parts: StepParts,
}

/// Which parts of each character's step a step runs.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum StepParts {
    /// Attention, then gaze IK: a whole step.
    Both,
    /// Attention alone ([`Crowd::step_attention`]).
    Attention,
    /// Gaze IK alone ([`Crowd::step_gaze`]).
    Gaze,
}

/// One flag per character: taken by a range of the open step. Claims are atomic so that
/// ranges from several threads are checked for overlap without a lock.
#[derive(Debug)]
pub(super) struct ClaimSet {
    words: Box<[AtomicU64]>,
}

impl ClaimSet {
    /// Flags for up to `capacity` characters, all clear; `what` names the caller's number
    /// `capacity` comes from, for [`Error::OutOfMemory`].
    pub fn new(capacity: usize, what: &dyn std::fmt::Display) -> Result<ClaimSet> {
        let words = capacity.div_ceil(64);
        let mut flags = crate::alloc::try_with_capacity(words, what)?;
        flags.extend((0..words).map(|_| AtomicU64::new(0)));
        Ok(ClaimSet {
            // Exactly as long as its capacity: boxing it does not reallocate.
            words: flags.into_boxed_slice(),
        })
    }

    /// Clears every flag.
    fn clear(&mut self) {
        for word in self.words.iter_mut() {
            *word.get_mut() = 0;
        }
    }

    /// The bits of word `word` that lie in `first .. end`.
    fn mask(word: usize, first: usize, end: usize) -> u64 {
        let low = first.saturating_sub(word * 64).min(64);
        let high = end.saturating_sub(word * 64).min(64);
        let below = |bits: usize| {
            if bits == 64 {
                u64::MAX
            } else {
                (1 << bits) - 1
            }
        };
        below(high) & !below(low)
    }

    /// Takes characters `first .. end` if none of them is taken; on overlap takes nothing
    /// and returns false. Two overlapping calls racing may both fail, never both succeed.
    fn claim(&self, first: usize, end: usize) -> bool {
        if first >= end {
            return true;
        }
        let words = first / 64..=(end - 1) / 64;
        for word in words.clone() {
            let mask = Self::mask(word, first, end);
            let before = self.words[word].fetch_or(mask, Ordering::AcqRel);
            if before & mask != 0 {
                // Undo: the words before were wholly ours; here only the bits we set.
                self.words[word].fetch_and(!(mask & !before), Ordering::AcqRel);
                for earlier in *words.start()..word {
                    self.words[earlier]
                        .fetch_and(!Self::mask(earlier, first, end), Ordering::AcqRel);
                }
                return false;
            }
        }
        true
    }

    /// The first run of unclaimed characters at or after `from`, below `count`.
    fn next_unclaimed(&mut self, from: usize, count: usize) -> Option<(usize, usize)> {
        let taken = |index: usize, words: &mut [AtomicU64]| {
            *words[index / 64].get_mut() & (1 << (index % 64)) != 0
        };
        let mut first = from;
        while first < count && taken(first, &mut self.words) {
            first += 1;
        }
        let mut end = first;
        while end < count && !taken(end, &mut self.words) {
            end += 1;
        }
        (first < count).then_some((first, end))
    }
}

/// An open step's ranges: shared with every thread that runs a part of the step.
#[derive(Debug, Clone, Copy)]
pub struct StepRanges<'a> {
    shared: &'a Shared,
    states: RawCharacterSlices,
    /// The characters in spatial-grid order (a permutation of the dense indices).
    grid_order: &'a [u32],
    claims: &'a ClaimSet,
    frame: Frame,
}

impl StepRanges<'_> {
    /// Number of characters in the step.
    pub fn character_count(&self) -> usize {
        self.states.len()
    }

    /// Steps characters `first .. first + count` in dense (storage) order, not the order
    /// readers see (see [`Crowd::gaze_dense`]): attention, then gaze IK.
    /// Safe to call from several threads at once on disjoint ranges. Fails without
    /// stepping anything if the range is out of bounds ([`Error::InvalidArgument`]) or
    /// overlaps one already taken in this step ([`Error::WrongState`]).
    pub fn run_range(&self, first: usize, count: usize) -> Result<()> {
        let characters = self.states.len();
        let end = match first.checked_add(count) {
            Some(end) if end <= characters => end,
            _ => {
                return Err(Error::InvalidArgument(format!(
                    "characters {first} .. {first} + {count} are out of range: there are \
                     {characters}"
                )))
            }
        };
        if !self.claims.claim(first, end) {
            return Err(Error::WrongState(format!(
                "characters {first} .. {end} overlap a range already stepped in this step"
            )));
        }
        // SAFETY: the arrays live in the crowd, which the `&mut` borrow behind these ranges
        // keeps alive, unmoved and otherwise untouched; the claim above succeeded, so no
        // other range of this step covers these characters.
        let slices = unsafe { self.states.range(first, count) };
        self.shared.step_characters(&self.frame, first, slices);
        Ok(())
    }

    /// Attention for the characters at positions `first .. first + count` of the grid
    /// order (neighbours in space are neighbours in this loop, so their data is in cache).
    ///
    /// # Safety
    /// No other call may touch these characters meanwhile: concurrent calls must take
    /// disjoint position ranges, and no [`run_range`](Self::run_range) may run.
    unsafe fn attend_in_grid_order(&self, first: usize, count: usize) {
        let mut batch = CandidateBatch::default();
        let order = &self.grid_order[first..first + count];
        for (position, &character) in order.iter().enumerate() {
            // Characters come in grid order, not memory order: start loading the state of
            // the one a few steps ahead (its neighbours are in cache already).
            if let Some(&ahead) = order.get(position + PREFETCH_AHEAD) {
                self.states.prefetch_attention(ahead as usize);
                self.shared.prefetch_attention(ahead as usize);
            }
            let character = character as usize;
            // SAFETY: the grid order is a permutation, so disjoint position ranges hold
            // disjoint characters; exclusivity otherwise is the caller's contract.
            let mut slices = unsafe { self.states.range(character, 1) };
            self.shared
                .attend(&self.frame, character, slices.character(0), &mut batch);
        }
    }

    /// Gaze IK for characters `first .. first + count` (dense order).
    ///
    /// # Safety
    /// As [`attend_in_grid_order`](Self::attend_in_grid_order), for dense ranges.
    unsafe fn move_gaze_range(&self, first: usize, count: usize) {
        // SAFETY: the caller's contract.
        let slices = unsafe { self.states.range(first, count) };
        self.shared.move_gaze(self.frame.dt, first, slices);
    }
}

impl Crowd {
    /// Steps every character `dt` seconds after the previous step: attention (by each
    /// character's model and level of detail), then gaze IK. With `threads > 1` in the
    /// config the characters are shared among the crowd's worker threads; the result is
    /// the same.
    pub fn step(&mut self, dt: f32) -> Result<()> {
        self.step_parts(dt, StepParts::Both)
    }

    /// Runs attention alone, without moving any gaze chain. For tools and benchmarks that
    /// only need who looks at what.
    pub fn step_attention(&mut self, dt: f32) -> Result<()> {
        self.step_parts(dt, StepParts::Attention)
    }

    /// Runs gaze IK alone: every chain moves towards what its character attends to now,
    /// and attention keeps its state. For benchmarks and tools that time or drive the two
    /// halves of a step apart.
    pub fn step_gaze(&mut self, dt: f32) -> Result<()> {
        self.step_parts(dt, StepParts::Gaze)
    }

    /// A step of `parts`, on the worker threads when there are some: attention for every
    /// character in grid order, then gaze IK for every character, each split into tasks.
    fn step_parts(&mut self, dt: f32, parts: StepParts) -> Result<()> {
        self.begin_step(dt)?;
        let pool = self.pool.take();
        let ranges = self.step_ranges()?;
        let count = ranges.character_count();
        let tasks = count.div_ceil(CHARACTERS_PER_TASK);
        let task_range = |task: usize| {
            let first = task * CHARACTERS_PER_TASK;
            (first, CHARACTERS_PER_TASK.min(count - first))
        };
        let run = |task: &(dyn Fn(usize) + Sync)| match &pool {
            Some(pool) => pool.run(tasks, task),
            None => {
                (0..tasks).for_each(task);
                Ok(())
            }
        };
        let mut result = Ok(());
        if parts != StepParts::Gaze {
            result = run(&|task| {
                let (first, count) = task_range(task);
                // SAFETY: tasks cover disjoint position ranges, and nothing else runs on
                // this step's characters until `run` returns.
                unsafe { ranges.attend_in_grid_order(first, count) }
            });
        }
        if parts != StepParts::Attention {
            let moved = run(&|task| {
                let (first, count) = task_range(task);
                // SAFETY: as above, for disjoint dense ranges.
                unsafe { ranges.move_gaze_range(first, count) }
            });
            result = result.and(moved);
        }
        // Every character was stepped: close the step without end_step's sweep.
        self.pool = pool;
        self.open_step = None;
        result
    }

    /// Begins a step `dt` seconds after the previous one: advances the plan's clock,
    /// rebuilds the spatial grid and fixes what every character shares this frame. Then
    /// run ranges of characters with [`step_ranges`](Self::step_ranges) (from any number of
    /// threads) or [`step_range`](Self::step_range), and finish with
    /// [`end_step`](Self::end_step). Fails without changing anything on a negative or
    /// non-finite `dt`, or if a step is already open ([`Error::WrongState`]).
    pub fn begin_step(&mut self, dt: f32) -> Result<()> {
        ensure_finite(dt, "dt")?;
        if dt < 0.0 {
            return Err(Error::InvalidArgument(format!("dt is {dt}, must be >= 0")));
        }
        if self.open_step.is_some() {
            return Err(Error::WrongState(
                "a step is already open: end it first".into(),
            ));
        }
        if let Some(plan) = &mut self.shared.plan {
            plan.advance(dt, &mut self.shared.scene);
        }
        self.shared.neighbours.rebuild(&self.shared.scene);
        let period = self.shared.config.reorder_period;
        if period > 0 && self.shared.steps.is_multiple_of(u64::from(period)) {
            self.store_in_grid_order();
        }
        let shared = &mut self.shared;
        let viewer = shared
            .viewer
            .and_then(|id| shared.scene.index_of(id))
            .map(|index| shared.scene.ground_positions()[index]);
        self.open_step = Some(Frame {
            dt,
            step_index: shared.steps,
            viewer,
            max_score: shared.scene.max_impact(),
            planned: shared.plan.is_some(),
            parts: StepParts::Both,
        });
        shared.steps += 1;
        self.claims.clear();
        self.grid_order.clear();
        let scene = &shared.scene;
        if scene.character_count() < GRID_ORDER_FROM {
            self.grid_order.extend(0..scene.character_count() as u32);
            return Ok(());
        }
        self.grid_order.extend(
            shared
                .neighbours
                .grid()
                .entries()
                .iter()
                .filter_map(|&entity| scene.character_at(entity as usize))
                .map(|character| character as u32),
        );
        if self.grid_order.len() != scene.character_count() {
            // The grid holds every entity, so this cannot happen; if it did, dense order
            // still steps every character once.
            debug_assert!(false, "a character is missing from the grid");
            self.grid_order.clear();
            self.grid_order.extend(0..scene.character_count() as u32);
        }
        Ok(())
    }

    /// Stores the entities in the spatial grid's order (just rebuilt) and the characters in
    /// the order of their entities, then rebuilds the grid on the new indices: neighbours in
    /// space become neighbours in memory, so the step reads every array in order rather
    /// than one cache line (and one page) per character. Nothing to do when storage is in
    /// grid order already (a crowd standing still), nor while a plan is active (it holds
    /// dense indices). Allocates nothing; results do not change (every choice breaks
    /// ties by id, never by index), nor does the order readers see.
    fn store_in_grid_order(&mut self) {
        let shared = &mut self.shared;
        let entities = shared.neighbours.grid().entries();
        let stored_so = entities
            .iter()
            .enumerate()
            .all(|(new, &old)| old as usize == new);
        if shared.plan.is_some() || stored_so {
            return;
        }
        // The old dense index of each character, in the new order.
        let order = &mut self.grid_order;
        let reorder = &mut self.reorder;
        shared.scene.reorder(entities, reorder, order);
        reorder.apply(&mut shared.params, order);
        reorder.apply(&mut shared.chain_of, order);
        reorder.apply(&mut shared.bases, order);
        reorder.apply(&mut shared.posed, order);
        reorder.apply(&mut shared.explicit, order);
        self.states.reorder(order, reorder);
        // The new dense index of each old one, for the readers' order.
        reorder.invert(order);
        for character in &mut self.read_order {
            *character = order[*character as usize];
        }
        shared.neighbours.rebuild(&shared.scene);
    }

    /// True between [`begin_step`](Self::begin_step) and [`end_step`](Self::end_step).
    pub fn is_step_open(&self) -> bool {
        self.open_step.is_some()
    }

    /// The open step's ranges, to run from several threads (`StepRanges` is `Sync`):
    /// each thread calls [`StepRanges::run_range`] on its own characters. Fails with
    /// [`Error::WrongState`] when no step is open.
    pub fn step_ranges(&mut self) -> Result<StepRanges<'_>> {
        let frame = self
            .open_step
            .ok_or_else(|| Error::WrongState("no step is open: begin one first".into()))?;
        Ok(StepRanges {
            states: self.states.raw(),
            grid_order: &self.grid_order,
            shared: &self.shared,
            claims: &self.claims,
            frame,
        })
    }

    /// Steps characters `first .. first + count` of the open step (see
    /// [`StepRanges::run_range`]).
    pub fn step_range(&mut self, first: usize, count: usize) -> Result<()> {
        self.step_ranges()?.run_range(first, count)
    }

    /// Ends the open step, first stepping every character that no range covered, so that
    /// a step always moves the whole crowd. Fails with [`Error::WrongState`] when no step
    /// is open.
    pub fn end_step(&mut self) -> Result<()> {
        let frame = self
            .open_step
            .ok_or_else(|| Error::WrongState("no step is open: begin one first".into()))?;
        let count = self.character_count();
        let mut from = 0;
        while let Some((first, end)) = self.claims.next_unclaimed(from, count) {
            let slices = self.states.slices().range(first, end);
            self.shared.step_characters(&frame, first, slices);
            from = end;
        }
        self.open_step = None;
        Ok(())
    }
}

impl Shared {
    /// Hints the processor to load what attention reads of character `character` that
    /// lives in the shared state: its parameters, its entity's ground state and grid slot.
    #[inline]
    fn prefetch_attention(&self, character: usize) {
        crate::math::prefetch(self.params.as_ptr().wrapping_add(character));
        if let Some(&entity) = self.scene.character_entities().get(character) {
            let entity = entity as usize;
            crate::math::prefetch(self.scene.ground_positions().as_ptr().wrapping_add(entity));
            crate::math::prefetch(self.scene.forwards().as_ptr().wrapping_add(entity));
            crate::math::prefetch(self.scene.headings().as_ptr().wrapping_add(entity));
            crate::math::prefetch(self.scene.velocities().as_ptr().wrapping_add(entity));
            self.neighbours.prefetch_entity(entity);
        }
    }

    /// One frame for the characters of `slices`, the first of which is character `first`:
    /// attention for each, then gaze IK for all, a lane group at a time (or one of the two, as
    /// `frame.parts` says).
    fn step_characters(&self, frame: &Frame, first: usize, mut slices: CharacterSlices<'_>) {
        if frame.parts != StepParts::Gaze {
            let mut batch = CandidateBatch::default();
            for local in 0..slices.lod.len() {
                self.attend(frame, first + local, slices.character(local), &mut batch);
            }
        }
        if frame.parts != StepParts::Attention {
            self.move_gaze(frame.dt, first, slices);
        }
    }

    /// Attention for one character by its model, every `period` steps (level of detail):
    /// the crowd model's best entities, threshold and interest point (online; a plan
    /// replaces them), or the saliency and baseline models' eye and head targets.
    fn attend(
        &self,
        frame: &Frame,
        character: usize,
        state: CharacterMut<'_>,
        batch: &mut CandidateBatch,
    ) {
        let config = &self.config;
        let period = match state.lod.period {
            0 => {
                let entity = self.scene.character_entities()[character] as usize;
                let far = config.lod_distance > 0.0
                    && frame.viewer.is_some_and(|viewer| {
                        viewer.distance(self.scene.ground_positions()[entity]) > config.lod_distance
                    });
                if far {
                    config.far_attention_period
                } else {
                    config.attention_period
                }
            }
            period => period,
        };
        state.lod.pending += frame.dt;
        if !(frame.step_index + u64::from(state.lod.stagger)).is_multiple_of(u64::from(period)) {
            return;
        }
        let dt = std::mem::take(&mut state.lod.pending);
        match self.params[character].model {
            AttentionModel::Crowd if frame.planned => {}
            AttentionModel::Crowd => {
                let ModelState::Crowd(tracker) = state.model else {
                    return;
                };
                let (best, second) = nearby_candidates(
                    &self.scene,
                    &self.neighbours,
                    &self.scorer,
                    character,
                    &self.params[character].weights,
                    batch,
                    |id| tracker.is_cooling(id),
                );
                tracker.update(best, second, frame.max_score, dt, &config.interest);
            }
            AttentionModel::Saliency => self.attend_saliency(character, dt, state),
            AttentionModel::Baseline => self.attend_baseline(character, dt, state),
        }
    }

    /// Gaze IK for the characters of `slices` (the first is character `first`), up to
    /// [`BATCH_LANES`] per [`GazeMotion::update_batch`] call (which runs them as many at a
    /// time as the processor's SIMD lanes hold). Within each chunk of [`SORT_CHUNK`]
    /// characters, those at rest with nothing to look at ([`GazeMotion::is_resting`]) are
    /// batched apart from the others: a lane group costs the same whichever of its lanes
    /// move, and a group of resting characters only carries their eye rays along. (A
    /// character's result does not depend on its batch.)
    fn move_gaze(&self, dt: f32, first: usize, slices: CharacterSlices<'_>) {
        let CharacterSlices {
            models,
            motions,
            gaze_randoms,
            ..
        } = slices;
        let count = motions.len();
        let mut chunk = 0;
        while chunk < count {
            let len = (count - chunk).min(SORT_CHUNK);
            let ahead_motions = motions.as_ptr();
            let motions = &mut motions[chunk..chunk + len];
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
                    motion: &motions[local],
                };
                self.gaze_request(first + chunk + local, view)
            });
            let resting = |local: usize| motions[local].is_resting(requests[local].as_ref());
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
                let mut each = motions.iter_mut();
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
                    self.move_group(
                        dt,
                        first + chunk,
                        group,
                        &requests,
                        &mut motions,
                        &mut randoms,
                    );
                    start += lanes;
                }
            }
            chunk += len;
        }
    }

    /// Gaze IK for one batch: the characters `first + group[i]`, whose requests are
    /// `requests[group[i]]` and whose motions and random streams are taken from
    /// `motions[group[i]]` and `randoms[group[i]]` (each `Some`, and `group` without
    /// repeats).
    fn move_group(
        &self,
        dt: f32,
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
            std::array::from_fn(|lane| self.character_transform(first + local(lane)));
        let chains: [&GazeChain; LANES] =
            std::array::from_fn(|lane| &self.chains[self.chain_of[first + local(lane)] as usize]);
        // Rest poses are read in place; a pose the engine set is unpacked here.
        let mut unpacked = [[Quat::IDENTITY; MAX_CHAIN_JOINTS]; LANES];
        for (lane, unpacked) in unpacked.iter_mut().enumerate().take(lanes) {
            let character = first + local(lane);
            if self.posed[character] {
                *unpacked = self.base_pose(character);
            }
        }
        let bases: [&[Quat; MAX_CHAIN_JOINTS]; LANES] = std::array::from_fn(|lane| {
            let character = first + local(lane);
            if self.posed[character] && lane < lanes {
                &unpacked[lane]
            } else {
                &self.chain_rests[self.chain_of[character] as usize]
            }
        });
        let inputs: [GazeInput<'_>; LANES] = std::array::from_fn(|lane| GazeInput {
            character: transforms[lane],
            base: &bases[lane][..chains[lane].joint_count()],
            request: requests[local(lane)],
            dt,
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
                        &self.config.gaze,
                        &inputs,
                    ),)*
                    _ => unreachable!("1 to BATCH_LANES characters per batch"),
                }
            };
        }
        update_lanes!(1 2 3 4 5 6 7 8 9 10 11 12 13 14 15 16);
    }

    /// The automatic interest point of a character (dense index) and its `S_max`.
    pub(super) fn automatic_target(
        &self,
        character: usize,
        tracker: Option<&crate::attention::interest::InterestTracker>,
    ) -> (u32, f32) {
        match (&self.plan, tracker) {
            (Some(plan), _) => {
                let (target, s_max, _) = plan.current(character);
                (target, s_max)
            }
            (None, Some(tracker)) => (tracker.interest(), tracker.s_max()),
            (None, None) => (NO_ENTITY, 0.0),
        }
    }

    /// What a character (dense index) should look at this frame: its explicit target if
    /// one applies, else what its attention model chose, as a gaze request.
    pub(super) fn gaze_request(
        &self,
        character: usize,
        view: CharacterView<'_>,
    ) -> Option<GazeRequest> {
        let model = self.params[character].model;
        let (automatic, s_max) = match model {
            AttentionModel::Crowd => self.automatic_target(character, view.model.tracker()),
            _ => (NO_ENTITY, 0.0),
        };
        let automatic = self
            .scene
            .index_of(automatic)
            .map(|index| (automatic, index));
        let model_request = match model {
            AttentionModel::Crowd => None,
            _ => self.model_request(character, view),
        };
        let idle = automatic.is_none() && model_request.is_none();
        let explicit = match self.explicit[character] {
            Some((target, TargetPriority::Override)) => Some(target),
            Some((target, TargetPriority::WhenIdle)) if idle => Some(target),
            _ => None,
        };
        let (key, point, interest_ratio) = match (explicit, automatic) {
            (Some(ExplicitTarget::Point(point)), _) => (EXPLICIT_POINT_KEY, point, 1.0),
            (Some(ExplicitTarget::Entity(id)), _) => {
                let index = self.scene.index_of(id)?;
                (u64::from(id), self.scene.look_at_point(index), 1.0)
            }
            (None, Some((id, index))) => {
                let max_score = self.scene.max_impact();
                let ratio = if max_score > 0.0 {
                    s_max / max_score
                } else {
                    1.0
                };
                (
                    u64::from(id),
                    self.scene.look_at_point(index),
                    ratio.clamp(0.05, 1.0),
                )
            }
            (None, None) => return model_request,
        };
        Some(GazeRequest {
            target_key: key,
            head_target: point,
            eye_target: point,
            interest_ratio,
            style: MotionStyle::Eased,
        })
    }

    /// A character's (dense index) world transform.
    pub(super) fn character_transform(&self, character: usize) -> CharacterTransform {
        let entity = self.scene.character_entities()[character] as usize;
        CharacterTransform::from_heading(
            self.scene.positions()[entity],
            self.config.world.up,
            self.scene.headings()[entity],
        )
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn claims_detect_overlap_and_undo_a_failed_claim() {
        let mut claims = ClaimSet::new(200, &"test").unwrap();
        assert!(claims.claim(10, 70));
        assert!(claims.claim(70, 130));
        assert!(!claims.claim(0, 11), "overlaps 10");
        assert!(!claims.claim(125, 190), "overlaps 125..130");
        // The failed claims took nothing: 0..10 and 130..200 are still free.
        assert_eq!(claims.next_unclaimed(0, 200), Some((0, 10)));
        assert_eq!(claims.next_unclaimed(10, 200), Some((130, 200)));
        assert!(claims.claim(130, 200));
        assert!(claims.claim(0, 10));
        assert_eq!(claims.next_unclaimed(0, 200), None);
        assert!(claims.claim(5, 5), "an empty range takes nothing");
        claims.clear();
        assert_eq!(claims.next_unclaimed(0, 200), Some((0, 200)));
    }

    #[test]
    fn masks_cover_exactly_the_range() {
        assert_eq!(ClaimSet::mask(0, 0, 64), u64::MAX);
        assert_eq!(ClaimSet::mask(0, 1, 3), 0b110);
        assert_eq!(ClaimSet::mask(1, 60, 70), 0b11_1111);
        assert_eq!(ClaimSet::mask(0, 60, 70), 0xF << 60);
        assert_eq!(ClaimSet::mask(2, 0, 64), 0);
    }
}
