//! Running a crowd over a scene, frame by frame, for the commands: the street scenario of the
//! paper, or the people of a trajectory file, online (frame by frame) or offline (the
//! paper's pipeline: record everything, plan with the exact percentile, then replay).
//!
//! An [`Observer`] sees every frame after the step (and may act before it: set a base pose).
//!
//! Conversations: the street's standing groups talk in turns
//! ([`Scenario::with_conversations`]); in a trajectory file, the people of each group (its
//! `group` column) present together form a conversation, and its `talking` column says who
//! talks.

use std::collections::{BTreeMap, BTreeSet, HashMap};
use std::time::{Duration, Instant};

use anyhow::{bail, Context, Result};
use crowdgaze::attention::following::FollowConfig;
use crowdgaze::attention::{AttentionModel, CharacterParams};
use crowdgaze::crowd::{ExplicitTarget, TargetPriority};
use crowdgaze::ik::GazeChain;
use crowdgaze::scenario::Scenario;
use crowdgaze::scene::EntityUpdate;
use crowdgaze::{CharacterDesc, Crowd, CrowdConfig, World};
use glam::{DVec3, Vec3};

use crate::output::progress;
use crate::traj::{Track, Trajectories, TIME_EPSILON};

/// The attention model of the characters.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum Model {
    /// Grillon & Thalmann 2009: scores of proximity, speed, orientation and periphery, an
    /// attention threshold per character, interest points held 1/3 s to 4 s.
    Crowd,
    /// Kokkinara, Oyekoya & Steed 2011: separate eye and head targets from saliency.
    Saliency,
    /// The stock behaviour the papers compare against.
    Baseline,
    /// Walkers as measured in the street with eye trackers: each walker coming into view
    /// fixated once with a set probability, after ~0.65 s, for ~0.5 s; close strangers
    /// looked at less; the path a few metres ahead the rest of the time. The crowd sees
    /// 17 m far with it (`CrowdConfig::street`).
    Street,
}

impl Model {
    /// The model's name on the command line.
    pub fn name(self) -> &'static str {
        match self {
            Model::Crowd => "crowd",
            Model::Saliency => "saliency",
            Model::Baseline => "baseline",
            Model::Street => "street",
        }
    }
}

/// Gives the characters `ids` of `crowd` the attention model `model`. Called after each
/// batch of characters is added.
pub fn configure_model(crowd: &mut Crowd, ids: &[u32], model: Model) -> Result<()> {
    let model = match model {
        Model::Crowd => AttentionModel::Crowd,
        Model::Saliency => AttentionModel::Saliency,
        Model::Baseline => AttentionModel::Baseline,
        Model::Street => AttentionModel::Street,
    };
    for &id in ids {
        let params = crowd.character_params(id)?;
        crowd.set_character_params(id, &CharacterParams { model, ..params })?;
    }
    Ok(())
}

/// How strongly characters follow others' gaze (gaze following).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, clap::ValueEnum)]
pub enum FollowStrength {
    /// Milgram, Bickman & Berkowitz 1969: 42 % of passers-by look up with one looker,
    /// 86 % with fifteen.
    #[default]
    Milgram,
    /// Gallup et al. 2012, an Oxford shopping street: about a quarter at most.
    Gallup,
}

impl FollowStrength {
    /// The name on the command line.
    pub fn name(self) -> &'static str {
        match self {
            FollowStrength::Milgram => "milgram",
            FollowStrength::Gallup => "gallup",
        }
    }

    /// Gaze following on at this strength, noticing lookers at most `max_distance` away
    /// (the crowd's view).
    pub fn config(self, max_distance: f32) -> FollowConfig {
        let base = match self {
            FollowStrength::Milgram => FollowConfig::MILGRAM,
            FollowStrength::Gallup => FollowConfig::GALLUP,
        };
        FollowConfig {
            enabled: true,
            distance: base.distance.min(max_distance),
            ..base
        }
    }
}

/// A person of a trajectory file made to stare at a point (`annotate --stare`): an
/// overriding explicit target while the window lasts.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Stare {
    /// The person's id in the file.
    pub person: u64,
    /// The point, in the file's axes (x, y on the ground, z up), metres.
    pub point: DVec3,
    /// From and to when (s, the file's clock); `None`: while the person is present.
    pub window: Option<(f64, f64)>,
}

