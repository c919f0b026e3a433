//! Threaded and ranged steps: identical outputs for 1, 2 and 4 threads and for any split
//! into ranges, ranges stepped concurrently from several threads, and the ranged step's
//! state rules through the C API.

// The `unsafe { cg_... }` calls below pass pointers to live values of the sizes the header
// asks for, or deliberately bad ones (NULL, misaligned, wrong struct_size) that the library
// must refuse: that is their safety comment, once for the file.
#![allow(clippy::undocumented_unsafe_blocks)]

mod support;

use crowdgaze::scenario::Scenario;
use crowdgaze::{Crowd, CrowdConfig};
use glam::Vec3;

const PEOPLE: usize = 150;
const FRAMES: usize = 90;
const DT: f32 = 1.0 / 30.0;

/// The mixed street of the support module on `threads` threads.
fn street(threads: u32) -> (Crowd, Scenario) {
    let config = CrowdConfig {
        threads,
        ..support::mixed_street_config()
    };
    support::mixed_street(config, PEOPLE, 40, 11)
}

/// Runs the street for `FRAMES` frames, stepping each with `step`, and returns the outputs
/// of every frame.
fn run(threads: u32, mut step: impl FnMut(&mut Crowd, usize)) -> Vec<Vec<u32>> {
    let (mut crowd, mut scenario) = street(threads);
    (0..FRAMES)
        .map(|frame| {
            scenario.advance(DT);
            scenario
                .push(&mut crowd, (frame + 1) as f64 * f64::from(DT))
                .unwrap();
            let viewer = Vec3::new(2.0 + frame as f32 * 0.05, 1.7, 1.0);
            crowd.set_viewer(viewer, 2.0).unwrap();
            step(&mut crowd, frame);
            support::output_bits(&crowd)
        })
        .collect()
}

#[test]
fn one_two_and_four_threads_give_identical_outputs() {
    let single = run(1, |crowd, _| crowd.step(DT).unwrap());
    // The crowd did something: people attend, heads turn.
    let last = single.last().unwrap();
    assert!(single.first().unwrap() != last);
    for threads in [2, 4, 0] {
        let threaded = run(threads, |crowd, _| crowd.step(DT).unwrap());
        support::assert_same(&single, &threaded, &format!("{threads} threads"));
    }
    // The two halves of a step, apart (the benchmarks' forms), on 1 and 3 threads.
    let halves = |crowd: &mut Crowd, _: usize| {
        crowd.step_attention(DT).unwrap();
        crowd.step_gaze(DT).unwrap();
    };
    let single_halves = run(1, halves);
    assert!(
        single_halves != single,
        "the halves advance twice per frame"
    );
    support::assert_same(
        &single_halves,
        &run(3, halves),
        "attention and gaze apart, 3 threads",
    );
}

#[test]
fn any_split_into_ranges_gives_identical_outputs() {
    let single = run(1, |crowd, _| crowd.step(DT).unwrap());
    // Ranges of odd sizes, in a scrambled order, one thread.
    let scrambled = run(1, |crowd, frame| {
        crowd.begin_step(DT).unwrap();
        let count = crowd.character_count();
        let size = 1 + (frame * 7) % 23;
        let mut starts: Vec<usize> = (0..count).step_by(size).collect();
        starts.reverse();
        let turn = frame % starts.len();
        starts.rotate_left(turn);
        for first in starts {
            crowd.step_range(first, size.min(count - first)).unwrap();
        }
        crowd.end_step().unwrap();
    });
    support::assert_same(&single, &scrambled, "scrambled ranges");
    // Only some ranges: end_step steps the rest.
    let partial = run(1, |crowd, frame| {
        crowd.begin_step(DT).unwrap();
        let count = crowd.character_count();
        crowd
            .step_range(frame % count, 10.min(count - frame % count))
            .unwrap();
        crowd.step_range(0, 3.min(frame % count)).unwrap();
        crowd.end_step().unwrap();
    });
    support::assert_same(&single, &partial, "partial ranges");
}

