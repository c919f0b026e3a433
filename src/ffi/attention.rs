//! C entry points of crowd attention: adding and removing entities, reading where
//! characters look, scoring a pair, and offline planning. (Pushing frames and stepping are
//! in `frame`.)

use glam::Vec3;

use super::chain::cg_chain_desc;
use super::crowd::{cg_crowd, crowd_mut, crowd_ref};
use super::error::Result;
use super::types::cg_vec3;
use super::{
    cg_status, ffi_boundary, read_versioned, write_optional, write_versioned, Out, Versioned,
};
use crate::attention::score::SubscoreWeights;
use crate::attention::{AttentionModel, CharacterParams};
use crate::crowd::{CharacterDesc, ObjectDesc};
use crate::error::{ensure_finite, Error};
use crate::world::World;

/// The id meaning "no entity": the target of a character that looks ahead.
pub const CG_NO_TARGET: u32 = u32::MAX;

/// `cg_entity_state.flags`: derive the heading from the direction of motion (the velocity
/// projected on the ground); below 0.1 m/s the last heading is kept. `heading` is then not
/// read at all: any value, NaN included, is accepted.
pub const CG_STATE_HEADING_FROM_MOTION: u32 = 1;
/// `cg_entity_state.flags`: `velocity` is given; otherwise it is the difference with the
/// entity's previous pushed position divided by the elapsed time.
pub const CG_STATE_HAS_VELOCITY: u32 = 2;
/// `cg_entity_state.flags`: the entity talks in this frame (lip-sync, chat, dialogue). A
/// talking entity is more interesting to the crowd model and the saliency model
/// (`cg_crowd_config.talking_gain`) and draws the baseline's head turns; in a conversation
/// (`cg_crowd_set_conversation`) it is the speaker the others listen to.
pub const CG_STATE_TALKING: u32 = 4;

/// Which model decides where a character looks (`cg_character_desc.attention_model`,
/// `cg_character_params.attention_model`).
#[repr(u32)]
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum cg_attention_model {
    /// Grillon & Thalmann 2009: one interest point for the whole gaze chain (default).
    Crowd = 0,
    /// Kokkinara, Oyekoya & Steed 2011: separate saliency-driven targets for eyes and head.
    Saliency = 1,
    /// The stock virtual-world behaviour: glances, and the head turns to people close by.
    Baseline = 2,
    /// Walkers as measured in the street with eye trackers: each walker coming into view
    /// fixated once with a set probability, after a latency, for about half a second;
    /// close strangers looked at less; the path ahead the rest of the time
    /// (`cg_crowd_config_init_street`, docs/street.md).
    Street = 3,
}

impl cg_attention_model {
    pub(crate) fn parse(value: u32) -> Result<AttentionModel> {
        match value {
            0 => Ok(AttentionModel::Crowd),
            1 => Ok(AttentionModel::Saliency),
            2 => Ok(AttentionModel::Baseline),
            3 => Ok(AttentionModel::Street),
            other => Err(Error::InvalidArgument(format!(
                "attention_model is {other}, not a cg_attention_model"
            ))
            .into()),
        }
    }

    pub(crate) fn from_model(model: AttentionModel) -> u32 {
        (match model {
            AttentionModel::Crowd => cg_attention_model::Crowd,
            AttentionModel::Saliency => cg_attention_model::Saliency,
            AttentionModel::Baseline => cg_attention_model::Baseline,
            AttentionModel::Street => cg_attention_model::Street,
        }) as u32
    }
}

/// Which part of an entity a character looks at (`cg_gaze_info.target_part`).
#[repr(u32)]
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum cg_target_part {
    /// The entity's look-at point (objects; characters under the crowd model).
    Whole = 0,
    /// A character's head.
    Head = 1,
    /// A character's left eye.
    LeftEye = 2,
    /// A character's right eye.
    RightEye = 3,
    /// A character's chest.
    Chest = 4,
    /// A character's torso.
    Torso = 5,
}

