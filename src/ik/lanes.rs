//! Many characters at once: vectors, quaternions and the gaze IK's rotation helpers in
//! structure-of-arrays form, one character per SIMD lane, generic over the lane width
//! ([`Wide`]: 4 lanes with glam's `Vec4`, 8 with AVX, 16 with AVX-512F; see
//! [`crate::math::wide::run_widest`]).
//!
//! The gaze solve is a chain of dependent steps (each joint waits for the one below it), so
//! one character leaves the processor mostly idle; a lane group of characters in the lanes of
//! the same instructions runs at nearly the cost of one. Branches become lane masks: both
//! sides are computed when the lanes disagree and the right one is selected per lane. Every
//! lane computes the same IEEE operations at every width, so a character's result does not
//! depend on the width or on its neighbours.
//!
//! Everything here is `#[inline(always)]`: it must be compiled inside the
//! instruction-set-specific functions that run it.

// The gathers fill several per-lane rows with one lane index.
#![allow(clippy::needless_range_loop)]

use std::ops::{Add, BitAnd, BitAndAssign, BitOr, Div, Mul, Neg, Not, Sub};

use glam::{Quat, Vec3A};

use crate::math::packed::PackedQuat;
use crate::math::wide::Wide;
pub(crate) use crate::math::wide::MAX_LANES;

/// One float per lane.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Floats<W>(W);

/// One boolean per lane.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Mask<W: Wide>(W::Mask);

impl<W: Wide> Floats<W> {
    /// 0 in every lane.
    #[inline(always)]
    pub(crate) fn zero() -> Self {
        Floats(W::splat(0.0))
    }

    /// 1 in every lane.
    #[inline(always)]
    pub(crate) fn one() -> Self {
        Floats(W::splat(1.0))
    }

    /// −1 in every lane.
    #[inline(always)]
    pub(crate) fn neg_one() -> Self {
        Floats(W::splat(-1.0))
    }

    /// The same value in every lane.
    #[inline(always)]
    pub(crate) fn splat(value: f32) -> Self {
        Floats(W::splat(value))
    }

    /// Lane `i` is `values[i]` (the values past the width are not used).
    #[inline(always)]
    pub(crate) fn load(values: &[f32; MAX_LANES]) -> Self {
        Floats(W::load(values))
    }

    /// Lane `i`'s value.
    #[inline(always)]
    pub(crate) fn lane(self, i: usize) -> f32 {
        self.0.lane(i)
    }

    /// Per lane: `a` where `m`, else `b`.
    #[inline(always)]
    pub(crate) fn select(m: Mask<W>, a: Self, b: Self) -> Self {
        Floats(W::select(m.0, a.0, b.0))
    }

    #[inline(always)]
    pub(crate) fn sqrt(self) -> Self {
        Floats(self.0.sqrt())
    }

    #[inline(always)]
    pub(crate) fn recip(self) -> Self {
        Floats(self.0.recip())
    }

    #[inline(always)]
    pub(crate) fn abs(self) -> Self {
        Floats(self.0.abs())
    }

    #[inline(always)]
    pub(crate) fn min(self, o: Self) -> Self {
        Floats(self.0.min(o.0))
    }

    #[inline(always)]
    pub(crate) fn max(self, o: Self) -> Self {
        Floats(self.0.max(o.0))
    }

    #[inline(always)]
    pub(crate) fn clamp(self, low: Self, high: Self) -> Self {
        self.max(low).min(high)
    }

    #[inline(always)]
    pub(crate) fn cmplt(self, o: Self) -> Mask<W> {
        Mask(self.0.cmplt(o.0))
    }

    #[inline(always)]
    pub(crate) fn cmple(self, o: Self) -> Mask<W> {
        Mask(self.0.cmple(o.0))
    }

    #[inline(always)]
    pub(crate) fn cmpgt(self, o: Self) -> Mask<W> {
        Mask(self.0.cmpgt(o.0))
    }

    #[inline(always)]
    pub(crate) fn cmpge(self, o: Self) -> Mask<W> {
        Mask(self.0.cmpge(o.0))
    }

    #[inline(always)]
    pub(crate) fn cmpeq(self, o: Self) -> Mask<W> {
        Mask(self.0.cmpeq(o.0))
    }
}