#[test]
fn ranges_stepped_from_four_threads_give_identical_outputs() {
    let single = run(1, |crowd, _| crowd.step(DT).unwrap());
    let concurrent = run(1, |crowd, frame| {
        crowd.begin_step(DT).unwrap();
        let ranges = crowd.step_ranges().unwrap();
        let count = ranges.character_count();
        let chunk = 17 + frame % 5;
        let next = std::sync::atomic::AtomicUsize::new(0);
        std::thread::scope(|scope| {
            for _ in 0..4 {
                scope.spawn(|| loop {
                    let first = next.fetch_add(chunk, std::sync::atomic::Ordering::Relaxed);
                    if first >= count {
                        break;
                    }
                    ranges.run_range(first, chunk.min(count - first)).unwrap();
                });
            }
        });
        crowd.end_step().unwrap();
    });
    support::assert_same(&single, &concurrent, "four threads on ranges");
}

#[test]
fn ranged_step_misuse_is_an_error_that_changes_nothing() {
    use crowdgaze::error::Error;
    let (mut crowd, mut scenario) = street(1);
    scenario.advance(DT);
    scenario.push(&mut crowd, f64::from(DT)).unwrap();
    assert!(matches!(crowd.step_range(0, 1), Err(Error::WrongState(_))));
    assert!(matches!(crowd.end_step(), Err(Error::WrongState(_))));
    crowd.begin_step(DT).unwrap();
    assert!(crowd.is_step_open());
    assert!(matches!(crowd.begin_step(DT), Err(Error::WrongState(_))));
    let count = crowd.character_count();
    assert!(matches!(
        crowd.step_range(count - 1, 2),
        Err(Error::InvalidArgument(_))
    ));
    assert!(matches!(
        crowd.step_range(usize::MAX, 2),
        Err(Error::InvalidArgument(_))
    ));
    crowd.step_range(10, 20).unwrap();
    let before = support::output_bits(&crowd);
    assert!(matches!(crowd.step_range(0, 11), Err(Error::WrongState(_))));
    assert!(matches!(crowd.step_range(29, 5), Err(Error::WrongState(_))));
    assert_eq!(
        support::output_bits(&crowd),
        before,
        "a refused range stepped nothing"
    );
    // Structural changes wait for the end of the step.
    assert!(matches!(
        scenario.push(&mut crowd, 2.0 * f64::from(DT)),
        Err(Error::WrongState(_))
    ));
    assert!(matches!(
        crowd.set_viewer(Vec3::ZERO, 1.0),
        Err(Error::WrongState(_))
    ));
    // The refused ranges took nothing: 0..10 and 30..34 can still be stepped.
    crowd.step_range(0, 10).unwrap();
    crowd.step_range(30, 4).unwrap();
    crowd.end_step().unwrap();
    assert!(!crowd.is_step_open());
    crowd.step(DT).unwrap();
}

/// The C API: begin, ranges from four threads, end; and WRONG_STATE on misuse.
mod c_api {
    use crowdgaze::ffi::attention::*;
    use crowdgaze::ffi::crowd::*;
    use crowdgaze::ffi::frame::*;
    use crowdgaze::ffi::status::cg_status;
    use crowdgaze::ffi::types::cg_vec3;

    struct Handle(*mut cg_crowd);
    // SAFETY: the tests below follow the crowd's threading rules (only step_range runs
    // concurrently).
    unsafe impl Send for Handle {}
    // SAFETY: as above.
    unsafe impl Sync for Handle {}

    fn crowd(threads: u32, characters: u32) -> *mut cg_crowd {
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
        config.threads = threads;
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
        for i in 0..characters {
            desc.position = cg_vec3 {
                x: (i % 16) as f32 * 1.3,
                y: 0.0,
                z: (i / 16) as f32 * 1.7,
            };
            desc.heading = i as f32 * 0.7;
            let mut id = 0;
            assert_eq!(
                unsafe { cg_crowd_add_character(handle, &desc, &mut id) },
                cg_status::Ok
            );
        }
        handle
    }

    fn gaze(handle: *mut cg_crowd) -> Vec<cg_gaze_info> {
        let mut count = 0;
        assert_eq!(
            unsafe { cg_crowd_character_count(handle, &mut count) },
            cg_status::Ok
        );
        let mut out = vec![cg_gaze_info::default(); count];
        let mut written = 0;
        assert_eq!(
            unsafe { cg_crowd_read_gaze(handle, out.as_mut_ptr(), out.len(), &mut written) },
            cg_status::Ok
        );
        out
    }

