//! Godot 3's values to and from the adapter's, and the boundary every exported method runs
//! inside: a panic is caught there and reported as a Godot error, never unwound into the
//! engine.

use std::panic::{catch_unwind, AssertUnwindSafe};
use std::sync::OnceLock;
use std::thread::ThreadId;

use crowdgaze_godot_adapter::{Reports, Xform};
use gdnative::nativescript::init::property::hint::{EnumHint, FloatHint, IntHint, RangeHint};
use gdnative::nativescript::user_data::{DeadlockPolicy, LockOptions, MutexData};
use gdnative::prelude::*;

/// The lock policy of the addon's nodes' data: a call that finds it locked fails at once
/// (as gdnative's default `LocalCellData` does) instead of waiting.
#[derive(Debug, Clone, Copy, Default)]
pub struct NoWait;

impl LockOptions for NoWait {
    const DEADLOCK_POLICY: DeadlockPolicy = DeadlockPolicy::Pessimistic;
}

/// The addon's nodes' data: usable from any thread (a node instanced on a loader thread,
/// then added to the tree on the main thread), unlike gdnative's default, which refuses
/// every call from another thread than the one that made the node.
pub type Data<T> = MutexData<T, NoWait>;

/// The main thread: the one the first `CrowdGaze` entered the tree on.
static MAIN_THREAD: OnceLock<ThreadId> = OnceLock::new();

/// Records the calling thread as the main thread (a `CrowdGaze` entering the tree or
/// processing: Godot does both on the main thread only).
pub fn on_main_thread_now() {
    let _ = MAIN_THREAD.get_or_init(|| std::thread::current().id());
}

/// True on the main thread (or before any `CrowdGaze` entered the tree: there is nothing
/// to join yet then).
pub fn is_main_thread() -> bool {
    MAIN_THREAD
        .get()
        .is_none_or(|main| *main == std::thread::current().id())
}

/// Godot's `Transform` as the adapter's [`Xform`] (the same twelve floats).
pub fn xform(transform: &Transform) -> Xform {
    let row = |v: Vector3| [v.x, v.y, v.z];
    let rows = &transform.basis.elements;
    Xform::from_rows(
        [row(rows[0]), row(rows[1]), row(rows[2])],
        row(transform.origin),
    )
}

/// The adapter's [`Xform`] as Godot's `Transform`.
pub fn transform(xform: &Xform) -> Transform {
    let rows = xform.rows();
    let vector = |v: [f32; 3]| Vector3::new(v[0], v[1], v[2]);
    Transform {
        basis: Basis {
            elements: [vector(rows[0]), vector(rows[1]), vector(rows[2])],
        },
        origin: vector(xform.origin.to_array()),
    }
}

/// A glam vector as Godot's.
pub fn vector(v: glam::Vec3) -> Vector3 {
    Vector3::new(v.x, v.y, v.z)
}

/// Godot's vector as glam's.
pub fn vec3(v: Vector3) -> glam::Vec3 {
    glam::Vec3::new(v.x, v.y, v.z)
}

/// A glam quaternion as Godot's `Quat` (x, y, z, w).
pub fn quat(q: glam::Quat) -> Quat {
    Quat::quaternion(q.x, q.y, q.z, q.w)
}

/// True in the editor (the addon's classes are tool classes: the editor runs them for their
/// configuration warnings and mapping report, and nothing else).
pub fn in_editor() -> bool {
    gdnative::api::Engine::godot_singleton().is_editor_hint()
}

/// A script's number (an integer or a float) as a float; `None` for anything else.
pub fn number(value: &Variant) -> Option<f64> {
    match value.get_type() {
        VariantType::F64 => value.try_to_f64(),
        VariantType::I64 => value.try_to_i64().map(|v| v as f64),
        _ => None,
    }
}

/// A node's path for messages: its path in the tree, else its class and name (Godot prints
/// an error of its own when asked the path of a node out of the tree).
pub fn node_path(node: &Node) -> String {
    if node.is_inside_tree() {
        node.get_path().to_string()
    } else {
        format!("{} '{}' (not in the tree)", node.get_class(), node.name())
    }
}

