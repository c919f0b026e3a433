//! Four characters at once: vectors, quaternions and the gaze IK's rotation helpers in
//! structure-of-arrays form, one character per SIMD lane (glam's `Vec4`: SSE2 on x86-64,
//! plain floats elsewhere).
//!
//! The gaze solve is a chain of dependent steps (each joint waits for the one below it), so
//! one character leaves the processor mostly idle; four characters in the four lanes of the
//! same instructions run at nearly the cost of one. Branches become lane masks: both sides
//! are computed when the lanes disagree and the right one is selected per lane.

use std::ops::{Add, BitAnd, BitAndAssign, BitOr, Div, Index, Mul, Neg, Not, Sub};

use glam::{BVec4A, Quat, Vec3A, Vec4};

use crate::math::packed::PackedQuat;

/// Number of 4-wide SIMD registers per lane group (two would interleave the dependency
/// chains of two groups of four characters, but costs as much as it gains).
const HALVES: usize = 1;

/// Number of characters processed together.
pub(crate) const LANES: usize = 4 * HALVES;

/// One float per lane.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Floats([Vec4; HALVES]);

/// One boolean per lane.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Mask([BVec4A; HALVES]);

impl Floats {
    pub(crate) const ZERO: Floats = Floats([Vec4::ZERO; HALVES]);
    pub(crate) const ONE: Floats = Floats([Vec4::ONE; HALVES]);
    pub(crate) const NEG_ONE: Floats = Floats([Vec4::NEG_ONE; HALVES]);

    #[inline(always)]
    fn map(self, f: impl Fn(Vec4) -> Vec4) -> Floats {
        Floats(self.0.map(f))
    }

    #[inline(always)]
    fn zip(self, o: Floats, f: impl Fn(Vec4, Vec4) -> Vec4) -> Floats {
        Floats(std::array::from_fn(|h| f(self.0[h], o.0[h])))
    }

    #[inline(always)]
    fn compare(self, o: Floats, f: impl Fn(Vec4, Vec4) -> BVec4A) -> Mask {
        Mask(std::array::from_fn(|h| f(self.0[h], o.0[h])))
    }

    /// The same value in every lane.
    #[inline(always)]
    pub(crate) fn splat(value: f32) -> Floats {
        Floats([Vec4::splat(value); HALVES])
    }

    /// Per lane: `a` where `m`, else `b`.
    #[inline(always)]
    pub(crate) fn select(m: Mask, a: Floats, b: Floats) -> Floats {
        Floats(std::array::from_fn(|h| {
            Vec4::select(m.0[h], a.0[h], b.0[h])
        }))
    }

    #[inline(always)]
    pub(crate) fn sqrt(self) -> Floats {
        self.map(Vec4::sqrt)
    }

    #[inline(always)]
    pub(crate) fn recip(self) -> Floats {
        self.map(Vec4::recip)
    }

    #[inline(always)]
    pub(crate) fn abs(self) -> Floats {
        self.map(Vec4::abs)
    }

    #[inline(always)]
    pub(crate) fn min(self, o: Floats) -> Floats {
        self.zip(o, Vec4::min)
    }

    #[inline(always)]
    pub(crate) fn max(self, o: Floats) -> Floats {
        self.zip(o, Vec4::max)
    }

    #[inline(always)]
    pub(crate) fn clamp(self, low: Floats, high: Floats) -> Floats {
        self.zip(low, Vec4::max).zip(high, Vec4::min)
    }

    #[inline(always)]
    pub(crate) fn cmplt(self, o: Floats) -> Mask {
        self.compare(o, Vec4::cmplt)
    }

    #[inline(always)]
    pub(crate) fn cmple(self, o: Floats) -> Mask {
        self.compare(o, Vec4::cmple)
    }

    #[inline(always)]
    pub(crate) fn cmpgt(self, o: Floats) -> Mask {
        self.compare(o, Vec4::cmpgt)
    }

    #[inline(always)]
    pub(crate) fn cmpge(self, o: Floats) -> Mask {
        self.compare(o, Vec4::cmpge)
    }

    #[inline(always)]
    pub(crate) fn cmpeq(self, o: Floats) -> Mask {
        self.compare(o, Vec4::cmpeq)
    }
}

impl Index<usize> for Floats {
    type Output = f32;

