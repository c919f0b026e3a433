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
//!   the character keeps turning the same way. The side changes only once the target is
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

use std::cell::Cell;

use glam::{Quat, Vec3, Vec3A};

use super::chain::{GazeChain, JointGroup, JointLimits, MAX_CHAIN_JOINTS};
use super::rotation::{atan2_upper, sin_cos_quarter};
use super::CharacterTransform;
use crate::error::{ensure_all_finite, ensure_finite, Error, Result};

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
    let mut solved = IDENTITY_DELTAS;
    let (solution, head) = solve_body_unchecked(
        chain,
        &prepared,
        character,
        base,
        head_target,
        side,
        &mut solved,
    );
    aim_eyes_unchecked(
        chain,
        &prepared,
        &head,
        base,
        eye_target,
        *side,
        &mut solved,
    );
    let count = chain.joint_count();
    deltas[..count].copy_from_slice(&solved[..count]);
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
    let (sin, cos) = sin_cos_quarter(0.5 * angle);
    (cos, sin)
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

/// The global eye (position, forward, up) in the world for a head frame.
#[inline]
fn global_eye(chain: &GazeChain, head: &Frame) -> (Vec3A, Vec3A, Vec3A) {
    let position = match chain.eye_indices() {
        Some([left, right]) => {
            let joints = chain.joints();
            let middle =
                0.5 * (Vec3A::from(joints[left].offset) + Vec3A::from(joints[right].offset));
            head.position + head.rotation.mul_vec3a(middle)
        }
        None => head.position,
    };
    (
        position,
        head.rotation.mul_vec3a(Vec3A::from(chain.eye_forward())),
        head.rotation.mul_vec3a(Vec3A::from(chain.eye_up())),
    )
}

/// Resolves the remembered side from the target direction `to_target` seen from an eye
/// looking along `forward` with up `up`; returns true if it switched while the target is
/// in the back half.
#[inline]
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

/// The direction to aim at for `to_target`, applying the behind-the-character rule with
/// the (resolved) side `side_sign`.
#[inline]
fn behind_adjusted(
    to_target: Vec3A,
    forward: Vec3A,
    up: Vec3A,
    side_sign: f32,
    prepared: &Prepared,
) -> Vec3A {
    let ahead = to_target.dot(forward);
    if ahead >= 0.0 {
        return to_target;
    }
    let zone = prepared.zone();
    let left = up.cross(forward);
    let across = to_target.dot(left);
    let back = -ahead;
    if across.abs() >= zone.tan_hysteresis * back {
        return to_target;
    }
    if across * side_sign > 0.0 && across.abs() >= zone.tan_clearance * back {
        return to_target;
    }
    let height = to_target.dot(up);
    let horizontal = (ahead * ahead + across * across).sqrt();
    forward * (-horizontal * zone.cos_clearance)
        + left * (side_sign * horizontal * zone.sin_clearance)
        + up * height
}

/// A rotation of angle θ ∈ [0, π] about a unit axis, kept as the cosine and sine of θ/2,
/// so that the solver never needs θ itself.
#[derive(Debug, Clone, Copy)]
struct Turn {
    axis: Vec3A,
    cos: f32,
    sin: f32,
}

impl Turn {
    /// No rotation.
    fn none(axis: Vec3A) -> Turn {
        Turn {
            axis,
            cos: 1.0,
            sin: 0.0,
        }
    }

    /// θ, radians.
    fn angle(self) -> f32 {
        2.0 * atan2_upper(self.sin, self.cos)
    }

    /// True if θ is larger than the angle whose half has cosine `half_cos`.
    #[inline]
    fn exceeds(self, (half_cos, _): (f32, f32)) -> bool {
        self.cos < half_cos
    }

    /// The rotation by θ − `reserve` (given by its half-angle's cosine and sine) about the
    /// same axis, or `None` if θ ≤ `reserve`.
    #[inline]
    fn less(self, (reserve_cos, reserve_sin): (f32, f32)) -> Option<Turn> {
        let sin = self.sin * reserve_cos - self.cos * reserve_sin;
        (sin > 0.0).then(|| Turn {
            axis: self.axis,
            cos: self.cos * reserve_cos + self.sin * reserve_sin,
            sin,
        })
    }