/// A new character. Set `struct_size`, fill it with `cg_character_desc_init`, then set
/// what you need.
#[repr(C)]
#[derive(Debug, Clone, Copy)]
pub struct cg_character_desc {
    /// Size of this struct in bytes: set it to `sizeof(cg_character_desc)` before every
    /// call taking the struct, `cg_character_desc_init` included.
    pub struct_size: u32,
    /// Heading, radians counter-clockwise about up (0 along forward). Default 0.
    pub heading: f32,
    /// `I_E`: how interesting this character is to others, in [0, 1e6]. Default 1.
    pub impact: f32,
    /// Root (ground) position in your units. Default origin.
    pub position: cg_vec3,
    /// The character's gaze chain (read during the call, not kept), or NULL (default) for
    /// the human chain of `cg_chain_desc_init_human` in the crowd's axes and units.
    pub chain: *const cg_chain_desc,
    /// A `cg_attention_model`. Default `CG_ATTENTION_MODEL_CROWD`.
    pub attention_model: u32,
}

/// A new scene object: something characters may look at. Set `struct_size`, fill it with
/// `cg_object_desc_init`, then set what you need.
#[repr(C)]
#[derive(Debug, Clone, Copy)]
pub struct cg_object_desc {
    /// Size of this struct in bytes: set it to `sizeof(cg_object_desc)` before every call
    /// taking the struct, `cg_object_desc_init` included.
    pub struct_size: u32,
    /// Its forward direction as a heading (radians), used by the orientation subscores.
    /// Default 0.
    pub heading: f32,
    /// Height of the point looked at above `position`, in your units, within ±1e6 m.
    /// Default 0.
    pub look_at_height: f32,
    /// `I_E`: how interesting it is, in [0, 1e6]. Default 1.
    pub impact: f32,
    /// Root position in your units. Default origin.
    pub position: cg_vec3,
}

/// One entity's state in a frame. Set `struct_size` and fill each with
/// `cg_entity_state_init` (or copy one that was), then set `id`, `position` and the rest.
#[repr(C)]
#[derive(Debug, Clone, Copy)]
pub struct cg_entity_state {
    /// Size of this struct in bytes: set it to `sizeof(cg_entity_state)` before every call
    /// taking the struct, `cg_entity_state_init` included; the same in every element of an
    /// array (it is the array's stride).
    pub struct_size: u32,
    /// The entity's id.
    pub id: u32,
    /// `CG_STATE_*` bits. Default 0.
    pub flags: u32,
    /// Heading, radians counter-clockwise about up; must be finite, except with
    /// `CG_STATE_HEADING_FROM_MOTION`, which ignores it (any value, NaN included).
    pub heading: f32,
    /// Root (ground) position in your units.
    pub position: cg_vec3,
    /// Velocity in your units per second; read only with `CG_STATE_HAS_VELOCITY`. A ground
    /// speed above 1e9 m/s (given, or from a jump between two frames) counts as 1e9 m/s.
    pub velocity: cg_vec3,
}

/// A character's attention parameters (Grillon & Thalmann 2009, eq. 7).
#[repr(C)]
#[derive(Debug, Clone, Copy)]
pub struct cg_character_params {
    /// Size of this struct in bytes: set it to `sizeof(cg_character_params)` before every
    /// call taking the struct, `cg_crowd_get_character_params` included.
    pub struct_size: u32,
    /// `ω_p`, weight of the proximity subscore.
    pub weight_proximity: f32,
    /// `ω_s`, weight of the relative-speed subscore.
    pub weight_speed: f32,
    /// `ω_o`, weight of the orientation subscore.
    pub weight_orientation: f32,
    /// `ω_pe`, weight of the periphery subscore.
    pub weight_periphery: f32,
    /// `a`/100: the fraction of time the character attends to something, in [0, 1].
    pub attention_fraction: f32,
    /// A `cg_attention_model`; may be changed at any time.
    pub attention_model: u32,
}

/// Where a character looks, as read by `cg_crowd_read_gaze`.
#[repr(C)]
#[derive(Debug, Clone, Copy, Default)]
pub struct cg_gaze_info {
    /// The character's id.
    pub character: u32,
    /// What the eyes look at: the interest point's (or eye target's) entity id, or
    /// `CG_NO_TARGET` when looking ahead or at an explicit point.
    pub target: u32,
    /// Which part of `target`, a `cg_target_part`.
    pub target_part: u32,
    /// What the head looks at: equal to `target` except under the saliency and baseline
    /// models, whose eyes and head have separate targets.
    pub head_target: u32,
    /// 1 if the character attends to an interest point, else 0.
    pub attending: u32,
    /// Interest points started so far (online), or planned constraints (offline).
    pub interest_count: u32,
    /// The point looked at, in your units: the interest point's look-at point, or 10 m
    /// straight ahead at eye height.
    pub target_position: cg_vec3,
    /// `S_max`: the best score this frame.
    pub s_max: f32,
    /// `A`: the character's attention threshold this frame; `FLT_MAX` when it cannot
    /// attend (an attention fraction of 0, or no score planned for it).
    pub threshold: f32,
    /// Share of the time so far spent attending (online), or planned (offline).
    pub attentive_fraction: f32,
}

