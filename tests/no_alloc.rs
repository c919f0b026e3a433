//! Per-frame calls allocate nothing: a counting global allocator (counter per thread) wraps
//! the system allocator, and [`assert_no_alloc`] fails if a closure allocates.
//!
//! Each feature adds its per-frame calls here, after a warm-up that may allocate.

// The `unsafe { cg_... }` calls below pass pointers to live values of the sizes the header
// asks for, or deliberately bad ones (NULL, misaligned, wrong struct_size) that the library
// must refuse: that is their safety comment, once for the file.
#![allow(clippy::undocumented_unsafe_blocks)]

mod support;

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;

struct CountingAllocator;

thread_local! {
    static ALLOCATIONS: Cell<u64> = const { Cell::new(0) };
}

// SAFETY: forwards every call to the system allocator unchanged; only counts.
unsafe impl GlobalAlloc for CountingAllocator {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        ALLOCATIONS.with(|count| count.set(count.get() + 1));
        // SAFETY: same contract as the caller's.
        unsafe { System.alloc(layout) }
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        // SAFETY: same contract as the caller's.
        unsafe { System.dealloc(ptr, layout) }
    }

    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        ALLOCATIONS.with(|count| count.set(count.get() + 1));
        // SAFETY: same contract as the caller's.
        unsafe { System.alloc_zeroed(layout) }
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        ALLOCATIONS.with(|count| count.set(count.get() + 1));
        // SAFETY: same contract as the caller's.
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static GLOBAL: CountingAllocator = CountingAllocator;

/// Number of allocations `work` made on this thread.
fn allocations_during<R>(work: impl FnOnce() -> R) -> (u64, R) {
    let before = ALLOCATIONS.with(Cell::get);
    let result = work();
    let after = ALLOCATIONS.with(Cell::get);
    (after - before, result)
}

/// Fails the test, naming `what`, if `work` allocates.
fn assert_no_alloc<R>(what: &str, work: impl FnOnce() -> R) -> R {
    let (count, result) = allocations_during(work);
    assert_eq!(count, 0, "{what} allocated {count} times");
    result
}

#[test]
fn the_counter_sees_allocations() {
    let (count, vector) = allocations_during(|| vec![1u8; 64]);
    assert_eq!(count, 1);
    drop(vector);
}

#[test]
fn status_and_version_queries_do_not_allocate() {
    use crowdgaze::ffi::{crowd, status, version};
    let mut config = std::mem::MaybeUninit::<crowd::cg_crowd_config>::uninit();
    // SAFETY: a versioned struct starts with its `uint32_t struct_size`, set before the call.
    unsafe {
        config
            .as_mut_ptr()
            .cast::<u32>()
            .write(std::mem::size_of::<crowd::cg_crowd_config>() as u32)
    };
    assert_eq!(
        unsafe { crowd::cg_crowd_config_init(config.as_mut_ptr()) },
        status::cg_status::Ok
    );
    let mut handle = std::ptr::null_mut();
    assert_eq!(
        unsafe { crowd::cg_crowd_create(config.as_ptr(), &mut handle) },
        status::cg_status::Ok
    );
    assert_no_alloc("status, version and config queries", || {
        for value in 0..12 {
            assert!(!status::cg_status_str(value).is_null());
        }
        assert_ne!(version::cg_version(), u32::MAX);
        assert!(!version::cg_version_string().is_null());
        assert_eq!(
            unsafe { crowd::cg_crowd_get_config(handle, config.as_mut_ptr()) },
            status::cg_status::Ok
        );
    });
    unsafe { crowd::cg_crowd_destroy(handle) };
}

