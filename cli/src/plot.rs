//! Pictures, each written as PNG and SVG with plotters:
//!
//! - a top-down view of the scene at a moment: people, their headings, a line from each
//!   one that looks at someone or something to what it looks at, and who stands in a group
//!   and who talks;
//! - the paper's Figure 1 for one character: `S_max(t)` coloured by the entity that gives it,
//!   the threshold `A`, and the `t_b`, `t_e` of each planned constraint;
//! - the paper's Figure 3: eye, head and torso yaw against time during gaze shifts (one
//!   character, an explicit target that jumps);
//! - the eyes of one character: where its eyes look in its head, how closed its lids are
//!   (blinks), and when its gaze shifts start, against time.

use std::path::{Path, PathBuf};
use std::sync::Once;

use anyhow::{anyhow, Context, Result};
use crowdgaze::crowd::{ExplicitTarget, TargetPriority};
use crowdgaze::ik::GazeChain;
use crowdgaze::scene::ids::{EntityKind, NO_ENTITY};
use crowdgaze::{CharacterDesc, Crowd, CrowdConfig, World};
use glam::{Quat, Vec2, Vec3};
use plotters::coord::Shift;
use plotters::prelude::*;

use crate::output::write_file;
use crate::sim::{Frame, Observer};

/// A plotters error as an `anyhow` error.
pub(crate) fn drawing<E: std::fmt::Debug>(error: E) -> anyhow::Error {
    anyhow!("drawing failed: {error:?}")
}

/// Registers the embedded font (DejaVu Sans) as plotters' "sans-serif", once.
/// Draws a chart's series legend, the same way on every figure.
fn draw_legend<'a, DB: DrawingBackend + 'a, CT: plotters::coord::CoordTranslate>(
    chart: &mut ChartContext<'a, DB, CT>,
) -> Result<()> {
    draw_legend_at(chart, SeriesLabelPosition::UpperRight)
}

/// Draws a chart's series legend at `position`, in the style of every figure.
pub(crate) fn draw_legend_at<'a, DB: DrawingBackend + 'a, CT: plotters::coord::CoordTranslate>(
    chart: &mut ChartContext<'a, DB, CT>,
    position: SeriesLabelPosition,
) -> Result<()> {
    chart
        .configure_series_labels()
        .position(position)
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .label_font(("sans-serif", 14))
        .draw()
        .map_err(drawing)
}

fn register_font() {
    static FONT: Once = Once::new();
    FONT.call_once(|| {
        let _ = plotters::style::register_font(
            "sans-serif",
            FontStyle::Normal,
            dejavu::sans::regular(),
        );
    });
}

/// A picture that can be drawn on any plotters backend.
pub trait Figure {
    /// Size in pixels.
    fn size(&self) -> (u32, u32);
    /// Draws the picture.
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<()>;
}

/// Writes `figure` as `<stem>.png` and `<stem>.svg`; returns both paths.
pub fn save<F: Figure>(figure: &F, stem: &Path) -> Result<[PathBuf; 2]> {
    register_font();
    let (width, height) = figure.size();
    let mut pixels = vec![0u8; width as usize * height as usize * 3];
    {
        let root = BitMapBackend::with_buffer(&mut pixels, (width, height)).into_drawing_area();
        figure.draw(&root)?;
        root.present().map_err(drawing)?;
    }
    let mut png_bytes = Vec::new();
    {
        let mut encoder = png::Encoder::new(&mut png_bytes, width, height);
        encoder.set_color(png::ColorType::Rgb);
        encoder.set_depth(png::BitDepth::Eight);
        encoder.set_compression(png::Compression::High);
        let mut writer = encoder.write_header().context("encoding PNG")?;
        writer.write_image_data(&pixels).context("encoding PNG")?;
    }
    let with_extension = |extension: &str| {
        let mut path = stem.as_os_str().to_owned();
        path.push(extension);
        PathBuf::from(path)
    };
    let png_path = with_extension(".png");
    write_file(&png_path, &png_bytes)?;
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (width, height)).into_drawing_area();
        figure.draw(&root)?;
        root.present().map_err(drawing)?;
    }
    let svg_path = with_extension(".svg");
    write_file(&svg_path, svg.as_bytes())?;
    Ok([png_path, svg_path])
}

/// A colour per entity id, stable across pictures.
fn entity_colour(id: u32) -> RGBColor {
    let colour = Palette99::pick((id as usize).wrapping_mul(7) % 99).to_rgba();
    RGBColor(colour.0, colour.1, colour.2)
}

