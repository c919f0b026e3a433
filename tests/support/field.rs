//! Real pedestrian trajectories (ETH seq_eth, UCY zara01) replayed at 30 frames per second
//! through a crowd, and the field statistics of walkers' gaze measured on the result: the
//! same definitions as the eye-tracking studies docs/street.md cites, computed from the
//! crowd's outputs (who each character's eyes are on) and the trajectories alone.

use std::collections::HashMap;

use crowdgaze::attention::AttentionModel;
use crowdgaze::crowd::{CharacterDesc, Crowd, CrowdConfig, ExplicitTarget, TargetPriority};
use crowdgaze::scene::EntityUpdate;
use crowdgaze::{Axis, World};
use glam::{Vec2, Vec3};

/// Frames per second of the replay.
pub const FPS: f32 = 30.0;

/// A recorded scene: the file and its seconds per frame number.
#[derive(Debug, Clone, Copy)]
pub struct SceneFile {
    /// Name for reports.
    pub name: &'static str,
    /// Path of the `frame,id,x,y` CSV.
    pub path: &'static str,
    /// Seconds per frame number (shared/data/README.md).
    pub seconds_per_frame: f64,
}

/// ETH seq_eth: one frame number is 1/15 s.
pub const ETH: SceneFile = SceneFile {
    name: "ETH seq_eth",
    path: concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../shared/data/pedestrians/eth_seq_eth.csv"
    ),
    seconds_per_frame: 1.0 / 15.0,
};

/// UCY zara01: one frame number is 1/25 s.
pub const ZARA: SceneFile = SceneFile {
    name: "UCY zara01",
    path: concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../shared/data/pedestrians/ucy_zara01.csv"
    ),
    seconds_per_frame: 1.0 / 25.0,
};

/// One person's samples: (seconds, ground position in metres).
#[derive(Debug, Clone)]
pub struct Track {
    pub person: u32,
    pub samples: Vec<(f64, Vec2)>,
}

impl Track {
    /// Position and velocity at `time`, if the track covers it: a cubic Hermite spline
    /// through the samples with Catmull-Rom tangents (one-sided at the ends), so that the
    /// velocity, hence the walking direction, is continuous.
    pub fn at(&self, time: f64) -> Option<(Vec2, Vec2)> {
        let samples = &self.samples;
        let (first, last) = (samples.first()?, samples.last()?);
        if time < first.0 || time > last.0 {
            return None;
        }
        let next = samples
            .partition_point(|s| s.0 < time)
            .clamp(1, samples.len() - 1);
        let (t0, p0) = samples[next - 1];
        let (t1, p1) = samples[next];
        let tangent = |i: usize| {
            let (before, after) = (
                samples[i.saturating_sub(1)],
                samples[(i + 1).min(samples.len() - 1)],
            );
            (after.1 - before.1) / (after.0 - before.0) as f32
        };
        let (m0, m1) = (tangent(next - 1), tangent(next));
        let h = (t1 - t0) as f32;
        let u = ((time - t0) / (t1 - t0)).clamp(0.0, 1.0) as f32;
        let (u2, u3) = (u * u, u * u * u);
        let position = p0 * (2.0 * u3 - 3.0 * u2 + 1.0)
            + m0 * h * (u3 - 2.0 * u2 + u)
            + p1 * (-2.0 * u3 + 3.0 * u2)
            + m1 * h * (u3 - u2);
        let velocity = (p0 * (6.0 * u2 - 6.0 * u)
            + m0 * h * (3.0 * u2 - 4.0 * u + 1.0)
            + p1 * (-6.0 * u2 + 6.0 * u)
            + m1 * h * (3.0 * u2 - 2.0 * u))
            / h;
        Some((position, velocity))
    }
}

/// The tracks of a scene file.
pub fn tracks(file: SceneFile) -> Vec<Track> {
    let mut by_person: HashMap<u32, Vec<(f64, Vec2)>> = HashMap::new();
    for (frame, person, x, y) in super::read_trajectories(file.path) {
        by_person
            .entry(person)
            .or_default()
            .push((f64::from(frame) * file.seconds_per_frame, Vec2::new(x, y)));
    }
    let mut tracks: Vec<Track> = by_person
        .into_iter()
        .filter(|(_, samples)| samples.len() >= 2)
        .map(|(person, mut samples)| {
            samples.sort_by(|a, b| a.0.total_cmp(&b.0));
            Track { person, samples }
        })
        .collect();
    tracks.sort_by_key(|t| t.person);
    tracks
}

/// A standing person staring at a point (a stimulus of gaze following).
#[derive(Debug, Clone, Copy)]
pub struct Starer {
    pub position: Vec2,
    /// Faces this way (radians about up, the crowd's axes).
    pub heading: f32,
    /// The point stared at (x, y on the ground, height).
    pub point: Vec3,
}

