//! Rows: DLB and DIB, of transforms and of key poses.

use crate::{
    corruption::{change, invalid, non_finite, Corruption},
    fixture::{Harness, Setup, JOINTS},
    table::Table,
    values::{
        bytes_of, dualquat_fields, elements, float_elements, floats, transform, ZERO_DUALQUAT,
    },
    INVALID, NULL_ARG,
};
use crowdgaze::ffi::blend::*;
use crowdgaze::ffi::status::cg_status;
use crowdgaze::ffi::types::cg_dualquat;
use std::mem::offset_of;

/// Which pointer arguments of a blend are passed as NULL.
#[derive(Clone, Copy, Default)]
struct Nulls {
    inputs: bool,
    weights: bool,
    out: bool,
}

pub(crate) fn or_null<T>(pointer: *const T, null: bool) -> *const T {
    if null {
        std::ptr::null()
    } else {
        pointer
    }
}

pub(crate) fn or_null_mut<T>(pointer: *mut T, null: bool) -> *mut T {
    or_null(pointer, null).cast_mut()
}

/// The arguments of a blend of `N` transforms (or of key poses of `joint_count` joints,
/// key-major), all of which a case may break.
#[repr(C)]
#[derive(Clone, Copy)]
struct BlendInput<const N: usize> {
    transforms: [cg_dualquat; N],
    weights: [f32; 2],
    /// The input count: transforms, or key poses.
    count: usize,
    precision: f32,
    max_iterations: u32,
    nulls: Nulls,
    /// Joints per key pose (pose blends).
    joint_count: usize,
    /// Write the output over the keys (pose blends).
    overlap: bool,
}

/// Two transforms to blend.
fn blend_input(_: &Harness) -> BlendInput<2> {
    BlendInput {
        transforms: [
            transform([0.0, 1.0, 0.0], 0.3, [1.0, 0.0, 0.0]),
            transform([1.0, 0.0, 0.0], -0.5, [0.0, 2.0, 0.0]),
        ],
        weights: [0.25, 0.75],
        count: 2,
        precision: 1e-6,
        max_iterations: 16,
        nulls: Nulls::default(),
        joint_count: 1,
        overlap: false,
    }
}

/// Two key poses of three joints to blend.
fn pose_input(h: &Harness) -> BlendInput<6> {
    let two = blend_input(h);
    BlendInput {
        transforms: std::array::from_fn(|i| {
            transform([0.0, 0.0, 1.0], 0.2 * i as f32, [0.1 * i as f32, 0.0, 1.0])
        }),
        joint_count: JOINTS,
        weights: two.weights,
        count: two.count,
        precision: two.precision,
        max_iterations: two.max_iterations,
        nulls: two.nulls,
        overlap: false,
    }
}

/// The corruptions shared by the four blends (whose transforms are called `name`): NULL
/// arrays, NaN and infinities in every transform and weight, a negative weight, weights
/// summing to 0, a transform with a zero real part, no inputs, an absurd count.
fn blend_corruptions<const N: usize>(name: &str) -> Vec<Corruption<BlendInput<N>>> {
    type B<const N: usize> = BlendInput<N>;
    let transforms = offset_of!(B<N>, transforms);
    let mut out = non_finite(&elements::<cg_dualquat>(
        name,
        transforms,
        N,
        &dualquat_fields(),
    ));
    out.extend(non_finite(&float_elements(
        "weights",
        offset_of!(B<N>, weights),
        2,
    )));
    out.extend([
        change(
            format!("({name} NULL, count 2)"),
            NULL_ARG,
            |v: &mut B<N>| v.nulls.inputs = true,
        ),
        change(
            format!("{name}[0] with a zero real part"),
            INVALID,
            |v: &mut B<N>| v.transforms[0] = ZERO_DUALQUAT,
        ),
    ]);
    out.extend([
        change("(weights NULL, count 2)", NULL_ARG, |v: &mut B<N>| {
            v.nulls.weights = true
        }),
        change("out NULL", NULL_ARG, |v: &mut B<N>| v.nulls.out = true),
    ]);
    out.extend(invalid::<B<N>>(&[
        ("weights[1] -0.5", |v| v.weights[1] = -0.5),
        ("weights -0 and 0", |v| v.weights = [-0.0, 0.0]),
        ("count 0", |v| v.count = 0),
        ("count SIZE_MAX", |v| v.count = usize::MAX),
    ]));
    out
}

