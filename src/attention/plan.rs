//! Offline attention (the paper's own pipeline): record whole trajectories, then score every
//! frame, take each character's exact `(100 − a)`th percentile of `S_max(t)` as its
//! threshold, and cut the frames into constraints `(entity, t_b, t_e)`.
//!
//! A constraint is a run of frames where one entity holds `S_max ≥ A`; runs shorter than
//! `min_hold` are dropped; a run longer than `d_l` is cut there, the entity cools down, and
//! the next-best entity (the second-best of each frame) may continue. Unlike the online
//! tracker, a constraint starts at the first frame of its run (no reaction delay).
//! Velocities are forward differences `(p(t+1) − p(t)) / Δt` (the last sample of an entity
//! uses the backward difference). An entity counts only between its first and last recorded
//! sample; never-recorded entities (static objects) always count.

use std::collections::HashMap;
use std::fmt::Display;

use glam::Vec3;

use super::candidates::{nearby_candidates, CandidateBatch, NeighbourIndex};
use super::interest::{Candidate, InterestConfig};
use super::quantile::exact_quantile;
use super::score::Scorer;
use super::CharacterParams;
use crate::alloc::{checked, try_insert, try_reserve, try_vec, try_with_capacity};
use crate::error::{Error, Result};
use crate::scene::ids::NO_ENTITY;
use crate::scene::{EntityUpdate, Scene};

/// A planned gaze constraint: look at `entity` from `begin` to `end` (seconds).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Constraint {
    /// Entity id of the interest point.
    pub entity: u32,
    /// `t_b`, start (s).
    pub begin: f64,
    /// `t_e`, end (s).
    pub end: f64,
    /// `S_max` at `t_b` (sets the activation speed).
    pub s_max: f32,
}

#[derive(Debug, Clone, Copy)]
struct RecordedFrame {
    time: f64,
    start: usize,
    end: usize,
}

/// Frames pushed while recording is on, in a buffer sized at creation.
#[derive(Debug, Clone)]
pub struct Recording {
    capacity: usize,
    frames: Vec<RecordedFrame>,
    states: Vec<EntityUpdate>,
}

impl Recording {
    /// A recording of at most `capacity` entity states (and frames), or
    /// [`Error::OutOfMemory`] for `what` (the caller's number `capacity` comes from).
    pub fn new(capacity: usize, what: &dyn Display) -> Result<Recording> {
        Ok(Recording {
            capacity,
            frames: try_with_capacity(capacity, what)?,
            states: try_with_capacity(capacity, what)?,
        })
    }

    /// Bytes of buffers per recorded state (a state and a frame's room).
    pub fn bytes_per_state() -> usize {
        std::mem::size_of::<RecordedFrame>() + std::mem::size_of::<EntityUpdate>()
    }

    /// True if recording is on.
    pub fn is_enabled(&self) -> bool {
        self.capacity > 0
    }

    /// Number of recorded frames.
    pub fn frame_count(&self) -> usize {
        self.frames.len()
    }

    /// Appends a frame of `count` states produced on the fly (`None` ones are skipped), or
    /// fails with [`Error::Capacity`] without recording anything.
    pub fn record_with(
        &mut self,
        time: f64,
        count: usize,
        state: impl Fn(usize) -> Option<EntityUpdate>,
    ) -> Result<()> {
        if self.states.len() + count > self.capacity || self.frames.len() >= self.capacity {
            return Err(Error::Capacity(format!(
                "the recording holds {} of max_recorded_states = {}; {} more do not fit",
                self.states.len(),
                self.capacity,
                count
            )));
        }
        let start = self.states.len();
        self.states.extend((0..count).filter_map(state));
        self.frames.push(RecordedFrame {
            time,
            start,
            end: self.states.len(),
        });
        Ok(())
    }

    /// Forgets every recorded frame (keeps the buffers).
    pub fn clear(&mut self) {
        self.frames.clear();
        self.states.clear();
    }
}

