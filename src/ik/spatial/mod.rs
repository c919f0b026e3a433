//! Spatial resolution (Grillon & Thalmann 2009): for one posture, the displacement map —
//! the delta rotation of every chain joint — that turns the character's gaze to a target.
//!
//! **Global eye.** The mid-point of the eyes, looking along the head's forward axis
//! ([`GazeChain::eye_forward`]); the head joint itself if the chain has no eyes.
//! `q_l` is the shortest rotation from the global eye's forward to the direction from the
//! global eye to the target, and `θ` its angle, both taken in the base posture.
//!
//! **Recruitment** by `θ` ([`RecruitmentBands`], defaults 15° and 30°): `θ ≤ 15°` moves the
//! eyes only; `15° < θ ≤ 30°` the eyes, head and cervicals (head and cervicals take
//! `θ − 15°`, no spine joint moves); beyond, the spine takes `θ − 30°`, head and cervicals
//! 15° and the eyes the last 15°. A chain without eyes gives their band to the head and
//! cervicals (recruited from 0°).
//!
//! **Shares.** Within a group of `n` joints (numbered `i = 1…n` bottom to top) the share
//! decreases up the chain following the paper's `c_i = (n − i)·2/(n(n − 1))`. As printed,
//! that formula gives the top joint 0 and is 0/0 for `n = 1`: in the paper it runs over the
//! whole chain, and its last, zero, share is the eyes', which take the rest by vergence.
//! Within a group we therefore evaluate it with the group plus the joint above it and drop
//! that joint's zero: `c_i = 2(n + 1 − i)/(n(n + 1))` — sums to 1, decreases linearly up the
//! chain, and is 1 for `n = 1`.
//!
//! **Remaining rotation.** Bottom to top, each joint takes its share of what *remains* of its
//! group's rotation, recomputed after the joints below it moved: the remaining rotation from
//! the global eye's current forward to the target, less the bands reserved for the groups
//! above, of which joint `i` takes `c_i / Σ_{j ≥ i} c_j = 2/(n + 2 − i)` (the group's top joint
//! takes all that is left). Moving a joint rotates the global eye rigidly about that joint,
//! so the forward kinematics are updated incrementally: O(n), no allocation. Each joint's
//! delta is clamped to its [`JointLimits`]; what a joint cannot take stays in the remaining
//! rotation and passes up the chain. Finally each eye rotates onto its own target
//! (vergence), within its limits.
//!
//! **Two targets.** The body (spine, cervicals, head) aims at `head_target`, the eyes
//! converge on `eye_target`; the crowd model passes the same point twice.
//!
//! **Degenerate targets.**
//! - *Behind the character*: the shortest rotation flips side as the target crosses straight
//!   behind. A [`TurnSide`] remembered between frames gives hysteresis: within
//!   [`SpatialConfig::behind_hysteresis`] of straight behind (measured about the head's up
//!   axis), a target on the other side is aimed at as if it were
//!   [`SpatialConfig::behind_clearance`] short of straight behind on the remembered side, so
//!   the character keeps turning the same way (the zone is oriented by the head's up axis in
//!   the base posture). The side changes only once the target is
//!   clearly on the other side; the solution then jumps, which [`SpatialSolution::side_switched`]
//!   reports so the temporal layer restarts a smooth shift. A new character with a target
//!   exactly behind turns left (counter-clockwise, like headings).
//! - *Straight above*: the shortest rotation is well defined (a pitch); limits stop it.
//! - *At the eye*: closer than [`SpatialConfig::near_distance`] the gaze rotation fades out
//!   smoothly (smoothstep of the distance), so a target at the eye itself asks for no
//!   rotation and never produces a NaN.
//!
//! **Output**: the delta local rotation of each chain joint; the final local rotation is
//! `base * delta` (glam's product: the delta acts in the joint's own frame, after its base
//! rotation).
//!
//! **Cost.** No trigonometry in the common case: rotations are kept as the cosine and sine of
//! their half-angle, the fractional turn is Kapoulkine's corrected nlerp (within about 10⁻³ of
//! the angle: the joints above correct it, the eyes end exactly on target), and clamping to
//! the limits is a few multiplications. The solver runs a lane group of characters at a time,
//! one per SIMD lane: 16 where the processor has AVX-512F, 8 with AVX, else 4 (the same bits
//! at every width; [`solve`] is the one-character entry, at 4 lanes; the crowd goes through
//! [`crate::ik::GazeMotion::update_batch`]).

// The lockstep loops index several per-lane and per-joint arrays with one index.
#![allow(clippy::needless_range_loop)]

use std::cell::Cell;

use glam::{Quat, Vec3, Vec3A, Vec4};

use super::chain::{
    GazeChain, JointGroup, JointLimits, CLAMP_SLACK, MAX_BODY_JOINTS, MAX_CHAIN_JOINTS,
};
use super::lanes::{atan2_upper, gather, mask, sin_cos_quarter, Floats, Mask, MAX_LANES, Q4, V3};
use super::CharacterTransform;
use crate::error::{ensure_all_finite, ensure_finite, Error, Result};
use crate::math::wide::Wide;

/// Angles that decide which groups of joints a gaze rotation recruits (radians).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RecruitmentBands {
    /// Up to this angle only the eyes move; beyond it the eyes keep this much of the
    /// rotation for themselves. Default 15° (the central foveal area's half-width).
    pub eyes_only: f32,
    /// Up to this angle the spine does not move; beyond it the eyes, head and cervicals
    /// keep this much for themselves. Default 30° (the central vision area's half-width).
    pub eyes_head_and_neck: f32,
}

impl Default for RecruitmentBands {
    fn default() -> Self {
        RecruitmentBands {
            eyes_only: 15f32.to_radians(),
            eyes_head_and_neck: 30f32.to_radians(),
        }
    }
}

/// Settings of the spatial resolution.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SpatialConfig {
    /// Which groups a rotation recruits.
    pub bands: RecruitmentBands,
    /// Half-width (radians, about the head's up axis) of the zone behind the character
    /// where the remembered [`TurnSide`] wins over the shortest rotation. Default 30°.
    pub behind_hysteresis: f32,
    /// How far short of straight behind (radians) a target on the other side within the
    /// hysteresis zone is aimed at. Default 10°. At most `behind_hysteresis`.
    pub behind_clearance: f32,
    /// Below this distance from the eye (metres) the gaze rotation fades out, reaching zero
    /// at the eye itself. Default 0.25 m.
    pub near_distance: f32,
}

impl Default for SpatialConfig {
    fn default() -> Self {
        SpatialConfig {
            bands: RecruitmentBands::default(),
            behind_hysteresis: 30f32.to_radians(),
            behind_clearance: 10f32.to_radians(),
            near_distance: 0.25,
        }
    }
}

