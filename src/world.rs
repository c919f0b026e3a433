//! World conventions: which way is up and forward, and the caller's length unit.
//!
//! crowdgaze keeps the caller's axes (no re-orientation of positions or joint rotations),
//! but works in metres inside: lengths are divided by `units_per_metre` on the way in and
//! multiplied on the way out. The ground plane is spanned by `forward` and `side = up × forward`;
//! a heading `h` (radians, counter-clockwise about `up`) points along
//! `cos h · forward + sin h · side`.

use glam::{Vec2, Vec3};

use crate::error::{Error, Result};

/// The smallest `units_per_metre` accepted: 0.001, kilometres.
pub const MIN_UNITS_PER_METRE: f32 = 1e-3;
/// The largest `units_per_metre` accepted: 1 000 000, micrometres.
pub const MAX_UNITS_PER_METRE: f32 = 1e6;

/// A signed coordinate axis.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Axis {
    /// +X.
    PositiveX,
    /// −X.
    NegativeX,
    /// +Y.
    PositiveY,
    /// −Y.
    NegativeY,
    /// +Z.
    PositiveZ,
    /// −Z.
    NegativeZ,
}

impl Axis {
    /// The axis as a unit vector.
    pub fn vector(self) -> Vec3 {
        match self {
            Axis::PositiveX => Vec3::X,
            Axis::NegativeX => Vec3::NEG_X,
            Axis::PositiveY => Vec3::Y,
            Axis::NegativeY => Vec3::NEG_Y,
            Axis::PositiveZ => Vec3::Z,
            Axis::NegativeZ => Vec3::NEG_Z,
        }
    }
}

/// The world's orientation and unit, fixed for a crowd's lifetime.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct World {
    /// The axis that points up.
    pub up_axis: Axis,
    /// The axis of heading 0.
    pub forward_axis: Axis,
    /// Unit vector pointing up (against gravity).
    pub up: Vec3,
    /// Unit vector of heading 0, perpendicular to `up`.
    pub forward: Vec3,
    /// `up × forward`: heading +90°.
    pub side: Vec3,
    /// How many of the caller's length units make one metre (1 for metres, 100 for Unreal's
    /// centimetres).
    pub units_per_metre: f32,
}

impl World {
    /// Builds the conventions, checking that `up` and `forward` are perpendicular and the
    /// unit is in [`MIN_UNITS_PER_METRE`, `MAX_UNITS_PER_METRE`].
    pub fn new(up: Axis, forward: Axis, units_per_metre: f32) -> Result<World> {
        let (up_axis, forward_axis) = (up, forward);
        let (up, forward) = (up.vector(), forward.vector());
        if up.dot(forward) != 0.0 {
            return Err(Error::InvalidArgument(
                "up_axis and forward_axis must be perpendicular".into(),
            ));
        }
        crate::error::ensure_finite(units_per_metre, "units_per_metre")?;
        if !(MIN_UNITS_PER_METRE..=MAX_UNITS_PER_METRE).contains(&units_per_metre) {
            return Err(Error::InvalidArgument(format!(
                "units_per_metre is {units_per_metre}, must be in \
                 [{MIN_UNITS_PER_METRE}, {MAX_UNITS_PER_METRE}]"
            )));
        }
        Ok(World {
            up_axis,
            forward_axis,
            up,
            forward,
            side: up.cross(forward),
            units_per_metre,
        })
    }

    /// Y up, +Z forward, metres (glTF's character convention; Godot's models face +Z too).
    pub fn y_up() -> World {
        World::new(Axis::PositiveY, Axis::PositiveZ, 1.0).expect("valid conventions")
    }

    /// A position or length in the caller's units, in metres.
    pub fn to_metres(&self, value: Vec3) -> Vec3 {
        value / self.units_per_metre
    }

    /// A position or length in metres, in the caller's units.
    pub fn from_metres(&self, value: Vec3) -> Vec3 {
        value * self.units_per_metre
    }

    /// The ground-plane coordinates (along `forward`, along `side`) of a point.
    pub fn ground(&self, point: Vec3) -> Vec2 {
        Vec2::new(point.dot(self.forward), point.dot(self.side))
    }

    /// The height of a point above the ground plane through the origin.
    pub fn height(&self, point: Vec3) -> f32 {
        point.dot(self.up)
    }

    /// The world direction of heading `heading` (radians, counter-clockwise about up).
    pub fn heading_direction(&self, heading: f32) -> Vec3 {
        let (sin, cos) = heading.sin_cos();
        self.forward * cos + self.side * sin
    }
}

impl Default for World {
    fn default() -> Self {
        World::y_up()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn heading_is_counter_clockwise_about_up() {
        let world = World::y_up();
        assert!(world.heading_direction(0.0).abs_diff_eq(Vec3::Z, 1e-6));
        // Y up, Z forward: a quarter turn counter-clockwise (seen from above) faces +X.
        let quarter = world.heading_direction(std::f32::consts::FRAC_PI_2);
        assert!(quarter.abs_diff_eq(Vec3::X, 1e-6));
        let z_up = World::new(Axis::PositiveZ, Axis::PositiveY, 1.0).unwrap();
        let quarter = z_up.heading_direction(std::f32::consts::FRAC_PI_2);
        assert!(quarter.abs_diff_eq(Vec3::NEG_X, 1e-6));
    }

    #[test]
    fn bad_conventions_are_rejected() {
        assert!(World::new(Axis::PositiveY, Axis::NegativeY, 1.0).is_err());
        assert!(World::new(Axis::PositiveY, Axis::PositiveZ, 0.0).is_err());
        assert!(World::new(Axis::PositiveY, Axis::PositiveZ, f32::NAN).is_err());
    }

    #[test]
    fn units_convert_both_ways() {
        let unreal = World::new(Axis::PositiveZ, Axis::PositiveX, 100.0).unwrap();
        let metres = unreal.to_metres(Vec3::new(150.0, 0.0, 0.0));
        assert_eq!(metres, Vec3::new(1.5, 0.0, 0.0));
        assert_eq!(unreal.from_metres(metres), Vec3::new(150.0, 0.0, 0.0));
        assert_eq!(unreal.ground(Vec3::new(1.0, 2.0, 3.0)), Vec2::new(1.0, 2.0));
    }
}