    #[inline(always)]
    fn index(&self, lane: usize) -> &f32 {
        &self.0[lane / 4][lane % 4]
    }
}

macro_rules! float_ops {
    ($($trait:ident $method:ident),*) => {$(
        impl $trait for Floats {
            type Output = Floats;
            #[inline(always)]
            fn $method(self, o: Floats) -> Floats {
                self.zip(o, |a, b| a.$method(b))
            }
        }
        impl $trait<f32> for Floats {
            type Output = Floats;
            #[inline(always)]
            fn $method(self, o: f32) -> Floats {
                self.map(|a| a.$method(o))
            }
        }
        impl $trait<Floats> for f32 {
            type Output = Floats;
            #[inline(always)]
            fn $method(self, o: Floats) -> Floats {
                o.map(|b| self.$method(b))
            }
        }
    )*};
}
float_ops!(Add add, Sub sub, Mul mul, Div div);

impl Neg for Floats {
    type Output = Floats;

    #[inline(always)]
    fn neg(self) -> Floats {
        self.map(|a| -a)
    }
}

impl Mask {
    /// The same value in every lane.
    #[inline(always)]
    pub(crate) fn splat(value: bool) -> Mask {
        Mask([BVec4A::splat(value); HALVES])
    }

    /// True if any lane is true.
    #[inline(always)]
    pub(crate) fn any(self) -> bool {
        self.0.iter().fold(0, |bits, half| bits | half.bitmask()) != 0
    }

    /// True if every lane is true.
    #[inline(always)]
    pub(crate) fn all(self) -> bool {
        self.0.iter().fold(0xF, |bits, half| bits & half.bitmask()) == 0xF
    }

    /// Lane `lane`'s value.
    #[inline(always)]
    pub(crate) fn test(self, lane: usize) -> bool {
        self.0[lane / 4].test(lane % 4)
    }
}

impl BitAnd for Mask {
    type Output = Mask;

    #[inline(always)]
    fn bitand(self, o: Mask) -> Mask {
        Mask(std::array::from_fn(|h| self.0[h] & o.0[h]))
    }
}

impl BitAndAssign for Mask {
    #[inline(always)]
    fn bitand_assign(&mut self, o: Mask) {
        *self = *self & o;
    }
}

impl BitOr for Mask {
    type Output = Mask;

    #[inline(always)]
    fn bitor(self, o: Mask) -> Mask {
        Mask(std::array::from_fn(|h| self.0[h] | o.0[h]))
    }
}

impl Not for Mask {
    type Output = Mask;

    #[inline(always)]
    fn not(self) -> Mask {
        Mask(self.0.map(|half| !half))
    }
}

/// The old names of the lane types.
pub(crate) type F4 = Floats;
pub(crate) type M4 = Mask;

/// A lane mask from a function of the lane index.
#[inline(always)]
pub(crate) fn mask(f: impl Fn(usize) -> bool) -> Mask {
    Mask(std::array::from_fn(|h| {
        BVec4A::new(f(4 * h), f(4 * h + 1), f(4 * h + 2), f(4 * h + 3))
    }))
}

/// One float per lane from a function of the lane index.
#[inline(always)]
pub(crate) fn gather(f: impl Fn(usize) -> f32) -> Floats {
    Floats(std::array::from_fn(|h| {
        Vec4::new(f(4 * h), f(4 * h + 1), f(4 * h + 2), f(4 * h + 3))
    }))
}

/// One 3-vector per lane.
#[derive(Debug, Clone, Copy)]
pub(crate) struct V3 {
    pub(crate) x: F4,
    pub(crate) y: F4,
    pub(crate) z: F4,
}

impl V3 {
    pub(crate) const ZERO: V3 = V3 {
        x: Floats::ZERO,
        y: Floats::ZERO,
        z: Floats::ZERO,
    };

    /// The same vector in every lane.
    #[inline(always)]
    pub(crate) fn splat(v: Vec3A) -> V3 {
        V3 {
            x: Floats::splat(v.x),
            y: Floats::splat(v.y),
            z: Floats::splat(v.z),
        }
    }

