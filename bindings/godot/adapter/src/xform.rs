//! Godot's `Transform` (Godot 3) and `Transform3D` (Godot 4) as plain glam values: a basis
//! whose columns are the local X, Y and Z axes, and an origin. The front ends copy Godot's
//! twelve floats in and out unchanged, so a pose written and read back compares equal.

use glam::{Mat3, Quat, Vec3};

/// An affine transform laid out as Godot's: `basis` (columns: the local axes, possibly
/// scaled) and `origin`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Xform {
    /// The basis: its columns are the transformed X, Y and Z axes.
    pub basis: Mat3,
    /// The translation.
    pub origin: Vec3,
}

impl Default for Xform {
    fn default() -> Self {
        Xform::IDENTITY
    }
}

impl Xform {
    /// No rotation, scale or translation.
    pub const IDENTITY: Xform = Xform {
        basis: Mat3::IDENTITY,
        origin: Vec3::ZERO,
    };

    /// From Godot's layout: the basis as three rows (Godot's `Basis` stores rows) and the
    /// origin.
    pub fn from_rows(rows: [[f32; 3]; 3], origin: [f32; 3]) -> Xform {
        Xform {
            basis: Mat3::from_cols_array_2d(&rows).transpose(),
            origin: Vec3::from_array(origin),
        }
    }

    /// The basis as three rows, as Godot stores it.
    pub fn rows(&self) -> [[f32; 3]; 3] {
        self.basis.transpose().to_cols_array_2d()
    }

    /// A rotation and a translation.
    pub fn from_rotation_translation(rotation: Quat, origin: Vec3) -> Xform {
        Xform {
            basis: Mat3::from_quat(rotation),
            origin,
        }
    }

    /// True if every component is finite.
    pub fn is_finite(&self) -> bool {
        self.basis.is_finite() && self.origin.is_finite()
    }

    /// `self * other`: `other` first, then `self` (Godot's order).
    pub fn mul(&self, other: &Xform) -> Xform {
        Xform {
            basis: self.basis * other.basis,
            origin: self.basis * other.origin + self.origin,
        }
    }

    /// Applies the transform to a point.
    pub fn transform_point(&self, point: Vec3) -> Vec3 {
        self.basis * point + self.origin
    }

    /// The inverse transform (`None` when the basis is singular).
    pub fn inverse(&self) -> Option<Xform> {
        let determinant = self.basis.determinant();
        if !determinant.is_finite() || determinant.abs() < 1e-12 {
            return None;
        }
        let basis = self.basis.inverse();
        Some(Xform {
            basis,
            origin: -(basis * self.origin),
        })
    }

    /// The lengths of the basis' columns: the scale along each local axis.
    pub fn scale(&self) -> Vec3 {
        Vec3::new(
            self.basis.x_axis.length(),
            self.basis.y_axis.length(),
            self.basis.z_axis.length(),
        )
    }

    /// The rotation of the basis, scale removed (Gram–Schmidt from the X axis, as Godot's
    /// `orthonormalized()`); identity for a degenerate basis.
    pub fn rotation(&self) -> Quat {
        rotation_of(&self.basis)
    }
}

/// The rotation of a basis, scale removed (Gram–Schmidt from the X axis); identity for a
/// degenerate basis.
pub fn rotation_of(basis: &Mat3) -> Quat {
    let x = basis.x_axis.normalize_or_zero();
    let y = (basis.y_axis - x * x.dot(basis.y_axis)).normalize_or_zero();
    if x == Vec3::ZERO || y == Vec3::ZERO {
        return Quat::IDENTITY;
    }
    // A mirrored basis (negative determinant) keeps its mirror in the scale: Z is X × Y.
    Quat::from_mat3(&Mat3::from_cols(x, y, x.cross(y))).normalize()
}

/// A basis of rotation `rotation` whose local axes are scaled by `scale`.
pub fn basis_of(rotation: Quat, scale: Vec3) -> Mat3 {
    let basis = Mat3::from_quat(rotation);
    if scale == Vec3::ONE {
        basis
    } else {
        basis * Mat3::from_diagonal(scale)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rows_round_trip_and_products_match_godot() {
        let rows = [[1.0, 2.0, 3.0], [4.0, 5.0, 6.0], [7.0, 8.0, 10.0]];
        let x = Xform::from_rows(rows, [1.0, 2.0, 3.0]);
        assert_eq!(x.rows(), rows);
        // Godot: basis.x (the X column) is (rows[0][0], rows[1][0], rows[2][0]).
        assert_eq!(x.basis.x_axis, Vec3::new(1.0, 4.0, 7.0));
        let inverse = x.inverse().unwrap();
        let identity = x.mul(&inverse);
        assert!(identity.basis.abs_diff_eq(Mat3::IDENTITY, 1e-5));
        assert!(identity.origin.abs_diff_eq(Vec3::ZERO, 1e-5));
        assert!(Xform {
            basis: Mat3::ZERO,
            origin: Vec3::ZERO
        }
        .inverse()
        .is_none());
    }

    #[test]
    fn rotation_ignores_scale() {
        let rotation = Quat::from_euler(glam::EulerRot::YXZ, 0.4, -0.3, 1.2);
        let scaled = Xform {
            basis: basis_of(rotation, Vec3::new(2.0, 0.5, 3.0)),
            origin: Vec3::ONE,
        };
        assert!(
            scaled.rotation().abs_diff_eq(rotation, 1e-6)
                || scaled.rotation().abs_diff_eq(-rotation, 1e-6)
        );
        assert!(scaled.scale().abs_diff_eq(Vec3::new(2.0, 0.5, 3.0), 1e-6));
        let mirrored = Xform {
            basis: basis_of(rotation, Vec3::new(1.0, 1.0, -1.0)),
            origin: Vec3::ZERO,
        };
        let q = mirrored.rotation();
        assert!(
            q.abs_diff_eq(rotation, 1e-5) || q.abs_diff_eq(-rotation, 1e-5),
            "{q}"
        );
        assert_eq!(Xform::default().rotation(), Quat::IDENTITY);
        assert_eq!(rotation_of(&Mat3::ZERO), Quat::IDENTITY);
        assert!(!Xform {
            basis: Mat3::IDENTITY,
            origin: Vec3::NAN
        }
        .is_finite());
    }
}
