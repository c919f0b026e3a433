//! The gaze chain: which joints a character turns to look (spine, cervicals, head, eyes),
//! where they are, how they rest and how far each may turn.
//!
//! Joints are listed bottom to top: `spine…, cervical…, head, left eye, right eye`. The body
//! joints (spine, cervicals, head) form a chain: each one's parent is the previous one, the
//! first one's parent is the *chain root*. The eyes' parent is the head. The chain root sits
//! at [`GazeChain::root_offset`] from the character's position and turns with the character.
//!
//! Convention: the chain is expressed in the world's axes for a character at heading 0 —
//! offsets in metres in the parent's local frame, rest rotations as local rotations. The
//! character's world transform is `translation(position) · rotation(heading about up)`
//! ([`super::CharacterTransform`]).
//!
//! A chain is plain fixed-size data (`Copy`, no heap): up to [`MAX_CHAIN_JOINTS`] joints.
//! [`GazeChain::new`] checks it; [`GazeChain::human`] builds the paper's 10-joint chain.

use glam::{Quat, Vec3, Vec3A};

use crate::error::{ensure_all_finite, Error, Result};

/// Most spine joints (lumbar and thoracic vertebrae) in a chain.
pub const MAX_SPINE_JOINTS: usize = 8;
/// Most cervical (neck) joints in a chain.
pub const MAX_CERVICAL_JOINTS: usize = 4;
/// Most joints in a chain: 8 spine + 4 cervical + 1 head + 2 eyes.
pub const MAX_CHAIN_JOINTS: usize = MAX_SPINE_JOINTS + MAX_CERVICAL_JOINTS + 1 + 2;
/// How far outside its limits (in half-angle sines, about 2·10⁻⁶ rad) a rotation may be and
/// still count as inside: a rotation clamped once is left alone afterwards.
pub(crate) const CLAMP_SLACK: f32 = 1e-6;

/// Most body (non-eye) joints in a chain.
pub const MAX_BODY_JOINTS: usize = MAX_SPINE_JOINTS + MAX_CERVICAL_JOINTS + 1;

/// Longest joint offset or root offset of a chain, metres: a chain is a body, and the
/// limit keeps a character's joint positions far from the float range's end.
pub const MAX_OFFSET_METRES: f32 = 1000.0;

/// Refuses an offset longer than [`MAX_OFFSET_METRES`].
fn check_offset(offset: Vec3, what: &str) -> Result<()> {
    let length = offset.length();
    if length > MAX_OFFSET_METRES {
        return Err(Error::InvalidArgument(format!(
            "{what} is {length} m long, at most {MAX_OFFSET_METRES} m"
        )));
    }
    Ok(())
}

/// What a joint of the gaze chain is.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum JointRole {
    /// A lumbar or thoracic vertebra.
    Spine,
    /// A cervical vertebra (neck).
    Cervical,
    /// The head (skull base).
    Head,
    /// The character's left eye.
    LeftEye,
    /// The character's right eye.
    RightEye,
}

/// The three sets of joints that move together, each with its own duration
/// (Grillon & Thalmann: eyes over `t_a/2`, head and cervicals over `t_a`, spine over `2 t_a`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum JointGroup {
    /// Both eyes.
    Eyes = 0,
    /// The head and the cervical joints.
    HeadAndNeck = 1,
    /// The spine joints.
    Spine = 2,
}

impl JointGroup {
    /// The groups, lightest first.
    pub const ALL: [JointGroup; 3] = [JointGroup::Eyes, JointGroup::HeadAndNeck, JointGroup::Spine];

    /// Index of the group in arrays indexed by group (`Eyes` 0, `HeadAndNeck` 1, `Spine` 2).
    #[inline]
    pub fn index(self) -> usize {
        self as usize
    }
}

impl JointRole {
    /// The group the joint moves with.
    #[inline]
    pub fn group(self) -> JointGroup {
        match self {
            JointRole::Spine => JointGroup::Spine,
            JointRole::Cervical | JointRole::Head => JointGroup::HeadAndNeck,
            JointRole::LeftEye | JointRole::RightEye => JointGroup::Eyes,
        }
    }

