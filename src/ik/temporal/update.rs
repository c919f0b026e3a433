//! The full update of one lane group, one character per SIMD lane, stage by stage: new
//! targets and the spatial solve, each character's phase and eased fractions `f_P`, the body
//! joints, the eyes, and the phase changes. [`UpdateGroups`] runs a batch through it in
//! lane groups of one width.

// The lockstep loops index several per-lane and per-joint arrays with one index.
#![allow(clippy::needless_range_loop)]

use glam::{Quat, Vec3A};

use super::config::{GazeConfig, GazeTiming, MotionStyle};
use super::input::GazeInput;
use super::pose::{eyeless_directions, heads_by_kinematics, settle};
use super::{GazeMotion, GazePhase};
use crate::ik::chain::{GazeChain, JointGroup, MAX_BODY_JOINTS};
use crate::ik::rotation::angle_between;
use crate::ik::spatial::{self, BodyLane, EyeFrames, Frames, Prepared, SpatialSolution, TurnSide};
use crate::ik::CharacterTransform;
use crate::math::lanes::{gather, mask, Mask, MAX_LANES, Q4, V3};
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
        let lanes = Lanes::new(motions.len(), chains, inputs, ok, filler);

        // 1. Lanes with a target: is it a new one? Then the spatial solve of the bodies.
        let mut goals = [Q4::<W>::identity(); MAX_BODY_JOINTS];
        let (new_target, solved, solved_heads) = solve_targets(
            motions, chains, inputs, &lanes, timing, prepared, &mut goals,
        );

        // 2. Each character's phase, timing and eased fractions.
        let progress = advance_phases(
            motions,
            chains,
            inputs,
            randoms,
            ok,
            timing,
            &new_target,
            &solved,
            &goals,
        );
        let blending = mask(|lane| progress.moving[lane] || progress.returning[lane]);
        let moving_mask = mask(|lane| progress.moving[lane]);

        // 3. Body joints.
        let same = spatial::same_chain(&lanes.chains);
        let (heads, mut at_rest) = settle_bodies(
            motions,
            &lanes,
            same,
            &progress,
            blending,
            moving_mask,
            &goals,
            solved_heads,
        );

        // 4. Eyes: vergence from the current head, or back to rest; then the eye rays.
        let (origins, directions) = settle_eyes(
            motions,
            &lanes,
            same,
            &progress,
            blending,
            prepared,
            &heads,
            &mut at_rest,
        );

        // 5. Phase changes, and the rays for debug drawing.
        change_phases(
            motions,
            chains,
            ok,
            &progress,
            at_rest,
            &origins,
            &directions,
        );
    }
}

