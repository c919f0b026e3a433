//! Conversations through the crowd (issue #25): over 10 simulated minutes of seeded
//! turn-taking, groups of two and three look at each other with Argyle's shares and glance
//! lengths; a talking passer-by draws more glances than a silent one (crowd model) and the
//! baseline's head turns; membership survives removals and storage reorders; outputs are
//! the same at every thread count; bad groups are refused and change nothing.

mod support;

use crowdgaze::attention::{AttentionModel, CharacterParams};
use crowdgaze::scenario::TurnTaking;
use crowdgaze::scene::EntityUpdate;
use crowdgaze::{CharacterDesc, Crowd, CrowdConfig, Error};
use glam::Vec3;

const DT: f32 = 1.0 / 30.0;

/// Who talks each frame in a group of `members` ([`TurnTaking`], seeded).
fn turns(members: usize, frames: usize, seed: u64) -> Vec<Option<usize>> {
    let mut random = crowdgaze::math::random::Random::new(seed);
    let mut turns = TurnTaking::new(members, 0.0);
    (0..frames)
        .map(|_| turns.advance(DT, &mut random))
        .collect()
}

/// A group standing in a circle of radius `radius` around `centre`, each facing the centre.
fn circle(centre: Vec3, members: usize, radius: f32) -> Vec<(Vec3, f32)> {
    (0..members)
        .map(|i| {
            let angle = std::f32::consts::TAU * i as f32 / members as f32;
            let position = centre + radius * Vec3::new(angle.sin(), 0.0, angle.cos());
            let to_centre = centre - position;
            (position, to_centre.x.atan2(to_centre.z))
        })
        .collect()
}

/// A crowd of standing groups (one per entry of `groups`, its members on the models given)
/// and a few walkers passing by.
struct Scene {
    crowd: Crowd,
    /// Each group's members' ids and places.
    groups: Vec<Vec<(u32, Vec3, f32)>>,
    /// Walkers: id, start, velocity.
    walkers: Vec<(u32, Vec3, Vec3)>,
    time: f64,
}

impl Scene {
    fn new(config: CrowdConfig, groups: &[&[AttentionModel]]) -> Scene {
        let mut crowd = Crowd::new(config).unwrap();
        let mut placed = Vec::new();
        for (g, models) in groups.iter().enumerate() {
            let centre = Vec3::new(6.0 * g as f32, 0.0, 0.0);
            let mut members = Vec::new();
            for ((position, heading), model) in
                circle(centre, models.len(), 0.7).into_iter().zip(*models)
            {
                let id = crowd
                    .add_character(&CharacterDesc {
                        position,
                        heading,
                        ..CharacterDesc::default()
                    })
                    .unwrap();
                let params = crowd.character_params(id).unwrap();
                crowd
                    .set_character_params(
                        id,
                        &CharacterParams {
                            model: *model,
                            ..params
                        },
                    )
                    .unwrap();
                members.push((id, position, heading));
            }
            let ids: Vec<u32> = members.iter().map(|m| m.0).collect();
            crowd.set_conversation(&ids).unwrap();
            placed.push(members);
        }
        let walkers = (0..4)
            .map(|i| {
                let start = Vec3::new(-8.0 + 3.0 * i as f32, 0.0, 4.0 + i as f32);
                let id = crowd
                    .add_character(&CharacterDesc {
                        position: start,
                        ..CharacterDesc::default()
                    })
                    .unwrap();
                (id, start, Vec3::new(1.2, 0.0, -0.1 * i as f32))
            })
            .collect();
        Scene {
            crowd,
            groups: placed,
            walkers,
            time: 0.0,
        }
    }

    /// Pushes one frame (`speakers[g]`: who talks in group `g`) and steps.
    fn frame(&mut self, speakers: &[Option<usize>]) {
        self.time += f64::from(DT);
        let mut updates = Vec::new();
        for (group, speaker) in self.groups.iter().zip(speakers) {
            for (member, &(id, position, heading)) in group.iter().enumerate() {
                updates.push(EntityUpdate {
                    id,
                    position,
                    heading,
                    heading_from_motion: false,
                    velocity: None,
                    talking: *speaker == Some(member),
                });
            }
        }
        for &(id, start, velocity) in &self.walkers {
            let position = start + velocity * (self.time as f32 % 16.0);
            updates.push(EntityUpdate {
                id,
                position,
                heading: 0.0,
                heading_from_motion: true,
                velocity: None,
                talking: false,
            });
        }
        self.crowd.push_frame(self.time, &updates).unwrap();
        self.crowd.step(DT).unwrap();
    }
}

