//! What a step reads of each character and each distinct gaze chain, set by the engine
//! between steps: per-character tables (attention parameters, chain, base pose, explicit
//! target) and the chains characters share with their rest poses and social parts.

use glam::{Quat, Vec3};

use super::values::{ExplicitTarget, TargetPriority};
use crate::alloc::{try_reserve, try_with_capacity};
use crate::attention::CharacterParams;
use crate::error::Result;
use crate::ik::{GazeChain, JointRole, MAX_CHAIN_JOINTS};
use crate::math::packed::PackedQuat;
use crate::scene::order::Reorder;

/// Per character, in the scene's dense character order: what the engine and game logic
/// set, and a step only reads.
#[derive(Debug)]
pub(super) struct Characters {
    /// Attention parameters.
    pub params: Vec<CharacterParams>,
    /// Index into [`Chains`].
    pub chain_of: Vec<u32>,
    /// True once the engine set a base pose, held in `bases`.
    pub posed: Vec<bool>,
    /// The base pose the engine set (local rotations of its chain joints), packed in 8
    /// bytes each (within 6e−6 rad, see [`PackedQuat`]).
    pub bases: Vec<[PackedQuat; MAX_CHAIN_JOINTS]>,
    /// Explicit target from game logic.
    pub explicit: Vec<StoredTarget>,
    /// Place in a conversation: its group's slot · 8 + its index among the members, or
    /// `NO_CONVERSATION` (see `conversations.rs`).
    pub conversation: Vec<u32>,
}

/// An explicit target and its priority in 16 bytes (the pair in an `Option` takes 20):
/// the priority shares the tag's word.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum StoredTarget {
    /// No explicit target.
    None,
    /// A world point (metres).
    Point(TargetPriority, Vec3),
    /// An entity's look-at point.
    Entity(TargetPriority, u32),
}

impl StoredTarget {
    /// Stores `target`.
    pub fn new(target: Option<(ExplicitTarget, TargetPriority)>) -> StoredTarget {
        match target {
            None => StoredTarget::None,
            Some((ExplicitTarget::Point(point), priority)) => StoredTarget::Point(priority, point),
            Some((ExplicitTarget::Entity(id), priority)) => StoredTarget::Entity(priority, id),
        }
    }

    /// The target stored.
    pub fn get(self) -> Option<(ExplicitTarget, TargetPriority)> {
        match self {
            StoredTarget::None => None,
            StoredTarget::Point(priority, point) => Some((ExplicitTarget::Point(point), priority)),
            StoredTarget::Entity(priority, id) => Some((ExplicitTarget::Entity(id), priority)),
        }
    }
}

impl Characters {
    /// Empty tables for up to `capacity` characters, or
    /// [`Error::OutOfMemory`](crate::error::Error::OutOfMemory) for `what`.
    pub fn with_capacity(capacity: usize, what: &dyn std::fmt::Display) -> Result<Characters> {
        Ok(Characters {
            params: try_with_capacity(capacity, what)?,
            chain_of: try_with_capacity(capacity, what)?,
            posed: try_with_capacity(capacity, what)?,
            bases: try_with_capacity(capacity, what)?,
            explicit: try_with_capacity(capacity, what)?,
            conversation: try_with_capacity(capacity, what)?,
        })
    }

    /// Adds a character with `params` on chain `chain`, at rest and without explicit target.
    pub fn push(&mut self, params: CharacterParams, chain: u32) {
        self.chain_of.push(chain);
        self.bases.push([PackedQuat::IDENTITY; MAX_CHAIN_JOINTS]);
        self.posed.push(false);
        self.explicit.push(StoredTarget::None);
        self.conversation
            .push(super::conversation_table::NO_CONVERSATION);
        self.params.push(params);
    }

    /// Removes character `index`, moving the last one into its place.
    pub fn swap_remove(&mut self, index: usize) {
        self.params.swap_remove(index);
        self.chain_of.swap_remove(index);
        self.bases.swap_remove(index);
        self.posed.swap_remove(index);
        self.explicit.swap_remove(index);
        self.conversation.swap_remove(index);
    }

    /// Stores the characters in a new order: character `i` is the one at `order[i]` before.
    pub fn reorder(&mut self, order: &[u32], reorder: &mut Reorder) {
        reorder.apply(&mut self.params, order);
        reorder.apply(&mut self.chain_of, order);
        reorder.apply(&mut self.bases, order);
        reorder.apply(&mut self.posed, order);
        reorder.apply(&mut self.explicit, order);
        reorder.apply(&mut self.conversation, order);
    }

