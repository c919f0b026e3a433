//! Four blends at once: DLB and DIB computed on four joints side by side, one joint per SIMD
//! lane (structure of arrays), which halves the cost of whole-pose DIB against one joint at a
//! time.
//!
//! [`DualQuat4`] holds one component of four dual quaternions in each `Vec4`. Its `log` and
//! `exp` avoid per-lane branches: the arctangent is Cephes' `atanf` with a selected range
//! reduction, and the sine factors are short series in the squared half angle below 0.25 rad
//! and closed forms above, chosen per lane; `exp` uses longer series, valid up to the largest
//! half angle `log` returns (π/2), and falls back to the scalar [`DualQuat::exp`] beyond.

use glam::{BVec4A, Mat4, Quat, Vec4};

use super::iterative::{DibOutcome, DibSettings};
use crate::math::dualquat::DualQuat;

/// Joints per group.
pub(crate) const LANES: usize = 4;

/// Half angle (radians) below which the lane series are used: their first omitted term is
/// then below 1e−13.
const SERIES_LIMIT: f32 = 0.25;

/// Below this fraction of `Σ w_k`, an aligned sum's real part is taken as cancelled (as in
/// [`super::linear`]).
const CANCELLED_SUM: f32 = 1e-3;

/// Four dual quaternions, one per lane: `rx` holds the real parts' x of all four, and so on.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub(crate) struct DualQuat4 {
    rx: Vec4,
    ry: Vec4,
    rz: Vec4,
    rw: Vec4,
    dx: Vec4,
    dy: Vec4,
    dz: Vec4,
    dw: Vec4,
}

impl DualQuat4 {
    const ZERO: DualQuat4 = DualQuat4 {
        rx: Vec4::ZERO,
        ry: Vec4::ZERO,
        rz: Vec4::ZERO,
        rw: Vec4::ZERO,
        dx: Vec4::ZERO,
        dy: Vec4::ZERO,
        dz: Vec4::ZERO,
        dw: Vec4::ZERO,
    };

    /// The four dual quaternions in lanes 0 to 3.
    #[inline]
    pub(crate) fn gather(q: [DualQuat; LANES]) -> DualQuat4 {
        let real = Mat4::from_cols(
            q[0].real.into(),
            q[1].real.into(),
            q[2].real.into(),
            q[3].real.into(),
        )
        .transpose();
        let dual = Mat4::from_cols(
            q[0].dual.into(),
            q[1].dual.into(),
            q[2].dual.into(),
            q[3].dual.into(),
        )
        .transpose();
        DualQuat4 {
            rx: real.x_axis,
            ry: real.y_axis,
            rz: real.z_axis,
            rw: real.w_axis,
            dx: dual.x_axis,
            dy: dual.y_axis,
            dz: dual.z_axis,
            dw: dual.w_axis,
        }
    }

    /// The four dual quaternions of the lanes.
    #[inline]
    pub(crate) fn scatter(self) -> [DualQuat; LANES] {
        let real = Mat4::from_cols(self.rx, self.ry, self.rz, self.rw).transpose();
        let dual = Mat4::from_cols(self.dx, self.dy, self.dz, self.dw).transpose();
        [
            DualQuat::from_parts(Quat::from_vec4(real.x_axis), Quat::from_vec4(dual.x_axis)),
            DualQuat::from_parts(Quat::from_vec4(real.y_axis), Quat::from_vec4(dual.y_axis)),
            DualQuat::from_parts(Quat::from_vec4(real.z_axis), Quat::from_vec4(dual.z_axis)),
            DualQuat::from_parts(Quat::from_vec4(real.w_axis), Quat::from_vec4(dual.w_axis)),
        ]
    }

    #[inline]
    fn select(mask: BVec4A, a: DualQuat4, b: DualQuat4) -> DualQuat4 {
        DualQuat4 {
            rx: Vec4::select(mask, a.rx, b.rx),
            ry: Vec4::select(mask, a.ry, b.ry),
            rz: Vec4::select(mask, a.rz, b.rz),
            rw: Vec4::select(mask, a.rw, b.rw),
            dx: Vec4::select(mask, a.dx, b.dx),
            dy: Vec4::select(mask, a.dy, b.dy),
            dz: Vec4::select(mask, a.dz, b.dz),
            dw: Vec4::select(mask, a.dw, b.dw),
        }
    }

