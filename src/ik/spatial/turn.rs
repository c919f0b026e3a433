//! A gaze rotation per lane, kept as the cosine and sine of its half-angle (`q_l` and its
//! angle `θ` without trigonometry): the shortest rotation towards a target, what is left of it
//! after a reserve, and Kapoulkine's corrected fraction of it.

use super::config::Prepared;
use crate::ik::lanes::{atan2_upper, sin_cos_quarter};
use crate::math::lanes::{Floats, Mask, V3};
use crate::math::wide::Wide;

/// Per lane, a rotation of angle θ ∈ [0, π] about a unit axis, kept as the cosine and sine
/// of θ/2, so that the solver never needs θ itself.
#[derive(Debug, Clone, Copy)]
pub(super) struct Turn<W> {
    pub(super) axis: V3<W>,
    pub(super) cos: Floats<W>,
    pub(super) sin: Floats<W>,
}

impl<W: Wide> Turn<W> {
    /// θ, radians.
    #[inline(always)]
    pub(super) fn angle(self) -> Floats<W> {
        2.0 * atan2_upper(self.sin, self.cos)
    }

    /// The rotation by θ − `reserve` (given by its half-angle's cosine and sine) about the
    /// same axis, and where that is more than nothing (θ > reserve).
    #[inline(always)]
    pub(super) fn less(self, reserve_cos: Floats<W>, reserve_sin: Floats<W>) -> (Turn<W>, Mask<W>) {
        let sin = self.sin * reserve_cos - self.cos * reserve_sin;
        let turn = Turn {
            axis: self.axis,
            cos: self.cos * reserve_cos + self.sin * reserve_sin,
            sin,
        };
        (turn, sin.cmpgt(Floats::zero()))
    }

    /// The rotation by `t`·θ, `t ∈ (0, 1]`: a normalised lerp from identity with
    /// Kapoulkine's parameter correction (within about 10⁻³ of `t`·θ; exact for `t = 1`).
    #[inline(always)]
    pub(super) fn fraction(self, t: Floats<W>) -> Turn<W> {
        let d = self.cos;
        let k_a = 1.0904 + d * (-3.2452 + d * (3.55645 - d * 1.43519));
        let k_b = 0.848_013 + d * (-1.06021 + d * 0.215_638);
        let half = t - 0.5;
        let k = k_a * half * half + k_b;
        let u = t + t * half * (t - 1.0) * k;
        let cos = 1.0 + u * (self.cos - 1.0);
        let sin = u * self.sin;
        let norm = (cos * cos + sin * sin).sqrt().recip();
        let whole = t.cmpge(Floats::one());
        Turn {
            axis: self.axis,
            cos: Floats::select(whole, self.cos, cos * norm),
            sin: Floats::select(whole, self.sin, sin * norm),
        }
    }
}

/// Per lane, the shortest rotation that turns the unit `forward` towards `to_target` (any
/// length), faded out near the eye. `fallback_axis` is used when the two are
/// (anti)parallel. Square roots only, no trigonometry (except within the near distance).
#[inline(always)]
pub(super) fn gaze_rotation<W: Wide>(
    forward: V3<W>,
    to_target: V3<W>,
    fallback_axis: V3<W>,
    prepared: &Prepared,
) -> Turn<W> {
    let cross = forward.cross(to_target);
    let ahead = forward.dot(to_target);
    let cross_squared = cross.length_squared();
    let distance_squared = ahead * ahead + cross_squared;
    // False for NaN too.
    let valid = distance_squared.cmpgt(Floats::splat(1e-12));
    let distance = distance_squared.sqrt();
    let cross_length = cross_squared.sqrt();
    // (|v| + f·v, f × v) is the rotation from f to v, up to its length.
    let w = distance + ahead;
    let norm = (w * w + cross_squared).sqrt().recip();
    let generic = valid & cross_squared.cmpgt(1e-14 * distance_squared);
    let mut turn = Turn {
        axis: cross.scale(cross_length.recip()),
        cos: w * norm,
        sin: cross_length * norm,
    };
    if !generic.all() {
        // Degenerate: straight ahead (or at the eye) is no turn, straight behind a half turn.
        let ahead_positive = ahead.cmpgt(Floats::zero());
        let degenerate_cos = Floats::select(ahead_positive | !valid, Floats::one(), Floats::zero());
        turn = Turn {
            axis: V3::select(generic, turn.axis, fallback_axis),
            cos: Floats::select(generic, turn.cos, degenerate_cos),
            sin: Floats::select(generic, turn.sin, 1.0 - degenerate_cos),
        };
    }
    let near = valid & distance.cmplt(Floats::splat(prepared.near_distance));
    if near.any() {
        let t = distance / prepared.near_distance;
        let faded = turn.angle() * (t * t * (3.0 - 2.0 * t));
        let (sin, cos) = sin_cos_quarter(0.5 * faded);
        turn.cos = Floats::select(near, cos, turn.cos);
        turn.sin = Floats::select(near, sin, turn.sin);
    }
    turn
}
