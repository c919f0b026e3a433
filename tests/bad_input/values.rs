//! Small helpers: C structs filled by their `_init`, plain C values and their bytes, a float
//! poked into a field, structs with spare bytes after them, the float fields of C types, and
//! the `struct_size` values no library accepts.

use crowdgaze::ffi::attention::*;

use crowdgaze::ffi::blend::*;
use crowdgaze::ffi::gaze::*;
use crowdgaze::ffi::last_error::cg_last_error_message;
use crowdgaze::ffi::status::cg_status;
use crowdgaze::ffi::types::{cg_dualquat, cg_quat, cg_vec3};
use std::ffi::c_char;
use std::mem::{offset_of, size_of, MaybeUninit};

/// Fills a struct with its `_init` function (after setting its `struct_size`).
pub(crate) fn init<T>(f: unsafe extern "C" fn(*mut T) -> cg_status) -> T {
    let mut value = MaybeUninit::<T>::uninit();
    // SAFETY: every versioned struct starts with `uint32_t struct_size`, which the caller
    // sets to its size before the `_init` call.
    unsafe {
        value
            .as_mut_ptr()
            .cast::<u32>()
            .write(std::mem::size_of::<T>() as u32)
    };
    ok(unsafe { f(value.as_mut_ptr()) });
    // SAFETY: initialised by the _init function just above.
    unsafe { value.assume_init() }
}

pub(crate) fn ok(status: cg_status) {
    assert_eq!(status, cg_status::Ok, "{}", last_error());
}

pub(crate) fn last_error() -> String {
    let mut buf = [0u8; 1024];
    let length = unsafe { cg_last_error_message(buf.as_mut_ptr().cast::<c_char>(), buf.len()) };
    String::from_utf8_lossy(&buf[..length.min(buf.len() - 1)]).into_owned()
}

/// Plain C data without padding or pointers that need a meaning: all-zero bytes are a valid
/// value, and every byte of a value is initialised (so it can be compared as bytes).
pub(crate) trait Plain: Copy {}
impl Plain for f32 {}
impl Plain for cg_quat {}
impl Plain for cg_vec3 {}
impl Plain for cg_dualquat {}
impl Plain for cg_gaze_info {}
impl Plain for cg_eye_info {}
impl Plain for cg_character_params {}
impl Plain for cg_constraint {}
impl Plain for cg_score_breakdown {}

pub(crate) fn zeroed<T: Plain>() -> T {
    // SAFETY: `Plain` types are integers and floats, for which zero bytes are valid.
    unsafe { std::mem::zeroed() }
}

/// A zeroed versioned struct with its `struct_size` set, ready for the call that fills it.
pub(crate) fn sized<T: Plain>() -> T {
    let mut value = zeroed::<T>();
    set_struct_size(&mut value, size_of::<T>() as u32);
    value
}

pub(crate) fn bytes_of<T: Plain>(values: &[T]) -> &[u8] {
    // SAFETY: `Plain` values have no padding, so every byte is initialised.
    unsafe { std::slice::from_raw_parts(values.as_ptr().cast::<u8>(), size_of_val(values)) }
}

/// Writes `x` into the f32 at byte `offset` of `value` (an offset from `offset_of!` of a
/// float field, or of an element's float field in an array).
pub(crate) fn poke<T: ?Sized>(value: &mut T, offset: usize, x: f32) {
    assert!(
        offset + 4 <= size_of_val(value),
        "offset {offset} is outside"
    );
    // SAFETY: in bounds (checked); the bytes are those of an f32 field (caller's offsets).
    unsafe {
        (value as *mut T)
            .cast::<u8>()
            .add(offset)
            .cast::<f32>()
            .write_unaligned(x)
    }
}

/// Writes `struct_size` (the first field of every versioned struct).
pub(crate) fn set_struct_size<T>(value: &mut T, size: u32) {
    assert!(size_of::<T>() >= 4);
    // SAFETY: every versioned struct starts with `uint32_t struct_size`.
    unsafe { (value as *mut T).cast::<u32>().write_unaligned(size) }
}

/// A struct followed by spare bytes, so that a library that wrongly trusted a too-big
/// `struct_size` would still read inside the allocation.
#[repr(C)]
pub(crate) struct Padded<T> {
    pub(crate) value: T,
    tail: [u64; 32],
}

