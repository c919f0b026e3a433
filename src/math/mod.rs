//! Small math the models share: fast approximations, the gaze ease curve, the seeded
//! random numbers, dual quaternions for rigid transforms, unit quaternions packed in 8 bytes,
//! and floats in SIMD lanes 4, 8 or 16 wide. (Vectors and quaternions come from glam.)

pub mod dualquat;
pub mod ease;
pub mod fast;
pub mod packed;
pub mod random;
pub(crate) mod wide;

/// `angle` (radians, finite) wrapped into [−π, π): the same direction. Angles already in
/// that range come back unchanged, bit for bit.
#[inline]
pub fn wrap_angle(angle: f32) -> f32 {
    use std::f32::consts::{PI, TAU};
    if (-PI..PI).contains(&angle) {
        angle
    } else {
        // rem_euclid may round up to TAU itself (then −π + TAU = π: still the same
        // direction, and within [−π, π]).
        (angle + PI).rem_euclid(TAU) - PI
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
