//! What each command does.

use std::collections::{BTreeSet, HashMap};
use std::io::Write;
use std::path::{Path, PathBuf};

use anyhow::{bail, Context, Result};
use crowdgaze::attention::TargetPart;
use crowdgaze::ik::{GazeChain, JointRole};
use crowdgaze::scene::ids::NO_ENTITY;
use crowdgaze::world::Axis;
use crowdgaze::{Crowd, World};
use glam::{DQuat, Quat};

use crate::bvh::Bvh;
use crate::cli::{
    AnnotateArgs, BvhArgs, DemoArgs, DemoScene, PlotArgs, PlotKind, StreetArgs, TimeArgs,
};
use crate::lookup::{print_summary, run_look_up, LookUpRun};
use crate::output::AtomicFile;
use crate::plot::{save, Collector, Figure3};
use crate::sim::{
    run_street, run_tracks, Frame, GazeStats, Model, Observer, RunStats, StreetRun, TrackRun,
};
use crate::skeleton::{global_rotation, joint_map, SkeletonChain};
use crate::traj::{TimeOptions, Trajectories};

fn time_options(args: &TimeArgs) -> TimeOptions {
    TimeOptions {
        time_per_frame: args.time_per_frame,
        sample_rate: args.sample_rate,
    }
}

fn street_run(args: &StreetArgs, offline: bool, quiet: bool) -> StreetRun {
    StreetRun {
        seconds: args.seconds,
        fps: 30.0,
        characters: args.characters,
        objects: args.objects,
        seed: args.seed,
        group_share: args.group_share,
        offline,
        quiet,
    }
}

/// Names of a chain's joints for column headers: spine1.., neck1.., head, eye_l, eye_r.
pub fn joint_names(chain: &GazeChain) -> Vec<String> {
    let (mut spine, mut neck) = (0, 0);
    chain
        .joints()
        .iter()
        .map(|joint| match joint.role {
            JointRole::Spine => {
                spine += 1;
                format!("spine{spine}")
            }
            JointRole::Cervical => {
                neck += 1;
                format!("neck{neck}")
            }
            JointRole::Head => "head".to_string(),
            JointRole::LeftEye => "eye_l".to_string(),
            JointRole::RightEye => "eye_r".to_string(),
        })
        .collect()
}

fn describe_time(trajectories: &Trajectories, args: &TimeArgs) -> String {
    match trajectories.detected_step {
        Some(step) => format!(
            "{:.4} s per frame number (detected: the most common step, {step} frame numbers, \
             taken as one sample at {} Hz)",
            trajectories.time_per_frame, args.sample_rate
        ),
        None => format!(
            "{:.4} s per frame number (--time-per-frame)",
            trajectories.time_per_frame
        ),
    }
}

// ---------------------------------------------------------------------------------------
// demo

/// `crowdgaze demo`.
pub fn demo(args: &DemoArgs) -> Result<()> {
    if args.scene == DemoScene::LookUp {
        return demo_look_up(args);
    }
    let run = street_run(&args.street, false, args.quiet);
    let seconds = run.frame_count() as f64 / run.fps;
    let mut collector = Collector {
        snapshot_times: vec![0.5 * seconds, seconds],
        title: "Street".to_string(),
        frame_count: run.frame_count(),
        ..Collector::default()
    };
    let stats = run_street(&run, &mut collector)?;
    let gaze = &collector.stats;
    let (low, high) = crowdgaze::CrowdConfig::default().attention_fraction_range;
    println!(
        "crowdgaze demo: the street (120 m x 14 m), {} characters, {} objects, {:.1} s at 30 fps, seed {}",
        args.street.characters, args.street.objects, seconds, args.street.seed
    );
    println!(
        "  attentive:   {:.1}% of character-frames (each character's a drawn in [{:.0}%, {:.0}%))",
        100.0 * gaze.attentive_fraction(),
        100.0 * low,
        100.0 * high
    );
    println!(
        "  gaze shifts: {:.1} per character per minute (new interest points)",
        gaze.shifts_per_minute()
    );
    println!("  mean S_max:  {:.3}", gaze.mean_s_max());
    print_groups(&stats, gaze, "characters");
    println!(
        "  cost:        {:.2} µs per character-frame (push_frame + step: attention and gaze IK), {:.2} s in all",
        stats.crowd_time.as_secs_f64() * 1e6 / stats.character_frames.max(1) as f64,
        stats.crowd_time.as_secs_f64()
    );
    if args.no_plots {
        return Ok(());
    }
    let mut written = Vec::new();
    for snapshot in &collector.snapshots {
        let stem = args.out.join(format!("topdown_{:.1}s", snapshot.time));
        written.extend(save(snapshot, &stem)?);
    }
    // Figure 1 comes from the offline plan: the same street again, recorded and planned.
    let mut planned = Collector {
        figure1_auto: true,
        frame_count: run.frame_count(),
        ..Collector::default()
    };
    run_street(&street_run(&args.street, true, args.quiet), &mut planned)?;
    planned.figure1.what = format!("character {}", planned.figure1.label);
    planned.figure1.span = 20.0;
    written.extend(save(
        &planned.figure1,
        &args
            .out
            .join(format!("figure1_character{}", planned.figure1.label)),
    )?);
    written.extend(save(
        &Figure3::simulate(6.0, 60.0)?,
        &args.out.join("figure3_gaze_shift"),
    )?);
    print_written(&written);
    Ok(())
}

