//! The ranged push: a frame pushed in parts, from one thread or several, gives the same
//! outputs bit for bit as one `push_frame` of the whole frame, on crowds of 1 and 4
//! threads; misuse is an error that changes nothing; and the same through the C API.

// The `unsafe { cg_... }` calls below pass pointers to live values of the sizes the header
// asks for: that is their safety comment, once for the file.
#![allow(clippy::undocumented_unsafe_blocks)]

mod support;

use std::sync::atomic::{AtomicUsize, Ordering};

use crowdgaze::error::Error;
use crowdgaze::scenario::Scenario;
use crowdgaze::scene::EntityUpdate;
use crowdgaze::{Crowd, CrowdConfig};
use glam::Vec3;

const PEOPLE: usize = 150;
const FRAMES: usize = 60;
const DT: f32 = 1.0 / 30.0;

/// How a test pushes a frame's states at time `t` into a crowd.
type Push<'a> = &'a dyn Fn(&mut Crowd, f64, &[EntityUpdate], usize);

/// The mixed street on `threads` threads; every third walker also gives its velocity, so
/// that both velocity paths run.
fn street(threads: u32) -> (Crowd, Scenario) {
    let config = CrowdConfig {
        threads,
        ..support::mixed_street_config()
    };
    support::mixed_street(config, PEOPLE, 40, 11)
}

/// The scenario's states for this frame.
fn states(crowd: &Crowd, scenario: &Scenario, frame: usize) -> Vec<EntityUpdate> {
    let world = crowd.config().world;
    (0..scenario.people.len())
        .map(|i| {
            let mut update = scenario.update(&world, i);
            if (i + frame).is_multiple_of(3) {
                let person = &scenario.people[i];
                update.velocity =
                    Some(world.forward * person.velocity.x + world.side * person.velocity.y);
            }
            update
        })
        .collect()
}

/// Runs the street for `FRAMES` frames on `threads` threads, pushing with `push`, and
/// returns every frame's outputs.
fn run(threads: u32, push: Push<'_>) -> Vec<Vec<u32>> {
    let (mut crowd, mut scenario) = street(threads);
    (0..FRAMES)
        .map(|frame| {
            scenario.advance(DT);
            let updates = states(&crowd, &scenario, frame);
            push(
                &mut crowd,
                (frame + 1) as f64 * f64::from(DT),
                &updates,
                frame,
            );
            crowd
                .set_viewer(Vec3::new(2.0 + frame as f32 * 0.05, 1.7, 1.0), 2.0)
                .unwrap();
            crowd.step(DT).unwrap();
            support::output_bits(&crowd)
        })
        .collect()
}

fn whole_frame(crowd: &mut Crowd, t: f64, updates: &[EntityUpdate], _: usize) {
    crowd.push_frame(t, updates).unwrap();
}

/// Ranges of odd sizes in a scrambled order, from one thread.
fn scrambled_ranges(crowd: &mut Crowd, t: f64, updates: &[EntityUpdate], frame: usize) {
    crowd.begin_push(t).unwrap();
    let size = 1 + (frame * 7) % 23;
    let mut parts: Vec<&[EntityUpdate]> = updates.chunks(size).collect();
    let turn = frame % parts.len();
    parts.rotate_left(turn);
    parts.reverse();
    for part in parts {
        crowd.push_range(part).unwrap();
    }
    crowd.end_push().unwrap();
}

/// Chunks taken by `threads` threads as they come.
fn concurrent_ranges(threads: usize) -> impl Fn(&mut Crowd, f64, &[EntityUpdate], usize) {
    move |crowd, t, updates, frame| {
        crowd.begin_push(t).unwrap();
        let ranges = crowd.push_ranges().unwrap();
        let chunk = 9 + frame % 13;
        let next = AtomicUsize::new(0);
        std::thread::scope(|scope| {
            for _ in 0..threads {
                scope.spawn(|| loop {
                    let first = next.fetch_add(chunk, Ordering::Relaxed);
                    if first >= updates.len() {
                        break;
                    }
                    let end = (first + chunk).min(updates.len());
                    ranges.push(&updates[first..end]).unwrap();
                });
            }
        });
        crowd.end_push().unwrap();
    }
}

