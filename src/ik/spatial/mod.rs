//! Spatial resolution (Grillon & Thalmann 2009): for one posture, the displacement map —
//! the delta rotation of every chain joint — that turns the character's gaze to a target.
//!
//! **Global eye.** The mid-point of the eyes, looking along the head's forward axis
//! ([`GazeChain::eye_forward`]); the head joint itself if the chain has no eyes.
//! `q_l` is the shortest rotation from the global eye's forward to the direction from the
//! global eye to the target, and `θ` its angle, both taken in the base posture.
//!
//! **Recruitment** by `θ` ([`RecruitmentBands`], defaults 15° and 30°): `θ ≤ 15°` moves the
//! eyes only; `15° < θ ≤ 30°` the eyes, head and cervicals (head and cervicals take
//! `θ − 15°`, no spine joint moves); beyond, the spine takes `θ − 30°`, head and cervicals
//! 15° and the eyes the last 15°. A chain without eyes gives their band to the head and
//! cervicals (recruited from 0°).
//!
//! **Shares.** Within a group of `n` joints (numbered `i = 1…n` bottom to top) the share
//! decreases up the chain following the paper's `c_i = (n − i)·2/(n(n − 1))`. As printed,
//! that formula gives the top joint 0 and is 0/0 for `n = 1`: in the paper it runs over the
//! whole chain, and its last, zero, share is the eyes', which take the rest by vergence.
//! Within a group we therefore evaluate it with the group plus the joint above it and drop
//! that joint's zero: `c_i = 2(n + 1 − i)/(n(n + 1))` — sums to 1, decreases linearly up the
//! chain, and is 1 for `n = 1`.
//!
//! **Remaining rotation.** Bottom to top, each joint takes its share of what *remains* of its
//! group's rotation, recomputed after the joints below it moved: the remaining rotation from
//! the global eye's current forward to the target, less the bands reserved for the groups
//! above, of which joint `i` takes `c_i / Σ_{j ≥ i} c_j = 2/(n + 2 − i)` (the group's top joint
//! takes all that is left). Moving a joint rotates the global eye rigidly about that joint,
//! so the forward kinematics are updated incrementally: O(n), no allocation. Each joint's
//! delta is clamped to its [`JointLimits`]; what a joint cannot take stays in the remaining
//! rotation and passes up the chain. Finally each eye rotates onto its own target
//! (vergence), within its limits.
//!
//! **Two targets.** The body (spine, cervicals, head) aims at `head_target`, the eyes
//! converge on `eye_target`; the crowd model passes the same point twice.
//!
//! **Degenerate targets.**
//! - *Behind the character*: the shortest rotation flips side as the target crosses straight
//!   behind. A [`TurnSide`] remembered between frames gives hysteresis: within
//!   [`SpatialConfig::behind_hysteresis`] of straight behind (measured about the head's up
//!   axis), a target on the other side is aimed at as if it were
//!   [`SpatialConfig::behind_clearance`] short of straight behind on the remembered side, so
//!   the character keeps turning the same way (the zone is oriented by the head's up axis in
//!   the base posture). The side changes only once the target is
//!   clearly on the other side; the solution then jumps, which [`SpatialSolution::side_switched`]
//!   reports so the temporal layer restarts a smooth shift. A new character with a target
//!   exactly behind turns left (counter-clockwise, like headings).
//! - *Straight above*: the shortest rotation is well defined (a pitch); limits stop it.
//! - *At the eye*: closer than [`SpatialConfig::near_distance`] the gaze rotation fades out
//!   smoothly (smoothstep of the distance), so a target at the eye itself asks for no
//!   rotation and never produces a NaN.
//!
//! **Output**: the delta local rotation of each chain joint; the final local rotation is
//! `base * delta` (glam's product: the delta acts in the joint's own frame, after its base
//! rotation).
//!
//! **Cost.** No trigonometry in the common case: rotations are kept as the cosine and sine of
//! their half-angle, the fractional turn is Kapoulkine's corrected nlerp (within about 10⁻³ of
//! the angle: the joints above correct it, the eyes end exactly on target), and clamping to
//! the limits is a few multiplications. The solver runs a lane group of characters at a time,
//! one per SIMD lane: 16 where the processor has AVX-512F, 8 with AVX, else 4 (the same bits
//! at every width; [`solve`] is the one-character entry, at 4 lanes; the crowd goes through
//! [`crate::ik::GazeMotion::update_batch`]).
//!
//! **Files.** `config.rs`: the settings and the constants prepared from them; `frames.rs`:
//! world frames by forward kinematics and the global eye; `behind.rs`: the [`TurnSide`] and
//! the behind-the-character rule; `turn.rs`: `q_l` as the cosine and sine of `θ/2`, and its
//! fractions; `limits.rs`: joint limits per lane; `body.rs`: the body joints' solve
//! (recruitment, shares, remaining rotation); `eyes.rs`: the eyes' vergence and rays;
//! `entry.rs`: the one-character entry points and the input checks.
//!
//! [`GazeChain::eye_forward`]: crate::ik::GazeChain::eye_forward
//! [`JointLimits`]: crate::ik::JointLimits

mod behind;
mod body;
mod config;
mod entry;
mod eyes;
mod frames;
mod limits;
mod turn;

use glam::Quat;

use super::chain::{GazeChain, JointGroup, MAX_CHAIN_JOINTS};

pub use behind::TurnSide;
pub use body::SpatialSolution;
pub(crate) use body::{solve_bodies, BodyLane};
pub(crate) use config::Prepared;
pub use config::{RecruitmentBands, SpatialConfig};
pub(crate) use entry::check_pose;
pub use entry::{eye_rays, solve};
pub(crate) use eyes::EyeFrames;
pub use eyes::EyeRays;
pub(crate) use frames::{offsets, same_chain, Frames};
pub(crate) use limits::Limits;

/// The group of joint `index` (a helper for per-group timing).
#[inline]
pub(crate) fn group_of(chain: &GazeChain, index: usize) -> JointGroup {
    chain.joints()[index].role.group()
}

/// Deltas all identity, as many as the largest chain.
pub(crate) const IDENTITY_DELTAS: [Quat; MAX_CHAIN_JOINTS] = [Quat::IDENTITY; MAX_CHAIN_JOINTS];

#[cfg(test)]
mod tests;
