//! The crowd: owns every character and object, and steps attention for each character.
//!
//! Per frame: [`Crowd::push_frame`] ingests positions and headings (velocities by finite
//! difference), [`Crowd::step`] rebuilds the spatial grid and runs attention for every
//! character, and [`Crowd::gaze`] reads the result. Nothing in those allocates.
//!
//! Offline (the paper's own pipeline): with `max_recorded_states > 0`, pushed frames are
//! also recorded; [`Crowd::plan`] then scores the whole recording, computes each
//! character's exact percentile threshold and its list of constraints
//! (`entity, t_b, t_e`), and stepping replays the recording following that plan.

mod models;
mod pool;
mod states;
mod step;

pub use models::{GlanceState, Look, LookTarget, ModelState};
pub use step::StepRanges;

use glam::{Quat, Vec3};

use crate::alloc::{try_reserve, try_with_capacity, Field};
use crate::attention::baseline::BaselineConfig;
use crate::attention::candidates::{
    all_pairs_candidates, nearby_candidates, CandidateBatch, NeighbourIndex,
};
use crate::attention::interest::{Candidate, InterestConfig};
use crate::attention::plan::{Constraint, Plan, Recording};
use crate::attention::saliency::SaliencyConfig;
use crate::attention::score::{ScoreBreakdown, Scorer, ScoringConfig};
use crate::attention::{AttentionModel, CharacterParams, TargetPart};
use crate::error::{ensure_finite, Error, Result};
use crate::ik::{GazeChain, GazeConfig, GazeMotion, MAX_CHAIN_JOINTS};
use crate::math::packed::PackedQuat;
use crate::math::random::{stream, Purpose};
use crate::scene::ids::{EntityKind, NO_ENTITY};
use crate::scene::order::Reorder;
use crate::scene::{EntityUpdate, Scene};
use crate::world::World;
use models::social_parts;
use pool::WorkerPool;
use states::{AttentionLod, CharacterStates};
use step::{ClaimSet, Frame};

/// Gaze-request key of explicit point targets (entity ids are below 2³²).
const EXPLICIT_POINT_KEY: u64 = 1 << 32;

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
    /// [`Crowd::state_bytes_per_character`] bytes (under 1 KiB), allocated at creation.
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
    /// Every `reorder_period` steps (default 32; 0: never) the crowd stores its entities and
    /// characters again in the spatial grid's order, so that neighbours in space are
    /// neighbours in memory and a step reads its state in order (see [`Crowd`]). Results
    /// and the character order readers see do not depend on it.
    pub reorder_period: u32,
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
            reorder_period: 32,
        }
    }
}

fn check_range(value: f32, low: f32, high: f32, what: &str) -> Result<()> {
    ensure_finite(value, what)?;
    if value < low || value > high {
        return Err(Error::InvalidArgument(format!(
            "{what} is {value}, must be in [{low}, {high}]"
        )));
    }
    Ok(())
}

/// Checks that a count lies in `low..=high`.
fn check_count(value: u32, low: u32, high: u32, what: &str) -> Result<()> {
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
        self.gaze.validate()
    }
}

/// Where a character is looking, after a step.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GazeInfo {
    /// The character's id.
    pub character: u32,
    /// What the eyes look at: the interest point's (or the eye target's) entity id, or
    /// [`NO_ENTITY`] when looking ahead or at an explicit point.
    pub target: u32,
    /// Which part of `target` (always [`TargetPart::Whole`] for the crowd model).
    pub target_part: TargetPart,
    /// What the head looks at (the same as `target` but for the saliency and baseline
    /// models, whose head and eyes have separate targets).
    pub head_target: u32,
    /// The point the eyes are sent to (metres): the target's look-at point (or part), an
    /// explicit point, or the point 10 m ahead at eye height when there is none.
    pub target_position: Vec3,
    /// `S_max` this frame.
    pub s_max: f32,
    /// The attention threshold `A` this frame; `f32::MAX` when the character cannot attend
    /// (an attention fraction of 0, or no score planned for it).
    pub threshold: f32,
    /// True if the character attends to an interest point.
    pub attending: bool,
    /// Fraction of the observed time spent attending so far.
    pub attentive_fraction: f32,
    /// Interest points started so far.
    pub interest_count: u32,
}

/// A description of a new character.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CharacterDesc {
    /// Root position (metres).
    pub position: Vec3,
    /// Heading (radians).
    pub heading: f32,
    /// `I_E`, how interesting this character is to others (≥ 0). Default 1.
    pub impact: f32,
    /// Attention parameters; `None` draws them from the crowd's seed.
    pub params: Option<CharacterParams>,
    /// The gaze chain (metres, world axes at heading 0); `None` is the human chain of
    /// [`GazeChain::human`] for the crowd's axes.
    pub chain: Option<GazeChain>,
    /// The attention model (used when `params` is `None`; otherwise `params.model`).
    pub model: AttentionModel,
}

