//! From a skeleton's bones to a gaze chain: which bones are spine, neck, head and eyes (by
//! name, read the way importers write them, with overrides), the chain's offsets, rest
//! rotations and limits in metres in the crowd's axes, and each frame's conversions between
//! the engine's bone rotations and the crowd's base pose and joints.
//!
//! The engines' adapters, the C ABI (`cg_rig_*`), the command-line tool's `bvh` command and
//! the examples share this mapping:
//!
//! 1. Each bone gets a [`BoneRole`]: the caller's override for its name
//!    ([`BoneMap::with_overrides`]), else the default rules ([`names`]), which read the
//!    names of Mixamo (with or without its `mixamorig` prefix), Unreal's mannequins and
//!    MetaHumans, Unity Humanoid and VRM, VRoid, Godot's humanoid profile, Daz Genesis 8
//!    and 9, Character Creator, SMPL-X, Rigify, CMU BVH, Rokoko and HumanIK rigs.
//! 2. [`map_skeleton`] finds the head, walks down its ancestors while they are neck then
//!    spine bones (the first other ancestor is the chain root), takes two eyes under the
//!    head (directly or through facial bones), and builds the
//!    [`GazeChain`](crate::ik::GazeChain). A mapping that would quietly leave out bones
//!    that plainly belong in the chain fails, naming the bone and the override that fixes
//!    it; [`MappedChain::report`] says which role each bone got and why.
//! 3. Each frame, [`MappedChain::base_pose`] turns the engine's bone local rotations into
//!    the crowd's base pose, and [`MappedChain::write_joints`] writes the crowd's joints
//!    back as bone local rotations (the rotations of the bones between chain joints, and
//!    of the chain root's ancestors, folded in and out).
//!
//! Conventions: bones are given at rest, each as a translation (caller's units) and a
//! rotation relative to its parent, parents before children; a bone without a parent is
//! relative to the character (its position on the ground, at heading 0). The chain root's
//! frame is the character's: its rotation is folded into the first chain joint's. Twist
//! axes and the eyes' forward and up are expressed in each joint's own frame at rest, so
//! skeletons whose bones have rotated rest poses (as imported models do) need nothing
//! special.

mod axes;
pub mod names;
mod pose;
mod report;

use std::collections::HashMap;

use glam::{Quat, Vec3};

use crate::error::{ensure_all_finite, Error, Result};
use crate::ik::chain::{MAX_CERVICAL_JOINTS, MAX_SPINE_JOINTS};
use crate::ik::{ChainJoint, GazeChain, JointLimits, JointRole, MAX_CHAIN_JOINTS};
use crate::world::Axis;

pub use axes::{nearest_axis, parse_axis};
pub use names::{default_role, read_name, ReadName, Side};
pub(crate) use pose::{BoneRotations, BoneRotationsMut};

/// The most bones a skeleton may have.
pub const MAX_BONES: usize = 65_536;

/// The longest bone name, bytes.
pub const MAX_NAME_BYTES: usize = 1024;

/// The longest bone offset, metres (a skeleton's units read wrong give kilometres).
pub const MAX_BONE_LENGTH: f32 = 1000.0;

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
    /// The character's left eye (under the head).
    LeftEye,
    /// The character's right eye (under the head).
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

/// Bone names to roles: the caller's overrides, by exact name (case-insensitive, with or
/// without a `namespace:` prefix), on top of the default rules ([`default_role`]).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct BoneMap {
    /// By lowercase name: the name as given, and its role.
    overrides: HashMap<String, (String, BoneRole)>,
}

