//! What a member of a conversation looks at: the member its glance is on (their eyes), or,
//! in a glance away, what its own attention model chose — or, when that is nothing, a point
//! beside the group, drawn for each glance (the model: [`crate::attention::conversation`]).

use glam::{Quat, Vec3};

use super::conversation_table::{slot_and_member, NO_CONVERSATION};
use super::look::LookContext;
use super::model_state::{Look, LookTarget};
use super::states::CharacterView;
use crate::attention::conversation::{away_offsets, MemberGaze, AWAY, MAX_MEMBERS};
use crate::attention::{AttentionModel, TargetPart};
use crate::ik::{GazeRequest, MotionStyle};

/// Gaze-request keys of away glances: this bit and the glance's draw count (entity ids are
/// below 2³², the other keys have bits 40 or 63).
const AWAY_KEY: u64 = 1 << 42;

/// How far from the eyes an away glance's point is, metres.
const AWAY_DISTANCE: f32 = 2.0;

/// A conversation member's gaze this frame.
#[derive(Debug, Clone, Copy)]
pub(super) struct ConversationGaze {
    /// The member's id.
    id: u32,
    /// Its glance.
    glance: MemberGaze,
    /// The id of the member looked at, when not away.
    partner: Option<u32>,
    /// The group's slot.
    slot: usize,
    /// The group's members (character ids); the first `count` are used.
    members: [u32; MAX_MEMBERS],
    /// How many members.
    count: usize,
}

impl ConversationGaze {
    /// True if `look` is on a member of the group: a glance away is not (the attention
    /// model's choice then gives way to a point beside the group).
    pub(super) fn among_members(&self, look: Look) -> bool {
        let members = &self.members[..self.count];
        members.contains(&look.eye.entity) || members.contains(&look.head.entity)
    }
}

impl LookContext<'_> {
    /// The gaze of a character (dense index) in a conversation, if it is in one.
    pub(super) fn conversation_gaze(&self, character: usize) -> Option<ConversationGaze> {
        let place = self.characters.conversation[character];
        if place == NO_CONVERSATION {
            return None;
        }
        let (slot, member) = slot_and_member(place);
        let group = self.conversations.group(slot);
        let glance = group.gaze[member];
        let partner = (glance.target != AWAY)
            .then(|| group.members[usize::from(glance.target)])
            .filter(|&id| self.scene.index_of(id).is_some());
        Some(ConversationGaze {
            id: group.members[member],
            glance,
            partner,
            slot,
            members: group.members,
            count: usize::from(group.count),
        })
    }

    /// The gaze request of a conversation member: its partner's eyes, or in a glance away
    /// `own` (what its attention model chose, if not a member) or else a point beside the
    /// group.
    pub(super) fn conversation_request(
        &self,
        character: usize,
        view: CharacterView<'_>,
        gaze: ConversationGaze,
        own: Option<GazeRequest>,
    ) -> Option<GazeRequest> {
        let style = match self.characters.params[character].model {
            AttentionModel::Saliency => MotionStyle::Saccadic,
            _ => self.eased_style,
        };
        if let Some(partner) = gaze.partner {
            let index = self.scene.index_of(partner)?;
            let point = self.scene.look_at_point(index);
            return Some(GazeRequest {
                target_key: u64::from(partner),
                head_target: point,
                eye_target: point,
                interest_ratio: 1.0,
                style,
            });
        }
        if own.is_some() {
            return own;
        }
        let point = self.away_point(character, view, gaze);
        Some(GazeRequest {
            target_key: AWAY_KEY | u64::from(gaze.glance.draws),
            head_target: point,
            eye_target: point,
            interest_ratio: 1.0,
            style,
        })
    }

    /// What a conversation member's eyes and head fixate: its partner, or `own`.
    pub(super) fn conversation_look(&self, gaze: ConversationGaze, own: Look) -> Look {
        match gaze.partner {
            Some(partner) => {
                let target = LookTarget {
                    entity: partner,
                    part: TargetPart::Whole,
                };
                Look {
                    eye: target,
                    head: target,
                }
            }
            None => own,
        }
    }

    /// The point of an away glance: from the member's eyes, the direction to the group's
    /// centre turned by the glance's yaw (about up) and pitch ([`away_offsets`]).
    fn away_point(
        &self,
        character: usize,
        view: CharacterView<'_>,
        gaze: ConversationGaze,
    ) -> Vec3 {
        let up = self.world.up;
        let eye = self.eye_position(character, view.motion);
        let group = self.conversations.group(gaze.slot);
        let (mut centre, mut count) = (Vec3::ZERO, 0.0);
        for &id in group.member_ids() {
            if let Some(index) = self.scene.index_of(id) {
                centre += self.scene.positions()[index];
                count += 1.0;
            }
        }
        let entity = self.scene.character_entities()[character] as usize;
        let ahead = self.world.heading_direction(self.scene.headings()[entity]);
        let to_centre = centre / count - eye;
        let level = (to_centre - up * to_centre.dot(up)).normalize_or(ahead);
        let (yaw, pitch) = away_offsets(self.seed, gaze.id, gaze.glance.draws);
        let side = up.cross(level).normalize_or_zero();
        let direction =
            Quat::from_axis_angle(up, yaw) * Quat::from_axis_angle(side, -pitch) * level;
        eye + direction * AWAY_DISTANCE
    }
}