impl Default for CharacterDesc {
    fn default() -> Self {
        CharacterDesc {
            position: Vec3::ZERO,
            heading: 0.0,
            impact: 1.0,
            params: None,
            chain: None,
            model: AttentionModel::Crowd,
        }
    }
}

/// A target set by game logic (top-down attention), overriding or completing the
/// automatic interest point.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ExplicitTarget {
    /// A world point (metres).
    Point(Vec3),
    /// An entity's look-at point, followed as it moves.
    Entity(u32),
}

/// When an explicit target applies.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TargetPriority {
    /// Always: the automatic interest point is ignored until the target is cleared.
    Override,
    /// Only while the character has no automatic interest point.
    WhenIdle,
}

/// Where a character's eyes are and where they look, after a step (world, metres).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EyeState {
    /// The character's id.
    pub character: u32,
    /// Left and right eye positions (the head's position twice for a chain without eyes).
    pub origins: [Vec3; 2],
    /// Left and right unit gaze directions.
    pub directions: [Vec3; 2],
}

/// A description of a new scene object.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ObjectDesc {
    /// Root position (metres).
    pub position: Vec3,
    /// Heading (radians): its forward direction, for the orientation subscores.
    pub heading: f32,
    /// Height of its look-at point above the root (metres).
    pub look_at_height: f32,
    /// `I_E`, how interesting it is (≥ 0). Default 1.
    pub impact: f32,
}

impl Default for ObjectDesc {
    fn default() -> Self {
        ObjectDesc {
            position: Vec3::ZERO,
            heading: 0.0,
            look_at_height: 0.0,
            impact: 1.0,
        }
    }
}

/// A crowd of characters and the objects they may look at.
///
/// Not safe for concurrent mutation; shared (`&Crowd`) reads may run concurrently. A step
/// may be split into ranges of characters run on several threads: see
/// [`begin_step`](Self::begin_step).
///
/// Storage order: every [`CrowdConfig::reorder_period`] steps the crowd stores its entities
/// and characters again in the spatial grid's order, so that neighbours in space are
/// neighbours in memory and a step reads its arrays in order (in a large crowd, a character
/// created anywhere would otherwise cost a cache line and a page of its own). Ids stay; the
/// order readers see ([`gaze_dense`](Self::gaze_dense), [`read_joints`](Self::read_joints))
/// stays creation order; only the ranges of [`step_range`](Self::step_range) index the
/// storage order.
#[derive(Debug)]
pub struct Crowd {
    /// What every character's step reads.
    shared: Shared,
    /// What each character's step writes.
    states: CharacterStates,
    /// Which characters a ranged step has taken.
    claims: ClaimSet,
    /// The order in which attention visits characters, refreshed by each step: spatial-grid
    /// order in large crowds (neighbours' data stays in cache), dense order otherwise.
    /// Before that, on a step that reorders storage, the reordering's character permutation.
    grid_order: Vec<u32>,
    /// The characters in the order readers see (creation order, a removed character's place
    /// taken by the last one): the dense index of each.
    read_order: Vec<u32>,
    /// Scratch space of the reordering into grid order.
    reorder: Reorder,
    /// The step begun by [`begin_step`](Self::begin_step) and not yet ended.
    open_step: Option<Frame>,
    /// Worker threads of [`step`](Self::step), when `threads > 1`.
    pool: Option<WorkerPool>,
}

/// The part of a crowd that stepping a character only reads: the scene, its neighbour
/// index, chains, parameters and game-logic inputs.
#[derive(Debug)]
struct Shared {
    config: CrowdConfig,
    scorer: Scorer,
    scene: Scene,
    neighbours: NeighbourIndex,
    /// Per character (dense, like the scene's character list).
    params: Vec<CharacterParams>,
    /// Distinct gaze chains; characters share equal ones.
    chains: Vec<GazeChain>,
    /// Per chain: the five social target points (head, eyes, chest, torso) in the
    /// character's frame at rest.
    chain_parts: Vec<[Vec3; 5]>,
    /// The viewer's entity id, once set.
    viewer: Option<u32>,
    /// Steps taken so far (staggers the level-of-detail updates).
    steps: u64,
    /// Per character: index into `chains`.
    chain_of: Vec<u32>,
    /// Per chain: the rest pose of its joints (local rotations), the base of every
    /// character whose engine has not set one.
    chain_rests: Vec<[Quat; MAX_CHAIN_JOINTS]>,
    /// Per character: true once the engine set a base pose, held in `bases`.
    posed: Vec<bool>,
    /// Per character: the base pose the engine set (local rotations of its chain joints),
    /// packed in 8 bytes each (within 6e−6 rad, see [`PackedQuat`]).
    bases: Vec<[PackedQuat; MAX_CHAIN_JOINTS]>,
    /// Per character: explicit target from game logic.
    explicit: Vec<Option<(ExplicitTarget, TargetPriority)>>,
    /// Characters ever added: the index of each one's random stream.
    characters_created: u64,
    /// Time of the last pushed frame.
    time: f64,
    recording: Recording,
    plan: Option<Plan>,
}

