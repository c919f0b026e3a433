//! Unit quaternions in 8 bytes instead of 16, for state that is stored often and read
//! rarely (a gaze shift's start pose).
//!
//! **Encoding ("smallest three").** Of the four components, the largest in magnitude is
//! left out; the other three, each within [−1/√2, 1/√2] (a unit quaternion's second largest
//! component is at most 1/√2), are stored as 20-bit signed integers `round(c · S)`,
//! `S = (2¹⁹ − 1)·√2`, with the index (2 bits) and the sign (1 bit) of the one left out.
//! Decoding rebuilds it as `±√(1 − a² − b² − c²)`. The sign is kept, so a quaternion comes
//! back close to itself component by component, not merely to the same rotation.
//!
//! **Precision.** Each stored component is off by at most `½/S` = 6.7·10⁻⁷ plus an f32
//! rounding (4·10⁻⁸), so the three together by `|Δv|` ≤ √3 · 7.2·10⁻⁷ = 1.24·10⁻⁶. The
//! rebuilt component `m` (≥ ½: the largest of four squares summing to 1) moves by
//! `|Δm| = |2v·Δv + |Δv|²| / (m + m̃)` ≤ √3·|Δv|, so `|q − q̃|` ≤ 2|Δv| = 2.5·10⁻⁶ and the
//! rotation from `q` to its decoding, `4 asin(|q − q̃|/2)`, is at most 5.0·10⁻⁶ rad. An input
//! of length `1 ± ε` (f32 normalisation leaves ε ≈ 2·10⁻⁷) adds at most ε to that, so the
//! bound is 6·10⁻⁶ rad for every unit quaternion, half turns included (where dropping `w`
//! alone would lose precision); 4.5·10⁻⁶ rad is the worst the tests see over 200 000
//! random rotations. Zero components are stored exactly: the identity, and any rotation
//! about a coordinate axis by 0 or π, come back bit for bit.

use glam::Quat;

/// Bits per stored component.
const BITS: u32 = 20;
const MASK: u64 = (1 << BITS) - 1;
/// Largest stored magnitude, `2¹⁹ − 1`.
const LARGEST: f32 = ((1u32 << (BITS - 1)) - 1) as f32;
/// `S`: a component of magnitude 1/√2 maps to `LARGEST`.
const SCALE: f32 = LARGEST * std::f32::consts::SQRT_2;
const INDEX_SHIFT: u32 = 3 * BITS;
const SIGN_BIT: u64 = 1 << (INDEX_SHIFT + 2);

/// A unit quaternion in 63 bits (see the module docs): within 6·10⁻⁶ rad of the one packed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct PackedQuat(u64);

impl PackedQuat {
    /// The identity, exactly.
    pub const IDENTITY: PackedQuat = PackedQuat(3 << INDEX_SHIFT);

    /// Packs a unit quaternion (non-unit input is packed as if normalised, within the same
    /// bound; a non-finite one gives an unspecified rotation).
    #[inline]
    pub fn pack(q: Quat) -> PackedQuat {
        let components = q.to_array();
        let mut largest = 3;
        for index in (0..3).rev() {
            if components[index].abs() > components[largest].abs() {
                largest = index;
            }
        }
        let mut bits = (largest as u64) << INDEX_SHIFT;
        if components[largest].is_sign_negative() {
            bits |= SIGN_BIT;
        }
        for (slot, &index) in OTHERS[largest].iter().enumerate() {
            bits |= (quantise(components[index]) as u64 & MASK) << (slot as u32 * BITS);
        }
        PackedQuat(bits)
    }

    /// The quaternion back (unit length within f32 rounding).
    #[inline]
    pub fn unpack(self) -> Quat {
        let (stored, left_out, negative) = self.parts();
        let [a, b, c] = stored;
        let rebuilt = rebuild(a, b, c);
        let rebuilt = if negative { -rebuilt } else { rebuilt };
        match left_out {
            0 => Quat::from_xyzw(rebuilt, a, b, c),
            1 => Quat::from_xyzw(a, rebuilt, b, c),
            2 => Quat::from_xyzw(a, b, rebuilt, c),
            _ => Quat::from_xyzw(a, b, c, rebuilt),
        }
    }

    /// The three stored components (in order), the index of the one left out, and whether
    /// it is negative: for unpacking several at once.
    #[inline(always)]
    pub(crate) fn parts(self) -> ([f32; 3], u32, bool) {
        let bits = self.0;
        let field = |slot: u32| {
            // Sign-extend the 20-bit field.
            let value = (((bits >> (slot * BITS)) as u32) << (32 - BITS)) as i32 >> (32 - BITS);
            value as f32 * (1.0 / SCALE)
        };
        (
            [field(0), field(1), field(2)],
            ((bits >> INDEX_SHIFT) & 3) as u32,
            bits & SIGN_BIT != 0,
        )
    }
}