#[test]
fn pushes_in_ranges_give_the_outputs_of_one_push() {
    for crowd_threads in [1, 4] {
        let expected = run(crowd_threads, &whole_frame);
        assert!(expected.first() != expected.last(), "the crowd moves");
        let what = |how: &str| format!("{how}, crowd of {crowd_threads} threads");
        support::assert_same(
            &expected,
            &run(crowd_threads, &scrambled_ranges),
            &what("scrambled ranges"),
        );
        for threads in [1, 2, 4] {
            support::assert_same(
                &expected,
                &run(crowd_threads, &concurrent_ranges(threads)),
                &what(&format!("ranges from {threads} threads")),
            );
        }
    }
}

#[test]
fn entities_left_out_of_a_ranged_push_keep_their_state() {
    // Pushing only half the people in ranges is pushing only that half in one call.
    let half = |crowd: &mut Crowd, t: f64, updates: &[EntityUpdate], _: usize| {
        crowd.begin_push(t).unwrap();
        for part in updates[..PEOPLE / 2].chunks(10) {
            crowd.push_range(part).unwrap();
        }
        crowd.end_push().unwrap();
    };
    let half_at_once = |crowd: &mut Crowd, t: f64, updates: &[EntityUpdate], _: usize| {
        crowd.push_frame(t, &updates[..PEOPLE / 2]).unwrap();
    };
    support::assert_same(&run(1, &half_at_once), &run(1, &half), "half the people");
}

/// Positions, velocities and headings of every entity, as bits.
fn scene_bits(crowd: &Crowd) -> Vec<u32> {
    let scene = crowd.scene();
    let mut bits: Vec<u32> = scene
        .positions()
        .iter()
        .flat_map(|p| p.to_array().map(f32::to_bits))
        .collect();
    bits.extend(scene.headings().iter().map(|h| h.to_bits()));
    let time = crowd.time().to_bits();
    bits.extend([time as u32, (time >> 32) as u32]);
    bits
}

#[test]
fn ranged_push_misuse_is_an_error_that_changes_nothing() {
    let (mut crowd, mut scenario) = street(1);
    scenario.advance(DT);
    scenario.push(&mut crowd, f64::from(DT)).unwrap();
    crowd.step(DT).unwrap();
    scenario.advance(DT);
    let updates = states(&crowd, &scenario, 1);
    let t = 2.0 * f64::from(DT);

    assert!(matches!(
        crowd.push_range(&updates),
        Err(Error::WrongState(_))
    ));
    assert!(matches!(crowd.end_push(), Err(Error::WrongState(_))));
    assert!(matches!(
        crowd.begin_push(f64::NAN),
        Err(Error::NonFinite(_))
    ));
    assert!(matches!(
        crowd.begin_push(0.0),
        Err(Error::InvalidArgument(_))
    ));
    assert!(!crowd.is_push_open());

    crowd.begin_push(t).unwrap();
    assert!(crowd.is_push_open());
    // While a push is open nothing else changes the crowd.
    assert!(matches!(crowd.begin_push(t), Err(Error::WrongState(_))));
    assert!(matches!(
        crowd.push_frame(t, &updates),
        Err(Error::WrongState(_))
    ));
    assert!(matches!(crowd.step(DT), Err(Error::WrongState(_))));
    assert!(matches!(crowd.begin_step(DT), Err(Error::WrongState(_))));
    assert!(matches!(
        crowd.set_viewer(Vec3::ZERO, 1.0),
        Err(Error::WrongState(_))
    ));
    crowd.push_range(&updates[10..20]).unwrap();
    let before = scene_bits(&crowd);
    // An entity pushed already (by an earlier range, or twice in this one), an unknown
    // id, a non-finite value: the range is refused whole.
    assert!(matches!(
        crowd.push_range(&updates[0..11]),
        Err(Error::WrongState(_))
    ));
    let twice = [updates[30], updates[31], updates[30]];
    assert!(matches!(
        crowd.push_range(&twice),
        Err(Error::WrongState(_))
    ));
    let mut unknown = updates[40..45].to_vec();
    unknown[3].id = 123_456_789;
    assert!(matches!(
        crowd.push_range(&unknown),
        Err(Error::NotFound(_))
    ));
    let mut nan = updates[40..45].to_vec();
    nan[4].position.x = f32::NAN;
    assert!(matches!(crowd.push_range(&nan), Err(Error::NonFinite(_))));
    assert_eq!(scene_bits(&crowd), before, "a refused range pushed nothing");
    // The refused ranges took nothing: their entities can still be pushed.
    crowd.push_range(&updates[0..10]).unwrap();
    crowd.push_range(&updates[20..]).unwrap();
    crowd.end_push().unwrap();
    assert!(!crowd.is_push_open());
    assert_eq!(crowd.time(), t);
    crowd.step(DT).unwrap();

    // The same frame in one push gives the same crowd.
    let (mut reference, mut reference_scenario) = street(1);
    reference_scenario.advance(DT);
    reference_scenario
        .push(&mut reference, f64::from(DT))
        .unwrap();
    reference.step(DT).unwrap();
    reference.push_frame(t, &updates).unwrap();
    reference.step(DT).unwrap();
    assert_eq!(
        support::output_bits(&crowd),
        support::output_bits(&reference)
    );
}

