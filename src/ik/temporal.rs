//! Temporal resolution (Grillon & Thalmann 2009): a character's gaze motion from frame to
//! frame — when each joint moves, how fast, and how it follows, switches and lets go of a
//! target.
//!
//! **Activation time.** A gaze shift towards a target lasts
//! `t_a = θ_head · S_MAX / (v_m · S_max)` (the paper's equation 10), `θ_head` the angle
//! (radians) of the rotation the head has to make in the chain root's frame (from the pose
//! at the start of the shift to the spatial solution: its own and the spine's share),
//! `v_m` the head speed ([`GazeTiming::head_speed`], 2π rad/s) and `S_max / S_MAX` the
//! target's *interest ratio* ([`GazeRequest::interest_ratio`], 1 for explicit targets).
//! `t_a` is capped at [`GazeTiming::max_activation_time`] (2 s, the paper's bound) and, our
//! addition, at least [`GazeTiming::min_activation_time`] (0.2 s), so that an eyes-only shift
//! (`θ_head = 0`) still lasts a saccade.
//!
//! **Desynchronisation.** The eyes move over `t_a/2`, the head and cervicals over `t_a`, the
//! spine over `2 t_a`, each with the ease `f_P` ([`crate::math::ease::Ease`], exactly 0 at the
//! start and 1 at the end). A body joint's delta goes from its delta at the start of the shift
//! to its share of the spatial solution, *recomputed every frame* (so moving targets are
//! followed) while keeping its eased fraction `f_P`. The eyes go from their start delta to
//! the vergence on the target *from the current, partly turned head*: they reach the target
//! at `t_a/2`, then re-centre as the head and spine catch up.
//!
//! **Restart.** A shift restarts — start = the current pose, progress 0, a new `t_a` — when
//! a new target arrives ([`GazeRequest::target_key`] changes, or a target after none), when
//! a target point moves more than [`GazeTiming::restart_distance`] between two frames, or when
//! the spatial solution switched side behind the character. A new target is reached from
//! wherever the joints are, never through the rest pose. The turn side for targets behind
//! ([`TurnSide`]) is remembered while one target is followed and decided afresh (the short
//! way in the base posture) for each new target.
//!
//! **Deactivation.** With no target, every delta returns to identity (the base motion)
//! over `t_d` drawn from [`GazeTiming::min_deactivation_time`]…
//! [`GazeTiming::max_deactivation_time`] with the caller's seeded random stream: the spine over
//! `t_d`, head and cervicals over `t_d/2`, eyes over `t_d/4`, each eased.
//!
//! **Speed limits and joint limits.** Every frame each joint's change is capped at its
//! group's [`GazeTiming::max_joint_speed`] × dt (a safety net for the rare discontinuities of
//! the spatial solution, such as a target crossing straight above the character), then
//! clamped to its limits, so both hold on every frame.

use glam::{Quat, Vec3};

use super::chain::{GazeChain, JointGroup, MAX_CHAIN_JOINTS};
use super::rotation::{angle_between, interpolate, step_toward};
use super::spatial::{self, BodyProblem, Frame, Prepared, SpatialConfig, TurnSide};
use super::CharacterTransform;
use crate::error::{ensure_all_finite, ensure_finite, Error, Result};
use crate::math::ease::Ease;
use crate::math::random::Random;

/// How many characters [`GazeMotion::update_batch`] best takes at once.
pub const BATCH_LANES: usize = 4;

/// Timing of gaze motions. Seconds, radians, metres.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GazeTiming {
    /// `v_m`, the head velocity of the activation time formula, rad/s. Default 2π (the
    /// paper: half the median maximal head velocity Grossman et al. measured).
    pub head_speed: f32,
    /// Shortest activation time `t_a`, s (our addition: eyes-only shifts last a saccade).
    /// Default 0.2.
    pub min_activation_time: f32,
    /// Longest activation time `t_a`, s. Default 2 (the paper).
    pub max_activation_time: f32,
    /// A target point moving more than this between two frames restarts the shift, metres.
    /// Default 0.5.
    pub restart_distance: f32,
    /// Shortest deactivation time `t_d`, s. Default 0.5.
    pub min_deactivation_time: f32,
    /// Longest deactivation time `t_d`, s. Default 1.5.
    pub max_deactivation_time: f32,
    /// Fastest any joint of a group may turn, rad/s, indexed by [`JointGroup::index`]
    /// (eyes, head and cervicals, spine). Defaults 900°/s (saccade velocities saturate
    /// there), 720°/s (4π, the median maximal head velocity of Grossman et al.), 360°/s.
    pub max_joint_speed: [f32; 3],
    /// The ease `f_P`.
    pub ease: Ease,
}