impl Stare {
    /// Parses `ID:X,Y,Z[:T0-T1]`.
    pub fn parse(text: &str) -> std::result::Result<Stare, String> {
        let usage = "expected ID:X,Y,Z or ID:X,Y,Z:T0-T1 (a person's id, a point in metres \
                     in the file's axes, z up; optionally from T0 to T1 seconds)";
        let fail = |why: String| Err(format!("--stare '{text}': {why}; {usage}"));
        let mut parts = text.split(':');
        let (Some(id), Some(point)) = (parts.next(), parts.next()) else {
            return fail("no point".into());
        };
        let window = parts.next();
        if parts.next().is_some() {
            return fail("too many ':'".into());
        }
        let Ok(person) = id.trim().parse::<u64>() else {
            return fail(format!(
                "'{id}' is not a person id (a non-negative integer)"
            ));
        };
        let mut coordinates = Vec::new();
        for value in point.split(',') {
            match value.trim().parse::<f64>() {
                Ok(v) if v.is_finite() => coordinates.push(v),
                _ => return fail(format!("'{value}' is not a coordinate")),
            }
        }
        let [x, y, z] = coordinates[..] else {
            return fail(format!(
                "the point has {} coordinates, not 3",
                coordinates.len()
            ));
        };
        let window = match window {
            None => None,
            Some(span) => {
                let times = span
                    .split_once('-')
                    .map(|(a, b)| (a.trim().parse::<f64>(), b.trim().parse::<f64>()));
                match times {
                    Some((Ok(from), Ok(to))) if from.is_finite() && to.is_finite() => {
                        if from > to {
                            return fail(format!("the window '{span}' ends before it starts"));
                        }
                        Some((from, to))
                    }
                    _ => return fail(format!("'{span}' is not a window T0-T1")),
                }
            }
        };
        Ok(Stare {
            person,
            point: DVec3::new(x, y, z),
            window,
        })
    }

    /// Whether the stare holds at time `t`.
    pub fn holds_at(&self, t: f64) -> bool {
        self.window
            .is_none_or(|(from, to)| from - TIME_EPSILON <= t && t <= to + TIME_EPSILON)
    }
}

/// A character present in a frame.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Present {
    /// The person's label: the id in the trajectory file, or the person's index in the
    /// street scenario.
    pub label: u64,
    /// The character's id in the crowd.
    pub id: u32,
}

/// One frame, as the observer sees it.
#[derive(Debug)]
pub struct Frame<'a> {
    /// Frame index from 0.
    pub index: usize,
    /// Time (s).
    pub time: f64,
    /// Time since the previous frame (s).
    pub dt: f32,
    /// The characters present in this frame.
    pub people: &'a [Present],
    /// The label of every character ever added, by crowd id.
    pub labels: &'a HashMap<u32, u64>,
}

/// What a command does with each frame.
pub trait Observer {
    /// The gaze chain of person `label` (`None`: the human chain).
    fn chain(&self, _label: u64) -> Option<GazeChain> {
        None
    }

    /// Called after the frame's states are pushed, before the step.
    fn before_step(&mut self, _crowd: &mut Crowd, _frame: &Frame) -> Result<()> {
        Ok(())
    }

    /// Called after the step.
    fn after_step(&mut self, crowd: &Crowd, frame: &Frame) -> Result<()>;
}

/// What a run measured.
#[derive(Debug, Clone, Default)]
pub struct RunStats {
    /// Frames stepped.
    pub frames: usize,
    /// Character-frames stepped (characters present, summed over frames).
    pub character_frames: usize,
    /// Time spent in `push_frame` and `step` (and `plan`, offline).
    pub crowd_time: Duration,
    /// Groups that stood together and talked (conversations formed; a group of a
    /// trajectory file counts once).
    pub groups: usize,
    /// People in those groups.
    pub grouped: usize,
}