/// The result of planning, and the cursor that replays it while stepping.
#[derive(Debug, Clone)]
pub struct Plan {
    frames: Vec<RecordedFrame>,
    /// The recorded states with their velocities filled in.
    states: Vec<EntityUpdate>,
    /// `[frame × characters]`: the best candidate of each character at each frame.
    best: Vec<Candidate>,
    character_count: usize,
    thresholds: Vec<f32>,
    attentive_fraction: Vec<f32>,
    constraints: Vec<Constraint>,
    /// `constraint_start[c] .. constraint_start[c + 1]` are character c's constraints.
    constraint_start: Vec<usize>,
    // Replay.
    clock: f64,
    started: bool,
    next_frame: usize,
    cursor: Vec<usize>,
}

impl Plan {
    /// Scores the whole recording and builds every character's threshold and constraints.
    /// Replays the recording through `scene` and `index` (their state afterwards is the last
    /// frame's).
    ///
    /// Errors: [`Error::OutOfMemory`] if the plan's buffers (a few bytes per recorded frame
    /// and character) cannot be allocated; `scene` and `index` are then unchanged.
    pub fn build(
        recording: &Recording,
        scene: &mut Scene,
        index: &mut NeighbourIndex,
        scorer: &Scorer,
        params: &[CharacterParams],
        interest: &InterestConfig,
    ) -> Result<Plan> {
        let character_count = scene.character_count();
        let frame_count = recording.frames.len();
        let what =
            &format!("a plan of {frame_count} recorded frames × {character_count} characters");
        let what: &dyn Display = what;
        // Every buffer first, and the replay on copies of the scene and the index, so that
        // running out of memory at any point leaves both as they were.
        let states = with_forward_velocities(recording, what)?;
        let spans = sample_spans(recording, what)?;
        let cells = checked(frame_count.checked_mul(character_count), what)?;
        let mut best = try_vec(checked(cells.checked_mul(2), what)?, Candidate::NONE, what)?;
        let mut present = try_vec(cells, false, what)?;
        let mut kept = try_with_capacity(cells, what)?;
        let mut active = try_with_capacity(scene.len(), what)?;
        let mut thresholds = try_vec(character_count, f32::INFINITY, what)?;
        let mut attentive_fraction = try_vec(character_count, 0.0, what)?;
        let mut constraints = Vec::new();
        let mut constraint_start = try_with_capacity(character_count + 1, what)?;
        let mut series = try_with_capacity(frame_count, what)?;
        let mut frames = try_with_capacity(frame_count, what)?;
        frames.extend_from_slice(&recording.frames);
        let cursor = try_vec(character_count, 0, what)?;
        let mut replay_scene = scene.try_clone(what)?;
        let mut replay_index = index.try_clone(what)?;
        let mut batch = Box::<CandidateBatch>::default();
        {
            let scene = &mut replay_scene;
            let index = &mut replay_index;
            for (f, frame) in recording.frames.iter().enumerate() {
                scene.apply(frame.time, &states[frame.start..frame.end]);
                index.rebuild(scene, scorer.config().talking_gain);
                active.clear();
                active.extend(scene.ids().iter().map(|id| match spans.get(id) {
                    Some(&(first, last)) => first <= frame.time && frame.time <= last,
                    None => true,
                }));
                for (c, character_params) in params.iter().enumerate().take(character_count) {
                    let entity = scene.character_entities()[c] as usize;
                    if !active[entity] {
                        continue;
                    }
                    present[f * character_count + c] = true;
                    let (first, second) = nearby_candidates(
                        scene,
                        index,
                        scorer,
                        c,
                        &character_params.weights,
                        &mut batch,
                        |id| scene.index_of(id).is_none_or(|other| !active[other]),
                    );
                    best[2 * (f * character_count + c)] = first;
                    best[2 * (f * character_count + c) + 1] = second;
                }
            }
        }

        for c in 0..character_count {
            constraint_start.push(constraints.len());
            series.clear();
            series.extend(
                (0..frame_count)
                    .filter(|f| present[f * character_count + c])
                    .map(|f| best[2 * (f * character_count + c)].score),
            );
            let fraction = params[c].attention_fraction;
            let threshold = if fraction <= 0.0 {
                f32::INFINITY
            } else if fraction >= 1.0 {
                0.0
            } else {
                exact_quantile(&mut series, 1.0 - fraction).unwrap_or(f32::INFINITY)
            };
            thresholds[c] = threshold;
            let first = constraints.len();
            cut_constraints(
                &recording.frames,
                |f| {
                    present[f * character_count + c].then(|| {
                        (
                            best[2 * (f * character_count + c)],
                            best[2 * (f * character_count + c) + 1],
                        )
                    })
                },
                threshold,
                interest,
                &mut constraints,
                what,
            )?;
            let observed: f64 =
                observed_time(&recording.frames, |f| present[f * character_count + c]);
            let attended: f64 = constraints[first..].iter().map(|k| k.end - k.begin).sum();
            attentive_fraction[c] = if observed > 0.0 {
                (attended / observed) as f32
            } else {
                0.0
            };
        }
        constraint_start.push(constraints.len());
        // Keep only the best of each frame for replay output.
        kept.extend(best.chunks(2).map(|pair| pair[0]));
        drop(best);
        // Nothing can fail from here on: the replayed state becomes the crowd's.
        *scene = replay_scene;
        *index = replay_index;

        Ok(Plan {
            frames,
            states,
            best: kept,
            character_count,
            thresholds,
            attentive_fraction,
            constraints,
            constraint_start,
            clock: recording.frames[0].time,
            started: false,
            next_frame: 0,
            cursor,
        })
    }