/// What a group's gaze did over a run.
#[derive(Debug, Default)]
struct Shares {
    listening: usize,
    listener_at_speaker: usize,
    speaking: usize,
    speaker_at_listener: usize,
    mutual: usize,
    glances: Vec<usize>,
    mutual_glances: Vec<usize>,
}

impl Shares {
    fn mean(runs: &[usize]) -> f32 {
        runs.iter().sum::<usize>() as f32 / runs.len() as f32 * DT
    }

    fn check(&self, what: &str) {
        let listener = self.listener_at_speaker as f32 / self.listening as f32;
        let speaker = self.speaker_at_listener as f32 / self.speaking as f32;
        let mutual = self.mutual as f32 / self.speaking as f32;
        let (glance, mutual_glance) = (Self::mean(&self.glances), Self::mean(&self.mutual_glances));
        println!(
            "{what}: listener → speaker {listener:.3}, speaker → listener {speaker:.3}, mutual \
             {mutual:.3}; mean glance {glance:.2} s ({} glances), mean mutual glance \
             {mutual_glance:.2} s ({})",
            self.glances.len(),
            self.mutual_glances.len()
        );
        for (value, target, name) in [
            (listener, 0.75, "listener → speaker"),
            (speaker, 0.41, "speaker → listener"),
            (mutual, 0.31, "mutual"),
        ] {
            assert!(
                (value - target).abs() <= 0.10,
                "{what}: {name} {value}, target {target}"
            );
        }
        for (value, target, name) in [
            (glance, 3.0, "glance"),
            (mutual_glance, 1.2, "mutual glance"),
        ] {
            assert!(
                (value - target).abs() <= 0.3 * target,
                "{what}: mean {name} {value} s, target {target} s"
            );
        }
    }
}

#[test]
fn groups_of_two_and_three_look_at_each_other_as_argyle_measured() {
    use AttentionModel::{Baseline, Crowd as CrowdModel, Saliency};
    let frames = 10 * 60 * 30;
    let mut scene = Scene::new(
        CrowdConfig::default(),
        &[&[CrowdModel, CrowdModel], &[CrowdModel, Saliency, Baseline]],
    );
    let scripts = [turns(2, frames, 11), turns(3, frames, 12)];
    let mut shares = [Shares::default(), Shares::default()];
    // Per group, per member: the member looked at and for how many frames; per pair, the
    // frames of mutual gaze so far.
    let mut runs: Vec<Vec<(u32, usize)>> = scene
        .groups
        .iter()
        .map(|g| vec![(u32::MAX, 0); g.len()])
        .collect();
    let mut mutual_runs: Vec<Vec<usize>> = scene
        .groups
        .iter()
        .map(|g| vec![0; g.len() * g.len()])
        .collect();
    for frame in 0..frames {
        let speakers: Vec<Option<usize>> = scripts.iter().map(|s| s[frame]).collect();
        scene.frame(&speakers);
        for (g, group) in scene.groups.iter().enumerate() {
            let ids: Vec<u32> = group.iter().map(|m| m.0).collect();
            let targets: Vec<u32> = ids
                .iter()
                .map(|&id| scene.crowd.gaze(id).unwrap().target)
                .collect();
            let share = &mut shares[g];
            if let Some(speaker) = speakers[g] {
                for (member, &target) in targets.iter().enumerate() {
                    if member == speaker {
                        share.speaking += 1;
                        if let Some(listener) = ids.iter().position(|&id| id == target) {
                            share.speaker_at_listener += 1;
                            share.mutual += usize::from(targets[listener] == ids[speaker]);
                        }
                    } else {
                        share.listening += 1;
                        share.listener_at_speaker += usize::from(target == ids[speaker]);
                    }
                }
            }
            for (member, &target) in targets.iter().enumerate() {
                let at_member = ids.contains(&target);
                let run = &mut runs[g][member];
                if at_member && run.0 == target {
                    run.1 += 1;
                } else {
                    if ids.contains(&run.0) && run.1 > 0 {
                        share.glances.push(run.1);
                    }
                    *run = (target, usize::from(at_member));
                }
                for other in member + 1..ids.len() {
                    let both = target == ids[other] && targets[other] == ids[member];
                    let run = &mut mutual_runs[g][member * ids.len() + other];
                    if both {
                        *run += 1;
                    } else if *run > 0 {
                        share.mutual_glances.push(*run);
                        *run = 0;
                    }
                }
            }
        }
    }
    shares[0].check("two members (crowd model)");
    shares[1].check("three members (crowd, saliency, baseline)");
}

