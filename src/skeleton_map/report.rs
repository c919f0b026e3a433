//! The mapping report: what the chain is, where it hangs, which way the skeleton faces and
//! why, the role each chain bone got (by name or by override), and the notes — text for a
//! log, an inspector or an error dialog.

use std::fmt::Write;

use super::{BoneRole, FacingFrom, MappedChain};

impl MappedChain {
    /// The name of bone `bone`.
    pub fn bone_name(&self, bone: usize) -> &str {
        &self.names[bone]
    }

    /// The mapping report (see the [module docs](self)), one line each:
    ///
    /// ```text
    /// gaze chain of 10 joints: 5 spine, 2 neck, head, 2 eyes; hangs from 'pelvis'
    /// up +Z, forward +Y (from left and right bone pairs)
    /// spine     'spine_01' (by name)
    /// ...
    /// ```
    pub fn report(&self) -> String {
        let chain = &self.chain;
        let mut text = String::new();
        let eyes = if chain.has_eyes() { ", 2 eyes" } else { "" };
        let _ = writeln!(
            text,
            "gaze chain of {} joints: {} spine, {} neck, head{eyes}; hangs from '{}'",
            chain.joint_count(),
            chain.spine_count(),
            chain.cervical_count(),
            self.names[self.root]
        );
        let facing = match self.facing_from {
            FacingFrom::Given => "given",
            FacingFrom::SidePairs => "from left and right bone pairs",
            FacingFrom::Eyes => "from the eyes in front of the head",
            FacingFrom::Toes => "from the toes in front of the feet",
        };
        let _ = writeln!(
            text,
            "up {}, forward {} ({facing})",
            axis_name(self.up),
            axis_name(self.forward)
        );
        for &bone in &self.bones {
            let how = if self.overridden[bone] {
                "override"
            } else {
                "by name"
            };
            let _ = writeln!(
                text,
                "{:<10}'{}' ({how})",
                self.roles[bone].name(),
                self.names[bone]
            );
        }
        let others = self
            .roles
            .iter()
            .enumerate()
            .filter(|(bone, role)| **role != BoneRole::None && !self.bones.contains(bone))
            .count();
        if others > 0 {
            let _ = writeln!(
                text,
                "{others} other bones have a role but are not in the chain (see roles)"
            );
        }
        for note in &self.notes {
            let _ = writeln!(text, "note: {note}");
        }
        text
    }
}

/// `+X`, `-Z`, ...
fn axis_name(axis: crate::world::Axis) -> &'static str {
    use crate::world::Axis::*;
    match axis {
        PositiveX => "+X",
        NegativeX => "-X",
        PositiveY => "+Y",
        NegativeY => "-Y",
        PositiveZ => "+Z",
        NegativeZ => "-Z",
    }
}
