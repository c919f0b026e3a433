//! The ids of a crowd's conversations: given in turn from one 32-bit counter shared by
//! every group slot, never `u32::MAX` (`CG_NO_TARGET`, "in none"), never one a live group
//! holds, and found again through an open-addressing table from id to slot, sized at
//! creation.
//!
//! Why a counter and not the slot with a per-slot generation: a 32-bit id that names its
//! slot leaves `2³² / capacity` ids to each slot, and one slot reused over and over (every
//! other slot held by a long-lived group) gives a removed group's id to a new one after
//! that many reuses — 512 at the largest capacity. With one counter, a removed group's id
//! comes back only when the counter has gone round: after at least `2³² − 1 − capacity`
//! more groups were formed since it was given (4 286 578 687 at the largest capacity,
//! 8 388 608), whatever the capacity and whichever groups stay.

use crate::alloc::try_vec;
use crate::error::Result;

/// No group has this id: what "in no conversation" reads as (`CG_NO_TARGET`).
pub(super) const NO_GROUP: u32 = u32::MAX;

/// An empty entry of the table.
const EMPTY: u32 = u32::MAX;

/// Ids of live groups and the slot of each.
#[derive(Debug)]
pub(super) struct GroupIds {
    /// The id of the group in each slot (stale for a free slot).
    ids: Vec<u32>,
    /// Open addressing with linear probing: each entry a live slot (whose id hashes to
    /// this entry or one before it, with no empty entry between) or [`EMPTY`]. At least
    /// twice as many entries as slots, a power of two, so that probes stay short and an
    /// empty entry always ends them.
    table: Vec<u32>,
    /// The next id to try giving: below [`NO_GROUP`].
    next: u32,
}

impl GroupIds {
    /// Ids for `capacity` slots, or [`Error::OutOfMemory`](crate::Error) for `what`.
    pub fn new(capacity: u32, what: &dyn std::fmt::Display) -> Result<GroupIds> {
        let entries = (capacity as usize * 2).max(2).next_power_of_two();
        Ok(GroupIds {
            ids: try_vec(capacity as usize, 0, what)?,
            table: try_vec(entries, EMPTY, what)?,
            next: 0,
        })
    }

    /// The entry where the table looks for `id` first (Fibonacci hashing: consecutive ids
    /// land far apart).
    fn home(&self, id: u32) -> usize {
        let bits = self.table.len().trailing_zeros();
        (u64::from(id).wrapping_mul(0x9E37_79B9_7F4A_7C15) >> (64 - bits)) as usize
    }

    /// The entry after `entry`, wrapping.
    fn after(&self, entry: usize) -> usize {
        (entry + 1) & (self.table.len() - 1)
    }

    /// The table entry holding `id`, if a live group has it.
    fn entry_of(&self, id: u32) -> Option<usize> {
        let mut entry = self.home(id);
        loop {
            match self.table[entry] {
                EMPTY => return None,
                slot if self.ids[slot as usize] == id => return Some(entry),
                _ => entry = self.after(entry),
            }
        }
    }

    /// The slot of the live group `id`.
    pub fn slot_of(&self, id: u32) -> Option<usize> {
        self.entry_of(id).map(|entry| self.table[entry] as usize)
    }

    /// The id of the group in `slot` (live, or the last one it held).
    pub fn id_of(&self, slot: usize) -> u32 {
        self.ids[slot]
    }

    /// Gives the group now in `slot` (which holds no live group) the next id that no live
    /// group holds, and returns it. Fewer live groups than there are ids: it always finds
    /// one, at once unless the counter has gone round to long-lived groups' ids.
    pub fn give(&mut self, slot: usize) -> u32 {
        let id = loop {
            let id = self.next;
            self.next = if id == NO_GROUP - 1 { 0 } else { id + 1 };
            if self.entry_of(id).is_none() {
                break id;
            }
        };
        self.ids[slot] = id;
        let mut entry = self.home(id);
        while self.table[entry] != EMPTY {
            entry = self.after(entry);
        }
        self.table[entry] = slot as u32;
        id
    }

