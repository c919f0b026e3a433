//! Attention cost per character-frame at a fixed pedestrian density (0.25 people/m², random
//! walkers in a square plaza, d_m = 10 m): attention alone and the whole step (attention
//! and gaze IK) at 1 000, 10 000 and 100 000 characters, the naive all-pairs scoring at
//! 1 000 and 10 000, and attention every 4th frame (level of detail) at 10 000, in the same
//! run.
//!
//! Run: `cargo bench --bench attention`. Criterion reports time per character-frame
//! (throughput in elements = characters).

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use crowdgaze::scenario::Scenario;
use crowdgaze::{Crowd, CrowdConfig};
use std::hint::black_box;

const DENSITY: f32 = 0.25;
const DT: f32 = 1.0 / 30.0;

fn plaza(characters: usize) -> Crowd {
    plaza_with(characters, 1)
}

/// A plaza whose characters update attention every `period` steps (level of detail).
fn plaza_with(characters: usize, period: u32) -> Crowd {
    let mut crowd = Crowd::new(CrowdConfig {
        max_characters: characters as u32,
        max_objects: 0,
        attention_period: period,
        ..CrowdConfig::default()
    })
    .expect("crowd");
    let mut scenario = Scenario::plaza(characters, DENSITY, 7);
    scenario.populate(&mut crowd).expect("populate");
    // Two frames so that velocities and headings come from motion, then a warm-up.
    for frame in 0..40 {
        scenario.advance(DT);
        scenario
            .push(&mut crowd, f64::from(frame as f32 * DT))
            .expect("push");
        crowd.step(DT).expect("step");
    }
    crowd
}

fn attention(c: &mut Criterion) {
    let mut group = c.benchmark_group("attention");
    group.sample_size(20);
    for characters in [1_000usize, 10_000, 100_000] {
        let mut crowd = plaza(characters);
        group.throughput(Throughput::Elements(characters as u64));
        group.bench_function(BenchmarkId::new("grid", characters), |b| {
            b.iter(|| crowd.step_attention(black_box(DT)).expect("attention"))
        });
        group.bench_function(BenchmarkId::new("grid_and_gaze_ik", characters), |b| {
            b.iter(|| crowd.step(black_box(DT)).expect("step"))
        });
        if characters <= 10_000 {
            group.sample_size(10);
            group.bench_function(BenchmarkId::new("all_pairs", characters), |b| {
                b.iter(|| {
                    for character in 0..crowd.character_count() {
                        black_box(crowd.best_all_pairs_dense(character));
                    }
                })
            });
            group.sample_size(20);
        }
    }
    // Level of detail: attention every 4th step (gaze IK every step), at 10 000.
    let mut crowd = plaza_with(10_000, 4);
    group.throughput(Throughput::Elements(10_000));
    group.bench_function(BenchmarkId::new("grid_lod4", 10_000), |b| {
        b.iter(|| crowd.step_attention(black_box(DT)).expect("attention"))
    });
    group.finish();
}

criterion_group!(benches, attention);
criterion_main!(benches);