// ---------------------------------------------------------------------------------------
// Top-down view.

/// One person in a top-down view (ground coordinates, metres).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PersonMark {
    /// The person's label.
    pub label: u64,
    /// Ground position.
    pub position: Vec2,
    /// Heading (radians, counter-clockwise from the first ground axis).
    pub heading: f32,
    /// Where it looks, if it attends to something (or, in a group, looks at a member).
    pub target: Option<Vec2>,
    /// It attends to an interest point of its attention model.
    pub attending: bool,
    /// It stands in a group (a conversation).
    pub in_group: bool,
    /// It talks.
    pub talking: bool,
}

/// The scene at one moment, seen from above.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Snapshot {
    /// Time (s).
    pub time: f64,
    /// The people present.
    pub people: Vec<PersonMark>,
    /// Scene objects.
    pub objects: Vec<Vec2>,
    /// A title.
    pub title: String,
}

impl Snapshot {
    /// Takes the crowd's state after a step.
    pub fn take(crowd: &Crowd, frame: &Frame, title: &str) -> Snapshot {
        let scene = crowd.scene();
        let world = *scene.world();
        let mut people = Vec::with_capacity(frame.people.len());
        for person in frame.people {
            let (Some(index), Ok(gaze)) = (scene.index_of(person.id), crowd.gaze(person.id)) else {
                continue;
            };
            let in_group = matches!(crowd.conversation_of(person.id), Ok(Some(_)));
            // A line to what it looks at: its interest point, or in a group the member
            // its glance is on.
            let looks = gaze.attending || (in_group && gaze.target != NO_ENTITY);
            people.push(PersonMark {
                label: person.label,
                position: world.ground(scene.positions()[index]),
                heading: scene.headings()[index],
                target: looks.then(|| world.ground(gaze.target_position)),
                attending: gaze.attending,
                in_group,
                talking: scene.talking()[index],
            });
        }
        let objects = scene
            .kinds()
            .iter()
            .zip(scene.positions())
            .filter(|(kind, _)| **kind == EntityKind::Object)
            .map(|(_, p)| world.ground(*p))
            .collect();
        Snapshot {
            time: frame.time,
            people,
            objects,
            title: title.to_string(),
        }
    }

    fn bounds(&self) -> (Vec2, Vec2) {
        let points = self
            .people
            .iter()
            .map(|p| p.position)
            .chain(self.people.iter().filter_map(|p| p.target))
            .chain(self.objects.iter().copied());
        let (mut low, mut high) = (Vec2::splat(f32::INFINITY), Vec2::splat(f32::NEG_INFINITY));
        for p in points {
            low = low.min(p);
            high = high.max(p);
        }
        if !low.is_finite() {
            return (Vec2::splat(-5.0), Vec2::splat(5.0));
        }
        let pad = Vec2::splat(1.5);
        let (low, high) = (low - pad, high + pad);
        // At least 10 m across each way.
        let centre = 0.5 * (low + high);
        let half = (0.5 * (high - low)).max(Vec2::splat(5.0));
        (centre - half, centre + half)
    }
}

