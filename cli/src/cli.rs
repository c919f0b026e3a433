//! The command line: `demo`, `annotate`, `plot` and `bvh`.

use std::path::PathBuf;

use clap::{Args, Parser, Subcommand};

use crate::sim::{FollowStrength, Model, Stare};

/// Believable gaze for crowd characters: attention (who looks at what, Grillon & Thalmann
/// 2009), gaze IK with human timing, from the command line.
#[derive(Debug, Parser)]
#[command(name = "crowdgaze", version, about, long_about = None)]
pub struct Cli {
    /// The command.
    #[command(subcommand)]
    pub command: Command,
}

/// The commands.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// The paper's street scene (130 characters walking, standing, sitting or talking in
    /// groups, 60 scene objects): prints a summary and writes pictures. --scene look-up: a
    /// group stops and looks up, and passers-by follow their gaze.
    Demo(DemoArgs),
    /// Adds gaze to pedestrian trajectories: who each person looks at, and the joint
    /// rotations of their gaze chain, per output frame.
    Annotate(AnnotateArgs),
    /// Writes pictures (PNG and SVG): top-down views, the paper's Figure 1 and Figure 3, one
    /// character's eyes and lids.
    Plot(PlotArgs),
    /// Adds gaze to a BVH clip walking the trajectory of one person of a trajectory file.
    Bvh(BvhArgs),
}

/// The street scene's settings.
#[derive(Debug, Clone, Args)]
pub struct StreetArgs {
    /// Simulated seconds.
    #[arg(long, default_value_t = 60.0)]
    pub seconds: f64,
    /// Number of characters.
    #[arg(long, default_value_t = 130)]
    pub characters: usize,
    /// Number of scene objects (shop windows, benches, lamps, posters).
    #[arg(long, default_value_t = 60)]
    pub objects: usize,
    /// Seed of the scene and of every random choice: same seed, same output.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Share of the characters standing in groups of two and three on the pavements,
    /// talking in turns (0 to 1; 0: no groups).
    #[arg(long, value_name = "SHARE", default_value_t = 0.17)]
    pub group_share: f32,
}

/// `crowdgaze demo`.
#[derive(Debug, Args)]
pub struct DemoArgs {
    /// The scene: the street (default), or look-up, the street where a group of
    /// people stops and stares at a point high on a facade and passers-by may look too
    /// (gaze following, Milgram et al. 1969).
    #[arg(long, value_enum, default_value_t = DemoScene::Street)]
    pub scene: DemoScene,
    /// look-up: how many people stop and look up.
    #[arg(long, value_name = "K", default_value_t = 5)]
    pub lookers: usize,
    /// look-up: when they stop (seconds from the start).
    #[arg(long, value_name = "S", default_value_t = 10.0)]
    pub look_at: f64,
    /// look-up: how strongly passers-by follow their gaze.
    #[arg(long, value_enum, value_name = "STRENGTH", default_value_t = FollowStrength::Milgram)]
    pub follow_strength: FollowStrength,
    /// look-up: turn gaze following off (the lookers are still there; nobody follows).
    #[arg(long)]
    pub no_follow: bool,
    /// The street.
    #[command(flatten)]
    pub street: StreetArgs,
    /// Directory of the pictures.
    #[arg(long, default_value = "target/demo")]
    pub out: PathBuf,
    /// Do not write pictures.
    #[arg(long)]
    pub no_plots: bool,
    /// Hide the progress bar.
    #[arg(long, short)]
    pub quiet: bool,
}

/// The scenes of `demo`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum DemoScene {
    /// The paper's street: attention, groups talking, the paper's figures.
    Street,
    /// The street where a group stops and looks up at a point 10 m up a facade: who of the
    /// passers-by saw them, who looked up too, and when.
    LookUp,
}

/// How frame numbers of a trajectory file become seconds.
#[derive(Debug, Clone, Args)]
pub struct TimeArgs {
    /// Seconds per frame number. Default: detected. The most common step between a
    /// person's consecutive frame numbers is taken as one sample period at --sample-rate
    /// (2.5 Hz, the ETH and UCY annotation rate: seq_eth steps 6 frame numbers, so 1/15 s
    /// each; zara01 steps 10, so 1/25 s).
    #[arg(long, value_name = "S")]
    pub time_per_frame: Option<f64>,
    /// Samples per second assumed when detecting the time per frame number.
    #[arg(long, value_name = "HZ", default_value_t = 2.5)]
    pub sample_rate: f64,
    /// First time to use, seconds on the file's clock (frame × time per frame).
    #[arg(long, value_name = "S")]
    pub start: Option<f64>,
    /// Last time to use, seconds on the file's clock.
    #[arg(long, value_name = "S")]
    pub end: Option<f64>,
}