impl Default for GazeTiming {
    fn default() -> Self {
        GazeTiming {
            head_speed: std::f32::consts::TAU,
            min_activation_time: 0.2,
            max_activation_time: 2.0,
            restart_distance: 0.5,
            min_deactivation_time: 0.5,
            max_deactivation_time: 1.5,
            max_joint_speed: [
                900f32.to_radians(),
                720f32.to_radians(),
                360f32.to_radians(),
            ],
            ease: Ease::default(),
        }
    }
}

impl GazeTiming {
    /// Checks the ranges: everything finite, `head_speed > 0`,
    /// `0 < min_activation_time ≤ max_activation_time`, `restart_distance ≥ 0`,
    /// `0 ≤ min_deactivation_time ≤ max_deactivation_time`, speeds > 0.
    pub fn validate(&self) -> Result<()> {
        ensure_all_finite(
            &[
                self.head_speed,
                self.min_activation_time,
                self.max_activation_time,
                self.restart_distance,
                self.min_deactivation_time,
                self.max_deactivation_time,
            ],
            "gaze timing",
        )?;
        ensure_all_finite(&self.max_joint_speed, "max_joint_speed")?;
        let bad = |what: &str| Err(Error::InvalidArgument(format!("gaze timing: {what}")));
        if self.head_speed <= 0.0 {
            return bad("head_speed must be > 0");
        }
        if self.min_activation_time <= 0.0 || self.max_activation_time < self.min_activation_time {
            return bad("need 0 < min_activation_time ≤ max_activation_time");
        }
        if self.restart_distance < 0.0 {
            return bad("restart_distance must be ≥ 0");
        }
        if self.min_deactivation_time < 0.0
            || self.max_deactivation_time < self.min_deactivation_time
        {
            return bad("need 0 ≤ min_deactivation_time ≤ max_deactivation_time");
        }
        if self.max_joint_speed.iter().any(|speed| *speed <= 0.0) {
            return bad("max_joint_speed must be > 0");
        }
        Ok(())
    }

    /// `t_a` for a head rotation of `head_angle` radians and an interest ratio
    /// `S_max / S_MAX` in (0, 1]: `head_angle / (v_m · ratio)`, clamped to
    /// [`GazeTiming::min_activation_time`, `GazeTiming::max_activation_time`].
    pub fn activation_time(&self, head_angle: f32, interest_ratio: f32) -> f32 {
        let ratio = interest_ratio.clamp(f32::MIN_POSITIVE, 1.0);
        let time = head_angle / (self.head_speed * ratio);
        if time.is_nan() {
            return self.max_activation_time;
        }
        time.clamp(self.min_activation_time, self.max_activation_time)
    }
}

/// Everything a [`GazeMotion`] needs to know besides the frame: spatial and timing settings.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct GazeConfig {
    /// Recruitment bands and the behind / near-target rules.
    pub spatial: SpatialConfig,
    /// Durations, speeds and the ease.
    pub timing: GazeTiming,
}

impl GazeConfig {
    /// Checks both parts.
    pub fn validate(&self) -> Result<()> {
        self.spatial.validate()?;
        self.timing.validate()
    }
}

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
}

impl GazeRequest {
    /// Look at `target` with head and eyes, interest ratio 1.
    pub fn at(target_key: u64, target: Vec3) -> GazeRequest {
        GazeRequest {
            target_key,
            head_target: target,
            eye_target: target,
            interest_ratio: 1.0,
        }
    }
}

/// One frame of input to [`GazeMotion::update`].
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

