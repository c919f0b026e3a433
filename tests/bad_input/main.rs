//! The bad-input matrix (issue #10): every C function of `include/crowdgaze.h` is called
//! with each kind of bad input that applies to it — NULL pointers and `(NULL, n > 0)` arrays,
//! NaN and infinities in every float input (struct fields and array elements included),
//! unknown, removed and wrong-kind ids, wrong `struct_size`, zero and absurd counts, full
//! capacities, enums out of range, calls in the wrong state.
//!
//! Each case states the status it must return, which must be one the header documents for
//! that function; the call must leave a one-line message in `cg_last_error_message` that
//! matches the status, and must change nothing: every observable output of the crowd (all
//! its readers, for every id), of the view blenders (weights and poses from every key
//! camera) and of the caller's output buffers is compared byte for byte before and after, and
//! the crowd's next frames and its plan must be bit-identical to those of an untouched crowd.
//!
//! The functions are read from the header at test time: a function without a row makes
//! `every_header_function_has_a_row` fail, naming it. To cover a new function, add its cases
//! with `Table::case` (or the helpers below it) in the `rows_*` function of its area.

// The `unsafe { cg_... }` calls below pass pointers to live values of the sizes the header
// asks for, or deliberately bad ones (NULL, misaligned, wrong struct_size) that the library
// must refuse: that is their safety comment, once for the file.
#![allow(clippy::undocumented_unsafe_blocks)]

use crowdgaze::ffi::attention::*;
use crowdgaze::ffi::blend::*;
use crowdgaze::ffi::chain::*;
use crowdgaze::ffi::crowd::*;
use crowdgaze::ffi::gaze::*;
use crowdgaze::ffi::last_error::cg_last_error_message;
use crowdgaze::ffi::status::{cg_status, cg_status_str};
use crowdgaze::ffi::types::{cg_axis, cg_dualquat, cg_quat, cg_vec3};
use crowdgaze::ffi::version::*;
use crowdgaze::ffi::view_blender::*;
use std::collections::{BTreeMap, BTreeSet, HashMap};
use std::ffi::{c_char, CStr};
use std::mem::{offset_of, size_of, MaybeUninit};
use std::ptr::{null, null_mut};
use std::rc::Rc;

const NULL_ARG: cg_status = cg_status::NullArgument;
const INVALID: cg_status = cg_status::InvalidArgument;
const NON_FINITE: cg_status = cg_status::NonFinite;
const NOT_FOUND: cg_status = cg_status::NotFound;
const CAPACITY: cg_status = cg_status::Capacity;
const BAD_SIZE: cg_status = cg_status::BadStructSize;
const WRONG_STATE: cg_status = cg_status::WrongState;

/// Fewest cases the matrix must run (it runs well over this; the floor catches rows lost
/// by accident).
const CASE_FLOOR: usize = 1500;

// ---------------------------------------------------------------------------------------------
// The header: its functions, each with its doc comment, and the values of the statuses.

struct Header {
    /// Function name → its doc comment, whitespace collapsed.
    functions: BTreeMap<String, String>,
    /// `CG_STATUS_*` name → value.
    statuses: BTreeMap<String, u32>,
}

impl Header {
    fn read() -> Header {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("include/crowdgaze.h");
        let text = std::fs::read_to_string(&path).expect("include/crowdgaze.h is readable");
        let mut functions = BTreeMap::new();
        let mut statuses = BTreeMap::new();
        let mut comment = Vec::new();
        for line in text.lines() {
            if let Some(doc) = line.strip_prefix("//") {
                comment.push(doc.trim().to_owned());
                continue;
            }
            if let Some((name, value)) = line.trim().trim_end_matches(',').split_once(" = ") {
                if name.starts_with("CG_STATUS_") {
                    statuses.insert(name.to_owned(), value.parse().expect("status value"));
                }
            }
            let declaration = line.starts_with(|c: char| c.is_ascii_alphabetic())
                && !line.starts_with("typedef")
                && !line.starts_with("enum ");
            if let (true, Some(open)) = (declaration, line.find('(')) {
                let name = line[..open]
                    .rsplit(|c: char| !(c.is_ascii_alphanumeric() || c == '_'))
                    .next()
                    .unwrap_or_default();
                if name.starts_with("cg_") {
                    functions.insert(name.to_owned(), comment.join(" "));
                }
            }
            comment.clear();
        }
        assert!(
            functions.len() > 40 && statuses.len() == cg_status::ALL.len(),
            "the header parser found {} functions and {} statuses: has the header's layout changed?",
            functions.len(),
            statuses.len()
        );
        Header {
            functions,
            statuses,
        }
    }

    /// The statuses the doc comment of `function` names, with those of the functions it
    /// refers to for its errors ("as `cg_…`", "those of `cg_…`").
    fn documented(&self, function: &str) -> BTreeSet<u32> {
        let mut found = BTreeSet::new();
        let mut pending = vec![function.to_owned()];
        let mut seen = BTreeSet::new();
        while let Some(name) = pending.pop() {
            if !seen.insert(name.clone()) {
                continue;
            }
            let Some(doc) = self.functions.get(&name) else {
                continue;
            };
            for (status, value) in &self.statuses {
                if doc.contains(status.as_str()) {
                    found.insert(*value);
                }
            }
            for marker in ["as `", "those of `", "as in `"] {
                for (at, _) in doc.match_indices(marker) {
                    let rest = &doc[at + marker.len()..];
                    let referenced = &rest[..rest.find('`').unwrap_or(0)];
                    if self.functions.contains_key(referenced) {
                        pending.push(referenced.to_owned());
                    }
                }
            }
        }
        found
    }

    fn status_name(&self, status: cg_status) -> &str {
        self.statuses
            .iter()
            .find(|(_, value)| **value == status as u32)
            .map_or("?", |(name, _)| name.as_str())
    }
}

// ---------------------------------------------------------------------------------------------
// Small helpers

