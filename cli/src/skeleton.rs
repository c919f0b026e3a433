//! From a BVH skeleton to a gaze chain: which joints are spine, neck and head (by name, with
//! a default map that `--map` overrides), which way is up and forward, and the chain's
//! offsets and limits in metres.

use std::collections::HashMap;

use anyhow::{anyhow, bail, Result};
use crowdgaze::ik::{ChainJoint, GazeChain, JointLimits, JointRole};
use crowdgaze::world::Axis;
use glam::{DQuat, DVec3, Quat, Vec3};

use crate::bvh::Bvh;

/// What a BVH joint is for the gaze chain.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Role {
    /// The body root (not turned by gaze; the chain hangs from it).
    Root,
    /// A spine joint.
    Spine,
    /// A neck joint.
    Neck,
    /// The head.
    Head,
    /// Not part of the chain.
    None,
}

impl Role {
    fn parse(text: &str) -> Option<Role> {
        Some(match text.trim().to_ascii_lowercase().as_str() {
            "root" | "hips" | "pelvis" => Role::Root,
            "spine" | "chest" => Role::Spine,
            "neck" | "cervical" => Role::Neck,
            "head" => Role::Head,
            "none" | "-" => Role::None,
            _ => return None,
        })
    }
}

/// The default map, by joint name (case-insensitive, after any `namespace:` prefix).
pub const DEFAULT_MAP: &[(&str, Role)] = &[
    ("Hips", Role::Root),
    ("Spine", Role::Spine),
    ("Spine1", Role::Spine),
    ("Spine2", Role::Spine),
    ("Spine3", Role::Spine),
    ("Chest", Role::Spine),
    ("UpperChest", Role::Spine),
    ("LowerBack", Role::Spine),
    ("Neck", Role::Neck),
    ("Neck1", Role::Neck),
    ("Head", Role::Head),
];

/// The joint map: the default one with `overrides` (`Name=role,Name=role`, roles `root`,
/// `spine`, `neck`, `head`, `none`) applied on top.
pub fn joint_map(overrides: Option<&str>) -> Result<HashMap<String, Role>> {
    let mut map: HashMap<String, Role> = DEFAULT_MAP
        .iter()
        .map(|(name, role)| (name.to_ascii_lowercase(), *role))
        .collect();
    if let Some(text) = overrides {
        for entry in text.split(',').filter(|e| !e.trim().is_empty()) {
            let (name, role) = entry
                .split_once('=')
                .ok_or_else(|| anyhow!("--map: '{entry}' is not NAME=ROLE"))?;
            let role = Role::parse(role).ok_or_else(|| {
                anyhow!("--map: '{role}' is not a role (root, spine, neck, head or none)")
            })?;
            map.insert(name.trim().to_ascii_lowercase(), role);
        }
    }
    Ok(map)
}

fn role_of(map: &HashMap<String, Role>, name: &str) -> Role {
    let short = name.rsplit(':').next().unwrap_or(name);
    map.get(&name.to_ascii_lowercase())
        .or_else(|| map.get(&short.to_ascii_lowercase()))
        .copied()
        .unwrap_or(Role::None)
}

/// A BVH skeleton's gaze chain and how it maps to the file.
#[derive(Debug, Clone)]
pub struct SkeletonChain {
    /// BVH joint index of each chain joint, bottom to top.
    pub joints: Vec<usize>,
    /// BVH joint index of the chain root (the parent of the first chain joint).
    pub root: usize,
    /// The gaze chain (metres, world axes).
    pub chain: GazeChain,
    /// Up axis.
    pub up: Axis,
    /// The direction the skeleton faces in its rest pose.
    pub forward: Axis,
}

