//! Behaviour of dual quaternion blending and view-adaptive animation, through the Rust API
//! and through the C ABI: round trips, DLB and DIB properties, view weights, key clips, and
//! every kind of bad input from C.

// The `unsafe { cg_... }` calls below pass pointers to live values of the sizes the header
// asks for, or deliberately bad ones (NULL, misaligned, wrong struct_size) that the library
// must refuse: that is their safety comment, once for the file.
#![allow(clippy::undocumented_unsafe_blocks)]

use std::f32::consts::{FRAC_PI_2, FRAC_PI_3, PI};
use std::ptr::{null, null_mut};

use glam::{Mat4, Quat, Vec3};

use crowdgaze::blend::{
    blend_pose_dib, dib, dlb, BlendMethod, DibSettings, KeyClip, ViewBlender, ViewBlenderConfig,
    ViewDistance,
};
use crowdgaze::ffi::blend::*;
use crowdgaze::ffi::cg_status;
use crowdgaze::ffi::last_error::last_error_message;
use crowdgaze::ffi::types::{cg_dualquat, cg_quat, cg_vec3};
use crowdgaze::ffi::view_blender::*;
use crowdgaze::math::random::Random;
use crowdgaze::DualQuat;

// ---------------------------------------------------------------------------------------------
// Helpers

fn transform(axis: Vec3, angle: f32, translation: Vec3) -> DualQuat {
    DualQuat::from_rotation_translation(Quat::from_axis_angle(axis.normalize(), angle), translation)
}

/// Same rigid transform (q̂ or −q̂) within `tolerance` on the 8 components.
fn same(a: DualQuat, b: DualQuat, tolerance: f32) -> bool {
    (a - b).length() <= tolerance || (a + b).length() <= tolerance
}

fn is_rigid(q: DualQuat) -> bool {
    (q.real.length() - 1.0).abs() < 1e-5 && q.real.dot(q.dual).abs() < 1e-5
}

fn random_transform(random: &mut Random, angle: f32, reach: f32) -> DualQuat {
    let axis = Vec3::new(
        random.range(-1.0, 1.0),
        random.range(-1.0, 1.0),
        random.range(-1.0, 1.0),
    )
    .try_normalize()
    .unwrap_or(Vec3::Y);
    transform(
        axis,
        random.range(-angle, angle),
        Vec3::new(
            random.range(-reach, reach),
            random.range(-reach, reach),
            random.range(-reach, reach),
        ),
    )
}

fn c(q: DualQuat) -> cg_dualquat {
    q.into()
}

fn rust(q: cg_dualquat) -> DualQuat {
    DualQuat::from_parts(
        Quat::from_xyzw(q.real.x, q.real.y, q.real.z, q.real.w),
        Quat::from_xyzw(q.dual.x, q.dual.y, q.dual.z, q.dual.w),
    )
}

const SENTINEL: cg_dualquat = cg_dualquat {
    real: cg_quat {
        x: 7.0,
        y: 7.0,
        z: 7.0,
        w: 7.0,
    },
    dual: cg_quat {
        x: 7.0,
        y: 7.0,
        z: 7.0,
        w: 7.0,
    },
};

fn vec3(x: f32, y: f32, z: f32) -> cg_vec3 {
    cg_vec3 { x, y, z }
}

// ---------------------------------------------------------------------------------------------
// Conversions

#[test]
fn rotation_translation_dual_quaternion_and_matrix_round_trip() {
    let mut random = Random::new(1);
    for _ in 0..200 {
        let q = random_transform(&mut random, PI, 50.0);
        let (rotation, translation) = q.to_rotation_translation();

        // Rust: rt → dq → matrix → dq → rt.
        let back = DualQuat::from_mat4(&q.to_mat4()).unwrap();
        assert!(
            same(back, q, 1e-6 * translation.length().max(1.0)),
            "{q:?} vs {back:?}"
        );
        let (r2, t2) = back.to_rotation_translation();
        assert!(r2.dot(rotation).abs() > 1.0 - 1e-6);
        assert!((t2 - translation).length() <= 1e-6 * translation.length().max(1.0));

        // C: the same through the ABI.
        let mut dq = SENTINEL;
        assert_eq!(
            unsafe { cg_dualquat_from_rt(&rotation.into(), &translation.into(), &mut dq) },
            cg_status::Ok
        );
        // 1e−6 relative to the translation: f32 resolves no better.
        let tolerance = 1e-6 * translation.length().max(1.0);
        assert!(same(rust(dq), q, tolerance));
        let mut matrix = [0.0f32; 16];
        assert_eq!(
            unsafe { cg_dualquat_to_matrix(&dq, matrix.as_mut_ptr()) },
            cg_status::Ok
        );
        let expected = Mat4::from_rotation_translation(rotation, translation).to_cols_array();
        for (a, b) in matrix.iter().zip(expected) {
            assert!(
                (a - b).abs() <= 1e-6 * b.abs().max(1.0) * 4.0,
                "{matrix:?} vs {expected:?}"
            );
        }
        let mut from_matrix = SENTINEL;
        assert_eq!(
            unsafe { cg_dualquat_from_matrix(matrix.as_ptr(), &mut from_matrix) },
            cg_status::Ok
        );
        let mut out_rotation = cg_quat::IDENTITY;
        let mut out_translation = cg_vec3::default();
        assert_eq!(
            unsafe { cg_dualquat_to_rt(&from_matrix, &mut out_rotation, &mut out_translation) },
            cg_status::Ok
        );
        let out_rotation = Quat::from_xyzw(
            out_rotation.x,
            out_rotation.y,
            out_rotation.z,
            out_rotation.w,
        );
        assert!(out_rotation.dot(rotation).abs() > 1.0 - 1e-6);
        let out_translation = Vec3::new(out_translation.x, out_translation.y, out_translation.z);
        assert!((out_translation - translation).length() <= 1e-6 * translation.length().max(1.0));
    }
}