impl Shared {
    /// A character's base pose (local rotations of its chain joints, the first
    /// `joint_count` used): its chain's rest pose, or the pose the engine set, unpacked.
    fn base_pose(&self, character: usize) -> [Quat; MAX_CHAIN_JOINTS] {
        if self.posed[character] {
            self.bases[character].map(PackedQuat::unpack)
        } else {
            self.chain_rests[self.chain_of[character] as usize]
        }
    }
}

impl Crowd {
    /// Creates an empty crowd, sizing every buffer from `config` (and starting its worker
    /// threads when `config.threads` asks for them).
    ///
    /// Errors: [`Error::InvalidArgument`] and [`Error::NonFinite`] (see
    /// [`CrowdConfig::validate`]), [`Error::OutOfMemory`] when the buffers of the capacities
    /// do not fit in memory (about [`state_bytes_per_character`](Self::state_bytes_per_character)
    /// per character and object, and [`Recording::bytes_per_state`] per recorded state),
    /// [`Error::Internal`] if a worker thread cannot be started. Nothing is left behind on
    /// error.
    pub fn new(config: CrowdConfig) -> Result<Crowd> {
        config.validate()?;
        // Every entity the scene may hold: characters, objects and the viewer.
        let capacity = (config.max_characters + config.max_objects + 1) as usize;
        let characters = config.max_characters as usize;
        let workers = config.worker_threads();
        let per_character = &Field("max_characters", config.max_characters.into());
        let per_entity = &Field(
            "max_characters + max_objects",
            u64::from(config.max_characters) + u64::from(config.max_objects),
        );
        let per_state = &Field("max_recorded_states", config.max_recorded_states.into());
        Ok(Crowd {
            shared: Shared {
                scorer: Scorer::new(config.scoring),
                // One object slot more than asked for: the viewer's (`capacity` counts it).
                scene: Scene::new(
                    config.world,
                    config.max_characters,
                    config.max_objects + 1,
                    per_entity,
                )?,
                neighbours: NeighbourIndex::new(capacity, config.scoring.max_distance, per_entity)?,
                params: try_with_capacity(characters, per_character)?,
                chains: Vec::new(),
                chain_parts: Vec::new(),
                chain_rests: Vec::new(),
                posed: try_with_capacity(characters, per_character)?,
                viewer: None,
                steps: 0,
                chain_of: try_with_capacity(characters, per_character)?,
                bases: try_with_capacity(characters, per_character)?,
                explicit: try_with_capacity(characters, per_character)?,
                characters_created: 0,
                time: f64::NEG_INFINITY,
                recording: Recording::new(config.max_recorded_states as usize, per_state)?,
                plan: None,
                config,
            },
            states: CharacterStates::with_capacity(characters, per_character)?,
            claims: ClaimSet::new(characters, per_character)?,
            grid_order: try_with_capacity(characters, per_character)?,
            read_order: try_with_capacity(characters, per_character)?,
            reorder: Reorder::new(capacity, per_entity)?,
            open_step: None,
            pool: (workers > 0)
                .then(|| WorkerPool::new(workers))
                .transpose()?,
        })
    }

    /// The configuration the crowd was created with.
    pub fn config(&self) -> &CrowdConfig {
        &self.shared.config
    }

    /// The scene (entities and their current state).
    pub fn scene(&self) -> &Scene {
        &self.shared.scene
    }

    /// Number of characters.
    pub fn character_count(&self) -> usize {
        self.shared.scene.character_count()
    }

    fn check_impact(impact: f32) -> Result<()> {
        check_range(impact, 0.0, 1e6, "impact")
    }

    fn check_params(params: &CharacterParams) -> Result<()> {
        crate::error::ensure_all_finite(&params.weights.to_array(), "weights")?;
        let sum: f32 = params.weights.to_array().iter().sum();
        if params.weights.to_array().iter().any(|w| *w < 0.0) || (sum - 1.0).abs() > 1e-3 {
            return Err(Error::InvalidArgument(
                "weights must be non-negative and sum to 1".into(),
            ));
        }
        check_range(params.attention_fraction, 0.0, 1.0, "attention_fraction")
    }