    /// Every character's final joint rotations, as bits.
    fn joints(handle: *mut cg_crowd) -> Vec<u32> {
        use crowdgaze::ffi::gaze::{cg_crowd_joint_total, cg_crowd_read_joints};
        use crowdgaze::ffi::types::cg_quat;
        let mut count = 0;
        assert_eq!(
            unsafe { cg_crowd_character_count(handle, &mut count) },
            cg_status::Ok
        );
        let mut total = 0;
        assert_eq!(
            unsafe { cg_crowd_joint_total(handle, 0, count as u32, &mut total) },
            cg_status::Ok
        );
        let mut out = vec![
            cg_quat {
                x: 0.0,
                y: 0.0,
                z: 0.0,
                w: 1.0
            };
            total
        ];
        assert_eq!(
            unsafe { cg_crowd_read_joints(handle, 0, count as u32, out.as_mut_ptr(), total) },
            cg_status::Ok
        );
        out.iter()
            .flat_map(|q| [q.x, q.y, q.z, q.w].map(f32::to_bits))
            .collect()
    }

    fn same(a: &[cg_gaze_info], b: &[cg_gaze_info]) -> bool {
        let bits = |g: &cg_gaze_info| {
            (
                g.character,
                g.target,
                g.s_max.to_bits(),
                g.threshold.to_bits(),
                g.target_position.x.to_bits(),
                g.target_position.z.to_bits(),
            )
        };
        a.iter().map(bits).eq(b.iter().map(bits))
    }

    #[test]
    fn ranges_from_four_threads_match_one_call_steps() {
        let one_call = crowd(1, 300);
        let pooled = crowd(2, 300);
        let ranged = crowd(1, 300);
        let shared = Handle(ranged);
        for frame in 0..40 {
            assert_eq!(unsafe { cg_crowd_step(one_call, 0.05) }, cg_status::Ok);
            assert_eq!(unsafe { cg_crowd_step(pooled, 0.05) }, cg_status::Ok);
            assert_eq!(unsafe { cg_crowd_begin_step(ranged, 0.05) }, cg_status::Ok);
            let next = std::sync::atomic::AtomicU32::new(0);
            std::thread::scope(|scope| {
                for _ in 0..4 {
                    scope.spawn(|| {
                        let handle = &shared;
                        loop {
                            let first = next.fetch_add(32, std::sync::atomic::Ordering::Relaxed);
                            if first >= 300 {
                                break;
                            }
                            let count = 32.min(300 - first);
                            assert_eq!(
                                unsafe { cg_crowd_step_range(handle.0, first, count) },
                                cg_status::Ok
                            );
                        }
                    });
                }
            });
            assert_eq!(unsafe { cg_crowd_end_step(ranged) }, cg_status::Ok);
            let expected = gaze(one_call);
            assert!(same(&expected, &gaze(pooled)), "pool, frame {frame}");
            assert!(same(&expected, &gaze(ranged)), "ranges, frame {frame}");
            let expected = joints(one_call);
            assert!(expected == joints(pooled), "pool joints, frame {frame}");
            assert!(expected == joints(ranged), "ranged joints, frame {frame}");
        }
        assert!(gaze(one_call).iter().any(|g| g.s_max > 0.0));
        for handle in [one_call, pooled, ranged] {
            unsafe { cg_crowd_destroy(handle) };
        }
    }