/// How to run a trajectory file.
#[derive(Debug, Clone)]
pub struct TrackRun {
    /// Axes of the crowd; the file's `x, y` lie along `forward` and `up × forward`, `z`
    /// along `up`. Metres.
    pub world: World,
    /// Output rate (frames per second).
    pub fps: f64,
    /// First time to run (s, the file's clock), default the file's start.
    pub start: Option<f64>,
    /// Last time to run (s), default the file's end.
    pub end: Option<f64>,
    /// Plan offline with the exact percentile.
    pub offline: bool,
    /// The attention model.
    pub model: Model,
    /// Seed of every random choice.
    pub seed: u64,
    /// Hide the progress bar.
    pub quiet: bool,
    /// Gaze following (`None`: off).
    pub follow: Option<FollowStrength>,
    /// People made to stare at points.
    pub stares: Vec<Stare>,
}

/// Gives the people present their stares that hold at `frame.time` (an overriding point
/// target) and takes them back from those whose stare has ended; `staring` holds the crowd
/// ids staring now.
fn apply_stares(
    crowd: &mut Crowd,
    run: &TrackRun,
    frame: &Frame,
    staring: &mut BTreeSet<u32>,
) -> Result<()> {
    if run.stares.is_empty() {
        return Ok(());
    }
    for person in frame.people {
        let stare = run
            .stares
            .iter()
            .find(|s| s.person == person.label && s.holds_at(frame.time));
        match stare {
            Some(stare) => {
                crowd.set_gaze_target(
                    person.id,
                    ExplicitTarget::Point(world_point(&run.world, stare.point)),
                    TargetPriority::Override,
                )?;
                staring.insert(person.id);
            }
            None => {
                if staring.remove(&person.id) {
                    crowd.clear_gaze_target(person.id)?;
                }
            }
        }
    }
    Ok(())
}

fn world_point(world: &World, p: DVec3) -> Vec3 {
    world.forward * p.x as f32 + world.side * p.y as f32 + world.up * p.z as f32
}

/// The crowd's state for a track at time `t`.
fn track_update(world: &World, track: &Track, id: u32, t: f64) -> EntityUpdate {
    let (position, velocity) = track.evaluate(t);
    EntityUpdate {
        id,
        position: world_point(world, position),
        heading: 0.0,
        heading_from_motion: true,
        velocity: Some(world_point(world, velocity)),
        talking: track.talking_at(t),
    }
}

/// Makes the people of each group present (`active`, with their crowd ids) a conversation
/// of the crowd: a group with two or more present is one, formed again when someone joins
/// (a person who leaves the crowd leaves its conversation; one left alone ends it). Adds the
/// groups formed to `formed`.
fn sync_conversations(
    crowd: &mut Crowd,
    active: &[(&Track, u32)],
    formed: &mut BTreeMap<u64, BTreeSet<u64>>,
) -> Result<()> {
    let mut groups: BTreeMap<u64, Vec<(u32, u64)>> = BTreeMap::new();
    for &(track, id) in active {
        if let Some(group) = track.group {
            groups.entry(group).or_default().push((id, track.person));
        }
    }
    for (group, people) in groups {
        let mut members: Vec<u32> = people.iter().map(|&(id, _)| id).collect();
        members.sort_unstable();
        if let Some(conversation) = crowd.conversation_of(members[0])? {
            let mut now = crowd.conversation_members(conversation)?.to_vec();
            now.sort_unstable();
            if now == members {
                continue;
            }
        }
        for &id in &members {
            if let Some(conversation) = crowd.conversation_of(id)? {
                crowd.remove_conversation(conversation)?;
            }
        }
        if members.len() >= 2 {
            crowd
                .set_conversation(&members)
                .with_context(|| format!("forming group {group}"))?;
            formed
                .entry(group)
                .or_default()
                .extend(people.iter().map(|&(_, person)| person));
        }
    }
    Ok(())
}

fn initial_heading(track: &Track) -> f32 {
    track
        .initial_direction()
        .map_or(0.0, |(x, y)| y.atan2(x) as f32)
}

/// Small positive `dt` steps that keep the offline replay clock (which adds `f32` steps)
/// at or past each frame time, so that each step replays exactly its frame.
struct ReplayClock {
    clock: f64,
}

