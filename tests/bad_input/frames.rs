//! Rows: frames and steps (push a frame, step, the ranged step's entry points).

use crate::{
    corruption::{change, inside, non_finite, struct_sizes, Corrupt, Corruption},
    fixture::{Harness, Setup},
    table::Table,
    values::{bad_sizes, floats},
    BAD_SIZE, CAPACITY, INVALID, NON_FINITE, NULL_ARG, WRONG_STATE,
};
use crowdgaze::ffi::attention::*;
use crowdgaze::ffi::frame::*;
use crowdgaze::ffi::status::cg_status;
use std::mem::{offset_of, size_of};
use std::ptr::{null, null_mut};
use std::rc::Rc;

/// Entities in a fixture's frame: four characters and two objects.
pub(crate) const MOVERS: usize = 6;

fn push(h: &mut Harness, states: &mut [cg_entity_state]) -> cg_status {
    let (t, _) = h.next_frame();
    unsafe { cg_crowd_push_frame(h.crowd, t, states.as_ptr(), states.len()) }
}

fn next_states(h: &Harness) -> Vec<cg_entity_state> {
    h.next_frame().1
}

/// Corruptions of the states of a frame, element by element.
fn frame_corruptions() -> Vec<Corruption<Vec<cg_entity_state>>> {
    type S = cg_entity_state;
    let mut out = Vec::new();
    for index in 0..MOVERS {
        let element = |name: String, expected, apply: Corrupt<S>| {
            change(
                format!("states[{index}].{name}"),
                expected,
                move |states: &mut Vec<S>| apply(&mut states[index]),
            )
        };
        for c in non_finite::<S>(&floats!(S: position.x, position.y, position.z)) {
            out.push(element(c.what, c.expected, c.apply));
        }
        // A heading is read (and checked) unless it comes from the motion.
        for c in non_finite::<S>(&floats!(S: heading)) {
            let apply = c.apply;
            out.push(element(
                format!("{} without CG_STATE_HEADING_FROM_MOTION", c.what),
                c.expected,
                Rc::new(move |s: &mut S| {
                    s.flags &= !CG_STATE_HEADING_FROM_MOTION;
                    apply(s)
                }),
            ));
        }
        for c in non_finite::<S>(&floats!(S: velocity.x, velocity.y, velocity.z)) {
            let apply = c.apply;
            out.push(element(
                format!("{} with CG_STATE_HAS_VELOCITY", c.what),
                c.expected,
                Rc::new(move |s: &mut S| {
                    s.flags |= CG_STATE_HAS_VELOCITY;
                    apply(s)
                }),
            ));
        }
        for (what, flags) in [
            ("flags 8 (an unknown bit)", 8),
            ("flags 0x80000000 (an unknown bit)", 0x8000_0000),
            ("flags CG_STATE_TALKING | 8", CG_STATE_TALKING | 8),
        ] {
            out.push(element(
                what.into(),
                INVALID,
                Rc::new(move |s: &mut S| s.flags = flags),
            ));
        }
        out.push(element(
            "flags UINT32_MAX".into(),
            INVALID,
            Rc::new(|s: &mut S| s.flags = u32::MAX),
        ));
        if index > 0 {
            for (what, size) in bad_sizes(size_of::<S>()) {
                out.push(element(
                    format!("struct_size {what}, unlike states[0]'s"),
                    BAD_SIZE,
                    Rc::new(move |s: &mut S| s.struct_size = size),
                ));
            }
        }
    }
    out.extend(inside(
        struct_sizes::<S>(),
        "states[0].",
        |s: &mut Vec<S>| &mut s[0],
    ));
    out
}

