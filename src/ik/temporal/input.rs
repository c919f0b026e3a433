//! What a character's gaze motion is given each frame: where the character stands, its base
//! pose, the time step and the target, if any ([`GazeInput`], [`GazeRequest`]).

use glam::{Quat, Vec3};

use super::config::MotionStyle;
use crate::ik::CharacterTransform;

/// What a character should look at this frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GazeRequest {
    /// Identity of the target (an entity id, say): a different key restarts the shift.
    pub target_key: u64,
    /// Where the spine, cervicals and head aim, world, metres.
    pub head_target: Vec3,
    /// Where the eyes converge, world, metres (the same point for the crowd model).
    pub eye_target: Vec3,
    /// `S_max / S_MAX` in (0, 1]: how interesting the target is relative to the most
    /// interesting thing possible; 1 for explicit targets. Values above 1 count as 1.
    pub interest_ratio: f32,
    /// How the shift to this target unfolds (taken when a shift starts).
    pub style: MotionStyle,
}

impl GazeRequest {
    /// Look at `target` with head and eyes, interest ratio 1.
    pub fn at(target_key: u64, target: Vec3) -> GazeRequest {
        GazeRequest {
            target_key,
            head_target: target,
            eye_target: target,
            interest_ratio: 1.0,
            style: MotionStyle::Eased,
        }
    }
}

/// One frame of input to [`GazeMotion::update`](crate::ik::GazeMotion::update).
#[derive(Debug, Clone, Copy)]
pub struct GazeInput<'a> {
    /// Where the character is and which way it faces.
    pub character: CharacterTransform,
    /// Base local rotation of each chain joint this frame (rest or animated pose; exactly
    /// `chain.joint_count()` unit quaternions).
    pub base: &'a [Quat],
    /// The target, or `None` to let go and return to the base motion.
    pub request: Option<GazeRequest>,
    /// Time since the previous update, seconds (≥ 0).
    pub dt: f32,
}
