//! What each character's attention model keeps between frames ([`ModelState`]), and where
//! the saliency and baseline models want its eyes and head ([`Look`]).

use crate::attention::baseline::BaselineState;
use crate::attention::interest::{InterestConfig, InterestTracker};
use crate::attention::saliency::FixationChannel;
use crate::attention::street::StreetState;
use crate::attention::{AttentionModel, TargetPart};
use crate::scene::ids::NO_ENTITY;

/// One of the things a character looks at: an entity and which part of it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct LookTarget {
    /// Entity id, or `NO_ENTITY`.
    pub entity: u32,
    /// The part of the entity.
    pub part: TargetPart,
}

impl LookTarget {
    /// Nothing.
    pub const NONE: LookTarget = LookTarget {
        entity: NO_ENTITY,
        part: TargetPart::Whole,
    };
}

/// Where the saliency or baseline model wants a character's eyes and head.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Look {
    /// The eyes' target.
    pub eye: LookTarget,
    /// The head's (and body's) target.
    pub head: LookTarget,
}

impl Look {
    /// Looking ahead.
    pub const NONE: Look = Look {
        eye: LookTarget::NONE,
        head: LookTarget::NONE,
    };

    /// Drops every reference to a removed entity.
    pub fn forget(&mut self, id: u32) {
        if self.eye.entity == id {
            self.eye = LookTarget::NONE;
        }
        if self.head.entity == id {
            self.head = LookTarget::NONE;
        }
    }
}

/// A character's saliency fixations: one channel for the eyes, one for the head.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct SaliencyState {
    /// The eyes' fixation.
    pub eye: FixationChannel,
    /// The head's fixation.
    pub head: FixationChannel,
}

/// The saliency and baseline models' state of a character: where they want its eyes and
/// head, the saliency fixations and the baseline's glances.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GlanceState {
    /// Where the model wants the eyes and head.
    pub look: Look,
    /// Saliency fixations.
    pub saliency: SaliencyState,
    /// Baseline glances.
    pub baseline: BaselineState,
}

/// What a character's attention model keeps between frames. Only the model the character
/// uses has state (a character carries the largest, not all): switching to or
/// from the crowd model starts the new model afresh; the saliency and baseline models
/// share theirs.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ModelState {
    /// The crowd model's online interest tracker.
    Crowd(InterestTracker),
    /// The saliency or baseline model's state.
    Glance(GlanceState),
    /// The street model's walkers in view and fixation.
    Street(StreetState),
}

impl ModelState {
    /// A fresh state for `model` (`interest` sets up the crowd model's tracker).
    pub fn new(model: AttentionModel, interest: &InterestConfig) -> Self {
        match model {
            AttentionModel::Crowd => ModelState::Crowd(InterestTracker::new(interest)),
            AttentionModel::Saliency | AttentionModel::Baseline => {
                ModelState::Glance(GlanceState {
                    look: Look::NONE,
                    saliency: SaliencyState::default(),
                    baseline: BaselineState::default(),
                })
            }
            AttentionModel::Street => ModelState::Street(StreetState::default()),
        }
    }

    /// True if this is the state `model` keeps.
    pub fn serves(&self, model: AttentionModel) -> bool {
        matches!(
            (self, model),
            (ModelState::Crowd(_), AttentionModel::Crowd)
                | (
                    ModelState::Glance(_),
                    AttentionModel::Saliency | AttentionModel::Baseline
                )
                | (ModelState::Street(_), AttentionModel::Street)
        )
    }

    /// The crowd model's tracker, if this is its state.
    pub fn tracker(&self) -> Option<&InterestTracker> {
        match self {
            ModelState::Crowd(tracker) => Some(tracker),
            _ => None,
        }
    }

    /// The saliency and baseline models' state, if this is theirs.
    pub fn glance(&self) -> Option<&GlanceState> {
        match self {
            ModelState::Glance(glance) => Some(glance),
            _ => None,
        }
    }

    /// Where the saliency, baseline or street model wants the eyes and head (nowhere for
    /// the crowd model, whose target is its tracker's interest point; the street model's
    /// path ahead is nowhere too: [`LookContext::model_request`](super::look::LookContext)
    /// places it).
    pub fn look(&self) -> Look {
        match self {
            ModelState::Crowd(_) => Look::NONE,
            ModelState::Glance(glance) => glance.look,
            ModelState::Street(street) => {
                let target = LookTarget {
                    entity: street.fixated(),
                    part: TargetPart::Head,
                };
                if target.entity == NO_ENTITY {
                    Look::NONE
                } else {
                    Look {
                        eye: target,
                        head: target,
                    }
                }
            }
        }
    }

    /// The street model's state, if this is its state.
    pub fn street(&self) -> Option<&StreetState> {
        match self {
            ModelState::Street(street) => Some(street),
            _ => None,
        }
    }

    /// Drops every reference to a removed entity.
    pub fn forget(&mut self, id: u32) {
        match self {
            ModelState::Crowd(tracker) => tracker.forget(id),
            ModelState::Glance(glance) => glance.look.forget(id),
            ModelState::Street(street) => street.forget(id),
        }
    }
}