/// Declares the lane-wise arithmetic operators, with a scalar on either side too.
macro_rules! float_ops {
    ($($trait:ident $method:ident),*) => {$(
        impl<W: Wide> $trait for Floats<W> {
            type Output = Floats<W>;
            #[inline(always)]
            fn $method(self, o: Floats<W>) -> Floats<W> {
                Floats(self.0.$method(o.0))
            }
        }
        impl<W: Wide> $trait<f32> for Floats<W> {
            type Output = Floats<W>;
            #[inline(always)]
            fn $method(self, o: f32) -> Floats<W> {
                Floats(self.0.$method(W::splat(o)))
            }
        }
        impl<W: Wide> $trait<Floats<W>> for f32 {
            type Output = Floats<W>;
            #[inline(always)]
            fn $method(self, o: Floats<W>) -> Floats<W> {
                Floats(W::splat(self).$method(o.0))
            }
        }
    )*};
}
float_ops!(Add add, Sub sub, Mul mul, Div div);

impl<W: Wide> Neg for Floats<W> {
    type Output = Floats<W>;

    #[inline(always)]
    fn neg(self) -> Floats<W> {
        Floats(-self.0)
    }
}

impl<W: Wide> Mask<W> {
    /// The same value in every lane.
    #[inline(always)]
    pub(crate) fn splat(value: bool) -> Self {
        Mask(W::mask_splat(value))
    }

    /// True if any lane is true.
    #[inline(always)]
    pub(crate) fn any(self) -> bool {
        W::any(self.0)
    }

    /// True if every lane is true.
    #[inline(always)]
    pub(crate) fn all(self) -> bool {
        W::all(self.0)
    }

    /// Lane `lane`'s value.
    #[inline(always)]
    pub(crate) fn test(self, lane: usize) -> bool {
        W::test(self.0, lane)
    }
}

impl<W: Wide> BitAnd for Mask<W> {
    type Output = Mask<W>;

    #[inline(always)]
    fn bitand(self, o: Mask<W>) -> Mask<W> {
        Mask(self.0 & o.0)
    }
}

impl<W: Wide> BitAndAssign for Mask<W> {
    #[inline(always)]
    fn bitand_assign(&mut self, o: Mask<W>) {
        *self = *self & o;
    }
}

impl<W: Wide> BitOr for Mask<W> {
    type Output = Mask<W>;

    #[inline(always)]
    fn bitor(self, o: Mask<W>) -> Mask<W> {
        Mask(self.0 | o.0)
    }
}

impl<W: Wide> Not for Mask<W> {
    type Output = Mask<W>;

    #[inline(always)]
    fn not(self) -> Mask<W> {
        Mask(!self.0)
    }
}

/// A lane mask from a function of the lane index (called for the lanes of the width only).
#[inline(always)]
pub(crate) fn mask<W: Wide>(f: impl Fn(usize) -> bool) -> Mask<W> {
    Mask(W::mask_from_fn(f))
}

/// One float per lane from a function of the lane index (called for the lanes of the width
/// only).
#[inline(always)]
pub(crate) fn gather<W: Wide>(f: impl Fn(usize) -> f32) -> Floats<W> {
    let mut values = [0.0; MAX_LANES];
    for (i, value) in values.iter_mut().enumerate().take(W::LANES) {
        *value = f(i);
    }
    Floats::load(&values)
}

/// One 3-vector per lane.
#[derive(Debug, Clone, Copy)]
pub(crate) struct V3<W> {
    pub(crate) x: Floats<W>,
    pub(crate) y: Floats<W>,
    pub(crate) z: Floats<W>,
}

impl<W: Wide> V3<W> {
    /// Zero in every lane.
    #[inline(always)]
    pub(crate) fn zero() -> Self {
        V3::splat(Vec3A::ZERO)
    }

    /// The same vector in every lane.
    #[inline(always)]
    pub(crate) fn splat(v: Vec3A) -> V3<W> {
        V3 {
            x: Floats::splat(v.x),
            y: Floats::splat(v.y),
            z: Floats::splat(v.z),
        }
    }

    /// Lane `i` gets `f(i)`.
    #[inline(always)]
    pub(crate) fn gather(f: impl Fn(usize) -> Vec3A) -> V3<W> {
        let mut xyz = [[0.0; MAX_LANES]; 3];
        for i in 0..W::LANES {
            let v = f(i);
            (xyz[0][i], xyz[1][i], xyz[2][i]) = (v.x, v.y, v.z);
        }
        V3 {
            x: Floats::load(&xyz[0]),
            y: Floats::load(&xyz[1]),
            z: Floats::load(&xyz[2]),
        }
    }

