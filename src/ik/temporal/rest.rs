//! The short update of a lane group whose every character rests (idle, no target): only the
//! eye rays of the base pose, by the same operations as the full update, so the same bits.

use glam::Quat;

use super::input::GazeInput;
use super::pose::{eyeless_directions, heads_by_kinematics};
use super::GazeMotion;
use crate::ik::chain::GazeChain;
use crate::ik::spatial::{self, EyeFrames};
use crate::ik::CharacterTransform;
use crate::math::lanes::{MAX_LANES, Q4, V3};
use crate::math::wide::Wide;

impl GazeMotion {
    /// [`update_lanes`](Self::update_lanes) for a lane group whose every character that
    /// passed its checks (`ok`) rests ([`is_resting`](Self::is_resting)): the eye rays of
    /// the base pose, by the same operations the full update makes on such a character (its
    /// deltas are identity and are multiplied in as such), so the same bits, without reading
    /// the deltas or solving anything.
    #[inline(always)]
    pub(super) fn rest_lanes<W: Wide>(
        motions: &mut [&mut GazeMotion],
        chains: &[&GazeChain],
        inputs: &[&GazeInput<'_>],
        ok: &[bool],
        filler: usize,
    ) {
        let n = motions.len();
        let used = |lane: usize| lane < n && ok[lane];
        let pick = |lane: usize| if used(lane) { lane } else { filler };
        let lane_chains: [&GazeChain; MAX_LANES] = std::array::from_fn(|lane| chains[pick(lane)]);
        let lane_bases: [&[Quat]; MAX_LANES] = std::array::from_fn(|lane| inputs[pick(lane)].base);
        let characters: [&CharacterTransform; MAX_LANES] =
            std::array::from_fn(|lane| &inputs[pick(lane)].character);
        let same = spatial::same_chain(&lane_chains);
        let shared_base = same
            && lane_bases
                .iter()
                .all(|base| std::ptr::eq(*base, lane_bases[0]));
        let body: [usize; MAX_LANES] = lane_chains.map(GazeChain::body_count);
        let joints = body.iter().copied().max().unwrap_or(0);
        let heads = heads_by_kinematics::<W>(
            &lane_chains,
            &characters,
            same,
            joints,
            |index| {
                if shared_base {
                    Q4::splat(lane_bases[0][index])
                } else {
                    Q4::gather(|lane| {
                        if index < body[lane] {
                            lane_bases[lane][index]
                        } else {
                            Quat::IDENTITY
                        }
                    })
                }
            },
            // The identity deltas multiplied in, as the full update does.
            |_| Q4::identity(),
        );
        let mut origins = [V3::zero(); 2];
        let mut directions = [V3::zero(); 2];
        for eye in 0..2 {
            let frames = EyeFrames::new(&lane_chains, &lane_bases, &heads, eye);
            origins[eye] = frames.position;
            directions[eye] = frames.direction(Q4::identity());
        }
        eyeless_directions(&lane_chains, &heads, &mut directions);
        for lane in 0..n {
            if ok[lane] {
                motions[lane].set_eye_rays(&origins, &directions, lane);
            }
        }
    }
}
