//! # crowdgaze for Godot 4.3+ (GDExtension)
//!
//! The same three nodes as the Godot 3.2 front end, over the same adapter
//! (`crowdgaze-godot-adapter`, which calls crowdgaze's Rust API), on Godot 4's classes:
//!
//! - `CrowdGaze` ([`crowd_gaze`], a `Node3D`): owns the crowd, reads every character and
//!   target and steps once per frame, makes the active camera the viewer, emits
//!   `interest_changed(character, target)`.
//! - `CrowdGazeCharacter` ([`character`], a `SkeletonModifier3D`): a child of a
//!   `Skeleton3D` that makes it a character, and writes its gaze after the animation, in
//!   the skeleton's modifier pass (the pose is restored by Godot afterwards: the gaze never
//!   feeds back).
//! - `GazeTarget` ([`target`], a `Node3D`): a scene object the characters may look at.
//!
//! This crate only checks, converts and forwards; every entry point runs inside
//! [`convert::boundary`], so no panic reaches the engine. It is built by
//! `scripts/godot-check` but not run here (no Godot 4 on the test machines): the Godot 3
//! front end runs the same adapter through its checks.

// No `missing_docs` lint: godot-rust's #[export] generates undocumented accessors (the
// fields carry the docs).

pub mod character;
pub mod convert;
pub mod crowd_gaze;
pub mod skeleton;
pub mod target;

use godot::prelude::*;

/// The extension's entry point.
struct CrowdGazeExtension;

// SAFETY: the one `ExtensionLibrary` of this library; godot-rust registers its classes.
#[gdextension]
unsafe impl ExtensionLibrary for CrowdGazeExtension {}