    /// Lane `i`'s vector.
    #[inline(always)]
    pub(crate) fn lane(&self, i: usize) -> Vec3A {
        Vec3A::new(self.x.lane(i), self.y.lane(i), self.z.lane(i))
    }

    #[inline(always)]
    pub(crate) fn add(self, o: V3<W>) -> V3<W> {
        V3 {
            x: self.x + o.x,
            y: self.y + o.y,
            z: self.z + o.z,
        }
    }

    #[inline(always)]
    pub(crate) fn sub(self, o: V3<W>) -> V3<W> {
        V3 {
            x: self.x - o.x,
            y: self.y - o.y,
            z: self.z - o.z,
        }
    }

    #[inline(always)]
    pub(crate) fn scale(self, s: Floats<W>) -> V3<W> {
        V3 {
            x: self.x * s,
            y: self.y * s,
            z: self.z * s,
        }
    }

    #[inline(always)]
    pub(crate) fn dot(self, o: V3<W>) -> Floats<W> {
        self.x * o.x + self.y * o.y + self.z * o.z
    }

    #[inline(always)]
    pub(crate) fn cross(self, o: V3<W>) -> V3<W> {
        V3 {
            x: self.y * o.z - self.z * o.y,
            y: self.z * o.x - self.x * o.z,
            z: self.x * o.y - self.y * o.x,
        }
    }

    #[inline(always)]
    pub(crate) fn length_squared(self) -> Floats<W> {
        self.dot(self)
    }

    /// Per lane: `a` where `m`, else `b`.
    #[inline(always)]
    pub(crate) fn select(m: Mask<W>, a: V3<W>, b: V3<W>) -> V3<W> {
        V3 {
            x: Floats::select(m, a.x, b.x),
            y: Floats::select(m, a.y, b.y),
            z: Floats::select(m, a.z, b.z),
        }
    }
}

/// One quaternion per lane.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Q4<W> {
    pub(crate) x: Floats<W>,
    pub(crate) y: Floats<W>,
    pub(crate) z: Floats<W>,
    pub(crate) w: Floats<W>,
}

impl<W: Wide> Q4<W> {
    /// The identity in every lane.
    #[inline(always)]
    pub(crate) fn identity() -> Self {
        Q4::splat(Quat::IDENTITY)
    }

    /// The same rotation in every lane.
    #[inline(always)]
    pub(crate) fn splat(q: Quat) -> Q4<W> {
        Q4 {
            x: Floats::splat(q.x),
            y: Floats::splat(q.y),
            z: Floats::splat(q.z),
            w: Floats::splat(q.w),
        }
    }

    /// Lane `i` gets `f(i)`.
    #[inline(always)]
    pub(crate) fn gather(f: impl Fn(usize) -> Quat) -> Q4<W> {
        let mut xyzw = [[0.0; MAX_LANES]; 4];
        for i in 0..W::LANES {
            let q = f(i);
            (xyzw[0][i], xyzw[1][i], xyzw[2][i], xyzw[3][i]) = (q.x, q.y, q.z, q.w);
        }
        Q4 {
            x: Floats::load(&xyzw[0]),
            y: Floats::load(&xyzw[1]),
            z: Floats::load(&xyzw[2]),
            w: Floats::load(&xyzw[3]),
        }
    }

    /// Lane `i` gets `packed(i).unpack()`, bit for bit, computed for the lanes together.
    #[inline(always)]
    pub(crate) fn unpack(packed: impl Fn(usize) -> PackedQuat) -> Q4<W> {
        let mut abc = [[0.0; MAX_LANES]; 3];
        let mut left_out = [3u32; MAX_LANES];
        let mut negative = [false; MAX_LANES];
        for i in 0..W::LANES {
            let (stored, index, sign) = packed(i).parts();
            (abc[0][i], abc[1][i], abc[2][i]) = (stored[0], stored[1], stored[2]);
            (left_out[i], negative[i]) = (index, sign);
        }
        let a = Floats::load(&abc[0]);
        let b = Floats::load(&abc[1]);
        let c = Floats::load(&abc[2]);
        // As PackedQuat::unpack: √max(0, 1 − a² − b² − c²), with the sign of the original.
        let rest = (Floats::one() - a * a - b * b - c * c)
            .max(Floats::zero())
            .sqrt();
        let rebuilt = Floats::select(mask(|i| negative[i]), -rest, rest);
        // Where the rebuilt component goes: mostly w (rotations up to 90° at least).
        if left_out.iter().all(|index| *index == 3) {
            return Q4 {
                x: a,
                y: b,
                z: c,
                w: rebuilt,
            };
        }
        let (is_x, is_y, is_z, is_w) = (
            mask(|i| left_out[i] == 0),
            mask(|i| left_out[i] == 1),
            mask(|i| left_out[i] == 2),
            mask(|i| left_out[i] == 3),
        );
        Q4 {
            x: Floats::select(is_x, rebuilt, a),
            y: Floats::select(is_x, a, Floats::select(is_y, rebuilt, b)),
            z: Floats::select(is_z, rebuilt, Floats::select(is_w, c, b)),
            w: Floats::select(is_w, rebuilt, c),
        }
    }

