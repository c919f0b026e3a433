//! One character's skeleton: the bones of its gaze chain (found by name with the library's
//! [`skeleton_map`](crowdgaze::skeleton_map)), its animated pose read as the base pose, and
//! the gaze written back as bone poses.
//!
//! Frames: the *character frame* is the library's, `translation(position) ·
//! rotation(heading about +Y)`, read from the character node's global transform (its
//! origin, and its +Z axis on the ground). The chain root's rotation in that frame is folded
//! into the first chain joint, as the library's chains expect.

use crowdgaze::ik::MAX_CHAIN_JOINTS;
use crowdgaze::skeleton_map::{map_skeleton, BoneMap, RestBone, SkeletonOptions};
use crowdgaze::world::{Axis, World};
use crowdgaze::{Error, Result};
use glam::{Quat, Vec3};

use crate::lids::{find_upper_lids, lid_angle};
use crate::xform::{basis_of, rotation_of, Xform};

/// Most bones from the chain root up to the skeleton's top (the chain root's ancestors,
/// itself included) that the adapter composes each frame.
pub const MAX_ROOT_DEPTH: usize = 16;

/// How a bone's pose relates to its local transform.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PoseConvention {
    /// Godot 3: the local transform is `rest * pose` (the pose is relative to the rest).
    RestTimesPose,
    /// Godot 4: the pose is the local transform (the rest is only the default pose).
    PoseIsLocal,
}

/// What the adapter needs from an engine's skeleton. The front ends implement it over
/// Godot's `Skeleton` (3) and `Skeleton3D` (4); the tests over a skeleton of their own.
pub trait SkeletonAccess {
    /// Number of bones.
    fn bone_count(&self) -> usize;
    /// A bone's name.
    fn bone_name(&self, bone: usize) -> String;
    /// A bone's parent (always a lower index), `None` for a top bone.
    fn bone_parent(&self, bone: usize) -> Option<usize>;
    /// A bone's rest transform, relative to its parent.
    fn bone_rest(&self, bone: usize) -> Xform;
    /// A bone's current pose (see [`PoseConvention`]).
    fn bone_pose(&self, bone: usize) -> Xform;
    /// Sets a bone's pose (see [`PoseConvention`]).
    fn set_bone_pose(&mut self, bone: usize, pose: Xform);
    /// The skeleton node's global transform.
    fn global_transform(&self) -> Xform;
}

/// The library's character frame for a node's global transform: its origin, and its
/// heading from its +Z axis projected on the ground (0 when it points straight up or down).
/// Returns the position, the heading and the frame.
pub fn character_frame(node: &Xform) -> (Vec3, f32, Xform) {
    let world = World::y_up();
    let facing = node.basis.z_axis;
    let heading = libm_atan2(facing.dot(world.side), facing.dot(world.forward));
    let rotation = Quat::from_axis_angle(world.up, heading);
    (
        node.origin,
        heading,
        Xform::from_rotation_translation(rotation, node.origin),
    )
}

/// The error for a mirrored transform (negative determinant): the gaze chain is built for
/// rotations, and a mirror turns the eyes the wrong way.
pub fn mirrored(what: &str) -> Error {
    Error::InvalidArgument(format!(
        "{what} is mirrored (a negative scale), which would aim the eyes wrong: use positive \
         scales (turn the model with a rotation instead)"
    ))
}

/// True if a transform mirrors (its basis' determinant is negative).
fn is_mirrored(x: &Xform) -> bool {
    x.basis.determinant() < 0.0
}

/// `atan2` that gives 0 for (0, 0) and never a NaN from finite input.
fn libm_atan2(y: f32, x: f32) -> f32 {
    if y == 0.0 && x == 0.0 {
        0.0
    } else {
        y.atan2(x)
    }
}