/// Everything the scoring function computed for one (character, entity) pair.
#[repr(C)]
#[derive(Debug, Clone, Copy, Default)]
pub struct cg_score_breakdown {
    /// `d`, ground distance in your units (`FLT_MAX` for entities farther apart than that).
    pub distance: f32,
    /// `α`, the entity's angle in the character's field of view (radians, 0 = ahead).
    pub view_angle: f32,
    /// `β`, angle between their forward directions (radians).
    pub heading_angle: f32,
    /// `rs`, relative speed in your units per second (at most `FLT_MAX`).
    pub relative_speed: f32,
    /// `S_p`, proximity subscore in [0, 1].
    pub proximity: f32,
    /// `S_s`, speed subscore in [0, 1].
    pub speed: f32,
    /// `S_o`, orientation subscore in [0, 1].
    pub orientation: f32,
    /// `S_pe`, periphery subscore in [0, 1].
    pub periphery: f32,
    /// `S`, the overall score (0 if pruned).
    pub total: f32,
    /// 1 if the entity was pruned (beyond `max_distance` or outside the field of view).
    pub pruned: u32,
}

/// A planned gaze constraint: look at `entity` from `begin` to `end` (seconds).
#[repr(C)]
#[derive(Debug, Clone, Copy, Default)]
pub struct cg_constraint {
    /// Entity id of the interest point.
    pub entity: u32,
    /// `S_max` when the constraint begins.
    pub s_max: f32,
    /// `t_b`, start time (s).
    pub begin: f64,
    /// `t_e`, end time (s).
    pub end: f64,
}

impl Versioned for cg_character_desc {
    const SIZES: &'static [usize] = &[std::mem::size_of::<cg_character_desc>()];
    const NAME: &'static str = "cg_character_desc";
    fn defaults() -> Self {
        cg_character_desc {
            struct_size: std::mem::size_of::<Self>() as u32,
            heading: 0.0,
            impact: 1.0,
            position: cg_vec3::default(),
            chain: std::ptr::null(),
            attention_model: cg_attention_model::Crowd as u32,
        }
    }
}

impl Versioned for cg_object_desc {
    const SIZES: &'static [usize] = &[std::mem::size_of::<cg_object_desc>()];
    const NAME: &'static str = "cg_object_desc";
    fn defaults() -> Self {
        cg_object_desc {
            struct_size: std::mem::size_of::<Self>() as u32,
            heading: 0.0,
            look_at_height: 0.0,
            impact: 1.0,
            position: cg_vec3::default(),
        }
    }
}

impl Versioned for cg_entity_state {
    const SIZES: &'static [usize] = &[std::mem::size_of::<cg_entity_state>()];
    const NAME: &'static str = "cg_entity_state";
    fn defaults() -> Self {
        cg_entity_state {
            struct_size: std::mem::size_of::<Self>() as u32,
            id: CG_NO_TARGET,
            flags: 0,
            heading: 0.0,
            position: cg_vec3::default(),
            velocity: cg_vec3::default(),
        }
    }
}

impl Versioned for cg_character_params {
    const SIZES: &'static [usize] = &[std::mem::size_of::<cg_character_params>()];
    const NAME: &'static str = "cg_character_params";
    fn defaults() -> Self {
        let weights = SubscoreWeights::EQUAL;
        cg_character_params {
            struct_size: std::mem::size_of::<Self>() as u32,
            weight_proximity: weights.proximity,
            weight_speed: weights.speed,
            weight_orientation: weights.orientation,
            weight_periphery: weights.periphery,
            attention_fraction: 0.4,
            attention_model: cg_attention_model::Crowd as u32,
        }
    }
}