/// `crowdgaze demo --scene look-up`.
fn demo_look_up(args: &DemoArgs) -> Result<()> {
    let run = LookUpRun {
        street: street_run(&args.street, false, args.quiet),
        lookers: args.lookers,
        start: args.look_at,
        follow: (!args.no_follow).then_some(args.follow_strength),
    };
    let result = run_look_up(&run)?;
    print_summary(&result, &run);
    if args.no_plots {
        return Ok(());
    }
    let written = save(&result, &args.out.join("look_up"))?;
    print_written(&written);
    Ok(())
}

/// The summary line of the conversations, if there were any.
fn print_groups(stats: &RunStats, gaze: &GazeStats, who: &str) {
    if stats.groups == 0 {
        return;
    }
    println!(
        "  groups:      {} standing together and talking in turns ({} {who}): listeners \
         look at the speaker {:.0}% of the time, speakers at a listener {:.0}%",
        stats.groups,
        stats.grouped,
        100.0 * gaze.listener_on_speaker_fraction(),
        100.0 * gaze.speaker_on_listener_fraction()
    );
}

fn print_written(paths: &[PathBuf]) {
    println!("  pictures:");
    for path in paths {
        println!("    {}", path.display());
    }
}

// ---------------------------------------------------------------------------------------
// annotate

/// The world of trajectory files: x, y on the ground, z up, metres.
pub fn trajectory_world() -> World {
    World::new(Axis::PositiveZ, Axis::PositiveX, 1.0).expect("valid axes")
}

/// The name of a target part in the output.
pub fn part_name(part: TargetPart) -> &'static str {
    match part {
        TargetPart::Whole => "whole",
        TargetPart::Head => "head",
        TargetPart::LeftEye => "left_eye",
        TargetPart::RightEye => "right_eye",
        TargetPart::Chest => "chest",
        TargetPart::Torso => "torso",
    }
}

struct AnnotateWriter {
    out: AtomicFile,
    stats: GazeStats,
    joints: Vec<Quat>,
    rows: usize,
    line: String,
    /// Each person's group (the input's `group` column).
    groups: HashMap<u64, Option<u64>>,
    /// Whether to write the followed point (gaze following on).
    follow: bool,
    /// The world of the file.
    world: World,
    /// Glances each person started because others looked somewhere (gaze following).
    glances: HashMap<u64, u32>,
}

