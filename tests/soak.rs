//! Soak: long runs through the C API. After every frame no output (gaze records, joint
//! rotations, eyes) is NaN or infinite; the resident memory does not grow after a warm-up;
//! and running the whole thing again gives bit-identical outputs (a hash of every output of
//! every frame).
//!
//! The street runs 10^6 character-frames with `CG_SOAK=full` (what `.ci/run` sets) and a
//! quarter of that by default; the real ETH trajectories loop 10 times at 30 fps (3 by
//! default), and the share of attentive character-frames must not drift from the first loop
//! to the last. Resident memory is the whole process's, so the tests here run one at a time.

// The `unsafe { cg_... }` calls below pass pointers to live values of the sizes the header
// asks for, or deliberately bad ones (NULL, misaligned, wrong struct_size) that the library
// must refuse: that is their safety comment, once for the file.
#![allow(clippy::undocumented_unsafe_blocks)]

mod support;

use crowdgaze::ffi::attention::*;

use crowdgaze::ffi::crowd::*;
use crowdgaze::ffi::gaze::*;
use crowdgaze::ffi::types::{cg_axis, cg_quat};
use crowdgaze::ik::MAX_CHAIN_JOINTS;
use std::collections::HashMap;
use std::hash::{DefaultHasher, Hasher};
use std::sync::Mutex;
use std::time::Instant;
use support::{check, entity_state, init, CrowdHandle, Street};

/// Resident memory may grow by this much after the warm-up (bytes).
const RESIDENT_SLACK: u64 = 64 * 1024;

/// Frames after which the street's resident memory is measured the first time.
const STREET_WARM_UP: u64 = 100;

/// One soak test at a time: resident memory is the whole process's.
static ONE_AT_A_TIME: Mutex<()> = Mutex::new(());

fn full() -> bool {
    std::env::var("CG_SOAK").is_ok_and(|value| value == "full")
}

/// The process's resident set size (bytes), from `/proc/self/statm`; `None` where there is
/// no such file.
fn resident_bytes() -> Option<u64> {
    let statm = std::fs::read_to_string("/proc/self/statm").ok()?;
    let pages: u64 = statm.split_whitespace().nth(1)?.parse().ok()?;
    // SAFETY: sysconf has no preconditions.
    let page = unsafe { libc::sysconf(libc::_SC_PAGESIZE) };
    Some(pages * u64::try_from(page).ok()?)
}

/// Reads every output of a crowd after each frame through the C API (into buffers sized
/// once), checks that no float is NaN or infinite, hashes every bit, and measures resident
/// memory when told.
struct Observer {
    gaze: Vec<cg_gaze_info>,
    joints: Vec<cg_quat>,
    eyes: Vec<cg_eye_info>,
    hash: DefaultHasher,
    frames: u64,
    character_frames: u64,
    resident_after_warm_up: Option<u64>,
    /// Character-frames in which the character attended to something.
    attending: u64,
}

impl Observer {
    fn new(max_characters: usize) -> Observer {
        Observer {
            gaze: vec![cg_gaze_info::default(); max_characters],
            joints: vec![cg_quat::IDENTITY; max_characters * MAX_CHAIN_JOINTS],
            eyes: vec![cg_eye_info::default(); max_characters],
            hash: DefaultHasher::new(),
            frames: 0,
            character_frames: 0,
            resident_after_warm_up: None,
            attending: 0,
        }
    }

    /// Fails unless every value is finite; hashes their bits.
    fn check_and_hash(&mut self, values: &[f32], what: &str, character: u32) {
        assert!(
            values.iter().all(|v| v.is_finite()),
            "frame {}, character {character}: {what} is {values:?}",
            self.frames
        );
        for value in values {
            self.hash.write_u32(value.to_bits());
        }
    }

    fn observe(&mut self, crowd: *const cg_crowd) {
        let mut count = 0;
        check(
            unsafe { cg_crowd_character_count(crowd, &mut count) },
            "count",
        );
        let mut written = 0;
        check(
            unsafe { cg_crowd_read_gaze(crowd, self.gaze.as_mut_ptr(), count, &mut written) },
            "cg_crowd_read_gaze",
        );
        assert_eq!(written, count);
        let mut total = 0;
        check(
            unsafe { cg_crowd_joint_total(crowd, 0, count as u32, &mut total) },
            "cg_crowd_joint_total",
        );
        check(
            unsafe {
                cg_crowd_read_joints(crowd, 0, count as u32, self.joints.as_mut_ptr(), total)
            },
            "cg_crowd_read_joints",
        );
        check(
            unsafe { cg_crowd_read_eyes(crowd, 0, count as u32, self.eyes.as_mut_ptr(), count) },
            "cg_crowd_read_eyes",
        );
        self.hash.write_usize(count);
        let joints_each = total / count.max(1);
        assert_eq!(total, joints_each * count, "every chain is the human one");
        for index in 0..count {
            let gaze = self.gaze[index];
            self.attending += u64::from(gaze.attending);
            let floats = [
                gaze.target_position.x,
                gaze.target_position.y,
                gaze.target_position.z,
                gaze.s_max,
                gaze.threshold,
                gaze.attentive_fraction,
            ];
            self.check_and_hash(&floats, "gaze", gaze.character);
            for word in [
                gaze.character,
                gaze.target,
                gaze.target_part,
                gaze.head_target,
                gaze.attending,
                gaze.interest_count,
            ] {
                self.hash.write_u32(word);
            }
            for joint in index * joints_each..(index + 1) * joints_each {
                let q = self.joints[joint];
                self.check_and_hash(&[q.x, q.y, q.z, q.w], "a joint", gaze.character);
            }
            let eyes = self.eyes[index];
            assert_eq!(eyes.character, gaze.character);
            for v in [
                eyes.left_origin,
                eyes.right_origin,
                eyes.left_direction,
                eyes.right_direction,
            ] {
                self.check_and_hash(&[v.x, v.y, v.z], "an eye", gaze.character);
            }
        }
        self.frames += 1;
        self.character_frames += count as u64;
    }

