//! Many blends at once: DLB and DIB computed on several joints side by side, one joint per
//! SIMD lane (structure of arrays), 4, 8 or 16 at a time (`math::wide::run_widest` picks the
//! width).
//!
//! [`DualQuatLanes`] holds one component of `W::LANES` dual quaternions in each lane vector
//! (see [`crate::math::wide`]). Its `log` and `exp` avoid per-lane branches: the arctangent is
//! Cephes' `atanf` with a selected range reduction, and the factors `a / sin a` and
//! `(a cos a − sin a) / sin³ a` are polynomials in the squared half angle fitted over 0 to π/2
//! (no division); `exp` uses series valid up to the largest half angle `log` returns (π/2),
//! and falls back to the scalar [`DualQuat::exp`] beyond. Every lane computes the same
//! operations whatever the width, so a joint's blend does not depend on the width or on its
//! neighbours.

use glam::Quat;

use super::iterative::{DibOutcome, DibSettings};
use super::linear::CANCELLED_SUM;
use crate::math::dualquat::DualQuat;
use crate::math::wide::{Wide, MAX_LANES};

/// `W::LANES` dual quaternions, one per lane: `rx` holds the real parts' x of all of them,
/// and so on.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct DualQuatLanes<W> {
    rx: W,
    ry: W,
    rz: W,
    rw: W,
    dx: W,
    dy: W,
    dz: W,
    dw: W,
}

impl<W: Wide> DualQuatLanes<W> {
    /// Zero in every lane.
    #[inline(always)]
    pub(crate) fn zero() -> Self {
        let zero = W::splat(0.0);
        DualQuatLanes {
            rx: zero,
            ry: zero,
            rz: zero,
            rw: zero,
            dx: zero,
            dy: zero,
            dz: zero,
            dw: zero,
        }
    }

    /// Lane `i` holds `q(i)`.
    #[inline(always)]
    pub(crate) fn gather(q: impl Fn(usize) -> DualQuat) -> Self {
        let [rx, ry, rz, rw, dx, dy, dz, dw] = W::transpose_in(|lane| {
            let q = q(lane);
            let (r, d) = (q.real, q.dual);
            [r.x, r.y, r.z, r.w, d.x, d.y, d.z, d.w]
        });
        DualQuatLanes {
            rx,
            ry,
            rz,
            rw,
            dx,
            dy,
            dz,
            dw,
        }
    }

    /// `f(i, q)` for the dual quaternion `q` of each lane `i`.
    #[inline(always)]
    pub(crate) fn scatter(self, mut f: impl FnMut(usize, DualQuat)) {
        let rows = [
            self.rx, self.ry, self.rz, self.rw, self.dx, self.dy, self.dz, self.dw,
        ];
        W::transpose_out(rows, |lane, [rx, ry, rz, rw, dx, dy, dz, dw]| {
            f(
                lane,
                DualQuat::from_parts(
                    Quat::from_xyzw(rx, ry, rz, rw),
                    Quat::from_xyzw(dx, dy, dz, dw),
                ),
            )
        });
    }

    /// The dual quaternion of lane `i`.
    #[inline(always)]
    pub(crate) fn lane(self, i: usize) -> DualQuat {
        DualQuat::from_parts(
            Quat::from_xyzw(
                self.rx.lane(i),
                self.ry.lane(i),
                self.rz.lane(i),
                self.rw.lane(i),
            ),
            Quat::from_xyzw(
                self.dx.lane(i),
                self.dy.lane(i),
                self.dz.lane(i),
                self.dw.lane(i),
            ),
        )
    }

    /// Lanes replaced by `f(i, lane i)` where `mask` is set (the slow path of rare lanes).
    #[inline(never)]
    fn replace_lanes(self, mask: W::Mask, f: impl Fn(usize, DualQuat) -> DualQuat) -> Self {
        Self::gather(|i| {
            let q = self.lane(i);
            if W::test(mask, i) {
                f(i, q)
            } else {
                q
            }
        })
    }