    /// Adds a character; returns its id.
    pub fn add_character(&mut self, desc: &CharacterDesc) -> Result<u32> {
        crate::error::ensure_all_finite(&desc.position.to_array(), "position")?;
        ensure_finite(desc.heading, "heading")?;
        Self::check_impact(desc.impact)?;
        if let Some(params) = &desc.params {
            Self::check_params(params)?;
        }
        self.ensure_online("add a character")?;
        let params = desc.params.unwrap_or_else(|| {
            let mut random = stream(
                self.shared.config.seed,
                Purpose::CharacterParams,
                self.shared.characters_created,
            );
            let mut params =
                CharacterParams::random(&mut random, self.shared.config.attention_fraction_range);
            params.model = desc.model;
            params
        });
        let world = self.shared.config.world;
        let chain = match desc.chain {
            Some(chain) => {
                chain.validate()?;
                chain
            }
            None => GazeChain::human(world.up, world.forward),
        };
        let known_chain = self.shared.chains.iter().position(|known| *known == chain);
        if known_chain.is_none()
            && self.character_count() < self.shared.config.max_characters as usize
        {
            // Room for a new distinct chain, before anything changes.
            let what = &Field("distinct gaze chains", self.shared.chains.len() as u64 + 1);
            try_reserve(&mut self.shared.chains, 1, what)?;
            try_reserve(&mut self.shared.chain_parts, 1, what)?;
            try_reserve(&mut self.shared.chain_rests, 1, what)?;
        }
        let id = self.shared.scene.add(
            EntityKind::Character,
            desc.position,
            desc.heading,
            chain.look_at_height(world.up),
            desc.impact,
        )?;
        let chain_index = match known_chain {
            Some(index) => index,
            None => {
                self.shared.chains.push(chain);
                self.shared.chain_parts.push(social_parts(&chain, world.up));
                let mut rest = [Quat::IDENTITY; MAX_CHAIN_JOINTS];
                for (slot, joint) in rest.iter_mut().zip(chain.joints()) {
                    *slot = joint.rest;
                }
                self.shared.chain_rests.push(rest);
                self.shared.chains.len() - 1
            }
        };
        let created = self.shared.characters_created;
        let seed = self.shared.config.seed;
        self.shared.chain_of.push(chain_index as u32);
        self.shared
            .bases
            .push([PackedQuat::IDENTITY; MAX_CHAIN_JOINTS]);
        self.shared.posed.push(false);
        self.shared.explicit.push(None);
        self.shared.params.push(params);
        self.shared.characters_created += 1;
        self.states.push(
            AttentionLod {
                stagger: (created % 64) as u32,
                period: 0,
                pending: 0.0,
            },
            ModelState::new(
                params.model,
                params.attention_fraction,
                &self.shared.config.interest,
            ),
            GazeMotion::new(&chain),
            stream(seed, Purpose::Saliency, created),
            stream(seed, Purpose::GazeTiming, created),
        );
        // The new character is the last both in dense order and in readers' order.
        self.read_order.push(self.read_order.len() as u32);
        Ok(id)
    }

    /// Adds a scene object; returns its id.
    pub fn add_object(&mut self, desc: &ObjectDesc) -> Result<u32> {
        crate::error::ensure_all_finite(&desc.position.to_array(), "position")?;
        ensure_finite(desc.heading, "heading")?;
        check_range(desc.look_at_height, -1e6, 1e6, "look_at_height")?;
        Self::check_impact(desc.impact)?;
        self.ensure_online("add an object")?;
        let objects = self.shared.scene.len()
            - self.character_count()
            - usize::from(self.shared.viewer.is_some());
        if objects >= self.shared.config.max_objects as usize {
            return Err(Error::Capacity(format!(
                "the crowd already holds max_objects = {} objects",
                self.shared.config.max_objects
            )));
        }
        self.shared.scene.add(
            EntityKind::Object,
            desc.position,
            desc.heading,
            desc.look_at_height,
            desc.impact,
        )
    }

    /// Removes a character or object. Characters looking at it look elsewhere.
    pub fn remove_entity(&mut self, id: u32) -> Result<()> {
        self.shared.scene.find(id)?;
        self.ensure_online("remove an entity")?;
        if let Some(slot) = self.shared.scene.remove(id)? {
            let slot = slot as usize;
            self.shared.params.swap_remove(slot);
            self.shared.chain_of.swap_remove(slot);
            self.shared.bases.swap_remove(slot);
            self.shared.posed.swap_remove(slot);
            self.shared.explicit.swap_remove(slot);
            self.states.swap_remove(slot);
            // Readers' order: the last character read takes the removed one's place, and the
            // last dense character (moved to `slot` above) is found at its new index.
            let last = self.read_order.len() - 1;
            if let Some(position) = self.read_order.iter().position(|&c| c as usize == slot) {
                self.read_order.swap_remove(position);
            }
            if let Some(moved) = self.read_order.iter_mut().find(|c| **c as usize == last) {
                *moved = slot as u32;
            }
        }
        if self.shared.viewer == Some(id) {
            self.shared.viewer = None;
        }
        for model in &mut self.states.models {
            model.forget(id);
        }
        for explicit in &mut self.shared.explicit {
            if matches!(explicit, Some((ExplicitTarget::Entity(target), _)) if *target == id) {
                *explicit = None;
            }
        }
        Ok(())
    }