/// Where a gaze motion is.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum GazePhase {
    /// No target, every delta identity.
    #[default]
    Idle,
    /// Turning towards a target (some group has not finished its eased shift).
    Shifting,
    /// Every group has arrived; following the target.
    Holding,
    /// Target dropped: going back to the base motion.
    Returning,
}

/// A character's gaze motion state: plain fixed-size data, no heap, 576 bytes
/// (`size_of::<GazeMotion>()`, checked by a test).
///
/// Not safe for concurrent mutation; each character owns one.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GazeMotion {
    /// The current delta of each joint (the output).
    deltas: [Quat; MAX_CHAIN_JOINTS],
    /// The deltas at the start of the current shift or return.
    start: [Quat; MAX_CHAIN_JOINTS],
    /// World eye positions after the last update (left, right).
    eye_origins: [Vec3; 2],
    /// World gaze directions after the last update (left, right).
    eye_directions: [Vec3; 2],
    /// The target points of the previous frame.
    last_head_target: Vec3,
    last_eye_target: Vec3,
    target_key: u64,
    /// Time since the start of the current shift or return, s.
    elapsed: f32,
    /// `t_a` of the current shift, s.
    activation_time: f32,
    /// `t_d` of the current return, s.
    deactivation_time: f32,
    joint_count: u8,
    phase: GazePhase,
    side: TurnSide,
}

impl GazeMotion {
    /// A motion at rest (every delta identity) for `chain`.
    pub fn new(chain: &GazeChain) -> GazeMotion {
        GazeMotion {
            deltas: spatial::IDENTITY_DELTAS,
            start: spatial::IDENTITY_DELTAS,
            eye_origins: [Vec3::ZERO; 2],
            eye_directions: [Vec3::ZERO; 2],
            last_head_target: Vec3::ZERO,
            last_eye_target: Vec3::ZERO,
            target_key: 0,
            elapsed: 0.0,
            activation_time: 0.0,
            deactivation_time: 0.0,
            joint_count: chain.joint_count() as u8,
            phase: GazePhase::Idle,
            side: TurnSide::UNDECIDED,
        }
    }

    /// The current delta local rotation of each chain joint: the final local rotation of
    /// joint `i` is `base[i] * deltas()[i]`.
    pub fn deltas(&self) -> &[Quat] {
        &self.deltas[..self.joint_count as usize]
    }

    /// Where the motion is.
    pub fn phase(&self) -> GazePhase {
        self.phase
    }

    /// `t_a` of the current (or last) shift, seconds.
    pub fn activation_time(&self) -> f32 {
        self.activation_time
    }

    /// `t_d` of the current (or last) return, seconds.
    pub fn deactivation_time(&self) -> f32 {
        self.deactivation_time
    }

    /// Seconds since the current shift or return started.
    pub fn elapsed(&self) -> f32 {
        self.elapsed
    }

    /// The side the character turns to for targets behind it.
    pub fn turn_side(&self) -> TurnSide {
        self.side
    }

    /// World positions of the left and right eyes after the last update (both the head's
    /// global eye for a chain without eyes), metres — for debug drawing.
    pub fn eye_origins(&self) -> [Vec3; 2] {
        self.eye_origins
    }

    /// World unit gaze directions of the left and right eyes after the last update.
    pub fn eye_directions(&self) -> [Vec3; 2] {
        self.eye_directions
    }

    /// The global eye after the last update: the mid-point of the eyes and the mean of
    /// their directions (unit).
    pub fn gaze_ray(&self) -> (Vec3, Vec3) {
        (
            0.5 * (self.eye_origins[0] + self.eye_origins[1]),
            (self.eye_directions[0] + self.eye_directions[1]).normalize_or_zero(),
        )
    }

    /// How long each group's current shift (or return) lasts, indexed by
    /// [`JointGroup::index`].
    pub fn group_durations(&self) -> [f32; 3] {
        match self.phase {
            GazePhase::Returning => {
                let t = self.deactivation_time;
                [0.25 * t, 0.5 * t, t]
            }
            _ => {
                let t = self.activation_time;
                [0.5 * t, t, 2.0 * t]
            }
        }
    }

