//! Pedestrian trajectories: reading `frame,id,x,y[,z]` CSV files (the format of the ETH and
//! UCY files in `shared/data/pedestrians/`), turning frame numbers into seconds, and
//! evaluating each person's track at any time with a smooth interpolation.
//!
//! Conversations: an optional `talking` column (0 or 1 per sample; empty is 0) says who
//! talks, held from each sample to the next; an optional `group` column puts people who
//! stand together and talk in groups (the same non-negative integer, one per person for
//! their whole track; empty or -1: no group; at most 8 people per group).
//!
//! Time: `t = frame × time_per_frame`. Unless given, the time per frame number is detected:
//! the most common step between a person's consecutive samples is taken to be one sample
//! period at the annotation rate (2.5 Hz, 0.4 s, for ETH and UCY: seq_eth steps 6 frame
//! numbers, zara01 10).
//!
//! Interpolation: a cubic Hermite spline through the samples with Catmull-Rom tangents for
//! uneven spacing (`m_i = (p_{i+1} − p_{i−1}) / (t_{i+1} − t_{i−1})`, one-sided at the
//! ends). It passes through every sample, has a continuous velocity, and gives the velocity
//! (hence the heading) as its derivative.

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use anyhow::{anyhow, bail, Context, Result};
use glam::DVec3;

/// How long apart two times may be and still count as the same (seconds).
pub const TIME_EPSILON: f64 = 1e-6;

/// One sample of a person's track.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sample {
    /// Frame number as in the file.
    pub frame: f64,
    /// Seconds (`frame × time_per_frame`).
    pub time: f64,
    /// `x, y, z` as in the file (metres; `z` is 0 when the file has no `z` column).
    pub position: DVec3,
    /// Line of the file it came from (1-based, the header is line 1).
    pub line: u64,
    /// Whether the person talks from this sample to the next (the `talking` column; false
    /// without one).
    pub talking: bool,
}

/// One person's samples, in time order.
#[derive(Debug, Clone, PartialEq)]
pub struct Track {
    /// The person's id in the file.
    pub person: u64,
    /// Samples in increasing time.
    pub samples: Vec<Sample>,
    /// The group the person stands in and talks with (the `group` column), if any.
    pub group: Option<u64>,
}

impl Track {
    /// Time of the first sample.
    pub fn first_time(&self) -> f64 {
        self.samples[0].time
    }

    /// Time of the last sample.
    pub fn last_time(&self) -> f64 {
        self.samples[self.samples.len() - 1].time
    }

    /// True if the track covers time `t` (give or take [`TIME_EPSILON`]).
    pub fn covers(&self, t: f64) -> bool {
        self.first_time() - TIME_EPSILON <= t && t <= self.last_time() + TIME_EPSILON
    }

    /// Position and velocity (per second) at time `t`, clamped to the track's span.
    pub fn evaluate(&self, t: f64) -> (DVec3, DVec3) {
        let samples = &self.samples;
        if samples.len() == 1 {
            return (samples[0].position, DVec3::ZERO);
        }
        let t = t.clamp(self.first_time(), self.last_time());
        // The segment [i, i + 1] holding t.
        let i = match samples.binary_search_by(|s| s.time.total_cmp(&t)) {
            Ok(i) => i.min(samples.len() - 2),
            Err(i) => i.saturating_sub(1).min(samples.len() - 2),
        };
        let (a, b) = (&samples[i], &samples[i + 1]);
        let h = b.time - a.time;
        let tangent = |k: usize| -> DVec3 {
            let previous = &samples[k.saturating_sub(1)];
            let next = &samples[(k + 1).min(samples.len() - 1)];
            (next.position - previous.position) / (next.time - previous.time)
        };
        let (m0, m1) = (tangent(i), tangent(i + 1));
        let u = (t - a.time) / h;
        let (u2, u3) = (u * u, u * u * u);
        let position = a.position * (2.0 * u3 - 3.0 * u2 + 1.0)
            + m0 * h * (u3 - 2.0 * u2 + u)
            + b.position * (-2.0 * u3 + 3.0 * u2)
            + m1 * h * (u3 - u2);
        let velocity = (a.position * (6.0 * u2 - 6.0 * u)
            + m0 * h * (3.0 * u2 - 4.0 * u + 1.0)
            + b.position * (-6.0 * u2 + 6.0 * u)
            + m1 * h * (3.0 * u2 - 2.0 * u))
            / h;
        (position, velocity)
    }

    /// Whether the person talks at time `t`: the `talking` of the last sample at or before
    /// `t` (the first sample's before the track starts).
    pub fn talking_at(&self, t: f64) -> bool {
        let after = self.samples.partition_point(|s| s.time <= t + TIME_EPSILON);
        self.samples[after.saturating_sub(1)].talking
    }

