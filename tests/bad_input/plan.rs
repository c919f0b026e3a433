//! Rows: offline planning (plan, clear the plan, read its constraints).

use crate::{fixture::Setup, table::Table, INVALID, NULL_ARG, WRONG_STATE};
use crowdgaze::ffi::attention::*;
use std::ptr::{null, null_mut};

pub(crate) fn rows_plan(t: &mut Table) {
    let f = "cg_crowd_plan";
    t.case(f, "crowd NULL", NULL_ARG, |_| unsafe {
        cg_crowd_plan(null_mut())
    });
    t.case_in(
        Setup::Unrecorded,
        f,
        "nothing recorded (max_recorded_states 0)",
        WRONG_STATE,
        |h| unsafe { cg_crowd_plan(h.crowd) },
    );
    t.case_in(
        Setup::Planned,
        f,
        "already planned",
        WRONG_STATE,
        |h| unsafe { cg_crowd_plan(h.crowd) },
    );

    let f = "cg_crowd_clear_plan";
    t.case(f, "crowd NULL", NULL_ARG, |_| unsafe {
        cg_crowd_clear_plan(null_mut())
    });

    let f = "cg_crowd_read_constraints";
    t.case_in(Setup::Planned, f, "crowd NULL", NULL_ARG, |h| {
        let id = h.character(0);
        unsafe {
            cg_crowd_read_constraints(
                null(),
                id,
                h.out.constraints.as_mut_ptr(),
                8,
                &mut h.out.count,
            )
        }
    });
    t.case_in(
        Setup::Planned,
        f,
        "(out NULL, count 2)",
        NULL_ARG,
        |h| unsafe {
            cg_crowd_read_constraints(h.crowd, h.character(0), null_mut(), 2, &mut h.out.count)
        },
    );
    t.case_in(Setup::Planned, f, "count SIZE_MAX", INVALID, |h| {
        let id = h.character(0);
        let out = h.out.constraints.as_mut_ptr();
        unsafe { cg_crowd_read_constraints(h.crowd, id, out, usize::MAX, &mut h.out.count) }
    });
    t.character_ids(Setup::Planned, f, |h, id| {
        let out = h.out.constraints.as_mut_ptr();
        unsafe { cg_crowd_read_constraints(h.crowd, id, out, 8, &mut h.out.count) }
    });
    for setup in [Setup::Online, Setup::Unrecorded] {
        t.case_in(setup, f, "no plan", WRONG_STATE, |h| {
            let id = h.character(0);
            let out = h.out.constraints.as_mut_ptr();
            unsafe { cg_crowd_read_constraints(h.crowd, id, out, 8, &mut h.out.count) }
        });
    }
}
