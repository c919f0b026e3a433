//! Each character's mutable state, as flat per-character arrays: what a step writes.
//!
//! Stepping a character reads the crowd's shared state (scene, neighbour index, chains,
//! parameters) and writes only that character's entries here. Keeping these arrays apart
//! lets disjoint ranges of characters be stepped at the same time: [`CharacterSlices`]
//! borrows a range of every array, and [`RawCharacterSlices`] hands ranges out to threads.

use crate::attention::following::FollowState;
use crate::ik::{BlinkState, GazeMotion};
use crate::math::random::Random;

use super::model_state::ModelState;

/// A character's level-of-detail state for attention updates.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct AttentionLod {
    /// Seconds since its last attention update.
    pub pending: f32,
    /// Offset of this character's updates within the period (below 64).
    pub stagger: u8,
    /// Its own period, 1 to 64 (0: the crowd's, by distance to the viewer).
    pub period: u8,
}

/// Applies one macro body to every per-character array, so that adding an array is one
/// line here and every operation below follows.
macro_rules! character_arrays {
    ($apply:ident) => {
        $apply! {
            /// Level-of-detail state of its attention updates.
            lod / lod: AttentionLod,
            /// The state of the character's attention model.
            models / model: ModelState,
            /// Random stream of the saliency and baseline choices.
            model_randoms / model_random: Random,
            /// Gaze motion state (the IK's output).
            motions / motion: GazeMotion,
            /// Random stream of the gaze timing draws.
            gaze_randoms / gaze_random: Random,
            /// Blinks (the eyelids' state).
            blinks / blink: BlinkState,
            /// Gaze following: the point glanced at and the current encounter.
            follows / follow: FollowState,
        }
    };
}

