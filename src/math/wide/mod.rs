//! Floats in SIMD lanes, generic over the width: the [`Wide`] trait, the lane-wise operations
//! every lane type has, so that one lane-wise algorithm is written once and runs at whichever
//! width the processor has ([`run_widest`] picks it).
//!
//! The lane types: `f32` (one lane) and glam's `Vec4` (SSE2 on x86-64, NEON on AArch64, plain
//! floats elsewhere) in `scalar.rs`; `F8` (AVX) in `avx.rs`; `F16` (AVX-512F) in `avx512.rs`.
//! `dispatch.rs` checks the processor and runs a [`LaneJob`] compiled for the widest type it
//! has.
//!
//! Every operation is the same IEEE operation on each lane (no fused multiply-add), so a lane
//! gives bit-identical results at every width. `F8` and `F16` (x86-64 only) wrap the
//! processor's AVX and AVX-512 instructions: they are used only after checking that the
//! processor has them, inside functions compiled for them ([`run_widest`]).

use std::ops::{Add, BitAnd, BitOr, BitOrAssign, Div, Mul, Neg, Not, Sub};

#[cfg(target_arch = "x86_64")]
mod avx;
#[cfg(target_arch = "x86_64")]
mod avx512;
mod dispatch;
mod scalar;

#[cfg(test)]
pub(crate) use dispatch::for_every_width;
pub use dispatch::set_max_simd_lanes;
pub(crate) use dispatch::{run_widest, widest_lanes, LaneJob};

// Private to this module: an F8 or F16 is only sound where the processor has AVX or
// AVX-512F, which `run_widest` checks before it hands them to a job. Tests elsewhere reach
// them through `for_every_width`, which checks the same.
#[cfg(all(target_arch = "x86_64", test))]
pub(crate) use {avx::F8, avx512::F16};

/// Floats in `LANES` lanes, with the lane-wise operations the blending code needs.
pub(crate) trait Wide:
    Copy
    + Add<Output = Self>
    + Add<f32, Output = Self>
    + Sub<Output = Self>
    + Sub<f32, Output = Self>
    + Mul<Output = Self>
    + Mul<f32, Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
{
    /// One boolean per lane.
    type Mask: Copy
        + std::fmt::Debug
        + BitAnd<Output = Self::Mask>
        + BitOr<Output = Self::Mask>
        + BitOrAssign
        + Not<Output = Self::Mask>;

    /// Number of lanes.
    const LANES: usize;

    /// The same value in every lane.
    fn splat(value: f32) -> Self;
    /// Lane `i` is `f(i)` (for tests: the hot paths gather with [`Wide::transpose_in`]).
    #[cfg_attr(not(test), allow(dead_code))]
    fn from_fn(f: impl FnMut(usize) -> f32) -> Self;
    /// Lane `i`.
    fn lane(self, i: usize) -> f32;
    /// Per lane: `a` where `mask`, else `b`.
    fn select(mask: Self::Mask, a: Self, b: Self) -> Self;
    /// Per lane `self < other`.
    fn cmplt(self, other: Self) -> Self::Mask;
    /// Per lane `self ≤ other`.
    fn cmple(self, other: Self) -> Self::Mask;
    /// Per lane `self > other`.
    fn cmpgt(self, other: Self) -> Self::Mask;
    /// Per lane `self ≥ other`.
    fn cmpge(self, other: Self) -> Self::Mask;
    /// Per lane square root.
    fn sqrt(self) -> Self;
    /// Per lane `1 / self`.
    fn recip(self) -> Self;
    /// Per lane maximum (operands are never NaN here).
    fn max(self, other: Self) -> Self;
    /// Mask lane `i` is `f(i)`.
    fn mask_from_fn(f: impl FnMut(usize) -> bool) -> Self::Mask;
    /// Whether mask lane `i` is set.
    fn test(mask: Self::Mask, i: usize) -> bool;
    /// Whether any mask lane is set.
    fn any(mask: Self::Mask) -> bool;
    /// Whether every mask lane is set.
    fn all(mask: Self::Mask) -> bool;
    /// Lanes `0..LANES` of `values`, which must hold at least `LANES` floats.
    fn load(values: &[f32]) -> Self;
    /// Per lane minimum (operands are never NaN here).
    fn min(self, other: Self) -> Self;
    /// Per lane absolute value (the sign bit cleared, as `f32::abs`).
    fn abs(self) -> Self;
    /// Per lane `self == other`.
    fn cmpeq(self, other: Self) -> Self::Mask;
    /// The same boolean in every mask lane.
    fn mask_splat(value: bool) -> Self::Mask;
    /// `2^self` for lanes holding whole numbers in [−126, 127] (built from exponent bits).
    fn exp2_whole(self) -> Self;
    /// The mask as bits: lane `i` is bit `i`.
    fn bitmask(mask: Self::Mask) -> u32;
    /// The mask of the first `count` lanes (every lane when `count ≥ LANES`).
    fn first_lanes(count: usize) -> Self::Mask;
    /// The largest lane (lanes are never NaN here).
    fn reduce_max(self) -> f32;
    /// Lane `i` holds `i`.
    fn lane_numbers() -> Self;
    /// Writes the lanes to the start of `out`, which must hold at least `LANES` floats.
    fn store(self, out: &mut [f32]);
    /// Lanes `at .. at + LANES` of `values`, without a bounds check (for hot loops whose
    /// indices are checked once, before the loop).
    ///
    /// # Safety
    /// `at + LANES ≤ values.len()`.
    #[inline(always)]
    unsafe fn load_at(values: &[f32], at: usize) -> Self {
        debug_assert!(at + Self::LANES <= values.len());
        // SAFETY: the caller guarantees the range is within `values`.
        Self::load(unsafe { values.get_unchecked(at..at + Self::LANES) })
    }
    /// [`Wide::compress_store`] to `out[at..]`, without a bounds check.
    ///
    /// # Safety
    /// `at + LANES ≤ out.len()`.
    #[inline(always)]
    unsafe fn compress_store_at(self, mask: Self::Mask, out: &mut [f32], at: usize) {
        debug_assert!(at + Self::LANES <= out.len());
        // SAFETY: the caller guarantees the range is within `out`.
        self.compress_store(mask, unsafe { out.get_unchecked_mut(at..at + Self::LANES) });
    }
    /// Writes the lanes set in `mask`, in lane order, to the start of `out`, which must hold
    /// at least `LANES` floats: the floats after the kept ones may be overwritten with
    /// anything. Bits are moved unchanged (integers carried as float bits survive).
    fn compress_store(self, mask: Self::Mask, out: &mut [f32]);
    /// Eight rows of `LANES` floats from eight-float columns: row `c` lane `i` is `f(i)[c]`.
    fn transpose_in(f: impl FnMut(usize) -> [f32; 8]) -> [Self; 8];
    /// The inverse of [`Wide::transpose_in`]: `f(i, column)` for each lane `i`.
    fn transpose_out(rows: [Self; 8], f: impl FnMut(usize, [f32; 8]));
}

/// The widest lane count of any [`Wide`] type.
pub(crate) const MAX_LANES: usize = 16;

/// Per lane `value` clamped to `[low, high]` with the comparisons of `f32::clamp` (so the
/// same bits, signed zeros included).
#[inline(always)]
pub(crate) fn clamp<W: Wide>(value: W, low: f32, high: f32) -> W {
    let (low, high) = (W::splat(low), W::splat(high));
    let value = W::select(value.cmplt(low), low, value);
    W::select(value.cmpgt(high), high, value)
}

#[cfg(test)]
mod tests;