    /// Lane `i`'s rotation.
    #[inline(always)]
    pub(crate) fn lane(&self, i: usize) -> Quat {
        Quat::from_xyzw(
            self.x.lane(i),
            self.y.lane(i),
            self.z.lane(i),
            self.w.lane(i),
        )
    }

    /// The rotation whose vector part is `v` and scalar part `w`.
    #[inline(always)]
    pub(crate) fn from_parts(v: V3<W>, w: Floats<W>) -> Q4<W> {
        Q4 {
            x: v.x,
            y: v.y,
            z: v.z,
            w,
        }
    }

    #[inline(always)]
    pub(crate) fn vector(self) -> V3<W> {
        V3 {
            x: self.x,
            y: self.y,
            z: self.z,
        }
    }

    #[inline(always)]
    pub(crate) fn conjugate(self) -> Q4<W> {
        Q4 {
            x: -self.x,
            y: -self.y,
            z: -self.z,
            w: self.w,
        }
    }

    #[inline(always)]
    pub(crate) fn dot(self, o: Q4<W>) -> Floats<W> {
        self.x * o.x + self.y * o.y + self.z * o.z + self.w * o.w
    }

    /// The Hamilton product `self * o` (apply `o`, then `self`), as glam's `Quat * Quat`.
    #[inline(always)]
    pub(crate) fn mul(self, o: Q4<W>) -> Q4<W> {
        Q4 {
            x: self.w * o.x + self.x * o.w + self.y * o.z - self.z * o.y,
            y: self.w * o.y - self.x * o.z + self.y * o.w + self.z * o.x,
            z: self.w * o.z + self.x * o.y - self.y * o.x + self.z * o.w,
            w: self.w * o.w - self.x * o.x - self.y * o.y - self.z * o.z,
        }
    }

    /// `v` rotated by the (unit) quaternion: `v + w t + u × t` with `t = 2 u × v`.
    #[inline(always)]
    pub(crate) fn rotate(self, v: V3<W>) -> V3<W> {
        let u = self.vector();
        let t = u.cross(v).scale(Floats::splat(2.0));
        v.add(t.scale(self.w)).add(u.cross(t))
    }

    /// The quaternion scaled to unit length.
    #[inline(always)]
    pub(crate) fn normalize(self) -> Q4<W> {
        let inverse = self.dot(self).sqrt().recip();
        Q4 {
            x: self.x * inverse,
            y: self.y * inverse,
            z: self.z * inverse,
            w: self.w * inverse,
        }
    }

    /// Per lane: exactly the identity.
    #[inline(always)]
    pub(crate) fn is_identity(self) -> Mask<W> {
        self.x.cmpeq(Floats::zero())
            & self.y.cmpeq(Floats::zero())
            & self.z.cmpeq(Floats::zero())
            & self.w.cmpeq(Floats::one())
    }

    /// Per lane: the two rotations equal, component by component (`==`).
    #[inline(always)]
    pub(crate) fn equals(self, o: Q4<W>) -> Mask<W> {
        self.x.cmpeq(o.x) & self.y.cmpeq(o.y) & self.z.cmpeq(o.z) & self.w.cmpeq(o.w)
    }

    /// Per lane: `a` where `m`, else `b`.
    #[inline(always)]
    pub(crate) fn select(m: Mask<W>, a: Q4<W>, b: Q4<W>) -> Q4<W> {
        Q4 {
            x: Floats::select(m, a.x, b.x),
            y: Floats::select(m, a.y, b.y),
            z: Floats::select(m, a.z, b.z),
            w: Floats::select(m, a.w, b.w),
        }
    }
}