    /// Advances the motion by `input.dt` and computes this frame's deltas.
    ///
    /// `random` is the character's own seeded stream (e.g.
    /// `stream(seed, Purpose::GazeTiming, character_index)`): it draws `t_d` when a target is
    /// dropped. Allocates nothing. To update a crowd, [`GazeMotion::update_batch`] does the
    /// same for several characters at once, faster.
    ///
    /// Errors (the motion is left unchanged): [`Error::InvalidArgument`] if `chain` has a
    /// different joint count than the one the motion was made for, `input.base` is not one
    /// rotation per joint, `dt < 0`, the interest ratio is ≤ 0, or `config` is out of range;
    /// [`Error::NonFinite`] for a NaN or infinite input.
    pub fn update(
        &mut self,
        chain: &GazeChain,
        config: &GazeConfig,
        input: &GazeInput<'_>,
        random: &mut Random,
    ) -> Result<()> {
        let [result] = GazeMotion::update_batch([self], [chain], config, [input], [random]);
        result
    }

    /// [`GazeMotion::update`] for `N` characters at once (each with its own chain, input and
    /// random stream): the same results, bit for bit, as `N` separate calls, but the
    /// characters' joints are processed in lockstep so that the processor overlaps their
    /// serial per-joint computations. [`BATCH_LANES`] characters per call is the sweet spot.
    /// Each character's result is independent: one failing leaves only its motion unchanged.
    pub fn update_batch<const N: usize>(
        motions: [&mut GazeMotion; N],
        chains: [&GazeChain; N],
        config: &GazeConfig,
        inputs: [&GazeInput<'_>; N],
        randoms: [&mut Random; N],
    ) -> [Result<()>; N] {
        if let Err(error) = config.validate() {
            return std::array::from_fn(|_| Err(error.clone()));
        }
        let results: [Result<()>; N] =
            std::array::from_fn(|lane| motions[lane].check(chains[lane], inputs[lane]));
        let ok: [bool; N] = std::array::from_fn(|lane| results[lane].is_ok());
        let prepared = Prepared::new(&config.spatial);
        let timing = &config.timing;

        // 1. Lanes with a target: is it a new one? Then the spatial solve of the bodies.
        let mut sides: [TurnSide; N] = std::array::from_fn(|lane| motions[lane].side);
        let mut new_target = [false; N];
        for lane in 0..N {
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
        let mut goals = [spatial::IDENTITY_DELTAS; N];
        let solved = {
            let mut problems: [Option<BodyProblem<'_>>; N] = [const { None }; N];
            for (lane, ((problem, side), goal)) in problems
                .iter_mut()
                .zip(sides.iter_mut())
                .zip(goals.iter_mut())
                .enumerate()
            {
                if let (true, Some(request)) = (ok[lane], &inputs[lane].request) {
                    *problem = Some(BodyProblem {
                        chain: chains[lane],
                        character: &inputs[lane].character,
                        base: inputs[lane].base,
                        head_target: request.head_target,
                        side,
                        deltas: goal,
                    });
                }
            }
            spatial::solve_bodies(&prepared, problems)
        };

        // 2. Each lane's phase, timing and eased fractions.
        let mut fractions = [[0.0f32; 3]; N];
        let mut max_steps = [[0.0f32; 3]; N];
        for lane in 0..N {
            if !ok[lane] {
                continue;
            }
            let motion = &mut *motions[lane];
            let input = inputs[lane];
            let chain = chains[lane];
            motion.side = sides[lane];
            match (&input.request, &solved[lane]) {
                (Some(request), Some((solution, _))) => {
                    if new_target[lane] || solution.side_switched {
                        motion.start = motion.deltas;
                        motion.elapsed = 0.0;
                        let body = chain.body_count();
                        let head_angle =
                            head_turn(input.base, &motion.start[..body], &goals[lane][..body]);
                        motion.activation_time =
                            timing.activation_time(head_angle, request.interest_ratio);
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
                        motion.start = motion.deltas;
                        motion.elapsed = 0.0;
                        motion.deactivation_time = randoms[lane]
                            .range(timing.min_deactivation_time, timing.max_deactivation_time);
                        motion.phase = GazePhase::Returning;
                    }
                    GazePhase::Returning => motion.elapsed += input.dt,
                    GazePhase::Idle => {}
                },
            }
            let elapsed = motion.elapsed;
            fractions[lane] = motion
                .group_durations()
                .map(|duration| eased(&timing.ease, elapsed, duration));
            max_steps[lane] = timing.max_joint_speed.map(|speed| speed * input.dt);
        }
        let moving: [bool; N] = std::array::from_fn(|lane| {
            ok[lane]
                && matches!(
                    motions[lane].phase,
                    GazePhase::Shifting | GazePhase::Holding
                )
        });
        let returning: [bool; N] =
            std::array::from_fn(|lane| ok[lane] && motions[lane].phase == GazePhase::Returning);

        // 3. Body joints, in lockstep, with each pose's forward kinematics on the way up.
        let mut heads: [Frame; N] =
            std::array::from_fn(|lane| spatial::root_frame(chains[lane], &inputs[lane].character));
        let mut at_rest = [true; N];
        let joints = (0..N)
            .filter(|lane| ok[*lane])
            .map(|lane| chains[lane].body_count())
            .max()
            .unwrap_or(0);
        for index in 0..joints {
            for lane in 0..N {
                let chain = chains[lane];
                if !ok[lane] || index >= chain.body_count() {
                    continue;
                }
                let motion = &mut *motions[lane];
                let group = spatial::group_of(chain, index).index();
                if moving[lane] || returning[lane] {
                    let goal = if moving[lane] {
                        goals[lane][index]
                    } else {
                        Quat::IDENTITY
                    };
                    let wanted = interpolate(motion.start[index], goal, fractions[lane][group]);
                    let delta = motion.settle(chain, index, wanted, max_steps[lane][group]);
                    at_rest[lane] &= delta == Quat::IDENTITY;
                    motion.deltas[index] = delta;
                }
                let head = &mut heads[lane];
                head.position += head.rotation.mul_vec3a(chain.joints()[index].offset.into());
                head.rotation = head.rotation * inputs[lane].base[index] * motion.deltas[index];
            }
        }

        // 4. Eyes: vergence from the current head, or back to rest.
        let eyes_group = JointGroup::Eyes.index();
        for eye in 0..2 {
            for lane in 0..N {
                let chain = chains[lane];
                let Some(indices) = chain.eye_indices() else {
                    continue;
                };
                if !(moving[lane] || returning[lane]) {
                    continue;
                }
                let index = indices[eye];
                let motion = &mut *motions[lane];
                let goal = match &inputs[lane].request {
                    Some(request) if moving[lane] => spatial::eye_goal(
                        chain,
                        &prepared,
                        &heads[lane],
                        inputs[lane].base,
                        index,
                        request.eye_target.into(),
                        motion.side_sign(),
                    ),
                    _ => Quat::IDENTITY,
                };
                let wanted = interpolate(motion.start[index], goal, fractions[lane][eyes_group]);
                let delta = motion.settle(chain, index, wanted, max_steps[lane][eyes_group]);
                at_rest[lane] &= delta == Quat::IDENTITY;
                motion.deltas[index] = delta;
            }
        }

        // 5. Phase changes, and the eye rays for debug drawing.
        for lane in 0..N {
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
            if returning[lane] && at_rest[lane] && motion.elapsed >= motion.deactivation_time {
                motion.phase = GazePhase::Idle;
                motion.side = TurnSide::UNDECIDED;
            }
            let count = chain.joint_count();
            let rays = spatial::eye_rays_unchecked(
                chain,
                &heads[lane],
                inputs[lane].base,
                &motion.deltas[..count],
            );
            motion.eye_origins = rays.origins;
            motion.eye_directions = rays.directions;
        }
        results
    }

    fn check(&self, chain: &GazeChain, input: &GazeInput<'_>) -> Result<()> {
        if chain.joint_count() != self.joint_count as usize {
            return Err(Error::InvalidArgument(format!(
                "this gaze motion was made for a chain of {} joints, not {}",
                self.joint_count,
                chain.joint_count()
            )));
        }
        if input.base.len() != chain.joint_count() {
            return Err(Error::InvalidArgument(format!(
                "base holds {} rotations, the chain has {} joints",
                input.base.len(),
                chain.joint_count()
            )));
        }
        spatial::check_pose(chain, &input.character, input.base, "base")?;
        ensure_finite(input.dt, "dt")?;
        if input.dt < 0.0 {
            return Err(Error::InvalidArgument(format!(
                "dt is {}, must be ≥ 0",
                input.dt
            )));
        }
        if let Some(request) = &input.request {
            ensure_all_finite(&request.head_target.to_array(), "head_target")?;
            ensure_all_finite(&request.eye_target.to_array(), "eye_target")?;
            ensure_finite(request.interest_ratio, "interest_ratio")?;
            if request.interest_ratio <= 0.0 {
                return Err(Error::InvalidArgument(format!(
                    "interest_ratio is {}, must be in (0, 1]",
                    request.interest_ratio
                )));
            }
        }
        Ok(())
    }

    /// The new delta of joint `index`: `wanted`, at most `max_step` radians from the current
    /// delta, within the joint's limits.
    #[inline(always)]
    fn settle(&self, chain: &GazeChain, index: usize, wanted: Quat, max_step: f32) -> Quat {
        let stepped = step_toward(self.deltas[index], wanted, max_step);
        if stepped == Quat::IDENTITY {
            return stepped;
        }
        chain.joints()[index].limits.clamp(stepped)
    }

    fn side_sign(&self) -> f32 {
        if self.side.sign() < 0 {
            -1.0
        } else {
            1.0
        }
    }
}

/// `f_P(elapsed / duration)`, 1 for a zero duration.
#[inline]
fn eased(ease: &Ease, elapsed: f32, duration: f32) -> f32 {
    if duration > 0.0 {
        ease.at(elapsed / duration)
    } else {
        1.0
    }
}

/// `θ_head`: the angle of the head's rotation, in the chain root's frame, from the pose
/// `base * from` to the pose `base * to` (body joints).
fn head_turn(base: &[Quat], from: &[Quat], to: &[Quat]) -> f32 {
    let body = from.len();
    let mut head_from = Quat::IDENTITY;
    let mut head_to = Quat::IDENTITY;
    for ((base, from), to) in base[..body].iter().zip(&from[..body]).zip(&to[..body]) {
        head_from = head_from * *base * *from;
        head_to = head_to * *base * *to;
    }
    angle_between(head_from, head_to)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn motion_state_is_small() {
        assert_eq!(std::mem::size_of::<GazeMotion>(), 576);
        assert!(std::mem::size_of::<GazeMotion>() < 1024);
    }

    #[test]
    fn activation_time_formula_and_bounds() {
        let timing = GazeTiming::default();
        // θ_head = π/2 at full interest: (π/2) / 2π = 0.25 s.
        assert!((timing.activation_time(std::f32::consts::FRAC_PI_2, 1.0) - 0.25).abs() < 1e-6);
        // Half the interest, twice the time.
        assert!((timing.activation_time(std::f32::consts::FRAC_PI_2, 0.5) - 0.5).abs() < 1e-6);
        // Capped at 2 s, at least 0.2 s.
        assert_eq!(timing.activation_time(3.0, 0.01), 2.0);
        assert_eq!(timing.activation_time(0.0, 1.0), 0.2);
        assert_eq!(
            timing.activation_time(1.0, 5.0),
            timing.activation_time(1.0, 1.0)
        );
    }

    #[test]
    fn timing_is_validated() {
        assert!(GazeTiming::default().validate().is_ok());
        let bad = GazeTiming {
            min_activation_time: 0.0,
            ..GazeTiming::default()
        };
        assert!(matches!(bad.validate(), Err(Error::InvalidArgument(_))));
        let bad = GazeTiming {
            head_speed: f32::NAN,
            ..GazeTiming::default()
        };
        assert!(matches!(bad.validate(), Err(Error::NonFinite(_))));
        let bad = GazeTiming {
            max_deactivation_time: 0.1,
            ..GazeTiming::default()
        };
        assert!(matches!(bad.validate(), Err(Error::InvalidArgument(_))));
    }
}