/// True the first time `node`'s `method` reports `error` outside a crowd's own reports
/// (a wrong call from a script), false after: print it then.
pub fn first_report(node: i64, method: &str, error: &dyn std::fmt::Display) -> bool {
    static REPORTS: std::sync::Mutex<Option<Reports>> = std::sync::Mutex::new(None);
    let mut reports = REPORTS.lock().unwrap_or_else(|e| e.into_inner());
    reports
        .get_or_insert_with(Reports::new)
        .first(node, method, error)
}

/// The inspector's slider for a value from 0 to 1.
pub fn unit_hint() -> FloatHint<f64> {
    FloatHint::Range(RangeHint::new(0.0, 1.0).with_step(0.01))
}

/// The inspector's slider for seconds (0 up, more typed in).
pub fn seconds_hint() -> FloatHint<f64> {
    FloatHint::Range(RangeHint::new(0.0, 10.0).with_step(0.01).or_greater())
}

/// The inspector's slider for an attention fraction (-1: the crowd's draw).
pub fn fraction_hint() -> FloatHint<f64> {
    FloatHint::Range(RangeHint::new(-1.0, 1.0).with_step(0.01))
}

/// The inspector's list of attention models.
pub fn model_hint() -> IntHint<i64> {
    IntHint::Enum(EnumHint::new(vec![
        "Crowd".into(),
        "Saliency".into(),
        "Baseline".into(),
        "Street".into(),
    ]))
}

/// The inspector's list of gaze-following strengths.
pub fn strength_hint() -> IntHint<i64> {
    IntHint::Enum(EnumHint::new(vec!["Milgram".into(), "Gallup".into()]))
}

/// The inspector's slider for the neck and head's turn, degrees.
pub fn head_turn_hint() -> FloatHint<f64> {
    FloatHint::Range(RangeHint::new(0.0, 180.0).with_step(1.0))
}

/// The inspector's slider for an eye's turn, degrees.
pub fn eye_angle_hint() -> FloatHint<f64> {
    FloatHint::Range(RangeHint::new(0.0, 90.0).with_step(1.0))
}

/// The inspector's slider for a gaze-share angle, degrees.
pub fn share_angle_hint() -> FloatHint<f64> {
    FloatHint::Range(RangeHint::new(0.0, 180.0).with_step(1.0))
}

/// The inspector's slider for the head speed, degrees per second.
pub fn head_speed_hint() -> FloatHint<f64> {
    FloatHint::Range(RangeHint::new(1.0, 1440.0).with_step(1.0).or_greater())
}

/// Runs an exported method's body; a panic becomes one Godot error naming `what`, and the
/// method returns `fallback`.
pub fn boundary<T>(what: &str, fallback: T, body: impl FnOnce() -> T) -> T {
    match catch_unwind(AssertUnwindSafe(body)) {
        Ok(value) => value,
        Err(payload) => {
            let message = payload
                .downcast_ref::<&str>()
                .map(|s| s.to_string())
                .or_else(|| payload.downcast_ref::<String>().cloned())
                .unwrap_or_else(|| "a panic".into());
            godot_error!("crowdgaze: internal error in {what}: {message}");
            fallback
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn transforms_round_trip_exactly() {
        let t = Transform {
            basis: Basis {
                elements: [
                    Vector3::new(1.0, 2.0, 3.0),
                    Vector3::new(4.0, 5.0, 6.0),
                    Vector3::new(7.0, 8.0, 9.5),
                ],
            },
            origin: Vector3::new(-1.0, 0.5, 2.0),
        };
        let x = xform(&t);
        // Godot's X axis is the first column of the rows.
        assert_eq!(x.basis.x_axis, glam::Vec3::new(1.0, 4.0, 7.0));
        assert_eq!(transform(&x), t);
    }

    #[test]
    fn a_panic_is_caught() {
        assert_eq!(boundary("test", 7, || 3), 3);
    }
}
