//! # crowdgaze-godot-adapter
//!
//! The engine-neutral half of crowdgaze's Godot addon, shared by its two front ends (the
//! Godot 4 GDExtension and the Godot 3.2 GDNative library): it turns a Godot scene into a
//! crowd and the crowd's gaze into bone poses. It calls crowdgaze's Rust API directly;
//! the front ends only check, convert Godot's values to and from [`Xform`], and forward.
//!
//! - [`skeleton`]: one character's skeleton — its chain bones found by name (the library's
//!   [`skeleton_map`](crowdgaze::skeleton_map), overridable per bone), its animated pose
//!   read as the base pose, its gaze written back as bone poses, in Godot 3's convention
//!   (`rest * pose`) or Godot 4's (the pose is the local transform).
//! - [`crowd`]: one `CrowdGaze` node's crowd — node keys ↔ entity ids, characters, targets
//!   and the viewer pushed each frame, the step, the gaze written, interest changes.
//! - [`character`]: a character node's settings as given, checked; its chain's limits.
//! - [`fade`]: influence (how much of the gaze the bones take) and its fades.
//! - [`lids`]: upper-lid bones and blink blend shapes found by name, the lid's angle.
//! - [`membership`]: which crowd a node joins, one character per skeleton.
//! - [`settings`]: the `CrowdGaze` node's settings as given, checked.
//! - [`editor`]: what the editor shows: configuration warnings, the mapping report.
//! - [`report`]: the messages' shape, and each error printed once per node and cause.
//! - [`xform`]: Godot's transform layout as glam values.
//!
//! Godot's conventions are the library's defaults: Y up, metres, characters facing +Z.
//! Nothing here panics on any input: bad transforms and skeletons come back as
//! [`crowdgaze::Error`]s for the front end to report.

#![warn(missing_docs)]

/// The library, re-exported so that the front ends use the adapter's version of it.
pub use crowdgaze;

pub mod character;
pub mod crowd;
pub mod editor;
pub mod fade;
pub mod lids;
pub mod membership;
pub mod report;
pub mod settings;
pub mod skeleton;
pub mod xform;

pub use character::{CharacterSettings, CharacterValues};
pub use crowd::{EntityNode, FollowStart, InterestChange, NodeKey, SceneCrowd};
pub use editor::{check_character, check_crowd, check_target, CharacterCheck, CrowdFound};
pub use fade::{Controls, Fade};
pub use membership::{choose_crowd, claim_skeleton, NamedNode, SkeletonClaim};
pub use report::{message, Reports};
pub use settings::CrowdSettings;
pub use skeleton::{PoseConvention, SkeletonAccess};
pub use xform::Xform;

#[cfg(test)]
mod tests;