#[test]
fn racing_ranges_of_the_same_entity_never_both_push_it() {
    let (mut crowd, mut scenario) = street(1);
    scenario.advance(DT);
    let updates = states(&crowd, &scenario, 0);
    for _ in 0..50 {
        crowd.begin_push(crowd.time().max(0.0) + 0.01).unwrap();
        let ranges = crowd.push_ranges().unwrap();
        let pushed = AtomicUsize::new(0);
        std::thread::scope(|scope| {
            for _ in 0..2 {
                scope.spawn(|| {
                    if ranges.push(&updates).is_ok() {
                        pushed.fetch_add(1, Ordering::Relaxed);
                    }
                });
            }
        });
        assert!(
            pushed.into_inner() <= 1,
            "both ranges pushed the same entities"
        );
        crowd.end_push().unwrap();
    }
}

#[test]
fn recording_crowds_push_whole_frames() {
    let config = CrowdConfig {
        max_recorded_states: 1000,
        ..support::mixed_street_config()
    };
    let (mut crowd, _) = support::mixed_street(config, 10, 2, 3);
    assert!(matches!(crowd.begin_push(0.1), Err(Error::WrongState(_))));
    assert!(!crowd.is_push_open());
}

/// The C API: begin, ranges from four threads, end; the same outputs as
/// `cg_crowd_push_frame`; WRONG_STATE for every other call meanwhile.
mod c_api {
    use super::support::{check, init, CrowdHandle};
    use crowdgaze::ffi::attention::*;
    use crowdgaze::ffi::crowd::*;
    use crowdgaze::ffi::frame::*;
    use crowdgaze::ffi::gaze::{cg_crowd_joint_total, cg_crowd_read_joints};
    use crowdgaze::ffi::status::cg_status;
    use crowdgaze::ffi::types::cg_quat;
    use glam::Vec3;
    use std::sync::atomic::{AtomicUsize, Ordering};

    const CHARACTERS: usize = 300;

    struct Shared(*mut cg_crowd);
    // SAFETY: only cg_crowd_push_range runs concurrently, as the header allows.
    unsafe impl Sync for Shared {}

    fn crowd() -> (CrowdHandle, Vec<cg_entity_state>) {
        let mut config: cg_crowd_config = init(cg_crowd_config_init);
        config.max_characters = CHARACTERS as u32;
        let crowd = CrowdHandle::new(&config);
        let states = (0..CHARACTERS)
            .map(|i| {
                let position = Vec3::new((i % 16) as f32 * 1.3, 0.0, (i / 16) as f32 * 1.7);
                let id = crowd.add_character(position, i as f32 * 0.7);
                let mut state: cg_entity_state = init(cg_entity_state_init);
                state.id = id;
                state.position = position.into();
                state.heading = i as f32 * 0.7;
                state.flags = if i % 2 == 0 {
                    CG_STATE_HEADING_FROM_MOTION | CG_STATE_HAS_VELOCITY
                } else {
                    0
                };
                state
            })
            .collect();
        (crowd, states)
    }