impl SpatialConfig {
    /// Checks the ranges: `0 ≤ eyes_only ≤ eyes_head_and_neck ≤ π`,
    /// `0 ≤ behind_clearance ≤ behind_hysteresis < 90°`, `near_distance ≥ 0`, all finite.
    pub fn validate(&self) -> Result<()> {
        ensure_all_finite(
            &[
                self.bands.eyes_only,
                self.bands.eyes_head_and_neck,
                self.behind_hysteresis,
                self.behind_clearance,
                self.near_distance,
            ],
            "spatial config",
        )?;
        let bands = self.bands;
        if bands.eyes_only < 0.0
            || bands.eyes_head_and_neck < bands.eyes_only
            || bands.eyes_head_and_neck > std::f32::consts::PI
        {
            return Err(Error::InvalidArgument(format!(
                "recruitment bands {} and {} must satisfy 0 ≤ eyes_only ≤ eyes_head_and_neck ≤ π",
                bands.eyes_only, bands.eyes_head_and_neck
            )));
        }
        if self.behind_clearance < 0.0
            || self.behind_hysteresis < self.behind_clearance
            || self.behind_hysteresis >= std::f32::consts::FRAC_PI_2
        {
            return Err(Error::InvalidArgument(format!(
                "behind_clearance {} and behind_hysteresis {} must satisfy 0 ≤ clearance ≤ \
                 hysteresis < π/2",
                self.behind_clearance, self.behind_hysteresis
            )));
        }
        if self.near_distance < 0.0 {
            return Err(Error::InvalidArgument(format!(
                "near_distance is {}, must be ≥ 0",
                self.near_distance
            )));
        }
        Ok(())
    }
}

/// Which way a character turns towards a target behind it, remembered between frames
/// (one byte of a character's state): undecided, left (counter-clockwise about up) or right.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct TurnSide(i8);

impl TurnSide {
    /// Not decided yet: the next target decides (left if exactly behind).
    pub const UNDECIDED: TurnSide = TurnSide(0);
    /// Counter-clockwise about up.
    pub const LEFT: TurnSide = TurnSide(1);
    /// Clockwise about up.
    pub const RIGHT: TurnSide = TurnSide(-1);

    /// +1 for left, −1 for right, 0 undecided.
    pub fn sign(self) -> i8 {
        self.0
    }

    fn resolved(self) -> f32 {
        if self.0 < 0 {
            -1.0
        } else {
            1.0
        }
    }
}

/// What a spatial solve found besides the deltas.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SpatialSolution {
    /// `θ`: the angle (radians) of `q_l`, the rotation the global eye needs in the base
    /// posture (after the behind and near-target rules).
    pub gaze_angle: f32,
    /// True if the remembered [`TurnSide`] changed while the target was behind: the solution
    /// jumped from one side to the other.
    pub side_switched: bool,
}

/// World positions and gaze directions of the two eyes (both the global eye for a chain
/// without eyes).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EyeRays {
    /// Eye positions, left then right, metres.
    pub origins: [Vec3; 2],
    /// Unit gaze directions, left then right.
    pub directions: [Vec3; 2],
}

/// Solves one posture: writes the delta rotation of every chain joint into
/// `deltas[..chain.joint_count()]` so that the body aims at `head_target` and the eyes
/// converge on `eye_target` (world positions, metres).
///
/// `base` holds the base local rotation of each chain joint (rest or animated pose, unit
/// quaternions); the final local rotation of joint `i` is `base[i] * deltas[i]`. `side` is
/// the character's remembered [`TurnSide`] (start with [`TurnSide::UNDECIDED`]).
///
/// Errors: [`Error::InvalidArgument`] if `base` or `deltas` is shorter than the chain or
/// `config` is out of range, [`Error::NonFinite`] for a NaN or infinite input.
#[allow(clippy::too_many_arguments)]
pub fn solve(
    chain: &GazeChain,
    config: &SpatialConfig,
    character: &CharacterTransform,
    base: &[Quat],
    head_target: Vec3,
    eye_target: Vec3,
    side: &mut TurnSide,
    deltas: &mut [Quat],
) -> Result<SpatialSolution> {
    config.validate()?;
    check_pose(chain, character, base, "base")?;
    if deltas.len() < chain.joint_count() {
        return Err(Error::InvalidArgument(format!(
            "deltas holds {} rotations, the chain has {} joints",
            deltas.len(),
            chain.joint_count()
        )));
    }
    ensure_all_finite(&head_target.to_array(), "head_target")?;
    ensure_all_finite(&eye_target.to_array(), "eye_target")?;
    let prepared = Prepared::new(config);
    // One character: the narrowest lanes do (every width gives the same bits).
    let mut goals = [Q4::<Vec4>::identity(); MAX_BODY_JOINTS];
    let mut lanes = [None; MAX_LANES];
    lanes[0] = Some(BodyLane {
        chain,
        character,
        base,
        head_target,
        side: *side,
    });
    let ([solved, ..], heads) = solve_bodies(&prepared, lanes, &mut goals);
    let (solution, new_side) = solved.ok_or_else(|| Error::Internal("empty solve".into()))?;
    *side = new_side;
    let body = chain.body_count();
    for (delta, goal) in deltas[..body].iter_mut().zip(&goals) {
        *delta = goal.lane(0);
    }
    if chain.has_eyes() {
        let chains = [chain; MAX_LANES];
        let bases = [base; MAX_LANES];
        let target = V3::splat(eye_target.into());
        let side_sign = Floats::splat(side.resolved());
        for eye in 0..2 {
            let frames = EyeFrames::new(&chains, &bases, &heads, eye);
            deltas[frames.index[0]] = frames.goal(&chains, &prepared, target, side_sign).lane(0);
        }
    }
    Ok(solution)
}

/// The eyes' world positions and gaze directions for the pose `base[i] * deltas[i]`.
///
/// Errors: as [`solve`].
pub fn eye_rays(
    chain: &GazeChain,
    character: &CharacterTransform,
    base: &[Quat],
    deltas: &[Quat],
) -> Result<EyeRays> {
    check_pose(chain, character, base, "base")?;
    check_pose(chain, character, deltas, "deltas")?;
    let head = head_frame(chain, character, base, deltas);
    Ok(eye_rays_unchecked(chain, &head, base, deltas))
}

/// Checks a slice of joint rotations against the chain, and the character transform.
pub(crate) fn check_pose(
    chain: &GazeChain,
    character: &CharacterTransform,
    rotations: &[Quat],
    what: &str,
) -> Result<()> {
    if rotations.len() < chain.joint_count() {
        return Err(Error::InvalidArgument(format!(
            "{what} holds {} rotations, the chain has {} joints",
            rotations.len(),
            chain.joint_count()
        )));
    }
    for rotation in &rotations[..chain.joint_count()] {
        if !rotation.is_finite() {
            return Err(Error::NonFinite(format!("{what} contains {rotation:?}")));
        }
    }
    ensure_all_finite(&character.position.to_array(), "character position")?;
    ensure_all_finite(&character.rotation.to_array(), "character rotation")?;
    ensure_finite(character.rotation.length() - 1.0, "character rotation")?;
    Ok(())
}