#[test]
fn osg_row_vector_matrices_are_read_as_is() {
    // osg::Matrixf for "rotate 90° about z, then translate (1, 2, 3)" in memory order
    // (row vectors: the 4th row is the translation).
    let osg: [f32; 16] = [
        0.0, 1.0, 0.0, 0.0, -1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 1.0, 2.0, 3.0, 1.0,
    ];
    let mut dq = SENTINEL;
    assert_eq!(
        unsafe { cg_dualquat_from_matrix(osg.as_ptr(), &mut dq) },
        cg_status::Ok
    );
    let q = rust(dq);
    assert!((q.transform_point(Vec3::X) - Vec3::new(1.0, 3.0, 3.0)).length() < 1e-6);
}

// ---------------------------------------------------------------------------------------------
// DLB and DIB

#[test]
fn dlb_equals_the_closed_formula_through_c() {
    let mut random = Random::new(2);
    for _ in 0..50 {
        let inputs: Vec<DualQuat> = (0..4)
            .map(|_| random_transform(&mut random, 1.0, 2.0))
            .collect();
        let weights: Vec<f32> = (0..4).map(|_| random.range(0.05, 1.0)).collect();
        // Σ w_k q̂_k (aligned to the first), then q̂ / ‖q̂‖ with the dual norm.
        let mut sum = DualQuat::ZERO;
        for (q, &w) in inputs.iter().zip(&weights) {
            let sign = if q.real.dot(inputs[0].real) < 0.0 {
                -1.0
            } else {
                1.0
            };
            sum = sum + *q * (w * sign);
        }
        let norm = sum.real.length();
        let real = sum.real / norm;
        let dual = sum.dual / norm - real * (real.dot(sum.dual) / norm);
        let expected = DualQuat::from_parts(real, dual);

        let c_inputs: Vec<cg_dualquat> = inputs.iter().map(|&q| c(q)).collect();
        let mut out = SENTINEL;
        assert_eq!(
            unsafe { cg_blend_dlb(c_inputs.as_ptr(), weights.as_ptr(), 4, &mut out) },
            cg_status::Ok
        );
        assert!(
            (rust(out) - expected).length() < 1e-6,
            "{out:?} vs {expected:?}"
        );
        assert!(is_rigid(rust(out)));
    }
}

#[test]
fn dib_of_two_is_sclerp_and_of_one_is_the_input() {
    let mut random = Random::new(3);
    for _ in 0..50 {
        let a = random_transform(&mut random, 2.5, 3.0);
        let b = random_transform(&mut random, 2.5, 3.0);
        let t = random.range(0.0, 1.0);
        let expected = a.sclerp(b, t);
        let inputs = [c(a), c(b)];
        let weights = [1.0 - t, t];
        let mut out = SENTINEL;
        assert_eq!(
            unsafe { cg_blend_dib(inputs.as_ptr(), weights.as_ptr(), 2, 1e-6, 16, &mut out) },
            cg_status::Ok
        );
        assert!(same(rust(out), expected, 1e-5));
        // The iteration itself reaches the same point (b split in two equal halves).
        let iterated = dib(
            &[a, b, b],
            &[1.0 - t, t / 2.0, t / 2.0],
            &DibSettings::default(),
        )
        .unwrap();
        assert!(iterated.converged);
        assert!(same(iterated.blend, expected, 1e-5), "t = {t}");

        let mut one = SENTINEL;
        assert_eq!(
            unsafe { cg_blend_dib(inputs.as_ptr(), [0.4f32].as_ptr(), 1, 1e-6, 16, &mut one) },
            cg_status::Ok
        );
        assert!(same(rust(one), a, 1e-6));
    }
}

#[test]
fn dib_is_coordinate_invariant_and_rigid() {
    let mut random = Random::new(4);
    let settings = DibSettings {
        precision: 1e-6,
        max_iterations: 50,
    };
    for _ in 0..40 {
        let inputs: Vec<DualQuat> = (0..5)
            .map(|_| random_transform(&mut random, 1.2, 1.5))
            .collect();
        let weights: Vec<f32> = (0..5).map(|_| random.range(0.05, 1.0)).collect();
        let blended = dib(&inputs, &weights, &settings).unwrap();
        assert!(blended.converged, "{blended:?}");
        assert!(is_rigid(blended.blend));

        let change = random_transform(&mut random, PI, 3.0);
        let moved: Vec<DualQuat> = inputs.iter().map(|&q| change * q).collect();
        let moved_blend = dib(&moved, &weights, &settings).unwrap();
        assert!(
            same(moved_blend.blend, change * blended.blend, 2e-5),
            "left: {:?} vs {:?}",
            moved_blend.blend,
            change * blended.blend
        );
        let reframed: Vec<DualQuat> = inputs.iter().map(|&q| q * change).collect();
        let reframed_blend = dib(&reframed, &weights, &settings).unwrap();
        assert!(same(reframed_blend.blend, blended.blend * change, 2e-5));
    }
}