    /// True for the two eyes.
    pub fn is_eye(self) -> bool {
        matches!(self, JointRole::LeftEye | JointRole::RightEye)
    }
}

/// How far a joint's *delta* rotation (the gaze displacement on top of its base rotation)
/// may go, as a swing-twist decomposition about a twist axis.
///
/// The delta `q` is split as `q = swing · twist`, `twist` a rotation about the twist axis
/// and `swing` a rotation about an axis perpendicular to it. The twist angle must lie in
/// `[min_twist, max_twist]` and the swing angle (the cone's half-angle) be at most
/// `max_swing`. The twist axis is in the joint's local frame (the frame the delta acts in).
/// For spine, neck and head it is the skeleton's up axis, so the twist is the yaw; for the
/// eyes it is the eye's forward axis, so the twist is the torsion (none, for human eyes).
///
/// The half-angle sines and cosines are cached, so that clamping needs no trigonometry.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct JointLimits {
    twist_axis: Vec3,
    max_swing: f32,
    min_twist: f32,
    max_twist: f32,
    /// cos and sin of `max_swing / 2`.
    swing_half: (f32, f32),
    /// cos and sin of `min_twist / 2`.
    min_twist_half: (f32, f32),
    /// cos and sin of `max_twist / 2`.
    max_twist_half: (f32, f32),
}

impl JointLimits {
    /// Limits about `twist_axis` (joint-local; normalised here): swing cone half-angle
    /// `max_swing` in [0, π], twist in `[min_twist, max_twist]` ⊂ [−π, π]. Radians.
    /// Nothing is checked here: [`JointLimits::validate`] (run by [`GazeChain::new`]) does.
    pub fn new(twist_axis: Vec3, max_swing: f32, min_twist: f32, max_twist: f32) -> JointLimits {
        let half = |angle: f32| {
            let (sin, cos) = (0.5 * angle).sin_cos();
            (cos, sin)
        };
        JointLimits {
            twist_axis: twist_axis.normalize_or_zero(),
            max_swing,
            min_twist,
            max_twist,
            swing_half: half(max_swing),
            min_twist_half: half(min_twist),
            max_twist_half: half(max_twist),
        }
    }

    /// No limit: any swing, twist in [−π, π].
    pub fn free(twist_axis: Vec3) -> JointLimits {
        use std::f32::consts::PI;
        JointLimits::new(twist_axis, PI, -PI, PI)
    }

    /// The twist axis, unit, in the joint's local frame.
    #[inline]
    pub fn twist_axis(&self) -> Vec3 {
        self.twist_axis
    }

    /// Largest swing angle (cone half-angle), radians.
    pub fn max_swing(&self) -> f32 {
        self.max_swing
    }

    /// Smallest twist angle, radians.
    pub fn min_twist(&self) -> f32 {
        self.min_twist
    }

    /// Largest twist angle, radians.
    pub fn max_twist(&self) -> f32 {
        self.max_twist
    }

    /// The cached (cos, sin) of half the swing limit, half the smallest and half the
    /// largest twist.
    #[inline]
    pub(crate) fn half_angles(&self) -> ((f32, f32), (f32, f32), (f32, f32)) {
        (self.swing_half, self.min_twist_half, self.max_twist_half)
    }

    /// Checks the limits: finite, unit twist axis, `0 ≤ max_swing ≤ π`,
    /// `−π ≤ min_twist ≤ max_twist ≤ π`.
    pub fn validate(&self, what: &str) -> Result<()> {
        use std::f32::consts::PI;
        ensure_all_finite(
            &[self.max_swing, self.min_twist, self.max_twist],
            &format!("{what} limits"),
        )?;
        ensure_all_finite(&self.twist_axis.to_array(), &format!("{what} twist axis"))?;
        if (self.twist_axis.length() - 1.0).abs() > 1e-3 {
            return Err(Error::InvalidArgument(format!(
                "{what} twist axis has zero length"
            )));
        }
        if !(0.0..=PI + 1e-6).contains(&self.max_swing) {
            return Err(Error::InvalidArgument(format!(
                "{what} max_swing is {}, must be in [0, π]",
                self.max_swing
            )));
        }
        if self.min_twist < -PI - 1e-6
            || self.max_twist > PI + 1e-6
            || self.min_twist > self.max_twist
        {
            return Err(Error::InvalidArgument(format!(
                "{what} twist range [{}, {}] must satisfy −π ≤ min ≤ max ≤ π",
                self.min_twist, self.max_twist
            )));
        }
        Ok(())
    }

