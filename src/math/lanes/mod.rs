//! Floats, vectors, quaternions and dual quaternions in structure-of-arrays form: one value
//! per SIMD lane, generic over the lane width ([`Wide`]: 4 lanes with glam's `Vec4`, 8 with
//! AVX, 16 with AVX-512F; see [`crate::math::wide::run_widest`]). The gaze IK runs one
//! character per lane, the pose blenders one joint per lane.
//!
//! A chain of dependent steps (a joint waits for the one below it, an iteration for the one
//! before) leaves the processor mostly idle for one value; a group in the lanes of the same
//! instructions runs at nearly the cost of one. Branches become lane masks: both sides are
//! computed when the lanes disagree and the right one is selected per lane. Every lane
//! computes the same IEEE operations at every width, so a lane's result does not depend on
//! the width or on its neighbours.
//!
//! Everything here is `#[inline(always)]`: it must be compiled inside the
//! instruction-set-specific functions that run it.
//!
//! - this file: [`Floats`] and [`Mask`], one float and one boolean per lane;
//! - `vector.rs`: [`V3`] and [`Q4`], 3-vectors and quaternions;
//! - `dual_quat.rs`: [`DualQuatLanes`], dual quaternions with a branch-free `log` and `exp`.

use std::ops::{Add, BitAnd, BitAndAssign, BitOr, BitOrAssign, Div, Mul, Neg, Not, Sub};

use crate::math::wide::Wide;
pub(crate) use crate::math::wide::MAX_LANES;

mod dual_quat;
#[cfg(test)]
pub(crate) mod tests;
mod vector;

pub(crate) use dual_quat::DualQuatLanes;
pub(crate) use vector::{Q4, V3};

/// One float per lane.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Floats<W>(W);

/// One boolean per lane.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Mask<W: Wide>(W::Mask);

impl<W: Wide> Floats<W> {
    /// 0 in every lane.
    #[inline(always)]
    pub(crate) fn zero() -> Self {
        Floats(W::splat(0.0))
    }

    /// 1 in every lane.
    #[inline(always)]
    pub(crate) fn one() -> Self {
        Floats(W::splat(1.0))
    }

    /// −1 in every lane.
    #[inline(always)]
    pub(crate) fn neg_one() -> Self {
        Floats(W::splat(-1.0))
    }

    /// The same value in every lane.
    #[inline(always)]
    pub(crate) fn splat(value: f32) -> Self {
        Floats(W::splat(value))
    }

    /// Lane `i` is `values[i]` (the values past the width are not used).
    #[inline(always)]
    pub(crate) fn load(values: &[f32; MAX_LANES]) -> Self {
        Floats(W::load(values))
    }

    /// Lane `i`'s value.
    #[inline(always)]
    pub(crate) fn lane(self, i: usize) -> f32 {
        self.0.lane(i)
    }

    /// Per lane: `a` where `m`, else `b`.
    #[inline(always)]
    pub(crate) fn select(m: Mask<W>, a: Self, b: Self) -> Self {
        Floats(W::select(m.0, a.0, b.0))
    }

    #[inline(always)]
    pub(crate) fn sqrt(self) -> Self {
        Floats(self.0.sqrt())
    }

    #[inline(always)]
    pub(crate) fn recip(self) -> Self {
        Floats(self.0.recip())
    }

    #[inline(always)]
    pub(crate) fn abs(self) -> Self {
        Floats(self.0.abs())
    }

    #[inline(always)]
    pub(crate) fn min(self, o: Self) -> Self {
        Floats(self.0.min(o.0))
    }

    #[inline(always)]
    pub(crate) fn max(self, o: Self) -> Self {
        Floats(self.0.max(o.0))
    }

    #[inline(always)]
    pub(crate) fn clamp(self, low: Self, high: Self) -> Self {
        self.max(low).min(high)
    }

    #[inline(always)]
    pub(crate) fn cmplt(self, o: Self) -> Mask<W> {
        Mask(self.0.cmplt(o.0))
    }

    #[inline(always)]
    pub(crate) fn cmple(self, o: Self) -> Mask<W> {
        Mask(self.0.cmple(o.0))
    }