/// One frame of the replay: every person present, where they are, how they move, and who
/// their eyes are on.
#[derive(Debug, Clone)]
pub struct Frame {
    pub time: f64,
    /// (track index, position, velocity, eyes' target track index, following).
    pub people: Vec<Present>,
}

/// A person in a frame.
#[derive(Debug, Clone, Copy)]
pub struct Present {
    pub track: usize,
    pub position: Vec2,
    pub velocity: Vec2,
    /// The track whose person the eyes are on, if any.
    pub fixated: Option<usize>,
    /// True while this person follows someone's gaze.
    pub following: bool,
    /// Glances at others' gaze point so far.
    pub glances: u32,
}

/// The crowd's axes for the files: z up, x forward (the ground plane is the files' x, y).
pub fn world() -> World {
    World::new(Axis::PositiveZ, Axis::PositiveX, 1.0).unwrap()
}

/// Replays `tracks` from their first to their last sample at [`FPS`] through a crowd of
/// `config` whose walkers use `model`, with `starers` standing still (staring during
/// `stare`, seconds after the start). Returns every frame. `seconds` limits the replay.
pub fn replay(
    tracks: &[Track],
    config: CrowdConfig,
    model: AttentionModel,
    starers: &[Starer],
    stare: std::ops::Range<f64>,
    seconds: Option<f64>,
) -> Vec<Frame> {
    let start = tracks
        .iter()
        .map(|t| t.samples[0].0)
        .fold(f64::INFINITY, f64::min);
    let mut end = tracks
        .iter()
        .map(|t| t.samples.last().unwrap().0)
        .fold(f64::NEG_INFINITY, f64::max);
    if let Some(seconds) = seconds {
        end = end.min(start + seconds);
    }
    let mut crowd = Crowd::new(CrowdConfig {
        world: world(),
        max_characters: (tracks.len() + starers.len()) as u32,
        ..config
    })
    .unwrap();
    let to3 = |p: Vec2| Vec3::new(p.x, p.y, 0.0);
    let mut starer_ids = Vec::new();
    for starer in starers {
        let id = crowd
            .add_character(&CharacterDesc {
                position: to3(starer.position),
                heading: starer.heading,
                model,
                ..Default::default()
            })
            .unwrap();
        starer_ids.push(id);
    }
    let mut ids: Vec<Option<u32>> = vec![None; tracks.len()];
    let mut track_of: HashMap<u32, usize> = HashMap::new();
    let dt = 1.0 / FPS;
    let mut frames = Vec::new();
    let mut updates = Vec::new();
    let mut frame_index = 0u64;
    let mut staring = false;
    loop {
        let time = start + frame_index as f64 * f64::from(dt);
        if time > end {
            break;
        }
        if staring && time >= start + stare.end {
            staring = false;
            for &id in &starer_ids {
                crowd.clear_gaze_target(id).unwrap();
            }
        }
        if !staring && (start + stare.start..start + stare.end).contains(&time) {
            staring = true;
            for (starer, &id) in starers.iter().zip(&starer_ids) {
                crowd
                    .set_gaze_target(
                        id,
                        ExplicitTarget::Point(starer.point),
                        TargetPriority::Override,
                    )
                    .unwrap();
            }
        }
        updates.clear();
        for (index, track) in tracks.iter().enumerate() {
            match (track.at(time), ids[index]) {
                (Some((position, velocity)), id) => {
                    let id = id.unwrap_or_else(|| {
                        let id = crowd
                            .add_character(&CharacterDesc {
                                position: to3(position),
                                model,
                                ..Default::default()
                            })
                            .unwrap();
                        ids[index] = Some(id);
                        track_of.insert(id, index);
                        id
                    });
                    updates.push(EntityUpdate {
                        id,
                        position: to3(position),
                        heading: 0.0,
                        heading_from_motion: true,
                        velocity: Some(to3(velocity)),
                        talking: false,
                    });
                }
                (None, Some(id)) if time > track.samples[0].0 => {
                    crowd.remove_entity(id).unwrap();
                    track_of.remove(&id);
                    ids[index] = None;
                }
                _ => {}
            }
        }
        for (starer, &id) in starers.iter().zip(&starer_ids) {
            updates.push(EntityUpdate {
                id,
                position: to3(starer.position),
                heading: starer.heading,
                heading_from_motion: false,
                velocity: Some(Vec3::ZERO),
                talking: false,
            });
        }
        crowd.push_frame(time, &updates).unwrap();
        crowd.step(dt).unwrap();
        let mut people = Vec::new();
        for (index, track) in tracks.iter().enumerate() {
            let Some(id) = ids[index] else { continue };
            let gaze = crowd.gaze(id).unwrap();
            let (followed, glances) = crowd.following(id).unwrap();
            let (position, velocity) = track.at(time).unwrap();
            people.push(Present {
                track: index,
                position,
                velocity,
                fixated: track_of.get(&gaze.target).copied(),
                following: followed.is_some(),
                glances,
            });
        }
        frames.push(Frame { time, people });
        frame_index += 1;
    }
    frames
}

