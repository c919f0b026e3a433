//! Gaze following on real trajectories (ETH seq_eth): a group standing beside the walkway
//! stares up at a point, as in Milgram, Bickman & Berkowitz (1969) and Gallup et al.
//! (2012); the share of passers-by who look too, by the group's size, against the field
//! figures (docs/street.md), and no tipping point. Prints the curve:
//! `cargo test --release --test following -- --nocapture`.

mod support;

use std::collections::HashMap;

use crowdgaze::attention::following::FollowConfig;
use crowdgaze::attention::AttentionModel;
use crowdgaze::crowd::CrowdConfig;
use glam::{Vec2, Vec3};
use support::field::{in_view, replay, tracks, Frame, Starer, ETH};

/// `count` people standing in a tight group beside ETH's walkway (which runs along x at
/// y ≈ 4–6), facing away from it, staring at a point 8 m up on the facade behind them.
fn stimulus_group(count: usize) -> Vec<Starer> {
    (0..count)
        .map(|i| Starer {
            position: Vec2::new(6.0 + 0.6 * (i % 5) as f32, 8.5 + 0.6 * (i / 5) as f32),
            heading: std::f32::consts::FRAC_PI_2,
            point: Vec3::new(7.2, 14.0, 8.0),
        })
        .collect()
}

/// What each passer-by (track index) did: saw a starer while walking (within the follow
/// distance and view), when it first glanced at the gaze point, whether it saw a starer
/// before that.
#[derive(Debug, Default, Clone, Copy)]
struct Passer {
    saw_starer: bool,
    first_glance: Option<f64>,
    saw_starer_before_glance: bool,
}

fn passers(frames: &[Frame], starers: &[Starer], config: &FollowConfig) -> HashMap<usize, Passer> {
    let mut passers: HashMap<usize, Passer> = HashMap::new();
    for frame in frames {
        for person in &frame.people {
            let passer = passers.entry(person.track).or_default();
            let sees = starers.iter().any(|starer| {
                in_view(
                    person.position,
                    person.velocity,
                    starer.position,
                    config.distance,
                    config.view_half_angle,
                )
            });
            passer.saw_starer |= sees;
            if person.glances > 0 && passer.first_glance.is_none() {
                passer.first_glance = Some(frame.time);
                passer.saw_starer_before_glance = passer.saw_starer;
            }
        }
    }
    passers
}

/// The share of passers-by who saw the group and looked where it looks.
fn share_following(model: AttentionModel, config: CrowdConfig, lookers: usize) -> f64 {
    let starers = stimulus_group(lookers);
    let frames = replay(
        &tracks(ETH),
        config.clone(),
        model,
        &starers,
        0.0..f64::INFINITY,
        None,
    );
    let passers = passers(&frames, &starers, &config.following);
    let saw: Vec<&Passer> = passers.values().filter(|p| p.saw_starer).collect();
    let followed = saw.iter().filter(|p| p.first_glance.is_some()).count();
    followed as f64 / saw.len() as f64
}

fn street_config(following: FollowConfig) -> CrowdConfig {
    CrowdConfig {
        following: FollowConfig {
            enabled: true,
            ..following
        },
        ..CrowdConfig::street()
    }
}

#[test]
fn passers_by_follow_a_staring_group_as_on_milgrams_street() {
    let sizes = [1, 2, 3, 5, 10, 15];
    let curve: Vec<f64> = sizes
        .iter()
        .map(|&k| {
            share_following(
                AttentionModel::Street,
                street_config(FollowConfig::MILGRAM),
                k,
            )
        })
        .collect();
    for (k, share) in sizes.iter().zip(&curve) {
        println!(
            "{k:2} lookers: {:.1} % of passers-by looked (Milgram: model {:.1} %)",
            100.0 * share,
            100.0 * FollowConfig::MILGRAM.probability(*k as f32)
        );
    }
    // Within 10 points of Milgram's 42 % and 86 % at the ends.
    assert!((curve[0] - 0.42).abs() <= 0.10, "{curve:?}");
    assert!((curve[5] - 0.86).abs() <= 0.10, "{curve:?}");
    // Rising (allowing a point of sampling noise) and saturating: the last five lookers
    // add far less than the first two.
    for pair in curve.windows(2) {
        assert!(pair[1] >= pair[0] - 0.01, "{curve:?}");
    }
    assert!(
        curve[5] - curve[4] < curve[1] - curve[0] + 0.02,
        "{curve:?}"
    );
    assert!(curve[1] - curve[0] > 0.05, "{curve:?}");

    // The weaker street of Gallup et al. (2012): about a quarter of passers-by.
    let gallup = share_following(
        AttentionModel::Street,
        street_config(FollowConfig::GALLUP),
        5,
    );
    println!("Gallup strength, 5 lookers: {:.1} %", 100.0 * gallup);
    assert!((0.15..=0.35).contains(&gallup), "{gallup}");
}

#[test]
fn every_attention_model_follows_and_off_means_off() {
    for model in [
        AttentionModel::Crowd,
        AttentionModel::Saliency,
        AttentionModel::Baseline,
        AttentionModel::Street,
    ] {
        let share = share_following(model, street_config(FollowConfig::MILGRAM), 5);
        let expected = f64::from(FollowConfig::MILGRAM.probability(5.0));
        println!("{model:?}: {:.1} % with 5 lookers", 100.0 * share);
        assert!((share - expected).abs() < 0.12, "{model:?}: {share}");
        let off_config = CrowdConfig {
            following: FollowConfig::MILGRAM,
            ..CrowdConfig::street()
        };
        assert!(!off_config.following.enabled);
        let off = share_following(model, off_config, 5);
        assert_eq!(off, 0.0, "{model:?} follows with following off");
    }
}