    /// Moves every state a little along its own direction at frame `frame`.
    fn advance(states: &mut [cg_entity_state], frame: usize) {
        for (i, state) in states.iter_mut().enumerate() {
            let angle = i as f32 * 0.37 + frame as f32 * 0.02;
            let velocity = Vec3::new(angle.cos(), 0.0, angle.sin()) * 1.2;
            state.velocity = velocity.into();
            state.position.x += velocity.x / 30.0;
            state.position.z += velocity.z / 30.0;
            state.heading += 0.01;
        }
    }

    /// Every character's gaze and final joint rotations, as bits.
    fn outputs(crowd: &CrowdHandle) -> Vec<u32> {
        let mut gaze = vec![cg_gaze_info::default(); CHARACTERS];
        let mut written = 0;
        check(
            unsafe {
                cg_crowd_read_gaze(
                    crowd.as_const(),
                    gaze.as_mut_ptr(),
                    gaze.len(),
                    &mut written,
                )
            },
            "cg_crowd_read_gaze",
        );
        let mut total = 0;
        check(
            unsafe { cg_crowd_joint_total(crowd.as_const(), 0, CHARACTERS as u32, &mut total) },
            "cg_crowd_joint_total",
        );
        let mut joints = vec![cg_quat::IDENTITY; total];
        check(
            unsafe {
                cg_crowd_read_joints(
                    crowd.as_const(),
                    0,
                    CHARACTERS as u32,
                    joints.as_mut_ptr(),
                    total,
                )
            },
            "cg_crowd_read_joints",
        );
        let mut bits: Vec<u32> = gaze
            .iter()
            .flat_map(|g| {
                [
                    g.target,
                    g.threshold.to_bits(),
                    g.target_position.x.to_bits(),
                    g.target_position.y.to_bits(),
                    g.target_position.z.to_bits(),
                ]
            })
            .collect();
        bits.extend(
            joints
                .iter()
                .flat_map(|q| [q.x, q.y, q.z, q.w].map(f32::to_bits)),
        );
        bits
    }

    #[test]
    fn ranges_from_four_threads_match_one_push() {
        let (whole, mut states) = crowd();
        let (ranged, _) = crowd();
        let shared = Shared(ranged.as_mut());
        for frame in 0..30 {
            advance(&mut states, frame);
            let t = (frame + 1) as f64 / 30.0;
            whole.push_and_step(t, 1.0 / 30.0, &states);
            check(
                unsafe { cg_crowd_begin_push(ranged.as_mut(), t) },
                "cg_crowd_begin_push",
            );
            let next = AtomicUsize::new(0);
            std::thread::scope(|scope| {
                for _ in 0..4 {
                    scope.spawn(|| {
                        let shared = &shared;
                        loop {
                            let first = next.fetch_add(37, Ordering::Relaxed);
                            if first >= CHARACTERS {
                                break;
                            }
                            let part = &states[first..(first + 37).min(CHARACTERS)];
                            check(
                                unsafe { cg_crowd_push_range(shared.0, part.as_ptr(), part.len()) },
                                "cg_crowd_push_range",
                            );
                        }
                    });
                }
            });
            check(
                unsafe { cg_crowd_end_push(ranged.as_mut()) },
                "cg_crowd_end_push",
            );
            check(
                unsafe { cg_crowd_step(ranged.as_mut(), 1.0 / 30.0) },
                "cg_crowd_step",
            );
            assert_eq!(outputs(&whole), outputs(&ranged), "frame {frame}");
        }
    }

    #[test]
    fn other_calls_wait_for_the_end_of_the_push() {
        let (crowd, states) = crowd();
        let handle = crowd.as_mut();
        let wrong = cg_status::WrongState;
        check(unsafe { cg_crowd_begin_push(handle, 0.5) }, "begin");
        assert_eq!(unsafe { cg_crowd_begin_push(handle, 0.5) }, wrong);
        assert_eq!(unsafe { cg_crowd_begin_step(handle, 0.1) }, wrong);
        assert_eq!(unsafe { cg_crowd_step(handle, 0.1) }, wrong);
        assert_eq!(unsafe { cg_crowd_step_range(handle, 0, 1) }, wrong);
        assert_eq!(unsafe { cg_crowd_end_step(handle) }, wrong);
        assert_eq!(
            unsafe { cg_crowd_push_frame(handle, 0.5, states.as_ptr(), states.len()) },
            wrong
        );
        let mut gaze = [cg_gaze_info::default(); 1];
        let mut written = 0;
        assert_eq!(
            unsafe { cg_crowd_read_gaze(handle, gaze.as_mut_ptr(), 1, &mut written) },
            wrong
        );
        check(
            unsafe { cg_crowd_push_range(handle, states.as_ptr(), states.len()) },
            "push_range",
        );
        check(unsafe { cg_crowd_end_push(handle) }, "end");
        assert_eq!(unsafe { cg_crowd_end_push(handle) }, wrong);
        assert_eq!(
            unsafe { cg_crowd_push_range(handle, states.as_ptr(), states.len()) },
            wrong
        );
        check(unsafe { cg_crowd_step(handle, 0.1) }, "step after the push");
    }
}