    /// Character `c`'s constraints (dense index).
    pub fn constraints(&self, character: usize) -> &[Constraint] {
        self.constraint_start
            .get(character)
            .zip(self.constraint_start.get(character + 1))
            .map(|(&a, &b)| &self.constraints[a..b])
            .unwrap_or(&[])
    }

    /// Character `c`'s exact threshold.
    pub fn threshold(&self, character: usize) -> f32 {
        self.thresholds
            .get(character)
            .copied()
            .unwrap_or(f32::INFINITY)
    }

    /// Fraction of its recorded time character `c` spends in constraints.
    pub fn attentive_fraction(&self, character: usize) -> f32 {
        self.attentive_fraction
            .get(character)
            .copied()
            .unwrap_or(0.0)
    }

    /// The replay clock (s).
    pub fn clock(&self) -> f64 {
        self.clock
    }

    /// Advances the replay clock by `dt` (the first call starts at the first frame) and
    /// applies every recorded frame up to it to `scene`.
    pub fn advance(&mut self, dt: f32, scene: &mut Scene) {
        if self.started {
            self.clock += f64::from(dt);
        }
        self.started = true;
        while self.next_frame < self.frames.len() && self.frames[self.next_frame].time <= self.clock
        {
            let frame = self.frames[self.next_frame];
            scene.apply(frame.time, &self.states[frame.start..frame.end]);
            self.next_frame += 1;
        }
        for character in 0..self.character_count.min(self.cursor.len()) {
            let list = self.constraints(character);
            let mut cursor = self.cursor[character];
            while cursor < list.len() && list[cursor].end <= self.clock {
                cursor += 1;
            }
            self.cursor[character] = cursor;
        }
    }

    /// For character `c` at the replay clock: the planned IP (or `NO_ENTITY`), `S_max` of
    /// the latest replayed frame, and the threshold.
    pub fn current(&self, character: usize) -> (u32, f32, f32) {
        if character >= self.character_count {
            return (NO_ENTITY, 0.0, f32::INFINITY);
        }
        let list = self.constraints(character);
        let target = list
            .get(self.cursor[character])
            .filter(|k| k.begin <= self.clock && self.clock < k.end)
            .map_or(NO_ENTITY, |k| k.entity);
        let s_max = match self.next_frame {
            0 => 0.0,
            f => self.best[(f - 1) * self.character_count + character].score,
        };
        (target, s_max, self.thresholds[character])
    }
}