/// Fills a struct with its `_init` function (after setting its `struct_size`).
fn init<T>(f: unsafe extern "C" fn(*mut T) -> cg_status) -> T {
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

fn ok(status: cg_status) {
    assert_eq!(status, cg_status::Ok, "{}", last_error());
}

fn last_error() -> String {
    let mut buf = [0u8; 1024];
    let length = unsafe { cg_last_error_message(buf.as_mut_ptr().cast::<c_char>(), buf.len()) };
    String::from_utf8_lossy(&buf[..length.min(buf.len() - 1)]).into_owned()
}

/// Plain C data without padding or pointers that need a meaning: all-zero bytes are a valid
/// value, and every byte of a value is initialised (so it can be compared as bytes).
trait Plain: Copy {}
impl Plain for f32 {}
impl Plain for cg_quat {}
impl Plain for cg_vec3 {}
impl Plain for cg_dualquat {}
impl Plain for cg_gaze_info {}
impl Plain for cg_eye_info {}
impl Plain for cg_character_params {}
impl Plain for cg_constraint {}
impl Plain for cg_score_breakdown {}

fn zeroed<T: Plain>() -> T {
    // SAFETY: `Plain` types are integers and floats, for which zero bytes are valid.
    unsafe { std::mem::zeroed() }
}

/// A zeroed versioned struct with its `struct_size` set, ready for the call that fills it.
fn sized<T: Plain>() -> T {
    let mut value = zeroed::<T>();
    set_struct_size(&mut value, size_of::<T>() as u32);
    value
}

fn bytes_of<T: Plain>(values: &[T]) -> &[u8] {
    // SAFETY: `Plain` values have no padding, so every byte is initialised.
    unsafe { std::slice::from_raw_parts(values.as_ptr().cast::<u8>(), size_of_val(values)) }
}

/// Writes `x` into the f32 at byte `offset` of `value` (an offset from `offset_of!` of a
/// float field, or of an element's float field in an array).
fn poke<T: ?Sized>(value: &mut T, offset: usize, x: f32) {
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
fn set_struct_size<T>(value: &mut T, size: u32) {
    assert!(size_of::<T>() >= 4);
    // SAFETY: every versioned struct starts with `uint32_t struct_size`.
    unsafe { (value as *mut T).cast::<u32>().write_unaligned(size) }
}

/// A struct followed by spare bytes, so that a library that wrongly trusted a too-big
/// `struct_size` would still read inside the allocation.
#[repr(C)]
struct Padded<T> {
    value: T,
    tail: [u64; 32],
}

fn padded<T>(value: T) -> Box<Padded<T>> {
    Box::new(Padded {
        value,
        tail: [0; 32],
    })
}

fn vec3(x: f32, y: f32, z: f32) -> cg_vec3 {
    cg_vec3 { x, y, z }
}

fn rotation(axis: [f32; 3], angle: f32) -> cg_quat {
    let (s, c) = (angle / 2.0).sin_cos();
    cg_quat {
        x: axis[0] * s,
        y: axis[1] * s,
        z: axis[2] * s,
        w: c,
    }
}

fn transform(axis: [f32; 3], angle: f32, t: [f32; 3]) -> cg_dualquat {
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

const ZERO_QUAT: cg_quat = cg_quat {
    x: 0.0,
    y: 0.0,
    z: 0.0,
    w: 0.0,
};

/// A rigid transform with a zero real part.
const ZERO_DUALQUAT: cg_dualquat = cg_dualquat {
    real: ZERO_QUAT,
    dual: cg_quat::IDENTITY,
};

/// Float fields of a C type as (name, byte offset): `floats!(T: a, b.x)`.
macro_rules! floats {
    ($t:ty: $($($field:ident).+),+ $(,)?) => {
        vec![$((stringify!($($field).+).replace(' ', ""), offset_of!($t, $($field).+))),+]
    };
}

type Fields = Vec<(String, usize)>;

fn vec3_fields() -> Fields {
    floats!(cg_vec3: x, y, z)
}

fn quat_fields() -> Fields {
    floats!(cg_quat: x, y, z, w)
}

fn dualquat_fields() -> Fields {
    floats!(cg_dualquat: real.x, real.y, real.z, real.w, dual.x, dual.y, dual.z, dual.w)
}

/// The fields of `inner` inside a field `name` at `offset`.
fn nested(name: &str, offset: usize, inner: Fields) -> Fields {
    inner
        .into_iter()
        .map(|(field, at)| match field.as_str() {
            "" => (name.to_owned(), offset + at),
            _ => (format!("{name}.{field}"), offset + at),
        })
        .collect()
}

/// The elements `name[0 .. count]` of an array of floats at `offset`.
fn float_elements(name: &str, offset: usize, count: usize) -> Fields {
    elements::<f32>(name, offset, count, &vec![(String::new(), 0)])
}

/// The fields of elements `0 .. count` of an array of `E` at `offset`, named `name[i]`.
fn elements<E>(name: &str, offset: usize, count: usize, inner: &Fields) -> Fields {
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

const BAD_FLOATS: [(&str, f32); 3] = [
    ("NaN", f32::NAN),
    ("+Inf", f32::INFINITY),
    ("-Inf", f32::NEG_INFINITY),
];

/// `struct_size` values no library version accepts for a struct of `size` bytes.
fn bad_sizes(size: usize) -> Vec<(String, u32)> {
    bad_sizes_from(size, size)
}

/// [`bad_sizes`] of a struct whose earlier versions, down to `smallest` bytes, are still
/// accepted: "one field short" is short of the smallest.
fn bad_sizes_from(size: usize, smallest: usize) -> Vec<(String, u32)> {
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

// ---------------------------------------------------------------------------------------------
// Corruptions of a valid input

type Corrupt<T> = Rc<dyn Fn(&mut T)>;

/// One way to break a valid input, and the status that must come back.
struct Corruption<T> {
    what: String,
    expected: cg_status,
    apply: Corrupt<T>,
}

fn change<T>(
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
fn invalid<T: 'static>(rows: &[Named<T>]) -> Vec<Corruption<T>> {
    rows.iter()
        .map(|&(what, apply)| change(what, INVALID, apply))
        .collect()
}

/// `attention_model` values that are no `cg_attention_model`: `CG_STATUS_INVALID_ARGUMENT`.
fn unknown_models<T: 'static>(field: fn(&mut T) -> &mut u32) -> Vec<Corruption<T>> {
    [3, u32::MAX]
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
fn non_finite<T>(fields: &Fields) -> Vec<Corruption<T>> {
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
fn struct_sizes<T>() -> Vec<Corruption<T>> {
    struct_sizes_from::<T>(size_of::<T>())
}

/// [`struct_sizes`] of a struct whose earlier versions, down to `smallest` bytes, are
/// still accepted.
fn struct_sizes_from<T>(smallest: usize) -> Vec<Corruption<T>> {
    bad_sizes_from(size_of::<T>(), smallest)
        .into_iter()
        .map(|(what, size)| {
            change(format!("struct_size {what}"), BAD_SIZE, move |v: &mut T| {
                set_struct_size(v, size)
            })
        })
        .collect()
}

/// The size of the older `cg_crowd_config` (before `reorder_period`), still accepted.
const OLDER_CROWD_CONFIG: usize = offset_of!(cg_crowd_config, reorder_period);

/// The cases of a function that fills a versioned struct `T` whose `struct_size` the caller
/// set to a size this library does not know (never set at all, 0, short of the oldest
/// layout's `smallest` bytes, longer than this library's): `CG_STATUS_BAD_STRUCT_SIZE`, and
/// not one byte written, of the struct or of the spare bytes after it.
fn bad_output_sizes<T: 'static>(
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
fn inside<T: 'static, U: 'static>(
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

// ---------------------------------------------------------------------------------------------
// The fixture: a populated crowd, three view blenders, and the caller's output buffers.

/// The state a case starts from.
#[derive(Clone, Copy, PartialEq, Eq, Hash, Debug)]
enum Setup {
    /// Characters (three attention models, two chains) and objects below capacity, a
    /// viewer, explicit targets, a base pose, a removed character and object, recording on,
    /// a few frames pushed and stepped.
    Online,
    /// `Online`, then planned (`cg_crowd_plan`) and stepped along the plan.
    Planned,
    /// `Online` with as many characters and objects as the capacities allow.
    Full,
    /// `Online` with the recording exactly full.
    RecordingFull,
    /// `Online` without recording and without a viewer.
    Unrecorded,
}

const FPS: f64 = 30.0;
const FRAMES: usize = 6;
const UNKNOWN_ID: u32 = 123_456_789;
const JOINTS: usize = 3;
const KEYS: usize = 3;

/// An entity of the fixture and how it moves: `start + velocity · t`.
#[derive(Clone, Copy)]
struct Mover {
    id: u32,
    start: [f32; 3],
    velocity: [f32; 3],
    heading: f32,
    flags: u32,
}

impl Mover {
    /// An entity standing at `start`, heading 1 rad.
    fn still(id: u32, start: [f32; 3]) -> Mover {
        Mover {
            id,
            start,
            velocity: [0.0; 3],
            heading: 1.0,
            flags: 0,
        }
    }
}

/// Output buffers handed to the functions; filled with a pattern that a failed call must
/// leave as it is.
#[repr(C)]
struct Outputs {
    /// Arrays: the crowd's readers, a matrix, the view blender's weights and poses.
    gaze: [cg_gaze_info; 8],
    constraints: [cg_constraint; 8],
    quats: [cg_quat; 64],
    eyes: [cg_eye_info; 8],
    matrix: [f32; 16],
    weights: [f32; 8],
    pose: [cg_dualquat; 8],
    /// Single values: `*out_id`, `*out_count` (and totals), new handles, filled structs,
    /// transforms and their parts.
    id: u32,
    count: usize,
    crowd: *mut cg_crowd,
    blender: *mut cg_view_blender,
    crowd_config: cg_crowd_config,
    chain: cg_chain_desc,
    params: cg_character_params,
    score: cg_score_breakdown,
    dual_quat: cg_dualquat,
    quat: cg_quat,
    vec3: cg_vec3,
}

impl Outputs {
    fn new() -> Box<Outputs> {
        let mut out = Box::<Outputs>::new_uninit();
        // SAFETY: every field is an integer, a float or a raw pointer, for which any bytes
        // are a valid value; write_bytes initialises all of them (and the padding).
        unsafe {
            out.as_mut_ptr().write_bytes(0xA5, 1);
            out.assume_init()
        }
    }

    fn bytes(&self) -> &[u8] {
        // SAFETY: every byte was initialised by `new`; a failed call writes nothing.
        unsafe {
            std::slice::from_raw_parts((self as *const Outputs).cast::<u8>(), size_of::<Outputs>())
        }
    }
}

struct Harness {
    crowd: *mut cg_crowd,
    /// Live characters: a crowd-model one, one with a chain without eyes, a saliency-model
    /// one, a baseline-model one.
    characters: Vec<u32>,
    /// Live objects.
    objects: Vec<u32>,
    movers: Vec<Mover>,
    viewer: Option<u32>,
    removed_character: u32,
    removed_object: u32,
    /// Time of the last pushed frame.
    time: f64,
    blender: *mut cg_view_blender,
    /// Every key has a clip, no key camera.
    blender_no_camera: *mut cg_view_blender,
    /// Key cameras, but key 1 has no clip.
    blender_no_clip: *mut cg_view_blender,
    out: Box<Outputs>,
    /// Problems a case found beyond its status (an input changed, …).
    problems: Vec<String>,
}

impl Drop for Harness {
    fn drop(&mut self) {
        unsafe { cg_crowd_destroy(self.crowd) };
        for blender in [self.blender, self.blender_no_camera, self.blender_no_clip] {
            unsafe { cg_view_blender_destroy(blender) };
        }
    }
}

/// The chain of the second character: the human chain without its eyes (8 joints).
fn chain_without_eyes() -> cg_chain_desc {
    let mut chain = MaybeUninit::<cg_chain_desc>::uninit();
    // SAFETY: a versioned struct starts with its `uint32_t struct_size`, set before the call.
    unsafe {
        chain
            .as_mut_ptr()
            .cast::<u32>()
            .write(std::mem::size_of::<cg_chain_desc>() as u32)
    };
    ok(unsafe {
        cg_chain_desc_init_human(
            chain.as_mut_ptr(),
            cg_axis::PositiveY as u32,
            cg_axis::PositiveZ as u32,
        )
    });
    // SAFETY: written by the successful call.
    let mut chain = unsafe { chain.assume_init() };
    chain.joint_count = 8;
    chain
}

fn human_chain() -> cg_chain_desc {
    let mut chain = chain_without_eyes();
    chain.joint_count = 10;
    chain
}

/// A base pose for a 10-joint chain, every joint turned a little.
fn base_pose() -> [cg_quat; 10] {
    std::array::from_fn(|joint| rotation([0.0, 1.0, 0.0], 0.02 * (joint as f32 + 1.0)))
}

impl Harness {
    fn new(setup: Setup) -> Harness {
        let mut config: cg_crowd_config = init(cg_crowd_config_init);
        config.max_characters = if setup == Setup::Full { 4 } else { 6 };
        config.max_objects = if setup == Setup::Full { 2 } else { 3 };
        config.max_recorded_states = match setup {
            Setup::Unrecorded => 0,
            Setup::RecordingFull => (6 * FRAMES) as u32,
            _ => 10_000,
        };
        let mut crowd = null_mut();
        ok(unsafe { cg_crowd_create(&config, &mut crowd) });
        let mut h = Harness {
            crowd,
            characters: Vec::new(),
            objects: Vec::new(),
            movers: Vec::new(),
            viewer: None,
            removed_character: 0,
            removed_object: 0,
            time: 0.0,
            blender: Harness::blender(true, [true; KEYS]),
            blender_no_camera: Harness::blender(false, [true; KEYS]),
            blender_no_clip: Harness::blender(true, [true, false, true]),
            out: Outputs::new(),
            problems: Vec::new(),
        };
        let no_eyes = chain_without_eyes();
        let crowd_model = cg_attention_model::Crowd as u32;
        h.add_character([0.0, 0.0, 0.0], [1.0, 0.0, 0.2], 0, crowd_model, null());
        h.add_character(
            [1.5, 0.0, 2.0],
            [0.0, 0.0, -0.8],
            CG_STATE_HEADING_FROM_MOTION,
            crowd_model,
            &no_eyes,
        );
        h.removed_character = h.add_character([5.0, 0.0, 5.0], [0.0; 3], 0, crowd_model, null());
        h.remove(h.removed_character);
        h.add_character(
            [-1.0, 0.0, 3.0],
            [0.5, 0.0, 0.5],
            CG_STATE_HAS_VELOCITY,
            cg_attention_model::Saliency as u32,
            null(),
        );
        h.add_character(
            [2.0, 0.0, -1.0],
            [0.0; 3],
            0,
            cg_attention_model::Baseline as u32,
            null(),
        );
        h.add_object([0.0, 1.0, 4.0], 2.0);
        h.removed_object = h.add_object([4.0, 0.0, 0.0], 1.0);
        h.remove(h.removed_object);
        h.add_object([-3.0, 0.0, 1.0], 0.5);
        if setup != Setup::Unrecorded {
            let mut viewer = 0;
            ok(unsafe { cg_crowd_set_viewer(crowd, &vec3(0.0, 1.7, 6.0), 1.5, &mut viewer) });
            h.viewer = Some(viewer);
        }
        let [c0, c1, c3, c4] = h.characters[..] else {
            unreachable!("four characters")
        };
        let mut target: cg_gaze_target = init(cg_gaze_target_init);
        target.kind = CG_GAZE_TARGET_ENTITY;
        target.entity = h.objects[0];
        target.priority = CG_GAZE_PRIORITY_WHEN_IDLE;
        ok(unsafe { cg_crowd_set_gaze_target(crowd, c1, &target) });
        target.kind = CG_GAZE_TARGET_POINT;
        target.point = vec3(3.0, 1.5, 3.0);
        target.priority = CG_GAZE_PRIORITY_OVERRIDE;
        ok(unsafe { cg_crowd_set_gaze_target(crowd, c0, &target) });
        ok(unsafe { cg_crowd_set_base_pose(crowd, c4, base_pose().as_ptr(), 10) });
        ok(unsafe { cg_crowd_set_attention_period(crowd, c3, 2) });
        for frame in 0..FRAMES {
            h.time = frame as f64 / FPS;
            let states = h.frame_at(h.time);
            ok(unsafe { cg_crowd_push_frame(crowd, h.time, states.as_ptr(), states.len()) });
            ok(unsafe { cg_crowd_step(crowd, (1.0 / FPS) as f32) });
        }
        assert_eq!(h.movers.len(), MOVERS, "entities in a frame");
        let mut joints = 0;
        ok(unsafe { cg_crowd_joint_total(crowd, 0, 4, &mut joints) });
        assert_eq!(joints, ALL_JOINTS, "joints of the four characters");
        if setup == Setup::Planned {
            ok(unsafe { cg_crowd_plan(crowd) });
            ok(unsafe { cg_crowd_step(crowd, (1.0 / FPS) as f32) });
            ok(unsafe { cg_crowd_step(crowd, (1.0 / FPS) as f32) });
        }
        h
    }

    fn add_character(
        &mut self,
        start: [f32; 3],
        velocity: [f32; 3],
        flags: u32,
        model: u32,
        chain: *const cg_chain_desc,
    ) -> u32 {
        let heading = 0.3 * self.movers.len() as f32;
        let mut desc: cg_character_desc = init(cg_character_desc_init);
        desc.position = vec3(start[0], start[1], start[2]);
        desc.heading = heading;
        desc.attention_model = model;
        desc.chain = chain;
        let mut id = 0;
        ok(unsafe { cg_crowd_add_character(self.crowd, &desc, &mut id) });
        self.characters.push(id);
        self.track(Mover {
            velocity,
            heading,
            flags,
            ..Mover::still(id, start)
        })
    }

    /// Remembers how a new entity moves; returns its id.
    fn track(&mut self, mover: Mover) -> u32 {
        self.movers.push(mover);
        mover.id
    }

    fn add_object(&mut self, start: [f32; 3], impact: f32) -> u32 {
        let mut desc: cg_object_desc = init(cg_object_desc_init);
        desc.position = vec3(start[0], start[1], start[2]);
        desc.impact = impact;
        desc.look_at_height = 1.2;
        let mut id = 0;
        ok(unsafe { cg_crowd_add_object(self.crowd, &desc, &mut id) });
        self.objects.push(id);
        self.track(Mover::still(id, start))
    }

    fn remove(&mut self, id: u32) {
        ok(unsafe { cg_crowd_remove_entity(self.crowd, id) });
        self.characters.retain(|&c| c != id);
        self.objects.retain(|&o| o != id);
        self.movers.retain(|m| m.id != id);
    }

    /// A view blender of `JOINTS` joints and `KEYS` keys: key 0 a looping clip, key 1 a
    /// pose, key 2 a clamped clip (those `clips` says), and cameras (if `cameras`) at +Z for
    /// key 0, +X for key 1, −Z and −X for key 2.
    fn blender(cameras: bool, clips: [bool; KEYS]) -> *mut cg_view_blender {
        let mut config: cg_view_blender_config = init(cg_view_blender_config_init);
        config.joint_count = JOINTS as u32;
        config.key_count = KEYS as u32;
        let mut blender = null_mut();
        ok(unsafe { cg_view_blender_create(&config, &mut blender) });
        let frames: Vec<cg_dualquat> = (0..4 * JOINTS)
            .map(|i| transform([0.0, 1.0, 0.0], 0.1 * i as f32, [0.0, 0.1 * i as f32, 0.0]))
            .collect();
        if clips[0] {
            ok(unsafe { cg_view_blender_set_key_clip(blender, 0, frames.as_ptr(), 4, 10.0, true) });
        }
        if clips[1] {
            let pose = [transform([1.0, 0.0, 0.0], 0.4, [0.2, 0.0, 0.0]); JOINTS];
            ok(unsafe { cg_view_blender_set_key_pose(blender, 1, pose.as_ptr(), JOINTS) });
        }
        if clips[2] {
            ok(unsafe {
                cg_view_blender_set_key_clip(blender, 2, frames[JOINTS..].as_ptr(), 2, 2.0, false)
            });
        }
        if cameras {
            for (direction, key) in [
                (vec3(0.0, 0.0, 1.0), 0),
                (vec3(1.0, 0.0, 0.0), 1),
                (vec3(0.0, 0.0, -1.0), 2),
                (vec3(-1.0, 0.0, 0.0), 2),
            ] {
                ok(unsafe { cg_view_blender_add_camera(blender, direction, key) });
            }
        }
        blender
    }

    /// Valid states of every live entity at time `t`.
    fn frame_at(&self, t: f64) -> Vec<cg_entity_state> {
        self.movers
            .iter()
            .map(|m| {
                let mut state: cg_entity_state = init(cg_entity_state_init);
                let t = t as f32;
                state.id = m.id;
                state.flags = m.flags;
                state.heading = m.heading;
                state.position = vec3(
                    m.start[0] + m.velocity[0] * t,
                    m.start[1] + m.velocity[1] * t,
                    m.start[2] + m.velocity[2] * t,
                );
                state.velocity = vec3(m.velocity[0], m.velocity[1], m.velocity[2]);
                state
            })
            .collect()
    }

    /// The next frame's time and states.
    fn next_frame(&self) -> (f64, Vec<cg_entity_state>) {
        let t = self.time + 1.0 / FPS;
        (t, self.frame_at(t))
    }

    /// Every id worth asking about: live, removed, the viewer, unknown, `CG_NO_TARGET`.
    fn ids(&self) -> Vec<u32> {
        let mut ids = self.characters.clone();
        ids.extend(&self.objects);
        ids.extend(self.viewer);
        ids.extend([
            self.removed_character,
            self.removed_object,
            UNKNOWN_ID,
            CG_NO_TARGET,
        ]);
        ids
    }

    fn character(&self, index: usize) -> u32 {
        self.characters[index]
    }

    fn object(&self) -> u32 {
        self.objects[0]
    }

    /// Records a problem a case found besides its status.
    fn note(&mut self, problem: impl Into<String>) {
        self.problems.push(problem.into());
    }

    /// Everything observable, by section.
    fn snapshot(&self) -> Snapshot {
        let mut s = crowd_snapshot(self.crowd, &self.ids());
        for (name, blender) in [
            ("blender", self.blender),
            ("blender_no_camera", self.blender_no_camera),
            ("blender_no_clip", self.blender_no_clip),
        ] {
            blender_snapshot(&mut s, name, blender);
        }
        s.section("output buffers").extend(self.out.bytes());
        s
    }

    /// The crowd's next frames and its plan: three frames pushed and stepped, read, then
    /// planned and read again.
    fn future(&self) -> Snapshot {
        let mut s = Snapshot::default();
        let steps = s.section("next frames: statuses");
        for k in 1..=3 {
            let t = self.time + k as f64 / FPS;
            let states = self.frame_at(t);
            status(steps, unsafe {
                cg_crowd_push_frame(self.crowd, t, states.as_ptr(), states.len())
            });
            status(steps, unsafe {
                cg_crowd_step(self.crowd, (1.0 / FPS) as f32)
            });
        }
        for (name, bytes) in crowd_snapshot(self.crowd, &self.ids()).sections {
            s.sections.push((format!("next frames: {name}"), bytes));
        }
        status(s.section("plan"), unsafe { cg_crowd_plan(self.crowd) });
        for (name, bytes) in crowd_snapshot(self.crowd, &self.ids()).sections {
            s.sections.push((format!("planned: {name}"), bytes));
        }
        s
    }
}

// ---------------------------------------------------------------------------------------------
// Snapshots

/// Observable outputs as named byte strings (floats by their bits, so NaN compares equal to
/// itself and −0 differs from +0).
#[derive(Default, PartialEq)]
struct Snapshot {
    sections: Vec<(String, Vec<u8>)>,
}

impl Snapshot {
    fn section(&mut self, name: impl Into<String>) -> &mut Vec<u8> {
        self.sections.push((name.into(), Vec::new()));
        &mut self.sections.last_mut().expect("just pushed").1
    }

    /// The names of the sections that differ from `other`'s.
    fn differences(&self, other: &Snapshot) -> Vec<String> {
        let mut out: Vec<String> = self
            .sections
            .iter()
            .zip(&other.sections)
            .filter(|(a, b)| a != b)
            .map(|((name, _), _)| name.clone())
            .collect();
        if self.sections.len() != other.sections.len() {
            out.push("the number of sections".into());
        }
        out
    }
}

fn status(bytes: &mut Vec<u8>, status: cg_status) {
    bytes.extend((status as u32).to_le_bytes());
}

fn count(bytes: &mut Vec<u8>, value: usize) {
    bytes.extend((value as u64).to_le_bytes());
}

/// Every reader of the crowd: count, config, gaze, joints (final and deltas), eyes, and
/// for every id its parameters, constraints and its score of every id.
fn crowd_snapshot(crowd: *const cg_crowd, ids: &[u32]) -> Snapshot {
    let mut s = Snapshot::default();
    let mut characters = 0usize;
    let b = s.section("cg_crowd_character_count");
    status(b, unsafe {
        cg_crowd_character_count(crowd, &mut characters)
    });
    count(b, characters);
    let mut config: cg_crowd_config = init(cg_crowd_config_init);
    let b = s.section("cg_crowd_get_config");
    status(b, unsafe { cg_crowd_get_config(crowd, &mut config) });
    b.extend(format!("{config:?}").bytes());
    let mut gaze = vec![zeroed::<cg_gaze_info>(); characters + 1];
    let mut written = usize::MAX;
    let b = s.section("cg_crowd_read_gaze");
    status(b, unsafe {
        cg_crowd_read_gaze(crowd, gaze.as_mut_ptr(), gaze.len(), &mut written)
    });
    count(b, written);
    b.extend(bytes_of(&gaze));
    let range = characters as u32;
    let mut total = 0usize;
    let b = s.section("cg_crowd_joint_total");
    status(b, unsafe {
        cg_crowd_joint_total(crowd, 0, range, &mut total)
    });
    count(b, total);
    type ReadJoints =
        unsafe extern "C" fn(*const cg_crowd, u32, u32, *mut cg_quat, usize) -> cg_status;
    for (name, read) in [
        ("cg_crowd_read_joints", cg_crowd_read_joints as ReadJoints),
        ("cg_crowd_read_joint_deltas", cg_crowd_read_joint_deltas),
    ] {
        let mut quats = vec![zeroed::<cg_quat>(); total];
        let b = s.section(name);
        status(b, unsafe {
            read(crowd, 0, range, quats.as_mut_ptr(), quats.len())
        });
        b.extend(bytes_of(&quats));
    }
    let mut eyes = vec![zeroed::<cg_eye_info>(); characters];
    let b = s.section("cg_crowd_read_eyes");
    status(b, unsafe {
        cg_crowd_read_eyes(crowd, 0, range, eyes.as_mut_ptr(), eyes.len())
    });
    b.extend(bytes_of(&eyes));
    for &id in ids {
        let mut params = [sized::<cg_character_params>()];
        let b = s.section(format!("cg_crowd_get_character_params({id})"));
        status(b, unsafe {
            cg_crowd_get_character_params(crowd, id, params.as_mut_ptr())
        });
        b.extend(bytes_of(&params));
        let mut constraints = [zeroed::<cg_constraint>(); 64];
        let mut total = usize::MAX;
        let b = s.section(format!("cg_crowd_read_constraints({id})"));
        status(b, unsafe {
            cg_crowd_read_constraints(
                crowd,
                id,
                constraints.as_mut_ptr(),
                constraints.len(),
                &mut total,
            )
        });
        count(b, total);
        b.extend(bytes_of(&constraints));
        let b = s.section(format!("cg_crowd_score({id}, *)"));
        for &entity in ids {
            let mut score = [zeroed::<cg_score_breakdown>()];
            status(b, unsafe {
                cg_crowd_score(crowd, id, entity, score.as_mut_ptr())
            });
            b.extend(bytes_of(&score));
        }
    }
    s
}

/// The weights and the evaluated poses of a blender for viewers on each key camera (where
/// one key alone is seen) and off them, at several times.
fn blender_snapshot(s: &mut Snapshot, name: &str, blender: *const cg_view_blender) {
    let b = s.section(name);
    let placed = transform([0.0, 1.0, 0.0], 0.7, [1.0, 0.0, 2.0]);
    for (character, origin) in [(IDENTITY_DQ, [0.0; 3]), (placed, [1.0, 0.0, 2.0])] {
        for direction in [
            [0.0, 0.0, 5.0],
            [5.0, 0.0, 0.0],
            [0.0, 0.0, -5.0],
            [-5.0, 0.0, 0.0],
            [0.0, 5.0, 0.0],
            [1.0, 2.0, 3.0],
        ] {
            let viewer = vec3(
                origin[0] + direction[0],
                origin[1] + direction[1],
                origin[2] + direction[2],
            );
            let mut weights = [0.0f32; KEYS];
            status(b, unsafe {
                cg_view_blender_weights(blender, &character, &viewer, weights.as_mut_ptr(), KEYS)
            });
            b.extend(bytes_of(&weights));
            for t in [0.0, 0.13, 0.55, 2.4] {
                let mut pose = [zeroed::<cg_dualquat>(); JOINTS];
                status(b, unsafe {
                    cg_view_blender_evaluate(
                        blender,
                        &character,
                        &viewer,
                        t,
                        pose.as_mut_ptr(),
                        JOINTS,
                    )
                });
                b.extend(bytes_of(&pose));
            }
        }
    }
}

const IDENTITY_DQ: cg_dualquat = cg_dualquat {
    real: cg_quat::IDENTITY,
    dual: ZERO_QUAT,
};

// ---------------------------------------------------------------------------------------------
// The table of cases, keyed by function name

type Call = Rc<dyn Fn(&mut Harness) -> cg_status>;

/// Picks an id from a fixture.
type Pick = fn(&Harness) -> u32;

struct Case {
    what: String,
    setup: Setup,
    expected: cg_status,
    call: Call,
}

enum Row {
    Cases(Vec<Case>),
    /// A function that cannot fail: why, and a check of how it takes its own odd inputs.
    NoFailureModes {
        why: &'static str,
        check: fn(),
    },
}

#[derive(Default)]
struct Table {
    rows: BTreeMap<&'static str, Row>,
}

impl Table {
    /// A case on the `Online` fixture.
    fn case(
        &mut self,
        function: &'static str,
        what: impl Into<String>,
        expected: cg_status,
        call: impl Fn(&mut Harness) -> cg_status + 'static,
    ) {
        self.case_in(Setup::Online, function, what, expected, call);
    }

    fn case_in(
        &mut self,
        setup: Setup,
        function: &'static str,
        what: impl Into<String>,
        expected: cg_status,
        call: impl Fn(&mut Harness) -> cg_status + 'static,
    ) {
        let row = self
            .rows
            .entry(function)
            .or_insert_with(|| Row::Cases(Vec::new()));
        let Row::Cases(cases) = row else {
            panic!("{function} is marked as having no failure modes")
        };
        cases.push(Case {
            what: what.into(),
            setup,
            expected,
            call: Rc::new(call),
        });
    }

    /// One case per corruption: `make` builds a valid input, the corruption breaks it,
    /// `call` hands it to the function.
    fn corrupt<T: 'static>(
        &mut self,
        setup: Setup,
        function: &'static str,
        corruptions: Vec<Corruption<T>>,
        make: impl Fn(&Harness) -> T + 'static,
        call: impl Fn(&mut Harness, &mut T) -> cg_status + 'static,
    ) {
        let make = Rc::new(make);
        let call = Rc::new(call);
        for corruption in corruptions {
            let (make, call, apply) = (make.clone(), call.clone(), corruption.apply);
            self.case_in(
                setup,
                function,
                corruption.what,
                corruption.expected,
                move |h| {
                    let mut input = make(h);
                    apply(&mut input);
                    call(h, &mut input)
                },
            );
        }
    }

    /// [`corrupt`](Self::corrupt) for a versioned struct passed with spare bytes after it:
    /// the corruptions apply to the struct, named `name.field`.
    fn corrupt_struct<T: 'static>(
        &mut self,
        function: &'static str,
        name: &str,
        corruptions: Vec<Corruption<T>>,
        make: impl Fn(&Harness) -> Box<Padded<T>> + 'static,
        call: impl Fn(&mut Harness, &T) -> cg_status + 'static,
    ) {
        let corruptions = inside(
            corruptions,
            &format!("{name}."),
            |p: &mut Box<Padded<T>>| &mut p.value,
        );
        self.corrupt(Setup::Online, function, corruptions, make, move |h, p| {
            call(h, &p.value)
        });
    }

    /// The rows of a setter `set(crowd, character, &value)`: the crowd or the value NULL,
    /// every bad character id, and each corruption of the value (set on character 2).
    fn character_setter<T: 'static>(
        &mut self,
        function: &'static str,
        name: &'static str,
        corruptions: Vec<Corruption<T>>,
        make: fn(&Harness) -> Box<Padded<T>>,
        set: unsafe extern "C" fn(*mut cg_crowd, u32, *const T) -> cg_status,
    ) {
        self.case(function, "crowd NULL", NULL_ARG, move |h| unsafe {
            set(null_mut(), h.character(2), &make(h).value)
        });
        self.case(
            function,
            format!("{name} NULL"),
            NULL_ARG,
            move |h| unsafe { set(h.crowd, h.character(2), null()) },
        );
        self.character_ids(Setup::Online, function, move |h, id| unsafe {
            set(h.crowd, id, &make(h).value)
        });
        self.corrupt_struct(function, name, corruptions, make, move |h, value| unsafe {
            set(h.crowd, h.character(2), value)
        });
    }

    /// The rows of a conversion `call(values, out)` of `N` floats: either pointer NULL, NaN
    /// and infinities in each value, and the `corruptions`.
    fn float_array<const N: usize, O: 'static>(
        &mut self,
        function: &'static str,
        name: &'static str,
        make: fn(&Harness) -> [f32; N],
        mut corruptions: Vec<Corruption<[f32; N]>>,
        call: unsafe extern "C" fn(*const f32, *mut O) -> cg_status,
        out: fn(&mut Harness) -> *mut O,
    ) {
        self.case(
            function,
            format!("{name} NULL"),
            NULL_ARG,
            move |h| unsafe { call(null(), out(h)) },
        );
        self.case(function, "out NULL", NULL_ARG, move |h| unsafe {
            call(make(h).as_ptr(), null_mut())
        });
        corruptions.extend(non_finite(&float_elements(name, 0, N)));
        self.corrupt(
            Setup::Online,
            function,
            corruptions,
            make,
            move |h, values| unsafe { call(values.as_ptr(), out(h)) },
        );
    }

    /// One case per `(what, expected, value)`: `call(h, value)`.
    fn each<V: Copy + 'static>(
        &mut self,
        setup: Setup,
        function: &'static str,
        cases: Vec<(String, cg_status, V)>,
        call: impl Fn(&mut Harness, V) -> cg_status + 'static,
    ) {
        let call = Rc::new(call);
        for (what, expected, value) in cases {
            let call = call.clone();
            self.case_in(setup, function, what, expected, move |h| call(h, value));
        }
    }

    /// NaN, +∞ and −∞ as a plain float argument: `call(h, value)`.
    fn non_finite_argument(
        &mut self,
        setup: Setup,
        function: &'static str,
        what: &str,
        call: impl Fn(&mut Harness, f32) -> cg_status + 'static,
    ) {
        let cases = BAD_FLOATS
            .iter()
            .map(|&(label, value)| (format!("{what} = {label}"), NON_FINITE, value))
            .collect();
        self.each(setup, function, cases, call);
    }

    /// One case per id `pick` gives: `call(h, id)`.
    fn ids(
        &mut self,
        setup: Setup,
        function: &'static str,
        cases: Vec<(String, cg_status, Pick)>,
        call: impl Fn(&mut Harness, u32) -> cg_status + 'static,
    ) {
        self.each(setup, function, cases, move |h, pick: Pick| {
            let id = pick(h);
            call(h, id)
        });
    }

    /// The id cases of a function taking a character id: unknown, removed and
    /// `CG_NO_TARGET` ids are `CG_STATUS_NOT_FOUND`; an object's or the viewer's id
    /// `CG_STATUS_INVALID_ARGUMENT`.
    fn character_ids(
        &mut self,
        setup: Setup,
        function: &'static str,
        call: impl Fn(&mut Harness, u32) -> cg_status + 'static,
    ) {
        let cases: [(&str, cg_status, Pick); 5] = [
            ("unknown", NOT_FOUND, |_| UNKNOWN_ID),
            ("removed character's", NOT_FOUND, |h| h.removed_character),
            ("CG_NO_TARGET as", NOT_FOUND, |_| CG_NO_TARGET),
            ("an object's", INVALID, |h| h.object()),
            ("the viewer's", INVALID, |h| h.viewer.expect("a viewer")),
        ];
        let cases = cases
            .into_iter()
            .map(|(what, expected, pick)| (format!("{what} id as character"), expected, pick))
            .collect();
        self.ids(setup, function, cases, call);
    }

    /// The id cases of a function taking any entity's id: unknown, removed character,
    /// removed object and `CG_NO_TARGET` are `CG_STATUS_NOT_FOUND`.
    fn entity_ids(
        &mut self,
        setup: Setup,
        function: &'static str,
        name: &str,
        call: impl Fn(&mut Harness, u32) -> cg_status + 'static,
    ) {
        let cases: [(&str, Pick); 4] = [
            ("unknown", |_| UNKNOWN_ID),
            ("a removed character's", |h| h.removed_character),
            ("a removed object's", |h| h.removed_object),
            ("CG_NO_TARGET as", |_| CG_NO_TARGET),
        ];
        let cases = cases
            .into_iter()
            .map(|(what, pick)| (format!("{what} id as {name}"), NOT_FOUND, pick))
            .collect();
        self.ids(setup, function, cases, call);
    }

    fn no_failure_modes(&mut self, function: &'static str, why: &'static str, check: fn()) {
        let previous = self
            .rows
            .insert(function, Row::NoFailureModes { why, check });
        assert!(previous.is_none(), "{function} has two rows");
    }

    fn case_count(&self) -> usize {
        self.rows
            .values()
            .map(|row| match row {
                Row::Cases(cases) => cases.len(),
                Row::NoFailureModes { .. } => 0,
            })
            .sum()
    }
}

fn table() -> Table {
    let mut t = Table::default();
    rows_init(&mut t);
    rows_crowd(&mut t);
    rows_entities(&mut t);
    rows_frames(&mut t);
    rows_attention(&mut t);
    rows_steps(&mut t);
    rows_plan(&mut t);
    rows_gaze(&mut t);
    rows_joints(&mut t);
    rows_dual_quaternions(&mut t);
    rows_blends(&mut t);
    rows_view_blender(&mut t);
    rows_infallible(&mut t);
    t
}

// ---------------------------------------------------------------------------------------------
// Running a case

/// Fails a call with a message no case produces, so that a case that fails without
/// recording its own message is seen.
fn set_sentinel_error() -> String {
    let mut desc = MaybeUninit::<cg_chain_desc>::uninit();
    assert_eq!(
        unsafe { cg_chain_desc_init_human(desc.as_mut_ptr(), 4242, 4) },
        INVALID
    );
    last_error()
}

/// The start every message of a failure with `status` has ("not found: …").
fn message_prefix(status: cg_status) -> String {
    // SAFETY: cg_status_str returns a static NUL-terminated string.
    let text = unsafe { CStr::from_ptr(cg_status_str(status as u32)) };
    let text = text.to_str().expect("ASCII");
    text.split(" (").next().unwrap_or(text).to_owned()
}

/// Runs one case; returns its problems (none if it held).
fn run_case(
    header: &Header,
    function: &str,
    case: &Case,
    futures: &mut HashMap<Setup, Snapshot>,
) -> Vec<String> {
    let mut problems = Vec::new();
    if !header
        .documented(function)
        .contains(&(case.expected as u32))
    {
        problems.push(format!(
            "expects {}, which the header does not document for this function",
            header.status_name(case.expected)
        ));
    }
    let mut h = Harness::new(case.setup);
    let before = h.snapshot();
    let sentinel = set_sentinel_error();
    let got = (case.call)(&mut h);
    let message = last_error();
    let after = h.snapshot();
    if got != case.expected {
        problems.push(format!(
            "returned {} ({message:?}) instead of {}",
            header.status_name(got),
            header.status_name(case.expected)
        ));
    }
    if got != cg_status::Ok {
        if message == sentinel || message.is_empty() {
            problems.push("left no message for cg_last_error_message".into());
        } else if message.contains('\n') {
            problems.push(format!("message is not one line: {message:?}"));
        } else if !message.starts_with(&message_prefix(got)) {
            problems.push(format!("message {message:?} does not match its status"));
        }
    }
    let changed = before.differences(&after);
    if !changed.is_empty() {
        problems.push(format!("changed what these read: {}", changed.join(", ")));
    }
    let reference = futures
        .entry(case.setup)
        .or_insert_with(|| Harness::new(case.setup).future());
    let changed = h.future().differences(reference);
    if !changed.is_empty() {
        problems.push(format!(
            "changed the crowd's next frames or plan: {}",
            changed.join(", ")
        ));
    }
    problems.append(&mut h.problems);
    problems
        .into_iter()
        .map(|problem| format!("{function}: {} ({:?}): {problem}", case.what, case.setup))
        .collect()
}

#[test]
fn every_header_function_has_a_row() {
    let header = Header::read();
    let table = table();
    let missing: Vec<&str> = header
        .functions
        .keys()
        .map(String::as_str)
        .filter(|name| !table.rows.contains_key(name))
        .collect();
    assert!(
        missing.is_empty(),
        "functions of include/crowdgaze.h without a row in tests/bad_input.rs: {}; add their \
         bad-input cases (or a `no_failure_modes` entry saying why there are none)",
        missing.join(", ")
    );
    let stale: Vec<&&str> = table
        .rows
        .keys()
        .filter(|name| !header.functions.contains_key(**name))
        .collect();
    assert!(
        stale.is_empty(),
        "rows for functions the header does not declare: {stale:?}"
    );
    let empty: Vec<&&str> = table
        .rows
        .iter()
        .filter(|(_, row)| matches!(row, Row::Cases(cases) if cases.is_empty()))
        .map(|(name, _)| name)
        .collect();
    assert!(empty.is_empty(), "rows without cases: {empty:?}");
}

#[test]
fn bad_input_gets_its_documented_status_and_changes_nothing() {
    let header = Header::read();
    let table = table();
    let mut futures = HashMap::new();
    let mut failures = Vec::new();
    let mut by_status = BTreeMap::<&str, usize>::new();
    let mut infallible = Vec::new();
    for (function, row) in &table.rows {
        match row {
            Row::Cases(cases) => {
                for case in cases {
                    *by_status
                        .entry(header.status_name(case.expected))
                        .or_default() += 1;
                    failures.extend(run_case(&header, function, case, &mut futures));
                }
            }
            Row::NoFailureModes { why, check } => {
                check();
                infallible.push(format!("{function} ({why})"));
            }
        }
    }
    let cases = table.case_count();
    eprintln!(
        "bad-input matrix: {} functions, {cases} cases ({by_status:?}); without failure \
         modes: {}",
        table.rows.len(),
        infallible.join("; ")
    );
    assert!(
        failures.is_empty(),
        "{} problems in {cases} cases:\n{}",
        failures.len(),
        failures.join("\n")
    );
    assert!(
        cases >= CASE_FLOOR,
        "only {cases} cases ran, fewer than {CASE_FLOOR}: rows were lost"
    );
}

/// The oracle must see a change: successful calls that change the crowd or a blender change
/// its snapshot or its next frames.
#[test]
fn the_snapshots_see_every_kind_of_change() {
    type Change = fn(&mut Harness) -> cg_status;
    let changes: [(&str, Change); 14] = [
        ("set_impact", |h| unsafe {
            cg_crowd_set_impact(h.crowd, h.object(), 3.0)
        }),
        ("set_base_pose", |h| {
            let pose = [rotation([1.0, 0.0, 0.0], 0.1); 10];
            unsafe { cg_crowd_set_base_pose(h.crowd, h.character(0), pose.as_ptr(), 10) }
        }),
        ("set_gaze_target", |h| {
            let mut target: cg_gaze_target = init(cg_gaze_target_init);
            target.point = vec3(-4.0, 1.0, 0.0);
            unsafe { cg_crowd_set_gaze_target(h.crowd, h.character(3), &target) }
        }),
        ("clear_gaze_target", |h| unsafe {
            cg_crowd_clear_gaze_target(h.crowd, h.character(0))
        }),
        ("set_attention_period", |h| unsafe {
            cg_crowd_set_attention_period(h.crowd, h.character(0), 7)
        }),
        ("set_character_params", |h| {
            let mut params = params_of(h);
            params.value.attention_fraction = 0.9;
            unsafe { cg_crowd_set_character_params(h.crowd, h.character(0), &params.value) }
        }),
        ("push_frame", |h| {
            let (t, states) = h.next_frame();
            unsafe { cg_crowd_push_frame(h.crowd, t, states.as_ptr(), 1) }
        }),
        ("step", |h| unsafe { cg_crowd_step(h.crowd, 0.01) }),
        ("add_object", |h| {
            let desc: cg_object_desc = init(cg_object_desc_init);
            unsafe { cg_crowd_add_object(h.crowd, &desc, &mut h.out.id) }
        }),
        ("remove_entity", |h| unsafe {
            cg_crowd_remove_entity(h.crowd, h.object())
        }),
        ("set_viewer", |h| unsafe {
            cg_crowd_set_viewer(h.crowd, &vec3(0.0, 1.7, 5.0), 1.5, null_mut())
        }),
        ("add_camera", |h| unsafe {
            cg_view_blender_add_camera(h.blender, vec3(0.0, 1.0, 0.0), 1)
        }),
        ("set_key_pose", |h| {
            let pose = [IDENTITY_DQ; JOINTS];
            unsafe { cg_view_blender_set_key_pose(h.blender, 2, pose.as_ptr(), JOINTS) }
        }),
        ("write an output", |h| unsafe {
            cg_crowd_character_count(h.crowd, &mut h.out.count)
        }),
    ];
    let untouched = Harness::new(Setup::Online);
    let (snapshot, future) = (untouched.snapshot(), untouched.future());
    for (what, change) in changes {
        let mut h = Harness::new(Setup::Online);
        assert!(h.snapshot() == snapshot, "fixtures differ");
        ok(change(&mut h));
        let seen = !h.snapshot().differences(&snapshot).is_empty()
            || !h.future().differences(&future).is_empty();
        assert!(seen, "the snapshots did not see {what}");
    }
}

/// Two fixtures built alike are alike, and so are their futures (the reference the cases
/// are compared with).
#[test]
fn fixtures_are_deterministic() {
    for setup in [
        Setup::Online,
        Setup::Planned,
        Setup::Full,
        Setup::RecordingFull,
        Setup::Unrecorded,
    ] {
        let (a, b) = (Harness::new(setup), Harness::new(setup));
        assert!(a.snapshot() == b.snapshot(), "{setup:?}");
        assert!(a.future() == b.future(), "{setup:?}");
    }
}

// ---------------------------------------------------------------------------------------------
// Rows: the `_init` functions

fn rows_init(t: &mut Table) {
    t.case(
        "cg_character_desc_init",
        "desc NULL",
        NULL_ARG,
        |_| unsafe { cg_character_desc_init(null_mut()) },
    );
    t.case("cg_object_desc_init", "desc NULL", NULL_ARG, |_| unsafe {
        cg_object_desc_init(null_mut())
    });
    t.case("cg_entity_state_init", "state NULL", NULL_ARG, |_| unsafe {
        cg_entity_state_init(null_mut())
    });
    t.case("cg_gaze_target_init", "target NULL", NULL_ARG, |_| unsafe {
        cg_gaze_target_init(null_mut())
    });
    t.case(
        "cg_crowd_config_init",
        "config NULL",
        NULL_ARG,
        |_| unsafe { cg_crowd_config_init(null_mut()) },
    );
    t.case(
        "cg_view_blender_config_init",
        "config NULL",
        NULL_ARG,
        |_| unsafe { cg_view_blender_config_init(null_mut()) },
    );
    let f = "cg_chain_desc_init_human";
    t.case(f, "desc NULL", NULL_ARG, |_| unsafe {
        cg_chain_desc_init_human(null_mut(), 2, 4)
    });
    for (what, up, forward) in [
        ("up_axis 6", 6, 4),
        ("up_axis UINT32_MAX", u32::MAX, 4),
        ("forward_axis 6", 2, 6),
        ("forward_axis UINT32_MAX", 2, u32::MAX),
        ("up_axis = forward_axis", 2, 2),
        ("forward_axis = -up_axis", 2, 3),
        ("up_axis = -forward_axis", 5, 4),
    ] {
        t.case(f, what, INVALID, move |h| unsafe {
            cg_chain_desc_init_human(&mut h.out.chain, up, forward)
        });
    }
    bad_output_sizes(t, f, size_of::<cg_chain_desc>(), |_, out| unsafe {
        cg_chain_desc_init_human(out, 2, 4)
    });
    bad_output_sizes(
        t,
        "cg_character_desc_init",
        size_of::<cg_character_desc>(),
        |_, out| unsafe { cg_character_desc_init(out) },
    );
    bad_output_sizes(
        t,
        "cg_object_desc_init",
        size_of::<cg_object_desc>(),
        |_, out| unsafe { cg_object_desc_init(out) },
    );
    bad_output_sizes(
        t,
        "cg_entity_state_init",
        size_of::<cg_entity_state>(),
        |_, out| unsafe { cg_entity_state_init(out) },
    );
    bad_output_sizes(
        t,
        "cg_gaze_target_init",
        size_of::<cg_gaze_target>(),
        |_, out| unsafe { cg_gaze_target_init(out) },
    );
    bad_output_sizes(
        t,
        "cg_crowd_config_init",
        OLDER_CROWD_CONFIG,
        |_, out| unsafe { cg_crowd_config_init(out) },
    );
    let f = "cg_view_blender_config_init";
    bad_output_sizes(t, f, size_of::<cg_view_blender_config>(), |_, out| unsafe {
        cg_view_blender_config_init(out)
    });
}

// ---------------------------------------------------------------------------------------------
// Rows: the crowd handle

fn crowd_config_floats() -> Fields {
    floats!(cg_crowd_config: units_per_metre, max_distance, field_of_view, speed_weight,
        periphery_max_angle, min_interest_time, max_interest_time, interest_cooldown,
        threshold_warmup, initial_threshold, attention_fraction_min, attention_fraction_max,
        eyes_only_angle, eyes_head_neck_angle, head_speed, max_activation_time,
        restart_distance, min_deactivation_time, max_deactivation_time, eye_fixation_time,
        head_fixation_time, random_pick_probability, social_weight, proximity_radius,
        lod_distance)
}

/// Values of `cg_crowd_config` outside their documented ranges.
fn crowd_config_out_of_range() -> Vec<Corruption<cg_crowd_config>> {
    type C = cg_crowd_config;
    invalid::<C>(&[
        ("max_characters 0", |c| c.max_characters = 0),
        ("max_characters 2^24 + 1", |c| {
            c.max_characters = (1 << 24) + 1
        }),
        ("max_characters UINT32_MAX", |c| c.max_characters = u32::MAX),
        ("max_objects 2^24 + 1", |c| c.max_objects = (1 << 24) + 1),
        ("up_axis 6", |c| c.up_axis = 6),
        ("forward_axis UINT32_MAX", |c| c.forward_axis = u32::MAX),
        ("forward_axis = up_axis", |c| c.forward_axis = c.up_axis),
        ("forward_axis = -up_axis", |c| {
            c.forward_axis = cg_axis::NegativeY as u32
        }),
        ("units_per_metre 0", |c| c.units_per_metre = 0.0),
        ("units_per_metre -100", |c| c.units_per_metre = -100.0),
        ("max_distance -1", |c| c.max_distance = -1.0),
        ("field_of_view 0", |c| c.field_of_view = 0.0),
        ("field_of_view 7 (> 2π)", |c| c.field_of_view = 7.0),
        ("speed_weight -1", |c| c.speed_weight = -1.0),
        ("periphery_max_angle 4 (> π)", |c| {
            c.periphery_max_angle = 4.0
        }),
        ("min_interest_time -1", |c| c.min_interest_time = -1.0),
        ("max_interest_time < min_interest_time", |c| {
            c.max_interest_time = c.min_interest_time / 2.0
        }),
        ("interest_cooldown -1", |c| c.interest_cooldown = -1.0),
        ("threshold_warmup -1", |c| c.threshold_warmup = -1.0),
        ("initial_threshold -1", |c| c.initial_threshold = -1.0),
        ("attention_fraction_min -0.1", |c| {
            c.attention_fraction_min = -0.1
        }),
        ("attention_fraction_max 1.5", |c| {
            c.attention_fraction_max = 1.5
        }),
        ("attention_fraction_min > attention_fraction_max", |c| {
            c.attention_fraction_min = c.attention_fraction_max + 0.1
        }),
        ("eyes_only_angle -0.1", |c| c.eyes_only_angle = -0.1),
        ("eyes_head_neck_angle < eyes_only_angle", |c| {
            c.eyes_head_neck_angle = c.eyes_only_angle / 2.0
        }),
        ("head_speed 0", |c| c.head_speed = 0.0),
        ("max_activation_time -1", |c| c.max_activation_time = -1.0),
        ("restart_distance -1", |c| c.restart_distance = -1.0),
        ("min_deactivation_time -1", |c| {
            c.min_deactivation_time = -1.0
        }),
        ("max_deactivation_time < min_deactivation_time", |c| {
            c.max_deactivation_time = c.min_deactivation_time / 2.0
        }),
        ("eye_fixation_time 0", |c| c.eye_fixation_time = 0.0),
        ("head_fixation_time -1", |c| c.head_fixation_time = -1.0),
        ("random_pick_probability 1.5", |c| {
            c.random_pick_probability = 1.5
        }),
        ("social_weight -1", |c| c.social_weight = -1.0),
        ("proximity_radius -1", |c| c.proximity_radius = -1.0),
        ("attention_period 0", |c| c.attention_period = 0),
        ("attention_period 65", |c| c.attention_period = 65),
        ("lod_distance -1", |c| c.lod_distance = -1.0),
        ("far_attention_period 0", |c| c.far_attention_period = 0),
        ("far_attention_period 65", |c| c.far_attention_period = 65),
        ("threads 65", |c| c.threads = 65),
        ("threads UINT32_MAX", |c| c.threads = u32::MAX),
    ])
}

fn rows_crowd(t: &mut Table) {
    let f = "cg_crowd_create";
    t.case(f, "config NULL", NULL_ARG, |h| unsafe {
        cg_crowd_create(null(), &mut h.out.crowd)
    });
    t.case(f, "out_crowd NULL", NULL_ARG, |_| unsafe {
        cg_crowd_create(&init(cg_crowd_config_init), null_mut())
    });
    // Callers built before `reorder_period` existed pass the size without it, which is
    // accepted.
    let mut corruptions = struct_sizes_from::<cg_crowd_config>(OLDER_CROWD_CONFIG);
    corruptions.extend(non_finite(&crowd_config_floats()));
    corruptions.extend(crowd_config_out_of_range());
    t.corrupt_struct(
        f,
        "config",
        corruptions,
        |_| padded(init(cg_crowd_config_init)),
        |h, config| unsafe { cg_crowd_create(config, &mut h.out.crowd) },
    );

    let f = "cg_crowd_get_config";
    t.case(f, "crowd NULL", NULL_ARG, |h| unsafe {
        cg_crowd_get_config(null(), &mut h.out.crowd_config)
    });
    t.case(f, "out_config NULL", NULL_ARG, |h| unsafe {
        cg_crowd_get_config(h.crowd, null_mut())
    });
    bad_output_sizes(t, f, OLDER_CROWD_CONFIG, |h, out| unsafe {
        cg_crowd_get_config(h.crowd, out)
    });

    let f = "cg_crowd_character_count";
    t.case(f, "crowd NULL", NULL_ARG, |h| unsafe {
        cg_crowd_character_count(null(), &mut h.out.count)
    });
    t.case(f, "out_count NULL", NULL_ARG, |h| unsafe {
        cg_crowd_character_count(h.crowd, null_mut())
    });
}

// ---------------------------------------------------------------------------------------------
// Rows: characters and objects

/// A character description (and a chain it may point to), each with spare bytes after it.
struct CharacterInput {
    desc: Box<Padded<cg_character_desc>>,
    chain: Box<Padded<cg_chain_desc>>,
}

impl CharacterInput {
    fn new(with_chain: bool) -> CharacterInput {
        let mut desc: cg_character_desc = init(cg_character_desc_init);
        desc.position = vec3(-2.0, 0.0, -2.0);
        desc.heading = 0.4;
        let mut input = CharacterInput {
            desc: padded(desc),
            chain: padded(human_chain()),
        };
        if with_chain {
            input.desc.value.chain = &input.chain.value;
        }
        input
    }
}

fn chain_floats(joint_count: usize) -> Fields {
    let mut joint = nested("offset", offset_of!(cg_chain_joint, offset), vec3_fields());
    joint.extend(nested(
        "rest",
        offset_of!(cg_chain_joint, rest),
        quat_fields(),
    ));
    joint.extend(nested(
        "twist_axis",
        offset_of!(cg_chain_joint, twist_axis),
        vec3_fields(),
    ));
    joint.extend(floats!(cg_chain_joint: max_swing, min_twist, max_twist));
    let mut fields = elements::<cg_chain_joint>(
        "joints",
        offset_of!(cg_chain_desc, joints),
        joint_count,
        &joint,
    );
    for (name, offset) in [
        ("eye_forward", offset_of!(cg_chain_desc, eye_forward)),
        ("eye_up", offset_of!(cg_chain_desc, eye_up)),
        ("root_offset", offset_of!(cg_chain_desc, root_offset)),
    ] {
        fields.extend(nested(name, offset, vec3_fields()));
    }
    fields
}

/// Chains the header calls invalid: joint count, roles and their order, zero axes and
/// rotations, limits out of range.
fn invalid_chains() -> Vec<Corruption<cg_chain_desc>> {
    type C = cg_chain_desc;
    invalid::<C>(&[
        ("joint_count 0", |c| c.joint_count = 0),
        ("joint_count 16", |c| c.joint_count = 16),
        ("joint_count UINT32_MAX", |c| c.joint_count = u32::MAX),
        ("joint_count 9 (one eye)", |c| c.joint_count = 9),
        ("joints[3].role 5", |c| c.joints[3].role = 5),
        ("joints[3].role UINT32_MAX", |c| c.joints[3].role = u32::MAX),
        ("two heads", |c| {
            c.joints[3].role = cg_joint_role::Head as u32
        }),
        ("an eye below the head", |c| c.joints.swap(7, 8)),
        ("joints[2].rest zero", |c| c.joints[2].rest = ZERO_QUAT),
        ("joints[5].twist_axis zero", |c| {
            c.joints[5].twist_axis = vec3(0.0, 0.0, 0.0)
        }),
        ("joints[5].max_swing -0.1", |c| c.joints[5].max_swing = -0.1),
        ("joints[5].max_swing 4 (> π)", |c| {
            c.joints[5].max_swing = 4.0
        }),
        ("joints[5].min_twist -4 (< -π)", |c| {
            c.joints[5].min_twist = -4.0
        }),
        ("joints[5].max_twist 4 (> π)", |c| {
            c.joints[5].max_twist = 4.0
        }),
        ("joints[5].min_twist > max_twist", |c| {
            c.joints[5].min_twist = c.joints[5].max_twist + 0.1
        }),
        ("eye_forward zero", |c| c.eye_forward = vec3(0.0, 0.0, 0.0)),
        ("eye_up zero", |c| c.eye_up = vec3(0.0, 0.0, 0.0)),
        ("eye_up parallel to eye_forward", |c| {
            c.eye_up = c.eye_forward
        }),
        // Offsets longer than 1 km (a fuzzed 3e38 overflowed the eye positions).
        ("joints[0].offset.z 3e38", |c| c.joints[0].offset.z = 3e38),
        ("joints[8].offset 1001 m", |c| {
            c.joints[8].offset = vec3(1001.0, 0.0, 0.0)
        }),
        ("root_offset -FLT_MAX", |c| {
            c.root_offset = vec3(0.0, -f32::MAX, 0.0)
        }),
    ])
}

fn add_character(h: &mut Harness, input: &mut CharacterInput) -> cg_status {
    unsafe { cg_crowd_add_character(h.crowd, &input.desc.value, &mut h.out.id) }
}

fn add_object(h: &mut Harness, desc: &cg_object_desc) -> cg_status {
    unsafe { cg_crowd_add_object(h.crowd, desc, &mut h.out.id) }
}

fn new_object(_: &Harness) -> Box<Padded<cg_object_desc>> {
    let mut desc: cg_object_desc = init(cg_object_desc_init);
    desc.position = vec3(2.0, 0.0, 4.0);
    padded(desc)
}

fn rows_entities(t: &mut Table) {
    let f = "cg_crowd_add_character";
    t.case(f, "crowd NULL", NULL_ARG, |h| {
        let input = CharacterInput::new(false);
        unsafe { cg_crowd_add_character(null_mut(), &input.desc.value, &mut h.out.id) }
    });
    t.case(f, "desc NULL", NULL_ARG, |h| unsafe {
        cg_crowd_add_character(h.crowd, null(), &mut h.out.id)
    });
    t.case(f, "out_id NULL", NULL_ARG, |h| {
        let input = CharacterInput::new(false);
        unsafe { cg_crowd_add_character(h.crowd, &input.desc.value, null_mut()) }
    });
    type D = cg_character_desc;
    let mut desc = struct_sizes::<D>();
    desc.extend(non_finite(
        &floats!(D: heading, impact, position.x, position.y, position.z),
    ));
    desc.extend(invalid::<D>(&[
        ("impact -1", |d| d.impact = -1.0),
        ("impact 1e7 (> 1e6)", |d| d.impact = 1e7),
    ]));
    desc.extend(unknown_models::<D>(|d| &mut d.attention_model));
    t.corrupt(
        Setup::Online,
        f,
        inside(desc, "desc.", |i: &mut CharacterInput| &mut i.desc.value),
        |_| CharacterInput::new(false),
        add_character,
    );
    let mut chain = struct_sizes::<cg_chain_desc>();
    chain.extend(non_finite(&chain_floats(10)));
    chain.extend(invalid_chains());
    t.corrupt(
        Setup::Online,
        f,
        inside(chain, "desc.chain->", |i: &mut CharacterInput| {
            &mut i.chain.value
        }),
        |_| CharacterInput::new(true),
        add_character,
    );
    t.case_in(Setup::Full, f, "max_characters reached", CAPACITY, |h| {
        add_character(h, &mut CharacterInput::new(false))
    });
    t.case_in(
        Setup::Full,
        f,
        "max_characters reached, with a chain",
        CAPACITY,
        |h| add_character(h, &mut CharacterInput::new(true)),
    );
    t.case_in(Setup::Planned, f, "a plan is active", WRONG_STATE, |h| {
        add_character(h, &mut CharacterInput::new(false))
    });

    let f = "cg_crowd_add_object";
    t.case(f, "crowd NULL", NULL_ARG, |h| {
        let desc = new_object(h);
        unsafe { cg_crowd_add_object(null_mut(), &desc.value, &mut h.out.id) }
    });
    t.case(f, "desc NULL", NULL_ARG, |h| unsafe {
        cg_crowd_add_object(h.crowd, null(), &mut h.out.id)
    });
    t.case(f, "out_id NULL", NULL_ARG, |h| {
        let desc = new_object(h);
        unsafe { cg_crowd_add_object(h.crowd, &desc.value, null_mut()) }
    });
    type O = cg_object_desc;
    let mut desc = struct_sizes::<O>();
    desc.extend(non_finite(
        &floats!(O: heading, look_at_height, impact, position.x,
        position.y, position.z),
    ));
    desc.extend(invalid::<O>(&[
        ("impact -1", |d| d.impact = -1.0),
        ("impact 1e7 (> 1e6)", |d| d.impact = 1e7),
        ("look_at_height 1e7 (> 1e6)", |d| d.look_at_height = 1e7),
    ]));
    t.corrupt_struct(f, "desc", desc, new_object, add_object);
    t.case_in(Setup::Full, f, "max_objects reached", CAPACITY, |h| {
        let desc = new_object(h);
        add_object(h, &desc.value)
    });
    t.case_in(Setup::Planned, f, "a plan is active", WRONG_STATE, |h| {
        let desc = new_object(h);
        add_object(h, &desc.value)
    });

    let f = "cg_crowd_remove_entity";
    t.case(f, "crowd NULL", NULL_ARG, |h| unsafe {
        cg_crowd_remove_entity(null_mut(), h.character(0))
    });
    t.entity_ids(Setup::Online, f, "id", |h, id| unsafe {
        cg_crowd_remove_entity(h.crowd, id)
    });
    t.entity_ids(Setup::Planned, f, "id while planned", |h, id| unsafe {
        cg_crowd_remove_entity(h.crowd, id)
    });
    let live: [(&str, Pick); 3] = [
        ("a character", |h| h.character(1)),
        ("an object", |h| h.object()),
        ("the viewer", |h| h.viewer.expect("a viewer")),
    ];
    for (what, id) in live {
        t.case_in(
            Setup::Planned,
            f,
            format!("{what} while a plan is active"),
            WRONG_STATE,
            move |h| unsafe { cg_crowd_remove_entity(h.crowd, id(h)) },
        );
    }
}

// ---------------------------------------------------------------------------------------------
// Rows: frames and steps

/// Entities in a fixture's frame: four characters and two objects.
const MOVERS: usize = 6;

fn push(h: &mut Harness, states: &mut [cg_entity_state]) -> cg_status {
    let (t, _) = h.next_frame();
    unsafe { cg_crowd_push_frame(h.crowd, t, states.as_ptr(), states.len()) }
}

fn next_states(h: &Harness) -> Vec<cg_entity_state> {
    h.next_frame().1
}

/// Corruptions of the states of a frame, element by element.
fn frame_corruptions() -> Vec<Corruption<Vec<cg_entity_state>>> {
    type S = cg_entity_state;
    let mut out = Vec::new();
    for index in 0..MOVERS {
        let element = |name: String, expected, apply: Corrupt<S>| {
            change(
                format!("states[{index}].{name}"),
                expected,
                move |states: &mut Vec<S>| apply(&mut states[index]),
            )
        };
        let plain = floats!(S: heading, position.x, position.y, position.z);
        for c in non_finite::<S>(&plain) {
            out.push(element(c.what, c.expected, c.apply));
        }
        for c in non_finite::<S>(&floats!(S: velocity.x, velocity.y, velocity.z)) {
            let apply = c.apply;
            out.push(element(
                format!("{} with CG_STATE_HAS_VELOCITY", c.what),
                c.expected,
                Rc::new(move |s: &mut S| {
                    s.flags |= CG_STATE_HAS_VELOCITY;
                    apply(s)
                }),
            ));
        }
        out.push(element(
            "flags 4 (an unknown bit)".into(),
            INVALID,
            Rc::new(|s: &mut S| s.flags = 4),
        ));
        out.push(element(
            "flags UINT32_MAX".into(),
            INVALID,
            Rc::new(|s: &mut S| s.flags = u32::MAX),
        ));
        if index > 0 {
            for (what, size) in bad_sizes(size_of::<S>()) {
                out.push(element(
                    format!("struct_size {what}, unlike states[0]'s"),
                    BAD_SIZE,
                    Rc::new(move |s: &mut S| s.struct_size = size),
                ));
            }
        }
    }
    out.extend(inside(
        struct_sizes::<S>(),
        "states[0].",
        |s: &mut Vec<S>| &mut s[0],
    ));
    out
}

fn rows_frames(t: &mut Table) {
    let f = "cg_crowd_push_frame";
    t.case(f, "crowd NULL", NULL_ARG, |h| {
        let (time, states) = h.next_frame();
        unsafe { cg_crowd_push_frame(null_mut(), time, states.as_ptr(), states.len()) }
    });
    t.case(f, "(states NULL, count 6)", NULL_ARG, |h| {
        let (time, _) = h.next_frame();
        unsafe { cg_crowd_push_frame(h.crowd, time, null(), MOVERS) }
    });
    for (label, value) in [
        ("NaN", f64::NAN),
        ("+Inf", f64::INFINITY),
        ("-Inf", f64::NEG_INFINITY),
    ] {
        t.case(f, format!("t = {label}"), NON_FINITE, move |h| {
            let states = next_states(h);
            unsafe { cg_crowd_push_frame(h.crowd, value, states.as_ptr(), states.len()) }
        });
    }
    t.case(f, "t earlier than the previous frame's", INVALID, |h| {
        let states = h.frame_at(h.time);
        unsafe { cg_crowd_push_frame(h.crowd, h.time - 0.5, states.as_ptr(), states.len()) }
    });
    t.case(
        f,
        "t earlier than the previous frame's, no states",
        INVALID,
        |h| unsafe { cg_crowd_push_frame(h.crowd, h.time - 1e-3, null(), 0) },
    );
    t.corrupt(
        Setup::Online,
        f,
        frame_corruptions(),
        next_states,
        |h, s| push(h, s),
    );
    for index in 0..MOVERS {
        t.entity_ids(
            Setup::Online,
            f,
            &format!("states[{index}].id"),
            move |h, id| {
                let mut states = next_states(h);
                states[index].id = id;
                push(h, &mut states)
            },
        );
    }
    for (what, count) in [
        ("count SIZE_MAX", usize::MAX),
        ("count × struct_size overflowing", usize::MAX / 8),
    ] {
        t.case(f, what, INVALID, move |h| {
            let (time, states) = h.next_frame();
            unsafe { cg_crowd_push_frame(h.crowd, time, states.as_ptr(), count) }
        });
    }
    t.case_in(
        Setup::RecordingFull,
        f,
        "the recording is full",
        CAPACITY,
        |h| {
            let mut states = next_states(h);
            push(h, &mut states)
        },
    );
    t.case_in(Setup::Planned, f, "a plan is active", WRONG_STATE, |h| {
        let mut states = next_states(h);
        push(h, &mut states)
    });
    t.case_in(
        Setup::Planned,
        f,
        "a plan is active, no states",
        WRONG_STATE,
        |h| {
            let (time, _) = h.next_frame();
            unsafe { cg_crowd_push_frame(h.crowd, time, null(), 0) }
        },
    );

    let f = "cg_crowd_step";
    t.case(f, "crowd NULL", NULL_ARG, |_| unsafe {
        cg_crowd_step(null_mut(), 0.1)
    });
    t.non_finite_argument(Setup::Online, f, "dt", |h, dt| unsafe {
        cg_crowd_step(h.crowd, dt)
    });
    t.non_finite_argument(Setup::Planned, f, "dt while planned", |h, dt| unsafe {
        cg_crowd_step(h.crowd, dt)
    });
    for (what, dt) in [
        ("dt -1", -1.0),
        ("dt -1e-30", -1e-30),
        ("dt -FLT_MAX", f32::MIN),
    ] {
        t.case(f, what, INVALID, move |h| unsafe {
            cg_crowd_step(h.crowd, dt)
        });
    }
}

/// The ranged step's entry points, on a crowd with no step open. (The misuse that needs an
/// open step — a second begin, overlapping ranges, every other call meanwhile — is in
/// `tests/threads.rs`, which compares the crowd with an untouched one afterwards.)
fn rows_steps(t: &mut Table) {
    let f = "cg_crowd_begin_step";
    t.case(f, "crowd NULL", NULL_ARG, |_| unsafe {
        cg_crowd_begin_step(null_mut(), 0.1)
    });
    t.non_finite_argument(Setup::Online, f, "dt", |h, dt| unsafe {
        cg_crowd_begin_step(h.crowd, dt)
    });
    t.non_finite_argument(Setup::Planned, f, "dt while planned", |h, dt| unsafe {
        cg_crowd_begin_step(h.crowd, dt)
    });
    for (what, dt) in [("dt -1", -1.0), ("dt -FLT_MAX", f32::MIN)] {
        t.case(f, what, INVALID, move |h| unsafe {
            cg_crowd_begin_step(h.crowd, dt)
        });
    }

    let f = "cg_crowd_step_range";
    t.case(f, "crowd NULL", NULL_ARG, |_| unsafe {
        cg_crowd_step_range(null_mut(), 0, 1)
    });
    for (what, first, count) in [
        ("no step open", 0, 1),
        ("no step open, count 0", 0, 0),
        ("no step open, range past the end", 0, u32::MAX),
        ("no step open, first UINT32_MAX", u32::MAX, u32::MAX),
    ] {
        t.case(f, what, WRONG_STATE, move |h| unsafe {
            cg_crowd_step_range(h.crowd, first, count)
        });
    }

    let f = "cg_crowd_end_step";
    t.case(f, "crowd NULL", NULL_ARG, |_| unsafe {
        cg_crowd_end_step(null_mut())
    });
    t.case(f, "no step open", WRONG_STATE, |h| unsafe {
        cg_crowd_end_step(h.crowd)
    });
    t.case_in(
        Setup::Planned,
        f,
        "no step open while planned",
        WRONG_STATE,
        |h| unsafe { cg_crowd_end_step(h.crowd) },
    );
}

// ---------------------------------------------------------------------------------------------
// Rows: attention

fn params_of(h: &Harness) -> Box<Padded<cg_character_params>> {
    let mut params = [sized::<cg_character_params>()];
    ok(unsafe { cg_crowd_get_character_params(h.crowd, h.character(0), params.as_mut_ptr()) });
    params[0].attention_fraction = 0.5;
    padded(params[0])
}

fn rows_attention(t: &mut Table) {
    let f = "cg_crowd_read_gaze";
    t.case(f, "crowd NULL", NULL_ARG, |h| unsafe {
        cg_crowd_read_gaze(null(), h.out.gaze.as_mut_ptr(), 8, &mut h.out.count)
    });
    t.case(f, "(out NULL, count 2)", NULL_ARG, |h| unsafe {
        cg_crowd_read_gaze(h.crowd, null_mut(), 2, &mut h.out.count)
    });
    t.case(f, "count SIZE_MAX", INVALID, |h| unsafe {
        cg_crowd_read_gaze(
            h.crowd,
            h.out.gaze.as_mut_ptr(),
            usize::MAX,
            &mut h.out.count,
        )
    });

    let f = "cg_crowd_score";
    t.case(f, "crowd NULL", NULL_ARG, |h| {
        let (a, b) = (h.character(0), h.character(1));
        unsafe { cg_crowd_score(null(), a, b, &mut h.out.score) }
    });
    t.case(f, "out NULL", NULL_ARG, |h| unsafe {
        cg_crowd_score(h.crowd, h.character(0), h.character(1), null_mut())
    });
    t.character_ids(Setup::Online, f, |h, id| {
        let entity = h.character(1);
        unsafe { cg_crowd_score(h.crowd, id, entity, &mut h.out.score) }
    });
    t.entity_ids(Setup::Online, f, "entity", |h, id| {
        let character = h.character(0);
        unsafe { cg_crowd_score(h.crowd, character, id, &mut h.out.score) }
    });

    let f = "cg_crowd_get_character_params";
    t.case(f, "crowd NULL", NULL_ARG, |h| {
        let id = h.character(0);
        unsafe { cg_crowd_get_character_params(null(), id, &mut h.out.params) }
    });
    t.case(f, "out_params NULL", NULL_ARG, |h| unsafe {
        cg_crowd_get_character_params(h.crowd, h.character(0), null_mut())
    });
    t.character_ids(Setup::Online, f, |h, id| unsafe {
        cg_crowd_get_character_params(h.crowd, id, &mut h.out.params)
    });
    bad_output_sizes(t, f, size_of::<cg_character_params>(), |h, out| unsafe {
        cg_crowd_get_character_params(h.crowd, h.character(0), out)
    });

    let f = "cg_crowd_set_character_params";
    type P = cg_character_params;
    let mut params = struct_sizes::<P>();
    let weights = floats!(P: weight_proximity, weight_speed, weight_orientation,
        weight_periphery);
    params.extend(non_finite(&weights));
    params.extend(non_finite(&floats!(P: attention_fraction)));
    for (field, offset) in weights {
        params.push(change(
            format!("{field} -0.1"),
            INVALID,
            move |p: &mut P| poke(p, offset, -0.1),
        ));
    }
    params.extend(invalid::<P>(&[
        ("all weights 0", |p| {
            (p.weight_proximity, p.weight_speed) = (0.0, 0.0);
            (p.weight_orientation, p.weight_periphery) = (0.0, 0.0);
        }),
        ("attention_fraction -0.1", |p| p.attention_fraction = -0.1),
        ("attention_fraction 1.1", |p| p.attention_fraction = 1.1),
    ]));
    params.extend(unknown_models::<P>(|p| &mut p.attention_model));
    t.character_setter(
        f,
        "params",
        params,
        params_of,
        cg_crowd_set_character_params,
    );

    let f = "cg_crowd_set_impact";
    t.case(f, "crowd NULL", NULL_ARG, |h| unsafe {
        cg_crowd_set_impact(null_mut(), h.object(), 1.0)
    });
    t.entity_ids(Setup::Online, f, "entity", |h, id| unsafe {
        cg_crowd_set_impact(h.crowd, id, 1.0)
    });
    let entities: [(&str, Pick); 3] = [
        ("a character's", |h| h.character(2)),
        ("an object's", |h| h.object()),
        ("the viewer's", |h| h.viewer.expect("a viewer")),
    ];
    for (what, id) in entities {
        t.non_finite_argument(
            Setup::Online,
            f,
            &format!("{what} impact"),
            move |h, v| unsafe { cg_crowd_set_impact(h.crowd, id(h), v) },
        );
        for (label, impact) in [
            ("-1", -1.0),
            ("-FLT_MIN", -f32::MIN_POSITIVE),
            ("1e7 (> 1e6)", 1e7),
        ] {
            t.case(
                f,
                format!("{what} impact {label}"),
                INVALID,
                move |h| unsafe { cg_crowd_set_impact(h.crowd, id(h), impact) },
            );
        }
    }

    let f = "cg_crowd_set_viewer";
    t.case(f, "crowd NULL", NULL_ARG, |h| unsafe {
        cg_crowd_set_viewer(null_mut(), &vec3(0.0, 1.7, 3.0), 1.0, &mut h.out.id)
    });
    for setup in [Setup::Online, Setup::Unrecorded] {
        let moving = if setup == Setup::Online {
            "moving the viewer"
        } else {
            "adding the viewer"
        };
        t.case_in(
            setup,
            f,
            format!("position NULL, {moving}"),
            NULL_ARG,
            |h| unsafe { cg_crowd_set_viewer(h.crowd, null(), 1.0, &mut h.out.id) },
        );
        t.corrupt(
            setup,
            f,
            inside(
                non_finite(&vec3_fields()),
                &format!("{moving}: position."),
                |p| p,
            ),
            |_| vec3(0.0, 1.7, 3.0),
            |h, position| unsafe { cg_crowd_set_viewer(h.crowd, position, 1.0, &mut h.out.id) },
        );
        t.non_finite_argument(setup, f, &format!("{moving}: impact"), |h, impact| unsafe {
            cg_crowd_set_viewer(h.crowd, &vec3(0.0, 1.7, 3.0), impact, &mut h.out.id)
        });
        for (label, impact) in [("-1", -1.0), ("1e7 (> 1e6)", 1e7)] {
            t.case_in(
                setup,
                f,
                format!("{moving}: impact {label}"),
                INVALID,
                move |h| unsafe {
                    cg_crowd_set_viewer(h.crowd, &vec3(0.0, 1.7, 3.0), impact, &mut h.out.id)
                },
            );
        }
    }
    t.case_in(
        Setup::Planned,
        f,
        "a plan is active",
        WRONG_STATE,
        |h| unsafe { cg_crowd_set_viewer(h.crowd, &vec3(0.0, 1.7, 3.0), 1.0, &mut h.out.id) },
    );

    let f = "cg_crowd_set_attention_period";
    t.case(f, "crowd NULL", NULL_ARG, |h| unsafe {
        cg_crowd_set_attention_period(null_mut(), h.character(0), 2)
    });
    t.character_ids(Setup::Online, f, |h, id| unsafe {
        cg_crowd_set_attention_period(h.crowd, id, 2)
    });
    for (what, period) in [("period 65", 65), ("period UINT32_MAX", u32::MAX)] {
        t.case(f, what, INVALID, move |h| unsafe {
            cg_crowd_set_attention_period(h.crowd, h.character(0), period)
        });
    }
}

// ---------------------------------------------------------------------------------------------
// Rows: offline planning

fn rows_plan(t: &mut Table) {
    let f = "cg_crowd_plan";
    t.case(f, "crowd NULL", NULL_ARG, |_| unsafe {
        cg_crowd_plan(null_mut())
    });
    t.case_in(
        Setup::Unrecorded,
        f,
        "nothing recorded (max_recorded_states 0)",
        WRONG_STATE,
        |h| unsafe { cg_crowd_plan(h.crowd) },
    );
    t.case_in(
        Setup::Planned,
        f,
        "already planned",
        WRONG_STATE,
        |h| unsafe { cg_crowd_plan(h.crowd) },
    );

    let f = "cg_crowd_clear_plan";
    t.case(f, "crowd NULL", NULL_ARG, |_| unsafe {
        cg_crowd_clear_plan(null_mut())
    });

    let f = "cg_crowd_read_constraints";
    t.case_in(Setup::Planned, f, "crowd NULL", NULL_ARG, |h| {
        let id = h.character(0);
        unsafe {
            cg_crowd_read_constraints(
                null(),
                id,
                h.out.constraints.as_mut_ptr(),
                8,
                &mut h.out.count,
            )
        }
    });
    t.case_in(
        Setup::Planned,
        f,
        "(out NULL, count 2)",
        NULL_ARG,
        |h| unsafe {
            cg_crowd_read_constraints(h.crowd, h.character(0), null_mut(), 2, &mut h.out.count)
        },
    );
    t.case_in(Setup::Planned, f, "count SIZE_MAX", INVALID, |h| {
        let id = h.character(0);
        let out = h.out.constraints.as_mut_ptr();
        unsafe { cg_crowd_read_constraints(h.crowd, id, out, usize::MAX, &mut h.out.count) }
    });
    t.character_ids(Setup::Planned, f, |h, id| {
        let out = h.out.constraints.as_mut_ptr();
        unsafe { cg_crowd_read_constraints(h.crowd, id, out, 8, &mut h.out.count) }
    });
    for setup in [Setup::Online, Setup::Unrecorded] {
        t.case_in(setup, f, "no plan", WRONG_STATE, |h| {
            let id = h.character(0);
            let out = h.out.constraints.as_mut_ptr();
            unsafe { cg_crowd_read_constraints(h.crowd, id, out, 8, &mut h.out.count) }
        });
    }
}

// ---------------------------------------------------------------------------------------------
// Rows: explicit gaze targets and base poses

fn point_target(_: &Harness) -> Box<Padded<cg_gaze_target>> {
    let mut target: cg_gaze_target = init(cg_gaze_target_init);
    target.point = vec3(-2.0, 1.6, 5.0);
    padded(target)
}

fn entity_target(h: &Harness, entity: u32) -> Box<Padded<cg_gaze_target>> {
    let mut target = point_target(h);
    target.value.kind = CG_GAZE_TARGET_ENTITY;
    target.value.entity = entity;
    target
}

/// Joint rotations for characters 0 (10 joints) and 1 (8 joints), packed.
const POSES_JOINTS: usize = 18;

fn rows_gaze(t: &mut Table) {
    let f = "cg_crowd_set_gaze_target";
    t.entity_ids(Setup::Online, f, "target entity", |h, id| {
        let target = entity_target(h, id);
        unsafe { cg_crowd_set_gaze_target(h.crowd, h.character(2), &target.value) }
    });
    t.case(f, "the character itself as target entity", INVALID, |h| {
        let target = entity_target(h, h.character(2));
        unsafe { cg_crowd_set_gaze_target(h.crowd, h.character(2), &target.value) }
    });
    type G = cg_gaze_target;
    let mut target = struct_sizes::<G>();
    target.extend(non_finite(&floats!(G: point.x, point.y, point.z)));
    target.extend(invalid::<G>(&[
        ("kind 2", |g| g.kind = 2),
        ("kind UINT32_MAX", |g| g.kind = u32::MAX),
        ("priority 2", |g| g.priority = 2),
        ("priority UINT32_MAX", |g| g.priority = u32::MAX),
    ]));
    t.character_setter(f, "target", target, point_target, cg_crowd_set_gaze_target);

    let f = "cg_crowd_clear_gaze_target";
    t.case(f, "crowd NULL", NULL_ARG, |h| unsafe {
        cg_crowd_clear_gaze_target(null_mut(), h.character(0))
    });
    t.character_ids(Setup::Online, f, |h, id| unsafe {
        cg_crowd_clear_gaze_target(h.crowd, id)
    });

    let f = "cg_crowd_set_base_pose";
    t.case(f, "crowd NULL", NULL_ARG, |h| unsafe {
        cg_crowd_set_base_pose(null_mut(), h.character(0), base_pose().as_ptr(), 10)
    });
    t.case(f, "(local NULL, count 10)", NULL_ARG, |h| unsafe {
        cg_crowd_set_base_pose(h.crowd, h.character(0), null(), 10)
    });
    t.case(f, "(local NULL, count 0)", INVALID, |h| unsafe {
        cg_crowd_set_base_pose(h.crowd, h.character(0), null(), 0)
    });
    t.character_ids(Setup::Online, f, |h, id| unsafe {
        cg_crowd_set_base_pose(h.crowd, id, base_pose().as_ptr(), 10)
    });
    let mut pose =
        non_finite::<[cg_quat; 10]>(&elements::<cg_quat>("local", 0, 10, &quat_fields()));
    pose.push(change("local[3] zero", INVALID, |p: &mut [cg_quat; 10]| {
        p[3] = ZERO_QUAT
    }));
    t.corrupt(
        Setup::Online,
        f,
        pose,
        |_| base_pose(),
        |h, pose| unsafe { cg_crowd_set_base_pose(h.crowd, h.character(0), pose.as_ptr(), 10) },
    );
    for (what, count) in [
        ("count 9 (the chain has 10)", 9),
        ("count 11 (the chain has 10)", 11),
        ("count 16 (above CG_MAX_CHAIN_JOINTS)", 16),
        ("count SIZE_MAX", usize::MAX),
    ] {
        t.case(f, what, INVALID, move |h| {
            let pose = [cg_quat::IDENTITY; 16];
            unsafe { cg_crowd_set_base_pose(h.crowd, h.character(0), pose.as_ptr(), count) }
        });
    }
    t.case(f, "10 rotations for a chain of 8", INVALID, |h| unsafe {
        cg_crowd_set_base_pose(h.crowd, h.character(1), base_pose().as_ptr(), 10)
    });

    let f = "cg_crowd_set_base_poses";
    let two = |h: &Harness| [h.character(0), h.character(1)];
    t.case(f, "crowd NULL", NULL_ARG, move |h| {
        let local = [cg_quat::IDENTITY; POSES_JOINTS];
        unsafe {
            cg_crowd_set_base_poses(null_mut(), two(h).as_ptr(), 2, local.as_ptr(), POSES_JOINTS)
        }
    });
    t.case(f, "(characters NULL, count 2)", NULL_ARG, |h| {
        let local = [cg_quat::IDENTITY; POSES_JOINTS];
        unsafe { cg_crowd_set_base_poses(h.crowd, null(), 2, local.as_ptr(), POSES_JOINTS) }
    });
    t.case(f, "(local NULL, count 18)", NULL_ARG, move |h| unsafe {
        cg_crowd_set_base_poses(h.crowd, two(h).as_ptr(), 2, null(), POSES_JOINTS)
    });
    t.character_ids(Setup::Online, f, move |h, id| {
        let ids = [h.character(0), id];
        let local = [cg_quat::IDENTITY; POSES_JOINTS];
        unsafe { cg_crowd_set_base_poses(h.crowd, ids.as_ptr(), 2, local.as_ptr(), POSES_JOINTS) }
    });
    let mut poses = non_finite::<[cg_quat; POSES_JOINTS]>(&elements::<cg_quat>(
        "local",
        0,
        POSES_JOINTS,
        &quat_fields(),
    ));
    poses.push(change(
        "local[12] zero",
        INVALID,
        |p: &mut [cg_quat; POSES_JOINTS]| p[12] = ZERO_QUAT,
    ));
    t.corrupt(
        Setup::Online,
        f,
        poses,
        |_| [rotation([1.0, 0.0, 0.0], 0.05); POSES_JOINTS],
        move |h, local| unsafe {
            cg_crowd_set_base_poses(h.crowd, two(h).as_ptr(), 2, local.as_ptr(), POSES_JOINTS)
        },
    );
    for (what, count) in [
        ("local_count 17 (the chains have 18)", POSES_JOINTS - 1),
        ("local_count 19 (the chains have 18)", POSES_JOINTS + 1),
        ("local_count SIZE_MAX", usize::MAX),
    ] {
        t.case(f, what, INVALID, move |h| {
            let local = [cg_quat::IDENTITY; POSES_JOINTS + 1];
            unsafe { cg_crowd_set_base_poses(h.crowd, two(h).as_ptr(), 2, local.as_ptr(), count) }
        });
    }
    t.case(f, "character_count SIZE_MAX", INVALID, move |h| {
        let local = [cg_quat::IDENTITY; POSES_JOINTS];
        let ids = two(h);
        unsafe {
            cg_crowd_set_base_poses(
                h.crowd,
                ids.as_ptr(),
                usize::MAX,
                local.as_ptr(),
                POSES_JOINTS,
            )
        }
    });
}

// ---------------------------------------------------------------------------------------------
// Rows: reading joints and eyes

type ReadQuats = unsafe extern "C" fn(*const cg_crowd, u32, u32, *mut cg_quat, usize) -> cg_status;

/// Characters 0 .. 4 have 10 + 8 + 10 + 10 joints.
const ALL_JOINTS: usize = 38;

fn rows_read_joints(t: &mut Table, f: &'static str, read: ReadQuats) {
    t.case(f, "crowd NULL", NULL_ARG, move |h| unsafe {
        read(null(), 0, 4, h.out.quats.as_mut_ptr(), 64)
    });
    t.case(f, "(out NULL, out_len 38)", NULL_ARG, move |h| unsafe {
        read(h.crowd, 0, 4, null_mut(), ALL_JOINTS)
    });
    for (what, first, count, out_len) in [
        ("first 5 past the last character", 5, 0, 64),
        ("first 4, count 1 past the last character", 4, 1, 64),
        ("count 5 of 4 characters", 0, 5, 64),
        ("first UINT32_MAX, count 2 (overflowing)", u32::MAX, 2, 64),
        ("first 1, count UINT32_MAX (overflowing)", 1, u32::MAX, 64),
        ("out_len 37 for 38 joints", 0, 4, ALL_JOINTS - 1),
        ("out_len 0 for 10 joints", 0, 1, 0),
        ("out_len SIZE_MAX", 0, 4, usize::MAX),
    ] {
        t.case(f, what, INVALID, move |h| unsafe {
            read(h.crowd, first, count, h.out.quats.as_mut_ptr(), out_len)
        });
    }
}

fn rows_joints(t: &mut Table) {
    let f = "cg_crowd_joint_total";
    t.case(f, "crowd NULL", NULL_ARG, |h| unsafe {
        cg_crowd_joint_total(null(), 0, 4, &mut h.out.count)
    });
    t.case(f, "out_total NULL", NULL_ARG, |h| unsafe {
        cg_crowd_joint_total(h.crowd, 0, 4, null_mut())
    });
    for (what, first, count) in [
        ("first 5 past the last character", 5, 0),
        ("count 5 of 4 characters", 0, 5),
        ("first UINT32_MAX, count UINT32_MAX", u32::MAX, u32::MAX),
    ] {
        t.case(f, what, INVALID, move |h| unsafe {
            cg_crowd_joint_total(h.crowd, first, count, &mut h.out.count)
        });
    }
    rows_read_joints(t, "cg_crowd_read_joints", cg_crowd_read_joints);
    rows_read_joints(t, "cg_crowd_read_joint_deltas", cg_crowd_read_joint_deltas);

    let f = "cg_crowd_read_eyes";
    t.case(f, "crowd NULL", NULL_ARG, |h| unsafe {
        cg_crowd_read_eyes(null(), 0, 4, h.out.eyes.as_mut_ptr(), 8)
    });
    t.case(f, "(out NULL, out_len 4)", NULL_ARG, |h| unsafe {
        cg_crowd_read_eyes(h.crowd, 0, 4, null_mut(), 4)
    });
    for (what, first, count, out_len) in [
        ("first 5 past the last character", 5, 0, 8),
        ("count 5 of 4 characters", 0, 5, 8),
        ("first UINT32_MAX, count 2 (overflowing)", u32::MAX, 2, 8),
        ("out_len 3 for 4 characters", 0, 4, 3),
        ("out_len SIZE_MAX", 0, 4, usize::MAX),
    ] {
        t.case(f, what, INVALID, move |h| unsafe {
            cg_crowd_read_eyes(h.crowd, first, count, h.out.eyes.as_mut_ptr(), out_len)
        });
    }
}

// ---------------------------------------------------------------------------------------------
// Rows: dual quaternions and the camera centre

#[repr(C)]
#[derive(Clone, Copy)]
struct RotationTranslation {
    rotation: cg_quat,
    translation: cg_vec3,
}

fn a_transform(_: &Harness) -> cg_dualquat {
    transform([0.0, 0.6, 0.8], 0.9, [1.0, -2.0, 0.5])
}

fn a_matrix(h: &Harness) -> [f32; 16] {
    let mut matrix = [0.0f32; 16];
    ok(unsafe { cg_dualquat_to_matrix(&a_transform(h), matrix.as_mut_ptr()) });
    matrix
}

/// `P = [I | −C]` for the camera centre C = (1, 2, 3), row-major.
fn a_projection(_: &Harness) -> [f32; 12] {
    [
        1.0, 0.0, 0.0, -1.0, //
        0.0, 1.0, 0.0, -2.0, //
        0.0, 0.0, 1.0, -3.0,
    ]
}

fn rows_dual_quaternions(t: &mut Table) {
    let f = "cg_dualquat_from_rt";
    let rt = |_: &Harness| RotationTranslation {
        rotation: rotation([1.0, 0.0, 0.0], 0.3),
        translation: vec3(1.0, 2.0, 3.0),
    };
    t.case(f, "rotation NULL", NULL_ARG, |h| unsafe {
        cg_dualquat_from_rt(null(), &vec3(1.0, 2.0, 3.0), &mut h.out.dual_quat)
    });
    t.case(f, "translation NULL", NULL_ARG, |h| unsafe {
        cg_dualquat_from_rt(&cg_quat::IDENTITY, null(), &mut h.out.dual_quat)
    });
    t.case(f, "out NULL", NULL_ARG, |_| unsafe {
        cg_dualquat_from_rt(&cg_quat::IDENTITY, &vec3(1.0, 2.0, 3.0), null_mut())
    });
    type Rt = RotationTranslation;
    let mut corruptions =
        non_finite::<Rt>(&nested("rotation", offset_of!(Rt, rotation), quat_fields()));
    corruptions.extend(non_finite::<Rt>(&nested(
        "translation",
        offset_of!(Rt, translation),
        vec3_fields(),
    )));
    corruptions.push(change("rotation zero", INVALID, |v: &mut Rt| {
        v.rotation = ZERO_QUAT
    }));
    corruptions.push(change("rotation of length 1e-9", INVALID, |v: &mut Rt| {
        v.rotation = cg_quat {
            w: 1e-9,
            ..ZERO_QUAT
        }
    }));
    t.corrupt(Setup::Online, f, corruptions, rt, |h, v| unsafe {
        cg_dualquat_from_rt(&v.rotation, &v.translation, &mut h.out.dual_quat)
    });

    let f = "cg_dualquat_to_rt";
    t.case(f, "dual_quat NULL", NULL_ARG, |h| unsafe {
        cg_dualquat_to_rt(null(), &mut h.out.quat, &mut h.out.vec3)
    });
    t.case(f, "out_rotation NULL", NULL_ARG, |h| unsafe {
        cg_dualquat_to_rt(&a_transform(h), null_mut(), &mut h.out.vec3)
    });
    t.case(f, "out_translation NULL", NULL_ARG, |h| unsafe {
        cg_dualquat_to_rt(&a_transform(h), &mut h.out.quat, null_mut())
    });
    t.corrupt(
        Setup::Online,
        f,
        dualquat_corruptions("dual_quat"),
        a_transform,
        |h, q| unsafe { cg_dualquat_to_rt(q, &mut h.out.quat, &mut h.out.vec3) },
    );

    let f = "cg_dualquat_to_matrix";
    t.case(f, "dual_quat NULL", NULL_ARG, |h| unsafe {
        cg_dualquat_to_matrix(null(), h.out.matrix.as_mut_ptr())
    });
    t.case(f, "out NULL", NULL_ARG, |h| unsafe {
        cg_dualquat_to_matrix(&a_transform(h), null_mut())
    });
    t.corrupt(
        Setup::Online,
        f,
        dualquat_corruptions("dual_quat"),
        a_transform,
        |h, q| unsafe { cg_dualquat_to_matrix(q, h.out.matrix.as_mut_ptr()) },
    );

    let bad = invalid::<[f32; 16]>(&[
        ("a scale of 2", |m| {
            m[..12].iter_mut().for_each(|v| *v *= 2.0)
        }),
        ("a shear", |m| m[4] += 0.5),
        ("a reflection", |m| m[..4].iter_mut().for_each(|v| *v = -*v)),
        ("a projection row", |m| m[3] = 0.1),
        ("all zero", |m| *m = [0.0; 16]),
    ]);
    let f = "cg_dualquat_from_matrix";
    t.float_array(f, "matrix", a_matrix, bad, cg_dualquat_from_matrix, |h| {
        &mut h.out.dual_quat
    });
    let bad = invalid::<[f32; 12]>(&[
        ("all zero", |p| *p = [0.0; 12]),
        ("an affine camera (last row 0 0 0 1)", |p| {
            p[8..].copy_from_slice(&[0.0, 0.0, 0.0, 1.0])
        }),
        ("rank 2 (two equal rows)", |p| p.copy_within(0..4, 4)),
        ("a centre too far for a float", |p| {
            p[3] = 1e30;
            p[0] = 1e-12;
        }),
    ]);
    let f = "cg_camera_center_from_projection";
    let centre = cg_camera_center_from_projection;
    t.float_array(f, "projection", a_projection, bad, centre, |h| {
        &mut h.out.vec3
    });
}

/// NaN and infinities in each component of a dual quaternion, and a zero real part.
fn dualquat_corruptions(name: &str) -> Vec<Corruption<cg_dualquat>> {
    let mut out = non_finite::<cg_dualquat>(&nested(name, 0, dualquat_fields()));
    out.push(change(
        format!("{name} with a zero real part"),
        INVALID,
        |q: &mut cg_dualquat| *q = ZERO_DUALQUAT,
    ));
    out
}

// ---------------------------------------------------------------------------------------------
// Rows: DLB and DIB

/// Which pointer arguments of a blend are passed as NULL.
#[derive(Clone, Copy, Default)]
struct Nulls {
    inputs: bool,
    weights: bool,
    out: bool,
}

fn or_null<T>(pointer: *const T, null: bool) -> *const T {
    if null {
        std::ptr::null()
    } else {
        pointer
    }
}

fn or_null_mut<T>(pointer: *mut T, null: bool) -> *mut T {
    or_null(pointer, null).cast_mut()
}

/// The arguments of a blend of `N` transforms (or of key poses of `joint_count` joints,
/// key-major), all of which a case may break.
#[repr(C)]
#[derive(Clone, Copy)]
struct BlendInput<const N: usize> {
    transforms: [cg_dualquat; N],
    weights: [f32; 2],
    /// The input count: transforms, or key poses.
    count: usize,
    precision: f32,
    max_iterations: u32,
    nulls: Nulls,
    /// Joints per key pose (pose blends).
    joint_count: usize,
    /// Write the output over the keys (pose blends).
    overlap: bool,
}

/// Two transforms to blend.
fn blend_input(_: &Harness) -> BlendInput<2> {
    BlendInput {
        transforms: [
            transform([0.0, 1.0, 0.0], 0.3, [1.0, 0.0, 0.0]),
            transform([1.0, 0.0, 0.0], -0.5, [0.0, 2.0, 0.0]),
        ],
        weights: [0.25, 0.75],
        count: 2,
        precision: 1e-6,
        max_iterations: 16,
        nulls: Nulls::default(),
        joint_count: 1,
        overlap: false,
    }
}

/// Two key poses of three joints to blend.
fn pose_input(h: &Harness) -> BlendInput<6> {
    let two = blend_input(h);
    BlendInput {
        transforms: std::array::from_fn(|i| {
            transform([0.0, 0.0, 1.0], 0.2 * i as f32, [0.1 * i as f32, 0.0, 1.0])
        }),
        joint_count: JOINTS,
        weights: two.weights,
        count: two.count,
        precision: two.precision,
        max_iterations: two.max_iterations,
        nulls: two.nulls,
        overlap: false,
    }
}

/// The corruptions shared by the four blends (whose transforms are called `name`): NULL
/// arrays, NaN and infinities in every transform and weight, a negative weight, weights
/// summing to 0, a transform with a zero real part, no inputs, an absurd count.
fn blend_corruptions<const N: usize>(name: &str) -> Vec<Corruption<BlendInput<N>>> {
    type B<const N: usize> = BlendInput<N>;
    let transforms = offset_of!(B<N>, transforms);
    let mut out = non_finite(&elements::<cg_dualquat>(
        name,
        transforms,
        N,
        &dualquat_fields(),
    ));
    out.extend(non_finite(&float_elements(
        "weights",
        offset_of!(B<N>, weights),
        2,
    )));
    out.extend([
        change(
            format!("({name} NULL, count 2)"),
            NULL_ARG,
            |v: &mut B<N>| v.nulls.inputs = true,
        ),
        change(
            format!("{name}[0] with a zero real part"),
            INVALID,
            |v: &mut B<N>| v.transforms[0] = ZERO_DUALQUAT,
        ),
    ]);
    out.extend([
        change("(weights NULL, count 2)", NULL_ARG, |v: &mut B<N>| {
            v.nulls.weights = true
        }),
        change("out NULL", NULL_ARG, |v: &mut B<N>| v.nulls.out = true),
    ]);
    out.extend(invalid::<B<N>>(&[
        ("weights[1] -0.5", |v| v.weights[1] = -0.5),
        ("weights -0 and 0", |v| v.weights = [-0.0, 0.0]),
        ("count 0", |v| v.count = 0),
        ("count SIZE_MAX", |v| v.count = usize::MAX),
    ]));
    out
}

/// DIB's settings out of range.
fn dib_corruptions<const N: usize>() -> Vec<Corruption<BlendInput<N>>> {
    let mut out = non_finite(&floats!(BlendInput<N>: precision));
    out.extend(invalid::<BlendInput<N>>(&[
        ("precision 0", |v| v.precision = 0.0),
        ("precision -1e-6", |v| v.precision = -1e-6),
        ("max_iterations 0", |v| v.max_iterations = 0),
        ("max_iterations 1001", |v| v.max_iterations = 1001),
        ("max_iterations UINT32_MAX", |v| v.max_iterations = u32::MAX),
    ]));
    out
}

/// The pose blends' corruptions: those of every blend, a layout overflowing, an output
/// over the keys.
fn pose_corruptions() -> Vec<Corruption<BlendInput<6>>> {
    let mut out = blend_corruptions("keys");
    out.extend(invalid::<BlendInput<6>>(&[
        ("key_count × joint_count overflowing", |v| {
            v.joint_count = usize::MAX / 2 + 1
        }),
        ("out_pose overlapping keys", |v| v.overlap = true),
    ]));
    out
}

impl<const N: usize> BlendInput<N> {
    /// The transforms, weights and output pointers, NULL where the case says; the output
    /// over the keys with `overlap`.
    fn pointers(
        &mut self,
        out: *mut cg_dualquat,
    ) -> (*const cg_dualquat, *const f32, *mut cg_dualquat) {
        let out = if self.overlap {
            self.transforms[1..].as_mut_ptr()
        } else {
            out
        };
        (
            or_null(self.transforms.as_ptr(), self.nulls.inputs),
            or_null(self.weights.as_ptr(), self.nulls.weights),
            or_null_mut(out, self.nulls.out),
        )
    }
}

fn dlb(h: &mut Harness, v: &mut BlendInput<2>) -> cg_status {
    let (inputs, weights, out) = v.pointers(&mut h.out.dual_quat);
    unsafe { cg_blend_dlb(inputs, weights, v.count, out) }
}

fn dib(h: &mut Harness, v: &mut BlendInput<2>) -> cg_status {
    let (inputs, weights, out) = v.pointers(&mut h.out.dual_quat);
    unsafe { cg_blend_dib(inputs, weights, v.count, v.precision, v.max_iterations, out) }
}

/// A pose blend called with the counts and settings of a copy of its input and the
/// pointers to use.
type PoseBlend = fn(BlendInput<6>, *const cg_dualquat, *const f32, *mut cg_dualquat) -> cg_status;

/// Calls a pose blend with `v`; checks that the keys are unchanged when the output
/// overlaps them.
fn pose_blend(h: &mut Harness, v: &mut BlendInput<6>, blend: PoseBlend) -> cg_status {
    let copy = *v;
    let (keys, weights, out) = v.pointers(h.out.pose.as_mut_ptr());
    let status = blend(copy, keys, weights, out);
    if status != cg_status::Ok && bytes_of(&copy.transforms[..]) != bytes_of(&v.transforms[..]) {
        h.note("a failed call wrote over its input keys");
    }
    status
}

fn rows_blends(t: &mut Table) {
    let mut dib_cases = blend_corruptions("inputs");
    dib_cases.extend(dib_corruptions());
    t.corrupt(
        Setup::Online,
        "cg_blend_dlb",
        blend_corruptions("inputs"),
        blend_input,
        dlb,
    );
    t.corrupt(Setup::Online, "cg_blend_dib", dib_cases, blend_input, dib);
    let mut dib_cases = pose_corruptions();
    dib_cases.extend(dib_corruptions());
    t.corrupt(
        Setup::Online,
        "cg_blend_pose_dlb",
        pose_corruptions(),
        pose_input,
        |h, v| {
            pose_blend(h, v, |v, keys, weights, out| unsafe {
                cg_blend_pose_dlb(keys, weights, v.count, v.joint_count, out)
            })
        },
    );
    t.corrupt(
        Setup::Online,
        "cg_blend_pose_dib",
        dib_cases,
        pose_input,
        |h, v| {
            pose_blend(h, v, |v, keys, weights, out| {
                let (count, joints) = (v.count, v.joint_count);
                unsafe {
                    cg_blend_pose_dib(
                        keys,
                        weights,
                        count,
                        joints,
                        v.precision,
                        v.max_iterations,
                        out,
                    )
                }
            })
        },
    );
}

// ---------------------------------------------------------------------------------------------
// Rows: the view blender

fn blender_config(_: &Harness) -> Box<Padded<cg_view_blender_config>> {
    let mut config: cg_view_blender_config = init(cg_view_blender_config_init);
    config.joint_count = JOINTS as u32;
    config.key_count = KEYS as u32;
    padded(config)
}

/// The arguments of `cg_view_blender_set_key_clip` and `_set_key_pose`: two frames of
/// three joints (a pose uses the first).
#[repr(C)]
#[derive(Clone, Copy)]
struct ClipInput {
    frames: [cg_dualquat; 6],
    /// Frames of a clip, or joints of a pose.
    count: usize,
    frames_per_second: f32,
    key: u32,
    /// Pass `frames` as NULL.
    null: bool,
}

fn clip_input(_: &Harness) -> ClipInput {
    ClipInput {
        frames: std::array::from_fn(|i| {
            transform([1.0, 0.0, 0.0], 0.05 * i as f32, [0.0, 0.0, 0.1 * i as f32])
        }),
        count: 2,
        frames_per_second: 24.0,
        key: 1,
        null: false,
    }
}

fn pose_key_input(h: &Harness) -> ClipInput {
    ClipInput {
        count: JOINTS,
        ..clip_input(h)
    }
}

/// NaN and infinities in the first `elements` transforms, a zero real part, a key out of
/// range, `(NULL, count)`.
fn clip_corruptions(elements: usize) -> Vec<Corruption<ClipInput>> {
    type C = ClipInput;
    let mut out = non_finite::<C>(&elements_of_frames(elements));
    out.extend([
        change(
            "the last transform with a zero real part",
            INVALID,
            move |c: &mut C| c.frames[elements - 1] = ZERO_DUALQUAT,
        ),
        change("key 3 (key_count is 3)", INVALID, |c: &mut C| c.key = 3),
        change("key UINT32_MAX", INVALID, |c: &mut C| c.key = u32::MAX),
        change(
            "frames NULL with a non-zero count",
            NULL_ARG,
            |c: &mut C| c.null = true,
        ),
    ]);
    out
}

fn elements_of_frames(count: usize) -> Fields {
    elements::<cg_dualquat>(
        "frames",
        offset_of!(ClipInput, frames),
        count,
        &dualquat_fields(),
    )
}

/// The arguments of `cg_view_blender_weights` and `_evaluate`.
#[derive(Clone, Copy)]
struct ViewInput {
    character: cg_dualquat,
    viewer: cg_vec3,
    /// Weights or joints asked for.
    count: usize,
    t: f64,
    /// Which blender: 0 the complete one, 1 the one without camera, 2 the one with a key
    /// without clip; 3 NULL.
    blender: u8,
    /// Pass `character`, `viewer`, the output as NULL.
    nulls: [bool; 3],
}

fn view_input(_: &Harness) -> ViewInput {
    ViewInput {
        character: transform([0.0, 1.0, 0.0], 0.7, [1.0, 0.0, 2.0]),
        viewer: vec3(1.5, 1.7, 7.0),
        count: 3,
        t: 0.4,
        blender: 0,
        nulls: [false; 3],
    }
}

fn view_corruptions() -> Vec<Corruption<ViewInput>> {
    type V = ViewInput;
    let mut out = inside(dualquat_corruptions("character"), "", |v: &mut V| {
        &mut v.character
    });
    out.extend(inside(
        non_finite(&vec3_fields()),
        "viewer.",
        |v: &mut V| &mut v.viewer,
    ));
    out.extend([
        change("blender NULL", NULL_ARG, |v: &mut V| v.blender = 3),
        change("character NULL", NULL_ARG, |v: &mut V| v.nulls[0] = true),
        change("viewer NULL", NULL_ARG, |v: &mut V| v.nulls[1] = true),
        change("output NULL with a count of 3", NULL_ARG, |v: &mut V| {
            v.nulls[2] = true
        }),
        change("count 2 (3 keys and joints)", INVALID, |v: &mut V| {
            v.count = 2
        }),
        change("count 4 (3 keys and joints)", INVALID, |v: &mut V| {
            v.count = 4
        }),
        change("count 0", INVALID, |v: &mut V| v.count = 0),
        change("count SIZE_MAX", INVALID, |v: &mut V| v.count = usize::MAX),
        change("viewer at the character's centre", INVALID, |v: &mut V| {
            v.viewer = vec3(1.0, 0.0, 2.0)
        }),
        change("no key camera yet", WRONG_STATE, |v: &mut V| v.blender = 1),
    ]);
    out
}

impl ViewInput {
    fn blender(&self, h: &Harness) -> *const cg_view_blender {
        match self.blender {
            0 => h.blender,
            1 => h.blender_no_camera,
            2 => h.blender_no_clip,
            _ => null(),
        }
    }

    fn character(&self) -> *const cg_dualquat {
        or_null(&self.character, self.nulls[0])
    }

    fn viewer(&self) -> *const cg_vec3 {
        or_null(&self.viewer, self.nulls[1])
    }
}

fn rows_view_blender(t: &mut Table) {
    let f = "cg_view_blender_create";
    t.case(f, "config NULL", NULL_ARG, |h| unsafe {
        cg_view_blender_create(null(), &mut h.out.blender)
    });
    t.case(f, "out_blender NULL", NULL_ARG, |h| unsafe {
        cg_view_blender_create(&blender_config(h).value, null_mut())
    });
    type C = cg_view_blender_config;
    let mut config = struct_sizes::<C>();
    config.extend(non_finite(&floats!(C: alpha, precision)));
    config.extend(invalid::<C>(&[
        ("joint_count 0", |c| c.joint_count = 0),
        ("joint_count 65537", |c| c.joint_count = 65537),
        ("joint_count UINT32_MAX", |c| c.joint_count = u32::MAX),
        ("key_count 0", |c| c.key_count = 0),
        ("key_count 33", |c| c.key_count = 33),
        ("alpha 1.9", |c| c.alpha = 1.9),
        ("alpha 4.1", |c| c.alpha = 4.1),
        ("distance 2", |c| c.distance = 2),
        ("method 2", |c| c.method = 2),
        ("method UINT32_MAX", |c| c.method = u32::MAX),
        ("precision 0", |c| c.precision = 0.0),
        ("precision -1", |c| c.precision = -1.0),
        ("max_iterations 0", |c| c.max_iterations = 0),
        ("max_iterations 1001", |c| c.max_iterations = 1001),
    ]));
    t.corrupt_struct(f, "config", config, blender_config, |h, config| unsafe {
        cg_view_blender_create(config, &mut h.out.blender)
    });

    let f = "cg_view_blender_set_key_clip";
    let set_clip = |h: &mut Harness, c: &mut ClipInput| {
        let frames = or_null(c.frames.as_ptr(), c.null);
        unsafe {
            cg_view_blender_set_key_clip(
                h.blender,
                c.key,
                frames,
                c.count,
                c.frames_per_second,
                true,
            )
        }
    };
    t.case(f, "blender NULL", NULL_ARG, |h| {
        let c = clip_input(h);
        unsafe { cg_view_blender_set_key_clip(null_mut(), 1, c.frames.as_ptr(), 2, 24.0, false) }
    });
    let mut clip = clip_corruptions(6);
    clip.extend(non_finite(&floats!(ClipInput: frames_per_second)));
    clip.extend(invalid::<ClipInput>(&[
        ("frame_count 0", |c| c.count = 0),
        ("frame_count × joint_count overflowing", |c| {
            c.count = usize::MAX
        }),
        ("frame_count × joint_count too big for memory", |c| {
            c.count = usize::MAX / 4
        }),
        ("frames_per_second 0", |c| c.frames_per_second = 0.0),
        ("frames_per_second -24", |c| c.frames_per_second = -24.0),
    ]));
    t.corrupt(Setup::Online, f, clip, clip_input, set_clip);

    let f = "cg_view_blender_set_key_pose";
    t.case(f, "blender NULL", NULL_ARG, |h| {
        let c = pose_key_input(h);
        unsafe { cg_view_blender_set_key_pose(null_mut(), 1, c.frames.as_ptr(), JOINTS) }
    });
    let mut pose = clip_corruptions(JOINTS);
    pose.extend(invalid::<ClipInput>(&[
        ("joint_count 2 (the blender has 3)", |c| c.count = 2),
        ("joint_count 4 (the blender has 3)", |c| c.count = 4),
        ("(pose NULL, joint_count 0)", |c| {
            c.count = 0;
            c.null = true;
        }),
        ("joint_count SIZE_MAX", |c| c.count = usize::MAX),
    ]));
    t.corrupt(Setup::Online, f, pose, pose_key_input, |h, c| {
        let pose = or_null(c.frames.as_ptr(), c.null);
        unsafe { cg_view_blender_set_key_pose(h.blender, c.key, pose, c.count) }
    });

    let f = "cg_view_blender_add_camera";
    t.case(f, "blender NULL", NULL_ARG, |_| unsafe {
        cg_view_blender_add_camera(null_mut(), vec3(0.0, 1.0, 0.0), 0)
    });
    let mut camera = inside(
        non_finite(&vec3_fields()),
        "direction.",
        |c: &mut ClipInput| &mut c.frames[0].real,
    );
    camera.extend(invalid::<ClipInput>(&[
        ("direction zero", |c| c.frames[0].real = ZERO_QUAT),
        ("key 3 (key_count is 3)", |c| c.key = 3),
        ("key UINT32_MAX", |c| c.key = u32::MAX),
    ]));
    t.corrupt(Setup::Online, f, camera, camera_input, |h, c| {
        let q = c.frames[0].real;
        unsafe { cg_view_blender_add_camera(h.blender, vec3(q.x, q.y, q.z), c.key) }
    });

    let f = "cg_view_blender_weights";
    t.corrupt(Setup::Online, f, view_corruptions(), view_input, |h, v| {
        let out = or_null_mut(h.out.weights.as_mut_ptr(), v.nulls[2]);
        unsafe { cg_view_blender_weights(v.blender(h), v.character(), v.viewer(), out, v.count) }
    });

    let f = "cg_view_blender_evaluate";
    let mut evaluate = view_corruptions();
    for (label, value) in [
        ("NaN", f64::NAN),
        ("+Inf", f64::INFINITY),
        ("-Inf", f64::NEG_INFINITY),
    ] {
        evaluate.push(change(
            format!("t = {label}"),
            NON_FINITE,
            move |v: &mut ViewInput| v.t = value,
        ));
    }
    evaluate.push(change(
        "key 1 has no clip or pose",
        WRONG_STATE,
        |v: &mut ViewInput| v.blender = 2,
    ));
    t.corrupt(Setup::Online, f, evaluate, view_input, |h, v| {
        let out = or_null_mut(h.out.pose.as_mut_ptr(), v.nulls[2]);
        unsafe {
            cg_view_blender_evaluate(v.blender(h), v.character(), v.viewer(), v.t, out, v.count)
        }
    });
}

/// A camera direction (in `frames[0].real`'s x, y, z) and its key.
fn camera_input(h: &Harness) -> ClipInput {
    let mut input = clip_input(h);
    input.frames[0].real = cg_quat {
        x: 0.0,
        y: 1.0,
        z: 0.0,
        w: 0.0,
    };
    input
}

// ---------------------------------------------------------------------------------------------
// Rows: functions that cannot fail

fn rows_infallible(t: &mut Table) {
    t.no_failure_modes(
        "cg_crowd_destroy",
        "returns nothing; NULL is accepted and ignored",
        || {
            let before = set_sentinel_error();
            unsafe { cg_crowd_destroy(null_mut()) };
            assert_eq!(
                last_error(),
                before,
                "cg_crowd_destroy(NULL) recorded an error"
            );
        },
    );
    t.no_failure_modes(
        "cg_view_blender_destroy",
        "returns nothing; NULL is accepted and ignored",
        || {
            let before = set_sentinel_error();
            unsafe { cg_view_blender_destroy(null_mut()) };
            assert_eq!(last_error(), before);
        },
    );
    t.no_failure_modes(
        "cg_last_error_message",
        "returns a length; a NULL or short buffer is documented",
        check_last_error_message,
    );
    t.no_failure_modes(
        "cg_status_str",
        "an unknown status gives \"unknown status\", never NULL",
        || {
            let first_unknown = cg_status::ALL.len() as u32;
            for value in [first_unknown, first_unknown + 1, 255, 0x8000_0000, u32::MAX] {
                let text = cg_status_str(value);
                assert!(!text.is_null(), "cg_status_str({value}) is NULL");
                // SAFETY: non-NULL, static and NUL-terminated by contract.
                let text = unsafe { CStr::from_ptr(text) };
                assert_eq!(
                    text.to_str(),
                    Ok("unknown status"),
                    "cg_status_str({value})"
                );
            }
            let known: BTreeSet<_> = cg_status::ALL
                .iter()
                // SAFETY: as above.
                .map(|s| unsafe { CStr::from_ptr(cg_status_str(*s as u32)) })
                .collect();
            assert_eq!(
                known.len(),
                cg_status::ALL.len(),
                "descriptions are distinct"
            );
            assert!(!known.contains(c"unknown status"));
        },
    );
    t.no_failure_modes("cg_version", "takes nothing; a constant", || {
        assert_eq!(
            cg_version(),
            (CG_VERSION_MAJOR << 16) | (CG_VERSION_MINOR << 8) | CG_VERSION_PATCH
        );
    });
    t.no_failure_modes(
        "cg_version_string",
        "takes nothing; a static string",
        || {
            // SAFETY: static and NUL-terminated by contract.
            let text = unsafe { CStr::from_ptr(cg_version_string()) };
            let expected = format!("{CG_VERSION_MAJOR}.{CG_VERSION_MINOR}.{CG_VERSION_PATCH}");
            assert_eq!(text.to_str(), Ok(expected.as_str()));
        },
    );
}

/// `cg_last_error_message` with a NULL buffer, a zero length, a one-byte buffer and a short
/// one: the full length always comes back, at most `len - 1` bytes and a NUL are written.
fn check_last_error_message() {
    let message = set_sentinel_error();
    let length = message.len();
    assert!(length > 8);
    assert_eq!(unsafe { cg_last_error_message(null_mut(), 0) }, length);
    assert_eq!(unsafe { cg_last_error_message(null_mut(), 100) }, length);
    let mut buf = [0x5Au8; 64];
    let pointer = buf.as_mut_ptr().cast::<c_char>();
    assert_eq!(unsafe { cg_last_error_message(pointer, 0) }, length);
    assert!(buf.iter().all(|&b| b == 0x5A), "len 0 wrote");
    assert_eq!(unsafe { cg_last_error_message(pointer, 1) }, length);
    assert_eq!(buf[0], 0, "len 1 writes the NUL alone");
    assert!(buf[1..].iter().all(|&b| b == 0x5A));
    assert_eq!(unsafe { cg_last_error_message(pointer, 6) }, length);
    assert_eq!(
        &buf[..6],
        &[message.as_bytes()[..5].to_vec(), vec![0]].concat()[..]
    );
    assert!(buf[6..].iter().all(|&b| b == 0x5A), "wrote past len");
    // A message is kept until the next failure on this thread, and is per thread.
    assert_eq!(
        std::thread::spawn(|| unsafe { cg_last_error_message(null_mut(), 0) })
            .join()
            .expect("thread"),
        0
    );
    assert_eq!(last_error(), message);
}

// ---------------------------------------------------------------------------------------------
// Extreme finite values are not bad input

/// Runs `work` on a thread and fails if it has not finished within a minute (a hang).
fn within_a_minute(what: &str, work: fn()) {
    let (done, finished) = std::sync::mpsc::channel();
    let thread = std::thread::spawn(move || {
        work();
        let _ = done.send(());
    });
    match finished.recv_timeout(std::time::Duration::from_secs(60)) {
        Ok(()) => thread.join().expect("no panic"),
        Err(std::sync::mpsc::RecvTimeoutError::Disconnected) => {
            std::panic::resume_unwind(thread.join().expect_err("it panicked"))
        }
        Err(std::sync::mpsc::RecvTimeoutError::Timeout) => panic!("{what} hangs"),
    }
}

/// Every gaze, joint and eye output of the crowd is finite.
fn assert_finite_outputs(h: &Harness, what: &str) {
    let mut gaze = [zeroed::<cg_gaze_info>(); 8];
    let mut count = 0;
    ok(unsafe { cg_crowd_read_gaze(h.crowd, gaze.as_mut_ptr(), 8, &mut count) });
    let mut joints = [zeroed::<cg_quat>(); ALL_JOINTS];
    ok(unsafe { cg_crowd_read_joints(h.crowd, 0, 4, joints.as_mut_ptr(), ALL_JOINTS) });
    let mut eyes = [zeroed::<cg_eye_info>(); 4];
    ok(unsafe { cg_crowd_read_eyes(h.crowd, 0, 4, eyes.as_mut_ptr(), 4) });
    let floats = |bytes: &[u8]| -> Vec<f32> {
        bytes
            .chunks_exact(4)
            .map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]))
            .collect()
    };
    let mut values = floats(bytes_of(&joints[..]));
    for info in &gaze[..count] {
        let t = info.target_position;
        values.extend([
            t.x,
            t.y,
            t.z,
            info.s_max,
            info.threshold,
            info.attentive_fraction,
        ]);
    }
    for eye in &eyes {
        values.extend(floats(&bytes_of(std::slice::from_ref(eye))[4..]));
    }
    assert!(values.iter().all(|v| v.is_finite()), "{what}: {values:?}");
}