    /// Takes back the id of the live group in `slot`: it names no group from now on.
    pub fn take_back(&mut self, slot: usize) {
        let Some(mut hole) = self.entry_of(self.ids[slot]) else {
            debug_assert!(false, "slot {slot} holds no live group");
            return;
        };
        // Backward-shift deletion: move up each later entry of the run that may sit in the
        // hole (its home is not cyclically in hole+1 ..= entry), so no probe stops early.
        let mut entry = hole;
        loop {
            self.table[hole] = EMPTY;
            loop {
                entry = self.after(entry);
                let slot = self.table[entry];
                if slot == EMPTY {
                    return;
                }
                let home = self.home(self.ids[slot as usize]);
                let stays = if hole <= entry {
                    hole < home && home <= entry
                } else {
                    hole < home || home <= entry
                };
                if !stays {
                    self.table[hole] = slot;
                    hole = entry;
                    break;
                }
            }
        }
    }

    /// Sets the counter, to test its wrapping without forming 2³² groups.
    #[cfg(test)]
    pub fn set_next(&mut self, next: u32) {
        self.next = next;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Forms a group in each of `slots` in turn, returning their ids.
    fn give_all(ids: &mut GroupIds, slots: impl IntoIterator<Item = usize>) -> Vec<u32> {
        slots.into_iter().map(|slot| ids.give(slot)).collect()
    }

    #[test]
    fn ids_go_round_below_no_group_and_skip_live_ones() {
        let mut ids = GroupIds::new(4, &"test").unwrap();
        assert_eq!(give_all(&mut ids, [0, 1]), [0, 1]);
        ids.set_next(NO_GROUP - 2);
        // 0xFFFF_FFFD, 0xFFFF_FFFE, then round to 0 and 1 (live: skipped) and 2.
        assert_eq!(give_all(&mut ids, [2, 3]), [NO_GROUP - 2, NO_GROUP - 1]);
        ids.take_back(2);
        assert_eq!(ids.give(2), 2, "0 and 1 are live, NO_GROUP never given");
        assert_eq!(ids.slot_of(0), Some(0));
        assert_eq!(ids.slot_of(1), Some(1));
        assert_eq!(ids.slot_of(2), Some(2));
        assert_eq!(ids.slot_of(NO_GROUP - 1), Some(3));
        assert_eq!(ids.slot_of(NO_GROUP - 2), None, "taken back");
        assert_eq!(ids.slot_of(NO_GROUP), None);
    }

    #[test]
    fn a_taken_back_id_names_nothing_until_the_counter_goes_round() {
        // The largest capacity, every slot but the last held by a long-lived group, the
        // last one reused over and over: its removed groups' ids come back only when the
        // counter has gone round, 2³² − 1 − capacity groups later. The counter is set to
        // just before the round, as if those groups had been formed.
        let capacity = 1 << 23;
        let last = capacity as usize - 1;
        let mut ids = GroupIds::new(capacity, &"test").unwrap();
        let held = give_all(&mut ids, 0..last);
        assert_eq!(held.last(), Some(&(capacity - 2)));
        let stale = ids.give(last);
        assert_eq!(stale, capacity - 1);
        ids.take_back(last);
        assert_eq!(
            ids.slot_of(stale),
            None,
            "a removed group's id names nothing"
        );
        ids.set_next(NO_GROUP - 2);
        let mut given = Vec::new();
        for _ in 0..3 {
            given.push(ids.give(last));
            ids.take_back(last);
        }
        // NO_GROUP − 2, NO_GROUP − 1, then round past NO_GROUP and every held id to the
        // first free one: `stale`, given again 2³² − 1 − capacity groups after it was.
        assert_eq!(given, [NO_GROUP - 2, NO_GROUP - 1, stale]);
        for (slot, &id) in held.iter().enumerate().step_by(4099) {
            assert_eq!(
                ids.slot_of(id),
                Some(slot),
                "held group {id} keeps its slot"
            );
        }
    }

    #[test]
    fn the_table_finds_every_live_id_after_removals() {
        // Deletions in every order of a small, crowded table keep every probe whole.
        let capacity = 16;
        let mut ids = GroupIds::new(capacity, &"test").unwrap();
        let mut live = vec![None; capacity as usize];
        let mut state = 12345u32;
        for _ in 0..20_000 {
            state = state.wrapping_mul(1_103_515_245).wrapping_add(12345);
            let slot = (state >> 16) as usize % capacity as usize;
            match live[slot] {
                Some(_) => {
                    ids.take_back(slot);
                    live[slot] = None;
                }
                None => live[slot] = Some(ids.give(slot)),
            }
            for (slot, id) in live.iter().enumerate() {
                if let Some(id) = *id {
                    assert_eq!(ids.slot_of(id), Some(slot));
                }
            }
        }
    }
}