    /// Each lane scaled by the matching lane of `s`.
    #[inline]
    fn scale(self, s: Vec4) -> DualQuat4 {
        DualQuat4 {
            rx: self.rx * s,
            ry: self.ry * s,
            rz: self.rz * s,
            rw: self.rw * s,
            dx: self.dx * s,
            dy: self.dy * s,
            dz: self.dz * s,
            dw: self.dw * s,
        }
    }

    /// `self + other · s`, lane by lane.
    #[inline]
    fn add_scaled(self, other: DualQuat4, s: Vec4) -> DualQuat4 {
        DualQuat4 {
            rx: self.rx + other.rx * s,
            ry: self.ry + other.ry * s,
            rz: self.rz + other.rz * s,
            rw: self.rw + other.rw * s,
            dx: self.dx + other.dx * s,
            dy: self.dy + other.dy * s,
            dz: self.dz + other.dz * s,
            dw: self.dw + other.dw * s,
        }
    }

    /// `self + other · s` for a pure `other` (scalar parts 0, as `log` returns).
    #[inline]
    fn add_pure_scaled(self, other: DualQuat4, s: Vec4) -> DualQuat4 {
        DualQuat4 {
            rx: self.rx + other.rx * s,
            ry: self.ry + other.ry * s,
            rz: self.rz + other.rz * s,
            dx: self.dx + other.dx * s,
            dy: self.dy + other.dy * s,
            dz: self.dz + other.dz * s,
            ..self
        }
    }

    /// Dot products of the real parts.
    #[inline]
    fn real_dot(self, other: DualQuat4) -> Vec4 {
        self.rx * other.rx + self.ry * other.ry + self.rz * other.rz + self.rw * other.rw
    }

    /// The quaternion conjugate of each lane.
    #[inline]
    fn conjugate(self) -> DualQuat4 {
        DualQuat4 {
            rx: -self.rx,
            ry: -self.ry,
            rz: -self.rz,
            rw: self.rw,
            dx: -self.dx,
            dy: -self.dy,
            dz: -self.dz,
            dw: self.dw,
        }
    }

    /// The dual quaternion product of each lane.
    #[inline]
    fn mul(self, b: DualQuat4) -> DualQuat4 {
        let a = self;
        // real = a.r b.r ; dual = a.r b.d + a.d b.r (Hamilton products, x y z w).
        let product = |(ax, ay, az, aw): (Vec4, Vec4, Vec4, Vec4),
                       (bx, by, bz, bw): (Vec4, Vec4, Vec4, Vec4)| {
            (
                aw * bx + ax * bw + ay * bz - az * by,
                aw * by - ax * bz + ay * bw + az * bx,
                aw * bz + ax * by - ay * bx + az * bw,
                aw * bw - ax * bx - ay * by - az * bz,
            )
        };
        let ar = (a.rx, a.ry, a.rz, a.rw);
        let (rx, ry, rz, rw) = product(ar, (b.rx, b.ry, b.rz, b.rw));
        let (px, py, pz, pw) = product(ar, (b.dx, b.dy, b.dz, b.dw));
        let (qx, qy, qz, qw) = product((a.dx, a.dy, a.dz, a.dw), (b.rx, b.ry, b.rz, b.rw));
        DualQuat4 {
            rx,
            ry,
            rz,
            rw,
            dx: px + qx,
            dy: py + qy,
            dz: pz + qz,
            dw: pw + qw,
        }
    }

    /// The Euclidean length of each lane's 8 components.
    #[inline]
    fn length(self) -> Vec4 {
        (self.rx * self.rx
            + self.ry * self.ry
            + self.rz * self.rz
            + self.rw * self.rw
            + self.dx * self.dx
            + self.dy * self.dy
            + self.dz * self.dz
            + self.dw * self.dw)
            .sqrt()
    }

