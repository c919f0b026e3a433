//! Interprets bytes as a sequence of C API calls on one crowd, one view blender and a rig, and
//! checks every call against the header's documentation.
//!
//! Encoding: the input is a list of operations `[op, n, n argument bytes]` (the arguments
//! end early with the input). `op % 64` picks an entry of [`ops::OPS`]; values past the
//! table are no-ops, so appending operations keeps every committed seed's meaning. The
//! argument bytes choose ids (live, removed, the viewer, random), floats (ordinary ones,
//! NaN, infinities, extremes, subnormals), counts, NULL or valid pointers and
//! `struct_size` variants; a zero byte is always the ordinary choice.
//!
//! After every call: its status must be one the header documents for it
//! ([`statuses`]; `CG_STATUS_INTERNAL` never), the outputs it wrote on success must be
//! finite, and a failed call must leave its outputs untouched. After every operation that
//! used them, the crowd's gaze, joints, joint deltas and eyes and the blender's weights and
//! pose are read back: all finite, the weights convex, and identical to before if the
//! operation's calls all failed. Any violation panics, which is how libFuzzer reports.

// The `unsafe { cg_... }` calls below pass pointers to live values of the sizes the header
// asks for, or deliberately bad ones (NULL, misaligned, wrong struct_size) that the library
// must refuse: that is their safety comment, once for the file.
#![allow(clippy::undocumented_unsafe_blocks)]

mod blend_ops;
mod crowd_ops;
mod input;
mod ops;
mod outputs;
mod rig_ops;
mod statuses;
mod values;

use crowdgaze::ffi::attention::{cg_crowd_read_gaze, cg_gaze_info};
use crowdgaze::ffi::crowd::{cg_crowd, cg_crowd_config, cg_crowd_destroy};
use crowdgaze::ffi::eyelids::{cg_crowd_read_eyelids, cg_eyelids};
use crowdgaze::ffi::following::cg_crowd_read_following;
use crowdgaze::ffi::gaze::{
    cg_crowd_joint_total, cg_crowd_read_eyes, cg_crowd_read_joint_deltas, cg_crowd_read_joints,
    cg_eye_info,
};
use crowdgaze::ffi::status::cg_status;
use crowdgaze::ffi::types::{cg_dualquat, cg_quat, cg_vec3};
use crowdgaze::ffi::view_blender::{
    cg_view_blender, cg_view_blender_destroy, cg_view_blender_evaluate, cg_view_blender_weights,
};
use input::Input;
use outputs::{bytes, non_finite, sentinel, sized_untouched, untouched, Output};
use std::ptr::null_mut;

/// Runs the calls `data` encodes on a fresh crowd and blender.
pub fn run(data: &[u8]) {
    let mut state = State::new();
    let mut before = [state.observe_crowd(), state.observe_blender()];
    let mut at = 0;
    while at < data.len() {
        let op = usize::from(data[at]) % 64;
        let length = usize::from(data.get(at + 1).copied().unwrap_or(0));
        let arguments = &data[(at + 2).min(data.len())..(at + 2 + length).min(data.len())];
        at += 2 + length;
        let Some(&(name, run_op)) = ops::OPS.get(op) else {
            continue;
        };
        state.operation = name;
        state.changed = false;
        state.touched.set([false; 2]);
        if trace() {
            eprintln!("{name} {arguments:?}");
        }
        run_op(&mut state, &mut Input::new(arguments));
        // Read back what the operation may have changed (both, if it made a new crowd or
        // blender: they share no state, but the check is cheap).
        let touched = state.touched.get();
        for (part, seen) in before.iter_mut().enumerate() {
            if !touched[part] {
                continue;
            }
            let after = match part {
                CROWD => state.observe_crowd(),
                _ => state.observe_blender(),
            };
            assert!(
                state.changed || after == *seen,
                "{name}: failed calls changed what the {} reads back",
                ["crowd", "blender"][part]
            );
            *seen = after;
        }
    }
}

/// Indices of [`State::touched`].
const CROWD: usize = 0;
const BLENDER: usize = 1;

/// Whether `CG_FUZZ_TRACE` is set: print each operation and its argument bytes.
fn trace() -> bool {
    static TRACE: std::sync::OnceLock<bool> = std::sync::OnceLock::new();
    *TRACE.get_or_init(|| std::env::var_os("CG_FUZZ_TRACE").is_some())
}

