//! Ingesting pushed entity states: checking one, and writing it into its entity's slots
//! (velocity by finite difference, heading from motion, turn rate), from one thread or,
//! through a [`SceneWriter`], from several at once.

use std::marker::PhantomData;

use glam::{DVec2, Vec2, Vec3};

use super::ids::IdTable;
use crate::error::{ensure_all_finite, ensure_finite, Result};
use crate::math::{prefetch, wrap_angle};
use crate::world::World;

/// Below this ground speed (m/s) a heading derived from motion keeps its last value, so
/// standing people do not spin.
pub const MIN_SPEED_FOR_HEADING: f32 = 0.1;

/// Fastest ground speed (m/s) an entity is taken to move at: a faster velocity, given or
/// derived from a jump between two frames, keeps its direction at this speed, so that speeds
/// and relative speeds stay finite. Far beyond what the speed subscore tells apart.
pub const MAX_SPEED: f32 = 1e9;

/// One entity's state for a frame, in metres and radians (converted from the caller's units).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EntityUpdate {
    /// Entity id.
    pub id: u32,
    /// Root (ground) position, world axes, metres.
    pub position: Vec3,
    /// Heading (radians, counter-clockwise about up, 0 along forward); ignored when
    /// `heading_from_motion`.
    pub heading: f32,
    /// Derive the heading from the velocity's direction.
    pub heading_from_motion: bool,
    /// The velocity (world, m/s) if the caller knows it; else a finite difference is used.
    pub velocity: Option<Vec3>,
    /// The entity talks (lip-sync, chat, dialogue) in this frame.
    pub talking: bool,
}

/// `displacement / elapsed` (elapsed > 0), its length limited to [`MAX_SPEED`]; in `f64`,
/// where a jump across the whole `f32` range in a tiny time cannot overflow.
#[inline]
fn limited_velocity(displacement: DVec2, elapsed: f64) -> Vec2 {
    // Common case first, exactly as below: a displacement with both components under
    // MAX_SPEED · elapsed / 2 is shorter than MAX_SPEED · elapsed.
    let half_most = 0.5 * f64::from(MAX_SPEED) * elapsed;
    if displacement.x.abs() < half_most && displacement.y.abs() < half_most {
        return (displacement / elapsed).as_vec2();
    }
    let distance = displacement.length();
    let most = f64::from(MAX_SPEED) * elapsed;
    if distance > most {
        (displacement * (f64::from(MAX_SPEED) / distance)).as_vec2()
    } else {
        (displacement / elapsed).as_vec2()
    }
}

/// `velocity.length() >= MIN_SPEED_FOR_HEADING`, with the same result, skipping the square
/// root unless the squared speed is within 1 % of the threshold's square.
#[inline(always)]
fn fast_enough_for_heading(velocity: Vec2) -> bool {
    const SQUARE: f32 = MIN_SPEED_FOR_HEADING * MIN_SPEED_FOR_HEADING;
    let squared = velocity.length_squared();
    if squared > SQUARE * 1.01 {
        true
    } else if squared < SQUARE * 0.99 {
        false
    } else {
        velocity.length() >= MIN_SPEED_FOR_HEADING
    }
}

/// The turn from heading `from` to heading `to` (both wrapped), in [−π, π).
#[inline]
fn turn(from: f32, to: f32) -> f32 {
    use std::f32::consts::{PI, TAU};
    let shifted = to - from + PI;
    // `rem_euclid` returns an operand in [0, 2π) unchanged: skip its `fmod` for the usual
    // turn, with the same bits.
    let within = if (0.0..TAU).contains(&shifted) {
        shifted
    } else {
        shifted.rem_euclid(TAU)
    };
    within - PI
}

/// An entity's motion from a pushed state and its previous sample, before it is written.
#[derive(Debug, Clone, Copy)]
struct Motion {
    ground: Vec2,
    velocity: Vec2,
    /// The heading as given or from the velocity, not yet wrapped.
    heading: f32,
    /// Seconds since the entity's previous sample.
    elapsed: f64,
}

