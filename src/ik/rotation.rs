//! Small rotation helpers of the gaze IK: axis-angle construction, the angle between two
//! rotations, interpolation that is exact at both ends, and a per-frame angular step limit.

use glam::{Quat, Vec3A};

/// The rotation of `angle` radians about the unit `axis`.
#[inline]
pub(crate) fn axis_angle(axis: Vec3A, angle: f32) -> Quat {
    let (sin, cos) = (0.5 * angle).sin_cos();
    let v = axis * sin;
    Quat::from_xyzw(v.x, v.y, v.z, cos)
}

/// The angle (radians, in [0, π]) of the rotation taking `a` to `b`.
#[inline]
pub(crate) fn angle_between(a: Quat, b: Quat) -> f32 {
    2.0 * a.dot(b).abs().min(1.0).acos()
}

/// Spherical interpolation from `a` to `b` (the short way), returning exactly `a` for
/// `t ≤ 0` and exactly `b` for `t ≥ 1`.
#[inline]
pub(crate) fn interpolate(a: Quat, b: Quat, t: f32) -> Quat {
    if t <= 0.0 {
        a
    } else if t >= 1.0 {
        b
    } else {
        a.slerp(b, t)
    }
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
    use glam::Vec3;

    #[test]
    fn steps_are_limited_and_ends_exact() {
        let a = Quat::from_rotation_y(0.2);
        let b = Quat::from_rotation_y(1.2);
        assert_eq!(interpolate(a, b, 0.0), a);
        assert_eq!(interpolate(a, b, 1.0), b);
        assert!((angle_between(a, interpolate(a, b, 0.25)) - 0.25).abs() < 1e-5);
        assert_eq!(step_toward(a, b, 1.5), b);
        let stepped = step_toward(a, b, 0.3);
        assert!((angle_between(a, stepped) - 0.3).abs() < 1e-5);
        assert!((angle_between(stepped, b) - 0.7).abs() < 1e-5);
        let q = axis_angle(Vec3A::X, 0.5);
        assert!(q.abs_diff_eq(Quat::from_axis_angle(Vec3::X, 0.5), 1e-6));
    }
}
