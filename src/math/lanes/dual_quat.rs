//! Dual quaternions in lanes ([`DualQuatLanes`]): a real and a dual [`Q4`], with the product,
//! normalisation, and a `log` and `exp` without per-lane branches, as [`DualQuat`]'s.
//!
//! The arctangent of `log` is Cephes' `atanf` with a selected range reduction, and the
//! factors `a / sin a` and `(a cos a − sin a) / sin³ a` are polynomials in the squared half
//! angle fitted over 0 to π/2 (no division); `exp` uses series valid up to the largest half
//! angle `log` returns (π/2), and falls back to the scalar [`DualQuat::exp`] beyond.

use glam::Quat;

use super::{Floats, Mask, Q4};
use crate::math::dualquat::DualQuat;
use crate::math::wide::Wide;

/// `W::LANES` dual quaternions, one per lane.
#[derive(Debug, Clone, Copy)]
pub(crate) struct DualQuatLanes<W> {
    /// The rotation parts.
    real: Q4<W>,
    /// The translation parts.
    dual: Q4<W>,
}

impl<W: Wide> DualQuatLanes<W> {
    /// Zero in every lane.
    #[inline(always)]
    pub(crate) fn zero() -> Self {
        let zero = Floats::zero();
        let q = Q4 {
            x: zero,
            y: zero,
            z: zero,
            w: zero,
        };
        DualQuatLanes { real: q, dual: q }
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
            real: Q4 {
                x: Floats(rx),
                y: Floats(ry),
                z: Floats(rz),
                w: Floats(rw),
            },
            dual: Q4 {
                x: Floats(dx),
                y: Floats(dy),
                z: Floats(dz),
                w: Floats(dw),
            },
        }
    }

    /// `f(i, q)` for the dual quaternion `q` of each lane `i`.
    #[inline(always)]
    pub(crate) fn scatter(self, mut f: impl FnMut(usize, DualQuat)) {
        let (r, d) = (self.real, self.dual);
        let rows = [r.x.0, r.y.0, r.z.0, r.w.0, d.x.0, d.y.0, d.z.0, d.w.0];
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
        DualQuat::from_parts(self.real.lane(i), self.dual.lane(i))
    }

    /// Lanes replaced by `f(i, lane i)` where `mask` is set (the slow path of rare lanes).
    #[inline(never)]
    pub(crate) fn replace_lanes(
        self,
        mask: Mask<W>,
        f: impl Fn(usize, DualQuat) -> DualQuat,
    ) -> Self {
        Self::gather(|i| {
            let q = self.lane(i);
            if mask.test(i) {
                f(i, q)
            } else {
                q
            }
        })
    }

    /// Per lane: `a` where `mask`, else `b`.
    #[inline(always)]
    pub(crate) fn select(mask: Mask<W>, a: Self, b: Self) -> Self {
        DualQuatLanes {
            real: Q4::select(mask, a.real, b.real),
            dual: Q4::select(mask, a.dual, b.dual),
        }
    }

    /// Each lane scaled by the matching lane of `s`.
    #[inline(always)]
    pub(crate) fn scale(self, s: Floats<W>) -> Self {
        DualQuatLanes {
            real: self.real.scale(s),
            dual: self.dual.scale(s),
        }
    }

    /// `self + other · s`, lane by lane.
    #[inline(always)]
    pub(crate) fn add_scaled(self, other: Self, s: Floats<W>) -> Self {
        DualQuatLanes {
            real: self.real.add_scaled(other.real, s),
            dual: self.dual.add_scaled(other.dual, s),
        }
    }

    /// `self + other · s` for a pure `other` (scalar parts 0, as `log` returns).
    #[inline(always)]
    pub(crate) fn add_pure_scaled(self, other: Self, s: Floats<W>) -> Self {
        let pure = |q: Q4<W>, o: Q4<W>| Q4 {
            x: q.x + o.x * s,
            y: q.y + o.y * s,
            z: q.z + o.z * s,
            w: q.w,
        };
        DualQuatLanes {
            real: pure(self.real, other.real),
            dual: pure(self.dual, other.dual),
        }
    }

    /// Dot products of the real parts.
    #[inline(always)]
    pub(crate) fn real_dot(self, other: Self) -> Floats<W> {
        self.real.dot(other.real)
    }

    /// The quaternion conjugate of each lane.
    #[inline(always)]
    pub(crate) fn conjugate(self) -> Self {
        DualQuatLanes {
            real: self.real.conjugate(),
            dual: self.dual.conjugate(),
        }
    }

    /// The dual quaternion product of each lane: real `a.r b.r`, dual `a.r b.d + a.d b.r`.
    #[inline(always)]
    pub(crate) fn mul(self, b: Self) -> Self {
        let p = self.real.mul(b.dual);
        let q = self.dual.mul(b.real);
        DualQuatLanes {
            real: self.real.mul(b.real),
            dual: Q4 {
                x: p.x + q.x,
                y: p.y + q.y,
                z: p.z + q.z,
                w: p.w + q.w,
            },
        }
    }

    /// The Euclidean length of each lane's 8 components.
    #[inline(always)]
    pub(crate) fn length(self) -> Floats<W> {
        let (r, d) = (self.real, self.dual);
        (r.x * r.x
            + r.y * r.y
            + r.z * r.z
            + r.w * r.w
            + d.x * d.x
            + d.y * d.y
            + d.z * d.z
            + d.w * d.w)
            .sqrt()
    }

    /// Each lane made a unit dual quaternion (as [`DualQuat::try_normalize`]; lanes must have
    /// a non-zero real part).
    #[inline(always)]
    pub(crate) fn normalize(self) -> Self {
        let inverse = self.real_dot(self).sqrt().recip();
        let unit = self.scale(inverse);
        let along = unit.real.dot(unit.dual);
        let (r, d) = (unit.real, unit.dual);
        DualQuatLanes {
            real: r,
            dual: Q4 {
                x: d.x - r.x * along,
                y: d.y - r.y * along,
                z: d.z - r.z * along,
                w: d.w - r.w * along,
            },
        }
    }

    /// [`DualQuat::log`] of each lane (the shorter screw; scalar parts of the result 0).
    #[inline(always)]
    pub(crate) fn log(self) -> Self {
        let zero = Floats::zero();
        // Flip lanes with w < 0 to the other representative.
        let sign = Floats::select(self.real.w.cmplt(zero), Floats::neg_one(), Floats::one());
        let q = self.scale(sign);
        let (r, d) = (q.real, q.dual);
        let sine = (r.x * r.x + r.y * r.y + r.z * r.z).sqrt();
        let cosine = r.w;
        let half_angle = first_quadrant_atan2(sine, cosine);
        // f1 = a / sin a and f2 = (a cos a − sin a) / sin³ a as polynomials in a², without
        // dividing by sin a.
        let angle_squared = half_angle * half_angle;
        let f1 = estrin9(angle_squared, &ANGLE_OVER_SINE);
        let f2 = estrin9(angle_squared, &SINE_FACTOR_DIFFERENCE);
        let dual_scale = d.w * f2;
        DualQuatLanes {
            real: Q4 {
                x: r.x * f1,
                y: r.y * f1,
                z: r.z * f1,
                w: zero,
            },
            dual: Q4 {
                x: d.x * f1 + r.x * dual_scale,
                y: d.y * f1 + r.y * dual_scale,
                z: d.z * f1 + r.z * dual_scale,
                w: zero,
            },
        }
    }

    /// [`DualQuat::exp`] of each lane (scalar parts ignored), by series valid for screws up
    /// to [`EXP_LIMIT`] (which covers ScLERP's and DIB's steps); a lane beyond takes the
    /// scalar path.
    #[inline(always)]
    pub(crate) fn exp(self) -> Self {
        let (r, d) = (self.real, self.dual);
        let angle_squared = r.x * r.x + r.y * r.y + r.z * r.z;
        let g1 = estrin9(angle_squared, &LONG_SINC);
        let g2 = estrin9(angle_squared, &LONG_SINC_DIFFERENCE);
        let cosine = estrin9(angle_squared, &LONG_COS);
        let pitch = r.x * d.x + r.y * d.y + r.z * d.z;
        let pitch_g2 = pitch * g2;
        let result = DualQuatLanes {
            real: Q4 {
                x: r.x * g1,
                y: r.y * g1,
                z: r.z * g1,
                w: cosine,
            },
            dual: Q4 {
                x: d.x * g1 + r.x * pitch_g2,
                y: d.y * g1 + r.y * pitch_g2,
                z: d.z * g1 + r.z * pitch_g2,
                w: -pitch * g1,
            },
        };
        let beyond = angle_squared.cmpge(Floats::splat(EXP_LIMIT * EXP_LIMIT));
        if beyond.any() {
            return result.replace_lanes(beyond, |lane, _| self.lane(lane).exp());
        }
        result
    }

    /// ScLERP of each lane: `a exp(t log(a* b))`, as [`DualQuat::sclerp`].
    #[inline(always)]
    pub(crate) fn sclerp(self, other: Self, t: f32) -> Self {
        let step = self.conjugate().mul(other).log().scale(Floats::splat(t));
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

/// `Σ c_i xⁱ` for nine coefficients by Estrin's scheme.
#[inline(always)]
fn estrin9<W: Wide>(x: Floats<W>, c: &[f32; 9]) -> Floats<W> {
    let x2 = x * x;
    let x4 = x2 * x2;
    let p01 = Floats::splat(c[0]) + x * c[1];
    let p23 = Floats::splat(c[2]) + x * c[3];
    let p45 = Floats::splat(c[4]) + x * c[5];
    let p67 = Floats::splat(c[6]) + x * c[7];
    let low = p01 + x2 * p23;
    let high = p45 + x2 * p67;
    low + x4 * (high + x4 * c[8])
}

/// `atan2(y, x)` lane by lane for `y, x ≥ 0` (see the scalar version in `math::dualquat`).
#[inline(always)]
pub(super) fn first_quadrant_atan2<W: Wide>(y: Floats<W>, x: Floats<W>) -> Floats<W> {
    use std::f32::consts::{FRAC_PI_2, FRAC_PI_4};
    const TAN_PI_8: f32 = 0.414_213_57;
    const TAN_3PI_8: f32 = 2.414_213_7;
    let low = y.cmple(x * TAN_PI_8);
    let high = y.cmpgt(x * TAN_3PI_8);
    let numerator = Floats::select(low, y, Floats::select(high, -x, y - x));
    let denominator = Floats::select(low, x, Floats::select(high, y, y + x));
    let base = Floats::select(
        low,
        Floats::zero(),
        Floats::select(high, Floats::splat(FRAC_PI_2), Floats::splat(FRAC_PI_4)),
    );
    // y = x = 0 only for a zero quaternion; keep it finite (angle 0).
    let z = numerator / denominator.max(Floats::splat(f32::MIN_POSITIVE));
    let z2 = z * z;
    let p = ((z2 * 8.053_744_5e-2 - 1.387_768_6e-1) * z2 + 1.997_771_1e-1) * z2 - 3.333_295e-1;
    base + z + z * z2 * p
}
