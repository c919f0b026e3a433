//! The crowd's storage order — entities and characters stored again in the spatial grid's
//! order every `reorder_period` steps — never shows: identical outputs, in the same reading
//! order, for every period, through removals, additions and ranged steps; and it does make
//! storage spatial.

mod support;

use crowdgaze::crowd::CharacterDesc;
use crowdgaze::scenario::Scenario;
use crowdgaze::{Crowd, CrowdConfig};
use glam::{Quat, Vec3};

const PEOPLE: usize = 160;
const FRAMES: usize = 80;
const DT: f32 = 1.0 / 30.0;

/// The mixed street of the support module, reordered every `reorder_period` steps.
fn street(reorder_period: u32) -> (Crowd, Scenario) {
    let config = CrowdConfig {
        reorder_period,
        ..support::mixed_street_config()
    };
    support::mixed_street(config, PEOPLE, 30, 5)
}

/// The outputs of [`support::output_bits`], after checking that the readers by id agree
/// with those by position: each character's joints, eyes and all-pairs search.
fn outputs(crowd: &Crowd) -> Vec<u32> {
    let count = crowd.character_count();
    let mut joints = vec![Quat::IDENTITY; crowd.joint_total(0, count).unwrap()];
    crowd.read_joints(0, count, false, &mut joints).unwrap();
    let mut offset = 0;
    let mut own = [Quat::IDENTITY; 16];
    for position in 0..count {
        let id = crowd.gaze_at(position).character;
        assert_eq!(crowd.eyes_at(position).character, id);
        let written = crowd.read_joints_of(id, false, &mut own).unwrap();
        assert_eq!(own[..written], joints[offset..offset + written]);
        assert_eq!(
            crowd.best_all_pairs_at(position),
            crowd.best_all_pairs(id).unwrap()
        );
        offset += written;
    }
    assert_eq!(offset, joints.len());
    support::output_bits(crowd)
}

/// Runs the street for `FRAMES` frames, stepping each with `step`; a sixth of the people
/// leave at frame 25 and four newcomers arrive at frame 45 (between steps, the way engines
/// do it). Returns the outputs of every frame.
fn run(reorder_period: u32, mut step: impl FnMut(&mut Crowd, usize)) -> Vec<Vec<u32>> {
    let (mut crowd, mut scenario) = street(reorder_period);
    let ids = scenario.character_ids().to_vec();
    let world = *crowd.scene().world();
    let mut present = [true; PEOPLE];
    (0..FRAMES)
        .map(|frame| {
            if frame == 25 {
                for person in (0..PEOPLE).step_by(6) {
                    crowd.remove_entity(ids[person]).unwrap();
                    present[person] = false;
                }
            }
            if frame == 45 {
                for k in 0..4 {
                    let desc = CharacterDesc {
                        position: Vec3::new(4.0 + 3.0 * k as f32, 0.0, 6.0),
                        heading: 0.5 * k as f32,
                        ..CharacterDesc::default()
                    };
                    crowd.add_character(&desc).unwrap();
                }
            }
            scenario.advance(DT);
            let updates: Vec<_> = (0..PEOPLE)
                .filter(|&person| present[person])
                .map(|person| scenario.update(&world, person))
                .collect();
            crowd
                .push_frame((frame + 1) as f64 * f64::from(DT), &updates)
                .unwrap();
            let viewer = Vec3::new(2.0 + frame as f32 * 0.05, 1.7, 1.0);
            crowd.set_viewer(viewer, 2.0).unwrap();
            step(&mut crowd, frame);
            outputs(&crowd)
        })
        .collect()
}

#[test]
fn every_reorder_period_gives_identical_outputs_in_the_same_order() {
    let never = run(0, |crowd, _| crowd.step(DT).unwrap());
    // The crowd did something, and the removals and additions took effect.
    assert!(never.first().unwrap() != never.last().unwrap());
    for period in [1, 3, 32] {
        let reordered = run(period, |crowd, _| crowd.step(DT).unwrap());
        support::assert_same(&never, &reordered, &format!("reorder period {period}"));
    }
    // Ranged steps index the storage order: any split still steps everyone once.
    let ranged = run(1, |crowd, frame| {
        crowd.begin_step(DT).unwrap();
        let count = crowd.character_count();
        let size = 1 + (frame * 5) % 17;
        for first in (0..count).step_by(size).rev() {
            crowd.step_range(first, size.min(count - first)).unwrap();
        }
        crowd.end_step().unwrap();
    });
    support::assert_same(&never, &ranged, "ranged steps, reordered every step");
}

/// Mean distance between entities stored one after the other.
fn mean_gap(crowd: &Crowd) -> f32 {
    let points = crowd.scene().ground_positions();
    let total: f32 = points
        .windows(2)
        .map(|pair| pair[0].distance(pair[1]))
        .sum();
    total / (points.len() - 1) as f32
}

#[test]
fn reordering_stores_neighbours_together() {
    let plaza = |reorder_period| {
        let config = CrowdConfig {
            reorder_period,
            max_characters: 3000,
            ..CrowdConfig::default()
        };
        let mut crowd = Crowd::new(config).unwrap();
        Scenario::plaza(3000, 0.25, 9).populate(&mut crowd).unwrap();
        crowd.step(DT).unwrap();
        crowd
    };
    let (created, reordered) = (plaza(0), plaza(1));
    let (created_gap, reordered_gap) = (mean_gap(&created), mean_gap(&reordered));
    // The plaza is about 110 m across: people created at random places are tens of metres
    // apart; in grid order, neighbours share a cell 1.25 m wide, 5 m tall.
    assert!(created_gap > 30.0, "creation order: {created_gap} m");
    assert!(reordered_gap < 3.0, "grid order: {reordered_gap} m");
    // Ids and the reading order are unchanged.
    for position in 0..3000 {
        assert_eq!(
            created.gaze_at(position).character,
            reordered.gaze_at(position).character
        );
    }
}
