//! Floats in SIMD lanes, generic over the width: glam's `Vec4` (SSE2 on x86-64, NEON on
//! AArch64, plain floats elsewhere) and 8- and 16-lane types ([`F8`], [`F16`]) for code
//! compiled with AVX or AVX-512 enabled, so one lane-wise algorithm runs at whichever width
//! the processor has: [`run_widest`] checks the processor and runs a [`LaneJob`] compiled
//! for it.
//!
//! Every operation is the same IEEE operation on each lane (no fused multiply-add), so a lane
//! gives bit-identical results at every width. [`F8`] and [`F16`] (x86-64 only) wrap the
//! processor's AVX and AVX-512 instructions: they are used only after checking that the
//! processor has them, inside functions compiled for them ([`run_widest`]).

use std::ops::{Add, BitAnd, BitOr, BitOrAssign, Div, Mul, Neg, Not, Sub};

use glam::{BVec4A, Mat4, Vec4};

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

impl Wide for Vec4 {
    type Mask = BVec4A;
    const LANES: usize = 4;

    #[inline(always)]
    fn splat(value: f32) -> Self {
        Vec4::splat(value)
    }
    #[inline(always)]
    fn from_fn(mut f: impl FnMut(usize) -> f32) -> Self {
        Vec4::new(f(0), f(1), f(2), f(3))
    }
    #[inline(always)]
    fn lane(self, i: usize) -> f32 {
        self[i]
    }
    #[inline(always)]
    fn select(mask: BVec4A, a: Self, b: Self) -> Self {
        Vec4::select(mask, a, b)
    }
    #[inline(always)]
    fn cmplt(self, other: Self) -> BVec4A {
        Vec4::cmplt(self, other)
    }
    #[inline(always)]
    fn cmple(self, other: Self) -> BVec4A {
        Vec4::cmple(self, other)
    }
    #[inline(always)]
    fn cmpgt(self, other: Self) -> BVec4A {
        Vec4::cmpgt(self, other)
    }
    #[inline(always)]
    fn cmpge(self, other: Self) -> BVec4A {
        Vec4::cmpge(self, other)
    }
    #[inline(always)]
    fn sqrt(self) -> Self {
        Vec4::sqrt(self)
    }
    #[inline(always)]
    fn recip(self) -> Self {
        Vec4::recip(self)
    }
    #[inline(always)]
    fn max(self, other: Self) -> Self {
        Vec4::max(self, other)
    }
    #[inline(always)]
    fn mask_from_fn(mut f: impl FnMut(usize) -> bool) -> BVec4A {
        BVec4A::new(f(0), f(1), f(2), f(3))
    }
    #[inline(always)]
    fn test(mask: BVec4A, i: usize) -> bool {
        mask.test(i)
    }
    #[inline(always)]
    fn any(mask: BVec4A) -> bool {
        mask.any()
    }
    #[inline(always)]
    fn all(mask: BVec4A) -> bool {
        mask.all()
    }
    #[inline(always)]
    fn load(values: &[f32]) -> Self {
        Vec4::from_slice(values)
    }
    #[inline(always)]
    fn min(self, other: Self) -> Self {
        Vec4::min(self, other)
    }
    #[inline(always)]
    fn abs(self) -> Self {
        Vec4::abs(self)
    }
    #[inline(always)]
    fn cmpeq(self, other: Self) -> BVec4A {
        Vec4::cmpeq(self, other)
    }
    #[inline(always)]
    fn mask_splat(value: bool) -> BVec4A {
        BVec4A::splat(value)
    }
    #[inline(always)]
    fn exp2_whole(self) -> Self {
        Vec4::new(
            exp2_whole(self.x),
            exp2_whole(self.y),
            exp2_whole(self.z),
            exp2_whole(self.w),
        )
    }
    #[inline(always)]
    fn bitmask(mask: BVec4A) -> u32 {
        mask.bitmask()
    }
    #[inline(always)]
    fn first_lanes(count: usize) -> BVec4A {
        BVec4A::new(count > 0, count > 1, count > 2, count > 3)
    }
    #[inline(always)]
    fn reduce_max(self) -> f32 {
        self.max_element()
    }
    #[inline(always)]
    fn lane_numbers() -> Self {
        Vec4::new(0.0, 1.0, 2.0, 3.0)
    }
    #[inline(always)]
    fn store(self, out: &mut [f32]) {
        self.write_to_slice(&mut out[..4]);
    }
    #[inline(always)]
    fn compress_store(self, mask: BVec4A, out: &mut [f32]) {
        let values = self.to_array();
        let (kept, _) = KEPT_LANES[mask.bitmask() as usize];
        for (out, lane) in out[..4].iter_mut().zip(kept) {
            *out = values[lane as usize];
        }
    }
    #[inline(always)]
    fn transpose_in(mut f: impl FnMut(usize) -> [f32; 8]) -> [Self; 8] {
        let columns = [f(0), f(1), f(2), f(3)];
        let half = |offset: usize| {
            let column = |i: usize| Vec4::from_slice(&columns[i][offset..offset + 4]);
            Mat4::from_cols(column(0), column(1), column(2), column(3)).transpose()
        };
        let (low, high) = (half(0), half(4));
        [
            low.x_axis,
            low.y_axis,
            low.z_axis,
            low.w_axis,
            high.x_axis,
            high.y_axis,
            high.z_axis,
            high.w_axis,
        ]
    }
    #[inline(always)]
    fn transpose_out(rows: [Self; 8], mut f: impl FnMut(usize, [f32; 8])) {
        let low = Mat4::from_cols(rows[0], rows[1], rows[2], rows[3]).transpose();
        let high = Mat4::from_cols(rows[4], rows[5], rows[6], rows[7]).transpose();
        for i in 0..4 {
            let (l, h) = (low.col(i), high.col(i));
            f(i, [l.x, l.y, l.z, l.w, h.x, h.y, h.z, h.w]);
        }
    }
}