    fn ensure_online(&self, what: &str) -> Result<()> {
        if self.open_step.is_some() {
            return Err(Error::WrongState(format!(
                "cannot {what} while a step is open (end it first)"
            )));
        }
        if self.shared.plan.is_some() {
            return Err(Error::WrongState(format!(
                "cannot {what} while a plan is active (clear it first)"
            )));
        }
        Ok(())
    }

    /// A character's attention parameters.
    pub fn character_params(&self, id: u32) -> Result<CharacterParams> {
        Ok(self.shared.params[self.shared.scene.character_index(id)?])
    }

    /// Replaces a character's attention parameters (weights must sum to 1). Changing the
    /// attention fraction restarts its percentile estimate; switching to or from the crowd
    /// model starts the new model's state afresh (see [`ModelState`]).
    pub fn set_character_params(&mut self, id: u32, params: &CharacterParams) -> Result<()> {
        let index = self.shared.scene.character_index(id)?;
        Self::check_params(params)?;
        let model = &mut self.states.models[index];
        if !model.serves(params.model) {
            *model = ModelState::new(
                params.model,
                params.attention_fraction,
                &self.shared.config.interest,
            );
        } else if params.attention_fraction != self.shared.params[index].attention_fraction {
            if let ModelState::Crowd(tracker) = model {
                tracker.set_attention_fraction(params.attention_fraction);
            }
        }
        self.shared.params[index] = *params;
        Ok(())
    }

    /// Sets an entity's impact factor `I_E` (≥ 0).
    pub fn set_impact(&mut self, id: u32, impact: f32) -> Result<()> {
        let (_, index) = self.shared.scene.find(id)?;
        Self::check_impact(impact)?;
        self.shared.scene.set_impact(index, impact);
        Ok(())
    }

    /// Time of the last pushed frame (−∞ before the first).
    pub fn time(&self) -> f64 {
        self.shared.time
    }

    /// Ingests one frame of entity states at time `time` (seconds, not earlier than the
    /// previous frame). Entities not listed keep their last state. With recording on, the
    /// states are also recorded for [`plan`](Self::plan). Fails without changing anything
    /// on an unknown id, a non-finite value, an earlier time, a full recording, or while a
    /// plan is active.
    pub fn push_frame(&mut self, time: f64, updates: &[EntityUpdate]) -> Result<()> {
        self.push_frame_with(time, updates.len(), |i| Ok(updates[i]))
    }

    /// [`push_frame`](Self::push_frame) for states produced on the fly: `state(i)` for
    /// `i < count` converts the caller's i-th state (it is called twice per state: once to
    /// check them all, once to apply). Lets a caller hand over its own layout without a
    /// buffer.
    pub fn push_frame_with<E: From<Error>>(
        &mut self,
        time: f64,
        count: usize,
        state: impl Fn(usize) -> std::result::Result<EntityUpdate, E>,
    ) -> std::result::Result<(), E> {
        if !time.is_finite() {
            return Err(Error::NonFinite(format!("frame time is {time}")).into());
        }
        if time < self.shared.time {
            return Err(Error::InvalidArgument(format!(
                "frame time {time} is earlier than the previous frame's {}",
                self.shared.time
            ))
            .into());
        }
        self.ensure_online("push a frame")?;
        for i in 0..count {
            self.shared.scene.check_update(&state(i)?)?;
        }
        if self.shared.recording.is_enabled() {
            self.shared
                .recording
                .record_with(time, count, |i| state(i).ok())?;
        }
        for i in 0..count {
            if let Ok(update) = state(i) {
                self.shared.scene.apply_one(time, &update);
            }
        }
        self.shared.time = time;
        Ok(())
    }

    /// The best and second-best entities for a character (by dense index) among those near
    /// it, skipping itself and entities on cool-down, on the index of the last step.
    fn best_nearby(&self, character: usize) -> (Candidate, Candidate) {
        let tracker = self.states.models[character].tracker();
        nearby_candidates(
            &self.shared.scene,
            &self.shared.neighbours,
            &self.shared.scorer,
            character,
            &self.shared.params[character].weights,
            &mut CandidateBatch::default(),
            |id| tracker.is_some_and(|tracker| tracker.is_cooling(id)),
        )
    }

    /// The same as the grid search, by scoring every entity (the all-pairs loop): a test
    /// oracle and the baseline of the benchmarks.
    pub fn best_all_pairs(&self, character_id: u32) -> Result<(Candidate, Candidate)> {
        let character = self.shared.scene.character_index(character_id)?;
        Ok(self.all_pairs_of(character))
    }