/// Writes `T`'s defaults into `*out`, up to its `struct_size` (the body of every `_init`
/// function).
fn init<T: Versioned>(out: *mut T, what: &str) -> Result<()> {
    // SAFETY: the caller passes a T of at least its struct_size bytes (or NULL, rejected).
    unsafe { write_versioned(out, T::defaults(), what) }
}

/// Fills `desc` with defaults (origin, heading 0, impact 1). Set `desc->struct_size =
/// sizeof(cg_character_desc)` first: only that many bytes are written, and `struct_size`
/// keeps its value. The caller owns `desc`.
///
/// Errors (nothing written): `CG_STATUS_NULL_ARGUMENT`, `CG_STATUS_BAD_STRUCT_SIZE`
/// (`struct_size` not a size the library knows, 0 or an unset field included).
/// Thread-safe.
#[no_mangle]
pub unsafe extern "C" fn cg_character_desc_init(desc: *mut cg_character_desc) -> cg_status {
    ffi_boundary!({ init(desc, "desc") })
}

/// Fills `desc` with defaults (origin, heading 0, look-at height 0, impact 1). Set
/// `desc->struct_size = sizeof(cg_object_desc)` first: only that many bytes are written,
/// and `struct_size` keeps its value. The caller owns `desc`.
///
/// Errors (nothing written): `CG_STATUS_NULL_ARGUMENT`, `CG_STATUS_BAD_STRUCT_SIZE`
/// (`struct_size` not a size the library knows, 0 or an unset field included).
/// Thread-safe.
#[no_mangle]
pub unsafe extern "C" fn cg_object_desc_init(desc: *mut cg_object_desc) -> cg_status {
    ffi_boundary!({ init(desc, "desc") })
}

/// Fills `state` with defaults (id `CG_NO_TARGET`, no flags, zeros). Set
/// `state->struct_size = sizeof(cg_entity_state)` first: only that many bytes are
/// written, and `struct_size` keeps its value. The caller owns `state`.
///
/// Errors (nothing written): `CG_STATUS_NULL_ARGUMENT`, `CG_STATUS_BAD_STRUCT_SIZE`
/// (`struct_size` not a size the library knows, 0 or an unset field included).
/// Thread-safe.
#[no_mangle]
pub unsafe extern "C" fn cg_entity_state_init(state: *mut cg_entity_state) -> cg_status {
    ffi_boundary!({ init(state, "state") })
}

fn metres(world: &World, value: cg_vec3, what: &str) -> Result<Vec3> {
    Ok(world.to_metres(value.to_finite(what)?))
}

/// Adds a character to the crowd and writes its id to `*out_id`. Its attention
/// parameters are drawn from the crowd's seed (change them with
/// `cg_crowd_set_character_params`). The id stays valid until `cg_crowd_remove_entity`.
///
/// Errors: `CG_STATUS_NULL_ARGUMENT`, `CG_STATUS_BAD_STRUCT_SIZE` (desc or its chain),
/// `CG_STATUS_NON_FINITE` (position, heading, impact or chain values),
/// `CG_STATUS_INVALID_ARGUMENT` (impact outside [0, 1e6], an invalid chain),
/// `CG_STATUS_CAPACITY` (already `max_characters`), `CG_STATUS_WRONG_STATE` (a plan is
/// active), `CG_STATUS_OUT_OF_MEMORY` (no memory for a new distinct chain). Not thread-safe
/// (mutates the crowd).
#[no_mangle]
pub unsafe extern "C" fn cg_crowd_add_character(
    crowd: *mut cg_crowd,
    desc: *const cg_character_desc,
    out_id: *mut u32,
) -> cg_status {
    ffi_boundary!({
        // SAFETY: handle contract of cg_crowd.
        let crowd = unsafe { crowd_mut(crowd) }?;
        // SAFETY: the caller passes a readable desc of at least its struct_size bytes.
        let desc = unsafe { read_versioned(desc) }?;
        // SAFETY: the caller provides a writable uint32_t (or NULL, rejected).
        let out_id = unsafe { Out::new(out_id, "out_id") }?;
        let world = crowd.config().world;
        let chain = if desc.chain.is_null() {
            None
        } else {
            // SAFETY: a non-null chain points to a readable cg_chain_desc of at least its
            // struct_size bytes (caller contract).
            let chain = unsafe { read_versioned(desc.chain) }?;
            Some(chain.to_core(world.units_per_metre)?)
        };
        let core = CharacterDesc {
            position: metres(&world, desc.position, "position")?,
            heading: desc.heading,
            impact: desc.impact,
            params: None,
            chain,
            model: cg_attention_model::parse(desc.attention_model)?,
        };
        let id = crowd.add_character(&core)?;
        out_id.write(id);
        Ok(())
    })
}

