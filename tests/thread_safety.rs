//! Calls taking a `const` handle may run concurrently with each other (the header says so
//! on each): four threads make every such call on the same stepped crowd (and view
//! blender, and rig) at once, round after round, and each thread's results must equal the results
//! of one thread alone, bit for bit. Failing calls are included: their messages are the
//! calling thread's own.

// The `unsafe { cg_... }` calls below pass pointers to live values of the sizes the header
// asks for, or deliberately bad ones (NULL, misaligned, wrong struct_size) that the library
// must refuse: that is their safety comment, once for the file.
#![allow(clippy::undocumented_unsafe_blocks)]

mod support;

use crowdgaze::ffi::attention::*;

use crowdgaze::ffi::chain::cg_chain_desc;
use crowdgaze::ffi::conversations::*;
use crowdgaze::ffi::crowd::*;
use crowdgaze::ffi::eyelids::*;
use crowdgaze::ffi::following::*;
use crowdgaze::ffi::frame::*;
use crowdgaze::ffi::gaze::*;
use crowdgaze::ffi::last_error::last_error_message;
use crowdgaze::ffi::rig::*;
use crowdgaze::ffi::status::cg_status;
use crowdgaze::ffi::types::{cg_dualquat, cg_quat, cg_vec3};
use crowdgaze::ffi::view_blender::*;
use crowdgaze::DualQuat;
use glam::{Quat, Vec3};
use std::collections::BTreeSet;
use std::fmt::Write;
use std::ptr::null_mut;
use std::sync::Barrier;
use support::{check, init, Street};

const THREADS: usize = 4;
const ROUNDS: usize = 100;

/// Every header function that takes a `const` crowd, blender or rig handle, as the
/// transcripts below call them; `const_functions_are_all_covered` keeps the list equal to
/// the header's.
const COVERED: [&str; 23] = [
    "cg_crowd_character_count",
    "cg_crowd_get_config",
    "cg_crowd_read_gaze",
    "cg_crowd_joint_total",
    "cg_crowd_read_joints",
    "cg_crowd_read_joint_deltas",
    "cg_crowd_read_eyes",
    "cg_crowd_read_eyelids",
    "cg_crowd_get_character_params",
    "cg_crowd_score",
    "cg_crowd_read_constraints",
    "cg_crowd_get_conversation",
    "cg_crowd_read_following",
    "cg_view_blender_weights",
    "cg_view_blender_evaluate",
    "cg_rig_chain",
    "cg_rig_bone_count",
    "cg_rig_joint_count",
    "cg_rig_chain_bones",
    "cg_rig_bone_roles",
    "cg_rig_report",
    "cg_rig_base_pose",
    "cg_rig_write_joints",
];

/// A handle shared by the reading threads.
struct Shared<T>(*const T);

impl<T> Shared<T> {
    fn get(&self) -> *const T {
        self.0
    }
}
// SAFETY: the threads make only calls that take a `const` handle, which the header allows to
// run concurrently, and nothing mutates the object while they run.
unsafe impl<T> Send for Shared<T> {}
// SAFETY: as above.
unsafe impl<T> Sync for Shared<T> {}

/// Appends a call's status, and its thread's last error message if it failed.
fn status(out: &mut String, what: &str, status: cg_status) {
    write!(out, "{what}: {status:?}").unwrap();
    if status != cg_status::Ok {
        write!(out, " ({})", last_error_message()).unwrap();
    }
    out.push('\n');
}

