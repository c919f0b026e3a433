//! A profiling harness: one crowd step part, timed over many frames, as µs per
//! character-frame — a program to run under `perf` or twice side by side (two builds,
//! alternating), not a benchmark (the README's numbers come from `scripts/bench`).
//!
//! ```text
//! cargo run --release --example profile -- [characters] [part] [frames] [threads]
//! ```
//!
//! `characters` (default 10 000) random walkers at 0.25 people/m² in the benchmarks'
//! plaza, created at random places, walk for 40 frames; then `frames` (default 100) steps
//! of `part` are timed: `attention`, `gaze` (gaze IK alone, attention frozen), `step` (both;
//! the default) or `moving` (both, the crowd walking on: a frame pushed before each step).
//! `threads` is `CrowdConfig::threads` (default 1).

use crowdgaze::scenario::Scenario;
use crowdgaze::{Crowd, CrowdConfig};
use std::time::Instant;

const DENSITY: f32 = 0.25;
const DT: f32 = 1.0 / 30.0;
const WALK_FRAMES: usize = 40;

fn argument<T: std::str::FromStr>(position: usize, default: T) -> T {
    match std::env::args().nth(position) {
        None => default,
        Some(text) => text.parse().unwrap_or_else(|_| {
            eprintln!("argument {position} ({text}) is not valid; see the file's doc comment");
            std::process::exit(2)
        }),
    }
}

fn main() -> crowdgaze::Result<()> {
    let characters: usize = argument(1, 10_000);
    let part: String = argument(2, "step".to_string());
    let frames: usize = argument(3, 100);
    let threads: u32 = argument(4, 1);
    if !["attention", "gaze", "step", "moving"].contains(&part.as_str())
        || frames == 0
        || characters == 0
    {
        eprintln!("part must be attention, gaze, step or moving; characters and frames above 0");
        std::process::exit(2);
    }
    let mut crowd = Crowd::new(CrowdConfig {
        max_characters: characters as u32,
        max_objects: 0,
        threads,
        ..CrowdConfig::default()
    })?;
    let mut scenario = Scenario::plaza(characters, DENSITY, 7);
    scenario.populate(&mut crowd)?;
    for frame in 0..WALK_FRAMES {
        scenario.advance(DT);
        scenario.push(&mut crowd, frame as f64 * f64::from(DT))?;
        crowd.step(DT)?;
    }
    let start = Instant::now();
    for frame in WALK_FRAMES..WALK_FRAMES + frames {
        match part.as_str() {
            "attention" => crowd.step_attention(DT)?,
            "gaze" => crowd.step_gaze(DT)?,
            "moving" => {
                scenario.advance(DT);
                scenario.push(&mut crowd, frame as f64 * f64::from(DT))?;
                crowd.step(DT)?;
            }
            _ => crowd.step(DT)?,
        }
    }
    let per_character_frame = start.elapsed().as_secs_f64() * 1e6 / (characters * frames) as f64;
    println!("{per_character_frame:.3} us per character-frame ({part}, {characters} characters, {threads} thread(s))");
    Ok(())
}
