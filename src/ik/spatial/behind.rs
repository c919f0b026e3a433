//! Targets behind the character: the [`TurnSide`] remembered between frames, its
//! hysteresis, and the direction aimed at instead of a target on the other side within the
//! zone behind.

use glam::Vec3A;

use super::config::Prepared;
use crate::math::lanes::{Floats, V3};
use crate::math::wide::Wide;

/// Which way a character turns towards a target behind it, remembered between frames
/// (one byte of a character's state): undecided, left (counter-clockwise about up) or right.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct TurnSide(i8);

impl TurnSide {
    /// Not decided yet: the next target decides (left if exactly behind).
    pub const UNDECIDED: TurnSide = TurnSide(0);
    /// Counter-clockwise about up.
    pub const LEFT: TurnSide = TurnSide(1);
    /// Clockwise about up.
    pub const RIGHT: TurnSide = TurnSide(-1);

    /// +1 for left, −1 for right, 0 undecided.
    pub fn sign(self) -> i8 {
        self.0
    }

    pub(super) fn resolved(self) -> f32 {
        if self.0 < 0 {
            -1.0
        } else {
            1.0
        }
    }
}
/// Resolves the remembered side from the target direction `to_target` seen from an eye
/// looking along `forward` with up `up`; returns true if it switched while the target is
/// in the back half.
pub(super) fn update_side(
    to_target: Vec3A,
    forward: Vec3A,
    up: Vec3A,
    side: &mut TurnSide,
    prepared: &Prepared,
) -> bool {
    let left = up.cross(forward);
    let ahead = to_target.dot(forward);
    let across = to_target.dot(left);
    let in_zone = ahead < 0.0 && across.abs() < prepared.zone().tan_hysteresis * -ahead;
    let natural = if across > 0.0 {
        1
    } else if across < 0.0 {
        -1
    } else {
        0
    };
    let old = side.0;
    if !in_zone || old == 0 {
        if natural != 0 {
            side.0 = natural;
        } else if old == 0 {
            side.0 = 1;
        }
    }
    old != 0 && side.0 != old && ahead < 0.0
}

/// Per lane, the direction to aim at for `to_target`, applying the behind-the-character
/// rule with the (resolved) side `side_sign` (±1).
#[inline(always)]
pub(super) fn behind_adjusted<W: Wide>(
    to_target: V3<W>,
    forward: V3<W>,
    up: V3<W>,
    side_sign: Floats<W>,
    prepared: &Prepared,
) -> V3<W> {
    let ahead = to_target.dot(forward);
    let behind = ahead.cmplt(Floats::zero());
    if !behind.any() {
        return to_target;
    }
    let zone = prepared.zone();
    let left = up.cross(forward);
    let across = to_target.dot(left);
    let back = -ahead;
    let in_zone = behind & across.abs().cmplt(zone.tan_hysteresis * back);
    let on_side =
        (across * side_sign).cmpgt(Floats::zero()) & across.abs().cmpge(zone.tan_clearance * back);
    let replace = in_zone & !on_side;
    if !replace.any() {
        return to_target;
    }
    let height = to_target.dot(up);
    let horizontal = (ahead * ahead + across * across).sqrt();
    let aimed = forward
        .scale(-horizontal * zone.cos_clearance)
        .add(left.scale(side_sign * horizontal * zone.sin_clearance))
        .add(up.scale(height));
    V3::select(replace, aimed, to_target)
}
