//! 3-vectors ([`V3`]) and quaternions ([`Q4`]) in lanes, with glam's formulas, operation
//! for operation.

// The gathers fill several per-lane rows with one lane index.
#![allow(clippy::needless_range_loop)]

use glam::{Quat, Vec3A};

use super::{mask, Floats, Mask, MAX_LANES};
use crate::math::packed::PackedQuat;
use crate::math::wide::Wide;

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

    /// Each component scaled by the matching lane of `s`.
    #[inline(always)]
    pub(crate) fn scale(self, s: Floats<W>) -> Q4<W> {
        Q4 {
            x: self.x * s,
            y: self.y * s,
            z: self.z * s,
            w: self.w * s,
        }
    }

    /// `self + o · s`, component by component.
    #[inline(always)]
    pub(crate) fn add_scaled(self, o: Q4<W>, s: Floats<W>) -> Q4<W> {
        Q4 {
            x: self.x + o.x * s,
            y: self.y + o.y * s,
            z: self.z + o.z * s,
            w: self.w + o.w * s,
        }
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