impl Observer for AnnotateWriter {
    fn after_step(&mut self, crowd: &Crowd, frame: &Frame) -> Result<()> {
        use std::fmt::Write as _;
        let scene = crowd.scene();
        for person in frame.people {
            let gaze = crowd.gaze(person.id)?;
            self.stats.add(person.id, &gaze, frame.dt);
            self.stats.add_conversation(crowd, person.id, &gaze)?;
            let count = crowd.chain(person.id)?.joint_count();
            self.joints.resize(count, Quat::IDENTITY);
            crowd.read_joints_of(person.id, false, &mut self.joints)?;
            let direction = crowd.gaze_motion(person.id)?.gaze_ray().1;
            let line = &mut self.line;
            line.clear();
            // What the eyes look at: the attention model's interest point, or in a
            // conversation the member looked at.
            let target = if gaze.target != NO_ENTITY {
                frame
                    .labels
                    .get(&gaze.target)
                    .map_or_else(|| format!("object{}", gaze.target), u64::to_string)
            } else {
                String::new()
            };
            let _ = write!(
                line,
                "{:.4},{},{},{},{},{},{},{},{},{}",
                frame.time,
                person.label,
                target,
                if gaze.attending || !target.is_empty() {
                    part_name(gaze.target_part)
                } else {
                    ""
                },
                u8::from(gaze.attending),
                gaze.s_max,
                gaze.threshold,
                direction.x,
                direction.y,
                direction.z
            );
            for q in &self.joints {
                let _ = write!(line, ",{},{},{},{}", q.x, q.y, q.z, q.w);
            }
            let lids = crowd.eyelids(person.id)?;
            let _ = write!(line, ",{},{}", lids.left_closure, lids.right_closure);
            let talking = scene
                .index_of(person.id)
                .is_some_and(|index| scene.talking()[index]);
            let _ = write!(line, ",{}", u8::from(talking));
            line.push(',');
            if crowd.conversation_of(person.id)?.is_some() {
                if let Some(group) = self.groups.get(&person.label).copied().flatten() {
                    let _ = write!(line, "{group}");
                }
            }
            if self.follow {
                let (point, glances) = crowd.following(person.id)?;
                let total = self.glances.entry(person.label).or_default();
                *total = (*total).max(glances);
                match point {
                    Some(p) => {
                        let ground = self.world.ground(p);
                        let _ = write!(line, ",{},{},{}", ground.x, ground.y, self.world.height(p));
                    }
                    None => line.push_str(",,,"),
                }
            }
            line.push('\n');
            self.out
                .write_all(line.as_bytes())
                .with_context(|| format!("{}: cannot write", self.out.path().display()))?;
            self.rows += 1;
        }
        Ok(())
    }
}

/// `crowdgaze annotate`.
pub fn annotate(args: &AnnotateArgs) -> Result<()> {
    let trajectories = Trajectories::read(&args.input, &time_options(&args.time))?;
    let world = trajectory_world();
    let mut out = AtomicFile::create(&args.out)?;
    let mut header =
        String::from("time,id,target,part,attending,s_max,threshold,gaze_x,gaze_y,gaze_z");
    for name in joint_names(&GazeChain::human(world.up, world.forward)) {
        for component in ["qx", "qy", "qz", "qw"] {
            header.push_str(&format!(",{name}_{component}"));
        }
    }
    header.push_str(",left_closure,right_closure,talking,group");
    if args.follow {
        header.push_str(",follow_x,follow_y,follow_z");
    }
    header.push('\n');
    let stares = args.stare.clone();
    out.write_all(header.as_bytes())
        .with_context(|| format!("{}: cannot write", args.out.display()))?;
    let mut writer = AnnotateWriter {
        out,
        stats: GazeStats::default(),
        joints: Vec::new(),
        rows: 0,
        line: String::new(),
        groups: trajectories
            .tracks
            .iter()
            .map(|track| (track.person, track.group))
            .collect(),
        follow: args.follow,
        world,
        glances: HashMap::new(),
    };
    let run = TrackRun {
        world,
        fps: args.fps,
        start: args.time.start,
        end: args.time.end,
        offline: args.offline,
        model: args.model,
        seed: args.seed,
        quiet: args.quiet,
        follow: args.follow.then_some(args.follow_strength),
        stares,
    };
    let stats = run_tracks(&trajectories, &run, &mut writer)?;
    let AnnotateWriter {
        out,
        stats: gaze,
        rows,
        glances,
        ..
    } = writer;
    out.commit()?;
    let (low, high) = crowdgaze::CrowdConfig::default().attention_fraction_range;
    println!(
        "crowdgaze annotate: {}: {} people, {} samples; {}",
        args.input.display(),
        trajectories.tracks.len(),
        trajectories.rows,
        describe_time(&trajectories, &args.time)
    );
    println!(
        "  {} frames at {} fps from {:.2} s, {} person-frames, model {}, {}",
        stats.frames,
        args.fps,
        trajectories
            .output_times(args.fps, args.time.start, args.time.end)
            .first()
            .copied()
            .unwrap_or(0.0),
        stats.character_frames,
        args.model.name(),
        if args.offline {
            "offline (exact percentile)"
        } else {
            "online"
        }
    );
    println!(
        "  attentive:   {:.1}% of person-frames (each person's a drawn in [{:.0}%, {:.0}%)), mean S_max {:.3}",
        100.0 * gaze.attentive_fraction(),
        100.0 * low,
        100.0 * high,
        gaze.mean_s_max()
    );
    println!(
        "  gaze shifts: {:.1} per person per minute",
        gaze.shifts_per_minute()
    );
    if trajectories.has_groups || trajectories.has_talking {
        let talkers = trajectories
            .tracks
            .iter()
            .filter(|track| track.samples.iter().any(|s| s.talking))
            .count();
        println!(
            "  talking:     {talkers} people talk (column 'talking'{})",
            if trajectories.has_groups {
                ", groups from column 'group'"
            } else {
                ""
            }
        );
    }
    print_groups(&stats, &gaze, "people");
    if !args.stare.is_empty() {
        let starers: BTreeSet<u64> = args.stare.iter().map(|s| s.person).collect();
        println!(
            "  staring:     {} people stare at a point (--stare): {}",
            starers.len(),
            starers
                .iter()
                .map(u64::to_string)
                .collect::<Vec<_>>()
                .join(", ")
        );
    }
    if args.follow {
        let followers = glances.values().filter(|&&g| g > 0).count();
        println!(
            "  following:   {followers} people glanced where others looked ({} glances, strength {}; columns follow_x,follow_y,follow_z)",
            glances.values().sum::<u32>(),
            args.follow_strength.name()
        );
    }
    println!(
        "  cost:        {:.2} µs per person-frame",
        stats.crowd_time.as_secs_f64() * 1e6 / stats.character_frames.max(1) as f64
    );
    println!("  wrote {} ({rows} rows)", args.out.display());
    Ok(())
}

