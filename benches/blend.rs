//! Benchmarks of pose blending (DESIGN §10): DLB and DIB (p = 1e−6) of a 27-joint pose from
//! K = 2, 3, 4, 8 key poses, and in the same run nalgebra's `UnitDualQuaternion::try_sclerp`
//! over the same 27 joints for K = 2 (the baseline: DIB of two inputs is ScLERP), next to our
//! own `DualQuat::sclerp`; and DIB at the paper's precision p = 1e−3 for K = 3. Budget: DLB
//! 27 × 3 ≤ 0.3 µs, DIB ≤ 2 µs.
//!
//! Run with `cargo bench --bench blend`; medians are in
//! `target/criterion/<group>/<bench>/new/estimates.json`.

use std::hint::black_box;
use std::time::Duration;

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use glam::{Quat, Vec3};
use nalgebra::{Quaternion, UnitDualQuaternion, UnitQuaternion, Vector3};

use crowdgaze::blend::{blend_pose_dib, blend_pose_dlb, DibSettings};
use crowdgaze::math::random::Random;
use crowdgaze::DualQuat;

const JOINTS: usize = 27;
const KEY_COUNTS: [usize; 4] = [2, 3, 4, 8];

/// Eight key poses of a 27-joint skeleton, key-major: bones 0.1–0.4 m long, each key's joint
/// rotated up to ±0.6 rad from a shared base about a random axis (the spread of key
/// animations looking left, front and right), the root moved up to 0.5 m.
fn key_poses(random: &mut Random) -> Vec<DualQuat> {
    let axis = |random: &mut Random| {
        Vec3::new(
            random.range(-1.0, 1.0),
            random.range(-1.0, 1.0),
            random.range(-1.0, 1.0),
        )
        .try_normalize()
        .unwrap_or(Vec3::Y)
    };
    let base: Vec<(Quat, Vec3)> = (0..JOINTS)
        .map(|joint| {
            let rotation = Quat::from_axis_angle(axis(random), random.range(-0.5, 0.5));
            let offset = if joint == 0 {
                Vec3::new(0.0, 1.0, 0.0)
            } else {
                Vec3::new(0.0, random.range(0.1, 0.4), 0.0)
            };
            (rotation, offset)
        })
        .collect();
    let mut keys = Vec::with_capacity(8 * JOINTS);
    for _ in 0..8 {
        for (joint, (rotation, offset)) in base.iter().enumerate() {
            let turn = Quat::from_axis_angle(axis(random), random.range(-0.6, 0.6));
            let moved = if joint == 0 {
                *offset + Vec3::new(random.range(-0.5, 0.5), 0.0, random.range(-0.5, 0.5))
            } else {
                *offset
            };
            keys.push(DualQuat::from_rotation_translation(turn * *rotation, moved));
        }
    }
    keys
}

fn weights(random: &mut Random, count: usize) -> Vec<f32> {
    let raw: Vec<f32> = (0..count).map(|_| random.range(0.1, 1.0)).collect();
    let total: f32 = raw.iter().sum();
    raw.iter().map(|w| w / total).collect()
}

fn to_nalgebra(q: DualQuat) -> UnitDualQuaternion<f32> {
    let (rotation, translation) = q.to_rotation_translation();
    UnitDualQuaternion::from_parts(
        Vector3::new(translation.x, translation.y, translation.z).into(),
        UnitQuaternion::from_quaternion(Quaternion::new(
            rotation.w, rotation.x, rotation.y, rotation.z,
        )),
    )
}