#[test]
fn dlb_is_close_to_dib_for_nearby_keys() {
    let mut random = Random::new(5);
    for _ in 0..40 {
        let inputs: Vec<DualQuat> = (0..3)
            .map(|_| random_transform(&mut random, 0.5, 0.3))
            .collect();
        let weights = [0.2f32, 0.3, 0.5];
        let linear = dlb(&inputs, &weights).unwrap();
        let iterative = dib(&inputs, &weights, &DibSettings::default()).unwrap();
        assert!(same(linear, iterative.blend, 2e-2));
    }
}

#[test]
fn antipodal_inputs_blend_the_short_way() {
    let a = transform(Vec3::Z, 0.2, Vec3::new(1.0, 0.0, 0.0));
    let b = transform(Vec3::Z, 0.8, Vec3::new(1.0, 0.0, 0.0));
    let c_ = transform(Vec3::Z, 0.5, Vec3::new(1.0, 0.0, 0.0));
    let weights = [0.25f32, 0.25, 0.5];
    for inputs in [[a, b, c_], [a, -b, c_], [-a, b, -c_]] {
        let linear = dlb(&inputs, &weights).unwrap();
        let iterative = dib(&inputs, &weights, &DibSettings::default())
            .unwrap()
            .blend;
        for q in [linear, iterative] {
            assert!(same(q, c_, 1e-5), "{inputs:?} -> {q:?}");
        }
    }
}

#[test]
fn not_converging_is_reported_with_the_best_result_written() {
    let inputs = [
        c(DualQuat::IDENTITY),
        c(transform(Vec3::Y, 2.5, Vec3::new(3.0, 0.0, 0.0))),
        c(transform(Vec3::X, 2.0, Vec3::new(0.0, 3.0, 0.0))),
    ];
    let weights = [0.3f32, 0.4, 0.3];
    let mut out = SENTINEL;
    assert_eq!(
        unsafe { cg_blend_dib(inputs.as_ptr(), weights.as_ptr(), 3, 1e-6, 1, &mut out) },
        cg_status::NotConverged
    );
    assert!(last_error_message().starts_with("not converged: DIB: 1 of 1"));
    let mut linear = SENTINEL;
    assert_eq!(
        unsafe { cg_blend_dlb(inputs.as_ptr(), weights.as_ptr(), 3, &mut linear) },
        cg_status::Ok
    );
    assert!(
        same(rust(out), rust(linear), 1e-6),
        "the best measured iterate is DLB"
    );
    // With enough iterations the same blend converges.
    assert_eq!(
        unsafe { cg_blend_dib(inputs.as_ptr(), weights.as_ptr(), 3, 1e-6, 100, &mut out) },
        cg_status::Ok
    );

    // Pose form: every joint is written, the status says some did not converge.
    let keys = [
        inputs[0], inputs[0], inputs[1], inputs[1], inputs[2], inputs[2],
    ];
    let mut pose = [SENTINEL; 2];
    assert_eq!(
        unsafe {
            cg_blend_pose_dib(
                keys.as_ptr(),
                weights.as_ptr(),
                3,
                2,
                1e-6,
                1,
                pose.as_mut_ptr(),
            )
        },
        cg_status::NotConverged
    );
    assert!(pose.iter().all(|q| *q != SENTINEL));
}

#[test]
fn pose_forms_blend_joint_by_joint() {
    let mut random = Random::new(6);
    let (keys, joints) = (3usize, 5usize);
    let poses: Vec<DualQuat> = (0..keys * joints)
        .map(|_| random_transform(&mut random, 0.8, 0.5))
        .collect();
    let weights = [0.5f32, 0.2, 0.3];
    let c_poses: Vec<cg_dualquat> = poses.iter().map(|&q| c(q)).collect();
    let mut linear = vec![SENTINEL; joints];
    let mut iterative = vec![SENTINEL; joints];
    assert_eq!(
        unsafe {
            cg_blend_pose_dlb(
                c_poses.as_ptr(),
                weights.as_ptr(),
                keys,
                joints,
                linear.as_mut_ptr(),
            )
        },
        cg_status::Ok
    );
    assert_eq!(
        unsafe {
            cg_blend_pose_dib(
                c_poses.as_ptr(),
                weights.as_ptr(),
                keys,
                joints,
                1e-6,
                16,
                iterative.as_mut_ptr(),
            )
        },
        cg_status::Ok
    );
    let mut rust_pose = vec![DualQuat::ZERO; joints];
    blend_pose_dib(
        &poses,
        &weights,
        joints,
        &DibSettings::default(),
        &mut rust_pose,
    )
    .unwrap();
    for j in 0..joints {
        let column: Vec<DualQuat> = (0..keys).map(|k| poses[k * joints + j]).collect();
        assert!(same(rust(linear[j]), dlb(&column, &weights).unwrap(), 1e-6));
        let expected = dib(&column, &weights, &DibSettings::default())
            .unwrap()
            .blend;
        assert!(same(rust(iterative[j]), expected, 1e-6));
        assert!(same(rust_pose[j], expected, 1e-6));
    }
    // An empty pose is valid.
    assert_eq!(
        unsafe { cg_blend_pose_dlb(null(), weights.as_ptr(), keys, 0, null_mut()) },
        cg_status::Ok
    );
}