    /// The swing and twist angles of a delta rotation (radians; twist signed about the twist
    /// axis, swing in [0, π]).
    pub fn swing_twist_angles(&self, rotation: Quat) -> (f32, f32) {
        let rotation = if rotation.w < 0.0 {
            -rotation
        } else {
            rotation
        };
        let axis = Vec3A::from(self.twist_axis);
        let projection = Vec3A::from(rotation.xyz()).dot(axis);
        let length = (rotation.w * rotation.w + projection * projection).sqrt();
        let twist = if length < 1e-9 {
            Quat::IDENTITY
        } else {
            let scale = projection / length;
            Quat::from_xyzw(
                axis.x * scale,
                axis.y * scale,
                axis.z * scale,
                rotation.w / length,
            )
        };
        let swing = rotation * twist.conjugate();
        let twist_angle = 2.0 * libm::atan2f(projection, rotation.w);
        let swing_angle = 2.0 * libm::atan2f(swing.xyz().length(), swing.w.abs());
        (swing_angle, twist_angle)
    }

    /// True if `rotation` is within the limits, give or take `tolerance` radians.
    pub fn contains(&self, rotation: Quat, tolerance: f32) -> bool {
        let (swing, twist) = self.swing_twist_angles(rotation);
        swing <= self.max_swing + tolerance
            && twist >= self.min_twist - tolerance
            && twist <= self.max_twist + tolerance
    }

    /// The rotation within the limits nearest to `rotation` (a unit quaternion): the twist is
    /// clamped to its range and the swing to its cone, each keeping its direction. A rotation
    /// already within the limits is returned unchanged, after a handful of multiplications
    /// (no square root, no trigonometry).
    ///
    /// The sign of `rotation` is kept as given: a rotation of more than π (w < 0) is clamped
    /// on the side it turns towards, not on the side of the short way round.
    #[inline]
    pub fn clamp(&self, rotation: Quat) -> Quat {
        let axis = Vec3A::from(self.twist_axis);
        let projection = Vec3A::from(rotation.xyz()).dot(axis);
        let w = rotation.w;
        // The twist is (w, projection) up to its length: (cos, sin) of half the twist angle.
        // It lies in [min, max] (an arc of the right half-plane, at most π wide) iff it is
        // counter-clockwise of `min` and clockwise of `max`; no normalisation needed.
        let (min_cos, min_sin) = self.min_twist_half;
        let (max_cos, max_sin) = self.max_twist_half;
        // With a slack of CLAMP_SLACK, so that a rotation clamped before counts as inside.
        let twist_inside = min_cos * projection - min_sin * w >= -CLAMP_SLACK
            && w * max_sin - projection * max_cos >= -CLAMP_SLACK;
        // For a unit rotation, the swing's scalar part (cos of half the swing angle) is
        // √(w² + projection²): compare squares, no square root.
        let (cone_cos, cone_sin) = self.swing_half;
        let twist_length_squared = w * w + projection * projection;
        let swing_inside = twist_length_squared >= cone_cos * cone_cos - CLAMP_SLACK;
        if twist_inside && swing_inside {
            return rotation;
        }
        let length = twist_length_squared.sqrt();
        let (mut twist_cos, mut twist_sin) = if length < 1e-9 {
            (1.0, 0.0)
        } else {
            (w / length, projection / length)
        };
        let twist = Quat::from_xyzw(
            axis.x * twist_sin,
            axis.y * twist_sin,
            axis.z * twist_sin,
            twist_cos,
        );
        let mut swing = rotation * twist.conjugate();
        if !twist_inside {
            let to_min = twist_cos * min_cos + twist_sin * min_sin;
            let to_max = twist_cos * max_cos + twist_sin * max_sin;
            (twist_cos, twist_sin) = if to_min > to_max {
                (min_cos, min_sin)
            } else {
                (max_cos, max_sin)
            };
        }
        let swing_vector = Vec3A::from(swing.xyz());
        let swing_sin = swing_vector.length();
        if !swing_inside {
            swing = if swing_sin > 1e-9 {
                let direction = swing_vector * (cone_sin / swing_sin);
                Quat::from_xyzw(direction.x, direction.y, direction.z, cone_cos)
            } else {
                // A full turn (w = −1) is no rotation at all.
                Quat::IDENTITY
            };
        }
        let twist = Quat::from_xyzw(
            axis.x * twist_sin,
            axis.y * twist_sin,
            axis.z * twist_sin,
            twist_cos,
        );
        (swing * twist).normalize()
    }
}