/// The settings turned into the constants the solver compares against. The behind-zone
/// constants need trigonometry, so they are computed only when a target is behind.
#[derive(Debug, Clone)]
pub(crate) struct Prepared {
    behind_hysteresis: f32,
    behind_clearance: f32,
    near_distance: f32,
    /// cos and sin of half of each band (the angles reserved for the groups above).
    eyes_only_half: (f32, f32),
    eyes_head_and_neck_half: (f32, f32),
    zone: Cell<Option<Zone>>,
}

/// cos and sin of half of `angle ∈ [0, π]`.
#[inline]
fn half_angle(angle: f32) -> (f32, f32) {
    let (sin, cos) = sin_cos_quarter(Floats::<Vec4>::splat(0.5 * angle));
    (cos.lane(0), sin.lane(0))
}

/// Constants of the zone behind the character.
#[derive(Debug, Clone, Copy)]
struct Zone {
    tan_hysteresis: f32,
    tan_clearance: f32,
    cos_clearance: f32,
    sin_clearance: f32,
}

impl Prepared {
    pub(crate) fn new(config: &SpatialConfig) -> Prepared {
        Prepared {
            behind_hysteresis: config.behind_hysteresis,
            behind_clearance: config.behind_clearance,
            near_distance: config.near_distance,
            eyes_only_half: half_angle(config.bands.eyes_only),
            eyes_head_and_neck_half: half_angle(config.bands.eyes_head_and_neck),
            zone: Cell::new(None),
        }
    }

    #[inline]
    fn zone(&self) -> Zone {
        if let Some(zone) = self.zone.get() {
            return zone;
        }
        let (sin_clearance, cos_clearance) = self.behind_clearance.sin_cos();
        let zone = Zone {
            tan_hysteresis: self.behind_hysteresis.tan(),
            tan_clearance: sin_clearance / cos_clearance,
            cos_clearance,
            sin_clearance,
        };
        self.zone.set(Some(zone));
        zone
    }
}

/// A world frame: position (metres) and rotation.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Frame {
    pub(crate) position: Vec3A,
    pub(crate) rotation: Quat,
}

/// The chain root's world frame.
#[inline]
pub(crate) fn root_frame(chain: &GazeChain, character: &CharacterTransform) -> Frame {
    Frame {
        position: Vec3A::from(character.position)
            + character
                .rotation
                .mul_vec3a(Vec3A::from(chain.root_offset())),
        rotation: character.rotation,
    }
}

/// The head's final world frame for the pose `base[i] * deltas[i]` (body joints only).
pub(crate) fn head_frame(
    chain: &GazeChain,
    character: &CharacterTransform,
    base: &[Quat],
    deltas: &[Quat],
) -> Frame {
    let mut frame = root_frame(chain, character);
    let body = chain.body_count();
    for ((joint, base), delta) in chain.joints()[..body]
        .iter()
        .zip(&base[..body])
        .zip(&deltas[..body])
    {
        frame.position += frame.rotation.mul_vec3a(Vec3A::from(joint.offset));
        frame.rotation = frame.rotation * *base * *delta;
    }
    frame
}

/// The eyes' mid-point in the head's frame (the head joint itself without eyes).
#[inline]
fn eye_middle(chain: &GazeChain) -> Vec3A {
    match chain.eye_indices() {
        Some([left, right]) => {
            let joints = chain.joints();
            0.5 * (Vec3A::from(joints[left].offset) + Vec3A::from(joints[right].offset))
        }
        None => Vec3A::ZERO,
    }
}

/// The global eye (position, forward) in the world for a head frame.
#[inline]
fn global_eye(chain: &GazeChain, head: &Frame) -> (Vec3A, Vec3A) {
    (
        head.position + head.rotation.mul_vec3a(eye_middle(chain)),
        head.rotation.mul_vec3a(Vec3A::from(chain.eye_forward())),
    )
}

/// Resolves the remembered side from the target direction `to_target` seen from an eye
/// looking along `forward` with up `up`; returns true if it switched while the target is
/// in the back half.
fn update_side(
    to_target: Vec3A,
    forward: Vec3A,
    up: Vec3A,
    side: &mut TurnSide,
    prepared: &Prepared,
) -> bool {
    let left = up.cross(forward);
    let ahead = to_target.dot(forward);
    let across = to_target.dot(left);
    let in_zone = ahead < 0.0 && across.abs() < prepared.zone().tan_hysteresis * -ahead;
    let natural = if across > 0.0 {
        1
    } else if across < 0.0 {
        -1
    } else {
        0
    };
    let old = side.0;
    if !in_zone || old == 0 {
        if natural != 0 {
            side.0 = natural;
        } else if old == 0 {
            side.0 = 1;
        }
    }
    old != 0 && side.0 != old && ahead < 0.0
}

/// Per lane, the direction to aim at for `to_target`, applying the behind-the-character
/// rule with the (resolved) side `side_sign` (±1).
#[inline(always)]
fn behind_adjusted<W: Wide>(
    to_target: V3<W>,
    forward: V3<W>,
    up: V3<W>,
    side_sign: Floats<W>,
    prepared: &Prepared,
) -> V3<W> {
    let ahead = to_target.dot(forward);
    let behind = ahead.cmplt(Floats::zero());
    if !behind.any() {
        return to_target;
    }
    let zone = prepared.zone();
    let left = up.cross(forward);
    let across = to_target.dot(left);
    let back = -ahead;
    let in_zone = behind & across.abs().cmplt(zone.tan_hysteresis * back);
    let on_side =
        (across * side_sign).cmpgt(Floats::zero()) & across.abs().cmpge(zone.tan_clearance * back);
    let replace = in_zone & !on_side;
    if !replace.any() {
        return to_target;
    }
    let height = to_target.dot(up);
    let horizontal = (ahead * ahead + across * across).sqrt();
    let aimed = forward
        .scale(-horizontal * zone.cos_clearance)
        .add(left.scale(side_sign * horizontal * zone.sin_clearance))
        .add(up.scale(height));
    V3::select(replace, aimed, to_target)
}

/// Per lane, a rotation of angle θ ∈ [0, π] about a unit axis, kept as the cosine and sine
/// of θ/2, so that the solver never needs θ itself.
#[derive(Debug, Clone, Copy)]
struct Turn<W> {
    axis: V3<W>,
    cos: Floats<W>,
    sin: Floats<W>,
}

impl<W: Wide> Turn<W> {
    /// θ, radians.
    #[inline(always)]
    fn angle(self) -> Floats<W> {
        2.0 * atan2_upper(self.sin, self.cos)
    }

