//! Cost of the gaze IK per character-frame on the paper's 10-joint human chain, 1 000
//! characters, and in the same run the damped-least-squares Jacobian IK baseline (the paper's
//! comparison) reaching the same gaze direction.
//!
//! Two scenes:
//! - **tracking**: every character follows one moving target (a pedestrian walking past at
//!   1.4 m/s, 1.5–6 m away, within ±100° of its heading, eye level ± 0.4 m);
//! - **crowd mix**: the same, but a new target every 3 s (staggered, on alternate sides, so
//!   a shift is always under way somewhere) and no target one time in ten (deactivation).
//!
//! One criterion iteration is one crowd frame (1 000 character-frames). `cargo bench --bench
//! gaze_ik` ends with a summary table of medians per character-frame and the ratios.

mod support;

use std::hint::black_box;
use std::time::Instant;

use criterion::{Criterion, Throughput};
use crowdgaze::ik::spatial;
use crowdgaze::ik::temporal::BATCH_LANES;
use crowdgaze::ik::{
    CharacterTransform, GazeChain, GazeConfig, GazeInput, GazeMotion, GazeRequest, TurnSide,
};
use crowdgaze::math::random::{stream, Purpose, Random};
use glam::{Quat, Vec3};
use support::jacobian::JacobianIk;

const CHARACTERS: usize = 1000;
const DT: f32 = 1.0 / 30.0;
const FRAMES_PER_TARGET: u32 = 90;
/// The characters left for a last, smaller `update_batch` call in each frame.
const LAST_BATCH: usize = CHARACTERS % BATCH_LANES;

/// Where one character stands and what it looks at.
struct Setup {
    transform: CharacterTransform,
    /// The target's offset from the character at the middle of its walk, and its velocity.
    target_offset: Vec3,
    target_velocity: Vec3,
}

/// A crowd of characters on a 2 m grid with random headings, each with its target.
struct Scene {
    chain: GazeChain,
    config: GazeConfig,
    base: Vec<Quat>,
    setups: Vec<Setup>,
    motions: Vec<GazeMotion>,
    randoms: Vec<Random>,
    /// New targets and deactivations (crowd mix) or one target each (tracking).
    mix: bool,
    frame: u32,
    next: usize,
}

impl Scene {
    fn new(mix: bool) -> Scene {
        let chain = GazeChain::human(Vec3::Y, Vec3::Z);
        let mut random = stream(1, Purpose::Scene, 0);
        let setups = (0..CHARACTERS)
            .map(|index| {
                let position = Vec3::new((index % 32) as f32 * 2.0, 0.0, (index / 32) as f32 * 2.0);
                let heading = random.range(-3.1, 3.1);
                let transform = CharacterTransform::from_heading(position, Vec3::Y, heading);
                let yaw = random.range(-100f32, 100.0).to_radians();
                let distance = random.range(1.5, 6.0);
                let height = random.range(1.2, 2.0);
                let local = Vec3::new(yaw.sin() * distance, height, yaw.cos() * distance);
                let speed = if index % 2 == 0 { 1.4 } else { -1.4 };
                let across = Vec3::new(yaw.cos(), 0.0, -yaw.sin()) * speed;
                Setup {
                    transform,
                    target_offset: transform.rotation * local,
                    target_velocity: transform.rotation * across,
                }
            })
            .collect();
        Scene {
            base: chain.joints().iter().map(|joint| joint.rest).collect(),
            motions: vec![GazeMotion::new(&chain); CHARACTERS],
            randoms: (0..CHARACTERS as u64)
                .map(|index| stream(1, Purpose::GazeTiming, index))
                .collect(),
            chain,
            config: GazeConfig::default(),
            setups,
            mix,
            frame: 0,
            next: 0,
        }
    }

    /// The request of character `index` at the current frame.
    fn request(&self, index: usize) -> Option<GazeRequest> {
        let setup = &self.setups[index];
        if !self.mix {
            // Walking back and forth across the character's view, 6 s each way.
            let period = 360;
            let phase = (self.frame + index as u32 * 13) % (2 * period);
            let walked = if phase < period {
                phase
            } else {
                2 * period - phase
            };
            let time = walked as f32 * DT - 3.0;
            let target =
                setup.transform.position + setup.target_offset + setup.target_velocity * time;
            return Some(GazeRequest::at(1, target));
        }
        let shifted = self.frame + (index as u32 * 7) % FRAMES_PER_TARGET;
        let segment = shifted / FRAMES_PER_TARGET;
        if (segment + index as u32).is_multiple_of(10) {
            return None;
        }
        let time = (shifted % FRAMES_PER_TARGET) as f32 * DT - 1.5;
        // Alternate sides from one target to the next.
        let offset = setup.target_offset;
        let flip = if segment.is_multiple_of(2) { 1.0 } else { -1.0 };
        let mirrored = setup.transform.rotation
            * (setup.transform.rotation.conjugate() * offset * Vec3::new(flip, 1.0, 1.0));
        let target = setup.transform.position + mirrored + setup.target_velocity * time;
        Some(GazeRequest::at(u64::from(segment), target))
    }

