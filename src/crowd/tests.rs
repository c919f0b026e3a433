//! Unit tests of the parent module.

use glam::Vec3;

use super::*;
use crate::error::Error;
use crate::ik::GazeChain;

#[test]
fn capacities_are_checked() {
    assert!(Crowd::new(CrowdConfig::default()).is_ok());
    let none = CrowdConfig {
        max_characters: 0,
        ..CrowdConfig::default()
    };
    assert!(matches!(Crowd::new(none), Err(Error::InvalidArgument(_))));
    let huge = CrowdConfig {
        max_objects: MAX_CAPACITY + 1,
        ..CrowdConfig::default()
    };
    assert!(matches!(Crowd::new(huge), Err(Error::InvalidArgument(_))));
}

use crate::alloc::fault::fail_after;
use crate::scenario::Scenario;

/// Runs `operation` with its `n`-th fallible allocation failing, for n = 0, 1, ...
/// until it succeeds; checks every failure is an out-of-memory error naming what it
/// sized and the bytes, and that `unchanged` holds after it. Returns the failures seen.
fn fail_each_allocation<T>(
    mut operation: impl FnMut() -> Result<T>,
    mut unchanged: impl FnMut(),
) -> usize {
    for n in 0.. {
        fail_after(Some(n));
        let result = operation();
        fail_after(None);
        match result {
            Ok(_) => return n,
            Err(Error::OutOfMemory(message)) => {
                assert!(
                    message.contains(" = ") || message.contains(" × "),
                    "{message}"
                );
                assert!(message.ends_with(" bytes"), "{message}");
            }
            Err(other) => panic!("allocation {n}: {other}"),
        }
        unchanged();
    }
    unreachable!()
}

#[test]
fn every_allocation_of_a_create_fails_cleanly() {
    let config = CrowdConfig {
        max_recorded_states: 100,
        threads: 3,
        ..CrowdConfig::default()
    };
    let failures = fail_each_allocation(|| Crowd::new(config.clone()), || {});
    // The scene, the neighbour index, the per-character arrays, the recording...
    assert!(failures >= 30, "{failures}");
}

#[test]
fn recordings_too_large_for_memory_fail_naming_the_field() {
    let config = CrowdConfig {
        max_recorded_states: u32::MAX,
        ..CrowdConfig::default()
    };
    // 275 GB of address space: refused by the allocator on most machines, reserved
    // untouched where memory is overcommitted.
    match Crowd::new(config) {
        Ok(crowd) => assert_eq!(crowd.config().max_recorded_states, u32::MAX),
        Err(error) => assert!(
            error
                .to_string()
                .starts_with("out of memory: max_recorded_states = 4294967295 needs "),
            "{error}"
        ),
    }
}

#[test]
fn a_new_chain_that_does_not_fit_adds_nothing() {
    let mut crowd = Crowd::new(CrowdConfig::default()).unwrap();
    crowd.add_character(&CharacterDesc::default()).unwrap();
    let human = GazeChain::human(Vec3::Y, Vec3::Z);
    let other = GazeChain::new(human.joints(), Vec3::Z, Vec3::Y, Vec3::Y * 0.9).unwrap();
    assert_ne!(other, human);
    let desc = CharacterDesc {
        chain: Some(other),
        ..CharacterDesc::default()
    };
    let before = format!("{:?}", crowd.scene());
    fail_after(Some(0));
    let result = crowd.add_character(&desc);
    fail_after(None);
    assert!(matches!(result, Err(Error::OutOfMemory(_))), "{result:?}");
    assert_eq!(crowd.character_count(), 1);
    assert_eq!(format!("{:?}", crowd.scene()), before);
    assert_eq!(crowd.shared.chains.all.len(), 1);
    crowd.add_character(&desc).unwrap();
    assert_eq!(crowd.shared.chains.all.len(), 2);
}

#[test]
fn a_plan_that_does_not_fit_changes_nothing() {
    let recorded = || {
        let config = CrowdConfig {
            max_characters: 40,
            max_objects: 8,
            max_recorded_states: 48 * 60,
            ..CrowdConfig::default()
        };
        let mut crowd = Crowd::new(config).unwrap();
        let mut scenario = Scenario::street(30, 6, 7);
        scenario.populate(&mut crowd).unwrap();
        for frame in 0..60 {
            scenario.advance(1.0 / 30.0);
            scenario.push(&mut crowd, frame as f64 / 30.0).unwrap();
        }
        crowd.rebuild_grid();
        crowd
    };
    let state = |crowd: &Crowd| {
        format!(
            "{:?} {:?} {}",
            crowd.shared.scene,
            crowd.shared.neighbours,
            crowd.is_planned()
        )
    };
    let mut crowd = recorded();
    let before = state(&crowd);
    let crowd_cell = std::cell::RefCell::new(&mut crowd);
    let failures = fail_each_allocation(
        || crowd_cell.borrow_mut().plan(),
        || assert_eq!(state(&crowd_cell.borrow()), before),
    );
    assert!(failures >= 15, "{failures}");
    let mut reference = recorded();
    reference.plan().unwrap();
    assert_eq!(state(&crowd), state(&reference));
    for id in 0..30 {
        if let Ok(constraints) = reference.constraints(id) {
            assert_eq!(crowd.constraints(id).unwrap(), constraints);
        }
    }
}
