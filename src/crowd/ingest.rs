//! Ingesting a frame: the entities' positions, headings and velocities from the engine,
//! checked, into the scene (and the recording, for the offline plan) — in one call, or in
//! ranges pushed from several threads ([`PushRanges`]).

use super::Crowd;
use crate::error::{Error, Result};
use crate::scene::{EntityUpdate, SceneWriter};

/// How many states ahead a push asks the processor for the entity slots it will write.
const PREFETCH_AHEAD: usize = 8;

/// How far past the previous state's entity a state's may be stored and still be left to
/// the processor's prefetcher (a few cache lines of the widest slot array).
const NEARBY: u32 = 16;

impl Crowd {
    /// Time of the last pushed frame (−∞ before the first).
    pub fn time(&self) -> f64 {
        self.shared.time
    }

    /// Ingests one frame of entity states at time `time` (seconds, not earlier than the
    /// previous frame). Entities not listed keep their last state; an entity listed twice
    /// takes both states in turn. With recording on, the states are also recorded for
    /// [`plan`](Self::plan). Fails without changing anything on an unknown id, a non-finite
    /// value, an earlier time, a full recording, while a plan is active or while a step or
    /// a ranged push is open.
    pub fn push_frame(&mut self, time: f64, updates: &[EntityUpdate]) -> Result<()> {
        self.push_frame_with(time, updates.len(), |i| Ok(updates[i]))
    }

    /// [`push_frame`](Self::push_frame) for states produced on the fly: `state(i)` for
    /// `i < count` converts the caller's i-th state (it is called more than once per state:
    /// to check them all, to record them with recording on, to apply). Lets a caller hand
    /// over its own layout without a buffer.
    pub fn push_frame_with<E: From<Error>>(
        &mut self,
        time: f64,
        count: usize,
        state: impl Fn(usize) -> std::result::Result<EntityUpdate, E>,
    ) -> std::result::Result<(), E> {
        self.check_frame_time(time)?;
        self.ensure_online("push a frame")?;
        // Check every state first, noting its entity's index while there is room (between
        // steps the grid order's buffer is free, and holds an index per entity), and
        // whether an entity comes twice (flagged in the push claims, free outside a ranged
        // push).
        let staged = &mut self.grid_order;
        staged.clear();
        let stage = count <= staged.capacity();
        let mut distinct = stage;
        let mut checked = Ok(());
        for i in 0..count {
            match state(i).and_then(|update| Ok(self.shared.scene.check_update(&update)?)) {
                Ok(index) if stage => {
                    staged.push(index as u32);
                    distinct &= self.pushed.claim_one_alone(index);
                }
                Ok(_) => {}
                Err(error) => {
                    checked = Err(error);
                    break;
                }
            }
        }
        self.pushed.release_alone(staged);
        checked?;
        if self.shared.recording.is_enabled() {
            self.shared
                .recording
                .record_with(time, count, |i| state(i).ok())?;
        }
        let shared = &mut *self.shared;
        if distinct {
            let writer = shared.scene.writer();
            let update = |i: usize| {
                // Ask for the slots of an entity ahead unless it follows the one before
                // (then the processor's own prefetcher streams them, and asking slows it).
                let ahead = i + PREFETCH_AHEAD;
                if let (Some(&before), Some(&next)) = (staged.get(ahead - 1), staged.get(ahead)) {
                    if next.wrapping_sub(before) > NEARBY {
                        writer.prefetch(next as usize);
                    }
                }
                Some((staged[i] as usize, state(i).ok()?))
            };
            // SAFETY: `check_update` returned each index for its state's id, so they are
            // in range, and no two alike; `&mut self` keeps every other access out.
            unsafe { writer.apply_distinct(time, count, update) };
        } else {
            // In order, one after the other: an entity listed twice takes both states.
            for i in 0..count {
                if let Ok(update) = state(i) {
                    shared.scene.apply_one(time, &update);
                }
            }
        }
        shared.time = time;
        Ok(())
    }

    /// Fails unless `time` may be the next frame's: finite, not before the previous one.
    fn check_frame_time(&self, time: f64) -> Result<()> {
        if !time.is_finite() {
            return Err(Error::NonFinite(format!("frame time is {time}")));
        }
        if time < self.shared.time {
            return Err(Error::InvalidArgument(format!(
                "frame time {time} is earlier than the previous frame's {}",
                self.shared.time
            )));
        }
        Ok(())
    }