/// The rotation of a bone pose's basis (rotation times per-axis scale, Godot's TRS) whose
/// column lengths are `scale`; [`rotation_of`] for any other basis.
fn pose_rotation(basis: &glam::Mat3, scale: Vec3) -> Quat {
    if scale == Vec3::ONE {
        Quat::from_mat3(basis).normalize()
    } else if scale.min_element() > 1e-6 {
        let unit = glam::Mat3::from_cols(
            basis.x_axis / scale.x,
            basis.y_axis / scale.y,
            basis.z_axis / scale.z,
        );
        if unit.determinant() > 0.0 {
            Quat::from_mat3(&unit).normalize()
        } else {
            rotation_of(basis)
        }
    } else {
        rotation_of(basis)
    }
}

/// A character's chain bones and what the adapter remembers of them between frames.
///
/// Laid out in order (`repr(C)`) so that most of what a frame touches is one run of memory,
/// from the start to the last chain joint's [`Joint`] (see [`prefetch`](Self::prefetch)).
#[derive(Debug, Clone)]
#[repr(C)]
pub struct BoundSkeleton {
    /// The chain root's rotation in the character frame this frame.
    root_rotation: Quat,
    /// The skeleton's bone count at registration (a skeleton whose count changes is
    /// refused until it is registered again).
    pub bone_count: usize,
    /// Number of chain joints.
    pub joint_count: usize,
    /// Length of `root_path`.
    pub root_depth: usize,
    /// Bit `k` set if chain bone `k`'s pose read this frame was still the one written.
    unchanged: u32,
    /// True once each joint's `written` holds the rotation written.
    has_written: bool,
    /// True if `lids` holds a lid bone (kept here, in the first cache line the write reads,
    /// so that a skeleton without lids costs no read of `lids`).
    lidded: bool,
    /// How bone poses relate to local transforms.
    convention: PoseConvention,
    /// The bone of each chain joint, bottom to top.
    pub bones: [usize; MAX_CHAIN_JOINTS],
    /// What is kept of each chain joint, side by side.
    joints: [Joint; MAX_CHAIN_JOINTS],
    /// The chain root and its ancestors, from the top bone down to the root.
    pub root_path: [usize; MAX_ROOT_DEPTH],
    /// Rest transform of each bone of `root_path`.
    root_rests: [Xform; MAX_ROOT_DEPTH],
    /// The name of each chain bone (for messages).
    names: Vec<String>,
    /// The parent of each chain bone at registration.
    parents: [Option<usize>; MAX_CHAIN_JOINTS],
    /// The bones between chain joints (eyes under a facial root), joint after joint.
    between: Vec<Between>,
    /// Joint `k`'s bones between it and the joint before it are
    /// `between[between_ends[k - 1]..between_ends[k]]` (none for the first joint).
    between_ends: [usize; MAX_CHAIN_JOINTS],
    /// The library's mapping report (see
    /// [`MappedChain::report`](crowdgaze::skeleton_map::MappedChain::report)).
    pub report: String,
    /// The mapping's notes (what it guessed, what it left out), one sentence each.
    pub notes: Vec<String>,
    /// The upper-lid bones found by name (left, right), if the skeleton has them.
    lids: [Option<Lid>; 2],
}

/// A bone between two chain joints (a facial root between the head and the eyes): read
/// each frame, never written.
#[derive(Debug, Clone, Copy)]
struct Between {
    /// The bone.
    bone: usize,
    /// Its rest transform.
    rest: Xform,
    /// Its parent at registration.
    parent: Option<usize>,
}

/// An upper-lid bone and what the adapter keeps of it between frames.
#[derive(Debug, Clone, Copy)]
struct Lid {
    /// The bone.
    bone: usize,
    /// The head's lateral axis (the character's left at rest) in the bone's frame: a
    /// rotation about it by a positive angle turns the lid down.
    axis: Vec3,
    /// The pose as the animation last set it.
    base: Xform,
    /// The pose last written, if any.
    written: Option<Xform>,
}

