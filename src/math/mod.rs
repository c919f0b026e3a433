//! Small math the models share: fast angles, the gaze ease curve and the seeded random
//! numbers.
//! (Vectors and quaternions come from glam.)

pub mod ease;
pub mod fast;
pub mod random;