    /// Each lane made a unit dual quaternion (as [`DualQuat::try_normalize`]; lanes must have
    /// a non-zero real part).
    #[inline]
    fn normalize(self) -> DualQuat4 {
        let inverse = self.real_dot(self).sqrt().recip();
        let unit = self.scale(inverse);
        let along = unit.rx * unit.dx + unit.ry * unit.dy + unit.rz * unit.dz + unit.rw * unit.dw;
        DualQuat4 {
            dx: unit.dx - unit.rx * along,
            dy: unit.dy - unit.ry * along,
            dz: unit.dz - unit.rz * along,
            dw: unit.dw - unit.rw * along,
            ..unit
        }
    }

    /// [`DualQuat::log`] of each lane (the shorter screw; scalar parts of the result 0).
    #[inline]
    fn log(self) -> DualQuat4 {
        // Flip lanes with w < 0 to the other representative.
        let sign = Vec4::select(self.rw.cmplt(Vec4::ZERO), Vec4::NEG_ONE, Vec4::ONE);
        let q = self.scale(sign);
        let sine = (q.rx * q.rx + q.ry * q.ry + q.rz * q.rz).sqrt();
        let cosine = q.rw;
        let half_angle = first_quadrant_atan2(sine, cosine);
        // f1 = a / sin a and f2 = (a cos a − sin a) / sin³ a: by series for small angles
        // (f1 = 1 / g1, f2 = g2 / g1³), directly above (where the series would be long).
        let (g1, g2) = sine_factors(half_angle * half_angle);
        let f1_small = g1.recip();
        let f2_small = g2 * f1_small * f1_small * f1_small;
        let inverse_sine = sine.recip();
        let f1_direct = half_angle * inverse_sine;
        let f2_direct = (f1_direct * cosine - Vec4::ONE) * inverse_sine * inverse_sine;
        let small = half_angle.cmplt(Vec4::splat(SERIES_LIMIT));
        let f1 = Vec4::select(small, f1_small, f1_direct);
        let f2 = Vec4::select(small, f2_small, f2_direct);
        let dual_scale = q.dw * f2;
        DualQuat4 {
            rx: q.rx * f1,
            ry: q.ry * f1,
            rz: q.rz * f1,
            rw: Vec4::ZERO,
            dx: q.dx * f1 + q.rx * dual_scale,
            dy: q.dy * f1 + q.ry * dual_scale,
            dz: q.dz * f1 + q.rz * dual_scale,
            dw: Vec4::ZERO,
        }
    }

    /// [`DualQuat::exp`] of each lane (scalar parts ignored), by series valid for screws up
    /// to [`EXP_LIMIT`] (which covers ScLERP's and DIB's steps); a lane beyond takes the
    /// scalar path.
    #[inline]
    fn exp(self) -> DualQuat4 {
        let angle_squared = self.rx * self.rx + self.ry * self.ry + self.rz * self.rz;
        let g1 = estrin9(angle_squared, &LONG_SINC);
        let g2 = estrin9(angle_squared, &LONG_SINC_DIFFERENCE);
        let cosine = estrin9(angle_squared, &LONG_COS);
        let pitch = self.rx * self.dx + self.ry * self.dy + self.rz * self.dz;
        let pitch_g2 = pitch * g2;
        let mut result = DualQuat4 {
            rx: self.rx * g1,
            ry: self.ry * g1,
            rz: self.rz * g1,
            rw: cosine,
            dx: self.dx * g1 + self.rx * pitch_g2,
            dy: self.dy * g1 + self.ry * pitch_g2,
            dz: self.dz * g1 + self.rz * pitch_g2,
            dw: -pitch * g1,
        };
        let beyond = angle_squared.cmpge(Vec4::splat(EXP_LIMIT * EXP_LIMIT));
        if beyond.any() {
            let lanes = self.scatter();
            let mut exact = result.scatter();
            for (lane, slot) in exact.iter_mut().enumerate() {
                if beyond.test(lane) {
                    *slot = lanes[lane].exp();
                }
            }
            result = DualQuat4::gather(exact);
        }
        result
    }

    /// ScLERP of each lane: `a exp(t log(a* b))`, as [`DualQuat::sclerp`].
    #[inline]
    pub(crate) fn sclerp(self, other: DualQuat4, t: f32) -> DualQuat4 {
        let step = self.conjugate().mul(other).log().scale(Vec4::splat(t));
        self.mul(step.exp()).normalize()
    }
}

