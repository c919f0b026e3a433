//! The look-up scene of `crowdgaze demo --scene look-up`: the paper's street, where at a set
//! time a group of people stops and stares at a point high on a building's facade (Milgram,
//! Bickman & Berkowitz 1969), and the street's reaction — who saw the group, who looked up
//! too (gaze following), and when — as a summary and a picture (a top-down view and a
//! timeline).
//!
//! The walkers use the street model (`AttentionModel::Street`, field-calibrated on walkers:
//! the crowd is [`CrowdConfig::street`], 17 m of view); the people standing, sitting or
//! talking keep the crowd model, whose interest points suit people who do not walk.
//! Following works the same for both.

use std::time::Instant;

use anyhow::{bail, Context, Result};
use crowdgaze::attention::following::FollowConfig;
use crowdgaze::scenario::{Activity, Scenario};
use crowdgaze::{Crowd, CrowdConfig};
use glam::{Vec2, Vec3};
use plotters::coord::Shift;
use plotters::prelude::*;

use crate::output::progress;
use crate::plot::{draw_legend_at, drawing, Figure};
use crate::sim::{configure_model, FollowStrength, Model, StreetRun};

/// Height of the point the group looks at, metres above the ground.
pub const POINT_HEIGHT: f32 = 10.0;

/// How to run the look-up scene.
#[derive(Debug, Clone, Copy)]
pub struct LookUpRun {
    /// The street (its `offline` is ignored: the scene runs frame by frame).
    pub street: StreetRun,
    /// How many people stop and look up.
    pub lookers: usize,
    /// When they stop (s).
    pub start: f64,
    /// Gaze following's strength (`None`: following off).
    pub follow: Option<FollowStrength>,
}

/// A person marked on the picture.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Mark {
    /// The person's index in the street.
    pub label: u64,
    /// Ground position when it happened (metres).
    pub position: Vec2,
    /// When (s).
    pub time: f64,
    /// Whether the person walks by (else stands, sits or talks in a group).
    pub walking: bool,
}

/// What the scene did.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct LookUp {
    /// Simulated seconds.
    pub seconds: f64,
    /// When the group stopped (s).
    pub start: f64,
    /// The point looked at: ground position (metres) and height.
    pub point: Vec2,
    /// The point's height (m).
    pub height: f32,
    /// Following's strength, if on.
    pub follow: Option<FollowStrength>,
    /// The lookers, where they stopped.
    pub lookers: Vec<Mark>,
    /// People who had a looker in view (within the follow distance, in the follow view)
    /// at some moment: where and when they first did.
    pub witnesses: Vec<Mark>,
    /// People who looked up: where and when their first glance started.
    pub followers: Vec<Mark>,
    /// Glances started in all.
    pub glances: u32,
    /// Each frame: (time, people glancing at the point).
    pub timeline: Vec<(f64, usize)>,
    /// Seconds spent in `push_frame` and `step`.
    pub crowd_seconds: f64,
    /// Character-frames stepped.
    pub character_frames: usize,
}

impl LookUp {
    /// Followers who never had a looker in view themselves (they followed followers).
    pub fn followers_unseen(&self) -> usize {
        self.followers
            .iter()
            .filter(|f| !self.witnesses.iter().any(|w| w.label == f.label))
            .count()
    }

    /// The most people glancing at once, and the first time it happened.
    pub fn peak(&self) -> (usize, f64) {
        self.timeline.iter().fold(
            (0, 0.0),
            |best, &(t, n)| if n > best.0 { (n, t) } else { best },
        )
    }
}

/// Whether a character at `position` facing `forward` (ground, unit) has a looker of
/// `lookers` in view for gaze following: within `config.distance`, within
/// `config.view_half_angle` of `forward` (the test the crowd makes).
fn sees(position: Vec2, forward: Vec2, lookers: &[Vec2], config: &FollowConfig) -> bool {
    let cos_half = config.view_half_angle.cos();
    lookers.iter().any(|&looker| {
        let offset = looker - position;
        let distance = offset.length();
        distance > 1e-4 && distance <= config.distance && forward.dot(offset) >= cos_half * distance
    })
}

