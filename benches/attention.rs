//! Cost per character-frame of a crowd step at a fixed pedestrian density (0.25 people/m²,
//! random walkers in a square plaza, d_m = 10 m), at 1 000, 10 000 and 100 000 characters
//! on 1 and 2 threads (`CrowdConfig::threads`): attention alone, gaze IK alone (10-joint
//! human chain), and the whole step; in the same run the naive all-pairs scoring at 1 000
//! and 10 000 (the baseline), attention every 4th frame (level of detail) at 10 000, and
//! at 10 000 the step and the gaze IK with blinks off, to show what blinks and lids cost;
//! and the paper's street of 1 000 people with a third of them standing in groups that talk
//! in turns, against the same street without groups; and gaze following off and on at
//! 100 000.
//!
//! Run: `cargo bench --bench attention`, or `scripts/bench` for the README's table.
//! Criterion reports time per crowd frame; throughput in elements = characters.

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use crowdgaze::attention::following::FollowConfig;
use crowdgaze::crowd::{ExplicitTarget, TargetPriority};
use crowdgaze::ik::BlinkSettings;
use crowdgaze::scenario::Scenario;
use crowdgaze::{Crowd, CrowdConfig};
use std::hint::black_box;

const DENSITY: f32 = 0.25;
const DT: f32 = 1.0 / 30.0;

/// A plaza whose characters update attention every `period` steps (level of detail),
/// stepped on `threads` threads.
fn plaza_with(characters: usize, period: u32, threads: u32) -> Crowd {
    plaza_configured(characters, period, threads, BlinkSettings::default())
}

/// [`plaza_with`] with `blinks`.
fn plaza_configured(characters: usize, period: u32, threads: u32, blinks: BlinkSettings) -> Crowd {
    let mut crowd = Crowd::new(CrowdConfig {
        blinks,
        max_characters: characters as u32,
        max_objects: 0,
        attention_period: period,
        threads,
        // Storage in spatial order, the step's own best case (the plaza is created in
        // random places); `benches/frame.rs` measures the engine's frame in the default.
        reorder_period: 32,
        ..CrowdConfig::default()
    })
    .expect("crowd");
    let mut scenario = Scenario::plaza(characters, DENSITY, 7);
    warm_up(&mut crowd, &mut scenario);
    crowd
}

/// Adds `scenario`'s people to `crowd` and plays 40 frames: two so that velocities and
/// headings come from motion, then a warm-up.
fn warm_up(crowd: &mut Crowd, scenario: &mut Scenario) {
    scenario.populate(crowd).expect("populate");
    for frame in 0..40 {
        scenario.advance(DT);
        scenario
            .push(crowd, f64::from(frame as f32 * DT))
            .expect("push");
        crowd.step(DT).expect("step");
    }
}

fn attention(c: &mut Criterion) {
    let mut group = c.benchmark_group("attention");
    group.sample_size(20);
    for characters in [1_000usize, 10_000, 100_000] {
        group.throughput(Throughput::Elements(characters as u64));
        for threads in [1, 2] {
            let mut crowd = plaza_with(characters, 1, threads);
            let name = |part: &str| BenchmarkId::new(format!("{part}_{threads}t"), characters);
            group.bench_function(name("attention"), |b| {
                b.iter(|| crowd.step_attention(black_box(DT)).expect("attention"))
            });
            group.bench_function(name("gaze_ik"), |b| {
                b.iter(|| crowd.step_gaze(black_box(DT)).expect("gaze"))
            });
            group.bench_function(name("step"), |b| {
                b.iter(|| crowd.step(black_box(DT)).expect("step"))
            });
            if characters <= 10_000 && threads == 1 {
                group.sample_size(10);
                group.bench_function(name("all_pairs"), |b| {
                    b.iter(|| {
                        for character in 0..crowd.character_count() {
                            black_box(crowd.best_all_pairs_at(character));
                        }
                    })
                });
                group.sample_size(20);
            }
        }
    }
    // Level of detail: attention every 4th step (gaze IK every step), at 10 000.
    let mut crowd = plaza_with(10_000, 4, 1);
    group.throughput(Throughput::Elements(10_000));
    group.bench_function(BenchmarkId::new("attention_lod4_1t", 10_000), |b| {
        b.iter(|| crowd.step_attention(black_box(DT)).expect("attention"))
    });
    // Blinks and lids: the same plaza with blinks on (the default) and off, interleaved.
    let never = BlinkSettings {
        mean_rate: 0.0,
        evoked_probability: 0.0,
        ..BlinkSettings::default()
    };
    let mut blinking = plaza_with(10_000, 1, 1);
    let mut still = plaza_configured(10_000, 1, 1, never);
    // Off first in each pair: the first of two benchmarks run back to back tends to be
    // measured slower, which here counts against blinking's cost, not for it.
    for (name, crowd) in [
        ("step_blinks_off_1t", &mut still),
        ("step_blinks_on_1t", &mut blinking),
    ] {
        group.bench_function(BenchmarkId::new(name, 10_000), |b| {
            b.iter(|| crowd.step(black_box(DT)).expect("step"))
        });
    }
    for (name, crowd) in [
        ("gaze_ik_blinks_off_1t", &mut still),
        ("gaze_ik_blinks_on_1t", &mut blinking),
    ] {
        group.bench_function(BenchmarkId::new(name, 10_000), |b| {
            b.iter(|| crowd.step_gaze(black_box(DT)).expect("gaze"))
        });
    }
    group.finish();
}