/// Everything the `const` calls say about `crowd`, as text. `Debug` prints each float in its
/// shortest round-trip form, so equal text is equal bits (all outputs are finite).
fn crowd_transcript(crowd: *const cg_crowd) -> String {
    let mut out = String::new();
    let mut count = 0;
    status(&mut out, "count", unsafe {
        cg_crowd_character_count(crowd, &mut count)
    });
    let mut config: cg_crowd_config = init(cg_crowd_config_init);
    status(&mut out, "config", unsafe {
        cg_crowd_get_config(crowd, &mut config)
    });
    writeln!(out, "{count} {config:?}").unwrap();

    let mut gaze = vec![cg_gaze_info::default(); count];
    let mut written = 0;
    let s = unsafe { cg_crowd_read_gaze(crowd, gaze.as_mut_ptr(), count, &mut written) };
    status(&mut out, "gaze", s);
    writeln!(out, "{written} {gaze:?}").unwrap();

    let mut total = 0;
    let s = unsafe { cg_crowd_joint_total(crowd, 0, count as u32, &mut total) };
    status(&mut out, "joint total", s);
    let mut joints = vec![cg_quat::IDENTITY; total];
    let s = unsafe { cg_crowd_read_joints(crowd, 0, count as u32, joints.as_mut_ptr(), total) };
    status(&mut out, "joints", s);
    let mut deltas = vec![cg_quat::IDENTITY; total];
    let s =
        unsafe { cg_crowd_read_joint_deltas(crowd, 0, count as u32, deltas.as_mut_ptr(), total) };
    status(&mut out, "deltas", s);
    let mut eyes = vec![cg_eye_info::default(); count];
    let s = unsafe { cg_crowd_read_eyes(crowd, 0, count as u32, eyes.as_mut_ptr(), count) };
    status(&mut out, "eyes", s);
    let mut lids = vec![cg_eyelids::default(); count];
    let s = unsafe { cg_crowd_read_eyelids(crowd, 0, count as u32, lids.as_mut_ptr(), count) };
    status(&mut out, "eyelids", s);
    writeln!(out, "{total} {joints:?} {deltas:?} {eyes:?} {lids:?}").unwrap();

    // Per character, as an engine's animation threads would: its joints, its parameters,
    // its conversation, how it scores its neighbour and its target, its planned constraints.
    let mut one = [cg_quat::IDENTITY; crowdgaze::ik::MAX_CHAIN_JOINTS];
    let mut constraints = vec![cg_constraint::default(); 64];
    for (index, info) in gaze.iter().enumerate() {
        let s =
            unsafe { cg_crowd_read_joints(crowd, index as u32, 1, one.as_mut_ptr(), one.len()) };
        status(&mut out, "one's joints", s);
        // SAFETY: cg_character_params is plain u32 and f32 fields: all zeros is a value.
        let mut params: cg_character_params = unsafe { std::mem::zeroed() };
        params.struct_size = std::mem::size_of::<cg_character_params>() as u32;
        let s = unsafe { cg_crowd_get_character_params(crowd, info.character, &mut params) };
        status(&mut out, "params", s);
        let mut group = 0;
        let s = unsafe { cg_crowd_get_conversation(crowd, info.character, &mut group) };
        status(&mut out, "conversation", s);
        let (mut point, mut following, mut glances) = (cg_vec3::default(), 0, 0);
        let s = unsafe {
            cg_crowd_read_following(
                crowd,
                info.character,
                &mut point,
                &mut following,
                &mut glances,
            )
        };
        status(&mut out, "following", s);
        writeln!(
            out,
            "{one:?} {params:?} {group} {point:?} {following} {glances}"
        )
        .unwrap();
        let neighbour = gaze[(index + 1) % gaze.len()].character;
        for entity in [neighbour, info.target, info.head_target] {
            let mut score = cg_score_breakdown::default();
            let s = unsafe { cg_crowd_score(crowd, info.character, entity, &mut score) };
            status(&mut out, "score", s);
            writeln!(out, "{score:?}").unwrap();
        }
        let mut total = 0;
        let s = unsafe {
            cg_crowd_read_constraints(
                crowd,
                info.character,
                constraints.as_mut_ptr(),
                constraints.len(),
                &mut total,
            )
        };
        status(&mut out, "constraints", s);
        writeln!(out, "{total} {:?}", &constraints[..total.min(64)]).unwrap();
    }
    // Bad arguments: each thread records its own message.
    let s = unsafe { cg_crowd_read_joints(crowd, count as u32, 1, one.as_mut_ptr(), one.len()) };
    status(&mut out, "joints past the end", s);
    status(&mut out, "unknown id", unsafe {
        cg_crowd_score(crowd, 0xdead_beef, 0, &mut cg_score_breakdown::default())
    });
    status(&mut out, "unknown id's conversation", unsafe {
        cg_crowd_get_conversation(crowd, 0xdead_beef, &mut 0)
    });
    out
}

