//! Crowd attention behaviour (Grillon & Thalmann 2009) through the Rust API: the grid
//! agrees with the all-pairs loop, characters attend about `a`% of the time, interest
//! points last between 1/3 s and `d_l`, seeds decide everything, and the real ETH
//! trajectories run through.

mod support;

use crowdgaze::attention::score::SubscoreWeights;
use crowdgaze::attention::CharacterParams;
use crowdgaze::scenario::Scenario;
use crowdgaze::scene::ids::NO_ENTITY;
use crowdgaze::scene::EntityUpdate;
use crowdgaze::{Crowd, CrowdConfig, Error};
use glam::Vec3;

const DT: f32 = 1.0 / 30.0;

fn street_crowd(seed: u64, config: CrowdConfig) -> (Crowd, Scenario) {
    let mut crowd = Crowd::new(CrowdConfig { seed, ..config }).unwrap();
    let mut scenario = Scenario::street(130, 60, seed);
    scenario.populate(&mut crowd).unwrap();
    (crowd, scenario)
}

fn run(crowd: &mut Crowd, scenario: &mut Scenario, frames: usize, each: impl FnMut(&Crowd)) {
    scenario.play(crowd, frames, DT, each).unwrap();
}

#[test]
fn grid_search_equals_all_pairs_on_random_scenes() {
    for seed in 0..6 {
        let mut crowd = Crowd::new(CrowdConfig {
            seed,
            max_characters: 400,
            ..CrowdConfig::default()
        })
        .unwrap();
        let density = [0.05, 0.25, 1.0][seed as usize % 3];
        let mut scenario = Scenario::plaza(300, density, seed);
        scenario.populate(&mut crowd).unwrap();
        run(&mut crowd, &mut scenario, 3, |_| {});
        crowd.rebuild_grid();
        let mut compared = 0;
        for &id in scenario.character_ids() {
            let grid = crowd.best_nearby_by_id(id).unwrap();
            let oracle = crowd.best_all_pairs(id).unwrap();
            assert_eq!(grid, oracle, "seed {seed}, character {id}");
            compared += usize::from(oracle.0.id != NO_ENTITY);
        }
        assert!(
            compared > 50,
            "seed {seed}: only {compared} characters saw anyone"
        );
    }
}

#[test]
fn attentive_fraction_follows_the_attention_percentage() {
    for fraction in [0.2f32, 0.4, 0.6] {
        let (mut crowd, mut scenario) = street_crowd(3, CrowdConfig::default());
        for &id in scenario.character_ids() {
            let params = crowd.character_params(id).unwrap();
            let params = CharacterParams {
                attention_fraction: fraction,
                ..params
            };
            crowd.set_character_params(id, &params).unwrap();
        }
        // Warm up 10 s, then measure 120 s.
        run(&mut crowd, &mut scenario, 300, |_| {});
        let ids = scenario.character_ids().to_vec();
        let mut attending = 0usize;
        let mut samples = 0usize;
        run(&mut crowd, &mut scenario, 3600, |crowd| {
            for &id in &ids {
                attending += usize::from(crowd.gaze(id).unwrap().attending);
                samples += 1;
            }
        });
        let measured = attending as f32 / samples as f32;
        println!("a = {fraction}: attentive {measured:.3}");
        assert!(
            (measured - fraction).abs() <= 0.05,
            "a = {fraction}: attentive {measured}"
        );
    }
}

