//! Entity ids: stable opaque `u32` handles mapped to dense storage slots in O(1).
//!
//! An id is `generation × slot_count + slot`. Removing an entity bumps its slot's
//! generation, so the old id is `NotFound` from then on; a slot whose next generation would
//! overflow is retired rather than reused, so an id never names two entities.

use crate::alloc::{try_clone, try_with_capacity};
use crate::error::{Error, Result};

/// The id that means "no entity" (`CG_NO_TARGET` in C).
pub const NO_ENTITY: u32 = u32::MAX;

/// What kind of entity an id names.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum EntityKind {
    /// Looks, and is looked at.
    Character,
    /// Is only looked at.
    Object,
}

#[derive(Debug, Clone, Copy)]
struct Slot {
    generation: u32,
    /// Live: [`LIVE`], [`OBJECT`] for an object, and the index into the dense storage in the
    /// low bits ([`DENSE`]). Free: the next free slot ([`NO_SLOT`] for none).
    state: u32,
}

const LIVE: u32 = 1 << 31;
const OBJECT: u32 = 1 << 30;
const DENSE: u32 = OBJECT - 1;
/// The end of the free list (the largest capacity is one less).
const NO_SLOT: u32 = DENSE;

/// The table from ids to dense indices: 8 bytes per slot, the free slots chained through
/// their own state (a stack: the slot freed last is reused first, the lowest first at
/// creation). Sized at creation; never allocates afterwards.
#[derive(Debug, Clone)]
pub struct IdTable {
    slots: Vec<Slot>,
    /// The first free slot, [`NO_SLOT`] if none.
    free: u32,
}

impl IdTable {
    /// A table for at most `capacity` live entities (below 2³⁰ − 1); `what` names the
    /// caller's numbers it is sized from, for [`Error::OutOfMemory`].
    pub fn new(capacity: u32, what: &dyn std::fmt::Display) -> Result<IdTable> {
        assert!(capacity < NO_SLOT, "id table capacity {capacity} too large");
        let mut slots = try_with_capacity(capacity as usize, what)?;
        slots.extend((0..capacity).map(|slot| Slot {
            generation: 0,
            state: if slot + 1 < capacity {
                slot + 1
            } else {
                NO_SLOT
            },
        }));
        Ok(IdTable {
            slots,
            free: if capacity > 0 { 0 } else { NO_SLOT },
        })
    }

    /// A copy of the table, or [`Error::OutOfMemory`] for `what`.
    pub fn try_clone(&self, what: &dyn std::fmt::Display) -> Result<IdTable> {
        Ok(IdTable {
            slots: try_clone(&self.slots, what)?,
            free: self.free,
        })
    }

    /// Bytes per slot (one slot per entity of the capacity).
    pub fn bytes_per_entity() -> usize {
        std::mem::size_of::<Slot>()
    }

    fn slot_count(&self) -> u32 {
        self.slots.len() as u32
    }

    fn make_id(&self, slot: u32) -> u32 {
        self.slots[slot as usize].generation * self.slot_count() + slot
    }

    /// Takes a free slot for an entity of `kind` at dense index `dense`, returning its id.
    pub fn insert(&mut self, kind: EntityKind, dense: u32) -> Result<u32> {
        let slot = self.free;
        if slot == NO_SLOT {
            return Err(Error::Capacity("no free entity id left".into()));
        }
        debug_assert!(dense < NO_SLOT);
        let entry = &mut self.slots[slot as usize];
        self.free = entry.state;
        let kind = match kind {
            EntityKind::Character => 0,
            EntityKind::Object => OBJECT,
        };
        entry.state = LIVE | kind | (dense & DENSE);
        Ok(self.make_id(slot))
    }

    fn slot_of(&self, id: u32) -> Option<u32> {
        let count = self.slot_count();
        if count == 0 || id == NO_ENTITY {
            return None;
        }
        let slot = id % count;
        let entry = self.slots[slot as usize];
        (entry.state & LIVE != 0 && entry.generation == id / count).then_some(slot)
    }

    /// The kind and dense index of a live id.
    pub fn lookup(&self, id: u32) -> Option<(EntityKind, u32)> {
        self.slot_of(id).map(|slot| {
            let state = self.slots[slot as usize].state;
            let kind = if state & OBJECT != 0 {
                EntityKind::Object
            } else {
                EntityKind::Character
            };
            (kind, state & DENSE)
        })
    }