    /// The rotation by θ − `reserve` (given by its half-angle's cosine and sine) about the
    /// same axis, and where that is more than nothing (θ > reserve).
    #[inline(always)]
    fn less(self, reserve_cos: Floats<W>, reserve_sin: Floats<W>) -> (Turn<W>, Mask<W>) {
        let sin = self.sin * reserve_cos - self.cos * reserve_sin;
        let turn = Turn {
            axis: self.axis,
            cos: self.cos * reserve_cos + self.sin * reserve_sin,
            sin,
        };
        (turn, sin.cmpgt(Floats::zero()))
    }

    /// The rotation by `t`·θ, `t ∈ (0, 1]`: a normalised lerp from identity with
    /// Kapoulkine's parameter correction (within about 10⁻³ of `t`·θ; exact for `t = 1`).
    #[inline(always)]
    fn fraction(self, t: Floats<W>) -> Turn<W> {
        let d = self.cos;
        let k_a = 1.0904 + d * (-3.2452 + d * (3.55645 - d * 1.43519));
        let k_b = 0.848_013 + d * (-1.06021 + d * 0.215_638);
        let half = t - 0.5;
        let k = k_a * half * half + k_b;
        let u = t + t * half * (t - 1.0) * k;
        let cos = 1.0 + u * (self.cos - 1.0);
        let sin = u * self.sin;
        let norm = (cos * cos + sin * sin).sqrt().recip();
        let whole = t.cmpge(Floats::one());
        Turn {
            axis: self.axis,
            cos: Floats::select(whole, self.cos, cos * norm),
            sin: Floats::select(whole, self.sin, sin * norm),
        }
    }
}

/// Per lane, the shortest rotation that turns the unit `forward` towards `to_target` (any
/// length), faded out near the eye. `fallback_axis` is used when the two are
/// (anti)parallel. Square roots only, no trigonometry (except within the near distance).
#[inline(always)]
fn gaze_rotation<W: Wide>(
    forward: V3<W>,
    to_target: V3<W>,
    fallback_axis: V3<W>,
    prepared: &Prepared,
) -> Turn<W> {
    let cross = forward.cross(to_target);
    let ahead = forward.dot(to_target);
    let cross_squared = cross.length_squared();
    let distance_squared = ahead * ahead + cross_squared;
    // False for NaN too.
    let valid = distance_squared.cmpgt(Floats::splat(1e-12));
    let distance = distance_squared.sqrt();
    let cross_length = cross_squared.sqrt();
    // (|v| + f·v, f × v) is the rotation from f to v, up to its length.
    let w = distance + ahead;
    let norm = (w * w + cross_squared).sqrt().recip();
    let generic = valid & cross_squared.cmpgt(1e-14 * distance_squared);
    let mut turn = Turn {
        axis: cross.scale(cross_length.recip()),
        cos: w * norm,
        sin: cross_length * norm,
    };
    if !generic.all() {
        // Degenerate: straight ahead (or at the eye) is no turn, straight behind a half turn.
        let ahead_positive = ahead.cmpgt(Floats::zero());
        let degenerate_cos = Floats::select(ahead_positive | !valid, Floats::one(), Floats::zero());
        turn = Turn {
            axis: V3::select(generic, turn.axis, fallback_axis),
            cos: Floats::select(generic, turn.cos, degenerate_cos),
            sin: Floats::select(generic, turn.sin, 1.0 - degenerate_cos),
        };
    }
    let near = valid & distance.cmplt(Floats::splat(prepared.near_distance));
    if near.any() {
        let t = distance / prepared.near_distance;
        let faded = turn.angle() * (t * t * (3.0 - 2.0 * t));
        let (sin, cos) = sin_cos_quarter(0.5 * faded);
        turn.cos = Floats::select(near, cos, turn.cos);
        turn.sin = Floats::select(near, sin, turn.sin);
    }
    turn
}

/// Per lane, a joint's limits.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Limits<W> {
    axis: V3<W>,
    min_cos: Floats<W>,
    min_sin: Floats<W>,
    max_cos: Floats<W>,
    max_sin: Floats<W>,
    cone_cos: Floats<W>,
    cone_sin: Floats<W>,
}

impl<W: Wide> Limits<W> {
    /// The same limits in every lane.
    #[inline(always)]
    pub(crate) fn splat(limits: &JointLimits) -> Limits<W> {
        let (cone, min, max) = limits.half_angles();
        Limits {
            axis: V3::splat(limits.twist_axis().into()),
            min_cos: Floats::splat(min.0),
            min_sin: Floats::splat(min.1),
            max_cos: Floats::splat(max.0),
            max_sin: Floats::splat(max.1),
            cone_cos: Floats::splat(cone.0),
            cone_sin: Floats::splat(cone.1),
        }
    }

    /// Each lane's limits of joint `indices[lane]` (free past the lane's joints).
    #[inline(always)]
    pub(crate) fn of_joints(
        chains: &[&GazeChain; MAX_LANES],
        same_chain: bool,
        indices: [usize; MAX_LANES],
    ) -> Limits<W> {
        let uniform = indices.iter().all(|index| *index == indices[0]);
        if same_chain && uniform {
            if let Some(joint) = chains[0].joints().get(indices[0]) {
                return Limits::splat(&joint.limits);
            }
        }
        Limits::gather(|i| match chains[i].joints().get(indices[i]) {
            Some(joint) => joint.limits,
            None => JointLimits::free(Vec3::Y),
        })
    }

    #[inline(always)]
    pub(crate) fn gather(f: impl Fn(usize) -> JointLimits) -> Limits<W> {
        // Rows: the twist axis's x, y, z, then the cosine and sine of the half angles of
        // the twist minimum, the twist maximum and the cone.
        let mut rows = [[0.0; MAX_LANES]; 9];
        for i in 0..W::LANES {
            let limits = f(i);
            let axis = limits.twist_axis();
            let (cone, min, max) = limits.half_angles();
            let column = [
                axis.x, axis.y, axis.z, min.0, min.1, max.0, max.1, cone.0, cone.1,
            ];
            for (row, value) in rows.iter_mut().zip(column) {
                row[i] = value;
            }
        }
        Limits {
            axis: V3 {
                x: Floats::load(&rows[0]),
                y: Floats::load(&rows[1]),
                z: Floats::load(&rows[2]),
            },
            min_cos: Floats::load(&rows[3]),
            min_sin: Floats::load(&rows[4]),
            max_cos: Floats::load(&rows[5]),
            max_sin: Floats::load(&rows[6]),
            cone_cos: Floats::load(&rows[7]),
            cone_sin: Floats::load(&rows[8]),
        }
    }

