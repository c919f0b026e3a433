//! Four characters at once: vectors, quaternions and the gaze IK's rotation helpers in
//! structure-of-arrays form, one character per SIMD lane (glam's `Vec4`: SSE2 on x86-64,
//! plain floats elsewhere).
//!
//! The gaze solve is a chain of dependent steps (each joint waits for the one below it), so
//! one character leaves the processor mostly idle; four characters in the four lanes of the
//! same instructions run at nearly the cost of one. Branches become lane masks: both sides
//! are computed when the lanes disagree and the right one is selected per lane.

use glam::{BVec4A, Quat, Vec3A, Vec4};

/// Number of characters processed together.
pub(crate) const LANES: usize = 4;

/// One float per lane.
pub(crate) type F4 = Vec4;
/// One boolean per lane.
pub(crate) type M4 = BVec4A;

/// A lane mask from a function of the lane index.
#[inline(always)]
pub(crate) fn mask(f: impl Fn(usize) -> bool) -> M4 {
    BVec4A::new(f(0), f(1), f(2), f(3))
}

/// One float per lane from a function of the lane index.
#[inline(always)]
pub(crate) fn gather(f: impl Fn(usize) -> f32) -> F4 {
    Vec4::new(f(0), f(1), f(2), f(3))
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
        x: Vec4::ZERO,
        y: Vec4::ZERO,
        z: Vec4::ZERO,
    };

    /// The same vector in every lane.
    #[inline(always)]
    pub(crate) fn splat(v: Vec3A) -> V3 {
        V3 {
            x: Vec4::splat(v.x),
            y: Vec4::splat(v.y),
            z: Vec4::splat(v.z),
        }
    }

    /// Lane `i` gets `f(i)`.
    #[inline(always)]
    pub(crate) fn gather(f: impl Fn(usize) -> Vec3A) -> V3 {
        let (a, b, c, d) = (f(0), f(1), f(2), f(3));
        V3 {
            x: Vec4::new(a.x, b.x, c.x, d.x),
            y: Vec4::new(a.y, b.y, c.y, d.y),
            z: Vec4::new(a.z, b.z, c.z, d.z),
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
            x: Vec4::select(m, a.x, b.x),
            y: Vec4::select(m, a.y, b.y),
            z: Vec4::select(m, a.z, b.z),
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
        x: Vec4::ZERO,
        y: Vec4::ZERO,
        z: Vec4::ZERO,
        w: Vec4::ONE,
    };

    /// The same rotation in every lane.
    #[inline(always)]
    pub(crate) fn splat(q: Quat) -> Q4 {
        Q4 {
            x: Vec4::splat(q.x),
            y: Vec4::splat(q.y),
            z: Vec4::splat(q.z),
            w: Vec4::splat(q.w),
        }
    }

    /// Lane `i` gets `f(i)`.
    #[inline(always)]
    pub(crate) fn gather(f: impl Fn(usize) -> Quat) -> Q4 {
        let (a, b, c, d) = (f(0), f(1), f(2), f(3));
        Q4 {
            x: Vec4::new(a.x, b.x, c.x, d.x),
            y: Vec4::new(a.y, b.y, c.y, d.y),
            z: Vec4::new(a.z, b.z, c.z, d.z),
            w: Vec4::new(a.w, b.w, c.w, d.w),
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
        let t = u.cross(v).scale(Vec4::splat(2.0));
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
        self.x.cmpeq(Vec4::ZERO)
            & self.y.cmpeq(Vec4::ZERO)
            & self.z.cmpeq(Vec4::ZERO)
            & self.w.cmpeq(Vec4::ONE)
    }

    /// Per lane: the two rotations bit for bit equal (well, `==` on each component).
    #[inline(always)]
    pub(crate) fn bits_equal(self, o: Q4) -> M4 {
        self.x.cmpeq(o.x) & self.y.cmpeq(o.y) & self.z.cmpeq(o.z) & self.w.cmpeq(o.w)
    }

    /// Per lane: `a` where `m`, else `b`.
    #[inline(always)]
    pub(crate) fn select(m: M4, a: Q4, b: Q4) -> Q4 {
        Q4 {
            x: Vec4::select(m, a.x, b.x),
            y: Vec4::select(m, a.y, b.y),
            z: Vec4::select(m, a.z, b.z),
            w: Vec4::select(m, a.w, b.w),
        }
    }
}

/// `atan2(y, x)` per lane for `y ≥ 0`, in [0, π]; 0 when both are 0. Absolute error
/// < 1.5·10⁻⁵ rad (a minimax polynomial of degree 11 on [0, 1]).
#[inline(always)]
pub(crate) fn atan2_upper(y: F4, x: F4) -> F4 {
    let ax = x.abs();
    let swap = y.cmpgt(ax);
    let small = Vec4::select(swap, ax, y);
    let large = Vec4::select(swap, y, ax);
    let t = small / large;
    let t = Vec4::select(large.cmpgt(Vec4::ZERO), t, Vec4::ZERO);
    let t2 = t * t;
    let mut angle = t
        * (0.999_977_26
            + t2 * (-0.332_623_47
                + t2 * (0.193_543_46
                    + t2 * (-0.116_432_87 + t2 * (0.052_653_32 - t2 * 0.011_721_2)))));
    angle = Vec4::select(swap, std::f32::consts::FRAC_PI_2 - angle, angle);
    angle = Vec4::select(x.cmplt(Vec4::ZERO), std::f32::consts::PI - angle, angle);
    Vec4::select(large.cmpgt(Vec4::ZERO), angle, Vec4::ZERO)
}

/// `(sin x, cos x)` per lane for `x ∈ [0, π/2]` (clamped), errors < 5·10⁻⁶ (Taylor
/// polynomials of degree 9 and 10).
#[inline(always)]
pub(crate) fn sin_cos_quarter(x: F4) -> (F4, F4) {
    let x = x.clamp(Vec4::ZERO, Vec4::splat(std::f32::consts::FRAC_PI_2));
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

/// Interpolation from `a` to `b` the short way per lane, exactly `a` for `t ≤ 0` and exactly
/// `b` for `t ≥ 1`. In between, a normalised lerp with a corrected parameter that follows
/// slerp's constant angular speed within about 10⁻³ of the angle (A. Kapoulkine,
/// "Approximating slerp", 2015): no trigonometry.
#[inline(always)]
pub(crate) fn interpolate(a: Q4, b: Q4, t: F4) -> Q4 {
    let dot = a.dot(b);
    let flip = dot.cmplt(Vec4::ZERO);
    let sign = Vec4::select(flip, Vec4::NEG_ONE, Vec4::ONE);
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
    let mixed = Q4::select(t.cmple(Vec4::ZERO), a, mixed);
    Q4::select(t.cmpge(Vec4::ONE), b, mixed)
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    #[test]
    fn lanes_match_glam() {
        let rotations = [
            Quat::from_rotation_y(0.3),
            Quat::from_axis_angle(Vec3::new(1.0, 2.0, 3.0).normalize(), 2.0),
            Quat::from_rotation_x(-1.0),
            Quat::IDENTITY,
        ];
        let vectors = [Vec3A::X, Vec3A::new(0.3, -2.0, 5.0), Vec3A::Z, Vec3A::ONE];
        let q = Q4::gather(|i| rotations[i]);
        let p = Q4::gather(|i| rotations[3 - i]);
        let v = V3::gather(|i| vectors[i]);
        for i in 0..LANES {
            assert!(q
                .rotate(v)
                .lane(i)
                .abs_diff_eq(rotations[i] * vectors[i], 1e-5));
            assert!(q
                .mul(p)
                .lane(i)
                .abs_diff_eq(rotations[i] * rotations[3 - i], 1e-6));
            let cross = v.cross(V3::splat(Vec3A::Y)).lane(i);
            assert!(cross.abs_diff_eq(vectors[i].cross(Vec3A::Y), 1e-6));
        }
        let t = Vec4::new(0.0, 0.3, 1.0, 0.7);
        let mixed = interpolate(q, p, t);
        assert_eq!(mixed.lane(0), rotations[0]);
        assert_eq!(mixed.lane(2), rotations[1]);
        for i in [1, 3] {
            let expected = rotations[i].slerp(rotations[3 - i], t[i]);
            assert!(mixed.lane(i).angle_between(expected) < 2e-3, "lane {i}");
        }
        assert!(Q4::IDENTITY.is_identity().all());
    }

    #[test]
    fn polynomials_are_accurate() {
        let mut worst: f32 = 0.0;
        for i in 0..=5_000 {
            let angle = std::f32::consts::PI * i as f32 / 5_000.0;
            let (y, x) = (angle.sin().max(0.0), angle.cos());
            let approx = atan2_upper(
                Vec4::new(y, y * 1e-3, y * 250.0, 0.0),
                Vec4::new(x, x * 1e-3, x * 250.0, 0.0),
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
            let (sin, cos) = sin_cos_quarter(Vec4::splat(x));
            worst = worst
                .max((sin[0] - x.sin()).abs())
                .max((cos[0] - x.cos()).abs());
        }
        assert!(worst < 5e-6, "sin/cos error {worst}");
    }
}