    /// The bytes one character takes in these tables.
    pub fn bytes_per_character() -> usize {
        use std::mem::size_of;
        size_of::<CharacterParams>()
            + size_of::<u32>()
            + size_of::<[PackedQuat; MAX_CHAIN_JOINTS]>()
            + size_of::<bool>()
            + size_of::<StoredTarget>()
            + size_of::<u32>() // place in a conversation
    }

    /// A character's chain, in `chains`.
    pub fn chain<'a>(&self, chains: &'a Chains, character: usize) -> &'a GazeChain {
        &chains.all[self.chain_of[character] as usize]
    }

    /// The base rotation of one chain joint of a character (see
    /// [`base_pose`](Self::base_pose)), without unpacking the others.
    pub fn base_rotation(&self, chains: &Chains, character: usize, joint: usize) -> Quat {
        if self.posed[character] {
            self.bases[character][joint].unpack()
        } else {
            chains.rests[self.chain_of[character] as usize][joint]
        }
    }

    /// A character's base pose (local rotations of its chain joints, the first
    /// `joint_count` used): its chain's rest pose, or the pose the engine set, unpacked.
    pub fn base_pose(&self, chains: &Chains, character: usize) -> [Quat; MAX_CHAIN_JOINTS] {
        if self.posed[character] {
            self.bases[character].map(PackedQuat::unpack)
        } else {
            chains.rests[self.chain_of[character] as usize]
        }
    }
}

/// The distinct gaze chains of a crowd (characters share equal ones), each with what a step
/// needs of it at rest. Grows by one when a character brings a new chain.
#[derive(Debug, Default)]
pub(super) struct Chains {
    /// The chains.
    pub all: Vec<GazeChain>,
    /// Per chain: the five social target points (head, eyes, chest, torso) in the
    /// character's frame at rest.
    pub parts: Vec<[Vec3; 5]>,
    /// Per chain: the rest pose of its joints (local rotations), the base of every
    /// character whose engine has not set one.
    pub rests: Vec<[Quat; MAX_CHAIN_JOINTS]>,
}

impl Chains {
    /// The index of a chain equal to `chain`, if there is one.
    pub fn find(&self, chain: &GazeChain) -> Option<usize> {
        self.all.iter().position(|known| known == chain)
    }

    /// Makes room for one more chain, or fails with
    /// [`Error::OutOfMemory`](crate::error::Error::OutOfMemory) changing nothing.
    pub fn reserve_one(&mut self) -> Result<()> {
        let what = &crate::alloc::Field("distinct gaze chains", self.all.len() as u64 + 1);
        try_reserve(&mut self.all, 1, what)?;
        try_reserve(&mut self.parts, 1, what)?;
        try_reserve(&mut self.rests, 1, what)?;
        Ok(())
    }

    /// Adds `chain` (room reserved), with its social parts for `up`; returns its index.
    pub fn push(&mut self, chain: GazeChain, up: Vec3) -> usize {
        self.all.push(chain);
        self.parts.push(social_parts(&chain, up));
        let mut rest = [Quat::IDENTITY; MAX_CHAIN_JOINTS];
        for (slot, joint) in rest.iter_mut().zip(chain.joints()) {
            *slot = joint.rest;
        }
        self.rests.push(rest);
        self.all.len() - 1
    }
}

/// The five social target points of a chain (head, left eye, right eye, chest, torso) in the
/// character's frame at rest (metres), in the order of [`TargetPart::SOCIAL`].
fn social_parts(chain: &GazeChain, up: Vec3) -> [Vec3; 5] {
    let joints = chain.joints();
    let mut positions = [Vec3::ZERO; crate::ik::MAX_CHAIN_JOINTS];
    let mut position = chain.root_offset();
    let mut rotation = Quat::IDENTITY;
    let mut head_rotation = Quat::IDENTITY;
    for (index, joint) in joints.iter().enumerate().take(chain.body_count()) {
        position += rotation * joint.offset;
        rotation *= joint.rest;
        positions[index] = position;
        if joint.role == JointRole::Head {
            head_rotation = rotation;
        }
    }
    let head_joint = positions[chain.head_index()];
    let side = up
        .cross(head_rotation * chain.eye_forward())
        .normalize_or_zero();
    let (left, right) = match chain.eye_indices() {
        Some([left, right]) => (
            head_joint + head_rotation * joints[left].offset,
            head_joint + head_rotation * joints[right].offset,
        ),
        None => (head_joint + side * 0.032, head_joint - side * 0.032),
    };
    let head = 0.5 * (left + right) + up * 0.06;
    let spines = chain.spine_count().max(1);
    let chest = positions[spines - 1];
    let torso = positions[(spines - 1) / 2];
    [head, left, right, chest, torso]
}
