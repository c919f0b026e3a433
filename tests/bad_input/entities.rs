//! Rows: characters and objects (add them, remove an entity).

use crate::{
    corruption::{inside, invalid, non_finite, struct_sizes, unknown_models, Corruption},
    fixture::{human_chain, Harness, Setup},
    table::{Pick, Table},
    values::{
        elements, floats, init, nested, padded, quat_fields, vec3, vec3_fields, Fields, Padded,
        ZERO_QUAT,
    },
    CAPACITY, NULL_ARG, WRONG_STATE,
};
use crowdgaze::ffi::attention::*;
use crowdgaze::ffi::chain::*;
use crowdgaze::ffi::status::cg_status;
use std::mem::offset_of;
use std::ptr::{null, null_mut};

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

pub(crate) fn rows_entities(t: &mut Table) {
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