    /// Like [`lookup`](Self::lookup), but a missing id is [`Error::NotFound`].
    pub fn find(&self, id: u32) -> Result<(EntityKind, u32)> {
        self.lookup(id)
            .ok_or_else(|| Error::NotFound(format!("entity {id} does not exist")))
    }

    /// Records that the live entity `id` now sits at dense index `dense`.
    pub fn relocate(&mut self, id: u32, dense: u32) {
        if let Some(slot) = self.slot_of(id) {
            let entry = &mut self.slots[slot as usize];
            entry.state = (entry.state & !DENSE) | (dense & DENSE);
        }
    }

    /// Frees `id`'s slot; the id is never valid again.
    pub fn remove(&mut self, id: u32) -> Result<()> {
        let slot = self
            .slot_of(id)
            .ok_or_else(|| Error::NotFound(format!("entity {id} does not exist")))?;
        let count = u64::from(self.slot_count());
        let entry = &mut self.slots[slot as usize];
        entry.generation += 1;
        // Retire the slot if its next id would overflow or collide with NO_ENTITY.
        let next_id = u64::from(entry.generation) * count + u64::from(slot);
        if next_id < u64::from(NO_ENTITY) {
            entry.state = self.free;
            self.free = slot;
        } else {
            entry.state = NO_SLOT;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn removed_ids_stay_dead_after_reuse() {
        let mut table = IdTable::new(2, &"test").unwrap();
        let a = table.insert(EntityKind::Character, 0).unwrap();
        let b = table.insert(EntityKind::Object, 0).unwrap();
        assert_ne!(a, b);
        assert!(table.insert(EntityKind::Object, 1).is_err());
        assert_eq!(table.lookup(b), Some((EntityKind::Object, 0)));
        table.remove(a).unwrap();
        assert!(table.lookup(a).is_none());
        assert!(matches!(table.remove(a), Err(Error::NotFound(_))));
        let c = table.insert(EntityKind::Character, 5).unwrap();
        assert_ne!(a, c);
        assert!(table.lookup(a).is_none());
        assert_eq!(table.lookup(c), Some((EntityKind::Character, 5)));
        table.relocate(c, 3);
        assert_eq!(table.find(c).unwrap(), (EntityKind::Character, 3));
        assert!(table.lookup(NO_ENTITY).is_none());
    }

    #[test]
    fn free_slots_are_reused_last_freed_first() {
        assert_eq!(IdTable::bytes_per_entity(), 8);
        let mut table = IdTable::new(3, &"test").unwrap();
        let ids: Vec<u32> = (0..3)
            .map(|dense| table.insert(EntityKind::Object, dense).unwrap())
            .collect();
        // Slots in order at creation: ids 0, 1, 2 (generation 0).
        assert_eq!(ids, [0, 1, 2]);
        table.remove(1).unwrap();
        table.remove(0).unwrap();
        // Generation 1: slot 0 (freed last) first, then slot 1.
        assert_eq!(table.insert(EntityKind::Character, 7).unwrap(), 3);
        assert_eq!(table.insert(EntityKind::Object, 8).unwrap(), 4);
        assert!(table.insert(EntityKind::Object, 9).is_err());
        assert_eq!(table.find(3).unwrap(), (EntityKind::Character, 7));
        assert_eq!(table.find(4).unwrap(), (EntityKind::Object, 8));
        assert_eq!(table.find(2).unwrap(), (EntityKind::Object, 2));
        assert!(IdTable::new(0, &"test")
            .unwrap()
            .insert(EntityKind::Object, 0)
            .is_err());
    }

    #[test]
    fn exhausted_slots_are_retired() {
        let mut table = IdTable::new(1, &"test").unwrap();
        table.slots[0].generation = u32::MAX - 1;
        let id = table.insert(EntityKind::Object, 0).unwrap();
        table.remove(id).unwrap();
        // The next generation would make the id NO_ENTITY: the slot is retired.
        assert!(matches!(
            table.insert(EntityKind::Object, 0),
            Err(Error::Capacity(_))
        ));
    }
}
