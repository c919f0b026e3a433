//! The gaze IK's lane helpers: the arctangent, sine and cosine and the rotation
//! interpolation it needs, one character per SIMD lane, on the lane types of
//! [`crate::math::lanes`]. Everything here is `#[inline(always)]`: it must be compiled inside
//! the instruction-set-specific functions that run it.

use crate::math::lanes::{Floats, Q4};
use crate::math::wide::Wide;

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
    use crate::math::lanes::{gather, MAX_LANES};
    use crate::math::wide::for_every_width;
    use glam::{Quat, Vec3, Vec4};

    #[test]
    fn interpolation_follows_slerp() {
        for_every_width!(interpolation_at());
    }

    fn interpolation_at<W: Wide>() {
        let rotations: [Quat; MAX_LANES] = std::array::from_fn(|i| {
            let axis = Vec3::new(1.0, 2.0 - i as f32, 3.0 + i as f32).normalize();
            Quat::from_axis_angle(axis, 0.4 * i as f32 - 1.0)
        });
        let mirror = |i: usize| W::LANES - 1 - i;
        let q = Q4::<W>::gather(|i| rotations[i]);
        let p = Q4::gather(|i| rotations[mirror(i)]);
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