    /// Per lane, [`JointLimits::clamp`]: the rotation within the limits nearest to
    /// `rotation`, and where it is `rotation` itself, unchanged.
    #[inline(always)]
    pub(crate) fn clamp(&self, rotation: Q4<W>) -> (Q4<W>, Mask<W>) {
        let projection = rotation.vector().dot(self.axis);
        let w = rotation.w;
        // With a slack of CLAMP_SLACK, so that a rotation clamped before counts as inside.
        let slack = Floats::splat(-CLAMP_SLACK);
        let twist_inside = (self.min_cos * projection - self.min_sin * w).cmpge(slack)
            & (w * self.max_sin - projection * self.max_cos).cmpge(slack);
        let twist_length_squared = w * w + projection * projection;
        let swing_inside = twist_length_squared.cmpge(self.cone_cos * self.cone_cos + slack);
        let inside = twist_inside & swing_inside;
        if inside.all() {
            return (rotation, inside);
        }
        let length = twist_length_squared.sqrt();
        let degenerate = length.cmplt(Floats::splat(1e-9));
        let inverse = length.recip();
        let twist_cos = Floats::select(degenerate, Floats::one(), w * inverse);
        let twist_sin = Floats::select(degenerate, Floats::zero(), projection * inverse);
        let twist = Q4::from_parts(self.axis.scale(twist_sin), twist_cos);
        let swing = rotation.mul(twist.conjugate());
        let to_min = twist_cos * self.min_cos + twist_sin * self.min_sin;
        let to_max = twist_cos * self.max_cos + twist_sin * self.max_sin;
        let nearer_min = to_min.cmpgt(to_max);
        let twist_cos = Floats::select(
            twist_inside,
            twist_cos,
            Floats::select(nearer_min, self.min_cos, self.max_cos),
        );
        let twist_sin = Floats::select(
            twist_inside,
            twist_sin,
            Floats::select(nearer_min, self.min_sin, self.max_sin),
        );
        // The swing's scalar part is the twist's length (see above): the swing is out of its
        // cone where the fast test said so.
        let swing = if swing_inside.all() {
            swing
        } else {
            let swing_vector = swing.vector();
            let swing_sin = swing_vector.length_squared().sqrt();
            let clamped_swing = Q4::select(
                swing_sin.cmpgt(Floats::splat(1e-9)),
                Q4::from_parts(swing_vector.scale(self.cone_sin / swing_sin), self.cone_cos),
                Q4::identity(),
            );
            Q4::select(swing_inside, swing, clamped_swing)
        };
        // Both factors are unit quaternions: so is their product.
        let clamped = swing.mul(Q4::from_parts(self.axis.scale(twist_sin), twist_cos));
        (Q4::select(inside, rotation, clamped), inside)
    }
}

/// Per lane, turns a joint whose pre-delta world rotation is `joint_rotation` by the world
/// rotation `turn`, within its limits: returns the local delta and the world rotation it
/// makes.
#[inline(always)]
fn turn_joint<W: Wide>(limits: &Limits<W>, joint_rotation: Q4<W>, turn: Turn<W>) -> (Q4<W>, Q4<W>) {
    let local_axis = joint_rotation.conjugate().rotate(turn.axis);
    let wanted = Q4::from_parts(local_axis.scale(turn.sin), turn.cos);
    let (delta, unchanged) = limits.clamp(wanted);
    let world = Q4::from_parts(turn.axis.scale(turn.sin), turn.cos);
    if unchanged.all() {
        return (delta, world);
    }
    // jr · delta · jr⁻¹: the delta's vector part seen in the world.
    let clamped_world = Q4::from_parts(joint_rotation.rotate(delta.vector()), delta.w);
    (delta, Q4::select(unchanged, world, clamped_world))
}

/// One character's part in a body solve.
#[derive(Debug, Clone, Copy)]
pub(crate) struct BodyLane<'a> {
    pub(crate) chain: &'a GazeChain,
    pub(crate) character: &'a CharacterTransform,
    pub(crate) base: &'a [Quat],
    pub(crate) head_target: Vec3,
    pub(crate) side: TurnSide,
}

/// Per lane, a world frame.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Frames<W> {
    pub(crate) position: V3<W>,
    pub(crate) rotation: Q4<W>,
}

impl<W: Wide> Frames<W> {
    /// Each lane's chain root.
    #[inline(always)]
    pub(crate) fn roots(
        chains: &[&GazeChain; MAX_LANES],
        characters: &[&CharacterTransform; MAX_LANES],
    ) -> Frames<W> {
        Frames {
            position: V3::gather(|i| root_frame(chains[i], characters[i]).position),
            rotation: Q4::gather(|i| characters[i].rotation),
        }
    }

    /// Moves to the next joint down the chain: `offset` in the current frame, then `rotation`.
    #[inline(always)]
    pub(crate) fn descend(&mut self, offset: V3<W>, rotation: Q4<W>) {
        self.position = self.position.add(self.rotation.rotate(offset));
        self.rotation = self.rotation.mul(rotation);
    }
}

/// Each lane's joint `index` offset (zero past the lane's body joints).
#[inline(always)]
pub(crate) fn offsets<W: Wide>(
    chains: &[&GazeChain; MAX_LANES],
    same_chain: bool,
    index: usize,
) -> V3<W> {
    if same_chain {
        return V3::splat(chains[0].joints()[index].offset.into());
    }
    V3::gather(|i| match chains[i].joints().get(index) {
        Some(joint) => joint.offset.into(),
        None => Vec3A::ZERO,
    })
}

/// True if every lane has the same chain.
#[inline(always)]
pub(crate) fn same_chain(chains: &[&GazeChain; MAX_LANES]) -> bool {
    chains.iter().all(|chain| std::ptr::eq(*chain, chains[0]))
}