#[test]
fn push_frame_step_and_read_gaze_do_not_allocate() {
    use crowdgaze::ffi::attention::*;
    use crowdgaze::ffi::crowd::*;
    use crowdgaze::ffi::eyelids::*;
    use crowdgaze::ffi::frame::*;
    use crowdgaze::ffi::status::cg_status;
    use crowdgaze::ffi::types::cg_vec3;

    let mut config = std::mem::MaybeUninit::<cg_crowd_config>::uninit();
    // SAFETY: a versioned struct starts with its `uint32_t struct_size`, set before the call.
    unsafe {
        config
            .as_mut_ptr()
            .cast::<u32>()
            .write(std::mem::size_of::<cg_crowd_config>() as u32)
    };
    assert_eq!(
        unsafe { cg_crowd_config_init(config.as_mut_ptr()) },
        cg_status::Ok
    );
    // SAFETY: initialised just above.
    let mut config = unsafe { config.assume_init() };
    // Storage reordered every 8 steps: 11 times in the measured frames.
    config.reorder_period = 8;
    let mut handle = std::ptr::null_mut();
    assert_eq!(
        unsafe { cg_crowd_create(&config, &mut handle) },
        cg_status::Ok
    );
    let mut desc = std::mem::MaybeUninit::<cg_character_desc>::uninit();
    // SAFETY: a versioned struct starts with its `uint32_t struct_size`, set before the call.
    unsafe {
        desc.as_mut_ptr()
            .cast::<u32>()
            .write(std::mem::size_of::<cg_character_desc>() as u32)
    };
    assert_eq!(
        unsafe { cg_character_desc_init(desc.as_mut_ptr()) },
        cg_status::Ok
    );
    // SAFETY: initialised just above.
    let mut desc = unsafe { desc.assume_init() };
    let mut states = Vec::new();
    for i in 0..200 {
        desc.position = cg_vec3 {
            x: (i % 20) as f32 * 1.5,
            y: 0.0,
            z: (i / 20) as f32 * 1.5,
        };
        let mut id = 0;
        assert_eq!(
            unsafe { cg_crowd_add_character(handle, &desc, &mut id) },
            cg_status::Ok
        );
        let mut state = std::mem::MaybeUninit::<cg_entity_state>::uninit();
        // SAFETY: a versioned struct starts with its `uint32_t struct_size`, set before the call.
        unsafe {
            state
                .as_mut_ptr()
                .cast::<u32>()
                .write(std::mem::size_of::<cg_entity_state>() as u32)
        };
        assert_eq!(
            unsafe { cg_entity_state_init(state.as_mut_ptr()) },
            cg_status::Ok
        );
        // SAFETY: initialised just above.
        let mut state = unsafe { state.assume_init() };
        state.id = id;
        state.position = desc.position;
        state.flags = CG_STATE_HEADING_FROM_MOTION;
        states.push(state);
    }
    let mut gaze = vec![cg_gaze_info::default(); 200];
    let mut eyelids = vec![cg_eyelids::default(); 200];
    let mut frame = |t: f64| {
        for (i, state) in states.iter_mut().enumerate() {
            state.position.x += if i % 2 == 0 { 0.04 } else { -0.04 };
        }
        if t * 30.0 % 3.0 < 2.0 {
            assert_eq!(
                unsafe { cg_crowd_push_frame(handle, t, states.as_ptr(), states.len()) },
                cg_status::Ok
            );
        } else {
            // The ranged push: three parts.
            assert_eq!(unsafe { cg_crowd_begin_push(handle, t) }, cg_status::Ok);
            for part in [&states[..70], &states[70..150], &states[150..]] {
                assert_eq!(
                    unsafe { cg_crowd_push_range(handle, part.as_ptr(), part.len()) },
                    cg_status::Ok
                );
            }
            assert_eq!(unsafe { cg_crowd_end_push(handle) }, cg_status::Ok);
        }
        if t * 30.0 % 2.0 < 1.0 {
            assert_eq!(unsafe { cg_crowd_step(handle, 1.0 / 30.0) }, cg_status::Ok);
        } else {
            // The ranged form: three ranges, the rest stepped by end_step.
            assert_eq!(
                unsafe { cg_crowd_begin_step(handle, 1.0 / 30.0) },
                cg_status::Ok
            );
            for (first, count) in [(0, 64), (128, 50), (64, 40)] {
                assert_eq!(
                    unsafe { cg_crowd_step_range(handle, first, count) },
                    cg_status::Ok
                );
            }
            assert_eq!(unsafe { cg_crowd_end_step(handle) }, cg_status::Ok);
        }
        let mut written = 0;
        assert_eq!(
            unsafe { cg_crowd_read_gaze(handle, gaze.as_mut_ptr(), gaze.len(), &mut written) },
            cg_status::Ok
        );
        assert_eq!(written, 200);
        assert_eq!(
            unsafe { cg_crowd_read_eyelids(handle, 0, 200, eyelids.as_mut_ptr(), eyelids.len()) },
            cg_status::Ok
        );
    };
    for i in 0..10 {
        frame(f64::from(i) / 30.0);
    }
    assert_no_alloc(
        "push_frame (and begin/range/end) + step (and begin/range/end, and storage \
         reorders) + read_gaze + read_eyelids",
        || {
            for i in 10..100 {
                frame(f64::from(i) / 30.0);
            }
        },
    );
    assert!(gaze.iter().any(|g| g.s_max > 0.0));
    unsafe { cg_crowd_destroy(handle) };
}