    /// Lane `i` gets `f(i)`.
    #[inline(always)]
    pub(crate) fn gather(f: impl Fn(usize) -> Vec3A) -> V3 {
        let lanes: [Vec3A; LANES] = std::array::from_fn(f);
        V3 {
            x: gather(|i| lanes[i].x),
            y: gather(|i| lanes[i].y),
            z: gather(|i| lanes[i].z),
        }
    }

    /// Lane `i`'s vector.
    #[inline(always)]
    pub(crate) fn lane(&self, i: usize) -> Vec3A {
        Vec3A::new(self.x[i], self.y[i], self.z[i])
    }

    #[inline(always)]
    pub(crate) fn add(self, o: V3) -> V3 {
        V3 {
            x: self.x + o.x,
            y: self.y + o.y,
            z: self.z + o.z,
        }
    }

    #[inline(always)]
    pub(crate) fn sub(self, o: V3) -> V3 {
        V3 {
            x: self.x - o.x,
            y: self.y - o.y,
            z: self.z - o.z,
        }
    }

    #[inline(always)]
    pub(crate) fn scale(self, s: F4) -> V3 {
        V3 {
            x: self.x * s,
            y: self.y * s,
            z: self.z * s,
        }
    }

    #[inline(always)]
    pub(crate) fn dot(self, o: V3) -> F4 {
        self.x * o.x + self.y * o.y + self.z * o.z
    }

    #[inline(always)]
    pub(crate) fn cross(self, o: V3) -> V3 {
        V3 {
            x: self.y * o.z - self.z * o.y,
            y: self.z * o.x - self.x * o.z,
            z: self.x * o.y - self.y * o.x,
        }
    }

    #[inline(always)]
    pub(crate) fn length_squared(self) -> F4 {
        self.dot(self)
    }

    /// Per lane: `a` where `m`, else `b`.
    #[inline(always)]
    pub(crate) fn select(m: M4, a: V3, b: V3) -> V3 {
        V3 {
            x: Floats::select(m, a.x, b.x),
            y: Floats::select(m, a.y, b.y),
            z: Floats::select(m, a.z, b.z),
        }
    }
}

/// One quaternion per lane.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Q4 {
    pub(crate) x: F4,
    pub(crate) y: F4,
    pub(crate) z: F4,
    pub(crate) w: F4,
}

impl Q4 {
    pub(crate) const IDENTITY: Q4 = Q4 {
        x: Floats::ZERO,
        y: Floats::ZERO,
        z: Floats::ZERO,
        w: Floats::ONE,
    };

    /// The same rotation in every lane.
    #[inline(always)]
    pub(crate) fn splat(q: Quat) -> Q4 {
        Q4 {
            x: Floats::splat(q.x),
            y: Floats::splat(q.y),
            z: Floats::splat(q.z),
            w: Floats::splat(q.w),
        }
    }

    /// Lane `i` gets `f(i)`.
    #[inline(always)]
    pub(crate) fn gather(f: impl Fn(usize) -> Quat) -> Q4 {
        let lanes: [Quat; LANES] = std::array::from_fn(f);
        Q4 {
            x: gather(|i| lanes[i].x),
            y: gather(|i| lanes[i].y),
            z: gather(|i| lanes[i].z),
            w: gather(|i| lanes[i].w),
        }
    }

    /// Lane `i` gets `packed[i].unpack()`, bit for bit, computed for the lanes together.
    #[inline(always)]
    pub(crate) fn unpack(packed: [PackedQuat; LANES]) -> Q4 {
        let parts = packed.map(PackedQuat::parts);
        let a = gather(|i| parts[i].0[0]);
        let b = gather(|i| parts[i].0[1]);
        let c = gather(|i| parts[i].0[2]);
        // As PackedQuat::unpack: √max(0, 1 − a² − b² − c²), with the sign of the original.
        let rest = (Floats::ONE - a * a - b * b - c * c)
            .max(Floats::ZERO)
            .sqrt();
        let rebuilt = Floats::select(mask(|i| parts[i].2), -rest, rest);
        // Where the rebuilt component goes: mostly w (rotations up to 90° at least).
        if parts.iter().all(|part| part.1 == 3) {
            return Q4 {
                x: a,
                y: b,
                z: c,
                w: rebuilt,
            };
        }
        let left_out = |index: u32| mask(|i| parts[i].1 == index);
        let (is_x, is_y, is_z, is_w) = (left_out(0), left_out(1), left_out(2), left_out(3));
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
        Quat::from_xyzw(self.x[i], self.y[i], self.z[i], self.w[i])
    }