/// Each lane's base rotation of joint `index` (identity past the lane's body joints, which
/// number `body[lane]`); `shared` if every lane has the same base pose.
#[inline(always)]
fn base_rotations<W: Wide>(
    lane: &[BodyLane<'_>; MAX_LANES],
    body: &[usize; MAX_LANES],
    shared: bool,
    index: usize,
) -> Q4<W> {
    if shared {
        return Q4::splat(lane[0].base[index]);
    }
    Q4::gather(|i| {
        if index < body[i] {
            lane[i].base[index]
        } else {
            Quat::IDENTITY
        }
    })
}

/// The spatial solve of the body joints (spine, cervicals, head) of up to `W::LANES`
/// characters,
/// one per lane, each towards its `head_target`: writes the deltas that are not identity
/// into `goals[joint]` (per lane; they come in as identity), and returns each lane's
/// solution and turn side, and the heads' final world frames. `None` lanes are skipped.
/// Inputs are assumed checked.
#[inline(always)]
pub(crate) fn solve_bodies<W: Wide>(
    prepared: &Prepared,
    lanes: [Option<BodyLane<'_>>; MAX_LANES],
    goals: &mut [Q4<W>; MAX_BODY_JOINTS],
) -> ([Option<(SpatialSolution, TurnSide)>; MAX_LANES], Frames<W>) {
    let Some(filler) = lanes.iter().flatten().next().copied() else {
        return (
            [None; MAX_LANES],
            Frames {
                position: V3::zero(),
                rotation: Q4::identity(),
            },
        );
    };
    let lane: [BodyLane<'_>; MAX_LANES] = std::array::from_fn(|i| lanes[i].unwrap_or(filler));
    let chains: [&GazeChain; MAX_LANES] = lane.map(|l| l.chain);
    let characters: [&CharacterTransform; MAX_LANES] = lane.map(|l| l.character);
    let same = same_chain(&chains);
    let body: [usize; MAX_LANES] = chains.map(GazeChain::body_count);
    let joints = body.iter().copied().max().unwrap_or(0);
    let shared_base = same && lane.iter().all(|l| std::ptr::eq(l.base, lane[0].base));
    // Multiplying by an identity base rotation changes no bit: skipped when every lane shares
    // one base pose and this joint's is identity (a crowd at rest).
    let identity_base = |index: usize| shared_base && lane[0].base[index] == Quat::IDENTITY;
    // The global eye in the base posture.
    let roots = Frames::roots(&chains, &characters);
    let spine_count = chains[0].spine_count();
    // The base posture's head frame, and its frame above the spine (where the solve starts
    // if no spine joint moves).
    let mut frame = roots;
    let mut above_spine = roots;
    for index in 0..joints {
        if identity_base(index) {
            frame.position = frame
                .position
                .add(frame.rotation.rotate(offsets(&chains, same, index)));
        } else {
            frame.descend(
                offsets(&chains, same, index),
                base_rotations(&lane, &body, shared_base, index),
            );
        }
        if index + 1 == spine_count {
            above_spine = frame;
        }
    }
    let base_head = frame;

    let mut eye = frame
        .position
        .add(frame.rotation.rotate(V3::gather(|i| eye_middle(chains[i]))));
    let mut forward = frame
        .rotation
        .rotate(V3::gather(|i| chains[i].eye_forward().into()));
    let up = frame
        .rotation
        .rotate(V3::gather(|i| chains[i].eye_up().into()));
    // q_l, θ and the turn side.
    let target = V3::gather(|i| lane[i].head_target.into());
    let to_target = target.sub(eye);
    let mut sides = lane.map(|l| l.side);
    let mut switched = [false; MAX_LANES];
    for i in 0..W::LANES {
        if lanes[i].is_some() {
            switched[i] = update_side(
                to_target.lane(i),
                forward.lane(i),
                up.lane(i),
                &mut sides[i],
                prepared,
            );
        }
    }
    let side_sign = gather(|i| sides[i].resolved());
    let aimed = behind_adjusted(to_target, forward, up, side_sign, prepared);
    let first = gaze_rotation(forward, aimed, up.scale(side_sign), prepared);
    // Recruitment and the angle each group leaves to the groups above it.
    let has_eyes = mask(|i| chains[i].has_eyes());
    let (eyes_only_cos, eyes_only_sin) = prepared.eyes_only_half;
    let (spine_reserve_cos, spine_reserve_sin) = prepared.eyes_head_and_neck_half;
    let head_recruited = !has_eyes | first.cos.cmplt(Floats::splat(eyes_only_cos));
    let spine_recruited = first.cos.cmplt(Floats::splat(spine_reserve_cos));
    let head_reserve_cos = Floats::select(has_eyes, Floats::splat(eyes_only_cos), Floats::one());
    let head_reserve_sin = Floats::select(has_eyes, Floats::splat(eyes_only_sin), Floats::zero());

    // Joints below the first that may move keep their base frames: start above them.
    let (first_joint, mut frame) = if !(head_recruited | spine_recruited).any() {
        (joints, base_head)
    } else if same && !spine_recruited.any() {
        (spine_count, above_spine)
    } else {
        (0, roots)
    };
    for index in first_joint..joints {
        frame.position = frame
            .position
            .add(frame.rotation.rotate(offsets(&chains, same, index)));
        let joint_rotation = if identity_base(index) {
            frame.rotation
        } else {
            frame
                .rotation
                .mul(base_rotations(&lane, &body, shared_base, index))
        };
        let in_chain = if same {
            Mask::splat(true)
        } else {
            mask(|i| index < body[i])
        };
        let is_spine = if same {
            Mask::splat(index < spine_count)
        } else {
            mask(|i| index < chains[i].spine_count())
        };
        let recruited = in_chain & ((is_spine & spine_recruited) | (!is_spine & head_recruited));
        let mut delta = Q4::identity();
        if recruited.any() {
            let remaining = if index == 0 {
                first
            } else {
                let aimed = behind_adjusted(target.sub(eye), forward, up, side_sign, prepared);
                gaze_rotation(forward, aimed, up.scale(side_sign), prepared)
            };
            let (budget, some_left) = remaining.less(
                Floats::select(is_spine, Floats::splat(spine_reserve_cos), head_reserve_cos),
                Floats::select(is_spine, Floats::splat(spine_reserve_sin), head_reserve_sin),
            );
            let moves = recruited & some_left;
            if moves.any() {
                // c_i / Σ_{j ≥ i} c_j with c_i ∝ n + 1 − i: 2 / (joints above + 2).
                let above_in_group = |chain: &GazeChain| {
                    if index < chain.spine_count() {
                        (chain.spine_count() - 1 - index) as f32
                    } else {
                        chain.head_index().saturating_sub(index) as f32
                    }
                };
                let share = if same {
                    Floats::splat(2.0 / (above_in_group(chains[0]) + 2.0))
                } else {
                    2.0 / (gather(|i| above_in_group(chains[i])) + 2.0)
                };
                let limits = Limits::of_joints(&chains, same, [index; MAX_LANES]);
                let (turned, turn) = turn_joint(&limits, joint_rotation, budget.fraction(share));
                delta = Q4::select(moves, turned, Q4::identity());
                // The joint turns the global eye rigidly about itself.
                let moved_eye = frame.position.add(turn.rotate(eye.sub(frame.position)));
                eye = V3::select(moves, moved_eye, eye);
                forward = V3::select(moves, turn.rotate(forward), forward);
                // `up` stays the head's up in the base posture: it only orients the behind
                // zone, and the spine and neck mostly turn about it.
                goals[index] = delta;
            }
        }
        frame.rotation = joint_rotation.mul(delta);
    }
    let angles = first.angle();
    let solutions = std::array::from_fn(|i| {
        lanes[i].filter(|_| i < W::LANES).map(|_| {
            (
                SpatialSolution {
                    gaze_angle: angles.lane(i),
                    side_switched: switched[i],
                },
                sides[i],
            )
        })
    });
    (solutions, frame)
}

/// Per lane, one eye's frame before its delta: position, rotation, and the eye's forward and
/// up axes in its own frame. Lanes without eyes get the head's global eye.
#[derive(Debug, Clone, Copy)]
pub(crate) struct EyeFrames<W: Wide> {
    pub(crate) position: V3<W>,
    pub(crate) rotation: Q4<W>,
    pub(crate) local_forward: V3<W>,
    local_up: V3<W>,
    /// Lanes whose chain has eyes.
    pub(crate) has_eyes: Mask<W>,
    /// Each lane's joint index of this eye (0 without eyes).
    pub(crate) index: [usize; MAX_LANES],
}

impl<W: Wide> EyeFrames<W> {
    /// Eye `eye` (0 left, 1 right) of each lane, below the heads' final frames.
    #[inline(always)]
    pub(crate) fn new(
        chains: &[&GazeChain; MAX_LANES],
        bases: &[&[Quat]; MAX_LANES],
        heads: &Frames<W>,
        eye: usize,
    ) -> EyeFrames<W> {
        let index = chains.map(|chain| chain.eye_indices().map_or(0, |eyes| eyes[eye]));
        let has_eyes = mask(|i| chains[i].has_eyes());
        // The eye's offset and its forward and up axes in its own frame.
        let eye_data = |chain: &GazeChain, index: usize| -> (Vec3A, Vec3A, Vec3A) {
            let (forward, up) = (chain.eye_forward().into(), chain.eye_up().into());
            if !chain.has_eyes() {
                return (eye_middle(chain), forward, up);
            }
            let joint = &chain.joints()[index];
            if joint.rest == Quat::IDENTITY {
                (joint.offset.into(), forward, up)
            } else {
                let to_eye = joint.rest.conjugate();
                (
                    joint.offset.into(),
                    to_eye.mul_vec3a(forward),
                    to_eye.mul_vec3a(up),
                )
            }
        };
        let (offset, local_forward, local_up) = if same_chain(chains) {
            let (offset, forward, up) = eye_data(chains[0], index[0]);
            (V3::splat(offset), V3::splat(forward), V3::splat(up))
        } else {
            let data: [(Vec3A, Vec3A, Vec3A); MAX_LANES] =
                std::array::from_fn(|i| eye_data(chains[i], index[i]));
            (
                V3::gather(|i| data[i].0),
                V3::gather(|i| data[i].1),
                V3::gather(|i| data[i].2),
            )
        };
        let rotation = if bases.iter().all(|base| std::ptr::eq(*base, bases[0]))
            && same_chain(chains)
            && (!chains[0].has_eyes() || bases[0][index[0]] == Quat::IDENTITY)
        {
            // Every lane's eye rests at identity in its base pose: nothing to multiply.
            heads.rotation
        } else {
            heads.rotation.mul(Q4::gather(|i| {
                if chains[i].has_eyes() {
                    bases[i][index[i]]
                } else {
                    Quat::IDENTITY
                }
            }))
        };
        EyeFrames {
            position: heads.position.add(heads.rotation.rotate(offset)),
            rotation,
            local_forward,
            local_up,
            has_eyes,
            index,
        }
    }

    /// Per lane, the vergence delta that turns this eye onto `target` (within its limits);
    /// identity for lanes without eyes.
    #[inline(always)]
    pub(crate) fn goal(
        &self,
        chains: &[&GazeChain; MAX_LANES],
        prepared: &Prepared,
        target: V3<W>,
        side_sign: Floats<W>,
    ) -> Q4<W> {
        let forward = self.rotation.rotate(self.local_forward);
        let up = self.rotation.rotate(self.local_up);
        let aimed = behind_adjusted(target.sub(self.position), forward, up, side_sign, prepared);
        let turn = gaze_rotation(forward, aimed, up.scale(side_sign), prepared);
        let limits = Limits::of_joints(chains, same_chain(chains), self.index);
        let (delta, _) = turn_joint(&limits, self.rotation, turn);
        Q4::select(
            self.has_eyes & turn.sin.cmpgt(Floats::zero()),
            delta,
            Q4::identity(),
        )
    }

    /// Per lane, the unit gaze direction for the eye's delta `delta`.
    #[inline(always)]
    pub(crate) fn direction(&self, delta: Q4<W>) -> V3<W> {
        let direction = self.rotation.mul(delta).rotate(self.local_forward);
        direction.scale(direction.length_squared().sqrt().recip())
    }
}

/// Eye positions and gaze directions in the world for a head frame and the eyes' deltas.
pub(crate) fn eye_rays_unchecked(
    chain: &GazeChain,
    head: &Frame,
    base: &[Quat],
    deltas: &[Quat],
) -> EyeRays {
    match chain.eye_indices() {
        Some(eyes) => {
            let mut rays = EyeRays {
                origins: [Vec3::ZERO; 2],
                directions: [Vec3::ZERO; 2],
            };
            for (slot, index) in eyes.into_iter().enumerate() {
                let joint = &chain.joints()[index];
                let local_forward = joint.rest.conjugate() * chain.eye_forward();
                let position = head.position + head.rotation.mul_vec3a(Vec3A::from(joint.offset));
                let rotation = head.rotation * base[index] * deltas[index];
                rays.origins[slot] = position.into();
                rays.directions[slot] = (rotation * local_forward).normalize_or_zero();
            }
            rays
        }
        None => {
            let (position, forward) = global_eye(chain, head);
            EyeRays {
                origins: [position.into(); 2],
                directions: [forward.normalize_or_zero().into(); 2],
            }
        }
    }
}

/// The group of joint `index` (a helper for per-group timing).
#[inline]
pub(crate) fn group_of(chain: &GazeChain, index: usize) -> JointGroup {
    chain.joints()[index].role.group()
}

/// Deltas all identity, as many as the largest chain.
pub(crate) const IDENTITY_DELTAS: [Quat; MAX_CHAIN_JOINTS] = [Quat::IDENTITY; MAX_CHAIN_JOINTS];

#[cfg(test)]
mod tests {
    use super::*;
    use std::f32::consts::PI;

    fn human() -> GazeChain {
        GazeChain::human(Vec3::Y, Vec3::Z)
    }

    fn rest(chain: &GazeChain) -> Vec<Quat> {
        chain.joints().iter().map(|j| j.rest).collect()
    }

    fn solve_at(
        chain: &GazeChain,
        target: Vec3,
        side: &mut TurnSide,
    ) -> (Vec<Quat>, SpatialSolution) {
        let mut deltas = vec![Quat::NAN; chain.joint_count()];
        let solution = solve(
            chain,
            &SpatialConfig::default(),
            &CharacterTransform::IDENTITY,
            &rest(chain),
            target,
            target,
            side,
            &mut deltas,
        )
        .unwrap();
        (deltas, solution)
    }

    /// A target at `yaw` degrees to the left, at eye height, `distance` metres away.
    fn around(yaw: f32, distance: f32) -> Vec3 {
        let yaw = yaw.to_radians();
        Vec3::new(yaw.sin() * distance, 1.62, yaw.cos() * distance)
    }

    #[test]
    fn shares_follow_the_linear_formula() {
        // Unlimited joints and a far target: the spine shares are c_i = 2(n+1−i)/(n(n+1)).
        let mut joints = human().joints().to_vec();
        for joint in &mut joints {
            joint.limits = JointLimits::free(joint.limits.twist_axis());
        }
        use super::super::chain::JointLimits;
        let chain = GazeChain::new(&joints, Vec3::Z, Vec3::Y, Vec3::Y * 0.95).unwrap();
        let (deltas, solution) = solve_at(&chain, around(100.0, 1000.0), &mut TurnSide::default());
        assert!((solution.gaze_angle - 100f32.to_radians()).abs() < 1e-3);
        let spine: Vec<f32> = deltas[..5]
            .iter()
            .map(|q| q.angle_between(Quat::IDENTITY))
            .collect();
        let budget = 70f32.to_radians();
        for (i, angle) in spine.iter().enumerate() {
            let expected = budget * 2.0 * (5 - i) as f32 / 30.0;
            assert!(
                (angle - expected).abs() < 2e-3,
                "spine {i}: {angle} vs {expected}"
            );
        }
        let neck: Vec<f32> = deltas[5..8]
            .iter()
            .map(|q| q.angle_between(Quat::IDENTITY))
            .collect();
        let budget = 15f32.to_radians();
        for (i, angle) in neck.iter().enumerate() {
            let expected = budget * 2.0 * (3 - i) as f32 / 12.0;
            assert!(
                (angle - expected).abs() < 2e-3,
                "neck {i}: {angle} vs {expected}"
            );
        }
    }

    #[test]
    fn bands_recruit_groups() {
        let chain = human();
        let (deltas, solution) = solve_at(&chain, around(10.0, 3.0), &mut TurnSide::default());
        assert!(solution.gaze_angle < 15f32.to_radians());
        assert!(deltas[..8].iter().all(|q| *q == Quat::IDENTITY));
        assert!(deltas[8] != Quat::IDENTITY);
        let (deltas, _) = solve_at(&chain, around(25.0, 3.0), &mut TurnSide::default());
        assert!(deltas[..5].iter().all(|q| *q == Quat::IDENTITY));
        assert!(deltas[5..8].iter().all(|q| *q != Quat::IDENTITY));
        let (deltas, _) = solve_at(&chain, around(60.0, 3.0), &mut TurnSide::default());
        assert!(deltas.iter().all(|q| *q != Quat::IDENTITY));
    }

    #[test]
    fn eyes_converge_on_the_target() {
        let chain = human();
        for yaw in [0.0, 5.0, 20.0, -40.0, 80.0, -100.0] {
            let target = around(yaw, 2.0) + Vec3::Y * 0.3;
            let (deltas, _) = solve_at(&chain, target, &mut TurnSide::default());
            let rays = eye_rays(
                &chain,
                &CharacterTransform::IDENTITY,
                &rest(&chain),
                &deltas,
            )
            .unwrap();
            for eye in 0..2 {
                let wanted = (target - rays.origins[eye]).normalize();
                let error = rays.directions[eye].angle_between(wanted);
                assert!(error < 0.5f32.to_radians(), "yaw {yaw} eye {eye}: {error}");
            }
        }
    }

    #[test]
    fn behind_keeps_its_side_with_hysteresis() {
        let chain = human();
        let mut side = TurnSide::UNDECIDED;
        let head_yaw = |deltas: &[Quat]| {
            let (_, twist) = chain.joints()[7].limits.swing_twist_angles(deltas[7]);
            twist
        };
        // Exactly behind, undecided: left.
        let (deltas, _) = solve_at(&chain, Vec3::new(0.0, 1.62, -3.0), &mut side);
        assert_eq!(side, TurnSide::LEFT);
        assert!(head_yaw(&deltas) > 0.0);
        // Sweep from 150° left through behind to 160° right (−160°): still turning left.
        for yaw in [150.0, 170.0, 179.0, 181.0, 190.0, 200.0, 205.0] {
            let (deltas, solution) = solve_at(&chain, around(yaw, 3.0), &mut side);
            assert_eq!(side, TurnSide::LEFT, "at {yaw}");
            assert!(!solution.side_switched);
            assert!(head_yaw(&deltas) > 0.0, "at {yaw}");
        }
        // Clearly on the right: switch, reported once.
        let (deltas, solution) = solve_at(&chain, around(215.0, 3.0), &mut side);
        assert_eq!(side, TurnSide::RIGHT);
        assert!(solution.side_switched);
        assert!(head_yaw(&deltas) < 0.0);
        let (_, solution) = solve_at(&chain, around(200.0, 3.0), &mut side);
        assert!(!solution.side_switched);
        assert_eq!(side, TurnSide::RIGHT);
    }

    #[test]
    fn degenerate_targets_give_finite_deltas() {
        let chain = human();
        let eye = chain.rest_eye_position();
        for target in [
            eye,
            eye + Vec3::Y * 5.0,
            eye - Vec3::Z * 2.0,
            eye + Vec3::Z * 1e-7,
            eye - Vec3::Y * 3.0,
        ] {
            let (deltas, _) = solve_at(&chain, target, &mut TurnSide::default());
            assert!(
                deltas
                    .iter()
                    .all(|q| q.is_finite() && (q.length() - 1.0).abs() < 1e-4),
                "{target}"
            );
        }
        let (deltas, solution) = solve_at(&chain, eye, &mut TurnSide::default());
        assert_eq!(solution.gaze_angle, 0.0);
        assert!(deltas[..8].iter().all(|q| *q == Quat::IDENTITY));
        let _ = PI;
    }

    #[test]
    fn bad_inputs_are_errors() {
        let chain = human();
        let mut deltas = vec![Quat::IDENTITY; 10];
        let base = rest(&chain);
        let call = |base: &[Quat], target: Vec3, deltas: &mut [Quat]| {
            solve(
                &chain,
                &SpatialConfig::default(),
                &CharacterTransform::IDENTITY,
                base,
                target,
                target,
                &mut TurnSide::default(),
                deltas,
            )
        };
        assert!(matches!(
            call(&base[..9], Vec3::Z, &mut deltas),
            Err(Error::InvalidArgument(_))
        ));
        assert!(matches!(
            call(&base, Vec3::NAN, &mut deltas),
            Err(Error::NonFinite(_))
        ));
        assert!(matches!(
            call(&base, Vec3::Z, &mut deltas[..3]),
            Err(Error::InvalidArgument(_))
        ));
    }
}
