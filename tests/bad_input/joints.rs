//! Rows: reading joints, eyes and eyelids.

use crate::{table::Table, INVALID, NULL_ARG};
use crowdgaze::ffi::crowd::*;
use crowdgaze::ffi::eyelids::*;
use crowdgaze::ffi::gaze::*;
use crowdgaze::ffi::status::cg_status;
use crowdgaze::ffi::types::cg_quat;
use std::ptr::{null, null_mut};

type ReadQuats = unsafe extern "C" fn(*const cg_crowd, u32, u32, *mut cg_quat, usize) -> cg_status;

/// Characters 0 .. 4 have 10 + 8 + 10 + 10 joints.
pub(crate) const ALL_JOINTS: usize = 38;

fn rows_read_joints(t: &mut Table, f: &'static str, read: ReadQuats) {
    t.case(f, "crowd NULL", NULL_ARG, move |h| unsafe {
        read(null(), 0, 4, h.out.quats.as_mut_ptr(), 64)
    });
    t.case(f, "(out NULL, out_len 38)", NULL_ARG, move |h| unsafe {
        read(h.crowd, 0, 4, null_mut(), ALL_JOINTS)
    });
    for (what, first, count, out_len) in [
        ("first 5 past the last character", 5, 0, 64),
        ("first 4, count 1 past the last character", 4, 1, 64),
        ("count 5 of 4 characters", 0, 5, 64),
        ("first UINT32_MAX, count 2 (overflowing)", u32::MAX, 2, 64),
        ("first 1, count UINT32_MAX (overflowing)", 1, u32::MAX, 64),
        ("out_len 37 for 38 joints", 0, 4, ALL_JOINTS - 1),
        ("out_len 0 for 10 joints", 0, 1, 0),
        ("out_len SIZE_MAX", 0, 4, usize::MAX),
    ] {
        t.case(f, what, INVALID, move |h| unsafe {
            read(h.crowd, first, count, h.out.quats.as_mut_ptr(), out_len)
        });
    }
}

pub(crate) fn rows_joints(t: &mut Table) {
    let f = "cg_crowd_joint_total";
    t.case(f, "crowd NULL", NULL_ARG, |h| unsafe {
        cg_crowd_joint_total(null(), 0, 4, &mut h.out.count)
    });
    t.case(f, "out_total NULL", NULL_ARG, |h| unsafe {
        cg_crowd_joint_total(h.crowd, 0, 4, null_mut())
    });
    for (what, first, count) in [
        ("first 5 past the last character", 5, 0),
        ("count 5 of 4 characters", 0, 5),
        ("first UINT32_MAX, count UINT32_MAX", u32::MAX, u32::MAX),
    ] {
        t.case(f, what, INVALID, move |h| unsafe {
            cg_crowd_joint_total(h.crowd, first, count, &mut h.out.count)
        });
    }
    rows_read_joints(t, "cg_crowd_read_joints", cg_crowd_read_joints);
    rows_read_joints(t, "cg_crowd_read_joint_deltas", cg_crowd_read_joint_deltas);

    let f = "cg_crowd_read_eyes";
    t.case(f, "crowd NULL", NULL_ARG, |h| unsafe {
        cg_crowd_read_eyes(null(), 0, 4, h.out.eyes.as_mut_ptr(), 8)
    });
    t.case(f, "(out NULL, out_len 4)", NULL_ARG, |h| unsafe {
        cg_crowd_read_eyes(h.crowd, 0, 4, null_mut(), 4)
    });
    for (what, first, count, out_len) in [
        ("first 5 past the last character", 5, 0, 8),
        ("count 5 of 4 characters", 0, 5, 8),
        ("first UINT32_MAX, count 2 (overflowing)", u32::MAX, 2, 8),
        ("out_len 3 for 4 characters", 0, 4, 3),
        ("out_len SIZE_MAX", 0, 4, usize::MAX),
    ] {
        t.case(f, what, INVALID, move |h| unsafe {
            cg_crowd_read_eyes(h.crowd, first, count, h.out.eyes.as_mut_ptr(), out_len)
        });
    }

    let f = "cg_crowd_read_eyelids";
    t.case(f, "crowd NULL", NULL_ARG, |h| unsafe {
        cg_crowd_read_eyelids(null(), 0, 4, h.out.eyelids.as_mut_ptr(), 8)
    });
    t.case(f, "(out NULL, out_len 4)", NULL_ARG, |h| unsafe {
        cg_crowd_read_eyelids(h.crowd, 0, 4, null_mut(), 4)
    });
    t.case(f, "out misaligned", INVALID, |h| unsafe {
        let misaligned = h
            .out
            .eyelids
            .as_mut_ptr()
            .cast::<u8>()
            .add(1)
            .cast::<cg_eyelids>();
        cg_crowd_read_eyelids(h.crowd, 0, 4, misaligned, 4)
    });
    for (what, first, count, out_len) in [
        ("first 5 past the last character", 5, 0, 8),
        ("count 5 of 4 characters", 0, 5, 8),
        ("first UINT32_MAX, count 2 (overflowing)", u32::MAX, 2, 8),
        ("first 1, count UINT32_MAX (overflowing)", 1, u32::MAX, 8),
        ("out_len 3 for 4 characters", 0, 4, 3),
        ("out_len SIZE_MAX", 0, 4, usize::MAX),
    ] {
        t.case(f, what, INVALID, move |h| unsafe {
            cg_crowd_read_eyelids(h.crowd, first, count, h.out.eyelids.as_mut_ptr(), out_len)
        });
    }
}
