//! Rows: the `_init` functions.

use crate::{
    corruption::{bad_output_sizes, OLDER_CROWD_CONFIG},
    table::Table,
    INVALID, NULL_ARG,
};
use crowdgaze::ffi::attention::*;
use crowdgaze::ffi::chain::*;
use crowdgaze::ffi::crowd::*;
use crowdgaze::ffi::gaze::*;
use crowdgaze::ffi::view_blender::*;
use std::mem::size_of;
use std::ptr::null_mut;

pub(crate) fn rows_init(t: &mut Table) {
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
        "cg_crowd_config_init_street",
        "config NULL",
        NULL_ARG,
        |_| unsafe { cg_crowd_config_init_street(null_mut()) },
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
    bad_output_sizes(
        t,
        "cg_crowd_config_init_street",
        OLDER_CROWD_CONFIG,
        |_, out| unsafe { cg_crowd_config_init_street(out) },
    );
    let f = "cg_view_blender_config_init";
    bad_output_sizes(t, f, size_of::<cg_view_blender_config>(), |_, out| unsafe {
        cg_view_blender_config_init(out)
    });
}
