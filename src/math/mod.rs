//! Small math the models share: fast approximations, the gaze ease curve, the seeded
//! random numbers, dual quaternions for rigid transforms, unit quaternions packed in 8 bytes,
//! and floats in SIMD lanes 4, 8 or 16 wide. (Vectors and quaternions come from glam.)

pub mod dualquat;
pub mod ease;
pub mod fast;
pub mod packed;
pub mod random;
pub(crate) mod wide;
