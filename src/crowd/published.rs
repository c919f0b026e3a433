//! The step's outputs laid out for the readers: each character's gaze and its chain's final
//! joint rotations, written by every step in the readers' order (creation order,
//! see [`Crowd::gaze_at`](super::Crowd::gaze_at)), so that reading the whole crowd is a copy
//! rather than a walk through each character's state out of storage order.
//!
//! The values are those the readers would compute (the same functions compute them), and
//! they are used only while nothing has changed since the step: every mutable borrow of the
//! crowd's shared part or per-character arrays goes through a [`Watched`], which notes it;
//! the readers then compute from the state as before. A step publishes only what was read
//! since the step before, so a crowd whose readers are not used pays nothing for them.

use std::sync::atomic::{AtomicBool, Ordering};

use glam::Quat;

use super::values::GazeInfo;
use crate::alloc::{try_reserve, try_with_capacity, Field};
use crate::error::Result;
use crate::ik::MAX_CHAIN_JOINTS;

/// A value whose every mutable borrow is noted (`changed`), so that the published outputs
/// know when the state they were computed from may differ.
#[derive(Debug)]
pub(super) struct Watched<T> {
    value: T,
    /// Set by every mutable borrow; cleared when the outputs are published.
    pub changed: bool,
}

impl<T> Watched<T> {
    /// `value`, changed since no publication.
    pub fn new(value: T) -> Watched<T> {
        Watched {
            value,
            changed: true,
        }
    }
}

impl<T> std::ops::Deref for Watched<T> {
    type Target = T;

    #[inline]
    fn deref(&self) -> &T {
        &self.value
    }
}

impl<T> std::ops::DerefMut for Watched<T> {
    #[inline]
    fn deref_mut(&mut self) -> &mut T {
        self.changed = true;
        &mut self.value
    }
}

/// The readers' copy of the last step's outputs.
#[derive(Debug)]
pub(super) struct Published {
    /// Each character's gaze, by reader position.
    pub gaze: Vec<GazeInfo>,
    /// The final local rotations (`base * delta`) of every chain joint, one chain after
    /// another in reader order, bottom to top.
    pub joints: Vec<Quat>,
    /// Where each reader position's joints start in `joints`, and the total after the last.
    pub joint_start: Vec<u32>,
    /// The reader position of each character, by storage index (the inverse of the
    /// readers' order).
    pub position_of: Vec<u32>,
    /// False when characters were added, removed or stored in another order since
    /// `joint_start` and `position_of` were computed.
    pub layout_current: bool,
    /// What the step publishes, decided when it begins by what was read since the step
    /// before. Once the step has ended, and while nothing has changed since, these outputs
    /// are the readers' (the crowd's [`Watched`] parts say whether anything changed).
    pub outputs: Outputs,
    /// Set by the readers of each output (they run under `&self`, possibly on several
    /// threads), taken by the next step: a crowd whose outputs nobody reads publishes none.
    pub gaze_wanted: AtomicBool,
    /// As `gaze_wanted`, for the final joint rotations.
    pub joints_wanted: AtomicBool,
}

/// Which outputs a step publishes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub(super) struct Outputs {
    /// Each character's gaze.
    pub gaze: bool,
    /// Each chain's final joint rotations.
    pub joints: bool,
}

impl Published {
    /// Empty buffers for up to `characters` characters, or [`crate::Error::OutOfMemory`]
    /// for `what`.
    pub fn with_capacity(characters: usize, what: &dyn std::fmt::Display) -> Result<Published> {
        Ok(Published {
            gaze: try_with_capacity(characters, what)?,
            joints: Vec::new(),
            joint_start: try_with_capacity(characters + 1, what)?,
            position_of: try_with_capacity(characters, what)?,
            layout_current: false,
            outputs: Outputs::default(),
            gaze_wanted: AtomicBool::new(false),
            joints_wanted: AtomicBool::new(false),
        })
    }

    /// Makes room for a new character's `joint_count` chain joints beside the others
    /// (fails when memory is short, with nothing observable changed), so that publishing
    /// never allocates. Then [`add_chain`](Self::add_chain) once the character is in.
    pub fn reserve_chain(&mut self, joint_count: usize) -> Result<()> {
        let what = &Field(
            "chain joints of all the characters",
            (self.joints.len() + joint_count) as u64,
        );
        try_reserve(&mut self.joints, joint_count, what)
    }

    /// Adds a new character's `joint_count` chain joints to `joints` (room made by
    /// [`reserve_chain`](Self::reserve_chain)), which holds every chain's joints.
    pub fn add_chain(&mut self, joint_count: usize) {
        self.joints
            .resize(self.joints.len() + joint_count, Quat::IDENTITY);
        self.layout_current = false;
    }

    /// Drops a removed character's `joint_count` chain joints from `joints`.
    pub fn release_chain(&mut self, joint_count: usize) {
        self.joints.truncate(self.joints.len() - joint_count);
        self.layout_current = false;
    }

    /// Notes that a reader asked for the output `flag` stands for (cheap: a load, and a
    /// store the first time).
    #[inline]
    pub fn want(flag: &AtomicBool) {
        if !flag.load(Ordering::Relaxed) {
            flag.store(true, Ordering::Relaxed);
        }
    }

    /// At the beginning of a step: publish this step what was read since the last one.
    pub fn begin_step(&mut self) {
        self.outputs = Outputs {
            gaze: std::mem::take(self.gaze_wanted.get_mut()),
            joints: std::mem::take(self.joints_wanted.get_mut()),
        };
    }

