//! Corruptions of a valid input: each one way to break it, with the status that must come back.

use crate::{
    fixture::Harness,
    table::Table,
    values::{bad_sizes_from, poke, set_struct_size, Fields, Padded, BAD_FLOATS},
    BAD_SIZE, INVALID, NON_FINITE,
};
use crowdgaze::ffi::crowd::*;
use crowdgaze::ffi::status::cg_status;
use std::mem::{offset_of, size_of};
use std::rc::Rc;

pub(crate) type Corrupt<T> = Rc<dyn Fn(&mut T)>;

/// One way to break a valid input, and the status that must come back.
pub(crate) struct Corruption<T> {
    pub(crate) what: String,
    pub(crate) expected: cg_status,
    pub(crate) apply: Corrupt<T>,
}

pub(crate) fn change<T>(
    what: impl Into<String>,
    expected: cg_status,
    apply: impl Fn(&mut T) + 'static,
) -> Corruption<T> {
    Corruption {
        what: what.into(),
        expected,
        apply: Rc::new(apply),
    }
}

/// A named change of an input.
type Named<T> = (&'static str, fn(&mut T));

/// Corruptions that each put one value out of its range: `CG_STATUS_INVALID_ARGUMENT`.
pub(crate) fn invalid<T: 'static>(rows: &[Named<T>]) -> Vec<Corruption<T>> {
    rows.iter()
        .map(|&(what, apply)| change(what, INVALID, apply))
        .collect()
}

/// `attention_model` values that are no `cg_attention_model`: `CG_STATUS_INVALID_ARGUMENT`.
pub(crate) fn unknown_models<T: 'static>(field: fn(&mut T) -> &mut u32) -> Vec<Corruption<T>> {
    [4, u32::MAX]
        .map(|model| {
            change(
                format!("attention_model {model}"),
                INVALID,
                move |v: &mut T| *field(v) = model,
            )
        })
        .into()
}

/// NaN, +∞ and −∞ in each of `fields` (offsets into `T`): `CG_STATUS_NON_FINITE`.
pub(crate) fn non_finite<T>(fields: &Fields) -> Vec<Corruption<T>> {
    let mut out = Vec::new();
    for (field, offset) in fields {
        for (label, value) in BAD_FLOATS {
            let offset = *offset;
            out.push(change(
                format!("{field} = {label}"),
                NON_FINITE,
                move |input: &mut T| poke(input, offset, value),
            ));
        }
    }
    out
}

/// Every wrong `struct_size` of a versioned struct `T`: `CG_STATUS_BAD_STRUCT_SIZE`.
pub(crate) fn struct_sizes<T>() -> Vec<Corruption<T>> {
    struct_sizes_from::<T>(size_of::<T>())
}

/// [`struct_sizes`] of a struct whose earlier versions, down to `smallest` bytes, are
/// still accepted.
pub(crate) fn struct_sizes_from<T>(smallest: usize) -> Vec<Corruption<T>> {
    bad_sizes_from(size_of::<T>(), smallest)
        .into_iter()
        .map(|(what, size)| {
            change(format!("struct_size {what}"), BAD_SIZE, move |v: &mut T| {
                set_struct_size(v, size)
            })
        })
        .collect()
}

/// The size of the oldest `cg_crowd_config` layout (before `reorder_period`), still
/// accepted, as are the later ones (before the blink fields, before the conversation fields).
pub(crate) const OLDER_CROWD_CONFIG: usize = offset_of!(cg_crowd_config, reorder_period);

/// The cases of a function that fills a versioned struct `T` whose `struct_size` the caller
/// set to a size this library does not know (never set at all, 0, short of the oldest
/// layout's `smallest` bytes, longer than this library's): `CG_STATUS_BAD_STRUCT_SIZE`, and
/// not one byte written, of the struct or of the spare bytes after it.
pub(crate) fn bad_output_sizes<T: 'static>(
    t: &mut Table,
    function: &'static str,
    smallest: usize,
    fill: impl Fn(&mut Harness, *mut T) -> cg_status + 'static,
) {
    let fill = Rc::new(fill);
    let mut sizes = bad_sizes_from(size_of::<T>(), smallest);
    sizes.push(("0xA5A5A5A5 (never set)".into(), 0xA5A5_A5A5));
    for (what, size) in sizes {
        let fill = fill.clone();
        t.case(
            function,
            format!("struct_size {what}"),
            BAD_SIZE,
            move |h| {
                let mut out = Box::<Padded<T>>::new_uninit();
                // SAFETY: versioned structs hold integers, floats and raw pointers, for which
                // any bytes are a valid value, as for the tail's u64s; write_bytes sets them all.
                let mut out = unsafe {
                    out.as_mut_ptr().write_bytes(0xA5, 1);
                    out.assume_init()
                };
                set_struct_size(&mut out.value, size);
                let view = |out: &Padded<T>| {
                    // SAFETY: every byte, padding included, was initialised by write_bytes.
                    unsafe {
                        std::slice::from_raw_parts(
                            (out as *const Padded<T>).cast::<u8>(),
                            size_of::<Padded<T>>(),
                        )
                    }
                    .to_vec()
                };
                let before = view(&out);
                let status = fill(h, &mut out.value);
                if view(&out) != before {
                    h.problems.push(format!(
                        "refused struct_size {what} but wrote into the caller's memory"
                    ));
                }
                status
            },
        );
    }
}

/// The same corruptions applied through a projection (a field of a bigger input).
pub(crate) fn inside<T: 'static, U: 'static>(
    corruptions: Vec<Corruption<U>>,
    name: &str,
    project: fn(&mut T) -> &mut U,
) -> Vec<Corruption<T>> {
    corruptions
        .into_iter()
        .map(|c| {
            let apply = c.apply;
            change(format!("{name}{}", c.what), c.expected, move |v: &mut T| {
                apply(project(v))
            })
        })
        .collect()
}