#[test]
fn interest_points_last_between_a_third_of_a_second_and_d_l() {
    let config = CrowdConfig::default();
    let (mut crowd, mut scenario) = street_crowd(5, config.clone());
    let ids = scenario.character_ids().to_vec();
    let mut current = vec![(NO_ENTITY, 0.0f32); ids.len()];
    let mut intervals = Vec::new();
    run(&mut crowd, &mut scenario, 1800, |crowd| {
        for (slot, &id) in ids.iter().enumerate() {
            let gaze = crowd.gaze(id).unwrap();
            let (target, held) = current[slot];
            if gaze.target == target && target != NO_ENTITY {
                current[slot].1 = held + DT;
            } else {
                if target != NO_ENTITY {
                    intervals.push(held);
                }
                current[slot] = (gaze.target, DT);
            }
        }
    });
    assert!(
        intervals.len() > 100,
        "only {} interest points",
        intervals.len()
    );
    let longest = intervals.iter().copied().fold(0.0, f32::max);
    assert!(
        longest <= config.interest.max_hold + 1.5 * DT,
        "longest {longest}"
    );
    // Online, an IP is confirmed after 1/3 s of holding S_max; it then lasts at least a
    // frame. The planned (offline) intervals carry the 1/3 s minimum themselves.
    assert!(intervals.iter().all(|&d| d >= DT * 0.5));
}

#[test]
fn planned_constraints_respect_min_hold_and_d_l_and_the_exact_percentile() {
    let config = CrowdConfig {
        max_recorded_states: 130 * 900,
        ..CrowdConfig::default()
    };
    let (mut crowd, mut scenario) = street_crowd(8, config.clone());
    for frame in 0..900 {
        scenario.advance(DT);
        scenario
            .push(&mut crowd, f64::from(frame as f32 * DT))
            .unwrap();
    }
    crowd.plan().unwrap();
    let mut total = 0;
    let mut attentive = 0.0;
    for &id in scenario.character_ids() {
        let constraints = crowd.constraints(id).unwrap();
        total += constraints.len();
        let mut previous_end = f64::NEG_INFINITY;
        for k in constraints {
            let length = k.end - k.begin;
            assert!(
                length >= f64::from(config.interest.min_hold) - 1e-6,
                "{k:?}"
            );
            assert!(
                length <= f64::from(config.interest.max_hold) + 1e-6,
                "{k:?}"
            );
            assert!(k.begin >= previous_end - 1e-9, "overlap {k:?}");
            assert!(k.s_max >= crowd.planned_threshold(id).unwrap());
            previous_end = k.end;
        }
        let gaze = crowd.gaze(id).unwrap();
        let a = crowd.character_params(id).unwrap().attention_fraction;
        attentive += gaze.attentive_fraction - a;
    }
    assert!(total > 100, "{total} constraints");
    let mean_gap = attentive / scenario.character_ids().len() as f32;
    assert!(
        mean_gap.abs() < 0.08,
        "planned attentive fraction is off by {mean_gap}"
    );
    // Stepping follows the plan: the gaze target is the constraint covering the clock.
    assert!(matches!(
        scenario.push(&mut crowd, 100.0),
        Err(Error::WrongState(_))
    ));
    let first = scenario.character_ids()[0];
    let constraints: Vec<_> = crowd.constraints(first).unwrap().to_vec();
    let mut clock = 0.0f64;
    crowd.step(DT).unwrap();
    for _ in 0..900 {
        let gaze = crowd.gaze(first).unwrap();
        let expected = constraints
            .iter()
            .find(|k| k.begin <= clock && clock < k.end)
            .map_or(NO_ENTITY, |k| k.entity);
        assert_eq!(gaze.target, expected, "at {clock}");
        crowd.step(DT).unwrap();
        clock += f64::from(DT);
    }
    crowd.clear_plan();
    assert!(scenario.push(&mut crowd, 100.0).is_ok());
}

fn outputs(seed: u64) -> Vec<(u32, u32, f32, f32)> {
    let (mut crowd, mut scenario) = street_crowd(seed, CrowdConfig::default());
    run(&mut crowd, &mut scenario, 300, |_| {});
    scenario
        .character_ids()
        .iter()
        .map(|&id| {
            let g = crowd.gaze(id).unwrap();
            (g.character, g.target, g.s_max, g.threshold)
        })
        .collect()
}