/// `atan2(y, x)` per lane for `y ≥ 0`, in [0, π]; 0 when both are 0. Absolute error
/// < 1.5·10⁻⁵ rad (a minimax polynomial of degree 11 on [0, 1]).
#[inline(always)]
pub(crate) fn atan2_upper<W: Wide>(y: Floats<W>, x: Floats<W>) -> Floats<W> {
    let ax = x.abs();
    let swap = y.cmpgt(ax);
    let small = Floats::select(swap, ax, y);
    let large = Floats::select(swap, y, ax);
    let t = small / large;
    let t = Floats::select(large.cmpgt(Floats::zero()), t, Floats::zero());
    let t2 = t * t;
    let mut angle = t
        * (0.999_977_26
            + t2 * (-0.332_623_47
                + t2 * (0.193_543_46
                    + t2 * (-0.116_432_87 + t2 * (0.052_653_32 - t2 * 0.011_721_2)))));
    angle = Floats::select(swap, std::f32::consts::FRAC_PI_2 - angle, angle);
    angle = Floats::select(x.cmplt(Floats::zero()), std::f32::consts::PI - angle, angle);
    Floats::select(large.cmpgt(Floats::zero()), angle, Floats::zero())
}

/// `(sin x, cos x)` per lane for `x ∈ [0, π/2]` (clamped), errors < 5·10⁻⁶ (Taylor
/// polynomials of degree 9 and 10).
#[inline(always)]
pub(crate) fn sin_cos_quarter<W: Wide>(x: Floats<W>) -> (Floats<W>, Floats<W>) {
    let x = x.clamp(Floats::zero(), Floats::splat(std::f32::consts::FRAC_PI_2));
    let x2 = x * x;
    let sin = x
        * (1.0
            + x2 * (-1.0 / 6.0
                + x2 * (1.0 / 120.0 + x2 * (-1.0 / 5040.0 + x2 * (1.0 / 362_880.0)))));
    let cos = 1.0
        + x2 * (-0.5
            + x2 * (1.0 / 24.0
                + x2 * (-1.0 / 720.0 + x2 * (1.0 / 40_320.0 - x2 * (1.0 / 3_628_800.0)))));
    (sin, cos)
}

/// [`interpolate_or`] starting from `a` at `t ≤ 0` too.
#[cfg(test)]
#[inline(always)]
pub(crate) fn interpolate<W: Wide>(a: Q4<W>, b: Q4<W>, t: Floats<W>) -> Q4<W> {
    interpolate_or(a, a, b, t)
}

