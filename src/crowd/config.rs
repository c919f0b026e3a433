//! How a crowd is set up: [`CrowdConfig`], its defaults and its checks, and the limits of
//! the capacities it sizes every buffer from.

use crate::attention::baseline::BaselineConfig;
use crate::attention::conversation::ConversationSettings;
use crate::attention::following::FollowConfig;
use crate::attention::interest::InterestConfig;
use crate::attention::saliency::SaliencyConfig;
use crate::attention::score::ScoringConfig;
use crate::attention::street::StreetConfig;
pub(super) use crate::error::check_range;
use crate::error::{Error, Result};
use crate::ik::{BlinkSettings, GazeConfig, MotionStyle};
use crate::world::World;

/// Most threads a crowd's step may use.
pub const MAX_THREADS: u32 = 64;

/// Largest capacity accepted for characters or objects (keeps index arithmetic in `u32`).
pub const MAX_CAPACITY: u32 = 1 << 24;

/// How a crowd is set up. Capacities are fixed for the crowd's lifetime: every buffer is
/// sized from them at creation, so stepping never allocates.
#[derive(Debug, Clone, PartialEq)]
pub struct CrowdConfig {
    /// Seed of every random choice (per-character weights, attention percentage,
    /// deactivation times). Same inputs and seed give bit-identical outputs.
    pub seed: u64,
    /// Most characters (entities that look) the crowd can hold at once, 1 to
    /// [`MAX_CAPACITY`] (2²⁴). Each takes about
    /// [`Crowd::state_bytes_per_character`] bytes (about 1 KiB), allocated at creation.
    pub max_characters: u32,
    /// Most scene objects (entities that are only looked at) the crowd can hold at once,
    /// 0 to [`MAX_CAPACITY`] (2²⁴). Each takes about 130 bytes, allocated at creation.
    pub max_objects: u32,
    /// Axes and length unit of the caller's world.
    pub world: World,
    /// The scoring function's settings (`d_m`, field of view, `ω_sw`, `β_m`).
    pub scoring: ScoringConfig,
    /// Interest-point timing and threshold warm-up.
    pub interest: InterestConfig,
    /// Range `[low, high)` from which each character's attention fraction `a`/100 is drawn.
    /// Default [0.2, 0.6).
    pub attention_fraction_range: (f32, f32),
    /// How many entity states `push_frame` may record for offline planning (0: no
    /// recording, online only), 0 to 2³² − 1. Each takes
    /// [`Recording::bytes_per_state`] bytes (64), allocated at creation: a recording that
    /// does not fit in memory fails the creation with [`Error::OutOfMemory`]. Default 0.
    pub max_recorded_states: u32,
    /// Gaze IK settings: recruitment bands and timing.
    pub gaze: GazeConfig,
    /// The saliency model's settings (characters using [`AttentionModel::Saliency`]).
    pub saliency: SaliencyConfig,
    /// The baseline's settings (characters using [`AttentionModel::Baseline`]).
    pub baseline: BaselineConfig,
    /// Level of detail: attention (not gaze IK, which runs every frame) is updated every
    /// `attention_period` steps per character, staggered so that each step updates an
    /// equal share of the crowd. 1 to 64; default 1 (every step).
    pub attention_period: u32,
    /// Level of detail by distance: characters farther than `lod_distance` (metres) from
    /// the viewer update attention every `far_attention_period` steps. 0 (default) turns
    /// this off.
    pub lod_distance: f32,
    /// See `lod_distance`. 1 to 64; default 4.
    pub far_attention_period: u32,
    /// Threads [`Crowd::step`] uses: 1 (default) steps on the caller's thread only; `n > 1`
    /// starts `n - 1` worker threads with the crowd, which share each step with the
    /// caller; 0 picks one per available core. At most 64. Results do not depend on it.
    pub threads: u32,
    /// Every `reorder_period` steps (default 0: never) the crowd stores its entities and
    /// characters again in the spatial grid's order, so that neighbours in space are
    /// neighbours in memory and a step reads its state in order (see
    /// [`Crowd`](super::Crowd)). That speeds the step of a large crowd created in random
    /// places, but pushes and reads in the engine's order then scatter: the engine's whole
    /// frame is faster without it (docs/performance.md), hence the default. Results and the
    /// character order readers see do not depend on it.
    pub reorder_period: u32,
    /// How the characters blink and how their upper lids follow the eyes
    /// ([`BlinkSettings`]; read them with [`Crowd::eyelids_at`](super::Crowd::eyelids_at)).
    pub blinks: BlinkSettings,
    /// How the eyes of the crowd model's and the baseline's characters time a shift:
    /// the paper's (default) or the human main sequence.
    pub eye_motion: EyeMotion,
    /// Most conversations (groups standing together and talking,
    /// [`Crowd::set_conversation`](super::Crowd::set_conversation)) at once, 0 to
    /// [`MAX_CAPACITY`] / 2. Each takes about 170 bytes, reserved at creation (a group's
    /// 132 bytes are touched only once a group has used its slot). Default 64. A removed
    /// group's id names no group until at least 2³² − 1 − `max_conversations` more groups
    /// have been formed ([`Crowd::set_conversation`](super::Crowd::set_conversation)).
    pub max_conversations: u32,
    /// How members of conversations look at each other.
    pub conversation: ConversationSettings,
    /// The street model's settings (characters using [`AttentionModel::Street`]; they
    /// notice walkers within `max_distance`: [`CrowdConfig::street`] sets it as the field
    /// measured).
    ///
    /// [`AttentionModel::Street`]: crate::attention::AttentionModel::Street
    pub street: StreetConfig,
    /// Gaze following, for characters of every model: off by default (the crowd then
    /// behaves exactly as without it). [`FollowConfig::MILGRAM`] and
    /// [`FollowConfig::GALLUP`] are its two measured strengths.
    pub following: FollowConfig,
}

