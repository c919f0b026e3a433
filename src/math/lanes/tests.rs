//! Tests of the lane types: each operation against glam's or [`DualQuat`]'s, at every
//! width, and the same bits as the one-value forms where they promise them.

use glam::{Quat, Vec3, Vec3A, Vec4};

use super::dual_quat::first_quadrant_atan2;
use super::*;
use crate::math::dualquat::DualQuat;
use crate::math::packed::PackedQuat;
use crate::math::random::Random;
use crate::math::wide::for_every_width;

#[test]
fn lanes_match_glam() {
    for_every_width!(lanes_match_glam_at());
}

fn lanes_match_glam_at<W: Wide>() {
    // The mask checks below need four lanes at least (one lane is the scalar form).
    if W::LANES < 4 {
        return;
    }
    let rotations: [Quat; MAX_LANES] = std::array::from_fn(|i| {
        let axis = Vec3::new(1.0, 2.0 - i as f32, 3.0 + i as f32).normalize();
        Quat::from_axis_angle(axis, 0.4 * i as f32 - 1.0)
    });
    let vectors: [Vec3A; MAX_LANES] =
        std::array::from_fn(|i| Vec3A::new(0.3 * i as f32, -2.0, 5.0 - i as f32));
    let mirror = |i: usize| W::LANES - 1 - i;
    let q = Q4::<W>::gather(|i| rotations[i]);
    let p = Q4::gather(|i| rotations[mirror(i)]);
    let v = V3::gather(|i| vectors[i]);
    for i in 0..W::LANES {
        let rotated = q.rotate(v).lane(i);
        assert!(rotated.abs_diff_eq(rotations[i] * vectors[i], 1e-5));
        let product = q.mul(p).lane(i);
        assert!(product.abs_diff_eq(rotations[i] * rotations[mirror(i)], 1e-6));
        let cross = v.cross(V3::splat(Vec3A::Y)).lane(i);
        assert!(cross.abs_diff_eq(vectors[i].cross(Vec3A::Y), 1e-6));
    }
    assert!(Q4::<W>::identity().is_identity().all());
    let m: Mask<W> = mask(|i| i == 2);
    assert!(m.any() && !m.all() && m.test(2) && !m.test(1));
    assert!((!Mask::<W>::splat(false)).all());
}

#[test]
fn unpacking_lanes_gives_the_bits_of_one() {
    for_every_width!(unpacking_at());
}

fn unpacking_at<W: Wide>() {
    let mut random = crate::math::random::Random::new(23);
    for round in 0..2_000 {
        let packed: [PackedQuat; MAX_LANES] = std::array::from_fn(|i| {
            let mut draw = || 2.0 * random.next_f32() - 1.0;
            let q = Quat::from_xyzw(draw(), draw(), draw(), draw()).normalize();
            // Every other round all lanes leave w out (the fast path).
            let q = if round % 2 == 0 && q.w.abs() < 0.9 {
                Quat::from_axis_angle(Vec3::new(draw(), draw(), 1.0).normalize(), draw())
            } else {
                q
            };
            PackedQuat::pack(if i == 2 { -q } else { q })
        });
        let lanes = Q4::<W>::unpack(|i| packed[i]);
        for (i, packed) in packed.iter().enumerate().take(W::LANES) {
            let (one, all) = (packed.unpack(), lanes.lane(i));
            assert_eq!(
                one.to_array().map(f32::to_bits),
                all.to_array().map(f32::to_bits)
            );
        }
    }
}

/// A rigid transform with a random axis, an angle within `±angle` and a translation within
/// ±2 in x and y (shared with the blenders' lane tests).
pub(crate) fn random_transform(random: &mut Random, angle: f32) -> DualQuat {
    let axis = Vec3::new(
        random.range(-1.0, 1.0),
        random.range(-1.0, 1.0),
        random.range(-1.0, 1.0),
    )
    .try_normalize()
    .unwrap_or(Vec3::X);
    DualQuat::from_rotation_translation(
        Quat::from_axis_angle(axis, random.range(-angle, angle)),
        Vec3::new(random.range(-2.0, 2.0), random.range(-2.0, 2.0), 0.5),
    )
}