/// A crowd of `count` characters standing at x = 0, 1, 2, ... and their ids.
fn standing(count: usize) -> (Crowd, Vec<u32>) {
    let mut crowd = Crowd::new(CrowdConfig::default()).unwrap();
    let ids = (0..count)
        .map(|i| {
            let desc = crowdgaze::CharacterDesc {
                position: Vec3::new(i as f32, 0.0, 0.0),
                ..Default::default()
            };
            crowd.add_character(&desc).unwrap()
        })
        .collect();
    (crowd, ids)
}

/// Entity `id`'s position.
fn position(crowd: &Crowd, id: u32) -> Vec3 {
    crowd.scene().positions()[crowd.scene().index_of(id).unwrap()]
}

/// Entity `id` moved to `position`.
fn moved(id: u32, x: f32) -> EntityUpdate {
    EntityUpdate {
        id,
        position: Vec3::new(x, 0.0, 5.0),
        heading: 0.0,
        heading_from_motion: false,
        velocity: None,
        talking: false,
    }
}

/// True if entity `id` can still be claimed in the open push (then it is, by this call).
fn claimable(crowd: &mut Crowd, id: u32) -> bool {
    crowd.push_range(&[moved(id, 100.0)]).is_ok()
}

/// A state closure with interior mutability: state 0 is `first` the first time it is
/// asked for and `later` after that; state 1 is `other`.
fn changing(
    first: EntityUpdate,
    later: EntityUpdate,
    other: EntityUpdate,
) -> impl Fn(usize) -> Result<EntityUpdate, Error> {
    let calls = std::cell::Cell::new(0);
    move |i| {
        if i > 0 {
            return Ok(other);
        }
        calls.set(calls.get() + 1);
        Ok(if calls.get() == 1 { first } else { later })
    }
}

#[test]
fn a_state_closure_naming_another_entity_the_second_time_writes_only_its_claims() {
    let (mut crowd, ids) = standing(4);
    let [a, b, c, d] = ids[..] else { panic!() };
    crowd.begin_push(1.0).unwrap();
    // Another call has pushed c; this one claims a and b, and is given c for a when it
    // applies.
    crowd.push_range(&[moved(c, 30.0)]).unwrap();
    let ranges = crowd.push_ranges().unwrap();
    let result = ranges.push_with(2, changing(moved(a, -1.0), moved(c, -1.0), moved(b, 20.0)));
    assert!(
        matches!(result, Err(Error::InvalidArgument(_))),
        "{result:?}"
    );
    // The claims are intact: a, b and c stay taken until the push ends.
    for taken in [a, b, c] {
        assert!(
            !claimable(&mut crowd, taken),
            "entity {taken} was given back"
        );
    }
    assert!(claimable(&mut crowd, d));
    crowd.end_push().unwrap();
    assert_eq!(
        position(&crowd, c).x,
        30.0,
        "another call's entity is not written"
    );
    assert_eq!(
        position(&crowd, a).x,
        0.0,
        "a state that changed is skipped"
    );
    assert_eq!(
        position(&crowd, b).x,
        20.0,
        "the consistent state is applied"
    );
}