fn blending(c: &mut Criterion) {
    let mut random = Random::new(0x0062_6c65_6e64);
    let keys = key_poses(&mut random);
    let all_weights: Vec<Vec<f32>> = KEY_COUNTS
        .iter()
        .map(|&k| weights(&mut random, k))
        .collect();
    let mut out = vec![DualQuat::IDENTITY; JOINTS];

    println!(
        "pose blends run {} joints side by side on this processor",
        crowdgaze::blend::simd_lanes()
    );
    let mut dlb = c.benchmark_group("dlb_27_joints");
    for (&k, w) in KEY_COUNTS.iter().zip(&all_weights) {
        dlb.bench_with_input(BenchmarkId::from_parameter(k), &k, |b, &k| {
            b.iter(|| {
                blend_pose_dlb(
                    black_box(&keys[..k * JOINTS]),
                    black_box(w),
                    JOINTS,
                    &mut out,
                )
                .expect("valid inputs");
                black_box(&out);
            })
        });
    }
    dlb.finish();

    let settings = DibSettings {
        precision: 1e-6,
        max_iterations: 16,
    };
    let mut dib = c.benchmark_group("dib_27_joints_p1e-6");
    for (&k, w) in KEY_COUNTS.iter().zip(&all_weights) {
        let outcome = blend_pose_dib(&keys[..k * JOINTS], w, JOINTS, &settings, &mut out)
            .expect("valid inputs");
        assert!(
            outcome.converged(),
            "DIB must converge on the bench data: {outcome:?}"
        );
        println!(
            "DIB K = {k}: at most {} iterations per joint, largest |x| {:.2e}",
            outcome.most_iterations, outcome.largest_residual
        );
        dib.bench_with_input(BenchmarkId::from_parameter(k), &k, |b, &k| {
            b.iter(|| {
                blend_pose_dib(
                    black_box(&keys[..k * JOINTS]),
                    black_box(w),
                    JOINTS,
                    &settings,
                    &mut out,
                )
                .expect("valid inputs");
                black_box(&out);
            })
        });
    }
    dib.finish();

    // The paper's own precision (Chaudhuri et al. used p = 0.001), K = 3.
    let coarse = DibSettings {
        precision: 1e-3,
        max_iterations: 16,
    };
    let mut dib_coarse = c.benchmark_group("dib_27_joints_p1e-3");
    dib_coarse.bench_function(BenchmarkId::from_parameter(3), |b| {
        b.iter(|| {
            blend_pose_dib(
                black_box(&keys[..3 * JOINTS]),
                black_box(&all_weights[1]),
                JOINTS,
                &coarse,
                &mut out,
            )
            .expect("valid inputs");
            black_box(&out);
        })
    });
    dib_coarse.finish();

    // Two inputs: DIB = ScLERP. nalgebra's try_sclerp over the same 27 joints, and ours.
    let t = all_weights[0][1];
    let first: Vec<UnitDualQuaternion<f32>> =
        keys[..JOINTS].iter().map(|&q| to_nalgebra(q)).collect();
    let second: Vec<UnitDualQuaternion<f32>> = keys[JOINTS..2 * JOINTS]
        .iter()
        .map(|&q| to_nalgebra(q))
        .collect();
    let mut nalgebra_out = vec![UnitDualQuaternion::<f32>::identity(); JOINTS];
    let mut sclerp = c.benchmark_group("sclerp_27_joints_k2");
    sclerp.bench_function("nalgebra_try_sclerp", |b| {
        b.iter(|| {
            for ((a, b), out) in first.iter().zip(&second).zip(nalgebra_out.iter_mut()) {
                *out = a.try_sclerp(black_box(b), black_box(t), 1e-6).unwrap_or(*a);
            }
            black_box(&nalgebra_out);
        })
    });
    sclerp.bench_function("crowdgaze_sclerp", |b| {
        b.iter(|| {
            for (joint, out) in out.iter_mut().enumerate() {
                *out = keys[joint].sclerp(black_box(keys[JOINTS + joint]), black_box(t));
            }
            black_box(&out);
        })
    });
    sclerp.finish();
}

fn config() -> Criterion {
    Criterion::default()
        .warm_up_time(Duration::from_secs(1))
        .measurement_time(Duration::from_secs(3))
        .sample_size(60)
}

criterion_group! {
    name = benches;
    config = config();
    targets = blending
}
criterion_main!(benches);
