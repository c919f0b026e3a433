//! Rows: gaze following (which characters glance where others stare).

use crate::{fixture::Setup, table::Table, INVALID, NULL_ARG};
use crowdgaze::ffi::following::cg_crowd_read_following;
use std::ptr::{null, null_mut};

pub(crate) fn rows_following(t: &mut Table) {
    let f = "cg_crowd_read_following";
    t.case(f, "crowd NULL", NULL_ARG, |h| {
        let id = h.character(0);
        let [following, glances] = &mut h.out.following;
        unsafe { cg_crowd_read_following(null(), id, &mut h.out.vec3, following, glances) }
    });
    t.case(f, "out_point NULL", NULL_ARG, |h| {
        let id = h.character(0);
        let [following, glances] = &mut h.out.following;
        unsafe { cg_crowd_read_following(h.crowd, id, null_mut(), following, glances) }
    });
    t.case(f, "out_following NULL", NULL_ARG, |h| {
        let id = h.character(0);
        let glances = &mut h.out.following[1];
        unsafe { cg_crowd_read_following(h.crowd, id, &mut h.out.vec3, null_mut(), glances) }
    });
    t.case(f, "out_glances NULL", NULL_ARG, |h| {
        let id = h.character(0);
        let following = &mut h.out.following[0];
        unsafe { cg_crowd_read_following(h.crowd, id, &mut h.out.vec3, following, null_mut()) }
    });
    t.case(f, "all outputs NULL", NULL_ARG, |h| unsafe {
        cg_crowd_read_following(h.crowd, h.character(0), null_mut(), null_mut(), null_mut())
    });
    t.case(f, "out_point misaligned", INVALID, |h| {
        let id = h.character(0);
        let [following, glances] = &mut h.out.following;
        let misaligned = unsafe { h.out.quats.as_mut_ptr().cast::<u8>().add(1).cast() };
        unsafe { cg_crowd_read_following(h.crowd, id, misaligned, following, glances) }
    });
    t.case(f, "out_glances misaligned", INVALID, |h| {
        let id = h.character(0);
        let following = &mut h.out.following[0];
        let misaligned = unsafe { h.out.bones.as_mut_ptr().cast::<u8>().add(1).cast() };
        unsafe { cg_crowd_read_following(h.crowd, id, &mut h.out.vec3, following, misaligned) }
    });
    t.character_ids(Setup::Online, f, |h, id| {
        let [following, glances] = &mut h.out.following;
        unsafe { cg_crowd_read_following(h.crowd, id, &mut h.out.vec3, following, glances) }
    });
}
