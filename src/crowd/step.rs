//! Stepping the crowd: one frame of the attention job then the gaze job for every
//! character, whole ([`Crowd::step`], on the crowd's worker threads) or in ranges run by
//! the engine's own threads ([`Crowd::begin_step`], [`StepRanges::run_range`],
//! [`Crowd::end_step`]). Both ways run the same jobs on the same inputs: the result does not
//! depend on how the crowd is split or how many threads run it.

use super::attention_job::{AttentionJob, Frame};
use super::gaze_job::GazeJob;
use super::look::LookContext;
use super::pool::WorkerPool;
use super::published::PublishTarget;
use super::ranges::StepRanges;
use super::states::RawCharacterSlices;
use super::values::{ExplicitTarget, TargetPriority};
use super::{Crowd, Shared};
use crate::attention::following::{Cue, CUE_CELL_MIN};
use crate::error::{ensure_finite, Error, Result};
use crate::scene::ids::EntityKind;

/// Characters per task when [`Crowd::step`] shares a step among its worker threads.
const CHARACTERS_PER_TASK: usize = 128;

/// From this many characters on, attention visits characters in spatial-grid order: the
/// neighbours' data (about 40 bytes an entity) then outgrows the caches, and visiting
/// neighbours one after another keeps it in them (each character's own state, read out of
/// order then, is prefetched a few characters ahead). Below, the dense order is as fast:
/// the neighbour data fits the caches anyway, and the per-character state is read in
/// sequence. (Measured on the plaza with the prefetch: grid order as fast at 10 000, 30%
/// faster at 100 000 than grid order without it.)
const GRID_ORDER_FROM: usize = 30_000;

/// The longest time one step simulates, seconds (one hour): a longer `dt` (a pause, a time
/// stamp passed as a step) moves attention, gaze, blinks and conversations on by this much,
/// long after every one of them has settled, and keeps their clocks finite. A plan's replay
/// clock still moves by the whole `dt`.
pub const MAX_SIMULATED_STEP: f32 = 3600.0;

impl Crowd {
    /// Steps every character `dt` seconds after the previous step: the attention job (by
    /// each character's model and level of detail), then the gaze job. With `threads > 1`
    /// in the config the characters are shared among the crowd's worker threads; the
    /// result is the same.
    pub fn step(&mut self, dt: f32) -> Result<()> {
        self.step_jobs(dt, true, true)
    }

    /// Runs the attention job alone, without moving any gaze chain. For tools and
    /// benchmarks that only need who looks at what.
    pub fn step_attention(&mut self, dt: f32) -> Result<()> {
        self.step_jobs(dt, true, false)
    }

    /// Runs the gaze job alone: every chain moves towards what its character attends to
    /// now, and attention keeps its state. For benchmarks and tools that time or drive the
    /// two halves of a step apart.
    pub fn step_gaze(&mut self, dt: f32) -> Result<()> {
        self.step_jobs(dt, false, true)
    }

    /// A whole step on the worker threads (when there are some): begin the frame, the
    /// attention job over every character in grid order, the gaze job over every character
    /// in storage order, each split into tasks of [`CHARACTERS_PER_TASK`].
    fn step_jobs(&mut self, dt: f32, attention: bool, gaze: bool) -> Result<()> {
        self.begin_step(dt)?;
        let pool = match self.pool.take() {
            // In a child forked from the process that started the workers, they are gone:
            // start them anew (or step on this thread alone if that fails; the result is
            // the same).
            Some(pool) if pool.is_forked() => WorkerPool::new(pool.workers()).ok(),
            pool => pool,
        };
        let ranges = self.step_ranges()?;
        let count = ranges.character_count();
        let mut result = Ok(());
        if attention {
            result = in_tasks(pool.as_ref(), count, &|first, count| {
                let order = &ranges.grid_order[first..first + count];
                // SAFETY: tasks cover disjoint parts of the grid order (a permutation), and
                // nothing else runs on this step's characters until `in_tasks` returns.
                unsafe { ranges.attention.run_in_order(order) }
            });
        }
        if gaze {
            let moved = in_tasks(pool.as_ref(), count, &|first, count| {
                // SAFETY: as above, for disjoint storage ranges.
                unsafe { ranges.gaze.run(first, count) }
            });
            result = result.and(moved);
        }
        // Every character was stepped: close the step without end_step's sweep.
        self.pool = pool;
        self.open_step = None;
        if gaze && result.is_ok() {
            self.published_by_step();
        }
        result
    }