/// Adds a scene object (something only looked at) and writes its id to `*out_id`.
///
/// Errors: `CG_STATUS_NULL_ARGUMENT`, `CG_STATUS_BAD_STRUCT_SIZE`, `CG_STATUS_NON_FINITE`,
/// `CG_STATUS_INVALID_ARGUMENT` (impact outside [0, 1e6], look-at height beyond ±1e6 m),
/// `CG_STATUS_CAPACITY` (already `max_objects`), `CG_STATUS_WRONG_STATE` (a plan is
/// active). Not thread-safe.
#[no_mangle]
pub unsafe extern "C" fn cg_crowd_add_object(
    crowd: *mut cg_crowd,
    desc: *const cg_object_desc,
    out_id: *mut u32,
) -> cg_status {
    ffi_boundary!({
        // SAFETY: handle contract of cg_crowd.
        let crowd = unsafe { crowd_mut(crowd) }?;
        // SAFETY: the caller passes a readable desc of at least its struct_size bytes.
        let desc = unsafe { read_versioned(desc) }?;
        // SAFETY: the caller provides a writable uint32_t (or NULL, rejected).
        let out_id = unsafe { Out::new(out_id, "out_id") }?;
        ensure_finite(desc.look_at_height, "look_at_height")?;
        let core = ObjectDesc {
            position: metres(&crowd.config().world, desc.position, "position")?,
            heading: desc.heading,
            look_at_height: desc.look_at_height / crowd.config().world.units_per_metre,
            impact: desc.impact,
        };
        let id = crowd.add_object(&core)?;
        out_id.write(id);
        Ok(())
    })
}

/// Removes a character or object. Its id is `CG_STATUS_NOT_FOUND` from then on; characters
/// that looked at it look elsewhere. Removing a character may change the order of
/// characters in `cg_crowd_read_gaze` (the last one takes its place).
///
/// Errors: `CG_STATUS_NULL_ARGUMENT`, `CG_STATUS_NOT_FOUND`, `CG_STATUS_WRONG_STATE` (a
/// plan is active). Not thread-safe.
#[no_mangle]
pub unsafe extern "C" fn cg_crowd_remove_entity(crowd: *mut cg_crowd, id: u32) -> cg_status {
    ffi_boundary!({
        // SAFETY: handle contract of cg_crowd.
        let crowd = unsafe { crowd_mut(crowd) }?;
        Ok(crowd.remove_entity(id)?)
    })
}

/// Writes the number of characters to `*out_count`. Errors: `CG_STATUS_NULL_ARGUMENT`.
/// Safe to call concurrently with other `const` calls.
#[no_mangle]
pub unsafe extern "C" fn cg_crowd_character_count(
    crowd: *const cg_crowd,
    out_count: *mut usize,
) -> cg_status {
    ffi_boundary!({
        // SAFETY: handle contract of cg_crowd.
        let crowd = unsafe { crowd_ref(crowd) }?;
        // SAFETY: the caller provides a writable size_t (or NULL, rejected).
        let out_count = unsafe { Out::new(out_count, "out_count") }?;
        out_count.write(crowd.character_count());
        Ok(())
    })
}