/// The objects under test and what the interpreter knows about them.
pub struct State {
    crowd: *mut cg_crowd,
    /// The config `crowd` was created with.
    config: cg_crowd_config,
    blender: *mut cg_view_blender,
    /// The blender's joints per pose and key animations.
    blend_joints: usize,
    blend_keys: usize,
    /// Ids returned by the crowd and not removed, and removed ones.
    live: Vec<u32>,
    removed: Vec<u32>,
    viewer: Option<u32>,
    /// The rig of the last successful `cg_rig_create` (NULL before), its bones and joints.
    rig: *mut crowdgaze::ffi::rig::cg_rig,
    rig_bones: usize,
    rig_joints: usize,
    /// Ids of the conversations the crowd returned, live or ended.
    conversations: Vec<u32>,
    /// Time of the last frame pushed successfully.
    time: f64,
    /// The operation running, for messages.
    operation: &'static str,
    /// Whether a call that may change the crowd or the blender succeeded.
    changed: bool,
    /// Whether the operation used the crowd, the blender (indexed by `CROWD`, `BLENDER`).
    touched: std::cell::Cell<[bool; 2]>,
}

impl Drop for State {
    fn drop(&mut self) {
        unsafe { cg_crowd_destroy(self.crowd) };
        unsafe { cg_view_blender_destroy(self.blender) };
        unsafe { crowdgaze::ffi::rig::cg_rig_destroy(self.rig) };
    }
}

impl State {
    /// Checks that `function` may return `status`, and returns it.
    fn call(&self, function: &str, status: cg_status) -> cg_status {
        let table = statuses::table();
        if !table.allows(function, status as u32) {
            panic!(
                "{} (in {}) returned {status:?}, not documented (allowed: {:?}): {}",
                function,
                self.operation,
                table.describe(function),
                crowdgaze::ffi::last_error::last_error_message()
            );
        }
        status
    }

    /// As [`State::call`], for a call that changes the crowd or the blender on success.
    fn change(&mut self, function: &str, status: cg_status) -> cg_status {
        self.touch(if function.starts_with("cg_view_blender") {
            BLENDER
        } else {
            CROWD
        });
        let status = self.call(function, status);
        self.changed |= succeeded(status);
        if trace() {
            let message = match succeeded(status) {
                true => String::new(),
                false => crowdgaze::ffi::last_error::last_error_message(),
            };
            eprintln!("  {function}: {status:?} {message}");
        }
        status
    }

    /// Checks the outputs of a call: `written` values finite after a success, nothing
    /// written after a failure.
    fn outputs<T: Output + std::fmt::Debug>(
        &self,
        function: &str,
        status: cg_status,
        out: &[T],
        written: usize,
    ) {
        if succeeded(status) {
            if let Some(bad) = non_finite(&out[..written.min(out.len())]) {
                panic!(
                    "{function} (in {}) wrote a non-finite value: {bad}",
                    self.operation
                );
            }
        } else {
            assert!(
                untouched(out),
                "{function} (in {}) failed with {status:?} but wrote its output",
                self.operation
            );
        }
    }

    /// [`outputs`](Self::outputs) of one versioned struct made by
    /// [`outputs::sized_sentinel`]: a failed call must leave it as it was, `struct_size`
    /// included.
    fn versioned_output<T: Output + std::fmt::Debug>(
        &self,
        function: &str,
        status: cg_status,
        out: &[T],
    ) {
        if succeeded(status) {
            self.outputs(function, status, out, 1);
        } else {
            assert!(
                sized_untouched(out),
                "{function} (in {}) failed with {status:?} but wrote its output",
                self.operation
            );
        }
    }

    /// Records that the operation used the crowd (`CROWD`) or the blender (`BLENDER`).
    fn touch(&self, part: usize) {
        let mut touched = self.touched.get();
        touched[part] = true;
        self.touched.set(touched);
    }

