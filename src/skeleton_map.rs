//! From a skeleton's bones to a gaze chain: which bones are spine, neck, head and eyes (by
//! name, with a default map that overrides change), and the chain's offsets, rest rotations
//! and limits in metres, in the character's frame.
//!
//! The engines' adapters and the command-line tool's `bvh` command share this mapping:
//!
//! 1. A [`BoneMap`](crate::skeleton_map::BoneMap) gives each bone name a
//!    [`BoneRole`](crate::skeleton_map::BoneRole) (case-insensitive, any `namespace:` prefix
//!    ignored): [`DEFAULT_BONE_MAP`](crate::skeleton_map::DEFAULT_BONE_MAP) with the
//!    caller's overrides.
//! 2. [`map_skeleton`](crate::skeleton_map::map_skeleton) finds the head, walks down its
//!    ancestors while they are neck then spine bones (the first other ancestor is the chain
//!    root), takes the head's two eye children if both are mapped, and builds the
//!    [`GazeChain`](crate::ik::GazeChain).
//!
//! Conventions: bones are given at rest, each as a translation (caller's units) and a
//! rotation relative to its parent, parents before children; a bone without a parent is
//! relative to the character (its position on the ground, at heading 0, in the world's
//! axes). The chain root's frame is the character's: its rest rotation is folded into the
//! first chain joint's, so an engine whose chain root turns (a pelvis that sways) passes
//! that turn in the first joint's base rotation (see
//! [`MappedChain::root`](crate::skeleton_map::MappedChain::root)). Twist axes and the eyes'
//! forward and up are expressed in each joint's own frame at rest, so skeletons whose bones
//! have rotated rest poses (as imported models do) need nothing special.

use std::collections::HashMap;

use glam::{Quat, Vec3};

use crate::error::{ensure_all_finite, Error, Result};
use crate::ik::chain::{MAX_CERVICAL_JOINTS, MAX_SPINE_JOINTS};
use crate::ik::{ChainJoint, GazeChain, JointLimits, JointRole};
use crate::world::Axis;

/// What a bone is for the gaze chain.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum BoneRole {
    /// The body root (not turned by gaze; the chain hangs from the first bone below the
    /// spine that is not a spine bone, whatever its role).
    Root,
    /// A spine bone (lumbar or thoracic).
    Spine,
    /// A neck (cervical) bone.
    Neck,
    /// The head.
    Head,
    /// The character's left eye (a child of the head).
    LeftEye,
    /// The character's right eye (a child of the head).
    RightEye,
    /// Not part of the chain.
    None,
}

impl BoneRole {
    /// Every role, in the order of [`BoneRole::name`]'s list.
    pub const ALL: [BoneRole; 7] = [
        BoneRole::Root,
        BoneRole::Spine,
        BoneRole::Neck,
        BoneRole::Head,
        BoneRole::LeftEye,
        BoneRole::RightEye,
        BoneRole::None,
    ];

    /// Parses a role name: `root` (or `hips`, `pelvis`), `spine` (or `chest`), `neck` (or
    /// `cervical`), `head`, `left_eye` (or `eye_l`), `right_eye` (or `eye_r`), `none` (or
    /// `-`); case-insensitive.
    pub fn parse(text: &str) -> Option<BoneRole> {
        Some(match text.trim().to_ascii_lowercase().as_str() {
            "root" | "hips" | "pelvis" => BoneRole::Root,
            "spine" | "chest" => BoneRole::Spine,
            "neck" | "cervical" => BoneRole::Neck,
            "head" => BoneRole::Head,
            "left_eye" | "lefteye" | "eye_l" => BoneRole::LeftEye,
            "right_eye" | "righteye" | "eye_r" => BoneRole::RightEye,
            "none" | "-" => BoneRole::None,
            _ => return None,
        })
    }

    /// The role's name as [`BoneRole::parse`] reads it.
    pub fn name(self) -> &'static str {
        match self {
            BoneRole::Root => "root",
            BoneRole::Spine => "spine",
            BoneRole::Neck => "neck",
            BoneRole::Head => "head",
            BoneRole::LeftEye => "left_eye",
            BoneRole::RightEye => "right_eye",
            BoneRole::None => "none",
        }
    }
}

