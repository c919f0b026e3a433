//! Plain data types shared by the whole C API: vectors, quaternions, dual quaternions, axes.

use glam::{Quat, Vec3};

use crate::error::{ensure_all_finite, Result};
use crate::world::Axis;

/// A 3-component vector of floats: a position (in the caller's units, see
/// `cg_crowd_config.units_per_metre`) or a direction.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct cg_vec3 {
    /// First component.
    pub x: f32,
    /// Second component.
    pub y: f32,
    /// Third component.
    pub z: f32,
}

/// A rotation quaternion, components in the order **x, y, z, w** (vector part first, scalar
/// last, as glam, Eigen's storage, Unreal's FQuat and Godot's Quaternion lay them out; OSG's
/// osg::Quat is x, y, z, w too). The identity is {0, 0, 0, 1}. Inputs should be unit length;
/// crowdgaze normalises them and rejects zero-length or non-finite ones.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct cg_quat {
    /// Vector part, x.
    pub x: f32,
    /// Vector part, y.
    pub y: f32,
    /// Vector part, z.
    pub z: f32,
    /// Scalar part.
    pub w: f32,
}

/// A dual quaternion `real + ε dual` describing a rigid transform: `real` is the rotation,
/// `dual = ½ (0, t) ⊗ real` encodes the translation t. Both parts use the x, y, z, w order.
/// Translations are at most 1e18 of your length units long (a longer one is
/// `CG_STATUS_INVALID_ARGUMENT`), so that blending and converting cannot overflow a float.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct cg_dualquat {
    /// Rotation part (unit quaternion).
    pub real: cg_quat,
    /// Translation part, `½ (0, t) ⊗ real`.
    pub dual: cg_quat,
}

/// A signed world axis, used to state which way is up and which way is forward.
#[repr(u32)]
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum cg_axis {
    /// +X.
    PositiveX = 0,
    /// −X.
    NegativeX = 1,
    /// +Y.
    PositiveY = 2,
    /// −Y.
    NegativeY = 3,
    /// +Z.
    PositiveZ = 4,
    /// −Z.
    NegativeZ = 5,
}

impl cg_axis {
    /// Converts a `uint32_t` from C into an [`Axis`], rejecting unknown values.
    pub(crate) fn parse(value: u32, what: &str) -> Result<Axis> {
        let axis = match value {
            0 => Axis::PositiveX,
            1 => Axis::NegativeX,
            2 => Axis::PositiveY,
            3 => Axis::NegativeY,
            4 => Axis::PositiveZ,
            5 => Axis::NegativeZ,
            other => {
                return Err(crate::error::Error::InvalidArgument(format!(
                    "{what} is {other}, not a cg_axis"
                )))
            }
        };
        Ok(axis)
    }

    /// The C value of an [`Axis`].
    pub(crate) fn from_axis(axis: Axis) -> u32 {
        (match axis {
            Axis::PositiveX => cg_axis::PositiveX,
            Axis::NegativeX => cg_axis::NegativeX,
            Axis::PositiveY => cg_axis::PositiveY,
            Axis::NegativeY => cg_axis::NegativeY,
            Axis::PositiveZ => cg_axis::PositiveZ,
            Axis::NegativeZ => cg_axis::NegativeZ,
        }) as u32
    }
}

impl cg_vec3 {
    /// Converts to glam after checking every component is finite.
    pub(crate) fn to_finite(self, what: &str) -> Result<Vec3> {
        ensure_all_finite(&[self.x, self.y, self.z], what)?;
        Ok(Vec3::new(self.x, self.y, self.z))
    }
}

impl From<Vec3> for cg_vec3 {
    fn from(v: Vec3) -> Self {
        cg_vec3 {
            x: v.x,
            y: v.y,
            z: v.z,
        }
    }
}

impl cg_quat {
    /// The identity rotation (not exported: C++17 has no designated initializers).
    /// cbindgen:ignore
    pub const IDENTITY: cg_quat = cg_quat {
        x: 0.0,
        y: 0.0,
        z: 0.0,
        w: 1.0,
    };

    /// Converts to a normalised glam quaternion after checking it is finite and not zero.
    pub(crate) fn to_unit(self, what: &str) -> Result<Quat> {
        ensure_all_finite(&[self.x, self.y, self.z, self.w], what)?;
        let q = Quat::from_xyzw(self.x, self.y, self.z, self.w);
        let length = q.length();
        if length.is_nan() || length <= 1e-6 || !length.is_finite() {
            return Err(crate::error::Error::InvalidArgument(format!(
                "{what} has length {length}, not a rotation"
            )));
        }
        Ok(q / length)
    }
}

impl From<Quat> for cg_quat {
    fn from(q: Quat) -> Self {
        cg_quat {
            x: q.x,
            y: q.y,
            z: q.z,
            w: q.w,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quaternions_are_normalised_and_checked() {
        let q = cg_quat {
            x: 0.0,
            y: 0.0,
            z: 0.0,
            w: 2.0,
        };
        assert_eq!(q.to_unit("q").unwrap(), Quat::IDENTITY);
        let zero = cg_quat {
            x: 0.0,
            y: 0.0,
            z: 0.0,
            w: 0.0,
        };
        assert!(zero.to_unit("q").is_err());
        let nan = cg_quat { x: f32::NAN, ..q };
        assert!(matches!(
            nan.to_unit("q"),
            Err(crate::error::Error::NonFinite(_))
        ));
    }

    #[test]
    fn axes_round_trip() {
        for value in 0..6 {
            let axis = cg_axis::parse(value, "axis").unwrap();
            assert_eq!(cg_axis::from_axis(axis), value);
        }
        assert!(cg_axis::parse(6, "axis").is_err());
    }
}
