//! Godot 3's `Skeleton` as the adapter's [`SkeletonAccess`]: bone poses relative to their
//! rests (`PoseConvention::RestTimesPose`).

use crowdgaze_godot_adapter::{SkeletonAccess, Xform};
use gdnative::api::Skeleton;
use gdnative::prelude::*;

use crate::convert::{transform, xform};

/// A live skeleton, for the length of one call.
pub struct GodotSkeleton<'a>(pub TRef<'a, Skeleton, Shared>);

impl SkeletonAccess for GodotSkeleton<'_> {
    fn bone_count(&self) -> usize {
        self.0.get_bone_count().max(0) as usize
    }

    fn bone_name(&self, bone: usize) -> String {
        self.0.get_bone_name(bone as i64).to_string()
    }

    fn bone_parent(&self, bone: usize) -> Option<usize> {
        let parent = self.0.get_bone_parent(bone as i64);
        (parent >= 0).then_some(parent as usize)
    }

    fn bone_rest(&self, bone: usize) -> Xform {
        xform(&self.0.get_bone_rest(bone as i64))
    }

    fn bone_pose(&self, bone: usize) -> Xform {
        xform(&self.0.get_bone_pose(bone as i64))
    }

    fn set_bone_pose(&mut self, bone: usize, pose: Xform) {
        self.0.set_bone_pose(bone as i64, transform(&pose));
    }

    fn global_transform(&self) -> Xform {
        xform(&self.0.global_transform())
    }
}
