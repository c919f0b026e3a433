//! The `cg_crowd` handle: its config struct, creation and destruction.

use std::cell::UnsafeCell;
use std::sync::atomic::{AtomicU32, AtomicU8, Ordering};

use super::error::{FfiError, Result};
use super::poison::{self, Poison};
use super::{
    ffi_boundary, handle_ref, into_c, layout_size, read_versioned, write_versioned, Handle, Out,
    Versioned,
};
use crate::crowd::{Crowd, CrowdConfig, PushRanges, StepRanges};
use crate::error::Error;

/// A crowd of characters and the objects they may look at (opaque).
///
/// Created by `cg_crowd_create`, destroyed by `cg_crowd_destroy`. Threading rules: calls
/// taking a `cg_crowd*` must not overlap with any other call on the same crowd, except
/// `cg_crowd_step_range`, which several threads may call at once on disjoint ranges
/// between `cg_crowd_begin_step` and `cg_crowd_end_step`, and `cg_crowd_push_range`,
/// likewise between `cg_crowd_begin_push` and `cg_crowd_end_push`. Calls taking a
/// `const cg_crowd*` may run concurrently with each other. While a ranged step or push is
/// open, every other call on the crowd fails with `CG_STATUS_WRONG_STATE`.
///
/// If a call that changes the crowd fails with `CG_STATUS_INTERNAL` (a bug, such as a caught
/// panic), the crowd may be half-updated and is poisoned: every later call on it, whatever
/// it is, fails with `CG_STATUS_POISONED`, whose message repeats the first failure's.
/// `cg_crowd_destroy` still frees it.
pub struct cg_crowd {
    _private: [u8; 0],
}

/// Phases of a crowd handle's ranged step and ranged push.
const IDLE: u8 = 0;
/// Between `cg_crowd_begin_step` and `cg_crowd_end_step`: only step ranges may run.
const OPEN: u8 = 1;
/// Inside `cg_crowd_begin_step`, `cg_crowd_end_step`, `cg_crowd_begin_push` or
/// `cg_crowd_end_push`.
const CHANGING: u8 = 2;
/// Between `cg_crowd_begin_push` and `cg_crowd_end_push`: only push ranges may run.
const PUSHING: u8 = 3;

/// What a range or end call says when no ranged step is open.
const NO_STEP_OPEN: &str = "no ranged step is open: call cg_crowd_begin_step first";
/// What a push range or end call says when no ranged push is open.
const NO_PUSH_OPEN: &str = "no ranged push is open: call cg_crowd_begin_push first";

/// The calls of a crowd that a test build can make panic once they have changed the crowd
/// (`testing::panic_next`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Hook {
    BeginStep = 1,
    StepRange = 2,
    EndStep = 3,
    Step = 4,
}

/// What a `cg_crowd*` points to: the core crowd, and the open ranged step, if any.
///
/// The crowd sits in an `UnsafeCell` because `cg_crowd_step_range` calls on several threads
/// step it through a shared reference to the handle (disjoint characters, see
/// [`StepRanges`]); every other call first checks that no ranged step is open.
pub(crate) struct CrowdHandle {
    /// `IDLE`, `OPEN`, `CHANGING` or `PUSHING`.
    phase: AtomicU8,
    /// `cg_crowd_step_range` and `cg_crowd_push_range` calls in progress.
    ranges_running: AtomicU32,
    /// The open step's ranges (`Some` exactly while `OPEN`). Declared before `crowd`, which
    /// it borrows, so that it is dropped first.
    ranges: UnsafeCell<Option<StepRanges<'static>>>,
    /// The open push's ranges (`Some` exactly while `PUSHING`); dropped before `crowd`, too.
    push_ranges: UnsafeCell<Option<PushRanges<'static>>>,
    crowd: UnsafeCell<Crowd>,
    /// Set by the first call that changed the crowd and failed inside the library.
    poison: Poison,
    /// Test builds: the [`Hook`] (as `u8`, 0 for none) at which the next call panics.
    #[cfg(feature = "test-hooks")]
    panic_at: AtomicU8,
}

// SAFETY: `cg_crowd` is the opaque type of crowd handles only.
unsafe impl Handle for CrowdHandle {
    type Opaque = cg_crowd;
    const NAME: &'static str = "crowd";
    fn poison(&self) -> &Poison {
        &self.poison
    }
}

// SAFETY: the cells are accessed as the phase protocol allows: `crowd` mutably only by the
// single thread that moved the phase out of OPEN (or by a caller with exclusive use of the
// handle, per the C contract), `ranges` written only while not OPEN and read only while
// OPEN, `push_ranges` likewise with PUSHING; `StepRanges` and `PushRanges` are `Sync`.
unsafe impl Sync for CrowdHandle {}