/// One lane: the scalar form of a lane-wise algorithm, the same operations on one float.
impl Wide for f32 {
    type Mask = bool;
    const LANES: usize = 1;

    #[inline(always)]
    fn splat(value: f32) -> Self {
        value
    }
    #[inline(always)]
    fn from_fn(mut f: impl FnMut(usize) -> f32) -> Self {
        f(0)
    }
    #[inline(always)]
    fn lane(self, _: usize) -> f32 {
        self
    }
    #[inline(always)]
    fn select(mask: bool, a: Self, b: Self) -> Self {
        if mask {
            a
        } else {
            b
        }
    }
    #[inline(always)]
    fn cmplt(self, other: Self) -> bool {
        self < other
    }
    #[inline(always)]
    fn cmple(self, other: Self) -> bool {
        self <= other
    }
    #[inline(always)]
    fn cmpgt(self, other: Self) -> bool {
        self > other
    }
    #[inline(always)]
    fn cmpge(self, other: Self) -> bool {
        self >= other
    }
    #[inline(always)]
    fn sqrt(self) -> Self {
        f32::sqrt(self)
    }
    #[inline(always)]
    fn recip(self) -> Self {
        1.0 / self
    }
    #[inline(always)]
    fn max(self, other: Self) -> Self {
        f32::max(self, other)
    }
    #[inline(always)]
    fn mask_from_fn(mut f: impl FnMut(usize) -> bool) -> bool {
        f(0)
    }
    #[inline(always)]
    fn test(mask: bool, _: usize) -> bool {
        mask
    }
    #[inline(always)]
    fn any(mask: bool) -> bool {
        mask
    }
    #[inline(always)]
    fn all(mask: bool) -> bool {
        mask
    }
    #[inline(always)]
    fn load(values: &[f32]) -> Self {
        values[0]
    }
    #[inline(always)]
    fn min(self, other: Self) -> Self {
        f32::min(self, other)
    }
    #[inline(always)]
    fn abs(self) -> Self {
        f32::abs(self)
    }
    #[inline(always)]
    fn cmpeq(self, other: Self) -> bool {
        self == other
    }
    #[inline(always)]
    fn mask_splat(value: bool) -> bool {
        value
    }
    #[inline(always)]
    fn exp2_whole(self) -> Self {
        exp2_whole(self)
    }
    #[inline(always)]
    fn bitmask(mask: bool) -> u32 {
        u32::from(mask)
    }
    #[inline(always)]
    fn first_lanes(count: usize) -> bool {
        count > 0
    }
    #[inline(always)]
    fn reduce_max(self) -> f32 {
        self
    }
    #[inline(always)]
    fn lane_numbers() -> Self {
        0.0
    }
    #[inline(always)]
    fn store(self, out: &mut [f32]) {
        out[0] = self;
    }
    #[inline(always)]
    fn compress_store(self, _: bool, out: &mut [f32]) {
        out[0] = self;
    }
    #[inline(always)]
    fn transpose_in(mut f: impl FnMut(usize) -> [f32; 8]) -> [Self; 8] {
        f(0)
    }
    #[inline(always)]
    fn transpose_out(rows: [Self; 8], mut f: impl FnMut(usize, [f32; 8])) {
        f(0, rows);
    }
}

