//! The ranged step: an open step's two jobs handed to any number of threads, each running
//! whole characters on a range of its own ([`StepRanges::run_range`]), and the claims that
//! keep ranges from overlapping.

use std::sync::atomic::{AtomicU64, Ordering};

use super::attention_job::AttentionJob;
use super::gaze_job::GazeJob;
use crate::error::{Error, Result};

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
    pub fn clear(&mut self) {
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
    pub fn next_unclaimed(&mut self, from: usize, count: usize) -> Option<(usize, usize)> {
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