/// A given ground velocity, its length limited to [`MAX_SPEED`]: `limited_velocity(velocity,
/// 1.0)`, with the same bits, without its trip through `f64` for the usual velocity.
#[inline(always)]
fn given_velocity(velocity: Vec2) -> Vec2 {
    // Both components under MAX_SPEED / 2: shorter than MAX_SPEED, and `f32 → f64 → f32`
    // (with the division by 1) gives back the same value.
    const HALF: f32 = 0.5 * MAX_SPEED;
    if velocity.x.abs() < HALF && velocity.y.abs() < HALF {
        velocity
    } else {
        limited_velocity(velocity.as_dvec2(), 1.0)
    }
}

/// Checks one update against `ids` without changing anything (the id is live, the values
/// it uses finite: not the heading of one whose heading comes from its motion) and returns
/// its entity's index.
pub(super) fn check(ids: &IdTable, update: &EntityUpdate) -> Result<usize> {
    let (_, index) = ids.find(update.id)?;
    ensure_all_finite(&update.position.to_array(), "position")?;
    if !update.heading_from_motion {
        ensure_finite(update.heading, "heading")?;
    }
    if let Some(velocity) = update.velocity {
        ensure_all_finite(&velocity.to_array(), "velocity")?;
    }
    Ok(index as usize)
}

/// Writes pushed states into a scene's entities, from any number of threads at once as
/// long as no two write the same entity (the crowd's ranged push claims each entity
/// first). Holds the scene's per-entity arrays for its lifetime; reads only the slots it
/// writes and the id table.
#[derive(Debug, Clone, Copy)]
pub struct SceneWriter<'a> {
    world: World,
    ids: &'a IdTable,
    /// Each entity's id, by entity index.
    dense_ids: &'a [u32],
    len: usize,
    position: *mut Vec3,
    ground: *mut Vec2,
    heading: *mut f32,
    forward: *mut Vec2,
    velocity: *mut Vec2,
    turn_rate: *mut f32,
    last_time: *mut f64,
    talking: *mut bool,
    _arrays: PhantomData<&'a mut [Vec3]>,
}

// SAFETY: the pointers are the scene's arrays, borrowed mutably for 'a; `apply_at`'s
// contract keeps two threads from touching one entity's slots.
unsafe impl Send for SceneWriter<'_> {}
// SAFETY: as above.
unsafe impl Sync for SceneWriter<'_> {}

/// The per-entity arrays a pushed state writes, for [`SceneWriter::new`].
pub(super) struct PushedArrays<'a> {
    pub position: &'a mut [Vec3],
    pub ground: &'a mut [Vec2],
    pub heading: &'a mut [f32],
    pub forward: &'a mut [Vec2],
    pub velocity: &'a mut [Vec2],
    pub turn_rate: &'a mut [f32],
    pub last_time: &'a mut [f64],
    pub talking: &'a mut [bool],
}

impl<'a> SceneWriter<'a> {
    /// A writer into a scene's arrays (all as long as its entities) with its id table and
    /// the ids by entity index.
    pub(super) fn new(
        world: World,
        ids: &'a IdTable,
        dense_ids: &'a [u32],
        arrays: PushedArrays<'a>,
    ) -> Self {
        let len = arrays.position.len();
        assert!(
            [
                arrays.ground.len(),
                arrays.heading.len(),
                arrays.forward.len(),
                arrays.velocity.len(),
                arrays.turn_rate.len(),
                arrays.last_time.len(),
                arrays.talking.len()
            ]
            .iter()
            .chain([&dense_ids.len()])
            .all(|&other| other == len),
            "a scene's entity arrays differ in length"
        );
        SceneWriter {
            world,
            ids,
            dense_ids,
            len,
            position: arrays.position.as_mut_ptr(),
            ground: arrays.ground.as_mut_ptr(),
            heading: arrays.heading.as_mut_ptr(),
            forward: arrays.forward.as_mut_ptr(),
            velocity: arrays.velocity.as_mut_ptr(),
            turn_rate: arrays.turn_rate.as_mut_ptr(),
            last_time: arrays.last_time.as_mut_ptr(),
            talking: arrays.talking.as_mut_ptr(),
            _arrays: PhantomData,
        }
    }
}