/// The field statistics of a replay (docs/street.md defines each).
#[derive(Debug, Clone, Default)]
pub struct FieldStats {
    /// Approaching walkers (in view ≥ 1 s, coming ≥ 1 m closer meanwhile).
    pub approaching: usize,
    /// Share of them fixated at least once.
    pub fixated_once: f64,
    /// Share of the fixated ones still in view 2.5 s after the first fixation that are
    /// fixated a second time.
    pub fixated_twice: f64,
    /// Median latency from coming into view to the first fixation (s).
    pub latency: f64,
    /// Median ground distance at the start of a fixation (m).
    pub distance: f64,
    /// The same for the first fixations on walkers that came into view [`FAR`] away or
    /// farther (from the edge of the view, not appearing within it).
    pub distance_far: f64,
    /// How many such far first fixations there were.
    pub far_count: usize,
    /// Median fixation duration (s).
    pub duration: f64,
    /// Share of walking time with the eyes on another walker.
    pub time_share: f64,
    /// The same for the walkers who met fewer, and more, people per minute than the median.
    pub time_share_by_met: (f64, f64),
    /// Share of time a walker in view is fixated, closer than 3 m and at 5–15 m.
    pub civil: (f64, f64),
}

/// Walkers first seen this far away (metres) came into view from its edge.
pub const FAR: f32 = 16.0;

fn median(values: &mut [f64]) -> f64 {
    if values.is_empty() {
        return f64::NAN;
    }
    values.sort_by(f64::total_cmp);
    values[values.len() / 2]
}

/// Whether `other` is in the view of a walker at `position` moving with `velocity`: within
/// `distance` and `half_angle` of the walking direction.
pub fn in_view(
    position: Vec2,
    velocity: Vec2,
    other: Vec2,
    distance: f32,
    half_angle: f32,
) -> bool {
    let offset = other - position;
    let length = offset.length();
    if length > distance || velocity.length() < 0.2 {
        return false;
    }
    length < 1e-3 || velocity.normalize().dot(offset) >= half_angle.cos() * length
}

/// The field statistics of `frames` (`view_distance`, `half_angle`: the view the studies'
/// "comes into view" means; the street preset's 17 m and 60°).
pub fn field_stats(frames: &[Frame], view_distance: f32, half_angle: f32) -> FieldStats {
    field_stats_of(frames, view_distance, half_angle, &|_| true)
}

/// Walkers (track indices) who meet fewer people per minute than the median walker: those
/// on a quiet street, like the studies' walkers.
pub fn quiet_walkers(
    frames: &[Frame],
    view_distance: f32,
    half_angle: f32,
) -> std::collections::HashSet<usize> {
    let dt = f64::from(1.0 / FPS);
    let mut walking: HashMap<usize, (f64, std::collections::HashSet<usize>)> = HashMap::new();
    for frame in frames {
        for me in &frame.people {
            if me.velocity.length() <= 0.5 {
                continue;
            }
            let entry = walking.entry(me.track).or_default();
            entry.0 += dt;
            for other in &frame.people {
                if other.track != me.track
                    && in_view(
                        me.position,
                        me.velocity,
                        other.position,
                        view_distance,
                        half_angle,
                    )
                {
                    entry.1.insert(other.track);
                }
            }
        }
    }
    let mut rates: Vec<(f64, usize)> = walking
        .iter()
        .filter(|(_, (seconds, _))| *seconds >= 5.0)
        .map(|(&track, (seconds, met))| (met.len() as f64 / (seconds / 60.0), track))
        .collect();
    rates.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
    rates[..rates.len() / 2].iter().map(|r| r.1).collect()
}

