//! From a BVH skeleton to a gaze chain: the library's bone map
//! ([`crowdgaze::skeleton_map`], shared with the engine adapters) read from the file's
//! hierarchy, with what is particular to BVH: identity rest rotations, three rotation
//! channels on every chain joint, and the chain root's height from the first frame.

use anyhow::{anyhow, bail, Result};
use crowdgaze::skeleton_map::{map_skeleton, BoneMap, RestBone, SkeletonOptions};
use crowdgaze::world::Axis;
use glam::{DQuat, DVec3, Quat};

use crate::bvh::Bvh;

pub use crowdgaze::skeleton_map::{parse_axis, BoneRole};

/// The joint map: the library's default one with `overrides` (`Name=role,Name=role`, roles
/// `root`, `spine`, `neck`, `head`, `left_eye`, `right_eye`, `none`) applied on top.
pub fn joint_map(overrides: Option<&str>) -> Result<BoneMap> {
    match overrides {
        Some(text) => BoneMap::with_overrides(text).map_err(|e| anyhow!("--map: {e}")),
        None => Ok(BoneMap::default()),
    }
}

/// A BVH skeleton's gaze chain and how it maps to the file.
#[derive(Debug, Clone)]
pub struct SkeletonChain {
    /// BVH joint index of each chain joint, bottom to top.
    pub joints: Vec<usize>,
    /// For each chain joint, the BVH joints between it and the chain joint before it, top
    /// down (a facial joint between the head and the eyes; empty for most).
    pub between: Vec<Vec<usize>>,
    /// BVH joint index of the chain root (the parent of the first chain joint).
    pub root: usize,
    /// The gaze chain (metres, world axes).
    pub chain: crowdgaze::ik::GazeChain,
    /// Up axis.
    pub up: Axis,
    /// The direction the skeleton faces in its rest pose.
    pub forward: Axis,
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
    /// from the rest positions of the `Left*` and `Right*` joints. The chain root stands at
    /// its rest height plus the first frame's root translation, along up.
    pub fn build(
        bvh: &Bvh,
        map: &BoneMap,
        up: Option<Axis>,
        forward: Option<Axis>,
        units_per_metre: f64,
    ) -> Result<SkeletonChain> {
        let bones: Vec<RestBone<'_>> = bvh
            .joints
            .iter()
            .map(|joint| RestBone {
                name: &joint.name,
                parent: joint.parent,
                translation: joint.offset.as_vec3(),
                rotation: Quat::IDENTITY,
            })
            .collect();
        let options = SkeletonOptions {
            up,
            forward,
            units_per_metre: units_per_metre as f32,
            root_offset: None,
            crowd_axes: None,
        };
        let mapped = map_skeleton(&bones, map, &options).map_err(|e| match e {
            crowdgaze::Error::InvalidArgument(message) => anyhow!("{message}"),
            other => anyhow!("{other}"),
        })?;
        // The joints between each chain joint and the one before it (eyes under facial
        // joints): their rotations are folded into the joint's base rotation each frame.
        let between = (0..mapped.joint_count())
            .map(|k| match k {
                0 => Vec::new(),
                _ => {
                    let path = mapped.joint_path(k);
                    path[..path.len() - 1].iter().map(|&b| b as usize).collect()
                }
            })
            .collect();
        for &index in &mapped.bones {
            if bvh.joints[index].euler_order().is_none() {
                bail!(
                    "joint {} needs three rotation channels to take gaze",
                    bvh.joints[index].name
                );
            }
        }
        // The chain root above the ground: its rest position plus the first frame's root
        // translation, along up.
        let rest = rest_positions(bvh);
        let root_translation = bvh
            .frames
            .first()
            .and_then(|f| bvh.joints[0].translation(f))
            .unwrap_or(DVec3::ZERO);
        let up_vector = mapped.up.vector().as_dvec3();
        let height = (rest[mapped.root] + root_translation).dot(up_vector) / units_per_metre;
        let chain = &mapped.chain;
        let chain = crowdgaze::ik::GazeChain::new(
            chain.joints(),
            chain.eye_forward(),
            chain.eye_up(),
            (up_vector * height).as_vec3(),
        )
        .map_err(|e| anyhow!("building the gaze chain: {e}"))?;
        Ok(SkeletonChain {
            joints: mapped.bones,
            between,
            root: mapped.root,
            chain,
            up: mapped.up,
            forward: mapped.forward,
        })
    }
}