/// Largest half angle (radians) of the screws `exp` takes by series: a little above π/2,
/// the largest half angle `log` returns.
const EXP_LIMIT: f32 = 1.6;

/// The series of `exp` in `x = φ²` up to [`EXP_LIMIT`] (first omitted terms below 1e−12).
const LONG_SINC: [f32; 9] = [
    1.0,
    -1.666_666_7e-1,
    8.333_333e-3,
    -1.984_127e-4,
    2.755_732e-6,
    -2.505_210_8e-8,
    1.605_904_4e-10,
    -7.647_164e-13,
    2.811_457_3e-15,
];
const LONG_SINC_DIFFERENCE: [f32; 9] = [
    -3.333_333_3e-1,
    3.333_333_4e-2,
    -1.190_476_2e-3,
    2.204_585_5e-5,
    -2.505_210_8e-7,
    1.927_085_3e-9,
    -1.070_602_9e-11,
    4.498_331_6e-14,
    -1.479_714_3e-16,
];
const LONG_COS: [f32; 9] = [
    1.0,
    -0.5,
    4.166_666_8e-2,
    -1.388_888_9e-3,
    2.480_158_7e-5,
    -2.755_732e-7,
    2.087_675_7e-9,
    -1.147_074_6e-11,
    4.779_477_3e-14,
];

/// `Σ c_i xⁱ` for nine coefficients by Estrin's scheme.
#[inline]
fn estrin9(x: Vec4, c: &[f32; 9]) -> Vec4 {
    let x2 = x * x;
    let x4 = x2 * x2;
    let p01 = Vec4::splat(c[0]) + x * c[1];
    let p23 = Vec4::splat(c[2]) + x * c[3];
    let p45 = Vec4::splat(c[4]) + x * c[5];
    let p67 = Vec4::splat(c[6]) + x * c[7];
    let low = p01 + x2 * p23;
    let high = p45 + x2 * p67;
    low + x4 * (high + x4 * c[8])
}

/// `sin φ / φ` and `(cos φ − sin φ / φ) / φ²` as series in `x = φ²`, for `log` below
/// [`SERIES_LIMIT`] (the first omitted terms are below 1e−13).
const SINC: [f32; 6] = [
    1.0,
    -1.0 / 6.0,
    1.0 / 120.0,
    -1.0 / 5040.0,
    1.0 / 362_880.0,
    -2.505_210_8e-8,
];
const SINC_DIFFERENCE: [f32; 6] = [
    -1.0 / 3.0,
    1.0 / 30.0,
    -1.0 / 840.0,
    1.0 / 45_360.0,
    -1.0 / 3_991_680.0,
    1.927_085_2e-9,
];

/// `Σ c_i xⁱ` by Estrin's scheme (shorter dependency chains than Horner's).
#[inline]
fn estrin(x: Vec4, c: &[f32; 6]) -> Vec4 {
    let x2 = x * x;
    let low = Vec4::splat(c[0]) + x * c[1];
    let middle = Vec4::splat(c[2]) + x * c[3];
    let high = Vec4::splat(c[4]) + x * c[5];
    low + x2 * (middle + x2 * high)
}

#[inline]
fn sine_factors(x: Vec4) -> (Vec4, Vec4) {
    (estrin(x, &SINC), estrin(x, &SINC_DIFFERENCE))
}

/// `atan2(y, x)` lane by lane for `y, x ≥ 0` (see the scalar version in `math::dualquat`).
#[inline]
fn first_quadrant_atan2(y: Vec4, x: Vec4) -> Vec4 {
    use std::f32::consts::{FRAC_PI_2, FRAC_PI_4};
    const TAN_PI_8: f32 = 0.414_213_57;
    const TAN_3PI_8: f32 = 2.414_213_7;
    let low = y.cmple(x * TAN_PI_8);
    let high = y.cmpgt(x * TAN_3PI_8);
    let numerator = Vec4::select(low, y, Vec4::select(high, -x, y - x));
    let denominator = Vec4::select(low, x, Vec4::select(high, y, y + x));
    let base = Vec4::select(
        low,
        Vec4::ZERO,
        Vec4::select(high, Vec4::splat(FRAC_PI_2), Vec4::splat(FRAC_PI_4)),
    );
    // y = x = 0 only for a zero quaternion; keep it finite (angle 0).
    let z = numerator / denominator.max(Vec4::splat(f32::MIN_POSITIVE));
    let z2 = z * z;
    let p = ((z2 * 8.053_744_5e-2 - 1.387_768_6e-1) * z2 + 1.997_771_1e-1) * z2 - 3.333_295e-1;
    base + z + z * z2 * p
}