/// [`field_stats`] for the walkers `observer` accepts (track indices).
pub fn field_stats_of(
    frames: &[Frame],
    view_distance: f32,
    half_angle: f32,
    observer: &dyn Fn(usize) -> bool,
) -> FieldStats {
    let dt = f64::from(1.0 / FPS);
    #[derive(Default)]
    struct Pair {
        first_seen: Option<(f64, f32)>,
        last_distance: f32,
        seen_time: f64,
        first_fixation: Option<f64>,
        first_fixation_end: Option<f64>,
        last_seen: f64,
        episodes: u32,
        fixating: bool,
    }
    let mut pairs: HashMap<(usize, usize), Pair> = HashMap::new();
    let mut durations = Vec::new();
    let mut distances = Vec::new();
    let mut far = Vec::new();
    let mut episode_start: HashMap<(usize, usize), f64> = HashMap::new();
    // Per walker: walking frames, frames on a walker, people met.
    let mut walking: HashMap<usize, (u32, u32, std::collections::HashSet<usize>)> = HashMap::new();
    let (mut near_frames, mut near_fixated, mut mid_frames, mut mid_fixated) = (0, 0, 0, 0);
    for frame in frames {
        for me in frame.people.iter().filter(|me| observer(me.track)) {
            let walks = me.velocity.length() > 0.5;
            if walks {
                let entry = walking.entry(me.track).or_default();
                entry.0 += 1;
                entry.1 += u32::from(me.fixated.is_some());
            }
            for other in &frame.people {
                if other.track == me.track {
                    continue;
                }
                let key = (me.track, other.track);
                let distance = me.position.distance(other.position);
                let seen = in_view(
                    me.position,
                    me.velocity,
                    other.position,
                    view_distance,
                    half_angle,
                );
                let fixates = me.fixated == Some(other.track);
                let pair = pairs.entry(key).or_default();
                if seen {
                    if walks {
                        walking.entry(me.track).or_default().2.insert(other.track);
                    }
                    if pair.first_seen.is_none() {
                        pair.first_seen = Some((frame.time, distance));
                    }
                    pair.seen_time += dt;
                    pair.last_distance = distance;
                    pair.last_seen = frame.time;
                    if distance < 3.0 {
                        near_frames += 1;
                        near_fixated += u32::from(fixates);
                    } else if (5.0..=15.0).contains(&distance) {
                        mid_frames += 1;
                        mid_fixated += u32::from(fixates);
                    }
                }
                if fixates && !pair.fixating {
                    pair.episodes += 1;
                    distances.push(f64::from(distance));
                    if pair.first_fixation.is_none() {
                        pair.first_fixation = Some(frame.time);
                        if let Some((_, seen_at)) = pair.first_seen {
                            if seen_at >= FAR {
                                far.push(f64::from(distance));
                            }
                        }
                    }
                    episode_start.insert(key, frame.time);
                } else if !fixates && pair.fixating {
                    if pair.first_fixation_end.is_none() {
                        pair.first_fixation_end = Some(frame.time);
                    }
                    if let Some(start) = episode_start.remove(&key) {
                        durations.push(frame.time - start);
                    }
                }
                pair.fixating = fixates;
            }
        }
    }
    let mut approaching = 0;
    let mut once = 0;
    let mut twice = 0;
    let mut stayed = 0;
    let mut latencies = Vec::new();
    for pair in pairs.values() {
        let Some((seen_at, first_distance)) = pair.first_seen else {
            continue;
        };
        if pair.seen_time < 1.0 || first_distance - pair.last_distance < 1.0 {
            continue;
        }
        approaching += 1;
        if let Some(first) = pair.first_fixation {
            once += 1;
            // Time for a second look: in view 2.5 s after the first (the longest gap and
            // a latency).
            if pair
                .first_fixation_end
                .is_some_and(|end| pair.last_seen - end >= 2.5)
            {
                stayed += 1;
                twice += usize::from(pair.episodes >= 2);
            }
            if first >= seen_at {
                latencies.push(first - seen_at);
            }
        }
    }
    let (mut walked, mut on_walkers) = (0u64, 0u64);
    let mut by_met: Vec<(f64, f64, f64)> = Vec::new();
    for (frames_walking, frames_on, met) in walking.values() {
        walked += u64::from(*frames_walking);
        on_walkers += u64::from(*frames_on);
        if *frames_walking as f64 * dt >= 5.0 {
            let minutes = *frames_walking as f64 * dt / 60.0;
            by_met.push((
                met.len() as f64 / minutes,
                f64::from(*frames_on),
                f64::from(*frames_walking),
            ));
        }
    }
    by_met.sort_by(|a, b| a.0.total_cmp(&b.0));
    let half = by_met.len() / 2;
    let share = |part: &[(f64, f64, f64)]| {
        part.iter().map(|p| p.1).sum::<f64>() / part.iter().map(|p| p.2).sum::<f64>()
    };
    FieldStats {
        approaching,
        fixated_once: once as f64 / approaching as f64,
        fixated_twice: twice as f64 / stayed as f64,
        latency: median(&mut latencies),
        distance: median(&mut distances),
        far_count: far.len(),
        distance_far: median(&mut far),
        duration: median(&mut durations),
        time_share: on_walkers as f64 / walked as f64,
        time_share_by_met: (share(&by_met[..half]), share(&by_met[half..])),
        civil: (
            f64::from(near_fixated) / f64::from(near_frames.max(1)),
            f64::from(mid_fixated) / f64::from(mid_frames.max(1)),
        ),
    }
}