    /// Begins a step `dt` seconds after the previous one: advances the plan's clock,
    /// rebuilds the spatial grid and fixes what every character shares this frame. Then
    /// run ranges of characters with [`step_ranges`](Self::step_ranges) (from any number of
    /// threads) or [`step_range`](Self::step_range), and finish with
    /// [`end_step`](Self::end_step). Any finite `dt` returns in a time bounded by the
    /// crowd's size; a step longer than [`MAX_SIMULATED_STEP`] simulates that much. Fails
    /// without changing anything on a negative or non-finite `dt`, or if a step or a push
    /// is already open ([`Error::WrongState`]).
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
        if self.open_push.is_some() {
            return Err(Error::WrongState(
                "a push is open: end it before stepping".into(),
            ));
        }
        let shared = &mut *self.shared;
        if let Some(plan) = &mut shared.plan {
            plan.advance(dt, &mut shared.scene);
        }
        let dt = dt.min(MAX_SIMULATED_STEP);
        let (settings, seed) = (&shared.config.conversation, shared.config.seed);
        shared
            .conversations
            .advance(settings, seed, dt, &shared.scene);
        shared
            .neighbours
            .rebuild(&shared.scene, shared.config.scoring.talking_gain);
        let period = self.shared.config.reorder_period;
        if period > 0 && self.shared.steps.is_multiple_of(u64::from(period)) {
            self.store_in_grid_order();
        }
        self.gather_cues();
        let shared = &mut *self.shared;
        let viewer = shared
            .viewer
            .and_then(|id| shared.scene.index_of(id))
            .map(|index| shared.scene.ground_positions()[index]);
        self.open_step = Some(Frame {
            dt,
            step_index: shared.steps,
            viewer,
            max_score: shared.scene.max_impact(),
        });
        shared.steps += 1;
        // Where the gaze job publishes each character's outputs, for the readers.
        let shared = &*self.shared;
        self.published.begin_step();
        self.published.lay_out(&self.read_order, |character| {
            shared
                .characters
                .chain(&shared.chains, character)
                .joint_count()
        });
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
        let shared = &mut *self.shared;
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
        shared.characters.reorder(order, reorder);
        self.states.reorder(order, reorder);
        // The new dense index of each old one, for the readers' order.
        reorder.invert(order);
        for character in &mut self.read_order {
            *character = order[*character as usize];
        }
        self.published.storage_moved();
        shared
            .neighbours
            .rebuild(&shared.scene, shared.config.scoring.talking_gain);
    }

    /// Gathers the characters that show a gaze worth following this step (nothing when
    /// following is off): a stare (weight 1) while game logic has one look at a point or
    /// an object with an overriding target, a glance (the glance weight) while one follows
    /// others' gaze; sorted by ground cell of the follow distance's size. Read-only during
    /// the step, so that no character sees another halfway through its update, whatever
    /// the ranges and threads.
    fn gather_cues(&mut self) {
        if !self.shared.config.following.enabled {
            return;
        }
        let following = self.shared.config.following;
        let cell_size = following.distance.max(CUE_CELL_MIN);
        let shared = &mut *self.shared;
        let (scene, characters, cues) = (&shared.scene, &shared.characters, &mut shared.cues);
        cues.clear();
        for (character, follow) in self.states.follows.iter().enumerate() {
            let entity = scene.character_entities()[character] as usize;
            let stare = match characters.explicit[character].get() {
                Some((ExplicitTarget::Point(point), TargetPriority::Override)) => Some(point),
                Some((ExplicitTarget::Entity(id), TargetPriority::Override)) => scene
                    .index_of(id)
                    .filter(|&index| scene.kinds()[index] != EntityKind::Character)
                    .map(|index| scene.look_at_point(index)),
                _ => None,
            };
            let (point, weight) = match (stare, follow.following()) {
                (Some(point), _) => (point, 1.0),
                (None, Some(point)) => (point, following.glance_cue_weight),
                (None, None) => continue,
            };
            if weight <= 0.0 || cues.len() == cues.capacity() {
                // (Never full: one per character at most, reserved at creation.)
                continue;
            }
            let ground = scene.ground_positions()[entity];
            cues.push(Cue {
                cell: Cue::cell_of(ground, cell_size),
                id: scene.ids()[entity],
                ground,
                velocity: scene.velocities()[entity],
                point,
                weight,
            });
        }
        cues.sort_unstable_by(|a, b| a.cell.cmp(&b.cell).then(a.id.cmp(&b.id)));
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
        let (attention, gaze) = self
            .shared
            .jobs(frame, self.states.raw(), self.published.target());
        attention.validate()?;
        gaze.validate()?;
        Ok(StepRanges {
            attention,
            gaze,
            grid_order: &self.grid_order,
            claims: &self.claims,
        })
    }

    /// Steps characters `first .. first + count` of the open step (see
    /// [`StepRanges::run_range`]).
    pub fn step_range(&mut self, first: usize, count: usize) -> Result<()> {
        self.step_ranges()?.run_range(first, count)
    }

    /// Marks the outputs the gaze job published during the step just closed as the
    /// readers': nothing has changed since.
    fn published_by_step(&mut self) {
        self.shared.changed = false;
        self.states.changed = false;
    }

    /// Ends the open step, first stepping every character that no range covered, so that
    /// a step always moves the whole crowd. Fails with [`Error::WrongState`] when no step
    /// is open.
    pub fn end_step(&mut self) -> Result<()> {
        let frame = self
            .open_step
            .ok_or_else(|| Error::WrongState("no step is open: begin one first".into()))?;
        let count = self.character_count();
        let (attention, gaze) = self
            .shared
            .jobs(frame, self.states.raw(), self.published.target());
        attention.validate()?;
        gaze.validate()?;
        let mut from = 0;
        while let Some((first, end)) = self.claims.next_unclaimed(from, count) {
            // SAFETY: `&mut self`: nothing else touches the crowd, and the arrays stay put
            // while the jobs run.
            unsafe {
                attention.run(first, end - first);
                gaze.run(first, end - first);
            }
            from = end;
        }
        self.open_step = None;
        self.published_by_step();
        Ok(())
    }
}