impl CrowdHandle {
    fn new(crowd: Crowd) -> CrowdHandle {
        CrowdHandle {
            phase: AtomicU8::new(IDLE),
            ranges_running: AtomicU32::new(0),
            ranges: UnsafeCell::new(None),
            push_ranges: UnsafeCell::new(None),
            crowd: UnsafeCell::new(crowd),
            poison: Poison::default(),
            #[cfg(feature = "test-hooks")]
            panic_at: AtomicU8::new(0),
        }
    }

    /// Arms the handle's poison for the running call, which is about to change the crowd.
    fn arm(&self) {
        poison::arm(&self.poison);
    }

    /// Test builds: makes the next call reaching `hook` panic there.
    #[cfg(feature = "test-hooks")]
    pub(crate) fn panic_next(&self, hook: Hook) {
        self.panic_at.store(hook as u8, Ordering::SeqCst);
    }

    /// Test builds (feature `test-hooks`): panics if [`panic_next`](Self::panic_next) asked
    /// for a panic at `hook`. Does nothing otherwise.
    #[inline]
    fn test_hook(&self, hook: Hook) {
        #[cfg(feature = "test-hooks")]
        {
            let asked =
                self.panic_at
                    .compare_exchange(hook as u8, 0, Ordering::SeqCst, Ordering::SeqCst);
            if asked.is_ok() {
                panic!("test hook: {hook:?} panics");
            }
        }
        #[cfg(not(feature = "test-hooks"))]
        let _ = hook;
    }

    fn ensure_idle(&self) -> Result<()> {
        let open = match self.phase.load(Ordering::SeqCst) {
            IDLE => return Ok(()),
            PUSHING => "a ranged push is open: finish it with cg_crowd_end_push first",
            _ => "a ranged step is open: finish it with cg_crowd_end_step first",
        };
        Err(Error::WrongState(open.into()).into())
    }

    /// Moves the phase from `from` to CHANGING, or fails with `refusal` (the phase was not
    /// `from`).
    fn enter_changing(&self, from: u8, refusal: &str) -> Result<()> {
        self.phase
            .compare_exchange(from, CHANGING, Ordering::SeqCst, Ordering::SeqCst)
            .map(|_| ())
            .map_err(|_| Error::WrongState(refusal.into()).into())
    }

    /// Opens a ranged step (`cg_crowd_begin_step`).
    ///
    /// # Safety
    /// No other call on this handle may run, but `step_range` (which then fails).
    pub(crate) unsafe fn begin_step(&self, dt: f32) -> Result<()> {
        self.enter_changing(
            IDLE,
            "a ranged step is already open: call cg_crowd_end_step first",
        )?;
        self.arm();
        // SAFETY: the phase is CHANGING, set by this thread: no range runs and, by the
        // caller's contract, no other call uses the crowd.
        let crowd = unsafe { &mut *self.crowd.get() };
        let opened = crowd.begin_step(dt).and_then(|()| crowd.step_ranges());
        match opened {
            Ok(ranges) => {
                // SAFETY: only the lifetime is erased: `ranges` borrows the crowd in this
                // handle, which stays in place and is not otherwise used until
                // `end_step` (or the handle's drop) clears `ranges` first.
                let ranges =
                    unsafe { std::mem::transmute::<StepRanges<'_>, StepRanges<'static>>(ranges) };
                // SAFETY: not OPEN, so no range reads the cell.
                unsafe { *self.ranges.get() = Some(ranges) };
                self.test_hook(Hook::BeginStep);
                self.phase.store(OPEN, Ordering::SeqCst);
                Ok(())
            }
            Err(error) => {
                self.phase.store(IDLE, Ordering::SeqCst);
                Err(error.into())
            }
        }
    }

    /// Runs `range` as one range of the ranged step or push open in phase `open`, counted
    /// in `ranges_running` so that the call closing it waits; fails with `not_open` in any
    /// other phase.
    fn in_range(&self, open: u8, not_open: &str, range: impl FnOnce() -> Result<()>) -> Result<()> {
        self.ranges_running.fetch_add(1, Ordering::SeqCst);
        let result = if self.phase.load(Ordering::SeqCst) == open {
            self.arm();
            range()
        } else {
            Err(Error::WrongState(not_open.into()).into())
        };
        self.ranges_running.fetch_sub(1, Ordering::SeqCst);
        result
    }

    /// Moves the phase from `open` to CHANGING to close a ranged step or push: fails with
    /// `not_open` in another phase, or, leaving it open, while `calls` (its ranges) are
    /// still running.
    fn enter_closing(&self, open: u8, not_open: &str, calls: &str) -> Result<()> {
        self.enter_changing(open, not_open)?;
        self.arm();
        if self.ranges_running.load(Ordering::SeqCst) != 0 {
            self.phase.store(open, Ordering::SeqCst);
            return Err(Error::WrongState(format!(
                "{calls} calls are still running on this crowd"
            ))
            .into());
        }
        Ok(())
    }