#[test]
fn gaze_motion_update_does_not_allocate() {
    use crowdgaze::ik::{
        CharacterTransform, GazeChain, GazeConfig, GazeInput, GazeMotion, GazeRequest,
    };
    use crowdgaze::math::random::{stream, Purpose};
    use glam::{Quat, Vec3};

    let chain = GazeChain::human(Vec3::Y, Vec3::Z);
    let config = GazeConfig::default();
    let base = [Quat::IDENTITY; 10];
    let mut motion = GazeMotion::new(&chain);
    let mut random = stream(1, Purpose::GazeTiming, 0);
    let character = CharacterTransform::from_heading(Vec3::new(1.0, 0.0, 2.0), Vec3::Y, 0.5);
    let mut frame = |request: Option<GazeRequest>, motion: &mut GazeMotion| {
        let input = GazeInput {
            character,
            base: &base,
            request,
            dt: 1.0 / 30.0,
        };
        motion.update(&chain, &config, &input, &mut random).unwrap();
    };
    // Warm-up (may allocate, e.g. thread-locals).
    frame(
        Some(GazeRequest::at(1, Vec3::new(0.0, 1.6, 5.0))),
        &mut motion,
    );
    assert_no_alloc("GazeMotion::update", || {
        for step in 0..300 {
            let time = step as f32 / 30.0;
            // A moving target, a new target, targets behind and at the eye, then none.
            let request = match step {
                0..=89 => Some(GazeRequest::at(1, Vec3::new(3.0 - time, 1.6, 2.0))),
                90..=179 => Some(GazeRequest::at(2, Vec3::new(-1.0, 1.8, -3.0))),
                180..=209 => Some(GazeRequest::at(3, Vec3::new(1.0, 1.62, 2.085))),
                _ => None,
            };
            frame(request, &mut motion);
        }
    });
}

