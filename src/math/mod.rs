//! Small math the models share: fast approximations, the gaze ease curve, the seeded
//! random numbers, dual quaternions for rigid transforms, unit quaternions packed in 8 bytes,
//! floats in SIMD lanes 4, 8 or 16 wide, and vectors, quaternions and dual
//! quaternions in those lanes. (Vectors and quaternions come from glam.)

pub mod dualquat;
pub mod ease;
pub mod fast;
pub(crate) mod lanes;
pub mod packed;
pub mod random;
pub(crate) mod wide;

pub use wide::set_max_simd_lanes;

/// `angle` (radians, finite) wrapped into [−π, π] (π only by rounding): the same direction
/// to within the rounding of the result. Angles already in [−π, π) come back unchanged, bit
/// for bit.
#[inline]
pub fn wrap_angle(angle: f32) -> f32 {
    use std::f32::consts::PI;
    if (-PI..PI).contains(&angle) {
        angle
    } else {
        // In f64: with f32's 2π, a large angle's remainder would drift from the direction
        // (by 0.42 rad at 10⁷ rad).
        use std::f64::consts::{PI, TAU};
        ((f64::from(angle) + PI).rem_euclid(TAU) - PI) as f32
    }
}

/// Hints the processor to load the cache lines of the value at `value` (its first
/// 256 bytes at most). A prefetch is only a hint: it never faults, whatever the address.
#[inline(always)]
pub(crate) fn prefetch<T>(value: *const T) {
    #[cfg(target_arch = "x86_64")]
    {
        use std::arch::x86_64::{_mm_prefetch, _MM_HINT_T0};
        let bytes = value.cast::<i8>();
        let mut offset = 0;
        while offset < std::mem::size_of::<T>().min(256) {
            // SAFETY: SSE is part of x86-64; a prefetch reads nothing and cannot fault.
            unsafe { _mm_prefetch::<_MM_HINT_T0>(bytes.wrapping_add(offset)) };
            offset += 64;
        }
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = value;
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f32::consts::PI;

    #[test]
    fn wrapped_angles_keep_their_direction() {
        for angle in [0.0f32, 1.0, -PI, PI - 1e-6, -3.0, 3.0] {
            assert_eq!(wrap_angle(angle).to_bits(), angle.to_bits(), "{angle}");
        }
        for angle in [PI, -PI - 1e-6, 7.0, -7.0, 100.0, -1234.5, 1e7] {
            let wrapped = wrap_angle(angle);
            assert!((-PI..=PI).contains(&wrapped), "{angle} -> {wrapped}");
            let (a, b) = (
                glam::Vec2::from_angle(angle),
                glam::Vec2::from_angle(wrapped),
            );
            assert!(a.distance(b) < 1e-6, "{angle} -> {wrapped}");
        }
    }
}