    fn advance(&mut self, characters: usize) {
        self.next += characters;
        if self.next == CHARACTERS {
            self.next = 0;
            self.frame += 1;
        }
    }

    /// Updates the next character with `GazeMotion::update`.
    fn step(&mut self) {
        let index = self.next;
        let input = GazeInput {
            character: self.setups[index].transform,
            base: &self.base,
            request: self.request(index),
            dt: DT,
        };
        self.motions[index]
            .update(&self.chain, &self.config, &input, &mut self.randoms[index])
            .expect("valid frame");
        self.advance(1);
    }

    /// Updates the next `N` characters with one `GazeMotion::update_batch` call.
    fn step_batch<const N: usize>(&mut self) {
        let first = self.next;
        let requests: [Option<GazeRequest>; N] =
            std::array::from_fn(|lane| self.request(first + lane));
        let inputs: [GazeInput<'_>; N] = std::array::from_fn(|lane| GazeInput {
            character: self.setups[first + lane].transform,
            base: &self.base,
            request: requests[lane],
            dt: DT,
        });
        let range = first..first + N;
        let motions = <&mut [GazeMotion; N]>::try_from(&mut self.motions[range.clone()])
            .expect("a whole batch");
        let randoms =
            <&mut [Random; N]>::try_from(&mut self.randoms[range]).expect("a whole batch");
        let results = GazeMotion::update_batch(
            motions.each_mut(),
            [&self.chain; N],
            &self.config,
            inputs.each_ref(),
            randoms.each_mut(),
        );
        for result in results {
            result.expect("valid frame");
        }
        self.advance(N);
    }

    /// The spatial solve alone (one posture, no timing) for the next character's target.
    fn solve(&mut self, deltas: &mut [Quat; 10], side: &mut TurnSide) {
        let index = self.next;
        let target = self
            .request(index)
            .map_or(Vec3::new(0.0, 1.6, 3.0), |r| r.head_target);
        spatial::solve(
            &self.chain,
            &self.config.spatial,
            &self.setups[index].transform,
            &self.base,
            target,
            target,
            side,
            deltas,
        )
        .expect("valid frame");
        self.advance(1);
    }

    /// The Jacobian baseline for the next character: from rest to the same gaze target.
    fn jacobian(&mut self, solver: &JacobianIk, deltas: &mut [Quat; 10]) -> (u32, bool) {
        let index = self.next;
        let target = self
            .request(index)
            .map_or(Vec3::new(0.0, 1.6, 3.0), |r| r.head_target);
        *deltas = [Quat::IDENTITY; 10];
        let transform = self.setups[index].transform;
        let outcome = solver.solve(&self.chain, &transform, &self.base, target, deltas);
        self.advance(1);
        outcome
    }

    /// A scene after 2 s, so that the motions are in their steady mix of phases.
    fn warmed_up(mix: bool) -> Scene {
        let mut scene = Scene::new(mix);
        for _ in 0..60 {
            scene.frame_batched();
        }
        scene
    }

    /// One crowd frame with `update_batch`, `BATCH_LANES` characters per call and the last
    /// few in one smaller call: how a crowd updates its characters.
    fn frame_batched(&mut self) {
        for _ in 0..CHARACTERS / BATCH_LANES {
            self.step_batch::<BATCH_LANES>();
        }
        if LAST_BATCH > 0 {
            self.step_batch::<{
                if LAST_BATCH > 0 {
                    LAST_BATCH
                } else {
                    1
                }
            }>();
        }
    }

    /// One crowd frame with `update`, one character per call.
    fn frame_single(&mut self) {
        for _ in 0..CHARACTERS {
            self.step();
        }
    }
}