    /// The rotation by `t`·θ, `t ∈ (0, 1]`: a normalised lerp from identity with
    /// Kapoulkine's parameter correction (within about 10⁻³ of `t`·θ; exact for `t = 1`).
    #[inline]
    fn fraction(self, t: f32) -> Turn {
        if t >= 1.0 {
            return self;
        }
        let d = self.cos;
        let k_a = 1.0904 + d * (-3.2452 + d * (3.55645 - d * 1.43519));
        let k_b = 0.848_013 + d * (-1.06021 + d * 0.215_638);
        let k = k_a * (t - 0.5) * (t - 0.5) + k_b;
        let t = t + t * (t - 0.5) * (t - 1.0) * k;
        let cos = 1.0 + t * (self.cos - 1.0);
        let sin = t * self.sin;
        let norm = (cos * cos + sin * sin).sqrt().recip();
        Turn {
            axis: self.axis,
            cos: cos * norm,
            sin: sin * norm,
        }
    }
}

/// The shortest rotation that turns the unit `forward` towards `to_target` (any length),
/// faded out near the eye. `fallback_axis` is used when the two are (anti)parallel.
/// Square roots only, no trigonometry (except within the near distance).
#[inline]
fn gaze_rotation(
    forward: Vec3A,
    to_target: Vec3A,
    fallback_axis: Vec3A,
    prepared: &Prepared,
) -> Turn {
    let cross = forward.cross(to_target);
    let ahead = forward.dot(to_target);
    let cross_squared = cross.length_squared();
    let distance_squared = ahead * ahead + cross_squared;
    // Also rejects NaN.
    if !(distance_squared > 1e-12) {
        return Turn::none(fallback_axis);
    }
    let distance = distance_squared.sqrt();
    let mut turn = if cross_squared > 1e-14 * distance_squared {
        // (|v| + f·v, f × v) is the rotation from f to v, up to its length.
        let cross_length = cross_squared.sqrt();
        let w = distance + ahead;
        let norm = (w * w + cross_squared).sqrt().recip();
        Turn {
            axis: cross / cross_length,
            cos: w * norm,
            sin: cross_length * norm,
        }
    } else if ahead > 0.0 {
        Turn::none(fallback_axis)
    } else {
        Turn {
            axis: fallback_axis,
            cos: 0.0,
            sin: 1.0,
        }
    };
    if distance < prepared.near_distance {
        let t = distance / prepared.near_distance;
        let (cos, sin) = half_angle(turn.angle() * t * t * (3.0 - 2.0 * t));
        turn.cos = cos;
        turn.sin = sin;
    }
    turn
}

/// Turns a joint whose pre-delta world rotation is `joint_rotation` by the world rotation
/// `turn`, within its limits: returns the local delta and the world rotation it makes.
#[inline]
fn turn_joint(limits: &JointLimits, joint_rotation: Quat, turn: Turn) -> (Quat, Quat) {
    let local_axis = joint_rotation.conjugate().mul_vec3a(turn.axis) * turn.sin;
    let wanted = Quat::from_xyzw(local_axis.x, local_axis.y, local_axis.z, turn.cos);
    let delta = limits.clamp(wanted);
    let world = if delta == wanted {
        let world_axis = turn.axis * turn.sin;
        Quat::from_xyzw(world_axis.x, world_axis.y, world_axis.z, turn.cos)
    } else {
        joint_rotation * delta * joint_rotation.conjugate()
    };
    (delta, world)
}

/// One character's body solve between two joints: the incremental forward kinematics
/// (the current joint's parent frame, the global eye) and what was decided from `q_l`.
#[derive(Debug, Clone, Copy)]
struct BodySolver {
    root: Frame,
    frame: Frame,
    eye: Vec3A,
    forward: Vec3A,
    up: Vec3A,
    target: Vec3A,
    first: Turn,
    side_sign: f32,
    head_recruited: bool,
    spine_recruited: bool,
    head_reserve: (f32, f32),
    side_switched: bool,
}

impl BodySolver {
    #[inline(always)]
    fn new(chain: &GazeChain, character: &CharacterTransform, target: Vec3) -> BodySolver {
        let root = root_frame(chain, character);
        BodySolver {
            root,
            frame: root,
            eye: Vec3A::ZERO,
            forward: Vec3A::Z,
            up: Vec3A::Y,
            target: target.into(),
            first: Turn::none(Vec3A::Y),
            side_sign: 1.0,
            head_recruited: false,
            spine_recruited: false,
            head_reserve: (1.0, 0.0),
            side_switched: false,
        }
    }

    /// Forward kinematics of the base posture, one joint.
    #[inline(always)]
    fn base_step(&mut self, chain: &GazeChain, base: &[Quat], index: usize) {
        let joint = &chain.joints()[index];
        self.frame.position += self.frame.rotation.mul_vec3a(Vec3A::from(joint.offset));
        self.frame.rotation *= base[index];
    }