    /// The direction of the first noticeable move (ground `x, y`), for an initial heading.
    pub fn initial_direction(&self) -> Option<(f64, f64)> {
        let start = self.samples[0].position;
        self.samples.iter().find_map(|s| {
            let d = s.position - start;
            (d.x.hypot(d.y) > 0.05).then_some((d.x, d.y))
        })
    }
}

/// How to turn frame numbers into seconds.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TimeOptions {
    /// Seconds per frame number, if known.
    pub time_per_frame: Option<f64>,
    /// The annotation rate (samples per second) assumed when detecting the frame step.
    pub sample_rate: f64,
}

impl Default for TimeOptions {
    fn default() -> Self {
        TimeOptions {
            time_per_frame: None,
            sample_rate: 2.5,
        }
    }
}

/// A trajectory file, read and checked.
#[derive(Debug, Clone)]
pub struct Trajectories {
    /// The file.
    pub path: PathBuf,
    /// One track per person, in order of first appearance.
    pub tracks: Vec<Track>,
    /// Seconds per frame number.
    pub time_per_frame: f64,
    /// The detected step between samples (frame numbers), when the time was detected.
    pub detected_step: Option<f64>,
    /// Number of data rows.
    pub rows: usize,
    /// Line of the last data row.
    pub last_line: u64,
    /// The file has a `talking` column.
    pub has_talking: bool,
    /// The file has a `group` column.
    pub has_groups: bool,
}

/// Most people in one group (the most members of a conversation).
pub const MAX_GROUP: usize = crowdgaze::attention::conversation::MAX_MEMBERS;

fn parse_number(path: &Path, line: u64, column: &str, text: &str) -> Result<f64> {
    let text = text.trim();
    let value: f64 = text.parse().map_err(|_| {
        anyhow!(
            "{}:{line}: column '{column}': '{text}' is not a number",
            path.display()
        )
    })?;
    if !value.is_finite() {
        bail!(
            "{}:{line}: column '{column}' is {text}, not a finite number",
            path.display()
        );
    }
    Ok(value)
}

fn parse_talking(path: &Path, line: u64, text: &str) -> Result<bool> {
    match text.trim() {
        "" | "0" => Ok(false),
        "1" => Ok(true),
        other => bail!(
            "{}:{line}: column 'talking': '{other}' is not 0 or 1",
            path.display()
        ),
    }
}

fn parse_group(path: &Path, line: u64, text: &str) -> Result<Option<u64>> {
    match text.trim() {
        "" | "-1" => Ok(None),
        other => other.parse().map(Some).map_err(|_| {
            anyhow!(
                "{}:{line}: column 'group': '{other}' is not a group id (a non-negative \
                 integer, or empty or -1 for none)",
                path.display()
            )
        }),
    }
}

fn parse_id(path: &Path, line: u64, text: &str) -> Result<u64> {
    let text = text.trim();
    text.parse().map_err(|_| {
        anyhow!(
            "{}:{line}: column 'id': '{text}' is not a person id (a non-negative integer)",
            path.display()
        )
    })
}

