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

/// The readers' published copy (`Published`) is written by a step when the readers were
/// used since the step before, is used right after it and equals what the readers compute
/// from the state; after any change it is left alone until the next step, and the readers
/// compute again.
#[test]
fn published_outputs_equal_the_readers_and_go_stale_on_any_change() {
    let config = CrowdConfig {
        max_characters: 64,
        max_objects: 4,
        ..CrowdConfig::default()
    };
    let mut crowd = Crowd::new(config).unwrap();
    let mut scenario = Scenario::plaza(40, 0.25, 3);
    scenario.populate(&mut crowd).unwrap();
    let object = crowd
        .add_object(&ObjectDesc {
            position: Vec3::new(1.0, 0.0, 2.0),
            heading: 0.0,
            look_at_height: 1.5,
            impact: 2.0,
        })
        .unwrap();
    let mut time = 0.0;
    let mut step = |crowd: &mut Crowd, scenario: &mut Scenario| {
        scenario.advance(1.0 / 30.0);
        time += 1.0 / 30.0;
        scenario.push(crowd, time).unwrap();
        crowd.step(1.0 / 30.0).unwrap();
    };
    /// Every reader's result from the state, the slow way.
    fn computed(crowd: &Crowd) -> (Vec<GazeInfo>, Vec<glam::Quat>) {
        let gaze = (0..crowd.character_count())
            .map(|position| crowd.gaze_of(crowd.dense_index(position)))
            .collect();
        let mut joints = vec![glam::Quat::NAN; 16 * crowd.character_count()];
        let mut written = 0;
        for position in 0..crowd.character_count() {
            let character = crowd.dense_index(position);
            written += crowd.write_joints(character, false, &mut joints[written..]);
        }
        joints.truncate(written);
        (gaze, joints)
    }
    /// What the readers return.
    fn read(crowd: &Crowd) -> (Vec<GazeInfo>, Vec<glam::Quat>) {
        let count = crowd.character_count();
        let gaze = (0..count).map(|position| crowd.gaze_at(position)).collect();
        let mut joints = vec![glam::Quat::NAN; crowd.joint_total(0, count).unwrap()];
        crowd.read_joints(0, count, false, &mut joints).unwrap();
        (gaze, joints)
    }
    type Change = Box<dyn Fn(&mut Crowd)>;
    let changes: Vec<(&str, Change)> = vec![
        (
            "push_frame",
            Box::new(|crowd: &mut Crowd| {
                let id = crowd.gaze_at(0).character;
                let update = crate::scene::EntityUpdate {
                    id,
                    position: Vec3::new(3.0, 0.0, -2.0),
                    heading: 1.0,
                    heading_from_motion: false,
                    velocity: None,
                    talking: false,
                };
                crowd.push_frame(crowd.time() + 0.01, &[update]).unwrap();
            }),
        ),
        (
            "set_gaze_target",
            Box::new(move |crowd: &mut Crowd| {
                let id = crowd.gaze_at(1).character;
                crowd
                    .set_gaze_target(id, ExplicitTarget::Entity(object), TargetPriority::Override)
                    .unwrap();
            }),
        ),
        (
            "remove_entity",
            Box::new(move |crowd: &mut Crowd| {
                crowd.remove_entity(object).unwrap();
            }),
        ),
        (
            "add_character",
            Box::new(|crowd: &mut Crowd| {
                crowd
                    .add_character(&CharacterDesc {
                        position: Vec3::new(0.5, 0.0, 0.5),
                        ..CharacterDesc::default()
                    })
                    .unwrap();
            }),
        ),
        // The one added above (the scenario keeps pushing its own).
        (
            "remove a character",
            Box::new(|crowd: &mut Crowd| {
                let id = crowd.gaze_at(crowd.character_count() - 1).character;
                crowd.remove_entity(id).unwrap();
            }),
        ),
        (
            "set_base_pose",
            Box::new(|crowd: &mut Crowd| {
                let id = crowd.gaze_at(3).character;
                let joints = crowd.chain(id).unwrap().joint_count();
                let pose = vec![glam::Quat::from_rotation_y(0.3); joints];
                crowd.set_base_pose(id, &pose).unwrap();
            }),
        ),
        (
            "set_viewer",
            Box::new(|crowd: &mut Crowd| {
                crowd.set_viewer(Vec3::new(0.0, 1.7, 4.0), 3.0).unwrap();
            }),
        ),
    ];
    /// True when the readers use what the last step published.
    fn published(crowd: &Crowd) -> bool {
        let outputs = crowd.published.outputs;
        outputs.gaze && outputs.joints && crowd.unchanged_since_step()
    }
    for _ in 0..20 {
        step(&mut crowd, &mut scenario);
    }
    // Nobody read: the steps published nothing.
    let outputs = crowd.published.outputs;
    assert!(!outputs.gaze && !outputs.joints);
    read(&crowd);
    for (name, change) in &changes {
        step(&mut crowd, &mut scenario);
        assert!(published(&crowd), "{name}: a step publishes what was read");
        assert_eq!(read(&crowd), computed(&crowd), "{name}: after a step");
        change(&mut crowd);
        assert!(!published(&crowd), "{name} leaves the published outputs");
        assert_eq!(read(&crowd), computed(&crowd), "{name}: after the change");
        step(&mut crowd, &mut scenario);
        assert_eq!(read(&crowd), computed(&crowd), "{name}: the step after");
    }
    // A ranged step publishes too.
    crowd.begin_step(1.0 / 30.0).unwrap();
    crowd.step_range(0, 5).unwrap();
    assert!(!published(&crowd));
    crowd.end_step().unwrap();
    assert!(published(&crowd));
    assert_eq!(read(&crowd), computed(&crowd), "after a ranged step");
}

#[test]
fn an_objects_look_at_height_can_change_and_a_characters_cannot() {
    let mut crowd = Crowd::new(CrowdConfig::default()).unwrap();
    let object = crowd
        .add_object(&crate::crowd::ObjectDesc {
            position: glam::Vec3::new(1.0, 0.0, 2.0),
            heading: 0.0,
            look_at_height: 1.0,
            impact: 1.0,
        })
        .unwrap();
    let character = crowd.add_character(&CharacterDesc::default()).unwrap();
    crowd.set_look_at_height(object, 2.5).unwrap();
    let index = crowd.scene().index_of(object).unwrap();
    assert_eq!(crowd.scene().look_at_point(index).y, 2.5);
    assert!(matches!(
        crowd.set_look_at_height(character, 1.0),
        Err(Error::InvalidArgument(_))
    ));
    assert!(matches!(
        crowd.set_look_at_height(object, f32::NAN),
        Err(Error::NonFinite(_))
    ));
    assert!(crowd.set_look_at_height(9999, 1.0).is_err());
    assert_eq!(crowd.scene().look_at_point(index).y, 2.5);
}