    /// Steps a range of the open step (`cg_crowd_step_range`); any number of threads.
    pub(crate) fn step_range(&self, first: usize, count: usize) -> Result<()> {
        self.in_range(OPEN, NO_STEP_OPEN, || {
            // SAFETY: OPEN, and `end_step` cannot leave OPEN while this call is counted in
            // `ranges_running` (it checks after its own SeqCst swap).
            let ranges = unsafe { &*self.ranges.get() }
                .as_ref()
                .ok_or_else(|| Error::Internal("an open step has no ranges".into()))?;
            let result = ranges.run_range(first, count).map_err(FfiError::from);
            self.test_hook(Hook::StepRange);
            result
        })
    }

    /// Ends the open step (`cg_crowd_end_step`).
    ///
    /// # Safety
    /// No other call on this handle may run, but `step_range` (which then fails or, when
    /// it got in first, makes this call fail).
    pub(crate) unsafe fn end_step(&self) -> Result<()> {
        self.enter_closing(OPEN, NO_STEP_OPEN, "cg_crowd_step_range")?;
        // SAFETY: CHANGING, and no range runs (ranges seen running above would have kept
        // the phase OPEN; later ones see CHANGING and leave).
        unsafe { *self.ranges.get() = None };
        // SAFETY: as above; the ranges' borrow of the crowd is gone.
        let result = unsafe { &mut *self.crowd.get() }
            .end_step()
            .map_err(FfiError::from);
        self.test_hook(Hook::EndStep);
        self.phase.store(IDLE, Ordering::SeqCst);
        result
    }

    /// Opens a ranged push (`cg_crowd_begin_push`).
    ///
    /// # Safety
    /// No other call on this handle may run, but `push_range` (which then fails).
    pub(crate) unsafe fn begin_push(&self, time: f64) -> Result<()> {
        self.enter_changing(IDLE, "a ranged step or push is already open: end it first")?;
        self.arm();
        // SAFETY: the phase is CHANGING, set by this thread: no range runs and, by the
        // caller's contract, no other call uses the crowd.
        let crowd = unsafe { &mut *self.crowd.get() };
        match crowd.begin_push(time).and_then(|()| crowd.push_ranges()) {
            Ok(ranges) => {
                // SAFETY: only the lifetime is erased: `ranges` borrows the crowd in this
                // handle, which stays in place and is not otherwise used until `end_push`
                // (or the handle's drop) clears `push_ranges` first.
                let ranges =
                    unsafe { std::mem::transmute::<PushRanges<'_>, PushRanges<'static>>(ranges) };
                // SAFETY: not PUSHING, so no range reads the cell.
                unsafe { *self.push_ranges.get() = Some(ranges) };
                self.phase.store(PUSHING, Ordering::SeqCst);
                Ok(())
            }
            Err(error) => {
                self.phase.store(IDLE, Ordering::SeqCst);
                Err(error.into())
            }
        }
    }

