//! Each frame's conversions between an engine's bone local rotations (in the skeleton's
//! order) and a mapped chain's base pose and joints: the rotations of the chain root's
//! ancestors and of the bones between chain joints are folded into the chain joints, and
//! out again when the joints are written back. Nothing is allocated.

use glam::Quat;

use super::MappedChain;
use crate::error::{ensure_all_finite, Error, Result};

impl MappedChain {
    /// Number of bones of the mapped skeleton (the length of the local rotation arrays).
    pub fn bone_count(&self) -> usize {
        self.names.len()
    }

    /// Number of chain joints (the length of base poses and joint arrays).
    pub fn joint_count(&self) -> usize {
        self.bones.len()
    }

    /// The bones whose local rotations make chain joint `joint`'s base rotation, top down,
    /// ending with its own: for the first joint every ancestor from the skeleton's top, for
    /// the others the bones after the previous joint (for the eyes, after the head).
    pub fn joint_path(&self, joint: usize) -> &[u32] {
        let start = match joint {
            0 => 0,
            _ => self.path_ends[joint - 1] as usize,
        };
        &self.paths[start..self.path_ends[joint] as usize]
    }

    /// Every bone whose local rotation the per-frame conversions read (the chain's bones,
    /// the bones between them and the chain root's ancestors), some more than once: the
    /// others are neither read nor written.
    pub fn bones_read(&self) -> &[u32] {
        &self.paths
    }

    /// The product of the local rotations of `path`'s bones.
    fn product<L: BoneRotations + ?Sized>(locals: &L, path: &[u32]) -> Quat {
        path.iter().fold(Quat::IDENTITY, |rotation, &bone| {
            rotation * locals.rotation(bone as usize)
        })
    }

    /// Checks a local rotation array against the skeleton.
    fn check_locals<L: BoneRotations + ?Sized>(&self, locals: &L, what: &str) -> Result<()> {
        if locals.bone_count() != self.bone_count() {
            return Err(Error::InvalidArgument(format!(
                "{what} has {} rotations, the skeleton {} bones",
                locals.bone_count(),
                self.bone_count()
            )));
        }
        Ok(())
    }

    /// The base pose (each chain joint's local rotation before gaze, for
    /// [`Crowd::set_base_pose`](crate::Crowd::set_base_pose)) from the engine's bone local
    /// rotations `locals` (one per bone, the skeleton's order, relative to each bone's
    /// parent), into `out` (one per chain joint). The first joint's is taken in the
    /// character's frame (every ancestor's rotation folded in, and the turn into the crowd's
    /// axes); a joint below bones that are not chain joints (an eye under facial bones)
    /// takes their rotations too.
    ///
    /// Errors (nothing written): [`Error::InvalidArgument`] for arrays of the wrong length,
    /// [`Error::NonFinite`] for a NaN or infinite rotation of a bone the chain reads.
    pub fn base_pose(&self, locals: &[Quat], out: &mut [Quat]) -> Result<()> {
        self.base_pose_of(locals, out)
    }

    /// [`MappedChain::base_pose`] over bone rotations of any layout (the C ABI's `cg_quat`
    /// arrays are read in place).
    pub(crate) fn base_pose_of<L: BoneRotations + ?Sized>(
        &self,
        locals: &L,
        out: &mut [Quat],
    ) -> Result<()> {
        self.check_locals(locals, "the local rotations")?;
        if out.len() != self.joint_count() {
            return Err(Error::InvalidArgument(format!(
                "the base pose has room for {} rotations, the chain {} joints",
                out.len(),
                self.joint_count()
            )));
        }
        for &bone in &self.paths {
            ensure_all_finite(
                &locals.rotation(bone as usize).to_array(),
                "bone local rotation",
            )?;
        }
        for (joint, slot) in out.iter_mut().enumerate() {
            let rotation = Self::product(locals, self.joint_path(joint));
            *slot = if joint == 0 {
                (self.turn * rotation).normalize()
            } else {
                rotation.normalize()
            };
        }
        Ok(())
    }

    /// Writes the crowd's joints (`joints`, one final local rotation per chain joint, as
    /// [`Crowd::read_joints`](crate::Crowd::read_joints) gives them) into the engine's bone
    /// local rotations `locals` (one per bone): each chain joint's bone gets the rotation
    /// that, with the other bones of its path as they are in `locals`, makes the joint's.
    /// Other bones are left alone.
    ///
    /// Errors (nothing written): [`Error::InvalidArgument`] for arrays of the wrong length,
    /// [`Error::NonFinite`] for a NaN or infinite rotation.
    pub fn write_joints(&self, joints: &[Quat], locals: &mut [Quat]) -> Result<()> {
        self.write_joints_into(joints, locals)
    }

    /// [`MappedChain::write_joints`] into bone rotations of any layout (the C ABI's
    /// `cg_quat` arrays are written in place).
    pub(crate) fn write_joints_into<L: BoneRotationsMut + ?Sized>(
        &self,
        joints: &[Quat],
        locals: &mut L,
    ) -> Result<()> {
        self.check_locals(locals, "the local rotations")?;
        if joints.len() != self.joint_count() {
            return Err(Error::InvalidArgument(format!(
                "{} joint rotations given, the chain has {} joints",
                joints.len(),
                self.joint_count()
            )));
        }
        for joint in joints {
            ensure_all_finite(&joint.to_array(), "joint rotation")?;
        }
        for &bone in &self.paths {
            ensure_all_finite(
                &locals.rotation(bone as usize).to_array(),
                "bone local rotation",
            )?;
        }
        for (joint, rotation) in joints.iter().enumerate() {
            let path = self.joint_path(joint);
            let (&bone, above) = path
                .split_last()
                .expect("a path ends with its joint's bone");
            let mut parent = Self::product(locals, above).normalize();
            if joint == 0 {
                parent = self.turn * parent;
            }
            locals.set_rotation(bone as usize, (parent.conjugate() * *rotation).normalize());
        }
        Ok(())
    }
}

/// Bone local rotations as the per-frame conversions read them: a slice of glam
/// quaternions, or a caller's array of another layout read in place (nothing is copied).
pub(crate) trait BoneRotations {
    /// Number of bones.
    fn bone_count(&self) -> usize;
    /// The local rotation of `bone` (`bone < bone_count()`).
    fn rotation(&self, bone: usize) -> Quat;
}

/// Bone local rotations the conversions also write.
pub(crate) trait BoneRotationsMut: BoneRotations {
    /// Sets the local rotation of `bone` (`bone < bone_count()`).
    fn set_rotation(&mut self, bone: usize, rotation: Quat);
}

impl BoneRotations for [Quat] {
    fn bone_count(&self) -> usize {
        self.len()
    }
    fn rotation(&self, bone: usize) -> Quat {
        self[bone]
    }
}

impl BoneRotationsMut for [Quat] {
    fn set_rotation(&mut self, bone: usize, rotation: Quat) {
        self[bone] = rotation;
    }
}
