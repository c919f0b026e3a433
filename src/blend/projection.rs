//! The viewer's position from a 3×4 projective camera matrix `P = K[R|t]` (Chaudhuri et al.,
//! §4.2): the camera centre `C` is the right null space of `P` (`P (C, 1) = 0`), which is
//! `C = −M⁻¹ p₄` with `M = K R` the left 3×3 block and `p₄` the last column (`= −Rᵀ t` when
//! `K` is invertible).

use glam::{DMat3, DVec3, Vec3};

use crate::error::{Error, Result};

/// `M` is taken as singular (a camera at infinity, or no camera at all) when
/// `|det M| ≤ SINGULAR · ‖M‖_F³`. A real pinhole camera with a focal length of f pixels has
/// `|det M| / ‖M‖_F³` about `0.35 / f`, far above this.
const SINGULAR: f64 = 1e-9;

/// The centre `C` of the camera `P`, given as 12 floats **row-major** (`p[4 r + c]` is row
/// `r`, column `c`, as OpenCV and Hartley & Zisserman write it). `P` may be scaled by any
/// non-zero factor. `C` is in the units and frame of the world `P` maps from.
///
/// Errors: [`Error::NonFinite`] (a NaN or infinite entry), [`Error::InvalidArgument`] (a
/// degenerate `P`: its left 3×3 block is singular, as for an affine camera or a rank-deficient
/// matrix, or the centre does not fit in f32).
pub fn camera_centre_from_projection(p: &[f32; 12]) -> Result<Vec3> {
    if let Some(bad) = p.iter().find(|v| !v.is_finite()) {
        return Err(Error::NonFinite(format!("P contains {bad}")));
    }
    let entry = |row: usize, column: usize| f64::from(p[4 * row + column]);
    let column = |c: usize| DVec3::new(entry(0, c), entry(1, c), entry(2, c));
    let m = DMat3::from_cols(column(0), column(1), column(2));
    let p4 = column(3);
    let determinant = m.determinant();
    let norm =
        (m.x_axis.length_squared() + m.y_axis.length_squared() + m.z_axis.length_squared()).sqrt();
    if determinant.abs() <= SINGULAR * norm * norm * norm {
        return Err(Error::InvalidArgument(
            "P is degenerate: its left 3x3 block is singular (camera at infinity or rank < 3)"
                .into(),
        ));
    }
    let centre = -(m.inverse() * p4);
    let single = centre.as_vec3();
    if !single.is_finite() {
        return Err(Error::InvalidArgument(format!(
            "the centre of P, {centre}, does not fit in a float"
        )));
    }
    Ok(single)
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::{DVec4, Mat3};

    fn row_major(k: Mat3, r: Mat3, t: Vec3) -> [f32; 12] {
        let m = k * r;
        let kt = k * t;
        let mut p = [0.0; 12];
        for row in 0..3 {
            for col in 0..3 {
                p[4 * row + col] = m.col(col)[row];
            }
            p[4 * row + 3] = kt[row];
        }
        p
    }

    #[test]
    fn centre_is_minus_r_transpose_t() {
        let k = Mat3::from_cols(
            Vec3::new(800.0, 0.0, 0.0),
            Vec3::new(0.0, 780.0, 0.0),
            Vec3::new(320.0, 240.0, 1.0),
        );
        let r = Mat3::from_rotation_y(0.6) * Mat3::from_rotation_x(-0.2);
        let centre = Vec3::new(1.5, 1.7, -4.0);
        let t = -(r * centre);
        let p = row_major(k, r, t);
        let found = camera_centre_from_projection(&p).unwrap();
        assert!((found - centre).length() < 1e-4, "{found}");
        // P C = 0 (the right null space), and scaling P changes nothing.
        let c = DVec4::new(found.x as f64, found.y as f64, found.z as f64, 1.0);
        for row in 0..3 {
            let r = DVec4::new(
                p[4 * row] as f64,
                p[4 * row + 1] as f64,
                p[4 * row + 2] as f64,
                p[4 * row + 3] as f64,
            );
            assert!(r.dot(c).abs() < 1e-4 * r.length(), "row {row}");
        }
        let scaled = p.map(|v| v * -0.001);
        assert!((camera_centre_from_projection(&scaled).unwrap() - centre).length() < 1e-4);
    }

    #[test]
    fn degenerate_cameras_are_rejected() {
        let zero = [0.0; 12];
        assert!(matches!(
            camera_centre_from_projection(&zero),
            Err(Error::InvalidArgument(_))
        ));
        // Affine camera: last row (0, 0, 0, 1).
        let affine = [1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0];
        assert!(matches!(
            camera_centre_from_projection(&affine),
            Err(Error::InvalidArgument(_))
        ));
        let mut nan = affine;
        nan[5] = f32::NAN;
        assert!(matches!(
            camera_centre_from_projection(&nan),
            Err(Error::NonFinite(_))
        ));
    }
}