/// One joint of a gaze chain.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ChainJoint {
    /// What the joint is.
    pub role: JointRole,
    /// Position of the joint in its parent's local frame (the chain root for the first
    /// joint, the head for the eyes), metres.
    pub offset: Vec3,
    /// Rest local rotation (unit quaternion), relative to the parent.
    pub rest: Quat,
    /// How far the gaze may turn the joint away from its base rotation.
    pub limits: JointLimits,
}

impl ChainJoint {
    /// A joint with a rest rotation.
    pub fn new(role: JointRole, offset: Vec3, rest: Quat, limits: JointLimits) -> ChainJoint {
        ChainJoint {
            role,
            offset,
            rest,
            limits,
        }
    }
}

/// A character's gaze chain: up to 8 spine, up to 4 cervical, exactly 1 head and 0 or 2 eye
/// joints, bottom to top. See the [module documentation](self) for the conventions.
///
/// Plain fixed-size data: `Copy`, no heap, 1 248 bytes. Characters that share a skeleton can
/// share one chain.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GazeChain {
    joints: [ChainJoint; MAX_CHAIN_JOINTS],
    joint_count: u8,
    spine_count: u8,
    cervical_count: u8,
    eye_forward: Vec3,
    eye_up: Vec3,
    root_offset: Vec3,
}

const PLACEHOLDER_JOINT: ChainJoint = ChainJoint {
    role: JointRole::Head,
    offset: Vec3::ZERO,
    rest: Quat::IDENTITY,
    limits: JointLimits {
        twist_axis: Vec3::Y,
        max_swing: 0.0,
        min_twist: 0.0,
        max_twist: 0.0,
        swing_half: (1.0, 0.0),
        min_twist_half: (1.0, 0.0),
        max_twist_half: (1.0, 0.0),
    },
};

impl GazeChain {
    /// Builds and checks a chain ([`GazeChain::validate`]).
    ///
    /// - `joints`: bottom to top, `spine…, cervical…, head[, left eye, right eye]`.
    /// - `eye_forward`, `eye_up`: the direction the eyes look and the head's up, both in the
    ///   head's local frame at rest; perpendicular, normalised here.
    /// - `root_offset`: the chain root's position relative to the character's position, in
    ///   the character's frame (for a human: up × pelvis height), metres.
    ///
    /// Errors: [`Error::InvalidArgument`] for a bad count, order, axis or limit,
    /// [`Error::NonFinite`] for a NaN or infinite value.
    pub fn new(
        joints: &[ChainJoint],
        eye_forward: Vec3,
        eye_up: Vec3,
        root_offset: Vec3,
    ) -> Result<GazeChain> {
        if joints.is_empty() || joints.len() > MAX_CHAIN_JOINTS {
            return Err(Error::InvalidArgument(format!(
                "a gaze chain has 1 to {MAX_CHAIN_JOINTS} joints, not {}",
                joints.len()
            )));
        }
        let mut chain = GazeChain {
            joints: [PLACEHOLDER_JOINT; MAX_CHAIN_JOINTS],
            joint_count: joints.len() as u8,
            spine_count: 0,
            cervical_count: 0,
            eye_forward: eye_forward.normalize_or_zero(),
            eye_up: eye_up.normalize_or_zero(),
            root_offset,
        };
        chain.joints[..joints.len()].copy_from_slice(joints);
        chain.spine_count = joints.iter().filter(|j| j.role == JointRole::Spine).count() as u8;
        chain.cervical_count = joints
            .iter()
            .filter(|j| j.role == JointRole::Cervical)
            .count() as u8;
        // Non-finite axes normalise to zero: report them as non-finite, not as zero-length.
        ensure_all_finite(&eye_forward.to_array(), "eye_forward")?;
        ensure_all_finite(&eye_up.to_array(), "eye_up")?;
        chain.validate()?;
        Ok(chain)
    }