pub(crate) fn rows_frames(t: &mut Table) {
    let f = "cg_crowd_push_frame";
    t.case(f, "crowd NULL", NULL_ARG, |h| {
        let (time, states) = h.next_frame();
        unsafe { cg_crowd_push_frame(null_mut(), time, states.as_ptr(), states.len()) }
    });
    t.case(f, "(states NULL, count 6)", NULL_ARG, |h| {
        let (time, _) = h.next_frame();
        unsafe { cg_crowd_push_frame(h.crowd, time, null(), MOVERS) }
    });
    for (label, value) in [
        ("NaN", f64::NAN),
        ("+Inf", f64::INFINITY),
        ("-Inf", f64::NEG_INFINITY),
    ] {
        t.case(f, format!("t = {label}"), NON_FINITE, move |h| {
            let states = next_states(h);
            unsafe { cg_crowd_push_frame(h.crowd, value, states.as_ptr(), states.len()) }
        });
    }
    t.case(f, "t earlier than the previous frame's", INVALID, |h| {
        let states = h.frame_at(h.time);
        unsafe { cg_crowd_push_frame(h.crowd, h.time - 0.5, states.as_ptr(), states.len()) }
    });
    t.case(
        f,
        "t earlier than the previous frame's, no states",
        INVALID,
        |h| unsafe { cg_crowd_push_frame(h.crowd, h.time - 1e-3, null(), 0) },
    );
    t.corrupt(
        Setup::Online,
        f,
        frame_corruptions(),
        next_states,
        |h, s| push(h, s),
    );
    for index in 0..MOVERS {
        t.entity_ids(
            Setup::Online,
            f,
            &format!("states[{index}].id"),
            move |h, id| {
                let mut states = next_states(h);
                states[index].id = id;
                push(h, &mut states)
            },
        );
    }
    for (what, count) in [
        ("count SIZE_MAX", usize::MAX),
        ("count × struct_size overflowing", usize::MAX / 8),
    ] {
        t.case(f, what, INVALID, move |h| {
            let (time, states) = h.next_frame();
            unsafe { cg_crowd_push_frame(h.crowd, time, states.as_ptr(), count) }
        });
    }
    t.case_in(
        Setup::RecordingFull,
        f,
        "the recording is full",
        CAPACITY,
        |h| {
            let mut states = next_states(h);
            push(h, &mut states)
        },
    );
    t.case_in(Setup::Planned, f, "a plan is active", WRONG_STATE, |h| {
        let mut states = next_states(h);
        push(h, &mut states)
    });
    t.case_in(
        Setup::Planned,
        f,
        "a plan is active, no states",
        WRONG_STATE,
        |h| {
            let (time, _) = h.next_frame();
            unsafe { cg_crowd_push_frame(h.crowd, time, null(), 0) }
        },
    );

    let f = "cg_crowd_step";
    t.case(f, "crowd NULL", NULL_ARG, |_| unsafe {
        cg_crowd_step(null_mut(), 0.1)
    });
    t.non_finite_argument(Setup::Online, f, "dt", |h, dt| unsafe {
        cg_crowd_step(h.crowd, dt)
    });
    t.non_finite_argument(Setup::Planned, f, "dt while planned", |h, dt| unsafe {
        cg_crowd_step(h.crowd, dt)
    });
    for (what, dt) in [
        ("dt -1", -1.0),
        ("dt -1e-30", -1e-30),
        ("dt -FLT_MAX", f32::MIN),
    ] {
        t.case(f, what, INVALID, move |h| unsafe {
            cg_crowd_step(h.crowd, dt)
        });
    }
}

/// The ranged step's entry points, on a crowd with no step open. (The misuse that needs an
/// open step — a second begin, overlapping ranges, every other call meanwhile — is in
/// `tests/threads.rs`, which compares the crowd with an untouched one afterwards.)
pub(crate) fn rows_steps(t: &mut Table) {
    let f = "cg_crowd_begin_step";
    t.case(f, "crowd NULL", NULL_ARG, |_| unsafe {
        cg_crowd_begin_step(null_mut(), 0.1)
    });
    t.non_finite_argument(Setup::Online, f, "dt", |h, dt| unsafe {
        cg_crowd_begin_step(h.crowd, dt)
    });
    t.non_finite_argument(Setup::Planned, f, "dt while planned", |h, dt| unsafe {
        cg_crowd_begin_step(h.crowd, dt)
    });
    for (what, dt) in [("dt -1", -1.0), ("dt -FLT_MAX", f32::MIN)] {
        t.case(f, what, INVALID, move |h| unsafe {
            cg_crowd_begin_step(h.crowd, dt)
        });
    }

    let f = "cg_crowd_step_range";
    t.case(f, "crowd NULL", NULL_ARG, |_| unsafe {
        cg_crowd_step_range(null_mut(), 0, 1)
    });
    for (what, first, count) in [
        ("no step open", 0, 1),
        ("no step open, count 0", 0, 0),
        ("no step open, range past the end", 0, u32::MAX),
        ("no step open, first UINT32_MAX", u32::MAX, u32::MAX),
    ] {
        t.case(f, what, WRONG_STATE, move |h| unsafe {
            cg_crowd_step_range(h.crowd, first, count)
        });
    }

    let f = "cg_crowd_end_step";
    t.case(f, "crowd NULL", NULL_ARG, |_| unsafe {
        cg_crowd_end_step(null_mut())
    });
    t.case(f, "no step open", WRONG_STATE, |h| unsafe {
        cg_crowd_end_step(h.crowd)
    });
    t.case_in(
        Setup::Planned,
        f,
        "no step open while planned",
        WRONG_STATE,
        |h| unsafe { cg_crowd_end_step(h.crowd) },
    );
}