/// Interpolation from `a` to `b` the short way per lane, exactly `at_zero` for `t ≤ 0` (`a`
/// is then not used: callers whose `a` means something only in the lanes under way) and
/// exactly `b` for `t ≥ 1`. In between, a normalised lerp with a corrected parameter that
/// follows slerp's constant angular speed within about 10⁻³ of the angle (A. Kapoulkine,
/// "Approximating slerp", 2015): no trigonometry.
#[inline(always)]
pub(crate) fn interpolate_or<W: Wide>(a: Q4<W>, at_zero: Q4<W>, b: Q4<W>, t: Floats<W>) -> Q4<W> {
    let dot = a.dot(b);
    let flip = dot.cmplt(Floats::zero());
    let sign = Floats::select(flip, Floats::neg_one(), Floats::one());
    let d = dot.abs();
    let k_a = 1.0904 + d * (-3.2452 + d * (3.55645 - d * 1.43519));
    let k_b = 0.848_013 + d * (-1.06021 + d * 0.215_638);
    let half = t - 0.5;
    let k = k_a * half * half + k_b;
    let u = t + t * half * (t - 1.0) * k;
    let mixed = Q4 {
        x: a.x + (b.x * sign - a.x) * u,
        y: a.y + (b.y * sign - a.y) * u,
        z: a.z + (b.z * sign - a.z) * u,
        w: a.w + (b.w * sign - a.w) * u,
    }
    .normalize();
    let mixed = Q4::select(t.cmple(Floats::zero()), at_zero, mixed);
    Q4::select(t.cmpge(Floats::one()), b, mixed)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::wide::for_every_width;
    use glam::{Vec3, Vec4};

    #[test]
    fn lanes_match_glam() {
        for_every_width!(lanes_match_glam_at());
    }

    fn lanes_match_glam_at<W: Wide>() {
        // The mask checks below need four lanes at least (one lane is the scalar form).
        if W::LANES < 4 {
            return;
        }
        let rotations: [Quat; MAX_LANES] = std::array::from_fn(|i| {
            let axis = Vec3::new(1.0, 2.0 - i as f32, 3.0 + i as f32).normalize();
            Quat::from_axis_angle(axis, 0.4 * i as f32 - 1.0)
        });
        let vectors: [Vec3A; MAX_LANES] =
            std::array::from_fn(|i| Vec3A::new(0.3 * i as f32, -2.0, 5.0 - i as f32));
        let mirror = |i: usize| W::LANES - 1 - i;
        let q = Q4::<W>::gather(|i| rotations[i]);
        let p = Q4::gather(|i| rotations[mirror(i)]);
        let v = V3::gather(|i| vectors[i]);
        for i in 0..W::LANES {
            let rotated = q.rotate(v).lane(i);
            assert!(rotated.abs_diff_eq(rotations[i] * vectors[i], 1e-5));
            let product = q.mul(p).lane(i);
            assert!(product.abs_diff_eq(rotations[i] * rotations[mirror(i)], 1e-6));
            let cross = v.cross(V3::splat(Vec3A::Y)).lane(i);
            assert!(cross.abs_diff_eq(vectors[i].cross(Vec3A::Y), 1e-6));
        }
        let t: Floats<W> = gather(|i| [0.0, 0.3, 1.0, 0.7][i % 4]);
        let mixed = interpolate(q, p, t);
        for i in 0..W::LANES {
            match i % 4 {
                0 => assert_eq!(mixed.lane(i), rotations[i]),
                2 => assert_eq!(mixed.lane(i), rotations[mirror(i)]),
                _ => {
                    let expected = rotations[i].slerp(rotations[mirror(i)], t.lane(i));
                    assert!(mixed.lane(i).angle_between(expected) < 2e-3, "lane {i}");
                }
            }
        }
        assert!(Q4::<W>::identity().is_identity().all());
        let m: Mask<W> = mask(|i| i == 2);
        assert!(m.any() && !m.all() && m.test(2) && !m.test(1));
        assert!((!Mask::<W>::splat(false)).all());
    }

    #[test]
    fn unpacking_lanes_gives_the_bits_of_one() {
        for_every_width!(unpacking_at());
    }

    fn unpacking_at<W: Wide>() {
        let mut random = crate::math::random::Random::new(23);
        for round in 0..2_000 {
            let packed: [PackedQuat; MAX_LANES] = std::array::from_fn(|i| {
                let mut draw = || 2.0 * random.next_f32() - 1.0;
                let q = Quat::from_xyzw(draw(), draw(), draw(), draw()).normalize();
                // Every other round all lanes leave w out (the fast path).
                let q = if round % 2 == 0 && q.w.abs() < 0.9 {
                    Quat::from_axis_angle(Vec3::new(draw(), draw(), 1.0).normalize(), draw())
                } else {
                    q
                };
                PackedQuat::pack(if i == 2 { -q } else { q })
            });
            let lanes = Q4::<W>::unpack(|i| packed[i]);
            for (i, packed) in packed.iter().enumerate().take(W::LANES) {
                let (one, all) = (packed.unpack(), lanes.lane(i));
                assert_eq!(
                    one.to_array().map(f32::to_bits),
                    all.to_array().map(f32::to_bits)
                );
            }
        }
    }

    #[test]
    fn polynomials_are_accurate() {
        let mut worst: f32 = 0.0;
        for i in 0..=5_000 {
            let angle = std::f32::consts::PI * i as f32 / 5_000.0;
            let (y, x) = (angle.sin().max(0.0), angle.cos());
            let approx = atan2_upper::<Vec4>(
                gather(|i| [y, y * 1e-3, y * 250.0, 0.0][i % 4]),
                gather(|i| [x, x * 1e-3, x * 250.0, 0.0][i % 4]),
            );
            for lane in 0..3 {
                worst = worst.max((approx.lane(lane) - y.atan2(x)).abs());
            }
            assert_eq!(approx.lane(3), 0.0);
        }
        assert!(worst < 1.5e-5, "atan2 error {worst}");
        let mut worst: f32 = 0.0;
        for i in 0..=5_000 {
            let x = std::f32::consts::FRAC_PI_2 * i as f32 / 5_000.0;
            let (sin, cos) = sin_cos_quarter(Floats::<Vec4>::splat(x));
            worst = worst
                .max((sin.lane(0) - x.sin()).abs())
                .max((cos.lane(0) - x.cos()).abs());
        }
        assert!(worst < 5e-6, "sin/cos error {worst}");
    }
}
