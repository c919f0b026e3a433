//! The 16-lane type, [`F16`]: one AVX-512 register, written with the processor's own vector
//! instructions (AVX-512F).
//!
//! Its operations are `#[inline(always)]` wrappers of AVX-512F intrinsics (and, for the
//! transposes, of AVX ones, which AVX-512F implies): they may only run once the processor is
//! known to have AVX-512F (`run_widest` checks before it uses them, and the tests skip them
//! otherwise), and they are compiled to single instructions where they are inlined into a
//! function compiled for it.

use std::arch::x86_64::*;
use std::ops::{Add, BitAnd, BitOr, BitOrAssign, Div, Mul, Neg, Not, Sub};

use super::avx::{binary, or_assign, rows_of, transpose8};
use super::Wide;

/// Sixteen floats, one per lane: one AVX-512 register. Only for processors with AVX-512F.
#[derive(Debug, Clone, Copy)]
pub(crate) struct F16(__m512);

/// One boolean per lane of [`F16`]: an AVX-512 mask register.
#[derive(Debug, Clone, Copy)]
pub(crate) struct M16(__mmask16);

binary!(F16, Add, add, _mm512_add_ps);
binary!(F16, Sub, sub, _mm512_sub_ps);
binary!(F16, Mul, mul, _mm512_mul_ps);
binary!(F16, Div, div, _mm512_div_ps);

impl Neg for F16 {
    type Output = Self;
    #[inline(always)]
    fn neg(self) -> Self {
        // SAFETY: AVX-512F is present (module docs).
        F16(unsafe {
            _mm512_castsi512_ps(_mm512_xor_si512(
                _mm512_castps_si512(self.0),
                _mm512_set1_epi32(i32::MIN),
            ))
        })
    }
}

impl BitAnd for M16 {
    type Output = Self;
    #[inline(always)]
    fn bitand(self, other: Self) -> Self {
        M16(self.0 & other.0)
    }
}

impl BitOr for M16 {
    type Output = Self;
    #[inline(always)]
    fn bitor(self, other: Self) -> Self {
        M16(self.0 | other.0)
    }
}

impl Not for M16 {
    type Output = Self;
    #[inline(always)]
    fn not(self) -> Self {
        M16(!self.0)
    }
}

or_assign!(M16);

impl Wide for F16 {
    type Mask = M16;
    const LANES: usize = 16;

