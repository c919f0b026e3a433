//! Conversations: groups of characters standing together and talking — forming and ending
//! them, and characters leaving them (the table: `conversation_table.rs`; the model:
//! [`crate::attention::conversation`]).

use super::conversation_table::{place, slot_and_member, NO_CONVERSATION};
use super::Crowd;
use crate::attention::conversation::{Conversation, MAX_MEMBERS};
use crate::error::{Error, Result};
use crate::scene::ids::EntityKind;

impl Crowd {
    /// Makes `members` (2 to 8 character ids, each in no other conversation) a group
    /// standing together and talking; returns the group's id. Members look at each other as
    /// people in conversation do ([`crate::attention::conversation`]); which of them talks
    /// comes with each pushed state (`talking`). Errors, changing nothing:
    /// [`Error::InvalidArgument`] for fewer than 2 or more than 8 members, a repeated id, an
    /// object, or a character already in a conversation; [`Error::NotFound`] for an unknown
    /// id; [`Error::Capacity`] when `max_conversations` groups exist already.
    ///
    /// Ids are given in turn from one 32-bit counter, skipping `u32::MAX` (`CG_NO_TARGET`,
    /// "in none") and live groups' ids: a removed group's id names no group until at least
    /// 2³² − 1 − `max_conversations` more groups have been formed (4 286 578 687 at the
    /// largest capacity), whatever the capacity and however long other groups last.
    pub fn set_conversation(&mut self, members: &[u32]) -> Result<u32> {
        if !(2..=MAX_MEMBERS).contains(&members.len()) {
            return Err(Error::InvalidArgument(format!(
                "a conversation has 2 to {MAX_MEMBERS} members, not {}",
                members.len()
            )));
        }
        let mut characters = [0usize; MAX_MEMBERS];
        for (position, &id) in members.iter().enumerate() {
            let (kind, _) = self.shared.scene.find(id)?;
            if kind != EntityKind::Character {
                return Err(Error::InvalidArgument(format!(
                    "entity {id} is an object: only characters converse"
                )));
            }
            if members[..position].contains(&id) {
                return Err(Error::InvalidArgument(format!(
                    "character {id} is listed twice"
                )));
            }
            let character = self.shared.scene.character_index(id)?;
            if self.shared.characters.conversation[character] != NO_CONVERSATION {
                let (slot, _) = slot_and_member(self.shared.characters.conversation[character]);
                return Err(Error::InvalidArgument(format!(
                    "character {id} is already in conversation {}",
                    self.shared.conversations.id_of(slot)
                )));
            }
            characters[position] = character;
        }
        let shared = &mut *self.shared;
        let table = &mut shared.conversations;
        let Some((slot, id)) = table.open(Conversation::new(members)) else {
            return Err(Error::Capacity(format!(
                "the crowd already holds max_conversations = {} conversations",
                table.capacity()
            )));
        };
        for (member, &character) in characters[..members.len()].iter().enumerate() {
            shared.characters.conversation[character] = place(slot, member);
        }
        Ok(id)
    }

    /// Ends conversation `group`: its members go back to their own attention.
    /// [`Error::NotFound`] if there is no such group.
    pub fn remove_conversation(&mut self, group: u32) -> Result<()> {
        let slot = self
            .shared
            .conversations
            .slot_of(group)
            .ok_or_else(|| Error::NotFound(format!("no conversation {group}")))?;
        self.dissolve(slot);
        Ok(())
    }

    /// The conversation character `character_id` is in, if any.
    pub fn conversation_of(&self, character_id: u32) -> Result<Option<u32>> {
        let character = self.shared.scene.character_index(character_id)?;
        let place = self.shared.characters.conversation[character];
        Ok((place != NO_CONVERSATION).then(|| {
            let (slot, _) = slot_and_member(place);
            self.shared.conversations.id_of(slot)
        }))
    }

    /// The members of conversation `group` (character ids), or [`Error::NotFound`].
    pub fn conversation_members(&self, group: u32) -> Result<&[u32]> {
        let table = &self.shared.conversations;
        let slot = table
            .slot_of(group)
            .ok_or_else(|| Error::NotFound(format!("no conversation {group}")))?;
        Ok(table.groups[slot].member_ids())
    }

    /// Frees group `slot`, its members back to their own attention.
    fn dissolve(&mut self, slot: usize) {
        let shared = &mut *self.shared;
        let table = &mut shared.conversations;
        for &id in table.groups[slot].member_ids() {
            if let Ok(character) = shared.scene.character_index(id) {
                shared.characters.conversation[character] = NO_CONVERSATION;
            }
        }
        table.close(slot);
    }

    /// Takes character `character` (dense index, still in the scene) out of its
    /// conversation, if it is in one; a group left with one member ends.
    pub(super) fn leave_conversation(&mut self, character: usize) {
        let place = self.shared.characters.conversation[character];
        if place == NO_CONVERSATION {
            return;
        }
        let (slot, member) = slot_and_member(place);
        self.shared.characters.conversation[character] = NO_CONVERSATION;
        let shared = &mut *self.shared;
        let group = &mut shared.conversations.groups[slot];
        if let Some(moved) = group.remove(member) {
            if let Ok(moved) = shared.scene.character_index(moved) {
                shared.characters.conversation[moved] = place;
            }
        }
        if group.count < 2 {
            self.dissolve(slot);
        }
    }
}