#[test]
fn same_seed_same_outputs_different_seed_different_weights() {
    let a = outputs(21);
    let b = outputs(21);
    assert_eq!(
        a.iter()
            .map(|o| (o.0, o.1, o.2.to_bits(), o.3.to_bits()))
            .collect::<Vec<_>>(),
        b.iter()
            .map(|o| (o.0, o.1, o.2.to_bits(), o.3.to_bits()))
            .collect::<Vec<_>>()
    );
    let weights = |seed| {
        let mut crowd = Crowd::new(CrowdConfig {
            seed,
            ..CrowdConfig::default()
        })
        .unwrap();
        let id = crowd.add_character(&Default::default()).unwrap();
        crowd.character_params(id).unwrap()
    };
    assert_eq!(weights(1), weights(1));
    assert_ne!(weights(1), weights(2));
}

#[test]
fn bad_input_changes_nothing() {
    let mut crowd = Crowd::new(CrowdConfig::default()).unwrap();
    let a = crowd.add_character(&Default::default()).unwrap();
    let good = EntityUpdate {
        id: a,
        position: Vec3::new(1.0, 0.0, 2.0),
        heading: 0.5,
        heading_from_motion: false,
        velocity: None,
        talking: false,
    };
    crowd.push_frame(1.0, &[good]).unwrap();
    let before = crowd.scene().positions().to_vec();
    let bad = [
        EntityUpdate {
            position: Vec3::new(5.0, 0.0, 5.0),
            ..good
        },
        EntityUpdate {
            position: Vec3::new(f32::NAN, 0.0, 0.0),
            ..good
        },
    ];
    assert!(matches!(
        crowd.push_frame(2.0, &bad),
        Err(Error::NonFinite(_))
    ));
    assert!(matches!(
        crowd.push_frame(2.0, &[EntityUpdate { id: 999, ..good }]),
        Err(Error::NotFound(_))
    ));
    assert!(matches!(
        crowd.push_frame(0.5, &[good]),
        Err(Error::InvalidArgument(_))
    ));
    assert_eq!(crowd.scene().positions(), &before[..]);
    assert_eq!(crowd.time(), 1.0);
    let weights = SubscoreWeights::normalised([1.0, 0.0, 0.0, 0.0]).unwrap();
    let params = CharacterParams {
        weights,
        attention_fraction: 1.5,
        model: Default::default(),
    };
    assert!(crowd.set_character_params(a, &params).is_err());
    crowd.remove_entity(a).unwrap();
    assert!(matches!(crowd.gaze(a), Err(Error::NotFound(_))));
    assert!(matches!(crowd.remove_entity(a), Err(Error::NotFound(_))));
}