impl BoneMap {
    /// The default rules with `overrides` applied: `Name=role` entries separated by commas
    /// (roles as [`BoneRole::parse`] reads them), e.g. `"mixamorig:Spine=none,Jaw=head"`.
    ///
    /// Errors: [`Error::InvalidArgument`] naming the entry that is not `NAME=ROLE`, the
    /// role that is not one, or a name given twice.
    pub fn with_overrides(overrides: &str) -> Result<BoneMap> {
        let mut map = BoneMap::default();
        for entry in overrides.split(',').filter(|e| !e.trim().is_empty()) {
            let (name, role) = entry.split_once('=').ok_or_else(|| {
                Error::InvalidArgument(format!("bone map: '{entry}' is not NAME=ROLE"))
            })?;
            let role = BoneRole::parse(role).ok_or_else(|| {
                Error::InvalidArgument(format!(
                    "bone map: '{}' is not a role (root, spine, neck, head, left_eye, \
                     right_eye or none)",
                    role.trim()
                ))
            })?;
            let name = name.trim();
            if name.is_empty() {
                return Err(Error::InvalidArgument(format!(
                    "bone map: '{entry}' names no bone"
                )));
            }
            if map.overrides.contains_key(&name.to_lowercase()) {
                return Err(Error::InvalidArgument(format!(
                    "bone map: bone '{name}' is given twice"
                )));
            }
            map.set(name, role);
        }
        Ok(map)
    }

    /// Maps `name` (case-insensitive) to `role`, replacing what the map said.
    pub fn set(&mut self, name: &str, role: BoneRole) {
        self.overrides
            .insert(name.to_lowercase(), (name.to_string(), role));
    }

    /// The override for `name`, if there is one: its full name's, else the one of the name
    /// after its last `:` (a namespace prefix such as `mixamorig:`).
    pub fn override_of(&self, name: &str) -> Option<BoneRole> {
        let short = name.rsplit(':').next().unwrap_or(name);
        self.overrides
            .get(&name.to_lowercase())
            .or_else(|| self.overrides.get(&short.to_lowercase()))
            .map(|(_, role)| *role)
    }

    /// The role of the bone called `name`: its override, else the default rules'.
    pub fn role_of(&self, name: &str) -> BoneRole {
        self.override_of(name).unwrap_or_else(|| default_role(name))
    }

    /// The overridden names: (lowercase, as given), for the check that each names a bone.
    fn override_names(&self) -> impl Iterator<Item = (&str, &str)> {
        self.overrides
            .iter()
            .map(|(lower, (given, _))| (lower.as_str(), given.as_str()))
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
    /// The skeleton's up axis; `None` takes the axis nearest to the rest-pose spine (chain
    /// root to head).
    pub up: Option<Axis>,
    /// The direction the skeleton faces at rest; `None` detects it from the rest pose
    /// (`left × up`, left from the bones whose names give a side, else from where the eyes
    /// or the toes are), and refuses a skeleton that shows none of them.
    pub forward: Option<Axis>,
    /// How many of the skeleton's length units make a metre.
    pub units_per_metre: f32,
    /// The chain root's position relative to the character (caller's units, the
    /// skeleton's axes); `None` takes its rest position.
    pub root_offset: Option<Vec3>,
    /// The crowd's up and forward axes: the chain, the base poses and the joints written
    /// back are turned from the skeleton's axes into them. `None`: the skeleton's own.
    pub crowd_axes: Option<(Axis, Axis)>,
}

impl Default for SkeletonOptions {
    /// Axes detected, metres, the rest position of the chain root, the skeleton's axes.
    fn default() -> Self {
        SkeletonOptions {
            up: None,
            forward: None,
            units_per_metre: 1.0,
            root_offset: None,
            crowd_axes: None,
        }
    }
}

/// How the mapping found the direction a skeleton faces.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FacingFrom {
    /// Given by the caller.
    Given,
    /// From the rest positions of bones named as left and right pairs.
    SidePairs,
    /// From the eyes' position in front of the head.
    Eyes,
    /// From the toes' position in front of the feet.
    Toes,
}