impl Figure for Snapshot {
    fn size(&self) -> (u32, u32) {
        let (low, high) = self.bounds();
        let extent = high - low;
        let width = 1400.0;
        let height = (width * extent.y / extent.x).clamp(260.0, 1100.0) + 70.0;
        (width as u32, height as u32)
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<()> {
        root.fill(&WHITE).map_err(drawing)?;
        let (low, high) = self.bounds();
        let attending = self.people.iter().filter(|p| p.attending).count();
        let grouped = self.people.iter().filter(|p| p.in_group).count();
        let talking = self.people.iter().filter(|p| p.talking).count();
        let mut caption = format!(
            "{} at t = {:.1} s: {} people, {} attending",
            self.title,
            self.time,
            self.people.len(),
            attending
        );
        if grouped > 0 || talking > 0 {
            caption += &format!(", {grouped} in groups, {talking} talking");
        }
        let mut chart = ChartBuilder::on(root)
            .caption(caption, ("sans-serif", 22))
            .margin(12)
            .x_label_area_size(36)
            .y_label_area_size(44)
            .build_cartesian_2d(low.x..high.x, low.y..high.y)
            .map_err(drawing)?;
        chart
            .configure_mesh()
            .x_desc("x (m)")
            .y_desc("y (m)")
            .light_line_style(WHITE.mix(0.0))
            .draw()
            .map_err(drawing)?;
        let grey = RGBColor(150, 150, 150);
        chart
            .draw_series(self.objects.iter().map(|p| {
                Rectangle::new(
                    [(p.x - 0.25, p.y - 0.25), (p.x + 0.25, p.y + 0.25)],
                    grey.filled(),
                )
            }))
            .map_err(drawing)?
            .label("scene object")
            .legend(move |(x, y)| Rectangle::new([(x - 4, y - 4), (x + 4, y + 4)], grey.filled()));
        let orange = RGBColor(230, 120, 20);
        chart
            .draw_series(self.people.iter().filter_map(|p| {
                p.target.map(|target| {
                    PathElement::new(
                        vec![(p.position.x, p.position.y), (target.x, target.y)],
                        orange.stroke_width(2),
                    )
                })
            }))
            .map_err(drawing)?
            .label("gaze: line to what it looks at")
            .legend(move |(x, y)| PathElement::new(vec![(x - 8, y), (x + 8, y)], orange));
        let blue = RGBColor(30, 80, 200);
        chart
            .draw_series(self.people.iter().map(|p| {
                let ahead = p.position + Vec2::from_angle(p.heading) * 0.9;
                PathElement::new(
                    vec![(p.position.x, p.position.y), (ahead.x, ahead.y)],
                    BLACK.stroke_width(2),
                )
            }))
            .map_err(drawing)?
            .label("heading")
            .legend(|(x, y)| PathElement::new(vec![(x - 8, y), (x + 8, y)], BLACK));
        chart
            .draw_series(self.people.iter().map(|p| {
                let style = if p.target.is_some() {
                    orange.filled()
                } else {
                    blue.filled()
                };
                Circle::new((p.position.x, p.position.y), 4, style)
            }))
            .map_err(drawing)?;
        chart
            .draw_series(std::iter::once(Circle::new(
                (low.x, low.y),
                0,
                blue.filled(),
            )))
            .map_err(drawing)?
            .label("person (orange: looking at someone or something)")
            .legend(move |(x, y)| Circle::new((x, y), 4, blue.filled()));
        // Groups: a green outline round each member; a purple ring round who talks.
        if self.people.iter().any(|p| p.in_group || p.talking) {
            let green = RGBColor(20, 140, 60);
            chart
                .draw_series(
                    self.people.iter().filter(|p| p.in_group).map(|p| {
                        Circle::new((p.position.x, p.position.y), 6, green.stroke_width(2))
                    }),
                )
                .map_err(drawing)?
                .label("in a group, standing together")
                .legend(move |(x, y)| Circle::new((x, y), 6, green.stroke_width(2)));
            let purple = RGBColor(150, 30, 170);
            chart
                .draw_series(
                    self.people.iter().filter(|p| p.talking).map(|p| {
                        Circle::new((p.position.x, p.position.y), 10, purple.stroke_width(2))
                    }),
                )
                .map_err(drawing)?
                .label("talking")
                .legend(move |(x, y)| Circle::new((x, y), 7, purple.stroke_width(2)));
            // The gaze lines inside groups are short: drawn again on top of the dots.
            chart
                .draw_series(self.people.iter().filter(|p| p.in_group).filter_map(|p| {
                    p.target.map(|target| {
                        PathElement::new(
                            vec![(p.position.x, p.position.y), (target.x, target.y)],
                            orange.stroke_width(2),
                        )
                    })
                }))
                .map_err(drawing)?;
        }
        draw_legend(&mut chart)
    }
}

// ---------------------------------------------------------------------------------------
// Figure 1.

/// The paper's Figure 1 for one character.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Figure1 {
    /// The character's label.
    pub label: u64,
    /// `(t, S_max, entity giving S_max)` per frame.
    pub series: Vec<(f64, f32, u32)>,
    /// The planned threshold `A`.
    pub threshold: f32,
    /// The planned constraints `(entity, t_b, t_e)`.
    pub constraints: Vec<(u32, f64, f64)>,
    /// What the character is (for the title).
    pub what: String,
    /// Seconds shown from the first sample (0: all).
    pub span: f64,
}