    /// [`best_all_pairs`](Self::best_all_pairs) by position in the character order (see
    /// [`gaze_dense`](Self::gaze_dense)). Panics if `position` is out of range.
    pub fn best_all_pairs_dense(&self, position: usize) -> (Candidate, Candidate) {
        self.all_pairs_of(self.dense_index(position))
    }

    /// The dense index (where its state is stored) of the character at `position` in the
    /// character order readers see. Panics if `position` is out of range.
    fn dense_index(&self, position: usize) -> usize {
        self.read_order[position] as usize
    }

    fn all_pairs_of(&self, character: usize) -> (Candidate, Candidate) {
        let tracker = self.states.models[character].tracker();
        all_pairs_candidates(
            &self.shared.scene,
            &self.shared.scorer,
            character,
            &self.shared.params[character].weights,
            |id| tracker.is_some_and(|tracker| tracker.is_cooling(id)),
        )
    }

    /// The grid search for one character by id, on the grid of the last step.
    pub fn best_nearby_by_id(&self, character_id: u32) -> Result<(Candidate, Candidate)> {
        let character = self.shared.scene.character_index(character_id)?;
        Ok(self.best_nearby(character))
    }

    /// Rebuilds the spatial grid from the current positions (done by every step).
    pub fn rebuild_grid(&mut self) {
        self.shared.neighbours.rebuild(&self.shared.scene);
    }

    /// Scores one (character, entity) pair on the current state, with every intermediate.
    pub fn score(&self, character_id: u32, entity_id: u32) -> Result<ScoreBreakdown> {
        let character = self.shared.scene.character_index(character_id)?;
        let (_, entity) = self.shared.scene.find(entity_id)?;
        let observer = self
            .shared
            .scene
            .ground_state(self.shared.scene.character_entities()[character] as usize);
        Ok(self.shared.scorer.score(
            &observer,
            &self.shared.scene.ground_state(entity),
            &self.shared.params[character].weights,
            self.shared.scene.impacts()[entity],
        ))
    }

    /// Where the character at `position` in the crowd's character order looks now. That
    /// order is creation order, except that removing a character moves the last one into
    /// its place; the crowd's own storage order (spatial, see [`Crowd`]) never shows
    /// through. Panics if `position` is out of range.
    pub fn gaze_dense(&self, position: usize) -> GazeInfo {
        self.gaze_of(self.dense_index(position))
    }

    /// Where a character (by dense index) looks now.
    fn gaze_of(&self, character: usize) -> GazeInfo {
        let entity = self.shared.scene.character_entities()[character] as usize;
        let tracker = self.states.models[character].tracker();
        let (target, s_max, threshold, attentive_fraction, interest_count) = match &self.shared.plan
        {
            Some(plan) => {
                let (target, s_max, threshold) = plan.current(character);
                let count = plan.constraints(character).len() as u32;
                (
                    target,
                    s_max,
                    threshold,
                    plan.attentive_fraction(character),
                    count,
                )
            }
            None => match tracker {
                Some(tracker) => {
                    let (attentive, observed) = tracker.attentive_seconds();
                    let fraction = if observed > 0.0 {
                        attentive / observed
                    } else {
                        0.0
                    };
                    (
                        tracker.interest(),
                        tracker.s_max(),
                        tracker.threshold(),
                        fraction,
                        tracker.interest_count(),
                    )
                }
                // Characters of the saliency and baseline models report what a fresh
                // tracker would: no interest point, the initial threshold.
                None => (
                    NO_ENTITY,
                    0.0,
                    self.shared.config.interest.initial_threshold,
                    0.0,
                    0,
                ),
            },
        };
        let view = self.states.view(character);
        let look = self.shared.current_look(character, view);
        let target_position = match self.shared.gaze_request(character, view) {
            Some(request) => request.eye_target,
            None => {
                let ahead = self
                    .shared
                    .config
                    .world
                    .heading_direction(self.shared.scene.headings()[entity]);
                self.shared.scene.look_at_point(entity) + ahead * 10.0
            }
        };
        let exists = |id: u32| self.shared.scene.index_of(id).is_some();
        let known = |id: u32| if exists(id) { id } else { NO_ENTITY };
        let attending = match self.shared.params[character].model {
            AttentionModel::Crowd => exists(target),
            _ => exists(look.eye.entity) || exists(look.head.entity),
        };
        GazeInfo {
            character: self.shared.scene.ids()[entity],
            target: known(look.eye.entity),
            target_part: look.eye.part,
            head_target: known(look.head.entity),
            target_position,
            s_max,
            // The trackers and the plan use +inf for "never"; callers get a finite value.
            threshold: threshold.min(f32::MAX),
            attending,
            attentive_fraction,
            interest_count,
        }
    }

    /// Where a character looks now, by id.
    pub fn gaze(&self, character_id: u32) -> Result<GazeInfo> {
        Ok(self.gaze_of(self.shared.scene.character_index(character_id)?))
    }

