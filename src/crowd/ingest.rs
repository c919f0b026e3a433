//! Ingesting a frame: the entities' positions, headings and velocities from the engine,
//! checked, into the scene (and the recording, for the offline plan) — in one call, or in
//! ranges pushed from several threads ([`PushRanges`]).

use super::claims::{ClaimChain, ClaimLinks, ClaimSet};
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
    /// `i < count` converts the caller's i-th state. Lets a caller hand over its own layout
    /// without a buffer. `state` is called more than once per state (to check them all, to
    /// record them with recording on, to apply) and should give the same state each time.
    /// If it does not, the call stays sound: a later call's state is applied only if it
    /// passes the checks and, when the first calls' entities were all distinct, names the
    /// same entity as the first call; the others are skipped, the rest of the frame is
    /// applied, and the call returns [`Error::InvalidArgument`].
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
        // whether an entity comes twice (flagged in the push claims, clear outside a ranged
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
        let shared = &mut *self.shared;
        let first = |i: usize| staged.get(i).copied();
        let mut skipped = false;
        if shared.recording.is_enabled() {
            let scene = &shared.scene;
            let skipped_here = std::cell::Cell::new(false);
            shared.recording.record_with(time, count, |i| {
                let update = again(&state, i, |u| scene.check_update(u), first(i));
                skipped_here.set(skipped_here.get() || update.is_none());
                update.map(|(_, update)| update)
            })?;
            skipped = skipped_here.get();
        }
        if distinct {
            let writer = shared.scene.writer();
            let states = (0..count).filter_map(|i| {
                // Ask for the slots of an entity ahead unless it follows the one before
                // (then the processor's own prefetcher streams them, and asking slows it).
                let ahead = i + PREFETCH_AHEAD;
                if let (Some(&before), Some(&next)) = (staged.get(ahead - 1), staged.get(ahead)) {
                    if next.wrapping_sub(before) > NEARBY {
                        writer.prefetch(next as usize);
                    }
                }
                let applied = again_at(&state, i, staged[i] as usize, &writer);
                skipped |= applied.is_none();
                applied
            });
            // SAFETY: `again_at` passes only the first call's index (from `check`: in range,
            // and distinct), with a state that names it; `&mut self` keeps every other
            // access out.
            unsafe { writer.apply_distinct(time, states) };
        } else {
            // In order, one after the other: an entity listed twice takes both states.
            for i in 0..count {
                match again(&state, i, |u| shared.scene.check_update(u), first(i)) {
                    Some((_, update)) => shared.scene.apply_one(time, &update),
                    None => skipped = true,
                }
            }
            #[cfg(test)]
            tests::IN_ORDER_PUSHES.with(|pushes| pushes.set(pushes.get() + 1));
        }
        shared.time = time;
        if skipped {
            return Err(inconsistent_states().into());
        }
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
        // The grid order's buffer, free between steps, holds the push's claim links: one
        // per entity (within its room for every entity: no allocation).
        let entities = self.shared.scene.len();
        if self.grid_order.len() < entities {
            self.grid_order.resize(entities, 0);
        }
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
            links: ClaimLinks::new(&mut self.grid_order),
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
        // Clear outside a ranged push: a whole frame's push reads them to find repeats.
        self.pushed.clear();
        self.shared.time = time;
        Ok(())
    }
}

/// State `i` from a later call of a push's `state`: with its entity's index if it passes
/// `check` and names the entity `first` (the first call's, when noted); else `None`.
fn again<E>(
    state: &impl Fn(usize) -> std::result::Result<EntityUpdate, E>,
    i: usize,
    check: impl FnOnce(&EntityUpdate) -> Result<usize>,
    first: Option<u32>,
) -> Option<(usize, EntityUpdate)> {
    let update = state(i).ok()?;
    let index = check(&update).ok()?;
    first
        .is_none_or(|first| first as usize == index)
        .then_some((index, update))
}

/// State `i` from a later call of a push's `state`, with `index`, the entity its first
/// call named (checked then), if it still names it with valid values; else `None`.
#[inline(always)]
fn again_at<E>(
    state: &impl Fn(usize) -> std::result::Result<EntityUpdate, E>,
    i: usize,
    index: usize,
    writer: &SceneWriter<'_>,
) -> Option<(usize, EntityUpdate)> {
    let update = state(i).ok()?;
    writer.recheck(index, &update).then_some((index, update))
}