/// Reads where characters look: fills `out[i]` for the first `min(count, characters)`
/// characters, in the crowd's character order (creation order, except that removing a
/// character moves the last one into its place), and writes how many it filled to
/// `*out_written` if `out_written` is not NULL. `out` stays yours; nothing is allocated.
///
/// Errors: `CG_STATUS_NULL_ARGUMENT` (crowd, or out NULL with count > 0),
/// `CG_STATUS_INVALID_ARGUMENT` (a count too large for any array). Safe to call
/// concurrently with other `const` calls.
#[no_mangle]
pub unsafe extern "C" fn cg_crowd_read_gaze(
    crowd: *const cg_crowd,
    out: *mut cg_gaze_info,
    count: usize,
    out_written: *mut usize,
) -> cg_status {
    ffi_boundary!({
        // SAFETY: handle contract of cg_crowd.
        let crowd = unsafe { crowd_ref(crowd) }?;
        // SAFETY: the caller provides `count` writable cg_gaze_info (or (NULL, 0)).
        let out = unsafe { super::slice_mut(out, count, "out") }?;
        // SAFETY: the caller provides a writable size_t, or NULL.
        let out_written = unsafe { Out::optional(out_written, "out_written") }?;
        let units = crowd.config().world.units_per_metre;
        let written = out.len().min(crowd.character_count());
        for (character, slot) in out.iter_mut().enumerate().take(written) {
            let gaze = crowd.gaze_at(character);
            *slot = cg_gaze_info {
                character: gaze.character,
                target: gaze.target,
                target_part: u32::from(gaze.target_part as u8),
                head_target: gaze.head_target,
                attending: u32::from(gaze.attending),
                interest_count: gaze.interest_count,
                target_position: (gaze.target_position * units).into(),
                s_max: gaze.s_max,
                threshold: gaze.threshold,
                attentive_fraction: gaze.attentive_fraction,
            };
        }
        write_optional(out_written, written);
        Ok(())
    })
}

/// Scores `entity` for `character` on the current state and writes every intermediate
/// (distances, angles, subscores, total, pruned) to `*out` — for tools and tests.
///
/// Errors: `CG_STATUS_NULL_ARGUMENT`, `CG_STATUS_NOT_FOUND` (either id),
/// `CG_STATUS_INVALID_ARGUMENT` (`character` is an object). Safe to call concurrently with
/// other `const` calls.
#[no_mangle]
pub unsafe extern "C" fn cg_crowd_score(
    crowd: *const cg_crowd,
    character: u32,
    entity: u32,
    out: *mut cg_score_breakdown,
) -> cg_status {
    ffi_boundary!({
        // SAFETY: handle contract of cg_crowd.
        let crowd = unsafe { crowd_ref(crowd) }?;
        // SAFETY: the caller provides a writable cg_score_breakdown (or NULL, rejected).
        let out = unsafe { Out::new(out, "out") }?;
        let score = crowd.score(character, entity)?;
        let units = crowd.config().world.units_per_metre;
        out.write(cg_score_breakdown {
            // Two entities near opposite ends of the float range are farther apart than
            // FLT_MAX: report the largest float, not infinity.
            distance: (score.distance * units).min(f32::MAX),
            view_angle: score.view_angle,
            heading_angle: score.heading_angle,
            relative_speed: (score.relative_speed * units).min(f32::MAX),
            proximity: score.proximity,
            speed: score.speed,
            orientation: score.orientation,
            periphery: score.periphery,
            total: score.total,
            pruned: u32::from(score.pruned),
        });
        Ok(())
    })
}

/// Writes a character's attention parameters to `*out_params`. Set
/// `out_params->struct_size = sizeof(cg_character_params)` first: only that many bytes are
/// written, and `struct_size` keeps its value. The caller owns `out_params`.
///
/// Errors (nothing written): `CG_STATUS_NULL_ARGUMENT`, `CG_STATUS_BAD_STRUCT_SIZE`
/// (`struct_size` not a size the library knows), `CG_STATUS_NOT_FOUND`,
/// `CG_STATUS_INVALID_ARGUMENT` (an object's id). Safe to call concurrently with other
/// `const` calls.
#[no_mangle]
pub unsafe extern "C" fn cg_crowd_get_character_params(
    crowd: *const cg_crowd,
    character: u32,
    out_params: *mut cg_character_params,
) -> cg_status {
    ffi_boundary!({
        // SAFETY: handle contract of cg_crowd.
        let crowd = unsafe { crowd_ref(crowd) }?;
        super::non_null(out_params, "out_params")?;
        let params = crowd.character_params(character)?;
        let params = cg_character_params {
            struct_size: std::mem::size_of::<cg_character_params>() as u32,
            weight_proximity: params.weights.proximity,
            weight_speed: params.weights.speed,
            weight_orientation: params.weights.orientation,
            weight_periphery: params.weights.periphery,
            attention_fraction: params.attention_fraction,
            attention_model: cg_attention_model::from_model(params.model),
        };
        // SAFETY: the caller provides a cg_character_params of at least its struct_size
        // bytes (checked non-null).
        unsafe { write_versioned(out_params, params, "out_params") }
    })
}