#[test]
fn real_eth_trajectories_run_through() {
    let path = support::ETH_SEQ_ETH;
    let rows = support::read_trajectories(path);
    // ETH seq_eth: 2.5 Hz samples, one frame number is 1/15 s; the ground plane is (x, y).
    let world =
        crowdgaze::World::new(crowdgaze::Axis::PositiveZ, crowdgaze::Axis::PositiveX, 1.0).unwrap();
    let mut crowd = Crowd::new(CrowdConfig {
        world,
        max_characters: 400,
        ..CrowdConfig::default()
    })
    .unwrap();
    let mut last_frame = std::collections::HashMap::new();
    for &(frame, person, _, _) in &rows {
        last_frame.insert(person, frame);
    }
    let mut ids = std::collections::HashMap::new();
    let mut updates = Vec::new();
    let mut attending = 0usize;
    let mut samples = 0usize;
    let mut s_max_sum = 0.0f64;
    let mut targets = std::collections::HashSet::new();
    let mut previous_time = None;
    let mut index = 0;
    while index < rows.len() {
        let frame = rows[index].0;
        updates.clear();
        while index < rows.len() && rows[index].0 == frame {
            let (_, person, x, y) = rows[index];
            let id = *ids.entry(person).or_insert_with(|| {
                crowd
                    .add_character(&crowdgaze::CharacterDesc {
                        position: Vec3::new(x, y, 0.0),
                        ..Default::default()
                    })
                    .unwrap()
            });
            updates.push(EntityUpdate {
                id,
                position: Vec3::new(x, y, 0.0),
                heading: 0.0,
                heading_from_motion: true,
                velocity: None,
                talking: false,
            });
            index += 1;
        }
        let time = f64::from(frame) / 15.0;
        crowd.push_frame(time, &updates).unwrap();
        let dt = previous_time.map_or(0.4, |p| (time - p) as f32);
        previous_time = Some(time);
        crowd.step(dt).unwrap();
        for update in &updates {
            let gaze = crowd.gaze(update.id).unwrap();
            assert!(gaze.s_max.is_finite() && gaze.threshold.is_finite());
            assert!(gaze.target_position.is_finite());
            attending += usize::from(gaze.attending);
            s_max_sum += f64::from(gaze.s_max);
            samples += 1;
            if gaze.attending {
                targets.insert((update.id, gaze.target));
            }
        }
        // People whose track ended leave the scene.
        for (&person, &last) in &last_frame {
            if last == frame {
                crowd.remove_entity(ids[&person]).unwrap();
            }
        }
    }
    let fraction = attending as f64 / samples as f64;
    let mean_s_max = s_max_sum / samples as f64;
    println!(
        "ETH seq_eth: {} people, {samples} person-frames, attentive {fraction:.3}, mean S_max \
         {mean_s_max:.3}, {} distinct (character, target) pairs",
        ids.len(),
        targets.len()
    );
    assert_eq!(ids.len(), 360);
    assert_eq!(samples, rows.len());
    assert!(
        (0.05..0.6).contains(&fraction),
        "attentive fraction {fraction}"
    );
    assert!(
        mean_s_max > 0.05 && mean_s_max < 1.0,
        "mean S_max {mean_s_max}"
    );
    assert!(targets.len() > 50);
}

#[test]
fn level_of_detail_spreads_attention_updates_and_keeps_the_attention_percentage() {
    let config = CrowdConfig {
        attention_period: 4,
        ..CrowdConfig::default()
    };
    let (mut crowd, mut scenario) = street_crowd(11, config);
    let ids = scenario.character_ids().to_vec();
    for &id in &ids {
        let params = crowd.character_params(id).unwrap();
        let params = CharacterParams {
            attention_fraction: 0.4,
            ..params
        };
        crowd.set_character_params(id, &params).unwrap();
    }
    run(&mut crowd, &mut scenario, 300, |_| {});
    let mut previous: Vec<f32> = ids
        .iter()
        .map(|&id| crowd.gaze(id).unwrap().s_max)
        .collect();
    let mut changes_per_character = vec![0usize; ids.len()];
    let mut most_per_step = 0;
    let (mut attending, mut samples) = (0usize, 0usize);
    run(&mut crowd, &mut scenario, 1800, |crowd| {
        let mut changed = 0;
        for (slot, &id) in ids.iter().enumerate() {
            let gaze = crowd.gaze(id).unwrap();
            if gaze.s_max != previous[slot] {
                changes_per_character[slot] += 1;
                changed += 1;
            }
            previous[slot] = gaze.s_max;
            attending += usize::from(gaze.attending);
            samples += 1;
        }
        most_per_step = most_per_step.max(changed);
    });
    // Each character is re-scored once every 4 steps, a quarter of the crowd at a time.
    assert!(changes_per_character.iter().all(|&c| c <= 1800 / 4 + 1));
    assert!(
        most_per_step <= ids.len() / 4 + 2,
        "{most_per_step} updated in one step"
    );
    let fraction = attending as f32 / samples as f32;
    println!("attention every 4th step: attentive {fraction:.3} for a = 0.4");
    assert!((fraction - 0.4).abs() <= 0.05, "attentive {fraction}");
    // A character's own period overrides the crowd's.
    crowd.set_attention_period(ids[0], 1).unwrap();
    assert!(crowd.set_attention_period(ids[0], 65).is_err());
}