    /// Pushes states into the open push (`cg_crowd_push_range`); any number of threads.
    /// `push` runs the push on the open push's ranges.
    pub(crate) fn push_range(
        &self,
        push: impl FnOnce(&PushRanges<'static>) -> Result<()>,
    ) -> Result<()> {
        self.in_range(PUSHING, NO_PUSH_OPEN, || {
            // SAFETY: PUSHING, and `end_push` cannot leave PUSHING while this call is
            // counted in `ranges_running` (it checks after its own SeqCst swap).
            let ranges = unsafe { &*self.push_ranges.get() }
                .as_ref()
                .ok_or_else(|| Error::Internal("an open push has no ranges".into()))?;
            push(ranges)
        })
    }

    /// Ends the open push (`cg_crowd_end_push`).
    ///
    /// # Safety
    /// No other call on this handle may run, but `push_range` (which then fails or, when
    /// it got in first, makes this call fail).
    pub(crate) unsafe fn end_push(&self) -> Result<()> {
        self.enter_closing(PUSHING, NO_PUSH_OPEN, "cg_crowd_push_range")?;
        // SAFETY: CHANGING, and no range runs (ranges seen running above would have kept
        // the phase PUSHING; later ones see CHANGING and leave).
        unsafe { *self.push_ranges.get() = None };
        // SAFETY: as above; the ranges' borrow of the crowd is gone.
        let result = unsafe { &mut *self.crowd.get() }
            .end_push()
            .map_err(FfiError::from);
        self.phase.store(IDLE, Ordering::SeqCst);
        result
    }
}

/// Settings of a crowd, fixed for its lifetime. Set `struct_size`, fill it with
/// `cg_crowd_config_init`, then change the fields you need.
#[repr(C)]
#[derive(Debug, Clone, Copy)]
pub struct cg_crowd_config {
    /// Size of this struct in bytes: set it to `sizeof(cg_crowd_config)` before every call
    /// taking the struct, `cg_crowd_config_init` included. The library reads and writes no
    /// more than this, so later versions can add fields without breaking older callers.
    pub struct_size: u32,
    /// Most characters (entities that look) the crowd holds at once, 1 to 16 777 216.
    /// Each takes about 1 KiB, allocated by `cg_crowd_create`. Default 1024.
    pub max_characters: u32,
    /// Seed of every random choice; same inputs and seed give bit-identical outputs.
    /// Default 0x6372_6f77_6467_617a.
    pub seed: u64,
    /// Most scene objects (entities that are only looked at), 0 to 16 777 216. Each takes
    /// about 130 bytes, allocated by `cg_crowd_create`. Default 256.
    pub max_objects: u32,
    /// Which world axis points up, a `cg_axis`. Default `CG_AXIS_POSITIVE_Y`.
    pub up_axis: u32,
    /// Which world axis heading 0 faces, a `cg_axis` perpendicular to `up_axis`.
    /// Headings are counter-clockwise about `up_axis`. Default `CG_AXIS_POSITIVE_Z`.
    pub forward_axis: u32,
    /// How many of your length units make one metre: 1 for metres (default), 100 for
    /// Unreal's centimetres; 0.001 (kilometres) to 1 000 000 (micrometres).
    pub units_per_metre: f32,
    /// How many entity states `cg_crowd_push_frame` may record for offline planning with
    /// `cg_crowd_plan` (0: no recording, online only), 0 to 4 294 967 295. Each takes 64
    /// bytes, allocated by `cg_crowd_create`. Default 0.
    pub max_recorded_states: u32,
    /// `d_m`: entities farther than this are never looked at, in your units. Default 10 m.
    pub max_distance: f32,
    /// Full horizontal field of view for attention, radians in (0, 2π]. Default π (180°).
    pub field_of_view: f32,
    /// `ω_sw`: speed subscore `S_s = min(1, ω_sw · rs)`, with `rs` in m/s; seconds per
    /// metre, >= 0. Default 0.5.
    pub speed_weight: f32,
    /// `β_m`: largest angle between two forward directions for the periphery subscore,
    /// radians in [0, π]. Default π/2.
    pub periphery_max_angle: f32,
    /// Seconds an entity must hold the best score above the threshold to become an interest
    /// point. Default 1/3.
    pub min_interest_time: f32,
    /// `d_l`: seconds after which an interest point gives way to the next best; >=
    /// `min_interest_time`. Default 4.
    pub max_interest_time: f32,
    /// Seconds during which an interest point dropped after `max_interest_time` is not picked
    /// again. Default 2.
    pub interest_cooldown: f32,
    /// Seconds of score history before a character's streaming percentile threshold is
    /// used; until then `initial_threshold` is. Default 1.
    pub threshold_warmup: f32,
    /// Threshold used during the warm-up. Default 0.35.
    pub initial_threshold: f32,
    /// Each character's attention fraction (`a`/100, the share of time it attends to
    /// something) is drawn uniformly in [`attention_fraction_min`, `attention_fraction_max`).
    /// Default 0.2.
    pub attention_fraction_min: f32,
    /// See `attention_fraction_min`. Default 0.6.
    pub attention_fraction_max: f32,
    /// Gaze IK: largest gaze rotation (radians) the eyes make alone. Default 15°.
    pub eyes_only_angle: f32,
    /// Gaze IK: largest gaze rotation (radians) without the spine (eyes, head and neck).
    /// Default 30°.
    pub eyes_head_neck_angle: f32,
    /// `v_m`: head velocity of the activation time `t_a = θ_head S_MAX / (v_m S_max)`,
    /// rad/s. Default 2π.
    pub head_speed: f32,
    /// Longest activation time `t_a` (s). Default 2.
    pub max_activation_time: f32,
    /// A target moving more than this between two frames (your units) restarts the gaze
    /// shift. Default 0.5 m.
    pub restart_distance: f32,
    /// The return to the base motion takes `t_d`, drawn in [min, max] seconds.
    /// Default 0.5.
    pub min_deactivation_time: f32,
    /// See `min_deactivation_time`. Default 1.5.
    pub max_deactivation_time: f32,
    /// Saliency model: longest eye fixation (s). Default 0.3.
    pub eye_fixation_time: f32,
    /// Saliency model: longest head fixation (s). Default 1.0.
    pub head_fixation_time: f32,
    /// Saliency model: probability that a new target is drawn at random among those in
    /// view, in [0, 1]. Default 0.25.
    pub random_pick_probability: f32,
    /// Saliency model: multiplier of the score of characters' parts over objects (>= 0).
    /// Default 1.5.
    pub social_weight: f32,
    /// Baseline model: a character closer than this (your units) turns the head.
    /// Default 2.5 m.
    pub proximity_radius: f32,
    /// Level of detail: each character's attention is updated every `attention_period`
    /// steps (1 to 64, staggered across the crowd); gaze IK still runs every step.
    /// Default 1.
    pub attention_period: u32,
    /// Level of detail by distance: beyond `lod_distance` (your units) from the viewer
    /// (`cg_crowd_set_viewer`), every `far_attention_period` steps. 0 turns it off
    /// (default).
    pub lod_distance: f32,
    /// See `lod_distance`; 1 to 64. Default 4.
    pub far_attention_period: u32,
    /// Threads `cg_crowd_step` uses: 1 (default) steps on the caller's thread only; n > 1
    /// starts n − 1 worker threads with the crowd, which share each step with the caller
    /// (parked between steps; nothing is allocated per step); 0 picks one per available
    /// core. At most 64. Results are identical for every value. Engines with their own job
    /// system leave it at 1 and use `cg_crowd_step_range` instead.
    pub threads: u32,
    /// Every `reorder_period` steps (default 0: never) the crowd stores its entities and
    /// characters again in spatial order, so that a step reads memory in order (a large
    /// crowd created in random places steps faster, but an engine's pushes and reads in its
    /// own order then scatter: its whole frame is faster without, hence the default).
    /// Results, ids and the order of `cg_crowd_read_gaze` do not depend on it; the ranges
    /// of `cg_crowd_step_range` index the storage order.
    pub reorder_period: u32,
    /// Blinks: the crowd's mean spontaneous blink rate, blinks per minute, 0 to 120 (0: no
    /// spontaneous blinks). Each character draws its own rate once in
    /// `blink_rate · [1 − blink_rate_spread, 1 + blink_rate_spread]`. Default 17 (adults
    /// at rest, Bentivoglio et al. 1997). Read the lids with `cg_crowd_read_eyelids`.
    pub blink_rate: f32,
    /// See `blink_rate`; in [0, 1). Default 0.5.
    pub blink_rate_spread: f32,
    /// Gaze-evoked blinks: shifts of the gaze up to this amplitude (radians) start no
    /// blink. In [0, `evoked_blink_full_amplitude`). Default 10°.
    pub evoked_blink_min_amplitude: f32,
    /// Gaze-evoked blinks: shifts from this amplitude (radians, above the minimum, at most
    /// π) start a blink with `evoked_blink_probability`; between the two the probability
    /// rises linearly. Default 33° (Evinger et al. 1994).
    pub evoked_blink_full_amplitude: f32,
    /// Gaze-evoked blinks: the probability that a large shift starts a blink, in [0, 1]
    /// (0: none). Default 0.97 (Evinger et al. 1994).
    pub evoked_blink_probability: f32,
    /// Upper lid pitch per radian of eye pitch, in [0, 2]. Default 1 (Becker & Fuchs 1988).
    pub lid_gain: f32,
    /// How the eyes of crowd-model and baseline characters time a gaze shift: a
    /// `CG_EYE_MOTION_*`. Default `CG_EYE_MOTION_PAPER`.
    pub eye_motion: u32,
    /// Most conversations (`cg_crowd_set_conversation`) at once, 0 to 8 388 608. Each
    /// takes about 170 bytes, reserved by `cg_crowd_create`. Default 64. A removed group's
    /// id names no group until at least 2^32 - 1 - max_conversations more groups have been
    /// formed (4 286 578 687 at 8 388 608).
    pub max_conversations: u32,
    /// The crowd model's and the saliency model's score of an entity that talks
    /// (`CG_STATE_TALKING`) is multiplied by this, 0 to 100 (1: talking changes nothing).
    /// Default 1.5.
    pub talking_gain: f32,
    /// Saliency model: the multiplier of the eyes' saliency (both eyes of a character) over
    /// its other parts, 0 to 100; higher makes eye contact last longer. Default 1.5.
    pub eye_part_weight: f32,
    /// Conversations: share of the time a listener looks at the speaker, in (0, 1).
    /// Default 0.75 (Argyle & Ingham 1972).
    pub listener_look_share: f32,
    /// Conversations: mean length of a listener's glance at the speaker, seconds (0, 600].
    /// Default 6.
    pub listener_glance_time: f32,
    /// Conversations: share of the time the speaker looks at a listener, in (0, 1).
    /// Default 0.41 (Argyle & Ingham 1972).
    pub speaker_look_share: f32,
    /// Conversations: mean length of the speaker's glance at a listener, seconds (0, 600].
    /// Default 1.8.
    pub speaker_glance_time: f32,
    /// Conversations: share of the time a member looks at another while no one talks, in
    /// (0, 1). Default 0.5.
    pub idle_look_share: f32,
    /// Conversations: mean length of such a glance, seconds (0, 600]. Default 2.5.
    pub idle_glance_time: f32,
    /// Conversations: a member who starts talking first looks away this long, seconds
    /// [0, 60] (0: not at all). Default 1 (Kendon 1967).
    pub turn_start_aversion_time: f32,
    /// Street model (`CG_ATTENTION_MODEL_STREET`, docs/street.md): half-angle of the view
    /// about the walking direction in which walkers are noticed, radians in [0, π].
    /// Default 60°. Walkers are noticed up to `max_distance` (`cg_crowd_config_init_street`
    /// sets 17 m, as measured).
    pub street_view_half_angle: f32,
    /// Street model: probability that a first fixation is planned for a walker coming into
    /// view, in [0, 1]. Default 0.95 (with the fixations missed while the eyes are busy,
    /// `street_miss_after`, walkers are fixated at least once 73–86 % of the time, as
    /// measured: docs/street.md).
    pub street_first_fixation_probability: f32,
    /// Street model: shortest latency from coming into view to the first fixation,
    /// seconds, at most `street_latency_max`. Default 0.55.
    pub street_latency_min: f32,
    /// Street model: longest such latency, seconds in [0, 60]. Default 0.75.
    pub street_latency_max: f32,
    /// Street model: median duration of a fixation on a walker, seconds in (0, 60].
    /// Default 0.5.
    pub street_fixation_median: f32,
    /// Street model: spread of fixation durations, the standard deviation of their natural
    /// logarithm, in [0, 2]. Default 0.35.
    pub street_fixation_log_spread: f32,
    /// Street model: probability that a fixated walker is fixated a second time, in [0, 1].
    /// Default 0.3.
    pub street_refixation_probability: f32,
    /// Street model: shortest wait before that second fixation, seconds, at most
    /// `street_refixation_gap_max`. Default 0.5.
    pub street_refixation_gap_min: f32,
    /// Street model: longest such wait, seconds in [0, 600]. Default 2.
    pub street_refixation_gap_max: f32,
    /// Street model: strangers closer than this (your units, at most 1 000 m) are looked at
    /// less, and the eyes go down the path while one is there (civil inattention).
    /// Default 3 m.
    pub street_civil_distance: f32,
    /// Street model: probability that a fixation due on a stranger closer than
    /// `street_civil_distance` still happens, in [0, 1]. Default 0.25.
    pub street_civil_look_probability: f32,
    /// Street model: how far ahead on the ground the eyes rest when no walker is fixated
    /// (your units, at most 1 000 m). Default 4 m.
    pub street_path_look_distance: f32,
    /// Street model: how far ahead on the ground the eyes go while a stranger is close
    /// (your units, at most 1 000 m). Default 2 m.
    pub street_civil_look_distance: f32,
    /// Gaze following, for characters of every model: 1 makes characters glance where
    /// others stare (a character whose `CG_GAZE_PRIORITY_OVERRIDE` target is a point or an
    /// object), 0 turns it off (default: the crowd behaves exactly as without it); no other
    /// value. Read who follows with `cg_crowd_read_following`.
    /// `cg_crowd_config_init_street` sets 1.
    pub follow_enabled: u32,
    /// Gaze following: probability that a passer-by who sees one person staring looks
    /// too, in [0, `follow_max_probability`]. Default 0.42 (Milgram et al. 1969; Gallup et
    /// al. 2012 measured 0.12 on a shopping street).
    pub follow_one_looker_probability: f32,
    /// Gaze following: the probability with many lookers, where it saturates, in [0, 1].
    /// Default 0.87 (Milgram et al. 1969; Gallup et al. 2012: 0.3).
    pub follow_max_probability: f32,
    /// Gaze following: lookers are noticed up to this ground distance (your units, at most
    /// 1 000 m, and at most `max_distance` while `follow_enabled`). Default 10 m.
    pub follow_distance: f32,
    /// Gaze following: half-angle of the view about the heading in which lookers are
    /// noticed, radians in [0, π]. Default π/2.
    pub follow_view_half_angle: f32,
    /// Gaze following: weight of a looker walking towards the character (one standing or
    /// walking ahead the same way weighs 1), in [0, 1]. Default 0.5.
    pub follow_oncoming_weight: f32,
    /// Gaze following: weight of a character that only glances because it follows (a
    /// stare weighs 1), in [0, 1]. Default 0.1 (a glance is a weak cue: following does
    /// not cascade).
    pub follow_glance_cue_weight: f32,
    /// Gaze following: shortest glance of a follower, seconds, at most
    /// `follow_glance_max`. Default 1.
    pub follow_glance_min: f32,
    /// Gaze following: longest glance, seconds in [0, 600]. Default 2.5.
    pub follow_glance_max: f32,
    /// Gaze following: seconds in [0, 3600] with no looker in view after which an
    /// encounter is over (the next lookers are decided afresh). Default 10.
    pub follow_forget_time: f32,
    /// Street model: a fixation due while the eyes are on someone else that has waited
    /// this long, seconds in [0, 60], is missed (attention is limited). Default 1.
    pub street_miss_after: f32,
    /// Gaze following: shortest time from deciding to follow to the glance, seconds, at
    /// most `follow_reaction_max`. Default 0.3.
    pub follow_reaction_min: f32,
    /// Gaze following: longest such time, seconds in [0, 60]. Default 1.
    pub follow_reaction_max: f32,
}

/// `cg_crowd_config.eye_motion`: the paper's timing (Grillon & Thalmann 2009): the eyes
/// arrive at half the activation time.
pub const CG_EYE_MOTION_PAPER: u32 = 0;
/// `cg_crowd_config.eye_motion`: the eyes' shift lasts as long as a human saccade of its
/// amplitude A, about 2.2 ms/° · A + 21 ms (the main sequence), at most 500°/s; the head,
/// neck and spine keep the paper's timing.
pub const CG_EYE_MOTION_MAIN_SEQUENCE: u32 = 1;

impl Versioned for cg_crowd_config {
    // Callers built against a header from before `reorder_period` (144 bytes), before the
    // blink fields (152 bytes), before the conversation fields (176 bytes) or before the
    // street and following fields (216 bytes) get the defaults of the fields they lack.
    const SIZES: &'static [usize] = &[
        layout_size::<cg_crowd_config>(std::mem::offset_of!(cg_crowd_config, reorder_period)),
        layout_size::<cg_crowd_config>(std::mem::offset_of!(cg_crowd_config, blink_rate)),
        layout_size::<cg_crowd_config>(std::mem::offset_of!(cg_crowd_config, max_conversations)),
        layout_size::<cg_crowd_config>(std::mem::offset_of!(
            cg_crowd_config,
            street_view_half_angle
        )),
        std::mem::size_of::<cg_crowd_config>(),
    ];
    const NAME: &'static str = "cg_crowd_config";