/// Entities at the two ends of the float range, moving at ±FLT_MAX: stepping returns (the
/// neighbour grid once doubled its cells forever on a bounding box wider than a float) and
/// every output stays finite.
#[test]
fn entities_at_the_ends_of_the_float_range() {
    within_a_minute("stepping a crowd spanning ±FLT_MAX", || {
        let mut h = Harness::new(Setup::Online);
        let (t, mut states) = h.next_frame();
        for (state, sign) in states.iter_mut().zip([1.0f32, -1.0, 1.0, -1.0]) {
            state.position.x = sign * f32::MAX;
            state.velocity = vec3(sign * f32::MAX, 0.0, -sign * f32::MAX);
            state.flags = CG_STATE_HAS_VELOCITY;
        }
        ok(unsafe { cg_crowd_push_frame(h.crowd, t, states.as_ptr(), states.len()) });
        ok(unsafe {
            cg_crowd_set_viewer(h.crowd, &vec3(f32::MAX, 0.0, f32::MAX), 1.0, null_mut())
        });
        for _ in 0..10 {
            ok(unsafe { cg_crowd_step(h.crowd, (1.0 / FPS) as f32) });
        }
        assert_finite_outputs(&h, "after stepping at ±FLT_MAX");
        h.time = t;
        let (t, states) = h.next_frame();
        ok(unsafe { cg_crowd_push_frame(h.crowd, t, states.as_ptr(), states.len()) });
        ok(unsafe { cg_crowd_plan(h.crowd) });
        ok(unsafe { cg_crowd_step(h.crowd, (1.0 / FPS) as f32) });
        assert_finite_outputs(&h, "after planning");
    });
}

