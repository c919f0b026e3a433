//! Godot 4's `Skeleton3D` as the adapter's [`SkeletonAccess`]: a bone's pose is its local
//! transform (`PoseConvention::PoseIsLocal`).

use crowdgaze_godot_adapter::{SkeletonAccess, Xform};
use godot::classes::Skeleton3D;
use godot::prelude::*;

use crate::convert::{transform, xform};

/// A live skeleton, for the length of one call.
pub struct GodotSkeleton(pub Gd<Skeleton3D>);

impl SkeletonAccess for GodotSkeleton {
    fn bone_count(&self) -> usize {
        self.0.get_bone_count().max(0) as usize
    }

    fn bone_name(&self, bone: usize) -> String {
        self.0.get_bone_name(bone as i32).to_string()
    }

    fn bone_parent(&self, bone: usize) -> Option<usize> {
        let parent = self.0.get_bone_parent(bone as i32);
        (parent >= 0).then_some(parent as usize)
    }

    fn bone_rest(&self, bone: usize) -> Xform {
        xform(&self.0.get_bone_rest(bone as i32))
    }

    fn bone_pose(&self, bone: usize) -> Xform {
        xform(&self.0.get_bone_pose(bone as i32))
    }

    fn set_bone_pose(&mut self, bone: usize, pose: Xform) {
        self.0.set_bone_pose(bone as i32, transform(&pose));
    }

    fn global_transform(&self) -> Xform {
        xform(&self.0.get_global_transform())
    }
}
