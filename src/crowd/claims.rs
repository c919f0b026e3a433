//! Claims: one atomic flag per character or entity, so that ranges run from several
//! threads (of a ranged step, of a ranged push) are checked for overlap without a lock;
//! and the chain of the entities each call of a ranged push claimed, so that it writes and
//! gives back those and no others.

use std::sync::atomic::{AtomicU32, AtomicU64, Ordering};

use crate::error::Result;

/// One flag per character (or entity): taken by a range of the open step (or push).
/// Claims are atomic so that ranges from several threads are checked for overlap without
/// a lock.
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
    pub fn claim(&self, first: usize, end: usize) -> bool {
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

    /// Takes flag `index` if it is clear, and returns whether it was.
    #[inline]
    pub fn claim_one(&self, index: usize) -> bool {
        let bit = 1 << (index % 64);
        self.words[index / 64].fetch_or(bit, Ordering::AcqRel) & bit == 0
    }

    /// Clears flag `index` (taken by this caller's [`claim_one`](Self::claim_one)).
    pub fn release_one(&self, index: usize) {
        self.words[index / 64].fetch_and(!(1 << (index % 64)), Ordering::AcqRel);
    }

    /// [`claim_one`](Self::claim_one) for a caller with the set to itself: no atomic
    /// operation.
    #[inline]
    pub fn claim_one_alone(&mut self, index: usize) -> bool {
        let bit = 1 << (index % 64);
        let word = self.words[index / 64].get_mut();
        let free = *word & bit == 0;
        *word |= bit;
        free
    }

    /// [`release_one`](Self::release_one) for a caller with the set to itself.
    #[inline]
    pub fn release_one_alone(&mut self, index: usize) {
        *self.words[index / 64].get_mut() &= !(1 << (index % 64));
    }

    /// Clears the flags `indices` took with [`claim_one_alone`](Self::claim_one_alone):
    /// one by one when they are few, else every flag at once.
    pub fn release_alone(&mut self, indices: &[u32]) {
        if indices.len() > self.words.len() / 4 {
            self.clear();
        } else {
            for &index in indices {
                self.release_one_alone(index as usize);
            }
        }
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

/// The entities one call claimed, in the order it claimed them: a chain through
/// [`ClaimLinks`].
#[derive(Debug, Clone, Copy, Default)]
pub(super) struct ClaimChain {
    head: u32,
    tail: u32,
    len: usize,
}

/// One link per entity: the next entity the call that claimed it claimed after it. Only
/// the call holding an entity's claim writes or reads its link, so each call's chain is its
/// own, whatever other threads do; the links are atomics only so that calls on several
/// threads may each use their own entities' links through one shared view. Kept in a
/// scratch buffer of one `u32` per entity, free while a ranged push is open.
#[derive(Debug, Clone, Copy)]
pub(super) struct ClaimLinks<'a> {
    links: &'a [AtomicU32],
}

// The view below relies on it.
const _: () = assert!(std::mem::align_of::<AtomicU32>() == std::mem::align_of::<u32>());

impl<'a> ClaimLinks<'a> {
    /// Links in `scratch`, one per entity (what it holds is overwritten as chains grow).
    pub fn new(scratch: &'a mut [u32]) -> ClaimLinks<'a> {
        let scratch: *mut [u32] = scratch;
        // SAFETY: `AtomicU32` has the size, bit validity and (asserted above) alignment of
        // `u32`; the exclusive borrow of `scratch` for 'a keeps every other access out
        // while the view lives.
        let links = unsafe { &*(scratch as *const [AtomicU32]) };
        ClaimLinks { links }
    }

    /// Appends entity `index`, which the chain's call has just claimed, to its chain.
    pub fn append(&self, chain: &mut ClaimChain, index: usize) {
        let index = index as u32;
        if chain.len == 0 {
            chain.head = index;
        } else {
            // Written and read by this call alone (it holds the tail's claim): relaxed.
            self.links[chain.tail as usize].store(index, Ordering::Relaxed);
        }
        chain.tail = index;
        chain.len += 1;
    }

    /// The chain's entities, in the order they were appended.
    pub fn walk(&self, chain: ClaimChain) -> impl Iterator<Item = usize> + '_ {
        let mut next = chain.head;
        (0..chain.len).map(move |k| {
            let index = next;
            if k + 1 < chain.len {
                next = self.links[index as usize].load(Ordering::Relaxed);
            }
            index as usize
        })
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
    fn single_claims_take_a_flag_once() {
        let mut claims = ClaimSet::new(130, &"test").unwrap();
        assert!(claims.claim_one(64));
        assert!(!claims.claim_one(64), "taken");
        assert!(claims.claim_one(129));
        assert_eq!(claims.next_unclaimed(0, 130), Some((0, 64)));
        assert_eq!(claims.next_unclaimed(65, 130), Some((65, 129)));
        claims.release_one(64);
        assert!(claims.claim_one(64), "released");
        assert!(!claims.claim_one_alone(129), "taken");
        assert!(claims.claim_one_alone(3));
        claims.release_one_alone(3);
        assert!(claims.claim_one(3), "released alone");
        let mut many = ClaimSet::new(1000, &"test").unwrap();
        for index in [3, 64, 999] {
            assert!(many.claim_one_alone(index));
        }
        many.release_alone(&[3, 64]);
        assert_eq!(
            many.next_unclaimed(0, 1000),
            Some((0, 999)),
            "only 999 is left"
        );
        many.release_alone(&[1; 5]);
        assert_eq!(
            many.next_unclaimed(0, 1000),
            Some((0, 1000)),
            "cleared at once"
        );
    }

    #[test]
    fn masks_cover_exactly_the_range() {
        assert_eq!(ClaimSet::mask(0, 0, 64), u64::MAX);
        assert_eq!(ClaimSet::mask(0, 1, 3), 0b110);
        assert_eq!(ClaimSet::mask(1, 60, 70), 0b11_1111);
        assert_eq!(ClaimSet::mask(0, 60, 70), 0xF << 60);
        assert_eq!(ClaimSet::mask(2, 0, 64), 0);
    }

    #[test]
    fn chains_walk_what_was_appended_in_order() {
        let mut scratch = vec![7u32; 10];
        let links = ClaimLinks::new(&mut scratch);
        let (mut first, mut second) = (ClaimChain::default(), ClaimChain::default());
        assert_eq!(links.walk(first).count(), 0);
        links.append(&mut first, 4);
        links.append(&mut second, 9);
        links.append(&mut first, 0);
        links.append(&mut first, 5);
        assert_eq!(links.walk(first).collect::<Vec<_>>(), [4, 0, 5]);
        assert_eq!(links.walk(second).collect::<Vec<_>>(), [9]);
    }
}