impl ReplayClock {
    fn step_to(&mut self, time: f64) -> f32 {
        let mut dt = ((time - self.clock).max(0.0)) as f32;
        while self.clock + f64::from(dt) < time {
            dt = f32::from_bits(dt.to_bits() + 1);
        }
        self.clock += f64::from(dt);
        dt
    }
}

/// Runs the people of `trajectories` through a crowd at `run.fps`, adding each person when
/// their track starts and removing them when it ends (online), or recording everything and
/// planning first (offline).
pub fn run_tracks(
    trajectories: &Trajectories,
    run: &TrackRun,
    observer: &mut dyn Observer,
) -> Result<RunStats> {
    if !(run.fps.is_finite() && run.fps > 0.0) {
        bail!("--fps is {}, must be positive", run.fps);
    }
    let times = trajectories.output_times(run.fps, run.start, run.end);
    if times.is_empty() {
        bail!(
            "{}: no sample between --start and --end (the file spans {:.2} s to {:.2} s)",
            trajectories.path.display(),
            trajectories.first_time(),
            trajectories.last_time()
        );
    }
    // Tracks present in at least one output frame, by first time.
    let mut tracks: Vec<&Track> = trajectories
        .tracks
        .iter()
        .filter(|track| times.iter().any(|&t| track.covers(t)))
        .collect();
    tracks.sort_by(|a, b| a.first_time().total_cmp(&b.first_time()));
    let frame_of = |track: &Track| times.iter().position(|&t| track.covers(t)).unwrap_or(0);
    let person_frames: usize = tracks
        .iter()
        .map(|track| times.iter().filter(|&&t| track.covers(t)).count())
        .sum();
    let group_count = tracks
        .iter()
        .filter_map(|track| track.group)
        .collect::<BTreeSet<u64>>()
        .len();
    for stare in &run.stares {
        if !trajectories.tracks.iter().any(|t| t.person == stare.person) {
            bail!(
                "--stare {}: {} has no person {}",
                stare.person,
                trajectories.path.display(),
                stare.person
            );
        }
    }
    let mut base = if run.model == Model::Street {
        CrowdConfig::street()
    } else {
        CrowdConfig::default()
    };
    base.following = match run.follow {
        Some(strength) => strength.config(base.scoring.max_distance),
        None => FollowConfig {
            enabled: false,
            ..base.following
        },
    };
    let config = CrowdConfig {
        seed: run.seed,
        max_characters: tracks.len().max(1) as u32,
        max_objects: 0,
        max_conversations: group_count.max(1) as u32,
        world: run.world,
        max_recorded_states: if run.offline {
            (person_frames + times.len() + 1) as u32
        } else {
            0
        },
        ..base
    };
    let mut crowd = Crowd::new(config).context("creating the crowd")?;
    let world = run.world;
    let mut staring = BTreeSet::new();
    let mut labels: HashMap<u32, u64> = HashMap::new();
    let mut stats = RunStats::default();
    let dt_of = |k: usize| -> f32 {
        if k == 0 {
            (1.0 / run.fps) as f32
        } else {
            (times[k] - times[k - 1]) as f32
        }
    };

    let add = |crowd: &mut Crowd,
               labels: &mut HashMap<u32, u64>,
               track: &Track,
               t: f64,
               chain: Option<GazeChain>|
     -> Result<u32> {
        let update = track_update(&world, track, 0, t);
        let id = crowd
            .add_character(&CharacterDesc {
                position: update.position,
                heading: initial_heading(track),
                chain,
                ..CharacterDesc::default()
            })
            .with_context(|| format!("adding person {}", track.person))?;
        labels.insert(id, track.person);
        Ok(id)
    };

    let mut present: Vec<Present> = Vec::new();
    let mut updates: Vec<EntityUpdate> = Vec::new();
    // Groups formed, with their people.
    let mut formed: BTreeMap<u64, BTreeSet<u64>> = BTreeMap::new();
    let count_groups = |stats: &mut RunStats, formed: &BTreeMap<u64, BTreeSet<u64>>| {
        stats.groups = formed.len();
        stats.grouped = formed.values().map(BTreeSet::len).sum();
    };
    if !run.offline {
        let bar = progress(times.len() as u64, "annotating", run.quiet);
        // (track, crowd id) of the people in the scene.
        let mut active: Vec<(&Track, u32)> = Vec::new();
        let mut next = 0;
        for (k, &t) in times.iter().enumerate() {
            let mut added = Vec::new();
            while next < tracks.len() && tracks[next].first_time() <= t + TIME_EPSILON {
                let track = tracks[next];
                next += 1;
                if track.covers(t) {
                    let id = add(
                        &mut crowd,
                        &mut labels,
                        track,
                        t,
                        observer.chain(track.person),
                    )?;
                    active.push((track, id));
                    added.push(id);
                }
            }
            if !added.is_empty() {
                configure_model(&mut crowd, &added, run.model)?;
            }
            if trajectories.has_groups {
                sync_conversations(&mut crowd, &active, &mut formed)?;
            }
            updates.clear();
            updates.extend(
                active
                    .iter()
                    .map(|&(track, id)| track_update(&world, track, id, t)),
            );
            present.clear();
            present.extend(active.iter().map(|&(track, id)| Present {
                label: track.person,
                id,
            }));
            let frame = Frame {
                index: k,
                time: t,
                dt: dt_of(k),
                people: &present,
                labels: &labels,
            };
            let started = Instant::now();
            crowd.push_frame(t, &updates).context("pushing a frame")?;
            stats.crowd_time += started.elapsed();
            apply_stares(&mut crowd, run, &frame, &mut staring)?;
            observer.before_step(&mut crowd, &frame)?;
            let started = Instant::now();
            crowd.step(frame.dt).context("stepping the crowd")?;
            stats.crowd_time += started.elapsed();
            observer.after_step(&crowd, &frame)?;
            stats.frames += 1;
            stats.character_frames += present.len();
            // People whose track ends before the next frame leave.
            if let Some(&next_time) = times.get(k + 1) {
                let mut kept = Vec::with_capacity(active.len());
                for (track, id) in active.drain(..) {
                    if track.covers(next_time) {
                        kept.push((track, id));
                    } else {
                        crowd.remove_entity(id).context("removing a person")?;
                    }
                }
                active = kept;
            }
            bar.inc(1);
        }
        bar.finish_and_clear();
        count_groups(&mut stats, &formed);
        return Ok(stats);
    }

    // Offline: everyone is added first (each counts only within its own span), every frame
    // recorded, then planned and replayed.
    let mut all: Vec<(&Track, u32)> = Vec::with_capacity(tracks.len());
    for &track in &tracks {
        let t = times[frame_of(track)];
        let id = add(
            &mut crowd,
            &mut labels,
            track,
            t,
            observer.chain(track.person),
        )?;
        all.push((track, id));
    }
    let ids: Vec<u32> = all.iter().map(|&(_, id)| id).collect();
    configure_model(&mut crowd, &ids, run.model)?;
    // Each group is one conversation for the whole run.
    sync_conversations(&mut crowd, &all, &mut formed)?;
    count_groups(&mut stats, &formed);
    let bar = progress(2 * times.len() as u64, "planning", run.quiet);
    let started = Instant::now();
    for &t in &times {
        updates.clear();
        updates.extend(
            all.iter()
                .filter(|(track, _)| track.covers(t))
                .map(|&(track, id)| track_update(&world, track, id, t)),
        );
        crowd.push_frame(t, &updates).context("recording a frame")?;
        bar.inc(1);
    }
    crowd.plan().context("planning")?;
    stats.crowd_time += started.elapsed();
    let mut clock = ReplayClock { clock: times[0] };
    for (k, &t) in times.iter().enumerate() {
        let dt = if k == 0 { dt_of(0) } else { clock.step_to(t) };
        present.clear();
        present.extend(
            all.iter()
                .filter(|(track, _)| track.covers(t))
                .map(|&(track, id)| Present {
                    label: track.person,
                    id,
                }),
        );
        let frame = Frame {
            index: k,
            time: t,
            dt,
            people: &present,
            labels: &labels,
        };
        apply_stares(&mut crowd, run, &frame, &mut staring)?;
        step_observed(&mut crowd, observer, &frame, dt, &mut stats)?;
        bar.inc(1);
    }
    bar.finish_and_clear();
    Ok(stats)
}