/// Sets a character's attention parameters. The four weights are rescaled to sum to 1;
/// changing `attention_fraction` restarts the character's threshold estimate (and its
/// warm-up). Switching `attention_model` to or from `CG_ATTENTION_MODEL_CROWD` starts the
/// new model afresh: a character keeps only its current model's state (the saliency and
/// baseline models share theirs). Get the current ones with
/// `cg_crowd_get_character_params` first.
///
/// Errors: `CG_STATUS_NULL_ARGUMENT`, `CG_STATUS_BAD_STRUCT_SIZE`, `CG_STATUS_NOT_FOUND`,
/// `CG_STATUS_NON_FINITE`, `CG_STATUS_INVALID_ARGUMENT` (a negative weight, all weights
/// zero, attention_fraction outside [0, 1], an object's id). Not thread-safe.
#[no_mangle]
pub unsafe extern "C" fn cg_crowd_set_character_params(
    crowd: *mut cg_crowd,
    character: u32,
    params: *const cg_character_params,
) -> cg_status {
    ffi_boundary!({
        // SAFETY: handle contract of cg_crowd.
        let crowd = unsafe { crowd_mut(crowd) }?;
        // SAFETY: the caller passes a readable struct of at least its struct_size bytes.
        let params = unsafe { read_versioned(params) }?;
        let raw = [
            params.weight_proximity,
            params.weight_speed,
            params.weight_orientation,
            params.weight_periphery,
        ];
        crate::error::ensure_all_finite(&raw, "weights")?;
        ensure_finite(params.attention_fraction, "attention_fraction")?;
        let weights = SubscoreWeights::normalised(raw).ok_or_else(|| {
            Error::InvalidArgument("weights must be >= 0 and not all zero".into())
        })?;
        Ok(crowd.set_character_params(
            character,
            &CharacterParams {
                weights,
                attention_fraction: params.attention_fraction,
                model: cg_attention_model::parse(params.attention_model)?,
            },
        )?)
    })
}

/// Sets an entity's impact factor `I_E` (in [0, 1e6]; how interesting it is to others).
///
/// Errors: `CG_STATUS_NULL_ARGUMENT`, `CG_STATUS_NOT_FOUND`, `CG_STATUS_NON_FINITE`,
/// `CG_STATUS_INVALID_ARGUMENT` (outside [0, 1e6]). Not thread-safe.
#[no_mangle]
pub unsafe extern "C" fn cg_crowd_set_impact(
    crowd: *mut cg_crowd,
    entity: u32,
    impact: f32,
) -> cg_status {
    ffi_boundary!({
        // SAFETY: handle contract of cg_crowd.
        let crowd = unsafe { crowd_mut(crowd) }?;
        Ok(crowd.set_impact(entity, impact)?)
    })
}

/// Plans attention offline over every recorded frame (the paper's pipeline): scores each
/// frame, sets each character's threshold to the exact percentile of its `S_max(t)`, and
/// cuts its constraints (`cg_crowd_read_constraints`). From then on `cg_crowd_step` replays
/// the recording from its first frame following the plan, and pushing frames or adding and
/// removing entities is `CG_STATUS_WRONG_STATE` until `cg_crowd_clear_plan`. Allocates
/// (once) for the plan: about 8 bytes per recorded frame and character (25 while planning).
///
/// Errors: `CG_STATUS_NULL_ARGUMENT`, `CG_STATUS_WRONG_STATE` (nothing recorded, or
/// already planned), `CG_STATUS_OUT_OF_MEMORY` (the plan does not fit in memory; the crowd
/// stays online and unchanged). Not thread-safe.
#[no_mangle]
pub unsafe extern "C" fn cg_crowd_plan(crowd: *mut cg_crowd) -> cg_status {
    ffi_boundary!({
        // SAFETY: handle contract of cg_crowd.
        let crowd = unsafe { crowd_mut(crowd) }?;
        Ok(crowd.plan()?)
    })
}

/// Leaves planned mode and forgets the recording; online stepping and pushing resume.
/// Errors: `CG_STATUS_NULL_ARGUMENT`. Not thread-safe.
#[no_mangle]
pub unsafe extern "C" fn cg_crowd_clear_plan(crowd: *mut cg_crowd) -> cg_status {
    ffi_boundary!({
        // SAFETY: handle contract of cg_crowd.
        let crowd = unsafe { crowd_mut(crowd) }?;
        crowd.clear_plan();
        Ok(())
    })
}