impl Trajectories {
    /// Reads and checks a `frame,id,x,y[,z][,talking][,group]` file (columns found by name
    /// in the header, in any order; other columns ignored). Errors name the file and line: a
    /// missing column, text where a number belongs, NaN or infinity, a row with the wrong
    /// number of fields, a person's time going backwards or repeating, a `talking` not 0 or
    /// 1, a person's group changing, more than 8 people in a group, an empty file.
    pub fn read(path: &Path, options: &TimeOptions) -> Result<Trajectories> {
        let file = std::fs::File::open(path)
            .with_context(|| format!("{}: cannot open", path.display()))?;
        let mut reader = csv::ReaderBuilder::new()
            .has_headers(true)
            .trim(csv::Trim::All)
            .from_reader(std::io::BufReader::new(file));
        let csv_error = |e: csv::Error| {
            let line = e.position().map_or(0, |p| p.line());
            let message = match e.kind() {
                csv::ErrorKind::UnequalLengths {
                    expected_len, len, ..
                } => format!("{len} fields, the header has {expected_len}"),
                csv::ErrorKind::Utf8 { .. } => "not UTF-8 text".to_string(),
                _ => e.to_string(),
            };
            anyhow!("{}:{line}: {message}", path.display())
        };
        let headers = reader.headers().map_err(csv_error)?.clone();
        let column = |name: &str| {
            headers
                .iter()
                .position(|h| h.trim().eq_ignore_ascii_case(name))
        };
        let mut indices = [0usize; 4];
        for (slot, name) in indices.iter_mut().zip(["frame", "id", "x", "y"]) {
            *slot = column(name).ok_or_else(|| {
                anyhow!(
                    "{}:1: missing column '{name}' (the header is '{}'; expected frame,id,x,y[,z])",
                    path.display(),
                    headers.iter().collect::<Vec<_>>().join(",")
                )
            })?;
        }
        let z_index = column("z");
        let talking_index = column("talking");
        let group_index = column("group");
        let [frame_index, id_index, x_index, y_index] = indices;

        let mut rows = Vec::new();
        let mut record = csv::StringRecord::new();
        let mut last_line = 1;
        while reader.read_record(&mut record).map_err(csv_error)? {
            let line = record.position().map_or(0, |p| p.line());
            last_line = line;
            if record.iter().all(|field| field.is_empty()) {
                continue;
            }
            let field = |index: usize| record.get(index).unwrap_or("");
            let frame = parse_number(path, line, "frame", field(frame_index))?;
            let person = parse_id(path, line, field(id_index))?;
            let x = parse_number(path, line, "x", field(x_index))?;
            let y = parse_number(path, line, "y", field(y_index))?;
            let z = match z_index {
                Some(index) => parse_number(path, line, "z", field(index))?,
                None => 0.0,
            };
            let talking = match talking_index {
                Some(index) => parse_talking(path, line, field(index))?,
                None => false,
            };
            let group = match group_index {
                Some(index) => parse_group(path, line, field(index))?,
                None => None,
            };
            rows.push(Row {
                frame,
                person,
                position: DVec3::new(x, y, z),
                line,
                talking,
                group,
            });
        }
        if rows.is_empty() {
            bail!("{}:{}: no data rows", path.display(), last_line);
        }

        // Group by person, checking that each person's frames increase.
        let mut order: HashMap<u64, usize> = HashMap::new();
        let mut tracks: Vec<Track> = Vec::new();
        // Each group's people, by the line of their first row.
        let mut groups: HashMap<u64, Vec<u64>> = HashMap::new();
        for row in &rows {
            let &Row {
                frame,
                person,
                position,
                line,
                talking,
                group,
            } = row;
            let index = *order.entry(person).or_insert_with(|| {
                tracks.push(Track {
                    person,
                    samples: Vec::new(),
                    group,
                });
                tracks.len() - 1
            });
            let track = &mut tracks[index];
            if track.group != group {
                let name = |group: Option<u64>| {
                    group.map_or_else(|| "no group".to_string(), |g| format!("group {g}"))
                };
                bail!(
                    "{}:{line}: person {person} is in {} here but in {} on line {}: a \
                     person stays in one group",
                    path.display(),
                    name(group),
                    name(track.group),
                    track.samples[0].line
                );
            }
            if let (Some(group), true) = (group, track.samples.is_empty()) {
                let people = groups.entry(group).or_default();
                people.push(person);
                if people.len() > MAX_GROUP {
                    bail!(
                        "{}:{line}: group {group} has more than {MAX_GROUP} people (person \
                         {person} is the {}th; a conversation has at most {MAX_GROUP})",
                        path.display(),
                        people.len()
                    );
                }
            }
            let samples = &mut track.samples;
            if let Some(previous) = samples.last() {
                if frame == previous.frame {
                    bail!(
                        "{}:{line}: person {person} has a second sample at frame {frame} \
                         (the first is on line {})",
                        path.display(),
                        previous.line
                    );
                }
                if frame < previous.frame {
                    bail!(
                        "{}:{line}: time goes backwards for person {person}: frame {frame} \
                         comes after frame {} (line {})",
                        path.display(),
                        previous.frame,
                        previous.line
                    );
                }
            }
            samples.push(Sample {
                frame,
                time: 0.0,
                position,
                line,
                talking,
            });
        }

        // Seconds per frame number.
        let (time_per_frame, detected_step) = match options.time_per_frame {
            Some(value) => {
                if !(value.is_finite() && value > 0.0) {
                    bail!("--time-per-frame is {value}, must be a positive number of seconds");
                }
                (value, None)
            }
            None => {
                let step = most_common_step(&tracks).unwrap_or(1.0);
                if !(options.sample_rate.is_finite() && options.sample_rate > 0.0) {
                    bail!("--sample-rate is {}, must be positive", options.sample_rate);
                }
                (1.0 / (options.sample_rate * step), Some(step))
            }
        };
        for track in &mut tracks {
            for sample in &mut track.samples {
                sample.time = sample.frame * time_per_frame;
            }
        }
        Ok(Trajectories {
            path: path.to_path_buf(),
            tracks,
            time_per_frame,
            detected_step,
            rows: rows.len(),
            last_line,
            has_talking: talking_index.is_some(),
            has_groups: group_index.is_some(),
        })
    }

