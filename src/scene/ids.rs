//! Entity ids: stable opaque `u32` handles mapped to dense storage slots in O(1).
//!
//! An id is `generation × slot_count + slot`. Removing an entity bumps its slot's
//! generation, so the old id is `NotFound` from then on; a slot whose next generation would
//! overflow is retired rather than reused, so an id never names two entities.

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
    /// Index into the dense storage of `kind` while live.
    dense: u32,
    kind: EntityKind,
    live: bool,
}

/// The table from ids to dense indices. Sized at creation; never allocates afterwards.
#[derive(Debug, Clone)]
pub struct IdTable {
    slots: Vec<Slot>,
    free: Vec<u32>,
}

impl IdTable {
    /// A table for at most `capacity` live entities.
    pub fn new(capacity: u32) -> IdTable {
        IdTable {
            slots: vec![
                Slot {
                    generation: 0,
                    dense: 0,
                    kind: EntityKind::Object,
                    live: false,
                };
                capacity as usize
            ],
            free: (0..capacity).rev().collect(),
        }
    }

    fn slot_count(&self) -> u32 {
        self.slots.len() as u32
    }

    fn make_id(&self, slot: u32) -> u32 {
        self.slots[slot as usize].generation * self.slot_count() + slot
    }

    /// Takes a free slot for an entity of `kind` at dense index `dense`, returning its id.
    pub fn insert(&mut self, kind: EntityKind, dense: u32) -> Result<u32> {
        let slot = self
            .free
            .pop()
            .ok_or_else(|| Error::Capacity("no free entity id left".into()))?;
        let entry = &mut self.slots[slot as usize];
        entry.dense = dense;
        entry.kind = kind;
        entry.live = true;
        Ok(self.make_id(slot))
    }

    fn slot_of(&self, id: u32) -> Option<u32> {
        let count = self.slot_count();
        if count == 0 || id == NO_ENTITY {
            return None;
        }
        let slot = id % count;
        let entry = self.slots[slot as usize];
        (entry.live && entry.generation == id / count).then_some(slot)
    }

    /// The kind and dense index of a live id.
    pub fn lookup(&self, id: u32) -> Option<(EntityKind, u32)> {
        self.slot_of(id).map(|slot| {
            let entry = self.slots[slot as usize];
            (entry.kind, entry.dense)
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
            self.slots[slot as usize].dense = dense;
        }
    }

    /// Frees `id`'s slot; the id is never valid again.
    pub fn remove(&mut self, id: u32) -> Result<()> {
        let slot = self
            .slot_of(id)
            .ok_or_else(|| Error::NotFound(format!("entity {id} does not exist")))?;
        let count = u64::from(self.slot_count());
        let entry = &mut self.slots[slot as usize];
        entry.live = false;
        entry.generation += 1;
        // Retire the slot if its next id would overflow or collide with NO_ENTITY.
        let next_id = u64::from(entry.generation) * count + u64::from(slot);
        if next_id < u64::from(NO_ENTITY) {
            self.free.push(slot);
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn removed_ids_stay_dead_after_reuse() {
        let mut table = IdTable::new(2);
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
    fn exhausted_slots_are_retired() {
        let mut table = IdTable::new(1);
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