/// The signed coordinate axis nearest to `v`.
pub fn nearest_axis(v: DVec3) -> Axis {
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

/// Parses an axis name: `x`, `-x`, `+y`, ...
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

/// Rest-pose position of every joint (file units, root at its offset).
pub fn rest_positions(bvh: &Bvh) -> Vec<DVec3> {
    let mut positions = vec![DVec3::ZERO; bvh.joints.len()];
    for (index, joint) in bvh.joints.iter().enumerate() {
        positions[index] = joint.offset + joint.parent.map_or(DVec3::ZERO, |p| positions[p]);
    }
    positions
}

/// The global rotation of joint `index` at `frame` (product of the locals from its root).
pub fn global_rotation(bvh: &Bvh, index: usize, frame: &[f64]) -> DQuat {
    let joint = &bvh.joints[index];
    let local = joint.rotation(frame);
    match joint.parent {
        Some(parent) => global_rotation(bvh, parent, frame) * local,
        None => local,
    }
}

impl SkeletonChain {
    /// Finds the chain in `bvh` with `map`, and the up and forward axes (detected unless
    /// given): up along the rest-pose spine (root to head), forward `left × up` with left
    /// from the rest positions of the `Left*` and `Right*` joints.
    pub fn build(
        bvh: &Bvh,
        map: &HashMap<String, Role>,
        up: Option<Axis>,
        forward: Option<Axis>,
        units_per_metre: f64,
    ) -> Result<SkeletonChain> {
        let roles: Vec<Role> = bvh.joints.iter().map(|j| role_of(map, &j.name)).collect();
        let head = roles.iter().position(|r| *r == Role::Head).ok_or_else(|| {
            anyhow!(
                "no head joint: none of the joints {} maps to 'head' (use --map NAME=head)",
                bvh.joints
                    .iter()
                    .map(|j| j.name.as_str())
                    .collect::<Vec<_>>()
                    .join(", ")
            )
        })?;
        // From the head down through neck and spine joints.
        let mut chain = vec![head];
        let mut parent = bvh.joints[head].parent;
        while let Some(index) = parent {
            match roles[index] {
                Role::Spine | Role::Neck => {
                    chain.push(index);
                    parent = bvh.joints[index].parent;
                }
                _ => break,
            }
        }
        let root = parent.ok_or_else(|| {
            anyhow!(
                "joint {} has no parent to hang the gaze chain from",
                bvh.joints[chain[chain.len() - 1]].name
            )
        })?;
        chain.reverse();
        let chain_roles: Vec<Role> = chain.iter().map(|&i| roles[i]).collect();
        let spine = chain_roles
            .iter()
            .take_while(|r| **r == Role::Spine)
            .count();
        let neck = chain_roles[spine..]
            .iter()
            .take_while(|r| **r == Role::Neck)
            .count();
        if spine + neck + 1 != chain.len() {
            bail!(
                "the joints below the head must be spine joints then neck joints: {}",
                chain
                    .iter()
                    .map(|&i| format!("{} ({:?})", bvh.joints[i].name, roles[i]))
                    .collect::<Vec<_>>()
                    .join(" > ")
            );
        }
        if spine > crowdgaze::ik::chain::MAX_SPINE_JOINTS
            || neck > crowdgaze::ik::chain::MAX_CERVICAL_JOINTS
        {
            bail!("the gaze chain has {spine} spine and {neck} neck joints: at most 8 and 4");
        }
        for &index in &chain {
            if bvh.joints[index].euler_order().is_none() {
                bail!(
                    "joint {} needs three rotation channels to take gaze",
                    bvh.joints[index].name
                );
            }
        }

        let rest = rest_positions(bvh);
        let up_axis = match up {
            Some(axis) => axis,
            None => nearest_axis(rest[head] - rest[root]),
        };
        let up_vector = up_axis.vector().as_dvec3();
        let forward_axis = match forward {
            Some(axis) => axis,
            None => {
                let mut left = DVec3::ZERO;
                for (index, joint) in bvh.joints.iter().enumerate() {
                    let name = joint.name.rsplit(':').next().unwrap_or(&joint.name);
                    if let Some(rest_name) = name.strip_prefix("Left") {
                        if let Some(right) = bvh.joint(&format!("Right{rest_name}")) {
                            left += rest[index] - rest[right];
                        }
                    }
                }
                let left = left - up_vector * left.dot(up_vector);
                if left.length() < 1e-9 {
                    // No left/right pairs: the usual facing for the up axis.
                    match up_axis {
                        Axis::PositiveZ | Axis::NegativeZ => Axis::NegativeY,
                        _ => Axis::PositiveZ,
                    }
                } else {
                    nearest_axis(left.cross(up_vector))
                }
            }
        };
        let forward_vector = forward_axis.vector();
        if forward_vector.dot(up_axis.vector()) != 0.0 {
            bail!("--forward must be perpendicular to --up");
        }
        let up_f = up_axis.vector();
        let scale = 1.0 / units_per_metre;
        let degrees = f32::to_radians;
        let limits = |role: Role| -> JointLimits {
            let (yaw, swing) = match role {
                Role::Spine => (40.0 / spine.max(1) as f32, 5.0),
                Role::Neck => (50.0 / neck.max(1) as f32, 20.0),
                _ if neck == 0 => (70.0, 30.0),
                _ => (20.0, 25.0),
            };
            JointLimits::new(up_f, degrees(swing), -degrees(yaw), degrees(yaw))
        };
        let joints: Vec<ChainJoint> = chain
            .iter()
            .zip(&chain_roles)
            .map(|(&index, &role)| {
                ChainJoint::new(
                    match role {
                        Role::Spine => JointRole::Spine,
                        Role::Neck => JointRole::Cervical,
                        _ => JointRole::Head,
                    },
                    (bvh.joints[index].offset * scale).as_vec3(),
                    Quat::IDENTITY,
                    limits(role),
                )
            })
            .collect();
        // The chain root above the ground: its rest position plus the first frame's root
        // translation, along up.
        let root_translation = bvh
            .frames
            .first()
            .and_then(|f| bvh.joints[0].translation(f))
            .unwrap_or(DVec3::ZERO);
        let height = (rest[root] + root_translation).dot(up_vector) * scale;
        let root_offset: Vec3 = (up_vector * height).as_vec3();
        let gaze_chain = GazeChain::new(&joints, forward_vector, up_f, root_offset)
            .map_err(|e| anyhow!("building the gaze chain: {e}"))?;
        Ok(SkeletonChain {
            joints: chain,
            root,
            chain: gaze_chain,
            up: up_axis,
            forward: forward_axis,
        })
    }
}