/// The default map, by bone name (case-insensitive, after any `namespace:` prefix): the
/// names of Mixamo, Biovision and the usual humanoid rigs, Godot's `SkeletonProfileHumanoid`
/// and Blender's `.L`/`.R` eyes.
pub const DEFAULT_BONE_MAP: &[(&str, BoneRole)] = &[
    ("Hips", BoneRole::Root),
    ("Spine", BoneRole::Spine),
    ("Spine1", BoneRole::Spine),
    ("Spine2", BoneRole::Spine),
    ("Spine3", BoneRole::Spine),
    ("Chest", BoneRole::Spine),
    ("UpperChest", BoneRole::Spine),
    ("LowerBack", BoneRole::Spine),
    ("Neck", BoneRole::Neck),
    ("Neck1", BoneRole::Neck),
    ("Head", BoneRole::Head),
    ("LeftEye", BoneRole::LeftEye),
    ("RightEye", BoneRole::RightEye),
    ("Eye_L", BoneRole::LeftEye),
    ("Eye_R", BoneRole::RightEye),
    ("Eye.L", BoneRole::LeftEye),
    ("Eye.R", BoneRole::RightEye),
];

/// Bone names to roles: [`DEFAULT_BONE_MAP`] with overrides on top.
#[derive(Debug, Clone, PartialEq)]
pub struct BoneMap {
    roles: HashMap<String, BoneRole>,
}

impl Default for BoneMap {
    fn default() -> Self {
        BoneMap {
            roles: DEFAULT_BONE_MAP
                .iter()
                .map(|(name, role)| (name.to_ascii_lowercase(), *role))
                .collect(),
        }
    }
}

impl BoneMap {
    /// The default map with `overrides` applied: `Name=role` entries separated by commas
    /// (roles as [`BoneRole::parse`] reads them), e.g. `"mixamorig:Spine=none,Jaw=head"`.
    ///
    /// Errors: [`Error::InvalidArgument`] naming the entry that is not `NAME=ROLE` or the
    /// role that is not one.
    pub fn with_overrides(overrides: &str) -> Result<BoneMap> {
        let mut map = BoneMap::default();
        for entry in overrides.split(',').filter(|e| !e.trim().is_empty()) {
            let (name, role) = entry.split_once('=').ok_or_else(|| {
                Error::InvalidArgument(format!("bone map: '{entry}' is not NAME=ROLE"))
            })?;
            let role = BoneRole::parse(role).ok_or_else(|| {
                Error::InvalidArgument(format!(
                    "bone map: '{role}' is not a role (root, spine, neck, head, left_eye, \
                     right_eye or none)"
                ))
            })?;
            map.set(name.trim(), role);
        }
        Ok(map)
    }

    /// Maps `name` (case-insensitive) to `role`, replacing what the map said.
    pub fn set(&mut self, name: &str, role: BoneRole) {
        self.roles.insert(name.to_ascii_lowercase(), role);
    }

    /// The role of the bone called `name`: its full name's entry, else the entry of the
    /// name after its last `:` (a namespace prefix such as `mixamorig:`), else
    /// [`BoneRole::None`].
    pub fn role_of(&self, name: &str) -> BoneRole {
        let short = name.rsplit(':').next().unwrap_or(name);
        self.roles
            .get(&name.to_ascii_lowercase())
            .or_else(|| self.roles.get(&short.to_ascii_lowercase()))
            .copied()
            .unwrap_or(BoneRole::None)
    }
}

/// One bone of a skeleton at rest.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RestBone<'a> {
    /// Its name.
    pub name: &'a str,
    /// Index of its parent among the bones (before it), `None` for a bone relative to the
    /// character.
    pub parent: Option<usize>,
    /// Translation from the parent, in the parent's frame (caller's units).
    pub translation: Vec3,
    /// Rotation relative to the parent (unit quaternion).
    pub rotation: Quat,
}

/// How [`map_skeleton`] reads a skeleton.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SkeletonOptions {
    /// The world's up axis; `None` takes the axis nearest to the rest-pose spine (chain
    /// root to head).
    pub up: Option<Axis>,
    /// The direction the character faces at heading 0; `None` takes `left × up`, left
    /// from the rest positions of the bones called `Left*` and `Right*` (the usual facing
    /// for the up axis if there are none: −Y for Z up, +Z otherwise).
    pub forward: Option<Axis>,
    /// How many of the skeleton's length units make a metre.
    pub units_per_metre: f32,
    /// The chain root's position relative to the character (caller's units, character
    /// frame); `None` takes its rest position.
    pub root_offset: Option<Vec3>,
}