    /// The paper's chain for an adult human — 5 spine, 2 cervical, 1 head, 2 eyes — for a
    /// skeleton whose up axis is `up` and which faces `forward` (perpendicular unit vectors,
    /// e.g. Y and Z; the character's left is `up × forward`). Rest rotations are identity.
    ///
    /// Proportions (metres, along `up` unless said): chain root (pelvis) at 0.95; spine
    /// joints 0.05, then 0.10 apart (1.00 – 1.40); cervicals at 1.46 and 1.51; head (skull
    /// base) at 1.56; eyes 0.06 above and 0.085 in front of it, 0.032 to either side —
    /// eye height 1.62.
    ///
    /// Limits (delta rotations): each spine joint ±8° yaw and a 5° swing cone (±40° of yaw
    /// for the spine); each cervical ±25° yaw, 20° swing; the head ±20° yaw, 25° swing
    /// (±70° of yaw for neck and head); eyes a 35° swing cone and no torsion.
    pub fn human(up: Vec3, forward: Vec3) -> GazeChain {
        let degrees = f32::to_radians;
        let up = up.normalize_or_zero();
        let forward = forward.normalize_or_zero();
        let left = up.cross(forward);
        let body = |role, offset: f32, yaw: f32, swing: f32| {
            ChainJoint::new(
                role,
                up * offset,
                Quat::IDENTITY,
                JointLimits::new(up, degrees(swing), -degrees(yaw), degrees(yaw)),
            )
        };
        let eye_limits = JointLimits::new(forward, degrees(35.0), 0.0, 0.0);
        let eye = |role, side: f32| {
            ChainJoint::new(
                role,
                up * 0.06 + forward * 0.085 + left * (0.032 * side),
                Quat::IDENTITY,
                eye_limits,
            )
        };
        let joints = [
            body(JointRole::Spine, 0.05, 8.0, 5.0),
            body(JointRole::Spine, 0.10, 8.0, 5.0),
            body(JointRole::Spine, 0.10, 8.0, 5.0),
            body(JointRole::Spine, 0.10, 8.0, 5.0),
            body(JointRole::Spine, 0.10, 8.0, 5.0),
            body(JointRole::Cervical, 0.06, 25.0, 20.0),
            body(JointRole::Cervical, 0.05, 25.0, 20.0),
            body(JointRole::Head, 0.05, 20.0, 25.0),
            eye(JointRole::LeftEye, 1.0),
            eye(JointRole::RightEye, -1.0),
        ];
        let mut chain = GazeChain {
            joints: [PLACEHOLDER_JOINT; MAX_CHAIN_JOINTS],
            joint_count: joints.len() as u8,
            spine_count: 5,
            cervical_count: 2,
            eye_forward: forward,
            eye_up: up,
            root_offset: up * 0.95,
        };
        chain.joints[..joints.len()].copy_from_slice(&joints);
        chain
    }

