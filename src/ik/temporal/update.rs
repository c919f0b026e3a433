//! The full update of one lane group, one character per SIMD lane, stage by stage: new
//! targets and the spatial solve, each character's phase and eased fractions `f_P`, the body
//! joints, the eyes, and the phase changes. [`UpdateGroups`] runs a batch through it in
//! lane groups of one width.

// The lockstep loops index several per-lane and per-joint arrays with one index.
#![allow(clippy::needless_range_loop)]

use glam::{Quat, Vec3A};

use super::config::{GazeConfig, MotionStyle};
use super::input::GazeInput;
use super::pose::{eyeless_directions, heads_by_kinematics, settle};
use super::{GazeMotion, GazePhase};
use crate::ik::chain::{GazeChain, JointGroup, MAX_BODY_JOINTS};
use crate::ik::lanes::{gather, mask, Mask, MAX_LANES, Q4, V3};
use crate::ik::rotation::angle_between;
use crate::ik::spatial::{self, BodyLane, EyeFrames, Prepared, TurnSide};
use crate::ik::CharacterTransform;
use crate::math::packed::PackedQuat;
use crate::math::random::Random;
use crate::math::wide::{LaneJob, Wide};

/// [`GazeMotion::update_batch`]'s characters, checked, updated in lane groups of the width
/// [`run_widest`](crate::math::wide::run_widest) picks.
pub(super) struct UpdateGroups<'a, 'm, 'r, 'c, 'i, 'b> {
    pub(super) motions: &'a mut [&'m mut GazeMotion],
    pub(super) chains: &'a [&'c GazeChain],
    pub(super) config: &'a GazeConfig,
    pub(super) inputs: &'a [&'i GazeInput<'b>],
    pub(super) randoms: &'a mut [&'r mut Random],
    /// Which characters passed their checks.
    pub(super) ok: &'a [bool],
    pub(super) prepared: &'a Prepared,
}

impl LaneJob for UpdateGroups<'_, '_, '_, '_, '_, '_> {
    type Output = ();

    #[inline(always)]
    fn run<W: Wide>(self) {
        let count = self.motions.len();
        let mut first = 0;
        while first < count {
            let end = count.min(first + W::LANES);
            GazeMotion::update_lanes::<W>(
                &mut self.motions[first..end],
                &self.chains[first..end],
                self.config,
                &self.inputs[first..end],
                &mut self.randoms[first..end],
                &self.ok[first..end],
                self.prepared,
            );
            first = end;
        }
    }
}

