//! # crowdgaze for Godot 3.2 (GDNative)
//!
//! Three NativeScript classes over the shared adapter (`crowdgaze-godot-adapter`), which
//! calls crowdgaze's Rust API:
//!
//! - `CrowdGaze` ([`crowd_gaze`]): owns the crowd, steps it once per frame, makes the
//!   active camera the viewer, emits `interest_changed(character, target)`.
//! - `CrowdGazeCharacter` ([`character`]): a child of a `Skeleton` that makes it a
//!   character (bones mapped to a gaze chain by name, overridable per bone).
//! - `GazeTarget` ([`target`]): a scene object the characters may look at.
//!
//! This crate only checks, converts and forwards; every exported method runs inside
//! [`convert::boundary`], so no panic reaches the engine.

#![warn(missing_docs)]

pub mod character;
pub mod convert;
pub mod crowd_gaze;
pub mod methods;
pub mod props;
pub mod skeleton;
pub mod target;

use gdnative::prelude::*;

fn init(handle: InitHandle) {
    // Tool classes: the editor runs them for their configuration warnings and the
    // character's mapping report; in the editor they join no crowd and write no bone.
    handle.add_tool_class::<crowd_gaze::CrowdGaze>();
    handle.add_tool_class::<character::CrowdGazeCharacter>();
    handle.add_tool_class::<target::GazeTarget>();
}

godot_init!(init);