    fn defaults() -> Self {
        cg_crowd_config::from_core(&CrowdConfig::default())
    }
}

/// Fills `config` with the defaults documented on each field. Set `config->struct_size =
/// sizeof(cg_crowd_config)` first: only that many bytes are written (an older, shorter
/// layout gets its own fields), and `struct_size` keeps its value. The caller owns
/// `config`.
///
/// Errors (nothing written): `CG_STATUS_NULL_ARGUMENT` if `config` is NULL,
/// `CG_STATUS_BAD_STRUCT_SIZE` if `struct_size` is not a size of this struct the library
/// knows (0 or an unset field included). Thread-safe.
#[no_mangle]
pub unsafe extern "C" fn cg_crowd_config_init(config: *mut cg_crowd_config) -> super::cg_status {
    ffi_boundary!({
        // SAFETY: the caller passes a cg_crowd_config it owns, of at least its struct_size
        // bytes (or NULL).
        unsafe { write_versioned(config, cg_crowd_config::defaults(), "config") }
    })
}

/// Fills `config` with the street preset: the defaults of `cg_crowd_config_init`, but
/// `max_distance` 17 m (walkers notice each other as far away as they were measured to
/// fixate each other) and `follow_enabled` 1 (gaze following at Milgram's strength). Give
/// the characters `CG_ATTENTION_MODEL_STREET` in their `cg_character_desc`
/// (docs/street.md). Set `config->struct_size = sizeof(cg_crowd_config)` first: only that
/// many bytes are written (an older, shorter layout gets its own fields: the street and
/// following fields are past 216 bytes), and `struct_size` keeps its value. The caller
/// owns `config`.
///
/// Like `cg_crowd_config_init`, this writes metres (`units_per_metre` 1): in other units,
/// set `units_per_metre` and multiply the length fields by it (`max_distance`,
/// `restart_distance`, `proximity_radius`, `street_civil_distance`,
/// `street_path_look_distance`, `street_civil_look_distance`, `follow_distance`): in
/// centimetres `max_distance` is then 1700.
///
/// Errors (nothing written): `CG_STATUS_NULL_ARGUMENT` if `config` is NULL,
/// `CG_STATUS_BAD_STRUCT_SIZE` if `struct_size` is not a size of this struct the library
/// knows (0 or an unset field included). Thread-safe.
#[no_mangle]
pub unsafe extern "C" fn cg_crowd_config_init_street(
    config: *mut cg_crowd_config,
) -> super::cg_status {
    ffi_boundary!({
        let street = cg_crowd_config::from_core(&CrowdConfig::street());
        // SAFETY: the caller passes a cg_crowd_config it owns, of at least its struct_size
        // bytes (or NULL).
        unsafe { write_versioned(config, street, "config") }
    })
}