/// Weights of FLT_MAX are >= 0 and not all zero: accepted and rescaled to ¼ each (their sum
/// once overflowed and the call failed).
#[test]
fn the_largest_weights_are_rescaled() {
    let h = Harness::new(Setup::Online);
    let mut params = params_of(&h);
    let p = &mut params.value;
    (p.weight_proximity, p.weight_speed) = (f32::MAX, f32::MAX);
    (p.weight_orientation, p.weight_periphery) = (f32::MAX, f32::MAX);
    ok(unsafe { cg_crowd_set_character_params(h.crowd, h.character(0), p) });
    let mut back = [sized::<cg_character_params>()];
    ok(unsafe { cg_crowd_get_character_params(h.crowd, h.character(0), back.as_mut_ptr()) });
    let b = back[0];
    let weights = [
        b.weight_proximity,
        b.weight_speed,
        b.weight_orientation,
        b.weight_periphery,
    ];
    assert_eq!(weights, [0.25; 4]);
}

/// A pose at any finite time is finite: `time × frames_per_second` overflowing a double
/// once made a looping clip's phase NaN.
#[test]
fn poses_at_the_ends_of_time_are_finite() {
    let h = Harness::new(Setup::Online);
    let character = transform([0.0, 1.0, 0.0], 0.7, [1.0, 0.0, 2.0]);
    let viewer = vec3(2.0, 2.0, 5.0);
    for t in [1e300, -1e300, f64::MAX, f64::MIN, 1e-300] {
        let mut pose = [zeroed::<cg_dualquat>(); JOINTS];
        ok(unsafe {
            cg_view_blender_evaluate(h.blender, &character, &viewer, t, pose.as_mut_ptr(), JOINTS)
        });
        let bytes = bytes_of(&pose[..]);
        assert!(
            bytes
                .chunks_exact(4)
                .all(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]).is_finite()),
            "t = {t}: {pose:?}"
        );
    }
}