pub(crate) fn padded<T>(value: T) -> Box<Padded<T>> {
    Box::new(Padded {
        value,
        tail: [0; 32],
    })
}

pub(crate) fn vec3(x: f32, y: f32, z: f32) -> cg_vec3 {
    cg_vec3 { x, y, z }
}

pub(crate) fn rotation(axis: [f32; 3], angle: f32) -> cg_quat {
    let (s, c) = (angle / 2.0).sin_cos();
    cg_quat {
        x: axis[0] * s,
        y: axis[1] * s,
        z: axis[2] * s,
        w: c,
    }
}

pub(crate) fn transform(axis: [f32; 3], angle: f32, t: [f32; 3]) -> cg_dualquat {
    let mut out = MaybeUninit::<cg_dualquat>::uninit();
    ok(unsafe {
        cg_dualquat_from_rt(
            &rotation(axis, angle),
            &vec3(t[0], t[1], t[2]),
            out.as_mut_ptr(),
        )
    });
    // SAFETY: written by the successful call.
    unsafe { out.assume_init() }
}

pub(crate) const ZERO_QUAT: cg_quat = cg_quat {
    x: 0.0,
    y: 0.0,
    z: 0.0,
    w: 0.0,
};

/// A rigid transform with a zero real part.
pub(crate) const ZERO_DUALQUAT: cg_dualquat = cg_dualquat {
    real: ZERO_QUAT,
    dual: cg_quat::IDENTITY,
};

/// Float fields of a C type as (name, byte offset): `floats!(T: a, b.x)`.
macro_rules! floats {
    ($t:ty: $($($field:ident).+),+ $(,)?) => {
        vec![$((stringify!($($field).+).replace(' ', ""), offset_of!($t, $($field).+))),+]
    };
}

pub(crate) use floats;

pub(crate) type Fields = Vec<(String, usize)>;

pub(crate) fn vec3_fields() -> Fields {
    floats!(cg_vec3: x, y, z)
}

pub(crate) fn quat_fields() -> Fields {
    floats!(cg_quat: x, y, z, w)
}

pub(crate) fn dualquat_fields() -> Fields {
    floats!(cg_dualquat: real.x, real.y, real.z, real.w, dual.x, dual.y, dual.z, dual.w)
}

/// The fields of `inner` inside a field `name` at `offset`.
pub(crate) fn nested(name: &str, offset: usize, inner: Fields) -> Fields {
    inner
        .into_iter()
        .map(|(field, at)| match field.as_str() {
            "" => (name.to_owned(), offset + at),
            _ => (format!("{name}.{field}"), offset + at),
        })
        .collect()
}

/// The elements `name[0 .. count]` of an array of floats at `offset`.
pub(crate) fn float_elements(name: &str, offset: usize, count: usize) -> Fields {
    elements::<f32>(name, offset, count, &vec![(String::new(), 0)])
}

/// The fields of elements `0 .. count` of an array of `E` at `offset`, named `name[i]`.
pub(crate) fn elements<E>(name: &str, offset: usize, count: usize, inner: &Fields) -> Fields {
    (0..count)
        .flat_map(|index| {
            nested(
                &format!("{name}[{index}]"),
                offset + index * size_of::<E>(),
                inner.clone(),
            )
        })
        .collect()
}

pub(crate) const BAD_FLOATS: [(&str, f32); 3] = [
    ("NaN", f32::NAN),
    ("+Inf", f32::INFINITY),
    ("-Inf", f32::NEG_INFINITY),
];

/// `struct_size` values no library version accepts for a struct of `size` bytes.
pub(crate) fn bad_sizes(size: usize) -> Vec<(String, u32)> {
    bad_sizes_from(size, size)
}

/// [`bad_sizes`] of a struct whose earlier versions, down to `smallest` bytes, are still
/// accepted: "one field short" is short of the smallest.
pub(crate) fn bad_sizes_from(size: usize, smallest: usize) -> Vec<(String, u32)> {
    vec![
        ("0".into(), 0),
        ("4 (the size field alone)".into(), 4),
        (
            format!("{} (one field short)", smallest - 4),
            smallest as u32 - 4,
        ),
        (format!("{} (one field more)", size + 4), size as u32 + 4),
        ("UINT32_MAX".into(), u32::MAX),
    ]
}