/// DLB of four joints: `input(k)` gives key `k` of the four, `weights` are checked and shared.
/// Signs align to the first input with a non-zero weight; a lane whose aligned sum cancels is
/// redone by the scalar DLB (which moves its pivot).
#[inline]
pub(crate) fn dlb4(weights: &[f32], input: &impl Fn(usize) -> DualQuat4) -> DualQuat4 {
    // The pivot is the first input with weight: the first one summed.
    let mut pivot = None;
    let mut sum = DualQuat4::ZERO;
    let mut total = 0.0;
    let inverse_total = super::inverse_total(weights);
    for (k, &weight) in weights.iter().enumerate() {
        if weight > 0.0 {
            let weight = super::unit_weight(weight, inverse_total);
            let q = input(k);
            let pivot = *pivot.get_or_insert(q);
            let w = Vec4::splat(weight);
            let signed = Vec4::select(q.real_dot(pivot).cmplt(Vec4::ZERO), -w, w);
            sum = sum.add_scaled(q, signed);
            total += weight;
        }
    }
    let limit = CANCELLED_SUM * total;
    let cancelled = sum.real_dot(sum).cmplt(Vec4::splat(limit * limit));
    if cancelled.any() {
        let mut lanes = sum.normalize().scatter();
        for (lane, slot) in lanes.iter_mut().enumerate() {
            if cancelled.test(lane) {
                *slot = super::linear::dlb_by(weights, |k| input(k).scatter()[lane]);
            }
        }
        return DualQuat4::gather(lanes);
    }
    sum.normalize()
}