    /// The rotation whose vector part is `v` and scalar part `w`.
    #[inline(always)]
    pub(crate) fn from_parts(v: V3, w: F4) -> Q4 {
        Q4 {
            x: v.x,
            y: v.y,
            z: v.z,
            w,
        }
    }

    #[inline(always)]
    pub(crate) fn vector(self) -> V3 {
        V3 {
            x: self.x,
            y: self.y,
            z: self.z,
        }
    }

    #[inline(always)]
    pub(crate) fn conjugate(self) -> Q4 {
        Q4 {
            x: -self.x,
            y: -self.y,
            z: -self.z,
            w: self.w,
        }
    }

    #[inline(always)]
    pub(crate) fn dot(self, o: Q4) -> F4 {
        self.x * o.x + self.y * o.y + self.z * o.z + self.w * o.w
    }

    /// The Hamilton product `self * o` (apply `o`, then `self`), as glam's `Quat * Quat`.
    #[inline(always)]
    pub(crate) fn mul(self, o: Q4) -> Q4 {
        Q4 {
            x: self.w * o.x + self.x * o.w + self.y * o.z - self.z * o.y,
            y: self.w * o.y - self.x * o.z + self.y * o.w + self.z * o.x,
            z: self.w * o.z + self.x * o.y - self.y * o.x + self.z * o.w,
            w: self.w * o.w - self.x * o.x - self.y * o.y - self.z * o.z,
        }
    }

    /// `v` rotated by the (unit) quaternion: `v + w t + u × t` with `t = 2 u × v`.
    #[inline(always)]
    pub(crate) fn rotate(self, v: V3) -> V3 {
        let u = self.vector();
        let t = u.cross(v).scale(Floats::splat(2.0));
        v.add(t.scale(self.w)).add(u.cross(t))
    }

