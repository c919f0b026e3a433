//! Cost of the gaze IK per character-frame: `GazeMotion::update` on the paper's 10-joint
//! human chain, for 1 000 characters following moving targets (with new targets and
//! deactivations now and then), the spatial solve alone, and, in the same run, the
//! damped-least-squares Jacobian IK baseline reaching the same gaze direction from rest.
//!
//! Each criterion iteration is one character-frame. `cargo bench --bench gaze_ik` also
//! prints a summary table of medians and the Jacobian / ours ratio.

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

/// Where one character stands and what it looks at.
struct Setup {
    transform: CharacterTransform,
    /// The target's position at time 0 of its current segment, its velocity, and its key.
    target_start: Vec3,
    target_velocity: Vec3,
}

/// A crowd of characters on a 2 m grid, each following a target walking past at 1.4 m/s,
/// 1.5–6 m away within ±100° of its heading, a new target every 3 s (staggered), and no
/// target one segment in ten.
struct Scene {
    chain: GazeChain,
    config: GazeConfig,
    base: Vec<Quat>,
    setups: Vec<Setup>,
    motions: Vec<GazeMotion>,
    randoms: Vec<Random>,
    frame: u32,
    next: usize,
}

impl Scene {
    fn new() -> Scene {
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
                let across =
                    Vec3::new(yaw.cos(), 0.0, -yaw.sin()) * if index % 2 == 0 { 1.4 } else { -1.4 };
                Setup {
                    transform,
                    target_start: position + transform.rotation * local,
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
            frame: 0,
            next: 0,
        }
    }

    /// The request of character `index` at the current frame.
    fn request(&self, index: usize) -> Option<GazeRequest> {
        let setup = &self.setups[index];
        let frames_per_segment = 90;
        let shifted = self.frame + (index as u32 * 7) % frames_per_segment;
        let segment = shifted / frames_per_segment;
        if (segment + index as u32) % 10 == 0 {
            return None;
        }
        let time = (shifted % frames_per_segment) as f32 * DT - 1.5;
        // Alternate sides from one segment to the next: a new target elsewhere.
        let flip = if segment % 2 == 0 { 1.0 } else { -1.0 };
        let offset = setup.target_start - setup.transform.position;
        let mirrored = Vec3::new(offset.x * flip, offset.y, offset.z);
        let target = setup.transform.position + mirrored + setup.target_velocity * time;
        Some(GazeRequest::at(u64::from(segment), target))
    }

    /// Updates the next character; one call is one character-frame.
    fn step(&mut self) {
        let index = self.next;
        let request = self.request(index);
        let input = GazeInput {
            character: self.setups[index].transform,
            base: &self.base,
            request,
            dt: DT,
        };
        self.motions[index]
            .update(&self.chain, &self.config, &input, &mut self.randoms[index])
            .expect("valid frame");
        self.next += 1;
        if self.next == CHARACTERS {
            self.next = 0;
            self.frame += 1;
        }
    }

    /// Updates the next `BATCH_LANES` characters with one `GazeMotion::update_batch` call
    /// (`CHARACTERS` is a multiple of `BATCH_LANES`).
    fn step_batch(&mut self) {
        let first = self.next;
        let requests: [Option<GazeRequest>; BATCH_LANES] =
            std::array::from_fn(|lane| self.request(first + lane));
        let inputs: [GazeInput<'_>; BATCH_LANES] = std::array::from_fn(|lane| GazeInput {
            character: self.setups[first + lane].transform,
            base: &self.base,
            request: requests[lane],
            dt: DT,
        });
        let [a, b, c, d] = &mut self.motions[first..first + BATCH_LANES] else {
            unreachable!("BATCH_LANES is 4")
        };
        let [ra, rb, rc, rd] = &mut self.randoms[first..first + BATCH_LANES] else {
            unreachable!("BATCH_LANES is 4")
        };
        let results = GazeMotion::update_batch(
            [a, b, c, d],
            [&self.chain; BATCH_LANES],
            &self.config,
            std::array::from_fn(|lane| &inputs[lane]),
            [ra, rb, rc, rd],
        );
        for result in results {
            result.expect("valid frame");
        }
        self.next += BATCH_LANES;
        if self.next == CHARACTERS {
            self.next = 0;
            self.frame += 1;
        }
    }

    /// The spatial solve alone for the next character.
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
        self.next = (self.next + 1) % CHARACTERS;
    }

    /// The Jacobian baseline for the next character: from rest to the same gaze target.
    fn jacobian(&mut self, solver: &JacobianIk, deltas: &mut [Quat; 10]) -> (u32, bool) {
        let index = self.next;
        let target = self
            .request(index)
            .map_or(Vec3::new(0.0, 1.6, 3.0), |r| r.head_target);
        *deltas = [Quat::IDENTITY; 10];
        let outcome = solver.solve(
            &self.chain,
            &self.setups[index].transform,
            &self.base,
            target,
            deltas,
        );
        self.next = (self.next + 1) % CHARACTERS;
        outcome
    }

    /// Runs a few seconds so that the motions are in their steady mix of phases.
    fn warmed_up() -> Scene {
        let mut scene = Scene::new();
        for _ in 0..CHARACTERS * 60 {
            scene.step();
        }
        scene
    }
}

