//! What a character looks at, resolved from everything that decides it: its attention
//! model's choice (or the plan's), an explicit target from game logic, and where the target
//! and the character's own eyes and head are now. Both jobs and the readers use it.

use glam::{Quat, Vec3};

use super::conversation_table::Conversations;
use super::model_state::{Look, LookTarget};
use super::states::CharacterView;
use super::tables::{Chains, Characters};
use super::values::{ExplicitTarget, TargetPriority, EXPLICIT_POINT_KEY};
use crate::attention::following::Cue;
use crate::attention::interest::InterestTracker;
use crate::attention::plan::Plan;
use crate::attention::street::StreetConfig;
use crate::attention::{AttentionModel, TargetPart};
use crate::ik::{CharacterTransform, GazeMotion, GazeRequest, MotionStyle};
use crate::scene::ids::NO_ENTITY;
use crate::scene::Scene;
use crate::world::World;

/// The gaze key of a glance at the point others look at (gaze following).
const FOLLOW_POINT_KEY: u64 = 1 << 41;
/// The gaze key of a street character's look down the path ahead.
const STREET_PATH_KEY: u64 = 1 << 42;
/// The gaze key of a street character's look nearer down the path, while a stranger is
/// close (civil inattention).
const STREET_CIVIL_KEY: u64 = 1 << 42 | 1;

/// What resolving a character's look reads (all shared, read-only during a step).
#[derive(Debug, Clone, Copy)]
pub(super) struct LookContext<'a> {
    /// The entities and their current state.
    pub scene: &'a Scene,
    /// The crowd's axes.
    pub world: World,
    /// Per-character parameters, chains, base poses and explicit targets.
    pub characters: &'a Characters,
    /// The distinct chains.
    pub chains: &'a Chains,
    /// The offline plan, when attention follows one.
    pub plan: Option<&'a Plan>,
    /// The conversations (who looks at whom in each).
    pub conversations: &'a Conversations,
    /// The crowd's seed (the away glances of conversations draw from it).
    pub seed: u64,
    /// The style of the crowd model's and the baseline's shifts: [`MotionStyle::Eased`],
    /// or [`MotionStyle::MainSequence`] ([`EyeMotion`](super::EyeMotion)).
    pub eased_style: MotionStyle,
    /// Whether gaze following is on (then a following character looks at the point).
    pub following: bool,
    /// Each character's gaze cue this step, for gaze following (empty when it is off).
    pub cues: &'a [Cue],
    /// The street model's settings.
    pub street: &'a StreetConfig,
}