/// Creates an empty crowd from `config` and stores its handle in `*out_crowd`.
///
/// All buffers are sized here from the capacities; later per-frame calls allocate nothing.
/// The caller owns the new crowd and must release it with `cg_crowd_destroy`.
/// `*out_crowd` is written only on success.
///
/// Errors: `CG_STATUS_NULL_ARGUMENT` (config or out_crowd NULL), `CG_STATUS_BAD_STRUCT_SIZE`
/// (`config->struct_size` not a size the library knows), `CG_STATUS_INVALID_ARGUMENT` (a
/// field out of range: capacities, axes not perpendicular or unknown, units_per_metre <= 0),
/// `CG_STATUS_NON_FINITE` (a float field NaN or infinite), `CG_STATUS_OUT_OF_MEMORY` (the
/// capacities' buffers do not fit in memory; the message names the field and the bytes
/// asked). Thread-safe.
#[no_mangle]
pub unsafe extern "C" fn cg_crowd_create(
    config: *const cg_crowd_config,
    out_crowd: *mut *mut cg_crowd,
) -> super::cg_status {
    ffi_boundary!({
        // SAFETY: the caller provides a writable cg_crowd* (or NULL, rejected).
        let out_crowd = unsafe { Out::new(out_crowd, "out_crowd") }?;
        // SAFETY: the caller passes a readable config of at least its struct_size bytes.
        let config = unsafe { read_versioned(config) }?.to_core()?;
        let crowd = Box::new(CrowdHandle::new(Crowd::new(config)?));
        out_crowd.write(into_c(crowd));
        Ok(())
    })
}