    /// A character's gaze chain.
    pub fn chain(&self, character_id: u32) -> Result<&GazeChain> {
        Ok(self.chain_of(self.shared.scene.character_index(character_id)?))
    }

    /// Number of chain joints of the characters `first .. first + count` (in the character
    /// order, see [`gaze_dense`](Self::gaze_dense)) together: the length of their packed
    /// joint outputs.
    pub fn joint_total(&self, first: usize, count: usize) -> Result<usize> {
        let range = self.character_range(first, count)?;
        Ok(self.read_order[range]
            .iter()
            .map(|&character| self.chain_of(character as usize).joint_count())
            .sum())
    }

    fn chain_of(&self, character: usize) -> &GazeChain {
        &self.shared.chains[self.shared.chain_of[character] as usize]
    }

    fn character_range(&self, first: usize, count: usize) -> Result<std::ops::Range<usize>> {
        let characters = self.character_count();
        match first.checked_add(count) {
            Some(end) if end <= characters => Ok(first..end),
            _ => Err(Error::InvalidArgument(format!(
                "characters {first} .. {first} + {count} are out of range: there are {characters}"
            ))),
        }
    }

    /// Sets a character's base pose: the local rotation of each chain joint, bottom to top
    /// (the engine's animated pose; the rest pose until set). Rotations are normalised.
    pub fn set_base_pose(&mut self, character_id: u32, local: &[Quat]) -> Result<()> {
        let character = self.shared.scene.character_index(character_id)?;
        let joints = self.shared.chains[self.shared.chain_of[character] as usize].joint_count();
        if local.len() != joints {
            return Err(Error::InvalidArgument(format!(
                "the base pose has {} rotations, the chain {joints} joints",
                local.len()
            )));
        }
        let mut base = [PackedQuat::IDENTITY; MAX_CHAIN_JOINTS];
        for (slot, rotation) in base.iter_mut().zip(local) {
            crate::error::ensure_all_finite(&rotation.to_array(), "base pose")?;
            let length = rotation.length();
            if length <= 1e-6 {
                return Err(Error::InvalidArgument(
                    "a base rotation has length 0".into(),
                ));
            }
            *slot = PackedQuat::pack(*rotation / length);
        }
        self.shared.bases[character] = base;
        self.shared.posed[character] = true;
        Ok(())
    }

    /// Gives a character an explicit target until [`clear_gaze_target`](Self::clear_gaze_target).
    pub fn set_gaze_target(
        &mut self,
        character_id: u32,
        target: ExplicitTarget,
        priority: TargetPriority,
    ) -> Result<()> {
        let character = self.shared.scene.character_index(character_id)?;
        match target {
            ExplicitTarget::Point(point) => {
                crate::error::ensure_all_finite(&point.to_array(), "target point")?
            }
            ExplicitTarget::Entity(id) => {
                self.shared.scene.find(id)?;
                if id == character_id {
                    return Err(Error::InvalidArgument(
                        "a character cannot look at itself".into(),
                    ));
                }
            }
        }
        self.shared.explicit[character] = Some((target, priority));
        Ok(())
    }

    /// Removes a character's explicit target; its automatic attention takes over again.
    pub fn clear_gaze_target(&mut self, character_id: u32) -> Result<()> {
        let character = self.shared.scene.character_index(character_id)?;
        self.shared.explicit[character] = None;
        Ok(())
    }

    /// Writes the chain joints of characters `first .. first + count` (in the character
    /// order, see [`gaze_dense`](Self::gaze_dense)) into `out`, packed one chain after
    /// another, bottom to top: the final local rotations `base * delta`, or the deltas
    /// alone with `deltas_only`. `out` must hold [`joint_total`](Self::joint_total)
    /// rotations; returns how many were written.
    pub fn read_joints(
        &self,
        first: usize,
        count: usize,
        deltas_only: bool,
        out: &mut [Quat],
    ) -> Result<usize> {
        let total = self.joint_total(first, count)?;
        if out.len() < total {
            return Err(Error::InvalidArgument(format!(
                "the output holds {} rotations, {total} are needed",
                out.len()
            )));
        }
        let mut written = 0;
        for &character in &self.read_order[first..first + count] {
            written += self.write_joints(character as usize, deltas_only, &mut out[written..]);
        }
        Ok(written)
    }

    /// [`read_joints`](Self::read_joints) for one character, by id: `out` must hold its
    /// chain's joint count of rotations; returns how many were written.
    pub fn read_joints_of(
        &self,
        character_id: u32,
        deltas_only: bool,
        out: &mut [Quat],
    ) -> Result<usize> {
        let character = self.shared.scene.character_index(character_id)?;
        let joints = self.chain_of(character).joint_count();
        if out.len() < joints {
            return Err(Error::InvalidArgument(format!(
                "the output holds {} rotations, {joints} are needed",
                out.len()
            )));
        }
        Ok(self.write_joints(character, deltas_only, out))
    }

