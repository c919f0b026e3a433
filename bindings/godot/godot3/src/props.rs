//! The nodes' exported properties as scripts set them, with the value's type checked by the
//! addon: gdnative refuses a value of the wrong type itself with "Incorrect type passed to
//! property", naming no node or property; through [`checked_property!`](crate::checked_property)
//! the addon takes any value ([`Given`]), and reports a refused one with its own message
//! (`crowdgaze: <node>: CrowdGaze.seed: a String is not an int; the value is kept`) once per
//! node, property and cause.
//!
//! To add a property to a node: declare the field without `#[property]` and add one
//! `checked_property!` line to the node's `register` function (a `#[property]` still works,
//! with gdnative's unchecked type).

use crowdgaze_godot_adapter::message;
use gdnative::nativescript::init::property::{Export, ExportInfo};
use gdnative::prelude::*;

use crate::convert::{first_report, node_path};

/// A property's value as a script gave it: the value, or the type of a value refused.
#[derive(Debug)]
pub struct Given<T>(pub Result<T, VariantType>);

impl<T: FromVariant> FromVariant for Given<T> {
    /// Never fails: a value of another type is kept as its type, for the message. An int
    /// is taken for a float property, a float holding a whole number for an int one (a
    /// script's `impact = 2`), and a String for a NodePath.
    fn from_variant(variant: &Variant) -> Result<Self, FromVariantError> {
        let number = match variant.get_type() {
            VariantType::I64 => variant.try_to_i64().map(|v| Variant::from_f64(v as f64)),
            VariantType::F64 => variant
                .try_to_f64()
                .filter(|v| v.fract() == 0.0 && v.abs() < 9.0e15)
                .map(|v| Variant::from_i64(v as i64)),
            // GDScript turns a String into a NodePath on assignment.
            VariantType::GodotString => {
                Some(NodePath::new(&variant.to_godot_string()).to_variant())
            }
            _ => None,
        };
        let value = T::from_variant(variant)
            .or_else(|error| number.map_or(Err(error), |number| T::from_variant(&number)));
        Ok(Given(value.map_err(|_| variant.get_type())))
    }
}

impl<T: ToVariant> ToVariant for Given<T> {
    fn to_variant(&self) -> Variant {
        match &self.0 {
            Ok(value) => value.to_variant(),
            Err(_) => Variant::new(),
        }
    }
}

impl<T: Export> Export for Given<T> {
    type Hint = T::Hint;

    /// The inspector sees `T`'s type and hint.
    fn export_info(hint: Option<Self::Hint>) -> ExportInfo {
        T::export_info(hint)
    }
}

/// A property's value handed out by its getter (a copy, or a new reference).
pub trait Share {
    /// The value, for the getter.
    fn share(&self) -> Self;
}

/// [`Share`] for the copyable property types.
macro_rules! share_copy {
    ($($t:ty),*) => {$(
        impl Share for $t {
            fn share(&self) -> Self {
                *self
            }
        }
    )*};
}
share_copy!(i64, f64, bool);

impl Share for GodotString {
    fn share(&self) -> Self {
        self.new_ref()
    }
}

impl Share for NodePath {
    fn share(&self) -> Self {
        self.new_ref()
    }
}

/// Godot's name of a variant type, for messages.
pub fn type_name(kind: VariantType) -> String {
    match kind {
        VariantType::Nil => "null".into(),
        VariantType::Bool => "bool".into(),
        VariantType::I64 => "int".into(),
        VariantType::F64 => "float".into(),
        VariantType::GodotString => "String".into(),
        VariantType::VariantArray => "Array".into(),
        VariantType::Dictionary => "Dictionary".into(),
        VariantType::Object => "Object".into(),
        other => format!("{other:?}"),
    }
}

/// Godot's name of a property's Rust type (as written in [`checked_property!`](crate::checked_property!)).
pub fn rust_type_name(rust: &str) -> &str {
    match rust {
        "i64" => "int",
        "f64" => "float",
        "GodotString" => "String",
        other => other,
    }
}

/// A value's type with its article, for messages: "an int", "a String", "null".
pub fn a_type(value: &Variant) -> String {
    with_article(&type_name(value.get_type()))
}

/// "an int", "a String", "null".
fn with_article(name: &str) -> String {
    match name.chars().next() {
        _ if name == "null" => name.to_string(),
        Some('a' | 'e' | 'i' | 'o' | 'u' | 'A' | 'E' | 'I' | 'O' | 'U') => format!("an {name}"),
        _ => format!("a {name}"),
    }
}

/// Reports a value of type `given` refused for property `property` (of Rust type `rust`,
/// or as `expected` says if it has one: `a float from 0 to 1`) of `owner`'s `class`,
/// once per node, property and cause.
pub fn refused(
    owner: &Node,
    class: &str,
    property: &str,
    (rust, expected): (&str, &[&str]),
    given: VariantType,
) {
    let method = format!("{class}.{property}");
    let expected = match expected.first() {
        Some(expected) => expected.to_string(),
        None => with_article(rust_type_name(rust)),
    };
    let error = format!("{} is not {expected}", with_article(&type_name(given)));
    if first_report(owner.get_instance_id(), &method, &error) {
        godot_error!(
            "{}",
            message(&node_path(owner), &method, &error, "the value is kept")
        );
    }
}

/// Registers a property of a class with the type of a script's value checked by the addon
/// (see the [module](crate::props)): `checked_property!(builder, Class, field: Type = default,
/// hint h, expects "a float from 0 to 1", then Self::after_set)`, the field named as the
/// property; `= default`, `hint` (the inspector's), `expects` (what a message says the value
/// must be, else its type) and `then` are optional. The field carries no `#[property]`
/// (which would register it again unchecked).
#[macro_export]
macro_rules! checked_property {
    ($builder:expr, $class:ty, $name:ident: $t:ty $(= $default:expr)? $(, hint $hint:expr)?
        $(, expects $expected:literal)? $(, then $after:path)?) => {
        $builder
            .add_property::<$crate::props::Given<$t>>(stringify!($name))
            $(.with_default($crate::props::Given(Ok($default))))?
            $(.with_hint($hint))?
            .with_getter(|this: &$class, _owner| {
                $crate::props::Given(Ok($crate::props::Share::share(&this.$name)))
            })
            .with_setter(|this: &mut $class, owner, value: $crate::props::Given<$t>| {
                match value.0 {
                    Ok(value) => {
                        this.$name = value;
                        $($after(this, owner);)?
                    }
                    Err(given) => $crate::props::refused(
                        &owner,
                        stringify!($class),
                        stringify!($name),
                        (stringify!($t), &[$($expected)?]),
                        given,
                    ),
                }
            })
            .done()
    };
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn types_have_godot_names() {
        assert_eq!(type_name(VariantType::GodotString), "String");
        assert_eq!(type_name(VariantType::Nil), "null");
        assert_eq!(type_name(VariantType::Vector3), "Vector3");
        assert_eq!(rust_type_name("i64"), "int");
        assert_eq!(rust_type_name("NodePath"), "NodePath");
        assert_eq!(with_article("int"), "an int");
        assert_eq!(with_article("String"), "a String");
        assert_eq!(with_article("null"), "null");
    }
}
