//! The C ABI, and only that: check every argument coming from C, convert it to the Rust
//! core's types, forward the call, convert the result back. No algorithm lives here.
//!
//! Every `extern "C"` body runs inside `ffi_boundary!` (`boundary`), which catches panics
//! (they never cross into C), poisons the handle a failed call was changing (`poison`),
//! records the error message for `cg_last_error_message`, and maps the error to a
//! [`cg_status`]. Everything crosses the boundary one way: handles through `handle`
//! (`Box` in, checked reference on each call, `Box` back on destroy), the caller's
//! pointers through `pointers` (arrays as slices, each output as an `Out` checked before
//! the call does anything), versioned structs through `versioned` (never read or written
//! past the caller's `struct_size`). The error kinds only a C caller can cause live in
//! `error`, beside the core's.
//!
//! Unsafe code: most of the crate's lives here, reading and writing through the caller's
//! pointers. The rest is in four places, each for speed or sharing: `math::wide` (SIMD
//! intrinsics, run only after the processor's check), `attention::candidates` (unchecked
//! loads within padding it asserts), `crowd::states` and `crowd::step` (disjoint character
//! ranges stepped from several threads) and `crowd::pool` (the worker threads' shared run).
//! Every unsafe block says why it is sound in a `// SAFETY:` comment, and every unsafe
//! operation sits in one (`unsafe_op_in_unsafe_fn` and `clippy::undocumented_unsafe_blocks`
//! are errors, Cargo.toml).
#![allow(non_camel_case_types)]
// Every exported function that takes a pointer is `unsafe extern "C"`: Rust callers see
// that they must keep its contract. The contract is one for all of them (each pointer NULL,
// or aligned and valid for the reads and writes the function's doc describes; each handle
// live), written once in the header's preamble (cbindgen.toml) rather than in 54 `# Safety`
// sections.
#![allow(clippy::missing_safety_doc)]

pub mod attention;
pub mod blend;
pub mod frame;
// Right after `blend`: cbindgen writes the header in the order modules are declared.
pub mod view_blender;

pub(crate) mod boundary;
pub mod chain;
pub mod conversations;
pub mod crowd;
mod crowd_config;
pub(crate) mod error;
pub mod eyelids;
pub mod following;
pub mod gaze;
mod handle;
pub mod last_error;
mod pointers;
mod poison;
pub mod rig;
pub mod status;
#[cfg(feature = "test-hooks")]
pub mod testing;
pub mod types;
pub mod version;
mod versioned;

pub use status::cg_status;

pub(crate) use boundary::ffi_boundary;
pub(crate) use handle::{handle_mut, handle_ref, into_c, Handle};
pub(crate) use pointers::{borrow, non_null, slice, slice_mut, write_optional, Out};
pub(crate) use versioned::{
    borrow_current, layout_size, read_versioned, write_versioned, Versioned,
};