#[test]
fn view_blending_does_not_allocate_per_frame() {
    use crowdgaze::ffi::blend::*;
    use crowdgaze::ffi::status::cg_status;
    use crowdgaze::ffi::types::{cg_dualquat, cg_quat, cg_vec3};
    use crowdgaze::ffi::view_blender::*;

    let (joints, keys) = (27usize, 3u32);
    let dq = |angle: f32, y: f32| {
        let (sin, cos) = (angle / 2.0).sin_cos();
        let real = cg_quat {
            x: 0.0,
            y: sin,
            z: 0.0,
            w: cos,
        };
        // dual = ½ (0, 0, y, 0)·real
        let dual = cg_quat {
            x: 0.5 * y * sin,
            y: 0.5 * y * cos,
            z: 0.0,
            w: 0.0,
        };
        cg_dualquat { real, dual }
    };
    for method in [cg_blend_method::Dlb, cg_blend_method::Dib] {
        // Setup (allocates): config, blender, three 10-frame looping clips, three cameras.
        let mut config = std::mem::MaybeUninit::<cg_view_blender_config>::uninit();
        // SAFETY: a versioned struct starts with its `uint32_t struct_size`, set before the call.
        unsafe {
            config
                .as_mut_ptr()
                .cast::<u32>()
                .write(std::mem::size_of::<cg_view_blender_config>() as u32)
        };
        assert_eq!(
            unsafe { cg_view_blender_config_init(config.as_mut_ptr()) },
            cg_status::Ok
        );
        // SAFETY: initialised by cg_view_blender_config_init.
        let mut config = unsafe { config.assume_init() };
        config.joint_count = joints as u32;
        config.key_count = keys;
        config.method = method as u32;
        let mut blender = std::ptr::null_mut();
        assert_eq!(
            unsafe { cg_view_blender_create(&config, &mut blender) },
            cg_status::Ok
        );
        for key in 0..keys {
            let frames: Vec<cg_dualquat> = (0..10 * joints)
                .map(|i| dq((key as f32 - 1.0) * 0.5 + 0.02 * (i / joints) as f32, 0.2))
                .collect();
            assert_eq!(
                unsafe {
                    cg_view_blender_set_key_clip(blender, key, frames.as_ptr(), 10, 30.0, true)
                },
                cg_status::Ok
            );
            let angle = (key as f32 - 1.0) * 1.0;
            let direction = cg_vec3 {
                x: angle.sin(),
                y: 0.0,
                z: angle.cos(),
            };
            assert_eq!(
                unsafe { cg_view_blender_add_camera(blender, direction, key) },
                cg_status::Ok
            );
        }
        let character = dq(0.3, 0.0);
        let mut weights = [0.0f32; 3];
        let mut pose = vec![dq(0.0, 0.0); joints];

        assert_no_alloc("cg_view_blender_weights and _evaluate", || {
            for frame in 0..120 {
                let angle = frame as f32 * 0.05;
                let viewer = cg_vec3 {
                    x: 4.0 * angle.sin(),
                    y: 1.6,
                    z: 4.0 * angle.cos(),
                };
                assert_eq!(
                    unsafe {
                        cg_view_blender_weights(
                            blender,
                            &character,
                            &viewer,
                            weights.as_mut_ptr(),
                            3,
                        )
                    },
                    cg_status::Ok
                );
                let status = unsafe {
                    cg_view_blender_evaluate(
                        blender,
                        &character,
                        &viewer,
                        f64::from(frame) / 30.0,
                        pose.as_mut_ptr(),
                        joints,
                    )
                };
                assert_eq!(status, cg_status::Ok);
            }
            // The stateless blends too, on the last pose (3 keys of 9 joints).
            let mut out = [pose[0]; 9];
            assert_eq!(
                unsafe {
                    cg_blend_pose_dlb(pose.as_ptr(), weights.as_ptr(), 3, 9, out.as_mut_ptr())
                },
                cg_status::Ok
            );
            assert_eq!(
                unsafe {
                    cg_blend_pose_dib(
                        pose.as_ptr(),
                        weights.as_ptr(),
                        3,
                        9,
                        1e-6,
                        16,
                        out.as_mut_ptr(),
                    )
                },
                cg_status::Ok
            );
            assert_eq!(
                unsafe {
                    cg_blend_dib(
                        pose.as_ptr(),
                        weights.as_ptr(),
                        3,
                        1e-6,
                        16,
                        out.as_mut_ptr(),
                    )
                },
                cg_status::Ok
            );
        });
        unsafe { cg_view_blender_destroy(blender) };
    }
}

#[test]
fn every_attention_model_and_gaze_ik_step_without_allocating() {
    use crowdgaze::scenario::Scenario;
    use crowdgaze::{Crowd, CrowdConfig};

    let mut crowd = Crowd::new(CrowdConfig::default()).unwrap();
    let mut scenario = Scenario::street(90, 30, 6);
    scenario.populate(&mut crowd).unwrap();
    support::mix_attention_models(&mut crowd, scenario.character_ids());
    let viewer_at = |frame: usize| glam::Vec3::new(5.0, 1.7, frame as f32 * 0.01);
    let mut frame = 0usize;
    let mut advance = |crowd: &mut Crowd, scenario: &mut Scenario| {
        frame += 1;
        scenario.advance(1.0 / 30.0);
        scenario.push(crowd, frame as f64 / 30.0).unwrap();
        crowd.set_viewer(viewer_at(frame), 2.0).unwrap();
        crowd.step(1.0 / 30.0).unwrap();
        let mut joints = [glam::Quat::IDENTITY; 900];
        crowd.read_joints(0, 90, false, &mut joints).unwrap();
        (0..90)
            .map(|character| crowd.eyelids_at(character).left_closure)
            .fold(0.0f32, f32::max)
    };
    for _ in 0..30 {
        advance(&mut crowd, &mut scenario);
    }
    // The steps blink (at 17 a minute, 90 characters blink a few times a second).
    let closed = assert_no_alloc(
        "crowd, saliency and baseline models with gaze IK, blinks and their eyelids read",
        || {
            (0..120)
                .map(|_| advance(&mut crowd, &mut scenario))
                .fold(0.0f32, f32::max)
        },
    );
    assert!(closed > 0.5, "no one blinked: {closed}");
}