/// How the eyes of the crowd model's and the baseline's characters time a gaze shift (the
/// saliency model keeps its paper's six-frame saccade).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum EyeMotion {
    /// Grillon & Thalmann 2009: the eyes arrive at half the activation time `t_a`
    /// ([`MotionStyle::Eased`]).
    #[default]
    Paper,
    /// The eyes' shift lasts as long as a human saccade of its amplitude, about
    /// 2.2 ms/° · A + 21 ms ([`MotionStyle::MainSequence`]); the head, neck and spine keep
    /// the paper's timing.
    MainSequence,
}

impl EyeMotion {
    /// The motion style of the shifts it times.
    pub fn eased_style(self) -> MotionStyle {
        match self {
            EyeMotion::Paper => MotionStyle::Eased,
            EyeMotion::MainSequence => MotionStyle::MainSequence,
        }
    }
}

impl Default for CrowdConfig {
    fn default() -> Self {
        CrowdConfig {
            seed: 0x6372_6f77_6467_617a, // "crowdgaz"
            max_characters: 1024,
            max_objects: 256,
            world: World::default(),
            scoring: ScoringConfig::default(),
            interest: InterestConfig::default(),
            attention_fraction_range: (0.2, 0.6),
            max_recorded_states: 0,
            gaze: GazeConfig::default(),
            saliency: SaliencyConfig::default(),
            baseline: BaselineConfig::default(),
            attention_period: 1,
            lod_distance: 0.0,
            far_attention_period: 4,
            threads: 1,
            reorder_period: 0,
            blinks: BlinkSettings::default(),
            eye_motion: EyeMotion::Paper,
            max_conversations: 64,
            conversation: ConversationSettings::default(),
            street: StreetConfig::default(),
            following: FollowConfig::MILGRAM,
        }
    }
}

/// How far walkers notice each other in the field street preset: Fotios et al. (2018)
/// measured fixations on other walkers at a typical 15 m; a walker coming into view at
/// 17 m, approaching at 2.6 m/s (two walkers at 1.3 m/s), is fixated after the 0.55–0.75 s
/// latency at about 15 m.
pub const STREET_VIEW_DISTANCE: f32 = 17.0;

impl CrowdConfig {
    /// The field-calibrated street: the default configuration with `max_distance` set to
    /// [`STREET_VIEW_DISTANCE`] (17 m), so that characters using
    /// [`AttentionModel::Street`](crate::attention::AttentionModel::Street) notice walkers
    /// as far away as walkers were measured to fixate them, and gaze following on at
    /// Milgram's strength ([`FollowConfig::MILGRAM`]). Give the characters the street model
    /// in their description.
    pub fn street() -> CrowdConfig {
        let mut config = CrowdConfig::default();
        config.scoring.max_distance = STREET_VIEW_DISTANCE;
        config.following.enabled = true;
        config
    }
}

