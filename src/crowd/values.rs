//! The values the crowd's API takes and returns: character and object descriptions,
//! explicit targets from game logic, and the gaze and eye reports of a step.

use glam::Vec3;

use crate::attention::{AttentionModel, CharacterParams, TargetPart};
use crate::ik::GazeChain;
#[cfg(doc)]
use crate::scene::ids::NO_ENTITY;

/// Gaze-request key of explicit point targets (entity ids are below 2³²).
pub(super) const EXPLICIT_POINT_KEY: u64 = 1 << 32;

/// Where a character is looking, after a step.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GazeInfo {
    /// The character's id.
    pub character: u32,
    /// What the eyes look at: the interest point's (or the eye target's) entity id, or
    /// [`NO_ENTITY`] when looking ahead or at an explicit point.
    pub target: u32,
    /// Which part of `target` (always [`TargetPart::Whole`] for the crowd model).
    pub target_part: TargetPart,
    /// What the head looks at (the same as `target` but for the saliency and baseline
    /// models, whose head and eyes have separate targets).
    pub head_target: u32,
    /// The point the eyes are sent to (metres): the target's look-at point (or part), an
    /// explicit point, or the point 10 m ahead at eye height when there is none.
    pub target_position: Vec3,
    /// `S_max` this frame.
    pub s_max: f32,
    /// The attention threshold `A` this frame; `f32::MAX` when the character cannot attend
    /// (an attention fraction of 0, or no score planned for it).
    pub threshold: f32,
    /// True if the character attends to an interest point.
    pub attending: bool,
    /// Fraction of the observed time spent attending so far.
    pub attentive_fraction: f32,
    /// Interest points started so far.
    pub interest_count: u32,
}

/// A description of a new character.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CharacterDesc {
    /// Root position (metres).
    pub position: Vec3,
    /// Heading (radians).
    pub heading: f32,
    /// `I_E`, how interesting this character is to others (≥ 0). Default 1.
    pub impact: f32,
    /// Attention parameters; `None` draws them from the crowd's seed.
    pub params: Option<CharacterParams>,
    /// The gaze chain (metres, world axes at heading 0); `None` is the human chain of
    /// [`GazeChain::human`] for the crowd's axes.
    pub chain: Option<GazeChain>,
    /// The attention model (used when `params` is `None`; otherwise `params.model`).
    pub model: AttentionModel,
}

impl Default for CharacterDesc {
    fn default() -> Self {
        CharacterDesc {
            position: Vec3::ZERO,
            heading: 0.0,
            impact: 1.0,
            params: None,
            chain: None,
            model: AttentionModel::Crowd,
        }
    }
}

/// A target set by game logic (top-down attention), overriding or completing the
/// automatic interest point.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ExplicitTarget {
    /// A world point (metres).
    Point(Vec3),
    /// An entity's look-at point, followed as it moves.
    Entity(u32),
}

/// When an explicit target applies.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TargetPriority {
    /// Always: the automatic interest point is ignored until the target is cleared.
    Override,
    /// Only while the character has no automatic interest point.
    WhenIdle,
}

/// A character's eyelids after a step ([`Crowd::eyelids_at`](super::Crowd::eyelids_at)).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct EyelidState {
    /// The character's id.
    pub character: u32,
    /// How closed the left eye's lids are: 0 open, 1 closed (a blink).
    pub left_closure: f32,
    /// How closed the right eye's lids are (both eyes blink together).
    pub right_closure: f32,
    /// The left upper lid's pitch in the head's frame, radians, positive up: it follows
    /// the eye's pitch ([`BlinkSettings::lid_gain`](crate::ik::BlinkSettings::lid_gain)),
    /// before the closure (which the engine blends towards its closed lid).
    pub left_lid_pitch: f32,
    /// The right upper lid's pitch, radians.
    pub right_lid_pitch: f32,
}

/// Where a character's eyes are and where they look, after a step (world, metres).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EyeState {
    /// The character's id.
    pub character: u32,
    /// Left and right eye positions (the head's position twice for a chain without eyes).
    pub origins: [Vec3; 2],
    /// Left and right unit gaze directions.
    pub directions: [Vec3; 2],
}

/// A description of a new scene object.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ObjectDesc {
    /// Root position (metres).
    pub position: Vec3,
    /// Heading (radians): its forward direction, for the orientation subscores.
    pub heading: f32,
    /// Height of its look-at point above the root (metres).
    pub look_at_height: f32,
    /// `I_E`, how interesting it is (≥ 0). Default 1.
    pub impact: f32,
}

impl Default for ObjectDesc {
    fn default() -> Self {
        ObjectDesc {
            position: Vec3::ZERO,
            heading: 0.0,
            look_at_height: 0.0,
            impact: 1.0,
        }
    }
}
