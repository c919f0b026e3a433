//! Rows: attention (read the gaze, scores, character parameters, impact, the viewer, the
//! attention period).

use crate::{
    corruption::{
        bad_output_sizes, change, inside, invalid, non_finite, struct_sizes, unknown_models,
    },
    fixture::{Harness, Setup},
    table::{Pick, Table},
    values::{floats, ok, padded, poke, sized, vec3, vec3_fields, Padded},
    INVALID, NULL_ARG, WRONG_STATE,
};
use crowdgaze::ffi::attention::*;
use std::mem::{offset_of, size_of};
use std::ptr::{null, null_mut};

pub(crate) fn params_of(h: &Harness) -> Box<Padded<cg_character_params>> {
    let mut params = [sized::<cg_character_params>()];
    ok(unsafe { cg_crowd_get_character_params(h.crowd, h.character(0), params.as_mut_ptr()) });
    params[0].attention_fraction = 0.5;
    padded(params[0])
}

pub(crate) fn rows_attention(t: &mut Table) {
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