/// Capacities at their documented maxima return `CG_STATUS_OK` or `CG_STATUS_OUT_OF_MEMORY`
/// (documented for the create), never abort the process; a failed create writes no handle
/// and names the field and the bytes asked.
///
/// Only the maxima that are safe to try in a process without an address-space cap are here:
/// a 275 GB recording is refused by the allocator (or, where memory is overcommitted,
/// reserved and never touched), and the largest view blender is small. The maxima that need
/// gigabytes (16 777 216 characters or objects, a clip or a plan larger than memory) run in
/// children capped at 2 GiB in `c_examples/out_of_memory.c`.
#[test]
fn capacities_at_their_maxima_return_ok_or_out_of_memory() {
    let header = Header::read();
    let allowed = [cg_status::Ok, cg_status::OutOfMemory];
    for function in ["cg_crowd_create", "cg_view_blender_create"] {
        assert!(
            header
                .documented(function)
                .contains(&(cg_status::OutOfMemory as u32)),
            "{function} does not document CG_STATUS_OUT_OF_MEMORY"
        );
    }

    let mut config: cg_crowd_config = init(cg_crowd_config_init);
    config.max_recorded_states = u32::MAX;
    let mut crowd: *mut cg_crowd = null_mut();
    let status = unsafe { cg_crowd_create(&config, &mut crowd) };
    assert!(allowed.contains(&status), "{status:?}: {}", last_error());
    if status == cg_status::Ok {
        let mut back: cg_crowd_config = init(cg_crowd_config_init);
        ok(unsafe { cg_crowd_get_config(crowd, &mut back) });
        assert_eq!(back.max_recorded_states, u32::MAX);
        unsafe { cg_crowd_destroy(crowd) };
    } else {
        assert!(crowd.is_null(), "a failed create wrote a handle");
        let message = last_error();
        assert!(
            message.starts_with("out of memory: max_recorded_states = 4294967295 needs ")
                && message.ends_with(" bytes")
                && !message.contains('\n'),
            "{message}"
        );
    }

    let mut config: cg_view_blender_config = init(cg_view_blender_config_init);
    config.joint_count = 65536;
    config.key_count = 32;
    let mut blender: *mut cg_view_blender = null_mut();
    ok(unsafe { cg_view_blender_create(&config, &mut blender) });
    unsafe { cg_view_blender_destroy(blender) };
}