/// Runs `transcript` once alone, then `ROUNDS` times on `THREADS` threads started together,
/// and fails unless every thread of every round wrote the same as the lone run.
fn same_on_every_thread<T>(handle: *const T, transcript: fn(*const T) -> String) {
    let alone = transcript(handle);
    let shared = Shared(handle);
    let barrier = Barrier::new(THREADS);
    for round in 0..ROUNDS {
        let results: Vec<String> = std::thread::scope(|scope| {
            let workers: Vec<_> = (0..THREADS)
                .map(|_| {
                    let (barrier, shared) = (&barrier, &shared);
                    scope.spawn(move || {
                        barrier.wait();
                        transcript(shared.get())
                    })
                })
                .collect();
            workers.into_iter().map(|w| w.join().unwrap()).collect()
        });
        for (thread, result) in results.iter().enumerate() {
            if *result != alone {
                let at = result
                    .bytes()
                    .zip(alone.bytes())
                    .position(|(a, b)| a != b)
                    .unwrap_or(result.len().min(alone.len()));
                let near =
                    |text: &str| text[at.saturating_sub(80)..(at + 80).min(text.len())].to_string();
                panic!(
                    "round {round}, thread {thread}: differs at byte {at}: {:?} instead of {:?}",
                    near(result),
                    near(&alone)
                );
            }
        }
    }
    println!(
        "{THREADS} threads x {ROUNDS} rounds: {} bytes of results each, all equal",
        alone.len()
    );
}

#[test]
fn const_crowd_calls_agree_across_threads() {
    // The street, recorded for 8 s and planned, then replayed for 4 s: every const call has
    // something to say (constraints included, and conversations: groups of 2, 3 and 4 from
    // the first frame on).
    let (characters, recorded_frames) = (130, 240);
    let mut street = Street::new(characters, 60, 7, (characters as u32 + 1) * recorded_frames);
    street.frame();
    let mut gaze = vec![cg_gaze_info::default(); characters];
    check(
        unsafe {
            cg_crowd_read_gaze(
                street.crowd.as_const(),
                gaze.as_mut_ptr(),
                characters,
                null_mut(),
            )
        },
        "cg_crowd_read_gaze",
    );
    let ids: Vec<u32> = gaze.iter().map(|info| info.character).collect();
    for members in [&ids[0..2], &ids[2..5], &ids[5..9]] {
        let mut group = 0;
        check(
            unsafe {
                cg_crowd_set_conversation(
                    street.crowd.as_mut(),
                    members.as_ptr(),
                    members.len(),
                    &mut group,
                )
            },
            "cg_crowd_set_conversation",
        );
    }
    for _ in 1..recorded_frames {
        street.frame();
    }
    check(
        unsafe { cg_crowd_plan(street.crowd.as_mut()) },
        "cg_crowd_plan",
    );
    for _ in 0..120 {
        check(
            unsafe { cg_crowd_step(street.crowd.as_mut(), Street::DT) },
            "cg_crowd_step",
        );
    }
    let text = crowd_transcript(street.crowd.as_const());
    assert!(text.contains("constraints: Ok") && !text.contains("NaN"));
    let mut group = CG_NO_TARGET;
    check(
        unsafe { cg_crowd_get_conversation(street.crowd.as_const(), ids[0], &mut group) },
        "cg_crowd_get_conversation",
    );
    assert_ne!(group, CG_NO_TARGET, "the first group still talks");
    same_on_every_thread(street.crowd.as_const(), crowd_transcript);
}

const JOINTS: usize = 5;
const KEYS: u32 = 3;