/// Asks the processor to fetch the cache lines of the addresses `start .. end` (a hint: no
/// memory is read, and no fault can come of it).
#[inline]
pub(crate) fn prefetch_bytes(start: usize, end: usize) {
    #[cfg(target_arch = "x86_64")]
    {
        use std::arch::x86_64::{_mm_prefetch, _MM_HINT_T0};
        const LINE: usize = 64;
        let mut line = start & !(LINE - 1);
        while line < end {
            // SAFETY: a prefetch is a hint: it never faults, whatever the address.
            unsafe { _mm_prefetch::<_MM_HINT_T0>(line as *const i8) };
            line += LINE;
        }
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = (start, end);
}

/// What the adapter keeps of one chain joint between frames.
#[derive(Debug, Clone, Copy)]
struct Joint {
    /// The bone's rest rotation.
    rest: Quat,
    /// The pre-gaze local rotation, last frame it was read.
    local: Quat,
    /// The rotation of the pose last written: that pose is
    /// `Xform { basis: basis_of(written, scale), origin }` (recomputed, not stored).
    written: Quat,
    /// The rotation of the bones between this joint and the joint before it, this frame
    /// (identity when there are none).
    above: Quat,
    /// The translation of the pose, as the animation last set it.
    origin: Vec3,
    /// The scale of the pose, as the animation last set it (1 within 10⁻⁵ is taken as
    /// exactly 1).
    scale: Vec3,
}

impl Joint {
    /// A joint at rest, nothing written.
    const REST: Joint = Joint {
        rest: Quat::IDENTITY,
        local: Quat::IDENTITY,
        written: Quat::IDENTITY,
        above: Quat::IDENTITY,
        origin: Vec3::ZERO,
        scale: Vec3::ONE,
    };

    /// The pose last written (meaningful once something was).
    fn written_pose(&self) -> Xform {
        Xform {
            basis: basis_of(self.written, self.scale),
            origin: self.origin,
        }
    }
}

/// What [`BoundSkeleton::read`] hands the crowd: the character's position and heading and
/// its base pose.
#[derive(Debug, Clone, Copy)]
pub struct PoseRead {
    /// Position (metres).
    pub position: Vec3,
    /// Heading (radians about +Y, 0 along +Z).
    pub heading: f32,
    /// The base pose: each chain joint's local rotation, the first one in the character
    /// frame.
    pub base: [Quat; MAX_CHAIN_JOINTS],
}

impl BoundSkeleton {
    /// Maps `skeleton`'s bones to a gaze chain with `map`. `node` is the character node's
    /// transform relative to the skeleton (its frame is the character's). Returns the
    /// binding and the chain to give the crowd.
    ///
    /// Errors: those of [`map_skeleton`] (no head: the message lists the bones), a chain
    /// root deeper than [`MAX_ROOT_DEPTH`], a non-finite or singular transform.
    pub fn bind(
        skeleton: &impl SkeletonAccess,
        node: &Xform,
        map: &BoneMap,
        convention: PoseConvention,
    ) -> Result<(BoundSkeleton, crowdgaze::ik::GazeChain)> {
        let count = skeleton.bone_count();
        let skeleton_global = skeleton.global_transform();
        if !skeleton_global.is_finite() || !node.is_finite() {
            return Err(Error::NonFinite(
                "the skeleton's or the character's transform is not finite".into(),
            ));
        }
        if is_mirrored(&skeleton_global) {
            return Err(mirrored("the skeleton's global transform"));
        }
        if is_mirrored(node) {
            return Err(mirrored("the character node's transform"));
        }
        let (_, _, frame) = character_frame(&skeleton_global.mul(node));
        // The skeleton in the character frame; its scale makes the length unit.
        let to_character = frame
            .inverse()
            .map(|inverse| inverse.mul(&skeleton_global))
            .ok_or_else(|| Error::InvalidArgument("the character frame is singular".into()))?;
        let scale = to_character.basis.determinant().abs().cbrt();
        if !(scale.is_finite() && scale > 1e-6) {
            return Err(Error::InvalidArgument(format!(
                "the skeleton's scale is {scale}: it must be positive"
            )));
        }
        let placement = to_character.rotation();
        let names: Vec<String> = (0..count).map(|b| skeleton.bone_name(b)).collect();
        let mut parents = Vec::with_capacity(count);
        let mut rests = Vec::with_capacity(count);
        for (bone, name) in names.iter().enumerate() {
            let parent = skeleton.bone_parent(bone).filter(|&p| p < bone);
            let rest = skeleton.bone_rest(bone);
            if !rest.is_finite() {
                return Err(Error::NonFinite(format!(
                    "bone {name}'s rest transform is not finite"
                )));
            }
            parents.push(parent);
            rests.push(rest);
        }
        let bones: Vec<RestBone<'_>> = (0..count)
            .map(|bone| {
                let rest = &rests[bone];
                // Top bones are placed in the character frame (in skeleton units).
                let (translation, rotation) = match parents[bone] {
                    Some(_) => (rest.origin, rest.rotation()),
                    None => (
                        placement * rest.origin + to_character.origin / scale,
                        placement * rest.rotation(),
                    ),
                };
                RestBone {
                    name: &names[bone],
                    parent: parents[bone],
                    translation,
                    rotation,
                }
            })
            .collect();
        let options = SkeletonOptions {
            up: Some(Axis::PositiveY),
            forward: Some(Axis::PositiveZ),
            units_per_metre: 1.0 / scale,
            root_offset: None,
            crowd_axes: None,
        };
        let mapped = map_skeleton(&bones, map, &options)?;
        let report = mapped.report();
        // The first joint's ancestors, from the top bone down (the chain root last).
        let first = mapped.joint_path(0);
        let path: Vec<usize> = first[..first.len().saturating_sub(1)]
            .iter()
            .map(|&bone| bone as usize)
            .collect();
        if path.len() > MAX_ROOT_DEPTH {
            return Err(Error::InvalidArgument(format!(
                "the chain root {} has more than {MAX_ROOT_DEPTH} ancestors",
                names[mapped.root]
            )));
        }
        // The bones between each later joint and the joint before it (eyes under a facial
        // root): their rotations are folded into the joint's, as the library's own
        // conversions do.
        let mut between = Vec::new();
        let mut between_ends = [0; MAX_CHAIN_JOINTS];
        for (k, end) in between_ends
            .iter_mut()
            .enumerate()
            .take(mapped.joint_count())
            .skip(1)
        {
            let joint_path = mapped.joint_path(k);
            for &bone in &joint_path[..joint_path.len().saturating_sub(1)] {
                let bone = bone as usize;
                between.push(Between {
                    bone,
                    rest: rests[bone],
                    parent: parents[bone],
                });
            }
            *end = between.len();
        }
        for &bone in mapped
            .bones
            .iter()
            .chain(&path)
            .chain(between.iter().map(|b| &b.bone))
        {
            if is_mirrored(&rests[bone]) {
                return Err(mirrored(&format!("bone {}'s rest", names[bone])));
            }
        }
        // Upper lids (not chain bones): each with the head's lateral axis in its rest
        // frame, from the rest globals in the skeleton's frame.
        let mut lids = [None, None];
        let found = find_upper_lids(names.iter().map(String::as_str));
        for (slot, bone) in lids.iter_mut().zip(found) {
            let Some(bone) = bone.filter(|b| !mapped.bones.contains(b)) else {
                continue;
            };
            let mut rotation = Quat::IDENTITY;
            let mut current = Some(bone);
            while let Some(b) = current {
                rotation = rests[b].rotation() * rotation;
                current = parents[b];
            }
            let lateral = placement.conjugate() * Vec3::X;
            let axis = (rotation.normalize().conjugate() * lateral).normalize_or_zero();
            if axis != Vec3::ZERO && axis.is_finite() {
                *slot = Some(Lid {
                    bone,
                    axis,
                    base: Xform::IDENTITY,
                    written: None,
                });
            }
        }
        let mut bound = BoundSkeleton {
            lidded: lids.iter().any(Option::is_some),
            lids,
            bone_count: count,
            bones: [0; MAX_CHAIN_JOINTS],
            joint_count: mapped.bones.len(),
            names: mapped.bones.iter().map(|&b| names[b].clone()).collect(),
            parents: [None; MAX_CHAIN_JOINTS],
            root_path: [0; MAX_ROOT_DEPTH],
            root_depth: path.len(),
            root_rests: [Xform::IDENTITY; MAX_ROOT_DEPTH],
            joints: [Joint::REST; MAX_CHAIN_JOINTS],
            has_written: false,
            unchanged: 0,
            root_rotation: Quat::IDENTITY,
            convention,
            between,
            between_ends,
            report,
            notes: mapped.notes.clone(),
        };
        for (k, &bone) in mapped.bones.iter().enumerate() {
            bound.bones[k] = bone;
            bound.parents[k] = parents[bone];
            let rest = rests[bone].rotation();
            // Until the first read, the local rotation is the rest one.
            bound.joints[k] = Joint {
                rest,
                local: rest,
                ..Joint::REST
            };
        }
        for (k, &bone) in path.iter().enumerate() {
            bound.root_path[k] = bone;
            bound.root_rests[k] = rests[bone];
        }
        Ok((bound, mapped.chain))
    }

    /// True if the skeleton's bones changed since the binding in a way that changes the
    /// chain: another bone count, or a chain bone or one of the chain root's ancestors
    /// given another parent (a head re-parented). Costs one call per chain bone and
    /// ancestor.
    pub fn hierarchy_changed(&self, skeleton: &impl SkeletonAccess) -> bool {
        if skeleton.bone_count() != self.bone_count {
            return true;
        }
        let chain = self.chain_bones().iter().zip(&self.parents);
        if chain
            .into_iter()
            .any(|(&bone, &parent)| skeleton.bone_parent(bone) != parent)
        {
            return true;
        }
        if self
            .between
            .iter()
            .any(|between| skeleton.bone_parent(between.bone) != between.parent)
        {
            return true;
        }
        let path = &self.root_path[..self.root_depth];
        path.iter().enumerate().any(|(k, &bone)| {
            let parent = if k == 0 { None } else { Some(path[k - 1]) };
            skeleton.bone_parent(bone) != parent
        })
    }

    /// The rotation of the bones between chain joint `k` and the joint before it (a
    /// facial root between the head and an eye), from their current poses; identity when
    /// there are none.
    fn above(&self, skeleton: &impl SkeletonAccess, k: usize) -> Result<Quat> {
        if k == 0 || k >= self.joint_count {
            return Ok(Quat::IDENTITY);
        }
        let bones = self
            .between
            .get(self.between_ends[k - 1]..self.between_ends[k])
            .unwrap_or_default();
        let mut rotation = Quat::IDENTITY;
        for between in bones {
            let pose = skeleton.bone_pose(between.bone);
            let local = self.local(&between.rest, &pose);
            if !local.is_finite() {
                return Err(Error::NonFinite(format!(
                    "the pose of bone {} (between chain bones) is not finite",
                    skeleton.bone_name(between.bone)
                )));
            }
            if is_mirrored(&local) {
                return Err(mirrored(&format!(
                    "bone {}'s pose",
                    skeleton.bone_name(between.bone)
                )));
            }
            rotation = (rotation * rotation_of(&local.basis)).normalize();
        }
        Ok(rotation)
    }

    /// Takes over what `old` (the binding this one replaces, mapped again) remembers of the
    /// bones both drive: each one's animated pose and the pose last written. Without it, a
    /// bone that nothing animates would hold the gaze written under the old binding, and the
    /// new one would read that as its animated pose.
    pub fn carry_over(&mut self, old: &BoundSkeleton) {
        for k in 0..self.joint_count {
            if let Some(j) = old.chain_bones().iter().position(|&b| b == self.bones[k]) {
                let rest = self.joints[k].rest;
                self.joints[k] = Joint {
                    rest,
                    ..old.joints[j]
                };
            }
        }
        self.has_written = old.has_written;
        for lid in self.lids.iter_mut().flatten() {
            if let Some(before) = old.lids.iter().flatten().find(|l| l.bone == lid.bone) {
                lid.base = before.base;
                lid.written = before.written;
            }
        }
    }

    /// True if the skeleton has upper-lid bones the adapter turns.
    pub fn has_lids(&self) -> bool {
        self.lidded
    }

    /// The upper-lid bones (left, right).
    pub fn lid_bones(&self) -> [Option<usize>; 2] {
        [self.lids[0].map(|l| l.bone), self.lids[1].map(|l| l.bone)]
    }

    /// Turns the upper-lid bones from their animated poses for the library's `eyelids`
    /// (lid pitch and closure), times `weight`. A pose that is still the one last written
    /// keeps the animated pose read before it (the turn never accumulates); a non-finite
    /// pose is left alone.
    pub fn write_lids(
        &mut self,
        skeleton: &mut impl SkeletonAccess,
        eyelids: &crowdgaze::crowd::EyelidState,
        weight: f32,
    ) {
        let sides = [
            (eyelids.left_lid_pitch, eyelids.left_closure),
            (eyelids.right_lid_pitch, eyelids.right_closure),
        ];
        for (lid, (pitch, closure)) in self.lids.iter_mut().zip(sides) {
            let Some(lid) = lid else {
                continue;
            };
            if lid.bone >= self.bone_count {
                continue;
            }
            let pose = skeleton.bone_pose(lid.bone);
            if !pose.is_finite() {
                continue;
            }
            if lid.written != Some(pose) {
                lid.base = pose;
            }
            let angle = lid_angle(pitch, closure, weight);
            let turn = glam::Mat3::from_quat(Quat::from_axis_angle(lid.axis, angle));
            let written = Xform {
                basis: lid.base.basis * turn,
                origin: lid.base.origin,
            };
            if pose != written {
                skeleton.set_bone_pose(lid.bone, written);
            }
            lid.written = Some(written);
        }
    }

    /// The chain bones, bottom to top.
    pub fn chain_bones(&self) -> &[usize] {
        &self.bones[..self.joint_count]
    }

    /// Asks the processor to bring what [`read`](Self::read) and [`write`](Self::write)
    /// touch into its caches, without waiting. Call it for the next character while
    /// working on one: the engine's own frame has pushed the adapter's data out of the
    /// caches by the time it runs, and the misses then overlap the work. Does nothing on
    /// processors other than x86-64.
    pub fn prefetch(&self) {
        let joints = &self.joints[..self.joint_count.min(MAX_CHAIN_JOINTS)];
        let end = joints.as_ptr_range().end as usize;
        prefetch_bytes(self as *const Self as usize, end);
        let depth = self.root_depth.min(MAX_ROOT_DEPTH);
        let path = self.root_path[..depth].as_ptr_range();
        prefetch_bytes(path.start as usize, path.end as usize);
        let rests = self.root_rests[..depth].as_ptr_range();
        prefetch_bytes(rests.start as usize, rests.end as usize);
    }

    /// The local transform of a bone from its rest and pose.
    fn local(&self, rest: &Xform, pose: &Xform) -> Xform {
        match self.convention {
            PoseConvention::RestTimesPose => rest.mul(pose),
            PoseConvention::PoseIsLocal => *pose,
        }
    }

    /// Reads the character's frame and its chain's animated pose. `node` is the character
    /// node's transform relative to the skeleton. A chain bone whose pose is still exactly what the adapter
    /// wrote last (nothing animated it since) keeps its previous local rotation, so the gaze
    /// never feeds back into the base pose.
    ///
    /// Errors: [`Error::NonFinite`] for a NaN or infinite transform (nothing is changed),
    /// [`Error::InvalidArgument`] if the skeleton's bone count changed.
    pub fn read(&mut self, skeleton: &impl SkeletonAccess, node: &Xform) -> Result<PoseRead> {
        if skeleton.bone_count() != self.bone_count {
            return Err(Error::InvalidArgument(format!(
                "the skeleton has {} bones, {} when the character was registered",
                skeleton.bone_count(),
                self.bone_count
            )));
        }
        if !node.is_finite() {
            return Err(Error::NonFinite(
                "the character node's transform is not finite".into(),
            ));
        }
        let skeleton_global = skeleton.global_transform();
        if !skeleton_global.is_finite() {
            return Err(Error::NonFinite(
                "the skeleton's global transform is not finite".into(),
            ));
        }
        if is_mirrored(&skeleton_global) {
            return Err(mirrored("the skeleton's global transform"));
        }
        if is_mirrored(node) {
            return Err(mirrored("the character node's transform"));
        }
        // The chain root's global transform, composed from the top bone down.
        let mut root = skeleton_global;
        for k in 0..self.root_depth {
            let pose = skeleton.bone_pose(self.root_path[k]);
            root = root.mul(&self.local(&self.root_rests[k], &pose));
        }
        if !root.is_finite() {
            return Err(Error::NonFinite(
                "a pose above the gaze chain is not finite".into(),
            ));
        }
        if is_mirrored(&root) {
            return Err(mirrored("a pose above the gaze chain"));
        }
        let mut poses = [Xform::IDENTITY; MAX_CHAIN_JOINTS];
        for (k, (slot, &bone)) in poses.iter_mut().zip(self.chain_bones()).enumerate() {
            *slot = skeleton.bone_pose(bone);
            if !slot.is_finite() {
                return Err(Error::NonFinite(format!(
                    "bone {}'s pose is not finite",
                    self.names[k]
                )));
            }
            if is_mirrored(slot) {
                return Err(mirrored(&format!("bone {}'s pose", self.names[k])));
            }
        }
        let mut above = [Quat::IDENTITY; MAX_CHAIN_JOINTS];
        if !self.between.is_empty() {
            for (k, slot) in above.iter_mut().enumerate().take(self.joint_count) {
                *slot = self.above(skeleton, k)?;
            }
        }
        let (position, heading, frame) = character_frame(&skeleton_global.mul(node));
        let mut read = PoseRead {
            position,
            heading,
            base: [Quat::IDENTITY; MAX_CHAIN_JOINTS],
        };
        self.root_rotation = (frame.rotation().conjugate() * rotation_of(&root.basis)).normalize();
        self.unchanged = 0;
        let joints = &mut self.joints[..self.joint_count];
        for (k, (pose, joint)) in poses.iter().zip(joints).enumerate() {
            let unchanged = self.has_written && *pose == joint.written_pose();
            if unchanged {
                self.unchanged |= 1 << k;
            } else {
                let scale = pose.scale();
                joint.scale = if scale.abs_diff_eq(Vec3::ONE, 1e-5) {
                    Vec3::ONE
                } else {
                    scale
                };
                joint.origin = pose.origin;
                let rotation = pose_rotation(&pose.basis, scale);
                joint.local = match self.convention {
                    PoseConvention::RestTimesPose => (joint.rest * rotation).normalize(),
                    PoseConvention::PoseIsLocal => rotation,
                };
            }
            joint.above = above[k];
            read.base[k] = if k == 0 {
                (self.root_rotation * joint.local).normalize()
            } else if self.between.is_empty() {
                joint.local
            } else {
                (joint.above * joint.local).normalize()
            };
        }
        Ok(read)
    }

    /// Writes the chain's final rotations (the library's `base * delta`, the first in the
    /// character frame) as bone poses, keeping each pose's translation and scale from
    /// the animation's last pose. Each local rotation is the animated one slerped towards
    /// the gaze's by `weight` (0: the animated pose, 1: the gaze). Call after
    /// [`read`](Self::read) in the same frame. A bone that still holds exactly the pose to
    /// write is not written again (nothing to update in the engine).
    pub fn write(&mut self, skeleton: &mut impl SkeletonAccess, rotations: &[Quat], weight: f32) {
        let joints = &mut self.joints[..self.joint_count];
        for (k, (rotation, joint)) in rotations.iter().zip(joints).enumerate() {
            let gaze = if k == 0 {
                self.root_rotation.conjugate() * *rotation
            } else {
                joint.above.conjugate() * *rotation
            };
            let local = if weight >= 1.0 {
                gaze
            } else {
                joint.local.slerp(gaze, weight.max(0.0))
            };
            let pose_rotation = match self.convention {
                PoseConvention::RestTimesPose => joint.rest.conjugate() * local,
                PoseConvention::PoseIsLocal => local,
            }
            .normalize();
            let pose = Xform {
                basis: basis_of(pose_rotation, joint.scale),
                origin: joint.origin,
            };
            if self.has_written
                && self.unchanged & (1 << k) != 0
                && pose.basis == basis_of(joint.written, joint.scale)
            {
                continue;
            }
            skeleton.set_bone_pose(self.bones[k], pose);
            joint.written = pose_rotation;
        }
        self.has_written = true;
    }
}
