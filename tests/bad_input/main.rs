//! The bad-input matrix (issue #10): every C function of `include/crowdgaze.h` is called
//! with each kind of bad input that applies to it — NULL pointers and `(NULL, n > 0)` arrays,
//! NaN and infinities in every float input (struct fields and array elements included),
//! unknown, removed and wrong-kind ids, wrong `struct_size`, zero and absurd counts, full
//! capacities, enums out of range, calls in the wrong state.
//!
//! Each case states the status it must return, which must be one the header documents for
//! that function; the call must leave a one-line message in `cg_last_error_message` that
//! matches the status, and must change nothing: every observable output of the crowd (all
//! its readers, for every id), of the view blenders (weights and poses from every key
//! camera) and of the caller's output buffers is compared byte for byte before and after, and
//! the crowd's next frames and its plan must be bit-identical to those of an untouched crowd.
//!
//! The functions are read from the header at test time: a function without a row makes
//! `every_header_function_has_a_row` fail, naming it. To cover a new function, add its cases
//! with `Table::case` (or the helpers after it in `table.rs`) in the `rows_*` function of the
//! module of its area.

// The `unsafe { cg_... }` calls in the files of this test pass pointers to live values of the
// sizes the header asks for, or deliberately bad ones (NULL, misaligned, wrong struct_size)
// that the library must refuse: that is their safety comment, once for all the files.
#![allow(clippy::undocumented_unsafe_blocks)]

// The machinery: the header, helpers for C values, corruptions of a valid input, the
// fixture, its snapshots, and the table of cases.
mod corruption;
mod fixture;
mod header;
mod snapshot;
mod table;
mod values;
// The Mixamo skeleton of the rig rows, shared with the other tests.
#[path = "../support/rig.rs"]
mod skeleton;

// The rows of the table, by area: each module's `rows_*` functions, which `table::table`
// calls.
mod attention;
mod blend;
mod conversations;
mod crowd;
mod dual_quaternions;
mod entities;
mod following;
mod frames;
mod gaze;
mod infallible;
mod init;
mod joints;
mod plan;
mod rig;
mod view_blender;

// Extreme finite values, which are not bad input.
mod extremes;

use crate::{
    attention::params_of,
    fixture::{Harness, Setup, JOINTS},
    header::Header,
    snapshot::{Snapshot, IDENTITY_DQ},
    table::{table, Case, Row},
    values::{init, last_error, ok, rotation, vec3},
};
use crowdgaze::ffi::attention::*;
use crowdgaze::ffi::chain::*;
use crowdgaze::ffi::conversations::*;
use crowdgaze::ffi::frame::*;
use crowdgaze::ffi::gaze::*;
use crowdgaze::ffi::status::{cg_status, cg_status_str};
use crowdgaze::ffi::view_blender::*;
use std::collections::{BTreeMap, HashMap};
use std::ffi::CStr;
use std::mem::MaybeUninit;
use std::ptr::null_mut;

const NULL_ARG: cg_status = cg_status::NullArgument;
const INVALID: cg_status = cg_status::InvalidArgument;
const NON_FINITE: cg_status = cg_status::NonFinite;
const NOT_FOUND: cg_status = cg_status::NotFound;
const CAPACITY: cg_status = cg_status::Capacity;
const BAD_SIZE: cg_status = cg_status::BadStructSize;
const WRONG_STATE: cg_status = cg_status::WrongState;

/// Fewest cases the matrix must run (it runs well over this; the floor catches rows lost
/// by accident).
const CASE_FLOOR: usize = 1500;

// ---------------------------------------------------------------------------------------------
// Running a case

/// Fails a call with a message no case produces, so that a case that fails without
/// recording its own message is seen.
fn set_sentinel_error() -> String {
    let mut desc = MaybeUninit::<cg_chain_desc>::uninit();
    assert_eq!(
        unsafe { cg_chain_desc_init_human(desc.as_mut_ptr(), 4242, 4) },
        INVALID
    );
    last_error()
}

/// The start every message of a failure with `status` has ("not found: …").
fn message_prefix(status: cg_status) -> String {
    // SAFETY: cg_status_str returns a static NUL-terminated string.
    let text = unsafe { CStr::from_ptr(cg_status_str(status as u32)) };
    let text = text.to_str().expect("ASCII");
    text.split(" (").next().unwrap_or(text).to_owned()
}

