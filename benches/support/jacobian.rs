//! The baseline of Grillon & Thalmann's comparison: a damped-least-squares (DLS) Jacobian IK
//! turning the same gaze chain until the gaze ray points at the target. Bench code only —
//! the library never iterates.
//!
//! Task: the error `e = d × v̂` between the cyclopean gaze direction `d` (the mean of the two
//! eyes' directions, from their mid-point `p`) and the unit direction `v̂` from `p` to the
//! target (`|e| = sin θ`). Every joint has 3 rotational DOF (a small world rotation `ω` about
//! its pivot); its 3×3 Jacobian block is
//! `J_j = [v̂]ₓ[d]ₓ + [d]ₓ(I − v̂v̂ᵀ)[r_j]ₓ / L` for a body joint (`r_j = p − pivot_j`,
//! `L = |t − p|`), and `½ [v̂]ₓ[d]ₓ` for an eye. Each iteration solves
//! `Δω = Jᵀ (J Jᵀ + λ² I)⁻¹ (−e)`, applies every joint's rotation and clamps it to its limits,
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
}

impl Default for JacobianIk {
    fn default() -> Self {
        JacobianIk {
            damping: 0.05,
            tolerance: 0.5f32.to_radians(),
            max_iterations: 100,
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
        for iteration in 0..self.max_iterations {
            let pose = forward(chain, character, base, deltas);
            let to_target = target - pose.eye;
            let distance = to_target.length();
            let direction = to_target / distance;
            let cos = pose.gaze.dot(direction).clamp(-1.0, 1.0);
            if cos.acos() <= self.tolerance {
                return (iteration, true);
            }
            let error = pose.gaze.cross(direction);
            let gaze_x = skew(pose.gaze);
            let direction_x = skew(direction);
            let turn = direction_x * gaze_x;
            let projector = Mat3::IDENTITY - outer(direction, direction);
            let parallax = gaze_x * projector * (1.0 / distance);
            let mut blocks = [Mat3::ZERO; 15];
            let mut normal = damping;
            for index in 0..count {
                let block = if index < body {
                    turn + parallax * skew(pose.eye - pose.pivots[index])
                } else {
                    turn * 0.5
                };
                normal += block * block.transpose();
                blocks[index] = block;
            }
            let solved = normal.inverse() * -error;
            for index in 0..count {
                let world = blocks[index].transpose() * solved;
                let local = pose.frames[index].conjugate() * world;
                let angle = local.length();
                if angle > 1e-9 {
                    let step = Quat::from_axis_angle(local / angle, angle);
                    let limits = chain.joints()[index].limits;
                    deltas[index] = limits.clamp((step * deltas[index]).normalize());
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