/// Runs the scene.
pub fn run_look_up(run: &LookUpRun) -> Result<LookUp> {
    let street = &run.street;
    if !(street.seconds.is_finite() && street.seconds > 0.0) {
        bail!("--seconds is {}, must be positive", street.seconds);
    }
    if !(0.0..=1.0).contains(&street.group_share) {
        bail!(
            "--group-share is {}, must be between 0 and 1",
            street.group_share
        );
    }
    if !(run.start.is_finite() && run.start >= 0.0 && run.start < street.seconds) {
        bail!(
            "--look-at is {}, must be within the run (0 to --seconds {})",
            run.start,
            street.seconds
        );
    }
    let mut scenario = Scenario::street(street.characters, street.objects, street.seed)
        .with_conversations(street.group_share, street.seed);
    let grouped: Vec<bool> = (0..scenario.people.len())
        .map(|i| scenario.group_of(i).is_some())
        .collect();
    let walkers = scenario
        .people
        .iter()
        .filter(|p| p.activity == Activity::Walking)
        .count();
    if run.lookers == 0 || run.lookers > walkers {
        bail!(
            "--lookers is {}, must be 1 to {walkers} (the street's walkers)",
            run.lookers
        );
    }
    let mut config = CrowdConfig::street();
    config.seed = street.seed;
    config.max_characters = street.characters.max(1) as u32;
    config.max_objects = street.objects as u32;
    config.following = match run.follow {
        Some(strength) => strength.config(config.scoring.max_distance),
        None => FollowConfig {
            enabled: false,
            ..config.following
        },
    };
    // What counts as seeing the group: following's own view, on or off.
    let view = run
        .follow
        .unwrap_or_default()
        .config(config.scoring.max_distance);
    let mut crowd = Crowd::new(config).context("creating the crowd")?;
    scenario
        .populate(&mut crowd)
        .context("populating the street")?;
    let ids = scenario.character_ids().to_vec();
    let walking: Vec<bool> = scenario
        .people
        .iter()
        .map(|p| p.activity == Activity::Walking)
        .collect();
    let pick = |walks: bool| -> Vec<u32> {
        ids.iter()
            .zip(&walking)
            .filter(|&(_, &w)| w == walks)
            .map(|(&id, _)| id)
            .collect()
    };
    let (walker_ids, other_ids) = (pick(true), pick(false));
    configure_model(&mut crowd, &walker_ids, Model::Street)?;
    configure_model(&mut crowd, &other_ids, Model::Crowd)?;
    let world = crowd.config().world;
    // The point: on the facade at the street's edge (side 0), halfway along, 10 m up; the
    // group stops on the pavement below it.
    let point = Vec2::new(0.5 * scenario.length, 0.0);
    let spot = Vec2::new(point.x, 2.5);
    let point_world: Vec3 = Scenario::world_point(&world, point, POINT_HEIGHT);

    let fps = street.fps;
    let frames = street.frame_count();
    let dt = (1.0 / fps) as f32;
    let start_frame = ((run.start * fps).round() as usize).min(frames - 1);
    let mut result = LookUp {
        seconds: frames as f64 / fps,
        start: start_frame as f64 / fps,
        point,
        height: POINT_HEIGHT,
        follow: run.follow,
        ..LookUp::default()
    };
    let count = ids.len();
    let mut is_looker = vec![false; count];
    let mut looker_positions: Vec<Vec2> = Vec::new();
    let mut seen = vec![false; count];
    let mut followed = vec![false; count];
    let mut glances = vec![0u32; count];
    let bar = progress(frames as u64, "look-up", street.quiet);
    let mut crowd_time = std::time::Duration::ZERO;
    for k in 0..frames {
        let t = k as f64 / fps;
        if k > 0 {
            scenario.advance(dt);
        }
        if k == start_frame {
            // The walkers nearest the spot (not in a talking group), nearest first, ties by
            // index: deterministic.
            let mut candidates: Vec<(f32, usize)> = (0..count)
                .filter(|&i| walking[i] && !grouped[i])
                .map(|i| (scenario.people[i].position.distance(spot), i))
                .collect();
            candidates.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
            for &(_, i) in candidates.iter().take(run.lookers) {
                scenario
                    .stop_and_look(&mut crowd, i, point_world)
                    .context("stopping a looker")?;
                is_looker[i] = true;
                looker_positions.push(scenario.people[i].position);
                result.lookers.push(Mark {
                    label: i as u64,
                    position: scenario.people[i].position,
                    time: t,
                    walking: true,
                });
            }
        }
        let started = Instant::now();
        scenario.push(&mut crowd, t).context("pushing a frame")?;
        crowd.step(dt).context("stepping the crowd")?;
        crowd_time += started.elapsed();
        result.character_frames += count;
        let scene = crowd.scene();
        let mut glancing = 0;
        for i in 0..count {
            if is_looker[i] {
                continue;
            }
            let id = ids[i];
            let Some(index) = scene.index_of(id) else {
                continue;
            };
            let position = scenario.people[i].position;
            let mark = Mark {
                label: i as u64,
                position,
                time: t,
                walking: walking[i],
            };
            let forward = world.ground(world.heading_direction(scene.headings()[index]));
            if !seen[i] && k >= start_frame && sees(position, forward, &looker_positions, &view) {
                seen[i] = true;
                result.witnesses.push(mark);
            }
            let (following, count) = crowd.following(id)?;
            glances[i] = count;
            if following.is_some() {
                glancing += 1;
                if !followed[i] {
                    followed[i] = true;
                    result.followers.push(mark);
                }
            }
        }
        result.timeline.push((t, glancing));
        bar.inc(1);
    }
    bar.finish_and_clear();
    result.glances = glances.iter().sum();
    result.crowd_seconds = crowd_time.as_secs_f64();
    Ok(result)
}