/// Runs one case; returns its problems (none if it held).
fn run_case(
    header: &Header,
    function: &str,
    case: &Case,
    futures: &mut HashMap<Setup, Snapshot>,
) -> Vec<String> {
    let mut problems = Vec::new();
    if !header
        .documented(function)
        .contains(&(case.expected as u32))
    {
        problems.push(format!(
            "expects {}, which the header does not document for this function",
            header.status_name(case.expected)
        ));
    }
    let mut h = Harness::new(case.setup);
    let before = h.snapshot();
    let sentinel = set_sentinel_error();
    let got = (case.call)(&mut h);
    let message = last_error();
    let after = h.snapshot();
    if got != case.expected {
        problems.push(format!(
            "returned {} ({message:?}) instead of {}",
            header.status_name(got),
            header.status_name(case.expected)
        ));
    }
    if got != cg_status::Ok {
        if message == sentinel || message.is_empty() {
            problems.push("left no message for cg_last_error_message".into());
        } else if message.contains('\n') {
            problems.push(format!("message is not one line: {message:?}"));
        } else if !message.starts_with(&message_prefix(got)) {
            problems.push(format!("message {message:?} does not match its status"));
        }
    }
    let changed = before.differences(&after);
    if !changed.is_empty() {
        problems.push(format!("changed what these read: {}", changed.join(", ")));
    }
    let reference = futures
        .entry(case.setup)
        .or_insert_with(|| Harness::new(case.setup).future());
    let changed = h.future().differences(reference);
    if !changed.is_empty() {
        problems.push(format!(
            "changed the crowd's next frames or plan: {}",
            changed.join(", ")
        ));
    }
    problems.append(&mut h.problems);
    problems
        .into_iter()
        .map(|problem| format!("{function}: {} ({:?}): {problem}", case.what, case.setup))
        .collect()
}

#[test]
fn every_header_function_has_a_row() {
    let header = Header::read();
    let table = table();
    let missing: Vec<&str> = header
        .functions
        .keys()
        .map(String::as_str)
        .filter(|name| !table.rows.contains_key(name))
        .collect();
    assert!(
        missing.is_empty(),
        "functions of include/crowdgaze.h without a row in tests/bad_input/: {}; add their \
         bad-input cases (or a `no_failure_modes` entry saying why there are none)",
        missing.join(", ")
    );
    let stale: Vec<&&str> = table
        .rows
        .keys()
        .filter(|name| !header.functions.contains_key(**name))
        .collect();
    assert!(
        stale.is_empty(),
        "rows for functions the header does not declare: {stale:?}"
    );
    let empty: Vec<&&str> = table
        .rows
        .iter()
        .filter(|(_, row)| matches!(row, Row::Cases(cases) if cases.is_empty()))
        .map(|(name, _)| name)
        .collect();
    assert!(empty.is_empty(), "rows without cases: {empty:?}");
}

#[test]
fn bad_input_gets_its_documented_status_and_changes_nothing() {
    let header = Header::read();
    let table = table();
    let mut futures = HashMap::new();
    let mut failures = Vec::new();
    let mut by_status = BTreeMap::<&str, usize>::new();
    let mut infallible = Vec::new();
    for (function, row) in &table.rows {
        match row {
            Row::Cases(cases) => {
                for case in cases {
                    *by_status
                        .entry(header.status_name(case.expected))
                        .or_default() += 1;
                    failures.extend(run_case(&header, function, case, &mut futures));
                }
            }
            Row::NoFailureModes { why, check } => {
                check();
                infallible.push(format!("{function} ({why})"));
            }
        }
    }
    let cases = table.case_count();
    eprintln!(
        "bad-input matrix: {} functions, {cases} cases ({by_status:?}); without failure \
         modes: {}",
        table.rows.len(),
        infallible.join("; ")
    );
    assert!(
        failures.is_empty(),
        "{} problems in {cases} cases:\n{}",
        failures.len(),
        failures.join("\n")
    );
    assert!(
        cases >= CASE_FLOOR,
        "only {cases} cases ran, fewer than {CASE_FLOOR}: rows were lost"
    );
}

