//! DIB's stopping rule ([`DibSettings`]) and what a blend reports ([`DibOutcome`] for one
//! transform, [`PoseOutcome`] for a pose), shared by the scalar and the lane code.

use crate::error::{Error, Result};
use crate::math::dualquat::DualQuat;

/// Largest `max_iterations` accepted, so that a call always ends quickly.
pub const MAX_ITERATIONS_LIMIT: u32 = 1000;

/// The stopping rule of DIB: precision `p` and the most updates allowed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DibSettings {
    /// `p`: stop when `‖x̂‖ < p` (radians and length units mixed, see the module docs).
    /// Finite and `> 0`. Default 1e−6.
    pub precision: f32,
    /// Most iterations (each computes `x̂` and applies it), 1 to [`MAX_ITERATIONS_LIMIT`].
    /// Default 16; typical poses need 2 to 4.
    pub max_iterations: u32,
}

impl Default for DibSettings {
    fn default() -> Self {
        DibSettings {
            precision: 1e-6,
            max_iterations: 16,
        }
    }
}

impl DibSettings {
    /// Checks the documented ranges.
    ///
    /// Errors: [`Error::NonFinite`] (precision NaN or infinite), [`Error::InvalidArgument`]
    /// (precision `≤ 0`, max_iterations 0 or above [`MAX_ITERATIONS_LIMIT`]).
    pub fn validate(&self) -> Result<()> {
        if !self.precision.is_finite() {
            return Err(Error::NonFinite(format!("precision is {}", self.precision)));
        }
        if self.precision <= 0.0 {
            return Err(Error::InvalidArgument(format!(
                "precision is {}, must be > 0",
                self.precision
            )));
        }
        if self.max_iterations == 0 || self.max_iterations > MAX_ITERATIONS_LIMIT {
            return Err(Error::InvalidArgument(format!(
                "max_iterations is {}, must be 1..={MAX_ITERATIONS_LIMIT}",
                self.max_iterations
            )));
        }
        Ok(())
    }
}

/// What DIB returned for one transform.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DibOutcome {
    /// The blended unit dual quaternion (the best iterate if not converged).
    pub blend: DualQuat,
    /// `‖x̂‖` of the last iteration if converged (below the precision), else the smallest
    /// `‖x̂‖` measured, the one at `blend`.
    pub residual: f32,
    /// Iterations run (0 for one or two inputs with weight, whose blend is known in closed
    /// form: the input itself, or ScLERP).
    pub iterations: u32,
    /// Whether `‖x̂‖ < p` was reached.
    pub converged: bool,
}

impl DibOutcome {
    /// A blend known exactly, without iterating.
    pub(crate) fn closed_form(blend: DualQuat) -> DibOutcome {
        DibOutcome {
            blend,
            residual: 0.0,
            iterations: 0,
            converged: true,
        }
    }

    /// `Ok(blend)` if converged, otherwise [`Error::NotConverged`] (the blend is still in
    /// `self` for callers that want the best result).
    pub fn into_result(self, settings: &DibSettings) -> Result<DualQuat> {
        if self.converged {
            Ok(self.blend)
        } else {
            Err(not_converged(1, 1, self.residual, settings))
        }
    }
}

/// How a pose blend went, joint by joint.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct PoseOutcome {
    /// Joints blended.
    pub joints: usize,
    /// Joints whose DIB did not reach the precision (0 for DLB).
    pub unconverged_joints: usize,
    /// Largest `‖x̂‖` over the joints (0 for DLB).
    pub largest_residual: f32,
    /// Most updates any joint needed (0 for DLB).
    pub most_iterations: u32,
}

impl PoseOutcome {
    /// True if every joint converged.
    pub fn converged(&self) -> bool {
        self.unconverged_joints == 0
    }

    /// `Ok(())` if every joint converged, otherwise [`Error::NotConverged`] saying how many
    /// did not (the pose has been written all the same).
    pub fn into_result(self, settings: &DibSettings) -> Result<()> {
        if self.converged() {
            Ok(())
        } else {
            Err(not_converged(
                self.unconverged_joints,
                self.joints,
                self.largest_residual,
                settings,
            ))
        }
    }

    pub(crate) fn add(&mut self, outcome: &DibOutcome) {
        self.joints += 1;
        if !outcome.converged {
            self.unconverged_joints += 1;
        }
        self.largest_residual = self.largest_residual.max(outcome.residual);
        self.most_iterations = self.most_iterations.max(outcome.iterations);
    }
}

fn not_converged(failed: usize, of: usize, residual: f32, settings: &DibSettings) -> Error {
    Error::NotConverged(format!(
        "DIB: {failed} of {of} blends did not reach precision {} in {} iterations \
         (largest |x| = {residual:.3e}); the best iterates were written",
        settings.precision, settings.max_iterations
    ))
}
