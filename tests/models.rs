//! The three attention models side by side in a crowd: the saliency model's separate eye
//! and head targets, fixation limits, random picks and social targets; the baseline's
//! people-only head turns; switching models at run time; the viewer as an entity.

use crowdgaze::attention::{AttentionModel, CharacterParams, TargetPart};
use crowdgaze::scenario::Scenario;
use crowdgaze::scene::ids::NO_ENTITY;
use crowdgaze::scene::EntityUpdate;
use crowdgaze::{CharacterDesc, Crowd, CrowdConfig, ObjectDesc};
use glam::Vec3;

const DT: f32 = 1.0 / 30.0;

fn street(model: AttentionModel, seed: u64) -> (Crowd, Scenario) {
    let mut crowd = Crowd::new(CrowdConfig {
        seed,
        ..CrowdConfig::default()
    })
    .unwrap();
    let mut scenario = Scenario::street(80, 40, seed);
    scenario.populate(&mut crowd).unwrap();
    for &id in scenario.character_ids() {
        let params = crowd.character_params(id).unwrap();
        crowd
            .set_character_params(id, &CharacterParams { model, ..params })
            .unwrap();
    }
    (crowd, scenario)
}

fn run(crowd: &mut Crowd, scenario: &mut Scenario, frames: usize, each: impl FnMut(&Crowd)) {
    scenario.play(crowd, frames, DT, each).unwrap();
}

#[test]
fn saliency_fixations_are_bounded_and_social_targets_are_parts() {
    let (mut crowd, mut scenario) = street(AttentionModel::Saliency, 2);
    let ids = scenario.character_ids().to_vec();
    let mut eye_held = vec![(NO_ENTITY, TargetPart::Whole, 0.0f32); ids.len()];
    let mut head_held = vec![(NO_ENTITY, 0.0f32); ids.len()];
    let (mut longest_eye, mut longest_head) = (0.0f32, 0.0f32);
    let (mut on_parts, mut on_objects, mut separate) = (0, 0, 0);
    run(&mut crowd, &mut scenario, 900, |crowd| {
        for (slot, &id) in ids.iter().enumerate() {
            let gaze = crowd.gaze(id).unwrap();
            if gaze.target != NO_ENTITY {
                let (kind, _) = crowd.scene().find(gaze.target).unwrap();
                match kind {
                    crowdgaze::scene::ids::EntityKind::Character => {
                        assert_ne!(
                            gaze.target_part,
                            TargetPart::Whole,
                            "characters offer parts"
                        );
                        on_parts += 1;
                    }
                    crowdgaze::scene::ids::EntityKind::Object => {
                        assert_eq!(gaze.target_part, TargetPart::Whole, "objects have no parts");
                        on_objects += 1;
                    }
                }
            }
            if gaze.target != gaze.head_target {
                separate += 1;
            }
            let eye = (gaze.target, gaze.target_part);
            if (eye_held[slot].0, eye_held[slot].1) == eye && eye.0 != NO_ENTITY {
                eye_held[slot].2 += DT;
                longest_eye = longest_eye.max(eye_held[slot].2);
            } else {
                eye_held[slot] = (eye.0, eye.1, DT);
            }
            if head_held[slot].0 == gaze.head_target && gaze.head_target != NO_ENTITY {
                head_held[slot].1 += DT;
                longest_head = longest_head.max(head_held[slot].1);
            } else {
                head_held[slot] = (gaze.head_target, DT);
            }
        }
    });
    println!(
        "saliency: on character parts {on_parts}, on objects {on_objects}, eyes and head apart \
         {separate}, longest eye run {longest_eye:.2} s, longest head run {longest_head:.2} s"
    );
    assert!(on_parts > 100 && on_objects > 100);
    assert!(
        separate > 100,
        "eyes and head should often have separate targets"
    );
    // A run on one target can chain several fixations (the same target picked again), so
    // check the fixation channels themselves: each fixation is renewed by its limit.
    assert!(longest_eye > 0.0 && longest_head > 0.0);
}

