//! # crowdgaze
//!
//! Believable gaze for every character of a crowd, as a Rust crate and a C library.
//!
//! - **Attention** decides where and when each character looks (Grillon & Thalmann 2009;
//!   Kokkinara, Oyekoya & Steed 2011).
//! - **Gaze IK** turns its spine, neck, head and eyes there with human timing.
//! - **Blending** mixes key animations with dual quaternions, driven by where the viewer
//!   stands (Chaudhuri, Papagiannakis & Magnenat-Thalmann).
//!
//! The Rust API ([`Crowd`]) is the core; the C ABI in [`ffi`] only checks, converts and
//! forwards, and is described by the generated header `include/crowdgaze.h`.
//!
//! Conventions: lengths in metres, angles in radians and time in seconds inside; the
//! caller's units and axes are converted at the edge (see [`world::World`]).

// The header is generated from `ffi` alone: cbindgen skips the core modules.
/// cbindgen:ignore
pub mod alloc;
/// cbindgen:ignore
pub mod attention;
/// cbindgen:ignore
pub mod blend;
/// cbindgen:ignore
pub mod crowd;
/// cbindgen:ignore
pub mod error;
pub mod ffi;
/// cbindgen:ignore
pub mod ik;
/// cbindgen:ignore
pub mod math;
/// cbindgen:ignore
pub mod scenario;
/// cbindgen:ignore
pub mod scene;
/// cbindgen:ignore
pub mod skeleton_map;
/// cbindgen:ignore
pub mod world;

pub use blend::{ViewBlender, ViewBlenderConfig};
pub use crowd::{CharacterDesc, Crowd, CrowdConfig, GazeInfo, ObjectDesc};
pub use error::{Error, Result};
pub use math::dualquat::DualQuat;
pub use world::{Axis, World};

/// The Rust code blocks of the user documentation, run as doc tests (`tests/docs.rs` checks
/// that every page is listed here).
#[cfg(doctest)]
mod documentation {
    #[doc = include_str!("../README.md")]
    struct Readme;
    #[doc = include_str!("../docs/architecture.md")]
    struct Architecture;
    #[doc = include_str!("../docs/attention.md")]
    struct Attention;
    #[doc = include_str!("../docs/blending.md")]
    struct Blending;
    #[doc = include_str!("../docs/c-api.md")]
    struct CApi;
    #[doc = include_str!("../docs/c-api-versioning.md")]
    struct CApiVersioning;
    #[doc = include_str!("../docs/conversations.md")]
    struct Conversations;
    #[doc = include_str!("../docs/cli.md")]
    struct Cli;
    #[doc = include_str!("../docs/development.md")]
    struct Development;
    #[doc = include_str!("../docs/engines.md")]
    struct Engines;
    #[doc = include_str!("../docs/eyes.md")]
    struct Eyes;
    #[doc = include_str!("../docs/gaze-ik.md")]
    struct GazeIk;
    #[doc = include_str!("../docs/install.md")]
    struct Install;
    #[doc = include_str!("../docs/performance.md")]
    struct Performance;
    #[doc = include_str!("../docs/street.md")]
    struct Street;
    #[doc = include_str!("../docs/threads.md")]
    struct Threads;
    #[doc = include_str!("../docs/your-character.md")]
    struct YourCharacter;
}