    #[test]
    fn misuse_returns_wrong_state_and_changes_nothing() {
        let handle = crowd(1, 40);
        assert_eq!(
            unsafe { cg_crowd_step_range(handle, 0, 1) },
            cg_status::WrongState
        );
        assert_eq!(unsafe { cg_crowd_end_step(handle) }, cg_status::WrongState);
        assert_eq!(unsafe { cg_crowd_step(handle, 0.05) }, cg_status::Ok);
        let before = gaze(handle);
        assert_eq!(
            unsafe { cg_crowd_begin_step(handle, f32::NAN) },
            cg_status::NonFinite
        );
        assert_eq!(
            unsafe { cg_crowd_begin_step(handle, -1.0) },
            cg_status::InvalidArgument
        );
        assert_eq!(
            unsafe { cg_crowd_step_range(handle, 0, 1) },
            cg_status::WrongState
        );
        assert_eq!(unsafe { cg_crowd_begin_step(handle, 0.05) }, cg_status::Ok);
        assert_eq!(
            unsafe { cg_crowd_begin_step(handle, 0.05) },
            cg_status::WrongState
        );
        // Every other call waits for the end of the step.
        assert_eq!(
            unsafe { cg_crowd_step(handle, 0.05) },
            cg_status::WrongState
        );
        let mut count = 0;
        assert_eq!(
            unsafe { cg_crowd_character_count(handle, &mut count) },
            cg_status::WrongState
        );
        assert_eq!(
            unsafe { cg_crowd_remove_entity(handle, 1) },
            cg_status::WrongState
        );
        assert_eq!(
            unsafe { cg_crowd_step_range(handle, 30, 11) },
            cg_status::InvalidArgument
        );
        assert_eq!(unsafe { cg_crowd_step_range(handle, 5, 10) }, cg_status::Ok);
        assert_eq!(
            unsafe { cg_crowd_step_range(handle, 14, 3) },
            cg_status::WrongState
        );
        assert_eq!(unsafe { cg_crowd_step_range(handle, 0, 0) }, cg_status::Ok);
        assert_eq!(
            unsafe { cg_crowd_step_range(std::ptr::null_mut(), 0, 1) },
            cg_status::NullArgument
        );
        assert_eq!(unsafe { cg_crowd_end_step(handle) }, cg_status::Ok);
        assert_eq!(unsafe { cg_crowd_end_step(handle) }, cg_status::WrongState);
        // The refused calls changed nothing: this crowd matches one stepped twice.
        let reference = crowd(1, 40);
        assert_eq!(unsafe { cg_crowd_step(reference, 0.05) }, cg_status::Ok);
        assert!(same(&before, &gaze(reference)));
        assert_eq!(unsafe { cg_crowd_step(reference, 0.05) }, cg_status::Ok);
        assert!(same(&gaze(reference), &gaze(handle)));
        assert!(joints(reference) == joints(handle));
        // A crowd destroyed with a step open is released cleanly.
        assert_eq!(unsafe { cg_crowd_begin_step(handle, 0.05) }, cg_status::Ok);
        unsafe { cg_crowd_destroy(handle) };
        unsafe { cg_crowd_destroy(reference) };
    }

    #[test]
    fn threads_out_of_range_is_refused() {
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
        assert_eq!(config.threads, 1);
        config.threads = 65;
        let mut handle = std::ptr::null_mut();
        assert_eq!(
            unsafe { cg_crowd_create(&config, &mut handle) },
            cg_status::InvalidArgument
        );
        assert!(handle.is_null());
        // A caller built before `reorder_period` existed has a 144-byte struct and says so:
        // its `threads` is read, `reorder_period` takes its default, and nothing past its
        // struct is read or written (guard bytes follow it here).
        #[repr(C, align(8))]
        struct Older {
            config: [u8; 144],
            guard: [u8; 64],
        }
        let older_size = std::mem::offset_of!(cg_crowd_config, reorder_period);
        assert_eq!(older_size, 144);
        let mut older = Older {
            config: [0; 144],
            guard: [0xA5; 64],
        };
        config.threads = 9;
        config.struct_size = older_size as u32;
        // SAFETY: copies the first 144 bytes of a cg_crowd_config into a 144-byte array.
        unsafe {
            std::ptr::copy_nonoverlapping(
                (&config as *const cg_crowd_config).cast::<u8>(),
                older.config.as_mut_ptr(),
                older_size,
            )
        };
        let older_config = (&mut older as *mut Older).cast::<cg_crowd_config>();
        assert_eq!(
            unsafe { cg_crowd_create(older_config, &mut handle) },
            cg_status::Ok
        );
        older.config = [0; 144];
        older.config[..4].copy_from_slice(&(older_size as u32).to_ne_bytes());
        assert_eq!(
            unsafe { cg_crowd_get_config(handle, older_config) },
            cg_status::Ok
        );
        assert_eq!(older.guard, [0xA5; 64], "written past the caller's struct");
        let field = |offset: usize| {
            u32::from_ne_bytes(older.config[offset..offset + 4].try_into().unwrap())
        };
        assert_eq!(field(0), 144, "struct_size keeps the caller's value");
        assert_eq!(field(std::mem::offset_of!(cg_crowd_config, threads)), 9);
        let mut read = std::mem::MaybeUninit::<cg_crowd_config>::uninit();
        // SAFETY: a versioned struct starts with its `uint32_t struct_size`, set before the call.
        unsafe {
            read.as_mut_ptr()
                .cast::<u32>()
                .write(std::mem::size_of::<cg_crowd_config>() as u32)
        };
        assert_eq!(
            unsafe { cg_crowd_get_config(handle, read.as_mut_ptr()) },
            cg_status::Ok
        );
        // SAFETY: written by the call above.
        let read = unsafe { read.assume_init() };
        assert_eq!((read.threads, read.reorder_period), (9, 0));
        unsafe { cg_crowd_destroy(handle) };
    }
}