/// DIB (Algorithm 1) of four joints at once, each lane stopping when its own `‖x̂‖ < p`:
/// the per-lane results are exactly what [`super::iterative`] documents. `inverse_total` is
/// `1 / Σ w_k`; lanes `lanes_used..4` are padding and ignored.
pub(crate) fn dib4(
    weights: &[f32],
    inverse_total: f64,
    settings: &DibSettings,
    lanes_used: usize,
    input: &impl Fn(usize) -> DualQuat4,
) -> [DibOutcome; LANES] {
    let precision = Vec4::splat(settings.precision);
    let mut blend = dlb4(weights, input);
    let mut best = blend;
    let mut best_residual = Vec4::INFINITY;
    let mut result = blend;
    let mut result_residual = Vec4::ZERO;
    let mut result_iterations = [0u32; LANES];
    let mut done = BVec4A::new(
        lanes_used < 1,
        lanes_used < 2,
        lanes_used < 3,
        lanes_used < 4,
    );
    let mut converged = BVec4A::FALSE;
    for iteration in 1..=settings.max_iterations {
        let inverse = blend.conjugate();
        let mut step = DualQuat4::ZERO;
        for (k, &weight) in weights.iter().enumerate() {
            if weight > 0.0 {
                let w = Vec4::splat(super::unit_weight(weight, inverse_total));
                step = step.add_pure_scaled(inverse.mul(input(k)).log(), w);
            }
        }
        let residual = step.length();
        let improved = residual.cmplt(best_residual);
        best = DualQuat4::select(improved, blend, best);
        best_residual = Vec4::select(improved, residual, best_residual);
        let next = blend.mul(step.exp()).normalize();
        let newly = residual.cmplt(precision) & !done;
        result = DualQuat4::select(newly, next, result);
        result_residual = Vec4::select(newly, residual, result_residual);
        for (lane, iterations) in result_iterations.iter_mut().enumerate() {
            if newly.test(lane) {
                *iterations = iteration;
            }
        }
        converged |= newly;
        done |= newly;
        if done.all() {
            break;
        }
        blend = next;
    }
    let chosen = DualQuat4::select(converged, result, best).scatter();
    let residuals = Vec4::select(converged, result_residual, best_residual).to_array();
    std::array::from_fn(|lane| DibOutcome {
        blend: chosen[lane],
        residual: residuals[lane],
        iterations: if converged.test(lane) {
            result_iterations[lane]
        } else {
            settings.max_iterations
        },
        converged: converged.test(lane),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::random::Random;
    use glam::Vec3;

    fn random_transform(random: &mut Random, angle: f32) -> DualQuat {
        let axis = Vec3::new(
            random.range(-1.0, 1.0),
            random.range(-1.0, 1.0),
            random.range(-1.0, 1.0),
        )
        .try_normalize()
        .unwrap_or(Vec3::X);
        DualQuat::from_rotation_translation(
            Quat::from_axis_angle(axis, random.range(-angle, angle)),
            Vec3::new(random.range(-2.0, 2.0), random.range(-2.0, 2.0), 0.5),
        )
    }

    #[test]
    fn gather_and_scatter_are_inverse() {
        let mut random = Random::new(11);
        let q: [DualQuat; 4] = std::array::from_fn(|_| random_transform(&mut random, 3.0));
        assert_eq!(DualQuat4::gather(q).scatter(), q);
    }

    #[test]
    fn lane_algebra_matches_the_scalar_one() {
        let mut random = Random::new(12);
        for _ in 0..200 {
            let a: [DualQuat; 4] = std::array::from_fn(|_| random_transform(&mut random, 6.0));
            let b: [DualQuat; 4] = std::array::from_fn(|_| random_transform(&mut random, 6.0));
            let (a4, b4) = (DualQuat4::gather(a), DualQuat4::gather(b));
            let product = a4.mul(b4).scatter();
            let log = a4.log().scatter();
            let exp = a4.log().exp().scatter();
            for lane in 0..4 {
                assert!((product[lane] - a[lane] * b[lane]).length() < 1e-5);
                assert!((log[lane] - a[lane].log()).length() < 2e-5, "{:?}", a[lane]);
                let back = exp[lane];
                assert!((back - a[lane]).length() < 2e-5 || (back + a[lane]).length() < 2e-5);
            }
            // Screws beyond the series fall back to the scalar exp.
            let big = a4.log().scale(Vec4::new(1.0, 1.5, 2.0, 0.1)).scatter();
            let exp_big = DualQuat4::gather(big).exp().scatter();
            for lane in 0..4 {
                assert!((exp_big[lane] - big[lane].exp()).length() < 2e-5);
            }
        }
    }

    #[test]
    fn lane_sclerp_matches_the_scalar_one() {
        let mut random = Random::new(13);
        for _ in 0..200 {
            let a: [DualQuat; 4] = std::array::from_fn(|_| random_transform(&mut random, 3.1));
            let b: [DualQuat; 4] = std::array::from_fn(|_| random_transform(&mut random, 3.1));
            for t in [0.0, 0.3, 0.5, 1.0] {
                let lanes = DualQuat4::gather(a)
                    .sclerp(DualQuat4::gather(b), t)
                    .scatter();
                for lane in 0..4 {
                    let scalar = a[lane].sclerp(b[lane], t);
                    let error = (lanes[lane] - scalar)
                        .length()
                        .min((lanes[lane] + scalar).length());
                    assert!(error < 2e-5, "t = {t}: {:?} vs {scalar:?}", lanes[lane]);
                }
            }
        }
    }

    #[test]
    fn lane_atan2_is_accurate() {
        for i in 0..=1000 {
            let angle = std::f32::consts::FRAC_PI_2 * i as f32 / 1000.0;
            let (y, x) = (angle.sin(), angle.cos().max(0.0));
            let lanes = first_quadrant_atan2(Vec4::splat(y), Vec4::splat(x));
            assert!((lanes.x - y.atan2(x)).abs() < 3e-7, "{angle}");
        }
        assert_eq!(first_quadrant_atan2(Vec4::ZERO, Vec4::ZERO), Vec4::ZERO);
    }
}
