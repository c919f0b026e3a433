//! The ranged step: an open step's two jobs handed to any number of threads, each running
//! whole characters on a range of its own ([`StepRanges::run_range`]).

use super::attention_job::AttentionJob;
use super::claims::ClaimSet;
use super::gaze_job::GazeJob;
use crate::error::{Error, Result};

/// An open step's ranges: shared with every thread that runs a part of the step.
#[derive(Debug, Clone, Copy)]
pub struct StepRanges<'a> {
    /// The attention job of the step.
    pub(super) attention: AttentionJob<'a>,
    /// The gaze job of the step.
    pub(super) gaze: GazeJob<'a>,
    /// The characters in spatial-grid order (a permutation of the storage indices).
    pub(super) grid_order: &'a [u32],
    pub(super) claims: &'a ClaimSet,
}

impl StepRanges<'_> {
    /// Number of characters in the step.
    pub fn character_count(&self) -> usize {
        self.attention.states.len()
    }

    /// Steps characters `first .. first + count` in storage order, not the order readers
    /// see (see [`Crowd::gaze_at`](super::Crowd::gaze_at)): the attention job, then the gaze
    /// job, on these characters. Safe to call from several threads at once on disjoint
    /// ranges. Fails without stepping anything if the range is out of bounds
    /// ([`Error::InvalidArgument`]) or overlaps one already taken in this step
    /// ([`Error::WrongState`]).
    pub fn run_range(&self, first: usize, count: usize) -> Result<()> {
        let characters = self.character_count();
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
        unsafe { self.run_unclaimed(first, count) };
        Ok(())
    }

    /// Both jobs on characters `first .. first + count`, without a claim.
    ///
    /// # Safety
    /// No other call may touch these characters meanwhile (a claim, or exclusive use of the
    /// crowd), and the arrays must be alive and unmoved.
    pub(super) unsafe fn run_unclaimed(&self, first: usize, count: usize) {
        // SAFETY: the caller's contract.
        unsafe {
            self.attention.run(first, count);
            self.gaze.run(first, count);
        }
    }
}
