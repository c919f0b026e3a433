//! A panic inside a call that changes a handle poisons it: the crowd or blender may be
//! half-updated (a ranged step left open, a range still counted as running, a step done but
//! reported failed), so every later call on it returns `CG_STATUS_POISONED` with the first
//! failure's message, and its `_destroy` still frees it.
//!
//! A rig is never changed, so never poisoned: a panic inside a call on it is caught, and
//! the next call works.
//!
//! The panics come from the test hooks of `crowdgaze::ffi::testing` (cargo feature
//! `test-hooks`, enabled for this crate's tests only). A counting allocator (bytes live per
//! thread) checks that `_destroy` frees a poisoned handle's memory.

// The `unsafe { cg_... }` calls below pass pointers to live values of the sizes the header
// asks for, or deliberately bad ones (NULL, misaligned, wrong struct_size) that the library
// must refuse: that is their safety comment, once for the file.
#![allow(clippy::undocumented_unsafe_blocks)]

use crowdgaze::ffi::attention::*;

use crowdgaze::ffi::conversations::*;
use crowdgaze::ffi::crowd::*;
use crowdgaze::ffi::eyelids::*;
use crowdgaze::ffi::following::*;
use crowdgaze::ffi::frame::*;
use crowdgaze::ffi::gaze::*;
use crowdgaze::ffi::last_error::last_error_message;
use crowdgaze::ffi::rig::*;
use crowdgaze::ffi::status::cg_status;
use crowdgaze::ffi::testing::{panic_next, panic_next_change, panic_next_rig_call, PanicAt};
use crowdgaze::ffi::types::{cg_dualquat, cg_quat, cg_vec3};
use crowdgaze::ffi::view_blender::*;
use std::alloc::{GlobalAlloc, Layout, System};

#[path = "support/rig.rs"]
mod support_rig;
use std::cell::Cell;
use std::mem::{size_of, MaybeUninit};
use std::ptr::null_mut;

// ---------------------------------------------------------------------------------------------
// Bytes live on this thread

struct CountingAllocator;

thread_local! {
    static LIVE: Cell<i64> = const { Cell::new(0) };
}

fn count(bytes: i64) {
    let _ = LIVE.try_with(|live| live.set(live.get() + bytes));
}

// SAFETY: forwards every call to the system allocator unchanged; only counts.
unsafe impl GlobalAlloc for CountingAllocator {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        count(layout.size() as i64);
        // SAFETY: same contract as the caller's.
        unsafe { System.alloc(layout) }
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        count(-(layout.size() as i64));
        // SAFETY: same contract as the caller's.
        unsafe { System.dealloc(ptr, layout) }
    }

    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        count(layout.size() as i64);
        // SAFETY: same contract as the caller's.
        unsafe { System.alloc_zeroed(layout) }
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        count(new_size as i64 - layout.size() as i64);
        // SAFETY: same contract as the caller's.
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static GLOBAL: CountingAllocator = CountingAllocator;

fn live() -> i64 {
    LIVE.with(Cell::get)
}

/// Most bytes a destroyed handle may leave live on the thread: the thread's last error
/// message grows with the longest one recorded.
const SLACK: i64 = 4096;

// ---------------------------------------------------------------------------------------------
// Helpers

/// The hooks' panics are expected: keep them off the test output (others still print).
fn quiet_panics() {
    static ONCE: std::sync::Once = std::sync::Once::new();
    ONCE.call_once(|| {
        let default = std::panic::take_hook();
        std::panic::set_hook(Box::new(move |info| {
            let payload = info.payload();
            let text = payload
                .downcast_ref::<String>()
                .map(String::as_str)
                .or_else(|| payload.downcast_ref::<&str>().copied())
                .unwrap_or("");
            if !text.starts_with("test hook:") {
                default(info);
            }
        }));
    });
}

fn ok(status: cg_status) {
    assert_eq!(status, cg_status::Ok, "{}", last_error_message());
}

/// A struct filled by its `_init` function, after setting its `struct_size`.
fn init<T>(f: unsafe extern "C" fn(*mut T) -> cg_status) -> T {
    let mut value = MaybeUninit::<T>::uninit();
    // SAFETY: every versioned struct starts with its `uint32_t struct_size`.
    unsafe {
        value
            .as_mut_ptr()
            .cast::<u32>()
            .write(size_of::<T>() as u32)
    };
    ok(unsafe { f(value.as_mut_ptr()) });
    // SAFETY: initialised by the _init function just above.
    unsafe { value.assume_init() }
}