    /// With the head's base frame reached: the global eye, the turn side, `q_l` and the
    /// recruitment. Rewinds to the chain root for [`BodySolver::step`].
    #[inline(always)]
    fn aim(&mut self, chain: &GazeChain, prepared: &Prepared, side: &mut TurnSide) {
        (self.eye, self.forward, self.up) = global_eye(chain, &self.frame);
        let to_target = self.target - self.eye;
        self.side_switched = update_side(to_target, self.forward, self.up, side, prepared);
        self.side_sign = side.resolved();
        let aimed = behind_adjusted(to_target, self.forward, self.up, self.side_sign, prepared);
        self.first = gaze_rotation(self.forward, aimed, self.up * self.side_sign, prepared);
        let has_eyes = chain.has_eyes();
        self.head_recruited = !has_eyes || self.first.exceeds(prepared.eyes_only_half);
        self.spine_recruited = self.first.exceeds(prepared.eyes_head_and_neck_half);
        self.head_reserve = if has_eyes {
            prepared.eyes_only_half
        } else {
            (1.0, 0.0)
        };
        self.frame = self.root;
    }

    /// Solves joint `index` (bottom to top): its share of the remaining rotation, clamped;
    /// moves the global eye with it. Returns the joint's delta.
    #[inline(always)]
    fn step(
        &mut self,
        chain: &GazeChain,
        prepared: &Prepared,
        base: &[Quat],
        index: usize,
    ) -> Quat {
        let joint = &chain.joints()[index];
        self.frame.position += self.frame.rotation.mul_vec3a(Vec3A::from(joint.offset));
        let joint_rotation = self.frame.rotation * base[index];
        let spine_count = chain.spine_count();
        let (recruited, reserve, above) = if index < spine_count {
            (
                self.spine_recruited,
                prepared.eyes_head_and_neck_half,
                spine_count - 1 - index,
            )
        } else {
            (
                self.head_recruited,
                self.head_reserve,
                chain.head_index() - index,
            )
        };
        let mut delta = Quat::IDENTITY;
        if recruited {
            let remaining = if index == 0 {
                self.first
            } else {
                let to_target = self.target - self.eye;
                let aimed =
                    behind_adjusted(to_target, self.forward, self.up, self.side_sign, prepared);
                gaze_rotation(self.forward, aimed, self.up * self.side_sign, prepared)
            };
            if let Some(budget) = remaining.less(reserve) {
                // c_i / Σ_{j ≥ i} c_j with c_i ∝ n + 1 − i: 2 / (joints above + 2).
                let share = 2.0 / (above as f32 + 2.0);
                let turn;
                (delta, turn) = turn_joint(&joint.limits, joint_rotation, budget.fraction(share));
                // The joint turns the global eye rigidly about itself.
                self.eye = self.frame.position + turn.mul_vec3a(self.eye - self.frame.position);
                self.forward = turn.mul_vec3a(self.forward);
                self.up = turn.mul_vec3a(self.up);
            }
        }
        self.frame.rotation = joint_rotation * delta;
        delta
    }

    fn solution(&self) -> SpatialSolution {
        SpatialSolution {
            gaze_angle: self.first.angle(),
            side_switched: self.side_switched,
        }
    }
}

/// One character's part in a body solve.
pub(crate) struct BodyProblem<'a> {
    pub(crate) chain: &'a GazeChain,
    pub(crate) character: &'a CharacterTransform,
    pub(crate) base: &'a [Quat],
    pub(crate) head_target: Vec3,
    pub(crate) side: &'a mut TurnSide,
    pub(crate) deltas: &'a mut [Quat; MAX_CHAIN_JOINTS],
}