/// The recorded states with every missing velocity filled by a forward difference.
fn with_forward_velocities(recording: &Recording, what: &dyn Display) -> Result<Vec<EntityUpdate>> {
    let mut states = try_with_capacity(recording.states.len(), what)?;
    states.extend_from_slice(&recording.states);
    let mut next_sample: HashMap<u32, (f64, Vec3)> = HashMap::new();
    let mut previous_sample: HashMap<u32, (f64, Vec3)> = HashMap::new();
    // Backward differences first (for each entity's last sample), then forward ones.
    let mut backward = try_vec(states.len(), None, what)?;
    for frame in &recording.frames {
        for k in frame.start..frame.end {
            let state = states[k];
            if let Some(&(time, position)) = previous_sample.get(&state.id) {
                if frame.time > time {
                    backward[k] = Some((state.position - position) / (frame.time - time) as f32);
                }
            }
            try_insert(
                &mut previous_sample,
                state.id,
                (frame.time, state.position),
                what,
            )?;
        }
    }
    for frame in recording.frames.iter().rev() {
        for k in frame.start..frame.end {
            let state = &mut states[k];
            let forward = next_sample
                .get(&state.id)
                .filter(|(time, _)| *time > frame.time)
                .map(|&(time, position)| (position - state.position) / (time - frame.time) as f32);
            if state.velocity.is_none() {
                state.velocity = Some(forward.or(backward[k]).unwrap_or(Vec3::ZERO));
            }
            try_insert(
                &mut next_sample,
                state.id,
                (frame.time, state.position),
                what,
            )?;
        }
    }
    Ok(states)
}

/// First and last recorded time of every recorded entity.
fn sample_spans(recording: &Recording, what: &dyn Display) -> Result<HashMap<u32, (f64, f64)>> {
    let mut spans: HashMap<u32, (f64, f64)> = HashMap::new();
    for frame in &recording.frames {
        for state in &recording.states[frame.start..frame.end] {
            match spans.get_mut(&state.id) {
                Some(span) => span.1 = frame.time,
                None => try_insert(&mut spans, state.id, (frame.time, frame.time), what)?,
            }
        }
    }
    Ok(spans)
}

/// Duration of frame `f`: until the next frame (the last frame lasts as long as the one
/// before it).
fn frame_duration(frames: &[RecordedFrame], f: usize) -> f64 {
    match (
        frames.get(f + 1),
        f.checked_sub(1).and_then(|p| frames.get(p)),
    ) {
        (Some(next), _) => next.time - frames[f].time,
        (None, Some(previous)) => frames[f].time - previous.time,
        (None, None) => 0.0,
    }
}

fn observed_time(frames: &[RecordedFrame], present: impl Fn(usize) -> bool) -> f64 {
    (0..frames.len())
        .filter(|&f| present(f))
        .map(|f| frame_duration(frames, f))
        .sum()
}