// ---------------------------------------------------------------------------------------------
// View weights

/// Three keys with cameras at 60° left, front and 60° right of a character facing +z (y up).
fn three_key_blender(alpha: f32, distance: ViewDistance) -> ViewBlender {
    let mut config = ViewBlenderConfig::new(1, 3);
    config.alpha = alpha;
    config.distance = distance;
    let mut blender = ViewBlender::new(config).unwrap();
    let (sin, cos) = FRAC_PI_3.sin_cos();
    blender.add_camera(Vec3::new(sin, 0.0, cos), 0).unwrap();
    blender.add_camera(Vec3::Z, 1).unwrap();
    blender.add_camera(Vec3::new(-sin, 0.0, cos), 2).unwrap();
    blender
}

fn weights_at(blender: &ViewBlender, character: DualQuat, viewer: Vec3) -> Vec<f32> {
    let mut w = vec![0.0; blender.config().key_count];
    blender.weights(character, viewer, &mut w).unwrap();
    w
}

#[test]
fn weights_are_convex_and_one_on_a_key_camera() {
    let character =
        DualQuat::from_rotation_translation(Quat::from_rotation_y(0.7), Vec3::new(12.0, 0.0, -3.0));
    for distance in [ViewDistance::Geodesic, ViewDistance::Chordal] {
        let blender = three_key_blender(2.0, distance);
        let mut random = Random::new(7);
        for _ in 0..500 {
            let viewer = Vec3::new(
                random.range(-20.0, 40.0),
                random.range(-5.0, 5.0),
                random.range(-20.0, 20.0),
            );
            let w = weights_at(&blender, character, viewer);
            assert!(w.iter().all(|&w| (0.0..=1.0).contains(&w)), "{w:?}");
            assert!((w.iter().sum::<f32>() - 1.0).abs() < 1e-6, "{w:?}");
        }
        // On each key camera, at any range: that key alone.
        for (camera, key) in blender.key_cameras().iter().map(|c| (c.direction, c.key)) {
            for range in [0.5f32, 3.0, 250.0] {
                let viewer = character.transform_point(camera.as_vec3() * range);
                let w = weights_at(&blender, character, viewer);
                for (k, &weight) in w.iter().enumerate() {
                    assert_eq!(weight, if k == key { 1.0 } else { 0.0 }, "{w:?}");
                }
            }
        }
    }
}

#[test]
fn weights_are_continuous_in_the_viewer_position() {
    let blender = three_key_blender(3.0, ViewDistance::Geodesic);
    let character = DualQuat::from_translation(Vec3::new(1.0, 0.0, 1.0));
    // Walk around the character in small steps, through every key camera.
    let steps = 20_000;
    let mut previous: Option<Vec<f32>> = None;
    for i in 0..=steps {
        let angle = 2.0 * PI * i as f32 / steps as f32;
        let viewer = Vec3::new(1.0 + 3.0 * angle.sin(), 0.0, 1.0 + 3.0 * angle.cos());
        let w = weights_at(&blender, character, viewer);
        if let Some(before) = &previous {
            let jump = w
                .iter()
                .zip(before)
                .map(|(a, b)| (a - b).abs())
                .fold(0.0f32, f32::max);
            assert!(jump < 0.01, "jump {jump} at step {i}: {before:?} -> {w:?}");
        }
        previous = Some(w);
    }
    // Just off a key camera the weight is just below 1.
    let (sin, cos) = FRAC_PI_3.sin_cos();
    let near = Vec3::new(1.0 + 3.0 * sin, 0.0001, 1.0 + 3.0 * cos);
    let w = weights_at(&blender, character, near);
    assert!(w[0] > 0.999_999 && w[0] <= 1.0, "{w:?}");
}

#[test]
fn many_cameras_may_map_to_one_key() {
    let mut blender = ViewBlender::new(ViewBlenderConfig::new(1, 2)).unwrap();
    blender.add_camera(Vec3::X, 0).unwrap();
    blender.add_camera(-Vec3::X, 0).unwrap();
    blender.add_camera(Vec3::Z, 1).unwrap();
    // Viewer at +z: key 1 alone; at −z (all three cameras at 90°... −z is 90° from ±x and 180°
    // from +z): key 0 sums two cameras.
    assert_eq!(
        weights_at(&blender, DualQuat::IDENTITY, Vec3::Z * 2.0),
        vec![0.0, 1.0]
    );
    let w = weights_at(&blender, DualQuat::IDENTITY, -Vec3::Z * 2.0);
    let (near, far) = (FRAC_PI_2.powi(-2), PI.powi(-2));
    let expected = 2.0 * near / (2.0 * near + far);
    assert!((w[0] - expected).abs() < 1e-6, "{w:?} vs {expected}");
    assert_eq!(
        weights_at(&blender, DualQuat::IDENTITY, -Vec3::X * 9.0),
        vec![1.0, 0.0]
    );
}