fn vec3(x: f32, y: f32, z: f32) -> cg_vec3 {
    cg_vec3 { x, y, z }
}

/// A crowd of three characters and an object, stepped once; its ids.
fn crowd() -> (*mut cg_crowd, Vec<u32>) {
    let config: cg_crowd_config = init(cg_crowd_config_init);
    let mut crowd = null_mut();
    ok(unsafe { cg_crowd_create(&config, &mut crowd) });
    let mut ids = Vec::new();
    for x in [0.0, 1.5, -1.5] {
        let mut desc: cg_character_desc = init(cg_character_desc_init);
        desc.position = vec3(x, 0.0, 0.0);
        let mut id = 0;
        ok(unsafe { cg_crowd_add_character(crowd, &desc, &mut id) });
        ids.push(id);
    }
    let mut object: cg_object_desc = init(cg_object_desc_init);
    object.position = vec3(0.0, 1.0, 3.0);
    let mut id = 0;
    ok(unsafe { cg_crowd_add_object(crowd, &object, &mut id) });
    ids.push(id);
    ok(unsafe { cg_crowd_step(crowd, 0.05) });
    (crowd, ids)
}

/// The names of the header's functions whose first parameter is a `handle` pointer (const
/// or not), but its `_destroy`.
fn header_functions_on(handle: &str) -> Vec<String> {
    let header = std::fs::read_to_string(
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("include/crowdgaze.h"),
    )
    .expect("include/crowdgaze.h");
    let mut names: Vec<String> = header
        .lines()
        .filter(|line| !line.starts_with("//") && !line.starts_with(' '))
        .filter_map(|line| {
            let (head, parameters) = line.split_once('(')?;
            let name = head.rsplit([' ', '*']).next()?;
            let first = parameters.trim_start_matches("const ");
            (name.starts_with("cg_") && first.starts_with(&format!("struct {handle} *")))
                .then(|| name.to_owned())
        })
        .filter(|name| !name.ends_with("_destroy"))
        .collect();
    names.sort();
    names
}

/// Checks that every call in `calls` fails with `CG_STATUS_POISONED` and `expected`, and
/// that they are every function of the header on `handle`.
fn all_poisoned(handle: &str, calls: &[(&str, &dyn Fn() -> cg_status)], expected: &str) {
    for (name, call) in calls {
        assert_eq!(
            call(),
            cg_status::Poisoned,
            "{name}: {}",
            last_error_message()
        );
        assert_eq!(last_error_message(), expected, "{name}");
    }
    let mut named: Vec<String> = calls.iter().map(|(name, _)| name.to_string()).collect();
    named.sort();
    named.dedup();
    assert_eq!(
        named,
        header_functions_on(handle),
        "calls on a poisoned {handle} checked vs the header's"
    );
}