/// Destroys a crowd created by `cg_crowd_create` and frees everything it owns, also when
/// the crowd is poisoned or a ranged step or a ranged push is open (the open frame is
/// dropped unapplied), and in a child process forked after its worker threads started (the
/// threads stayed in the parent: nothing to stop).
///
/// NULL is accepted and ignored. The handle must not be used afterwards, and no other call
/// on this crowd may be running: not even a `cg_crowd_push_range` or `cg_crowd_step_range`
/// of an open frame (end or abandon them first).
#[no_mangle]
pub unsafe extern "C" fn cg_crowd_destroy(crowd: *mut cg_crowd) {
    // SAFETY: a crowd handle from cg_crowd_create (or NULL), destroyed once and not in use
    // (the caller's contract).
    unsafe { super::handle::destroy::<CrowdHandle>(crowd) }
}

/// Reborrows a crowd handle as its handle state (for the ranged step); fails if the crowd
/// is poisoned.
///
/// # Safety
/// `crowd`, if not NULL, must be a live handle from `cg_crowd_create`.
pub(crate) unsafe fn crowd_handle<'a>(crowd: *const cg_crowd) -> Result<&'a CrowdHandle> {
    // SAFETY: forwarded contract.
    unsafe { handle_ref::<CrowdHandle>(crowd) }
}