/// Frames in which an observer standing at the origin facing +z, on `model`, looks at each
/// of two walkers crossing in front of it side by side, the first talking.
fn glances_at_talker_and_silent(model: AttentionModel, seed: u64) -> (usize, usize) {
    let mut crowd = Crowd::new(CrowdConfig {
        seed,
        ..CrowdConfig::default()
    })
    .unwrap();
    let observer = crowd.add_character(&CharacterDesc::default()).unwrap();
    let params = crowd.character_params(observer).unwrap();
    crowd
        .set_character_params(observer, &CharacterParams { model, ..params })
        .unwrap();
    // Two walkers, mirror images about the observer's forward axis, one talking.
    let start = [Vec3::new(-1.0, 0.0, 1.5), Vec3::new(1.0, 0.0, 1.5)];
    let walkers: Vec<u32> = start
        .iter()
        .map(|&position| {
            crowd
                .add_character(&CharacterDesc {
                    position,
                    ..CharacterDesc::default()
                })
                .unwrap()
        })
        .collect();
    let (mut at_talker, mut at_silent) = (0, 0);
    let mut time = 0.0;
    for frame in 0..3000 {
        time += f64::from(DT);
        // Back and forth along z, 1.5 to 4.5 m ahead, mirrored.
        let phase = (frame % 200) as f32 / 200.0;
        let z = 1.5 + 3.0 * (1.0 - (2.0 * phase - 1.0).abs());
        let updates: Vec<EntityUpdate> = walkers
            .iter()
            .zip(&start)
            .enumerate()
            .map(|(i, (&id, &position))| EntityUpdate {
                id,
                position: Vec3::new(position.x, 0.0, z),
                heading: 0.0,
                heading_from_motion: true,
                velocity: None,
                talking: i == 0,
            })
            .collect();
        crowd.push_frame(time, &updates).unwrap();
        crowd.step(DT).unwrap();
        let gaze = crowd.gaze(observer).unwrap();
        let looked = if model == AttentionModel::Baseline {
            gaze.head_target
        } else {
            gaze.target
        };
        at_talker += usize::from(looked == walkers[0]);
        at_silent += usize::from(looked == walkers[1]);
    }
    (at_talker, at_silent)
}

#[test]
fn a_talking_passer_by_draws_more_glances_than_a_silent_one() {
    for model in [AttentionModel::Crowd, AttentionModel::Baseline] {
        let (mut talker, mut silent) = (0, 0);
        for seed in 1..=4 {
            let (t, s) = glances_at_talker_and_silent(model, seed);
            talker += t;
            silent += s;
        }
        println!("{model:?}: {talker} frames on the talker, {silent} on the silent one");
        assert!(
            talker > silent + silent / 4,
            "{model:?}: talker {talker}, silent {silent}"
        );
    }
}