/// Every function taking a crowd, called with valid arguments (`ids` of the crowd's
/// characters and object).
fn every_crowd_call(crowd: *mut cg_crowd, ids: &[u32], expected: &str) {
    let (a, b, object) = (ids[0], ids[1], ids[3]);
    let mut state: cg_entity_state = init(cg_entity_state_init);
    state.id = a;
    let desc: cg_character_desc = init(cg_character_desc_init);
    let object_desc: cg_object_desc = init(cg_object_desc_init);
    let mut target: cg_gaze_target = init(cg_gaze_target_init);
    (target.kind, target.entity) = (CG_GAZE_TARGET_ENTITY, object);
    let mut params = cg_character_params {
        struct_size: size_of::<cg_character_params>() as u32,
        weight_proximity: 0.25,
        weight_speed: 0.25,
        weight_orientation: 0.25,
        weight_periphery: 0.25,
        attention_fraction: 0.5,
        attention_model: 0,
    };
    let mut config: cg_crowd_config = init(cg_crowd_config_init);
    let pose = [cg_quat::IDENTITY; 10];
    let mut quats = [cg_quat::IDENTITY; 30];
    let mut gaze = [cg_gaze_info::default(); 3];
    let mut eyes = [cg_eye_info::default(); 3];
    let mut eyelids = [cg_eyelids::default(); 3];
    let mut constraints = [cg_constraint::default(); 4];
    let mut score = cg_score_breakdown::default();
    let (mut id, mut count) = (u32::MAX, usize::MAX);
    let (mut point, mut flags) = (vec3(7.0, 7.0, 7.0), [u32::MAX; 2]);
    let viewer = vec3(0.0, 1.7, 5.0);
    // The outputs, as the raw pointers a C caller passes (the calls below share them).
    let (id_out, count_out): (*mut u32, *mut usize) = (&mut id, &mut count);
    let (score_out, params_out): (*mut cg_score_breakdown, *mut cg_character_params) =
        (&mut score, &mut params);
    let config_out: *mut cg_crowd_config = &mut config;
    let (gaze_out, eyes_out) = (gaze.as_mut_ptr(), eyes.as_mut_ptr());
    let eyelids_out = eyelids.as_mut_ptr();
    let (point_out, flags_out): (*mut cg_vec3, *mut u32) = (&mut point, flags.as_mut_ptr());
    let (constraints_out, quats_out) = (constraints.as_mut_ptr(), quats.as_mut_ptr());
    let calls: [(&str, &dyn Fn() -> cg_status); 36] = [
        ("cg_crowd_begin_step", &|| unsafe {
            cg_crowd_begin_step(crowd, 0.05)
        }),
        ("cg_crowd_step_range", &|| unsafe {
            cg_crowd_step_range(crowd, 0, 1)
        }),
        ("cg_crowd_end_step", &|| unsafe { cg_crowd_end_step(crowd) }),
        ("cg_crowd_step", &|| unsafe { cg_crowd_step(crowd, 0.05) }),
        ("cg_crowd_begin_push", &|| unsafe {
            cg_crowd_begin_push(crowd, 1.0)
        }),
        ("cg_crowd_push_range", &|| unsafe {
            cg_crowd_push_range(crowd, &state, 1)
        }),
        ("cg_crowd_end_push", &|| unsafe { cg_crowd_end_push(crowd) }),
        ("cg_crowd_push_frame", &|| unsafe {
            cg_crowd_push_frame(crowd, 1.0, &state, 1)
        }),
        ("cg_crowd_add_character", &|| unsafe {
            cg_crowd_add_character(crowd, &desc, id_out)
        }),
        ("cg_crowd_add_object", &|| unsafe {
            cg_crowd_add_object(crowd, &object_desc, id_out)
        }),
        ("cg_crowd_remove_entity", &|| unsafe {
            cg_crowd_remove_entity(crowd, b)
        }),
        ("cg_crowd_character_count", &|| unsafe {
            cg_crowd_character_count(crowd, count_out)
        }),
        ("cg_crowd_read_gaze", &|| unsafe {
            cg_crowd_read_gaze(crowd, gaze_out, 3, null_mut())
        }),
        ("cg_crowd_score", &|| unsafe {
            cg_crowd_score(crowd, a, b, score_out)
        }),
        ("cg_crowd_get_character_params", &|| unsafe {
            cg_crowd_get_character_params(crowd, a, params_out)
        }),
        ("cg_crowd_set_character_params", &|| unsafe {
            cg_crowd_set_character_params(crowd, a, params_out)
        }),
        ("cg_crowd_set_impact", &|| unsafe {
            cg_crowd_set_impact(crowd, a, 2.0)
        }),
        ("cg_crowd_plan", &|| unsafe { cg_crowd_plan(crowd) }),
        ("cg_crowd_clear_plan", &|| unsafe {
            cg_crowd_clear_plan(crowd)
        }),
        ("cg_crowd_read_constraints", &|| unsafe {
            cg_crowd_read_constraints(crowd, a, constraints_out, 4, null_mut())
        }),
        ("cg_crowd_set_viewer", &|| unsafe {
            cg_crowd_set_viewer(crowd, &viewer, 1.0, null_mut())
        }),
        ("cg_crowd_set_attention_period", &|| unsafe {
            cg_crowd_set_attention_period(crowd, a, 2)
        }),
        ("cg_crowd_get_config", &|| unsafe {
            cg_crowd_get_config(crowd, config_out)
        }),
        ("cg_crowd_set_gaze_target", &|| unsafe {
            cg_crowd_set_gaze_target(crowd, a, &target)
        }),
        ("cg_crowd_clear_gaze_target", &|| unsafe {
            cg_crowd_clear_gaze_target(crowd, a)
        }),
        ("cg_crowd_set_base_pose", &|| unsafe {
            cg_crowd_set_base_pose(crowd, a, pose.as_ptr(), 10)
        }),
        ("cg_crowd_set_base_poses", &|| unsafe {
            cg_crowd_set_base_poses(crowd, &a, 1, pose.as_ptr(), 10)
        }),
        ("cg_crowd_joint_total", &|| unsafe {
            cg_crowd_joint_total(crowd, 0, 3, count_out)
        }),
        ("cg_crowd_read_joints", &|| unsafe {
            cg_crowd_read_joints(crowd, 0, 3, quats_out, 30)
        }),
        ("cg_crowd_read_joint_deltas", &|| unsafe {
            cg_crowd_read_joint_deltas(crowd, 0, 3, quats_out, 30)
        }),
        ("cg_crowd_read_eyes", &|| unsafe {
            cg_crowd_read_eyes(crowd, 0, 3, eyes_out, 3)
        }),
        ("cg_crowd_read_eyelids", &|| unsafe {
            cg_crowd_read_eyelids(crowd, 0, 3, eyelids_out, 3)
        }),
        ("cg_crowd_set_conversation", &|| unsafe {
            cg_crowd_set_conversation(crowd, [a, b].as_ptr(), 2, id_out)
        }),
        ("cg_crowd_remove_conversation", &|| unsafe {
            cg_crowd_remove_conversation(crowd, 0)
        }),
        ("cg_crowd_get_conversation", &|| unsafe {
            cg_crowd_get_conversation(crowd, a, id_out)
        }),
        ("cg_crowd_read_following", &|| unsafe {
            cg_crowd_read_following(crowd, a, point_out, flags_out, flags_out.add(1))
        }),
    ];
    all_poisoned("cg_crowd", &calls, expected);
    // Nothing was written.
    assert_eq!((id, count), (u32::MAX, usize::MAX));
    assert_eq!((point, flags), (vec3(7.0, 7.0, 7.0), [u32::MAX; 2]));
    assert!(gaze.iter().all(|g| g.character == 0 && g.target == 0));
    assert!(eyes.iter().all(|e| e.character == 0));
    assert!(eyelids.iter().all(|e| *e == cg_eyelids::default()));
    assert!(constraints.iter().all(|c| c.entity == 0));
    assert!(quats.iter().all(|q| *q == cg_quat::IDENTITY));
    assert_eq!((score.total, params.attention_fraction), (0.0, 0.5));
    assert_eq!(config.seed, init(cg_crowd_config_init).seed);
}

