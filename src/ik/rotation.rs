//! Small rotation helpers of the gaze IK, written for speed: polynomial arctangent, sine and
//! cosine (errors below 2·10⁻⁵ rad, far under the 0.5° the gaze needs), interpolation that is
//! exact at both ends, and a per-frame angular step limit.

use std::f32::consts::{FRAC_PI_2, PI};

use glam::{Quat, Vec4};

/// `atan2(y, x)` for `y ≥ 0`, in [0, π]; 0 when both are 0. Absolute error < 1.5·10⁻⁵ rad
/// (a minimax polynomial of degree 11 on [0, 1]).
#[inline]
pub(crate) fn atan2_upper(y: f32, x: f32) -> f32 {
    let ax = x.abs();
    let (small, large) = if y > ax { (ax, y) } else { (y, ax) };
    if large <= 0.0 {
        return 0.0;
    }
    let t = small / large;
    let t2 = t * t;
    let mut angle = t
        * (0.999_977_26
            + t2 * (-0.332_623_47
                + t2 * (0.193_543_46
                    + t2 * (-0.116_432_87 + t2 * (0.052_653_32 - t2 * 0.011_721_2)))));
    if y > ax {
        angle = FRAC_PI_2 - angle;
    }
    if x < 0.0 {
        angle = PI - angle;
    }
    angle
}

/// `(sin x, cos x)` for `x ∈ [0, π/2]` (clamped), errors < 5·10⁻⁶ (Taylor polynomials of
/// degree 9 and 10).
#[inline]
pub(crate) fn sin_cos_quarter(x: f32) -> (f32, f32) {
    let x = x.clamp(0.0, FRAC_PI_2);
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

/// The angle (radians, in [0, π]) of the rotation taking `a` to `b`.
#[inline]
pub(crate) fn angle_between(a: Quat, b: Quat) -> f32 {
    2.0 * a.dot(b).abs().min(1.0).acos()
}

/// Interpolation from `a` to `b` the short way, returning exactly `a` for `t ≤ 0` and
/// exactly `b` for `t ≥ 1`. In between, a normalised lerp with a corrected parameter that
/// follows slerp's constant angular speed within about 10⁻³ of the angle (A. Kapoulkine,
/// "Approximating slerp", 2015): no trigonometry.
#[inline]
pub(crate) fn interpolate(a: Quat, b: Quat, t: f32) -> Quat {
    if t <= 0.0 {
        return a;
    }
    if t >= 1.0 {
        return b;
    }
    let dot = a.dot(b);
    let (b, d) = if dot < 0.0 { (-b, -dot) } else { (b, dot) };
    let k_a = 1.0904 + d * (-3.2452 + d * (3.55645 - d * 1.43519));
    let k_b = 0.848_013 + d * (-1.06021 + d * 0.215_638);
    let k = k_a * (t - 0.5) * (t - 0.5) + k_b;
    let corrected = t + t * (t - 0.5) * (t - 1.0) * k;
    let mixed = Vec4::from(a) + (Vec4::from(b) - Vec4::from(a)) * corrected;
    Quat::from_vec4(mixed * mixed.length_recip())
}

/// `to`, or the rotation `max_angle` radians from `from` towards it if `to` is farther:
/// a joint never turns faster than its group's speed limit. Trigonometry only when the
/// limit binds.
#[inline]
pub(crate) fn step_toward(from: Quat, to: Quat, max_angle: f32) -> Quat {
    let dot = from.dot(to).abs().min(1.0);
    // angle = 2 acos(dot) ≤ max ⟺ 1 − dot ≤ 1 − cos(max/2); 1 − cos h ≥ h²/2 − h⁴/24.
    let half = 0.5 * max_angle;
    let half_squared = half * half;
    if 1.0 - dot <= half_squared * (0.5 - half_squared / 24.0) {
        return to;
    }
    let angle = 2.0 * dot.acos();
    if angle <= max_angle {
        return to;
    }
    from.slerp(to, max_angle / angle)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn polynomials_are_accurate() {
        let mut worst: f32 = 0.0;
        for i in 0..=20_000 {
            let angle = PI * i as f32 / 20_000.0;
            for radius in [1e-3f32, 1.0, 250.0] {
                let (y, x) = (angle.sin() * radius, angle.cos() * radius);
                worst = worst.max((atan2_upper(y.max(0.0), x) - y.max(0.0).atan2(x)).abs());
            }
        }
        assert!(worst < 1.5e-5, "atan2 error {worst}");
        assert_eq!(atan2_upper(0.0, 0.0), 0.0);
        assert_eq!(atan2_upper(0.0, 1.0), 0.0);
        let mut worst: f32 = 0.0;
        for i in 0..=10_000 {
            let x = FRAC_PI_2 * i as f32 / 10_000.0;
            let (sin, cos) = sin_cos_quarter(x);
            worst = worst.max((sin - x.sin()).abs()).max((cos - x.cos()).abs());
        }
        assert!(worst < 5e-6, "sin/cos error {worst}");
        assert_eq!(sin_cos_quarter(0.0), (0.0, 1.0));
    }

    #[test]
    fn interpolation_and_steps() {
        let a = Quat::from_rotation_y(0.2);
        let b = Quat::from_rotation_y(1.2);
        assert_eq!(interpolate(a, b, 0.0), a);
        assert_eq!(interpolate(a, b, 1.0), b);
        for i in 1..10 {
            let t = i as f32 / 10.0;
            let q = interpolate(a, b, t);
            assert!((angle_between(a, q) - t).abs() < 2e-3, "{t}");
            assert!((q.length() - 1.0).abs() < 1e-6);
        }
        // The short way even when the quaternions are on opposite hemispheres.
        let q = interpolate(a, -b, 0.5);
        assert!((angle_between(a, q) - 0.5).abs() < 2e-3);
        assert_eq!(step_toward(a, b, 1.5), b);
        let stepped = step_toward(a, b, 0.3);
        assert!((angle_between(a, stepped) - 0.3).abs() < 1e-5);
        assert!((angle_between(stepped, b) - 0.7).abs() < 1e-5);
    }
}
