//! World frames by forward kinematics: a chain root's and a head's frame for one character
//! ([`Frame`]) or per lane ([`Frames`]), the global eye (the eyes' mid-point, looking along
//! the head's forward axis), and the per-lane joint data the lockstep loops read.

use glam::{Quat, Vec3A};

use crate::ik::chain::GazeChain;
use crate::ik::CharacterTransform;
use crate::math::lanes::{MAX_LANES, Q4, V3};
use crate::math::wide::Wide;

/// A world frame: position (metres) and rotation.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Frame {
    pub(crate) position: Vec3A,
    pub(crate) rotation: Quat,
}

/// The chain root's world frame.
#[inline]
pub(crate) fn root_frame(chain: &GazeChain, character: &CharacterTransform) -> Frame {
    Frame {
        position: Vec3A::from(character.position)
            + character
                .rotation
                .mul_vec3a(Vec3A::from(chain.root_offset())),
        rotation: character.rotation,
    }
}

/// The head's final world frame for the pose `base[i] * deltas[i]` (body joints only).
pub(crate) fn head_frame(
    chain: &GazeChain,
    character: &CharacterTransform,
    base: &[Quat],
    deltas: &[Quat],
) -> Frame {
    let mut frame = root_frame(chain, character);
    let body = chain.body_count();
    for ((joint, base), delta) in chain.joints()[..body]
        .iter()
        .zip(&base[..body])
        .zip(&deltas[..body])
    {
        frame.position += frame.rotation.mul_vec3a(Vec3A::from(joint.offset));
        frame.rotation = frame.rotation * *base * *delta;
    }
    frame
}

/// The eyes' mid-point in the head's frame (the head joint itself without eyes).
#[inline]
pub(super) fn eye_middle(chain: &GazeChain) -> Vec3A {
    match chain.eye_indices() {
        Some([left, right]) => {
            let joints = chain.joints();
            0.5 * (Vec3A::from(joints[left].offset) + Vec3A::from(joints[right].offset))
        }
        None => Vec3A::ZERO,
    }
}

/// The global eye (position, forward) in the world for a head frame.
#[inline]
pub(super) fn global_eye(chain: &GazeChain, head: &Frame) -> (Vec3A, Vec3A) {
    (
        head.position + head.rotation.mul_vec3a(eye_middle(chain)),
        head.rotation.mul_vec3a(Vec3A::from(chain.eye_forward())),
    )
}
/// Per lane, a world frame.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Frames<W> {
    pub(crate) position: V3<W>,
    pub(crate) rotation: Q4<W>,
}

impl<W: Wide> Frames<W> {
    /// Each lane's chain root.
    #[inline(always)]
    pub(crate) fn roots(
        chains: &[&GazeChain; MAX_LANES],
        characters: &[&CharacterTransform; MAX_LANES],
    ) -> Frames<W> {
        Frames {
            position: V3::gather(|i| root_frame(chains[i], characters[i]).position),
            rotation: Q4::gather(|i| characters[i].rotation),
        }
    }

    /// Moves to the next joint down the chain: `offset` in the current frame, then `rotation`.
    #[inline(always)]
    pub(crate) fn descend(&mut self, offset: V3<W>, rotation: Q4<W>) {
        self.position = self.position.add(self.rotation.rotate(offset));
        self.rotation = self.rotation.mul(rotation);
    }
}

/// Each lane's joint `index` offset (zero past the lane's body joints).
#[inline(always)]
pub(crate) fn offsets<W: Wide>(
    chains: &[&GazeChain; MAX_LANES],
    same_chain: bool,
    index: usize,
) -> V3<W> {
    if same_chain {
        return V3::splat(chains[0].joints()[index].offset.into());
    }
    // Past a lane's body joints come its eyes (or nothing): a zero offset, not theirs.
    V3::gather(|i| {
        let chain = chains[i];
        if index < chain.body_count() {
            chain.joints()[index].offset.into()
        } else {
            Vec3A::ZERO
        }
    })
}

/// True if every lane has the same chain.
#[inline(always)]
pub(crate) fn same_chain(chains: &[&GazeChain; MAX_LANES]) -> bool {
    chains.iter().all(|chain| std::ptr::eq(*chain, chains[0]))
}