impl Figure1 {
    /// Adds this frame of character `id` (call after each step of a planned crowd).
    /// `present(entity)` tells whether an entity counts this frame (people of a trajectory
    /// file count only within their track, as in the plan).
    pub fn record(
        &mut self,
        crowd: &Crowd,
        id: u32,
        time: f64,
        present: impl Fn(u32) -> bool,
    ) -> Result<()> {
        let gaze = crowd.gaze(id)?;
        let (first, second) = crowd.best_nearby_by_id(id)?;
        let best = [first, second]
            .into_iter()
            .find(|c| present(c.id))
            .map_or(u32::MAX, |c| c.id);
        self.series.push((time, gaze.s_max.max(0.0), best));
        if self.constraints.is_empty() && crowd.is_planned() {
            self.threshold = crowd.planned_threshold(id)?;
            self.constraints = crowd
                .constraints(id)?
                .iter()
                .map(|k| (k.entity, k.begin, k.end))
                .collect();
        }
        Ok(())
    }
}

impl Figure for Figure1 {
    fn size(&self) -> (u32, u32) {
        (1400, 520)
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<()> {
        root.fill(&WHITE).map_err(drawing)?;
        let (t0, mut t1) = match (self.series.first(), self.series.last()) {
            (Some(a), Some(b)) if b.0 > a.0 => (a.0, b.0),
            (Some(a), _) => (a.0, a.0 + 1.0),
            _ => (0.0, 1.0),
        };
        if self.span > 0.0 {
            t1 = t1.min(t0 + self.span);
        }
        let series: Vec<(f64, f32, u32)> = self
            .series
            .iter()
            .copied()
            .filter(|s| s.0 <= t1 + 1e-9)
            .collect();
        let constraints: Vec<(u32, f64, f64)> = self
            .constraints
            .iter()
            .filter(|k| k.1 < t1)
            .map(|&(entity, begin, end)| (entity, begin.max(t0), end.min(t1)))
            .collect();
        let width = f64::from(self.size().0) - 100.0;
        let top = series
            .iter()
            .map(|s| s.1)
            .fold(self.threshold.max(0.1), f32::max)
            * 1.15;
        let mut chart = ChartBuilder::on(root)
            .caption(
                format!(
                    "Figure 1: S_max(t) of {}, coloured by the entity that scores best; \
                     threshold A; planned constraints [t_b, t_e] shaded",
                    self.what
                ),
                ("sans-serif", 20),
            )
            .margin(12)
            .x_label_area_size(36)
            .y_label_area_size(50)
            .build_cartesian_2d(t0..t1, 0f32..top)
            .map_err(drawing)?;
        chart
            .configure_mesh()
            .x_desc("t (s)")
            .y_desc("S_max")
            .light_line_style(WHITE.mix(0.0))
            .draw()
            .map_err(drawing)?;
        // Constraint bands.
        chart
            .draw_series(constraints.iter().map(|&(entity, begin, end)| {
                Rectangle::new(
                    [(begin, 0.0), (end, top)],
                    entity_colour(entity).mix(0.15).filled(),
                )
            }))
            .map_err(drawing)?;
        for &(entity, begin, end) in &constraints {
            let colour = entity_colour(entity);
            let labelled = (end - begin) / (t1 - t0) * width > 36.0;
            for (t, name) in [(begin, "t_b"), (end, "t_e")] {
                chart
                    .draw_series(std::iter::once(PathElement::new(
                        vec![(t, 0.0), (t, top * 0.93)],
                        colour.stroke_width(1),
                    )))
                    .map_err(drawing)?;
                if !labelled {
                    continue;
                }
                let dx = if name == "t_b" { -0.012 } else { 0.002 } * (t1 - t0);
                chart
                    .draw_series(std::iter::once(Text::new(
                        name,
                        (t + dx, top * 0.985),
                        ("sans-serif", 12).into_font().color(&colour),
                    )))
                    .map_err(drawing)?;
            }
        }
        // S_max, one run per entity.
        let mut start = 0;
        while start < series.len() {
            let entity = series[start].2;
            let mut end = start + 1;
            while end < series.len() && series[end].2 == entity {
                end += 1;
            }
            // Join to the next run's first point so the curve is continuous.
            let stop = (end + 1).min(series.len());
            let colour = if entity == u32::MAX {
                RGBColor(160, 160, 160)
            } else {
                entity_colour(entity)
            };
            chart
                .draw_series(LineSeries::new(
                    series[start..stop].iter().map(|s| (s.0, s.1)),
                    colour.stroke_width(2),
                ))
                .map_err(drawing)?;
            start = end;
        }
        chart
            .draw_series(std::iter::once(PathElement::new(
                vec![(t0, self.threshold), (t1, self.threshold)],
                BLACK.stroke_width(2),
            )))
            .map_err(drawing)?
            .label(format!(
                "A = {:.3} (planned, exact percentile)",
                self.threshold
            ))
            .legend(|(x, y)| PathElement::new(vec![(x - 8, y), (x + 8, y)], BLACK.stroke_width(2)));
        draw_legend(&mut chart)
    }
}

// ---------------------------------------------------------------------------------------
// Figure 3.

/// Yaws (degrees, left positive) at one time of Figure 3.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Yaws {
    /// Time (s).
    pub time: f64,
    /// Direction of the target.
    pub target: f32,
    /// The eyes' gaze.
    pub eyes: f32,
    /// The head (spine, neck and head joints accumulated).
    pub head: f32,
    /// The torso (spine joints accumulated).
    pub torso: f32,
}

