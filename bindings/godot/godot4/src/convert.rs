//! Godot 4's values to and from the adapter's, and the boundary every entry point runs
//! inside: a panic is caught there and reported as a Godot error, never unwound into the
//! engine.

use std::panic::{catch_unwind, AssertUnwindSafe};

use crowdgaze_godot_adapter::Xform;
use godot::prelude::*;

/// Godot's `Transform3D` as the adapter's [`Xform`] (the same twelve floats).
pub fn xform(transform: &Transform3D) -> Xform {
    let row = |v: Vector3| [v.x, v.y, v.z];
    let rows = &transform.basis.rows;
    Xform::from_rows(
        [row(rows[0]), row(rows[1]), row(rows[2])],
        row(transform.origin),
    )
}

/// The adapter's [`Xform`] as Godot's `Transform3D`.
pub fn transform(xform: &Xform) -> Transform3D {
    let rows = xform.rows();
    let vector = |v: [f32; 3]| Vector3::new(v[0], v[1], v[2]);
    Transform3D::new(
        Basis::from_rows(vector(rows[0]), vector(rows[1]), vector(rows[2])),
        vector(xform.origin.to_array()),
    )
}

/// A glam vector as Godot's.
pub fn vector(v: glam::Vec3) -> Vector3 {
    Vector3::new(v.x, v.y, v.z)
}

/// Godot's vector as glam's.
pub fn vec3(v: Vector3) -> glam::Vec3 {
    glam::Vec3::new(v.x, v.y, v.z)
}

/// A glam quaternion as Godot's `Quaternion` (x, y, z, w).
pub fn quaternion(q: glam::Quat) -> Quaternion {
    Quaternion::new(q.x, q.y, q.z, q.w)
}

/// Lines of text as Godot's `PackedStringArray` (configuration warnings).
pub fn strings(lines: &[String]) -> PackedStringArray {
    lines
        .iter()
        .map(|line| GString::from(line.as_str()))
        .collect()
}

/// True in the editor (the addon's classes are tool classes: the editor runs them for their
/// configuration warnings and mapping report, and nothing else).
pub fn in_editor() -> bool {
    godot::classes::Engine::singleton().is_editor_hint()
}

/// Runs an entry point's body; a panic becomes one Godot error naming `what`, and the
/// entry point returns `fallback`.
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