#[test]
fn a_failed_push_gives_back_its_own_claims_whatever_the_closure_says() {
    let (mut crowd, ids) = standing(3);
    let [a, b, c] = ids[..] else { panic!() };
    crowd.begin_push(1.0).unwrap();
    crowd.push_range(&[moved(c, 30.0)]).unwrap();
    let ranges = crowd.push_ranges().unwrap();
    // State 0 is a, then c (another call's claim) when asked again; state 1 an unknown id:
    // the call fails and gives back a, not c.
    let unknown = moved(u32::MAX - 1, 0.0);
    let result = ranges.push_with(2, changing(moved(a, -1.0), moved(c, -1.0), unknown));
    assert!(matches!(result, Err(Error::NotFound(_))), "{result:?}");
    assert!(
        !claimable(&mut crowd, c),
        "another call's claim was given back"
    );
    assert!(claimable(&mut crowd, a), "the failed call's claim was kept");
    assert!(claimable(&mut crowd, b));
    crowd.end_push().unwrap();
    assert_eq!(position(&crowd, c).x, 30.0);
}

#[test]
fn threads_with_inconsistent_closures_never_write_each_others_entities() {
    // Each thread claims its own quarter, then names the next thread's entities when asked
    // again: nothing is written, and every entity stays its owner's.
    const THREADS: usize = 4;
    const EACH: usize = 64;
    let (mut crowd, ids) = standing(THREADS * EACH);
    let before: Vec<Vec3> = ids.iter().map(|&id| position(&crowd, id)).collect();
    for round in 0..20 {
        crowd.begin_push(1.0 + round as f64).unwrap();
        let ranges = crowd.push_ranges().unwrap();
        let errors = AtomicUsize::new(0);
        std::thread::scope(|scope| {
            for thread in 0..THREADS {
                let (ids, ranges, errors) = (&ids, &ranges, &errors);
                scope.spawn(move || {
                    let calls: Vec<AtomicUsize> = (0..EACH).map(|_| AtomicUsize::new(0)).collect();
                    let result = ranges.push_with(EACH, |i| {
                        let later = calls[i].fetch_add(1, Ordering::Relaxed) > 0;
                        let owner = if later {
                            (thread + 1) % THREADS
                        } else {
                            thread
                        };
                        Ok::<_, Error>(moved(ids[owner * EACH + i], -7.0))
                    });
                    if matches!(result, Err(Error::InvalidArgument(_))) {
                        errors.fetch_add(1, Ordering::Relaxed);
                    }
                });
            }
        });
        assert_eq!(errors.into_inner(), THREADS);
        crowd.end_push().unwrap();
        for (k, &id) in ids.iter().enumerate() {
            assert_eq!(
                position(&crowd, id),
                before[k],
                "round {round}: entity {id}"
            );
        }
    }
    // Consistent closures on the same threads (counting their calls) push everything.
    crowd.begin_push(100.0).unwrap();
    let ranges = crowd.push_ranges().unwrap();
    std::thread::scope(|scope| {
        for thread in 0..THREADS {
            let (ids, ranges) = (&ids, &ranges);
            scope.spawn(move || {
                let calls = AtomicUsize::new(0);
                ranges
                    .push_with(EACH, |i| {
                        calls.fetch_add(1, Ordering::Relaxed);
                        Ok::<_, Error>(moved(ids[thread * EACH + i], i as f32))
                    })
                    .unwrap();
                assert_eq!(calls.into_inner(), 2 * EACH);
            });
        }
    });
    crowd.end_push().unwrap();
    for (k, &id) in ids.iter().enumerate() {
        assert_eq!(position(&crowd, id).x, (k % EACH) as f32);
    }
}

#[test]
fn a_whole_frame_closure_giving_another_state_the_second_time_is_refused() {
    let (mut crowd, ids) = standing(3);
    let [a, b, c] = ids[..] else { panic!() };
    for later in [moved(b, 9.0), moved(a, f32::NAN), moved(u32::MAX - 1, 9.0)] {
        let time = crowd.time().max(0.0) + 1.0;
        let result = crowd.push_frame_with(time, 2, changing(moved(a, 1.5), later, moved(c, 7.0)));
        assert!(
            matches!(result, Err(Error::InvalidArgument(_))),
            "{later:?}"
        );
        assert_eq!(position(&crowd, a).x, 0.0, "{later:?}: skipped");
        assert_eq!(position(&crowd, b).x, 1.0, "{later:?}: not written");
        assert_eq!(position(&crowd, c).x, 7.0, "{later:?}: applied");
    }
}