/// Prints the summary of a look-up run.
pub fn print_summary(result: &LookUp, run: &LookUpRun) {
    let street = &run.street;
    println!(
        "crowdgaze demo --scene look-up: the street (120 m x 14 m), {} characters, {} objects, {:.1} s at 30 fps, seed {}",
        street.characters, street.objects, result.seconds, street.seed
    );
    println!(
        "  models:      walkers the street model, people standing, sitting or talking the crowd model; following {}",
        result
            .follow
            .map_or_else(|| "off".to_string(), |s| format!("on ({})", s.name()))
    );
    let labels = |marks: &[Mark]| {
        marks
            .iter()
            .map(|m| m.label.to_string())
            .collect::<Vec<_>>()
            .join(", ")
    };
    println!(
        "  lookers:     {} {} at t = {:.1} s and stare at a point {:.0} m up the facade at ({:.1}, {:.1}): people {}",
        result.lookers.len(),
        if result.lookers.len() == 1 {
            "walker stops"
        } else {
            "walkers stop"
        },
        result.start,
        result.height,
        result.point.x,
        result.point.y,
        labels(&result.lookers)
    );
    let seen_walking = result.witnesses.iter().filter(|w| w.walking).count();
    println!(
        "  saw them:    {} people had a looker in view within 10 m, ±90° ({} walking by)",
        result.witnesses.len(),
        seen_walking
    );
    let unseen = result.followers_unseen();
    let seen = result.followers.len() - unseen;
    println!(
        "  looked up:   {} people: {seen} of the {} who saw them ({:.0}%), {unseen} who saw only others looking up; {} glances in all",
        result.followers.len(),
        result.witnesses.len(),
        100.0 * seen as f64 / result.witnesses.len().max(1) as f64,
        result.glances
    );
    if !result.followers.is_empty() {
        // Followers are recorded in time order.
        let delays: Vec<f64> = result
            .followers
            .iter()
            .map(|f| f.time - result.start)
            .collect();
        let quantile = |q: f64| delays[((delays.len() - 1) as f64 * q).round() as usize];
        let within = |s: f64| delays.iter().filter(|&&d| d <= s + 1e-9).count();
        let (peak, at) = result.peak();
        println!(
            "  when:        first glance t0 + {:.1} s, median + {:.1} s, last + {:.1} s; {} within 1 s, {} within 10 s",
            delays[0],
            quantile(0.5),
            delays[delays.len() - 1],
            within(1.0),
            within(10.0)
        );
        println!("  at once:     at most {peak} looking up together (t = {at:.1} s)");
    }
    println!(
        "  cost:        {:.2} µs per character-frame (push_frame + step), {:.2} s in all",
        result.crowd_seconds * 1e6 / result.character_frames.max(1) as f64,
        result.crowd_seconds
    );
}