/// `2^whole` for a whole number in [−126, 127], from its exponent bits. Without a float →
/// integer conversion: adding 1.5·2²³ leaves the integer in the low bits of the sum, so a
/// loop of these vectorises.
#[inline(always)]
fn exp2_whole(whole: f32) -> f32 {
    const MAGIC: f32 = 12_582_912.0;
    let biased = (whole + MAGIC)
        .to_bits()
        .wrapping_add(127)
        .wrapping_sub(MAGIC.to_bits());
    f32::from_bits(biased << 23)
}

/// For each 4-bit mask of kept lanes: the kept lanes in order (then zeros) and their count.
const KEPT_LANES: [([u32; 4], usize); 16] = {
    let mut table = [([0u32; 4], 0usize); 16];
    let mut mask = 0;
    while mask < 16 {
        let mut count = 0;
        let mut lane = 0;
        while lane < 4 {
            if mask & (1 << lane) != 0 {
                table[mask].0[count] = lane as u32;
                count += 1;
            }
            lane += 1;
        }
        table[mask].1 = count;
        mask += 1;
    }
    table
};

/// Per lane `value` clamped to `[low, high]` with the comparisons of `f32::clamp` (so the
/// same bits, signed zeros included).
#[inline(always)]
pub(crate) fn clamp<W: Wide>(value: W, low: f32, high: f32) -> W {
    let (low, high) = (W::splat(low), W::splat(high));
    let value = W::select(value.cmplt(low), low, value);
    W::select(value.cmpgt(high), high, value)
}

// Private to this module: an F8 or F16 is only sound where the processor has AVX or
// AVX-512F, which `run_widest` checks before it hands them to a job. Tests elsewhere reach
// them through `for_every_width`, which checks the same.
#[cfg(all(target_arch = "x86_64", not(test)))]
use x86::{F16, F8};
#[cfg(all(target_arch = "x86_64", test))]
pub(crate) use x86::{F16, F8};

/// The widest lane count of any [`Wide`] type.
pub(crate) const MAX_LANES: usize = 16;

/// Work written once for any lane width: [`run_widest`] runs it at the widest width the
/// processor offers, compiled for that instruction set.
pub(crate) trait LaneJob {
    /// What the job returns.
    type Output;
    /// The job at width `W`. Implementations mark it `#[inline(always)]`, and everything it
    /// calls too, so that it is compiled inside the instruction-set-specific caller (a call
    /// left out of line is compiled without AVX and is slow).
    fn run<W: Wide>(self) -> Self::Output;
}

/// Runs `job` with 16 lanes where the processor has AVX-512F, 8 with AVX, else 4 (glam's
/// `Vec4`: SSE2 on x86-64, NEON on AArch64, plain floats elsewhere). Results are the same bits
/// at every width. The wide forms are also compiled with POPCNT (every processor with AVX
/// has it): counting a mask's lanes is then one instruction rather than fifteen, and a
/// search's batch length waits on that count.
#[inline]
pub(crate) fn run_widest<J: LaneJob>(job: J) -> J::Output {
    #[cfg(target_arch = "x86_64")]
    if std::is_x86_feature_detected!("popcnt") {
        if std::is_x86_feature_detected!("avx512f") {
            // SAFETY: the processor has AVX-512F and POPCNT, checked just above.
            return unsafe { run_avx512(job) };
        }
        if std::is_x86_feature_detected!("avx") {
            // SAFETY: the processor has AVX and POPCNT, checked just above.
            return unsafe { run_avx(job) };
        }
    }
    job.run::<Vec4>()
}