    #[inline(always)]
    pub(crate) fn cmpgt(self, o: Self) -> Mask<W> {
        Mask(self.0.cmpgt(o.0))
    }

    #[inline(always)]
    pub(crate) fn cmpge(self, o: Self) -> Mask<W> {
        Mask(self.0.cmpge(o.0))
    }

    #[inline(always)]
    pub(crate) fn cmpeq(self, o: Self) -> Mask<W> {
        Mask(self.0.cmpeq(o.0))
    }
}

/// Declares the lane-wise arithmetic operators, with a scalar on either side too.
macro_rules! float_ops {
    ($($trait:ident $method:ident),*) => {$(
        impl<W: Wide> $trait for Floats<W> {
            type Output = Floats<W>;
            #[inline(always)]
            fn $method(self, o: Floats<W>) -> Floats<W> {
                Floats(self.0.$method(o.0))
            }
        }
        impl<W: Wide> $trait<f32> for Floats<W> {
            type Output = Floats<W>;
            #[inline(always)]
            fn $method(self, o: f32) -> Floats<W> {
                Floats(self.0.$method(W::splat(o)))
            }
        }
        impl<W: Wide> $trait<Floats<W>> for f32 {
            type Output = Floats<W>;
            #[inline(always)]
            fn $method(self, o: Floats<W>) -> Floats<W> {
                Floats(W::splat(self).$method(o.0))
            }
        }
    )*};
}
float_ops!(Add add, Sub sub, Mul mul, Div div);

impl<W: Wide> Neg for Floats<W> {
    type Output = Floats<W>;

    #[inline(always)]
    fn neg(self) -> Floats<W> {
        Floats(-self.0)
    }
}

impl<W: Wide> Mask<W> {
    /// The same value in every lane.
    #[inline(always)]
    pub(crate) fn splat(value: bool) -> Self {
        Mask(W::mask_splat(value))
    }

    /// True if any lane is true.
    #[inline(always)]
    pub(crate) fn any(self) -> bool {
        W::any(self.0)
    }

    /// True if every lane is true.
    #[inline(always)]
    pub(crate) fn all(self) -> bool {
        W::all(self.0)
    }

    /// Lane `lane`'s value.
    #[inline(always)]
    pub(crate) fn test(self, lane: usize) -> bool {
        W::test(self.0, lane)
    }
}

impl<W: Wide> BitAnd for Mask<W> {
    type Output = Mask<W>;

    #[inline(always)]
    fn bitand(self, o: Mask<W>) -> Mask<W> {
        Mask(self.0 & o.0)
    }
}

impl<W: Wide> BitAndAssign for Mask<W> {
    #[inline(always)]
    fn bitand_assign(&mut self, o: Mask<W>) {
        *self = *self & o;
    }
}

impl<W: Wide> BitOr for Mask<W> {
    type Output = Mask<W>;

    #[inline(always)]
    fn bitor(self, o: Mask<W>) -> Mask<W> {
        Mask(self.0 | o.0)
    }
}

impl<W: Wide> BitOrAssign for Mask<W> {
    #[inline(always)]
    fn bitor_assign(&mut self, o: Mask<W>) {
        *self = *self | o;
    }
}

impl<W: Wide> Not for Mask<W> {
    type Output = Mask<W>;

    #[inline(always)]
    fn not(self) -> Mask<W> {
        Mask(!self.0)
    }
}

/// A lane mask from a function of the lane index (called for the lanes of the width only).
#[inline(always)]
pub(crate) fn mask<W: Wide>(f: impl Fn(usize) -> bool) -> Mask<W> {
    Mask(W::mask_from_fn(f))
}

/// One float per lane from a function of the lane index (called for the lanes of the width
/// only).
#[inline(always)]
pub(crate) fn gather<W: Wide>(f: impl Fn(usize) -> f32) -> Floats<W> {
    let mut values = [0.0; MAX_LANES];
    for (i, value) in values.iter_mut().enumerate().take(W::LANES) {
        *value = f(i);
    }
    Floats::load(&values)
}