/// Cuts one character's frames into constraints (see the module docs). `frame(f)` gives
/// the best and second-best candidates of frame `f`, or `None` if absent.
fn cut_constraints(
    frames: &[RecordedFrame],
    frame: impl Fn(usize) -> Option<(Candidate, Candidate)>,
    threshold: f32,
    interest: &InterestConfig,
    out: &mut Vec<Constraint>,
    what: &dyn Display,
) -> Result<()> {
    let min_hold = f64::from(interest.min_hold);
    let max_hold = f64::from(interest.max_hold);
    let cooldown = f64::from(interest.cooldown);
    let mut run: Option<Constraint> = None;
    let mut cooling: Option<(u32, f64)> = None;
    let close = |run: Option<Constraint>, end: f64, out: &mut Vec<Constraint>| -> Result<()> {
        if let Some(mut k) = run {
            k.end = end;
            if k.end - k.begin >= min_hold - 1e-6 {
                try_reserve(out, 1, what)?;
                out.push(k);
            }
        }
        Ok(())
    };
    for (f, recorded) in frames.iter().enumerate() {
        let time = recorded.time;
        if cooling.is_some_and(|(_, until)| time >= until) {
            cooling = None;
        }
        let is_cooling = |c: &Candidate| cooling.is_some_and(|(id, _)| id == c.id);
        let effective = frame(f).and_then(|(first, second)| {
            [first, second]
                .into_iter()
                .find(|c| c.id != NO_ENTITY && !is_cooling(c))
                .filter(|c| c.score > 0.0 && c.score >= threshold)
        });
        match (run, effective) {
            (Some(k), Some(c)) if k.entity == c.id => {
                if time - k.begin >= max_hold {
                    // d_l reached: cut, cool down, and let the next-best continue now.
                    close(run, time, out)?;
                    cooling = Some((k.entity, time + cooldown));
                    run = frame(f)
                        .map(|(first, second)| if first.id == k.entity { second } else { first })
                        .filter(|c| c.id != NO_ENTITY && c.score > 0.0 && c.score >= threshold)
                        .map(|c| Constraint {
                            entity: c.id,
                            begin: time,
                            end: time,
                            s_max: c.score,
                        });
                }
            }
            (_, Some(c)) => {
                close(run, time, out)?;
                run = Some(Constraint {
                    entity: c.id,
                    begin: time,
                    end: time,
                    s_max: c.score,
                });
            }
            (_, None) => {
                close(run, time, out)?;
                run = None;
            }
        }
    }
    if let Some(last) = frames.last() {
        let end = last.time + frame_duration(frames, frames.len() - 1);
        close(run, end, out)?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn frames(count: usize, dt: f64) -> Vec<RecordedFrame> {
        (0..count)
            .map(|f| RecordedFrame {
                time: f as f64 * dt,
                start: 0,
                end: 0,
            })
            .collect()
    }

    fn c(id: u32, score: f32) -> Candidate {
        Candidate { id, score }
    }

    #[test]
    fn runs_become_constraints_if_long_enough() {
        let frames = frames(30, 0.1);
        // Entity 1 above the threshold for frames 2..5 (0.3 s: too short), entity 2 for
        // frames 10..20 (1 s).
        let pick = |f: usize| {
            Some(match f {
                2..=4 => (c(1, 0.8), Candidate::NONE),
                10..=19 => (c(2, 0.9), c(1, 0.1)),
                _ => (c(1, 0.1), Candidate::NONE),
            })
        };
        let mut out = Vec::new();
        cut_constraints(
            &frames,
            pick,
            0.5,
            &InterestConfig::default(),
            &mut out,
            &"test",
        )
        .unwrap();
        assert_eq!(out.len(), 1);
        assert_eq!(out[0].entity, 2);
        assert!((out[0].begin - 1.0).abs() < 1e-9 && (out[0].end - 2.0).abs() < 1e-9);
    }

    #[test]
    fn long_runs_are_cut_at_max_hold_and_the_next_best_continues() {
        let frames = frames(100, 0.1);
        let pick = |_| Some((c(1, 0.9), c(2, 0.7)));
        let mut out = Vec::new();
        cut_constraints(
            &frames,
            pick,
            0.5,
            &InterestConfig::default(),
            &mut out,
            &"test",
        )
        .unwrap();
        assert_eq!(out[0].entity, 1);
        assert!((out[0].end - out[0].begin - 4.0).abs() < 1e-6);
        assert_eq!(out[1].entity, 2);
        assert!((out[1].begin - out[0].end).abs() < 1e-9, "no gap");
        for k in &out {
            assert!(k.end - k.begin <= 4.0 + 1e-6);
            assert!(k.end - k.begin >= 1.0 / 3.0 - 1e-6);
        }
    }
}