/// How many lanes [`run_widest`] runs with on this processor.
pub(crate) fn widest_lanes() -> usize {
    struct Lanes;
    impl LaneJob for Lanes {
        type Output = usize;
        #[inline(always)]
        fn run<W: Wide>(self) -> usize {
            W::LANES
        }
    }
    run_widest(Lanes)
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f,popcnt")]
fn run_avx512<J: LaneJob>(job: J) -> J::Output {
    job.run::<F16>()
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx,popcnt")]
fn run_avx<J: LaneJob>(job: J) -> J::Output {
    job.run::<F8>()
}

/// The 8- and 16-lane types, written with the processor's own vector instructions.
///
/// Their operations are `#[inline(always)]` wrappers of AVX and AVX-512 intrinsics: they may
/// only run once the processor is known to have the instruction set ([`run_widest`] checks
/// before it uses them, and the tests skip them otherwise), and they are
/// compiled to single instructions where they are inlined into a function compiled for it.
#[cfg(target_arch = "x86_64")]
mod x86 {
    use std::arch::x86_64::*;
    use std::ops::{Add, BitAnd, BitOr, BitOrAssign, Div, Mul, Neg, Not, Sub};

    use super::Wide;

    /// Eight floats, one per lane: one AVX register. Only for processors with AVX.
    #[derive(Debug, Clone, Copy)]
    pub(crate) struct F8(__m256);

    /// One boolean per lane of [`F8`]: all bits of the lane set or clear.
    #[derive(Debug, Clone, Copy)]
    pub(crate) struct M8(__m256);

    /// Sixteen floats, one per lane: one AVX-512 register. Only for processors with AVX-512F.
    #[derive(Debug, Clone, Copy)]
    pub(crate) struct F16(__m512);

    /// One boolean per lane of [`F16`]: an AVX-512 mask register.
    #[derive(Debug, Clone, Copy)]
    pub(crate) struct M16(__mmask16);

    /// Declares a binary operator of a wide type as one intrinsic.
    macro_rules! binary {
        ($type:ident, $trait:ident, $method:ident, $intrinsic:ident) => {
            impl $trait for $type {
                type Output = Self;
                #[inline(always)]
                fn $method(self, other: Self) -> Self {
                    // SAFETY: wide values exist only on processors with the instruction set
                    // (see the module docs).
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

    binary!(F8, Add, add, _mm256_add_ps);
    binary!(F8, Sub, sub, _mm256_sub_ps);
    binary!(F8, Mul, mul, _mm256_mul_ps);
    binary!(F16, Add, add, _mm512_add_ps);
    binary!(F16, Sub, sub, _mm512_sub_ps);
    binary!(F16, Mul, mul, _mm512_mul_ps);
    binary!(F8, Div, div, _mm256_div_ps);
    binary!(F16, Div, div, _mm512_div_ps);

    impl Neg for F8 {
        type Output = Self;
        #[inline(always)]
        fn neg(self) -> Self {
            // SAFETY: AVX is present (module docs).
            F8(unsafe { _mm256_xor_ps(self.0, _mm256_set1_ps(-0.0)) })
        }
    }

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

    /// `a |= b` as `a = a | b`, for the mask types.
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

    or_assign!(M8, M16);

    /// Transposes the 8 × 8 block `rows` in place (row `r` lane `i` ↔ row `i` lane `r`).
    ///
    /// # Safety
    /// The processor has AVX.
    #[inline(always)]
    unsafe fn transpose8(rows: [__m256; 8]) -> [__m256; 8] {
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
    unsafe fn rows_of(columns: [[f32; 8]; 8]) -> [__m256; 8] {
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
            let (low_lanes, low_count) = super::KEPT_LANES[bits & 15];
            let low_count = low_count.min(4);
            let (high_lanes, _) = super::KEPT_LANES[bits >> 4];
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
}

/// Runs a generic test function `f::<W>()` for every width this processor can run (the wider
/// ones only where the processor has AVX or AVX-512F, as under valgrind it may not).
#[cfg(test)]
macro_rules! for_every_width {
    ($f:ident ( $($arg:expr),* )) => {{
        $f::<f32>($($arg),*);
        $f::<glam::Vec4>($($arg),*);
        #[cfg(target_arch = "x86_64")]
        {
            if std::is_x86_feature_detected!("avx") {
                $f::<$crate::math::wide::F8>($($arg),*);
            }
            if std::is_x86_feature_detected!("avx512f") {
                $f::<$crate::math::wide::F16>($($arg),*);
            }
        }
    }};
}
#[cfg(test)]
pub(crate) use for_every_width;

#[cfg(test)]
mod tests;
