//! Long random sequences of C API calls on one crowd — good and bad arguments mixed — must
//! never panic (`CG_STATUS_INTERNAL`), never leave a NaN in any output, and keep the crowd
//! usable. Deterministic (seeded); a quick cousin of a fuzz target.

// The `unsafe { cg_... }` calls below pass pointers to live values of the sizes the header
// asks for, or deliberately bad ones (NULL, misaligned, wrong struct_size) that the library
// must refuse: that is their safety comment, once for the file.
#![allow(clippy::undocumented_unsafe_blocks)]

use crowdgaze::ffi::attention::*;

use crowdgaze::ffi::crowd::*;
use crowdgaze::ffi::frame::*;
use crowdgaze::ffi::gaze::*;
use crowdgaze::ffi::status::cg_status;
use crowdgaze::ffi::types::{cg_quat, cg_vec3};
use crowdgaze::math::random::Random;
use std::mem::MaybeUninit;
use std::ptr::{null, null_mut};

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
    assert_eq!(unsafe { f(value.as_mut_ptr()) }, cg_status::Ok);
    // SAFETY: initialised by the _init function just above.
    unsafe { value.assume_init() }
}

struct Fuzz {
    random: Random,
}

impl Fuzz {
    fn float(&mut self) -> f32 {
        match self.random.below(20) {
            0 => f32::NAN,
            1 => f32::INFINITY,
            2 => -1.0e30,
            3 => 0.0,
            _ => self.random.range(-12.0, 12.0),
        }
    }
    fn good_float(&mut self) -> f32 {
        self.random.range(-12.0, 12.0)
    }
    fn vec3(&mut self, bad: bool) -> cg_vec3 {
        if bad {
            cg_vec3 {
                x: self.float(),
                y: self.float(),
                z: self.float(),
            }
        } else {
            cg_vec3 {
                x: self.good_float(),
                y: 0.0,
                z: self.good_float(),
            }
        }
    }
    fn id(&mut self, known: &[u32]) -> u32 {
        match (self.random.below(6), known.is_empty()) {
            (0, _) | (_, true) => self.random.next_u64() as u32,
            _ => known[self.random.below(known.len() as u32) as usize],
        }
    }
}

fn no_nan(values: &[f32], what: &str) {
    assert!(values.iter().all(|v| v.is_finite()), "{what}: {values:?}");
}