/// `crowdgaze annotate`.
#[derive(Debug, Args)]
#[command(
    after_help = "Input: CSV with a header naming the columns frame,id,x,y (and \
optionally z, talking, group), in any order; x and y in metres on the ground. talking: 0 or 1 \
per sample (held until the next sample); group: people with the same group id (a non-negative \
integer, the same on all of a person's rows; empty or -1 for none; at most 8 people) stand \
together and talk: those present together form a conversation. Tracks are resampled to --fps \
with a cubic Hermite (Catmull-Rom) spline, headings follow the motion, each person enters when \
their track starts and leaves when it ends.\n\nOutput, one row per output frame and person \
present: time,id,target,part,attending,s_max,threshold,gaze_x,gaze_y,gaze_z, then \
<joint>_qx,_qy,_qz,_qw for each joint of the gaze chain (spine1-5, neck1-2, head, eye_l, \
eye_r: final local rotations, base * delta), then left_closure,right_closure: how closed each \
eye's lids are, 0 open to 1 closed (blinks), then talking (0 or 1, from the input) and group \
(the group id while the person is in a conversation, else empty). target is the id of the \
person looked at (empty when looking ahead); the gaze direction is in the file's (x, y, up) \
axes. With --follow, three more columns: follow_x,follow_y,follow_z, the point the person \
glances at because others look there (gaze following; the file's axes, metres), empty when \
not following.\n\nGaze following: --stare ID:X,Y,Z[:T0-T1] makes person ID stare at the \
point (X, Y on the ground, Z up, metres) from T0 to T1 seconds on the file's clock (default: \
while present), as game logic would; repeat it for several people. With --follow, people who \
see starers within 10 m in front of them may glance at the point for 1-2.5 s (followers \
count as weaker cues for others)."
)]
pub struct AnnotateArgs {
    /// The trajectory file (frame,id,x,y[,z][,talking][,group]).
    #[arg(long)]
    pub input: PathBuf,
    /// The output CSV.
    #[arg(long)]
    pub out: PathBuf,
    /// The attention model.
    #[arg(long, value_enum, default_value_t = Model::Crowd)]
    pub model: Model,
    /// Output frames per second.
    #[arg(long, default_value_t = 30.0)]
    pub fps: f64,
    /// Plan offline with the exact percentile (the paper's pipeline: every frame recorded,
    /// each person's threshold from their whole track), instead of frame by frame.
    #[arg(long)]
    pub offline: bool,
    /// Time conversion and window.
    #[command(flatten)]
    pub time: TimeArgs,
    /// Seed of every random choice.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Turn gaze following on: people glance where the starers they see look; adds the
    /// columns follow_x,follow_y,follow_z.
    #[arg(long)]
    pub follow: bool,
    /// How strongly people follow (with --follow).
    #[arg(long, value_enum, value_name = "STRENGTH", default_value_t = FollowStrength::Milgram, requires = "follow")]
    pub follow_strength: FollowStrength,
    /// Make person ID stare at the point X,Y,Z (metres, the file's axes, Z up), from T0 to
    /// T1 seconds (default: while present); repeatable.
    #[arg(long, value_name = "ID:X,Y,Z[:T0-T1]", value_parser = Stare::parse)]
    pub stare: Vec<Stare>,
    /// Hide the progress bar.
    #[arg(long, short)]
    pub quiet: bool,
}

/// Which pictures `plot` writes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum PlotKind {
    /// Top-down views at --times.
    Topdown,
    /// The paper's Figure 1 for --character.
    Figure1,
    /// The paper's Figure 3.
    Figure3,
    /// The eyes of --character against time: their yaw and pitch relative to the head, the
    /// lids' closure (blinks) and the gaze shifts' starts with their amplitudes.
    Eyes,
    /// All four.
    All,
}