#[test]
fn alpha_focuses_the_weights() {
    // A viewer 20° from the front camera: the front key's weight grows with α.
    let viewer = Vec3::new(20f32.to_radians().sin(), 0.0, 20f32.to_radians().cos()) * 4.0;
    let mut previous = 0.0;
    for alpha in [2.0f32, 3.0, 4.0] {
        let blender = three_key_blender(alpha, ViewDistance::Geodesic);
        let w = weights_at(&blender, DualQuat::IDENTITY, viewer);
        assert!(w[1] > previous, "alpha {alpha}: {w:?}");
        previous = w[1];
        // Equation 2 by hand.
        let d = [40f32.to_radians(), 20f32.to_radians(), 80f32.to_radians()];
        let inv: Vec<f32> = d.iter().map(|d| d.powf(-alpha)).collect();
        let total: f32 = inv.iter().sum();
        for k in 0..3 {
            assert!((w[k] - inv[k] / total).abs() < 1e-5, "{w:?}");
        }
    }
}

#[test]
fn the_viewer_at_the_centre_is_an_error_not_a_nan() {
    let blender = three_key_blender(2.0, ViewDistance::Geodesic);
    let character = DualQuat::from_translation(Vec3::new(5.0, 1.0, 2.0));
    let mut w = [0.5f32; 3];
    assert!(blender
        .weights(character, Vec3::new(5.0, 1.0, 2.0), &mut w)
        .is_err());
    assert_eq!(w, [0.5; 3]);
}

// ---------------------------------------------------------------------------------------------
// Key clips and evaluation

#[test]
fn evaluate_samples_clips_and_blends_them() {
    // Two joints; key 0 turns the head left over one second (looping at 4 fps), key 1 is a
    // static pose looking right.
    let joints = 2;
    let mut config = ViewBlenderConfig::new(joints, 2);
    config.method = BlendMethod::Dib;
    let mut blender = ViewBlender::new(config).unwrap();
    let frames: Vec<DualQuat> = (0..4)
        .flat_map(|f| {
            [
                DualQuat::from_translation(Vec3::Y),
                DualQuat::from_rotation_translation(
                    Quat::from_rotation_y(0.2 * f as f32),
                    Vec3::Y * 0.5,
                ),
            ]
        })
        .collect();
    blender
        .set_key_clip(0, KeyClip::new(&frames, joints, 4.0, true).unwrap())
        .unwrap();
    let right = [
        DualQuat::from_translation(Vec3::Y),
        DualQuat::from_rotation_translation(Quat::from_rotation_y(-0.8), Vec3::Y * 0.5),
    ];
    blender.set_key_pose(1, &right).unwrap();
    blender.add_camera(Vec3::X, 0).unwrap();
    blender.add_camera(-Vec3::X, 1).unwrap();

    let mut pose = [DualQuat::ZERO; 2];
    // On key 0's camera at t = 0.375 s: frame 1.5 of key 0.
    blender
        .evaluate(DualQuat::IDENTITY, Vec3::X * 3.0, 0.375, &mut pose)
        .unwrap();
    let (_, angle) = pose[1].real.to_axis_angle();
    assert!((angle - 0.3).abs() < 1e-4, "{angle}");
    // On key 1's camera: the static pose, whatever the time.
    blender
        .evaluate(DualQuat::IDENTITY, -Vec3::X * 3.0, 123.0, &mut pose)
        .unwrap();
    assert!(same(pose[1], right[1], 1e-6));
    // Halfway (in front): the two heads averaged — at t = 0 key 0's head is straight.
    let outcome = blender
        .evaluate(DualQuat::IDENTITY, Vec3::Z * 3.0, 0.0, &mut pose)
        .unwrap();
    assert!(outcome.converged());
    let (axis, angle) = pose[1].real.to_axis_angle();
    assert!(
        (angle - 0.4).abs() < 1e-4 && axis.y < -0.99,
        "{axis} {angle}"
    );
    assert!(pose.iter().all(|&q| is_rigid(q)));
}

// ---------------------------------------------------------------------------------------------
// The C view blender and bad input from C

fn c_config(joints: u32, keys: u32) -> cg_view_blender_config {
    let mut config = std::mem::MaybeUninit::<cg_view_blender_config>::uninit();
    // SAFETY: a versioned struct starts with its `uint32_t struct_size`, set before the call.
    unsafe {
        config
            .as_mut_ptr()
            .cast::<u32>()
            .write(std::mem::size_of::<cg_view_blender_config>() as u32)
    };
    assert_eq!(
        unsafe { cg_view_blender_config_init(config.as_mut_ptr()) },
        cg_status::Ok
    );
    // SAFETY: initialised by cg_view_blender_config_init.
    let mut config = unsafe { config.assume_init() };
    config.joint_count = joints;
    config.key_count = keys;
    config
}

fn c_blender(method: cg_blend_method) -> *mut cg_view_blender {
    let mut config = c_config(1, 3);
    config.method = method as u32;
    let mut blender = null_mut();
    assert_eq!(
        unsafe { cg_view_blender_create(&config, &mut blender) },
        cg_status::Ok
    );
    let (sin, cos) = FRAC_PI_3.sin_cos();
    let cameras = [
        vec3(sin, 0.0, cos),
        vec3(0.0, 0.0, 1.0),
        vec3(-sin, 0.0, cos),
    ];
    for (key, camera) in cameras.into_iter().enumerate() {
        let pose = [c(transform(Vec3::Y, (key as f32 - 1.0) * -0.9, Vec3::Y))];
        assert_eq!(
            unsafe { cg_view_blender_set_key_pose(blender, key as u32, pose.as_ptr(), 1) },
            cg_status::Ok
        );
        assert_eq!(
            unsafe { cg_view_blender_add_camera(blender, camera, key as u32) },
            cg_status::Ok
        );
    }
    blender
}