impl Default for SkeletonOptions {
    /// Axes detected, metres, the rest position of the chain root.
    fn default() -> Self {
        SkeletonOptions {
            up: None,
            forward: None,
            units_per_metre: 1.0,
            root_offset: None,
        }
    }
}

/// A skeleton's gaze chain and which bones it turns.
#[derive(Debug, Clone, PartialEq)]
pub struct MappedChain {
    /// The bone of each chain joint, bottom to top (spine, neck, head, then the left and
    /// right eye if the chain has eyes).
    pub bones: Vec<usize>,
    /// The chain root: the parent of the first chain joint. Its rotation relative to the
    /// character is folded into the first joint: that joint's base rotation is
    /// `root_rotation * local_rotation`, with `root_rotation` the root's rotation in the
    /// character's frame.
    pub root: usize,
    /// The gaze chain (metres, the world's axes at heading 0).
    pub chain: GazeChain,
    /// The world's up axis.
    pub up: Axis,
    /// The direction the character faces at heading 0.
    pub forward: Axis,
}

/// The signed coordinate axis nearest to `v`.
pub fn nearest_axis(v: Vec3) -> Axis {
    let a = v.abs();
    if a.x >= a.y && a.x >= a.z {
        if v.x >= 0.0 {
            Axis::PositiveX
        } else {
            Axis::NegativeX
        }
    } else if a.y >= a.z {
        if v.y >= 0.0 {
            Axis::PositiveY
        } else {
            Axis::NegativeY
        }
    } else if v.z >= 0.0 {
        Axis::PositiveZ
    } else {
        Axis::NegativeZ
    }
}

/// Parses an axis name: `x`, `+x`, `-x`, `y`, ... (case-insensitive).
pub fn parse_axis(text: &str) -> Option<Axis> {
    Some(match text.trim().to_ascii_lowercase().as_str() {
        "x" | "+x" => Axis::PositiveX,
        "-x" => Axis::NegativeX,
        "y" | "+y" => Axis::PositiveY,
        "-y" => Axis::NegativeY,
        "z" | "+z" => Axis::PositiveZ,
        "-z" => Axis::NegativeZ,
        _ => return None,
    })
}

