//! The settings of the temporal resolution: [`GazeTiming`] (`v_m` and the bounds of the
//! activation time `t_a`, the deactivation time `t_d`, the restart distance, the speed caps,
//! the ease `f_P`, the saccadic durations and the main sequence), the [`MotionStyle`] of a
//! shift, and [`GazeConfig`], the spatial and timing settings together.

use crate::error::{ensure_all_finite, Error, Result};
use crate::ik::spatial::SpatialConfig;
use crate::math::ease::Ease;

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
    ///
    /// [`JointGroup::index`]: crate::ik::JointGroup::index
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
    /// [`MotionStyle::MainSequence`]: an eye shift of amplitude `A` lasts
    /// `main_sequence_base + main_sequence_per_radian · A`, s. Default 0.021 (21 ms; the
    /// human main sequence, about 2.2 ms/° · A + 21 ms: Carpenter 1988, *Movements of the
    /// Eyes*; Baloh et al. 1975; Bahill, Clark & Stark 1975).
    pub main_sequence_base: f32,
    /// See `main_sequence_base`, s per radian. Default 2.2 ms/° (0.126 s/rad).
    pub main_sequence_per_radian: f32,
    /// [`MotionStyle::MainSequence`]: the eyes turn at most this fast during the saccade,
    /// rad/s. Default 500°/s, where the peak velocity of large human saccades saturates
    /// (Baloh et al. 1975; Bahill, Clark & Stark 1975).
    pub main_sequence_peak_velocity: f32,
    /// [`MotionStyle::MainSequence`]: the saccade's progress curve. Default `f_P` with
    /// steepness 2.68, whose velocity peaks at 1.6 times its mean (our choice: a bell like
    /// the body's, flatter, so that the main sequence's durations keep the peak velocity
    /// of a 20° saccade under the 500°/s saturation).
    pub saccade_ease: Ease,
}

/// The steepness of [`GazeTiming::saccade_ease`]'s default: a velocity peak 1.6 times the
/// mean.
pub const SACCADE_STEEPNESS: f32 = 2.68;

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
            main_sequence_base: 0.021,
            main_sequence_per_radian: 0.0022 * (180.0 / std::f32::consts::PI),
            main_sequence_peak_velocity: 500f32.to_radians(),
            saccade_ease: Ease::new(SACCADE_STEEPNESS),
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
        ensure_all_finite(
            &[
                self.main_sequence_base,
                self.main_sequence_per_radian,
                self.main_sequence_peak_velocity,
            ],
            "main sequence",
        )?;
        if self.main_sequence_base <= 0.0
            || self.main_sequence_per_radian < 0.0
            || self.main_sequence_peak_velocity <= 0.0
        {
            return Err(Error::InvalidArgument(
                "gaze timing: main_sequence_base and main_sequence_peak_velocity must be > 0, \
                 main_sequence_per_radian ≥ 0"
                    .into(),
            ));
        }
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

impl GazeTiming {
    /// How long an eye shift of `amplitude` radians lasts on the main sequence, s
    /// ([`MotionStyle::MainSequence`]).
    pub fn main_sequence_duration(&self, amplitude: f32) -> f32 {
        self.main_sequence_base + self.main_sequence_per_radian * amplitude
    }
}

/// Everything a [`GazeMotion`] needs to know besides the frame: spatial and timing settings.
///
/// [`GazeMotion`]: crate::ik::GazeMotion
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
    /// As [`Eased`](Self::Eased) for the head, neck and spine, but the eyes' shift lasts as
    /// long as a human saccade of its amplitude `A` (the main sequence,
    /// [`GazeTiming::main_sequence_duration`]: about 2.2 ms/° · A + 21 ms), along
    /// [`GazeTiming::saccade_ease`] and no faster than
    /// [`GazeTiming::main_sequence_peak_velocity`]; `A` is the angle between the eyes'
    /// direction when the shift starts and the target (before the character's first frame,
    /// when the eyes have no direction yet, the eyes take the eased `t_a / 2`).
    MainSequence,
}