#[test]
fn the_c_view_blender_works_end_to_end() {
    for method in [cg_blend_method::Dlb, cg_blend_method::Dib] {
        let blender = c_blender(method);
        let character = c(DualQuat::from_rotation_translation(
            Quat::from_rotation_y(1.0),
            Vec3::new(2.0, 0.0, 3.0),
        ));
        let viewer = vec3(6.0, 1.6, -1.0);
        let mut w = [0.0f32; 3];
        assert_eq!(
            unsafe { cg_view_blender_weights(blender, &character, &viewer, w.as_mut_ptr(), 3) },
            cg_status::Ok
        );
        assert!((w.iter().sum::<f32>() - 1.0).abs() < 1e-6);
        let mut pose = [SENTINEL];
        assert_eq!(
            unsafe {
                cg_view_blender_evaluate(blender, &character, &viewer, 0.5, pose.as_mut_ptr(), 1)
            },
            cg_status::Ok
        );
        assert!(is_rigid(rust(pose[0])));
        unsafe { cg_view_blender_destroy(blender) };
    }
    unsafe { cg_view_blender_destroy(null_mut()) };
}

#[test]
fn bad_input_from_c_is_rejected_and_changes_nothing() {
    let q = c(DualQuat::IDENTITY);
    let w = [1.0f32];
    let mut out = SENTINEL;
    let mut nan = q;
    nan.dual.x = f32::NAN;
    let mut zero = q;
    zero.real = cg_quat {
        x: 0.0,
        y: 0.0,
        z: 0.0,
        w: 0.0,
    };

    // NULL and counts.
    assert_eq!(
        unsafe { cg_blend_dlb(null(), w.as_ptr(), 1, &mut out) },
        cg_status::NullArgument
    );
    assert_eq!(
        unsafe { cg_blend_dlb(&q, null(), 1, &mut out) },
        cg_status::NullArgument
    );
    assert_eq!(
        unsafe { cg_blend_dlb(&q, w.as_ptr(), 1, null_mut()) },
        cg_status::NullArgument
    );
    assert_eq!(
        unsafe { cg_blend_dlb(null(), null(), 0, &mut out) },
        cg_status::InvalidArgument
    );
    assert_eq!(
        unsafe { cg_dualquat_from_rt(null(), &vec3(0.0, 0.0, 0.0), &mut out) },
        cg_status::NullArgument
    );
    assert_eq!(
        unsafe { cg_dualquat_to_rt(&q, null_mut(), &mut cg_vec3::default()) },
        cg_status::NullArgument
    );
    assert_eq!(
        unsafe { cg_dualquat_from_matrix(null(), &mut out) },
        cg_status::NullArgument
    );
    assert_eq!(
        unsafe { cg_camera_center_from_projection(null(), &mut cg_vec3::default()) },
        cg_status::NullArgument
    );
    // Non-finite anywhere.
    assert_eq!(
        unsafe { cg_blend_dlb(&nan, w.as_ptr(), 1, &mut out) },
        cg_status::NonFinite
    );
    assert_eq!(
        unsafe { cg_blend_dlb(&q, [f32::INFINITY].as_ptr(), 1, &mut out) },
        cg_status::NonFinite
    );
    assert_eq!(
        unsafe { cg_blend_dib(&q, w.as_ptr(), 1, f32::NAN, 4, &mut out) },
        cg_status::NonFinite
    );
    assert_eq!(
        unsafe { cg_dualquat_from_rt(&cg_quat::IDENTITY, &vec3(f32::NAN, 0.0, 0.0), &mut out) },
        cg_status::NonFinite
    );
    let mut matrix = Mat4::IDENTITY.to_cols_array();
    matrix[13] = f32::INFINITY;
    assert_eq!(
        unsafe { cg_dualquat_from_matrix(matrix.as_ptr(), &mut out) },
        cg_status::NonFinite
    );
    // Invalid values.
    assert_eq!(
        unsafe { cg_blend_dlb(&zero, w.as_ptr(), 1, &mut out) },
        cg_status::InvalidArgument
    );
    assert_eq!(
        unsafe { cg_blend_dlb(&q, [-1.0f32].as_ptr(), 1, &mut out) },
        cg_status::InvalidArgument
    );
    assert_eq!(
        unsafe { cg_blend_dlb(&q, [0.0f32].as_ptr(), 1, &mut out) },
        cg_status::InvalidArgument
    );
    assert_eq!(
        unsafe { cg_blend_dib(&q, w.as_ptr(), 1, 0.0, 4, &mut out) },
        cg_status::InvalidArgument
    );
    assert_eq!(
        unsafe { cg_blend_dib(&q, w.as_ptr(), 1, 1e-6, 0, &mut out) },
        cg_status::InvalidArgument
    );
    assert_eq!(
        unsafe { cg_blend_dib(&q, w.as_ptr(), 1, 1e-6, 1001, &mut out) },
        cg_status::InvalidArgument
    );
    let scaled = Mat4::from_scale(Vec3::splat(2.0)).to_cols_array();
    assert_eq!(
        unsafe { cg_dualquat_from_matrix(scaled.as_ptr(), &mut out) },
        cg_status::InvalidArgument
    );
    // Pose forms: counts, overflow, aliasing.
    let keys = [q, q];
    let mut pose = [SENTINEL, SENTINEL];
    assert_eq!(
        unsafe { cg_blend_pose_dlb(keys.as_ptr(), w.as_ptr(), 1, usize::MAX, pose.as_mut_ptr()) },
        cg_status::InvalidArgument
    );
    let mut aliased = [q, q];
    assert_eq!(
        unsafe { cg_blend_pose_dlb(aliased.as_ptr(), w.as_ptr(), 1, 2, aliased.as_mut_ptr()) },
        cg_status::InvalidArgument
    );
    assert_eq!(
        unsafe { cg_blend_pose_dlb(keys.as_ptr(), w.as_ptr(), 1, 2, null_mut()) },
        cg_status::NullArgument
    );
    assert_eq!(out, SENTINEL, "failed calls write nothing");
    assert_eq!(pose, [SENTINEL, SENTINEL]);

    // Degenerate projection matrices.
    let mut centre = vec3(9.0, 9.0, 9.0);
    let affine = [
        1.0f32, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0,
    ];
    assert_eq!(
        unsafe { cg_camera_center_from_projection(affine.as_ptr(), &mut centre) },
        cg_status::InvalidArgument
    );
    assert_eq!(
        unsafe { cg_camera_center_from_projection([0.0f32; 12].as_ptr(), &mut centre) },
        cg_status::InvalidArgument
    );
    let mut nan_p = affine;
    nan_p[2] = f32::NAN;
    assert_eq!(
        unsafe { cg_camera_center_from_projection(nan_p.as_ptr(), &mut centre) },
        cg_status::NonFinite
    );
    assert_eq!(centre, vec3(9.0, 9.0, 9.0));
    // A good one: K = diag(500, 500, 1), R = I, centre (1, 2, 3) → t = −C.
    let good = [
        500.0f32, 0.0, 0.0, -500.0, 0.0, 500.0, 0.0, -1000.0, 0.0, 0.0, 1.0, -3.0,
    ];
    assert_eq!(
        unsafe { cg_camera_center_from_projection(good.as_ptr(), &mut centre) },
        cg_status::Ok
    );
    assert!(
        (centre.x - 1.0).abs() < 1e-5
            && (centre.y - 2.0).abs() < 1e-5
            && (centre.z - 3.0).abs() < 1e-5
    );
}