    #[inline(always)]
    fn select(mask: W::Mask, a: Self, b: Self) -> Self {
        DualQuatLanes {
            rx: W::select(mask, a.rx, b.rx),
            ry: W::select(mask, a.ry, b.ry),
            rz: W::select(mask, a.rz, b.rz),
            rw: W::select(mask, a.rw, b.rw),
            dx: W::select(mask, a.dx, b.dx),
            dy: W::select(mask, a.dy, b.dy),
            dz: W::select(mask, a.dz, b.dz),
            dw: W::select(mask, a.dw, b.dw),
        }
    }

    /// Each lane scaled by the matching lane of `s`.
    #[inline(always)]
    fn scale(self, s: W) -> Self {
        DualQuatLanes {
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
    #[inline(always)]
    fn add_scaled(self, other: Self, s: W) -> Self {
        DualQuatLanes {
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
    #[inline(always)]
    fn add_pure_scaled(self, other: Self, s: W) -> Self {
        DualQuatLanes {
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
    #[inline(always)]
    fn real_dot(self, other: Self) -> W {
        self.rx * other.rx + self.ry * other.ry + self.rz * other.rz + self.rw * other.rw
    }

    /// The quaternion conjugate of each lane.
    #[inline(always)]
    fn conjugate(self) -> Self {
        DualQuatLanes {
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
    #[inline(always)]
    fn mul(self, b: Self) -> Self {
        let a = self;
        // real = a.r b.r ; dual = a.r b.d + a.d b.r.
        let ar = (a.rx, a.ry, a.rz, a.rw);
        let (rx, ry, rz, rw) = hamilton(ar, (b.rx, b.ry, b.rz, b.rw));
        let (px, py, pz, pw) = hamilton(ar, (b.dx, b.dy, b.dz, b.dw));
        let (qx, qy, qz, qw) = hamilton((a.dx, a.dy, a.dz, a.dw), (b.rx, b.ry, b.rz, b.rw));
        DualQuatLanes {
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
    #[inline(always)]
    fn length(self) -> W {
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
    #[inline(always)]
    fn normalize(self) -> Self {
        let inverse = self.real_dot(self).sqrt().recip();
        let unit = self.scale(inverse);
        let along = unit.rx * unit.dx + unit.ry * unit.dy + unit.rz * unit.dz + unit.rw * unit.dw;
        DualQuatLanes {
            dx: unit.dx - unit.rx * along,
            dy: unit.dy - unit.ry * along,
            dz: unit.dz - unit.rz * along,
            dw: unit.dw - unit.rw * along,
            ..unit
        }
    }

    /// [`DualQuat::log`] of each lane (the shorter screw; scalar parts of the result 0).
    #[inline(always)]
    fn log(self) -> Self {
        let (zero, one) = (W::splat(0.0), W::splat(1.0));
        // Flip lanes with w < 0 to the other representative.
        let sign = W::select(self.rw.cmplt(zero), W::splat(-1.0), one);
        let q = self.scale(sign);
        let sine = (q.rx * q.rx + q.ry * q.ry + q.rz * q.rz).sqrt();
        let cosine = q.rw;
        let half_angle = first_quadrant_atan2(sine, cosine);
        // f1 = a / sin a and f2 = (a cos a − sin a) / sin³ a as polynomials in a², without
        // dividing by sin a.
        let angle_squared = half_angle * half_angle;
        let f1 = estrin9(angle_squared, &ANGLE_OVER_SINE);
        let f2 = estrin9(angle_squared, &SINE_FACTOR_DIFFERENCE);
        let dual_scale = q.dw * f2;
        DualQuatLanes {
            rx: q.rx * f1,
            ry: q.ry * f1,
            rz: q.rz * f1,
            rw: zero,
            dx: q.dx * f1 + q.rx * dual_scale,
            dy: q.dy * f1 + q.ry * dual_scale,
            dz: q.dz * f1 + q.rz * dual_scale,
            dw: zero,
        }
    }

    /// [`DualQuat::exp`] of each lane (scalar parts ignored), by series valid for screws up
    /// to [`EXP_LIMIT`] (which covers ScLERP's and DIB's steps); a lane beyond takes the
    /// scalar path.
    #[inline(always)]
    fn exp(self) -> Self {
        let angle_squared = self.rx * self.rx + self.ry * self.ry + self.rz * self.rz;
        let g1 = estrin9(angle_squared, &LONG_SINC);
        let g2 = estrin9(angle_squared, &LONG_SINC_DIFFERENCE);
        let cosine = estrin9(angle_squared, &LONG_COS);
        let pitch = self.rx * self.dx + self.ry * self.dy + self.rz * self.dz;
        let pitch_g2 = pitch * g2;
        let result = DualQuatLanes {
            rx: self.rx * g1,
            ry: self.ry * g1,
            rz: self.rz * g1,
            rw: cosine,
            dx: self.dx * g1 + self.rx * pitch_g2,
            dy: self.dy * g1 + self.ry * pitch_g2,
            dz: self.dz * g1 + self.rz * pitch_g2,
            dw: -pitch * g1,
        };
        let beyond = angle_squared.cmpge(W::splat(EXP_LIMIT * EXP_LIMIT));
        if W::any(beyond) {
            return result.replace_lanes(beyond, |lane, _| self.lane(lane).exp());
        }
        result
    }

    /// ScLERP of each lane: `a exp(t log(a* b))`, as [`DualQuat::sclerp`].
    #[inline(always)]
    pub(crate) fn sclerp(self, other: Self, t: f32) -> Self {
        let step = self.conjugate().mul(other).log().scale(W::splat(t));
        self.mul(step.exp()).normalize()
    }
}

/// The keys of a group of joints: key `k` with one joint per lane. Implementations are
/// `#[inline(always)]`, so that reading a key compiles inside the width-specific caller.
pub(crate) trait LaneKeys<W> {
    /// Key `k` of the group.
    fn key(&self, k: usize) -> DualQuatLanes<W>;
}

/// Keys gathered beforehand, key `k` at index `k`.
impl<W: Copy> LaneKeys<W> for [DualQuatLanes<W>] {
    #[inline(always)]
    fn key(&self, k: usize) -> DualQuatLanes<W> {
        self[k]
    }
}

/// The group of joints `start ..` of a pose whose joint `j` of key `k` is `input(k, j)`; lanes
/// past the last joint repeat it.
pub(crate) struct PoseKeys<'a, F> {
    /// Joint `j` of key `k`.
    pub(crate) input: &'a F,
    /// Joints per key.
    pub(crate) joint_count: usize,
    /// The group's first joint.
    pub(crate) start: usize,
}

impl<W: Wide, F: Fn(usize, usize) -> DualQuat> LaneKeys<W> for PoseKeys<'_, F> {
    #[inline(always)]
    fn key(&self, k: usize) -> DualQuatLanes<W> {
        let last = self.joint_count.saturating_sub(1);
        DualQuatLanes::gather(|lane| (self.input)(k, (self.start + lane).min(last)))
    }
}

/// The Hamilton product of quaternions given as lane vectors `(x, y, z, w)`.
#[inline(always)]
fn hamilton<W: Wide>(
    (ax, ay, az, aw): (W, W, W, W),
    (bx, by, bz, bw): (W, W, W, W),
) -> (W, W, W, W) {
    (
        aw * bx + ax * bw + ay * bz - az * by,
        aw * by - ax * bz + ay * bw + az * bx,
        aw * bz + ax * by - ay * bx + az * bw,
        aw * bw - ax * bx - ay * by - az * bz,
    )
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
#[inline(always)]
fn estrin9<W: Wide>(x: W, c: &[f32; 9]) -> W {
    let x2 = x * x;
    let x4 = x2 * x2;
    let p01 = W::splat(c[0]) + x * c[1];
    let p23 = W::splat(c[2]) + x * c[3];
    let p45 = W::splat(c[4]) + x * c[5];
    let p67 = W::splat(c[6]) + x * c[7];
    let low = p01 + x2 * p23;
    let high = p45 + x2 * p67;
    low + x4 * (high + x4 * c[8])
}

/// `a / sin a` for half angles `a` from 0 to π/2, as a polynomial in `x = a²` (fitted to the
/// relative error of f32: below 1e−7 in f32 arithmetic; tested against the scalar log).
const ANGLE_OVER_SINE: [f32; 9] = [
    1.0,
    1.666_666_6e-1,
    1.944_457_7e-2,
    2.049_709_4e-3,
    2.111_284_3e-4,
    2.003_658_3e-5,
    3.012_455_6e-6,
    -9.048_367e-8,
    7.687_444e-8,
];

/// `(a cos a − sin a) / sin³ a` for half angles from 0 to π/2, as a polynomial in `x = a²`
/// (relative error below 2e−7 in f32 arithmetic).
const SINE_FACTOR_DIFFERENCE: [f32; 9] = [
    -3.333_333_4e-1,
    -1.333_330_9e-1,
    -3.174_879_4e-2,
    -5.914_026_4e-3,
    -9.872_065e-4,
    -1.135_087_4e-4,
    -3.941_549e-5,
    4.468_812e-6,
    -1.583_71e-6,
];

/// `atan2(y, x)` lane by lane for `y, x ≥ 0` (see the scalar version in `math::dualquat`).
#[inline(always)]
fn first_quadrant_atan2<W: Wide>(y: W, x: W) -> W {
    use std::f32::consts::{FRAC_PI_2, FRAC_PI_4};
    const TAN_PI_8: f32 = 0.414_213_57;
    const TAN_3PI_8: f32 = 2.414_213_7;
    let low = y.cmple(x * TAN_PI_8);
    let high = y.cmpgt(x * TAN_3PI_8);
    let numerator = W::select(low, y, W::select(high, -x, y - x));
    let denominator = W::select(low, x, W::select(high, y, y + x));
    let base = W::select(
        low,
        W::splat(0.0),
        W::select(high, W::splat(FRAC_PI_2), W::splat(FRAC_PI_4)),
    );
    // y = x = 0 only for a zero quaternion; keep it finite (angle 0).
    let z = numerator / denominator.max(W::splat(f32::MIN_POSITIVE));
    let z2 = z * z;
    let p = ((z2 * 8.053_744_5e-2 - 1.387_768_6e-1) * z2 + 1.997_771_1e-1) * z2 - 3.333_295e-1;
    base + z + z * z2 * p
}

/// DLB of `W::LANES` joints: `input(k)` gives key `k` of them, `weights` are checked and
/// shared. Signs align to the first input with a non-zero weight; a lane whose aligned sum
/// cancels is redone by the scalar DLB (which moves its pivot).
#[inline(always)]
pub(crate) fn dlb_lanes<W: Wide>(
    weights: &[f32],
    input: &(impl LaneKeys<W> + ?Sized),
) -> DualQuatLanes<W> {
    // The pivot is the first input with weight: the first one summed.
    let mut pivot = None;
    let mut sum = DualQuatLanes::zero();
    let mut total = 0.0;
    let inverse_total = super::inverse_total(weights);
    for (k, &weight) in weights.iter().enumerate() {
        if weight > 0.0 {
            let weight = super::unit_weight(weight, inverse_total);
            let q = input.key(k);
            let pivot = *pivot.get_or_insert(q);
            let w = W::splat(weight);
            let signed = W::select(q.real_dot(pivot).cmplt(W::splat(0.0)), -w, w);
            sum = sum.add_scaled(q, signed);
            total += weight;
        }
    }
    let limit = CANCELLED_SUM * total;
    let cancelled = sum.real_dot(sum).cmplt(W::splat(limit * limit));
    if W::any(cancelled) {
        return sum.normalize().replace_lanes(cancelled, |lane, _| {
            super::linear::dlb_by(weights, |k| input.key(k).lane(lane))
        });
    }
    sum.normalize()
}

/// DIB (Algorithm 1) of `W::LANES` joints at once, each lane stopping when its own
/// `‖x̂‖ < p`: the per-lane results are exactly what [`super::iterative`] documents.
/// `inverse_total` is `1 / Σ w_k`; lanes `lanes_used..` are padding and ignored; `write(i, …)`
/// receives the outcome of each lane `i < lanes_used`.
#[inline(always)]
pub(crate) fn dib_lanes<W: Wide>(
    weights: &[f32],
    inverse_total: f64,
    settings: &DibSettings,
    lanes_used: usize,
    input: &(impl LaneKeys<W> + ?Sized),
    mut write: impl FnMut(usize, &DibOutcome),
) {
    let precision = W::splat(settings.precision);
    let mut blend = dlb_lanes(weights, input);
    let mut best = blend;
    let mut best_residual = W::splat(f32::INFINITY);
    let mut result = blend;
    let mut result_residual = W::splat(0.0);
    let mut result_iterations = [0u32; MAX_LANES];
    let mut done = W::mask_from_fn(|lane| lane >= lanes_used);
    let mut converged = W::mask_from_fn(|_| false);
    for iteration in 1..=settings.max_iterations {
        let inverse = blend.conjugate();
        let mut step = DualQuatLanes::zero();
        for (k, &weight) in weights.iter().enumerate() {
            if weight > 0.0 {
                let w = W::splat(super::unit_weight(weight, inverse_total));
                step = step.add_pure_scaled(inverse.mul(input.key(k)).log(), w);
            }
        }
        let residual = step.length();
        let improved = residual.cmplt(best_residual);
        best = DualQuatLanes::select(improved, blend, best);
        best_residual = W::select(improved, residual, best_residual);
        let next = blend.mul(step.exp()).normalize();
        let newly = residual.cmplt(precision) & !done;
        result = DualQuatLanes::select(newly, next, result);
        result_residual = W::select(newly, residual, result_residual);
        if W::any(newly) {
            for (lane, iterations) in result_iterations.iter_mut().enumerate().take(W::LANES) {
                if W::test(newly, lane) {
                    *iterations = iteration;
                }
            }
        }
        converged |= newly;
        done |= newly;
        if W::all(done) {
            break;
        }
        blend = next;
    }
    let residuals = W::select(converged, result_residual, best_residual);
    DualQuatLanes::select(converged, result, best).scatter(|lane, blend| {
        if lane < lanes_used {
            let converged = W::test(converged, lane);
            write(
                lane,
                &DibOutcome {
                    blend,
                    residual: residuals.lane(lane),
                    iterations: if converged {
                        result_iterations[lane]
                    } else {
                        settings.max_iterations
                    },
                    converged,
                },
            );
        }
    });
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::random::Random;
    use crate::math::wide::for_every_width;
    use glam::Vec3;
    use glam::Vec4;

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

    fn lanes<W: Wide>(lanes: DualQuatLanes<W>) -> Vec<DualQuat> {
        let mut out = vec![DualQuat::IDENTITY; W::LANES];
        lanes.scatter(|i, q| out[i] = q);
        out
    }

    fn random_lanes<W: Wide>(random: &mut Random, angle: f32) -> (Vec<DualQuat>, DualQuatLanes<W>) {
        let q: Vec<DualQuat> = (0..W::LANES)
            .map(|_| random_transform(random, angle))
            .collect();
        let gathered = DualQuatLanes::gather(|i| q[i]);
        (q, gathered)
    }

    fn gather_and_scatter_are_inverse<W: Wide>() {
        let mut random = Random::new(11);
        let (q, gathered) = random_lanes::<W>(&mut random, 3.0);
        assert_eq!(lanes(gathered), q);
        for (i, &q) in q.iter().enumerate() {
            assert_eq!(gathered.lane(i), q);
        }
    }

    fn lane_algebra_matches_the_scalar_one<W: Wide>() {
        let mut random = Random::new(12);
        for _ in 0..200 {
            let (a, a4) = random_lanes::<W>(&mut random, 6.0);
            let (b, b4) = random_lanes::<W>(&mut random, 6.0);
            let product = lanes(a4.mul(b4));
            let log = lanes(a4.log());
            let exp = lanes(a4.log().exp());
            for lane in 0..W::LANES {
                assert!((product[lane] - a[lane] * b[lane]).length() < 1e-5);
                assert!((log[lane] - a[lane].log()).length() < 2e-5, "{:?}", a[lane]);
                let back = exp[lane];
                assert!((back - a[lane]).length() < 2e-5 || (back + a[lane]).length() < 2e-5);
            }
            // Screws beyond the series fall back to the scalar exp.
            let factors = [1.0, 1.5, 2.0, 0.1];
            let big4 = a4.log().scale(W::from_fn(|i| factors[i % 4]));
            let big = lanes(big4);
            let exp_big = lanes(big4.exp());
            for lane in 0..W::LANES {
                assert!((exp_big[lane] - big[lane].exp()).length() < 2e-5);
            }
        }
    }

    fn lane_sclerp_matches_the_scalar_one<W: Wide>() {
        let mut random = Random::new(13);
        for _ in 0..200 {
            let (a, a4) = random_lanes::<W>(&mut random, 3.1);
            let (b, b4) = random_lanes::<W>(&mut random, 3.1);
            for t in [0.0, 0.3, 0.5, 1.0] {
                let blended = lanes(a4.sclerp(b4, t));
                for lane in 0..W::LANES {
                    let scalar = a[lane].sclerp(b[lane], t);
                    let error = (blended[lane] - scalar)
                        .length()
                        .min((blended[lane] + scalar).length());
                    assert!(error < 2e-5, "t = {t}: {:?} vs {scalar:?}", blended[lane]);
                }
            }
        }
    }

    #[test]
    fn every_width_gathers_and_scatters() {
        for_every_width!(gather_and_scatter_are_inverse());
    }

    #[test]
    fn lane_algebra_matches_the_scalar_one_at_every_width() {
        for_every_width!(lane_algebra_matches_the_scalar_one());
    }

    #[test]
    fn lane_sclerp_matches_the_scalar_one_at_every_width() {
        for_every_width!(lane_sclerp_matches_the_scalar_one());
    }

    /// A joint's DIB does not depend on the width it was computed at: the same bits in a
    /// lane of 4, 8 or 16.
    #[test]
    fn dib_gives_the_same_bits_at_every_width() {
        let mut random = Random::new(14);
        let weights = [0.2, 0.5, 0.3];
        let keys: Vec<Vec<DualQuat>> = (0..3)
            .map(|_| {
                (0..16)
                    .map(|_| random_transform(&mut random, 1.5))
                    .collect()
            })
            .collect();
        let settings = DibSettings::default();
        fn run<W: Wide>(
            keys: &[Vec<DualQuat>],
            weights: &[f32],
            settings: &DibSettings,
        ) -> Vec<DibOutcome> {
            let mut out = Vec::new();
            for start in (0..16).step_by(W::LANES) {
                let gathered: Vec<DualQuatLanes<W>> = keys
                    .iter()
                    .map(|key| DualQuatLanes::gather(|i| key[start + i]))
                    .collect();
                dib_lanes(weights, 1.0, settings, W::LANES, &gathered[..], |_, o| {
                    out.push(*o)
                });
            }
            out
        }
        let four = run::<Vec4>(&keys, &weights, &settings);
        assert_eq!(four.len(), 16);
        assert!(four.iter().all(|o| o.converged && o.iterations >= 1));
        fn same_as_four<W: Wide>(
            four: &[DibOutcome],
            keys: &[Vec<DualQuat>],
            weights: &[f32],
            settings: &DibSettings,
        ) {
            assert_eq!(run::<W>(keys, weights, settings), four);
        }
        for_every_width!(same_as_four(&four, &keys, &weights, &settings));
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