    /// Checks the chain: 1 to [`MAX_CHAIN_JOINTS`] joints ordered `spine…, cervical…, head,
    /// [left eye, right eye]` with at most 8 spine and 4 cervical joints, exactly one head and
    /// both eyes or none; finite offsets, unit rest rotations (±1e-3), valid limits; unit,
    /// perpendicular eye forward and up axes.
    ///
    /// Errors: [`Error::NonFinite`] for NaN or infinity, [`Error::InvalidArgument`] otherwise.
    pub fn validate(&self) -> Result<()> {
        let count = self.joint_count as usize;
        if count == 0 || count > MAX_CHAIN_JOINTS {
            return Err(Error::InvalidArgument(format!(
                "a gaze chain has 1 to {MAX_CHAIN_JOINTS} joints, not {count}"
            )));
        }
        let joints = &self.joints[..count];
        // Order: spine*, cervical*, head, (left eye, right eye)?
        let spine = joints
            .iter()
            .take_while(|j| j.role == JointRole::Spine)
            .count();
        let cervical = joints[spine..]
            .iter()
            .take_while(|j| j.role == JointRole::Cervical)
            .count();
        let rest = &joints[spine + cervical..];
        let tail_ok = match rest {
            [head] => head.role == JointRole::Head,
            [head, left, right] => {
                head.role == JointRole::Head
                    && left.role == JointRole::LeftEye
                    && right.role == JointRole::RightEye
            }
            _ => false,
        };
        if !tail_ok {
            return Err(Error::InvalidArgument(
                "gaze chain joints must be ordered spine…, cervical…, one head, then both eyes \
                 (left, right) or none"
                    .into(),
            ));
        }
        if spine > MAX_SPINE_JOINTS || cervical > MAX_CERVICAL_JOINTS {
            return Err(Error::InvalidArgument(format!(
                "a gaze chain has at most {MAX_SPINE_JOINTS} spine and {MAX_CERVICAL_JOINTS} \
                 cervical joints, not {spine} and {cervical}"
            )));
        }
        if spine != self.spine_count as usize || cervical != self.cervical_count as usize {
            return Err(Error::Internal(
                "gaze chain joint counts out of date".into(),
            ));
        }
        for (index, joint) in joints.iter().enumerate() {
            let what = format!("joint {index} ({:?})", joint.role);
            ensure_all_finite(&joint.offset.to_array(), &format!("{what} offset"))?;
            check_offset(joint.offset, &format!("{what} offset"))?;
            ensure_all_finite(&joint.rest.to_array(), &format!("{what} rest rotation"))?;
            if (joint.rest.length() - 1.0).abs() > 1e-3 {
                return Err(Error::InvalidArgument(format!(
                    "{what} rest rotation has length {}, not 1",
                    joint.rest.length()
                )));
            }
            joint.limits.validate(&what)?;
        }
        ensure_all_finite(&self.root_offset.to_array(), "root_offset")?;
        check_offset(self.root_offset, "root_offset")?;
        ensure_all_finite(&self.eye_forward.to_array(), "eye_forward")?;
        ensure_all_finite(&self.eye_up.to_array(), "eye_up")?;
        for (axis, name) in [(self.eye_forward, "eye_forward"), (self.eye_up, "eye_up")] {
            if (axis.length() - 1.0).abs() > 1e-3 {
                return Err(Error::InvalidArgument(format!(
                    "{name} must be a non-zero direction"
                )));
            }
        }
        if self.eye_forward.dot(self.eye_up).abs() > 1e-3 {
            return Err(Error::InvalidArgument(
                "eye_forward and eye_up must be perpendicular".into(),
            ));
        }
        Ok(())
    }

    /// The joints, bottom to top.
    #[inline]
    pub fn joints(&self) -> &[ChainJoint] {
        &self.joints[..self.joint_count as usize]
    }

    /// Number of joints (1 to [`MAX_CHAIN_JOINTS`]).
    #[inline]
    pub fn joint_count(&self) -> usize {
        self.joint_count as usize
    }

    /// Number of spine joints (0 to 8).
    #[inline]
    pub fn spine_count(&self) -> usize {
        self.spine_count as usize
    }

    /// Number of cervical joints (0 to 4).
    #[inline]
    pub fn cervical_count(&self) -> usize {
        self.cervical_count as usize
    }

    /// Number of body joints: spine, cervicals and head (the eyes excluded).
    #[inline]
    pub fn body_count(&self) -> usize {
        (self.spine_count + self.cervical_count) as usize + 1
    }

    /// Index of the head joint.
    #[inline]
    pub fn head_index(&self) -> usize {
        self.body_count() - 1
    }

    /// True if the chain has its two eyes.
    #[inline]
    pub fn has_eyes(&self) -> bool {
        self.joint_count() == self.body_count() + 2
    }

    /// Indices of the left and right eye joints, if any.
    #[inline]
    pub fn eye_indices(&self) -> Option<[usize; 2]> {
        self.has_eyes()
            .then(|| [self.body_count(), self.body_count() + 1])
    }

    /// The direction the eyes look at rest, unit, in the head's local frame.
    #[inline]
    pub fn eye_forward(&self) -> Vec3 {
        self.eye_forward
    }