/// Steps the crowd once, between the observer's look before and after, timing the step
/// and counting the frame and its characters.
fn step_observed(
    crowd: &mut Crowd,
    observer: &mut dyn Observer,
    frame: &Frame<'_>,
    dt: f32,
    stats: &mut RunStats,
) -> Result<()> {
    observer.before_step(crowd, frame)?;
    let started = Instant::now();
    crowd.step(dt).context("stepping the crowd")?;
    stats.crowd_time += started.elapsed();
    observer.after_step(crowd, frame)?;
    stats.frames += 1;
    stats.character_frames += frame.people.len();
    Ok(())
}

/// How to run the paper's street scene.
#[derive(Debug, Clone, Copy)]
pub struct StreetRun {
    /// Simulated seconds.
    pub seconds: f64,
    /// Frames per second.
    pub fps: f64,
    /// Characters.
    pub characters: usize,
    /// Scene objects.
    pub objects: usize,
    /// Seed of the scene and of every random choice of the crowd.
    pub seed: u64,
    /// Share of the characters standing in groups of two and three, talking in turns
    /// ([`Scenario::with_conversations`]).
    pub group_share: f32,
    /// Plan offline with the exact percentile.
    pub offline: bool,
    /// Hide the progress bar.
    pub quiet: bool,
}