#[test]
fn random_call_sequences_never_panic_or_produce_nan() {
    for seed in 0..4u64 {
        let mut fuzz = Fuzz {
            random: Random::new(seed),
        };
        let mut config: cg_crowd_config = init(cg_crowd_config_init);
        config.max_characters = 12;
        config.max_objects = 4;
        config.max_recorded_states = 400;
        let mut crowd = null_mut();
        assert_eq!(
            unsafe { cg_crowd_create(&config, &mut crowd) },
            cg_status::Ok
        );
        let mut ids: Vec<u32> = Vec::new();
        let mut time = 0.0f64;
        let mut succeeded = 0;
        let mut failed = 0;
        for step in 0..4000 {
            let bad = fuzz.random.below(5) == 0;
            let status = match fuzz.random.below(14) {
                0 | 1 => {
                    let mut desc: cg_character_desc = init(cg_character_desc_init);
                    desc.position = fuzz.vec3(bad);
                    desc.heading = if bad { fuzz.float() } else { fuzz.good_float() };
                    desc.attention_model = fuzz.random.below(if bad { 5 } else { 3 });
                    let mut id = 0;
                    let status = unsafe { cg_crowd_add_character(crowd, &desc, &mut id) };
                    if status == cg_status::Ok {
                        ids.push(id);
                    }
                    status
                }
                2 => {
                    let mut desc: cg_object_desc = init(cg_object_desc_init);
                    desc.position = fuzz.vec3(bad);
                    desc.impact = if bad { fuzz.float() } else { 1.0 };
                    let mut id = 0;
                    let status = unsafe { cg_crowd_add_object(crowd, &desc, &mut id) };
                    if status == cg_status::Ok {
                        ids.push(id);
                    }
                    status
                }
                3 => {
                    let id = fuzz.id(&ids);
                    let status = unsafe { cg_crowd_remove_entity(crowd, id) };
                    if status == cg_status::Ok {
                        ids.retain(|&known| known != id);
                    }
                    status
                }
                4 | 5 => {
                    let count = fuzz.random.below(6) as usize;
                    let states: Vec<cg_entity_state> = (0..count)
                        .map(|_| {
                            let mut state: cg_entity_state = init(cg_entity_state_init);
                            state.id = fuzz.id(&ids);
                            state.position = fuzz.vec3(bad);
                            state.flags = fuzz.random.below(if bad { 8 } else { 4 });
                            state.velocity = fuzz.vec3(bad);
                            state
                        })
                        .collect();
                    time += if bad { -0.5 } else { 1.0 / 30.0 };
                    let pointer = if bad && count > 0 && fuzz.random.below(2) == 0 {
                        null()
                    } else {
                        states.as_ptr()
                    };
                    let status = unsafe { cg_crowd_push_frame(crowd, time, pointer, count) };
                    if status != cg_status::Ok && !bad {
                        time -= 1.0 / 30.0;
                    }
                    status
                }
                6 | 7 => {
                    let dt = if bad { fuzz.float() } else { 1.0 / 30.0 };
                    unsafe { cg_crowd_step(crowd, dt) }
                }
                8 => {
                    let mut gaze = vec![cg_gaze_info::default(); 16];
                    let mut written = 0;
                    let status =
                        unsafe { cg_crowd_read_gaze(crowd, gaze.as_mut_ptr(), 16, &mut written) };
                    for g in &gaze[..written] {
                        no_nan(
                            &[
                                g.target_position.x,
                                g.target_position.y,
                                g.target_position.z,
                                g.s_max,
                                g.attentive_fraction,
                            ],
                            "gaze",
                        );
                    }
                    status
                }
                9 => {
                    let first = fuzz.random.below(14);
                    let count = fuzz.random.below(14);
                    let mut joints = vec![cg_quat::IDENTITY; fuzz.random.below(160) as usize];
                    let status = unsafe {
                        cg_crowd_read_joints(crowd, first, count, joints.as_mut_ptr(), joints.len())
                    };
                    if status == cg_status::Ok {
                        for q in &joints {
                            no_nan(&[q.x, q.y, q.z, q.w], "joints");
                        }
                    }
                    let mut eyes = vec![cg_eye_info::default(); 14];
                    let eye_status = unsafe {
                        cg_crowd_read_eyes(crowd, first, count, eyes.as_mut_ptr(), eyes.len())
                    };
                    if eye_status == cg_status::Ok {
                        for e in &eyes[..count as usize] {
                            no_nan(
                                &[e.left_origin.x, e.left_direction.y, e.right_direction.z],
                                "eyes",
                            );
                        }
                    }
                    status
                }
                10 => {
                    let mut target: cg_gaze_target = init(cg_gaze_target_init);
                    target.kind = fuzz.random.below(if bad { 4 } else { 2 });
                    target.priority = fuzz.random.below(if bad { 4 } else { 2 });
                    target.entity = fuzz.id(&ids);
                    target.point = fuzz.vec3(bad);
                    let character = fuzz.id(&ids);
                    if fuzz.random.below(4) == 0 {
                        unsafe { cg_crowd_clear_gaze_target(crowd, character) }
                    } else {
                        unsafe { cg_crowd_set_gaze_target(crowd, character, &target) }
                    }
                }
                11 => {
                    let count = if bad {
                        fuzz.random.below(20) as usize
                    } else {
                        10
                    };
                    let local: Vec<cg_quat> = (0..count)
                        .map(|_| cg_quat {
                            x: if bad {
                                fuzz.float()
                            } else {
                                fuzz.random.range(-0.2, 0.2)
                            },
                            y: fuzz.random.range(-0.2, 0.2),
                            z: 0.0,
                            w: 1.0,
                        })
                        .collect();
                    unsafe { cg_crowd_set_base_pose(crowd, fuzz.id(&ids), local.as_ptr(), count) }
                }
                12 => {
                    let position = fuzz.vec3(bad);
                    let mut id = 0;
                    match fuzz.random.below(4) {
                        0 => unsafe {
                            cg_crowd_set_attention_period(
                                crowd,
                                fuzz.id(&ids),
                                fuzz.random.below(70),
                            )
                        },
                        1 => {
                            let status =
                                unsafe { cg_crowd_set_viewer(crowd, &position, 1.0, &mut id) };
                            if status == cg_status::Ok && !ids.contains(&id) {
                                ids.push(id);
                            }
                            status
                        }
                        2 => unsafe { cg_crowd_plan(crowd) },
                        _ => unsafe { cg_crowd_clear_plan(crowd) },
                    }
                }
                _ => {
                    let mut score = cg_score_breakdown::default();
                    let status =
                        unsafe { cg_crowd_score(crowd, fuzz.id(&ids), fuzz.id(&ids), &mut score) };
                    if status == cg_status::Ok {
                        no_nan(&[score.total, score.distance, score.view_angle], "score");
                    }
                    status
                }
            };
            if status == cg_status::Ok {
                succeeded += 1;
            } else {
                failed += 1;
            }
            if status == cg_status::Internal {
                panic!(
                    "seed {seed}, call {step}: internal error: {}",
                    crowdgaze::ffi::last_error::last_error_message()
                );
            }
        }
        println!("seed {seed}: {succeeded} calls succeeded, {failed} failed as documented");
        // Both kinds must be well represented for the sequence to mean anything.
        assert!(succeeded > 1500 && failed > 400, "{succeeded} / {failed}");
        // Still usable afterwards.
        assert_eq!(unsafe { cg_crowd_clear_plan(crowd) }, cg_status::Ok);
        assert_eq!(unsafe { cg_crowd_step(crowd, 1.0 / 30.0) }, cg_status::Ok);
        unsafe { cg_crowd_destroy(crowd) };
    }
}