// ---------------------------------------------------------------------------------------------
// Tests

#[test]
fn a_panic_in_any_step_call_poisons_the_crowd_and_destroy_still_frees_it() {
    quiet_panics();
    for at in [
        PanicAt::BeginStep,
        PanicAt::StepRange,
        PanicAt::EndStep,
        PanicAt::Step,
    ] {
        let before = live();
        let (crowd, ids) = crowd();
        let held = live() - before;
        assert!(held > 100 * SLACK, "the crowd holds only {held} bytes");
        // SAFETY: a live handle.
        let panic_next = || assert_eq!(unsafe { panic_next(crowd, at) }, cg_status::Ok);
        let status = match at {
            PanicAt::BeginStep => {
                panic_next();
                unsafe { cg_crowd_begin_step(crowd, 0.05) }
            }
            PanicAt::StepRange => {
                ok(unsafe { cg_crowd_begin_step(crowd, 0.05) });
                ok(unsafe { cg_crowd_step_range(crowd, 2, 1) });
                panic_next();
                unsafe { cg_crowd_step_range(crowd, 0, 2) }
            }
            PanicAt::EndStep => {
                ok(unsafe { cg_crowd_begin_step(crowd, 0.05) });
                ok(unsafe { cg_crowd_step_range(crowd, 0, 1) });
                panic_next();
                unsafe { cg_crowd_end_step(crowd) }
            }
            PanicAt::Step => {
                panic_next();
                unsafe { cg_crowd_step(crowd, 0.05) }
            }
        };
        assert_eq!(status, cg_status::Internal, "{at:?}");
        let first = last_error_message();
        assert_eq!(
            first,
            format!("internal error: caught panic: test hook: {at:?} panics")
        );
        let expected = format!("poisoned: an earlier call failed inside the library: {first}");
        // Every later call, twice over: the crowd stays poisoned.
        every_crowd_call(crowd, &ids, &expected);
        every_crowd_call(crowd, &ids, &expected);
        unsafe { cg_crowd_destroy(crowd) };
        let left = live() - before;
        assert!(left < SLACK, "{at:?}: {left} bytes left live after destroy");
    }
}