impl Shared {
    /// What resolving a character's look reads, now (for the jobs and the readers).
    pub(super) fn look(&self) -> LookContext<'_> {
        LookContext {
            scene: &self.scene,
            world: self.config.world,
            characters: &self.characters,
            chains: &self.chains,
            plan: self.plan.as_ref(),
            eased_style: self.config.eye_motion.eased_style(),
            conversations: &self.conversations,
            seed: self.config.seed,
            following: self.config.following.enabled,
            cues: &self.cues,
            street: &self.config.street,
        }
    }

    /// The two jobs of a step with `frame`, writing into the arrays of `states`.
    fn jobs(
        &self,
        frame: Frame,
        states: RawCharacterSlices,
        publish: PublishTarget,
    ) -> (AttentionJob<'_>, GazeJob<'_>) {
        let look = self.look();
        let attention = AttentionJob {
            frame,
            config: &self.config,
            scorer: &self.scorer,
            neighbours: &self.neighbours,
            look,
            states,
        };
        let gaze = GazeJob {
            dt: frame.dt,
            config: &self.config.gaze,
            look,
            states,
            publish,
            initial_threshold: self.config.interest.initial_threshold,
            blinks: &self.config.blinks,
            seed: self.config.seed,
        };
        (attention, gaze)
    }
}

/// Runs `task(first, count)` over `0 .. count` in pieces of [`CHARACTERS_PER_TASK`], on
/// `pool`'s threads when there is one.
fn in_tasks(
    pool: Option<&WorkerPool>,
    count: usize,
    task: &(dyn Fn(usize, usize) + Sync),
) -> Result<()> {
    let tasks = count.div_ceil(CHARACTERS_PER_TASK);
    let run = |index: usize| {
        let first = index * CHARACTERS_PER_TASK;
        task(first, CHARACTERS_PER_TASK.min(count - first));
    };
    match pool {
        Some(pool) => pool.run(tasks, &run),
        None => {
            (0..tasks).for_each(run);
            Ok(())
        }
    }
}