/// The magnitude of the component left out, from the three stored: `√max(0, 1 − a² − b² − c²)`.
/// (The four-lane unpacking in `ik::lanes` does the same operations in the same order, so
/// it gives the same bits.)
#[inline(always)]
fn rebuild(a: f32, b: f32, c: f32) -> f32 {
    (1.0 - a * a - b * b - c * c).max(0.0).sqrt()
}

/// The components stored when component `i` is left out, in order.
const OTHERS: [[usize; 3]; 4] = [[1, 2, 3], [0, 2, 3], [0, 1, 3], [0, 1, 2]];

/// `round(component · S)`, clamped to ±(2¹⁹ − 1), rounding half to even: adding 1.5·2²³ to a
/// value below 2²² in magnitude leaves it rounded to an integer in the low bits of the
/// sum's mantissa (no rounding instruction, libm call or saturating conversion).
#[inline]
fn quantise(component: f32) -> i32 {
    const MAGIC: f32 = 12_582_912.0;
    let scaled = (component * SCALE).clamp(-LARGEST, LARGEST);
    (scaled + MAGIC).to_bits() as i32 - MAGIC.to_bits() as i32
}

impl Default for PackedQuat {
    fn default() -> Self {
        PackedQuat::IDENTITY
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::random::Random;
    use glam::{Vec3, Vec4};

    /// The rotation angle from `a` to `b`, in f64: `4 asin(|a − b|/2)` between the two
    /// normalised, sign-aligned quaternions (well conditioned for small angles, unlike
    /// `2 acos(a·b)`).
    fn angle(a: Quat, b: Quat) -> f64 {
        let unit = |q: Quat| {
            let q = q.to_array().map(f64::from);
            let length = q.iter().map(|c| c * c).sum::<f64>().sqrt();
            q.map(|c| c / length)
        };
        let (a, mut b) = (unit(a), unit(b));
        if a.iter().zip(&b).map(|(x, y)| x * y).sum::<f64>() < 0.0 {
            b = b.map(|c| -c);
        }
        let chord = a
            .iter()
            .zip(&b)
            .map(|(x, y)| (x - y) * (x - y))
            .sum::<f64>()
            .sqrt();
        4.0 * (0.5 * chord).asin()
    }

    #[test]
    fn identity_and_axis_rotations_come_back_exactly() {
        assert_eq!(std::mem::size_of::<PackedQuat>(), 8);
        assert_eq!(PackedQuat::pack(Quat::IDENTITY), PackedQuat::IDENTITY);
        assert_eq!(PackedQuat::IDENTITY.unpack(), Quat::IDENTITY);
        assert_eq!(PackedQuat::default().unpack(), Quat::IDENTITY);
        for q in [
            -Quat::IDENTITY,
            Quat::from_xyzw(1.0, 0.0, 0.0, 0.0),
            Quat::from_xyzw(0.0, -1.0, 0.0, 0.0),
            Quat::from_xyzw(0.0, 0.0, 1.0, 0.0),
        ] {
            assert_eq!(PackedQuat::pack(q).unpack(), q);
        }
    }

    #[test]
    fn every_rotation_comes_back_within_six_microradians() {
        let mut random = Random::new(17);
        let mut worst_angle: f64 = 0.0;
        let mut worst_component: f32 = 0.0;
        let mut check = |q: Quat| {
            let back = PackedQuat::pack(q).unpack();
            worst_angle = worst_angle.max(angle(q, back));
            worst_component = worst_component.max(Vec4::from(q - back).abs().max_element());
            assert!((back.length() - 1.0).abs() < 1e-6, "{q:?} → {back:?}");
        };
        for _ in 0..200_000 {
            // Uniform on the sphere of unit quaternions, both signs.
            let mut draw = || 2.0 * random.next_f32() - 1.0;
            let q = Quat::from_xyzw(draw(), draw(), draw(), draw());
            if q.length() > 0.1 {
                check(q.normalize());
            }
        }
        // Small deltas, near half turns and ties between the largest components.
        for step in 0..=2_000 {
            let angle = std::f32::consts::TAU * step as f32 / 2_000.0;
            for axis in [
                Vec3::X,
                Vec3::new(1.0, 1.0, 0.0).normalize(),
                Vec3::ONE.normalize(),
            ] {
                check(Quat::from_axis_angle(axis, angle));
                check(Quat::from_axis_angle(axis, 1e-4 * angle));
            }
        }
        check(Quat::from_xyzw(0.5, -0.5, 0.5, 0.5));
        check(Quat::from_xyzw(
            std::f32::consts::FRAC_1_SQRT_2,
            0.0,
            0.0,
            -std::f32::consts::FRAC_1_SQRT_2,
        ));
        assert!(worst_angle < 6e-6, "worst rotation error {worst_angle} rad");
        assert!(
            worst_component < 2.5e-6,
            "worst component error {worst_component}"
        );
    }

    #[test]
    fn the_sign_is_kept() {
        let q = Quat::from_axis_angle(Vec3::new(0.3, -0.8, 0.2).normalize(), 2.5);
        for q in [q, -q] {
            let back = PackedQuat::pack(q).unpack();
            assert!(q.dot(back) > 0.999_999, "{q:?} → {back:?}");
        }
    }
}