impl SceneWriter<'_> {
    /// The scene's world conventions.
    pub fn world(&self) -> World {
        self.world
    }

    /// Checks one update without changing anything (the id is live, the values finite)
    /// and returns its entity's index, for [`apply_at`](Self::apply_at).
    pub fn check(&self, update: &EntityUpdate) -> Result<usize> {
        check(self.ids, update)
    }

    /// True if `update` is for entity `index` (below the entity count; its id is the
    /// entity's) and its values pass [`check`](Self::check): the same verdict as `check`
    /// returning `index`, without looking the id up. For a state read a second time.
    #[inline(always)]
    pub fn recheck(&self, index: usize, update: &EntityUpdate) -> bool {
        let finite = |v: Vec3| v.is_finite();
        self.dense_ids.get(index) == Some(&update.id)
            && finite(update.position)
            && (update.heading_from_motion || update.heading.is_finite())
            && update.velocity.is_none_or(finite)
    }

    /// The entity index of a live id, if any.
    pub fn index_of(&self, id: u32) -> Option<usize> {
        self.ids.lookup(id).map(|(_, index)| index as usize)
    }

    /// Asks the processor for the slots that [`apply_at`](Self::apply_at) on entity
    /// `index` reads and writes. Only a hint: any `index` is harmless.
    #[inline(always)]
    pub fn prefetch(&self, index: usize) {
        if index < self.len {
            prefetch(self.position.wrapping_add(index));
            prefetch(self.ground.wrapping_add(index));
            prefetch(self.heading.wrapping_add(index));
            prefetch(self.forward.wrapping_add(index));
            prefetch(self.velocity.wrapping_add(index));
            prefetch(self.turn_rate.wrapping_add(index));
            prefetch(self.last_time.wrapping_add(index));
            prefetch(self.talking.wrapping_add(index));
        }
    }

    /// Writes `update`, taken at `time` (seconds), into entity `index`: its position and
    /// ground position; its velocity as given or from the difference with its previous
    /// sample (limited to [`MAX_SPEED`]); its heading as given or from the velocity's
    /// direction (kept below [`MIN_SPEED_FOR_HEADING`]), wrapped; its turn rate from the
    /// previous heading.
    ///
    /// # Safety
    /// `index` must be below the scene's entity count, the index of `update.id` (from
    /// [`check`](Self::check)), and no other thread may read or write entity `index`'s
    /// slots during the call.
    #[inline]
    pub unsafe fn apply_at(&self, index: usize, time: f64, update: &EntityUpdate) {
        // SAFETY: forwarded contract.
        unsafe {
            let motion = self.motion_at(index, time, update);
            self.write_at(index, time, update, &motion);
        }
    }

    /// [`apply_at`](Self::apply_at) for updates of distinct entities, each with its entity
    /// index. The same writes, in blocks: each block's motions first, then its writes, so
    /// that the processor overlaps one entity's trigonometry with the next one's.
    ///
    /// # Safety
    /// Every index must be below the scene's entity count and the index of its update's id, no
    /// two alike, and no other thread may read or write these entities' slots meanwhile.
    #[inline]
    pub unsafe fn apply_distinct(
        &self,
        time: f64,
        updates: impl IntoIterator<Item = (usize, EntityUpdate)>,
    ) {
        const BLOCK: usize = 16;
        let mut block = [None; BLOCK];
        let mut updates = updates.into_iter();
        loop {
            let mut filled = 0;
            // The block first: no update is taken that the block has no room for.
            for (slot, (index, update)) in block.iter_mut().zip(updates.by_ref()) {
                // SAFETY: the caller's contract; nothing is written yet, and the entities
                // are distinct, so no write of this block precedes its read.
                let motion = unsafe { self.motion_at(index, time, &update) };
                *slot = Some((index, update, motion));
                filled += 1;
            }
            for (index, update, motion) in block[..filled].iter().flatten() {
                // SAFETY: the caller's contract.
                unsafe { self.write_at(*index, time, update, motion) };
            }
            if filled < BLOCK {
                return;
            }
        }
    }

    /// What `update` makes of entity `index`'s motion, from its previous sample: the
    /// first half of [`apply_at`](Self::apply_at). Reads the entity's slots only.
    ///
    /// # Safety
    /// As [`apply_at`](Self::apply_at).
    #[inline(always)]
    unsafe fn motion_at(&self, index: usize, time: f64, update: &EntityUpdate) -> Motion {
        debug_assert!(index < self.len);
        // SAFETY: index < len (contract): the pointers are in bounds, and no other thread
        // writes these slots meanwhile.
        let (previous_ground, previous_velocity, previous_heading, last_time) = unsafe {
            (
                *self.ground.add(index),
                *self.velocity.add(index),
                *self.heading.add(index),
                *self.last_time.add(index),
            )
        };
        let ground = self.world.ground(update.position);
        let elapsed = time - last_time;
        let velocity = match update.velocity {
            Some(velocity) => given_velocity(self.world.ground(velocity)),
            None if elapsed > 0.0 && elapsed.is_finite() => {
                limited_velocity(ground.as_dvec2() - previous_ground.as_dvec2(), elapsed)
            }
            None => previous_velocity,
        };
        let heading = if update.heading_from_motion {
            if fast_enough_for_heading(velocity) {
                velocity.y.atan2(velocity.x)
            } else {
                previous_heading
            }
        } else {
            update.heading
        };
        Motion {
            ground,
            velocity,
            heading,
            elapsed,
        }
    }

    /// Writes `update` and its `motion` into entity `index`: the second half of
    /// [`apply_at`](Self::apply_at).
    ///
    /// # Safety
    /// As [`apply_at`](Self::apply_at).
    #[inline(always)]
    unsafe fn write_at(&self, index: usize, time: f64, update: &EntityUpdate, motion: &Motion) {
        // SAFETY: index < len (contract): every pointer below is in bounds, and no other
        // thread touches these slots meanwhile.
        let (position, ground, heading, forward, velocity, turn_rate, last_time, talking) = unsafe {
            (
                &mut *self.position.add(index),
                &mut *self.ground.add(index),
                &mut *self.heading.add(index),
                &mut *self.forward.add(index),
                &mut *self.velocity.add(index),
                &mut *self.turn_rate.add(index),
                &mut *self.last_time.add(index),
                &mut *self.talking.add(index),
            )
        };
        // Stored headings are wrapped: the turn is taken between wrapped ones (an in-range
        // heading is its own wrap, bit for bit).
        let wrapped = wrap_angle(motion.heading);
        if motion.elapsed > 0.0 && motion.elapsed.is_finite() {
            *turn_rate = turn(*heading, wrapped) / motion.elapsed as f32;
        }
        *position = update.position;
        *ground = motion.ground;
        *velocity = motion.velocity;
        *heading = wrapped;
        *forward = Vec2::from_angle(motion.heading);
        *last_time = time;
        *talking = update.talking;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shortcuts_give_the_bits_of_the_full_formulas() {
        use std::f32::consts::{PI, TAU};
        // The speed test around its threshold, and far from it.
        let mut speed = 0.09f32;
        while speed < 0.11 {
            for angle in [0.0f32, 0.7, 2.0, -1.3] {
                let velocity = Vec2::from_angle(angle) * speed;
                assert_eq!(
                    fast_enough_for_heading(velocity),
                    velocity.length() >= MIN_SPEED_FOR_HEADING,
                    "{velocity}"
                );
            }
            speed = speed.next_up();
        }
        for velocity in [Vec2::ZERO, Vec2::new(3.0, -4.0), Vec2::new(1e-20, 0.0)] {
            assert_eq!(
                fast_enough_for_heading(velocity),
                velocity.length() >= MIN_SPEED_FOR_HEADING
            );
        }
        // The turn between wrapped headings, against rem_euclid itself.
        let headings = [-PI, -3.0, -1.0, -1e-7, 0.0, 1e-7, 0.5, 3.0, PI.next_down()];
        for from in headings {
            for to in headings {
                let full = (to - from + PI).rem_euclid(TAU) - PI;
                assert_eq!(turn(from, to).to_bits(), full.to_bits(), "{from} -> {to}");
            }
        }
        // A displacement over the speed limit keeps its direction; under it, it divides.
        let fast = limited_velocity(DVec2::new(3e9, 4e9), 1.0);
        assert!((fast.length() - MAX_SPEED).abs() < 1e3 && fast.x > 0.0);
        let slow = DVec2::new(0.3, -0.4);
        assert_eq!(limited_velocity(slow, 0.5), (slow / 0.5).as_vec2());
        for velocity in [
            Vec2::new(0.3, -1.7e-3),
            Vec2::new(4.9e8, -4.9e8),
            Vec2::new(6e8, 9e8),
            Vec2::new(-3e38, 1.0),
        ] {
            let full = limited_velocity(velocity.as_dvec2(), 1.0);
            assert_eq!(given_velocity(velocity), full, "{velocity}");
        }
    }
}