macro_rules! define_states {
    ($($(#[$doc:meta])* $name:ident / $one:ident: $type:ty,)*) => {
        /// The per-character arrays, in the scene's dense character order, sized at creation.
        #[derive(Debug)]
        pub(super) struct CharacterStates {
            $($(#[$doc])* pub $name: Vec<$type>,)*
        }

        /// A range of characters' state, borrowed mutably from every array.
        pub(super) struct CharacterSlices<'a> {
            $($(#[$doc])* pub $name: &'a mut [$type],)*
        }

        /// A character's state to be written by its attention update (one entry of each array
        /// that attention writes).
        #[allow(dead_code)] // one entry per array; attention leaves the gaze stream alone
        pub(super) struct CharacterMut<'a> {
            $(pub $one: &'a mut $type,)*
        }

        /// The per-character arrays as raw pointers, so that threads may each take a
        /// disjoint range (see [`RawCharacterSlices::range`]).
        #[derive(Debug, Clone, Copy)]
        pub(super) struct RawCharacterSlices {
            len: usize,
            $($name: *mut $type,)*
        }

        impl CharacterStates {
            /// Empty arrays holding up to `capacity` characters without reallocating, or
            /// [`Error::OutOfMemory`](crate::error::Error::OutOfMemory) for `what`.
            pub fn with_capacity(
                capacity: usize,
                what: &dyn std::fmt::Display,
            ) -> crate::error::Result<CharacterStates> {
                Ok(CharacterStates {
                    $($name: crate::alloc::try_with_capacity(capacity, what)?,)*
                })
            }

            /// Removes character `index`, moving the last one into its place (the scene's
            /// order after a removal).
            pub fn swap_remove(&mut self, index: usize) {
                $(self.$name.swap_remove(index);)*
            }

            /// Stores the characters in a new order: character `i` is the one at index
            /// `order[i]` before (see [`crate::scene::Scene::reorder`]).
            pub fn reorder(&mut self, order: &[u32], reorder: &mut crate::scene::order::Reorder) {
                $(reorder.apply(&mut self.$name, order);)*
            }

            /// The arrays as raw pointers. They stay valid while `self` is neither moved
            /// nor resized nor otherwise accessed.
            pub fn raw(&mut self) -> RawCharacterSlices {
                RawCharacterSlices {
                    len: self.lod.len(),
                    $($name: self.$name.as_mut_ptr(),)*
                }
            }

            fn check_lengths(&self) -> bool {
                true $(&& self.$name.len() == self.lod.len())*
            }
        }

        impl<'a> CharacterSlices<'a> {
            /// Character `index` (within this range).
            pub fn character(&mut self, index: usize) -> CharacterMut<'_> {
                CharacterMut { $($one: &mut self.$name[index],)* }
            }
        }

        impl RawCharacterSlices {
            /// Asks the processor to start loading character `index`'s entries of the
            /// arrays attention writes into cache (a hint: it reads nothing and never
            /// faults; an index out of range is ignored).
            #[inline]
            pub fn prefetch_attention(&self, index: usize) {
                if index < self.len {
                    crate::math::prefetch(self.lod.wrapping_add(index));
                    crate::math::prefetch(self.models.wrapping_add(index));
                    crate::math::prefetch(self.model_randoms.wrapping_add(index));
                }
            }

            /// Characters `first .. first + count`, borrowed mutably.
            ///
            /// # Safety
            /// The arrays these pointers came from must still be alive and unmoved, and for
            /// as long as the result lives no other reference may access these characters'
            /// entries: ranges handed to concurrent callers must be disjoint.
            pub unsafe fn range<'a>(&self, first: usize, count: usize) -> CharacterSlices<'a> {
                assert!(first <= self.len && count <= self.len - first);
                // SAFETY: `first + count <= len` elements are initialised at each pointer
                // (checked above); exclusivity is the caller's contract.
                unsafe {
                    CharacterSlices {
                        $($name: std::slice::from_raw_parts_mut(self.$name.add(first), count),)*
                    }
                }
            }
        }
    };
}

character_arrays!(define_states);

impl CharacterStates {
    /// Adds a character's state at the end (following no one's gaze yet).
    pub fn push(
        &mut self,
        lod: AttentionLod,
        model: ModelState,
        motion: GazeMotion,
        model_random: Random,
        gaze_random: Random,
        blink: BlinkState,
    ) {
        self.lod.push(lod);
        self.models.push(model);
        self.model_randoms.push(model_random);
        self.motions.push(motion);
        self.gaze_randoms.push(gaze_random);
        self.blinks.push(blink);
        self.follows.push(FollowState::default());
        debug_assert!(self.check_lengths());
    }
}

/// What reading a character's gaze request needs of its state.
#[derive(Debug, Clone, Copy)]
pub(super) struct CharacterView<'a> {
    pub model: &'a ModelState,
    pub motion: &'a GazeMotion,
    pub follow: &'a FollowState,
}

impl CharacterStates {
    /// Character `index`'s view.
    pub fn view(&self, index: usize) -> CharacterView<'_> {
        CharacterView {
            model: &self.models[index],
            motion: &self.motions[index],
            follow: &self.follows[index],
        }
    }
}

// SAFETY: the pointers address `Send + Sync` plain data in arrays that outlive every use
// (contract of `RawCharacterSlices::range`); sending or sharing the pointers themselves is
// harmless, and every access goes through `range`, whose caller guarantees exclusivity.
unsafe impl Send for RawCharacterSlices {}
// SAFETY: see `Send` above.
unsafe impl Sync for RawCharacterSlices {}

impl RawCharacterSlices {
    /// Number of characters.
    pub fn len(&self) -> usize {
        self.len
    }
}

/// The bytes one character takes in these arrays.
pub(super) fn bytes_per_character() -> usize {
    macro_rules! sum_sizes {
        ($($(#[$doc:meta])* $name:ident / $one:ident: $type:ty,)*) => {
            0 $(+ std::mem::size_of::<$type>())*
        };
    }
    character_arrays!(sum_sizes)
}