/// Half the length of street shown, metres either side of the point.
const HALF_VIEW: f32 = 22.0;

impl Figure for LookUp {
    fn size(&self) -> (u32, u32) {
        (960, 620)
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<()> {
        root.fill(&WHITE).map_err(drawing)?;
        let (top, bottom) = root.split_vertically(380);
        let (x0, x1) = (self.point.x - HALF_VIEW, self.point.x + HALF_VIEW);
        // The street is 14 m across; the far facade above it leaves room for the legend.
        let (y0, width, y1) = (-1.5f32, 14.0f32, 21.5f32);
        let inside = |p: Vec2| (x0..=x1).contains(&p.x) && (y0..=width).contains(&p.y);
        let mut chart = ChartBuilder::on(&top)
            .caption(
                format!(
                    "{} people stop at t = {:.0} s and look {:.0} m up the facade: {} saw them, {} looked up too",
                    self.lookers.len(),
                    self.start,
                    self.height,
                    self.witnesses.len(),
                    self.followers.len()
                ),
                ("sans-serif", 20),
            )
            .margin(10)
            .x_label_area_size(32)
            .y_label_area_size(40)
            .build_cartesian_2d(x0..x1, y0..y1)
            .map_err(drawing)?;
        chart
            .configure_mesh()
            .x_desc("along the street (m)")
            .y_desc("across (m)")
            .light_line_style(WHITE.mix(0.0))
            .draw()
            .map_err(drawing)?;
        let facade = RGBColor(90, 90, 90);
        chart
            .draw_series([
                Rectangle::new([(x0, y0), (x1, 0.0)], facade.mix(0.35).filled()),
                Rectangle::new([(x0, width), (x1, y1)], facade.mix(0.35).filled()),
            ])
            .map_err(drawing)?
            .label("facade")
            .legend(move |(x, y)| {
                Rectangle::new([(x - 6, y - 4), (x + 6, y + 4)], facade.mix(0.35).filled())
            });
        let red = RGBColor(200, 30, 30);
        let orange = RGBColor(235, 130, 20);
        let grey = RGBColor(140, 140, 140);
        let target = (self.point.x, self.point.y);
        let followers: Vec<&Mark> = self
            .followers
            .iter()
            .filter(|f| inside(f.position))
            .collect();
        // Lines from the followers and the lookers to the point (its place on the ground).
        chart
            .draw_series(followers.iter().map(|f| {
                PathElement::new(
                    vec![(f.position.x, f.position.y), target],
                    orange.mix(0.6).stroke_width(1),
                )
            }))
            .map_err(drawing)?;
        chart
            .draw_series(self.lookers.iter().map(|l| {
                PathElement::new(
                    vec![(l.position.x, l.position.y), target],
                    red.stroke_width(2),
                )
            }))
            .map_err(drawing)?;
        chart
            .draw_series(
                self.witnesses
                    .iter()
                    .filter(|w| inside(w.position))
                    .filter(|w| !self.followers.iter().any(|f| f.label == w.label))
                    .map(|w| Circle::new((w.position.x, w.position.y), 4, grey.stroke_width(2))),
            )
            .map_err(drawing)?
            .label("saw the group, did not look up (where first seen)")
            .legend(move |(x, y)| Circle::new((x, y), 4, grey.stroke_width(2)));
        chart
            .draw_series(
                followers
                    .iter()
                    .map(|f| Circle::new((f.position.x, f.position.y), 5, orange.filled())),
            )
            .map_err(drawing)?
            .label("looked up too (where, and seconds after the group stopped)")
            .legend(move |(x, y)| Circle::new((x, y), 5, orange.filled()));
        chart
            .draw_series(followers.iter().map(|f| {
                Text::new(
                    format!("+{:.1}s", f.time - self.start),
                    (f.position.x + 0.35, f.position.y + 0.9),
                    ("sans-serif", 13).into_font().color(&BLACK),
                )
            }))
            .map_err(drawing)?;
        chart
            .draw_series(
                self.lookers
                    .iter()
                    .map(|l| Circle::new((l.position.x, l.position.y), 6, red.filled())),
            )
            .map_err(drawing)?
            .label("stopped and looking up")
            .legend(move |(x, y)| Circle::new((x, y), 6, red.filled()));
        chart
            .draw_series(std::iter::once(TriangleMarker::new(
                target,
                9,
                BLACK.filled(),
            )))
            .map_err(drawing)?
            .label(format!("the point, {:.0} m up", self.height))
            .legend(|(x, y)| TriangleMarker::new((x, y), 6, BLACK.filled()));
        draw_legend_at(&mut chart, SeriesLabelPosition::UpperRight)?;

        // The timeline: how many look up, against time.
        let most = self
            .timeline
            .iter()
            .map(|&(_, n)| n)
            .max()
            .unwrap_or(0)
            .max(self.followers.len())
            .max(1);
        let mut timeline = ChartBuilder::on(&bottom)
            .caption("people looking up because others do", ("sans-serif", 18))
            .margin(10)
            .x_label_area_size(32)
            .y_label_area_size(40)
            .build_cartesian_2d(0.0..self.seconds, 0.0..(most as f64 + 1.0))
            .map_err(drawing)?;
        timeline
            .configure_mesh()
            .x_desc("time (s)")
            .y_desc("people")
            .light_line_style(WHITE.mix(0.0))
            .draw()
            .map_err(drawing)?;
        timeline
            .draw_series(std::iter::once(PathElement::new(
                vec![(self.start, 0.0), (self.start, most as f64 + 1.0)],
                red.stroke_width(2),
            )))
            .map_err(drawing)?
            .label("the group stops")
            .legend(move |(x, y)| PathElement::new(vec![(x - 8, y), (x + 8, y)], red));
        timeline
            .draw_series(LineSeries::new(
                self.timeline.iter().map(|&(t, n)| (t, n as f64)),
                orange.stroke_width(2),
            ))
            .map_err(drawing)?
            .label("glancing at the point now")
            .legend(move |(x, y)| PathElement::new(vec![(x - 8, y), (x + 8, y)], orange));
        let mut cumulative: Vec<(f64, f64)> = vec![(0.0, 0.0)];
        for (n, f) in self.followers.iter().enumerate() {
            cumulative.push((f.time, n as f64));
            cumulative.push((f.time, (n + 1) as f64));
        }
        cumulative.push((self.seconds, self.followers.len() as f64));
        let blue = RGBColor(30, 80, 200);
        timeline
            .draw_series(LineSeries::new(cumulative, blue.stroke_width(2)))
            .map_err(drawing)?
            .label("have looked up so far")
            .legend(move |(x, y)| PathElement::new(vec![(x - 8, y), (x + 8, y)], blue));
        draw_legend_at(&mut timeline, SeriesLabelPosition::LowerRight)
    }
}
