//! Argument values built from the input: vectors, quaternions, rigid transforms, weights.

use super::input::Input;
use super::rigid;
use crowdgaze::ffi::types::{cg_dualquat, cg_quat, cg_vec3};

/// Any three floats of [`Input::float`].
pub fn vec3(input: &mut Input) -> cg_vec3 {
    cg_vec3 {
        x: input.float(),
        y: input.float(),
        z: input.float(),
    }
}

/// A point around `(0, height, 0)`.
pub fn point(input: &mut Input, height: f32) -> cg_vec3 {
    let mut point = vec3(input);
    point.y += height;
    point
}

/// A rotation: mostly a small unnormalised one, rarely zero, tiny or any four floats.
pub fn quat(input: &mut Input) -> cg_quat {
    match input.below(16) {
        13 => cg_quat {
            x: 0.0,
            y: 0.0,
            z: 0.0,
            w: 0.0,
        },
        14 => cg_quat {
            x: input.float(),
            y: input.float(),
            z: input.float(),
            w: input.float(),
        },
        15 => cg_quat {
            x: 1.0e-30,
            y: 0.0,
            z: -1.0e-30,
            w: 1.0e-30,
        },
        _ => cg_quat {
            x: input.float() / 8.0,
            y: input.float() / 8.0,
            z: input.float() / 8.0,
            w: 1.0,
        },
    }
}

/// A rigid transform: mostly a rotation about the vertical and a translation, rarely any
/// eight floats, a zero real part, the antipodal form or a huge translation.
pub fn dualquat(input: &mut Input) -> cg_dualquat {
    match input.below(16) {
        12 => cg_dualquat {
            real: quat(input),
            dual: cg_quat {
                x: input.float(),
                y: input.float(),
                z: input.float(),
                w: input.float(),
            },
        },
        13 => cg_dualquat {
            real: cg_quat {
                x: 0.0,
                y: 0.0,
                z: 0.0,
                w: 0.0,
            },
            dual: quat(input),
        },
        14 => {
            let q = rigid(input.float(), vec3(input));
            let negate = |q: cg_quat| cg_quat {
                x: -q.x,
                y: -q.y,
                z: -q.z,
                w: -q.w,
            };
            cg_dualquat {
                real: negate(q.real),
                dual: negate(q.dual),
            }
        }
        15 => rigid(
            input.float(),
            cg_vec3 {
                x: 3.0e37,
                y: input.float(),
                z: -3.0e37,
            },
        ),
        _ => rigid(input.float(), vec3(input)),
    }
}

/// `count` rigid transforms.
pub fn dualquats(input: &mut Input, count: usize) -> Vec<cg_dualquat> {
    (0..count).map(|_| dualquat(input)).collect()
}

/// A blend weight: mostly in [0, 4), rarely negative, zero or any float.
pub fn weight(input: &mut Input) -> f32 {
    match input.below(16) {
        13 => -0.5,
        14 => input.float(),
        15 => 0.0,
        _ => f32::from(input.byte()) / 64.0 + 0.01,
    }
}