/// Checks that a count lies in `low..=high`.
pub(super) fn check_count(value: u32, low: u32, high: u32, what: &str) -> Result<()> {
    if !(low..=high).contains(&value) {
        return Err(Error::InvalidArgument(format!(
            "{what} is {value}, must be {low}..={high}"
        )));
    }
    Ok(())
}

impl CrowdConfig {
    /// Worker threads to start besides the caller's: `threads - 1`, with 0 meaning one
    /// thread per available core.
    pub fn worker_threads(&self) -> usize {
        let threads = match self.threads {
            0 => std::thread::available_parallelism().map_or(1, |cores| cores.get()),
            threads => threads as usize,
        };
        threads.clamp(1, MAX_THREADS as usize) - 1
    }

    /// Checks every field against its documented range.
    pub fn validate(&self) -> Result<()> {
        check_count(self.max_characters, 1, MAX_CAPACITY, "max_characters")?;
        check_count(self.max_objects, 0, MAX_CAPACITY, "max_objects")?;
        let scoring = &self.scoring;
        check_range(scoring.max_distance, 0.01, 1000.0, "max_distance")?;
        check_range(
            scoring.field_of_view,
            0.01,
            std::f32::consts::TAU,
            "field_of_view",
        )?;
        check_range(scoring.speed_weight, 0.0, 1000.0, "speed_weight")?;
        check_range(
            scoring.periphery_max_angle,
            0.0,
            std::f32::consts::PI,
            "periphery_max_angle",
        )?;
        let interest = &self.interest;
        check_range(interest.min_hold, 0.0, 60.0, "min_hold")?;
        check_range(interest.max_hold, interest.min_hold, 3600.0, "max_hold")?;
        check_range(interest.cooldown, 0.0, 3600.0, "cooldown")?;
        check_range(interest.warmup, 0.0, 3600.0, "warmup")?;
        check_range(interest.initial_threshold, 0.0, 1e6, "initial_threshold")?;
        let (low, high) = self.attention_fraction_range;
        let saliency = &self.saliency;
        check_range(saliency.eye_fixation, 1e-3, 60.0, "eye_fixation")?;
        check_range(saliency.head_fixation, 1e-3, 60.0, "head_fixation")?;
        check_range(
            saliency.random_pick_probability,
            0.0,
            1.0,
            "random_pick_probability",
        )?;
        check_range(saliency.social_weight, 0.0, 100.0, "social_weight")?;
        for weight in saliency.part_weights {
            check_range(weight, 0.0, 100.0, "part_weights")?;
        }
        check_range(self.scoring.talking_gain, 0.0, 100.0, "talking_gain")?;
        for (field, what) in [
            (saliency.eye_field, "eye field"),
            (saliency.head_field, "head field"),
        ] {
            check_range(field.half_horizontal, 0.0, std::f32::consts::PI, what)?;
            check_range(field.half_vertical, 0.0, std::f32::consts::FRAC_PI_2, what)?;
        }
        check_count(self.attention_period, 1, 64, "attention_period")?;
        check_count(self.far_attention_period, 1, 64, "far_attention_period")?;
        check_range(self.lod_distance, 0.0, 1e6, "lod_distance")?;
        check_count(self.threads, 0, MAX_THREADS, "threads")?;
        let baseline = &self.baseline;
        check_range(baseline.proximity_radius, 0.0, 1000.0, "proximity_radius")?;
        check_range(
            baseline.glance_interval_min,
            0.01,
            3600.0,
            "glance_interval_min",
        )?;
        check_range(
            baseline.glance_interval_max,
            baseline.glance_interval_min,
            3600.0,
            "glance_interval_max",
        )?;
        check_range(
            baseline.glance_away_probability,
            0.0,
            1.0,
            "glance_away_probability",
        )?;
        check_range(low, 0.0, 1.0, "attention_fraction_min")?;
        check_range(high, low, 1.0, "attention_fraction_max")?;
        self.blinks.validate()?;
        check_count(
            self.max_conversations,
            0,
            MAX_CAPACITY / 2,
            "max_conversations",
        )?;
        self.conversation.validate()?;
        self.street.validate()?;
        self.following.validate(self.scoring.max_distance)?;
        self.gaze.validate()
    }
}