/// The street of `people` (the papers' mix, 60 props), a third of them in conversations or
/// none, warmed up; and its scenario, to move it on.
fn street(people: usize, conversations: bool) -> (Crowd, Scenario) {
    let mut crowd = Crowd::new(CrowdConfig {
        max_characters: people as u32,
        max_conversations: people as u32,
        ..CrowdConfig::default()
    })
    .expect("crowd");
    let mut scenario = Scenario::street(people, 60, 3);
    if conversations {
        scenario = scenario.with_conversations(1.0 / 3.0, 5);
    }
    warm_up(&mut crowd, &mut scenario);
    (crowd, scenario)
}

/// The street with and without conversations: each frame moves the people and pushes
/// their states (not timed), then steps (timed).
fn conversations(c: &mut Criterion) {
    let mut group = c.benchmark_group("street");
    group.sample_size(20);
    let people = 1_000;
    group.throughput(Throughput::Elements(people as u64));
    for (name, talking) in [("step_alone_1t", false), ("step_conversations_1t", true)] {
        let (mut crowd, mut scenario) = street(people, talking);
        let mut time = 40.0 * f64::from(DT);
        group.bench_function(BenchmarkId::new(name, people), |b| {
            b.iter_custom(|iterations| {
                let mut total = std::time::Duration::ZERO;
                for _ in 0..iterations {
                    time += f64::from(DT);
                    scenario.advance(DT);
                    scenario.push(&mut crowd, time).expect("push");
                    let start = std::time::Instant::now();
                    crowd.step(black_box(DT)).expect("step");
                    total += start.elapsed();
                }
                total
            })
        });
    }
    group.finish();
}

/// Gaze following's cost at 100 000 characters: the plaza with one character in a thousand
/// staring at a point 8 m up (an overriding gaze target), stepped with following off and
/// on (off first, as for blinks).
fn following(c: &mut Criterion) {
    let mut group = c.benchmark_group("following");
    group.sample_size(10);
    let characters = 100_000;
    group.throughput(Throughput::Elements(characters as u64));
    for (name, enabled) in [
        ("step_following_off_1t", false),
        ("step_following_on_1t", true),
    ] {
        let mut crowd = Crowd::new(CrowdConfig {
            max_characters: characters as u32,
            max_objects: 0,
            reorder_period: 32,
            following: FollowConfig {
                enabled,
                ..FollowConfig::MILGRAM
            },
            ..CrowdConfig::default()
        })
        .expect("crowd");
        let mut scenario = Scenario::plaza(characters, DENSITY, 7);
        scenario.populate(&mut crowd).expect("populate");
        for &id in scenario.character_ids().iter().step_by(1000) {
            crowd
                .set_gaze_target(
                    id,
                    ExplicitTarget::Point(glam::Vec3::new(0.0, 8.0, 0.0)),
                    TargetPriority::Override,
                )
                .expect("stare");
        }
        for frame in 0..40 {
            scenario.advance(DT);
            scenario
                .push(&mut crowd, f64::from(frame as f32 * DT))
                .expect("push");
            crowd.step(DT).expect("step");
        }
        group.bench_function(BenchmarkId::new(name, characters), |b| {
            b.iter(|| crowd.step(black_box(DT)).expect("step"))
        });
    }
    group.finish();
}

/// Writes the bytes of state per character beside criterion's results, for the table.
fn state_bytes(_: &mut Criterion) {
    let directory = std::path::Path::new(env!("CARGO_TARGET_TMPDIR"))
        .parent()
        .expect("target directory")
        .join("criterion");
    std::fs::create_dir_all(&directory).expect("criterion directory");
    std::fs::write(
        directory.join("state_bytes_per_character.txt"),
        Crowd::state_bytes_per_character().to_string(),
    )
    .expect("write the state size");
}

criterion_group!(benches, attention, conversations, following, state_bytes);
criterion_main!(benches);