fn benches(criterion: &mut Criterion) {
    let mut group = criterion.benchmark_group("gaze_ik");
    group.throughput(Throughput::Elements(CHARACTERS as u64));
    for (mix, name) in [(false, "tracking"), (true, "crowd mix")] {
        let mut scene = Scene::warmed_up(mix);
        group.bench_function(format!("update_batch, {name}, 1000 characters"), |b| {
            b.iter(|| scene.frame_batched())
        });
    }
    let mut scene = Scene::warmed_up(false);
    group.bench_function("update (one per call), tracking, 1000 characters", |b| {
        b.iter(|| scene.frame_single())
    });
    let mut scene = Scene::warmed_up(false);
    let mut deltas = [Quat::IDENTITY; 10];
    let mut side = TurnSide::default();
    group.bench_function("spatial::solve, tracking, 1000 characters", |b| {
        b.iter(|| {
            for _ in 0..CHARACTERS {
                scene.solve(&mut deltas, &mut side);
                black_box(&deltas);
            }
        })
    });
    group.sample_size(10);
    let mut scene = Scene::warmed_up(false);
    let solver = JacobianIk::default();
    group.bench_function("Jacobian DLS IK, tracking, 1000 characters", |b| {
        b.iter(|| {
            for _ in 0..CHARACTERS {
                black_box(scene.jacobian(&solver, &mut deltas));
            }
        })
    });
    group.finish();
}

/// Median over `samples` crowd frames of `frame`, in ns per character.
fn median_ns(samples: usize, mut frame: impl FnMut()) -> f64 {
    let mut timings: Vec<f64> = (0..samples)
        .map(|_| {
            let start = Instant::now();
            frame();
            start.elapsed().as_nanos() as f64 / CHARACTERS as f64
        })
        .collect();
    timings.sort_by(f64::total_cmp);
    timings[samples / 2]
}

/// The table for the README: medians over crowd frames of 1 000 characters.
fn summary() {
    let mut scene = Scene::warmed_up(false);
    let tracking = median_ns(301, || scene.frame_batched());
    let mut scene = Scene::warmed_up(true);
    let mix = median_ns(301, || scene.frame_batched());
    let mut scene = Scene::warmed_up(false);
    let single = median_ns(101, || scene.frame_single());
    let mut scene = Scene::warmed_up(false);
    let mut deltas = [Quat::IDENTITY; 10];
    let mut side = TurnSide::default();
    let solve = median_ns(101, || {
        for _ in 0..CHARACTERS {
            scene.solve(&mut deltas, &mut side);
            black_box(&deltas);
        }
    });
    let mut scene = Scene::warmed_up(false);
    let solver = JacobianIk::default();
    let (mut iterations, mut converged, mut calls) = (0u64, 0u64, 0u64);
    let jacobian = median_ns(21, || {
        for _ in 0..CHARACTERS {
            let (used, reached) = black_box(scene.jacobian(&solver, &mut deltas));
            iterations += u64::from(used);
            converged += u64::from(reached);
            calls += 1;
        }
    });
    // The SIMD width the gaze IK runs at (the same detection as the blending's).
    let lanes = crowdgaze::blend::simd_lanes();
    println!();
    println!("| 10-joint human chain, {CHARACTERS} characters | median ns per character-frame |");
    println!("|---|---:|");
    println!("| `GazeMotion::update_batch` ({BATCH_LANES} per call, {lanes} lanes), tracking | {tracking:.0} |");
    println!("| `GazeMotion::update_batch` ({BATCH_LANES} per call, {lanes} lanes), crowd mix | {mix:.0} |");
    println!("| `GazeMotion::update` (1 per call), tracking | {single:.0} |");
    println!("| `spatial::solve` (1 per call, one posture), tracking | {solve:.0} |");
    println!(
        "| Jacobian DLS IK from rest to 0.5°, tracking ({:.1} iterations on average, {:.0}% within 0.5°) | {jacobian:.0} |",
        iterations as f64 / calls as f64,
        100.0 * converged as f64 / calls as f64
    );
    println!();
    println!(
        "Jacobian / `update_batch` (tracking): {:.0}×",
        jacobian / tracking
    );
    println!("Jacobian / `update`: {:.0}×", jacobian / single);
    println!("Jacobian / `spatial::solve`: {:.0}×", jacobian / solve);
}

fn main() {
    let mut criterion = Criterion::default().configure_from_args();
    benches(&mut criterion);
    criterion.final_summary();
    if std::env::args().any(|argument| argument == "--bench") {
        summary();
    }
}