    /// The quaternion scaled to unit length.
    #[inline(always)]
    pub(crate) fn normalize(self) -> Q4 {
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
    pub(crate) fn is_identity(self) -> M4 {
        self.x.cmpeq(Floats::ZERO)
            & self.y.cmpeq(Floats::ZERO)
            & self.z.cmpeq(Floats::ZERO)
            & self.w.cmpeq(Floats::ONE)
    }

    /// Per lane: the two rotations equal, component by component (`==`).
    #[inline(always)]
    pub(crate) fn equals(self, o: Q4) -> M4 {
        self.x.cmpeq(o.x) & self.y.cmpeq(o.y) & self.z.cmpeq(o.z) & self.w.cmpeq(o.w)
    }

    /// Per lane: `a` where `m`, else `b`.
    #[inline(always)]
    pub(crate) fn select(m: M4, a: Q4, b: Q4) -> Q4 {
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
pub(crate) fn atan2_upper(y: F4, x: F4) -> F4 {
    let ax = x.abs();
    let swap = y.cmpgt(ax);
    let small = Floats::select(swap, ax, y);
    let large = Floats::select(swap, y, ax);
    let t = small / large;
    let t = Floats::select(large.cmpgt(Floats::ZERO), t, Floats::ZERO);
    let t2 = t * t;
    let mut angle = t
        * (0.999_977_26
            + t2 * (-0.332_623_47
                + t2 * (0.193_543_46
                    + t2 * (-0.116_432_87 + t2 * (0.052_653_32 - t2 * 0.011_721_2)))));
    angle = Floats::select(swap, std::f32::consts::FRAC_PI_2 - angle, angle);
    angle = Floats::select(x.cmplt(Floats::ZERO), std::f32::consts::PI - angle, angle);
    Floats::select(large.cmpgt(Floats::ZERO), angle, Floats::ZERO)
}

/// `(sin x, cos x)` per lane for `x ∈ [0, π/2]` (clamped), errors < 5·10⁻⁶ (Taylor
/// polynomials of degree 9 and 10).
#[inline(always)]
pub(crate) fn sin_cos_quarter(x: F4) -> (F4, F4) {
    let x = x.clamp(Floats::ZERO, Floats::splat(std::f32::consts::FRAC_PI_2));
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
pub(crate) fn interpolate(a: Q4, b: Q4, t: F4) -> Q4 {
    interpolate_or(a, a, b, t)
}

/// Interpolation from `a` to `b` the short way per lane, exactly `at_zero` for `t ≤ 0` (`a`
/// is then not used: callers whose `a` means something only in the lanes under way) and
/// exactly `b` for `t ≥ 1`. In between, a normalised lerp with a corrected parameter that
/// follows slerp's constant angular speed within about 10⁻³ of the angle (A. Kapoulkine,
/// "Approximating slerp", 2015): no trigonometry.
#[inline(always)]
pub(crate) fn interpolate_or(a: Q4, at_zero: Q4, b: Q4, t: F4) -> Q4 {
    let dot = a.dot(b);
    let flip = dot.cmplt(Floats::ZERO);
    let sign = Floats::select(flip, Floats::NEG_ONE, Floats::ONE);
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
    let mixed = Q4::select(t.cmple(Floats::ZERO), at_zero, mixed);
    Q4::select(t.cmpge(Floats::ONE), b, mixed)
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    #[test]
    fn lanes_match_glam() {
        let rotations: [Quat; LANES] = std::array::from_fn(|i| {
            let axis = Vec3::new(1.0, 2.0 - i as f32, 3.0 + i as f32).normalize();
            Quat::from_axis_angle(axis, 0.4 * i as f32 - 1.0)
        });
        let vectors: [Vec3A; LANES] =
            std::array::from_fn(|i| Vec3A::new(0.3 * i as f32, -2.0, 5.0 - i as f32));
        let mirror = |i: usize| LANES - 1 - i;
        let q = Q4::gather(|i| rotations[i]);
        let p = Q4::gather(|i| rotations[mirror(i)]);
        let v = V3::gather(|i| vectors[i]);
        for i in 0..LANES {
            let rotated = q.rotate(v).lane(i);
            assert!(rotated.abs_diff_eq(rotations[i] * vectors[i], 1e-5));
            let product = q.mul(p).lane(i);
            assert!(product.abs_diff_eq(rotations[i] * rotations[mirror(i)], 1e-6));
            let cross = v.cross(V3::splat(Vec3A::Y)).lane(i);
            assert!(cross.abs_diff_eq(vectors[i].cross(Vec3A::Y), 1e-6));
        }
        let t = gather(|i| [0.0, 0.3, 1.0, 0.7][i % 4]);
        let mixed = interpolate(q, p, t);
        for i in 0..LANES {
            match i % 4 {
                0 => assert_eq!(mixed.lane(i), rotations[i]),
                2 => assert_eq!(mixed.lane(i), rotations[mirror(i)]),
                _ => {
                    let expected = rotations[i].slerp(rotations[mirror(i)], t[i]);
                    assert!(mixed.lane(i).angle_between(expected) < 2e-3, "lane {i}");
                }
            }
        }
        assert!(Q4::IDENTITY.is_identity().all());
        let m = mask(|i| i == 2);
        assert!(m.any() && !m.all() && m.test(2) && !m.test(1));
        assert!((!Mask::splat(false)).all());
    }

    #[test]
    fn unpacking_four_lanes_gives_the_bits_of_one() {
        let mut random = crate::math::random::Random::new(23);
        for round in 0..2_000 {
            let packed: [PackedQuat; LANES] = std::array::from_fn(|i| {
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
            let lanes = Q4::unpack(packed);
            for (i, packed) in packed.iter().enumerate() {
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
            let approx = atan2_upper(
                gather(|i| [y, y * 1e-3, y * 250.0, 0.0][i % 4]),
                gather(|i| [x, x * 1e-3, x * 250.0, 0.0][i % 4]),
            );
            for lane in 0..3 {
                worst = worst.max((approx[lane] - y.atan2(x)).abs());
            }
            assert_eq!(approx[3], 0.0);
        }
        assert!(worst < 1.5e-5, "atan2 error {worst}");
        let mut worst: f32 = 0.0;
        for i in 0..=5_000 {
            let x = std::f32::consts::FRAC_PI_2 * i as f32 / 5_000.0;
            let (sin, cos) = sin_cos_quarter(Floats::splat(x));
            worst = worst
                .max((sin[0] - x.sin()).abs())
                .max((cos[0] - x.cos()).abs());
        }
        assert!(worst < 5e-6, "sin/cos error {worst}");
    }
}