    /// Reads back everything the crowd shows (gaze, joints, joint deltas, eyes), checks it
    /// is finite, and returns its bytes.
    fn observe_crowd(&self) -> Vec<u8> {
        let mut seen = Vec::new();
        {
            let mut gaze = sentinel::<cg_gaze_info>(self.config.max_characters as usize);
            let mut written = 0;
            let status = unsafe {
                cg_crowd_read_gaze(self.crowd, gaze.as_mut_ptr(), gaze.len(), &mut written)
            };
            assert_eq!(self.call("cg_crowd_read_gaze", status), cg_status::Ok);
            self.outputs("cg_crowd_read_gaze", status, &gaze, written);
            seen.extend_from_slice(bytes(&gaze[..written]));
            let characters = written as u32;
            let mut total = 0;
            let status = unsafe { cg_crowd_joint_total(self.crowd, 0, characters, &mut total) };
            assert_eq!(self.call("cg_crowd_joint_total", status), cg_status::Ok);
            for (function, read) in [
                ("cg_crowd_read_joints", cg_crowd_read_joints as ReadJoints),
                ("cg_crowd_read_joint_deltas", cg_crowd_read_joint_deltas),
            ] {
                let mut joints = sentinel::<cg_quat>(total);
                let status = unsafe { read(self.crowd, 0, characters, joints.as_mut_ptr(), total) };
                assert_eq!(self.call(function, status), cg_status::Ok);
                self.outputs(function, status, &joints, total);
                seen.extend_from_slice(bytes(&joints));
            }
            let mut eyes = sentinel::<cg_eye_info>(written);
            let status = unsafe {
                cg_crowd_read_eyes(self.crowd, 0, characters, eyes.as_mut_ptr(), written)
            };
            assert_eq!(self.call("cg_crowd_read_eyes", status), cg_status::Ok);
            self.outputs("cg_crowd_read_eyes", status, &eyes, written);
            seen.extend_from_slice(bytes(&eyes));
            let mut eyelids = sentinel::<cg_eyelids>(written);
            let status = unsafe {
                cg_crowd_read_eyelids(self.crowd, 0, characters, eyelids.as_mut_ptr(), written)
            };
            assert_eq!(self.call("cg_crowd_read_eyelids", status), cg_status::Ok);
            self.outputs("cg_crowd_read_eyelids", status, &eyelids, written);
            seen.extend_from_slice(bytes(&eyelids));
            for info in &gaze[..written] {
                let mut point = sentinel::<cg_vec3>(1);
                let mut flags = sentinel::<u32>(2);
                let status = unsafe {
                    let (following, glances) = (flags.as_mut_ptr(), flags.as_mut_ptr().add(1));
                    cg_crowd_read_following(
                        self.crowd,
                        info.character,
                        point.as_mut_ptr(),
                        following,
                        glances,
                    )
                };
                assert_eq!(self.call("cg_crowd_read_following", status), cg_status::Ok);
                self.outputs("cg_crowd_read_following", status, &point, 1);
                assert!(flags[0] <= 1, "following is {}", flags[0]);
                seen.extend_from_slice(bytes(&point));
                seen.extend_from_slice(bytes(&flags));
            }
        }
        seen
    }

    /// Reads back the blender's weights and pose for a fixed view, checks they are finite
    /// and the weights convex, and returns their bytes and statuses.
    fn observe_blender(&self) -> Vec<u8> {
        let mut seen = Vec::new();
        {
            let character = rigid(
                0.3,
                cg_vec3 {
                    x: 1.0,
                    y: 0.0,
                    z: -2.0,
                },
            );
            let viewer = cg_vec3 {
                x: 2.0,
                y: 1.5,
                z: 4.0,
            };
            let mut weights = sentinel::<f32>(self.blend_keys);
            let status = unsafe {
                cg_view_blender_weights(
                    self.blender,
                    &character,
                    &viewer,
                    weights.as_mut_ptr(),
                    weights.len(),
                )
            };
            self.call("cg_view_blender_weights", status);
            self.outputs("cg_view_blender_weights", status, &weights, weights.len());
            if succeeded(status) {
                let sum: f32 = weights.iter().sum();
                assert!(
                    weights.iter().all(|w| (0.0..=1.0).contains(w)) && (sum - 1.0).abs() < 1e-4,
                    "cg_view_blender_weights (after {}): not convex: {weights:?}",
                    self.operation
                );
            }
            seen.extend((status as u32).to_le_bytes());
            seen.extend_from_slice(bytes(&weights));
            let mut pose = sentinel::<cg_dualquat>(self.blend_joints);
            let status = unsafe {
                cg_view_blender_evaluate(
                    self.blender,
                    &character,
                    &viewer,
                    0.4,
                    pose.as_mut_ptr(),
                    pose.len(),
                )
            };
            self.call("cg_view_blender_evaluate", status);
            self.outputs("cg_view_blender_evaluate", status, &pose, pose.len());
            seen.extend((status as u32).to_le_bytes());
            seen.extend_from_slice(bytes(&pose));
        }
        seen
    }