/// The error of a push whose `state` closure gave different states on two calls.
fn inconsistent_states() -> Error {
    Error::InvalidArgument(
        "the state closure gave a different state for the same index on a later call: \
         the states it gave the same were applied, the others skipped"
            .into(),
    )
}

/// An open push's ranges: shared with every thread that pushes a part of the frame. Each
/// entity may be pushed once per push: its first push claims it.
#[derive(Debug, Clone, Copy)]
pub struct PushRanges<'a> {
    writer: SceneWriter<'a>,
    claims: &'a ClaimSet,
    /// Each call's chain of the entities it claimed.
    links: ClaimLinks<'a>,
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
    /// [`Crowd::push_frame_with`] takes them: `state` is called twice per state (to check
    /// it and claim its entity, then to apply it) and should give the same state both
    /// times. If it does not, the call stays sound: it writes only the entities it claimed,
    /// each at most once, and gives back only its own claims. A state whose second call
    /// names another entity or fails its checks is skipped (its entity stays claimed,
    /// keeping its last state), the others are applied, and the call returns
    /// [`Error::InvalidArgument`].
    pub fn push_with<E: From<Error>>(
        &self,
        count: usize,
        state: impl Fn(usize) -> std::result::Result<EntityUpdate, E>,
    ) -> std::result::Result<(), E> {
        // Check each state and claim its entity, so that no other thread writes it; chain
        // the entities claimed: state k named the chain's k-th.
        let mut chain = ClaimChain::default();
        let mut failure = None;
        for i in 0..count {
            let checked = state(i).and_then(|update| {
                let index = self.writer.check(&update)?;
                if self.claims.claim_one(index) {
                    Ok(index)
                } else {
                    Err(Error::WrongState(format!(
                        "entity {} was pushed already in this push",
                        update.id
                    ))
                    .into())
                }
            });
            match checked {
                Ok(index) => self.links.append(&mut chain, index),
                Err(error) => {
                    failure = Some(error);
                    break;
                }
            }
        }
        if let Some(error) = failure {
            // Give back what this call took, and only that.
            for index in self.links.walk(chain) {
                self.claims.release_one(index);
            }
            return Err(error);
        }
        let mut skipped = false;
        let states = self.links.walk(chain).enumerate().filter_map(|(k, index)| {
            let applied = again_at(&state, k, index, &self.writer);
            skipped |= applied.is_none();
            applied
        });
        // SAFETY: every index passed is one of this call's chain: in range (`check`
        // returned it), claimed by this call above, so no other thread writes it in this
        // push, and each once (a claim succeeds once); and `again_at` passes it only with a
        // state naming it.
        unsafe { self.writer.apply_distinct(self.time, states) };
        if skipped {
            return Err(inconsistent_states().into());
        }
        Ok(())
    }
}

#[cfg(test)]
pub(super) mod tests {
    use std::cell::Cell;

    use glam::Vec3;

    use super::super::{CharacterDesc, Crowd, CrowdConfig};
    use crate::scene::EntityUpdate;

    thread_local! {
        /// Whole-frame pushes that took the in-order path, on this thread.
        pub static IN_ORDER_PUSHES: Cell<usize> = const { Cell::new(0) };
    }

    #[test]
    fn a_whole_frame_after_a_ranged_push_takes_the_fast_path() {
        let mut crowd = Crowd::new(CrowdConfig::default()).unwrap();
        let states: Vec<EntityUpdate> = (0..3)
            .map(|i| {
                let desc = CharacterDesc {
                    position: Vec3::new(i as f32, 0.0, 0.0),
                    ..CharacterDesc::default()
                };
                EntityUpdate {
                    id: crowd.add_character(&desc).unwrap(),
                    position: Vec3::new(i as f32, 0.0, 1.0),
                    heading: 0.0,
                    heading_from_motion: false,
                    velocity: None,
                    talking: false,
                }
            })
            .collect();
        crowd.begin_push(1.0).unwrap();
        crowd.push_range(&states).unwrap();
        crowd.end_push().unwrap();
        let in_order = || IN_ORDER_PUSHES.with(Cell::get);
        let before = in_order();
        crowd.push_frame(2.0, &states).unwrap();
        assert_eq!(
            in_order(),
            before,
            "distinct states after a ranged push: fast"
        );
        crowd.push_frame(3.0, &[states[0], states[0]]).unwrap();
        assert_eq!(in_order(), before + 1, "an entity twice: in order");
        crowd.push_frame(4.0, &states).unwrap();
        assert_eq!(in_order(), before + 1, "distinct states again: fast");
    }
}
