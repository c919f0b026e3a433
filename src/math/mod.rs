//! Small math the models share: fast approximations, the gaze ease curve, the seeded
//! random numbers, dual quaternions for rigid transforms, and unit quaternions packed in
//! 8 bytes. (Vectors and quaternions come from glam.)

pub mod dualquat;
pub mod ease;
pub mod fast;
pub mod packed;
pub mod random;
pub(crate) mod wide;
