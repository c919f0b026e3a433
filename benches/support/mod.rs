//! Bench-only helpers: the Jacobian IK baseline the paper compares its solver with.

pub mod jacobian;
