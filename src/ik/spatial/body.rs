//! The spatial solve of the body joints (spine, cervicals, head) of a lane group of
//! characters: `q_l` and `θ` in the base posture, recruitment by the bands, and each joint's
//! share `c_i` of what remains of its group's rotation, bottom to top.

// The lockstep loops index several per-lane and per-joint arrays with one index.
#![allow(clippy::needless_range_loop)]

use glam::{Quat, Vec3};

use super::behind::{behind_adjusted, update_side, TurnSide};
use super::config::Prepared;
use super::frames::{eye_middle, offsets, same_chain, Frames};
use super::limits::{turn_joint, Limits};
use super::turn::gaze_rotation;
use crate::ik::chain::{GazeChain, MAX_BODY_JOINTS};
use crate::ik::CharacterTransform;
use crate::math::lanes::{gather, mask, Floats, Mask, MAX_LANES, Q4, V3};
use crate::math::wide::Wide;

/// What a spatial solve found besides the deltas.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SpatialSolution {
    /// `θ`: the angle (radians) of `q_l`, the rotation the global eye needs in the base
    /// posture (after the behind and near-target rules).
    pub gaze_angle: f32,
    /// True if the remembered [`TurnSide`] changed while the target was behind: the solution
    /// jumped from one side to the other.
    pub side_switched: bool,
}
/// One character's part in a body solve.
#[derive(Debug, Clone, Copy)]
pub(crate) struct BodyLane<'a> {
    pub(crate) chain: &'a GazeChain,
    pub(crate) character: &'a CharacterTransform,
    pub(crate) base: &'a [Quat],
    pub(crate) head_target: Vec3,
    pub(crate) side: TurnSide,
}
/// Each lane's base rotation of joint `index` (identity past the lane's body joints, which
/// number `body[lane]`); `shared` if every lane has the same base pose.
#[inline(always)]
fn base_rotations<W: Wide>(
    lane: &[BodyLane<'_>; MAX_LANES],
    body: &[usize; MAX_LANES],
    shared: bool,
    index: usize,
) -> Q4<W> {
    if shared {
        return Q4::splat(lane[0].base[index]);
    }
    Q4::gather(|i| {
        if index < body[i] {
            lane[i].base[index]
        } else {
            Quat::IDENTITY
        }
    })
}

/// The spatial solve of the body joints (spine, cervicals, head) of up to `W::LANES`
/// characters,
/// one per lane, each towards its `head_target`: writes the deltas that are not identity
/// into `goals[joint]` (per lane; they come in as identity), and returns each lane's
/// solution and turn side, and the heads' final world frames. `None` lanes are skipped.
/// Inputs are assumed checked.
#[inline(always)]
pub(crate) fn solve_bodies<W: Wide>(
    prepared: &Prepared,
    lanes: [Option<BodyLane<'_>>; MAX_LANES],
    goals: &mut [Q4<W>; MAX_BODY_JOINTS],
) -> ([Option<(SpatialSolution, TurnSide)>; MAX_LANES], Frames<W>) {
    let Some(filler) = lanes.iter().flatten().next().copied() else {
        return (
            [None; MAX_LANES],
            Frames {
                position: V3::zero(),
                rotation: Q4::identity(),
            },
        );
    };
    let lane: [BodyLane<'_>; MAX_LANES] = std::array::from_fn(|i| lanes[i].unwrap_or(filler));
    let chains: [&GazeChain; MAX_LANES] = lane.map(|l| l.chain);
    let characters: [&CharacterTransform; MAX_LANES] = lane.map(|l| l.character);
    let same = same_chain(&chains);
    let body: [usize; MAX_LANES] = chains.map(GazeChain::body_count);
    let joints = body.iter().copied().max().unwrap_or(0);
    let shared_base = same && lane.iter().all(|l| std::ptr::eq(l.base, lane[0].base));
    // Multiplying by an identity base rotation changes no bit: skipped when every lane shares
    // one base pose and this joint's is identity (a crowd at rest).
    let identity_base = |index: usize| shared_base && lane[0].base[index] == Quat::IDENTITY;
    // The global eye in the base posture.
    let roots = Frames::roots(&chains, &characters);
    let spine_count = chains[0].spine_count();
    // The base posture's head frame, and its frame above the spine (where the solve starts
    // if no spine joint moves).
    let mut frame = roots;
    let mut above_spine = roots;
    for index in 0..joints {
        if identity_base(index) {
            frame.position = frame
                .position
                .add(frame.rotation.rotate(offsets(&chains, same, index)));
        } else {
            frame.descend(
                offsets(&chains, same, index),
                base_rotations(&lane, &body, shared_base, index),
            );
        }
        if index + 1 == spine_count {
            above_spine = frame;
        }
    }
    let base_head = frame;

    let mut eye = frame
        .position
        .add(frame.rotation.rotate(V3::gather(|i| eye_middle(chains[i]))));
    let mut forward = frame
        .rotation
        .rotate(V3::gather(|i| chains[i].eye_forward().into()));
    let up = frame
        .rotation
        .rotate(V3::gather(|i| chains[i].eye_up().into()));
    // q_l, θ and the turn side.
    let target = V3::gather(|i| lane[i].head_target.into());
    let to_target = target.sub(eye);
    let mut sides = lane.map(|l| l.side);
    let mut switched = [false; MAX_LANES];
    for i in 0..W::LANES {
        if lanes[i].is_some() {
            switched[i] = update_side(
                to_target.lane(i),
                forward.lane(i),
                up.lane(i),
                &mut sides[i],
                prepared,
            );
        }
    }
    let side_sign = gather(|i| sides[i].resolved());
    let aimed = behind_adjusted(to_target, forward, up, side_sign, prepared);
    let first = gaze_rotation(forward, aimed, up.scale(side_sign), prepared);
    // Recruitment and the angle each group leaves to the groups above it.
    let has_eyes = mask(|i| chains[i].has_eyes());
    let (eyes_only_cos, eyes_only_sin) = prepared.eyes_only_half;
    let (spine_reserve_cos, spine_reserve_sin) = prepared.eyes_head_and_neck_half;
    let head_recruited = !has_eyes | first.cos.cmplt(Floats::splat(eyes_only_cos));
    let spine_recruited = first.cos.cmplt(Floats::splat(spine_reserve_cos));
    let head_reserve_cos = Floats::select(has_eyes, Floats::splat(eyes_only_cos), Floats::one());
    let head_reserve_sin = Floats::select(has_eyes, Floats::splat(eyes_only_sin), Floats::zero());

    // Joints below the first that may move keep their base frames: start above them.
    let (first_joint, mut frame) = if !(head_recruited | spine_recruited).any() {
        (joints, base_head)
    } else if same && !spine_recruited.any() {
        (spine_count, above_spine)
    } else {
        (0, roots)
    };
    for index in first_joint..joints {
        frame.position = frame
            .position
            .add(frame.rotation.rotate(offsets(&chains, same, index)));
        let joint_rotation = if identity_base(index) {
            frame.rotation
        } else {
            frame
                .rotation
                .mul(base_rotations(&lane, &body, shared_base, index))
        };
        let in_chain = if same {
            Mask::splat(true)
        } else {
            mask(|i| index < body[i])
        };
        let is_spine = if same {
            Mask::splat(index < spine_count)
        } else {
            mask(|i| index < chains[i].spine_count())
        };
        let recruited = in_chain & ((is_spine & spine_recruited) | (!is_spine & head_recruited));
        let mut delta = Q4::identity();
        if recruited.any() {
            let remaining = if index == 0 {
                first
            } else {
                let aimed = behind_adjusted(target.sub(eye), forward, up, side_sign, prepared);
                gaze_rotation(forward, aimed, up.scale(side_sign), prepared)
            };
            let (budget, some_left) = remaining.less(
                Floats::select(is_spine, Floats::splat(spine_reserve_cos), head_reserve_cos),
                Floats::select(is_spine, Floats::splat(spine_reserve_sin), head_reserve_sin),
            );
            let moves = recruited & some_left;
            if moves.any() {
                // c_i / Σ_{j ≥ i} c_j with c_i ∝ n + 1 − i: 2 / (joints above + 2).
                let above_in_group = |chain: &GazeChain| {
                    if index < chain.spine_count() {
                        (chain.spine_count() - 1 - index) as f32
                    } else {
                        chain.head_index().saturating_sub(index) as f32
                    }
                };
                let share = if same {
                    Floats::splat(2.0 / (above_in_group(chains[0]) + 2.0))
                } else {
                    2.0 / (gather(|i| above_in_group(chains[i])) + 2.0)
                };
                let limits = Limits::of_joints(&chains, same, [index; MAX_LANES]);
                let (turned, turn) = turn_joint(&limits, joint_rotation, budget.fraction(share));
                delta = Q4::select(moves, turned, Q4::identity());
                // The joint turns the global eye rigidly about itself.
                let moved_eye = frame.position.add(turn.rotate(eye.sub(frame.position)));
                eye = V3::select(moves, moved_eye, eye);
                forward = V3::select(moves, turn.rotate(forward), forward);
                // `up` stays the head's up in the base posture: it only orients the behind
                // zone, and the spine and neck mostly turn about it.
                goals[index] = delta;
            }
        }
        frame.rotation = joint_rotation.mul(delta);
    }
    let angles = first.angle();
    let solutions = std::array::from_fn(|i| {
        lanes[i].filter(|_| i < W::LANES).map(|_| {
            (
                SpatialSolution {
                    gaze_angle: angles.lane(i),
                    side_switched: switched[i],
                },
                sides[i],
            )
        })
    });
    (solutions, frame)
}