    /// The head's up direction, unit, in the head's local frame (perpendicular to
    /// [`GazeChain::eye_forward`]).
    #[inline]
    pub fn eye_up(&self) -> Vec3 {
        self.eye_up
    }

    /// The chain root's position relative to the character's position, character frame,
    /// metres.
    #[inline]
    pub fn root_offset(&self) -> Vec3 {
        self.root_offset
    }

    /// The *global eye* at rest, relative to the character's position in the character's
    /// frame (metres): the mid-point of the eyes, or the head joint if the chain has no eyes.
    pub fn rest_eye_position(&self) -> Vec3 {
        let mut position = self.root_offset;
        let mut rotation = Quat::IDENTITY;
        for joint in &self.joints()[..self.body_count()] {
            position += rotation * joint.offset;
            rotation *= joint.rest;
        }
        match self.eye_indices() {
            Some([left, right]) => {
                position + rotation * (0.5 * (self.joints[left].offset + self.joints[right].offset))
            }
            None => position,
        }
    }

    /// The look-at height: how far above the character's position its global eye is at
    /// rest, along the world's `up` (metres; ≈ 1.62 for [`GazeChain::human`]). The attention
    /// model aims at this height on other characters, so nobody stares at feet.
    pub fn look_at_height(&self, up: Vec3) -> f32 {
        self.rest_eye_position().dot(up.normalize_or_zero())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f32::consts::PI;

    #[test]
    fn human_chain_is_valid_with_human_proportions() {
        for (up, forward) in [
            (Vec3::Y, Vec3::Z),
            (Vec3::Z, Vec3::NEG_Y),
            (Vec3::Z, Vec3::X),
        ] {
            let chain = GazeChain::human(up, forward);
            chain.validate().unwrap();
            assert_eq!(chain.joint_count(), 10);
            assert_eq!(chain.spine_count(), 5);
            assert_eq!(chain.cervical_count(), 2);
            assert_eq!(chain.head_index(), 7);
            assert_eq!(chain.eye_indices(), Some([8, 9]));
            assert!((chain.look_at_height(up) - 1.62).abs() < 1e-5);
            // The left eye is on the character's left (up × forward).
            let left = chain.joints()[8].offset.dot(up.cross(forward));
            assert!(left > 0.0);
            let chain_new = GazeChain::new(
                chain.joints(),
                chain.eye_forward(),
                chain.eye_up(),
                chain.root_offset(),
            )
            .unwrap();
            assert_eq!(chain_new, chain);
        }
        assert_eq!(std::mem::size_of::<GazeChain>(), 1248);
    }

    fn human_joints() -> Vec<ChainJoint> {
        GazeChain::human(Vec3::Y, Vec3::Z).joints().to_vec()
    }

    #[test]
    fn bad_chains_are_rejected() {
        let new = |joints: &[ChainJoint]| GazeChain::new(joints, Vec3::Z, Vec3::Y, Vec3::ZERO);
        let joints = human_joints();
        assert!(new(&joints).is_ok());
        assert!(new(&joints[..8]).is_ok(), "no eyes is fine");
        assert!(new(&joints[7..8]).is_ok(), "a lone head is fine");
        assert!(matches!(new(&[]), Err(Error::InvalidArgument(_))));
        assert!(
            matches!(new(&joints[..9]), Err(Error::InvalidArgument(_))),
            "one eye"
        );
        let mut swapped = joints.clone();
        swapped.swap(8, 9);
        assert!(
            matches!(new(&swapped), Err(Error::InvalidArgument(_))),
            "eyes swapped"
        );
        let mut no_head = joints.clone();
        no_head[7].role = JointRole::Cervical;
        assert!(matches!(new(&no_head), Err(Error::InvalidArgument(_))));
        let mut order = joints.clone();
        order.swap(4, 5);
        assert!(
            matches!(new(&order), Err(Error::InvalidArgument(_))),
            "cervical below spine"
        );
        let mut too_many_spine = vec![joints[0]; 9];
        too_many_spine.push(joints[7]);
        assert!(matches!(
            new(&too_many_spine),
            Err(Error::InvalidArgument(_))
        ));
        let mut nan = joints.clone();
        nan[3].offset.x = f32::NAN;
        assert!(matches!(new(&nan), Err(Error::NonFinite(_))));
        let mut not_unit = joints.clone();
        not_unit[2].rest = Quat::from_xyzw(0.0, 0.0, 0.0, 2.0);
        assert!(matches!(new(&not_unit), Err(Error::InvalidArgument(_))));
        let mut bad_limits = joints.clone();
        bad_limits[1].limits = JointLimits::new(Vec3::Y, 0.1, 0.5, -0.5);
        assert!(matches!(new(&bad_limits), Err(Error::InvalidArgument(_))));
        bad_limits[1].limits = JointLimits::new(Vec3::ZERO, 0.1, -0.5, 0.5);
        assert!(matches!(new(&bad_limits), Err(Error::InvalidArgument(_))));
        bad_limits[1].limits = JointLimits::new(Vec3::Y, f32::NAN, -0.5, 0.5);
        assert!(matches!(new(&bad_limits), Err(Error::NonFinite(_))));
        let axes = |forward, up| GazeChain::new(&joints, forward, up, Vec3::ZERO);
        assert!(matches!(
            axes(Vec3::ZERO, Vec3::Y),
            Err(Error::InvalidArgument(_))
        ));
        assert!(matches!(
            axes(Vec3::Z, Vec3::Z),
            Err(Error::InvalidArgument(_))
        ));
        assert!(matches!(axes(Vec3::NAN, Vec3::Y), Err(Error::NonFinite(_))));
        assert!(matches!(
            GazeChain::new(&joints, Vec3::Z, Vec3::Y, Vec3::INFINITY),
            Err(Error::NonFinite(_))
        ));
    }

    #[test]
    fn clamping_respects_swing_and_twist() {
        let limits = JointLimits::new(Vec3::Y, 0.4, -0.3, 0.5);
        // Inside: unchanged, bit for bit.
        let inside = Quat::from_rotation_y(0.2) * Quat::from_rotation_x(0.1);
        assert_eq!(limits.clamp(inside), inside);
        // Twist beyond either end goes to that end.
        let (_, twist) = limits.swing_twist_angles(limits.clamp(Quat::from_rotation_y(1.2)));
        assert!((twist - 0.5).abs() < 1e-5);
        let (_, twist) = limits.swing_twist_angles(limits.clamp(Quat::from_rotation_y(-1.0)));
        assert!((twist + 0.3).abs() < 1e-5);
        // Swing beyond the cone keeps its direction.
        let clamped = limits.clamp(Quat::from_rotation_x(1.0));
        let (swing, twist) = limits.swing_twist_angles(clamped);
        assert!((swing - 0.4).abs() < 1e-5 && twist.abs() < 1e-5);
        assert!(clamped.xyz().normalize().abs_diff_eq(Vec3::X, 1e-5));
        // Both at once, random rotations: always inside afterwards.
        let mut random = crate::math::random::Random::new(3);
        for _ in 0..2000 {
            let axis = Vec3::new(
                random.range(-1.0, 1.0),
                random.range(-1.0, 1.0),
                random.range(-1.0, 1.0),
            )
            .normalize_or(Vec3::X);
            let q = Quat::from_axis_angle(axis, random.range(-PI, PI));
            let clamped = limits.clamp(q);
            assert!(limits.contains(clamped, 1e-4), "{q:?} -> {clamped:?}");
            assert!((clamped.length() - 1.0).abs() < 1e-5);
        }
        // Eyes: no torsion at all.
        let eye = JointLimits::new(Vec3::Z, 0.6, 0.0, 0.0);
        let (swing, twist) = eye.swing_twist_angles(eye.clamp(Quat::from_rotation_z(0.3)));
        assert!(swing.abs() < 1e-5 && twist.abs() < 1e-5);
        // A rotation the long way round (more than π) clamps on the side it turns towards.
        let long_way = Quat::from_axis_angle(Vec3::Y, 1.2 * PI);
        let (_, twist) = limits.swing_twist_angles(limits.clamp(long_way));
        assert!((twist - 0.5).abs() < 1e-5, "{twist}");
    }
}
