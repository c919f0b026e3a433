//! The 8-lane type, [`F8`]: one AVX register, written with the processor's own vector
//! instructions (AVX, not AVX2); and the 8 × 8 transposes the 16-lane type shares.
//!
//! Its operations are `#[inline(always)]` wrappers of AVX intrinsics: they may only run once
//! the processor is known to have AVX (`run_widest` checks before it uses them, and the tests
//! skip them otherwise), and they are compiled to single instructions where they are inlined
//! into a function compiled for it.

use std::arch::x86_64::*;
use std::ops::{Add, BitAnd, BitOr, BitOrAssign, Div, Mul, Neg, Not, Sub};

use super::scalar::KEPT_LANES;
use super::Wide;

/// Eight floats, one per lane: one AVX register. Only for processors with AVX.
#[derive(Debug, Clone, Copy)]
pub(crate) struct F8(__m256);

/// One boolean per lane of [`F8`]: all bits of the lane set or clear.
#[derive(Debug, Clone, Copy)]
pub(crate) struct M8(__m256);

/// Declares a binary operator of a wide type as one intrinsic (for [`F8`] here and the
/// 16-lane type in `avx512.rs`).
macro_rules! binary {
    ($type:ident, $trait:ident, $method:ident, $intrinsic:ident) => {
        impl $trait for $type {
            type Output = Self;
            #[inline(always)]
            fn $method(self, other: Self) -> Self {
                // SAFETY: wide values exist only on processors with the instruction set
                // (see the docs of the module that expands this macro).
                $type(unsafe { $intrinsic(self.0, other.0) })
            }
        }
        impl $trait<f32> for $type {
            type Output = Self;
            #[inline(always)]
            fn $method(self, other: f32) -> Self {
                self.$method(<$type as Wide>::splat(other))
            }
        }
    };
}
pub(super) use binary;

binary!(F8, Add, add, _mm256_add_ps);
binary!(F8, Sub, sub, _mm256_sub_ps);
binary!(F8, Mul, mul, _mm256_mul_ps);
binary!(F8, Div, div, _mm256_div_ps);

impl Neg for F8 {
    type Output = Self;
    #[inline(always)]
    fn neg(self) -> Self {
        // SAFETY: AVX is present (module docs).
        F8(unsafe { _mm256_xor_ps(self.0, _mm256_set1_ps(-0.0)) })
    }
}

impl BitAnd for M8 {
    type Output = Self;
    #[inline(always)]
    fn bitand(self, other: Self) -> Self {
        // SAFETY: AVX is present (module docs).
        M8(unsafe { _mm256_and_ps(self.0, other.0) })
    }
}

impl BitOr for M8 {
    type Output = Self;
    #[inline(always)]
    fn bitor(self, other: Self) -> Self {
        // SAFETY: AVX is present (module docs).
        M8(unsafe { _mm256_or_ps(self.0, other.0) })
    }
}

impl Not for M8 {
    type Output = Self;
    #[inline(always)]
    fn not(self) -> Self {
        // SAFETY: AVX is present (module docs).
        M8(unsafe { _mm256_xor_ps(self.0, _mm256_castsi256_ps(_mm256_set1_epi32(-1))) })
    }
}

/// `a |= b` as `a = a | b`, for the mask types (here and in `avx512.rs`).
macro_rules! or_assign {
    ($($mask:ident),*) => {$(
        impl BitOrAssign for $mask {
            #[inline(always)]
            fn bitor_assign(&mut self, other: Self) {
                *self = *self | other;
            }
        }
    )*};
}
pub(super) use or_assign;

or_assign!(M8);