/// `crowdgaze plot`.
#[derive(Debug, Args)]
pub struct PlotArgs {
    /// Which pictures.
    #[arg(long, value_enum, default_value_t = PlotKind::All)]
    pub what: PlotKind,
    /// A trajectory file to show instead of the street scene.
    #[arg(long)]
    pub input: Option<PathBuf>,
    /// Times of the top-down views (seconds; on the file's clock with --input), comma
    /// separated. Default: the middle and the end.
    #[arg(long, value_delimiter = ',')]
    pub times: Vec<f64>,
    /// The character of Figure 1 and of the eyes: its index in the street (0-based), or its
    /// id in --input. Default: the one with the most planned constraints.
    #[arg(long)]
    pub character: Option<u64>,
    /// Seconds of Figure 1 and of the eyes shown, from the character's first frame (0: all).
    #[arg(long, default_value_t = 20.0)]
    pub span: f64,
    /// The street scene (without --input).
    #[command(flatten)]
    pub street: StreetArgs,
    /// Time conversion and window (with --input).
    #[command(flatten)]
    pub time: TimeArgs,
    /// Frames per second (with --input; the street runs at 30).
    #[arg(long, default_value_t = 10.0)]
    pub fps: f64,
    /// Directory of the pictures.
    #[arg(long, default_value = "target/plots")]
    pub out: PathBuf,
    /// Hide the progress bar.
    #[arg(long, short)]
    pub quiet: bool,
}

/// `crowdgaze bvh`.
#[derive(Debug, Args)]
#[command(
    after_help = "Default joint map (case-insensitive, any 'namespace:' prefix ignored): \
Hips=root, Spine=spine, Spine1=spine, Spine2=spine, Spine3=spine, Chest=spine, \
UpperChest=spine, LowerBack=spine, Neck=neck, Neck1=neck, Head=head, LeftEye=left_eye, \
RightEye=right_eye (also Eye_L, Eye.L and the R ones). The chain runs from the head down \
through neck and spine joints; its root is the first joint below them; eyes are children of \
the head, both or neither.\n\nThe \
trajectory's x runs along the skeleton's rest facing direction (--forward) and y along its \
left; the clip loops if the track is longer. Output: the same hierarchy and channel orders; \
the root follows the trajectory (keeping the clip's height), turns with the walking \
direction, and the chain joints get the gaze on top of the clip's pose (final = clip * \
delta)."
)]
pub struct BvhArgs {
    /// The BVH clip (its pose is the base motion).
    #[arg(long)]
    pub skeleton: PathBuf,
    /// The trajectory file (frame,id,x,y[,z]).
    #[arg(long)]
    pub trajectory: PathBuf,
    /// The person of the trajectory file the clip follows; the others are the crowd it
    /// looks at.
    #[arg(long)]
    pub id: u64,
    /// The output BVH.
    #[arg(long)]
    pub out: PathBuf,
    /// The clip's length unit: how many make a metre. The default, 39.37, is inches, which
    /// fits the test clips (undocumented units, a child-sized skeleton of ~45 units).
    #[arg(long, value_name = "U", default_value_t = 39.37)]
    pub units_per_metre: f64,
    /// The clip's up axis (x, y, z, -x, ...). Default: along its rest-pose spine.
    #[arg(long, value_parser = parse_axis_arg)]
    pub up: Option<crowdgaze::world::Axis>,
    /// The direction the skeleton faces in its rest pose. Default: left × up, left from
    /// its Left*/Right* joints.
    #[arg(long, value_parser = parse_axis_arg, allow_hyphen_values = true)]
    pub forward: Option<crowdgaze::world::Axis>,
    /// Joint map overrides, NAME=ROLE comma separated (roles: root, spine, neck, head,
    /// left_eye, right_eye, none).
    #[arg(long, value_name = "MAP")]
    pub map: Option<String>,
    /// Time conversion and window.
    #[command(flatten)]
    pub time: TimeArgs,
    /// Seed of every random choice.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Hide the progress bar.
    #[arg(long, short)]
    pub quiet: bool,
}

fn parse_axis_arg(text: &str) -> Result<crowdgaze::world::Axis, String> {
    crate::skeleton::parse_axis(text)
        .ok_or_else(|| format!("'{text}' is not an axis (x, y, z, -x, -y or -z)"))
}
