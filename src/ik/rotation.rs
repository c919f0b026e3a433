//! Scalar rotation helpers of the gaze IK: the angle between two rotations, and a per-frame
//! angular step limit.

use glam::Quat;

/// The angle (radians, in [0, π]) of the rotation taking `a` to `b`.
#[inline]
pub(crate) fn angle_between(a: Quat, b: Quat) -> f32 {
    2.0 * a.dot(b).abs().min(1.0).acos()
}

/// `to`, or the rotation `max_angle` radians from `from` towards it if `to` is farther:
/// a joint never turns faster than its group's speed limit.
#[inline]
pub(crate) fn step_toward(from: Quat, to: Quat, max_angle: f32) -> Quat {
    let angle = angle_between(from, to);
    if angle <= max_angle {
        return to;
    }
    from.slerp(to, max_angle / angle)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn steps_are_limited() {
        let a = Quat::from_rotation_y(0.2);
        let b = Quat::from_rotation_y(1.2);
        assert!((angle_between(a, b) - 1.0).abs() < 1e-5);
        assert_eq!(step_toward(a, b, 1.5), b);
        let stepped = step_toward(a, b, 0.3);
        assert!((angle_between(a, stepped) - 0.3).abs() < 1e-5);
        assert!((angle_between(stepped, b) - 0.7).abs() < 1e-5);
    }
}