/// Transposes the 8 × 8 block `rows` in place (row `r` lane `i` ↔ row `i` lane `r`).
///
/// # Safety
/// The processor has AVX.
#[inline(always)]
pub(super) unsafe fn transpose8(rows: [__m256; 8]) -> [__m256; 8] {
    let [r0, r1, r2, r3, r4, r5, r6, r7] = rows;
    // SAFETY: these intrinsics need AVX, which the caller guarantees.
    unsafe {
        let (t0, t1) = (_mm256_unpacklo_ps(r0, r1), _mm256_unpackhi_ps(r0, r1));
        let (t2, t3) = (_mm256_unpacklo_ps(r2, r3), _mm256_unpackhi_ps(r2, r3));
        let (t4, t5) = (_mm256_unpacklo_ps(r4, r5), _mm256_unpackhi_ps(r4, r5));
        let (t6, t7) = (_mm256_unpacklo_ps(r6, r7), _mm256_unpackhi_ps(r6, r7));
        let u0 = _mm256_shuffle_ps::<0x44>(t0, t2);
        let u1 = _mm256_shuffle_ps::<0xEE>(t0, t2);
        let u2 = _mm256_shuffle_ps::<0x44>(t1, t3);
        let u3 = _mm256_shuffle_ps::<0xEE>(t1, t3);
        let u4 = _mm256_shuffle_ps::<0x44>(t4, t6);
        let u5 = _mm256_shuffle_ps::<0xEE>(t4, t6);
        let u6 = _mm256_shuffle_ps::<0x44>(t5, t7);
        let u7 = _mm256_shuffle_ps::<0xEE>(t5, t7);
        [
            _mm256_permute2f128_ps::<0x20>(u0, u4),
            _mm256_permute2f128_ps::<0x20>(u1, u5),
            _mm256_permute2f128_ps::<0x20>(u2, u6),
            _mm256_permute2f128_ps::<0x20>(u3, u7),
            _mm256_permute2f128_ps::<0x31>(u0, u4),
            _mm256_permute2f128_ps::<0x31>(u1, u5),
            _mm256_permute2f128_ps::<0x31>(u2, u6),
            _mm256_permute2f128_ps::<0x31>(u3, u7),
        ]
    }
}

/// Loads eight columns of eight floats and transposes them into eight rows.
///
/// # Safety
/// The processor has AVX.
#[inline(always)]
pub(super) unsafe fn rows_of(columns: [[f32; 8]; 8]) -> [__m256; 8] {
    // SAFETY: the caller guarantees AVX; each load reads one whole column of 8 floats.
    unsafe {
        let mut loaded = [_mm256_setzero_ps(); 8];
        for (row, column) in loaded.iter_mut().zip(&columns) {
            *row = _mm256_loadu_ps(column.as_ptr());
        }
        transpose8(loaded)
    }
}

/// Eight columns of eight floats from eight rows.
///
/// # Safety
/// The processor has AVX.
#[inline(always)]
unsafe fn columns_of(rows: [__m256; 8]) -> [[f32; 8]; 8] {
    let mut columns = [[0.0; 8]; 8];
    // SAFETY: the caller guarantees AVX; each store writes one whole column of 8 floats.
    unsafe {
        for (column, row) in columns.iter_mut().zip(transpose8(rows)) {
            _mm256_storeu_ps(column.as_mut_ptr(), row);
        }
    }
    columns
}

impl Wide for F8 {
    type Mask = M8;
    const LANES: usize = 8;

