//! Small math the models share: the gaze ease curve and the seeded random numbers.
//! (Vectors and quaternions come from glam.)

pub mod ease;
pub mod random;