#[test]
fn following_does_not_tip_the_crowd() {
    // One starer for a minute in the busiest scene, then it stops.
    let starers = stimulus_group(1);
    let config = street_config(FollowConfig::MILGRAM);
    let frames = replay(
        &tracks(ETH),
        config.clone(),
        AttentionModel::Street,
        &starers,
        0.0..60.0,
        Some(120.0),
    );
    let passers = passers(&frames, &starers, &config.following);
    let start = frames[0].time;
    let present: Vec<&Passer> = passers.values().collect();
    let followed = present.iter().filter(|p| p.first_glance.is_some()).count();
    let second_hand = present
        .iter()
        .filter(|p| p.first_glance.is_some() && !p.saw_starer_before_glance)
        .count();
    let without_starer = present
        .iter()
        .filter(|p| !p.saw_starer_before_glance)
        .count();
    let late = present
        .iter()
        .filter(|p| p.first_glance.is_some_and(|t| t > start + 70.0))
        .count();
    println!(
        "no tipping point: {} people, {followed} glanced at the point, {second_hand} of \
         {without_starer} without seeing the starer first; {late} started more than 10 s \
         after the starer stopped",
        present.len()
    );
    // Followers of followers exist but are few: no cascade through the crowd.
    assert!(
        followed < present.len() / 2,
        "{followed} of {}",
        present.len()
    );
    assert!(
        (second_hand as f64) < 0.15 * without_starer as f64,
        "{second_hand} of {without_starer}"
    );
    // Once the stimulus is gone, following dies out.
    assert_eq!(late, 0);
}

#[test]
fn following_does_not_tip_the_papers_busy_street() {
    use crowdgaze::scenario::{Activity, Scenario};
    use crowdgaze::Crowd;
    // The paper's street (130 people, twice ETH's density), with one walker stopping to
    // stare 10 m up for 40 s.
    let dt = 1.0 / 30.0;
    let mut scenario = Scenario::street(130, 60, 1);
    let mut crowd = Crowd::new(CrowdConfig {
        max_characters: 130,
        max_objects: 60,
        ..street_config(FollowConfig::MILGRAM)
    })
    .unwrap();
    scenario.populate(&mut crowd).unwrap();
    let ids = scenario.character_ids().to_vec();
    let world = crowd.config().world;
    let point = Scenario::world_point(&world, Vec2::new(0.5 * scenario.length, 0.0), 10.0);
    let spot = Vec2::new(0.5 * scenario.length, 2.5);
    let looker = (0..ids.len())
        .filter(|&i| scenario.people[i].activity == Activity::Walking)
        .min_by(|&a, &b| {
            let distance = |i: usize| scenario.people[i].position.distance(spot);
            distance(a).total_cmp(&distance(b))
        })
        .unwrap();
    let follow = crowd.config().following;
    let (mut saw, mut first_hand, mut second_hand, mut late) = (0, 0, 0, 0);
    let mut seen = vec![false; ids.len()];
    let mut glanced = vec![false; ids.len()];
    for frame in 0..100 * 30 {
        let time = f64::from(frame) / 30.0;
        if frame == 10 * 30 {
            scenario.stop_and_look(&mut crowd, looker, point).unwrap();
        }
        if frame == 50 * 30 {
            crowd.clear_gaze_target(ids[looker]).unwrap();
        }
        scenario.advance(dt);
        scenario.push(&mut crowd, time).unwrap();
        crowd.step(dt).unwrap();
        let staring = (10 * 30..50 * 30).contains(&frame);
        let looker_at = scenario.people[looker].position;
        for (i, &id) in ids.iter().enumerate() {
            if i == looker {
                continue;
            }
            let scene = crowd.scene();
            let index = scene.index_of(id).unwrap();
            let forward = world.ground(world.heading_direction(scene.headings()[index]));
            let here = scenario.people[i].position;
            if staring
                && !seen[i]
                && in_view(
                    here,
                    forward,
                    looker_at,
                    follow.distance,
                    follow.view_half_angle,
                )
            {
                seen[i] = true;
                saw += 1;
            }
            if crowd.following(id).unwrap().1 > 0 && !glanced[i] {
                glanced[i] = true;
                if seen[i] {
                    first_hand += 1;
                } else {
                    second_hand += 1;
                }
                late += usize::from(frame > 60 * 30);
            }
        }
    }
    println!(
        "busy street: {saw} saw the starer, {first_hand} of them looked up; {second_hand} \
         looked up having seen only followers; {late} started more than 10 s after the \
         starer stopped"
    );
    assert!(first_hand > 0);
    // Followers draw some more (attention does spread: Gallup et al. 2012), but fewer
    // than they are — below one new follower each, so no cascade — and the street as a
    // whole does not turn to look.
    assert!(second_hand < first_hand, "{second_hand} vs {first_hand}");
    assert!(first_hand + second_hand < ids.len() / 2);
    assert_eq!(late, 0);
}