/// One criterion iteration is one crowd frame: every character updated once.
fn benches(criterion: &mut Criterion) {
    let mut group = criterion.benchmark_group("gaze_ik");
    group.throughput(Throughput::Elements(CHARACTERS as u64));
    let mut scene = Scene::warmed_up();
    group.bench_function("GazeMotion::update, 1000 characters", |b| {
        b.iter(|| {
            for _ in 0..CHARACTERS {
                scene.step();
            }
        })
    });
    let mut scene = Scene::warmed_up();
    group.bench_function("GazeMotion::update_batch (4 lanes), 1000 characters", |b| {
        b.iter(|| {
            for _ in 0..CHARACTERS / BATCH_LANES {
                scene.step_batch();
            }
        })
    });
    let mut scene = Scene::warmed_up();
    let mut deltas = [Quat::IDENTITY; 10];
    let mut side = TurnSide::default();
    group.bench_function("spatial::solve, 1000 characters", |b| {
        b.iter(|| {
            for _ in 0..CHARACTERS {
                scene.solve(&mut deltas, &mut side);
                black_box(&deltas);
            }
        })
    });
    group.sample_size(10);
    let mut scene = Scene::warmed_up();
    let solver = JacobianIk::default();
    group.bench_function("Jacobian DLS IK, 1000 characters", |b| {
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
    let mut scene = Scene::warmed_up();
    let update = median_ns(301, || {
        for _ in 0..CHARACTERS {
            scene.step();
        }
    });
    let mut scene = Scene::warmed_up();
    let batch = median_ns(301, || {
        for _ in 0..CHARACTERS / BATCH_LANES {
            scene.step_batch();
        }
    });
    let mut scene = Scene::warmed_up();
    let mut deltas = [Quat::IDENTITY; 10];
    let mut side = TurnSide::default();
    let solve = median_ns(301, || {
        for _ in 0..CHARACTERS {
            scene.solve(&mut deltas, &mut side);
            black_box(&deltas);
        }
    });
    let mut scene = Scene::warmed_up();
    let solver = JacobianIk::default();
    let (mut iterations, mut converged, mut calls) = (0u64, 0u64, 0u64);
    let jacobian = median_ns(31, || {
        for _ in 0..CHARACTERS {
            let (used, reached) = black_box(scene.jacobian(&solver, &mut deltas));
            iterations += u64::from(used);
            converged += u64::from(reached);
            calls += 1;
        }
    });
    println!();
    println!("| 10-joint human chain, {CHARACTERS} characters, moving targets | median ns per character-frame |");
    println!("|---|---:|");
    println!("| `GazeMotion::update_batch`, {BATCH_LANES} characters per call | {batch:.0} |");
    println!("| `GazeMotion::update`, one character per call | {update:.0} |");
    println!("| `spatial::solve` alone (one posture, no timing) | {solve:.0} |");
    println!(
        "| Jacobian DLS IK from rest to 0.5° ({:.1} iterations on average, {:.0}% within 0.5°) | {jacobian:.0} |",
        iterations as f64 / calls as f64,
        100.0 * converged as f64 / calls as f64
    );
    println!();
    println!("Jacobian / `update_batch`: {:.0}×", jacobian / batch);
    println!("Jacobian / `update`: {:.0}×", jacobian / update);
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