/// A skeleton's gaze chain, which bones it turns, and each frame's conversions.
#[derive(Debug, Clone, PartialEq)]
pub struct MappedChain {
    /// The bone of each chain joint, bottom to top (spine, neck, head, then the left and
    /// right eye if the chain has eyes).
    pub bones: Vec<usize>,
    /// The chain root: the bone the first chain joint hangs from (through the bones of its
    /// path, if any). Its rotation relative to the character is folded into the first
    /// joint's base rotation (see [`MappedChain::base_pose`]).
    pub root: usize,
    /// The gaze chain (metres, the crowd's axes at heading 0).
    pub chain: GazeChain,
    /// The skeleton's up axis.
    pub up: Axis,
    /// The direction the skeleton faces at heading 0.
    pub forward: Axis,
    /// How the facing was found.
    pub facing_from: FacingFrom,
    /// The role each bone got, in the skeleton's order.
    pub roles: Vec<BoneRole>,
    /// Whether each bone's role came from an override.
    pub overridden: Vec<bool>,
    /// What the caller should know of the mapping (a chain without neck, an eye found
    /// through facial bones...).
    pub notes: Vec<String>,
    /// The bones' names (for the report).
    names: Vec<String>,
    /// The turn from the skeleton's axes into the crowd's.
    turn: Quat,
    /// For each chain joint, the bones whose local rotations make its base rotation, top
    /// down and ending with the joint's own bone: for the first joint, every ancestor from
    /// the skeleton's top; for the others, the bones after the previous joint (for the
    /// eyes, after the head).
    paths: Vec<u32>,
    /// Where each joint's path ends in `paths`.
    path_ends: [u32; MAX_CHAIN_JOINTS],
}

/// At most this many names in a message, then how many more.
const NAMES_IN_A_MESSAGE: usize = 12;

/// `names`, comma separated, at most [`NAMES_IN_A_MESSAGE`] of them (for messages).
fn name_list<'a>(names: impl ExactSizeIterator<Item = &'a str>) -> String {
    let count = names.len();
    if count == 0 {
        return "none".into();
    }
    let mut text = names
        .take(NAMES_IN_A_MESSAGE)
        .map(|name| format!("'{}'", shorten(name)))
        .collect::<Vec<_>>()
        .join(", ");
    if count > NAMES_IN_A_MESSAGE {
        text += &format!(" and {} more", count - NAMES_IN_A_MESSAGE);
    }
    text
}

/// A name cut to 64 characters for a message.
fn shorten(name: &str) -> String {
    if name.chars().count() <= 64 {
        name.to_string()
    } else {
        name.chars().take(61).collect::<String>() + "..."
    }
}

/// The rest pose of every bone relative to the character: (rotation, position), caller's
/// units. Checks the parents, the names and the values.
pub fn rest_globals(bones: &[RestBone<'_>]) -> Result<Vec<(Quat, Vec3)>> {
    if bones.len() > MAX_BONES {
        return Err(Error::InvalidArgument(format!(
            "the skeleton has {} bones, at most {MAX_BONES}",
            bones.len()
        )));
    }
    let mut globals: Vec<(Quat, Vec3)> = Vec::with_capacity(bones.len());
    for (index, bone) in bones.iter().enumerate() {
        if bone.name.trim().is_empty() || bone.name.len() > MAX_NAME_BYTES {
            return Err(Error::InvalidArgument(format!(
                "bone {index} has {} name: names have 1 to {MAX_NAME_BYTES} bytes",
                if bone.name.trim().is_empty() {
                    "an empty"
                } else {
                    "a too long"
                }
            )));
        }
        ensure_all_finite(&bone.translation.to_array(), "bone rest translation")?;
        ensure_all_finite(&bone.rotation.to_array(), "bone rest rotation")?;
        let length = bone.rotation.length();
        if (length - 1.0).abs() > 1e-3 {
            return Err(Error::InvalidArgument(format!(
                "bone {index} ('{}') has a rest rotation of length {length}, not 1",
                shorten(bone.name)
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
                    "bone {index} ('{}') has parent {parent}: parents come before children",
                    shorten(bone.name)
                )))
            }
        });
    }
    let mut seen: HashMap<&str, usize> = HashMap::with_capacity(bones.len());
    for (index, bone) in bones.iter().enumerate() {
        if let Some(first) = seen.insert(bone.name, index) {
            return Err(Error::InvalidArgument(format!(
                "bones {first} and {index} are both called '{}': names must be unique",
                shorten(bone.name)
            )));
        }
    }
    Ok(globals)
}