    fn warmed_up(&mut self) {
        self.resident_after_warm_up = resident_bytes();
    }

    fn finish(self, started: Instant) -> Outcome {
        Outcome {
            hash: self.hash.finish(),
            frames: self.frames,
            character_frames: self.character_frames,
            resident: self.resident_after_warm_up.zip(resident_bytes()),
            seconds: started.elapsed().as_secs_f64(),
        }
    }
}

/// What one run produced.
#[derive(Debug, Clone, Copy)]
struct Outcome {
    hash: u64,
    frames: u64,
    character_frames: u64,
    /// Resident memory (bytes) after the warm-up and at the end.
    resident: Option<(u64, u64)>,
    seconds: f64,
}

/// Prints both runs, then checks memory and determinism.
fn judge(what: &str, runs: [Outcome; 2]) {
    for (run, outcome) in runs.iter().enumerate() {
        let memory = outcome.resident.map_or(
            "not measured (no /proc/self/statm)".into(),
            |(warm, end)| {
                format!(
                    "{} KiB after the warm-up, {} KiB at the end",
                    warm / 1024,
                    end / 1024
                )
            },
        );
        println!(
            "{what}, run {}: {} frames, {} character-frames in {:.2} s; resident {memory}; hash {:016x}",
            run + 1,
            outcome.frames,
            outcome.character_frames,
            outcome.seconds,
            outcome.hash
        );
        if let Some((warm, end)) = outcome.resident {
            assert!(
                end <= warm + RESIDENT_SLACK,
                "{what}, run {}: resident memory grew from {warm} to {end} bytes",
                run + 1
            );
        }
    }
    assert!(runs[0].character_frames > 0);
    assert_eq!(
        runs[0].hash, runs[1].hash,
        "{what}: a second run gave different outputs"
    );
}

fn street_run(characters: usize, frames: u64) -> Outcome {
    let started = Instant::now();
    let mut street = Street::new(characters, 60, 1, 0);
    let mut observer = Observer::new(characters);
    for frame in 1..=frames {
        street.frame();
        observer.observe(street.crowd.as_const());
        if frame == STREET_WARM_UP {
            observer.warmed_up();
        }
    }
    observer.finish(started)
}

#[test]
fn street_soak() {
    let _one = ONE_AT_A_TIME.lock().unwrap_or_else(|e| e.into_inner());
    // 10^6 character-frames in full; the street holds 1 000 people (0.6 per m²).
    let (characters, frames) = if full() { (1000, 1000) } else { (500, 500) };
    let runs = [
        street_run(characters, frames),
        street_run(characters, frames),
    ];
    assert_eq!(runs[0].character_frames, characters as u64 * frames);
    judge("street", runs);
}

/// A person's samples: time (s) and ground position (m).
struct Track {
    samples: Vec<(f64, f32, f32)>,
}

impl Track {
    fn first(&self) -> f64 {
        self.samples[0].0
    }

    fn last(&self) -> f64 {
        self.samples[self.samples.len() - 1].0
    }

    /// The position at `t` (within the track), linear between samples. `cursor` is the
    /// sample at or before the previous call's time (0 for a new pass over the track).
    fn at(&self, t: f64, cursor: &mut usize) -> (f32, f32) {
        let samples = &self.samples;
        while *cursor + 1 < samples.len() && samples[*cursor + 1].0 <= t {
            *cursor += 1;
        }
        let (t0, x0, y0) = samples[*cursor];
        let Some(&(t1, x1, y1)) = samples.get(*cursor + 1) else {
            return (x0, y0);
        };
        let u = ((t - t0) / (t1 - t0)) as f32;
        (x0 + u * (x1 - x0), y0 + u * (y1 - y0))
    }

    /// Heading of the first noticeable move (radians from +X towards +Y).
    fn initial_heading(&self) -> f32 {
        let (_, x0, y0) = self.samples[0];
        self.samples
            .iter()
            .find(|&&(_, x, y)| (x - x0).hypot(y - y0) > 0.05)
            .map_or(0.0, |&(_, x, y)| (y - y0).atan2(x - x0))
    }
}