impl StreetRun {
    /// Number of frames.
    pub fn frame_count(&self) -> usize {
        (self.seconds * self.fps).round().max(1.0) as usize
    }

    /// The crowd's configuration for the street.
    pub fn config(&self) -> CrowdConfig {
        let frames = self.frame_count();
        CrowdConfig {
            seed: self.seed,
            max_characters: self.characters.max(1) as u32,
            max_objects: self.objects as u32,
            max_recorded_states: if self.offline {
                (self.characters * frames + frames + 1) as u32
            } else {
                0
            },
            ..CrowdConfig::default()
        }
    }
}

/// Runs the street scene (`Scenario::street`) through a crowd, online or offline.
pub fn run_street(run: &StreetRun, observer: &mut dyn Observer) -> Result<RunStats> {
    if !(run.seconds.is_finite() && run.seconds > 0.0) {
        bail!("--seconds is {}, must be positive", run.seconds);
    }
    if run.characters == 0 {
        bail!("--characters must be at least 1");
    }
    if !(0.0..=1.0).contains(&run.group_share) {
        bail!(
            "--group-share is {}, must be between 0 and 1",
            run.group_share
        );
    }
    let mut scenario = Scenario::street(run.characters, run.objects, run.seed)
        .with_conversations(run.group_share, run.seed);
    let mut crowd = Crowd::new(run.config()).context("creating the crowd")?;
    scenario
        .populate(&mut crowd)
        .context("populating the street")?;
    let ids = scenario.character_ids().to_vec();
    configure_model(&mut crowd, &ids, Model::Crowd)?;
    let present: Vec<Present> = ids
        .iter()
        .enumerate()
        .map(|(i, &id)| Present {
            label: i as u64,
            id,
        })
        .collect();
    let labels: HashMap<u32, u64> = present.iter().map(|p| (p.id, p.label)).collect();
    let frames = run.frame_count();
    let dt = (1.0 / run.fps) as f32;
    let mut stats = RunStats {
        groups: scenario.groups.len(),
        grouped: scenario.groups.iter().map(|g| g.members.len()).sum(),
        ..RunStats::default()
    };
    let bar = progress(
        frames as u64 * if run.offline { 2 } else { 1 },
        if run.offline { "planning" } else { "street" },
        run.quiet,
    );
    let time_of = |k: usize| k as f64 / run.fps;
    if run.offline {
        let started = Instant::now();
        for k in 0..frames {
            if k > 0 {
                scenario.advance(dt);
            }
            scenario
                .push(&mut crowd, time_of(k))
                .context("recording a frame")?;
            bar.inc(1);
        }
        crowd.plan().context("planning")?;
        stats.crowd_time += started.elapsed();
    }
    let mut clock = ReplayClock { clock: 0.0 };
    for k in 0..frames {
        let t = time_of(k);
        let step_dt = if run.offline && k > 0 {
            clock.step_to(t)
        } else {
            dt
        };
        let frame = Frame {
            index: k,
            time: t,
            dt: step_dt,
            people: &present,
            labels: &labels,
        };
        if !run.offline {
            if k > 0 {
                scenario.advance(dt);
            }
            let started = Instant::now();
            scenario.push(&mut crowd, t).context("pushing a frame")?;
            stats.crowd_time += started.elapsed();
        }
        step_observed(&mut crowd, observer, &frame, step_dt, &mut stats)?;
        bar.inc(1);
    }
    bar.finish_and_clear();
    Ok(stats)
}