    /// An id to pass: mostly a live one, sometimes a removed one, the viewer's,
    /// `CG_NO_TARGET` or any value.
    fn id(&self, input: &mut Input) -> u32 {
        let pick = |ids: &[u32], input: &mut Input| match ids.len() {
            0 => None,
            n => Some(ids[input.below(256) as usize % n]),
        };
        let id = match input.below(16) {
            12 => pick(&self.removed, input),
            13 => self.viewer,
            14 => Some(u32::MAX),
            15 => Some(input.u32()),
            _ => pick(&self.live, input),
        };
        id.unwrap_or(0)
    }

    /// A conversation id to pass: mostly one the crowd returned (live or ended; 0 if none),
    /// sometimes `CG_NO_TARGET`, one past the last returned, or any value.
    fn conversation(&self, input: &mut Input) -> u32 {
        let last = self.conversations.last().copied().unwrap_or(0);
        match input.below(16) {
            13 => u32::MAX,
            14 => last.wrapping_add(1),
            15 => input.u32(),
            _ => match self.conversations.len() {
                0 => 0,
                n => self.conversations[input.below(256) as usize % n],
            },
        }
    }

    /// The crowd handle, rarely NULL.
    fn crowd(&self, input: &mut Input) -> *mut cg_crowd {
        self.touch(CROWD);
        or_null(self.crowd, input)
    }

    /// The blender handle, rarely NULL.
    fn blender(&self, input: &mut Input) -> *mut cg_view_blender {
        self.touch(BLENDER);
        or_null(self.blender, input)
    }
}

type ReadJoints = unsafe extern "C" fn(*const cg_crowd, u32, u32, *mut cg_quat, usize) -> cg_status;

/// Whether a status means the call did its work (and wrote its outputs).
fn succeeded(status: cg_status) -> bool {
    matches!(status, cg_status::Ok | cg_status::NotConverged)
}

/// `pointer`, or NULL when the input asks for it.
fn or_null<T>(pointer: *mut T, input: &mut Input) -> *mut T {
    if input.rare() {
        null_mut()
    } else {
        pointer
    }
}

/// A pointer to `value`, or NULL when the input asks for it.
fn pointer_to<T>(value: &T, input: &mut Input) -> *const T {
    if input.rare() {
        std::ptr::null()
    } else {
        value
    }
}

/// A pointer to the first of `values` (dangling if empty), or NULL when the input asks.
fn array_pointer<T>(values: &[T], input: &mut Input) -> *const T {
    if input.rare() {
        std::ptr::null()
    } else {
        values.as_ptr()
    }
}

/// The unit dual quaternion of a rotation by `angle` about the vertical, then a
/// translation `t`. Written out rather than through `cg_dualquat_from_rt`, which refuses
/// the NaN, infinite and huge values the fuzzer feeds in here on purpose.
fn rigid(angle: f32, t: cg_vec3) -> cg_dualquat {
    let (s, c) = (angle / 2.0).sin_cos();
    let real = cg_quat {
        x: 0.0,
        y: s,
        z: 0.0,
        w: c,
    };
    // dual = ½ (t, 0) ⊗ real
    let dual = cg_quat {
        x: 0.5 * (t.x * real.w + t.y * real.z - t.z * real.y),
        y: 0.5 * (t.y * real.w + t.z * real.x - t.x * real.z),
        z: 0.5 * (t.z * real.w + t.x * real.y - t.y * real.x),
        w: -0.5 * (t.x * real.x + t.y * real.y + t.z * real.z),
    };
    cg_dualquat { real, dual }
}

impl State {
    /// A state with the crowd and the blender every run starts from.
    fn new() -> State {
        let mut state = State {
            crowd: null_mut(),
            // Replaced by `first_crowd`.
            config: outputs::sentinel::<cg_crowd_config>(1)[0],
            blender: null_mut(),
            blend_joints: 0,
            blend_keys: 0,
            live: Vec::new(),
            removed: Vec::new(),
            viewer: None,
            rig: null_mut(),
            rig_bones: 0,
            rig_joints: 0,
            conversations: Vec::new(),
            time: 0.0,
            operation: "start",
            changed: false,
            touched: std::cell::Cell::new([false; 2]),
        };
        crowd_ops::first_crowd(&mut state);
        blend_ops::first_blender(&mut state);
        state
    }
}
