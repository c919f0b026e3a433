//! The per-lane pose steps the full and the resting update share: settling a joint from its
//! start pose towards its goal (the fraction `f_P`, the speed cap, the limits), the heads'
//! frames by forward kinematics, and the rays of chains without eyes.

use crate::ik::chain::GazeChain;
use crate::ik::lanes::interpolate_or;
use crate::ik::rotation::step_toward;
use crate::ik::spatial::{self, Frames, Limits};
use crate::ik::CharacterTransform;
use crate::math::lanes::{mask, Floats, Mask, MAX_LANES, Q4, V3};
use crate::math::wide::Wide;

/// Per lane: the start pose interpolated towards `goal` by `fraction`, at most `max_step`
/// radians from `current`, within the limits of joint `indices[lane]`. Returns the new
/// deltas and where they are exactly identity.
///
/// `start()` unpacks the start pose. A lane whose fraction is still 0 (the frame a shift
/// starts, and any before the ease leaves 0) keeps `current` instead, which is then exactly
/// its start pose: the fraction only grows during a shift, and a fraction of 0 leaves a
/// joint where it is. So a shift starts exactly from where the joints are.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
pub(super) fn settle<W: Wide>(
    chains: &[&GazeChain; MAX_LANES],
    same_chain: bool,
    indices: [usize; MAX_LANES],
    start: impl Fn() -> Q4<W>,
    current: Q4<W>,
    goal: Q4<W>,
    fraction: Floats<W>,
    max_step: Floats<W>,
) -> (Q4<W>, Mask<W>) {
    // Once a group has arrived (f_P = 1), its joints follow the goal, which the spatial
    // solve already clamped: no interpolation, no clamping, unless the speed limit binds.
    let arrived = fraction.cmpge(Floats::one()).all();
    let wanted = if arrived {
        goal
    } else {
        // At a fraction of 0 the joint stays where it is (exactly its start pose).
        interpolate_or(start(), current, goal, fraction)
    };
    // Within the speed limit iff 1 − |current·wanted| ≤ 1 − cos(max/2), which is at least
    // h²/2 − h⁴/24 for h = max/2: a test without trigonometry; the rare lanes over the limit
    // are stepped one by one.
    let dot = current.dot(wanted).abs().min(Floats::one());
    let half = 0.5 * max_step;
    let half_squared = half * half;
    let fast = (1.0 - dot).cmple(half_squared * (0.5 - half_squared / 24.0));
    let stepped = if fast.all() {
        wanted
    } else {
        let slow = Q4::gather(|lane| {
            step_toward(current.lane(lane), wanted.lane(lane), max_step.lane(lane))
        });
        Q4::select(fast, wanted, slow)
    };
    if arrived && fast.all() {
        return (stepped, stepped.is_identity());
    }
    let limits = Limits::of_joints(chains, same_chain, indices);
    let (clamped, _) = limits.clamp(stepped);
    (clamped, clamped.is_identity())
}

/// The heads' world frames by forward kinematics from each lane's chain root, joint `index`
/// turning by `base(index)` then `delta(index)` (past a lane's body joints, identity).
/// Multiplied as in the spatial solve, (parent · base) · delta, so that both ways give the
/// same values and a character's result never depends on its batch. `same_chain`: every
/// lane has the same chain.
#[inline(always)]
pub(super) fn heads_by_kinematics<W: Wide>(
    chains: &[&GazeChain; MAX_LANES],
    characters: &[&CharacterTransform; MAX_LANES],
    same_chain: bool,
    joints: usize,
    base: impl Fn(usize) -> Q4<W>,
    delta: impl Fn(usize) -> Q4<W>,
) -> Frames<W> {
    let mut heads = Frames::roots(chains, characters);
    for index in 0..joints {
        let offset = spatial::offsets(chains, same_chain, index);
        heads.position = heads.position.add(heads.rotation.rotate(offset));
        heads.rotation = heads.rotation.mul(base(index)).mul(delta(index));
    }
    heads
}

/// Chains without eyes: both rays of such a lane are the head's global eye, its forward
/// direction carried by the head's frame.
#[inline(always)]
pub(super) fn eyeless_directions<W: Wide>(
    chains: &[&GazeChain; MAX_LANES],
    heads: &Frames<W>,
    directions: &mut [V3<W>; 2],
) {
    let eyeless = !mask(|lane| chains[lane].has_eyes());
    if eyeless.any() {
        let forward = heads
            .rotation
            .rotate(V3::gather(|lane| chains[lane].eye_forward().into()));
        for direction in directions {
            *direction = V3::select(eyeless, forward, *direction);
        }
    }
}
