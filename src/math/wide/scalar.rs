//! The 1- and 4-lane types: `f32` (the scalar form of a lane-wise algorithm) and glam's
//! `Vec4` (SSE2 on x86-64, NEON on AArch64, plain floats elsewhere), which every processor
//! runs; and the table of kept lanes that compresses 4 lanes (also the 8-lane type's halves).

use glam::{BVec4A, Mat4, Vec4};

use super::Wide;

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
/// (`Vec4` compresses with it, and the 8-lane type each of its halves.)
pub(super) const KEPT_LANES: [([u32; 4], usize); 16] = {
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