// ---------------------------------------------------------------------------------------
// plot

/// `crowdgaze plot`.
pub fn plot(args: &PlotArgs) -> Result<()> {
    let wants = |kind: PlotKind| args.what == kind || args.what == PlotKind::All;
    let mut written = Vec::new();
    if wants(PlotKind::Topdown) || wants(PlotKind::Figure1) || wants(PlotKind::Eyes) {
        let mut collector = Collector {
            figure1_label: args.character,
            figure1_auto: args.character.is_none(),
            eyes_wanted: wants(PlotKind::Eyes),
            ..Collector::default()
        };
        if let Some(input) = &args.input {
            let trajectories = Trajectories::read(input, &time_options(&args.time))?;
            if let Some(label) = args.character {
                trajectories.track(label)?;
            }
            let times = trajectories.output_times(args.fps, args.time.start, args.time.end);
            let (Some(&first), Some(&last)) = (times.first(), times.last()) else {
                bail!("{}: no sample between --start and --end", input.display());
            };
            collector.snapshot_times = snapshot_times(&args.times, first, last);
            collector.frame_count = times.len();
            collector.title = file_name(input);
            run_tracks(
                &trajectories,
                &TrackRun {
                    world: trajectory_world(),
                    fps: args.fps,
                    start: args.time.start,
                    end: args.time.end,
                    offline: true,
                    model: Model::Crowd,
                    seed: args.street.seed,
                    quiet: args.quiet,
                    follow: None,
                    stares: Vec::new(),
                },
                &mut collector,
            )?;
            collector.figure1.what = format!("person {}", collector.figure1.label);
        } else {
            let run = street_run(&args.street, true, args.quiet);
            if let Some(label) = args.character {
                if label >= args.street.characters as u64 {
                    bail!(
                        "--character {label}: the street has characters 0 to {}",
                        args.street.characters.saturating_sub(1)
                    );
                }
            }
            let seconds = run.frame_count() as f64 / run.fps;
            collector.snapshot_times = snapshot_times(&args.times, 0.0, seconds - 1.0 / run.fps);
            collector.frame_count = run.frame_count();
            collector.title = "Street".to_string();
            run_street(&run, &mut collector)?;
            collector.figure1.what = format!("character {}", collector.figure1.label);
        }
        if wants(PlotKind::Topdown) {
            for snapshot in &collector.snapshots {
                let stem = args.out.join(format!("topdown_{:.1}s", snapshot.time));
                written.extend(save(snapshot, &stem)?);
            }
        }
        if wants(PlotKind::Figure1) {
            collector.figure1.span = args.span;
            let stem = args.out.join(format!(
                "figure1_{}",
                collector.figure1.what.replace(' ', "")
            ));
            written.extend(save(&collector.figure1, &stem)?);
        }
        if wants(PlotKind::Eyes) {
            collector.eyes.span = args.span;
            collector.eyes.what = collector.figure1.what.clone();
            let stem = args
                .out
                .join(format!("eyes_{}", collector.eyes.what.replace(' ', "")));
            written.extend(save(&collector.eyes, &stem)?);
        }
    }
    if wants(PlotKind::Figure3) {
        written.extend(save(
            &Figure3::simulate(6.0, 60.0)?,
            &args.out.join("figure3_gaze_shift"),
        )?);
    }
    print_written(&written);
    Ok(())
}