/// Test builds (feature `test-hooks`): panics if the next call reaching `hook` was asked
/// to panic (`testing::panic_next`). Does nothing otherwise.
///
/// # Safety
/// `crowd`, if not NULL, must be a live handle from `cg_crowd_create`.
pub(crate) unsafe fn test_hook(crowd: *const cg_crowd, hook: Hook) {
    // SAFETY: forwarded contract.
    if let Ok(handle) = unsafe { crowd_handle(crowd) } {
        handle.test_hook(hook);
    }
}

/// Reborrows a crowd handle as the core crowd; fails while a ranged step is open or the
/// crowd is poisoned.
///
/// # Safety
/// `crowd`, if not NULL, must be a live handle from `cg_crowd_create`, with no other
/// mutable access for `'a`.
pub(crate) unsafe fn crowd_ref<'a>(crowd: *const cg_crowd) -> Result<&'a Crowd> {
    // SAFETY: forwarded contract.
    let handle = unsafe { crowd_handle(crowd) }?;
    handle.ensure_idle()?;
    // SAFETY: no ranged step is open, and by the caller's contract nothing mutates the
    // crowd for `'a`.
    Ok(unsafe { &*handle.crowd.get() })
}

/// Reborrows a crowd handle mutably as the core crowd, for a call that changes it (its
/// poison is armed for the call); fails while a ranged step is open.
///
/// # Safety
/// `crowd`, if not NULL, must be a live handle from `cg_crowd_create`, not accessed by
/// anything else for `'a`.
pub(crate) unsafe fn crowd_mut<'a>(crowd: *mut cg_crowd) -> Result<&'a mut Crowd> {
    // SAFETY: forwarded contract.
    let handle = unsafe { crowd_handle(crowd) }?;
    handle.ensure_idle()?;
    handle.arm();
    // SAFETY: no ranged step is open, and by the caller's contract nothing else accesses
    // the crowd for `'a`.
    Ok(unsafe { &mut *handle.crowd.get() })
}

/// Copies the settings `crowd` was created with into `*out_config`. Set
/// `out_config->struct_size = sizeof(cg_crowd_config)` first: only that many bytes are
/// written, and `struct_size` keeps its value. The caller owns `out_config`.
///
/// Errors (nothing written): `CG_STATUS_NULL_ARGUMENT` if either pointer is NULL,
/// `CG_STATUS_BAD_STRUCT_SIZE` (`out_config->struct_size` not a size the library knows).
/// Safe to call concurrently with other `const` calls on the same crowd.
#[no_mangle]
pub unsafe extern "C" fn cg_crowd_get_config(
    crowd: *const cg_crowd,
    out_config: *mut cg_crowd_config,
) -> super::cg_status {
    ffi_boundary!({
        // SAFETY: handle contract of cg_crowd.
        let crowd = unsafe { crowd_ref(crowd) }?;
        let config = cg_crowd_config::from_core(crowd.config());
        // SAFETY: the caller provides a cg_crowd_config of at least its struct_size bytes
        // (or NULL).
        unsafe { write_versioned(out_config, config, "out_config") }
    })
}
