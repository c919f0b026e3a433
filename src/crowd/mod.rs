//! The crowd: owns every character and object, and steps attention and gaze for each.
//!
//! A frame, as an engine runs it:
//!
//! 1. **Ingest** ([`Crowd::push_frame`], `ingest.rs`): positions and headings of the
//!    entities (velocities by finite difference), checked, into the scene; or in ranges
//!    from several threads ([`Crowd::begin_push`], [`PushRanges::push`], [`Crowd::end_push`]).
//! 2. **Begin the step** ([`Crowd::begin_step`], `step.rs`): the plan's clock, the spatial
//!    grid, every `reorder_period` steps the storage order, the frame's shared values.
//! 3. **The attention job** (`attention_job.rs`, with `attention_models.rs`): each
//!    character's attention model picks what it attends to.
//! 4. **The gaze job** (`gaze_job.rs`): each character's spine, neck, head and eyes turn
//!    towards that target (what it looks at is resolved in `look.rs`), and it blinks
//!    (`blinks.rs`).
//! 5. **Read back** ([`Crowd::gaze_at`], [`Crowd::read_joints`], [`Crowd::eyelids_at`],
//!    `readback.rs`): where characters look, their joint rotations, eyes and eyelids, in
//!    the order the engine created them.
//!
//! [`Crowd::step`] runs 2 to 4 on the crowd's worker threads; an engine with its own job
//! system runs the same jobs in ranges ([`Crowd::begin_step`], [`StepRanges::run_range`],
//! [`Crowd::end_step`], `ranges.rs`). Nothing in a frame allocates.
//!
//! Around the frame: the crowd's settings (`config.rs`), the values its API takes and
//! returns (`values.rs`), adding and changing entities (`entities.rs`), the per-character
//! tables and shared chains a step reads (`tables.rs`) and the arrays it writes
//! (`states.rs`, `model_state.rs`), the offline plan (`planning.rs`), tools and oracles
//! (`diagnostics.rs`) and the worker threads (`pool.rs`).
//!
//! Offline (the paper's own pipeline): with `max_recorded_states > 0`, pushed frames are
//! also recorded; [`Crowd::plan`] then scores the whole recording, computes each
//! character's exact percentile threshold and its list of constraints
//! (`entity, t_b, t_e`), and stepping replays the recording following that plan.

mod attention_job;
mod attention_models;
mod blinks;
mod claims;
mod config;
mod conversation_ids;
mod conversation_look;
mod conversation_table;
mod conversations;
mod diagnostics;
mod entities;
mod gaze_job;
mod ingest;
mod look;
mod model_state;
mod outputs;
mod planning;
mod pool;
mod published;
mod ranges;
mod readback;
mod states;
mod step;
mod tables;
mod values;

pub use config::{CrowdConfig, EyeMotion, MAX_CAPACITY, MAX_THREADS};
pub use ingest::PushRanges;
pub use model_state::{GlanceState, Look, LookTarget, ModelState, SaliencyState};
pub use ranges::StepRanges;
pub use step::MAX_SIMULATED_STEP;
pub use values::{
    CharacterDesc, ExplicitTarget, EyeState, EyelidState, GazeInfo, ObjectDesc, TargetPriority,
};

use crate::alloc::{try_with_capacity, Field};
use crate::attention::candidates::NeighbourIndex;
use crate::attention::following::Cue;
use crate::attention::plan::{Plan, Recording};
use crate::attention::score::Scorer;
use crate::error::Result;
use crate::scene::order::Reorder;
use crate::scene::Scene;
use attention_job::Frame;
use claims::ClaimSet;
use conversation_table::Conversations;
use pool::WorkerPool;
use published::{Published, Watched};
use states::CharacterStates;
use tables::{Chains, Characters};