/// True if `ancestor` is `bone` or one of its ancestors.
fn is_ancestor(bones: &[RestBone<'_>], ancestor: usize, mut bone: usize) -> bool {
    loop {
        if bone == ancestor {
            return true;
        }
        match bones[bone].parent {
            Some(parent) => bone = parent,
            None => return false,
        }
    }
}

/// The bones from just below `top` (exclusive; `None`: from the skeleton's top) down to
/// `bone` (inclusive), top down.
fn path_between(bones: &[RestBone<'_>], top: Option<usize>, bone: usize) -> Vec<u32> {
    let mut path = vec![bone as u32];
    let mut current = bones[bone].parent;
    while let Some(index) = current {
        if Some(index) == top {
            break;
        }
        path.push(index as u32);
        current = bones[index].parent;
    }
    path.reverse();
    path
}

/// The head: the one bone mapped to `head`, or of several the one with eyes under it.
fn find_head(bones: &[RestBone<'_>], roles: &[BoneRole]) -> Result<usize> {
    let heads: Vec<usize> = (0..bones.len())
        .filter(|&i| roles[i] == BoneRole::Head)
        .collect();
    match heads.as_slice() {
        [] => Err(Error::InvalidArgument(format!(
            "no head bone: none of the {} bones ({}) is named as a head; map one with \
             NAME=head",
            bones.len(),
            name_list(bones.iter().map(|b| b.name))
        ))),
        [head] => Ok(*head),
        several => {
            let with_eyes: Vec<usize> = several
                .iter()
                .copied()
                .filter(|&head| {
                    (0..bones.len()).any(|i| {
                        matches!(roles[i], BoneRole::LeftEye | BoneRole::RightEye)
                            && i != head
                            && is_ancestor(bones, head, i)
                    })
                })
                .collect();
            if let [head] = with_eyes.as_slice() {
                return Ok(*head);
            }
            Err(Error::InvalidArgument(format!(
                "{} bones are named as a head ({}): map the others with NAME=none",
                several.len(),
                name_list(several.iter().map(|&i| bones[i].name))
            )))
        }
    }
}

/// The eye of `role` under the head.
fn find_eye(
    bones: &[RestBone<'_>],
    roles: &[BoneRole],
    head: usize,
    role: BoneRole,
) -> Result<Option<usize>> {
    let candidates: Vec<usize> = (0..bones.len()).filter(|&i| roles[i] == role).collect();
    let under: Vec<usize> = candidates
        .iter()
        .copied()
        .filter(|&i| i != head && is_ancestor(bones, head, i))
        .collect();
    if under.is_empty() {
        if let Some(&eye) = candidates.first() {
            return Err(Error::InvalidArgument(format!(
                "eye bone '{}' is not under the head bone '{}': map the right head, or the \
                 eye with {}=none",
                shorten(bones[eye].name),
                shorten(bones[head].name),
                shorten(bones[eye].name)
            )));
        }
        return Ok(None);
    }
    // Of several (`FACIAL_L_Eye` and `FACIAL_L_EyeParallel`), the plainest name, then the
    // closest to the head.
    Ok(under.iter().copied().min_by_key(|&i| {
        (
            read_name(bones[i].name).words.len(),
            path_between(bones, Some(head), i).len(),
        )
    }))
}

/// Maps a skeleton's bones to a gaze chain with `map` (see the [module docs](self)).
///
/// Limits (on the delta rotations, about each joint's up): the spine shares 40° of yaw (5°
/// of swing each), the neck 50° (20°), the head 20° (25°) — 70° and 30° when there is no
/// neck; the eyes a 35° cone and no torsion.
///
/// Errors ([`Error::InvalidArgument`] naming the bones and the override that fixes it): no
/// bone maps to `head`; the walk down from the head stops at a bone that is not recognised
/// while spine or neck bones lie below it; the head hangs from the chain root with no neck
/// or spine between (unless an override names that bone `root`: a head-only chain meant);
/// the bones below the head are not spine bones then neck bones; more than 8 spine or 4
/// neck bones; one eye without the other, an eye not under the head, or eye bones under
/// the head that no role takes; a facing that the rest pose does not show; duplicate or
/// empty names, a parent after its child, more than [`MAX_BONES`] bones, a non-unit rest
/// rotation, a bone longer than [`MAX_BONE_LENGTH`], overrides that name no bone;
/// [`Error::NonFinite`] for a NaN or infinite rest value.
pub fn map_skeleton(
    bones: &[RestBone<'_>],
    map: &BoneMap,
    options: &SkeletonOptions,
) -> Result<MappedChain> {
    let units = options.units_per_metre;
    if !(units.is_finite() && units > 0.0 && units <= 1e6) {
        return Err(Error::InvalidArgument(format!(
            "units_per_metre is {units}, must be in (0, 1e6]"
        )));
    }
    let skeleton_globals = rest_globals(bones)?;
    for (bone, (_, _)) in bones.iter().zip(&skeleton_globals) {
        let length = bone.translation.length() / units;
        if length > MAX_BONE_LENGTH {
            return Err(Error::InvalidArgument(format!(
                "bone '{}' is {length} m from its parent, more than {MAX_BONE_LENGTH} m: is \
                 units_per_metre ({units}) right?",
                shorten(bone.name)
            )));
        }
    }
    let mut stray: Vec<&str> = map
        .override_names()
        .filter(|(lower, _)| {
            !bones.iter().any(|b| {
                let short = b.name.rsplit(':').next().unwrap_or(b.name);
                b.name.to_lowercase() == *lower || short.to_lowercase() == *lower
            })
        })
        .map(|(_, given)| given)
        .collect();
    stray.sort_unstable();
    if let Some(name) = stray.first() {
        return Err(Error::InvalidArgument(format!(
            "the bone map names '{}', but the skeleton has no bone of that name",
            shorten(name)
        )));
    }
    let overridden: Vec<bool> = bones
        .iter()
        .map(|b| map.override_of(b.name).is_some())
        .collect();
    let roles: Vec<BoneRole> = bones.iter().map(|b| map.role_of(b.name)).collect();
    let head = find_head(bones, &roles)?;

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
            "bone '{}' has no parent to hang the gaze chain from: map the bone below the \
             head's spine as NAME=root, or give the skeleton a root",
            shorten(bones[chain[chain.len() - 1]].name)
        ))
    })?;
    check_where_the_walk_stopped(bones, &roles, &overridden, &chain, root)?;
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
            "the bones below the head must be spine bones then neck bones: {} (fix the \
             roles with NAME=spine or NAME=neck)",
            chain
                .iter()
                .map(|&i| format!("{} ({})", shorten(bones[i].name), roles[i].name()))
                .collect::<Vec<_>>()
                .join(" > ")
        )));
    }
    if spine > MAX_SPINE_JOINTS || neck > MAX_CERVICAL_JOINTS {
        return Err(Error::InvalidArgument(format!(
            "the gaze chain has {spine} spine and {neck} neck bones: at most \
             {MAX_SPINE_JOINTS} and {MAX_CERVICAL_JOINTS} (map the extra ones with NAME=none \
             and the one below them with NAME=root)"
        )));
    }
    let mut notes = Vec::new();
    if neck == 0 && spine > 0 {
        notes.push("no neck bone: the head turns with the neck's share too".to_string());
    }
    if spine == 0 && neck > 0 {
        notes.push("no spine bone: the body below the neck does not turn".to_string());
    }
    if spine + neck == 0 {
        notes.push(format!(
            "a head-only chain, as meant by the override {}=root",
            shorten(bones[root].name)
        ));
    }

    // The eyes: both or none, under the head.
    let eyes = match (
        find_eye(bones, &roles, head, BoneRole::LeftEye)?,
        find_eye(bones, &roles, head, BoneRole::RightEye)?,
    ) {
        (None, None) => {
            check_no_eye_left_out(bones, &roles, &overridden, head)?;
            None
        }
        (Some(left), Some(right)) => Some([left, right]),
        (Some(eye), None) | (None, Some(eye)) => {
            return Err(Error::InvalidArgument(format!(
                "eye bone '{}' has no other eye: map both (NAME=left_eye, NAME=right_eye) or \
                 neither ({}=none)",
                shorten(bones[eye].name),
                shorten(bones[eye].name)
            )))
        }
    };
    if let Some(eyes) = eyes {
        for eye in eyes {
            if bones[eye].parent != Some(head) {
                notes.push(format!(
                    "eye '{}' hangs from the head through {}",
                    shorten(bones[eye].name),
                    name_list(
                        path_between(bones, Some(head), eye)
                            .iter()
                            .rev()
                            .skip(1)
                            .rev()
                            .map(|&i| bones[i as usize].name)
                            .collect::<Vec<_>>()
                            .into_iter()
                    )
                ));
            }
        }
    }

    let up_axis = match options.up {
        Some(axis) => axis,
        None => nearest_axis(skeleton_globals[head].1 - skeleton_globals[root].1),
    };
    let (forward_axis, facing_from) = match options.forward {
        Some(axis) => (axis, FacingFrom::Given),
        None => {
            let (axis, how, mirrored) =
                axes::detect_forward(bones, &skeleton_globals, up_axis, eyes, head)?;
            if mirrored {
                notes.push(
                    "the bones named left lie on the character's right: a mirrored \
                     (left-handed) space, such as Unreal's; the facing comes from the eyes or \
                     toes, and each eye keeps its name"
                        .to_string(),
                );
            }
            (axis, how)
        }
    };
    if forward_axis.vector().dot(up_axis.vector()) != 0.0 {
        return Err(Error::InvalidArgument(
            "the forward axis must be perpendicular to the up axis".into(),
        ));
    }
    let (crowd_up, crowd_forward) = options.crowd_axes.unwrap_or((up_axis, forward_axis));
    if crowd_forward.vector().dot(crowd_up.vector()) != 0.0 {
        return Err(Error::InvalidArgument(
            "the crowd's forward axis must be perpendicular to its up axis".into(),
        ));
    }
    let turn = axes::turn_between((up_axis, forward_axis), (crowd_up, crowd_forward));
    let globals: Vec<(Quat, Vec3)> = skeleton_globals
        .iter()
        .map(|&(rotation, position)| ((turn * rotation).normalize(), turn * position))
        .collect();
    let up = crowd_up.vector();
    let forward = crowd_forward.vector();
    let height = (globals[head].1 - globals[root].1).dot(up) / units;
    if height.abs() < 1e-3 {
        return Err(Error::InvalidArgument(format!(
            "the head '{}' is {height} m above the chain root '{}' at rest: the rest pose \
             or the up axis is wrong",
            shorten(bones[head].name),
            shorten(bones[root].name)
        )));
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
    // Each joint relative to the one before it (the first to the chain root, whose frame
    // is the character's), from the rest globals: bones between them are folded in.
    let relative = |parent: Option<usize>, bone: usize| -> (Vec3, Quat) {
        let (rotation, position) = globals[bone];
        match parent {
            None => (position - globals[root].1, rotation),
            Some(parent) => {
                let (parent_rotation, parent_position) = globals[parent];
                (
                    parent_rotation.conjugate() * (position - parent_position),
                    (parent_rotation.conjugate() * rotation).normalize(),
                )
            }
        }
    };
    let mut joints: Vec<ChainJoint> = Vec::with_capacity(chain.len() + 2);
    let mut previous = None;
    for (&index, &role) in chain.iter().zip(&chain_roles) {
        let (offset, rest) = relative(previous, index);
        joints.push(ChainJoint::new(
            match role {
                BoneRole::Spine => JointRole::Spine,
                BoneRole::Neck => JointRole::Cervical,
                _ => JointRole::Head,
            },
            offset * scale,
            rest,
            limits(role, globals[index].0),
        ));
        previous = Some(index);
    }
    // The eyes look along the crowd's forward at rest: in the head's frame, and each in
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
            let (offset, rest) = relative(Some(head), eye);
            joints.push(ChainJoint::new(
                role,
                offset * scale,
                rest,
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
    let root_offset = match options.root_offset {
        Some(offset) => turn * offset,
        None => globals[root].1,
    } * scale;
    ensure_all_finite(&root_offset.to_array(), "root_offset")?;
    let gaze_chain = GazeChain::new(&joints, eye_forward, eye_up, root_offset)?;

    // The paths each frame composes.
    let mut paths = Vec::new();
    let mut path_ends = [0u32; MAX_CHAIN_JOINTS];
    for (k, &bone) in chain_bones.iter().enumerate() {
        let top = match k {
            0 => None,
            _ if k < chain.len() => Some(chain_bones[k - 1]),
            _ => Some(head),
        };
        paths.extend(path_between(bones, top, bone));
        path_ends[k] = paths.len() as u32;
    }
    Ok(MappedChain {
        bones: chain_bones,
        root,
        chain: gaze_chain,
        up: up_axis,
        forward: forward_axis,
        facing_from,
        roles,
        overridden,
        notes,
        names: bones.iter().map(|b| b.name.to_string()).collect(),
        turn,
        paths,
        path_ends,
    })
}

/// Fails if the walk down from the head stopped at `root` where it plainly should have
/// gone on: `root` is not recognised while spine or neck bones lie below it; or the head
/// hangs from it directly and no override says that is meant.
fn check_where_the_walk_stopped(
    bones: &[RestBone<'_>],
    roles: &[BoneRole],
    overridden: &[bool],
    chain: &[usize],
    root: usize,
) -> Result<()> {
    let name = shorten(bones[root].name);
    let below: Vec<usize> = {
        let mut found = Vec::new();
        let mut current = bones[root].parent;
        while let Some(index) = current {
            let read = read_name(bones[index].name);
            if matches!(roles[index], BoneRole::Spine | BoneRole::Neck)
                || (!overridden[index] && read.mentions_spine_or_neck())
            {
                found.push(index);
            }
            current = bones[index].parent;
        }
        found
    };
    let meant_as_root = overridden[root] && roles[root] == BoneRole::Root;
    if roles[root] != BoneRole::Root && !below.is_empty() && !meant_as_root {
        return Err(Error::InvalidArgument(format!(
            "the gaze chain stops at bone '{name}', which is not a spine or neck bone, but \
             {} below it look like spine or neck bones: map '{name}' with {name}=spine (or \
             {name}=neck) to carry the chain through it, or {name}=root to hang the chain \
             from it",
            name_list(below.iter().map(|&i| bones[i].name))
        )));
    }
    if chain.len() == 1 && !meant_as_root {
        return Err(Error::InvalidArgument(format!(
            "the head '{}' hangs from '{name}' with no neck or spine bone between: the gaze \
             would turn the head alone. Map the neck and spine bones (NAME=neck, NAME=spine), \
             or, if a head-only chain is meant, say so with {name}=root",
            shorten(bones[chain[0]].name)
        )));
    }
    Ok(())
}

/// Fails if bones under the head look like eyes but neither eye role took them.
fn check_no_eye_left_out(
    bones: &[RestBone<'_>],
    roles: &[BoneRole],
    overridden: &[bool],
    head: usize,
) -> Result<()> {
    let eyes: Vec<usize> = (0..bones.len())
        .filter(|&i| {
            i != head
                && roles[i] == BoneRole::None
                && !overridden[i]
                && read_name(bones[i].name).mentions_eye()
                && is_ancestor(bones, head, i)
        })
        .collect();
    if eyes.is_empty() {
        return Ok(());
    }
    let first = shorten(bones[eyes[0]].name);
    Err(Error::InvalidArgument(format!(
        "bones under the head look like eyes ({}) but none is mapped as one: map them with \
         NAME=left_eye and NAME=right_eye, or leave the eyes out with {first}=none for each",
        name_list(eyes.iter().map(|&i| bones[i].name))
    )))
}

#[cfg(test)]
mod tests;
