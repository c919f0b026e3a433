//! Small math the models share: fast approximations, the gaze ease curve, the seeded
//! random numbers, and dual quaternions for rigid transforms. (Vectors and quaternions come
//! from glam.)

pub mod dualquat;
pub mod ease;
pub mod fast;
pub mod random;