/// The paper's Figure 3: yaw of eyes, head and torso during gaze shifts.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Figure3 {
    /// One sample per frame.
    pub series: Vec<Yaws>,
}

/// Yaw (degrees) of a world direction about `world.up`, from `world.forward`.
fn yaw(world: &World, direction: Vec3) -> f32 {
    direction
        .dot(world.side)
        .atan2(direction.dot(world.forward))
        .to_degrees()
}

impl Figure3 {
    /// Runs one character at rest for `seconds` at `fps`: no target for 0.5 s, then a point
    /// 60° to its left, then at 3 s a point 40° to its right, both 2 m away at eye height.
    /// Each frame the chain's joints are read and accumulated: the spine gives the torso
    /// yaw, neck and head add to give the head yaw, and the eyes' gaze gives the eye yaw.
    pub fn simulate(seconds: f64, fps: f64) -> Result<Figure3> {
        let mut crowd = Crowd::new(CrowdConfig {
            max_characters: 1,
            max_objects: 0,
            ..CrowdConfig::default()
        })?;
        let world = crowd.config().world;
        let id = crowd.add_character(&CharacterDesc::default())?;
        let chain = *crowd.chain(id)?;
        let eye_height = chain.look_at_height(world.up);
        let point = |degrees: f32| {
            world.heading_direction(degrees.to_radians()) * 2.0 + world.up * eye_height
        };
        let targets = [(0.5, 60.0f32), (3.0, -40.0f32)];
        let mut joints = vec![Quat::IDENTITY; chain.joint_count()];
        let frames = (seconds * fps).round() as usize;
        let dt = (1.0 / fps) as f32;
        let mut figure = Figure3::default();
        let mut current: Option<f32> = None;
        for k in 0..=frames {
            let t = k as f64 / fps;
            let wanted = targets
                .iter()
                .rev()
                .find(|(start, _)| t >= *start)
                .map(|&(_, degrees)| degrees);
            if wanted != current {
                match wanted {
                    Some(degrees) => crowd.set_gaze_target(
                        id,
                        ExplicitTarget::Point(point(degrees)),
                        TargetPriority::Override,
                    )?,
                    None => crowd.clear_gaze_target(id)?,
                }
                current = wanted;
            }
            crowd.push_frame(
                t,
                &[crowdgaze::scene::EntityUpdate {
                    id,
                    position: Vec3::ZERO,
                    heading: 0.0,
                    heading_from_motion: false,
                    velocity: None,
                    talking: false,
                }],
            )?;
            crowd.step(dt)?;
            crowd.read_joints(0, 1, false, &mut joints)?;
            let mut rotation = Quat::IDENTITY;
            let mut torso = 0.0;
            for (joint, local) in chain.joints()[..chain.body_count()].iter().zip(&joints) {
                rotation *= *local;
                if joint.role == crowdgaze::ik::JointRole::Spine {
                    torso = yaw(&world, rotation * world.forward);
                }
            }
            let head = yaw(&world, rotation * chain.eye_forward());
            let eyes = crowd.eyes_at(0);
            let eyes = yaw(&world, eyes.directions[0] + eyes.directions[1]);
            figure.series.push(Yaws {
                time: t,
                target: current.unwrap_or(0.0),
                eyes,
                head,
                torso,
            });
        }
        Ok(figure)
    }
}

