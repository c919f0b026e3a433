//! The table of cases, keyed by function name, and the helpers that add a function's cases.

use crate::{
    attention::rows_attention,
    blend::rows_blends,
    conversations::rows_conversations,
    corruption::{inside, non_finite, Corruption},
    crowd::rows_crowd,
    dual_quaternions::rows_dual_quaternions,
    entities::rows_entities,
    fixture::{Harness, Setup, UNKNOWN_ID},
    following::rows_following,
    frames::{rows_frames, rows_pushes, rows_steps},
    gaze::rows_gaze,
    infallible::rows_infallible,
    init::rows_init,
    joints::rows_joints,
    plan::rows_plan,
    rig::rows_rig,
    values::{float_elements, Padded, BAD_FLOATS},
    view_blender::rows_view_blender,
    INVALID, NON_FINITE, NOT_FOUND, NULL_ARG,
};
use crowdgaze::ffi::attention::*;
use crowdgaze::ffi::crowd::*;
use crowdgaze::ffi::status::cg_status;
use std::collections::BTreeMap;
use std::ptr::{null, null_mut};
use std::rc::Rc;

type Call = Rc<dyn Fn(&mut Harness) -> cg_status>;

/// Picks an id from a fixture.
pub(crate) type Pick = fn(&Harness) -> u32;

pub(crate) struct Case {
    pub(crate) what: String,
    pub(crate) setup: Setup,
    pub(crate) expected: cg_status,
    pub(crate) call: Call,
}

pub(crate) enum Row {
    Cases(Vec<Case>),
    /// A function that cannot fail: why, and a check of how it takes its own odd inputs.
    NoFailureModes {
        why: &'static str,
        check: fn(),
    },
}

#[derive(Default)]
pub(crate) struct Table {
    pub(crate) rows: BTreeMap<&'static str, Row>,
}

impl Table {
    /// A case on the `Online` fixture.
    pub(crate) fn case(
        &mut self,
        function: &'static str,
        what: impl Into<String>,
        expected: cg_status,
        call: impl Fn(&mut Harness) -> cg_status + 'static,
    ) {
        self.case_in(Setup::Online, function, what, expected, call);
    }

    pub(crate) fn case_in(
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
    pub(crate) fn corrupt<T: 'static>(
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
    pub(crate) fn corrupt_struct<T: 'static>(
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
    pub(crate) fn character_setter<T: 'static>(
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
    pub(crate) fn float_array<const N: usize, O: 'static>(
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
    pub(crate) fn non_finite_argument(
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
    pub(crate) fn character_ids(
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
    pub(crate) fn entity_ids(
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

    pub(crate) fn no_failure_modes(
        &mut self,
        function: &'static str,
        why: &'static str,
        check: fn(),
    ) {
        let previous = self
            .rows
            .insert(function, Row::NoFailureModes { why, check });
        assert!(previous.is_none(), "{function} has two rows");
    }

    pub(crate) fn case_count(&self) -> usize {
        self.rows
            .values()
            .map(|row| match row {
                Row::Cases(cases) => cases.len(),
                Row::NoFailureModes { .. } => 0,
            })
            .sum()
    }
}

pub(crate) fn table() -> Table {
    let mut t = Table::default();
    rows_init(&mut t);
    rows_crowd(&mut t);
    rows_entities(&mut t);
    rows_conversations(&mut t);
    rows_following(&mut t);
    rows_frames(&mut t);
    rows_attention(&mut t);
    rows_steps(&mut t);
    rows_pushes(&mut t);
    rows_plan(&mut t);
    rows_gaze(&mut t);
    rows_joints(&mut t);
    rows_dual_quaternions(&mut t);
    rows_blends(&mut t);
    rows_view_blender(&mut t);
    rows_rig(&mut t);
    rows_infallible(&mut t);
    t
}