    #[inline(always)]
    fn splat(value: f32) -> Self {
        // SAFETY: AVX-512F is present (module docs).
        F16(unsafe { _mm512_set1_ps(value) })
    }
    #[inline(always)]
    fn from_fn(f: impl FnMut(usize) -> f32) -> Self {
        let values: [f32; 16] = std::array::from_fn(f);
        // SAFETY: AVX-512F is present (module docs); `values` holds 16 floats.
        F16(unsafe { _mm512_loadu_ps(values.as_ptr()) })
    }
    #[inline(always)]
    fn lane(self, i: usize) -> f32 {
        // A permutation, not a store and a load (which would wait for the store).
        // SAFETY: AVX-512F is present (module docs).
        unsafe {
            let index = _mm512_set1_epi32((i & 15) as i32);
            _mm512_cvtss_f32(_mm512_permutexvar_ps(index, self.0))
        }
    }
    #[inline(always)]
    fn select(mask: M16, a: Self, b: Self) -> Self {
        // SAFETY: AVX-512F is present (module docs).
        F16(unsafe { _mm512_mask_blend_ps(mask.0, b.0, a.0) })
    }
    #[inline(always)]
    fn cmplt(self, other: Self) -> M16 {
        // SAFETY: AVX-512F is present (module docs).
        M16(unsafe { _mm512_cmp_ps_mask::<_CMP_LT_OQ>(self.0, other.0) })
    }
    #[inline(always)]
    fn cmple(self, other: Self) -> M16 {
        // SAFETY: AVX-512F is present (module docs).
        M16(unsafe { _mm512_cmp_ps_mask::<_CMP_LE_OQ>(self.0, other.0) })
    }
    #[inline(always)]
    fn cmpgt(self, other: Self) -> M16 {
        // SAFETY: AVX-512F is present (module docs).
        M16(unsafe { _mm512_cmp_ps_mask::<_CMP_GT_OQ>(self.0, other.0) })
    }
    #[inline(always)]
    fn cmpge(self, other: Self) -> M16 {
        // SAFETY: AVX-512F is present (module docs).
        M16(unsafe { _mm512_cmp_ps_mask::<_CMP_GE_OQ>(self.0, other.0) })
    }
    #[inline(always)]
    fn sqrt(self) -> Self {
        // SAFETY: AVX-512F is present (module docs).
        F16(unsafe { _mm512_sqrt_ps(self.0) })
    }
    #[inline(always)]
    fn recip(self) -> Self {
        F16::splat(1.0) / self
    }
    #[inline(always)]
    fn max(self, other: Self) -> Self {
        // SAFETY: AVX-512F is present (module docs).
        F16(unsafe { _mm512_max_ps(self.0, other.0) })
    }
    #[inline(always)]
    fn mask_from_fn(mut f: impl FnMut(usize) -> bool) -> M16 {
        M16((0..16).fold(0, |bits, i| bits | (u16::from(f(i)) << i)))
    }
    #[inline(always)]
    fn test(mask: M16, i: usize) -> bool {
        (mask.0 >> i) & 1 != 0
    }
    #[inline(always)]
    fn any(mask: M16) -> bool {
        mask.0 != 0
    }
    #[inline(always)]
    fn all(mask: M16) -> bool {
        mask.0 == u16::MAX
    }
    #[inline(always)]
    fn load(values: &[f32]) -> Self {
        let values = &values[..16];
        // SAFETY: AVX-512F is present (module docs); `values` holds 16 floats.
        F16(unsafe { _mm512_loadu_ps(values.as_ptr()) })
    }
    #[inline(always)]
    fn min(self, other: Self) -> Self {
        // SAFETY: AVX-512F is present (module docs).
        F16(unsafe { _mm512_min_ps(self.0, other.0) })
    }
    #[inline(always)]
    fn abs(self) -> Self {
        // SAFETY: AVX-512F is present (module docs).
        F16(unsafe { _mm512_abs_ps(self.0) })
    }
    #[inline(always)]
    fn cmpeq(self, other: Self) -> M16 {
        // SAFETY: AVX-512F is present (module docs).
        M16(unsafe { _mm512_cmp_ps_mask::<_CMP_EQ_OQ>(self.0, other.0) })
    }
    #[inline(always)]
    fn mask_splat(value: bool) -> M16 {
        M16(if value { u16::MAX } else { 0 })
    }
    #[inline(always)]
    fn exp2_whole(self) -> Self {
        // SAFETY: AVX-512F is present (module docs).
        F16(unsafe {
            let biased = _mm512_add_epi32(_mm512_cvtps_epi32(self.0), _mm512_set1_epi32(127));
            _mm512_castsi512_ps(_mm512_slli_epi32::<23>(biased))
        })
    }
    #[inline(always)]
    fn bitmask(mask: M16) -> u32 {
        u32::from(mask.0)
    }
    #[inline(always)]
    fn first_lanes(count: usize) -> M16 {
        M16(if count >= 16 {
            u16::MAX
        } else {
            (1u16 << count) - 1
        })
    }
    #[inline(always)]
    fn reduce_max(self) -> f32 {
        // SAFETY: AVX-512F is present (module docs).
        unsafe { _mm512_reduce_max_ps(self.0) }
    }
    #[inline(always)]
    fn lane_numbers() -> Self {
        // SAFETY: AVX-512F is present (module docs).
        F16(unsafe {
            _mm512_setr_ps(
                0.0, 1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0, 10.0, 11.0, 12.0, 13.0, 14.0,
                15.0,
            )
        })
    }
    #[inline(always)]
    fn store(self, out: &mut [f32]) {
        let out = &mut out[..16];
        // SAFETY: AVX-512F is present (module docs); `out` holds 16 floats.
        unsafe { _mm512_storeu_ps(out.as_mut_ptr(), self.0) }
    }
    #[inline(always)]
    fn compress_store(self, mask: M16, out: &mut [f32]) {
        let out = &mut out[..16];
        // SAFETY: AVX-512F is present (module docs); `out` holds 16 floats. Compressed
        // in a register, then stored whole (a compressing store to memory is slow on
        // some processors).
        unsafe {
            _mm512_storeu_ps(out.as_mut_ptr(), _mm512_maskz_compress_ps(mask.0, self.0));
        }
    }
    #[inline(always)]
    fn transpose_in(mut f: impl FnMut(usize) -> [f32; 8]) -> [Self; 8] {
        // Lanes 0–7 and 8–15 are two 8 × 8 transposes, joined into 16-lane rows.
        let low: [[f32; 8]; 8] = std::array::from_fn(&mut f);
        let high: [[f32; 8]; 8] = std::array::from_fn(|i| f(i + 8));
        // SAFETY: AVX-512F (which implies AVX) is present (module docs).
        unsafe {
            let (low, high) = (rows_of(low), rows_of(high));
            std::array::from_fn(|r| {
                let joined = _mm512_insertf64x4::<1>(
                    _mm512_castpd256_pd512(_mm256_castps_pd(low[r])),
                    _mm256_castps_pd(high[r]),
                );
                F16(_mm512_castpd_ps(joined))
            })
        }
    }
    #[inline(always)]
    fn transpose_out(rows: [Self; 8], mut f: impl FnMut(usize, [f32; 8])) {
        // SAFETY: AVX-512F (which implies AVX) is present (module docs).
        unsafe {
            let mut low = [_mm256_setzero_ps(); 8];
            let mut high = [_mm256_setzero_ps(); 8];
            for ((row, low), high) in rows.iter().zip(&mut low).zip(&mut high) {
                let row = _mm512_castps_pd(row.0);
                *low = _mm256_castpd_ps(_mm512_castpd512_pd256(row));
                *high = _mm256_castpd_ps(_mm512_extractf64x4_pd::<1>(row));
            }
            let (low, high) = (transpose8(low), transpose8(high));
            for (i, row) in low.into_iter().chain(high).enumerate() {
                let mut column = [0.0; 8];
                _mm256_storeu_ps(column.as_mut_ptr(), row);
                f(i, column);
            }
        }
    }
}
