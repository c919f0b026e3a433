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
//! the spatial solution, such as an eye target crossing straight behind the head), then
//! clamped to its limits, so both hold on every frame.
//!
//! **Batches.** [`GazeMotion::update_batch`] updates up to [`BATCH_LANES`] (16) characters in
//! one call, in lane groups of as many as the processor's SIMD registers hold (16 with
//! AVX-512F, 8 with AVX, else 4; chosen at run time), one character per lane; batches of up
//! to four, such as [`GazeMotion::update`] (a batch of one, which costs about as much as four),
//! run at four lanes. Every width computes the same IEEE operations in each lane, so a
//! character's results are exactly the same whatever batch it is in, wherever, and whatever
//! the width: a crowd stays deterministic however its characters are split between threads
//! and whichever processor runs it. A lane group whose every character rests
//! ([`GazeMotion::is_resting`]) takes a short update that gives the same bits, so batching
//! resting characters apart from moving ones (as the crowd does) makes them cheap.

// The lockstep loops index several per-lane and per-joint arrays with one index.
#![allow(clippy::needless_range_loop)]

use glam::{Quat, Vec3, Vec3A, Vec4};

use super::chain::{GazeChain, JointGroup, MAX_BODY_JOINTS, MAX_CHAIN_JOINTS};
use super::lanes::{gather, interpolate_or, mask, Floats, Mask, MAX_LANES, Q4, V3};
use super::rotation::{angle_between, step_toward};
use super::spatial::{
    self, BodyLane, EyeFrames, Frames, Limits, Prepared, SpatialConfig, TurnSide,
};
use super::CharacterTransform;
use crate::error::{ensure_all_finite, ensure_finite, Error, Result};
use crate::math::ease::{head_progress, saccade_progress, Ease};
use crate::math::packed::PackedQuat;
use crate::math::random::Random;
use crate::math::wide::{run_widest, LaneJob, Wide};

/// How many characters [`GazeMotion::update_batch`] takes at most, and best takes at once: the
/// widest lane group (16, AVX-512F); narrower processors run a batch in several groups.
pub const BATCH_LANES: usize = MAX_LANES;

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
    /// [`MotionStyle::Saccadic`]: the eye saccade's duration, s. Default 0.2 (the paper's
    /// six frames of 1/30 s).
    pub saccade_duration: f32,
    /// [`MotionStyle::Saccadic`]: the head movement lasts `head_base_duration +
    /// head_duration_per_radian · θ_head`, s. Default 0.25 (our choice; the paper leaves
    /// the head's duration to its fitted curve).
    pub head_base_duration: f32,
    /// See `head_base_duration`, s per radian of head turn. Default 0.45 (a 60° head turn
    /// takes about 0.72 s).
    pub head_duration_per_radian: f32,
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
            saccade_duration: 0.2,
            head_base_duration: 0.25,
            head_duration_per_radian: 0.45,
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
        ensure_all_finite(
            &[
                self.saccade_duration,
                self.head_base_duration,
                self.head_duration_per_radian,
            ],
            "saccadic timing",
        )?;
        if self.saccade_duration <= 0.0
            || self.head_base_duration <= 0.0
            || self.head_duration_per_radian < 0.0
        {
            return Err(Error::InvalidArgument(
                "gaze timing: saccade_duration and head_base_duration must be > 0, \
                 head_duration_per_radian ≥ 0"
                    .into(),
            ));
        }
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

/// How a gaze shift unfolds in time.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum MotionStyle {
    /// Grillon & Thalmann 2009: eyes over `t_a/2`, head and neck over `t_a`, spine over
    /// `2 t_a`, each eased by `f_P`.
    #[default]
    Eased,
    /// Kokkinara, Oyekoya & Steed 2011: the eyes jump in a saccade of six frames with the
    /// profile `14 e^(−π/4 (x − 3)²)`; the head (and, over 1.5 times as long, the spine)
    /// follows `θ_h(u) = e^(0.027u)(sin(πu/2))^1.90` over a duration that grows with the
    /// head's turn ([`GazeTiming::head_base_duration`]).
    Saccadic,
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
    /// How the shift to this target unfolds (taken when a shift starts).
    pub style: MotionStyle,
}

