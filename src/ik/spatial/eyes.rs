//! The eyes: each eye's frame below the head, its vergence delta onto the eye target (within
//! its limits), and the eyes' world rays ([`EyeRays`]).

use glam::{Quat, Vec3, Vec3A};

use super::behind::behind_adjusted;
use super::config::Prepared;
use super::frames::{eye_middle, global_eye, same_chain, Frame, Frames};
use super::limits::{turn_joint, Limits};
use super::turn::gaze_rotation;
use crate::ik::chain::GazeChain;
use crate::math::lanes::{mask, Floats, Mask, MAX_LANES, Q4, V3};
use crate::math::wide::Wide;

/// World positions and gaze directions of the two eyes (both the global eye for a chain
/// without eyes).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EyeRays {
    /// Eye positions, left then right, metres.
    pub origins: [Vec3; 2],
    /// Unit gaze directions, left then right.
    pub directions: [Vec3; 2],
}
/// Per lane, one eye's frame before its delta: position, rotation, and the eye's forward and
/// up axes in its own frame. Lanes without eyes get the head's global eye.
#[derive(Debug, Clone, Copy)]
pub(crate) struct EyeFrames<W: Wide> {
    pub(crate) position: V3<W>,
    pub(crate) rotation: Q4<W>,
    pub(crate) local_forward: V3<W>,
    local_up: V3<W>,
    /// Lanes whose chain has eyes.
    pub(crate) has_eyes: Mask<W>,
    /// Each lane's joint index of this eye (0 without eyes).
    pub(crate) index: [usize; MAX_LANES],
}

impl<W: Wide> EyeFrames<W> {
    /// Eye `eye` (0 left, 1 right) of each lane, below the heads' final frames.
    #[inline(always)]
    pub(crate) fn new(
        chains: &[&GazeChain; MAX_LANES],
        bases: &[&[Quat]; MAX_LANES],
        heads: &Frames<W>,
        eye: usize,
    ) -> EyeFrames<W> {
        let index = chains.map(|chain| chain.eye_indices().map_or(0, |eyes| eyes[eye]));
        let has_eyes = mask(|i| chains[i].has_eyes());
        // The eye's offset and its forward and up axes in its own frame.
        let eye_data = |chain: &GazeChain, index: usize| -> (Vec3A, Vec3A, Vec3A) {
            let (forward, up) = (chain.eye_forward().into(), chain.eye_up().into());
            if !chain.has_eyes() {
                return (eye_middle(chain), forward, up);
            }
            let joint = &chain.joints()[index];
            if joint.rest == Quat::IDENTITY {
                (joint.offset.into(), forward, up)
            } else {
                let to_eye = joint.rest.conjugate();
                (
                    joint.offset.into(),
                    to_eye.mul_vec3a(forward),
                    to_eye.mul_vec3a(up),
                )
            }
        };
        let (offset, local_forward, local_up) = if same_chain(chains) {
            let (offset, forward, up) = eye_data(chains[0], index[0]);
            (V3::splat(offset), V3::splat(forward), V3::splat(up))
        } else {
            let data: [(Vec3A, Vec3A, Vec3A); MAX_LANES] =
                std::array::from_fn(|i| eye_data(chains[i], index[i]));
            (
                V3::gather(|i| data[i].0),
                V3::gather(|i| data[i].1),
                V3::gather(|i| data[i].2),
            )
        };
        let rotation = if bases.iter().all(|base| std::ptr::eq(*base, bases[0]))
            && same_chain(chains)
            && (!chains[0].has_eyes() || bases[0][index[0]] == Quat::IDENTITY)
        {
            // Every lane's eye rests at identity in its base pose: nothing to multiply.
            heads.rotation
        } else {
            heads.rotation.mul(Q4::gather(|i| {
                if chains[i].has_eyes() {
                    bases[i][index[i]]
                } else {
                    Quat::IDENTITY
                }
            }))
        };
        EyeFrames {
            position: heads.position.add(heads.rotation.rotate(offset)),
            rotation,
            local_forward,
            local_up,
            has_eyes,
            index,
        }
    }

    /// Per lane, the vergence delta that turns this eye onto `target` (within its limits);
    /// identity for lanes without eyes.
    #[inline(always)]
    pub(crate) fn goal(
        &self,
        chains: &[&GazeChain; MAX_LANES],
        prepared: &Prepared,
        target: V3<W>,
        side_sign: Floats<W>,
    ) -> Q4<W> {
        let forward = self.rotation.rotate(self.local_forward);
        let up = self.rotation.rotate(self.local_up);
        let aimed = behind_adjusted(target.sub(self.position), forward, up, side_sign, prepared);
        let turn = gaze_rotation(forward, aimed, up.scale(side_sign), prepared);
        let limits = Limits::of_joints(chains, same_chain(chains), self.index);
        let (delta, _) = turn_joint(&limits, self.rotation, turn);
        Q4::select(
            self.has_eyes & turn.sin.cmpgt(Floats::zero()),
            delta,
            Q4::identity(),
        )
    }

    /// Per lane, the unit gaze direction for the eye's delta `delta`.
    #[inline(always)]
    pub(crate) fn direction(&self, delta: Q4<W>) -> V3<W> {
        let direction = self.rotation.mul(delta).rotate(self.local_forward);
        direction.scale(direction.length_squared().sqrt().recip())
    }
}

/// Eye positions and gaze directions in the world for a head frame and the eyes' deltas.
pub(crate) fn eye_rays_unchecked(
    chain: &GazeChain,
    head: &Frame,
    base: &[Quat],
    deltas: &[Quat],
) -> EyeRays {
    match chain.eye_indices() {
        Some(eyes) => {
            let mut rays = EyeRays {
                origins: [Vec3::ZERO; 2],
                directions: [Vec3::ZERO; 2],
            };
            for (slot, index) in eyes.into_iter().enumerate() {
                let joint = &chain.joints()[index];
                let local_forward = joint.rest.conjugate() * chain.eye_forward();
                let position = head.position + head.rotation.mul_vec3a(Vec3A::from(joint.offset));
                let rotation = head.rotation * base[index] * deltas[index];
                rays.origins[slot] = position.into();
                rays.directions[slot] = (rotation * local_forward).normalize_or_zero();
            }
            rays
        }
        None => {
            let (position, forward) = global_eye(chain, head);
            EyeRays {
                origins: [position.into(); 2],
                directions: [forward.normalize_or_zero().into(); 2],
            }
        }
    }
}