#[test]
fn failures_that_are_not_internal_do_not_poison() {
    let (crowd, ids) = crowd();
    assert_eq!(
        unsafe { cg_crowd_step(crowd, -1.0) },
        cg_status::InvalidArgument
    );
    assert_eq!(
        unsafe { cg_crowd_step_range(crowd, 0, 1) },
        cg_status::WrongState
    );
    assert_eq!(
        unsafe { cg_crowd_remove_entity(crowd, 4242) },
        cg_status::NotFound
    );
    ok(unsafe { cg_crowd_begin_step(crowd, 0.05) });
    assert_eq!(unsafe { cg_crowd_step(crowd, 0.05) }, cg_status::WrongState);
    assert_eq!(
        unsafe { cg_crowd_step_range(crowd, 0, 9) },
        cg_status::InvalidArgument
    );
    ok(unsafe { cg_crowd_end_step(crowd) });
    ok(unsafe { cg_crowd_step(crowd, 0.05) });
    ok(unsafe { cg_crowd_remove_entity(crowd, ids[1]) });
    unsafe { cg_crowd_destroy(crowd) };
}

/// A two-joint, one-key blender with a pose and a camera.
fn blender() -> *mut cg_view_blender {
    let mut config: cg_view_blender_config = init(cg_view_blender_config_init);
    (config.joint_count, config.key_count) = (2, 1);
    let mut blender = null_mut();
    ok(unsafe { cg_view_blender_create(&config, &mut blender) });
    let pose = [identity(); 2];
    ok(unsafe { cg_view_blender_set_key_pose(blender, 0, pose.as_ptr(), 2) });
    ok(unsafe { cg_view_blender_add_camera(blender, vec3(0.0, 0.0, 1.0), 0) });
    blender
}

fn identity() -> cg_dualquat {
    cg_dualquat {
        real: cg_quat::IDENTITY,
        dual: cg_quat {
            x: 0.0,
            y: 0.0,
            z: 0.0,
            w: 0.0,
        },
    }
}

#[test]
fn a_panic_in_a_blender_change_poisons_it_and_destroy_still_frees_it() {
    quiet_panics();
    let before = live();
    let blender = blender();
    // SAFETY: a live handle.
    assert_eq!(unsafe { panic_next_change(blender) }, cg_status::Ok);
    assert_eq!(
        unsafe { cg_view_blender_add_camera(blender, vec3(1.0, 0.0, 0.0), 0) },
        cg_status::Internal
    );
    let first = last_error_message();
    let expected = format!("poisoned: an earlier call failed inside the library: {first}");
    let pose = [identity(); 2];
    let character = identity();
    let viewer = vec3(0.0, 1.0, 5.0);
    let mut weights = [f32::NAN; 1];
    let mut out = [identity(); 2];
    let (weights_out, pose_out) = (weights.as_mut_ptr(), out.as_mut_ptr());
    let calls: [(&str, &dyn Fn() -> cg_status); 5] = [
        ("cg_view_blender_set_key_clip", &|| unsafe {
            cg_view_blender_set_key_clip(blender, 0, pose.as_ptr(), 1, 30.0, false)
        }),
        ("cg_view_blender_set_key_pose", &|| unsafe {
            cg_view_blender_set_key_pose(blender, 0, pose.as_ptr(), 2)
        }),
        ("cg_view_blender_add_camera", &|| unsafe {
            cg_view_blender_add_camera(blender, vec3(0.0, 0.0, -1.0), 0)
        }),
        ("cg_view_blender_weights", &|| unsafe {
            cg_view_blender_weights(blender, &character, &viewer, weights_out, 1)
        }),
        ("cg_view_blender_evaluate", &|| unsafe {
            cg_view_blender_evaluate(blender, &character, &viewer, 0.0, pose_out, 2)
        }),
    ];
    all_poisoned("cg_view_blender", &calls, &expected);
    assert!(weights[0].is_nan(), "nothing written");
    assert!(out.iter().all(|q| q.dual.w == 0.0 && q.real.w == 1.0));
    unsafe { cg_view_blender_destroy(blender) };
    let left = live() - before;
    assert!(left < SLACK, "{left} bytes left live after destroy");
}