/// Everything the `const` calls say about `blender`: weights and poses for viewers around
/// a character, over two seconds of its looping clips.
fn blender_transcript(blender: *const cg_view_blender) -> String {
    let mut out = String::new();
    let character: cg_dualquat =
        DualQuat::from_rotation_translation(Quat::from_rotation_y(0.5), Vec3::new(2.0, 0.0, 5.0))
            .into();
    let mut weights = [0.0f32; KEYS as usize];
    let mut pose = [cg_dualquat::from(DualQuat::IDENTITY); JOINTS];
    let mut viewer = cg_vec3::default();
    for step in 0..48 {
        let angle = step as f32 * 0.13;
        viewer = cg_vec3 {
            x: 2.0 + 3.0 * angle.sin(),
            y: 1.6,
            z: 5.0 + 3.0 * angle.cos(),
        };
        let s = unsafe {
            cg_view_blender_weights(blender, &character, &viewer, weights.as_mut_ptr(), 3)
        };
        status(&mut out, "weights", s);
        let t = f64::from(step) / 24.0;
        let s = unsafe {
            cg_view_blender_evaluate(blender, &character, &viewer, t, pose.as_mut_ptr(), JOINTS)
        };
        status(&mut out, "evaluate", s);
        writeln!(out, "{weights:?} {pose:?}").unwrap();
    }
    let s = unsafe {
        cg_view_blender_evaluate(blender, &character, &viewer, 0.0, pose.as_mut_ptr(), 2)
    };
    status(&mut out, "evaluate with a wrong joint count", s);
    out
}

#[test]
fn const_view_blender_calls_agree_across_threads() {
    for method in [cg_blend_method::Dlb, cg_blend_method::Dib] {
        let mut config: cg_view_blender_config = init(cg_view_blender_config_init);
        config.joint_count = JOINTS as u32;
        config.key_count = KEYS;
        config.method = method as u32;
        let mut blender = null_mut();
        check(
            unsafe { cg_view_blender_create(&config, &mut blender) },
            "create",
        );
        for key in 0..KEYS {
            // Key k turns the body towards its side and nods, over 12 frames at 10 fps.
            let side = 1.0 - key as f32;
            let frames: Vec<cg_dualquat> = (0..12)
                .flat_map(|f| {
                    let phase = f as f32 / 12.0 * std::f32::consts::TAU;
                    (0..JOINTS).map(move |j| {
                        let turn = Quat::from_rotation_y(side * 0.35 * (j + 1) as f32 / 3.0);
                        let nod = Quat::from_rotation_x(0.1 * (phase + j as f32).sin());
                        DualQuat::from_rotation_translation(turn * nod, Vec3::Y * 0.3).into()
                    })
                })
                .collect();
            check(
                unsafe {
                    cg_view_blender_set_key_clip(blender, key, frames.as_ptr(), 12, 10.0, true)
                },
                "set_key_clip",
            );
            let direction = cg_vec3 {
                x: side,
                y: 0.0,
                z: 1.0 - side.abs() * 0.5,
            };
            check(
                unsafe { cg_view_blender_add_camera(blender, direction, key) },
                "add_camera",
            );
        }
        same_on_every_thread(blender.cast_const(), blender_transcript);
        unsafe { cg_view_blender_destroy(blender) };
    }
}