impl GazeMotion {
    /// [`GazeMotion::update_batch`] for one lane group of at most `W::LANES` characters
    /// (`motions.len()`, and as many chains, inputs, random streams and `ok` flags), whose
    /// checks are done: `ok[i]` says whether character `i` passed them.
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    fn update_lanes<W: Wide>(
        motions: &mut [&mut GazeMotion],
        chains: &[&GazeChain],
        config: &GazeConfig,
        inputs: &[&GazeInput<'_>],
        randoms: &mut [&mut Random],
        ok: &[bool],
        prepared: &Prepared,
    ) {
        let Some(filler) = (0..motions.len()).find(|lane| ok[*lane]) else {
            return;
        };
        if (0..motions.len())
            .all(|lane| !ok[lane] || motions[lane].is_resting(inputs[lane].request.as_ref()))
        {
            Self::rest_lanes::<W>(motions, chains, inputs, ok, filler);
            return;
        }
        let timing = &config.timing;
        let n = motions.len();
        // Every SIMD lane gets a character: lanes past N or failing their checks compute a
        // copy of the first good one, and their results are dropped.
        let used = |lane: usize| lane < n && ok[lane];
        let pick = |lane: usize| if used(lane) { lane } else { filler };
        let lane_chains: [&GazeChain; MAX_LANES] = std::array::from_fn(|lane| chains[pick(lane)]);
        let lane_inputs: [&GazeInput<'_>; MAX_LANES] =
            std::array::from_fn(|lane| inputs[pick(lane)]);
        let lane_bases: [&[Quat]; MAX_LANES] = lane_inputs.map(|input| input.base);
        let characters: [&CharacterTransform; MAX_LANES] =
            lane_inputs.map(|input| &input.character);

        // 1. Lanes with a target: is it a new one? Then the spatial solve of the bodies.
        let mut new_target = [false; MAX_LANES];
        let mut sides = [TurnSide::UNDECIDED; MAX_LANES];
        for lane in 0..n {
            sides[lane] = motions[lane].side;
        }
        for lane in 0..n {
            if let (true, Some(request)) = (ok[lane], &inputs[lane].request) {
                let motion = &*motions[lane];
                let active = matches!(motion.phase, GazePhase::Shifting | GazePhase::Holding);
                let jumped = request.head_target.distance(motion.last_head_target)
                    > timing.restart_distance
                    || request.eye_target.distance(motion.last_eye_target)
                        > timing.restart_distance;
                new_target[lane] = !active || request.target_key != motion.target_key || jumped;
                if new_target[lane] {
                    // The turn side is remembered while following one target, not across
                    // targets: a new target behind is reached the short way.
                    sides[lane] = TurnSide::UNDECIDED;
                }
            }
        }
        let mut goals = [Q4::<W>::identity(); MAX_BODY_JOINTS];
        let (solved, solved_heads) = spatial::solve_bodies(
            prepared,
            std::array::from_fn(|lane| {
                if !used(lane) {
                    return None;
                }
                inputs[lane].request.map(|request| BodyLane {
                    chain: chains[lane],
                    character: &inputs[lane].character,
                    base: inputs[lane].base,
                    head_target: request.head_target,
                    side: sides[lane],
                })
            }),
            &mut goals,
        );

        // 2. Each character's phase, timing and eased fractions.
        let mut fractions = [[0.0f32; 3]; MAX_LANES];
        let mut max_steps = [[0.0f32; 3]; MAX_LANES];
        let mut moving = [false; MAX_LANES];
        let mut returning = [false; MAX_LANES];
        for lane in 0..n {
            if !ok[lane] {
                continue;
            }
            let motion = &mut *motions[lane];
            let input = inputs[lane];
            match (&input.request, &solved[lane]) {
                (Some(request), Some((solution, side))) => {
                    motion.side = *side;
                    if new_target[lane] || solution.side_switched {
                        motion.remember_start();
                        motion.elapsed = 0.0;
                        let body = chains[lane].body_count();
                        let head_angle = head_turn(
                            &input.base[..body],
                            &motion.deltas[..body],
                            goals[..body].iter().map(|goal| goal.lane(lane)),
                        );
                        motion.style = request.style;
                        motion.saccade_duration = timing.saccade_duration;
                        motion.activation_time = match request.style {
                            MotionStyle::Eased => {
                                timing.activation_time(head_angle, request.interest_ratio)
                            }
                            MotionStyle::Saccadic => {
                                timing.head_base_duration
                                    + timing.head_duration_per_radian * head_angle
                            }
                        };
                        motion.phase = GazePhase::Shifting;
                    } else {
                        motion.elapsed += input.dt;
                    }
                    motion.target_key = request.target_key;
                    motion.last_head_target = request.head_target;
                    motion.last_eye_target = request.eye_target;
                }
                _ => match motion.phase {
                    GazePhase::Shifting | GazePhase::Holding => {
                        motion.remember_start();
                        motion.elapsed = 0.0;
                        motion.deactivation_time = randoms[lane]
                            .range(timing.min_deactivation_time, timing.max_deactivation_time);
                        motion.phase = GazePhase::Returning;
                    }
                    GazePhase::Returning => motion.elapsed += input.dt,
                    GazePhase::Idle => {}
                },
            }
            fractions[lane] = motion.group_fractions(&timing.ease);
            max_steps[lane] = timing.max_joint_speed.map(|speed| speed * input.dt);
            moving[lane] = matches!(motion.phase, GazePhase::Shifting | GazePhase::Holding);
            returning[lane] = motion.phase == GazePhase::Returning;
        }
        let blending = mask(|lane| moving[lane] || returning[lane]);
        let moving_mask = mask(|lane| moving[lane]);

        // 3. Body joints.
        let same = spatial::same_chain(&lane_chains);
        let body: [usize; MAX_LANES] = lane_chains.map(GazeChain::body_count);
        let joints = body.iter().copied().max().unwrap_or(0);
        let mut at_rest = Mask::splat(true);
        // Lanes whose every body joint ends exactly on the spatial solution.
        let mut on_goal = mask(|lane| moving[lane]);
        for index in 0..joints {
            let in_chain = mask(|lane| index < body[lane]);
            let blend = blending & in_chain;
            if !blend.any() {
                continue;
            }
            let current = Q4::gather(|lane| {
                if used(lane) && index < body[lane] {
                    motions[lane].deltas[index]
                } else {
                    Quat::IDENTITY
                }
            });
            let groups: [usize; MAX_LANES] = std::array::from_fn(|lane| {
                if index < body[lane] {
                    spatial::group_of(lane_chains[lane], index).index()
                } else {
                    0
                }
            });
            let start = || {
                Q4::unpack(|lane| {
                    if used(lane) && index < body[lane] {
                        motions[lane].start[index]
                    } else {
                        PackedQuat::IDENTITY
                    }
                })
            };
            let goal = Q4::select(moving_mask, goals[index], Q4::identity());
            let (settled, rest) = settle(
                &lane_chains,
                same,
                [index; MAX_LANES],
                start,
                current,
                goal,
                gather(|lane| fractions[lane][groups[lane]]),
                gather(|lane| max_steps[lane][groups[lane]]),
            );
            at_rest &= !blend | rest;
            on_goal &= !in_chain | settled.equals(goal);
            for lane in 0..n {
                if blend.test(lane) {
                    motions[lane].deltas[index] = settled.lane(lane);
                }
            }
        }
        // The heads' frames: the spatial solve's when every character is on its solution
        // (following its target), else the forward kinematics of the new pose.
        let all_on_goal = (0..W::LANES).all(|lane| !used(lane) || on_goal.test(lane));
        let heads = if all_on_goal {
            solved_heads
        } else {
            heads_by_kinematics(
                &lane_chains,
                &characters,
                same,
                joints,
                |index| {
                    Q4::gather(|lane| {
                        if index < body[lane] {
                            lane_bases[lane][index]
                        } else {
                            Quat::IDENTITY
                        }
                    })
                },
                |index| {
                    Q4::gather(|lane| {
                        if used(lane) && index < body[lane] {
                            motions[lane].deltas[index]
                        } else {
                            Quat::IDENTITY
                        }
                    })
                },
            )
        };

        // 4. Eyes: vergence from the current head, or back to rest; then the eye rays.
        let eye_fractions = gather(|lane| fractions[lane][JointGroup::Eyes.index()]);
        let eye_steps = gather(|lane| max_steps[lane][JointGroup::Eyes.index()]);
        let eye_target = V3::gather(|lane| match &lane_inputs[lane].request {
            Some(request) => request.eye_target.into(),
            None => Vec3A::ZERO,
        });
        let side_sign = gather(|lane| {
            if used(lane) && motions[lane].side.sign() < 0 {
                -1.0
            } else {
                1.0
            }
        });
        let mut origins = [V3::zero(); 2];
        let mut directions = [V3::zero(); 2];
        for eye in 0..2 {
            let frames = EyeFrames::new(&lane_chains, &lane_bases, &heads, eye);
            let mut delta = Q4::gather(|lane| {
                if used(lane) && lane_chains[lane].has_eyes() {
                    motions[lane].deltas[frames.index[lane]]
                } else {
                    Quat::IDENTITY
                }
            });
            let blend = blending & frames.has_eyes;
            if blend.any() {
                let goal = frames.goal(&lane_chains, prepared, eye_target, side_sign);
                let goal = Q4::select(mask(|lane| moving[lane]), goal, Q4::identity());
                let start = || {
                    Q4::unpack(|lane| {
                        if used(lane) && lane_chains[lane].has_eyes() {
                            motions[lane].start[frames.index[lane]]
                        } else {
                            PackedQuat::IDENTITY
                        }
                    })
                };
                let (settled, rest) = settle(
                    &lane_chains,
                    same,
                    frames.index,
                    start,
                    delta,
                    goal,
                    eye_fractions,
                    eye_steps,
                );
                delta = Q4::select(blend, settled, delta);
                at_rest &= !blend | rest;
                for lane in 0..n {
                    if blend.test(lane) {
                        motions[lane].deltas[frames.index[lane]] = delta.lane(lane);
                    }
                }
            }
            origins[eye] = frames.position;
            directions[eye] = frames.direction(delta);
        }
        eyeless_directions(&lane_chains, &heads, &mut directions);

        // 5. Phase changes, and the rays for debug drawing.
        for lane in 0..n {
            if !ok[lane] {
                continue;
            }
            let motion = &mut *motions[lane];
            let chain = chains[lane];
            if moving[lane] && motion.phase == GazePhase::Shifting {
                let durations = motion.group_durations();
                let longest = if chain.spine_count() > 0 {
                    durations[JointGroup::Spine.index()]
                } else {
                    durations[JointGroup::HeadAndNeck.index()]
                };
                if motion.elapsed >= longest {
                    motion.phase = GazePhase::Holding;
                }
            }
            if returning[lane] && at_rest.test(lane) && motion.elapsed >= motion.deactivation_time {
                motion.phase = GazePhase::Idle;
                motion.side = TurnSide::UNDECIDED;
            }
            motion.set_eye_rays(&origins, &directions, lane);
        }
    }
}

/// `θ_head`: the angle of the head's rotation, in the chain root's frame, from the pose
/// `base * from` to the pose `base * to` (body joints).
fn head_turn(base: &[Quat], from: &[Quat], to: impl Iterator<Item = Quat>) -> f32 {
    let mut head_from = Quat::IDENTITY;
    let mut head_to = Quat::IDENTITY;
    for ((base, from), to) in base.iter().zip(from).zip(to) {
        head_from = head_from * *base * *from;
        head_to = head_to * *base * to;
    }
    angle_between(head_from, head_to)
}