/// A crowd of characters and the objects they may look at.
///
/// Not safe for concurrent mutation; shared (`&Crowd`) reads may run concurrently. A step
/// may be split into ranges of characters run on several threads: see
/// [`begin_step`](Self::begin_step); a frame's push into parts pushed from several threads:
/// see [`begin_push`](Self::begin_push).
///
/// Storage order: every [`CrowdConfig::reorder_period`] steps the crowd stores its entities
/// and characters again in the spatial grid's order, so that neighbours in space are
/// neighbours in memory and a step reads its arrays in order (in a large crowd, a character
/// created anywhere would otherwise cost a cache line and a page of its own). Ids stay; the
/// order readers see ([`gaze_at`](Self::gaze_at), [`read_joints`](Self::read_joints))
/// stays creation order; only the ranges of [`step_range`](Self::step_range) index the
/// storage order.
#[derive(Debug)]
pub struct Crowd {
    /// What every character's step reads.
    shared: Watched<Shared>,
    /// What each character's step writes.
    states: Watched<CharacterStates>,
    /// The last step's outputs in the readers' order, while `shared` and `states` have not
    /// changed since.
    published: Published,
    /// Which characters a ranged step has taken.
    claims: ClaimSet,
    /// Which entities the open ranged push has taken.
    pushed: ClaimSet,
    /// The order in which attention visits characters, refreshed by each step: spatial-grid
    /// order in large crowds (neighbours' data stays in cache), dense order otherwise.
    /// Before that, on a step that reorders storage, the reordering's character permutation.
    /// Between steps, a push's scratch: the entity index of each pushed state. Room for
    /// every entity.
    grid_order: Vec<u32>,
    /// The characters in the order readers see (creation order, a removed character's place
    /// taken by the last one): the dense index of each.
    read_order: Vec<u32>,
    /// Scratch space of the reordering into grid order.
    reorder: Reorder,
    /// The step begun by [`begin_step`](Self::begin_step) and not yet ended.
    open_step: Option<Frame>,
    /// The time of the push begun by [`begin_push`](Self::begin_push) and not yet ended.
    open_push: Option<f64>,
    /// Worker threads of [`step`](Self::step), when `threads > 1`.
    pool: Option<WorkerPool>,
}

/// The part of a crowd that stepping a character only reads: the scene and its neighbour
/// index, the per-character tables and chains, the plan; and the crowd's clock.
#[derive(Debug)]
struct Shared {
    config: CrowdConfig,
    scorer: Scorer,
    scene: Scene,
    neighbours: NeighbourIndex,
    /// Per character (dense, like the scene's character list): parameters, chain, base
    /// pose, explicit target, place in a conversation.
    characters: Characters,
    /// Distinct gaze chains; characters share equal ones.
    chains: Chains,
    /// The viewer's entity id, once set.
    viewer: Option<u32>,
    /// Steps taken so far (staggers the level-of-detail updates).
    steps: u64,
    /// Characters ever added: the index of each one's random stream.
    characters_created: u64,
    /// Time of the last pushed frame.
    time: f64,
    recording: Recording,
    plan: Option<Plan>,
    /// The groups standing together and talking.
    conversations: Conversations,
    /// Each character's gaze cue this step (what gaze following sees of it), gathered as
    /// the step begins; sized at creation when following is on, empty otherwise.
    cues: Vec<Cue>,
}

impl Crowd {
    /// Creates an empty crowd, sizing every buffer from `config` (and starting its worker
    /// threads when `config.threads` asks for them).
    ///
    /// Errors: [`Error::InvalidArgument`] and [`Error::NonFinite`] (see
    /// [`CrowdConfig::validate`]), [`Error::OutOfMemory`] when the buffers of the capacities
    /// do not fit in memory (about [`state_bytes_per_character`](Self::state_bytes_per_character)
    /// and [`output_bytes_per_character`](Self::output_bytes_per_character) per character
    /// and object, and [`Recording::bytes_per_state`] per recorded state),
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
            shared: Watched::new(Shared {
                scorer: Scorer::new(config.scoring),
                // One object slot more than asked for: the viewer's (`capacity` counts it).
                scene: Scene::new(
                    config.world,
                    config.max_characters,
                    config.max_objects + 1,
                    per_entity,
                )?,
                neighbours: NeighbourIndex::new(capacity, config.scoring.max_distance, per_entity)?,
                characters: Characters::with_capacity(characters, per_character)?,
                chains: Chains::default(),
                viewer: None,
                steps: 0,
                characters_created: 0,
                time: f64::NEG_INFINITY,
                recording: Recording::new(config.max_recorded_states as usize, per_state)?,
                plan: None,
                conversations: Conversations::new(
                    config.max_conversations,
                    &Field("max_conversations", config.max_conversations.into()),
                )?,
                cues: if config.following.enabled {
                    try_with_capacity(characters, per_character)?
                } else {
                    Vec::new()
                },
                config,
            }),
            states: Watched::new(CharacterStates::with_capacity(characters, per_character)?),
            published: Published::with_capacity(characters, per_character)?,
            claims: ClaimSet::new(characters, per_character)?,
            pushed: ClaimSet::new(capacity, per_entity)?,
            grid_order: try_with_capacity(capacity, per_entity)?,
            read_order: try_with_capacity(characters, per_character)?,
            reorder: Reorder::new(capacity, per_entity)?,
            open_step: None,
            open_push: None,
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
}

#[cfg(test)]
mod tests;