impl Figure for Figure3 {
    fn size(&self) -> (u32, u32) {
        (1100, 560)
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<()> {
        root.fill(&WHITE).map_err(drawing)?;
        let t1 = self.series.last().map_or(1.0, |s| s.time);
        let mut chart = ChartBuilder::on(root)
            .caption(
                "Figure 3: eyes lead, head follows, torso last (yaw during two gaze shifts)",
                ("sans-serif", 20),
            )
            .margin(12)
            .x_label_area_size(36)
            .y_label_area_size(50)
            .build_cartesian_2d(0.0..t1, -60f32..80f32)
            .map_err(drawing)?;
        chart
            .configure_mesh()
            .x_desc("t (s)")
            .y_desc("yaw (degrees, left positive)")
            .light_line_style(RGBColor(235, 235, 235))
            .draw()
            .map_err(drawing)?;
        chart
            .draw_series(DashedLineSeries::new(
                self.series.iter().map(|s| (s.time, s.target)),
                6,
                4,
                BLACK.into(),
            ))
            .map_err(drawing)?
            .label("target direction")
            .legend(|(x, y)| PathElement::new(vec![(x - 8, y), (x + 8, y)], BLACK));
        type Line = (&'static str, RGBColor, fn(&Yaws) -> f32);
        let lines: [Line; 3] = [
            ("eyes", RGBColor(30, 80, 200), |s| s.eyes),
            ("head (spine + neck + head)", RGBColor(230, 120, 20), |s| {
                s.head
            }),
            ("torso (spine)", RGBColor(40, 150, 60), |s| s.torso),
        ];
        for (name, colour, value) in lines {
            chart
                .draw_series(LineSeries::new(
                    self.series.iter().map(|s| (s.time, value(s))),
                    colour.stroke_width(3),
                ))
                .map_err(drawing)?
                .label(name)
                .legend(move |(x, y)| {
                    PathElement::new(vec![(x - 8, y), (x + 8, y)], colour.stroke_width(3))
                });
        }
        draw_legend(&mut chart)
    }
}

// ---------------------------------------------------------------------------------------
// Eyes and lids.

/// One character's eyes and lids after one step.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EyeSample {
    /// Time (s).
    pub time: f64,
    /// Yaw of the eyes in the head (degrees, left positive): the mean of both eyes'
    /// directions, from the head's forward about the head's up.
    pub yaw: f32,
    /// Pitch of the eyes in the head (degrees, up positive).
    pub pitch: f32,
    /// How closed the lids are: 0 open, 1 closed (both eyes blink together; the left's).
    pub closure: f32,
}

/// The eyes of one character against time: the yaw and pitch of its eyes relative to its
/// head, the closure of its lids, and the start of each gaze shift with its amplitude.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct EyesFigure {
    /// The character's label.
    pub label: u64,
    /// One sample per frame.
    pub series: Vec<EyeSample>,
    /// The gaze shifts that started: `(t, amplitude in degrees)`.
    pub shift_starts: Vec<(f64, f32)>,
    /// What the character is (for the title).
    pub what: String,
    /// Seconds shown from the first sample (0: all).
    pub span: f64,
}

/// The mean direction of a chain's two eyes in the head's frame, from the chain's joints
/// (final local rotations, base × delta); `None` for a chain without eyes.
pub fn eye_direction_in_head(chain: &GazeChain, joints: &[Quat]) -> Option<Vec3> {
    let eyes = chain.eye_indices()?;
    let direction: Vec3 = eyes
        .iter()
        .map(|&index| {
            let rest_forward = chain.joints()[index].rest.conjugate() * chain.eye_forward();
            joints[index] * rest_forward
        })
        .sum();
    Some(direction.normalize_or_zero())
}

impl EyesFigure {
    /// Adds this frame of character `id` (call after each step).
    pub fn record(&mut self, crowd: &Crowd, id: u32, time: f64) -> Result<()> {
        let chain = crowd.chain(id)?;
        let mut joints = vec![Quat::IDENTITY; chain.joint_count()];
        crowd.read_joints_of(id, false, &mut joints)?;
        let direction = eye_direction_in_head(chain, &joints).unwrap_or(chain.eye_forward());
        let (forward, up) = (chain.eye_forward(), chain.eye_up());
        let left = up.cross(forward);
        let lids = crowd.eyelids(id)?;
        self.series.push(EyeSample {
            time,
            yaw: direction
                .dot(left)
                .atan2(direction.dot(forward))
                .to_degrees(),
            pitch: direction.dot(up).clamp(-1.0, 1.0).asin().to_degrees(),
            closure: lids.left_closure,
        });
        if let Some(amplitude) = crowd.gaze_motion(id)?.shift_start_amplitude() {
            self.shift_starts.push((time, amplitude.to_degrees()));
        }
        Ok(())
    }
}

