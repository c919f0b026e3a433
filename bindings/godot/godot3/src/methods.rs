//! The nodes' methods as scripts call them, with the number of arguments checked by the
//! addon first: gdnative's own check prints "Incorrect number of parameters" naming no node
//! or method; this one prints the addon's message (`crowdgaze: <node>: <Class.method>: too
//! many arguments: ...`) once per node, method and cause, and the call returns null.
//!
//! [`checked_method!`](crate::checked_method) registers one method: gdnative's own wrapper
//! ([`godot_wrap_method!`](gdnative::godot_wrap_method)) does the conversions and the call,
//! behind `call_checked`, which checks the count.
//!
//! To add a method to a node: write it in the node's `#[methods]` block without `#[export]`
//! and add one `checked_method!` line to the node's `register` function (an `#[export]`
//! still works, with gdnative's unchecked count).

use std::ffi::c_void;

use crowdgaze_godot_adapter::message;
use gdnative::nativescript::init::{
    ClassBuilder, RpcMode, ScriptMethod, ScriptMethodAttributes, ScriptMethodFn,
};
use gdnative::nativescript::NativeClass;
use gdnative::prelude::*;

use crate::convert::{boundary, first_report, node_path};

/// A method registered through [`call_checked`]: who it is, the arguments it takes, and
/// gdnative's wrapper that converts them and calls it.
struct Checked {
    /// `Class.method`, for messages.
    name: String,
    /// Its arguments' names, in order.
    params: &'static [&'static str],
    /// gdnative's wrapper of the Rust method.
    inner: ScriptMethodFn,
}

/// Registers `method` of `C` under `name`, taking the arguments `params`: a call with
/// another number of arguments is reported and does nothing. `inner` is gdnative's
/// wrapper of the method (see [`checked_method!`](crate::checked_method)).
pub fn add_checked<C: NativeClass>(
    builder: &ClassBuilder<C>,
    name: &str,
    params: &'static [&'static str],
    inner: ScriptMethodFn,
) {
    let checked = Box::new(Checked {
        name: format!("{}.{name}", C::class_name()),
        params,
        inner,
    });
    builder.add_method_advanced(ScriptMethod {
        name,
        method_ptr: Some(call_checked),
        attributes: ScriptMethodAttributes {
            rpc_mode: RpcMode::Disabled,
        },
        method_data: Box::into_raw(checked).cast::<c_void>(),
        free_func: Some(free_checked),
    });
}

/// The message for `given` arguments to a method taking `params`, `None` if that is right.
pub fn count_error(params: &[&str], given: usize) -> Option<String> {
    let expected = params.len();
    if given == expected {
        return None;
    }
    let takes = match expected {
        0 => "takes no argument".to_string(),
        1 => format!("takes 1 argument ({})", params[0]),
        n => format!("takes {n} arguments ({})", params.join(", ")),
    };
    let how = if given < expected {
        "too few"
    } else {
        "too many"
    };
    Some(format!(
        "{how} arguments: it {takes}, the call gave {given}"
    ))
}

/// Godot's entry to a checked method: checks the argument count, then calls gdnative's
/// wrapper (which checks the types).
///
/// # Safety
///
/// Called by Godot only, with the `method_data` [`add_checked`] registered, the script
/// instance's `user_data`, and `num_args` arguments at `args`.
unsafe extern "C" fn call_checked(
    this: *mut gdnative::sys::godot_object,
    method_data: *mut c_void,
    user_data: *mut c_void,
    num_args: std::os::raw::c_int,
    args: *mut *mut gdnative::sys::godot_variant,
) -> gdnative::sys::godot_variant {
    // SAFETY: `method_data` is the `Checked` leaked by `add_checked`, freed only by
    // `free_checked` when the class is unregistered.
    let Some(checked) = (unsafe { method_data.cast::<Checked>().as_ref() }) else {
        return Variant::new().forget();
    };
    let given = usize::try_from(num_args).unwrap_or(0);
    if let Some(error) = count_error(checked.params, given) {
        boundary(&checked.name, (), || {
            // SAFETY: Godot calls a script method on a live object on the calling thread;
            // it is one of the addon's nodes (a `Spatial`), used within this call.
            let node = std::ptr::NonNull::new(this)
                .map(|object| unsafe { Ref::<Node, Shared>::from_sys(object).assume_safe() });
            let (key, path) = node.map_or((0, String::from("?")), |node| {
                (node.get_instance_id(), node_path(&node))
            });
            if first_report(key, &checked.name, &error) {
                godot_error!(
                    "{}",
                    message(&path, &checked.name, &error, "nothing is done")
                );
            }
        });
        return Variant::new().forget();
    }
    // SAFETY: the arguments Godot gave, passed on unchanged to gdnative's wrapper, which
    // takes the same ones (it does not read `method_data`).
    unsafe { (checked.inner)(this, method_data, user_data, num_args, args) }
}

/// Frees a [`Checked`] when Godot unregisters the class.
///
/// # Safety
///
/// Called by Godot once, with the `method_data` [`add_checked`] registered.
unsafe extern "C" fn free_checked(method_data: *mut c_void) {
    if !method_data.is_null() {
        // SAFETY: made by `Box::into_raw` in `add_checked`, freed once.
        drop(unsafe { Box::from_raw(method_data.cast::<Checked>()) });
    }
}

/// Registers a method of a class with its argument count checked by the addon (see the
/// [module](mod@crate::methods)): `checked_method!(builder, Class, [names of the arguments],
/// fn name(&self, owner: &Spatial, a: Variant) -> Type)`, the signature as written on
/// the method (without `#[export]`, which would register it again unchecked).
#[macro_export]
macro_rules! checked_method {
    ($builder:expr, $class:ty, [$($param:literal),*], fn $name:ident($($signature:tt)*) $(-> $ret:ty)?) => {
        $crate::methods::add_checked(
            $builder,
            stringify!($name),
            &[$($param),*],
            gdnative::godot_wrap_method!($class, fn $name($($signature)*) $(-> $ret)?),
        )
    };
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counts_are_reported_with_the_arguments_expected() {
        assert_eq!(count_error(&["character"], 1), None);
        assert_eq!(count_error(&[], 0), None);
        assert_eq!(
            count_error(&["character"], 0).unwrap(),
            "too few arguments: it takes 1 argument (character), the call gave 0"
        );
        assert_eq!(
            count_error(&["character", "target"], 3).unwrap(),
            "too many arguments: it takes 2 arguments (character, target), the call gave 3"
        );
        assert_eq!(
            count_error(&[], 1).unwrap(),
            "too many arguments: it takes no argument, the call gave 1"
        );
    }
}
