//! Rows: explicit gaze targets and base poses.

use crate::{
    corruption::{change, invalid, non_finite, struct_sizes},
    fixture::{base_pose, Harness, Setup},
    table::Table,
    values::{elements, floats, init, padded, quat_fields, rotation, vec3, Padded, ZERO_QUAT},
    INVALID, NULL_ARG,
};
use crowdgaze::ffi::gaze::*;
use crowdgaze::ffi::types::cg_quat;
use std::mem::offset_of;
use std::ptr::{null, null_mut};

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

pub(crate) fn rows_gaze(t: &mut Table) {
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