#[test]
fn conversations_step_without_allocating() {
    use crowdgaze::scenario::Scenario;
    use crowdgaze::{Crowd, CrowdConfig};

    let mut crowd = Crowd::new(CrowdConfig::default()).unwrap();
    let mut scenario = Scenario::street(90, 20, 8).with_conversations(1.0 / 3.0, 4);
    scenario.populate(&mut crowd).unwrap();
    support::mix_attention_models(&mut crowd, scenario.character_ids());
    let mut frame = 0usize;
    let mut advance = |crowd: &mut Crowd, scenario: &mut Scenario| {
        frame += 1;
        scenario.advance(1.0 / 30.0);
        scenario.push(crowd, frame as f64 / 30.0).unwrap();
        crowd.step(1.0 / 30.0).unwrap();
        (0..90)
            .filter(|&character| crowd.gaze_at(character).target != u32::MAX)
            .count()
    };
    for _ in 0..30 {
        advance(&mut crowd, &mut scenario);
    }
    let looking = assert_no_alloc("groups talking in turns, all three models", || {
        (0..300)
            .map(|_| advance(&mut crowd, &mut scenario))
            .sum::<usize>()
    });
    assert!(looking > 0);
    // Forming and ending a group allocates nothing either (its slot was made at creation).
    let ids: Vec<u32> = scenario.character_ids().to_vec();
    let group = scenario.groups[0].conversation.unwrap();
    assert_no_alloc("ending and forming a conversation", || {
        crowd.remove_conversation(group).unwrap();
        crowd.set_conversation(&ids[..2]).unwrap();
    });
}

#[test]
fn rig_conversions_do_not_allocate_per_frame() {
    use crowdgaze::ffi::chain::cg_chain_desc;
    use crowdgaze::ffi::gaze::*;
    use crowdgaze::ffi::rig::*;
    use crowdgaze::ffi::types::cg_quat;

    // Setup (allocates): the Mixamo rig, a crowd in centimetres with the character, and a
    // few seconds of the engine's poses.
    let skeleton = support::rig::Skeleton::mixamo();
    let rig = skeleton.rig(100.0);
    let mut chain: cg_chain_desc = unsafe { std::mem::zeroed() };
    chain.struct_size = std::mem::size_of::<cg_chain_desc>() as u32;
    support::check(unsafe { cg_rig_chain(rig.0, &mut chain) }, "cg_rig_chain");
    let mut config: crowdgaze::ffi::crowd::cg_crowd_config =
        support::init(crowdgaze::ffi::crowd::cg_crowd_config_init);
    config.units_per_metre = 100.0;
    let crowd = support::CrowdHandle::new(&config);
    let mut desc: crowdgaze::ffi::attention::cg_character_desc =
        support::init(crowdgaze::ffi::attention::cg_character_desc_init);
    desc.chain = &chain;
    let mut id = 0;
    support::check(
        unsafe {
            crowdgaze::ffi::attention::cg_crowd_add_character(crowd.as_mut(), &desc, &mut id)
        },
        "cg_crowd_add_character",
    );
    let poses: Vec<Vec<cg_quat>> = (0..30).map(|f| skeleton.animated(f as f32 * 0.1)).collect();
    let mut bones = poses[0].clone();
    let (mut base, mut joints) = ([cg_quat::IDENTITY; 7], [cg_quat::IDENTITY; 7]);
    let mut report = [0 as std::ffi::c_char; 64];
    let state = support::entity_state(id, 0.0, false);
    let ok = crowdgaze::ffi::status::cg_status::Ok;
    for (frame, pose) in poses.iter().enumerate() {
        // The first frame warms up; every later one must not allocate in the rig's calls.
        let check = |what: &str, work: &mut dyn FnMut()| {
            if frame == 0 {
                work();
            } else {
                assert_no_alloc(what, work);
            }
        };
        check("cg_rig_base_pose", &mut || {
            bones.copy_from_slice(pose);
            let status =
                unsafe { cg_rig_base_pose(rig.0, bones.as_ptr(), 65, base.as_mut_ptr(), 7) };
            assert_eq!(status, ok);
        });
        assert_eq!(
            unsafe { cg_crowd_set_base_pose(crowd.as_mut(), id, base.as_ptr(), 7) },
            ok
        );
        crowd.push_and_step(
            frame as f64 / 30.0,
            1.0 / 30.0,
            std::slice::from_ref(&state),
        );
        assert_eq!(
            unsafe { cg_crowd_read_joints(crowd.as_const(), 0, 1, joints.as_mut_ptr(), 7) },
            ok
        );
        check("cg_rig_write_joints and cg_rig_report", &mut || {
            let status =
                unsafe { cg_rig_write_joints(rig.0, joints.as_ptr(), 7, bones.as_mut_ptr(), 65) };
            assert_eq!(status, ok);
            assert!(unsafe { cg_rig_report(rig.0, report.as_mut_ptr(), 64) } > 64);
        });
    }
}