/// Everything the `const` calls say about `rig`: its chain, counts, bones, roles and report,
/// and the base poses and joints written back over a few seconds of a swaying skeleton.
fn rig_transcript(rig: *const cg_rig) -> String {
    let mut out = String::new();
    let mut chain: cg_chain_desc = unsafe { std::mem::zeroed() };
    chain.struct_size = std::mem::size_of::<cg_chain_desc>() as u32;
    status(&mut out, "chain", unsafe { cg_rig_chain(rig, &mut chain) });
    let (mut bones, mut joints) = (0u32, 0u32);
    status(&mut out, "bones", unsafe {
        cg_rig_bone_count(rig, &mut bones)
    });
    status(&mut out, "joints", unsafe {
        cg_rig_joint_count(rig, &mut joints)
    });
    let mut list = [0u32; 65];
    status(&mut out, "chain bones", unsafe {
        cg_rig_chain_bones(rig, list.as_mut_ptr(), 65)
    });
    writeln!(out, "{chain:?} {bones} {joints} {list:?}").unwrap();
    status(&mut out, "roles", unsafe {
        cg_rig_bone_roles(rig, list.as_mut_ptr(), 65)
    });
    let mut report = [0 as std::ffi::c_char; 4096];
    let length = unsafe { cg_rig_report(rig, report.as_mut_ptr(), report.len()) };
    writeln!(out, "{list:?} {length} {:?}", &report[..length]).unwrap();
    let skeleton = support::rig::Skeleton::mixamo();
    for step in 0..24 {
        let mut posed = skeleton.animated(step as f32 * 0.2);
        let mut base = [cg_quat::IDENTITY; 7];
        status(&mut out, "base pose", unsafe {
            cg_rig_base_pose(rig, posed.as_ptr(), 65, base.as_mut_ptr(), 7)
        });
        let turned =
            base.map(|q| (Quat::from_xyzw(q.x, q.y, q.z, q.w) * Quat::from_rotation_y(0.2)).into());
        status(&mut out, "write joints", unsafe {
            cg_rig_write_joints(rig, turned.as_ptr(), 7, posed.as_mut_ptr(), 65)
        });
        writeln!(out, "{base:?} {posed:?}").unwrap();
    }
    let mut posed = skeleton.animated(0.0);
    status(&mut out, "write joints with a wrong joint count", unsafe {
        cg_rig_write_joints(
            rig,
            [cg_quat::IDENTITY; 6].as_ptr(),
            6,
            posed.as_mut_ptr(),
            65,
        )
    });
    out
}

#[test]
fn const_rig_calls_agree_across_threads() {
    let skeleton = support::rig::Skeleton::mixamo();
    let rig = skeleton.rig(100.0);
    same_on_every_thread(rig.0.cast_const(), rig_transcript);
}

/// The header functions whose first parameter is a `const` crowd, blender or rig handle,
/// each with its doc comment.
fn header_const_functions() -> Vec<(String, String)> {
    let header = include_str!("../include/crowdgaze.h");
    let lines: Vec<&str> = header.lines().collect();
    let mut found = Vec::new();
    for (index, line) in lines.iter().enumerate() {
        let Some((_, rest)) = line.split_once(" cg_") else {
            continue;
        };
        let Some((name, parameters)) = rest.split_once('(') else {
            continue;
        };
        let is_const_handle = parameters.starts_with("const struct cg_crowd *")
            || parameters.starts_with("const struct cg_view_blender *")
            || parameters.starts_with("const struct cg_rig *");
        if line.starts_with("//") || !is_const_handle {
            continue;
        }
        let doc: Vec<&str> = lines[..index]
            .iter()
            .rev()
            .take_while(|l| l.starts_with("//"))
            .map(|l| l.trim_start_matches("//").trim())
            .collect();
        let doc = doc.into_iter().rev().collect::<Vec<_>>().join(" ");
        found.push((format!("cg_{name}"), doc));
    }
    found
}

#[test]
fn const_functions_are_all_covered_and_documented_as_concurrent() {
    let functions = header_const_functions();
    let names: BTreeSet<&str> = functions.iter().map(|(name, _)| name.as_str()).collect();
    assert_eq!(names, COVERED.into_iter().collect::<BTreeSet<_>>());
    for (name, doc) in &functions {
        assert!(
            doc.contains("concurrently with other"),
            "{name}: its doc does not say it may run concurrently with other const calls"
        );
    }
}

// The Rust types behind the handles are `Sync`, checked at compile time: a shared reference
// cannot race (no `Cell`, no unsynchronised cache), which is what lets the const calls overlap.
const _: fn() = || {
    fn sync<T: Sync>() {}
    sync::<crowdgaze::Crowd>();
    sync::<crowdgaze::ViewBlender>();
    sync::<crowdgaze::skeleton_map::MappedChain>();
};