/// DIB's settings out of range.
fn dib_corruptions<const N: usize>() -> Vec<Corruption<BlendInput<N>>> {
    let mut out = non_finite(&floats!(BlendInput<N>: precision));
    out.extend(invalid::<BlendInput<N>>(&[
        ("precision 0", |v| v.precision = 0.0),
        ("precision -1e-6", |v| v.precision = -1e-6),
        ("max_iterations 0", |v| v.max_iterations = 0),
        ("max_iterations 1001", |v| v.max_iterations = 1001),
        ("max_iterations UINT32_MAX", |v| v.max_iterations = u32::MAX),
    ]));
    out
}

/// The pose blends' corruptions: those of every blend, a layout overflowing, an output
/// over the keys.
fn pose_corruptions() -> Vec<Corruption<BlendInput<6>>> {
    let mut out = blend_corruptions("keys");
    out.extend(invalid::<BlendInput<6>>(&[
        ("key_count × joint_count overflowing", |v| {
            v.joint_count = usize::MAX / 2 + 1
        }),
        ("out_pose overlapping keys", |v| v.overlap = true),
    ]));
    out
}

impl<const N: usize> BlendInput<N> {
    /// The transforms, weights and output pointers, NULL where the case says; the output
    /// over the keys with `overlap`.
    fn pointers(
        &mut self,
        out: *mut cg_dualquat,
    ) -> (*const cg_dualquat, *const f32, *mut cg_dualquat) {
        let out = if self.overlap {
            self.transforms[1..].as_mut_ptr()
        } else {
            out
        };
        (
            or_null(self.transforms.as_ptr(), self.nulls.inputs),
            or_null(self.weights.as_ptr(), self.nulls.weights),
            or_null_mut(out, self.nulls.out),
        )
    }
}

fn dlb(h: &mut Harness, v: &mut BlendInput<2>) -> cg_status {
    let (inputs, weights, out) = v.pointers(&mut h.out.dual_quat);
    unsafe { cg_blend_dlb(inputs, weights, v.count, out) }
}

fn dib(h: &mut Harness, v: &mut BlendInput<2>) -> cg_status {
    let (inputs, weights, out) = v.pointers(&mut h.out.dual_quat);
    unsafe { cg_blend_dib(inputs, weights, v.count, v.precision, v.max_iterations, out) }
}

/// A pose blend called with the counts and settings of a copy of its input and the
/// pointers to use.
type PoseBlend = fn(BlendInput<6>, *const cg_dualquat, *const f32, *mut cg_dualquat) -> cg_status;

/// Calls a pose blend with `v`; checks that the keys are unchanged when the output
/// overlaps them.
fn pose_blend(h: &mut Harness, v: &mut BlendInput<6>, blend: PoseBlend) -> cg_status {
    let copy = *v;
    let (keys, weights, out) = v.pointers(h.out.pose.as_mut_ptr());
    let status = blend(copy, keys, weights, out);
    if status != cg_status::Ok && bytes_of(&copy.transforms[..]) != bytes_of(&v.transforms[..]) {
        h.note("a failed call wrote over its input keys");
    }
    status
}

pub(crate) fn rows_blends(t: &mut Table) {
    let mut dib_cases = blend_corruptions("inputs");
    dib_cases.extend(dib_corruptions());
    t.corrupt(
        Setup::Online,
        "cg_blend_dlb",
        blend_corruptions("inputs"),
        blend_input,
        dlb,
    );
    t.corrupt(Setup::Online, "cg_blend_dib", dib_cases, blend_input, dib);
    let mut dib_cases = pose_corruptions();
    dib_cases.extend(dib_corruptions());
    t.corrupt(
        Setup::Online,
        "cg_blend_pose_dlb",
        pose_corruptions(),
        pose_input,
        |h, v| {
            pose_blend(h, v, |v, keys, weights, out| unsafe {
                cg_blend_pose_dlb(keys, weights, v.count, v.joint_count, out)
            })
        },
    );
    t.corrupt(
        Setup::Online,
        "cg_blend_pose_dib",
        dib_cases,
        pose_input,
        |h, v| {
            pose_blend(h, v, |v, keys, weights, out| {
                let (count, joints) = (v.count, v.joint_count);
                unsafe {
                    cg_blend_pose_dib(
                        keys,
                        weights,
                        count,
                        joints,
                        v.precision,
                        v.max_iterations,
                        out,
                    )
                }
            })
        },
    );
}