fn snapshot_times(wanted: &[f64], first: f64, last: f64) -> Vec<f64> {
    let mut times: Vec<f64> = if wanted.is_empty() {
        vec![0.5 * (first + last), last]
    } else {
        wanted.iter().map(|t| t.clamp(first, last)).collect()
    };
    times.sort_by(f64::total_cmp);
    times.dedup();
    times
}

fn file_name(path: &Path) -> String {
    path.file_name().map_or_else(
        || path.display().to_string(),
        |n| n.to_string_lossy().into_owned(),
    )
}

// ---------------------------------------------------------------------------------------
// bvh

struct BvhGaze<'a> {
    bvh: &'a Bvh,
    skeleton: &'a SkeletonChain,
    person: u64,
    world: World,
    units_per_metre: f64,
    /// Output motion.
    frames: Vec<Vec<f64>>,
    base: Vec<Quat>,
    attending_frames: usize,
}

impl<'a> BvhGaze<'a> {
    fn clip_frame(&self, index: usize) -> &'a [f64] {
        let bvh: &'a Bvh = self.bvh;
        &bvh.frames[index % bvh.frames.len()]
    }

    /// The clip's facing yaw at a frame: its chain root's rest forward, turned.
    fn clip_yaw(&self, frame: &[f64]) -> f64 {
        let up = self.world.up.as_dvec3();
        let forward = self.world.forward.as_dvec3();
        let side = self.world.side.as_dvec3();
        let facing = global_rotation(self.bvh, self.skeleton.root, frame) * forward;
        let facing = facing - up * facing.dot(up);
        facing.dot(side).atan2(facing.dot(forward))
    }

    fn heading(&self, crowd: &Crowd, id: u32) -> Result<f64> {
        let scene = crowd.scene();
        let index = scene
            .index_of(id)
            .context("the walking character left the crowd")?;
        Ok(f64::from(scene.headings()[index]))
    }
}

impl Observer for BvhGaze<'_> {
    fn chain(&self, label: u64) -> Option<GazeChain> {
        (label == self.person).then_some(self.skeleton.chain)
    }

    fn before_step(&mut self, crowd: &mut Crowd, frame: &Frame) -> Result<()> {
        let Some(person) = frame.people.iter().find(|p| p.label == self.person) else {
            return Ok(());
        };
        let clip = self.clip_frame(frame.index);
        let up = self.world.up.as_dvec3();
        let yaw = self.clip_yaw(clip);
        // The chain root's rotation in the character's frame: the clip's, less its facing.
        let root =
            DQuat::from_axis_angle(up, -yaw) * global_rotation(self.bvh, self.skeleton.root, clip);
        self.base.clear();
        for (k, &joint) in self.skeleton.joints.iter().enumerate() {
            let local = self.bvh.joints[joint].rotation(clip);
            // Joints between this one and the chain joint before it (an eye under a facial
            // joint) turn it too.
            let above = self.skeleton.between[k]
                .iter()
                .fold(DQuat::IDENTITY, |q, &b| {
                    q * self.bvh.joints[b].rotation(clip)
                });
            let base = if k == 0 { root * local } else { above * local };
            self.base.push(base.as_quat());
        }
        crowd.set_base_pose(person.id, &self.base)?;
        Ok(())
    }

    fn after_step(&mut self, crowd: &Crowd, frame: &Frame) -> Result<()> {
        let Some(person) = frame.people.iter().find(|p| p.label == self.person) else {
            return Ok(());
        };
        let clip = self.clip_frame(frame.index).to_vec();
        let mut row = clip.clone();
        let up = self.world.up.as_dvec3();
        let heading = self.heading(crowd, person.id)?;
        let yaw = self.clip_yaw(&clip);
        let scene = crowd.scene();
        let index = scene
            .index_of(person.id)
            .context("the walking character left")?;
        let position = scene.positions()[index].as_dvec3() * self.units_per_metre;
        // The root: on the trajectory, at the clip's height, turned to the walking direction.
        let root = &self.bvh.joints[0];
        if let Some(translation) = root.translation(&clip) {
            let value = position - up * position.dot(up) + up * translation.dot(up);
            for (k, channel) in root.channels.iter().enumerate() {
                if let Some(axis) = channel.position_axis() {
                    row[root.first_channel + k] = value[axis];
                }
            }
        }
        if root.euler_order().is_some() {
            let turned = DQuat::from_axis_angle(up, heading - yaw) * root.rotation(&clip);
            root.set_rotation(&mut row, turned, &clip)?;
        }
        // The chain: the clip's pose, then the gaze.
        let deltas = crowd.gaze_motion(person.id)?.deltas();
        for (&joint, delta) in self.skeleton.joints.iter().zip(deltas) {
            let joint = &self.bvh.joints[joint];
            let rotation = joint.rotation(&clip) * delta.as_dquat();
            joint.set_rotation(&mut row, rotation, &clip)?;
        }
        if crowd.gaze(person.id)?.attending {
            self.attending_frames += 1;
        }
        self.frames.push(row);
        Ok(())
    }
}

