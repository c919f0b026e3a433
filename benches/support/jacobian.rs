//! The baseline of Grillon & Thalmann's comparison: a damped-least-squares (DLS) Jacobian IK
//! turning the same gaze chain until the gaze ray points at the target. Bench code only —
//! the library never iterates.
//!
//! Task: the error `e = θ a`, the rotation vector from the cyclopean gaze direction `d` (the
//! mean of the two eyes' directions, from their mid-point `p`) to the unit direction `v̂` from
//! `p` to the target. Every joint has 3 rotational DOF (a small world rotation `ω` about its
//! pivot); its 3×3 Jacobian block is `J_j = −(I − d dᵀ) + [d]ₓ(I − v̂v̂ᵀ)[r_j]ₓ / L` for a body
//! joint (the turn of the gaze, and the parallax of the eye moving by `ω × r_j`,
//! `r_j = p − pivot_j`, `L = |t − p|`), and `−½ (I − d dᵀ)` for an eye. Each iteration solves
//! `Δω = Jᵀ (J Jᵀ + λ² I)⁻¹ (−e)`, applies every joint's rotation and clamps it to its limits
//! (a joint stopped by a limit leaves the Jacobian: the clamping loop of Baerlocher & Boulic),
//! until the gaze is within the tolerance or the iteration limit is reached.

// The loops index the per-joint arrays (pivots, frames, blocks, deltas) together.
#![allow(clippy::needless_range_loop)]

use crowdgaze::ik::{CharacterTransform, GazeChain};
use glam::{Mat3, Quat, Vec3};

/// Settings of the DLS solve.
#[derive(Debug, Clone, Copy)]
pub struct JacobianIk {
    /// Damping λ.
    pub damping: f32,
    /// Stop when the gaze is within this angle of the target, radians.
    pub tolerance: f32,
    /// Most iterations.
    pub max_iterations: u32,
    /// Largest error (radians) corrected in one iteration.
    pub max_step: f32,
}

impl Default for JacobianIk {
    fn default() -> Self {
        JacobianIk {
            damping: 0.05,
            tolerance: 0.5f32.to_radians(),
            max_iterations: 100,
            max_step: 0.3,
        }
    }
}

/// One forward-kinematics pass: each joint's pivot and pre-delta frame rotation, the eye
/// mid-point and the cyclopean gaze direction.
struct Pose {
    pivots: [Vec3; 15],
    frames: [Quat; 15],
    eye: Vec3,
    gaze: Vec3,
}

fn forward(
    chain: &GazeChain,
    character: &CharacterTransform,
    base: &[Quat],
    deltas: &[Quat],
) -> Pose {
    let joints = chain.joints();
    let body = chain.body_count();
    let mut pose = Pose {
        pivots: [Vec3::ZERO; 15],
        frames: [Quat::IDENTITY; 15],
        eye: Vec3::ZERO,
        gaze: Vec3::ZERO,
    };
    let mut position = character.position + character.rotation * chain.root_offset();
    let mut rotation = character.rotation;
    for index in 0..body {
        position += rotation * joints[index].offset;
        let frame = rotation * base[index];
        pose.pivots[index] = position;
        pose.frames[index] = frame;
        rotation = frame * deltas[index];
    }
    match chain.eye_indices() {
        Some(eyes) => {
            let mut gaze = Vec3::ZERO;
            let mut eye = Vec3::ZERO;
            for index in eyes {
                let pivot = position + rotation * joints[index].offset;
                let frame = rotation * base[index];
                let local_forward = joints[index].rest.conjugate() * chain.eye_forward();
                pose.pivots[index] = pivot;
                pose.frames[index] = frame;
                eye += 0.5 * pivot;
                gaze += frame * deltas[index] * local_forward;
            }
            pose.eye = eye;
            pose.gaze = gaze.normalize();
        }
        None => {
            pose.eye = position;
            pose.gaze = (rotation * chain.eye_forward()).normalize();
        }
    }
    pose
}

impl JacobianIk {
    /// Solves from `deltas` (e.g. identity) towards `target`; returns the iterations used and
    /// whether the tolerance was reached.
    pub fn solve(
        &self,
        chain: &GazeChain,
        character: &CharacterTransform,
        base: &[Quat],
        target: Vec3,
        deltas: &mut [Quat],
    ) -> (u32, bool) {
        let count = chain.joint_count();
        let body = chain.body_count();
        let damping = Mat3::from_diagonal(Vec3::splat(self.damping * self.damping));
        // Joints stopped by their limits leave the Jacobian (Baerlocher & Boulic's clamping
        // loop), so that the others take over.
        let mut saturated = [false; 15];
        for iteration in 0..self.max_iterations {
            let pose = forward(chain, character, base, deltas);
            let to_target = target - pose.eye;
            let distance = to_target.length();
            let direction = to_target / distance;
            let cos = pose.gaze.dot(direction).clamp(-1.0, 1.0);
            if cos.acos() <= self.tolerance {
                return (iteration, true);
            }
            // The error is the rotation vector θ·axis from the gaze to the target direction
            // (linear in a turn about the axis, unlike sin θ, whose slope vanishes at 90°).
            let cross = pose.gaze.cross(direction);
            let sin = cross.length();
            let angle = sin.atan2(cos);
            let error = if sin > 1e-9 {
                cross * (angle / sin)
            } else {
                Vec3::ZERO
            };
            let gaze_x = skew(pose.gaze);
            // A turn ω of the gaze changes the error by −(I − d dᵀ) ω.
            let turn = outer(pose.gaze, pose.gaze) - Mat3::IDENTITY;
            let projector = Mat3::IDENTITY - outer(direction, direction);
            let parallax = gaze_x * projector * (1.0 / distance);
            let mut blocks = [Mat3::ZERO; 15];
            let mut normal = damping;
            for index in 0..count {
                if std::mem::take(&mut saturated[index]) {
                    blocks[index] = Mat3::ZERO;
                    continue;
                }
                let block = if index < body {
                    turn + parallax * skew(pose.eye - pose.pivots[index])
                } else {
                    turn * 0.5
                };
                normal += block * block.transpose();
                blocks[index] = block;
            }
            // Buss & Kim's error clamping: at most `max_step` radians per iteration, so that
            // the linear model stays valid for large turns.
            let length = error.length();
            let error = if length > self.max_step {
                error * (self.max_step / length)
            } else {
                error
            };
            let solved = normal.inverse() * -error;
            for index in 0..count {
                let world = blocks[index].transpose() * solved;
                let local = pose.frames[index].conjugate() * world;
                let angle = local.length();
                if angle > 1e-9 {
                    let step = Quat::from_axis_angle(local / angle, angle);
                    let limits = chain.joints()[index].limits;
                    let wanted = (step * deltas[index]).normalize();
                    let clamped = limits.clamp(wanted);
                    // Stopped by a limit this time: left out of the next iteration only.
                    saturated[index] = clamped != wanted;
                    deltas[index] = clamped;
                }
            }
        }
        (self.max_iterations, false)
    }
}

fn skew(v: Vec3) -> Mat3 {
    Mat3::from_cols(
        Vec3::new(0.0, v.z, -v.y),
        Vec3::new(-v.z, 0.0, v.x),
        Vec3::new(v.y, -v.x, 0.0),
    )
}

fn outer(a: Vec3, b: Vec3) -> Mat3 {
    Mat3::from_cols(a * b.x, a * b.y, a * b.z)
}