#[test]
fn the_street_model_and_gaze_following_step_and_read_without_allocating() {
    use crowdgaze::ffi::attention::{
        cg_attention_model, cg_character_desc, cg_character_desc_init, cg_crowd_add_character,
    };
    use crowdgaze::ffi::crowd::{cg_crowd_config, cg_crowd_config_init_street};
    use crowdgaze::ffi::following::cg_crowd_read_following;
    use crowdgaze::ffi::gaze::{cg_crowd_set_gaze_target, cg_gaze_target, cg_gaze_target_init};
    use crowdgaze::ffi::types::cg_vec3;
    use glam::Vec3;

    let mut config: cg_crowd_config = support::init(cg_crowd_config_init_street);
    config.max_characters = 40;
    let crowd = support::CrowdHandle::new(&config);
    // Five people stare at a point up high; 35 street-model characters walk past them.
    let mut states = Vec::new();
    for i in 0..40 {
        let walking = i >= 5;
        let position = if walking {
            Vec3::new(2.0 + (i % 5) as f32, 0.0, -12.0 + (i % 8) as f32 * 3.0)
        } else {
            Vec3::new(-1.0 + 0.5 * i as f32, 0.0, 0.0)
        };
        let mut desc: cg_character_desc = support::init(cg_character_desc_init);
        desc.attention_model = cg_attention_model::Street as u32;
        desc.position = position.into();
        let mut id = 0;
        let status = unsafe { cg_crowd_add_character(crowd.as_mut(), &desc, &mut id) };
        support::check(status, "cg_crowd_add_character");
        let mut state = support::entity_state(id, 0.0, walking);
        state.position = position.into();
        states.push((state, if i % 2 == 0 { 0.04 } else { -0.04 }));
    }
    let mut target: cg_gaze_target = support::init(cg_gaze_target_init);
    target.point = cg_vec3 {
        x: 0.0,
        y: 12.0,
        z: -6.0,
    };
    for (state, _) in &states[..5] {
        let status = unsafe { cg_crowd_set_gaze_target(crowd.as_mut(), state.id, &target) };
        support::check(status, "cg_crowd_set_gaze_target");
    }
    let mut pushed: Vec<_> = states.iter().map(|(state, _)| *state).collect();
    let mut frame = 0;
    let mut advance = || {
        frame += 1;
        for (state, (_, speed)) in pushed.iter_mut().zip(&states).skip(5) {
            state.position.z += speed;
        }
        crowd.push_and_step(f64::from(frame) / 30.0, 1.0 / 30.0, &pushed);
        let mut glances_in_all = 0;
        for state in &pushed {
            let (mut point, mut following, mut glances) = (cg_vec3::default(), 0, 0);
            let status = unsafe {
                cg_crowd_read_following(
                    crowd.as_const(),
                    state.id,
                    &mut point,
                    &mut following,
                    &mut glances,
                )
            };
            support::check(status, "cg_crowd_read_following");
            glances_in_all += glances;
        }
        glances_in_all
    };
    for _ in 0..30 {
        advance();
    }
    let glances = assert_no_alloc("the street model, gaze following and its reader", || {
        (0..300).map(|_| advance()).max().unwrap_or(0)
    });
    assert!(glances > 0, "no one followed the stare");
}