    /// Begins a frame pushed in ranges at time `time` (seconds, not earlier than the
    /// previous frame): then push the entities' states in parts with
    /// [`push_ranges`](Self::push_ranges) (from any number of threads) or
    /// [`push_range`](Self::push_range), and finish with [`end_push`](Self::end_push). The
    /// result is the same as one [`push_frame`](Self::push_frame) of all the parts, whatever
    /// the split, as long as no entity is pushed twice. Until `end_push`, the crowd cannot
    /// step, change its entities or push a whole frame ([`Error::WrongState`]).
    ///
    /// Fails without changing anything on a non-finite or earlier `time`, while a step or
    /// a push is open or a plan is active, or with recording on (record frames with
    /// `push_frame`) ([`Error::WrongState`]).
    pub fn begin_push(&mut self, time: f64) -> Result<()> {
        self.check_frame_time(time)?;
        self.ensure_online("begin a push")?;
        if self.shared.recording.is_enabled() {
            return Err(Error::WrongState(
                "cannot push in ranges with recording on (max_recorded_states > 0): push \
                 whole frames"
                    .into(),
            ));
        }
        self.pushed.clear();
        self.open_push = Some(time);
        Ok(())
    }

    /// True between [`begin_push`](Self::begin_push) and [`end_push`](Self::end_push).
    pub fn is_push_open(&self) -> bool {
        self.open_push.is_some()
    }

    /// The open push's ranges, to push from several threads (`PushRanges` is `Sync`): each
    /// thread calls [`PushRanges::push`] with its own entities' states. Fails with
    /// [`Error::WrongState`] when no push is open.
    pub fn push_ranges(&mut self) -> Result<PushRanges<'_>> {
        let time = self
            .open_push
            .ok_or_else(|| Error::WrongState("no push is open: begin one first".into()))?;
        Ok(PushRanges {
            writer: self.shared.scene.writer(),
            claims: &self.pushed,
            time,
        })
    }

    /// Pushes some entities' states into the open push (see [`PushRanges::push`]).
    pub fn push_range(&mut self, updates: &[EntityUpdate]) -> Result<()> {
        self.push_ranges()?.push(updates)
    }

    /// Ends the open push: the frame's time becomes the crowd's. Entities no range pushed
    /// keep their last state. Fails with [`Error::WrongState`] when no push is open.
    pub fn end_push(&mut self) -> Result<()> {
        let time = self
            .open_push
            .take()
            .ok_or_else(|| Error::WrongState("no push is open: begin one first".into()))?;
        self.shared.time = time;
        Ok(())
    }
}

/// An open push's ranges: shared with every thread that pushes a part of the frame. Each
/// entity may be pushed once per push: its first push claims it.
#[derive(Debug, Clone, Copy)]
pub struct PushRanges<'a> {
    writer: SceneWriter<'a>,
    claims: &'a super::claims::ClaimSet,
    time: f64,
}

impl PushRanges<'_> {
    /// The crowd's world conventions (units, axes).
    pub fn world(&self) -> crate::world::World {
        self.writer.world()
    }

    /// Pushes these entities' states into the open push, as
    /// [`Crowd::push_frame`] would. Safe to call from several threads at once. Fails
    /// without changing anything on an unknown id or a non-finite value, or if an entity
    /// is listed twice or was pushed already in this push, by this thread or another
    /// ([`Error::WrongState`]).
    pub fn push(&self, updates: &[EntityUpdate]) -> Result<()> {
        self.push_with(updates.len(), |i| Ok(updates[i]))
    }

    /// [`push`](Self::push) for states produced on the fly, as
    /// [`Crowd::push_frame_with`] takes them (`state` may be called more than once per
    /// state).
    pub fn push_with<E: From<Error>>(
        &self,
        count: usize,
        state: impl Fn(usize) -> std::result::Result<EntityUpdate, E>,
    ) -> std::result::Result<(), E> {
        // Check each state and claim its entity, so that no other thread writes it.
        let mut claimed = 0;
        let mut failure = None;
        while claimed < count {
            let checked = state(claimed).and_then(|update| {
                let index = self.writer.check(&update)?;
                if self.claims.claim_one(index) {
                    Ok(())
                } else {
                    Err(Error::WrongState(format!(
                        "entity {} was pushed already in this push",
                        update.id
                    ))
                    .into())
                }
            });
            if let Err(error) = checked {
                failure = Some(error);
                break;
            }
            claimed += 1;
        }
        if let Some(error) = failure {
            // Give back what this call took: states before the failing one checked.
            for i in 0..claimed {
                if let Some(index) = state(i).ok().and_then(|u| self.writer.index_of(u.id)) {
                    self.claims.release_one(index);
                }
            }
            return Err(error);
        }
        let update = |i: usize| {
            let update = state(i).ok()?;
            Some((self.writer.index_of(update.id)?, update))
        };
        // SAFETY: the index of a live id is in range, and this call claimed each entity
        // above: they are distinct, and no other thread writes them in this push.
        unsafe { self.writer.apply_distinct(self.time, count, update) };
        Ok(())
    }
}