/// Reads a character's planned constraints, in time order: fills the first
/// `min(count, total)` of `out` and writes the total number to `*out_total` (which may be
/// NULL). Call with `(NULL, 0)` to learn the total.
///
/// Errors: `CG_STATUS_NULL_ARGUMENT`, `CG_STATUS_NOT_FOUND`, `CG_STATUS_INVALID_ARGUMENT`
/// (an object's id), `CG_STATUS_WRONG_STATE` (no plan). Safe to call concurrently with
/// other `const` calls.
#[no_mangle]
pub unsafe extern "C" fn cg_crowd_read_constraints(
    crowd: *const cg_crowd,
    character: u32,
    out: *mut cg_constraint,
    count: usize,
    out_total: *mut usize,
) -> cg_status {
    ffi_boundary!({
        // SAFETY: handle contract of cg_crowd.
        let crowd = unsafe { crowd_ref(crowd) }?;
        // SAFETY: the caller provides `count` writable cg_constraint (or (NULL, 0)).
        let out = unsafe { super::slice_mut(out, count, "out") }?;
        // SAFETY: the caller provides a writable size_t, or NULL.
        let out_total = unsafe { Out::optional(out_total, "out_total") }?;
        let constraints = crowd.constraints(character)?;
        for (slot, constraint) in out.iter_mut().zip(constraints) {
            *slot = cg_constraint {
                entity: constraint.entity,
                s_max: constraint.s_max,
                begin: constraint.begin,
                end: constraint.end,
            };
        }
        write_optional(out_total, constraints.len());
        Ok(())
    })
}

/// Makes the viewer (the user or the camera) an entity that characters may look at, or
/// moves it: `position` in your units is the point looked at, `impact` its `I_E` (in
/// [0, 1e6]). The first call adds it (it has its own slot, beyond `max_objects`) and writes
/// its id to `*out_id` (which may be NULL); later calls move it (velocity and heading come
/// from its motion between frames). Remove it with `cg_crowd_remove_entity`.
///
/// Errors: `CG_STATUS_NULL_ARGUMENT`, `CG_STATUS_NON_FINITE`, `CG_STATUS_INVALID_ARGUMENT`
/// (impact outside [0, 1e6]), `CG_STATUS_WRONG_STATE` (a plan is active). Not thread-safe.
#[no_mangle]
pub unsafe extern "C" fn cg_crowd_set_viewer(
    crowd: *mut cg_crowd,
    position: *const cg_vec3,
    impact: f32,
    out_id: *mut u32,
) -> cg_status {
    ffi_boundary!({
        // SAFETY: handle contract of cg_crowd.
        let crowd = unsafe { crowd_mut(crowd) }?;
        // SAFETY: the caller passes a readable cg_vec3 (or NULL, rejected).
        let position = unsafe { super::borrow(position, "position") }?;
        // SAFETY: the caller provides a writable uint32_t, or NULL.
        let out_id = unsafe { Out::optional(out_id, "out_id") }?;
        let position = metres(&crowd.config().world, *position, "position")?;
        ensure_finite(impact, "impact")?;
        let id = crowd.set_viewer(position, impact)?;
        write_optional(out_id, id);
        Ok(())
    })
}

/// Sets how often `character`'s attention is updated: every `period` steps (1 to 64), or 0
/// for the crowd's level of detail (`cg_crowd_config.attention_period`, or
/// `far_attention_period` beyond `lod_distance` from the viewer). Its gaze still moves
/// every step.
///
/// Errors: `CG_STATUS_NULL_ARGUMENT`, `CG_STATUS_NOT_FOUND`, `CG_STATUS_INVALID_ARGUMENT`
/// (period > 64, an object's id). Not thread-safe.
#[no_mangle]
pub unsafe extern "C" fn cg_crowd_set_attention_period(
    crowd: *mut cg_crowd,
    character: u32,
    period: u32,
) -> cg_status {
    ffi_boundary!({
        // SAFETY: handle contract of cg_crowd.
        let crowd = unsafe { crowd_mut(crowd) }?;
        Ok(crowd.set_attention_period(character, period)?)
    })
}