/// A lane group's characters spread over every SIMD lane: lanes past the group or failing
/// their checks compute a copy of the first good character (`filler`), and their results
/// are dropped.
struct Lanes<'a, 'b> {
    /// How many characters the group has.
    n: usize,
    /// Which of them passed their checks.
    ok: &'a [bool],
    /// Each lane's chain.
    chains: [&'a GazeChain; MAX_LANES],
    /// Each lane's input.
    inputs: [&'a GazeInput<'b>; MAX_LANES],
    /// Each lane's base pose.
    bases: [&'b [Quat]; MAX_LANES],
    /// Each lane's character transform.
    characters: [&'a CharacterTransform; MAX_LANES],
}

impl<'a, 'b> Lanes<'a, 'b> {
    /// The lanes of a group of `n` characters whose first good one is `filler`.
    #[inline(always)]
    fn new(
        n: usize,
        chains: &[&'a GazeChain],
        inputs: &[&'a GazeInput<'b>],
        ok: &'a [bool],
        filler: usize,
    ) -> Lanes<'a, 'b> {
        let used = |lane: usize| lane < n && ok[lane];
        let pick = |lane: usize| if used(lane) { lane } else { filler };
        let lane_chains: [&GazeChain; MAX_LANES] = std::array::from_fn(|lane| chains[pick(lane)]);
        let lane_inputs: [&GazeInput<'_>; MAX_LANES] =
            std::array::from_fn(|lane| inputs[pick(lane)]);
        let lane_bases: [&[Quat]; MAX_LANES] = lane_inputs.map(|input| input.base);
        let characters: [&CharacterTransform; MAX_LANES] =
            lane_inputs.map(|input| &input.character);
        Lanes {
            n,
            ok,
            chains: lane_chains,
            inputs: lane_inputs,
            bases: lane_bases,
            characters,
        }
    }

    /// True if lane `lane` holds one of the group's characters that passed its checks.
    #[inline(always)]
    fn used(&self, lane: usize) -> bool {
        lane < self.n && self.ok[lane]
    }
}

/// Stage 2's findings, per lane: how far each group (eyes, head and neck, spine) is through
/// its motion, how far it may turn this frame, and whether the character turns towards a
/// target or returns to its base motion.
struct Progress {
    /// Each group's fraction `f_P` (or saccadic progress).
    fractions: [[f32; 3]; MAX_LANES],
    /// Each group's largest turn this frame, radians.
    max_steps: [[f32; 3]; MAX_LANES],
    /// Shifting or holding.
    moving: [bool; MAX_LANES],
    /// Returning.
    returning: [bool; MAX_LANES],
}

/// A lane's spatial solution and turn side, `None` without a target.
type Solved = Option<(SpatialSolution, TurnSide)>;

/// Stage 1: for each character with a target, whether it is a new one (none was followed,
/// a different key, or a point that jumped more than [`GazeTiming::restart_distance`]; the
/// turn side is then forgotten), then the spatial solve of the bodies towards the targets.
/// Writes the body goals into `goals`; returns the new-target flags, each lane's solution
/// and turn side, and the heads' frames on their solutions.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn solve_targets<W: Wide>(
    motions: &[&mut GazeMotion],
    chains: &[&GazeChain],
    inputs: &[&GazeInput<'_>],
    lanes: &Lanes<'_, '_>,
    timing: &GazeTiming,
    prepared: &Prepared,
    goals: &mut [Q4<W>; MAX_BODY_JOINTS],
) -> ([bool; MAX_LANES], [Solved; MAX_LANES], Frames<W>) {
    let n = motions.len();
    let ok = lanes.ok;
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
                || request.eye_target.distance(motion.last_eye_target) > timing.restart_distance;
            new_target[lane] = !active || request.target_key != motion.target_key || jumped;
            if new_target[lane] {
                // The turn side is remembered while following one target, not across
                // targets: a new target behind is reached the short way.
                sides[lane] = TurnSide::UNDECIDED;
            }
        }
    }
    let (solved, solved_heads) = spatial::solve_bodies(
        prepared,
        std::array::from_fn(|lane| {
            if !lanes.used(lane) {
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
        goals,
    );
    (new_target, solved, solved_heads)
}

/// Stage 2: each character's phase and timing. A new target or a switch of side starts a
/// shift from the current pose (`t_a` from `θ_head`, or the saccadic durations); a dropped
/// target starts a return over `t_d`, drawn from the character's stream; otherwise time goes
/// on. Then each group's fraction and speed cap.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn advance_phases<W: Wide>(
    motions: &mut [&mut GazeMotion],
    chains: &[&GazeChain],
    inputs: &[&GazeInput<'_>],
    randoms: &mut [&mut Random],
    ok: &[bool],
    timing: &GazeTiming,
    new_target: &[bool; MAX_LANES],
    solved: &[Solved; MAX_LANES],
    goals: &[Q4<W>; MAX_BODY_JOINTS],
) -> Progress {
    let n = motions.len();
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
                        MotionStyle::MainSequence => {
                            let activation =
                                timing.activation_time(head_angle, request.interest_ratio);
                            motion.saccade_duration = match motion.eye_angle_to(request.eye_target)
                            {
                                Some(amplitude) => timing.main_sequence_duration(amplitude),
                                None => 0.5 * activation,
                            };
                            activation
                        }
                        MotionStyle::Saccadic => {
                            timing.head_base_duration + timing.head_duration_per_radian * head_angle
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
        fractions[lane] = motion.group_fractions(timing);
        max_steps[lane] = timing.max_joint_speed.map(|speed| speed * input.dt);
        if motion.style == MotionStyle::MainSequence
            && motion.phase == GazePhase::Shifting
            && motion.elapsed < motion.saccade_duration
        {
            let eyes = &mut max_steps[lane][JointGroup::Eyes.index()];
            *eyes = eyes.min(timing.main_sequence_peak_velocity * input.dt);
        }
        moving[lane] = matches!(motion.phase, GazePhase::Shifting | GazePhase::Holding);
        returning[lane] = motion.phase == GazePhase::Returning;
    }
    Progress {
        fractions,
        max_steps,
        moving,
        returning,
    }
}

/// Stage 3: the body joints, bottom to top. Each goes from its start pose towards its share
/// of the spatial solution (or back to identity) by its group's fraction, within its speed
/// cap and limits ([`settle`]). Returns the heads' frames — the spatial solve's when every
/// character ends on its solution, else by forward kinematics of the new pose — and where
/// the joints rest (identity).
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn settle_bodies<W: Wide>(
    motions: &mut [&mut GazeMotion],
    lanes: &Lanes<'_, '_>,
    same: bool,
    progress: &Progress,
    blending: Mask<W>,
    moving_mask: Mask<W>,
    goals: &[Q4<W>; MAX_BODY_JOINTS],
    solved_heads: Frames<W>,
) -> (Frames<W>, Mask<W>) {
    let n = motions.len();
    let Progress {
        fractions,
        max_steps,
        moving,
        ..
    } = progress;
    let body: [usize; MAX_LANES] = lanes.chains.map(GazeChain::body_count);
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
            if lanes.used(lane) && index < body[lane] {
                motions[lane].deltas[index]
            } else {
                Quat::IDENTITY
            }
        });
        let groups: [usize; MAX_LANES] = std::array::from_fn(|lane| {
            if index < body[lane] {
                spatial::group_of(lanes.chains[lane], index).index()
            } else {
                0
            }
        });
        let start = || {
            Q4::unpack(|lane| {
                if lanes.used(lane) && index < body[lane] {
                    motions[lane].start[index]
                } else {
                    PackedQuat::IDENTITY
                }
            })
        };
        let goal = Q4::select(moving_mask, goals[index], Q4::identity());
        let (settled, rest) = settle(
            &lanes.chains,
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
    let all_on_goal = (0..W::LANES).all(|lane| !lanes.used(lane) || on_goal.test(lane));
    let heads = if all_on_goal {
        solved_heads
    } else {
        heads_by_kinematics(
            &lanes.chains,
            &lanes.characters,
            same,
            joints,
            |index| {
                Q4::gather(|lane| {
                    if index < body[lane] {
                        lanes.bases[lane][index]
                    } else {
                        Quat::IDENTITY
                    }
                })
            },
            |index| {
                Q4::gather(|lane| {
                    if lanes.used(lane) && index < body[lane] {
                        motions[lane].deltas[index]
                    } else {
                        Quat::IDENTITY
                    }
                })
            },
        )
    };
    (heads, at_rest)
}

/// Stage 4: the eyes. Each goes from its start pose towards its vergence on the eye target
/// from the current head (or back to identity) by the eyes' fraction, within its speed cap
/// and limits; `at_rest` is narrowed to where they rest. Returns the eye rays (origins and
/// directions, left and right).
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn settle_eyes<W: Wide>(
    motions: &mut [&mut GazeMotion],
    lanes: &Lanes<'_, '_>,
    same: bool,
    progress: &Progress,
    blending: Mask<W>,
    prepared: &Prepared,
    heads: &Frames<W>,
    at_rest: &mut Mask<W>,
) -> ([V3<W>; 2], [V3<W>; 2]) {
    let n = motions.len();
    let Progress {
        fractions,
        max_steps,
        moving,
        ..
    } = progress;
    let eye_fractions = gather(|lane| fractions[lane][JointGroup::Eyes.index()]);
    let eye_steps = gather(|lane| max_steps[lane][JointGroup::Eyes.index()]);
    let eye_target = V3::gather(|lane| match &lanes.inputs[lane].request {
        Some(request) => request.eye_target.into(),
        None => Vec3A::ZERO,
    });
    let side_sign = gather(|lane| {
        if lanes.used(lane) && motions[lane].side.sign() < 0 {
            -1.0
        } else {
            1.0
        }
    });
    let mut origins = [V3::zero(); 2];
    let mut directions = [V3::zero(); 2];
    for eye in 0..2 {
        let frames = EyeFrames::new(&lanes.chains, &lanes.bases, heads, eye);
        let mut delta = Q4::gather(|lane| {
            if lanes.used(lane) && lanes.chains[lane].has_eyes() {
                motions[lane].deltas[frames.index[lane]]
            } else {
                Quat::IDENTITY
            }
        });
        let blend = blending & frames.has_eyes;
        if blend.any() {
            let goal = frames.goal(&lanes.chains, prepared, eye_target, side_sign);
            let goal = Q4::select(mask(|lane| moving[lane]), goal, Q4::identity());
            let start = || {
                Q4::unpack(|lane| {
                    if lanes.used(lane) && lanes.chains[lane].has_eyes() {
                        motions[lane].start[frames.index[lane]]
                    } else {
                        PackedQuat::IDENTITY
                    }
                })
            };
            let (settled, rest) = settle(
                &lanes.chains,
                same,
                frames.index,
                start,
                delta,
                goal,
                eye_fractions,
                eye_steps,
            );
            delta = Q4::select(blend, settled, delta);
            *at_rest &= !blend | rest;
            for lane in 0..n {
                if blend.test(lane) {
                    motions[lane].deltas[frames.index[lane]] = delta.lane(lane);
                }
            }
        }
        origins[eye] = frames.position;
        directions[eye] = frames.direction(delta);
    }
    eyeless_directions(&lanes.chains, heads, &mut directions);
    (origins, directions)
}

/// Stage 5: phase changes — a shift whose slowest group (the spine, else the head and
/// neck) is done holds; a return done and at rest goes idle and forgets its turn side — and
/// each character keeps its eye rays for debug drawing.
#[inline(always)]
fn change_phases<W: Wide>(
    motions: &mut [&mut GazeMotion],
    chains: &[&GazeChain],
    ok: &[bool],
    progress: &Progress,
    at_rest: Mask<W>,
    origins: &[V3<W>; 2],
    directions: &[V3<W>; 2],
) {
    let n = motions.len();
    for lane in 0..n {
        if !ok[lane] {
            continue;
        }
        let motion = &mut *motions[lane];
        let chain = chains[lane];
        if progress.moving[lane] && motion.phase == GazePhase::Shifting {
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
        if progress.returning[lane]
            && at_rest.test(lane)
            && motion.elapsed >= motion.deactivation_time
        {
            motion.phase = GazePhase::Idle;
            motion.side = TurnSide::UNDECIDED;
        }
        motion.set_eye_rays(origins, directions, lane);
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
