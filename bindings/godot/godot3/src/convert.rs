//! Godot 3's values to and from the adapter's, and the boundary every exported method runs
//! inside: a panic is caught there and reported as a Godot error, never unwound into the
//! engine.

use std::panic::{catch_unwind, AssertUnwindSafe};
use std::sync::OnceLock;
use std::thread::ThreadId;

use crowdgaze_godot_adapter::{message, Reports, Xform};
use gdnative::core_types::FromVariantError;
use gdnative::nativescript::init::property::hint::{EnumHint, FloatHint, IntHint, RangeHint};
use gdnative::nativescript::init::property::{Export, ExportInfo};
use gdnative::nativescript::init::ClassBuilder;
use gdnative::nativescript::user_data::{DeadlockPolicy, LockOptions, MutexData};
use gdnative::nativescript::NativeClass;
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

/// A node's path for messages, or its name while it is out of the tree (Godot reports an
/// error for the path of a node out of the tree).
pub fn node_name(node: &Node) -> String {
    if node.is_inside_tree() {
        node.get_path().to_string()
    } else {
        node.name().to_string()
    }
}

/// Reports once per node and cause that a property of `node` was given a value of the
/// wrong type (`error`, from [`add_checked`]); `method` is the class and `set`.
pub fn refuse_once(reports: &mut Reports, node: &Node, method: &str, error: &str) {
    if reports.first(node.get_instance_id(), "type", &error) {
        godot_error!(
            "{}",
            message(
                &node_name(node),
                method,
                &error,
                "the property keeps its value"
            )
        );
    }
}

/// A variant's type as GDScript names it (`null`, `int`, `float`, `String`, ...), for
/// messages.
pub fn type_name(value: &Variant) -> String {
    match value.get_type() {
        VariantType::Nil => "null".into(),
        VariantType::Bool => "a bool".into(),
        VariantType::I64 => "an int".into(),
        VariantType::F64 => "a float".into(),
        VariantType::GodotString => "a String".into(),
        VariantType::VariantArray => "an Array".into(),
        VariantType::Dictionary => "a Dictionary".into(),
        VariantType::Object => "an Object".into(),
        other => format!("a {other:?}"),
    }
}

/// A property's value as a script or the inspector sets it. gdnative refuses a value of
/// another type before the node sees it, with a message that names no node; registered as
/// `Given<T>`, a property takes any value, and the node reports one of the wrong type
/// itself (see [`add_checked`]). Exported as `T` (same type and hints in the inspector).
#[derive(Debug, Clone, PartialEq)]
pub struct Given<T> {
    /// The value, if it has the property's type.
    value: Option<T>,
    /// The type given instead, as GDScript names it.
    refused: String,
}

impl<T> Given<T> {
    /// A value of the property's type.
    pub fn new(value: T) -> Self {
        Given {
            value: Some(value),
            refused: String::new(),
        }
    }
}

impl<T: FromVariant> FromVariant for Given<T> {
    /// Takes a value of type `T`, and what GDScript converts to it on assignment: an int
    /// for a float, a String for a NodePath.
    fn from_variant(variant: &Variant) -> Result<Self, FromVariantError> {
        let converted = match variant.get_type() {
            VariantType::I64 => Some((variant.to_i64() as f64).to_variant()),
            VariantType::GodotString => {
                Some(NodePath::new(&variant.to_godot_string()).to_variant())
            }
            _ => None,
        };
        let value = T::from_variant(variant)
            .ok()
            .or_else(|| converted.and_then(|v| T::from_variant(&v).ok()));
        Ok(match value {
            Some(value) => Given::new(value),
            None => Given {
                value: None,
                refused: type_name(variant),
            },
        })
    }
}

impl<T: ToVariant> ToVariant for Given<T> {
    fn to_variant(&self) -> Variant {
        self.value
            .as_ref()
            .map_or_else(Variant::new, ToVariant::to_variant)
    }
}

impl<T: Export> Export for Given<T> {
    type Hint = T::Hint;

    fn export_info(hint: Option<Self::Hint>) -> ExportInfo {
        T::export_info(hint)
    }
}

/// A property of type `T` of a `Spatial`-based class `C`, to register with
/// [`add_checked`].
pub struct Checked<C, T: Export> {
    /// Its name.
    pub name: &'static str,
    /// Its type as a message says it (`a float`).
    pub expected: &'static str,
    /// Its default.
    pub default: T,
    /// The inspector's hint.
    pub hint: Option<T::Hint>,
    /// Reads it.
    pub get: fn(&C) -> T,
    /// Sets it (a value of type `T`).
    pub set: fn(&mut C, TRef<Spatial>, T),
    /// Reports a value of another type: `"<name> was given <type>: it must be <expected>"`.
    pub refuse: fn(&mut C, TRef<Spatial>, &str),
}

/// Registers `property`: a value of its type goes to its `set`, one of any other type to its
/// `refuse`, instead of gdnative's own message.
pub fn add_checked<C, T>(builder: &ClassBuilder<C>, property: Checked<C, T>)
where
    C: NativeClass<Base = Spatial>,
    C::UserData: gdnative::nativescript::Map + gdnative::nativescript::MapMut,
    T: Export + FromVariant + 'static,
{
    let Checked {
        name,
        expected,
        default,
        hint,
        get,
        set,
        refuse,
    } = property;
    let builder = builder
        .add_property::<Given<T>>(name)
        .with_default(Given::new(default))
        .with_getter(move |this: &C, _owner: TRef<Spatial>| Given::new(get(this)))
        .with_setter(move |this: &mut C, owner: TRef<Spatial>, given: Given<T>| {
            boundary("property setter", (), || match given.value {
                Some(value) => set(this, owner, value),
                None => refuse(
                    this,
                    owner,
                    &format!("{name} was given {}: it must be {expected}", given.refused),
                ),
            })
        });
    match hint {
        Some(hint) => builder.with_hint(hint).done(),
        None => builder.done(),
    }
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
    ]))
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