impl Figure for EyesFigure {
    fn size(&self) -> (u32, u32) {
        (1400, 720)
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<()> {
        root.fill(&WHITE).map_err(drawing)?;
        let (t0, mut t1) = match (self.series.first(), self.series.last()) {
            (Some(a), Some(b)) if b.time > a.time => (a.time, b.time),
            (Some(a), _) => (a.time, a.time + 1.0),
            _ => (0.0, 1.0),
        };
        if self.span > 0.0 {
            t1 = t1.min(t0 + self.span);
        }
        let shown = |t: f64| t <= t1 + 1e-9;
        let series: Vec<EyeSample> = self
            .series
            .iter()
            .copied()
            .filter(|s| shown(s.time))
            .collect();
        let shifts: Vec<(f64, f32)> = self
            .shift_starts
            .iter()
            .copied()
            .filter(|s| shown(s.0))
            .collect();
        let blinks = series
            .windows(2)
            .filter(|pair| pair[0].closure == 0.0 && pair[1].closure > 0.0)
            .count();
        let root = root
            .titled(
                &format!(
                    "The eyes of {}: eye yaw and pitch relative to the head, lid closure, \
                     gaze shift starts ({} shifts, {blinks} blinks seen)",
                    self.what,
                    shifts.len()
                ),
                ("sans-serif", 20),
            )
            .map_err(drawing)?;
        let (upper, lower) = root.split_vertically(440);
        // The eyes' angles, symmetric about 0, at least ±10°; a band below for the shifts'
        // labels and one above for the legend.
        let extent = series
            .iter()
            .map(|s| s.yaw.abs().max(s.pitch.abs()))
            .fold(10.0f32, f32::max)
            * 1.1;
        let (bottom, top) = (-1.25 * extent, 1.6 * extent);
        let shift_colour = RGBColor(120, 60, 170);
        let shift_style = |amplitude: f32| {
            // 1 px for small shifts, up to 5 px from 40°.
            shift_colour.stroke_width((1.0 + amplitude / 10.0).clamp(1.0, 5.0) as u32)
        };
        let mut eyes = ChartBuilder::on(&upper)
            .margin(12)
            .x_label_area_size(30)
            .y_label_area_size(60)
            .build_cartesian_2d(t0..t1, bottom..top)
            .map_err(drawing)?;
        eyes.configure_mesh()
            .y_desc("eyes in the head (degrees)")
            .y_label_formatter(&|v| format!("{v:.0}"))
            .light_line_style(RGBColor(235, 235, 235))
            .draw()
            .map_err(drawing)?;
        for &(t, amplitude) in &shifts {
            eyes.draw_series(std::iter::once(PathElement::new(
                vec![(t, -1.06 * extent), (t, top)],
                shift_style(amplitude),
            )))
            .map_err(drawing)?;
            eyes.draw_series(std::iter::once(Text::new(
                format!("{amplitude:.0}°"),
                (t - 0.006 * (t1 - t0), -1.09 * extent),
                ("sans-serif", 12).into_font().color(&shift_colour),
            )))
            .map_err(drawing)?;
        }
        eyes.draw_series(std::iter::once(PathElement::new(
            vec![(t0, 0.0), (t1, 0.0)],
            RGBColor(160, 160, 160).stroke_width(1),
        )))
        .map_err(drawing)?;
        let blue = RGBColor(30, 80, 200);
        eyes.draw_series(LineSeries::new(
            series.iter().map(|s| (s.time, s.yaw)),
            blue.stroke_width(2),
        ))
        .map_err(drawing)?
        .label("eye yaw relative to the head (left positive)")
        .legend(move |(x, y)| PathElement::new(vec![(x - 8, y), (x + 8, y)], blue.stroke_width(2)));
        let green = RGBColor(40, 150, 60);
        eyes.draw_series(LineSeries::new(
            series.iter().map(|s| (s.time, s.pitch)),
            green.stroke_width(1),
        ))
        .map_err(drawing)?
        .label("eye pitch relative to the head (up positive)")
        .legend(move |(x, y)| PathElement::new(vec![(x - 8, y), (x + 8, y)], green));
        // An empty series for the legend entry of the markers.
        eyes.draw_series(std::iter::empty::<PathElement<(f64, f32)>>())
            .map_err(drawing)?
            .label("gaze shift starts (labelled and thickened by amplitude)")
            .legend(move |(x, y)| {
                PathElement::new(vec![(x, y - 7), (x, y + 7)], shift_colour.stroke_width(3))
            });
        draw_legend(&mut eyes)?;

        let mut lids = ChartBuilder::on(&lower)
            .margin(12)
            .x_label_area_size(36)
            .y_label_area_size(60)
            .build_cartesian_2d(t0..t1, 0f32..1.5f32)
            .map_err(drawing)?;
        lids.configure_mesh()
            .x_desc("t (s)")
            .y_desc("lid closure")
            .y_labels(4)
            // Closures run 0 to 1; above is room for the legend.
            .y_label_formatter(&|v| {
                if *v <= 1.0 {
                    format!("{v:.1}")
                } else {
                    String::new()
                }
            })
            .light_line_style(RGBColor(235, 235, 235))
            .draw()
            .map_err(drawing)?;
        for &(t, amplitude) in &shifts {
            lids.draw_series(std::iter::once(PathElement::new(
                vec![(t, 0.0), (t, 1.5)],
                shift_style(amplitude),
            )))
            .map_err(drawing)?;
        }
        let orange = RGBColor(230, 120, 20);
        lids.draw_series(LineSeries::new(
            series.iter().map(|s| (s.time, s.closure)),
            orange.stroke_width(2),
        ))
        .map_err(drawing)?
        .label("lid closure (0 open, 1 closed: a blink)")
        .legend(move |(x, y)| {
            PathElement::new(vec![(x - 8, y), (x + 8, y)], orange.stroke_width(2))
        });
        draw_legend(&mut lids)
    }
}

// ---------------------------------------------------------------------------------------
// Collecting what the pictures need while a crowd runs.

/// An observer that takes top-down snapshots at chosen times and records one character's
/// Figure 1 series (and, if wanted, its eyes).
#[derive(Debug, Default)]
pub struct Collector {
    /// Times of the wanted snapshots (s), ascending.
    pub snapshot_times: Vec<f64>,
    /// The snapshots taken.
    pub snapshots: Vec<Snapshot>,
    /// Title of the snapshots.
    pub title: String,
    /// The label of the character of Figure 1, if wanted.
    pub figure1_label: Option<u64>,
    /// Pick the character of Figure 1 (the one with the most planned constraints) when the
    /// run is planned.
    pub figure1_auto: bool,
    /// Figure 1's data.
    pub figure1: Figure1,
    /// Record the eyes of Figure 1's character too.
    pub eyes_wanted: bool,
    /// The eyes of Figure 1's character, if wanted.
    pub eyes: EyesFigure,
    /// Gaze statistics.
    pub stats: crate::sim::GazeStats,
    /// Number of frames in the run (to pick the last one for a snapshot time past the end).
    pub frame_count: usize,
}

impl Observer for Collector {
    fn before_step(&mut self, crowd: &mut Crowd, frame: &Frame) -> Result<()> {
        if frame.index == 0 && self.figure1_auto && crowd.is_planned() {
            let mut best: Option<(usize, u64)> = None;
            for person in frame.labels.iter().map(|(&id, &label)| (id, label)) {
                let count = crowd.constraints(person.0)?.len();
                if best.is_none_or(|(c, l)| count > c || (count == c && person.1 < l)) {
                    best = Some((count, person.1));
                }
            }
            self.figure1_label = best.map(|(_, label)| label);
        }
        if let Some(label) = self.figure1_label {
            self.figure1.label = label;
            self.eyes.label = label;
        }
        Ok(())
    }

    fn after_step(&mut self, crowd: &Crowd, frame: &Frame) -> Result<()> {
        for person in frame.people {
            let gaze = crowd.gaze(person.id)?;
            self.stats.add(person.id, &gaze, frame.dt);
            self.stats.add_conversation(crowd, person.id, &gaze)?;
        }
        let next = self.snapshots.len();
        if let Some(&wanted) = self.snapshot_times.get(next) {
            let last = frame.index + 1 == self.frame_count;
            if frame.time + 1e-9 >= wanted || last {
                self.snapshots
                    .push(Snapshot::take(crowd, frame, &self.title));
            }
        }
        if let Some(label) = self.figure1_label {
            if let Some(person) = frame.people.iter().find(|p| p.label == label) {
                let present = |entity: u32| {
                    !frame.labels.contains_key(&entity)
                        || frame.people.iter().any(|p| p.id == entity)
                };
                self.figure1.record(crowd, person.id, frame.time, present)?;
                if self.eyes_wanted {
                    self.eyes.record(crowd, person.id, frame.time)?;
                }
            }
        }
        Ok(())
    }
}
