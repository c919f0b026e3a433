//! The table of a crowd's conversations: a fixed number of group slots (sized at creation
//! by [`CrowdConfig::max_conversations`](super::CrowdConfig)), each character's place in
//! one, and the per-step advance of every group — who talks, who looks at whom — run once
//! per step before the jobs (the model: [`crate::attention::conversation`]).

use crate::alloc::try_with_capacity;
use crate::attention::conversation::{Conversation, ConversationSettings, MAX_MEMBERS};
use crate::error::Result;
use crate::scene::Scene;

/// A character's place in the conversations ([`super::tables::Characters::conversation`]):
/// none.
pub(super) const NO_CONVERSATION: u32 = u32::MAX;

/// The conversations of a crowd: a fixed number of slots, each free or holding one group.
#[derive(Debug)]
pub(super) struct Conversations {
    /// The groups, by slot (a free slot's content is stale).
    pub groups: Vec<Conversation>,
    /// Whether each slot holds a group.
    pub live: Vec<bool>,
    /// Each slot's generation: a group's id is `slot + capacity · generation` (wrapping),
    /// so that the id of a removed group does not name the next one in its slot — until
    /// a slot has been reused about 2³² / capacity times (67 million at the default 64).
    pub generations: Vec<u32>,
    /// Free slots, the next one last.
    pub free: Vec<u32>,
}

impl Conversations {
    /// Room for `capacity` groups, or [`Error::OutOfMemory`] for `what`.
    pub fn new(capacity: u32, what: &dyn std::fmt::Display) -> Result<Conversations> {
        let slots = capacity as usize;
        let mut table = Conversations {
            groups: try_with_capacity(slots, what)?,
            live: try_with_capacity(slots, what)?,
            generations: try_with_capacity(slots, what)?,
            free: try_with_capacity(slots, what)?,
        };
        table.groups.resize(slots, Conversation::new(&[0, 0]));
        table.live.resize(slots, false);
        table.generations.resize(slots, 0);
        table.free.extend((0..capacity).rev());
        Ok(table)
    }

    pub fn capacity(&self) -> u32 {
        self.groups.len() as u32
    }

    /// The slot of group `id`, if it is live.
    pub fn slot_of(&self, id: u32) -> Option<usize> {
        let capacity = self.capacity();
        if capacity == 0 {
            return None;
        }
        let slot = (id % capacity) as usize;
        (self.live[slot] && self.generations[slot] == id / capacity).then_some(slot)
    }

    /// The id of the group in `slot`.
    pub fn id_of(&self, slot: usize) -> u32 {
        (slot as u32).wrapping_add(self.capacity().wrapping_mul(self.generations[slot]))
    }

    /// The group in `slot` (live or not).
    pub fn group(&self, slot: usize) -> &Conversation {
        &self.groups[slot]
    }

    /// Advances every group by `dt`, each member talking as its entity's last pushed state
    /// says.
    pub fn advance(&mut self, settings: &ConversationSettings, seed: u64, dt: f32, scene: &Scene) {
        let talking = scene.talking();
        for (group, _) in self
            .groups
            .iter_mut()
            .zip(&self.live)
            .filter(|(_, &live)| live)
        {
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