/// `crowdgaze bvh`.
pub fn bvh(args: &BvhArgs) -> Result<()> {
    if !(args.units_per_metre.is_finite() && args.units_per_metre > 0.0) {
        bail!(
            "--units-per-metre is {}, must be positive",
            args.units_per_metre
        );
    }
    let clip = Bvh::read(&args.skeleton)?;
    if clip.frames.is_empty() {
        bail!("{}: the clip has no frames", args.skeleton.display());
    }
    let trajectories = Trajectories::read(&args.trajectory, &time_options(&args.time))?;
    let track = trajectories.track(args.id)?;
    let map = joint_map(args.map.as_deref())?;
    let skeleton = SkeletonChain::build(&clip, &map, args.up, args.forward, args.units_per_metre)
        .with_context(|| format!("{}", args.skeleton.display()))?;
    let world = World::new(skeleton.up, skeleton.forward, 1.0)
        .with_context(|| format!("{}: axes", args.skeleton.display()))?;
    let fps = 1.0 / clip.frame_time;
    let start = args
        .time
        .start
        .unwrap_or(f64::NEG_INFINITY)
        .max(track.first_time());
    let end = args
        .time
        .end
        .unwrap_or(f64::INFINITY)
        .min(track.last_time());
    if end < start {
        bail!(
            "{}: person {} is not in the file between --start and --end (their track spans {:.2} s to {:.2} s)",
            args.trajectory.display(),
            args.id,
            track.first_time(),
            track.last_time()
        );
    }
    let mut observer = BvhGaze {
        bvh: &clip,
        skeleton: &skeleton,
        person: args.id,
        world,
        units_per_metre: args.units_per_metre,
        frames: Vec::new(),
        base: Vec::new(),
        attending_frames: 0,
    };
    let run = TrackRun {
        world,
        fps,
        start: Some(start),
        end: Some(end),
        offline: false,
        model: Model::Crowd,
        seed: args.seed,
        quiet: args.quiet,
        follow: None,
        stares: Vec::new(),
    };
    run_tracks(&trajectories, &run, &mut observer)?;
    let frames = observer.frames.len();
    let attending = observer.attending_frames;
    let out = Bvh {
        joints: clip.joints.clone(),
        channel_count: clip.channel_count,
        frame_time: clip.frame_time,
        frames: observer.frames,
    };
    let mut file = AtomicFile::create(&args.out)?;
    file.write_all(out.to_text().as_bytes())
        .with_context(|| format!("{}: cannot write", args.out.display()))?;
    file.commit()?;
    let names: Vec<&str> = skeleton
        .joints
        .iter()
        .map(|&j| clip.joints[j].name.as_str())
        .collect();
    println!(
        "crowdgaze bvh: {} ({} frames at {:.2} fps), up {:?}, facing {:?}, {} units per metre",
        args.skeleton.display(),
        clip.frames.len(),
        fps,
        skeleton.up,
        skeleton.forward,
        args.units_per_metre
    );
    println!(
        "  gaze chain: {} > {}",
        clip.joints[skeleton.root].name,
        names.join(" > ")
    );
    println!(
        "  person {} of {}: {:.2} s to {:.2} s, {} other people",
        args.id,
        args.trajectory.display(),
        start,
        end,
        trajectories.tracks.len() - 1
    );
    println!(
        "  wrote {} ({frames} frames; attending in {:.1}% of them)",
        args.out.display(),
        100.0 * attending as f64 / frames.max(1) as f64
    );
    Ok(())
}