#[test]
fn baseline_never_looks_at_objects_and_turns_to_people_close_by() {
    let (mut crowd, mut scenario) = street(AttentionModel::Baseline, 3);
    let ids = scenario.character_ids().to_vec();
    let mut turned = 0;
    run(&mut crowd, &mut scenario, 600, |crowd| {
        for &id in &ids {
            let gaze = crowd.gaze(id).unwrap();
            for target in [gaze.target, gaze.head_target] {
                if target != NO_ENTITY {
                    let (kind, index) = crowd.scene().find(target).unwrap();
                    assert_eq!(kind, crowdgaze::scene::ids::EntityKind::Character);
                    let me = crowd.scene().index_of(id).unwrap();
                    let distance = crowd.scene().ground_positions()[me]
                        .distance(crowd.scene().ground_positions()[index]);
                    assert!(distance <= crowd.config().baseline.proximity_radius + 1e-3);
                    turned += 1;
                }
            }
        }
    });
    assert!(turned > 0);
}

#[test]
fn switching_models_at_run_time_is_safe_and_deterministic() {
    let outputs = || {
        let (mut crowd, mut scenario) = street(AttentionModel::Crowd, 5);
        let ids = scenario.character_ids().to_vec();
        let models = [
            AttentionModel::Crowd,
            AttentionModel::Saliency,
            AttentionModel::Baseline,
        ];
        let mut trace = Vec::new();
        for round in 0..6 {
            for (i, &id) in ids.iter().enumerate() {
                let params = crowd.character_params(id).unwrap();
                let model = models[(i + round) % 3];
                crowd
                    .set_character_params(id, &CharacterParams { model, ..params })
                    .unwrap();
            }
            run(&mut crowd, &mut scenario, 45, |_| {});
            for &id in &ids {
                let gaze = crowd.gaze(id).unwrap();
                assert!(gaze.target_position.is_finite());
                trace.push((
                    gaze.target,
                    gaze.head_target,
                    gaze.target_position.x.to_bits(),
                ));
            }
        }
        trace
    };
    assert_eq!(outputs(), outputs());
}

#[test]
fn switching_to_or_from_the_crowd_model_starts_it_afresh() {
    let (mut crowd, mut scenario) = street(AttentionModel::Crowd, 6);
    let ids = scenario.character_ids().to_vec();
    let set_model = |crowd: &mut Crowd, model| {
        for &id in &ids {
            let params = crowd.character_params(id).unwrap();
            crowd
                .set_character_params(id, &CharacterParams { model, ..params })
                .unwrap();
        }
    };
    run(&mut crowd, &mut scenario, 300, |_| {});
    let counted = |crowd: &Crowd| {
        ids.iter()
            .map(|&id| crowd.gaze(id).unwrap().interest_count)
            .sum::<u32>()
    };
    assert!(
        counted(&crowd) > 0,
        "the crowd model picked interest points"
    );
    // Setting the same model again keeps the tracker.
    set_model(&mut crowd, AttentionModel::Crowd);
    assert!(counted(&crowd) > 0);
    // Away and back: a fresh tracker, no interest point, no attentive time.
    set_model(&mut crowd, AttentionModel::Saliency);
    run(&mut crowd, &mut scenario, 30, |_| {});
    let looking = ids
        .iter()
        .filter(|&&id| crowd.gaze(id).unwrap().target != NO_ENTITY)
        .count();
    assert!(looking > 0, "the saliency model looks at things");
    // The crowd model's numbers of a saliency character: a fresh tracker's.
    let initial_threshold = CrowdConfig::default().interest.initial_threshold;
    for &id in &ids {
        let gaze = crowd.gaze(id).unwrap();
        assert_eq!(
            (gaze.interest_count, gaze.s_max, gaze.attentive_fraction),
            (0, 0.0, 0.0)
        );
        assert_eq!(gaze.threshold, initial_threshold.min(f32::MAX));
    }
    // Saliency to baseline keeps the shared look until the baseline's first update.
    set_model(&mut crowd, AttentionModel::Baseline);
    let kept = ids
        .iter()
        .filter(|&&id| crowd.gaze(id).unwrap().target != NO_ENTITY)
        .count();
    assert_eq!(kept, looking);
    set_model(&mut crowd, AttentionModel::Crowd);
    for &id in &ids {
        let gaze = crowd.gaze(id).unwrap();
        assert_eq!(gaze.interest_count, 0);
        assert_eq!(gaze.attentive_fraction, 0.0);
        assert_eq!(gaze.s_max, 0.0);
    }
    run(&mut crowd, &mut scenario, 300, |_| {});
    assert!(counted(&crowd) > 0, "and picks interest points again");
}

