//! Rows: dual quaternions (from and to rotation and translation, to and from a matrix) and the
//! camera centre of a projection.

use crate::{
    corruption::{change, invalid, non_finite, Corruption},
    fixture::{Harness, Setup},
    table::Table,
    values::{
        dualquat_fields, nested, ok, quat_fields, rotation, transform, vec3, vec3_fields,
        ZERO_DUALQUAT, ZERO_QUAT,
    },
    INVALID, NULL_ARG,
};
use crowdgaze::ffi::blend::*;
use crowdgaze::ffi::types::{cg_dualquat, cg_quat, cg_vec3};
use std::mem::offset_of;
use std::ptr::{null, null_mut};

#[repr(C)]
#[derive(Clone, Copy)]
struct RotationTranslation {
    rotation: cg_quat,
    translation: cg_vec3,
}

fn a_transform(_: &Harness) -> cg_dualquat {
    transform([0.0, 0.6, 0.8], 0.9, [1.0, -2.0, 0.5])
}

fn a_matrix(h: &Harness) -> [f32; 16] {
    let mut matrix = [0.0f32; 16];
    ok(unsafe { cg_dualquat_to_matrix(&a_transform(h), matrix.as_mut_ptr()) });
    matrix
}

/// `P = [I | −C]` for the camera centre C = (1, 2, 3), row-major.
fn a_projection(_: &Harness) -> [f32; 12] {
    [
        1.0, 0.0, 0.0, -1.0, //
        0.0, 1.0, 0.0, -2.0, //
        0.0, 0.0, 1.0, -3.0,
    ]
}

pub(crate) fn rows_dual_quaternions(t: &mut Table) {
    let f = "cg_dualquat_from_rt";
    let rt = |_: &Harness| RotationTranslation {
        rotation: rotation([1.0, 0.0, 0.0], 0.3),
        translation: vec3(1.0, 2.0, 3.0),
    };
    t.case(f, "rotation NULL", NULL_ARG, |h| unsafe {
        cg_dualquat_from_rt(null(), &vec3(1.0, 2.0, 3.0), &mut h.out.dual_quat)
    });
    t.case(f, "translation NULL", NULL_ARG, |h| unsafe {
        cg_dualquat_from_rt(&cg_quat::IDENTITY, null(), &mut h.out.dual_quat)
    });
    t.case(f, "out NULL", NULL_ARG, |_| unsafe {
        cg_dualquat_from_rt(&cg_quat::IDENTITY, &vec3(1.0, 2.0, 3.0), null_mut())
    });
    type Rt = RotationTranslation;
    let mut corruptions =
        non_finite::<Rt>(&nested("rotation", offset_of!(Rt, rotation), quat_fields()));
    corruptions.extend(non_finite::<Rt>(&nested(
        "translation",
        offset_of!(Rt, translation),
        vec3_fields(),
    )));
    corruptions.push(change("rotation zero", INVALID, |v: &mut Rt| {
        v.rotation = ZERO_QUAT
    }));
    corruptions.push(change("rotation of length 1e-9", INVALID, |v: &mut Rt| {
        v.rotation = cg_quat {
            w: 1e-9,
            ..ZERO_QUAT
        }
    }));
    t.corrupt(Setup::Online, f, corruptions, rt, |h, v| unsafe {
        cg_dualquat_from_rt(&v.rotation, &v.translation, &mut h.out.dual_quat)
    });

    let f = "cg_dualquat_to_rt";
    t.case(f, "dual_quat NULL", NULL_ARG, |h| unsafe {
        cg_dualquat_to_rt(null(), &mut h.out.quat, &mut h.out.vec3)
    });
    t.case(f, "out_rotation NULL", NULL_ARG, |h| unsafe {
        cg_dualquat_to_rt(&a_transform(h), null_mut(), &mut h.out.vec3)
    });
    t.case(f, "out_translation NULL", NULL_ARG, |h| unsafe {
        cg_dualquat_to_rt(&a_transform(h), &mut h.out.quat, null_mut())
    });
    t.corrupt(
        Setup::Online,
        f,
        dualquat_corruptions("dual_quat"),
        a_transform,
        |h, q| unsafe { cg_dualquat_to_rt(q, &mut h.out.quat, &mut h.out.vec3) },
    );

    let f = "cg_dualquat_to_matrix";
    t.case(f, "dual_quat NULL", NULL_ARG, |h| unsafe {
        cg_dualquat_to_matrix(null(), h.out.matrix.as_mut_ptr())
    });
    t.case(f, "out NULL", NULL_ARG, |h| unsafe {
        cg_dualquat_to_matrix(&a_transform(h), null_mut())
    });
    t.corrupt(
        Setup::Online,
        f,
        dualquat_corruptions("dual_quat"),
        a_transform,
        |h, q| unsafe { cg_dualquat_to_matrix(q, h.out.matrix.as_mut_ptr()) },
    );

    let bad = invalid::<[f32; 16]>(&[
        ("a scale of 2", |m| {
            m[..12].iter_mut().for_each(|v| *v *= 2.0)
        }),
        ("a shear", |m| m[4] += 0.5),
        ("a reflection", |m| m[..4].iter_mut().for_each(|v| *v = -*v)),
        ("a projection row", |m| m[3] = 0.1),
        ("all zero", |m| *m = [0.0; 16]),
    ]);
    let f = "cg_dualquat_from_matrix";
    t.float_array(f, "matrix", a_matrix, bad, cg_dualquat_from_matrix, |h| {
        &mut h.out.dual_quat
    });
    let bad = invalid::<[f32; 12]>(&[
        ("all zero", |p| *p = [0.0; 12]),
        ("an affine camera (last row 0 0 0 1)", |p| {
            p[8..].copy_from_slice(&[0.0, 0.0, 0.0, 1.0])
        }),
        ("rank 2 (two equal rows)", |p| p.copy_within(0..4, 4)),
        ("a centre too far for a float", |p| {
            p[3] = 1e30;
            p[0] = 1e-12;
        }),
    ]);
    let f = "cg_camera_center_from_projection";
    let centre = cg_camera_center_from_projection;
    t.float_array(f, "projection", a_projection, bad, centre, |h| {
        &mut h.out.vec3
    });
}

/// NaN and infinities in each component of a dual quaternion, and a zero real part.
pub(crate) fn dualquat_corruptions(name: &str) -> Vec<Corruption<cg_dualquat>> {
    let mut out = non_finite::<cg_dualquat>(&nested(name, 0, dualquat_fields()));
    out.push(change(
        format!("{name} with a zero real part"),
        INVALID,
        |q: &mut cg_dualquat| *q = ZERO_DUALQUAT,
    ));
    out
}