/// The oracle must see a change: successful calls that change the crowd or a blender change
/// its snapshot or its next frames.
#[test]
fn the_snapshots_see_every_kind_of_change() {
    type Change = fn(&mut Harness) -> cg_status;
    let changes: [(&str, Change); 16] = [
        ("set_impact", |h| unsafe {
            cg_crowd_set_impact(h.crowd, h.object(), 3.0)
        }),
        ("set_base_pose", |h| {
            let pose = [rotation([1.0, 0.0, 0.0], 0.1); 10];
            unsafe { cg_crowd_set_base_pose(h.crowd, h.character(0), pose.as_ptr(), 10) }
        }),
        ("set_gaze_target", |h| {
            let mut target: cg_gaze_target = init(cg_gaze_target_init);
            target.point = vec3(-4.0, 1.0, 0.0);
            unsafe { cg_crowd_set_gaze_target(h.crowd, h.character(3), &target) }
        }),
        ("clear_gaze_target", |h| unsafe {
            cg_crowd_clear_gaze_target(h.crowd, h.character(0))
        }),
        ("set_attention_period", |h| unsafe {
            cg_crowd_set_attention_period(h.crowd, h.character(0), 7)
        }),
        ("set_character_params", |h| {
            let mut params = params_of(h);
            params.value.attention_fraction = 0.9;
            unsafe { cg_crowd_set_character_params(h.crowd, h.character(0), &params.value) }
        }),
        ("push_frame", |h| {
            let (t, states) = h.next_frame();
            unsafe { cg_crowd_push_frame(h.crowd, t, states.as_ptr(), 1) }
        }),
        ("step", |h| unsafe { cg_crowd_step(h.crowd, 0.01) }),
        ("add_object", |h| {
            let desc: cg_object_desc = init(cg_object_desc_init);
            unsafe { cg_crowd_add_object(h.crowd, &desc, &mut h.out.id) }
        }),
        ("remove_entity", |h| unsafe {
            cg_crowd_remove_entity(h.crowd, h.object())
        }),
        ("set_conversation", |h| {
            let (members, mut group) = ([h.character(2), h.character(3)], 0);
            unsafe { cg_crowd_set_conversation(h.crowd, members.as_ptr(), 2, &mut group) }
        }),
        ("remove_conversation", |h| unsafe {
            cg_crowd_remove_conversation(h.crowd, h.conversation)
        }),
        ("set_viewer", |h| unsafe {
            cg_crowd_set_viewer(h.crowd, &vec3(0.0, 1.7, 5.0), 1.5, null_mut())
        }),
        ("add_camera", |h| unsafe {
            cg_view_blender_add_camera(h.blender, vec3(0.0, 1.0, 0.0), 1)
        }),
        ("set_key_pose", |h| {
            let pose = [IDENTITY_DQ; JOINTS];
            unsafe { cg_view_blender_set_key_pose(h.blender, 2, pose.as_ptr(), JOINTS) }
        }),
        ("write an output", |h| unsafe {
            cg_crowd_character_count(h.crowd, &mut h.out.count)
        }),
    ];
    let untouched = Harness::new(Setup::Online);
    let (snapshot, future) = (untouched.snapshot(), untouched.future());
    for (what, change) in changes {
        let mut h = Harness::new(Setup::Online);
        assert!(h.snapshot() == snapshot, "fixtures differ");
        ok(change(&mut h));
        let seen = !h.snapshot().differences(&snapshot).is_empty()
            || !h.future().differences(&future).is_empty();
        assert!(seen, "the snapshots did not see {what}");
    }
}

/// Two fixtures built alike are alike, and so are their futures (the reference the cases
/// are compared with).
#[test]
fn fixtures_are_deterministic() {
    for setup in [
        Setup::Online,
        Setup::Planned,
        Setup::Full,
        Setup::RecordingFull,
        Setup::Unrecorded,
    ] {
        let (a, b) = (Harness::new(setup), Harness::new(setup));
        assert!(a.snapshot() == b.snapshot(), "{setup:?}");
        assert!(a.future() == b.future(), "{setup:?}");
    }
}
