//! The table of a crowd's conversations: a fixed number of group slots (sized at creation
//! by [`CrowdConfig::max_conversations`](super::CrowdConfig)), each character's place in
//! one, and the per-step advance of every group — who talks, who looks at whom — run once
//! per step before the jobs (the model: [`crate::attention::conversation`]).

use super::conversation_ids::GroupIds;
use crate::alloc::try_with_capacity;
use crate::attention::conversation::{Conversation, ConversationSettings, MAX_MEMBERS};
use crate::error::Result;
use crate::scene::Scene;

/// A character's place in the conversations ([`super::tables::Characters::conversation`]):
/// none.
pub(super) const NO_CONVERSATION: u32 = u32::MAX;

/// A slot's place in the live list: none (the slot is free).
const NOT_LIVE: u32 = u32::MAX;

/// The conversations of a crowd: a fixed number of slots, each free or holding one group.
/// Only the live groups cost anything per step: they are listed apart, and the step goes
/// through that list alone.
#[derive(Debug)]
pub(super) struct Conversations {
    /// The groups, by slot (a free slot's content is stale). Grows, within the room made at
    /// creation, to the highest slot used so far: a crowd made for millions of groups
    /// touches only the memory of those it has held.
    pub groups: Vec<Conversation>,
    /// The live slots, in no particular order: what [`advance`](Self::advance) visits.
    live: Vec<u32>,
    /// Each used slot's index in `live`, or [`NOT_LIVE`].
    live_at: Vec<u32>,
    /// Free slots below `groups.len()`, the next one last.
    free: Vec<u32>,
    /// The groups' ids ([`GroupIds`]: a removed group's id names no other group until
    /// 2³² − 1 − capacity more groups have been formed).
    ids: GroupIds,
    /// Most groups at once.
    capacity: u32,
}

impl Conversations {
    /// Room for `capacity` groups, or [`Error::OutOfMemory`](crate::Error) for `what`.
    pub fn new(capacity: u32, what: &dyn std::fmt::Display) -> Result<Conversations> {
        let slots = capacity as usize;
        Ok(Conversations {
            groups: try_with_capacity(slots, what)?,
            live: try_with_capacity(slots, what)?,
            live_at: try_with_capacity(slots, what)?,
            free: try_with_capacity(slots, what)?,
            ids: GroupIds::new(capacity, what)?,
            capacity,
        })
    }

    pub fn capacity(&self) -> u32 {
        self.capacity
    }

    /// The slot of group `id`, if it is live.
    pub fn slot_of(&self, id: u32) -> Option<usize> {
        self.ids.slot_of(id)
    }

    /// The id of the group in `slot` (live; else the last one it held).
    pub fn id_of(&self, slot: usize) -> u32 {
        self.ids.id_of(slot)
    }

    /// The group in `slot` (live or not).
    pub fn group(&self, slot: usize) -> &Conversation {
        &self.groups[slot]
    }

    /// Makes `group` live in a free slot and gives it an id: returns the slot and the id,
    /// or `None` when every slot is taken. Allocates nothing.
    pub fn open(&mut self, group: Conversation) -> Option<(usize, u32)> {
        let slot = match self.free.pop() {
            Some(slot) => {
                let slot = slot as usize;
                self.groups[slot] = group;
                slot
            }
            None if self.groups.len() < self.capacity as usize => {
                // Within the room made at creation: no allocation.
                self.groups.push(group);
                self.live_at.push(NOT_LIVE);
                self.groups.len() - 1
            }
            None => return None,
        };
        self.live_at[slot] = self.live.len() as u32;
        self.live.push(slot as u32);
        Some((slot, self.ids.give(slot)))
    }

    /// Frees the live group's `slot`: its id names no group from now on.
    pub fn close(&mut self, slot: usize) {
        let at = std::mem::replace(&mut self.live_at[slot], NOT_LIVE) as usize;
        self.live.swap_remove(at);
        if let Some(&moved) = self.live.get(at) {
            self.live_at[moved as usize] = at as u32;
        }
        self.ids.take_back(slot);
        self.free.push(slot as u32);
    }

    /// The live slots, in no particular order.
    #[cfg(test)]
    pub fn live_slots(&self) -> &[u32] {
        &self.live
    }

    /// Advances every live group by `dt`, each member talking as its entity's last pushed
    /// state says. Visits the live groups only: free slots cost nothing.
    pub fn advance(&mut self, settings: &ConversationSettings, seed: u64, dt: f32, scene: &Scene) {
        let talking = scene.talking();
        for &slot in &self.live {
            let group = &mut self.groups[slot as usize];
            let mut flags = [false; MAX_MEMBERS];
            for (flag, &id) in flags.iter_mut().zip(group.member_ids()) {
                *flag = scene.index_of(id).is_some_and(|index| talking[index]);
            }
            group.advance(settings, seed, dt, &flags);
        }
    }
}

/// A character's place value: its group's slot and its index among the members.
pub(super) fn place(slot: usize, member: usize) -> u32 {
    (slot * MAX_MEMBERS + member) as u32
}

/// The slot and member index of a place value.
pub(super) fn slot_and_member(place: u32) -> (usize, usize) {
    let place = place as usize;
    (place / MAX_MEMBERS, place % MAX_MEMBERS)
}

#[cfg(test)]
mod tests {
    use super::super::{CharacterDesc, Crowd, CrowdConfig};
    use glam::Vec3;

    #[test]
    fn a_step_visits_the_live_groups_alone() {
        // The largest capacity, three groups formed and one ended: the table holds the
        // three slots used, no more, and a step advances the two live groups alone.
        let mut crowd = Crowd::new(CrowdConfig {
            max_characters: 10,
            max_conversations: 1 << 23,
            ..CrowdConfig::default()
        })
        .unwrap();
        let mut add = |x| {
            let position = Vec3::new(x, 0.0, 0.0);
            crowd.add_character(&CharacterDesc {
                position,
                ..CharacterDesc::default()
            })
        };
        let ids: Vec<u32> = [0.0, 1.0, 3.0, 4.0, 6.0, 7.0]
            .map(|x| add(x).unwrap())
            .into();
        let groups: Vec<u32> = ids
            .chunks(2)
            .map(|pair| crowd.set_conversation(pair).unwrap())
            .collect();
        crowd.remove_conversation(groups[1]).unwrap();
        let table = &crowd.shared.conversations;
        assert_eq!(table.groups.len(), 3, "slots never used do not exist");
        let mut live = table.live_slots().to_vec();
        live.sort_unstable();
        assert_eq!(live, [0, 2], "the list a step visits");
        let (first, ended) = (*table.group(0), *table.group(1));
        for _ in 0..30 {
            crowd.step(1.0 / 30.0).unwrap();
        }
        let table = &crowd.shared.conversations;
        assert_ne!(table.group(0), &first, "a live group advances");
        assert_eq!(table.group(1), &ended, "an ended group is not visited");
    }
}