/// The spatial solve of the body joints (spine, cervicals, head) of up to `N` characters,
/// each towards its `head_target`: writes `deltas[..body_count]` of each and returns the
/// solutions and the heads' final world frames. `None` lanes are skipped. Inputs are
/// assumed checked.
///
/// The characters' joints are solved in lockstep, joint by joint, so that the processor
/// overlaps their independent dependency chains (each joint waits for the one below it).
pub(crate) fn solve_bodies<const N: usize>(
    prepared: &Prepared,
    mut problems: [Option<BodyProblem<'_>>; N],
) -> [Option<(SpatialSolution, Frame)>; N] {
    let mut solvers: [Option<BodySolver>; N] = std::array::from_fn(|lane| {
        problems[lane]
            .as_ref()
            .map(|p| BodySolver::new(p.chain, p.character, p.head_target))
    });
    let joints = problems
        .iter()
        .flatten()
        .map(|p| p.chain.body_count())
        .max()
        .unwrap_or(0);
    for index in 0..joints {
        for lane in 0..N {
            if let (Some(solver), Some(problem)) = (&mut solvers[lane], &problems[lane]) {
                if index < problem.chain.body_count() {
                    solver.base_step(problem.chain, problem.base, index);
                }
            }
        }
    }
    for lane in 0..N {
        if let (Some(solver), Some(problem)) = (&mut solvers[lane], &mut problems[lane]) {
            solver.aim(problem.chain, prepared, problem.side);
        }
    }
    for index in 0..joints {
        for lane in 0..N {
            if let (Some(solver), Some(problem)) = (&mut solvers[lane], &mut problems[lane]) {
                if index < problem.chain.body_count() {
                    problem.deltas[index] =
                        solver.step(problem.chain, prepared, problem.base, index);
                }
            }
        }
    }
    std::array::from_fn(|lane| solvers[lane].map(|solver| (solver.solution(), solver.frame)))
}

/// The spatial solve of one character's body joints (see [`solve_bodies`]).
pub(crate) fn solve_body_unchecked(
    chain: &GazeChain,
    prepared: &Prepared,
    character: &CharacterTransform,
    base: &[Quat],
    head_target: Vec3,
    side: &mut TurnSide,
    deltas: &mut [Quat; MAX_CHAIN_JOINTS],
) -> (SpatialSolution, Frame) {
    let [solved] = solve_bodies(
        prepared,
        [Some(BodyProblem {
            chain,
            character,
            base,
            head_target,
            side,
            deltas,
        })],
    );
    solved.unwrap_or((
        SpatialSolution {
            gaze_angle: 0.0,
            side_switched: false,
        },
        root_frame(chain, character),
    ))
}

/// Each eye's local forward and up axes: the chain's eye axes (head frame at rest) seen
/// from the eye's rest frame.
#[inline]
fn eye_local_axes(chain: &GazeChain, eye_index: usize) -> (Vec3A, Vec3A) {
    let to_eye = chain.joints()[eye_index].rest.conjugate();
    (
        to_eye.mul_vec3a(Vec3A::from(chain.eye_forward())),
        to_eye.mul_vec3a(Vec3A::from(chain.eye_up())),
    )
}

/// Vergence: the delta of each eye that turns it onto `eye_target` (within its limits),
/// given the head's final world frame. Writes the eyes' entries of `deltas`; nothing for a
/// chain without eyes. Inputs are assumed checked.
pub(crate) fn aim_eyes_unchecked(
    chain: &GazeChain,
    prepared: &Prepared,
    head: &Frame,
    base: &[Quat],
    eye_target: Vec3,
    side: TurnSide,
    deltas: &mut [Quat],
) {
    let Some(eyes) = chain.eye_indices() else {
        return;
    };
    let target = Vec3A::from(eye_target);
    let side_sign = side.resolved();
    for index in eyes {
        deltas[index] = eye_goal(chain, prepared, head, base, index, target, side_sign);
    }
}

/// One eye's vergence delta.
#[inline]
pub(crate) fn eye_goal(
    chain: &GazeChain,
    prepared: &Prepared,
    head: &Frame,
    base: &[Quat],
    index: usize,
    target: Vec3A,
    side_sign: f32,
) -> Quat {
    let joint = &chain.joints()[index];
    let (local_forward, local_up) = eye_local_axes(chain, index);
    let position = head.position + head.rotation.mul_vec3a(Vec3A::from(joint.offset));
    let eye_rotation = head.rotation * base[index];
    let forward = eye_rotation.mul_vec3a(local_forward);
    let up = eye_rotation.mul_vec3a(local_up);
    let aimed = behind_adjusted(target - position, forward, up, side_sign, prepared);
    let turn = gaze_rotation(forward, aimed, up * side_sign, prepared);
    if turn.sin <= 0.0 {
        return Quat::IDENTITY;
    }
    turn_joint(&joint.limits, eye_rotation, turn).0
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
                let (local_forward, _) = eye_local_axes(chain, index);
                let position = head.position + head.rotation.mul_vec3a(Vec3A::from(joint.offset));
                let rotation = head.rotation * base[index] * deltas[index];
                rays.origins[slot] = position.into();
                rays.directions[slot] =
                    rotation.mul_vec3a(local_forward).normalize_or_zero().into();
            }
            rays
        }
        None => {
            let (position, forward, _) = global_eye(chain, head);
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