/// Gaze statistics gathered frame by frame.
#[derive(Debug, Clone, Default)]
pub struct GazeStats {
    /// Character-frames seen.
    pub samples: usize,
    /// Character-frames attending to an interest point.
    pub attending: usize,
    /// Sum of `S_max`.
    pub s_max_sum: f64,
    /// Character-seconds seen.
    pub seconds: f64,
    /// Times a character started looking at a new interest point.
    pub shifts: usize,
    /// Character-frames in a conversation.
    pub member_frames: usize,
    /// Of those, frames talking.
    pub speaker_frames: usize,
    /// Of the talking frames, those looking at another member.
    pub speaker_on_listener: usize,
    /// Frames of members listening (not talking while another member talks).
    pub listener_frames: usize,
    /// Of those, frames looking at a member who talks.
    pub listener_on_speaker: usize,
    /// Each character's last target.
    last_target: HashMap<u32, u32>,
}

impl GazeStats {
    /// Adds a character's gaze of this frame.
    pub fn add(&mut self, id: u32, gaze: &crowdgaze::GazeInfo, dt: f32) {
        self.samples += 1;
        self.seconds += f64::from(dt);
        self.s_max_sum += f64::from(gaze.s_max);
        if gaze.attending {
            self.attending += 1;
            let previous = self.last_target.insert(id, gaze.target);
            if previous != Some(gaze.target) {
                self.shifts += 1;
            }
        } else {
            self.last_target.remove(&id);
        }
    }

    /// Adds a character's conversation of this frame, if it is in one: whether it talks,
    /// and whether it looks at the speaker (a listener) or at a listener (the speaker).
    pub fn add_conversation(
        &mut self,
        crowd: &Crowd,
        id: u32,
        gaze: &crowdgaze::GazeInfo,
    ) -> Result<()> {
        let Some(group) = crowd.conversation_of(id)? else {
            return Ok(());
        };
        let scene = crowd.scene();
        let talks = |id: u32| scene.index_of(id).is_some_and(|i| scene.talking()[i]);
        let members = crowd.conversation_members(group)?;
        let at_member = gaze.target != id && members.contains(&gaze.target);
        self.member_frames += 1;
        if talks(id) {
            self.speaker_frames += 1;
            self.speaker_on_listener += usize::from(at_member);
        } else if members.iter().any(|&m| m != id && talks(m)) {
            self.listener_frames += 1;
            self.listener_on_speaker += usize::from(at_member && talks(gaze.target));
        }
        Ok(())
    }

    /// Share of listening frames spent looking at the speaker.
    pub fn listener_on_speaker_fraction(&self) -> f64 {
        self.listener_on_speaker as f64 / self.listener_frames.max(1) as f64
    }

    /// Share of talking frames spent looking at a listener.
    pub fn speaker_on_listener_fraction(&self) -> f64 {
        self.speaker_on_listener as f64 / self.speaker_frames.max(1) as f64
    }

    /// Share of character-frames attending.
    pub fn attentive_fraction(&self) -> f64 {
        self.attending as f64 / self.samples.max(1) as f64
    }

    /// Mean `S_max`.
    pub fn mean_s_max(&self) -> f64 {
        self.s_max_sum / self.samples.max(1) as f64
    }

    /// Gaze shifts (new interest points) per character per minute.
    pub fn shifts_per_minute(&self) -> f64 {
        if self.seconds > 0.0 {
            self.shifts as f64 / (self.seconds / 60.0)
        } else {
            0.0
        }
    }
}