/// Pushes `states` as one range of a push opened at the fixture's last frame time (so a
/// refused range, then `cg_crowd_end_push`, leaves the crowd as it was), and returns the
/// range's status.
fn push_in_range(h: &mut Harness, states: &mut [cg_entity_state]) -> cg_status {
    let begun = unsafe { cg_crowd_begin_push(h.crowd, h.time) };
    assert_eq!(begun, cg_status::Ok, "cg_crowd_begin_push");
    let status = unsafe { cg_crowd_push_range(h.crowd, states.as_ptr(), states.len()) };
    let ended = unsafe { cg_crowd_end_push(h.crowd) };
    assert_eq!(ended, cg_status::Ok, "cg_crowd_end_push");
    status
}

/// The ranged push's entry points. A range's states are checked as `cg_crowd_push_frame`'s
/// (the same corruptions and ids, each in a push of its own); concurrent misuse is in
/// `tests/threads.rs`.
pub(crate) fn rows_pushes(t: &mut Table) {
    let f = "cg_crowd_begin_push";
    t.case(f, "crowd NULL", NULL_ARG, |h| unsafe {
        cg_crowd_begin_push(null_mut(), h.next_frame().0)
    });
    for (label, value) in [
        ("NaN", f64::NAN),
        ("+Inf", f64::INFINITY),
        ("-Inf", f64::NEG_INFINITY),
    ] {
        t.case_in(
            Setup::Unrecorded,
            f,
            format!("t = {label}"),
            NON_FINITE,
            move |h| unsafe { cg_crowd_begin_push(h.crowd, value) },
        );
    }
    t.case_in(
        Setup::Unrecorded,
        f,
        "t earlier than the previous frame's",
        INVALID,
        |h| unsafe { cg_crowd_begin_push(h.crowd, h.time - 0.5) },
    );
    t.case(f, "recording is on", WRONG_STATE, |h| unsafe {
        cg_crowd_begin_push(h.crowd, h.next_frame().0)
    });
    t.case_in(
        Setup::Planned,
        f,
        "a plan is active",
        WRONG_STATE,
        |h| unsafe { cg_crowd_begin_push(h.crowd, h.next_frame().0) },
    );

    let f = "cg_crowd_push_range";
    t.case(f, "crowd NULL", NULL_ARG, |h| {
        let states = next_states(h);
        unsafe { cg_crowd_push_range(null_mut(), states.as_ptr(), states.len()) }
    });
    t.case(f, "no push open", WRONG_STATE, |h| {
        let states = next_states(h);
        unsafe { cg_crowd_push_range(h.crowd, states.as_ptr(), states.len()) }
    });
    t.case(f, "no push open, no states", WRONG_STATE, |h| unsafe {
        cg_crowd_push_range(h.crowd, null(), 0)
    });
    t.case_in(
        Setup::Unrecorded,
        f,
        "(states NULL, count 6)",
        NULL_ARG,
        |h| {
            let begun = unsafe { cg_crowd_begin_push(h.crowd, h.time) };
            assert_eq!(begun, cg_status::Ok);
            let status = unsafe { cg_crowd_push_range(h.crowd, null(), MOVERS) };
            assert_eq!(unsafe { cg_crowd_end_push(h.crowd) }, cg_status::Ok);
            status
        },
    );
    t.corrupt(
        Setup::Unrecorded,
        f,
        frame_corruptions(),
        |h| h.frame_at(h.time),
        |h, states| push_in_range(h, states),
    );
    for index in 0..MOVERS {
        t.entity_ids(
            Setup::Unrecorded,
            f,
            &format!("states[{index}].id"),
            move |h, id| {
                let mut states = h.frame_at(h.time);
                states[index].id = id;
                push_in_range(h, &mut states)
            },
        );
    }
    for index in 1..MOVERS {
        t.case_in(
            Setup::Unrecorded,
            f,
            format!("states[{index}] the same entity as states[0]"),
            WRONG_STATE,
            move |h| {
                let mut states = h.frame_at(h.time);
                states[index] = states[0];
                push_in_range(h, &mut states)
            },
        );
    }
    t.case_in(Setup::Unrecorded, f, "count SIZE_MAX", INVALID, |h| {
        let states = h.frame_at(h.time);
        let begun = unsafe { cg_crowd_begin_push(h.crowd, h.time) };
        assert_eq!(begun, cg_status::Ok);
        let status = unsafe { cg_crowd_push_range(h.crowd, states.as_ptr(), usize::MAX) };
        assert_eq!(unsafe { cg_crowd_end_push(h.crowd) }, cg_status::Ok);
        status
    });

    let f = "cg_crowd_end_push";
    t.case(f, "crowd NULL", NULL_ARG, |_| unsafe {
        cg_crowd_end_push(null_mut())
    });
    t.case(f, "no push open", WRONG_STATE, |h| unsafe {
        cg_crowd_end_push(h.crowd)
    });
}