    /// The track of person `person`, or an error naming the file and its data lines.
    pub fn track(&self, person: u64) -> Result<&Track> {
        self.tracks
            .iter()
            .find(|t| t.person == person)
            .ok_or_else(|| {
                let (low, high) = self
                    .tracks
                    .iter()
                    .fold((u64::MAX, 0), |(l, h), t| (l.min(t.person), h.max(t.person)));
                anyhow!(
                    "{}:2-{}: no person with id {person} (the file's {} people have ids {low} to {high})",
                    self.path.display(),
                    self.last_line,
                    self.tracks.len()
                )
            })
    }

    /// Time of the earliest sample.
    pub fn first_time(&self) -> f64 {
        self.tracks
            .iter()
            .map(Track::first_time)
            .fold(f64::INFINITY, f64::min)
    }

    /// Time of the latest sample.
    pub fn last_time(&self) -> f64 {
        self.tracks
            .iter()
            .map(Track::last_time)
            .fold(f64::NEG_INFINITY, f64::max)
    }

    /// Output times at `fps`: the grid `first_time + k / fps` within `[start, end]` and the
    /// file's span.
    pub fn output_times(&self, fps: f64, start: Option<f64>, end: Option<f64>) -> Vec<f64> {
        let anchor = self.first_time();
        let low = start.unwrap_or(f64::NEG_INFINITY).max(anchor);
        let high = end.unwrap_or(f64::INFINITY).min(self.last_time());
        if high < low - TIME_EPSILON {
            return Vec::new();
        }
        let first = ((low - anchor) * fps - 1e-6).ceil().max(0.0) as u64;
        let last = ((high - anchor) * fps + 1e-6).floor() as u64;
        (first..=last).map(|k| anchor + k as f64 / fps).collect()
    }
}

/// One data row of a trajectory file.
struct Row {
    frame: f64,
    person: u64,
    position: DVec3,
    line: u64,
    talking: bool,
    group: Option<u64>,
}

/// The most common positive step between a person's consecutive frame numbers.
fn most_common_step(tracks: &[Track]) -> Option<f64> {
    let mut counts: HashMap<i64, (usize, f64)> = HashMap::new();
    for track in tracks {
        for pair in track.samples.windows(2) {
            let step = pair[1].frame - pair[0].frame;
            let key = (step * 1e6).round() as i64;
            counts.entry(key).or_insert((0, step)).0 += 1;
        }
    }
    counts
        .into_iter()
        .max_by(|a, b| a.1 .0.cmp(&b.1 .0).then(b.0.cmp(&a.0)))
        .map(|(_, (_, step))| step)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn track(points: &[(f64, f64, f64)]) -> Track {
        Track {
            person: 1,
            samples: points
                .iter()
                .enumerate()
                .map(|(i, &(time, x, y))| Sample {
                    frame: time,
                    time,
                    position: DVec3::new(x, y, 0.0),
                    line: i as u64 + 2,
                    talking: i % 2 == 1,
                })
                .collect(),
            group: None,
        }
    }

    #[test]
    fn interpolation_passes_through_samples_and_is_smooth() {
        let t = track(&[
            (0.0, 0.0, 0.0),
            (0.4, 0.5, 0.0),
            (0.8, 1.0, 0.2),
            (1.2, 1.5, 0.6),
        ]);
        for s in &t.samples {
            let (p, _) = t.evaluate(s.time);
            assert!((p - s.position).length() < 1e-12);
        }
        // Velocity is the derivative of position.
        for k in 1..119 {
            let time = k as f64 * 0.01;
            let (_, v) = t.evaluate(time);
            let (a, _) = t.evaluate(time - 1e-6);
            let (b, _) = t.evaluate(time + 1e-6);
            assert!(((b - a) / 2e-6 - v).length() < 1e-4, "{time}");
        }
        // A straight line at constant speed stays one.
        let line = track(&[(0.0, 0.0, 0.0), (1.0, 1.0, 0.0), (2.0, 2.0, 0.0)]);
        let (p, v) = line.evaluate(0.3);
        assert!((p.x - 0.3).abs() < 1e-12 && (v.x - 1.0).abs() < 1e-12);
    }

    #[test]
    fn talking_holds_from_each_sample_to_the_next() {
        // Samples at 0, 0.4, 0.8: talking at the odd ones.
        let t = track(&[(0.0, 0.0, 0.0), (0.4, 0.0, 0.0), (0.8, 0.0, 0.0)]);
        let at = |time: f64| t.talking_at(time);
        assert!(!at(-1.0) && !at(0.0) && !at(0.39));
        assert!(at(0.4) && at(0.79));
        assert!(!at(0.8) && !at(5.0));
    }

    #[test]
    fn two_samples_interpolate_linearly() {
        let t = track(&[(0.0, 0.0, 0.0), (0.4, 0.4, 0.0)]);
        let (p, v) = t.evaluate(0.2);
        assert!((p.x - 0.2).abs() < 1e-12 && (v.x - 1.0).abs() < 1e-12);
    }
}
