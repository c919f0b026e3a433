//! Gaze IK (Grillon & Thalmann 2009): the gaze chain a character turns, the spatial
//! resolution that spreads one gaze rotation over it, and the temporal resolution that
//! plays it out with human timing.
//!
//! - [`chain`](crate::ik::chain): [`GazeChain`](crate::ik::GazeChain), the spine, neck, head
//!   and eye joints, bottom to top, with their offsets, rest rotations and limits.
//! - [`spatial`](crate::ik::spatial): one frame's displacement map — the delta rotation of
//!   every joint that makes the eyes look at a target
//!   ([`spatial::solve`](crate::ik::spatial::solve)).
//! - [`temporal`](crate::ik::temporal): [`GazeMotion`](crate::ik::GazeMotion), a character's
//!   gaze state from frame to frame: activation time, eyes → head → spine desynchronisation,
//!   the ease `f_P`, moving targets, restarts and deactivation.
//! - [`eyelids`](crate::ik::eyelids): [`BlinkState`](crate::ik::BlinkState), a character's
//!   spontaneous and gaze-evoked blinks, and upper lids that follow the eyes' pitch.
//!
//! Every output is a *delta* (displacement) local rotation per chain joint: the joint's final
//! local rotation is `base * delta` (glam's product: the delta acts in the joint's own frame,
//! after its base rotation), where `base` is the rest pose or the engine's animated pose.
//!
//! Units: metres, radians, seconds. The chain is expressed in the world's axes for a
//! character at heading 0; a character's world transform is
//! `translation(position) · rotation(heading about world up)`
//! ([`CharacterTransform`](crate::ik::CharacterTransform)).
//!
//! A crowd's frame, [`BATCH_LANES`](crate::ik::temporal::BATCH_LANES) characters per call:
//!
//! ```
//! use crowdgaze::ik::temporal::BATCH_LANES;
//! use crowdgaze::ik::{CharacterTransform, GazeChain, GazeConfig, GazeInput, GazeMotion, GazeRequest};
//! use crowdgaze::math::random::{stream, Purpose, Random};
//! use glam::{Quat, Vec3};
//!
//! let chain = GazeChain::human(Vec3::Y, Vec3::Z);
//! let rest: Vec<Quat> = chain.joints().iter().map(|joint| joint.rest).collect();
//! let config = GazeConfig::default();
//! let mut motions = vec![GazeMotion::new(&chain); 2 * BATCH_LANES];
//! let mut randoms: Vec<Random> = (0..2 * BATCH_LANES as u64).map(|i| stream(42, Purpose::GazeTiming, i)).collect();
//! for (chunk, (motions, randoms)) in motions
//!     .chunks_exact_mut(BATCH_LANES)
//!     .zip(randoms.chunks_exact_mut(BATCH_LANES))
//!     .enumerate()
//! {
//!     let inputs: [GazeInput<'_>; BATCH_LANES] = std::array::from_fn(|lane| GazeInput {
//!         character: CharacterTransform::from_heading(
//!             Vec3::new((chunk * BATCH_LANES + lane) as f32, 0.0, 0.0),
//!             Vec3::Y,
//!             0.0,
//!         ),
//!         base: &rest,
//!         request: Some(GazeRequest::at(7, Vec3::new(2.0, 1.6, 3.0))),
//!         dt: 1.0 / 30.0,
//!     });
//!     let motions = <&mut [GazeMotion; BATCH_LANES]>::try_from(motions).unwrap();
//!     let randoms = <&mut [Random; BATCH_LANES]>::try_from(randoms).unwrap();
//!     let results = GazeMotion::update_batch(
//!         motions.each_mut(),
//!         [&chain; BATCH_LANES],
//!         &config,
//!         inputs.each_ref(),
//!         randoms.each_mut(),
//!     );
//!     for result in results {
//!         result.unwrap();
//!     }
//! }
//! // Final local rotation of joint i: rest[i] * motions[c].deltas()[i].
//! assert_eq!(motions[0].deltas().len(), 10);
//! ```

pub mod chain;
pub mod eyelids;
mod lanes;
mod rotation;
pub mod spatial;
pub mod temporal;

use glam::{Quat, Vec3};

pub use chain::{
    ChainJoint, GazeChain, JointGroup, JointLimits, JointRole, MAX_CERVICAL_JOINTS,
    MAX_CHAIN_JOINTS, MAX_SPINE_JOINTS,
};
pub use eyelids::{BlinkSettings, BlinkState};
pub use spatial::{RecruitmentBands, SpatialConfig, SpatialSolution, TurnSide};
pub use temporal::{
    GazeConfig, GazeInput, GazeMotion, GazePhase, GazeRequest, GazeTiming, MotionStyle,
};

/// Where a character stands and which way it faces: its world transform is
/// `translation(position) · rotation`.
///
/// For a crowd character, `rotation` is the heading about the world's up axis
/// ([`CharacterTransform::from_heading`]); any rotation works (e.g. a pelvis orientation).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CharacterTransform {
    /// The character's position (on the ground), metres.
    pub position: Vec3,
    /// The character's orientation (unit quaternion).
    pub rotation: Quat,
}

impl CharacterTransform {
    /// At the origin, heading 0.
    pub const IDENTITY: CharacterTransform = CharacterTransform {
        position: Vec3::ZERO,
        rotation: Quat::IDENTITY,
    };

    /// A character at `position` turned by `heading` radians counter-clockwise about `up`
    /// (the world convention of [`crate::world::World`]).
    pub fn from_heading(position: Vec3, up: Vec3, heading: f32) -> CharacterTransform {
        CharacterTransform {
            position,
            rotation: Quat::from_axis_angle(up, heading),
        }
    }

    /// True if every component is finite.
    pub fn is_finite(&self) -> bool {
        self.position.is_finite() && self.rotation.is_finite()
    }
}

impl Default for CharacterTransform {
    fn default() -> Self {
        CharacterTransform::IDENTITY
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::world::World;

    #[test]
    fn heading_matches_the_world_convention() {
        for world in [
            World::y_up(),
            World::new(crate::Axis::PositiveZ, crate::Axis::NegativeY, 1.0).unwrap(),
        ] {
            for heading in [0.0f32, 0.7, -2.0, 3.0] {
                let character = CharacterTransform::from_heading(Vec3::ZERO, world.up, heading);
                let facing = character.rotation * world.forward;
                assert!(facing.abs_diff_eq(world.heading_direction(heading), 1e-5));
            }
        }
    }
}