impl GazeRequest {
    /// Look at `target` with head and eyes, interest ratio 1.
    pub fn at(target_key: u64, target: Vec3) -> GazeRequest {
        GazeRequest {
            target_key,
            head_target: target,
            eye_target: target,
            interest_ratio: 1.0,
            style: MotionStyle::Eased,
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

/// A character's gaze motion state: plain fixed-size data, no heap, 464 bytes
/// (`size_of::<GazeMotion>()`, checked by a test).
///
/// Not safe for concurrent mutation; each character owns one.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GazeMotion {
    /// The current delta of each joint (the output).
    deltas: [Quat; MAX_CHAIN_JOINTS],
    /// The deltas at the start of the current shift or return, packed (within 6·10⁻⁶ rad;
    /// see [`PackedQuat`]). They are read only while a group is under way, and never on the
    /// frame a shift starts or while its eased fraction is still 0: the joints are exactly
    /// on their start pose then, and the current deltas serve instead.
    start: [PackedQuat; MAX_CHAIN_JOINTS],
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
    /// The style of the current shift.
    style: MotionStyle,
    /// The eye saccade's duration of a saccadic shift, s.
    saccade_duration: f32,
}

impl GazeMotion {
    /// A motion at rest (every delta identity) for `chain`.
    pub fn new(chain: &GazeChain) -> GazeMotion {
        GazeMotion {
            deltas: spatial::IDENTITY_DELTAS,
            start: [PackedQuat::IDENTITY; MAX_CHAIN_JOINTS],
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
            style: MotionStyle::Eased,
            saccade_duration: 0.0,
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
                match self.style {
                    MotionStyle::Eased => [0.5 * t, t, 2.0 * t],
                    // t_a holds the head's duration; the eyes' saccade is kept apart.
                    MotionStyle::Saccadic => [self.saccade_duration, t, 1.5 * t],
                }
            }
        }
    }

    /// The fraction of its motion each group has done (eyes, head and neck, spine): `f_P`,
    /// or for a saccadic shift the saccade and head curves.
    fn group_fractions(&self, ease: &Ease) -> [f32; 3] {
        let durations = self.group_durations();
        let elapsed = self.elapsed;
        if self.phase == GazePhase::Returning || self.style == MotionStyle::Eased {
            return durations.map(|duration| eased(ease, elapsed, duration));
        }
        let progress = |duration: f32| {
            if duration > 0.0 {
                elapsed / duration
            } else {
                1.0
            }
        };
        [
            saccade_progress(6.0 * progress(durations[0])),
            head_progress(progress(durations[1])),
            head_progress(progress(durations[2])),
        ]
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

    /// [`GazeMotion::update`] for `N` characters at once, `1 ≤ N ≤ BATCH_LANES` (each with its
    /// own chain, input and random stream): the same results as `N` separate calls, computed
    /// together, one character per SIMD lane, in lane groups of the processor's width (16
    /// with AVX-512F, 8 with AVX, else 4; four for `N ≤ 4`, one for `N = 1`) — a lane
    /// group costs about as much as one character.
    /// Each character's result is independent: one failing leaves only its motion unchanged.
    ///
    /// A crowd updates its characters in chunks of [`BATCH_LANES`] (and the last few with a
    /// smaller `N`).
    pub fn update_batch<const N: usize>(
        motions: [&mut GazeMotion; N],
        chains: [&GazeChain; N],
        config: &GazeConfig,
        inputs: [&GazeInput<'_>; N],
        randoms: [&mut Random; N],
    ) -> [Result<()>; N] {
        const {
            assert!(
                N >= 1 && N <= BATCH_LANES,
                "1 to BATCH_LANES characters per batch"
            )
        };
        if let Err(error) = config.validate() {
            return std::array::from_fn(|_| Err(error.clone()));
        }
        let results: [Result<()>; N] =
            std::array::from_fn(|lane| motions[lane].check(chains[lane], inputs[lane]));
        let ok: [bool; N] = std::array::from_fn(|lane| results[lane].is_ok());
        if ok.contains(&true) {
            Self::update_checked(motions, chains, config, inputs, randoms, &ok);
        }
        results
    }

    /// [`update_batch`](Self::update_batch) for inputs known to pass its checks: the
    /// crowd's, whose every part was checked when it came in (its configuration when the
    /// crowd was made, poses, positions and targets when they were set). Debug builds
    /// check them again.
    pub(crate) fn update_batch_prechecked<const N: usize>(
        motions: [&mut GazeMotion; N],
        chains: [&GazeChain; N],
        config: &GazeConfig,
        inputs: [&GazeInput<'_>; N],
        randoms: [&mut Random; N],
    ) {
        debug_assert!(config.validate().is_ok());
        debug_assert!((0..N).all(|lane| motions[lane].check(chains[lane], inputs[lane]).is_ok()));
        Self::update_checked(motions, chains, config, inputs, randoms, &[true; N]);
    }

    /// [`update_batch`](Self::update_batch) once its checks are done: `ok[lane]` says which
    /// characters passed them (the others are left as they are).
    fn update_checked<const N: usize>(
        motions: [&mut GazeMotion; N],
        chains: [&GazeChain; N],
        config: &GazeConfig,
        inputs: [&GazeInput<'_>; N],
        randoms: [&mut Random; N],
        ok: &[bool; N],
    ) {
        let prepared = Prepared::new(&config.spatial);
        let (mut motions, mut randoms) = (motions, randoms);
        let groups = UpdateGroups {
            motions: &mut motions,
            chains: &chains,
            config,
            inputs: &inputs,
            randoms: &mut randoms,
            ok,
            prepared: &prepared,
        };
        if N == 1 {
            // One character: the one-lane (scalar) form of the same code.
            groups.run::<f32>();
        } else if N <= 4 {
            // A few characters: four lanes fill them at less cost than wider ones (the same
            // bits at every width).
            groups.run::<Vec4>();
        } else {
            run_widest(groups);
        }
    }

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

    /// Keeps lane `lane` of the eye rays (left, right) as this motion's.
    #[inline(always)]
    fn set_eye_rays<W: Wide>(
        &mut self,
        origins: &[V3<W>; 2],
        directions: &[V3<W>; 2],
        lane: usize,
    ) {
        for eye in 0..2 {
            self.eye_origins[eye] = origins[eye].lane(lane).into();
            self.eye_directions[eye] = directions[eye].lane(lane).into();
        }
    }

    /// True if the motion is at rest (idle: every delta identity) and `request` is none: an
    /// update then only carries the eye rays along with the character. A lane group whose
    /// every character rests skips everything else, while one that mixes them with moving
    /// ones costs the full update in every lane (the results are the same bits either way):
    /// batching them apart took the crowd's gaze step at 10 000 characters, 62 % of them
    /// resting, from 0.462 to 0.270 µs per character-frame (A/B, medians of 7 runs).
    #[inline]
    pub fn is_resting(&self, request: Option<&GazeRequest>) -> bool {
        self.phase == GazePhase::Idle && request.is_none()
    }

    /// [`update_lanes`](Self::update_lanes) for a lane group whose every character that
    /// passed its checks (`ok`) rests ([`is_resting`](Self::is_resting)): the eye rays of
    /// the base pose, by the same operations the full update makes on such a character (its
    /// deltas are identity and are multiplied in as such), so the same bits, without reading
    /// the deltas or solving anything.
    #[inline(always)]
    fn rest_lanes<W: Wide>(
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

    /// The current deltas become the start of a new shift or return.
    fn remember_start(&mut self) {
        let count = self.joint_count as usize;
        for (start, delta) in self.start[..count].iter_mut().zip(&self.deltas) {
            *start = PackedQuat::pack(*delta);
        }
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
}

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
fn settle<W: Wide>(
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
fn heads_by_kinematics<W: Wide>(
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
fn eyeless_directions<W: Wide>(
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
fn head_turn(base: &[Quat], from: &[Quat], to: impl Iterator<Item = Quat>) -> f32 {
    let mut head_from = Quat::IDENTITY;
    let mut head_to = Quat::IDENTITY;
    for ((base, from), to) in base.iter().zip(from).zip(to) {
        head_from = head_from * *base * *from;
        head_to = head_to * *base * to;
    }
    angle_between(head_from, head_to)
}

/// [`GazeMotion::update_batch`]'s characters, checked, updated in lane groups of the width
/// [`run_widest`] picks.
struct UpdateGroups<'a, 'm, 'r, 'c, 'i, 'b> {
    motions: &'a mut [&'m mut GazeMotion],
    chains: &'a [&'c GazeChain],
    config: &'a GazeConfig,
    inputs: &'a [&'i GazeInput<'b>],
    randoms: &'a mut [&'r mut Random],
    /// Which characters passed their checks.
    ok: &'a [bool],
    prepared: &'a Prepared,
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
#[cfg(test)]
mod tests {
    use super::*;
    use crate::ik::chain::{ChainJoint, JointLimits, JointRole};
    use crate::math::random::{stream, Purpose};
    use crate::math::wide::for_every_width;

    /// One character's state after a frame, floats as their bits.
    type State = (
        Vec<[u32; 4]>,
        [[u32; 3]; 2],
        [[u32; 3]; 2],
        GazePhase,
        TurnSide,
    );

    /// A vector's bits.
    fn bits(v: Vec3) -> [u32; 3] {
        v.to_array().map(f32::to_bits)
    }

    /// A short chain without eyes (spine, neck, head), so that lane groups mix chains.
    fn eyeless_chain() -> GazeChain {
        let limits = |yaw: f32, swing: f32| {
            JointLimits::new(
                Vec3::Y,
                swing.to_radians(),
                -yaw.to_radians(),
                yaw.to_radians(),
            )
        };
        let joints = [
            (
                JointRole::Spine,
                Vec3::new(0.0, 0.1, 0.0),
                limits(10.0, 8.0),
            ),
            (
                JointRole::Spine,
                Vec3::new(0.0, 0.2, 0.0),
                limits(10.0, 8.0),
            ),
            (
                JointRole::Cervical,
                Vec3::new(0.0, 0.25, 0.02),
                limits(35.0, 30.0),
            ),
            (
                JointRole::Head,
                Vec3::new(0.0, 0.1, 0.0),
                limits(40.0, 30.0),
            ),
        ]
        .map(|(role, offset, limits)| ChainJoint::new(role, offset, Quat::IDENTITY, limits));
        GazeChain::new(&joints, Vec3::Z, Vec3::Y, Vec3::new(0.0, 1.0, 0.0)).expect("valid chain")
    }

    /// 16 characters (three kinds of chain and base pose, each placed and turned its own way,
    /// with targets that jump, go behind and drop out) run for `frames` frames in batches of
    /// `batch` characters, in lane groups of `W`: every character's state after every frame.
    fn run_at<W: Wide>(frames: usize, batch: usize) -> Vec<Vec<State>> {
        let human = GazeChain::human(Vec3::Y, Vec3::Z);
        let eyeless = eyeless_chain();
        let rest: Vec<Quat> = human.joints().iter().map(|joint| joint.rest).collect();
        let animated: Vec<Quat> = (0..10)
            .map(|i| {
                Quat::from_rotation_x(0.02 * i as f32) * Quat::from_rotation_y(-0.03 * i as f32)
            })
            .collect();
        let eyeless_rest = vec![Quat::IDENTITY; eyeless.joint_count()];
        let config = GazeConfig::default();
        let count = 16;
        let chains: Vec<&GazeChain> = (0..count)
            .map(|i| if i % 5 == 3 { &eyeless } else { &human })
            .collect();
        let mut motions: Vec<GazeMotion> = chains.iter().map(|c| GazeMotion::new(c)).collect();
        let mut randoms: Vec<Random> = (0..count)
            .map(|i| stream(5, Purpose::GazeTiming, i as u64))
            .collect();
        let prepared = Prepared::new(&config.spatial);
        let mut history = Vec::new();
        for frame in 0..frames {
            let inputs: Vec<GazeInput<'_>> = (0..count)
                .map(|i| {
                    let base = match (i % 5, i % 2) {
                        (3, _) => &eyeless_rest,
                        (_, 0) => &rest,
                        _ => &animated,
                    };
                    let phase = (frame + 23 * i) % 90;
                    let yaw = ((i * 47 + frame / 30 * 61) % 340) as f32 - 170.0;
                    let position = Vec3::new(i as f32, 0.0, (i % 3) as f32);
                    let target = position
                        + Vec3::new(yaw.to_radians().sin(), 1.6, yaw.to_radians().cos()) * 2.0
                        + Vec3::X * (frame as f32 * 0.02);
                    GazeInput {
                        character: CharacterTransform::from_heading(
                            position,
                            Vec3::Y,
                            i as f32 * 0.7,
                        ),
                        base,
                        request: (phase < 70)
                            .then(|| GazeRequest::at((frame / 30 + i) as u64, target)),
                        dt: 1.0 / 30.0,
                    }
                })
                .collect();
            let input_refs: Vec<&GazeInput<'_>> = inputs.iter().collect();
            let mut motion_refs: Vec<&mut GazeMotion> = motions.iter_mut().collect();
            let mut random_refs: Vec<&mut Random> = randoms.iter_mut().collect();
            for first in (0..count).step_by(batch) {
                let end = count.min(first + batch);
                UpdateGroups {
                    motions: &mut motion_refs[first..end],
                    chains: &chains[first..end],
                    config: &config,
                    inputs: &input_refs[first..end],
                    randoms: &mut random_refs[first..end],
                    ok: &[true; 16][first..end],
                    prepared: &prepared,
                }
                .run::<W>();
            }
            history.push(
                motions
                    .iter()
                    .map(|m| {
                        (
                            m.deltas()
                                .iter()
                                .map(|q| q.to_array().map(f32::to_bits))
                                .collect(),
                            m.eye_origins().map(bits),
                            m.eye_directions().map(bits),
                            m.phase(),
                            m.turn_side(),
                        )
                    })
                    .collect(),
            );
        }
        history
    }

    /// The batched gaze IK does not depend on the width it runs at: the same bits for every
    /// character at 4, 8 and 16 lanes.
    #[test]
    fn update_batch_gives_the_same_bits_at_every_width() {
        let frames = 200;
        let four = run_at::<Vec4>(frames, 16);
        let phases: std::collections::HashSet<String> = four
            .iter()
            .flat_map(|frame| frame.iter().map(|state| format!("{:?}", state.3)))
            .collect();
        assert_eq!(phases.len(), 4, "every phase is exercised: {phases:?}");
        fn same_as_four<W: Wide>(four: &[Vec<State>], frames: usize) {
            let wide = run_at::<W>(frames, 16);
            for (frame, (wide, four)) in wide.iter().zip(four).enumerate() {
                assert_eq!(wide, four, "frame {frame} at {} lanes", W::LANES);
            }
        }
        for_every_width!(same_as_four(&four, frames));
    }

    /// A character at rest with nothing to look at gets the same bits from the resting
    /// characters' short update (its lane group rests wholly: here, a batch of one) as from
    /// the full update (its group has moving characters), frame after frame.
    #[test]
    fn resting_characters_get_the_same_bits_from_the_short_update() {
        let frames = 600;
        let together = run_at::<Vec4>(frames, 16);
        let alone = run_at::<Vec4>(frames, 1);
        // Updates of a resting character (idle before and after) in a group where another
        // character moves: the short update ran for it alone, the full one in the group.
        let idle = |state: &State| state.3 == GazePhase::Idle;
        let compared: usize = together
            .windows(2)
            .filter(|frames| !frames[1].iter().all(idle))
            .map(|frames| {
                let (before, after) = (&frames[0], &frames[1]);
                (0..after.len())
                    .filter(|&character| idle(&before[character]) && idle(&after[character]))
                    .count()
            })
            .sum();
        assert!(compared >= 40, "only {compared} resting updates compared");
        for (frame, (alone, together)) in alone.iter().zip(&together).enumerate() {
            assert_eq!(alone, together, "frame {frame}");
        }
    }

    #[test]
    fn motion_state_is_small() {
        assert_eq!(std::mem::size_of::<GazeMotion>(), 464);
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