    #[inline(always)]
    fn splat(value: f32) -> Self {
        // SAFETY: AVX is present (module docs).
        F8(unsafe { _mm256_set1_ps(value) })
    }
    #[inline(always)]
    fn from_fn(f: impl FnMut(usize) -> f32) -> Self {
        let values: [f32; 8] = std::array::from_fn(f);
        // SAFETY: AVX is present (module docs); `values` holds 8 floats.
        F8(unsafe { _mm256_loadu_ps(values.as_ptr()) })
    }
    #[inline(always)]
    fn lane(self, i: usize) -> f32 {
        // A permutation within the lane's half, not a store and a load (which would
        // wait for the store).
        // SAFETY: AVX is present (module docs).
        unsafe {
            let half = if i & 4 == 0 {
                _mm256_castps256_ps128(self.0)
            } else {
                _mm256_extractf128_ps::<1>(self.0)
            };
            _mm_cvtss_f32(_mm_permutevar_ps(half, _mm_set1_epi32((i & 3) as i32)))
        }
    }
    #[inline(always)]
    fn select(mask: M8, a: Self, b: Self) -> Self {
        // SAFETY: AVX is present (module docs).
        F8(unsafe { _mm256_blendv_ps(b.0, a.0, mask.0) })
    }
    #[inline(always)]
    fn cmplt(self, other: Self) -> M8 {
        // SAFETY: AVX is present (module docs).
        M8(unsafe { _mm256_cmp_ps::<_CMP_LT_OQ>(self.0, other.0) })
    }
    #[inline(always)]
    fn cmple(self, other: Self) -> M8 {
        // SAFETY: AVX is present (module docs).
        M8(unsafe { _mm256_cmp_ps::<_CMP_LE_OQ>(self.0, other.0) })
    }
    #[inline(always)]
    fn cmpgt(self, other: Self) -> M8 {
        // SAFETY: AVX is present (module docs).
        M8(unsafe { _mm256_cmp_ps::<_CMP_GT_OQ>(self.0, other.0) })
    }
    #[inline(always)]
    fn cmpge(self, other: Self) -> M8 {
        // SAFETY: AVX is present (module docs).
        M8(unsafe { _mm256_cmp_ps::<_CMP_GE_OQ>(self.0, other.0) })
    }
    #[inline(always)]
    fn sqrt(self) -> Self {
        // SAFETY: AVX is present (module docs).
        F8(unsafe { _mm256_sqrt_ps(self.0) })
    }
    #[inline(always)]
    fn recip(self) -> Self {
        F8::splat(1.0) / self
    }
    #[inline(always)]
    fn max(self, other: Self) -> Self {
        // SAFETY: AVX is present (module docs).
        F8(unsafe { _mm256_max_ps(self.0, other.0) })
    }
    #[inline(always)]
    fn mask_from_fn(mut f: impl FnMut(usize) -> bool) -> M8 {
        let bits: [i32; 8] = std::array::from_fn(|i| if f(i) { -1 } else { 0 });
        // SAFETY: AVX is present (module docs); `bits` holds 8 integers.
        M8(unsafe { _mm256_castsi256_ps(_mm256_loadu_si256(bits.as_ptr().cast())) })
    }
    #[inline(always)]
    fn test(mask: M8, i: usize) -> bool {
        // SAFETY: AVX is present (module docs).
        (unsafe { _mm256_movemask_ps(mask.0) } >> i) & 1 != 0
    }
    #[inline(always)]
    fn any(mask: M8) -> bool {
        // SAFETY: AVX is present (module docs).
        unsafe { _mm256_movemask_ps(mask.0) != 0 }
    }
    #[inline(always)]
    fn all(mask: M8) -> bool {
        // SAFETY: AVX is present (module docs).
        unsafe { _mm256_movemask_ps(mask.0) == 0xff }
    }
    #[inline(always)]
    fn load(values: &[f32]) -> Self {
        let values = &values[..8];
        // SAFETY: AVX is present (module docs); `values` holds 8 floats.
        F8(unsafe { _mm256_loadu_ps(values.as_ptr()) })
    }
    #[inline(always)]
    fn min(self, other: Self) -> Self {
        // SAFETY: AVX is present (module docs).
        F8(unsafe { _mm256_min_ps(self.0, other.0) })
    }
    #[inline(always)]
    fn abs(self) -> Self {
        // SAFETY: AVX is present (module docs).
        F8(unsafe { _mm256_andnot_ps(_mm256_set1_ps(-0.0), self.0) })
    }
    #[inline(always)]
    fn cmpeq(self, other: Self) -> M8 {
        // SAFETY: AVX is present (module docs).
        M8(unsafe { _mm256_cmp_ps::<_CMP_EQ_OQ>(self.0, other.0) })
    }
    #[inline(always)]
    fn mask_splat(value: bool) -> M8 {
        let bits = if value { -1 } else { 0 };
        // SAFETY: AVX is present (module docs).
        M8(unsafe { _mm256_castsi256_ps(_mm256_set1_epi32(bits)) })
    }
    #[inline(always)]
    fn exp2_whole(self) -> Self {
        // SAFETY: AVX is present (module docs); the integer steps run on 128-bit halves
        // (SSE2), as 256-bit integer arithmetic needs AVX2.
        unsafe {
            let whole = _mm256_cvtps_epi32(self.0);
            let bias = _mm_set1_epi32(127);
            let exponent = |half: __m128i| _mm_slli_epi32::<23>(_mm_add_epi32(half, bias));
            let low = exponent(_mm256_castsi256_si128(whole));
            let high = exponent(_mm256_extractf128_si256::<1>(whole));
            F8(_mm256_castsi256_ps(_mm256_set_m128i(high, low)))
        }
    }
    #[inline(always)]
    fn bitmask(mask: M8) -> u32 {
        // SAFETY: AVX is present (module docs).
        unsafe { _mm256_movemask_ps(mask.0) as u32 }
    }
    #[inline(always)]
    fn first_lanes(count: usize) -> M8 {
        let count = count.min(8) as f32;
        // SAFETY: AVX is present (module docs).
        M8(unsafe {
            let lanes = _mm256_setr_ps(0.0, 1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0);
            _mm256_cmp_ps::<_CMP_LT_OQ>(lanes, _mm256_set1_ps(count))
        })
    }
    #[inline(always)]
    fn reduce_max(self) -> f32 {
        // SAFETY: AVX is present (module docs).
        unsafe {
            let half = _mm_max_ps(
                _mm256_castps256_ps128(self.0),
                _mm256_extractf128_ps::<1>(self.0),
            );
            let pairs = _mm_max_ps(half, _mm_movehl_ps(half, half));
            _mm_cvtss_f32(_mm_max_ss(pairs, _mm_shuffle_ps::<0b01>(pairs, pairs)))
        }
    }
    #[inline(always)]
    fn lane_numbers() -> Self {
        // SAFETY: AVX is present (module docs).
        F8(unsafe { _mm256_setr_ps(0.0, 1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0) })
    }
    #[inline(always)]
    fn store(self, out: &mut [f32]) {
        let out = &mut out[..8];
        // SAFETY: AVX is present (module docs); `out` holds 8 floats.
        unsafe { _mm256_storeu_ps(out.as_mut_ptr(), self.0) }
    }
    #[inline(always)]
    fn compress_store(self, mask: M8, out: &mut [f32]) {
        let out = &mut out[..8];
        let bits = Self::bitmask(mask) as usize;
        let (low_lanes, low_count) = KEPT_LANES[bits & 15];
        let low_count = low_count.min(4);
        let (high_lanes, _) = KEPT_LANES[bits >> 4];
        // SAFETY: AVX is present (module docs); each half is compressed by a lane
        // permutation (`vpermilps`) and stored as 4 floats, the high half right after
        // the low half's kept ones: at most 4 + 4 floats, and `out` holds 8.
        unsafe {
            let permute = |half: __m128, lanes: [u32; 4]| {
                _mm_permutevar_ps(half, _mm_loadu_si128(lanes.as_ptr().cast()))
            };
            let low = permute(_mm256_castps256_ps128(self.0), low_lanes);
            let high = permute(_mm256_extractf128_ps::<1>(self.0), high_lanes);
            _mm_storeu_ps(out.as_mut_ptr(), low);
            _mm_storeu_ps(out[low_count..low_count + 4].as_mut_ptr(), high);
        }
    }
    #[inline(always)]
    fn transpose_in(f: impl FnMut(usize) -> [f32; 8]) -> [Self; 8] {
        // SAFETY: AVX is present (module docs).
        let [r0, r1, r2, r3, r4, r5, r6, r7] = unsafe { rows_of(std::array::from_fn(f)) };
        [
            F8(r0),
            F8(r1),
            F8(r2),
            F8(r3),
            F8(r4),
            F8(r5),
            F8(r6),
            F8(r7),
        ]
    }
    #[inline(always)]
    fn transpose_out(rows: [Self; 8], mut f: impl FnMut(usize, [f32; 8])) {
        let [r0, r1, r2, r3, r4, r5, r6, r7] = rows;
        let rows = [r0.0, r1.0, r2.0, r3.0, r4.0, r5.0, r6.0, r7.0];
        // SAFETY: AVX is present (module docs).
        let columns = unsafe { columns_of(rows) };
        for (i, column) in columns.into_iter().enumerate() {
            f(i, column);
        }
    }
}