/// A rig is immutable: a panic inside any call on it is caught and returns
/// `CG_STATUS_INTERNAL` with nothing written, and it poisons nothing (no call can have left
/// the rig half-updated): the next call works. Its `_destroy` frees it.
#[test]
fn a_panic_in_a_rig_call_is_caught_and_poisons_nothing() {
    quiet_panics();
    let skeleton = support_rig::Skeleton::mixamo();
    let bones = skeleton.animated(0.4);
    let mut written = bones.clone();
    let before = live();
    let mut desc = skeleton.desc(1.0);
    desc.struct_size = size_of::<cg_rig_desc>() as u32;
    let mut rig = null_mut();
    ok(unsafe { cg_rig_create(&desc, &mut rig) });
    let rig = rig.cast_const();
    let mut chain: crowdgaze::ffi::chain::cg_chain_desc = unsafe { std::mem::zeroed() };
    chain.struct_size = size_of::<crowdgaze::ffi::chain::cg_chain_desc>() as u32;
    let mut count = u32::MAX;
    let mut list = [u32::MAX; 65];
    let mut base = [cg_quat::IDENTITY; 7];
    let mut report = [0x5A as std::ffi::c_char; 16];
    let (chain_out, count_out, list_out) = (
        &mut chain as *mut _,
        &mut count as *mut u32,
        list.as_mut_ptr(),
    );
    let (base_out, written_out, report_out) =
        (base.as_mut_ptr(), written.as_mut_ptr(), report.as_mut_ptr());
    let calls: [(&str, &dyn Fn() -> cg_status); 8] = [
        ("cg_rig_chain", &|| unsafe { cg_rig_chain(rig, chain_out) }),
        ("cg_rig_bone_count", &|| unsafe {
            cg_rig_bone_count(rig, count_out)
        }),
        ("cg_rig_joint_count", &|| unsafe {
            cg_rig_joint_count(rig, count_out)
        }),
        ("cg_rig_chain_bones", &|| unsafe {
            cg_rig_chain_bones(rig, list_out, 65)
        }),
        ("cg_rig_bone_roles", &|| unsafe {
            cg_rig_bone_roles(rig, list_out, 65)
        }),
        (
            "cg_rig_report",
            &|| match unsafe { cg_rig_report(rig, report_out, 16) } {
                0 => cg_status::Internal,
                _ => cg_status::Ok,
            },
        ),
        ("cg_rig_base_pose", &|| unsafe {
            cg_rig_base_pose(rig, bones.as_ptr(), 65, base_out, 7)
        }),
        ("cg_rig_write_joints", &|| unsafe {
            cg_rig_write_joints(rig, base_out, 7, written_out, 65)
        }),
    ];
    for (name, call) in &calls {
        ok(unsafe { panic_next_rig_call(rig) });
        assert_eq!(call(), cg_status::Internal, "{name}");
        assert!(
            last_error_message().starts_with("internal error: caught panic: test hook"),
            "{name}: {}",
            last_error_message()
        );
    }
    assert_eq!(chain.joint_count, 0, "nothing written");
    assert_eq!((count, list), (u32::MAX, [u32::MAX; 65]));
    assert_eq!(base, [cg_quat::IDENTITY; 7]);
    assert!(written == bones && report == [0x5A; 16]);
    for (name, call) in &calls {
        assert_eq!(call(), cg_status::Ok, "{name} after a caught panic");
    }
    let mut names: Vec<&str> = calls.iter().map(|(name, _)| *name).collect();
    names.sort();
    assert_eq!(names, header_functions_on("cg_rig"), "every call on a rig");
    unsafe { cg_rig_destroy(rig.cast_mut()) };
    let left = live() - before;
    assert!(left < SLACK, "{left} bytes left live after destroy");
}