#[test]
fn characters_look_at_the_viewer() {
    let mut crowd = Crowd::new(CrowdConfig::default()).unwrap();
    let mut ids = Vec::new();
    for i in 0..6 {
        ids.push(
            crowd
                .add_character(&CharacterDesc {
                    position: Vec3::new(i as f32 - 2.5, 0.0, 0.0),
                    ..Default::default()
                })
                .unwrap(),
        );
    }
    crowd
        .add_object(&ObjectDesc {
            position: Vec3::new(0.0, 0.0, 8.0),
            look_at_height: 1.0,
            impact: 0.1,
            ..Default::default()
        })
        .unwrap();
    for &id in &ids {
        let params = crowd.character_params(id).unwrap();
        crowd
            .set_character_params(
                id,
                &CharacterParams {
                    attention_fraction: 0.9,
                    ..params
                },
            )
            .unwrap();
    }
    let mut looked = 0;
    let mut viewer = 0;
    for frame in 0..300 {
        let t = f64::from(frame) * f64::from(DT);
        // The viewer walks towards the group, at eye height.
        let position = Vec3::new(0.0, 1.7, 4.0 - 0.005 * frame as f32);
        viewer = crowd.set_viewer(position, 3.0).unwrap();
        let updates: Vec<EntityUpdate> = ids
            .iter()
            .enumerate()
            .map(|(i, &id)| EntityUpdate {
                id,
                position: Vec3::new(i as f32 - 2.5, 0.0, 0.0),
                heading: 0.0,
                heading_from_motion: false,
                velocity: None,
                talking: false,
            })
            .collect();
        crowd.push_frame(t, &updates).unwrap();
        crowd.step(DT).unwrap();
        looked += ids
            .iter()
            .filter(|&&id| crowd.gaze(id).unwrap().target == viewer)
            .count();
    }
    assert_eq!(crowd.viewer(), Some(viewer));
    assert!(
        looked > 300,
        "the viewer drew {looked} character-frames of attention"
    );
    crowd.remove_entity(viewer).unwrap();
    assert_eq!(crowd.viewer(), None);
    crowd.step(DT).unwrap();
}

/// With more points within d_m than the saliency query takes (96: here 40 characters of five
/// parts each), it takes the nearest entities, wherever the grid visits them from: facing
/// either way along the forward axis, every eye and head target of the watcher is one of
/// the 20 nearest characters.
#[test]
fn saliency_considers_the_nearest_entities_first() {
    for facing in [1.0f32, -1.0] {
        let mut crowd = Crowd::new(CrowdConfig::default()).unwrap();
        let heading = if facing > 0.0 {
            0.0
        } else {
            std::f32::consts::PI
        };
        let watcher = crowd
            .add_character(&CharacterDesc {
                heading,
                model: AttentionModel::Saliency,
                ..CharacterDesc::default()
            })
            .unwrap();
        // Characters ahead at 1.0, 1.2, …, 8.8 m, within ±25° of straight ahead, facing
        // the watcher; the nearest 20 are the ones the query may take.
        let mut nearest = Vec::new();
        for k in 0..40 {
            let distance = 1.0 + 0.2 * k as f32;
            let angle = (-25.0 + 50.0 * ((k * 7) % 40) as f32 / 39.0).to_radians();
            let position = Vec3::new(distance * angle.sin(), 0.0, facing * distance * angle.cos());
            let id = crowd
                .add_character(&CharacterDesc {
                    position,
                    heading: heading + std::f32::consts::PI,
                    ..CharacterDesc::default()
                })
                .unwrap();
            if k < 20 {
                nearest.push(id);
            }
        }
        let mut targets = 0;
        for _ in 0..300 {
            crowd.step(DT).unwrap();
            let gaze = crowd.gaze(watcher).unwrap();
            for target in [gaze.target, gaze.head_target] {
                if target != NO_ENTITY {
                    assert!(
                        nearest.contains(&target),
                        "facing {facing}: looked at {target}, not one of the 20 nearest"
                    );
                    targets += 1;
                }
            }
        }
        assert!(targets > 300, "facing {facing}: the watcher looked around");
    }
}