/// The people of a `frame,id,x,y` file in order of first appearance. One sample is 0.4 s
/// (2.5 Hz): the smallest step between a person's consecutive frame numbers.
fn tracks(rows: &[(u32, u32, f32, f32)]) -> Vec<Track> {
    let mut order = Vec::new();
    let mut by_person: HashMap<u32, Vec<(u32, f32, f32)>> = HashMap::new();
    for &(frame, person, x, y) in rows {
        by_person
            .entry(person)
            .or_insert_with(|| {
                order.push(person);
                Vec::new()
            })
            .push((frame, x, y));
    }
    let step = by_person
        .values()
        .flat_map(|samples| samples.windows(2).map(|w| w[1].0 - w[0].0))
        .min()
        .expect("two samples of one person");
    let seconds_per_frame = 0.4 / f64::from(step);
    order
        .iter()
        .map(|person| {
            let mut samples = by_person[person].clone();
            samples.sort_by_key(|s| s.0);
            Track {
                samples: samples
                    .into_iter()
                    .map(|(frame, x, y)| (f64::from(frame) * seconds_per_frame, x, y))
                    .collect(),
            }
        })
        .collect()
}

/// The ETH people looped `loops` times at 30 fps, Z up and X forward (the file's ground
/// plane): each loop replays the file's span and one more second, on a clock that keeps
/// going. A person enters the crowd when their track starts and leaves when it ends, so
/// every loop adds and removes everyone again (new ids, reused slots). Also returns the
/// attentive share of each loop's character-frames.
fn eth_run(tracks: &[Track], loops: u64) -> (Outcome, Vec<f64>) {
    const FPS: f64 = 30.0;
    let started = Instant::now();
    let mut config: cg_crowd_config = init(cg_crowd_config_init);
    config.up_axis = cg_axis::PositiveZ as u32;
    config.forward_axis = cg_axis::PositiveX as u32;
    config.max_characters = tracks.len() as u32;
    config.max_objects = 0;
    let crowd = CrowdHandle::new(&config);
    let first = tracks
        .iter()
        .map(Track::first)
        .fold(f64::INFINITY, f64::min);
    let last = tracks.iter().map(Track::last).fold(0.0, f64::max);
    let frames_per_loop = ((last - first + 1.0) * FPS).ceil() as u64;
    let mut present: Vec<Option<u32>> = vec![None; tracks.len()];
    let mut cursors = vec![0usize; tracks.len()];
    let mut states = Vec::with_capacity(tracks.len());
    let mut observer = Observer::new(tracks.len());
    let mut attentive = Vec::new();
    let mut loop_start = (0, 0);
    for frame in 0..loops * frames_per_loop {
        let local = first + (frame % frames_per_loop) as f64 / FPS;
        states.clear();
        for (index, track) in tracks.iter().enumerate() {
            let on = track.first() <= local && local <= track.last();
            match (on, present[index]) {
                (true, known) => {
                    let (x, y) = track.at(local, &mut cursors[index]);
                    let position = glam::Vec3::new(x, y, 0.0);
                    let id = known
                        .unwrap_or_else(|| crowd.add_character(position, track.initial_heading()));
                    present[index] = Some(id);
                    let mut state = entity_state(id, 0.0, true);
                    state.position = position.into();
                    states.push(state);
                }
                (false, Some(id)) => {
                    crowd.remove(id);
                    present[index] = None;
                    cursors[index] = 0;
                }
                (false, None) => {}
            }
        }
        crowd.push_and_step(frame as f64 / FPS, (1.0 / FPS) as f32, &states);
        observer.observe(crowd.as_const());
        if frame + 1 == frames_per_loop {
            observer.warmed_up();
        }
        if (frame + 1) % frames_per_loop == 0 {
            let (attending, character_frames) = loop_start;
            attentive.push(
                (observer.attending - attending) as f64
                    / (observer.character_frames - character_frames) as f64,
            );
            loop_start = (observer.attending, observer.character_frames);
        }
    }
    (observer.finish(started), attentive)
}

#[test]
fn eth_loop_soak() {
    let _one = ONE_AT_A_TIME.lock().unwrap_or_else(|e| e.into_inner());
    let tracks = tracks(&support::read_trajectories(support::ETH_SEQ_ETH));
    let loops = if full() { 10 } else { 3 };
    let (first, attentive) = eth_run(&tracks, loops);
    let (second, _) = eth_run(&tracks, loops);
    println!(
        "ETH seq_eth: {} people, {loops} loops (resident memory measured after the first), \
         attentive share per loop {attentive:.3?}",
        tracks.len()
    );
    judge("ETH", [first, second]);
    // The same people again and again: the behaviour must not drift over the hours.
    let drift = attentive[attentive.len() - 1] - attentive[0];
    assert!(drift.abs() < 0.05, "attentive share drifted by {drift:.3}");
}