/// The rest pose of every bone relative to the character: (rotation, position), caller's
/// units. Checks the parents and the values.
pub fn rest_globals(bones: &[RestBone<'_>]) -> Result<Vec<(Quat, Vec3)>> {
    let mut globals: Vec<(Quat, Vec3)> = Vec::with_capacity(bones.len());
    for (index, bone) in bones.iter().enumerate() {
        ensure_all_finite(&bone.translation.to_array(), "bone rest translation")?;
        ensure_all_finite(&bone.rotation.to_array(), "bone rest rotation")?;
        let length = bone.rotation.length();
        if !(0.5..=2.0).contains(&length) {
            return Err(Error::InvalidArgument(format!(
                "bone {} has a rest rotation of length {length}, not 1",
                bone.name
            )));
        }
        let rotation = bone.rotation / length;
        globals.push(match bone.parent {
            None => (rotation, bone.translation),
            Some(parent) if parent < index => {
                let (parent_rotation, parent_position) = globals[parent];
                (
                    (parent_rotation * rotation).normalize(),
                    parent_position + parent_rotation * bone.translation,
                )
            }
            Some(parent) => {
                return Err(Error::InvalidArgument(format!(
                    "bone {index} ({}) has parent {parent}: parents come before children",
                    bone.name
                )))
            }
        });
    }
    Ok(globals)
}

/// The names of `bones`, comma separated (for error messages).
fn bone_names(bones: &[RestBone<'_>]) -> String {
    if bones.is_empty() {
        return "none".into();
    }
    bones.iter().map(|b| b.name).collect::<Vec<_>>().join(", ")
}

/// Maps a skeleton's bones to a gaze chain with `map` (see the [module docs](self)).
///
/// Limits (on the delta rotations, about each joint's up): the spine shares 40° of yaw (5°
/// of swing each), the neck 50° (20°), the head 20° (25°) — 70° and 30° when there is no
/// neck; the eyes a 35° cone and no torsion.
///
/// Errors ([`Error::InvalidArgument`] naming the bones): no bone maps to `head` (the message
/// lists the bones found), the head has no parent to hang the chain from, the bones below
/// the head are not spine bones then neck bones, more than 8 spine or 4 neck bones, one eye
/// without the other or an eye that is not a child of the head, axes that are not
/// perpendicular; [`Error::NonFinite`] for a NaN or infinite rest value.
pub fn map_skeleton(
    bones: &[RestBone<'_>],
    map: &BoneMap,
    options: &SkeletonOptions,
) -> Result<MappedChain> {
    let units = options.units_per_metre;
    if !(units.is_finite() && units > 0.0) {
        return Err(Error::InvalidArgument(format!(
            "units_per_metre is {units}, must be positive"
        )));
    }
    let globals = rest_globals(bones)?;
    let roles: Vec<BoneRole> = bones.iter().map(|b| map.role_of(b.name)).collect();
    let head = roles
        .iter()
        .position(|r| *r == BoneRole::Head)
        .ok_or_else(|| {
            Error::InvalidArgument(format!(
                "no head bone: none of the bones ({}) maps to 'head' (map one with NAME=head)",
                bone_names(bones)
            ))
        })?;
    // From the head down through neck and spine bones.
    let mut chain = vec![head];
    let mut parent = bones[head].parent;
    while let Some(index) = parent {
        match roles[index] {
            BoneRole::Spine | BoneRole::Neck => {
                chain.push(index);
                parent = bones[index].parent;
            }
            _ => break,
        }
    }
    let root = parent.ok_or_else(|| {
        Error::InvalidArgument(format!(
            "bone {} has no parent to hang the gaze chain from",
            bones[chain[chain.len() - 1]].name
        ))
    })?;
    chain.reverse();
    let chain_roles: Vec<BoneRole> = chain.iter().map(|&i| roles[i]).collect();
    let spine = chain_roles
        .iter()
        .take_while(|r| **r == BoneRole::Spine)
        .count();
    let neck = chain_roles[spine..]
        .iter()
        .take_while(|r| **r == BoneRole::Neck)
        .count();
    if spine + neck + 1 != chain.len() {
        return Err(Error::InvalidArgument(format!(
            "the bones below the head must be spine bones then neck bones: {}",
            chain
                .iter()
                .map(|&i| format!("{} ({})", bones[i].name, roles[i].name()))
                .collect::<Vec<_>>()
                .join(" > ")
        )));
    }
    if spine > MAX_SPINE_JOINTS || neck > MAX_CERVICAL_JOINTS {
        return Err(Error::InvalidArgument(format!(
            "the gaze chain has {spine} spine and {neck} neck bones: at most \
             {MAX_SPINE_JOINTS} and {MAX_CERVICAL_JOINTS}"
        )));
    }
    // The eyes: both or none, children of the head.
    let find = |role: BoneRole| roles.iter().position(|r| *r == role);
    let eyes = match (find(BoneRole::LeftEye), find(BoneRole::RightEye)) {
        (None, None) => None,
        (Some(left), Some(right)) => {
            for eye in [left, right] {
                if bones[eye].parent != Some(head) {
                    return Err(Error::InvalidArgument(format!(
                        "eye bone {} is not a child of the head bone {}",
                        bones[eye].name, bones[head].name
                    )));
                }
            }
            Some([left, right])
        }
        (Some(eye), None) | (None, Some(eye)) => {
            return Err(Error::InvalidArgument(format!(
                "eye bone {} has no other eye: map both (left_eye, right_eye) or neither",
                bones[eye].name
            )))
        }
    };

    let up_axis = match options.up {
        Some(axis) => axis,
        None => nearest_axis(globals[head].1 - globals[root].1),
    };
    let up = up_axis.vector();
    let forward_axis = match options.forward {
        Some(axis) => axis,
        None => detect_forward(bones, &globals, up_axis),
    };
    let forward = forward_axis.vector();
    if forward.dot(up) != 0.0 {
        return Err(Error::InvalidArgument(
            "the forward axis must be perpendicular to the up axis".into(),
        ));
    }

    let scale = 1.0 / units;
    let degrees = f32::to_radians;
    // Limits about the joint's up (twist) and the cone around it (swing).
    let limits = |role: BoneRole, frame: Quat| -> JointLimits {
        let (yaw, swing) = match role {
            BoneRole::Spine => (40.0 / spine.max(1) as f32, 5.0),
            BoneRole::Neck => (50.0 / neck.max(1) as f32, 20.0),
            _ if neck == 0 => (70.0, 30.0),
            _ => (20.0, 25.0),
        };
        JointLimits::new(
            frame.conjugate() * up,
            degrees(swing),
            -degrees(yaw),
            degrees(yaw),
        )
    };
    let root_rotation = globals[root].0;
    let mut joints: Vec<ChainJoint> = Vec::with_capacity(chain.len() + 2);
    for (k, (&index, &role)) in chain.iter().zip(&chain_roles).enumerate() {
        let bone = &bones[index];
        // The first joint hangs from the chain root, whose frame is the character's.
        let (offset, rest) = if k == 0 {
            (
                root_rotation * bone.translation,
                root_rotation * bone.rotation,
            )
        } else {
            (bone.translation, bone.rotation)
        };
        joints.push(ChainJoint::new(
            match role {
                BoneRole::Spine => JointRole::Spine,
                BoneRole::Neck => JointRole::Cervical,
                _ => JointRole::Head,
            },
            offset * scale,
            rest.normalize(),
            limits(role, globals[index].0),
        ));
    }
    // The eyes look along the character's forward at rest: in the head's frame, and each in
    // its own frame for its twist (torsion) axis.
    let head_rotation = globals[head].0;
    let eye_forward = head_rotation.conjugate() * forward;
    let eye_up = head_rotation.conjugate() * up;
    let mut chain_bones = chain.clone();
    if let Some(eyes) = eyes {
        for (eye, role) in eyes
            .into_iter()
            .zip([JointRole::LeftEye, JointRole::RightEye])
        {
            let bone = &bones[eye];
            joints.push(ChainJoint::new(
                role,
                bone.translation * scale,
                bone.rotation.normalize(),
                JointLimits::new(
                    globals[eye].0.conjugate() * forward,
                    degrees(35.0),
                    0.0,
                    0.0,
                ),
            ));
            chain_bones.push(eye);
        }
    }
    let root_offset = options.root_offset.unwrap_or(globals[root].1) * scale;
    ensure_all_finite(&root_offset.to_array(), "root_offset")?;
    let gaze_chain = GazeChain::new(&joints, eye_forward, eye_up, root_offset)?;
    Ok(MappedChain {
        bones: chain_bones,
        root,
        chain: gaze_chain,
        up: up_axis,
        forward: forward_axis,
    })
}

/// `left × up`, left from the rest positions of the `Left*`/`Right*` bone pairs; the usual
/// facing for the up axis without pairs.
fn detect_forward(bones: &[RestBone<'_>], globals: &[(Quat, Vec3)], up_axis: Axis) -> Axis {
    let up = up_axis.vector();
    let mut left = Vec3::ZERO;
    for (index, bone) in bones.iter().enumerate() {
        let name = bone.name.rsplit(':').next().unwrap_or(bone.name);
        if let Some(rest_name) = name.strip_prefix("Left") {
            let wanted = format!("Right{rest_name}");
            let right = bones.iter().position(|b| {
                let other = b.name.rsplit(':').next().unwrap_or(b.name);
                other.eq_ignore_ascii_case(&wanted)
            });
            if let Some(right) = right {
                left += globals[index].1 - globals[right].1;
            }
        }
    }
    let left = left - up * left.dot(up);
    if left.length() < 1e-9 {
        match up_axis {
            Axis::PositiveZ | Axis::NegativeZ => Axis::NegativeY,
            _ => Axis::PositiveZ,
        }
    } else {
        nearest_axis(left.cross(up))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A BVH-like skeleton, Z up, facing −Y, identity rests (units of 10 cm).
    fn biovision() -> Vec<RestBone<'static>> {
        let bone = |name, parent, x: f32, y: f32, z: f32| RestBone {
            name,
            parent,
            translation: Vec3::new(x, y, z),
            rotation: Quat::IDENTITY,
        };
        vec![
            bone("Hips", None, 0.0, 0.0, 9.5),
            bone("Spine", Some(0), 0.0, 0.0, 1.0),
            bone("Spine1", Some(1), 0.0, 0.0, 1.5),
            bone("Neck", Some(2), 0.0, 0.0, 2.5),
            bone("Head", Some(3), 0.0, 0.0, 1.0),
            bone("LeftArm", Some(2), 2.0, 0.0, 2.0),
            bone("RightArm", Some(2), -2.0, 0.0, 2.0),
        ]
    }

    fn metres_of_ten_cm() -> SkeletonOptions {
        SkeletonOptions {
            units_per_metre: 10.0,
            ..SkeletonOptions::default()
        }
    }

    #[test]
    fn a_biovision_skeleton_maps_like_the_cli_did() {
        let bones = biovision();
        let mapped = map_skeleton(&bones, &BoneMap::default(), &metres_of_ten_cm()).unwrap();
        assert_eq!(mapped.bones, vec![1, 2, 3, 4]);
        assert_eq!(mapped.root, 0);
        assert_eq!(
            (mapped.up, mapped.forward),
            (Axis::PositiveZ, Axis::NegativeY)
        );
        let chain = &mapped.chain;
        assert_eq!((chain.spine_count(), chain.cervical_count()), (2, 1));
        assert!(!chain.has_eyes());
        assert_eq!(chain.joints()[2].offset, Vec3::new(0.0, 0.0, 0.25));
        assert!(chain
            .root_offset()
            .abs_diff_eq(Vec3::new(0.0, 0.0, 0.95), 1e-6));
        assert_eq!(chain.eye_forward(), Vec3::NEG_Y);
        assert_eq!(chain.joints()[0].limits.twist_axis(), Vec3::Z);
        // Spine 40° shared by two, neck 50°, head 20°.
        let yaw = |k: usize| chain.joints()[k].limits.max_twist().to_degrees();
        assert!((yaw(0) - 20.0).abs() < 1e-4 && (yaw(2) - 50.0).abs() < 1e-4);
        assert!((yaw(3) - 20.0).abs() < 1e-4);
    }

    /// The same skeleton in Godot's axes (Y up, +Z forward) with every bone's rest rotated
    /// as importers do (each bone's Y along the bone) and two eyes: the chain must place
    /// the joints, eyes and axes where the plain one does.
    #[test]
    fn rotated_rests_give_the_same_world_pose() {
        let plain = [
            ("Hips", None, Vec3::new(0.0, 0.95, 0.0)),
            ("Spine", Some(0), Vec3::new(0.0, 0.1, 0.0)),
            ("Chest", Some(1), Vec3::new(0.0, 0.3, 0.02)),
            ("Neck", Some(2), Vec3::new(0.0, 0.2, -0.02)),
            ("Head", Some(3), Vec3::new(0.0, 0.08, 0.0)),
            ("LeftEye", Some(4), Vec3::new(0.03, 0.06, 0.08)),
            ("RightEye", Some(4), Vec3::new(-0.03, 0.06, 0.08)),
        ];
        // Each bone's rest rotation: an arbitrary turn, compensated in its children.
        let turns: Vec<Quat> = (0..plain.len())
            .map(|i| {
                Quat::from_euler(
                    glam::EulerRot::YXZ,
                    0.3 * i as f32,
                    -0.2,
                    0.1 + 0.05 * i as f32,
                )
            })
            .collect();
        let mut globals = Vec::new();
        let mut bones = Vec::new();
        for (i, (name, parent, translation)) in plain.iter().enumerate() {
            let world = match parent {
                None => *translation,
                Some(p) => globals[*p] + *translation,
            };
            globals.push(world);
            let (parent_turn, parent_world) = match parent {
                None => (Quat::IDENTITY, Vec3::ZERO),
                Some(p) => (turns[*p], globals[*p]),
            };
            bones.push(RestBone {
                name,
                parent: *parent,
                translation: parent_turn.conjugate() * (world - parent_world),
                rotation: parent_turn.conjugate() * turns[i],
            });
        }
        let options = SkeletonOptions {
            up: Some(Axis::PositiveY),
            forward: Some(Axis::PositiveZ),
            ..SkeletonOptions::default()
        };
        let mapped = map_skeleton(&bones, &BoneMap::default(), &options).unwrap();
        assert_eq!(mapped.bones, vec![1, 2, 3, 4, 5, 6]);
        let chain = &mapped.chain;
        assert!(chain.has_eyes());
        // Forward kinematics of the chain at rest reach the same points.
        let mut position = chain.root_offset();
        let mut rotation = Quat::IDENTITY;
        for (k, joint) in chain.joints()[..chain.body_count()].iter().enumerate() {
            position += rotation * joint.offset;
            rotation *= joint.rest;
            assert!(position.abs_diff_eq(globals[k + 1], 1e-5), "joint {k}");
            // Every body joint twists about the world's up.
            assert!((rotation * joint.limits.twist_axis()).abs_diff_eq(Vec3::Y, 1e-5));
        }
        assert!((rotation * chain.eye_forward()).abs_diff_eq(Vec3::Z, 1e-5));
        assert!((rotation * chain.eye_up()).abs_diff_eq(Vec3::Y, 1e-5));
        for (k, eye) in [5, 6].into_iter().enumerate() {
            let joint = chain.joints()[chain.body_count() + k];
            assert!((position + rotation * joint.offset).abs_diff_eq(globals[eye], 1e-5));
            let eye_rotation = rotation * joint.rest;
            assert!((eye_rotation * joint.limits.twist_axis()).abs_diff_eq(Vec3::Z, 1e-5));
        }
        assert!((chain.look_at_height(Vec3::Y) - 1.69).abs() < 1e-4);
    }

    #[test]
    fn overrides_and_namespaces() {
        let map = BoneMap::with_overrides(" Jaw=head , Head=none,mixamorig:Neck=spine").unwrap();
        assert_eq!(map.role_of("jaw"), BoneRole::Head);
        assert_eq!(map.role_of("Head"), BoneRole::None);
        assert_eq!(map.role_of("mixamorig:Neck"), BoneRole::Spine);
        assert_eq!(map.role_of("other:Neck"), BoneRole::Neck);
        assert_eq!(map.role_of("mixamorig:Spine2"), BoneRole::Spine);
        assert_eq!(map.role_of("Eye.L"), BoneRole::LeftEye);
        assert_eq!(map.role_of("Tail"), BoneRole::None);
        for role in BoneRole::ALL {
            assert_eq!(BoneRole::parse(role.name()), Some(role));
        }
        for bad in ["Head", "Head=brain", "=x"] {
            let error = BoneMap::with_overrides(bad).unwrap_err();
            assert!(matches!(error, Error::InvalidArgument(_)), "{bad}: {error}");
        }
        assert_eq!(parse_axis("-Z"), Some(Axis::NegativeZ));
        assert_eq!(parse_axis("w"), None);
    }

    #[test]
    fn bad_skeletons_are_explained() {
        let options = metres_of_ten_cm();
        let message = |bones: &[RestBone<'_>]| {
            map_skeleton(bones, &BoneMap::default(), &options)
                .unwrap_err()
                .to_string()
        };
        let mut headless = biovision();
        headless[4].name = "Skull";
        let text = message(&headless);
        assert!(
            text.contains("no head bone") && text.contains("Hips, Spine"),
            "{text}"
        );
        assert!(message(&[]).contains("(none)"));
        let lone = [RestBone {
            name: "Head",
            parent: None,
            translation: Vec3::ZERO,
            rotation: Quat::IDENTITY,
        }];
        assert!(message(&lone).contains("no parent"));
        let mut upside = biovision();
        upside[2].name = "Neck1";
        upside[3].name = "Spine3";
        assert!(message(&upside).contains("spine bones then neck bones"));
        let mut one_eye = biovision();
        one_eye.push(RestBone {
            name: "LeftEye",
            parent: Some(4),
            translation: Vec3::ZERO,
            rotation: Quat::IDENTITY,
        });
        assert!(message(&one_eye).contains("no other eye"));
        one_eye.push(RestBone {
            name: "RightEye",
            parent: Some(3),
            translation: Vec3::ZERO,
            rotation: Quat::IDENTITY,
        });
        assert!(message(&one_eye).contains("not a child of the head"));
        let mut nan = biovision();
        nan[2].translation.y = f32::NAN;
        assert!(matches!(
            map_skeleton(&nan, &BoneMap::default(), &options),
            Err(Error::NonFinite(_))
        ));
        let mut loop_ = biovision();
        loop_[1].parent = Some(3);
        assert!(message(&loop_).contains("parents come before children"));
        let sideways = SkeletonOptions {
            up: Some(Axis::PositiveZ),
            forward: Some(Axis::NegativeZ),
            ..options
        };
        assert!(map_skeleton(&biovision(), &BoneMap::default(), &sideways).is_err());
        let zero = SkeletonOptions {
            units_per_metre: 0.0,
            ..options
        };
        assert!(map_skeleton(&biovision(), &BoneMap::default(), &zero).is_err());
    }
}