/// A crowd filled to capacity with the viewer added before the last character: every
/// entity is in the spatial grid (the viewer's slot is counted), so each character is
/// stepped and the viewer can be looked at. (The grid once held one entity too few.)
#[test]
fn a_full_crowd_with_a_viewer_steps_everyone() {
    use crowdgaze::crowd::CharacterDesc;
    let config = CrowdConfig {
        max_characters: 3,
        max_objects: 0,
        ..CrowdConfig::default()
    };
    for threads in [1, 2] {
        let mut crowd = Crowd::new(CrowdConfig {
            threads,
            ..config.clone()
        })
        .unwrap();
        let watcher = crowd.add_character(&CharacterDesc::default()).unwrap();
        crowd
            .add_character(&CharacterDesc {
                position: Vec3::new(-6.0, 0.0, -6.0),
                ..CharacterDesc::default()
            })
            .unwrap();
        let viewer = crowd.set_viewer(Vec3::new(0.0, 1.7, 2.0), 5.0).unwrap();
        crowd
            .add_character(&CharacterDesc {
                position: Vec3::new(6.0, 0.0, -6.0),
                ..CharacterDesc::default()
            })
            .unwrap();
        let mut looked_at_viewer = false;
        for _ in 0..60 {
            crowd.step(DT).unwrap();
            looked_at_viewer |= crowd.gaze(watcher).unwrap().target == viewer;
        }
        assert!(
            looked_at_viewer,
            "{threads} threads: the viewer was never looked at"
        );
    }
}

/// From 30 000 characters on, attention visits characters in spatial-grid order: the
/// outputs still equal the ranged step's (dense ranges) bit for bit, on 1 and 2 threads.
#[test]
fn a_large_crowd_in_grid_order_matches_dense_ranges() {
    let characters = 30_000;
    let plaza = |threads: u32| {
        let mut crowd = Crowd::new(CrowdConfig {
            max_characters: characters as u32,
            max_objects: 0,
            threads,
            ..CrowdConfig::default()
        })
        .unwrap();
        let mut scenario = Scenario::plaza(characters, 0.25, 3);
        scenario.populate(&mut crowd).unwrap();
        (crowd, scenario)
    };
    let run = |threads: u32, ranged: bool| {
        let (mut crowd, mut scenario) = plaza(threads);
        for frame in 0..6 {
            scenario.advance(DT);
            scenario
                .push(&mut crowd, f64::from(frame) * f64::from(DT))
                .unwrap();
            if ranged {
                crowd.begin_step(DT).unwrap();
                for first in (0..characters).step_by(1000) {
                    crowd.step_range(first, 1000).unwrap();
                }
                crowd.end_step().unwrap();
            } else {
                crowd.step(DT).unwrap();
            }
        }
        support::output_bits(&crowd)
    };
    let ranged = run(1, true);
    assert!(ranged == run(1, false), "grid order, 1 thread");
    assert!(ranged == run(2, false), "grid order, 2 threads");
}

#[test]
fn the_mixed_street_steps_every_model_and_follows_gaze() {
    // What the identity tests above compare includes street-model walkers and gaze
    // following (three people stare up; passers-by may look too).
    let (mut crowd, mut scenario) = street(1);
    for frame in 0..FRAMES * 3 {
        scenario.advance(DT);
        scenario
            .push(&mut crowd, (frame + 1) as f64 * f64::from(DT))
            .unwrap();
        crowd.step(DT).unwrap();
    }
    let glances: u32 = scenario
        .character_ids()
        .iter()
        .map(|&id| crowd.following(id).unwrap().1)
        .sum();
    let street_fixations: u32 = scenario
        .character_ids()
        .iter()
        .skip(3)
        .step_by(4)
        .map(|&id| crowd.gaze(id).unwrap().interest_count)
        .sum();
    assert!(glances > 0, "nobody followed the starers' gaze");
    assert!(street_fixations > 0, "the street walkers fixated nobody");
}