    /// The buffers for the gaze job to write into, laid out (see [`lay_out`](Self::lay_out)),
    /// for the characters they were laid out for.
    pub fn target(&mut self) -> PublishTarget {
        debug_assert!(self.layout_current);
        PublishTarget {
            gaze: self.gaze.as_mut_ptr(),
            joints: self.joints.as_mut_ptr(),
            joint_start: self.joint_start.as_ptr(),
            position_of: self.position_of.as_ptr(),
            characters: self.position_of.len(),
            joint_total: self.joints.len(),
            outputs: self.outputs,
        }
    }

    /// Marks the layout stale (the storage order changed).
    pub fn storage_moved(&mut self) {
        self.layout_current = false;
    }

    /// Recomputes `position_of` and `joint_start` for `read_order` (the storage index of
    /// each reader position) when the layout is stale; `joints_of(storage index)` is a
    /// character's chain joint count. Allocates nothing: the buffers hold every character.
    pub fn lay_out(&mut self, read_order: &[u32], joints_of: impl Fn(usize) -> usize) {
        if self.layout_current {
            return;
        }
        let characters = read_order.len();
        self.position_of.resize(characters, 0);
        self.joint_start.clear();
        let mut start = 0u32;
        for (position, &character) in read_order.iter().enumerate() {
            self.position_of[character as usize] = position as u32;
            self.joint_start.push(start);
            start += joints_of(character as usize) as u32;
        }
        self.joint_start.push(start);
        self.gaze.resize(
            characters,
            GazeInfo {
                character: 0,
                target: 0,
                target_part: crate::attention::TargetPart::Whole,
                head_target: 0,
                target_position: glam::Vec3::ZERO,
                s_max: 0.0,
                threshold: 0.0,
                attending: false,
                attentive_fraction: 0.0,
                interest_count: 0,
            },
        );
        debug_assert_eq!(start as usize, self.joints.len(), "every chain's joints");
        self.layout_current = true;
    }
}

/// The published buffers as raw pointers, so that the gaze job's ranges, on several
/// threads, each write their own characters' entries (a character's reader position and
/// joint span are its own: the positions are a permutation).
#[derive(Debug, Clone, Copy)]
pub(super) struct PublishTarget {
    gaze: *mut GazeInfo,
    joints: *mut Quat,
    joint_start: *const u32,
    position_of: *const u32,
    characters: usize,
    joint_total: usize,
    /// What to write.
    outputs: Outputs,
}

// SAFETY: the pointers address plain `Send + Sync` data in buffers that outlive every use
// (contract of `PublishTarget::write`); sending or sharing the pointers is harmless.
unsafe impl Send for PublishTarget {}
// SAFETY: see `Send` above.
unsafe impl Sync for PublishTarget {}

impl PublishTarget {
    /// The characters the buffers were laid out for.
    pub fn characters(&self) -> usize {
        self.characters
    }

    /// What this step publishes.
    pub fn outputs(&self) -> Outputs {
        self.outputs
    }

    /// Asks the processor for the cache lines the outputs of the character at storage index
    /// `character` go to (a hint: it never faults), so that writing them a few characters
    /// later does not wait for memory.
    #[inline]
    pub fn prefetch(&self, character: usize) {
        if character >= self.characters {
            return;
        }
        // SAFETY: `character` is in range and the arrays are alive (contract of `write`,
        // which every use of a target precedes or follows).
        let (position, start) = unsafe {
            let position = *self.position_of.add(character) as usize;
            (position, *self.joint_start.add(position) as usize)
        };
        crate::math::prefetch(self.gaze.wrapping_add(position));
        crate::math::prefetch(
            self.joints
                .wrapping_add(start)
                .cast::<[Quat; MAX_CHAIN_JOINTS]>(),
        );
    }

    /// Writes the outputs of the character at storage index `character` this step publishes
    /// (see [`outputs`](Self::outputs)): `gaze()` at its reader position, and its joints,
    /// which `joints` writes to the start of the slice it gets (its chain's span) and counts.
    ///
    /// # Safety
    /// The buffers must still be alive, unmoved and laid out as when this target was made,
    /// and no other code may access this character's entries meanwhile (concurrent callers
    /// take distinct characters).
    pub unsafe fn write(
        &self,
        character: usize,
        gaze: impl FnOnce() -> GazeInfo,
        joints: impl FnOnce(&mut [Quat]) -> usize,
    ) {
        assert!(character < self.characters);
        // SAFETY: `character` is in range (checked above) and the arrays are alive.
        let position = unsafe { *self.position_of.add(character) } as usize;
        // SAFETY: as above; `joint_start` has one entry more than there are characters.
        let (start, end) = unsafe {
            (
                *self.joint_start.add(position) as usize,
                *self.joint_start.add(position + 1) as usize,
            )
        };
        assert!(position < self.characters && start <= end && end <= self.joint_total);
        // SAFETY: in range (checked above); this character's entries are the caller's alone.
        unsafe {
            if self.outputs.gaze {
                self.gaze.add(position).write(gaze());
            }
            if self.outputs.joints {
                let span = std::slice::from_raw_parts_mut(self.joints.add(start), end - start);
                let written = joints(span);
                debug_assert_eq!(written, end - start);
            }
        }
    }
}