impl LookContext<'_> {
    /// The world point of `target` now (metres), if its entity exists.
    pub fn target_point(&self, target: LookTarget) -> Option<Vec3> {
        let index = self.scene.index_of(target.entity)?;
        if target.part == TargetPart::Whole {
            return Some(self.scene.look_at_point(index));
        }
        let character = self.scene.character_at(index)?;
        let parts = &self.chains.parts[self.characters.chain_of[character] as usize];
        let rotation = Quat::from_axis_angle(self.world.up, self.scene.headings()[index]);
        Some(self.scene.positions()[index] + rotation * parts[target.part as usize - 1])
    }

    /// A character's eye position (the mid-point of its eyes, world metres): where the
    /// last gaze update put it, or at rest before the first one.
    pub fn eye_position(&self, character: usize, motion: &GazeMotion) -> Vec3 {
        let origins = motion.eye_origins();
        if origins[0] != Vec3::ZERO || origins[1] != Vec3::ZERO {
            return 0.5 * (origins[0] + origins[1]);
        }
        let transform = self.character_transform(character);
        let chain = self.characters.chain(self.chains, character);
        transform.position + transform.rotation * chain.rest_eye_position()
    }

    /// The direction the character's head faces now (world, unit): the eyes' rest forward
    /// carried through the body joints' current local rotations.
    pub fn head_forward(&self, character: usize, motion: &GazeMotion) -> Vec3 {
        let chain = self.characters.chain(self.chains, character);
        let deltas = motion.deltas();
        let mut rotation = self.character_transform(character).rotation;
        let body = chain.body_count();
        let base = self.characters.base_pose(self.chains, character);
        for (base, delta) in base[..body].iter().zip(&deltas[..body]) {
            rotation *= *base * *delta;
        }
        (rotation * chain.eye_forward()).normalize_or_zero()
    }

    /// A character's (dense index) world transform.
    pub fn character_transform(&self, character: usize) -> CharacterTransform {
        let entity = self.scene.character_entities()[character] as usize;
        CharacterTransform::from_heading(
            self.scene.positions()[entity],
            self.world.up,
            self.scene.headings()[entity],
        )
    }

    /// The automatic interest point of a character (dense index) and its `S_max`.
    pub fn automatic_target(
        &self,
        character: usize,
        tracker: Option<&InterestTracker>,
    ) -> (u32, f32) {
        match (&self.plan, tracker) {
            (Some(plan), _) => {
                let (target, s_max, _) = plan.current(character);
                (target, s_max)
            }
            (None, Some(tracker)) => (tracker.interest(), tracker.s_max()),
            (None, None) => (NO_ENTITY, 0.0),
        }
    }

    /// What a character (dense index) should look at this frame: its explicit target if
    /// one overrides, else its conversation's choice if it is in one, else what its
    /// attention model chose (or an explicit target that fills in), as a gaze request.
    pub fn gaze_request(&self, character: usize, view: CharacterView<'_>) -> Option<GazeRequest> {
        if let Some(point) = self.followed_point(character, view) {
            return Some(GazeRequest {
                target_key: FOLLOW_POINT_KEY,
                head_target: point,
                eye_target: point,
                interest_ratio: 1.0,
                style: self.eased_style,
            });
        }
        let own = self.own_request(character, view);
        match self.conversation_gaze(character) {
            Some(gaze) if !self.overridden(character) => {
                let own = own.filter(|_| !gaze.among_members(self.own_look(character, view)));
                self.conversation_request(character, view, gaze, own)
            }
            _ => own,
        }
    }

    /// The point the character glances at because others look there (gaze following),
    /// unless an explicit target overrides everything.
    pub fn followed_point(&self, character: usize, view: CharacterView<'_>) -> Option<Vec3> {
        if !self.following || self.overridden(character) {
            return None;
        }
        view.follow.following()
    }

    /// True if the character has an explicit target that overrides everything else.
    fn overridden(&self, character: usize) -> bool {
        matches!(
            self.characters.explicit[character].get(),
            Some((_, TargetPriority::Override))
        )
    }

    /// [`gaze_request`](Self::gaze_request) without the character's conversation.
    fn own_request(&self, character: usize, view: CharacterView<'_>) -> Option<GazeRequest> {
        let model = self.characters.params[character].model;
        let (automatic, s_max) = match model {
            AttentionModel::Crowd => self.automatic_target(character, view.model.tracker()),
            _ => (NO_ENTITY, 0.0),
        };
        let automatic = self
            .scene
            .index_of(automatic)
            .map(|index| (automatic, index));
        let model_request = match model {
            AttentionModel::Crowd => None,
            _ => self.model_request(character, view),
        };
        let idle = automatic.is_none() && model_request.is_none();
        let explicit = match self.characters.explicit[character].get() {
            Some((target, TargetPriority::Override)) => Some(target),
            Some((target, TargetPriority::WhenIdle)) if idle => Some(target),
            _ => None,
        };
        let (key, point, interest_ratio) = match (explicit, automatic) {
            (Some(ExplicitTarget::Point(point)), _) => (EXPLICIT_POINT_KEY, point, 1.0),
            (Some(ExplicitTarget::Entity(id)), _) => {
                let index = self.scene.index_of(id)?;
                (u64::from(id), self.scene.look_at_point(index), 1.0)
            }
            (None, Some((id, index))) => {
                let max_score = self.scene.max_impact();
                let ratio = if max_score > 0.0 {
                    s_max / max_score
                } else {
                    1.0
                };
                (
                    u64::from(id),
                    self.scene.look_at_point(index),
                    ratio.clamp(0.05, 1.0),
                )
            }
            (None, None) => return model_request,
        };
        Some(GazeRequest {
            target_key: key,
            head_target: point,
            eye_target: point,
            interest_ratio,
            style: self.eased_style,
        })
    }

    /// The gaze request of a saliency or baseline character: head and eyes each at their
    /// own target (straight ahead where there is none; the baseline's glance offsets the
    /// eyes).
    pub fn model_request(&self, character: usize, view: CharacterView<'_>) -> Option<GazeRequest> {
        let look = view.model.look();
        let entity = self.scene.character_entities()[character] as usize;
        if let (Some(street), LookTarget::NONE) = (view.model.street(), look.head) {
            // The path a few steps ahead (nearer, so lower, while a stranger is close).
            let (distance, key) = if street.is_civil() {
                (self.street.civil_look_distance, STREET_CIVIL_KEY)
            } else {
                (self.street.path_look_distance, STREET_PATH_KEY)
            };
            let ahead = self.world.heading_direction(self.scene.headings()[entity]);
            let point = self.scene.positions()[entity] + ahead * distance;
            return Some(GazeRequest {
                target_key: key,
                head_target: point,
                eye_target: point,
                interest_ratio: 1.0,
                style: self.eased_style,
            });
        }
        let eye = self.eye_position(character, view.motion);
        let up = self.world.up;
        let ahead = self.world.heading_direction(self.scene.headings()[entity]);
        let head_point = self.target_point(look.head);
        let head_target = head_point.unwrap_or(eye + ahead * 10.0);
        let mut eye_target = self.target_point(look.eye).unwrap_or(head_target);
        if self.characters.params[character].model == AttentionModel::Baseline {
            let (yaw, pitch) = view
                .model
                .glance()
                .map_or((0.0, 0.0), |state| state.baseline.glance);
            if yaw != 0.0 || pitch != 0.0 {
                let direction = (head_target - eye).normalize_or(ahead);
                let side = up.cross(direction).normalize_or_zero();
                let turned = Quat::from_axis_angle(up, yaw)
                    * Quat::from_axis_angle(side, -pitch)
                    * direction;
                eye_target = eye + turned * 10.0;
            }
        }
        if head_point.is_none()
            && self.target_point(look.eye).is_none()
            && eye_target == head_target
        {
            // Nothing to look at and no glance: let go, back to the base motion.
            return None;
        }
        // A new head target restarts the shift; the eyes follow theirs within it.
        let key = (u64::from(look.head.entity) << 3 | look.head.part as u64) | 1 << 40;
        Some(GazeRequest {
            target_key: key,
            head_target,
            eye_target,
            interest_ratio: 1.0,
            style: match self.characters.params[character].model {
                AttentionModel::Saliency => MotionStyle::Saccadic,
                _ => self.eased_style,
            },
        })
    }

    /// The targets a character's eyes and head fixate (dense index), resolving explicit
    /// targets, its conversation and the crowd model's interest point.
    pub fn current_look(&self, character: usize, view: CharacterView<'_>) -> Look {
        if self.followed_point(character, view).is_some() {
            return Look::NONE;
        }
        let own = self.own_look(character, view);
        match self.conversation_gaze(character) {
            Some(gaze) if !self.overridden(character) => {
                let own = if gaze.among_members(own) {
                    Look::NONE
                } else {
                    own
                };
                self.conversation_look(gaze, own)
            }
            _ => own,
        }
    }

    /// [`current_look`](Self::current_look) without the character's conversation.
    fn own_look(&self, character: usize, view: CharacterView<'_>) -> Look {
        let explicit = match self.characters.explicit[character].get() {
            Some((ExplicitTarget::Entity(id), priority)) => Some((id, priority)),
            _ => None,
        };
        let automatic = match self.characters.params[character].model {
            AttentionModel::Crowd => {
                let (target, _) = self.automatic_target(character, view.model.tracker());
                let target = LookTarget {
                    entity: target,
                    part: TargetPart::Whole,
                };
                Look {
                    eye: target,
                    head: target,
                }
            }
            _ => view.model.look(),
        };
        let automatic_exists = self.scene.index_of(automatic.head.entity).is_some()
            || self.scene.index_of(automatic.eye.entity).is_some();
        match explicit {
            Some((id, TargetPriority::Override)) => {
                let target = LookTarget {
                    entity: id,
                    part: TargetPart::Whole,
                };
                Look {
                    eye: target,
                    head: target,
                }
            }
            Some((id, TargetPriority::WhenIdle)) if !automatic_exists => {
                let target = LookTarget {
                    entity: id,
                    part: TargetPart::Whole,
                };
                Look {
                    eye: target,
                    head: target,
                }
            }
            _ => automatic,
        }
    }
}