#[test]
fn bad_input_to_the_c_view_blender() {
    // Configs.
    let mut blender = null_mut();
    assert_eq!(
        unsafe { cg_view_blender_config_init(null_mut()) },
        cg_status::NullArgument
    );
    let mut config = c_config(1, 3);
    assert_eq!(
        unsafe { cg_view_blender_create(null(), &mut blender) },
        cg_status::NullArgument
    );
    assert_eq!(
        unsafe { cg_view_blender_create(&config, null_mut()) },
        cg_status::NullArgument
    );
    config.struct_size = 3;
    assert_eq!(
        unsafe { cg_view_blender_create(&config, &mut blender) },
        cg_status::BadStructSize
    );
    assert!(last_error_message().contains("cg_view_blender_config.struct_size is 3"));
    for (field, status) in [
        ("joints", cg_status::InvalidArgument),
        ("keys", cg_status::InvalidArgument),
        ("alpha", cg_status::InvalidArgument),
        ("alpha nan", cg_status::NonFinite),
        ("method", cg_status::InvalidArgument),
        ("distance", cg_status::InvalidArgument),
        ("precision", cg_status::InvalidArgument),
    ] {
        let mut config = c_config(1, 3);
        match field {
            "joints" => config.joint_count = 0,
            "keys" => config.key_count = 33,
            "alpha" => config.alpha = 5.0,
            "alpha nan" => config.alpha = f32::NAN,
            "method" => config.method = 2,
            "distance" => config.distance = 7,
            _ => config.precision = -1.0,
        }
        assert_eq!(
            unsafe { cg_view_blender_create(&config, &mut blender) },
            status,
            "{field}"
        );
    }
    assert!(blender.is_null(), "outputs are written only on success");

    // Setup calls.
    let config = c_config(2, 2);
    assert_eq!(
        unsafe { cg_view_blender_create(&config, &mut blender) },
        cg_status::Ok
    );
    let pose = [c(DualQuat::IDENTITY); 2];
    let mut nan_pose = pose;
    nan_pose[1].real.w = f32::NAN;
    assert_eq!(
        unsafe { cg_view_blender_set_key_pose(null_mut(), 0, pose.as_ptr(), 2) },
        cg_status::NullArgument
    );
    assert_eq!(
        unsafe { cg_view_blender_set_key_pose(blender, 0, null(), 2) },
        cg_status::NullArgument
    );
    assert_eq!(
        unsafe { cg_view_blender_set_key_pose(blender, 0, pose.as_ptr(), 1) },
        cg_status::InvalidArgument
    );
    assert_eq!(
        unsafe { cg_view_blender_set_key_pose(blender, 2, pose.as_ptr(), 2) },
        cg_status::InvalidArgument
    );
    assert_eq!(
        unsafe { cg_view_blender_set_key_pose(blender, 0, nan_pose.as_ptr(), 2) },
        cg_status::NonFinite
    );
    assert_eq!(
        unsafe { cg_view_blender_set_key_clip(blender, 0, null(), 0, 30.0, false) },
        cg_status::InvalidArgument
    );
    assert_eq!(
        unsafe { cg_view_blender_set_key_clip(blender, 0, pose.as_ptr(), 1, f32::NAN, false) },
        cg_status::NonFinite
    );
    let two_frames = [pose, pose].concat();
    assert_eq!(
        unsafe { cg_view_blender_set_key_clip(blender, 0, two_frames.as_ptr(), 2, 0.0, true) },
        cg_status::InvalidArgument
    );
    assert_eq!(
        unsafe {
            cg_view_blender_set_key_clip(blender, 0, two_frames.as_ptr(), usize::MAX, 30.0, true)
        },
        cg_status::InvalidArgument
    );
    assert_eq!(
        unsafe { cg_view_blender_add_camera(blender, vec3(0.0, 0.0, 0.0), 0) },
        cg_status::InvalidArgument
    );
    assert_eq!(
        unsafe { cg_view_blender_add_camera(blender, vec3(f32::NAN, 0.0, 1.0), 0) },
        cg_status::NonFinite
    );
    assert_eq!(
        unsafe { cg_view_blender_add_camera(blender, vec3(0.0, 0.0, 1.0), 9) },
        cg_status::InvalidArgument
    );

    // Per-frame calls before setup is complete.
    let character = c(DualQuat::IDENTITY);
    let viewer = vec3(0.0, 0.0, 3.0);
    let mut w = [0.25f32; 2];
    let mut out = [SENTINEL; 2];
    assert_eq!(
        unsafe { cg_view_blender_weights(blender, &character, &viewer, w.as_mut_ptr(), 2) },
        cg_status::WrongState
    );
    assert_eq!(
        unsafe { cg_view_blender_add_camera(blender, vec3(0.0, 0.0, 1.0), 0) },
        cg_status::Ok
    );
    assert_eq!(
        unsafe { cg_view_blender_add_camera(blender, vec3(1.0, 0.0, 0.0), 1) },
        cg_status::Ok
    );
    assert_eq!(
        unsafe { cg_view_blender_evaluate(blender, &character, &viewer, 0.0, out.as_mut_ptr(), 2) },
        cg_status::WrongState
    );
    assert_eq!(
        unsafe { cg_view_blender_set_key_clip(blender, 0, two_frames.as_ptr(), 2, 30.0, true) },
        cg_status::Ok
    );
    assert_eq!(
        unsafe { cg_view_blender_set_key_pose(blender, 1, pose.as_ptr(), 2) },
        cg_status::Ok
    );

    // Per-frame calls with bad arguments.
    let mut nan_character = character;
    nan_character.dual.z = f32::INFINITY;
    assert_eq!(
        unsafe { cg_view_blender_weights(null(), &character, &viewer, w.as_mut_ptr(), 2) },
        cg_status::NullArgument
    );
    assert_eq!(
        unsafe { cg_view_blender_weights(blender, null(), &viewer, w.as_mut_ptr(), 2) },
        cg_status::NullArgument
    );
    assert_eq!(
        unsafe { cg_view_blender_weights(blender, &character, null(), w.as_mut_ptr(), 2) },
        cg_status::NullArgument
    );
    assert_eq!(
        unsafe { cg_view_blender_weights(blender, &character, &viewer, null_mut(), 2) },
        cg_status::NullArgument
    );
    assert_eq!(
        unsafe { cg_view_blender_weights(blender, &character, &viewer, w.as_mut_ptr(), 1) },
        cg_status::InvalidArgument
    );
    assert_eq!(
        unsafe { cg_view_blender_weights(blender, &nan_character, &viewer, w.as_mut_ptr(), 2) },
        cg_status::NonFinite
    );
    assert_eq!(
        unsafe {
            cg_view_blender_weights(
                blender,
                &character,
                &vec3(0.0, f32::NAN, 0.0),
                w.as_mut_ptr(),
                2,
            )
        },
        cg_status::NonFinite
    );
    let at_centre = vec3(0.0, 0.0, 0.0);
    assert_eq!(
        unsafe { cg_view_blender_weights(blender, &character, &at_centre, w.as_mut_ptr(), 2) },
        cg_status::InvalidArgument
    );
    assert!(last_error_message().contains("centre"));
    assert_eq!(
        unsafe {
            cg_view_blender_evaluate(blender, &character, &at_centre, 0.0, out.as_mut_ptr(), 2)
        },
        cg_status::InvalidArgument
    );
    assert_eq!(
        unsafe {
            cg_view_blender_evaluate(blender, &character, &viewer, f64::NAN, out.as_mut_ptr(), 2)
        },
        cg_status::NonFinite
    );
    assert_eq!(
        unsafe { cg_view_blender_evaluate(blender, &character, &viewer, 0.0, out.as_mut_ptr(), 3) },
        cg_status::InvalidArgument
    );
    assert_eq!(w, [0.25; 2]);
    assert_eq!(out, [SENTINEL; 2]);

    // And then it works.
    assert_eq!(
        unsafe { cg_view_blender_weights(blender, &character, &viewer, w.as_mut_ptr(), 2) },
        cg_status::Ok
    );
    assert_eq!(w, [1.0, 0.0]);
    assert_eq!(
        unsafe { cg_view_blender_evaluate(blender, &character, &viewer, 0.0, out.as_mut_ptr(), 2) },
        cg_status::Ok
    );
    unsafe { cg_view_blender_destroy(blender) };
}