    /// Writes the chain joints of the character at dense index `character` to the start of
    /// `out` (which holds them all); returns how many.
    fn write_joints(&self, character: usize, deltas_only: bool, out: &mut [Quat]) -> usize {
        let deltas = self.states.motions[character].deltas();
        let base = self.shared.base_pose(character);
        for ((slot, delta), base) in out.iter_mut().zip(deltas).zip(&base) {
            *slot = if deltas_only { *delta } else { *base * *delta };
        }
        deltas.len()
    }

    /// Where the eyes of the character at `position` in the character order (see
    /// [`gaze_dense`](Self::gaze_dense)) are and look after the last step. Panics if
    /// `position` is out of range.
    pub fn eyes_dense(&self, position: usize) -> EyeState {
        let character = self.dense_index(position);
        let motion = &self.states.motions[character];
        let entity = self.shared.scene.character_entities()[character] as usize;
        EyeState {
            character: self.shared.scene.ids()[entity],
            origins: motion.eye_origins(),
            directions: motion.eye_directions(),
        }
    }

    /// A character's gaze motion (phase, timing), by id.
    pub fn gaze_motion(&self, character_id: u32) -> Result<&GazeMotion> {
        Ok(&self.states.motions[self.shared.scene.character_index(character_id)?])
    }

    /// Sets how often a character's attention is updated: every `period` steps (1 to 64),
    /// or 0 for the crowd's level of detail (`attention_period`, or `far_attention_period`
    /// beyond `lod_distance` from the viewer). Gaze IK still runs every step.
    pub fn set_attention_period(&mut self, character_id: u32, period: u32) -> Result<()> {
        let character = self.shared.scene.character_index(character_id)?;
        check_count(period, 0, 64, "period")?;
        self.states.lod[character].period = period;
        Ok(())
    }

    /// Bytes of state the crowd keeps per character: its per-character arrays, its entity's
    /// share of the scene and the neighbour index, and the step's per-character scratch
    /// (visiting order, and two bit sets counted as one byte). All are buffers sized at
    /// creation.
    pub fn state_bytes_per_character() -> usize {
        use std::mem::size_of;
        let per_character = size_of::<CharacterParams>()
            + size_of::<u32>() // chain index
            + size_of::<[PackedQuat; MAX_CHAIN_JOINTS]>()
            + size_of::<bool>() // posed
            + size_of::<Option<(ExplicitTarget, TargetPriority)>>()
            + size_of::<u32>() // place in the readers' order
            + size_of::<u32>() // attention's visiting order (scratch)
            + 1 // a bit each of the ranged step's claims and the reordering (scratch)
            + states::bytes_per_character();
        per_character + Scene::bytes_per_entity() + NeighbourIndex::bytes_per_entity()
    }

    /// Plans attention offline over the recorded frames (see the module docs). Requires
    /// `max_recorded_states > 0` and at least one recorded frame. The plan holds about
    /// 8 bytes per recorded frame and character (25 while planning): when that does not
    /// fit in memory this fails with [`Error::OutOfMemory`] and changes nothing.
    pub fn plan(&mut self) -> Result<()> {
        self.ensure_online("plan again")?;
        if self.shared.recording.frame_count() == 0 {
            return Err(Error::WrongState(
                "nothing recorded: set max_recorded_states and push frames before planning".into(),
            ));
        }
        let plan = Plan::build(
            &self.shared.recording,
            &mut self.shared.scene,
            &mut self.shared.neighbours,
            &self.shared.scorer,
            &self.shared.params,
            &self.shared.config.interest,
        )?;
        self.shared.plan = Some(plan);
        Ok(())
    }

    /// Leaves planned mode and forgets the recording; pushing frames works again.
    pub fn clear_plan(&mut self) {
        self.shared.plan = None;
        self.shared.recording.clear();
    }

    /// True while stepping follows a plan.
    pub fn is_planned(&self) -> bool {
        self.shared.plan.is_some()
    }

    /// A character's planned constraints (entity, `t_b`, `t_e`), in time order.
    pub fn constraints(&self, character_id: u32) -> Result<&[Constraint]> {
        let character = self.shared.scene.character_index(character_id)?;
        let plan = self
            .shared
            .plan
            .as_ref()
            .ok_or_else(|| Error::WrongState("no plan: call plan() first".into()))?;
        Ok(plan.constraints(character))
    }

    /// A character's planned threshold `A` (the exact percentile).
    pub fn planned_threshold(&self, character_id: u32) -> Result<f32> {
        let character = self.shared.scene.character_index(character_id)?;
        let plan = self
            .shared
            .plan
            .as_ref()
            .ok_or_else(|| Error::WrongState("no plan: call plan() first".into()))?;
        Ok(plan.threshold(character))
    }
}

#[cfg(test)]
mod tests;