#[test]
fn membership_survives_removals_and_storage_reorders() {
    let mut scene = Scene::new(
        CrowdConfig {
            reorder_period: 1,
            ..CrowdConfig::default()
        },
        &[&[AttentionModel::Crowd; 3], &[AttentionModel::Crowd; 2]],
    );
    let first: Vec<u32> = scene.groups[0].iter().map(|m| m.0).collect();
    let second: Vec<u32> = scene.groups[1].iter().map(|m| m.0).collect();
    let group = scene.crowd.conversation_of(first[0]).unwrap().unwrap();
    let other = scene.crowd.conversation_of(second[0]).unwrap().unwrap();
    for _ in 0..60 {
        scene.frame(&[Some(1), None]);
    }
    // Storage was reordered every step: every member still in its group.
    for &id in &first {
        assert_eq!(scene.crowd.conversation_of(id).unwrap(), Some(group));
    }
    // A walker leaves; then a member of the first group: the others stay together.
    let walker = scene.walkers.pop().unwrap().0;
    scene.crowd.remove_entity(walker).unwrap();
    scene.crowd.remove_entity(first[0]).unwrap();
    scene.groups[0].remove(0);
    let mut left: Vec<u32> = scene.crowd.conversation_members(group).unwrap().to_vec();
    left.sort_unstable();
    assert_eq!(left, vec![first[1], first[2]]);
    for _ in 0..60 {
        scene.frame(&[Some(0), None]);
    }
    assert_eq!(scene.crowd.conversation_of(first[2]).unwrap(), Some(group));
    // A member of the pair leaves: a group of one ends, its last member is free.
    scene.crowd.remove_entity(second[1]).unwrap();
    scene.groups[1].remove(1);
    assert_eq!(scene.crowd.conversation_of(second[0]).unwrap(), None);
    assert!(matches!(
        scene.crowd.conversation_members(other),
        Err(Error::NotFound(_))
    ));
    // Ending a group frees its members; its id is gone, and a new group takes the slot
    // under another id.
    scene.crowd.remove_conversation(group).unwrap();
    assert_eq!(scene.crowd.conversation_of(first[1]).unwrap(), None);
    assert!(matches!(
        scene.crowd.remove_conversation(group),
        Err(Error::NotFound(_))
    ));
    let again = scene
        .crowd
        .set_conversation(&[first[1], second[0]])
        .unwrap();
    assert_ne!(again, group);
    assert_ne!(again, other);
    for _ in 0..30 {
        scene.frame(&[Some(0), None]);
    }
}

#[test]
fn bad_groups_are_refused_and_change_nothing() {
    let mut scene = Scene::new(CrowdConfig::default(), &[&[AttentionModel::Crowd; 2]]);
    let members: Vec<u32> = scene.groups[0].iter().map(|m| m.0).collect();
    let walkers: Vec<u32> = scene.walkers.iter().map(|w| w.0).collect();
    let object = scene
        .crowd
        .add_object(&crowdgaze::ObjectDesc {
            position: Vec3::new(3.0, 1.0, 3.0),
            ..crowdgaze::ObjectDesc::default()
        })
        .unwrap();
    let cases: Vec<(Vec<u32>, &str)> = vec![
        (vec![walkers[0]], "a group of one"),
        (
            vec![walkers[0], members[0]],
            "a character already in a group",
        ),
        (vec![walkers[0], walkers[0]], "an id twice"),
        (vec![walkers[0], object], "an object"),
        (vec![walkers[0], 123_456], "an unknown id"),
        (
            walkers
                .iter()
                .chain(&walkers)
                .chain(&walkers)
                .copied()
                .collect(),
            "twelve members",
        ),
    ];
    for (ids, what) in cases {
        let error = scene.crowd.set_conversation(&ids).unwrap_err();
        match (what, &error) {
            ("an unknown id", Error::NotFound(_)) => {}
            (_, Error::InvalidArgument(_)) if what != "an unknown id" => {}
            _ => panic!("{what}: {error:?}"),
        }
        for &id in &walkers {
            assert_eq!(scene.crowd.conversation_of(id).unwrap(), None, "{what}");
        }
    }
    // Capacity: a crowd with room for one conversation.
    let mut small = Scene::new(
        CrowdConfig {
            max_conversations: 1,
            ..CrowdConfig::default()
        },
        &[&[AttentionModel::Crowd; 2]],
    );
    let walkers: Vec<u32> = small.walkers.iter().map(|w| w.0).collect();
    assert!(matches!(
        small.crowd.set_conversation(&walkers[..2]),
        Err(Error::Capacity(_))
    ));
    // NaN settings.
    let mut config = CrowdConfig::default();
    config.conversation.listener_share = f32::NAN;
    assert!(matches!(Crowd::new(config), Err(Error::NonFinite(_))));
    let mut config = CrowdConfig::default();
    config.scoring.talking_gain = f32::NAN;
    assert!(matches!(Crowd::new(config), Err(Error::NonFinite(_))));
}