fn lanes<W: Wide>(lanes: DualQuatLanes<W>) -> Vec<DualQuat> {
    let mut out = vec![DualQuat::IDENTITY; W::LANES];
    lanes.scatter(|i, q| out[i] = q);
    out
}

fn random_lanes<W: Wide>(random: &mut Random, angle: f32) -> (Vec<DualQuat>, DualQuatLanes<W>) {
    let q: Vec<DualQuat> = (0..W::LANES)
        .map(|_| random_transform(random, angle))
        .collect();
    let gathered = DualQuatLanes::gather(|i| q[i]);
    (q, gathered)
}

fn gather_and_scatter_are_inverse<W: Wide>() {
    let mut random = Random::new(11);
    let (q, gathered) = random_lanes::<W>(&mut random, 3.0);
    assert_eq!(lanes(gathered), q);
    for (i, &q) in q.iter().enumerate() {
        assert_eq!(gathered.lane(i), q);
    }
}

fn lane_algebra_matches_the_scalar_one<W: Wide>() {
    let mut random = Random::new(12);
    for _ in 0..200 {
        let (a, a4) = random_lanes::<W>(&mut random, 6.0);
        let (b, b4) = random_lanes::<W>(&mut random, 6.0);
        let product = lanes(a4.mul(b4));
        let log = lanes(a4.log());
        let exp = lanes(a4.log().exp());
        for lane in 0..W::LANES {
            assert!((product[lane] - a[lane] * b[lane]).length() < 1e-5);
            assert!((log[lane] - a[lane].log()).length() < 2e-5, "{:?}", a[lane]);
            let back = exp[lane];
            assert!((back - a[lane]).length() < 2e-5 || (back + a[lane]).length() < 2e-5);
        }
        // Screws beyond the series fall back to the scalar exp.
        let factors = [1.0, 1.5, 2.0, 0.1];
        let big4 = a4.log().scale(gather(|i| factors[i % 4]));
        let big = lanes(big4);
        let exp_big = lanes(big4.exp());
        for lane in 0..W::LANES {
            assert!((exp_big[lane] - big[lane].exp()).length() < 2e-5);
        }
    }
}

fn lane_sclerp_matches_the_scalar_one<W: Wide>() {
    let mut random = Random::new(13);
    for _ in 0..200 {
        let (a, a4) = random_lanes::<W>(&mut random, 3.1);
        let (b, b4) = random_lanes::<W>(&mut random, 3.1);
        for t in [0.0, 0.3, 0.5, 1.0] {
            let blended = lanes(a4.sclerp(b4, t));
            for lane in 0..W::LANES {
                let scalar = a[lane].sclerp(b[lane], t);
                let error = (blended[lane] - scalar)
                    .length()
                    .min((blended[lane] + scalar).length());
                assert!(error < 2e-5, "t = {t}: {:?} vs {scalar:?}", blended[lane]);
            }
        }
    }
}

#[test]
fn every_width_gathers_and_scatters() {
    for_every_width!(gather_and_scatter_are_inverse());
}

#[test]
fn lane_algebra_matches_the_scalar_one_at_every_width() {
    for_every_width!(lane_algebra_matches_the_scalar_one());
}

#[test]
fn lane_sclerp_matches_the_scalar_one_at_every_width() {
    for_every_width!(lane_sclerp_matches_the_scalar_one());
}

#[test]
fn lane_atan2_is_accurate() {
    for i in 0..=1000 {
        let angle = std::f32::consts::FRAC_PI_2 * i as f32 / 1000.0;
        let (y, x) = (angle.sin(), angle.cos().max(0.0));
        let lanes = first_quadrant_atan2(Floats::<Vec4>::splat(y), Floats::splat(x));
        assert!((lanes.lane(0) - y.atan2(x)).abs() < 3e-7, "{angle}");
    }
    let zero = Floats::<Vec4>::zero();
    assert_eq!(first_quadrant_atan2(zero, zero).lane(0), 0.0);
}
