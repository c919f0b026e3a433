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
//!
//! **Files.** `config.rs`: the settings ([`GazeTiming`], [`GazeConfig`], [`MotionStyle`]);
//! `input.rs`: what a frame asks for ([`GazeRequest`], [`GazeInput`]); this file: the state
//! ([`GazeMotion`]) and its per-group durations and fractions; `batch.rs`: the entry points,
//! their checks and the choice of width; `update.rs`: the full update of a lane group, stage
//! by stage; `rest.rs`: the short update of a resting lane group; `pose.rs`: the per-lane
//! pose steps both share (settling a joint, the heads' frames, eyeless rays).

mod batch;
mod config;
mod input;
mod pose;
mod rest;
mod update;

use glam::{Quat, Vec3};

use super::chain::{GazeChain, MAX_CHAIN_JOINTS};
use super::spatial::{self, TurnSide};
use crate::math::ease::{head_progress, saccade_progress, Ease};
use crate::math::lanes::{MAX_LANES, V3};
use crate::math::packed::PackedQuat;
use crate::math::wide::Wide;

pub use config::{GazeConfig, GazeTiming, MotionStyle};
pub use input::{GazeInput, GazeRequest};

/// How many characters [`GazeMotion::update_batch`] takes at most, and best takes at once: the
/// widest lane group (16, AVX-512F); narrower processors run a batch in several groups.
pub const BATCH_LANES: usize = MAX_LANES;
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

    /// The angle (radians) between where the eyes look now ([`gaze_ray`](Self::gaze_ray))
    /// and the direction from them to `target`; `None` before the first update (the eyes
    /// have no direction yet) or for a target at the eyes.
    pub fn eye_angle_to(&self, target: Vec3) -> Option<f32> {
        let (origin, direction) = self.gaze_ray();
        let to_target = (target - origin).normalize_or_zero();
        if direction == Vec3::ZERO || to_target == Vec3::ZERO {
            return None;
        }
        Some(direction.dot(to_target).clamp(-1.0, 1.0).acos())
    }

    /// The amplitude (radians) of the gaze shift that started in the last update, if one
    /// did: the angle the eyes have to turn to its eye target ([`eye_angle_to`]
    /// (Self::eye_angle_to)); `None` when no shift started (or the eyes have no direction
    /// yet).
    pub fn shift_start_amplitude(&self) -> Option<f32> {
        if self.phase != GazePhase::Shifting || self.elapsed != 0.0 {
            return None;
        }
        self.eye_angle_to(self.last_eye_target)
    }

    /// How long each group's current shift (or return) lasts, indexed by
    /// [`JointGroup::index`](crate::ik::JointGroup::index).
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
                    // The eyes' main-sequence duration is kept apart.
                    MotionStyle::MainSequence => [self.saccade_duration, t, 2.0 * t],
                    // t_a holds the head's duration; the eyes' saccade is kept apart.
                    MotionStyle::Saccadic => [self.saccade_duration, t, 1.5 * t],
                }
            }
        }
    }

    /// The fraction of its motion each group has done (eyes, head and neck, spine): `f_P`,
    /// for a main-sequence shift the eyes' along the saccade's ease, for a saccadic shift
    /// the saccade and head curves.
    fn group_fractions(&self, timing: &GazeTiming) -> [f32; 3] {
        let ease = &timing.ease;
        let durations = self.group_durations();
        let elapsed = self.elapsed;
        if self.phase == GazePhase::Returning || self.style == MotionStyle::Eased {
            return durations.map(|duration| eased(ease, elapsed, duration));
        }
        if self.style == MotionStyle::MainSequence {
            return [
                eased(&timing.saccade_ease, elapsed, durations[0]),
                eased(ease, elapsed, durations[1]),
                eased(ease, elapsed, durations[2]),
            ];
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
    /// batching them apart, as the crowd does, makes resting characters cheap.
    #[inline]
    pub fn is_resting(&self, request: Option<&GazeRequest>) -> bool {
        self.phase == GazePhase::Idle && request.is_none()
    }

    /// The current deltas become the start of a new shift or return.
    fn remember_start(&mut self) {
        let count = self.joint_count as usize;
        for (start, delta) in self.start[..count].iter_mut().zip(&self.deltas) {
            *start = PackedQuat::pack(*delta);
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

#[cfg(test)]
mod tests;