#[test]
fn conversations_give_the_same_outputs_at_every_thread_count() {
    use AttentionModel::{Baseline, Crowd as CrowdModel, Saliency};
    let run = |threads: u32| -> Vec<Vec<u32>> {
        let mut scene = Scene::new(
            CrowdConfig {
                threads,
                ..CrowdConfig::default()
            },
            &[&[CrowdModel, Saliency], &[CrowdModel, Baseline, Saliency]],
        );
        let scripts = [turns(2, 300, 3), turns(3, 300, 4)];
        (0..300)
            .map(|frame| {
                scene.frame(&[scripts[0][frame], scripts[1][frame]]);
                support::output_bits(&scene.crowd)
            })
            .collect()
    };
    let one = run(1);
    support::assert_same(&one, &run(1), "a second run");
    support::assert_same(&one, &run(4), "4 threads");
}

/// Forms `formed` pairs' groups in a crowd of capacity `capacity`, ends those at
/// `released` (in that order: the table's next free slots), then forms and ends one more
/// pair's group `cycles` times. Every id given is new, never `CG_NO_TARGET` (u32::MAX)
/// nor a live group's; ending it leaves every other group alone; its stale id ends
/// nothing afterwards and its members are in no group.
fn reuse_group_ids(capacity: u32, formed: usize, released: std::ops::Range<usize>, cycles: usize) {
    let characters = 2 * (formed + 1);
    let mut crowd = Crowd::new(CrowdConfig {
        max_characters: characters as u32,
        max_conversations: capacity,
        ..CrowdConfig::default()
    })
    .unwrap();
    let ids: Vec<u32> = (0..characters)
        .map(|i| {
            let desc = CharacterDesc {
                position: Vec3::new(i as f32, 0.0, 0.0),
                ..Default::default()
            };
            crowd.add_character(&desc).unwrap()
        })
        .collect();
    let pairs: Vec<&[u32]> = ids.chunks(2).collect();
    let mut groups: Vec<Option<u32>> = pairs[..formed]
        .iter()
        .map(|pair| Some(crowd.set_conversation(pair).unwrap()))
        .collect();
    let mut given: std::collections::HashSet<u32> = groups.iter().flatten().copied().collect();
    for group in &mut groups[released] {
        crowd.remove_conversation(group.take().unwrap()).unwrap();
    }
    let held: Vec<(usize, u32)> = groups
        .iter()
        .enumerate()
        .filter_map(|(pair, group)| group.map(|group| (pair, group)))
        .collect();
    let cycling = pairs[formed];
    for cycle in 0..cycles {
        let group = crowd.set_conversation(cycling).unwrap();
        let what = format!("capacity {capacity}, cycle {cycle}: id {group}");
        assert_ne!(group, u32::MAX, "{what} is CG_NO_TARGET");
        assert!(given.insert(group), "{what} was given before");
        assert_eq!(
            crowd.conversation_of(cycling[0]).unwrap(),
            Some(group),
            "{what}"
        );
        crowd.remove_conversation(group).unwrap();
        assert!(
            matches!(crowd.remove_conversation(group), Err(Error::NotFound(_))),
            "{what}: a stale id ends nothing"
        );
        assert_eq!(crowd.conversation_of(cycling[1]).unwrap(), None, "{what}");
    }
    for &(pair, group) in &held {
        assert_eq!(crowd.conversation_members(group).unwrap(), pairs[pair]);
        for &member in pairs[pair] {
            assert_eq!(crowd.conversation_of(member).unwrap(), Some(group));
        }
    }
}

#[test]
fn a_removed_groups_id_never_names_a_live_group() {
    // The default: every slot but one held, the last one reused.
    reuse_group_ids(64, 63, 0..0, 3000);
    // 2²⁰ − 1: a slot reused 4 096 times gave u32::MAX (CG_NO_TARGET) with ids
    // slot + capacity × generation.
    reuse_group_ids(1_048_575, 4097, 0..4096, 4200);
    // 8 372 256 · 513 = 2³² + 32: slot 0 reused 513 times gave the id of the live group in
    // slot 32, and ending it ended that group.
    reuse_group_ids(8_372_256, 33, 0..1, 600);
    // The largest capacity, 2²³: slot 1 reused 512 times gave its first id again.
    reuse_group_ids(1 << 23, 1, 0..0, 600);
}
